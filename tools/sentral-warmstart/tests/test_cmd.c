// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: save, restore, status, show, calibrate and accel-cal against
 * a fake chip and a fake clock.
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>

#include "caldata.h"
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
	FILE *outf, *errf;
};

static int setup(void **state)
{
	struct ctx *c = calloc(1, sizeof(*c));

	strcpy(c->dir, "/tmp/sw-cmd-XXXXXX");
	if (!mkdtemp(c->dir))
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
	c->o.target_score = 3.0;
	c->o.timeout_s = 60;
	c->o.samples = 32;
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
	return c->out;
}

static bool load(struct ctx *c, struct sw_file *f)
{
	uint8_t buf[SW_FILE_MAX_READ + 1];
	struct sw_err e;
	size_t len;

	sw_err_clear(&e);
	if (sw_file_read(c->path, SW_READ_STATE, buf, &len, NULL, &e))
		return false;
	return sw_file_decode(buf, len, f, NULL, 0) == SW_CHECK_OK;
}

static int save(struct ctx *c)
{
	sw_err_clear(&c->e);
	return sw_cmd_save(&c->fb.b, &c->o, &c->env, &c->e);
}

static int restore(struct ctx *c)
{
	sw_err_clear(&c->e);
	return sw_cmd_restore(&c->fb.b, &c->o, &c->env, &c->e);
}

static void test_save_good(void **state)
{
	struct ctx *c = *state;
	struct sw_file f;
	struct stat st;

	c->fb.cs.score_raw = sw_score_raw(2.9);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.version, 2);
	assert_int_equal(f.state, 4);
	assert_int_equal(f.judgement, SW_JUDGED_SCORE);
	assert_int_equal(f.score_raw, sw_score_raw(2.9));
	assert_true(f.saved_at == 1800000000);
	assert_int_equal(f.chip.rom_version, 0x09e6);
	assert_memory_equal(f.payload, c->fb.blob, SW_BLOB_SIZE);
	assert_int_equal(stat(c->path, &st), 0);
	assert_int_equal(st.st_mode & 0777, 0600);
	assert_non_null(strstr(out_text(c), "saved iio:device0"));
}

static void test_save_policy_refusals(void **state)
{
	struct ctx *c = *state;
	struct sw_file f;

	/* The policy saying no is a success (the unit's stop action). */
	c->fb.cs.level = 2;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "not saving iio:device0 calibration"));
	assert_non_null(strstr(out_text(c), "not stable (level 2 (calibrating), score 2.499%; needs 4)"));
	assert_int_equal(access(c->path, F_OK), -1);

	c->fb.cs.level = 4;
	c->fb.cs.score_raw = sw_score_raw(6.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_int_equal(access(c->path, F_OK), -1);
	c->o.max_score = 7.0;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));

	/* A good file is not replaced by a worse calibration... */
	c->o.max_score = 5.0;
	c->fb.cs.score_raw = sw_score_raw(2.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	c->fb.cs.score_raw = sw_score_raw(4.0);
	sw_blob_set_param(c->fb.blob, 1, 99.0f);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "worse"));
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, sw_score_raw(2.0));
	/* ...unless forced. */
	c->o.force = true;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, sw_score_raw(4.0));
	assert_true(sw_blob_param(f.payload, 1) == 99.0f);
}

static void test_save_over_bad_file(void **state)
{
	struct ctx *c = *state;
	struct sw_file f;
	FILE *fp;

	fp = fopen(c->path, "w");
	assert_non_null(fp);
	fputs("garbage", fp);
	fclose(fp);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "replacing unusable"));
	assert_true(load(c, &f));

	/* A file for another ROM does not block a save either. */
	c->fb.chip.rom_version = 0x07a8;
	c->fb.cs.score_raw = sw_score_raw(4.9);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.chip.rom_version, 0x07a8);
}

static void test_save_nonfinite_blob(void **state)
{
	struct ctx *c = *state;

	sw_blob_set_param(c->fb.blob, 20, 0.0f / 0.0f);
	assert_int_equal(save(c), SW_EXIT_IO);
	assert_non_null(strstr(c->e.msg, "mcoeffs[3]"));
	assert_int_equal(access(c->path, F_OK), -1);
}

static void test_save_refuses_symlink(void **state)
{
	struct ctx *c = *state;
	char target[128];

	snprintf(target, sizeof(target), "%s/elsewhere", c->dir);
	assert_int_equal(symlink(target, c->path), 0);
	assert_int_equal(save(c), SW_EXIT_PERM);
	assert_non_null(strstr(c->e.msg, "symbolic link"));
	assert_int_equal(access(target, F_OK), -1);
}

static void test_restore_good(void **state)
{
	struct ctx *c = *state;
	uint8_t saved[SW_BLOB_SIZE];

	assert_int_equal(save(c), SW_EXIT_OK);
	memcpy(saved, c->fb.blob, SW_BLOB_SIZE);
	/* A fresh power-on: defaults in the chip, not calibrated. */
	memset(c->fb.blob, 0, SW_BLOB_SIZE);
	c->fb.cs.level = 2;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 1);
	assert_memory_equal(c->fb.blob, saved, SW_BLOB_SIZE);
	assert_non_null(strstr(out_text(c), "restored iio:device0 calibration from "));
	assert_non_null(strstr(out_text(c), ": level 4 (stable), score 2.499% (saved: level 4 (stable), score 2.499%)"));
}

static void test_restore_missing(void **state)
{
	struct ctx *c = *state;

	assert_int_equal(restore(c), SW_EXIT_NOFILE);
	assert_non_null(strstr(c->e.msg, "does not exist"));
	c->o.if_present = true;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "nothing to restore"));
	assert_int_equal(c->fb.writes, 0);
}

static void test_restore_refuses_bad_files(void **state)
{
	struct ctx *c = *state;
	uint8_t good[SW_FILE_SIZE], buf[SW_FILE_SIZE];
	const struct { size_t off; const char *check; } cases[] = {
		{ 0, "wrong magic" }, { 8, "unknown version" },
		{ 28, "payload size" }, { 40, "bad CRC" }, { 175, "bad CRC" },
	};
	struct sw_err e;
	size_t i;
	FILE *fp;

	assert_int_equal(save(c), SW_EXIT_OK);
	fp = fopen(c->path, "r");
	assert_non_null(fp);
	assert_int_equal(fread(good, 1, sizeof(good), fp), sizeof(good));
	fclose(fp);
	for (i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
		memcpy(buf, good, sizeof(buf));
		buf[cases[i].off] ^= 0x10;
		sw_err_clear(&e);
		assert_int_equal(sw_file_write_atomic(c->path, buf, sizeof(buf),
						      true, &e), SW_EXIT_OK);
		assert_int_equal(restore(c), SW_EXIT_FILE);
		if (!strstr(c->e.msg, cases[i].check))
			fail_msg("offset %zu: \"%s\" lacks \"%s\"", cases[i].off,
				 c->e.msg, cases[i].check);
		assert_non_null(strstr(c->e.msg, "not touched"));
		assert_non_null(strstr(c->e.msg, ".ws.refused for inspection"));
	}
	/* Truncated. */
	assert_int_equal(sw_file_write_atomic(c->path, good, 100, true, &e),
			 SW_EXIT_OK);
	assert_int_equal(restore(c), SW_EXIT_FILE);
	assert_non_null(strstr(c->e.msg, "truncated"));
	/* --if-present does not excuse a bad file. */
	assert_int_equal(sw_file_write_atomic(c->path, good, 100, true, &e),
			 SW_EXIT_OK);
	c->o.if_present = true;
	assert_int_equal(restore(c), SW_EXIT_FILE);
	assert_int_equal(c->fb.writes, 0);
}

/* A refused state file is moved aside: put it back for the next case. */
static void unrefuse(struct ctx *c)
{
	char aside[160];

	snprintf(aside, sizeof(aside), "%s.refused", c->path);
	assert_int_equal(rename(aside, c->path), 0);
}

static void test_restore_chip_mismatch(void **state)
{
	struct ctx *c = *state;

	assert_int_equal(save(c), SW_EXIT_OK);
	c->fb.chip.ram_version = 0x0c06;
	assert_int_equal(restore(c), SW_EXIT_FILE);
	assert_non_null(strstr(c->e.msg, "RAM version mismatch"));
	assert_non_null(strstr(c->e.msg, "--force"));
	unrefuse(c);
	c->fb.chip.ram_version = 0x0c05;
	c->fb.chip.product_id = 0x81;
	assert_int_equal(restore(c), SW_EXIT_FILE);
	assert_non_null(strstr(c->e.msg, "ProductID mismatch"));
	unrefuse(c);
	c->fb.chip.product_id = 0x80;
	c->fb.chip.rom_version = 0x07a8;
	assert_int_equal(restore(c), SW_EXIT_FILE);
	assert_non_null(strstr(c->e.msg, "ROM version mismatch"));
	unrefuse(c);
	assert_int_equal(c->fb.writes, 0);
	c->o.force = true;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 1);
	assert_non_null(strstr(out_text(c), "restoring anyway"));
}

/*
 * A driver with the identity in calibration_data's header checks it
 * itself: restore writes the file's identity and asks the chip's only
 * when the driver refused, to say which differs; the chip untouched and
 * the file set aside, or with --force written as the chip's.
 */
static void test_restore_driver_checks_identity(void **state)
{
	struct ctx *c = *state;
	uint8_t saved[SW_BLOB_SIZE];

	assert_int_equal(save(c), SW_EXIT_OK);
	memcpy(saved, c->fb.blob, SW_BLOB_SIZE);
	memset(c->fb.blob, 0, SW_BLOB_SIZE);
	c->fb.b.checks_identity = true;
	c->fb.chip_infos = 0;
	c->fb.reads = 0;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 1);
	assert_memory_equal(c->fb.blob, saved, SW_BLOB_SIZE);
	assert_int_equal(c->fb.chip_infos, 0);
	assert_int_equal(c->fb.reads, 0);

	/* Another firmware since the save; RevisionID alone is no mismatch */
	memset(c->fb.blob, 0, SW_BLOB_SIZE);
	c->fb.chip.ram_version = 0x0c06;
	assert_int_equal(restore(c), SW_EXIT_FILE);
	assert_int_equal(c->fb.writes, 1);
	assert_int_equal(c->fb.chip_infos, 1);
	assert_non_null(strstr(c->e.msg, "RAM version mismatch (file 0x0c05, chip 0x0c06): saved on another chip or firmware; the chip was not touched (--force restores anyway); moved aside to "));
	unrefuse(c);
	c->fb.chip.ram_version = 0x0c05;
	c->fb.chip.revision_id ^= 1;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 2);
	assert_memory_equal(c->fb.blob, saved, SW_BLOB_SIZE);

	c->fb.chip.rom_version = 0x07a8;
	c->o.force = true;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 3);
	assert_non_null(strstr(out_text(c), "ROM version mismatch (file 0x09e6, chip 0x07a8); restoring anyway (--force)"));
}

/*
 * status with such a driver: one read of the blob gives the identity and
 * the comparison with the saved file, as one read gave the comparison.
 */
static void test_status_identity_from_blob(void **state)
{
	struct ctx *c = *state;

	assert_int_equal(save(c), SW_EXIT_OK);
	c->fb.b.checks_identity = true;
	c->fb.reads = 0;
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_int_equal(c->fb.reads, 1);
	assert_non_null(strstr(out_text(c), "chip:                ProductID 0x80, RevisionID 0x02, ROM 0x09e6, RAM 0x0c05\n"));
	assert_non_null(strstr(out_text(c), "restored:            yes: "));

	c->fb.fail_read = SW_EXIT_IO;
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "chip:                unknown (fake: read failed)\n"));
	assert_non_null(strstr(out_text(c), "restored:            unknown (fake: read failed)\n"));
}

static void test_restore_not_calibrated_after(void **state)
{
	struct ctx *c = *state;
	uint64_t t0;

	assert_int_equal(save(c), SW_EXIT_OK);
	c->fb.cs.level = 1;
	c->fb.level_after_write = -1;
	t0 = c->clk.now_ms;
	assert_int_equal(restore(c), SW_EXIT_CAL);
	assert_non_null(strstr(c->e.msg, "but the calibration level is 1 (unreliable sensor data), not 4 (stable)"));
	/* It waited, but not for ever. */
	assert_true(c->clk.now_ms - t0 >= 2000 && c->clk.now_ms - t0 < 3000);
}

static void test_restore_write_error(void **state)
{
	struct ctx *c = *state;

	assert_int_equal(save(c), SW_EXIT_OK);
	c->fb.fail_write = SW_EXIT_IO;
	assert_int_equal(restore(c), SW_EXIT_IO);
	assert_non_null(strstr(c->e.msg, "fake: write failed"));
}

/*
 * Issue 14.3: a value read from the chip is input, not truth. A score below
 * 0 % (raw < 0x8000, or the -100 % a NaN used to turn into) looked better
 * than any saved file: one bad read replaced a good calibration and then
 * blocked every later save.
 */
static void test_save_distrusts_chip_values(void **state)
{
	struct ctx *c = *state;
	static const uint16_t bad_scores[] = { 0x7fff, 0x7000, 0x0000 };
	struct sw_file f;
	size_t i;

	c->fb.cs.score_raw = sw_score_raw(2.5);
	assert_int_equal(save(c), SW_EXIT_OK);
	for (i = 0; i < sizeof(bad_scores) / sizeof(bad_scores[0]); i++) {
		c->fb.cs.score_raw = bad_scores[i];
		sw_blob_set_param(c->fb.blob, 1, 77.0f);
		assert_int_not_equal(save(c), SW_EXIT_OK);
		assert_non_null(strstr(c->e.msg, "below 0 %"));
		assert_non_null(strstr(c->e.msg, "not saving"));
		/* Not even --force takes an impossible value. */
		c->o.force = true;
		assert_int_not_equal(save(c), SW_EXIT_OK);
		c->o.force = false;
		assert_true(load(c, &f));
		assert_int_equal(f.score_raw, sw_score_raw(2.5));
		assert_true(sw_blob_param(f.payload, 1) == 0.5f);
	}
	c->fb.cs.score_raw = sw_score_raw(2.5);
	c->fb.cs.level = 5;
	assert_int_not_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(c->e.msg, "level 5 is not 0..4"));
	c->fb.cs.level = 4;
	c->fb.cs.gyro_bias_update = 2;
	assert_int_not_equal(save(c), SW_EXIT_OK);
	c->fb.cs.gyro_bias_update = 0;
	/* A good read saves again: nothing was blocked. */
	c->fb.cs.score_raw = sw_score_raw(1.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, sw_score_raw(1.0));
}

/* A file saved before the fix from a bad read no longer blocks saves. */
static void test_save_replaces_file_with_bad_score(void **state)
{
	struct ctx *c = *state;
	uint8_t buf[SW_FILE_SIZE];
	struct sw_file f;
	struct sw_err e;

	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	f.score_raw = 0x4000;	/* -50 % */
	sw_file_encode(&f, buf);
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(c->path, buf, sizeof(buf), true,
					      &e), SW_EXIT_OK);
	c->fb.cs.score_raw = sw_score_raw(4.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "replacing unusable"));
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, sw_score_raw(4.0));
}

/*
 * Issue 12.3: a refused state file is moved aside with its reason, and the
 * next save writes a good calibration in its place.
 */
static void test_restore_refused_then_save(void **state)
{
	struct ctx *c = *state;
	uint8_t good[SW_FILE_SIZE], back[SW_FILE_SIZE];
	char aside[160];
	struct sw_file f;
	FILE *fp;

	snprintf(aside, sizeof(aside), "%s.refused", c->path);
	assert_int_equal(save(c), SW_EXIT_OK);
	fp = fopen(c->path, "r+");
	assert_non_null(fp);
	assert_int_equal(fread(good, 1, sizeof(good), fp), sizeof(good));
	assert_int_equal(fseek(fp, 100, SEEK_SET), 0);
	fputc(good[100] ^ 0x10, fp);
	fclose(fp);
	c->o.if_present = true;
	c->fb.cs.level = 0;
	assert_int_equal(restore(c), SW_EXIT_FILE);
	assert_int_equal(SW_EXIT_FILE, 65);	/* systemctl: "65/DATAERR" */
	assert_non_null(strstr(c->e.msg, "refused: bad CRC"));
	assert_non_null(strstr(c->e.msg, "moved aside to"));
	assert_int_equal(c->fb.writes, 0);
	assert_int_equal(access(c->path, F_OK), -1);
	fp = fopen(aside, "r");
	assert_non_null(fp);
	assert_int_equal(fread(back, 1, sizeof(back), fp), sizeof(back));
	fclose(fp);
	good[100] ^= 0x10;
	assert_memory_equal(back, good, sizeof(good));
	/* The next boot starts uncalibrated, no longer refused... */
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "nothing to restore"));
	/* ...and the stop action saves what the chip learns meanwhile. */
	c->fb.cs.level = 4;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(access(aside, F_OK), 0);

	/* A --file file is the user's: refused, left where it is. */
	c->o.file = aside;
	assert_int_equal(restore(c), SW_EXIT_FILE);
	assert_null(strstr(c->e.msg, "moved aside"));
	assert_int_equal(access(aside, F_OK), 0);
}

/*
 * Issue 14.5: a missing state directory is not "no file yet": on a system
 * without systemd, /var may not be mounted when udev runs the restore.
 */
static void test_restore_missing_state_dir(void **state)
{
	struct ctx *c = *state;
	char absent[128];

	snprintf(absent, sizeof(absent), "%s/absent", c->dir);
	c->o.state_dir = absent;
	c->o.if_present = true;
	assert_int_equal(restore(c), SW_EXIT_STATEDIR);
	assert_non_null(strstr(c->e.msg, "state directory"));
	assert_non_null(strstr(c->e.msg, "does not exist"));
	assert_null(strstr(out_text(c), "nothing to restore"));
	assert_int_equal(c->fb.writes, 0);
	/* status says so; save creates it (0700). */
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "state directory"));
	assert_int_equal(save(c), SW_EXIT_OK);
	snprintf(absent, sizeof(absent), "%s/absent/platform-sentral-sim-0x28.ws",
		 c->dir);
	assert_int_equal(access(absent, F_OK), 0);
}

/*
 * Issue 14.1: a file saved under a key of an older version (udev's ID_PATH
 * or the I2C client's name) is moved to the new key once, with a line
 * saying so, and restored.
 */
static void test_migrate_legacy_key(void **state)
{
	struct ctx *c = *state;
	uint8_t saved[SW_BLOB_SIZE];
	char legacy[160];

	strcpy(c->fb.b.legacy_key[1], "0-0028");
	snprintf(legacy, sizeof(legacy), "%s/0-0028.ws", c->dir);
	c->o.file = legacy;
	assert_int_equal(save(c), SW_EXIT_OK);
	c->o.file = NULL;
	memcpy(saved, c->fb.blob, SW_BLOB_SIZE);
	memset(c->fb.blob, 0, SW_BLOB_SIZE);
	c->fb.cs.level = 0;
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "0-0028.ws (saved under an older key) moves here"));
	assert_int_equal(access(legacy, F_OK), 0);
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "migrated"));
	assert_int_equal(access(legacy, F_OK), -1);
	assert_int_equal(access(c->path, F_OK), 0);
	assert_memory_equal(c->fb.blob, saved, SW_BLOB_SIZE);

	/* Once: a file under the new key wins, the old one stays untouched. */
	c->o.file = legacy;
	assert_int_equal(save(c), SW_EXIT_OK);
	c->o.file = NULL;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(access(legacy, F_OK), 0);
}

static void test_status(void **state)
{
	struct ctx *c = *state;

	c->fb.cs.mag_cal_update = 1;
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "calibration level:   4 (stable)\n"
				"calibration score:   2.499%\n"
				"gyro bias update:    0\n"
				"mag cal update:      1\n"));
	assert_non_null(strstr(out_text(c), "no saved calibration"));
	assert_null(strstr(out_text(c), "restored:"));
	assert_int_equal(c->fb.reads, 0);
	assert_int_equal(save(c), SW_EXIT_OK);
	c->o.json = true;
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "{\"device\":\"iio:device0\",\"backend\":\"fake\",\"key\":\"platform-sentral-sim-0x28\",\"product_id\":128,"));
	/* the save read calibration_data, which clears the driver's flags */
	assert_non_null(strstr(out_text(c), ",\"level\":4,\"level_name\":\"stable\",\"calibration_score\":2.499,\"calibration_score_raw\":33587,\"gyro_bias_update\":0,\"mag_calibration_update\":0,\"file\":"));
	assert_non_null(strstr(out_text(c), ",\"saved\":{\"version\":2,\"level\":4,\"level_name\":\"stable\",\"calibration_score\":2.499,\"calibration_score_raw\":33587,\"saved_at\":1800000000},\"judgement\":\"score\",\"restored\":true}\n"));
}

/* The output of one status command, exit 0. */
static const char *status_out(struct ctx *c)
{
	size_t from;

	fflush(c->outf);
	from = c->out_len;
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	fflush(c->outf);
	return c->out + from;
}

/* Issue 23.6: where the firmware came from, and the feature sensors. */
static void test_status_hub(void **state)
{
	struct ctx *c = *state;
	struct sw_feature *p = &c->fb.hub.features[0];

	/* the USFS board: barometer and thermometer, an EEPROM */
	assert_non_null(strstr(status_out(c),
			       "ROM 0x09e6, RAM 0x0c05\n"
			       "firmware:            from the board's EEPROM\n"
			       "feature sensors:     pressure 100.012 kPa at 25 Hz\n"
			       "                     temperature 25.03 C at 25 Hz\n"
			       "calibration level:   4 (stable)"));
	c->o.json = true;
	assert_non_null(strstr(status_out(c),
			       "\"ram_version\":3077,\"firmware_source\":\"eeprom\",\"feature_sensors\":[{\"name\":\"pressure\",\"value\":100.012,\"unit\":\"kPa\",\"rate_hz\":25},{\"name\":\"temperature\",\"value\":25.03,\"unit\":\"C\",\"rate_hz\":25}],\"level\":4,"));

	/* uploaded by the host; a buffer streams: no value, the rate still */
	c->fb.hub.fw_source = SW_FW_HOST;
	p->have_value = false;
	c->o.json = false;
	assert_non_null(strstr(status_out(c),
			       "firmware:            uploaded by the host\n"
			       "feature sensors:     pressure (no value while a buffer streams) at 25 Hz\n"
			       "                     temperature 25.03 C at 25 Hz\n"));
	c->o.json = true;
	assert_non_null(strstr(status_out(c),
			       "\"firmware_source\":\"host\",\"feature_sensors\":[{\"name\":\"pressure\",\"value\":null,\"unit\":\"kPa\",\"rate_hz\":25},{\"name\":\"temperature\",\"value\":25.03,"));

	/* an older driver (no firmware_source); a board without any */
	c->fb.hub.fw_source = SW_FW_UNKNOWN;
	strcpy(c->fb.hub.fw_why,
	       "this em7180 driver does not say: no firmware_source attribute");
	c->fb.hub.nfeatures = 0;
	c->o.json = false;
	assert_non_null(strstr(status_out(c),
			       "firmware:            unknown (this em7180 driver does not say: no firmware_source attribute)\n"
			       "feature sensors:     none\n"));
	c->o.json = true;
	assert_non_null(strstr(status_out(c),
			       ",\"firmware_source\":null,\"feature_sensors\":[],\"level\":4,"));

	/* humidity: all three in slot order */
	c->fb.hub.nfeatures = 3;
	p->have_value = true;
	c->fb.hub.features[2] = c->fb.hub.features[1];
	c->fb.hub.features[1] = (struct sw_feature){
		.kind = SW_FEATURE_HUMIDITY, .have_value = true,
		.value = 45.004, .rate_hz = 10,
	};
	c->o.json = false;
	assert_non_null(strstr(status_out(c),
			       "feature sensors:     pressure 100.012 kPa at 25 Hz\n"
			       "                     humidity 45.00 % at 10 Hz\n"
			       "                     temperature 25.03 C at 25 Hz\n"));
	c->o.json = true;
	assert_non_null(strstr(status_out(c),
			       "{\"name\":\"humidity\",\"value\":45.00,\"unit\":\"%\",\"rate_hz\":10},"));

	/* failing to read them does not fail status */
	c->fb.hub_fail = SW_EXIT_IO;
	c->o.json = false;
	assert_non_null(strstr(status_out(c),
			       "firmware:            unknown (iio:device0: reading in_pressure_raw: Input/output error)\n"
			       "feature sensors:     unknown (iio:device0: reading in_pressure_raw: Input/output error)\n"
			       "calibration level:   4"));
	c->o.json = true;
	assert_non_null(strstr(status_out(c),
			       ",\"firmware_source\":null,\"feature_sensors\":null,\"level\":4,"));
}

/* Firmware without the application note's layout: the level only. */
static void level_only(struct ctx *c)
{
	c->fb.cs.has_score = false;
	c->fb.cs.score_raw = 0;
	c->fb.cs.gyro_bias_update = 0;
	c->fb.cs.mag_cal_update = 0;
}

/*
 * A USFS board: the level only. status shows it, no score or flags, and
 * whether the chip holds the saved file (one read of the blob).
 */
static void test_status_level_only(void **state)
{
	struct ctx *c = *state;

	level_only(c);
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "calibration level:   4 (stable)\n"
				"calibration score:   not reported by this firmware (saved by the level alone)\n"
				"saved file:          "));
	assert_null(strstr(out_text(c), "gyro bias update:"));
	c->o.json = true;
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), ",\"level\":4,\"level_name\":\"stable\",\"calibration_score\":null,\"calibration_score_raw\":null,\"gyro_bias_update\":null,\"mag_calibration_update\":null,\"file\":"));
	assert_non_null(strstr(out_text(c), ",\"saved\":null,\"saved_problem\":\"no saved calibration yet\",\"judgement\":null,\"restored\":null}\n"));
	c->o.json = false;

	/* saved by the stable rule; the chip holds it */
	assert_int_equal(save(c), SW_EXIT_OK);
	c->fb.reads = 0;
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_int_equal(c->fb.reads, 1);
	assert_non_null(strstr(out_text(c), ".ws: level 4 (stable), no score, saved 2027-01-15T08:00:00Z\n"
				"restored:            yes: the chip holds the saved calibration (parameters 18-23 and 27-29 within 0.5 %)\n"));

	/* a power-on: the chip's defaults, not the file's */
	c->fb.cs.level = 2;
	sw_blob_set_param(c->fb.blob, 18, 0.0f);
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "calibration level:   2 (calibrating)\n"));
	assert_non_null(strstr(out_text(c), "restored:            no: parameter 18 (mcoeffs[1]) is 0 on the chip, 9 in the file\n"));
	c->o.json = true;
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), ",\"saved\":{\"version\":2,\"level\":4,\"level_name\":\"stable\",\"calibration_score\":null,\"calibration_score_raw\":null,\"saved_at\":1800000000},\"judgement\":\"stable\",\"restored\":false}\n"));
	/* a glitch is an error, not a level */
	c->fb.cs.level = FAKE_GLITCH;
	assert_int_equal(sw_cmd_status(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_IO);
}

static void test_show(void **state)
{
	struct ctx *c = *state;
	struct sw_opts o = c->o;

	c->fb.offset[0] = -47;
	assert_int_equal(save(c), SW_EXIT_OK);
	o.file = c->path;
	assert_int_equal(sw_cmd_show(&o, &c->env, &c->e), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "format:              SNTRLWS1 version 2, 176 bytes, CRC-32 0x"));
	assert_non_null(strstr(out_text(c), "ROM version:         0x09e6\n"
				"RAM version:         0x0c05\n"
				"calibration level:   4 (stable)\n"
				"judgement:           score (the application note's score)\n"
				"calibration score:   2.499% (raw 0x8333)\n"));
	assert_non_null(strstr(out_text(c), " 1  xstates[1]  "));
	assert_non_null(strstr(out_text(c), "27  acoeffs[4]  0xbcbbe447"));
	assert_non_null(strstr(out_text(c), "(accel X offset, -47 LSB)"));
	assert_non_null(strstr(out_text(c), "35  gcoeffs[6]"));

	/*
	 * Extremes a valid file may hold: a save time past INT64_MAX is not
	 * shown as 1969, a huge offset saturates instead of showing 0 LSB.
	 */
	{
		uint8_t buf[SW_FILE_SIZE];
		struct sw_file f;
		struct sw_err e;

		assert_true(load(c, &f));
		f.saved_at = UINT64_MAX;
		sw_blob_set_param(f.payload, 27, -3.4e38f);
		sw_file_encode(&f, buf);
		sw_err_clear(&e);
		assert_int_equal(sw_file_write_atomic(c->path, buf, sizeof(buf),
						      true, &e), SW_EXIT_OK);
	}
	assert_int_equal(sw_cmd_show(&o, &c->env, &c->e), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c),
			       "saved at:            ? (18446744073709551615)"));
	assert_non_null(strstr(out_text(c), "(accel X offset, -2147483648 LSB)"));
	assert_null(strstr(out_text(c), "1969"));

	assert_int_equal(truncate(c->path, 150), 0);
	assert_int_equal(sw_cmd_show(&o, &c->env, &c->e), SW_EXIT_FILE);
	assert_non_null(strstr(c->e.msg, "refused: truncated"));
}

static const struct fake_step cal_ok[] = {
	{ 0, 2, 0xffff, 1 },		/* an update from before */
	{ 3000, 2, 0xffff, 1 },		/* gyro bias learned */
	{ 3500, 2, 0xffff, 0 },
	{ 5000, 3, 0xffff, 0 },		/* a transient: not stable */
	{ 7000, 4, 0x8000 + 3276, 0 },	/* about 10 % */
	{ 9000, 4, 0x8000 + 1500, 0 },
	{ 11000, 4, 0x8000 + 900, 0 },	/* 2.747 %: done */
};

/* A field of 49 uT around the simulator's hard-iron offset (uT). */
static void mag_at(double z, double lon, double ut[3])
{
	double s = sqrt(1 - z * z);

	ut[0] = 25.0 + 49.0 * s * cos(lon);
	ut[1] = -12.5 + 49.0 * s * sin(lon);
	ut[2] = 40.0 + 49.0 * z;
}

/* Every direction in 10 s: a golden-angle spiral, one point per 25 ms. */
static void mag_sphere(uint64_t t, double ut[3])
{
	mag_at(1 - 2 * (double)(t % 10000) / 10000, (double)(t / 25) * 2.39996,
	       ut);
}

/* A turn about Z at 90 degrees per second, nothing else. */
static void mag_spin(uint64_t t, double ut[3])
{
	mag_at(0.91, (double)t * M_PI / 2000, ut);
}

static void test_calibrate(void **state)
{
	struct ctx *c = *state;
	struct sw_file f;

	c->clk.now_ms = 0;
	c->fb.script = cal_ok;
	c->fb.nsteps = sizeof(cal_ok) / sizeof(cal_ok[0]);
	c->fb.blob_follows_score = true;
	c->fb.mag = mag_sphere;
	assert_int_equal(sw_cmd_calibrate(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_true(c->clk.now_ms >= 11000 && c->clk.now_ms < 12000);
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, 0x8000 + 900);
	assert_true(sw_blob_param(f.payload, 18) == (float)(0x8000 + 900));
	assert_non_null(strstr(out_text(c), "figure-8"));
	assert_non_null(strstr(out_text(c), "calibrate: level 4/4 (stable), score 2.747%, best 2.747%, coverage "));
	assert_non_null(strstr(out_text(c), "Calibration stable: score 2.747%, "));
	/* 40 samples a second, and most of the sphere seen in 8 s of turning */
	assert_in_range(c->fb.mag_reads, 300, 400);
	assert_non_null(strstr(out_text(c), "% of the sphere covered."));
	assert_non_null(strstr(out_text(c), "coverage 9"));
}

static void test_calibrate_json(void **state)
{
	struct ctx *c = *state;
	const char *line, *end;
	int objects = 0;

	c->clk.now_ms = 0;
	c->o.json = true;
	c->fb.script = cal_ok;
	c->fb.nsteps = sizeof(cal_ok) / sizeof(cal_ok[0]);
	c->fb.mag = mag_sphere;
	assert_int_equal(sw_cmd_calibrate(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	/* stdout holds JSON objects only, one a line; messages go to stderr */
	for (line = out_text(c); *line; line = end + 1) {
		end = strchr(line, '\n');
		assert_non_null(end);
		assert_int_equal(line[0], '{');
		assert_int_equal(end[-1], '}');
		objects++;
	}
	/* one per 250 ms over the 8 s of step 2, the end and the save */
	assert_in_range(objects, 30, 36);
	assert_non_null(strstr(c->out, "{\"event\":\"progress\",\"elapsed_ms\":"));
	assert_non_null(strstr(c->out, ",\"level\":3,\"level_name\":\"stable with a magnetic transient\",\"score\":99.997,\"best_score\":null,\"coverage\":"));
	assert_non_null(strstr(c->out, "\"fit\":\"sphere\",\"regions\":\"1"));
	assert_non_null(strstr(c->out, "{\"event\":\"complete\","));
	assert_non_null(strstr(c->out, "{\"event\":\"saved\",\"level\":4,\"score\":2.747,\"file\":\""));
	fflush(c->errf);
	assert_non_null(strstr(c->err, "Gyro bias learned"));
	assert_non_null(strstr(c->err, "saved iio:device0 calibration"));
}

/* Stuck at 4 %, then worse: keep and save the 4 % snapshot. */
static const struct fake_step cal_plateau[] = {
	{ 0, 2, 0xffff, 1 },
	{ 500, 2, 0xffff, 1 },
	{ 2000, 4, 0x8000 + 1311, 0 },	/* 4.0 % */
	{ 4000, 4, 0x8000 + 1600, 0 },	/* 4.9 % */
};

static void test_calibrate_timeout_keeps_best(void **state)
{
	struct ctx *c = *state;
	struct sw_file f;

	c->clk.now_ms = 0;
	c->o.timeout_s = 10;
	c->fb.script = cal_plateau;
	c->fb.nsteps = sizeof(cal_plateau) / sizeof(cal_plateau[0]);
	c->fb.blob_follows_score = true;
	assert_int_equal(sw_cmd_calibrate(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, 0x8000 + 1311);
	assert_true(sw_blob_param(f.payload, 18) == (float)(0x8000 + 1311));
	assert_non_null(strstr(out_text(c), "Timed out"));
}

static const struct fake_step cal_never[] = {
	{ 0, 2, 0xffff, 1 },
	{ 500, 2, 0xffff, 1 },
	{ 1000, 3, 0xffff, 0 },
};

static void test_calibrate_incomplete(void **state)
{
	struct ctx *c = *state;

	c->clk.now_ms = 0;
	c->o.timeout_s = 5;
	c->fb.script = cal_never;
	c->fb.nsteps = 3;
	c->fb.mag = mag_spin;
	assert_int_equal(sw_cmd_calibrate(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_CAL);
	assert_non_null(strstr(c->e.msg, "did not become stable within 5 s (level 3 of 4, stable with a magnetic transient; "));
	/* and says what motion is missing */
	assert_non_null(strstr(c->e.msg, "0% of the sphere covered; it has only turned about its Z axis: also tilt it"));
	assert_int_equal(access(c->path, F_OK), -1);

	/* Never still: the gyro bias is never learned. */
	c->clk.now_ms = 0;
	c->fb.nsteps = 0;
	sw_err_clear(&c->e);
	assert_int_equal(sw_cmd_calibrate(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_CAL);
	assert_non_null(strstr(c->e.msg, "gyro bias"));
}

static void test_calibrate_tty_map(void **state)
{
	struct ctx *c = *state;
	const char *o;

	c->clk.now_ms = 0;
	c->env.tty = true;
	c->fb.script = cal_ok;
	c->fb.nsteps = sizeof(cal_ok) / sizeof(cal_ok[0]);
	c->fb.mag = mag_sphere;
	assert_int_equal(sw_cmd_calibrate(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	o = out_text(c);
	/* the 9-line view is redrawn in place: cursor up 9 lines */
	assert_non_null(strstr(o, "\033[9Asphere coverage "));
	/* the +Z cap, centred above the 34 regions of the widest band */
	assert_non_null(strstr(o, "\n  +Z                 #\033[K\n"));
	assert_non_null(strstr(o, "level 4/4 (stable), score 2.747%, best 2.747%, "));
	assert_non_null(strstr(o, "hint: "));
}

static void test_accel_cal(void **state)
{
	struct ctx *c = *state;

	/* The seed's Table 1 bias, noise of +-2 LSB. */
	c->fb.bias[0] = -47;
	c->fb.bias[1] = -15;
	c->fb.bias[2] = 46;
	c->fb.noise = 2;
	assert_int_equal(sw_cmd_accel_cal(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_int_equal(c->fb.offset[0], -47);
	assert_int_equal(c->fb.offset[1], -15);
	assert_int_equal(c->fb.offset[2], 46);
	assert_non_null(strstr(out_text(c), "-0.022936 -0.007320 0.022448 g"));
	/* Running it again with the offsets applied changes nothing. */
	assert_int_equal(sw_cmd_accel_cal(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_int_equal(c->fb.offset[0], -47);
	assert_int_equal(c->fb.offset[2], 46);
}

static void test_accel_cal_refusals(void **state)
{
	struct ctx *c = *state;

	c->fb.noise = 50;
	assert_int_equal(sw_cmd_accel_cal(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_CAL);
	assert_non_null(strstr(c->e.msg, "moved"));
	c->fb.noise = 0;
	c->fb.bias[2] = -2048;	/* lying on its side */
	sw_err_clear(&c->e);
	assert_int_equal(sw_cmd_accel_cal(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_CAL);
	assert_non_null(strstr(c->e.msg, "Z facing down"));
	assert_int_equal(c->fb.offset[2], 0);
	c->fb.bias[2] = 10;
	c->fb.offset_readback_wrong = true;
	sw_err_clear(&c->e);
	assert_int_equal(sw_cmd_accel_cal(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_CAL);
	assert_non_null(strstr(c->e.msg, "read back"));
}

/*
 * Issue 14.3: accel-cal added the chip's current offset to the measured
 * error in int (old + lround(...)): an offset near INT_MAX overflowed.
 */
static void test_accel_cal_distrusts_offsets(void **state)
{
	struct ctx *c = *state;
	static const int lying[3] = { 2147483647, 0, 0 };

	c->fb.bias[0] = 40;
	c->fb.offset_reported = lying;
	assert_int_equal(sw_cmd_accel_cal(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_IO);
	assert_non_null(strstr(c->e.msg, "offset reads 2147483647 LSB, out of range"));
	assert_int_equal(c->fb.offset[0], 0);
}


/*
 * Issue 19.3: accel offsets are the user's work. After accel-cal, a save
 * with a calibration worse than the saved file's said "not saving" and
 * exited 0, and the offsets were lost at the next boot. They go into the
 * saved file, which keeps its own magnetic calibration and header.
 */
static void test_save_keeps_accel_offsets(void **state)
{
	struct ctx *c = *state;
	struct sw_file f;

	c->fb.cs.score_raw = sw_score_raw(2.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	/* later, a worse calibration and the user's new offsets */
	c->fb.cs.score_raw = sw_score_raw(4.0);
	sw_blob_set_param(c->fb.blob, 18, 99.0f);
	c->fb.offset[0] = -47;
	c->fb.offset[1] = -15;
	c->fb.offset[2] = 46;
	c->clk.wall_s += 60;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "saved iio:device0 accel offsets -47 -15 46 LSB to "));
	assert_non_null(strstr(out_text(c), "the accel offsets differ from the saved file's; its calibration (level 4 (stable), score 1.999%) is kept: score 4.001% is worse"));
	assert_true(load(c, &f));
	assert_int_equal(f.state, 4);
	assert_int_equal(f.score_raw, sw_score_raw(2.0));
	assert_true(sw_blob_param(f.payload, 18) == 9.0f);
	assert_int_equal(sw_get_le32(f.payload + 4 * 26), 0xbcbbe447);
	assert_int_equal(sw_get_le32(f.payload + 4 * 27), 0xbbefdc9c);
	assert_int_equal(sw_get_le32(f.payload + 4 * 28), 0x3cb7e4de);
	assert_true(f.saved_at == c->clk.wall_s);
	/* Once: the same offsets again are no reason. */
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "not saving iio:device0 calibration"));
	/* A better calibration takes everything, offsets included. */
	c->fb.cs.score_raw = sw_score_raw(1.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, sw_score_raw(1.0));
	assert_true(sw_blob_param(f.payload, 18) == 99.0f);
	assert_int_equal(sw_get_le32(f.payload + 4 * 26), 0xbcbbe447);
}

/*
 * Offsets with no saved file: the chip's blob as it is, but only once it
 * is stable (level 4); a --force'd file of a calibration not stable is
 * restored without waiting for a level it never had. Zero offsets (a chip
 * not restored since power-on) never replace saved ones.
 */
static void test_save_offsets_without_file(void **state)
{
	struct ctx *c = *state;
	struct sw_file f;
	uint64_t t0;

	c->fb.cs.level = 1;
	c->fb.cs.score_raw = sw_score_raw(20.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_int_equal(access(c->path, F_OK), -1);
	c->fb.offset[2] = 46;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "the chip's accel offsets are saved with its calibration once it is stable"));
	assert_int_equal(access(c->path, F_OK), -1);
	c->fb.cs.level = 4;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "the chip holds accel offsets and no usable file does: saving its calibration as it is, although score 20.001% is above the limit"));
	assert_true(load(c, &f));
	assert_int_equal(f.state, 4);
	assert_int_equal(sw_g_to_lsb(sw_blob_param(f.payload, 29)), 46);

	/* forced while unreliable; the next boot's offsets at their zero */
	c->fb.cs.level = 1;
	c->o.force = true;
	assert_int_equal(save(c), SW_EXIT_OK);
	c->o.force = false;
	c->fb.offset[2] = 0;
	c->fb.level_after_write = -1;
	t0 = c->clk.now_ms;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.offset[2], 46);
	assert_true(c->clk.now_ms - t0 < 100);
	assert_non_null(strstr(out_text(c), ": level 1 (unreliable sensor data), score 20.001% (saved: level 1 (unreliable sensor data), score 20.001%)"));

	c->fb.cs.level = 4;
	c->fb.cs.score_raw = sw_score_raw(2.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	/* a boot without a restore: offsets 0, a worse calibration */
	c->fb.offset[2] = 0;
	c->fb.cs.score_raw = sw_score_raw(3.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "not saving"));
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, sw_score_raw(2.0));
	assert_int_equal(sw_g_to_lsb(sw_blob_param(f.payload, 29)), 46);
}

/* accel-cal saves what it calibrated, unless --no-save. */
static void test_accel_cal_saves(void **state)
{
	struct ctx *c = *state;
	struct sw_file f;

	c->fb.cs.score_raw = sw_score_raw(2.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	c->fb.cs.score_raw = sw_score_raw(4.0);
	c->fb.bias[0] = -47;
	c->fb.bias[2] = 46;
	c->o.no_save = true;
	assert_int_equal(sw_cmd_accel_cal(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "Run 'save' to keep them."));
	assert_true(load(c, &f));
	assert_int_equal(sw_g_to_lsb(sw_blob_param(f.payload, 27)), 0);

	c->fb.bias[0] = -40;
	c->o.no_save = false;
	assert_int_equal(sw_cmd_accel_cal(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "saved iio:device0 accel offsets -40 0 46 LSB to "));
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, sw_score_raw(2.0));
	assert_int_equal(sw_g_to_lsb(sw_blob_param(f.payload, 27)), -40);
	assert_int_equal(sw_g_to_lsb(sw_blob_param(f.payload, 29)), 46);
}

/*
 * Issue 19.4: one glitched read (a raw score of 0x0000, -100 %) looked
 * like the best calibration and the target reached: calibrate stopped at
 * once, the save refused the value and the good snapshot was lost. It is
 * skipped; the good calibration that follows is saved.
 */
static const struct fake_step cal_glitch[] = {
	{ 0, 2, 0xffff, 1 },
	{ 500, 2, 0xffff, 1 },
	{ 2000, 4, 0x8000 + 1400, 0 },	/* 4.3 % */
	{ 3000, 4, 0x0000, 0 },		/* a bad read */
	{ 3300, 7, 0x8000 + 100, 0 },	/* another: level 7 */
	{ 3400, FAKE_GLITCH, 0x8000, 0 }, /* the driver's EIO, twice */
	{ 3600, 4, 0x8000 + 1200, 0 },	/* 3.7 % */
	{ 6000, 4, 0x8000 + 900, 0 },	/* 2.747 %: done */
};

static void test_calibrate_glitch(void **state)
{
	struct ctx *c = *state;
	struct sw_file f;

	c->clk.now_ms = 0;
	c->fb.script = cal_glitch;
	c->fb.nsteps = sizeof(cal_glitch) / sizeof(cal_glitch[0]);
	c->fb.blob_follows_score = true;
	c->fb.mag = mag_sphere;
	assert_int_equal(sw_cmd_calibrate(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_true(c->clk.now_ms >= 6000 && c->clk.now_ms < 7000);
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, 0x8000 + 900);
	assert_true(sw_blob_param(f.payload, 18) == (float)(0x8000 + 900));
	assert_null(strstr(out_text(c), "-100.000"));
}

/* An update flag left from before the calibration started is not one. */
static void test_calibrate_stale_gyro_flag(void **state)
{
	static const struct fake_step stale[] = {
		{ 0, 2, 0xffff, 1 },
	};
	struct ctx *c = *state;

	c->clk.now_ms = 0;
	c->o.timeout_s = 5;
	c->fb.script = stale;
	c->fb.nsteps = 1;
	assert_int_equal(sw_cmd_calibrate(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_CAL);
	assert_non_null(strstr(c->e.msg, "gyro bias not learned within 5 s"));
}

struct lock_probe {
	const char *path;
	int tries, busy;
};

/* Another writer's view at the moment the policy looks at the chip. */
static void try_lock(struct fake_be *f)
{
	struct lock_probe *p = f->data;
	struct sw_err e;
	int fd;

	sw_err_clear(&e);
	fd = sw_file_lock_open(p->path, true, &e);
	assert_true(fd >= 0);
	p->tries++;
	if (!sw_file_lock_try(fd))
		p->busy++;
	close(fd);
}

/*
 * Issue 19.4: writers take turns. The lock is held from the policy's look
 * at the saved file (the chip's identity is read just before it) to the
 * rename, and released after.
 */
static void test_save_holds_lock(void **state)
{
	struct ctx *c = *state;
	struct lock_probe p = { .path = c->path };
	char lock[160];
	struct stat st;
	int fd;

	c->fb.on_chip_info = try_lock;
	c->fb.data = &p;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_int_equal(p.tries, 1);
	assert_int_equal(p.busy, 1);
	c->fb.on_chip_info = NULL;
	fd = sw_file_lock_open(c->path, true, &c->e);
	assert_true(sw_file_lock_try(fd));
	close(fd);
	snprintf(lock, sizeof(lock), "%s/.platform-sentral-sim-0x28.ws.lock",
		 c->dir);
	assert_int_equal(lstat(lock, &st), 0);
	assert_int_equal(st.st_mode & 07777, 0600);
}

/*
 * A writer that holds the lock for ever: the next one waits 30 s, then
 * fails naming the lock file, and the saved file is untouched.
 */
static void test_save_lock_timeout(void **state)
{
	struct ctx *c = *state;
	struct sw_file f;
	uint64_t t0;
	int fd;

	c->fb.cs.score_raw = sw_score_raw(3.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	fd = sw_file_lock_open(c->path, true, &c->e);
	assert_true(sw_file_lock_try(fd));
	c->fb.cs.score_raw = sw_score_raw(1.0);
	t0 = c->clk.now_ms;
	assert_int_equal(save(c), SW_EXIT_IO);
	assert_true(c->clk.now_ms - t0 >= 30000 && c->clk.now_ms - t0 < 31000);
	assert_non_null(strstr(c->e.msg, "/.platform-sentral-sim-0x28.ws.lock: another writer of "));
	assert_non_null(strstr(c->e.msg, "has held it for 30 s"));
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, sw_score_raw(3.0));
	close(fd);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, sw_score_raw(1.0));
}

/* The lock file is refused through a symlink, like the saved file. */
static void test_lock_refuses_symlink(void **state)
{
	struct ctx *c = *state;
	char lock[160], target[160];

	snprintf(lock, sizeof(lock), "%s/.platform-sentral-sim-0x28.ws.lock",
		 c->dir);
	snprintf(target, sizeof(target), "%s/elsewhere", c->dir);
	assert_int_equal(symlink(target, lock), 0);
	assert_int_equal(save(c), SW_EXIT_PERM);
	assert_non_null(strstr(c->e.msg, "symbolic link"));
	assert_int_equal(access(target, F_OK), -1);
	assert_int_equal(access(c->path, F_OK), -1);
}

/* A refused file that a save replaced meanwhile is not moved aside. */
static void replace_file(struct fake_be *f)
{
	struct ctx *c = f->data;
	struct sw_file nf;
	uint8_t buf[SW_FILE_SIZE];
	struct sw_err e;

	memset(&nf, 0, sizeof(nf));
	nf.chip = f->chip;
	nf.version = SW_FILE_VERSION;
	nf.state = 4;
	nf.judgement = SW_JUDGED_SCORE;
	nf.score_raw = sw_score_raw(1.5);
	fake_fill_blob(nf.payload);
	sw_file_encode(&nf, buf);
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(c->path, buf, sizeof(buf), true,
					      &e), SW_EXIT_OK);
}

static void test_restore_set_aside_checks_again(void **state)
{
	struct ctx *c = *state;
	struct sw_file f;

	assert_int_equal(save(c), SW_EXIT_OK);
	c->fb.chip.rom_version = 0x07a8;
	c->fb.on_chip_info = replace_file;
	c->fb.data = c;
	assert_int_equal(restore(c), SW_EXIT_FILE);
	assert_non_null(strstr(c->e.msg, "not moved aside: it changed meanwhile"));
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, sw_score_raw(1.5));
}

/* What the driver's errno means, and what to do about it. */
static void test_iio_errors(void **state)
{
	struct sw_err e;

	(void)state;
	sw_err_clear(&e);
	assert_int_equal(sw_iio_err(&e, "iio:device2", "writing", "calibration_data",
				    EBUSY, false), SW_EXIT_IO);
	assert_string_equal(e.msg, "iio:device2: writing calibration_data: Device or resource busy: a buffer is enabled on iio:device2 (a program is streaming from it, or one that exited without disabling it): stop it, or write 0 to /sys/bus/iio/devices/iio:device2/buffer/enable");
	sw_err_clear(&e);
	assert_int_equal(sw_iio_err(&e, "iio:device0", "reading",
				    "in_magn_calibration_auto_status", ENODEV,
				    false), SW_EXIT_DEVICE);
	assert_non_null(strstr(e.msg, "iio:device0 is gone (unbound or unplugged)"));
	sw_err_clear(&e);
	assert_int_equal(sw_iio_err(&e, "iio:device0", "reading",
				    "in_magn_calibration_auto_status", ENOENT,
				    true), SW_EXIT_DEVICE);
	assert_non_null(strstr(e.msg, "is gone"));
	sw_err_clear(&e);
	assert_int_equal(sw_iio_err(&e, "iio:device0", "reading",
				    "in_magn_calibration_update", ENOENT,
				    false), SW_EXIT_DRIVER);
	assert_non_null(strstr(e.msg, "no such attribute: it is older or newer than this tool"));
	sw_err_clear(&e);
	assert_int_equal(sw_iio_err(&e, "iio:device0", "writing",
				    "calibration_data", ETIMEDOUT, false),
			 SW_EXIT_IO);
	assert_non_null(strstr(e.msg, "did not acknowledge"));
}

/* Score in percent as the script's raw value. */
#define PCT(p) ((uint16_t)(0x8000 + (int)((p) * 327.68 + 0.5)))

/*
 * A calibration that keeps moving, looked at every 30 s (the default):
 * saves at most every 300 s, only 0.5 points better than the saved file,
 * and each a poll after the change at most.
 */
static const struct fake_step drifting[] = {
	{ 0, 2, PCT(50.0), 0 },
	{ 45000, 4, PCT(3.0), 0 },	/* first good one: saved at 60 s */
	{ 75000, 4, PCT(2.8), 0 },	/* 0.2 better: not worth a write */
	{ 105000, 4, PCT(2.4), 0 },	/* 0.6 better, 60 s after the write */
	{ 200000, 4, PCT(2.3), 0 },	/* still waiting: saved at 360 s */
	{ 400000, 2, PCT(10.0), 0 },	/* the field changed */
	{ 500000, 4, PCT(2.0), 0 },	/* 0.3 better than 2.3 */
	{ 700000, 4, PCT(1.7), 0 },	/* 0.6 better, interval past: 720 s */
};

static int count(const char *s, const char *what)
{
	int n = 0;

	while ((s = strstr(s, what))) {
		n++;
		s += strlen(what);
	}
	return n;
}

static int watch(struct ctx *c)
{
	sw_err_clear(&c->e);
	return sw_cmd_watch(&c->fb.b, &c->o, &c->env, &c->e);
}

static void watch_defaults(struct ctx *c, const struct fake_step *steps,
			   size_t n, uint64_t gone_ms)
{
	c->clk.now_ms = 0;
	c->o.poll_s = 30;
	c->o.interval_s = 300;
	c->o.margin = 0.5;
	c->fb.script = steps;
	c->fb.nsteps = n;
	c->fb.gone_ms = gone_ms;
}

static void test_watch(void **state)
{
	struct ctx *c = *state;
	struct sw_file f;

	watch_defaults(c, drifting, sizeof(drifting) / sizeof(drifting[0]),
		       800000);
	c->fb.blob_follows_score = true;
	assert_int_equal(watch(c), SW_EXIT_DEVICE);
	assert_int_equal(count(out_text(c), "saved iio:device0 calibration"), 3);
	assert_non_null(strstr(out_text(c), "score 3.000% is within the limit"));
	assert_non_null(strstr(out_text(c), "score 2.301% is better than the saved 3.000%"));
	assert_non_null(strstr(out_text(c), "score 1.700% is better than the saved 2.301%"));
	/* told once that a save waits, with when */
	assert_int_equal(count(out_text(c), "but the last write was"), 1);
	assert_non_null(strstr(out_text(c), "the last write was 60 s ago: saving it in 240 s"));
	/* the snapshot of the chip at 720 s is the one saved then */
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, PCT(1.7));
	assert_true(sw_blob_param(f.payload, 18) == (float)PCT(1.7));
	assert_true(f.saved_at == c->clk.wall_s);
	/*
	 * One look every 30 s from 0 to 780 s, and a save's look before and
	 * after its read of the blob; the blob is read for the saves only.
	 */
	assert_int_equal(c->fb.state_reads, 27 + 3 * 2);
	assert_int_equal(c->fb.reads, 3);
}

/*
 * At the defaults a newly complete and better calibration is saved within
 * one poll (30 s), never a minute late.
 */
static void test_watch_notices_within_a_poll(void **state)
{
	static const struct fake_step steps[] = {
		{ 0, 2, PCT(30.0), 0 },
		{ 61000, 4, PCT(2.7), 0 },
	};
	struct ctx *c = *state;
	struct sw_file f;

	watch_defaults(c, steps, 2, 95000);
	assert_int_equal(watch(c), SW_EXIT_DEVICE);
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, PCT(2.7));
	assert_int_equal(count(out_text(c), "saved iio:device0 calibration"), 1);
	/* polls at 0, 30, 60 and 90 s: saved at 90 s, 29 s after the change */
	assert_int_equal(c->fb.state_reads, 4 + 2);
}

/*
 * The device unbound or unplugged: noticed at the next look, exit 69 with
 * a message that says so, never a loop of errors.
 */
static void test_watch_device_gone(void **state)
{
	static const struct fake_step steps[] = {
		{ 0, 4, PCT(3.0), 0 },
	};
	struct ctx *c = *state;

	watch_defaults(c, steps, 1, 100000);
	c->o.poll_s = 7;
	assert_int_equal(watch(c), SW_EXIT_DEVICE);
	assert_int_equal(SW_EXIT_DEVICE, 69);
	assert_true(c->clk.now_ms >= 100000 && c->clk.now_ms < 107000);
	assert_non_null(strstr(c->e.msg, "iio:device0 is gone (unbound or unplugged)"));
	assert_non_null(strstr(c->e.msg, "; stopped watching it"));
	fflush(c->errf);
	assert_int_equal(count(c->err, "error"), 0);
	assert_null(strstr(out_text(c), "stopped watching iio:device0"));
}

/* A margin of 0: any better score is saved, an equal one never. */
static void test_watch_margin_zero(void **state)
{
	static const struct fake_step steps[] = {
		{ 0, 4, PCT(3.0), 0 },
		{ 400000, 4, PCT(3.0), 0 },
		{ 800000, 4, PCT(2.99), 0 },
	};
	struct ctx *c = *state;

	watch_defaults(c, steps, 3, 900000);
	c->o.margin = 0;
	assert_int_equal(watch(c), SW_EXIT_DEVICE);
	assert_int_equal(count(out_text(c), "saved iio:device0 calibration"), 2);
}

static void unlink_after_100s(struct fake_be *f)
{
	if (f->clk->now_ms >= 100000)
		unlink(f->data);
}

/*
 * A state directory that cannot be used is reported once, not at every
 * look, and the calibration is saved at the first look after it is
 * repaired.
 */
static void test_watch_state_dir_repaired(void **state)
{
	static const struct fake_step steps[] = {
		{ 0, 4, PCT(3.0), 0 },
	};
	struct ctx *c = *state;
	char sub[160];

	watch_defaults(c, steps, 1, 200000);
	snprintf(sub, sizeof(sub), "%s/sub", c->dir);
	c->o.state_dir = sub;
	/* a state directory that cannot be made: a file in its way */
	assert_int_equal(close(open(sub, O_CREAT | O_WRONLY, 0600)), 0);
	c->fb.on_chip_info = unlink_after_100s;
	c->fb.data = sub;
	assert_int_equal(watch(c), SW_EXIT_DEVICE);
	fflush(c->errf);
	assert_int_equal(count(c->err, "sentral-warmstart: error:"), 1);
	assert_int_equal(count(out_text(c), "watch: looking again every 30 s"), 1);
	assert_int_equal(count(out_text(c), "saved iio:device0 calibration"), 1);
	snprintf(sub, sizeof(sub), "%s/sub/platform-sentral-sim-0x28.ws", c->dir);
	assert_int_equal(access(sub, F_OK), 0);
}

/*
 * Accel offsets written (accel-cal, calibbias) are saved by the watcher
 * too, once, into the saved file: its worse-or-equal calibration does not
 * replace the better one saved.
 */
static void test_watch_saves_offsets(void **state)
{
	static const struct fake_step steps[] = {
		{ 0, 4, PCT(2.0), 0 },
		{ 100000, 4, PCT(2.2), 0 },
	};
	struct ctx *c = *state;
	struct sw_file f;

	watch_defaults(c, steps, 2, 1000000);
	c->fb.offset[0] = 12;
	c->fb.nsteps = 1;
	assert_int_equal(save(c), SW_EXIT_OK);
	c->fb.nsteps = 2;
	c->clk.now_ms = 0;
	assert_int_equal(watch(c), SW_EXIT_DEVICE);
	assert_int_equal(count(out_text(c), "saved iio:device0"), 1);
	/* the user's offsets, a minute later */
	c->fb.offset[0] = -47;
	c->fb.offset[2] = 46;
	c->clk.now_ms = 0;
	c->fb.gone_ms = 1000000;
	assert_int_equal(watch(c), SW_EXIT_DEVICE);
	assert_int_equal(count(out_text(c), "saved iio:device0 accel offsets -47 0 46 LSB"), 1);
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, PCT(2.0));
	assert_int_equal(sw_g_to_lsb(sw_blob_param(f.payload, 27)), -47);
	assert_int_equal(sw_g_to_lsb(sw_blob_param(f.payload, 29)), 46);
}

/* import-board: an EEPROM image written to DIR/eeprom, imported. */
static int import_image(struct ctx *c, const uint8_t *img, size_t len,
			enum sw_board_layout l, bool force)
{
	struct sw_opts o = c->o;
	char image[160];
	FILE *f;

	snprintf(image, sizeof(image), "%s/eeprom", c->dir);
	f = fopen(image, "w");
	assert_non_null(f);
	assert_int_equal(fwrite(img, 1, len, f), len);
	assert_int_equal(fclose(f), 0);
	o.image = image;
	o.layout = l;
	o.force = force;
	sw_err_clear(&c->e);
	return sw_cmd_import_board(&c->fb.b, &o, &c->env, &c->e);
}

/* The state directory holds the writers' lock file at most: no state file. */
static void assert_nothing_written(struct ctx *c)
{
	struct stat st;
	char cmd[200];

	assert_int_equal(lstat(c->path, &st), -1);
	snprintf(cmd, sizeof(cmd),
		 "test -z \"$(ls -A '%s' | grep -v -x -e eeprom -e '.platform-sentral-sim-0x28.ws.lock')\"",
		 c->dir);
	assert_int_equal(system(cmd), 0);
}

static void test_import_board(void **state)
{
	static uint8_t img[SW_BOARD_EEPROM_SIZE];
	struct ctx *c = *state;
	uint8_t blob[SW_BLOB_SIZE];
	struct sw_file f;
	struct stat st;

	fake_board_image(img, SW_BOARD_GT);
	/* The chip holds something else: the import takes the board's. */
	sw_blob_set_param(c->fb.blob, 18, 9.0f);
	fake_fill_blob(blob);
	assert_int_equal(import_image(c, img, sizeof(img), SW_BOARD_GT, false),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c),
			       "imported iio:device0's calibration from the board's EEPROM (gt layout, parameters at 0x8000)"));
	assert_non_null(strstr(out_text(c), "x 2049/-2047"));
	assert_non_null(strstr(out_text(c), "is not imported"));
	assert_true(load(c, &f));
	assert_memory_equal(f.payload, blob, SW_BLOB_SIZE);
	/* The chip's identity, as save records it; no status or score known. */
	assert_int_equal(f.chip.product_id, 0x80);
	assert_int_equal(f.chip.rom_version, 0x09e6);
	assert_int_equal(f.chip.ram_version, c->fb.chip.ram_version);
	assert_int_equal(f.version, 2);
	assert_int_equal(f.judgement, SW_JUDGED_NONE);
	assert_int_equal(f.state, 0);
	assert_int_equal(f.score_raw, 0);
	assert_true(f.saved_at == 1800000000);
	assert_int_equal(stat(c->path, &st), 0);
	assert_int_equal(st.st_mode & 0777, 0600);
	assert_int_equal(c->fb.writes, 0);

	/* restore writes exactly the board's parameters to the chip. */
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 1);
	assert_memory_equal(c->fb.blob, blob, SW_BLOB_SIZE);

	/*
	 * A stable calibration the chip reaches later replaces the import,
	 * by either rule: the import is not stable.
	 */
	sw_blob_set_param(c->fb.blob, 18, 7.0f);
	c->fb.cs.level = 4;
	c->fb.cs.score_raw = sw_score_raw(4.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.state, 4);
	assert_int_equal(f.judgement, SW_JUDGED_SCORE);
	assert_true(sw_blob_param(f.payload, 18) == 7.0f);
	assert_int_equal(import_image(c, img, sizeof(img), SW_BOARD_GT, true),
			 SW_EXIT_OK);
	level_only(c);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "stable, and the saved calibration (imported from the board's EEPROM) is not"));
	assert_true(load(c, &f));
	assert_int_equal(f.judgement, SW_JUDGED_STABLE);
	assert_true(sw_blob_param(f.payload, 18) == 7.0f);
}

static void test_import_board_kw(void **state)
{
	static uint8_t img[SW_BOARD_EEPROM_SIZE];
	struct ctx *c = *state;
	uint8_t blob[SW_BLOB_SIZE];
	struct sw_file f;

	fake_board_image(img, SW_BOARD_KW);
	fake_fill_blob(blob);
	/* The default layout finds nothing, and says where to look. */
	assert_int_equal(import_image(c, img, sizeof(img), SW_BOARD_GT, false),
			 SW_EXIT_FILE);
	assert_non_null(strstr(c->e.msg, "--layout kw"));
	assert_nothing_written(c);
	assert_int_equal(import_image(c, img, sizeof(img), SW_BOARD_KW, false),
			 SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_memory_equal(f.payload, blob, SW_BLOB_SIZE);
}

static void test_import_board_refusals(void **state)
{
	static uint8_t img[SW_BOARD_EEPROM_SIZE];
	struct ctx *c = *state;
	struct sw_opts o = c->o;

	/* A blank (erased) EEPROM. */
	memset(img, 0xff, sizeof(img));
	assert_int_equal(import_image(c, img, sizeof(img), SW_BOARD_GT, false),
			 SW_EXIT_FILE);
	assert_non_null(strstr(c->e.msg,
			       "refused: no calibration saved (erased) (bytes 0x8000..0x808b are all 0xff); nothing written"));
	assert_nothing_written(c);

	/* The utility's marker damaged. */
	fake_board_image(img, SW_BOARD_GT);
	img[0x8098] = 0xab;
	assert_int_equal(import_image(c, img, sizeof(img), SW_BOARD_GT, true),
			 SW_EXIT_FILE);
	assert_non_null(strstr(c->e.msg,
			       "refused: no valid-block marker (byte 0x8098 is 0xab, not 0xaa)"));
	assert_nothing_written(c);

	/* A parameter that is not a number. */
	fake_board_image(img, SW_BOARD_GT);
	sw_put_le32(img + 0x8000 + 4 * 20, 0x7fc00000);
	assert_int_equal(import_image(c, img, sizeof(img), SW_BOARD_GT, true),
			 SW_EXIT_FILE);
	assert_non_null(strstr(c->e.msg,
			       "refused: non-finite float (parameter 21"));
	assert_nothing_written(c);

	/* A dump cut short inside the block; an empty one. */
	fake_board_image(img, SW_BOARD_GT);
	assert_int_equal(import_image(c, img, 0x8050, SW_BOARD_GT, true),
			 SW_EXIT_FILE);
	assert_non_null(strstr(c->e.msg, "refused: image too short (32848 bytes"));
	assert_nothing_written(c);
	assert_int_equal(import_image(c, img, 0, SW_BOARD_GT, true),
			 SW_EXIT_FILE);
	assert_nothing_written(c);

	/* No image at all. */
	o.image = "/nonexistent/eeprom";
	sw_err_clear(&c->e);
	assert_int_equal(sw_cmd_import_board(&c->fb.b, &o, &c->env, &c->e),
			 SW_EXIT_NOFILE);
	assert_non_null(strstr(c->e.msg, "EEPROM image /nonexistent/eeprom does not exist"));
	assert_nothing_written(c);
	assert_int_equal(c->fb.writes, 0);
}

static void test_import_board_keeps_saved(void **state)
{
	static uint8_t img[SW_BOARD_EEPROM_SIZE];
	struct ctx *c = *state;
	uint8_t before[SW_FILE_SIZE], after[SW_FILE_SIZE];
	uint8_t blob[SW_BLOB_SIZE];
	struct sw_file f;
	FILE *fp;

	/* A calibration saved here first. */
	c->fb.cs.score_raw = sw_score_raw(2.9);
	assert_int_equal(save(c), SW_EXIT_OK);
	fp = fopen(c->path, "r");
	assert_int_equal(fread(before, 1, sizeof(before), fp), sizeof(before));
	fclose(fp);

	/* Without --force it stays, byte for byte; the command succeeds. */
	fake_board_image(img, SW_BOARD_GT);
	sw_blob_set_param(img + 0x8000, 5, 123.0f);
	assert_int_equal(import_image(c, img, sizeof(img), SW_BOARD_GT, false),
			 SW_EXIT_OK);
	assert_non_null(strstr(out_text(c),
			       "not importing the board's calibration for iio:device0"));
	assert_non_null(strstr(out_text(c), "(--force replaces it)"));
	fp = fopen(c->path, "r");
	assert_int_equal(fread(after, 1, sizeof(after), fp), sizeof(after));
	fclose(fp);
	assert_memory_equal(before, after, sizeof(before));

	/* With --force the board's calibration replaces it. */
	assert_int_equal(import_image(c, img, sizeof(img), SW_BOARD_GT, true),
			 SW_EXIT_OK);
	assert_true(load(c, &f));
	fake_fill_blob(blob);
	sw_blob_set_param(blob, 5, 123.0f);
	assert_memory_equal(f.payload, blob, SW_BLOB_SIZE);
	assert_int_equal(f.judgement, SW_JUDGED_NONE);
}

/* The state file as a given version and header would have it. */
static void put_state_file(struct ctx *c, int version, int state,
			   enum sw_judgement j, uint16_t score_raw)
{
	uint8_t buf[SW_FILE_SIZE];
	struct sw_file f;
	struct sw_err e;

	memset(&f, 0, sizeof(f));
	f.chip = c->fb.chip;
	f.version = version;
	f.state = state;
	f.judgement = j;
	f.score_raw = score_raw;
	f.saved_at = 1700000000;
	fake_fill_blob(f.payload);
	sw_file_encode(&f, buf);
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(c->path, buf, sizeof(buf), true,
					      &e), SW_EXIT_OK);
}

/* The state file's bytes, to tell that nothing was written. */
static void file_bytes(struct ctx *c, uint8_t *buf)
{
	FILE *fp = fopen(c->path, "r");

	assert_non_null(fp);
	assert_int_equal(fread(buf, 1, SW_FILE_SIZE, fp), SW_FILE_SIZE);
	fclose(fp);
}

/*
 * Issue 31: firmware without the application note's score (a USFS
 * board). save judges by the level and the coefficients: a stable
 * calibration is saved when no usable file exists or a magnetometer
 * coefficient (18-23) moved beyond 0.5 % (of 1 below 1); never at a
 * level below 4. Before, it exited 78 ("not reported").
 */
static void test_save_stable_rule(void **state)
{
	struct ctx *c = *state;
	uint8_t before[SW_FILE_SIZE], after[SW_FILE_SIZE];
	struct sw_file f;
	int lv;

	level_only(c);
	/* no file + stable: saved */
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "saved iio:device0 calibration to "));
	assert_non_null(strstr(out_text(c), ": stable, and no usable saved calibration\n"));
	assert_true(load(c, &f));
	assert_int_equal(f.version, 2);
	assert_int_equal(f.state, 4);
	assert_int_equal(f.judgement, SW_JUDGED_STABLE);
	assert_int_equal(f.score_raw, 0);
	assert_memory_equal(f.payload, c->fb.blob, SW_BLOB_SIZE);

	/* stable, the same coefficients: not written again */
	file_bytes(c, before);
	c->clk.wall_s += 600;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "not saving iio:device0 calibration to "));
	assert_non_null(strstr(out_text(c), "stable, and the magnetometer coefficients (parameters 18-23) are within 0.5 % of the saved file's"));
	file_bytes(c, after);
	assert_memory_equal(before, after, SW_FILE_SIZE);

	/* within the tolerance (9.5 * 1.004), and the rest moving: no */
	sw_blob_set_param(c->fb.blob, 19, 9.5f * 1.004f);
	sw_blob_set_param(c->fb.blob, 33, 1.0f);
	assert_int_equal(save(c), SW_EXIT_OK);
	file_bytes(c, after);
	assert_memory_equal(before, after, SW_FILE_SIZE);

	/* beyond it (9.5 * 1.006): saved */
	sw_blob_set_param(c->fb.blob, 19, 9.5f * 1.006f);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "stable, and parameter 19 (mcoeffs[2]) moved from the saved file's by more than 0.5 %"));
	assert_true(load(c, &f));
	assert_true(sw_blob_param(f.payload, 19) == 9.5f * 1.006f);
	assert_true(f.saved_at == c->clk.wall_s);

	/* levels 3, 2, 1 and 0 never save, however far it moved */
	file_bytes(c, before);
	sw_blob_set_param(c->fb.blob, 20, 100.0f);
	for (lv = 3; lv >= 0; lv--) {
		c->fb.cs.level = lv;
		assert_int_equal(save(c), SW_EXIT_OK);
		file_bytes(c, after);
		assert_memory_equal(before, after, SW_FILE_SIZE);
	}
	assert_non_null(strstr(out_text(c), "calibration not stable (level 3 (stable with a magnetic transient); needs 4)"));
	assert_non_null(strstr(out_text(c), "calibration not stable (level 2 (calibrating); needs 4): move the device in a figure-8 first"));
	assert_non_null(strstr(out_text(c), "(level 1 (unreliable sensor data); needs 4): the sensor data is unreliable"));
	assert_non_null(strstr(out_text(c), "(level 0 (halted); needs 4): the fusion algorithm is halted (standby)"));
	/* --force takes it, as the level it is at */
	c->o.force = true;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.state, 0);
	assert_int_equal(f.judgement, SW_JUDGED_STABLE);
}

/*
 * A glitch (the driver's EIO, a level out of range) is an error and
 * writes nothing; so is a calibration that was stable before the blob
 * read and not after it (or the other way round): the blob is judged by
 * the worse of the two states.
 */
static void test_save_glitch_and_change(void **state)
{
	struct ctx *c = *state;
	uint8_t before[SW_FILE_SIZE], after[SW_FILE_SIZE];
	int rule;

	for (rule = 0; rule < 2; rule++) {
		if (rule)
			level_only(c);
		c->fb.cs.level = 4;
		c->fb.level_after_read = -1;
		c->o.force = true;
		assert_int_equal(save(c), SW_EXIT_OK);
		c->o.force = false;
		file_bytes(c, before);
		sw_blob_set_param(c->fb.blob, 18, 50.0f + rule);
		c->fb.cs.score_raw = sw_score_raw(1.0);

		c->fb.cs.level = FAKE_GLITCH;
		c->fb.reads = 0;
		assert_int_equal(save(c), SW_EXIT_IO);
		assert_non_null(strstr(c->e.msg, "in_magn_calibration_auto_status: Input/output error"));
		assert_int_equal(c->fb.reads, 0);
		c->fb.cs.level = 9;
		assert_int_equal(save(c), SW_EXIT_IO);
		assert_non_null(strstr(c->e.msg, "level 9 is not 0..4, read from the chip: not saving"));
		file_bytes(c, after);
		assert_memory_equal(before, after, SW_FILE_SIZE);

		/* stable, then a transient under the read */
		c->fb.cs.level = 4;
		c->fb.level_after_read = 3;
		assert_int_equal(save(c), SW_EXIT_OK);
		assert_non_null(strstr(out_text(c), "calibration not stable (level 3"));
		/* calibrating, then stable under the read */
		c->fb.cs.level = 2;
		c->fb.level_after_read = 4;
		assert_int_equal(save(c), SW_EXIT_OK);
		file_bytes(c, after);
		assert_memory_equal(before, after, SW_FILE_SIZE);
		/* stable on both reads: saved */
		c->fb.level_after_read = -1;
		assert_int_equal(save(c), SW_EXIT_OK);
		file_bytes(c, after);
		assert_memory_not_equal(before, after, SW_FILE_SIZE);
	}
}

/*
 * Files of either rule and version restore on either firmware: a
 * version 1 file (status 3 and a score) on a chip without a score, a
 * version 2 file saved by the stable rule on a chip with one. A stable
 * file waits for the level to come back (3 or 4), any other does not.
 */
static void test_restore_across_rules(void **state)
{
	struct ctx *c = *state;
	uint8_t blob[SW_BLOB_SIZE];
	struct sw_file f;

	fake_fill_blob(blob);
	put_state_file(c, SW_FILE_VERSION_1, 3, SW_JUDGED_SCORE,
		       sw_score_raw(2.0));
	level_only(c);
	c->fb.cs.level = 2;
	memset(c->fb.blob, 0, SW_BLOB_SIZE);
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 1);
	assert_memory_equal(c->fb.blob, blob, SW_BLOB_SIZE);
	assert_non_null(strstr(out_text(c), ": level 4 (stable) (saved: version 1: status 3, score 1.999%)\n"));
	/* the stable rule finds the chip holding it: nothing to write */
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "are within 0.5 % of the saved file's"));
	assert_true(load(c, &f));
	assert_int_equal(f.version, 1);
	/* new accel offsets: the file goes to version 2, its header kept */
	c->fb.cs.level = 2;
	c->fb.offset[0] = -47;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.version, 2);
	assert_int_equal(f.state, 4);
	assert_int_equal(f.judgement, SW_JUDGED_SCORE);
	assert_int_equal(f.score_raw, sw_score_raw(2.0));
	assert_int_equal(sw_g_to_lsb(sw_blob_param(f.payload, 27)), -47);

	/* a transient right after the restore is no failure */
	c->fb.level_after_write = 3;
	assert_int_equal(restore(c), SW_EXIT_OK);
	/* a version 1 file saved incomplete does not wait */
	put_state_file(c, SW_FILE_VERSION_1, 2, SW_JUDGED_SCORE,
		       sw_score_raw(20.0));
	c->fb.level_after_write = -1;
	c->fb.cs.level = 2;
	assert_int_equal(restore(c), SW_EXIT_OK);

	/* a stable-rule file on a chip with a score */
	put_state_file(c, SW_FILE_VERSION, 4, SW_JUDGED_STABLE, 0);
	c->fb.cs.has_score = true;
	c->fb.cs.score_raw = sw_score_raw(99.0);
	c->fb.level_after_write = 4;
	c->fb.writes = 0;
	memset(c->fb.blob, 0, SW_BLOB_SIZE);
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 1);
	assert_memory_equal(c->fb.blob, blob, SW_BLOB_SIZE);
	assert_non_null(strstr(out_text(c), ": level 4 (stable), score 98.999% (saved: level 4 (stable), no score)\n"));
	/* and the score rule takes over with an acceptable score */
	c->fb.cs.score_raw = sw_score_raw(4.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.judgement, SW_JUDGED_SCORE);
	assert_int_equal(f.score_raw, sw_score_raw(4.0));
	/* a stable file whose level does not come back in 2 s */
	put_state_file(c, SW_FILE_VERSION, 4, SW_JUDGED_STABLE, 0);
	c->fb.level_after_write = 2;
	assert_int_equal(restore(c), SW_EXIT_CAL);
	assert_non_null(strstr(c->e.msg, "(level 4 (stable), no score) but the calibration level is 2 (calibrating), not 4 (stable)"));
	/* a level out of range after the write is no success */
	c->fb.level_after_write = 9;
	assert_int_equal(restore(c), SW_EXIT_IO);
	assert_non_null(strstr(c->e.msg, ", then read from the chip: calibration level 9 is not 0..4"));
}

/* show: the version, the level or status, and the judgement. */
static void test_show_versions(void **state)
{
	struct ctx *c = *state;
	struct sw_opts o = c->o;
	size_t from;

	o.file = c->path;
	put_state_file(c, SW_FILE_VERSION_1, 3, SW_JUDGED_SCORE,
		       sw_score_raw(2.0));
	assert_int_equal(sw_cmd_show(&o, &c->env, &c->e), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "format:              SNTRLWS1 version 1, 176 bytes"));
	assert_non_null(strstr(out_text(c), "RAM version:         0x0c05\n"
				"calibration status:  3 (complete: stable)\n"
				"judgement:           score (the application note's score)\n"
				"calibration score:   1.999% (raw 0x828f)\n"
				"saved at:            "));
	from = c->out_len;
	put_state_file(c, SW_FILE_VERSION, 4, SW_JUDGED_STABLE, 0);
	assert_int_equal(sw_cmd_show(&o, &c->env, &c->e), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c) + from, "RAM version:         0x0c05\n"
				"calibration level:   4 (stable)\n"
				"judgement:           stable (the level alone: the firmware reports no score)\n"
				"saved at:            "));
	from = c->out_len;
	put_state_file(c, SW_FILE_VERSION, 0, SW_JUDGED_NONE, 0);
	assert_int_equal(sw_cmd_show(&o, &c->env, &c->e), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c) + from, "RAM version:         0x0c05\n"
				"judgement:           none (imported from the board's EEPROM: no level or score)\n"
				"saved at:            "));
}

/* Guided to level 4 where the firmware has no score: no step 1. */
static void test_calibrate_level_only(void **state)
{
	static const struct fake_step steps[] = {
		{ 0, 2, 0, 0 },
		{ 3000, 3, 0, 0 },
		{ 4000, FAKE_GLITCH, 0, 0 },
		{ 4300, 4, 0, 0 },
	};
	struct ctx *c = *state;
	struct sw_file f;

	level_only(c);
	c->clk.now_ms = 0;
	c->fb.script = steps;
	c->fb.nsteps = 4;
	c->fb.mag = mag_sphere;
	assert_int_equal(sw_cmd_calibrate(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_OK);
	assert_true(c->clk.now_ms >= 4300 && c->clk.now_ms < 4600);
	assert_null(strstr(out_text(c), "Step 1/2"));
	assert_null(strstr(out_text(c), ", score "));
	assert_non_null(strstr(out_text(c), "until the calibration is stable (level 4; this firmware reports no score; up to 60 s)"));
	assert_non_null(strstr(out_text(c), "calibrate: level 3/4 (stable with a magnetic transient), coverage "));
	assert_non_null(strstr(out_text(c), "Calibration stable: "));
	assert_non_null(strstr(out_text(c), "saved iio:device0 calibration to "));
	assert_true(load(c, &f));
	assert_int_equal(f.judgement, SW_JUDGED_STABLE);
	assert_int_equal(f.state, 4);

	/* never stable: nothing saved, and says at which level it stayed */
	unlink(c->path);
	c->clk.now_ms = 0;
	c->o.timeout_s = 2;
	c->fb.nsteps = 2;
	c->o.json = true;
	assert_int_equal(sw_cmd_calibrate(&c->fb.b, &c->o, &c->env, &c->e),
			 SW_EXIT_CAL);
	assert_non_null(strstr(c->e.msg, "did not become stable within 2 s (level 2 of 4, calibrating;"));
	assert_non_null(strstr(c->out, "\"level\":2,\"level_name\":\"calibrating\",\"score\":null,\"best_score\":null,"));
	assert_int_equal(access(c->path, F_OK), -1);
}

/* At poll times, the coefficients the chip has learned by then. */
static void learn_at_130s(struct fake_be *f)
{
	if (f->clk->now_ms >= 130000)
		sw_blob_set_param(f->blob, 18, 20.0f);
}

/*
 * Without a score: the level rises to 4 at 45 s (saved at 60 s: no
 * file); it drops and rises again at 130 s with new coefficients, within
 * the 300 s since the write: the blob is read once, the save waits and
 * is made at 360 s, the first poll allowed, while the level stays 4.
 */
static void test_watch_stable_pending(void **state)
{
	static const struct fake_step steps[] = {
		{ 0, 2, 0, 0 },
		{ 45000, 4, 0, 0 },
		{ 100000, 2, 0, 0 },
		{ 130000, 4, 0, 0 },
	};
	struct ctx *c = *state;
	struct sw_file f;

	level_only(c);
	watch_defaults(c, steps, 4, 400000);
	c->fb.on_chip_info = learn_at_130s;
	assert_int_equal(watch(c), SW_EXIT_DEVICE);
	assert_int_equal(count(out_text(c), "saved iio:device0 calibration"), 2);
	assert_non_null(strstr(out_text(c), "stable, and no usable saved calibration"));
	assert_int_equal(count(out_text(c), "but the last write was"), 1);
	assert_non_null(strstr(out_text(c), "watch: iio:device0 has a calibration to save (level 4, stable, and parameter 18 (mcoeffs[1]) moved from the saved file's by more than 0.5 %), but the last write was 90 s ago: saving it in 210 s unless it changes"));
	assert_true(load(c, &f));
	assert_true(sw_blob_param(f.payload, 18) == 20.0f);
	assert_true(f.saved_at == c->clk.wall_s);
	/* the blob: at 60 s, at the rise at 150 s, for the save at 360 s */
	assert_int_equal(c->fb.reads, 3);
}

/* A save held back is dropped when the level falls before it is allowed. */
static void test_watch_pending_dropped(void **state)
{
	static const struct fake_step steps[] = {
		{ 0, 4, 0, 0 },
		{ 100000, 2, 0, 0 },
		{ 130000, 4, 0, 0 },
		{ 200000, 3, 0, 0 },
		{ 500000, 4, 0, 0 },
	};
	struct ctx *c = *state;

	level_only(c);
	watch_defaults(c, steps, 5, 560000);
	c->fb.on_chip_info = learn_at_130s;
	assert_int_equal(watch(c), SW_EXIT_DEVICE);
	/* at 0 s (no file), not at 360 s (level 3), at 510 s (it rose) */
	assert_int_equal(count(out_text(c), "saved iio:device0 calibration"), 2);
	assert_int_equal(count(out_text(c), "but the last write was"), 1);
	assert_int_equal(c->fb.reads, 3);
}

/* The lock held by another writer from 130 s to 200 s; learned at 130 s. */
static void lock_130s_to_200s(struct fake_be *f)
{
	static int fd = -1;
	struct sw_err e;

	learn_at_130s(f);
	sw_err_clear(&e);
	if (f->clk->now_ms >= 130000 && f->clk->now_ms < 200000 && fd < 0) {
		fd = sw_file_lock_open(f->data, true, &e);
		assert_true(fd >= 0 && sw_file_lock_try(fd));
	} else if (f->clk->now_ms >= 200000 && fd >= 0) {
		close(fd);
		fd = -1;
	}
}

/*
 * Without a score, a save that fails (here: another writer holds the lock
 * for longer than a writer waits) is tried again once the write interval
 * has passed, while the level stays 4: the level rose once, at 130 s,
 * and the save at 150 s failed after waiting 30 s; tried again at 450 s.
 */
static void test_watch_stable_save_retried(void **state)
{
	static const struct fake_step steps[] = {
		{ 0, 4, 0, 0 },
		{ 100000, 2, 0, 0 },
		{ 130000, 4, 0, 0 },
	};
	struct ctx *c = *state;
	struct sw_file f;

	level_only(c);
	assert_int_equal(save(c), SW_EXIT_OK);
	watch_defaults(c, steps, 3, 500000);
	c->fb.on_chip_info = lock_130s_to_200s;
	c->fb.data = c->path;
	assert_int_equal(watch(c), SW_EXIT_DEVICE);
	fflush(c->errf);
	assert_int_equal(count(c->err, "has held it for 30 s"), 1);
	assert_int_equal(count(out_text(c), "watch: trying again in 300 s"), 1);
	assert_int_equal(count(strstr(out_text(c), "watching "),
			       "saved iio:device0 calibration"), 1);
	assert_non_null(strstr(out_text(c), "stable, and parameter 18 (mcoeffs[1]) moved"));
	assert_true(load(c, &f));
	assert_true(sw_blob_param(f.payload, 18) == 20.0f);
	assert_true(c->clk.now_ms >= 450000);
}

/* The blob cannot be read from 140 s to 170 s; learned at 130 s. */
static void no_blob_140s_to_170s(struct fake_be *f)
{
	learn_at_130s(f);
	f->fail_read = f->clk->now_ms >= 140000 && f->clk->now_ms < 170000 ?
		       SW_EXIT_IO : 0;
}

/*
 * Without a score, the look at the blob after a rise to 4 that fails (a
 * bus error) is reported and made again at the next poll: the save it
 * finds waiting is made once the write interval has passed.
 */
static void test_watch_stable_look_retried(void **state)
{
	static const struct fake_step steps[] = {
		{ 0, 2, 0, 0 },
		{ 45000, 4, 0, 0 },
		{ 100000, 2, 0, 0 },
		{ 130000, 4, 0, 0 },
	};
	struct ctx *c = *state;
	struct sw_file f;

	level_only(c);
	watch_defaults(c, steps, 4, 400000);
	c->fb.on_chip_info = no_blob_140s_to_170s;
	assert_int_equal(watch(c), SW_EXIT_DEVICE);
	fflush(c->errf);
	assert_int_equal(count(c->err, "fake: read failed"), 1);
	assert_int_equal(count(out_text(c), "watch: looking again every 30 s"), 1);
	/* at 60 s (no file) and at 360 s, held back from the look at 180 s */
	assert_int_equal(count(out_text(c), "saved iio:device0 calibration"), 2);
	assert_non_null(strstr(out_text(c), "but the last write was 120 s ago: saving it in 180 s unless it changes"));
	assert_true(load(c, &f));
	assert_true(sw_blob_param(f.payload, 18) == 20.0f);
}

/*
 * Idle without a score: one look at the level a poll and nothing else;
 * the blob was read once, at the first look, where the level was 4.
 */
static void test_watch_idle_reads_level(void **state)
{
	static const struct fake_step steady[] = {
		{ 0, 4, 0, 0 },
	};
	struct ctx *c = *state;
	uint8_t before[SW_FILE_SIZE], after[SW_FILE_SIZE];

	level_only(c);
	assert_int_equal(save(c), SW_EXIT_OK);
	file_bytes(c, before);
	c->fb.reads = 0;
	c->fb.state_reads = 0;
	watch_defaults(c, steady, 1, 300000);
	assert_int_equal(watch(c), SW_EXIT_DEVICE);
	/* polls at 0, 30, ..., 270 s; the first one's snapshot: 2 more */
	assert_int_equal(c->fb.state_reads, 10 + 2);
	assert_int_equal(c->fb.reads, 1);
	assert_int_equal(count(out_text(c), "not saving iio:device0 calibration"), 1);
	file_bytes(c, after);
	assert_memory_equal(before, after, SW_FILE_SIZE);
}

/* STATE/firmware/NAME, the directory the driver's files live in. */
static void fw_path(struct ctx *c, const char *name, char *out, size_t len)
{
	snprintf(out, len, "%s/firmware%s%s", c->dir, *name ? "/" : "", name);
}

/* Does the driver's file NAME hold exactly blob? */
/* The driver's file holds payload as the chip's blob: the fake's identity */
static bool caldata_holds(struct ctx *c, const char *name,
			  const uint8_t *payload)
{
	uint8_t buf[SW_CALDATA_SIZE + 1], want[SW_CALDATA_SIZE];
	char path[256];
	ssize_t n;
	int fd;

	sw_caldata_encode(&c->fb.chip, payload, want);
	fw_path(c, name, path, sizeof(path));
	fd = open(path, O_RDONLY | O_NOFOLLOW);
	if (fd < 0)
		return false;
	n = read(fd, buf, sizeof(buf));
	close(fd);
	return n == SW_CALDATA_SIZE && !memcmp(buf, want, SW_CALDATA_SIZE);
}

static bool fw_exists(struct ctx *c, const char *name)
{
	char path[256];
	struct stat st;

	fw_path(c, name, path, sizeof(path));
	return lstat(path, &st) == 0;
}

static void fw_touch(struct ctx *c, const char *name)
{
	char path[256];
	int fd;

	fw_path(c, name, path, sizeof(path));
	fd = open(path, O_WRONLY | O_CREAT | O_EXCL, 0600);
	assert_true(fd >= 0);
	close(fd);
}

/* Entries of STATE/firmware, "." and ".." left out. */
static int fw_count(struct ctx *c)
{
	char path[256];
	struct dirent *de;
	DIR *d;
	int n = 0;

	fw_path(c, "", path, sizeof(path));
	d = opendir(path);
	if (!d)
		return -1;
	while ((de = readdir(d)))
		n += strcmp(de->d_name, ".") && strcmp(de->d_name, "..");
	closedir(d);
	return n;
}

#define CALDATA "caldata-1-0028.bin"

/*
 * Every save also writes the file the driver restores at probe: the saved
 * file's payload behind the chip's identity, named by the I2C client, 0600
 * in a 0700 directory; the files of the same client that drivers before
 * 1.2.0 read (named by ROM and RAM versions too) go, other clients' and
 * other names stay.
 */
static void test_caldata_on_save(void **state)
{
	struct ctx *c = *state;
	char path[256], target[256];
	struct sw_file f;
	struct stat st;

	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_true(caldata_holds(c, CALDATA, f.payload));
	fw_path(c, CALDATA, path, sizeof(path));
	assert_int_equal(stat(path, &st), 0);
	assert_int_equal(st.st_mode & 0777, 0600);
	fw_path(c, "", path, sizeof(path));
	assert_int_equal(stat(path, &st), 0);
	assert_int_equal(st.st_mode & 0777, 0700);
	assert_int_equal(fw_count(c), 1);

	/*
	 * A firmware update (RAM 0x0c06), then a better calibration, the
	 * files of an older driver left.
	 */
	fw_touch(c, "caldata-09e6-0c04-1-0028.bin");
	fw_touch(c, "caldata-09e6-0c05-1-0028.bin");
	fw_touch(c, "caldata-07a8-0c05-1-0028.bin");
	fw_touch(c, "caldata-09e6-0c05-11-0028.bin");
	fw_touch(c, "caldata-09e6-0c05-1-0028.bin.orig");
	fw_touch(c, "caldata-9e6-0c05-1-0028.bin");
	fw_touch(c, "caldata-09E6-0c05-1-0028.bin");
	snprintf(target, sizeof(target), "%s/target", c->dir);
	fw_path(c, "caldata-09e6-0c03-1-0028.bin", path, sizeof(path));
	assert_int_equal(symlink(target, path), 0);
	assert_non_null(fopen(target, "w"));
	c->fb.chip.ram_version = 0x0c06;
	c->fb.cs.score_raw = sw_score_raw(1.5);
	sw_blob_set_param(c->fb.blob, 18, 42.0f);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_true(caldata_holds(c, CALDATA, f.payload));
	assert_false(fw_exists(c, "caldata-09e6-0c06-1-0028.bin"));
	assert_false(fw_exists(c, "caldata-09e6-0c04-1-0028.bin"));
	assert_false(fw_exists(c, "caldata-09e6-0c05-1-0028.bin"));
	assert_false(fw_exists(c, "caldata-07a8-0c05-1-0028.bin"));
	assert_false(fw_exists(c, "caldata-09e6-0c03-1-0028.bin"));
	assert_int_equal(access(target, F_OK), 0);
	assert_true(fw_exists(c, "caldata-09e6-0c05-11-0028.bin"));
	assert_true(fw_exists(c, "caldata-09e6-0c05-1-0028.bin.orig"));
	assert_true(fw_exists(c, "caldata-9e6-0c05-1-0028.bin"));
	assert_true(fw_exists(c, "caldata-09E6-0c05-1-0028.bin"));
	assert_int_equal(fw_count(c), 5);
}

/*
 * calibration_data's header: format 1, ProductID, RevisionID, 0, ROM and
 * RAM versions little-endian, then the payload; another format or a
 * reserved byte set is no blob this tool knows.
 */
static void test_caldata_header(void **state)
{
	static const uint8_t hdr[SW_CALDATA_HDR_SIZE] = {
		1, 0x80, 0x02, 0, 0xe6, 0x09, 0x05, 0x0c,
	};
	struct ctx *c = *state;
	uint8_t blob[SW_CALDATA_SIZE], payload[SW_BLOB_SIZE];
	struct sw_chip_info chip;

	sw_caldata_encode(&c->fb.chip, c->fb.blob, blob);
	assert_memory_equal(blob, hdr, sizeof(hdr));
	assert_memory_equal(&blob[SW_CALDATA_HDR_SIZE], c->fb.blob, SW_BLOB_SIZE);
	assert_true(sw_caldata_decode(blob, &chip, payload));
	assert_memory_equal(&chip, &c->fb.chip, sizeof(chip));
	assert_memory_equal(payload, c->fb.blob, SW_BLOB_SIZE);
	blob[0] = 2;
	assert_false(sw_caldata_decode(blob, &chip, payload));
	blob[0] = 1;
	blob[3] = 1;
	assert_false(sw_caldata_decode(blob, &chip, payload));
}

/*
 * A save killed while it wrote the driver's file leaves its temporary file;
 * the next save removes it even when the driver's file holds its blob
 * already and is not written again.
 */
static void test_caldata_stale_temp(void **state)
{
	struct ctx *c = *state;
	struct timespec old[2] = { { .tv_sec = 1 }, { .tv_sec = 1 } };
	char path[256];

	assert_int_equal(save(c), SW_EXIT_OK);
	fw_touch(c, "." CALDATA ".0badcafe.tmp");
	fw_path(c, "." CALDATA ".0badcafe.tmp", path, sizeof(path));
	assert_int_equal(utimensat(AT_FDCWD, path, old, 0), 0);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_false(fw_exists(c, "." CALDATA ".0badcafe.tmp"));
	assert_int_equal(fw_count(c), 1);
}

/* An offsets save and an import: the new state file's payload. */
static void test_caldata_follows_file(void **state)
{
	static uint8_t img[SW_BOARD_EEPROM_SIZE];
	struct ctx *c = *state;
	struct sw_file f;

	c->fb.cs.score_raw = sw_score_raw(2.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	c->fb.cs.score_raw = sw_score_raw(4.0);
	sw_blob_set_param(c->fb.blob, 18, 99.0f);
	c->fb.offset[0] = -47;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "saved iio:device0 accel offsets -47 0 0 LSB"));
	assert_true(load(c, &f));
	assert_true(sw_blob_param(f.payload, 18) == 9.0f);
	assert_true(caldata_holds(c, CALDATA, f.payload));

	fake_board_image(img, SW_BOARD_GT);
	assert_int_equal(import_image(c, img, sizeof(img), SW_BOARD_GT, true),
			 SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.judgement, SW_JUDGED_NONE);
	assert_true(caldata_holds(c, CALDATA, f.payload));
	assert_int_equal(fw_count(c), 1);
}

/*
 * Only the state file has one (the unit restores that one), only with the
 * driver (over i2c-dev no driver probes).
 */
static void test_caldata_not_for_file_or_i2c(void **state)
{
	struct ctx *c = *state;
	char other[160];

	snprintf(other, sizeof(other), "%s/mine.ws", c->dir);
	c->o.file = other;
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_int_equal(access(other, F_OK), 0);
	c->o.file = NULL;
	c->fb.b.client[0] = '\0';
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_int_equal(access(c->path, F_OK), 0);
	assert_int_equal(fw_count(c), -1);
	c->o.if_present = true;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(fw_count(c), -1);
}

/*
 * Never through a symlink, the directory's or the file's; the save of the
 * state file stands, with a warning that the driver cannot restore it.
 */
static void test_caldata_refuses_symlink(void **state)
{
	struct ctx *c = *state;
	char elsewhere[160], path[256], target[160];
	struct sw_file f;

	snprintf(elsewhere, sizeof(elsewhere), "%s/elsewhere", c->dir);
	assert_int_equal(mkdir(elsewhere, 0700), 0);
	fw_path(c, "", path, sizeof(path));
	assert_int_equal(symlink(elsewhere, path), 0);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_non_null(strstr(out_text(c), "warning: "));
	assert_non_null(strstr(out_text(c), "symbolic link"));
	assert_non_null(strstr(out_text(c), "the driver cannot restore this calibration at probe"));
	assert_int_equal(rmdir(elsewhere), 0);

	assert_int_equal(unlink(path), 0);
	assert_int_equal(mkdir(path, 0700), 0);
	snprintf(target, sizeof(target), "%s/target", c->dir);
	fw_path(c, CALDATA, path, sizeof(path));
	assert_int_equal(symlink(target, path), 0);
	c->fb.cs.score_raw = sw_score_raw(1.0);
	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	assert_int_equal(f.score_raw, sw_score_raw(1.0));
	assert_int_equal(access(target, F_OK), -1);
	assert_non_null(strstr(out_text(c), CALDATA ": is a symbolic link"));
}

/*
 * restore --if-present after the driver restored at probe: the chip holds
 * the file's calibration (parameters 18..23 and 27..29 within the
 * tolerance), nothing is written, exit 0. Anything else restores as
 * before; without --if-present (a user's restore) it always writes.
 */
static void test_restore_already_at_probe(void **state)
{
	struct ctx *c = *state;
	uint8_t saved[SW_BLOB_SIZE];
	int reads;

	assert_int_equal(save(c), SW_EXIT_OK);
	memcpy(saved, c->fb.blob, SW_BLOB_SIZE);
	c->o.if_present = true;
	reads = c->fb.reads;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 0);
	assert_int_equal(c->fb.reads, reads + 1);
	assert_non_null(strstr(out_text(c), "iio:device0: already restored at probe: it holds the calibration of "));
	assert_non_null(strstr(out_text(c), "(parameters 18-23 and 27-29 within 0.5 %); nothing written"));

	/* Within the tolerance, and a parameter that is not compared */
	sw_blob_set_param(c->fb.blob, 20, sw_blob_param(saved, 20) * 1.004f);
	sw_blob_set_param(c->fb.blob, 33, 1234.0f);
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 0);

	/* Beyond it: restored */
	sw_blob_set_param(c->fb.blob, 20, sw_blob_param(saved, 20) * 1.006f);
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 1);
	assert_memory_equal(c->fb.blob, saved, SW_BLOB_SIZE);

	/* The accel offsets too: 0.0244 g is beyond 0.005 g */
	c->fb.offset[2] = 50;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 2);

	/* A user's restore writes whatever the chip holds */
	c->o.if_present = false;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 3);

	/* Over i2c-dev there was no probe */
	c->o.if_present = true;
	c->fb.b.client[0] = '\0';
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 4);
}

/*
 * The first boot after an upgrade from a version without the driver's
 * file: restore writes it, whether it restored or found the chip holding
 * the calibration (a reboot that kept the chip powered).
 */
static void test_restore_writes_caldata(void **state)
{
	struct ctx *c = *state;
	char path[256];
	struct sw_file f;
	FILE *fp;

	assert_int_equal(save(c), SW_EXIT_OK);
	assert_true(load(c, &f));
	fw_path(c, CALDATA, path, sizeof(path));
	assert_int_equal(unlink(path), 0);
	fw_touch(c, "caldata-09e6-0c04-1-0028.bin");
	memset(c->fb.blob, 0, SW_BLOB_SIZE);
	c->fb.cs.level = 2;
	c->o.if_present = true;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 1);
	assert_true(caldata_holds(c, CALDATA, f.payload));
	assert_int_equal(fw_count(c), 1);

	assert_int_equal(unlink(path), 0);
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_non_null(strstr(out_text(c), "already restored at probe"));
	assert_int_equal(c->fb.writes, 1);
	assert_true(caldata_holds(c, CALDATA, f.payload));

	/* A bad state file: the driver's file is left as it is */
	fp = fopen(c->path, "r+");
	assert_non_null(fp);
	assert_int_equal(fseek(fp, 100, SEEK_SET), 0);
	assert_int_equal(fputc(0x5a, fp), 0x5a);
	assert_int_equal(fclose(fp), 0);
	c->o.if_present = false;
	assert_int_equal(restore(c), SW_EXIT_FILE);
	assert_true(caldata_holds(c, CALDATA, f.payload));
}

/* A save that replaced the state file while restore ran: its file stays. */
static void replace_state_file(struct fake_be *fb)
{
	struct ctx *c = fb->data;
	uint8_t out[SW_FILE_SIZE];
	struct sw_file nf;
	struct sw_err e;

	memset(&nf, 0, sizeof(nf));
	nf.chip = fb->chip;
	nf.version = SW_FILE_VERSION;
	nf.state = 4;
	nf.judgement = SW_JUDGED_STABLE;
	fake_fill_blob(nf.payload);
	sw_blob_set_param(nf.payload, 18, 77.0f);
	sw_file_encode(&nf, out);
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(c->path, out, sizeof(out), true, &e),
			 SW_EXIT_OK);
	fb->on_chip_info = NULL;
}

static void test_restore_caldata_after_save(void **state)
{
	struct ctx *c = *state;
	char path[256];

	assert_int_equal(save(c), SW_EXIT_OK);
	fw_path(c, CALDATA, path, sizeof(path));
	assert_int_equal(unlink(path), 0);
	memset(c->fb.blob, 0, SW_BLOB_SIZE);
	c->fb.data = c;
	c->fb.on_chip_info = replace_state_file;
	assert_int_equal(restore(c), SW_EXIT_OK);
	assert_int_equal(c->fb.writes, 1);
	assert_false(fw_exists(c, CALDATA));
}

#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)

int main(void)
{
	const struct CMUnitTest tests[] = {
		T(test_save_good),
		T(test_save_policy_refusals),
		T(test_save_over_bad_file),
		T(test_save_nonfinite_blob),
		T(test_save_refuses_symlink),
		T(test_restore_good),
		T(test_restore_driver_checks_identity),
		T(test_status_identity_from_blob),
		T(test_restore_missing),
		T(test_restore_refuses_bad_files),
		T(test_restore_chip_mismatch),
		T(test_restore_not_calibrated_after),
		T(test_restore_write_error),
		T(test_save_distrusts_chip_values),
		T(test_save_replaces_file_with_bad_score),
		T(test_restore_refused_then_save),
		T(test_restore_missing_state_dir),
		T(test_migrate_legacy_key),
		T(test_status),
		T(test_status_hub),
		T(test_status_level_only),
		T(test_show),
		T(test_calibrate),
		T(test_calibrate_timeout_keeps_best),
		T(test_calibrate_incomplete),
		T(test_calibrate_json),
		T(test_calibrate_tty_map),
		T(test_accel_cal),
		T(test_accel_cal_refusals),
		T(test_accel_cal_distrusts_offsets),
		T(test_save_keeps_accel_offsets),
		T(test_save_offsets_without_file),
		T(test_accel_cal_saves),
		T(test_calibrate_glitch),
		T(test_calibrate_stale_gyro_flag),
		T(test_save_holds_lock),
		T(test_save_lock_timeout),
		T(test_lock_refuses_symlink),
		T(test_restore_set_aside_checks_again),
		T(test_iio_errors),
		T(test_watch),
		T(test_watch_notices_within_a_poll),
		T(test_watch_device_gone),
		T(test_watch_margin_zero),
		T(test_watch_state_dir_repaired),
		T(test_watch_saves_offsets),
		T(test_import_board),
		T(test_import_board_kw),
		T(test_import_board_refusals),
		T(test_import_board_keeps_saved),
		T(test_save_stable_rule),
		T(test_save_glitch_and_change),
		T(test_restore_across_rules),
		T(test_show_versions),
		T(test_calibrate_level_only),
		T(test_watch_stable_pending),
		T(test_watch_pending_dropped),
		T(test_watch_stable_save_retried),
		T(test_watch_stable_look_retried),
		T(test_watch_idle_reads_level),
		T(test_caldata_header),
		T(test_caldata_on_save),
		T(test_caldata_stale_temp),
		T(test_caldata_follows_file),
		T(test_caldata_not_for_file_or_i2c),
		T(test_caldata_refuses_symlink),
		T(test_restore_already_at_probe),
		T(test_restore_writes_caldata),
		T(test_restore_caldata_after_save),
	};

	return cmocka_run_group_tests_name("commands", tests, NULL, NULL);
}
