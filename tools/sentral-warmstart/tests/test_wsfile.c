// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: the saved-file format, its checks and its atomic write.
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>
#include <cmocka.h>
#include <zlib.h>

#include "wsfile.h"
#include "fake_backend.h"

static void sample_file(struct sw_file *f)
{
	memset(f, 0, sizeof(*f));
	f->chip.product_id = 0x80;
	f->chip.revision_id = 0x02;
	f->chip.rom_version = 0x09e6;
	f->chip.ram_version = 0x0c05;
	f->version = SW_FILE_VERSION;
	f->state = 4;
	f->judgement = SW_JUDGED_SCORE;
	f->score_raw = 0x817a;
	f->saved_at = 0x123456789aULL;
	fake_fill_blob(f->payload);
}

static void test_roundtrip(void **state)
{
	uint8_t buf[SW_FILE_SIZE];
	struct sw_file in, out;
	char detail[160];

	(void)state;
	sample_file(&in);
	assert_int_equal(sw_file_encode(&in, buf), SW_FILE_SIZE);
	assert_int_equal(sw_file_decode(buf, sizeof(buf), &out, detail,
					 sizeof(detail)), SW_CHECK_OK);
	assert_int_equal(out.chip.product_id, 0x80);
	assert_int_equal(out.chip.revision_id, 0x02);
	assert_int_equal(out.chip.rom_version, 0x09e6);
	assert_int_equal(out.chip.ram_version, 0x0c05);
	assert_int_equal(out.version, 2);
	assert_int_equal(out.state, 4);
	assert_int_equal(out.judgement, SW_JUDGED_SCORE);
	assert_int_equal(out.score_raw, 0x817a);
	assert_true(out.saved_at == 0x123456789aULL);
	assert_memory_equal(out.payload, in.payload, SW_BLOB_SIZE);
}

/* The man page's byte layout, checked byte by byte. */
static void test_layout(void **state)
{
	uint8_t buf[SW_FILE_SIZE];
	struct sw_file f;

	(void)state;
	assert_int_equal(SW_FILE_SIZE, 176);
	sample_file(&f);
	sw_file_encode(&f, buf);
	assert_memory_equal(buf, "SNTRLWS1", 8);
	assert_int_equal(buf[8], 2);
	assert_int_equal(buf[9], 0);
	assert_int_equal(buf[10], 0x80);
	assert_int_equal(buf[11], 0x02);
	assert_int_equal(buf[12], 0xe6);
	assert_int_equal(buf[13], 0x09);
	assert_int_equal(buf[14], 0x05);
	assert_int_equal(buf[15], 0x0c);
	assert_int_equal(buf[16], 4);
	assert_int_equal(buf[17], 1);
	assert_int_equal(buf[18], 0x7a);
	assert_int_equal(buf[19], 0x81);
	assert_int_equal(buf[20], 0x9a);
	assert_int_equal(buf[24], 0x12);
	assert_int_equal(buf[27], 0);
	assert_int_equal(buf[28], 140);
	assert_int_equal(buf[29], 0);
	assert_int_equal(buf[30], 0);
	assert_int_equal(buf[31], 0);
	/* Parameter 1 = 0.5f = 0x3f000000, little-endian. */
	assert_int_equal(buf[32], 0x00);
	assert_int_equal(buf[35], 0x3f);
	assert_int_equal(sw_get_le32(buf + 172),
			 (uint32_t)crc32(0L, buf, 172));
}

static void test_every_truncation(void **state)
{
	uint8_t buf[SW_FILE_SIZE];
	struct sw_file f;
	size_t len;

	(void)state;
	sample_file(&f);
	sw_file_encode(&f, buf);
	for (len = 0; len < SW_FILE_SIZE; len++) {
		enum sw_file_check c = sw_file_decode(buf, len, NULL, NULL, 0);

		if (c != SW_CHECK_TRUNCATED)
			fail_msg("length %zu: got \"%s\"", len,
				 sw_check_name(c));
	}
}

static void test_trailing(void **state)
{
	uint8_t buf[SW_FILE_SIZE + 1];
	struct sw_file f;

	(void)state;
	sample_file(&f);
	sw_file_encode(&f, buf);
	buf[SW_FILE_SIZE] = 0;
	assert_int_equal(sw_file_decode(buf, sizeof(buf), NULL, NULL, 0),
			 SW_CHECK_TRAILING);
}

/* Which check must name a flipped bit at this offset. */
static enum sw_file_check flip_check(size_t off)
{
	if (off < 8)
		return SW_CHECK_MAGIC;
	if (off < 10)
		return SW_CHECK_VERSION;
	if (off == 28 || off == 29)
		return SW_CHECK_PAYLOAD_SIZE;
	return SW_CHECK_CRC;
}

static void test_every_bit_flip(void **state)
{
	uint8_t good[SW_FILE_SIZE], buf[SW_FILE_SIZE];
	struct sw_file f;
	size_t off;
	int bit, n = 0;

	(void)state;
	sample_file(&f);
	sw_file_encode(&f, good);
	for (off = 0; off < SW_FILE_SIZE; off++) {
		for (bit = 0; bit < 8; bit++) {
			enum sw_file_check c;

			memcpy(buf, good, sizeof(buf));
			buf[off] ^= (uint8_t)(1u << bit);
			c = sw_file_decode(buf, sizeof(buf), NULL, NULL, 0);
			if (c != flip_check(off))
				fail_msg("flip at byte %zu bit %d: got \"%s\", want \"%s\"",
					 off, bit, sw_check_name(c),
					 sw_check_name(flip_check(off)));
			n++;
		}
	}
	assert_int_equal(n, SW_FILE_SIZE * 8);
}

static void test_nonfinite(void **state)
{
	const float bad[] = { NAN, INFINITY, -INFINITY };
	uint8_t buf[SW_FILE_SIZE];
	char detail[160];
	struct sw_file f;
	size_t i;
	int n;

	(void)state;
	for (i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		for (n = 1; n <= SW_NPARAMS; n++) {
			sample_file(&f);
			sw_blob_set_param(f.payload, n, bad[i]);
			/* A valid CRC: only the value check can catch it. */
			sw_file_encode(&f, buf);
			assert_int_equal(sw_file_decode(buf, sizeof(buf), NULL,
							detail, sizeof(detail)),
					 SW_CHECK_NONFINITE);
			assert_non_null(strstr(detail, sw_param_name(n)));
		}
	}
	/* A subnormal and the largest float are finite and fine. */
	sample_file(&f);
	sw_blob_set_param(f.payload, 5, 1e-45f);
	sw_blob_set_param(f.payload, 6, 3.4028235e38f);
	sw_file_encode(&f, buf);
	assert_int_equal(sw_file_decode(buf, sizeof(buf), NULL, NULL, 0),
			 SW_CHECK_OK);
}

/* A field of a file with a good CRC: only the field check can catch it. */
static enum sw_file_check with_byte(const struct sw_file *f, size_t off,
				    uint8_t v)
{
	uint8_t buf[SW_FILE_SIZE];

	sw_file_encode(f, buf);
	buf[off] = v;
	sw_put_le32(buf + 172, (uint32_t)crc32(0L, buf, 172));
	return sw_file_decode(buf, sizeof(buf), NULL, NULL, 0);
}

static void test_bad_fields(void **state)
{
	uint8_t buf[SW_FILE_SIZE];
	char detail[160];
	struct sw_file f;

	(void)state;
	/* version 2: level 0..4, judgement 0..2 */
	sample_file(&f);
	assert_int_equal(with_byte(&f, 16, 4), SW_CHECK_OK);
	assert_int_equal(with_byte(&f, 16, 5), SW_CHECK_FIELD);
	assert_int_equal(with_byte(&f, 17, 2), SW_CHECK_FIELD);
	assert_int_equal(with_byte(&f, 17, 3), SW_CHECK_FIELD);
	assert_int_equal(with_byte(&f, 30, 1), SW_CHECK_FIELD);
	assert_int_equal(with_byte(&f, 31, 1), SW_CHECK_FIELD);

	sample_file(&f);
	sw_file_encode(&f, buf);
	buf[8] = 3;
	assert_int_equal(sw_file_decode(buf, sizeof(buf), NULL, detail,
					 sizeof(detail)), SW_CHECK_VERSION);
	assert_string_equal(detail, "format version 3, this tool reads versions 1 and 2");

	/* A score below 0 % came from a bad read (issue 14.3). */
	sample_file(&f);
	f.score_raw = 0x7fff;
	sw_file_encode(&f, buf);
	assert_int_equal(sw_file_decode(buf, sizeof(buf), NULL, NULL, 0),
			 SW_CHECK_FIELD);
	f.score_raw = 0x8000;
	sw_file_encode(&f, buf);
	assert_int_equal(sw_file_decode(buf, sizeof(buf), NULL, NULL, 0),
			 SW_CHECK_OK);
	/* judged stable or not at all: no score */
	f.judgement = SW_JUDGED_STABLE;
	f.score_raw = 0;
	assert_int_equal(with_byte(&f, 18, 0), SW_CHECK_OK);
	assert_int_equal(with_byte(&f, 19, 0x80), SW_CHECK_FIELD);
	f.judgement = SW_JUDGED_NONE;
	f.state = 0;
	assert_int_equal(with_byte(&f, 18, 0), SW_CHECK_OK);
	assert_int_equal(with_byte(&f, 18, 1), SW_CHECK_FIELD);
}

/*
 * Version 1 (before the level): status 0..3 in byte 16, byte 17 reserved,
 * always a score. Still read, and re-encoded byte for byte.
 */
static void test_version_1(void **state)
{
	uint8_t buf[SW_FILE_SIZE], again[SW_FILE_SIZE];
	struct sw_file f, back;
	char desc[96];

	(void)state;
	sample_file(&f);
	f.version = SW_FILE_VERSION_1;
	f.state = 3;
	f.judgement = SW_JUDGED_STABLE;	/* not written in version 1 */
	sw_file_encode(&f, buf);
	assert_int_equal(buf[8], 1);
	assert_int_equal(buf[16], 3);
	assert_int_equal(buf[17], 0);
	assert_int_equal(sw_file_decode(buf, sizeof(buf), &back, NULL, 0),
			 SW_CHECK_OK);
	assert_int_equal(back.version, 1);
	assert_int_equal(back.state, 3);
	assert_int_equal(back.judgement, SW_JUDGED_SCORE);
	assert_int_equal(back.score_raw, 0x817a);
	sw_file_encode(&back, again);
	assert_memory_equal(buf, again, sizeof(buf));
	/* status 3 is stable; 0..2 are not */
	assert_int_equal(sw_file_level(&back), 4);
	sw_file_describe(&back, desc, sizeof(desc));
	assert_string_equal(desc, "version 1: status 3, score 1.154%");
	back.state = 2;
	assert_int_equal(sw_file_level(&back), 2);
	assert_int_equal(with_byte(&f, 16, 4), SW_CHECK_FIELD);
	assert_int_equal(with_byte(&f, 17, 1), SW_CHECK_FIELD);
	assert_int_equal(with_byte(&f, 19, 0x7f), SW_CHECK_FIELD);
	assert_int_equal(with_byte(&f, 16, 0), SW_CHECK_OK);
}

static void test_describe(void **state)
{
	struct sw_file f;
	char desc[96];

	(void)state;
	sample_file(&f);
	sw_file_describe(&f, desc, sizeof(desc));
	assert_string_equal(desc, "level 4 (stable), score 1.154%");
	f.judgement = SW_JUDGED_STABLE;
	f.score_raw = 0;
	sw_file_describe(&f, desc, sizeof(desc));
	assert_string_equal(desc, "level 4 (stable), no score");
	assert_int_equal(sw_file_level(&f), 4);
	f.judgement = SW_JUDGED_NONE;
	f.state = 0;
	sw_file_describe(&f, desc, sizeof(desc));
	assert_string_equal(desc, "imported from the board's EEPROM");
	assert_string_equal(sw_judgement_name(SW_JUDGED_NONE), "none");
	assert_string_equal(sw_judgement_name(SW_JUDGED_SCORE), "score");
	assert_string_equal(sw_judgement_name(SW_JUDGED_STABLE), "stable");
	assert_string_equal(sw_judgement_name((enum sw_judgement)3), "?");
}

/* calibration_score as the driver prints it, and nothing else (issue 14.3). */
static void test_parse_score(void **state)
{
	static const char *const bad[] = {
		"nan", "-nan", "NAN", "inf", "-inf", "infinity", "1e3", "0x10",
		"", "-", ".5", "5.", "1 ", " 1", "100.000", "-100.001", "3,5",
		"999999999999999999999",
	};
	uint16_t raw = 0;
	size_t i;

	(void)state;
	for (i = 0; i < sizeof(bad) / sizeof(bad[0]); i++)
		if (sw_parse_score(bad[i], &raw))
			fail_msg("\"%s\" was taken for a score", bad[i]);
	assert_true(sw_parse_score("2.747", &raw));
	assert_int_equal(raw, 0x8000 + 900);
	assert_true(sw_parse_score("0.000", &raw));
	assert_int_equal(raw, 0x8000);
	/* Parsed, but below 0 %: sw_score_raw_valid() says no. */
	assert_true(sw_parse_score("-5.000", &raw));
	assert_false(sw_score_raw_valid(raw));
	assert_true(sw_parse_score("-100.000", &raw));
	assert_int_equal(raw, 0);
	/* A NaN never becomes a valid raw score. */
	assert_false(sw_score_raw_valid(sw_score_raw(0.0 / 0.0)));
}

static void test_match_chip(void **state)
{
	struct sw_chip_info chip = { 0x80, 0x02, 0x09e6, 0x0c05 };
	struct sw_file f;
	char detail[160];

	(void)state;
	sample_file(&f);
	assert_int_equal(sw_file_match_chip(&f, &chip, NULL, 0), SW_CHECK_OK);
	chip.revision_id = 0x03;	/* reported, not enforced */
	assert_int_equal(sw_file_match_chip(&f, &chip, NULL, 0), SW_CHECK_OK);
	chip.product_id = 0x81;
	assert_int_equal(sw_file_match_chip(&f, &chip, detail, sizeof(detail)),
			 SW_CHECK_PRODUCT);
	assert_string_equal(detail, "file 0x80, chip 0x81");
	chip.product_id = 0x80;
	chip.rom_version = 0x07a8;
	assert_int_equal(sw_file_match_chip(&f, &chip, NULL, 0), SW_CHECK_ROM);
	chip.rom_version = 0x09e6;
	chip.ram_version = 0;
	assert_int_equal(sw_file_match_chip(&f, &chip, NULL, 0), SW_CHECK_RAM);
}

static void test_check_names(void **state)
{
	(void)state;
	assert_string_equal(sw_check_name(SW_CHECK_MAGIC), "wrong magic");
	assert_string_equal(sw_check_name(SW_CHECK_VERSION), "unknown version");
	assert_string_equal(sw_check_name(SW_CHECK_CRC), "bad CRC");
	assert_string_equal(sw_check_name(SW_CHECK_TRUNCATED), "truncated");
	assert_string_equal(sw_check_name(SW_CHECK_PAYLOAD_SIZE), "payload size");
	assert_string_equal(sw_check_name(SW_CHECK_NONFINITE), "non-finite float");
	assert_string_equal(sw_param_name(1), "xstates[1]");
	assert_string_equal(sw_param_name(17), "nparams[9]");
	assert_string_equal(sw_param_name(18), "mcoeffs[1]");
	assert_string_equal(sw_param_name(27), "acoeffs[4]");
	assert_string_equal(sw_param_name(35), "gcoeffs[6]");
	assert_string_equal(sw_param_name(36), "?");
}

/* Seed Table 1, bit-exact; and LSB -> g -> LSB over the whole range. */
static void test_accel_units(void **state)
{
	const struct { int lsb; uint32_t bits; } t1[] = {
		{ -47, 0xBCBBE447 }, { -15, 0xBBEFDC9C }, { 46, 0x3CB7E4DE },
	};
	uint8_t b[4];
	size_t i;
	int lsb;

	(void)state;
	for (i = 0; i < 3; i++) {
		sw_blob_set_param(b, 1, sw_lsb_to_g(t1[i].lsb));
		assert_int_equal(sw_get_le32(b), t1[i].bits);
		/* Bus order is little-endian: lowest byte first. */
		assert_int_equal(b[0], t1[i].bits & 0xff);
	}
	for (lsb = -32768; lsb <= 32767; lsb++)
		if (sw_g_to_lsb(sw_lsb_to_g(lsb)) != lsb)
			fail_msg("lsb %d does not round-trip", lsb);
	/* Any float a file may hold: saturated, not wrapped to 0. */
	assert_int_equal(sw_g_to_lsb(3.4e38f), INT_MAX);
	assert_int_equal(sw_g_to_lsb(-3.4e38f), INT_MIN);
	assert_int_equal(sw_g_to_lsb(2e6f), INT_MAX);
	assert_int_equal(sw_g_to_lsb(NAN), 0);
}

static void test_score(void **state)
{
	char text[32];
	unsigned int raw;

	(void)state;
	assert_true(sw_score_pct(0x8000) == 0.0);
	assert_true(fabs(sw_score_pct(0x0000) + 100.0) < 1e-9);
	/* The driver prints 3 decimals; that is enough to recover the raw value. */
	for (raw = 0; raw <= 0xffff; raw++) {
		snprintf(text, sizeof(text), "%.3f", sw_score_pct((uint16_t)raw));
		if (sw_score_raw(strtod(text, NULL)) != raw)
			fail_msg("raw 0x%04x -> \"%s\" does not round-trip", raw,
				 text);
	}
}

/* Atomic write in a scratch directory. */
struct scratch {
	char dir[64];
	char state[128];
	char file[192];
};

static int scratch_setup(void **state)
{
	struct scratch *s = calloc(1, sizeof(*s));

	strcpy(s->dir, "/tmp/sw-test-XXXXXX");
	if (!mkdtemp(s->dir))
		return -1;
	snprintf(s->state, sizeof(s->state), "%s/state", s->dir);
	snprintf(s->file, sizeof(s->file), "%s/key.ws", s->state);
	*state = s;
	return 0;
}

static int scratch_teardown(void **state)
{
	struct scratch *s = *state;
	char cmd[128];

	snprintf(cmd, sizeof(cmd), "rm -rf '%s'", s->dir);
	if (system(cmd) != 0)
		return -1;
	free(s);
	return 0;
}

static int count_entries(const char *dir)
{
	struct dirent *de;
	DIR *d = opendir(dir);
	int n = 0;

	assert_non_null(d);
	while ((de = readdir(d)))
		if (strcmp(de->d_name, ".") && strcmp(de->d_name, ".."))
			n++;
	closedir(d);
	return n;
}

static void test_atomic_write(void **state)
{
	struct scratch *s = *state;
	uint8_t buf[SW_FILE_SIZE], back[SW_FILE_MAX_READ + 1];
	struct sw_err e;
	struct sw_file f;
	struct stat st;
	size_t len;
	int i;

	sample_file(&f);
	sw_file_encode(&f, buf);
	sw_err_clear(&e);
	umask(0);	/* the file must be 0600 whatever the umask */
	assert_int_equal(sw_file_write_atomic(s->file, buf, sizeof(buf), true,
					      &e), SW_EXIT_OK);
	umask(022);
	assert_int_equal(stat(s->state, &st), 0);
	assert_int_equal(st.st_mode & 07777, 0700);
	assert_int_equal(lstat(s->file, &st), 0);
	assert_true(S_ISREG(st.st_mode));
	assert_int_equal(st.st_mode & 07777, 0600);
	assert_int_equal(count_entries(s->state), 1);	/* no temp left */
	assert_int_equal(sw_file_read(s->file, SW_READ_STATE, back, &len, NULL,
				      &e), SW_EXIT_OK);
	assert_int_equal(len, SW_FILE_SIZE);
	assert_memory_equal(back, buf, len);

	/* Replacing: the new content, still one file. */
	for (i = 0; i < 3; i++) {
		f.score_raw = (uint16_t)(0x8100 + i);
		sw_file_encode(&f, buf);
		assert_int_equal(sw_file_write_atomic(s->file, buf, sizeof(buf),
						      true, &e), SW_EXIT_OK);
	}
	assert_int_equal(count_entries(s->state), 1);
	assert_int_equal(sw_file_read(s->file, SW_READ_STATE, back, &len, NULL,
				      &e), SW_EXIT_OK);
	assert_memory_equal(back, buf, SW_FILE_SIZE);

	/*
	 * Issue 14.5: a state directory open to others is refused, never
	 * chmod'ed: with --state-dir /var/lib it would break other services.
	 */
	assert_int_equal(chmod(s->state, 0755), 0);
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(s->file, buf, sizeof(buf), true,
					      &e), SW_EXIT_PERM);
	assert_non_null(strstr(e.msg, "group or others have access (mode 0755)"));
	assert_int_equal(stat(s->state, &st), 0);
	assert_int_equal(st.st_mode & 07777, 0755);
	assert_int_equal(count_entries(s->state), 1);
}

/*
 * Issue 14.5: a save killed between creating its temporary file and the
 * rename left it for ever. The next save removes such files: ours by name
 * and owner, older than 2 s, and not locked by a save still running.
 */
static void test_stale_temp_removed(void **state)
{
	struct scratch *s = *state;
	char stale[256], live[256], young[256], other[256];
	uint8_t buf[SW_FILE_SIZE];
	struct timespec old[2] = { { 1000, 0 }, { 1000, 0 } };
	struct sw_err e;
	struct sw_file f;
	int lock_fd;

	sample_file(&f);
	sw_file_encode(&f, buf);
	assert_int_equal(mkdir(s->state, 0700), 0);
	snprintf(stale, sizeof(stale), "%s/.key.ws.0badf00d.tmp", s->state);
	snprintf(live, sizeof(live), "%s/.key.ws.12345678.tmp", s->state);
	snprintf(young, sizeof(young), "%s/.key.ws.abcdef01.tmp", s->state);
	snprintf(other, sizeof(other), "%s/.other.ws.0badf00d.tmp", s->state);
	assert_int_equal(close(open(stale, O_CREAT | O_WRONLY, 0600)), 0);
	assert_int_equal(close(open(young, O_CREAT | O_WRONLY, 0600)), 0);
	assert_int_equal(close(open(other, O_CREAT | O_WRONLY, 0600)), 0);
	lock_fd = open(live, O_CREAT | O_WRONLY, 0600);
	assert_true(lock_fd >= 0);
	assert_int_equal(flock(lock_fd, LOCK_EX), 0);
	assert_int_equal(utimensat(AT_FDCWD, stale, old, 0), 0);
	assert_int_equal(utimensat(AT_FDCWD, live, old, 0), 0);
	assert_int_equal(utimensat(AT_FDCWD, other, old, 0), 0);
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(s->file, buf, sizeof(buf), true,
					      &e), SW_EXIT_OK);
	assert_int_equal(access(stale, F_OK), -1);
	assert_int_equal(access(live, F_OK), 0);	/* a save in progress */
	assert_int_equal(access(young, F_OK), 0);	/* just created */
	assert_int_equal(access(other, F_OK), 0);	/* another key's */
	close(lock_fd);
	assert_int_equal(count_entries(s->state), 4);
}

/*
 * Issue 14.5: "never through a symlink" held for the last component only
 * as written: "--state-dir LINK/" (a trailing slash) and a --file in a
 * symlinked directory were followed.
 */
static void test_no_symlink_dir_bypass(void **state)
{
	struct scratch *s = *state;
	uint8_t buf[SW_FILE_SIZE], back[SW_FILE_MAX_READ + 1];
	char linkdir[192], via[256];
	struct sw_err e;
	struct sw_file f;
	size_t len;

	sample_file(&f);
	sw_file_encode(&f, buf);
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(s->file, buf, sizeof(buf), true,
					      &e), SW_EXIT_OK);
	snprintf(linkdir, sizeof(linkdir), "%s/linkdir", s->dir);
	assert_int_equal(symlink(s->state, linkdir), 0);
	snprintf(via, sizeof(via), "%s//key.ws", linkdir);	/* "--state-dir LINK/" */
	sw_err_clear(&e);
	assert_int_equal(sw_file_read(via, SW_READ_STATE, back, &len, NULL, &e),
			 SW_EXIT_PERM);
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(via, buf, sizeof(buf), true, &e),
			 SW_EXIT_PERM);
	snprintf(via, sizeof(via), "%s/key.ws", linkdir);	/* --file LINK/key.ws */
	sw_err_clear(&e);
	assert_int_equal(sw_file_read(via, SW_READ_OWNED, back, &len, NULL, &e),
			 SW_EXIT_PERM);
	assert_non_null(strstr(e.msg, "symbolic link"));
	snprintf(via, sizeof(via), "%s/./key.ws", linkdir);	/* LINK/. */
	sw_err_clear(&e);
	assert_int_equal(sw_file_read(via, SW_READ_OWNED, back, &len, NULL, &e),
			 SW_EXIT_USAGE);
	/* Reading for show only: a symlink the user named is harmless. */
	snprintf(via, sizeof(via), "%s/key.ws", linkdir);
	assert_int_equal(sw_file_read(via, SW_READ_ANY, back, &len, NULL, &e),
			 SW_EXIT_OK);
}

static void test_refuses_symlink(void **state)
{
	struct scratch *s = *state;
	uint8_t buf[SW_FILE_SIZE], back[SW_FILE_MAX_READ + 1];
	char victim[192], linkdir[192], viafile[224];
	struct sw_err e;
	struct sw_file f;
	struct stat st;
	size_t len;
	int err;

	sample_file(&f);
	sw_file_encode(&f, buf);
	assert_int_equal(mkdir(s->state, 0700), 0);
	snprintf(victim, sizeof(victim), "%s/victim", s->dir);
	{
		FILE *v = fopen(victim, "w");

		assert_non_null(v);
		fputs("precious\n", v);
		fclose(v);
	}
	assert_int_equal(symlink(victim, s->file), 0);

	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(s->file, buf, sizeof(buf), true,
					      &e), SW_EXIT_PERM);
	assert_non_null(strstr(e.msg, "symbolic link"));
	assert_int_equal(lstat(s->file, &st), 0);
	assert_true(S_ISLNK(st.st_mode));
	assert_int_equal(stat(victim, &st), 0);
	assert_int_equal(st.st_size, 9);	/* untouched */
	assert_int_equal(count_entries(s->state), 1);	/* no temp left */

	/* Reading through it is refused as well. */
	sw_err_clear(&e);
	assert_int_equal(sw_file_read(s->file, SW_READ_STATE, back, &len, &err,
				      &e), SW_EXIT_PERM);
	assert_int_equal(err, ELOOP);

	/* A symlinked state directory is refused. */
	snprintf(linkdir, sizeof(linkdir), "%s/linkdir", s->dir);
	assert_int_equal(symlink(s->state, linkdir), 0);
	snprintf(viafile, sizeof(viafile), "%s/other.ws", linkdir);
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(viafile, buf, sizeof(buf), true,
					      &e), SW_EXIT_PERM);
	assert_int_equal(count_entries(s->state), 1);

	/* A target that is a directory is refused, nothing left behind. */
	assert_int_equal(unlink(s->file), 0);
	assert_int_equal(mkdir(s->file, 0700), 0);
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(s->file, buf, sizeof(buf), true,
					      &e), SW_EXIT_FILE);
	assert_int_equal(count_entries(s->state), 1);
}

static void test_read_oversized(void **state)
{
	struct scratch *s = *state;
	uint8_t big[8192] = { 0 }, back[SW_FILE_MAX_READ + 1];
	struct sw_err e;
	size_t len;
	FILE *fp;

	memcpy(big, "SNTRLWS1\x01", 9);
	assert_int_equal(mkdir(s->state, 0700), 0);
	fp = fopen(s->file, "w");
	assert_non_null(fp);
	assert_int_equal(fwrite(big, 1, sizeof(big), fp), sizeof(big));
	fclose(fp);
	sw_err_clear(&e);
	assert_int_equal(sw_file_read(s->file, SW_READ_STATE, back, &len, NULL,
				      &e), SW_EXIT_OK);
	assert_int_equal(len, SW_FILE_MAX_READ + 1);
	back[28] = 140;
	back[29] = 0;
	assert_int_equal(sw_file_decode(back, len, NULL, NULL, 0),
			 SW_CHECK_TRAILING);
}

static void expect_read(const char *path, enum sw_read_mode mode, int want,
			const char *msg)
{
	uint8_t back[SW_FILE_MAX_READ + 1];
	struct sw_err e;
	size_t len;

	sw_err_clear(&e);
	assert_int_equal(sw_file_read(path, mode, back, &len, NULL, &e), want);
	if (msg && !strstr(e.msg, msg))
		fail_msg("\"%s\" lacks \"%s\"", e.msg, msg);
}

/*
 * The state file decides what reaches the chip at boot: it is read only
 * when nobody but us can have written it or swapped it in its directory.
 */
static void test_read_trust(void **state)
{
	struct scratch *s = *state;
	uint8_t buf[SW_FILE_SIZE];
	char linkdir[192], viafile[224];
	struct sw_err e;
	struct sw_file f;
	struct stat st;

	sample_file(&f);
	sw_file_encode(&f, buf);
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(s->file, buf, sizeof(buf), true,
					      &e), SW_EXIT_OK);
	expect_read(s->file, SW_READ_STATE, SW_EXIT_OK, NULL);

	/* A file others may write. */
	assert_int_equal(chmod(s->file, 0620), 0);
	expect_read(s->file, SW_READ_STATE, SW_EXIT_PERM,
		    "refused: file writable by group or others");
	expect_read(s->file, SW_READ_OWNED, SW_EXIT_PERM,
		    "refused: file writable by group or others");
	expect_read(s->file, SW_READ_ANY, SW_EXIT_OK, NULL);
	assert_int_equal(chmod(s->file, 0600), 0);

	/* A state directory others may write: not for --file's directory. */
	assert_int_equal(chmod(s->state, 0773), 0);
	expect_read(s->file, SW_READ_STATE, SW_EXIT_PERM,
		    "refused: directory writable by group or others");
	expect_read(s->file, SW_READ_OWNED, SW_EXIT_OK, NULL);
	assert_int_equal(chmod(s->state, 0700), 0);

	/* A state directory that is a symlink. */
	snprintf(linkdir, sizeof(linkdir), "%s/linkdir", s->dir);
	assert_int_equal(symlink(s->state, linkdir), 0);
	snprintf(viafile, sizeof(viafile), "%s/key.ws", linkdir);
	expect_read(viafile, SW_READ_STATE, SW_EXIT_PERM, "symbolic link");
	expect_read(viafile, SW_READ_OWNED, SW_EXIT_PERM, "symbolic link");

	/* A missing state directory is not a missing file: /var unmounted? */
	snprintf(viafile, sizeof(viafile), "%s/absent/key.ws", s->dir);
	expect_read(viafile, SW_READ_STATE, SW_EXIT_STATEDIR, "does not exist");
	expect_read(viafile, SW_READ_OWNED, SW_EXIT_NOFILE, "does not exist");
	snprintf(viafile, sizeof(viafile), "%s/absent.ws", s->state);
	expect_read(viafile, SW_READ_STATE, SW_EXIT_NOFILE, "does not exist");

	/*
	 * Writing with --file leaves its directory's mode alone: a save to
	 * /tmp/x.ws as root used to chmod /tmp 0700.
	 */
	assert_int_equal(chmod(s->dir, 01777), 0);
	snprintf(viafile, sizeof(viafile), "%s/other.ws", s->dir);
	assert_int_equal(sw_file_write_atomic(viafile, buf, sizeof(buf), false,
					      &e), SW_EXIT_OK);
	assert_int_equal(stat(s->dir, &st), 0);
	assert_int_equal(st.st_mode & 07777, 01777);
	assert_int_equal(chmod(s->dir, 0700), 0);

	/* Someone else's file or state directory (needs root to set up). */
	if (geteuid() != 0)
		return;
	assert_int_equal(chown(s->file, 65534, 65534), 0);
	expect_read(s->file, SW_READ_STATE, SW_EXIT_PERM,
		    "refused: file owned by uid 65534, not uid 0");
	expect_read(s->file, SW_READ_OWNED, SW_EXIT_PERM,
		    "refused: file owned by uid 65534");
	assert_int_equal(chown(s->file, 0, 0), 0);
	assert_int_equal(chown(s->state, 65534, 65534), 0);
	expect_read(s->file, SW_READ_STATE, SW_EXIT_PERM,
		    "refused: directory owned by uid 65534, not uid 0");
	sw_err_clear(&e);
	assert_int_equal(sw_file_write_atomic(s->file, buf, sizeof(buf), true,
					      &e), SW_EXIT_PERM);
	assert_non_null(strstr(e.msg, "directory owned by uid 65534"));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_roundtrip),
		cmocka_unit_test(test_layout),
		cmocka_unit_test(test_every_truncation),
		cmocka_unit_test(test_trailing),
		cmocka_unit_test(test_every_bit_flip),
		cmocka_unit_test(test_nonfinite),
		cmocka_unit_test(test_bad_fields),
		cmocka_unit_test(test_version_1),
		cmocka_unit_test(test_describe),
		cmocka_unit_test(test_match_chip),
		cmocka_unit_test(test_check_names),
		cmocka_unit_test(test_accel_units),
		cmocka_unit_test(test_score),
		cmocka_unit_test(test_parse_score),
		cmocka_unit_test_setup_teardown(test_atomic_write,
						scratch_setup, scratch_teardown),
		cmocka_unit_test_setup_teardown(test_refuses_symlink,
						scratch_setup, scratch_teardown),
		cmocka_unit_test_setup_teardown(test_read_trust,
						scratch_setup, scratch_teardown),
		cmocka_unit_test_setup_teardown(test_read_oversized,
						scratch_setup, scratch_teardown),
		cmocka_unit_test_setup_teardown(test_stale_temp_removed,
						scratch_setup, scratch_teardown),
		cmocka_unit_test_setup_teardown(test_no_symlink_dir_bypass,
						scratch_setup, scratch_teardown),
	};

	return cmocka_run_group_tests_name("wsfile", tests, NULL, NULL);
}
