// SPDX-License-Identifier: GPL-2.0-only
/*
 * libFuzzer target: the saved-file parser.
 *
 * The input is the content of a state file. Properties checked:
 *  - sw_file_decode() never crashes, whatever the bytes and whether or not
 *    the caller wants the detail text;
 *  - it accepts only a file of exactly SW_FILE_SIZE bytes, and whatever it
 *    accepts re-encodes to the identical bytes (nothing is lost or
 *    normalised, so a restore writes what was saved);
 *  - `show` on the same bytes succeeds exactly when decode does.
 *
 * Random bytes almost never carry a correct CRC-32, which would leave the
 * checks after it unexplored: a second pass repairs the CRC of a
 * full-sized input and decodes again.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <unistd.h>
#include <zlib.h>

#include "cmd.h"
#include "wsfile.h"

static int memfd = -1;
static FILE *devnull;

static void check_show(const uint8_t *buf, size_t len, bool valid)
{
	char path[64];
	struct sw_opts o;
	struct sw_env env;
	struct sw_err e;
	int ret;

	if (ftruncate(memfd, 0) < 0 ||
	    pwrite(memfd, buf, len, 0) != (ssize_t)len)
		abort();
	snprintf(path, sizeof(path), "/proc/self/fd/%d", memfd);
	memset(&o, 0, sizeof(o));
	o.cmd = SW_CMD_SHOW;
	o.file = path;
	sw_env_init(&env, devnull, devnull);
	sw_err_clear(&e);
	ret = sw_cmd_show(&o, &env, &e);
	if ((ret == SW_EXIT_OK) != valid) {
		fprintf(stderr, "show returned %d (%s), decode said %s\n",
			ret, e.msg, valid ? "valid" : "invalid");
		abort();
	}
	if (ret != SW_EXIT_OK && ret != SW_EXIT_FILE)
		abort();
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
		if (sw_file_match_chip(&f, &f.chip, NULL, 0) != SW_CHECK_OK)
			abort();
	}
	check_show(buf, len, c == SW_CHECK_OK);
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
	(void)argc;
	(void)argv;
	memfd = memfd_create("fuzz-wsfile", MFD_CLOEXEC);
	devnull = fopen("/dev/null", "w");
	if (memfd < 0 || !devnull)
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
