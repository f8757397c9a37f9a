// SPDX-License-Identifier: GPL-2.0-only
/*
 * libFuzzer target: the saved-file parser and the commands that read it.
 *
 * The input is the content of a state file. Properties checked:
 *  - sw_file_decode() never crashes, whatever the bytes and whether or not
 *    the caller wants the detail text, and gives the same verdict each way;
 *  - it accepts only a file of exactly SW_FILE_SIZE bytes, and whatever it
 *    accepts re-encodes to the identical bytes (nothing is lost or
 *    normalised, so a restore writes what was saved);
 *  - `show` succeeds exactly when decode does; with --json it prints one
 *    line, one object with every parameter and no "nan" or "inf";
 *  - `restore` (against the fake chip of the unit tests) writes the chip
 *    exactly when the file decodes and matches the chip (with --force:
 *    when it decodes), and then writes the file's payload; a file it
 *    refuses is moved aside to KEY.ws.refused, byte for byte;
 *  - `status` copes with whatever file is there; `save` over a valid file
 *    succeeds and either leaves it as it was (the policy said no) or
 *    writes a file that decodes and carries the chip's blob.
 *
 * Random bytes almost never carry a correct CRC-32, which would leave the
 * checks after it unexplored: a second pass repairs the CRC of a
 * full-sized input and runs everything again.
 */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <zlib.h>

#include "cmd.h"
#include "wsfile.h"
#include "tests/fake_backend.h"

static char dir[4096], path[4096 + 32], aside[4096 + 48];
static FILE *devnull;

static void put_file(const uint8_t *buf, size_t len)
{
	int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW |
		      O_CLOEXEC, 0600);

	if (fd < 0 || write(fd, buf, len) != (ssize_t)len || close(fd) < 0)
		abort();
}

/* p holds exactly buf. */
static bool same_file(const char *p, const uint8_t *buf, size_t len)
{
	uint8_t back[SW_FILE_MAX_READ + 1];
	struct sw_err e;
	size_t n;

	/* The read stops one byte past the limit, as the tool's own does. */
	if (len > SW_FILE_MAX_READ + 1)
		len = SW_FILE_MAX_READ + 1;
	sw_err_clear(&e);
	return !sw_file_read(p, SW_READ_ANY, back, &n, NULL, &e) &&
	       n == len && !memcmp(back, buf, len);
}

static void setup(struct fake_be *fb, struct fake_clock *clk,
		  struct sw_env *env, struct sw_opts *o, struct sw_err *e)
{
	clk->now_ms = 1000;
	clk->wall_s = 1800000000;
	fake_init(fb, clk);
	fake_env(env, clk, devnull, devnull);
	memset(o, 0, sizeof(*o));
	o->state_dir = dir;
	o->address = 0x28;
	o->max_score = 5.0;
	o->target_score = 3.0;
	o->timeout_s = 60;
	o->samples = 32;
	sw_err_clear(e);
}

static void check_show_json(struct sw_opts *o, struct sw_env *env,
			    enum sw_file_check c)
{
	char *out = NULL;
	size_t n = 0;
	struct sw_err e;
	int ret;

	env->out = open_memstream(&out, &n);
	if (!env->out)
		abort();
	o->json = true;
	sw_err_clear(&e);
	ret = sw_cmd_show(o, env, &e);
	fclose(env->out);
	env->out = devnull;
	o->json = false;
	if ((ret == SW_EXIT_OK) != (c == SW_CHECK_OK))
		abort();
	if (ret != SW_EXIT_OK ? n != 0 :
	    strncmp(out, "{\"file\":", 8) || n < 4 ||
	    strcmp(out + n - 3, "]}\n") || strchr(out, '\n') != out + n - 1 ||
	    !strstr(out, "{\"number\":35,") || strstr(out, "nan") ||
	    strstr(out, "inf"))
		abort();
	free(out);
}

static void check_commands(const uint8_t *buf, size_t len,
			   enum sw_file_check c, const struct sw_file *f)
{
	struct fake_clock clk;
	struct fake_be fb;
	struct sw_env env;
	struct sw_opts o;
	struct sw_err e;
	bool match;
	int ret;

	match = c == SW_CHECK_OK &&
		sw_file_match_chip(f, &(struct sw_chip_info){ 0x80, 0x02,
			0x09e6, 0x0c05 }, NULL, 0) == SW_CHECK_OK;

	put_file(buf, len);
	setup(&fb, &clk, &env, &o, &e);
	o.cmd = SW_CMD_SHOW;
	o.file = path;
	ret = sw_cmd_show(&o, &env, &e);
	if ((ret == SW_EXIT_OK) != (c == SW_CHECK_OK) ||
	    (ret != SW_EXIT_OK && ret != SW_EXIT_FILE))
		abort();
	check_show_json(&o, &env, c);

	/* Restore, from the state directory: the chip's key is the name. */
	setup(&fb, &clk, &env, &o, &e);
	memset(fb.blob, 0, sizeof(fb.blob));
	ret = sw_cmd_restore(&fb.b, &o, &env, &e);
	if ((ret == SW_EXIT_OK) != match || fb.writes != (match ? 1 : 0))
		abort();
	if (match && memcmp(fb.blob, f->payload, SW_BLOB_SIZE) != 0)
		abort();
	if (!match && !same_file(aside, buf, len))
		abort();

	put_file(buf, len);
	setup(&fb, &clk, &env, &o, &e);
	o.force = true;
	memset(fb.blob, 0, sizeof(fb.blob));
	ret = sw_cmd_restore(&fb.b, &o, &env, &e);
	if ((ret == SW_EXIT_OK) != (c == SW_CHECK_OK) ||
	    fb.writes != (c == SW_CHECK_OK ? 1 : 0))
		abort();
	if (c == SW_CHECK_OK && memcmp(fb.blob, f->payload, SW_BLOB_SIZE))
		abort();

	/* Text or JSON: the file system calls dominate; one of them will do. */
	put_file(buf, len);
	setup(&fb, &clk, &env, &o, &e);
	o.json = len && (buf[len - 1] & 1);
	if (sw_cmd_status(&fb.b, &o, &env, &e) != SW_EXIT_OK)
		abort();

	/*
	 * Save over a valid file: the policy compares with it. (Over an
	 * invalid one it always writes, which costs an fsync and teaches
	 * nothing new.) Refused by the policy, or a good file.
	 */
	if (c != SW_CHECK_OK)
		return;
	setup(&fb, &clk, &env, &o, &e);
	if (sw_cmd_save(&fb.b, &o, &env, &e) != SW_EXIT_OK)
		abort();
	if (!same_file(path, buf, len)) {
		uint8_t back[SW_FILE_MAX_READ + 1];
		struct sw_file nf;
		size_t n;

		if (sw_file_read(path, SW_READ_STATE, back, &n, NULL, &e) ||
		    sw_file_decode(back, n, &nf, NULL, 0) != SW_CHECK_OK ||
		    memcmp(nf.payload, fb.blob, SW_BLOB_SIZE) != 0)
			abort();
	}
}

static void check_one(const uint8_t *buf, size_t len)
{
	uint8_t out[SW_FILE_SIZE];
	char detail[160], tiny[4];
	enum sw_file_check c, c2;
	struct sw_file f;

	memset(&f, 0xa5, sizeof(f));
	memset(detail, 'x', sizeof(detail));
	c = sw_file_decode(buf, len, &f, detail, sizeof(detail));
	if (!memchr(detail, '\0', sizeof(detail)))
		abort();
	if (strcmp(sw_check_name(c), "unknown check") == 0)
		abort();

	/* The same verdict with no detail, a tiny detail and no output. */
	c2 = sw_file_decode(buf, len, NULL, NULL, 0);
	if (c2 != c)
		abort();
	memset(tiny, 'x', sizeof(tiny));
	c2 = sw_file_decode(buf, len, NULL, tiny, sizeof(tiny));
	if (c2 != c || !memchr(tiny, '\0', sizeof(tiny)))
		abort();

	if (c == SW_CHECK_OK) {
		if (len != SW_FILE_SIZE)
			abort();
		if (sw_file_encode(&f, out) != SW_FILE_SIZE ||
		    memcmp(out, buf, SW_FILE_SIZE) != 0) {
			fprintf(stderr, "round trip changed the file\n");
			abort();
		}
	}
	check_commands(buf, len, c, &f);
}

static void cleanup(void)
{
	unlink(path);
	unlink(aside);
	rmdir(dir);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	const char *tmp = getenv("TMPDIR");

	(void)argc;
	(void)argv;
	/* tmpfs when there is one: save fsyncs. */
	if (!tmp)
		tmp = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
	if (snprintf(dir, sizeof(dir), "%s/sw-fuzz-XXXXXX", tmp) >=
	    (int)sizeof(dir) || !mkdtemp(dir)) {
		perror("fuzz_wsfile: cannot make a directory in TMPDIR");
		abort();
	}
	snprintf(path, sizeof(path), "%s/platform-sentral-sim-0x28.ws", dir);
	snprintf(aside, sizeof(aside), "%s.refused", path);
	atexit(cleanup);
	devnull = fopen("/dev/null", "w");
	if (!devnull)
		abort();
	return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	uint8_t fixed[SW_FILE_SIZE];

	check_one(data, size);
	if (size == SW_FILE_SIZE) {
		memcpy(fixed, data, size);
		sw_put_le32(fixed + SW_FILE_SIZE - 4,
			    (uint32_t)crc32(0L, fixed, SW_FILE_SIZE - 4));
		check_one(fixed, size);
	}
	return 0;
}
