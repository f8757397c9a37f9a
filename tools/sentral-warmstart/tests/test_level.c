// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: the calibration level from AlgorithmStatus (the driver's
 * table), the application note's layout check (a)-(e) that the i2c-dev
 * backend shares with the driver, and the checks of a state read.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>
#include <cmocka.h>

#include "level.h"

static void test_level_table(void **state)
{
	(void)state;
	/* first match wins */
	assert_int_equal(sw_level_of_algo_status(0x01), SW_LEVEL_HALTED);
	assert_int_equal(sw_level_of_algo_status(0x3f), SW_LEVEL_HALTED);
	assert_int_equal(sw_level_of_algo_status(0x20), SW_LEVEL_UNRELIABLE);
	assert_int_equal(sw_level_of_algo_status(0x38), SW_LEVEL_UNRELIABLE);
	assert_int_equal(sw_level_of_algo_status(0x00), SW_LEVEL_CALIBRATING);
	/* still, slowdown, a transient: still calibrating without bit 3 */
	assert_int_equal(sw_level_of_algo_status(0x16), SW_LEVEL_CALIBRATING);
	assert_int_equal(sw_level_of_algo_status(0x18), SW_LEVEL_TRANSIENT);
	assert_int_equal(sw_level_of_algo_status(0x08), SW_LEVEL_STABLE);
	assert_int_equal(sw_level_of_algo_status(0x0c), SW_LEVEL_STABLE);
	/* reserved bits: a glitch, whatever else is set */
	assert_int_equal(sw_level_of_algo_status(0xff), -1);
	assert_int_equal(sw_level_of_algo_status(0x48), -1);
	assert_int_equal(sw_level_of_algo_status(0x88), -1);

	assert_string_equal(sw_level_name(0), "halted");
	assert_string_equal(sw_level_name(1), "unreliable sensor data");
	assert_string_equal(sw_level_name(2), "calibrating");
	assert_string_equal(sw_level_name(3), "stable with a magnetic transient");
	assert_string_equal(sw_level_name(4), "stable");
	assert_string_equal(sw_level_name(5), "out of range");
	assert_string_equal(sw_level_name(-1), "out of range");
}

/* 0x43..0x4E: status, flags, score raw as the application note has them. */
static void appnote(uint8_t *r, uint8_t status, uint8_t flags, uint16_t score)
{
	memset(r, 0, SW_APPNOTE_LEN);
	r[0] = status;
	r[1] = flags;
	sw_put_le16(r + 10, score);
}

static void test_layout(void **state)
{
	uint8_t r[SW_APPNOTE_LEN];

	(void)state;
	/* complete, flags, 2.747 %, stable */
	appnote(r, 0x03, 0x03, 0x8000 + 900);
	assert_true(sw_appnote_layout(0x08, r, true));
	/* a transient in both */
	appnote(r, 0x07, 0x00, 0x8000);
	assert_true(sw_appnote_layout(0x18, r, true));
	/* calibrating in both */
	appnote(r, 0x01, 0x02, 0xffff);
	assert_true(sw_appnote_layout(0x00, r, true));

	/* (a) bits 7:4 of 0x43 */
	appnote(r, 0x13, 0x00, 0x8000);
	assert_false(sw_appnote_layout(0x08, r, true));
	assert_false(sw_appnote_layout(0x08, r, false));
	/* (b) bits 7:2 of 0x44 */
	appnote(r, 0x03, 0x04, 0x8000);
	assert_false(sw_appnote_layout(0x08, r, false));
	/* (c) a score below 0 %: 0x4D-0x4E of a USFS board read 0 */
	appnote(r, 0x03, 0x00, 0x7fff);
	assert_false(sw_appnote_layout(0x08, r, false));
	appnote(r, 0x00, 0x00, 0x0000);
	assert_false(sw_appnote_layout(0x00, r, true));
	/* (d) MagTransient in 0x43 but not in AlgorithmStatus: full check only */
	appnote(r, 0x07, 0x00, 0x8000);
	assert_false(sw_appnote_layout(0x08, r, true));
	assert_true(sw_appnote_layout(0x08, r, false));
	/* (e) complete without CalibStable, and the other way round */
	appnote(r, 0x03, 0x00, 0x8000);
	assert_false(sw_appnote_layout(0x00, r, true));
	appnote(r, 0x02, 0x00, 0x8000);
	assert_false(sw_appnote_layout(0x08, r, true));
	assert_true(sw_appnote_layout(0x08, r, false));

	/* USFS linear acceleration (-0.05 g in z: 0xff9a) in 0x43-0x44 */
	appnote(r, 0x9a, 0xff, 0x0000);
	assert_false(sw_appnote_layout(0x08, r, true));
	/* a glitch reads 0xff everywhere */
	memset(r, 0xff, sizeof(r));
	assert_false(sw_appnote_layout(0xff, r, false));
}

/* A burst of 0x38..0x4E: AlgorithmStatus, then 0x43.. at offset 11. */
static void burst(uint8_t *b, uint8_t algo, uint8_t status, uint8_t flags,
		  uint16_t score)
{
	memset(b, 0, SW_CAL_REGS_LEN);
	b[0] = algo;
	appnote(b + SW_APPNOTE_FIRST - SW_ALGO_STATUS, status, flags, score);
}

/* The i2c-dev backend's reading of one burst, read after read. */
static void test_state_of_regs(void **state)
{
	enum sw_layout layout = SW_LAYOUT_UNKNOWN;
	uint8_t b[SW_CAL_REGS_LEN];
	struct sw_cal_state cs;

	(void)state;
	assert_int_equal(SW_CAL_REGS_LEN, 23);
	/* halted: the level, and the layout not decided yet */
	burst(b, 0x01, 0x03, 0x00, 0x8000);
	assert_true(sw_cal_state_of_regs(b, &layout, &cs));
	assert_int_equal(cs.level, SW_LEVEL_HALTED);
	assert_false(cs.has_score);
	assert_int_equal(layout, SW_LAYOUT_UNKNOWN);
	/* a glitch: an error, nothing decided */
	memset(b, 0xff, sizeof(b));
	assert_false(sw_cal_state_of_regs(b, &layout, &cs));
	assert_int_equal(layout, SW_LAYOUT_UNKNOWN);
	/* running, the application note's layout: score and flags */
	burst(b, 0x08, 0x03, 0x02, 0x8000 + 900);
	assert_true(sw_cal_state_of_regs(b, &layout, &cs));
	assert_int_equal(layout, SW_LAYOUT_APPNOTE);
	assert_int_equal(cs.level, SW_LEVEL_STABLE);
	assert_true(cs.has_score);
	assert_int_equal(cs.score_raw, 0x8000 + 900);
	assert_int_equal(cs.gyro_bias_update, 1);
	assert_int_equal(cs.mag_cal_update, 0);
	/* later reads need (a)-(c) only: 0x43 a moment behind 0x38 */
	burst(b, 0x18, 0x03, 0x00, 0x8000 + 900);
	assert_true(sw_cal_state_of_regs(b, &layout, &cs));
	assert_int_equal(cs.level, SW_LEVEL_TRANSIENT);
	assert_true(cs.has_score);
	/* one that fails them demotes the firmware for good */
	burst(b, 0x08, 0x03, 0x00, 0x1234);
	assert_true(sw_cal_state_of_regs(b, &layout, &cs));
	assert_int_equal(layout, SW_LAYOUT_OTHER);
	assert_false(cs.has_score);
	assert_int_equal(cs.score_raw, 0);
	burst(b, 0x08, 0x03, 0x00, 0x8000 + 900);
	assert_true(sw_cal_state_of_regs(b, &layout, &cs));
	assert_false(cs.has_score);
	assert_int_equal(cs.level, SW_LEVEL_STABLE);

	/* a USFS board: linear acceleration in 0x3F-0x44, 0 in 0x4D-0x4E */
	layout = SW_LAYOUT_UNKNOWN;
	burst(b, 0x0c, 0x9a, 0xff, 0x0000);
	assert_true(sw_cal_state_of_regs(b, &layout, &cs));
	assert_int_equal(layout, SW_LAYOUT_OTHER);
	assert_int_equal(cs.level, SW_LEVEL_STABLE);
	assert_false(cs.has_score);
	/* at rest before the first accel sample: (c) still tells */
	layout = SW_LAYOUT_UNKNOWN;
	burst(b, 0x00, 0x00, 0x00, 0x0000);
	assert_true(sw_cal_state_of_regs(b, &layout, &cs));
	assert_int_equal(layout, SW_LAYOUT_OTHER);
	assert_int_equal(cs.level, SW_LEVEL_CALIBRATING);
}

static void test_state_check(void **state)
{
	struct sw_cal_state cs = { .level = 4 };
	char why[128];

	(void)state;
	/* the level alone: score and flags are not looked at */
	assert_true(sw_cal_state_check(&cs, why, sizeof(why)));
	cs.level = 5;
	assert_false(sw_cal_state_check(&cs, why, sizeof(why)));
	assert_string_equal(why, "calibration level 5 is not 0..4");
	cs.level = -1;
	assert_false(sw_cal_state_check(&cs, why, sizeof(why)));
	cs.level = 0;
	assert_true(sw_cal_state_check(&cs, why, sizeof(why)));
	cs.has_score = true;
	cs.score_raw = 0x7fff;
	assert_false(sw_cal_state_check(&cs, why, sizeof(why)));
	assert_non_null(strstr(why, "below 0 %"));
	cs.score_raw = 0x8000;
	cs.mag_cal_update = 2;
	assert_false(sw_cal_state_check(&cs, why, sizeof(why)));
	assert_non_null(strstr(why, "update flags"));
	cs.mag_cal_update = 1;
	assert_true(sw_cal_state_check(&cs, why, sizeof(why)));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_level_table),
		cmocka_unit_test(test_layout),
		cmocka_unit_test(test_state_of_regs),
		cmocka_unit_test(test_state_check),
	};

	return cmocka_run_group_tests_name("level", tests, NULL, NULL);
}
