// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: finding and checking the USFS utilities' calibration block in
 * an image of the board's EEPROM. Every image is made here.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "fake_backend.h"

static uint8_t img[SW_BOARD_EEPROM_SIZE + 1];

static enum sw_board_check parse(size_t len, enum sw_board_layout l,
				 struct sw_board_cal *cal, char *detail)
{
	return sw_board_parse(img, len, l, cal, detail, 300);
}

static void test_good_gt(void **state)
{
	struct sw_board_cal cal;
	uint8_t blob[SW_BLOB_SIZE];
	char detail[300];

	(void)state;
	fake_board_image(img, SW_BOARD_GT);
	fake_fill_blob(blob);
	assert_int_equal(parse(SW_BOARD_EEPROM_SIZE, SW_BOARD_GT, &cal, detail),
			 SW_BOARD_OK);
	assert_int_equal(cal.params_at, 0x8000);
	assert_memory_equal(cal.blob, blob, SW_BLOB_SIZE);
	assert_true(cal.accel_present);
	assert_true(cal.accel_in_range);
	assert_int_equal(cal.acc_max[0], 2049);
	assert_int_equal(cal.acc_min[2], -2045);
	/* A dump that stops right after the marker is enough. */
	assert_int_equal(parse(0x8099, SW_BOARD_GT, &cal, detail), SW_BOARD_OK);
}

static void test_good_kw(void **state)
{
	struct sw_board_cal cal;
	uint8_t blob[SW_BLOB_SIZE];
	char detail[300];

	(void)state;
	fake_board_image(img, SW_BOARD_KW);
	fake_fill_blob(blob);
	assert_int_equal(parse(SW_BOARD_EEPROM_SIZE, SW_BOARD_KW, &cal, detail),
			 SW_BOARD_OK);
	assert_int_equal(cal.params_at, 0x7f00);
	assert_memory_equal(cal.blob, blob, SW_BLOB_SIZE);
	assert_int_equal(cal.acc_max[1], 2050);
	/* Read as gt (the default): nothing there, and the message points at --layout kw. */
	assert_int_equal(parse(SW_BOARD_EEPROM_SIZE, SW_BOARD_GT, &cal, detail),
			 SW_BOARD_BLANK);
	assert_non_null(strstr(detail, "--layout kw"));
	img[0x8098] = 0x55;
	assert_int_equal(parse(SW_BOARD_EEPROM_SIZE, SW_BOARD_GT, &cal, detail),
			 SW_BOARD_MARKER_BAD);
	assert_non_null(strstr(detail, "--layout kw"));
}

static void test_blank(void **state)
{
	struct sw_board_cal cal;
	char detail[300];

	(void)state;
	memset(img, 0xff, SW_BOARD_EEPROM_SIZE);
	assert_int_equal(parse(SW_BOARD_EEPROM_SIZE, SW_BOARD_GT, &cal, detail),
			 SW_BOARD_BLANK);
	assert_string_equal(sw_board_check_name(SW_BOARD_BLANK),
			    "no calibration saved (erased)");
	assert_non_null(strstr(detail, "0x8000..0x808b are all 0xff"));
	assert_null(strstr(detail, "--layout kw"));
	assert_int_equal(parse(SW_BOARD_EEPROM_SIZE, SW_BOARD_KW, &cal, detail),
			 SW_BOARD_BLANK);
}

static void test_marker(void **state)
{
	struct sw_board_cal cal;
	char detail[300];
	int v;

	(void)state;
	/* Every value but 0xaa, 0xff (erased, half-written) included. */
	for (v = 0; v < 256; v++) {
		if (v == 0xaa)
			continue;
		fake_board_image(img, SW_BOARD_GT);
		img[0x8098] = (uint8_t)v;
		assert_int_equal(parse(SW_BOARD_EEPROM_SIZE, SW_BOARD_GT, &cal,
				       detail), SW_BOARD_MARKER_BAD);
	}
	assert_non_null(strstr(detail, "byte 0x8098 is 0xff, not 0xaa"));
}

static void test_nonfinite(void **state)
{
	static const uint32_t bad[] = { 0x7fc00000, 0xff800000, 0x7f800000,
					0x7f800001 };
	struct sw_board_cal cal;
	char detail[300];
	size_t i;
	int n;

	(void)state;
	for (i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		for (n = 1; n <= SW_NPARAMS; n += 17) {
			fake_board_image(img, SW_BOARD_GT);
			sw_put_le32(img + 0x8000 + 4 * (n - 1), bad[i]);
			assert_int_equal(parse(SW_BOARD_EEPROM_SIZE, SW_BOARD_GT,
					       &cal, detail),
					 SW_BOARD_NONFINITE);
		}
	}
	assert_non_null(strstr(detail, "parameter 35"));
	assert_non_null(strstr(detail, "at 0x8088"));
}

static void test_sizes(void **state)
{
	struct sw_board_cal cal;
	char detail[300];
	size_t len;

	(void)state;
	fake_board_image(img, SW_BOARD_GT);
	/* Short: nothing, half a page, up to the last parameter, no marker. */
	for (len = 0; len < 0x8099; len += len < 0x8000 ? 0x1000 : 1)
		assert_int_equal(parse(len, SW_BOARD_GT, &cal, detail),
				 SW_BOARD_SHORT);
	assert_int_equal(parse(0x8098, SW_BOARD_GT, &cal, detail),
			 SW_BOARD_SHORT);
	assert_non_null(strstr(detail, "32920 bytes"));
	assert_non_null(strstr(detail, "0x8000..0x8098"));
	fake_board_image(img, SW_BOARD_KW);
	assert_int_equal(parse(0x7f97, SW_BOARD_KW, &cal, detail),
			 SW_BOARD_SHORT);
	assert_int_equal(parse(0x7f98, SW_BOARD_KW, &cal, detail), SW_BOARD_OK);
	/* Longer than an M24512: not an image of one. */
	assert_int_equal(parse(SW_BOARD_EEPROM_SIZE + 1, SW_BOARD_KW, &cal,
			       detail), SW_BOARD_TOO_LARGE);
}

static void test_accel(void **state)
{
	struct sw_board_cal cal;
	char detail[300];

	(void)state;
	/* Out of the utility's bounds: still a block, the cal flagged. */
	fake_board_image(img, SW_BOARD_GT);
	sw_put_le16(img + 0x808c + 2, 1799);
	assert_int_equal(parse(SW_BOARD_EEPROM_SIZE, SW_BOARD_GT, &cal, detail),
			 SW_BOARD_OK);
	assert_true(cal.accel_present);
	assert_false(cal.accel_in_range);
	/* Never calibrated: erased. */
	memset(img + 0x808c, 0xff, SW_BOARD_ACCEL_SIZE);
	assert_int_equal(parse(SW_BOARD_EEPROM_SIZE, SW_BOARD_GT, &cal, detail),
			 SW_BOARD_OK);
	assert_false(cal.accel_present);
}

static void test_layout_names(void **state)
{
	enum sw_board_layout l = SW_BOARD_GT;

	(void)state;
	assert_true(sw_board_layout_parse("kw", &l));
	assert_int_equal(l, SW_BOARD_KW);
	assert_true(sw_board_layout_parse("gt", &l));
	assert_int_equal(l, SW_BOARD_GT);
	assert_false(sw_board_layout_parse("GT", &l));
	assert_false(sw_board_layout_parse("", &l));
	assert_string_equal(sw_board_layout_name(SW_BOARD_KW), "kw");
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_good_gt),
		cmocka_unit_test(test_good_kw),
		cmocka_unit_test(test_blank),
		cmocka_unit_test(test_marker),
		cmocka_unit_test(test_nonfinite),
		cmocka_unit_test(test_sizes),
		cmocka_unit_test(test_accel),
		cmocka_unit_test(test_layout_names),
	};

	return cmocka_run_group_tests_name("board", tests, NULL, NULL);
}
