// SPDX-License-Identifier: GPL-2.0-only
/*
 * Writes the fuzzers' seed corpora (committed under fuzz/corpus/): state
 * files made by the tool's own encoder and atomic writer, a few files each
 * failing one check, and sample command lines (arguments separated by NUL
 * bytes). Run by "make fuzz-seeds".
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wsfile.h"

static const char *dir;

static void put(const char *sub, const char *name, const void *buf,
		size_t len)
{
	char path[4096];
	struct sw_err e;

	snprintf(path, sizeof(path), "%s/%s/%s", dir, sub, name);
	sw_err_clear(&e);
	if (sw_file_write_atomic(path, buf, len, false, &e)) {
		fprintf(stderr, "mkseeds: %s\n", e.msg);
		exit(1);
	}
}

static void sample(struct sw_file *f)
{
	int n;

	memset(f, 0, sizeof(*f));
	f->chip.product_id = 0x80;
	f->chip.revision_id = 0x02;
	f->chip.rom_version = 0x09e6;
	f->chip.ram_version = 0x0c05;
	f->version = SW_FILE_VERSION;
	f->state = 4;
	f->judgement = SW_JUDGED_SCORE;
	f->score_raw = sw_score_raw(1.5);
	f->saved_at = 1795000000;
	for (n = 1; n <= SW_NPARAMS; n++)
		sw_blob_set_param(f->payload, n, (float)n * 0.5f);
	sw_blob_set_param(f->payload, SW_PARAM_ACCEL_X, sw_lsb_to_g(-47));
	sw_blob_set_param(f->payload, SW_PARAM_ACCEL_X + 1, sw_lsb_to_g(-15));
	sw_blob_set_param(f->payload, SW_PARAM_ACCEL_X + 2, sw_lsb_to_g(46));
}

static void wsfile_seeds(void)
{
	uint8_t buf[SW_FILE_SIZE + 1];
	struct sw_file f;

	sample(&f);
	sw_file_encode(&f, buf);
	put("wsfile", "valid.ws", buf, SW_FILE_SIZE);

	/* Each judgement, and version 1. */
	f.judgement = SW_JUDGED_STABLE;
	f.score_raw = 0;
	sw_file_encode(&f, buf);
	put("wsfile", "valid-stable.ws", buf, SW_FILE_SIZE);
	f.judgement = SW_JUDGED_NONE;
	f.state = 0;
	sw_file_encode(&f, buf);
	put("wsfile", "valid-import.ws", buf, SW_FILE_SIZE);
	sample(&f);
	f.version = SW_FILE_VERSION_1;
	f.state = 3;
	sw_file_encode(&f, buf);
	put("wsfile", "valid-v1.ws", buf, SW_FILE_SIZE);

	/* Extremes that must still be accepted. */
	sample(&f);
	f.state = 0;
	f.score_raw = 0xffff;
	f.saved_at = UINT64_MAX;
	sw_blob_set_param(f.payload, 1, -0.0f);
	sw_blob_set_param(f.payload, 2, 3.4e38f);
	sw_blob_set_param(f.payload, 3, 1e-45f);
	sw_blob_set_param(f.payload, SW_PARAM_ACCEL_X, -3.4e38f);
	sw_blob_set_param(f.payload, SW_PARAM_ACCEL_X + 1, 2e6f);
	sw_file_encode(&f, buf);
	put("wsfile", "valid-extremes.ws", buf, SW_FILE_SIZE);

	/* One failed check each. */
	sample(&f);
	sw_file_encode(&f, buf);
	put("wsfile", "empty.ws", buf, 0);
	put("wsfile", "truncated-magic.ws", buf, 5);
	put("wsfile", "truncated-header.ws", buf, 20);
	put("wsfile", "truncated-payload.ws", buf, SW_FILE_SIZE - 1);
	buf[SW_FILE_SIZE] = '\n';
	put("wsfile", "trailing.ws", buf, SW_FILE_SIZE + 1);
	buf[40] ^= 1;
	put("wsfile", "bad-crc.ws", buf, SW_FILE_SIZE);

	f.state = 5;
	sw_file_encode(&f, buf);
	put("wsfile", "bad-level.ws", buf, SW_FILE_SIZE);
	f.state = 4;
	f.judgement = SW_JUDGED_STABLE;
	sw_file_encode(&f, buf);
	put("wsfile", "bad-stable-score.ws", buf, SW_FILE_SIZE);
	f.judgement = (enum sw_judgement)3;
	f.score_raw = 0;
	sw_file_encode(&f, buf);
	put("wsfile", "bad-judgement.ws", buf, SW_FILE_SIZE);
	sample(&f);
	f.version = SW_FILE_VERSION_1;
	f.state = 4;
	sw_file_encode(&f, buf);
	put("wsfile", "bad-status-v1.ws", buf, SW_FILE_SIZE);

	sample(&f);
	sw_blob_set_param(f.payload, 7, NAN);
	sw_file_encode(&f, buf);
	put("wsfile", "nan-param.ws", buf, SW_FILE_SIZE);

	sample(&f);
	sw_blob_set_param(f.payload, SW_NPARAMS, -INFINITY);
	sw_file_encode(&f, buf);
	put("wsfile", "inf-param.ws", buf, SW_FILE_SIZE);

	sample(&f);
	sw_file_encode(&f, buf);
	sw_put_le16(buf + 8, 3);
	put("wsfile", "version-3.ws", buf, SW_FILE_SIZE);
}

#define ARGV(name, s) put("cli", name, s, sizeof(s) - 1)

static void cli_seeds(void)
{
	ARGV("status-json", "status\0--json");
	ARGV("status-device", "--device\0iio:device0\0status\0--file\0/tmp/a.ws");
	ARGV("save-i2c", "--i2c\0/dev/i2c-1\0--address\0" "0x29\0save\0--force\0--max-score\0" "4.5");
	ARGV("restore", "restore\0--if-present\0-f\0/var/lib/sentral-warmstart/x.ws");
	ARGV("calibrate", "calibrate\0--timeout\0" "60\0--target-score=2.5\0--max-score\0" "5");
	ARGV("accel-cal", "--state-dir=/tmp/s\0accel-cal\0--samples\0" "128\0--no-save");
	ARGV("show", "show\0/tmp/x.ws");
	ARGV("import-board", "import-board\0/sys/bus/nvmem/devices/1-00500/nvmem\0--layout\0kw\0--force");
	ARGV("watch", "watch\0--interval\0" "60\0--margin=0.25\0--max-score\0" "4\0--poll\0" "5");
	ARGV("help", "-hV");
	ARGV("cluster", "-dfoo\0status");
	ARGV("end-of-options", "show\0--\0--json");
	ARGV("missing-arg", "save\0--file");
	ARGV("unknown", "status\0-x");
	ARGV("i2c-name", "--i2c\0sentral-sim\0--address\0" "40\0key");
	ARGV("i2c-number", "--i2c\0" "010\0--force\0status");
	ARGV("numbers", "watch\0--poll\0" "010\0--interval\0" "0x3c\0--margin\0.5");
	ARGV("show-json", "show\0/tmp/x.ws\0--json");
	ARGV("help-anywhere", "status\0--bogus\0--timeout\0x\0--help");
	ARGV("version-extra", "--version\0extra");
	ARGV("command-help", "accel-cal\0-h");
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: mkseeds DIR\n");
		return 1;
	}
	dir = argv[1];
	wsfile_seeds();
	cli_seeds();
	return 0;
}
