// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: what show and key print for scripts (--json), against a
 * fake chip.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <cmocka.h>

#include "fake_backend.h"
#include "wsfile.h"

struct ctx {
	char dir[64];
	char path[128];
	struct fake_clock clk;
	struct fake_be fb;
	struct sw_opts o;
	struct sw_env env;
	struct sw_err e;
	char *out, *err;
	size_t out_len, err_len;
	size_t mark;		/* out_text() from here */
	FILE *outf, *errf;
};

static int setup(void **state)
{
	struct ctx *c = calloc(1, sizeof(*c));

	strcpy(c->dir, "/tmp/sw-out-XXXXXX");
	if (!c || !mkdtemp(c->dir))
		return -1;
	snprintf(c->path, sizeof(c->path), "%s/platform-sentral-sim-0x28.ws",
		 c->dir);
	c->clk.now_ms = 1000;
	c->clk.wall_s = 1800000000;
	fake_init(&c->fb, &c->clk);
	c->outf = open_memstream(&c->out, &c->out_len);
	c->errf = open_memstream(&c->err, &c->err_len);
	fake_env(&c->env, &c->clk, c->outf, c->errf);
	c->o.state_dir = c->dir;
	c->o.address = 0x28;
	c->o.max_score = 5.0;
	sw_err_clear(&c->e);
	*state = c;
	return 0;
}

static int teardown(void **state)
{
	struct ctx *c = *state;
	char cmd[128];

	fclose(c->outf);
	fclose(c->errf);
	free(c->out);
	free(c->err);
	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", c->dir);
	if (system(cmd) != 0)
		return -1;
	free(c);
	return 0;
}

static const char *out_text(struct ctx *c)
{
	fflush(c->outf);
	return c->out ? c->out + c->mark : "";
}

/* Forget what was printed so far. */
static void clear_out(struct ctx *c)
{
	fflush(c->outf);
	c->mark = c->out_len;
}

/* The file save writes for the fake chip, -47 LSB of accel X offset. */
static void save_file(struct ctx *c)
{
	c->fb.offset[0] = -47;
	assert_int_equal(sw_cmd_save(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	clear_out(c);
}

static int show(struct ctx *c)
{
	struct sw_opts o = c->o;

	o.file = c->path;
	o.json = true;
	sw_err_clear(&c->e);
	return sw_cmd_show(&o, &c->env, &c->e);
}

/* Issue 33.3: show --json, one object on one line. Before: no --json. */
static void test_show_json(void **state)
{
	struct ctx *c = *state;
	const char *out;
	char want[512];

	save_file(c);
	assert_int_equal(show(c), SW_EXIT_OK);
	out = out_text(c);
	snprintf(want, sizeof(want),
		 "{\"file\":\"%s\",\"version\":2,\"size\":176,\"crc32\":",
		 c->path);
	assert_memory_equal(out, want, strlen(want));
	assert_non_null(strstr(out,
			       ",\"product_id\":128,\"revision_id\":2,\"rom_version\":2534,\"ram_version\":3077,\"status\":null,\"level\":4,\"level_name\":\"stable\",\"judgement\":\"score\",\"calibration_score\":2.499,\"calibration_score_raw\":33587,\"saved_at\":1800000000,\"parameters\":[{\"number\":1,\"name\":\"xstates[1]\",\"raw\":1056964608,\"value\":0.5},{\"number\":2,"));
	/* Table 1 of the seed app note: -47 LSB is 0xbcbbe447 */
	assert_non_null(strstr(out,
			       "{\"number\":27,\"name\":\"acoeffs[4]\",\"raw\":3166430279,\"value\":-0.0229359996,\"accel_lsb\":-47},"));
	assert_non_null(strstr(out, "{\"number\":35,\"name\":\"gcoeffs[6]\","));
	/* one line */
	assert_string_equal(out + strlen(out) - 3, "]}\n");
	assert_ptr_equal(strchr(out, '\n'), out + strlen(out) - 1);
}

/* A version 1 file and an import: status, and no level. */
static void test_show_json_kinds(void **state)
{
	struct ctx *c = *state;
	uint8_t buf[SW_FILE_SIZE];
	struct sw_file f;
	struct sw_err e;

	memset(&f, 0, sizeof(f));
	f.version = SW_FILE_VERSION_1;
	f.state = 3;
	f.judgement = SW_JUDGED_SCORE;
	f.score_raw = 0x8333;
	fake_fill_blob(f.payload);
	sw_file_encode(&f, buf);
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(c->path, buf, sizeof(buf), true,
					      &e), SW_EXIT_OK);
	assert_int_equal(show(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c),
			       ",\"version\":1,\"size\":176,"));
	assert_non_null(strstr(out_text(c),
			       ",\"status\":3,\"level\":4,\"level_name\":\"stable\",\"judgement\":\"score\",\"calibration_score\":2.499,"));

	clear_out(c);
	f.version = SW_FILE_VERSION;
	f.state = 0;
	f.judgement = SW_JUDGED_NONE;
	f.score_raw = 0;
	sw_file_encode(&f, buf);
	assert_int_equal(sw_file_write_atomic(c->path, buf, sizeof(buf), true,
					      &e), SW_EXIT_OK);
	assert_int_equal(show(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c),
			       ",\"status\":null,\"level\":null,\"level_name\":null,\"judgement\":\"none\",\"calibration_score\":null,\"calibration_score_raw\":null,\"saved_at\":0,"));
}

/* A refused file: the error, and nothing on standard output. */
static void test_show_json_refused(void **state)
{
	struct ctx *c = *state;

	save_file(c);
	assert_int_equal(truncate(c->path, 150), 0);
	assert_int_equal(show(c), SW_EXIT_FILE);
	assert_non_null(strstr(c->e.msg, "refused: truncated"));
	assert_string_equal(out_text(c), "");
}

static int key(struct ctx *c, bool json, bool udev)
{
	struct sw_opts o = c->o;

	o.json = json;
	o.udev = udev;
	sw_err_clear(&c->e);
	return sw_cmd_key(&c->fb.b, &o, &c->env, &c->e);
}

/* Issue 33.3: key --json. Before: no --json. */
static void test_key_json(void **state)
{
	struct ctx *c = *state;
	char want[512];

	assert_int_equal(key(c, true, false), SW_EXIT_OK);
	snprintf(want, sizeof(want),
		 "{\"device\":\"iio:device0\",\"backend\":\"fake\",\"key\":\"platform-sentral-sim-0x28\",\"unit\":\"platform\\\\x2dsentral\\\\x2dsim\\\\x2d0x28\",\"file\":\"%s\"}\n",
		 c->path);
	assert_string_equal(out_text(c), want);

	/* The plain forms are as they were. */
	clear_out(c);
	assert_int_equal(key(c, false, false), SW_EXIT_OK);
	assert_string_equal(out_text(c), "platform-sentral-sim-0x28\n");
	clear_out(c);
	assert_int_equal(key(c, false, true), SW_EXIT_OK);
	assert_string_equal(out_text(c),
			    "SENTRAL_WARMSTART_KEY=platform-sentral-sim-0x28\nSENTRAL_WARMSTART_UNIT=platform\\x2dsentral\\x2dsim\\x2d0x28\n");
}

/* A key too long for a unit name: --udev fails, --json says null. */
static void test_key_json_long(void **state)
{
	struct ctx *c = *state;
	char key_[SW_KEY_MAX];

	memset(key_, '-', 60);
	key_[60] = '\0';
	strcpy(c->fb.b.key, key_);
	assert_int_equal(key(c, false, true), SW_EXIT_DEVICE);
	assert_non_null(strstr(c->e.msg, "too long for a systemd unit name"));
	assert_int_equal(key(c, true, false), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), ",\"unit\":null,\"file\":"));
}

int main(void)
{
#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)
	const struct CMUnitTest tests[] = {
		T(test_show_json),
		T(test_show_json_kinds),
		T(test_show_json_refused),
		T(test_key_json),
		T(test_key_json_long),
	};

	return cmocka_run_group_tests_name("output", tests, NULL, NULL);
}
