// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: the save policy's decisions, by the score rule (firmware
 * with the application note's score) and by the stable rule (the level
 * alone), and the tolerance of the coefficients' comparison.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>
#include <cmocka.h>

#include "policy.h"

/* The score rule: a chip and a saved file with a score each. */
static bool decide(int level, double pct, bool have_old, int old_level,
		   double old_pct, bool force, char *why, size_t len)
{
	struct sw_policy_in in = {
		.level = level, .has_score = true,
		.score_raw = sw_score_raw(pct),
		.max_score = SW_DEFAULT_MAX_SCORE, .have_old = have_old,
		.old_level = old_level, .old_has_score = true,
		.old_score_raw = sw_score_raw(old_pct), .old_desc = "old",
		.force = force,
	};

	return sw_policy_save(&in, why, len);
}

static void test_not_stable_refused(void **state)
{
	static const char *const hints[] = {
		"halted", "unreliable", "figure-8", "magnetic transient",
	};
	char why[256];
	int lv;

	(void)state;
	for (lv = 0; lv < 4; lv++) {
		assert_false(decide(lv, 1.0, false, 0, 0, false, why, sizeof(why)));
		assert_non_null(strstr(why, "not stable"));
		assert_non_null(strstr(why, hints[lv]));
	}
	/* Not even when better than a file. */
	assert_false(decide(2, 1.0, true, 4, 9.0, false, why, sizeof(why)));
	/* A stable one that became a transient is not saved over a stable one. */
	assert_false(decide(3, 1.0, true, 4, 2.0, false, why, sizeof(why)));
	assert_string_equal(why, "calibration not stable (level 3 (stable with a magnetic transient), score 1.001%; needs 4): a magnetic transient: keep the device away from magnets and steel");
}

static void test_limit(void **state)
{
	char why[256];

	(void)state;
	assert_true(decide(4, 2.9, false, 0, 0, false, why, sizeof(why)));
	assert_true(decide(4, 5.0, false, 0, 0, false, why, sizeof(why)));
	assert_false(decide(4, 5.01, false, 0, 0, false, why, sizeof(why)));
	assert_non_null(strstr(why, "above the limit"));
}

static void test_configurable_limit(void **state)
{
	struct sw_policy_in in = {
		.level = 4, .has_score = true, .score_raw = sw_score_raw(6.5),
		.max_score = 7.0,
	};
	char why[256];

	(void)state;
	assert_true(sw_policy_save(&in, why, sizeof(why)));
	in.max_score = 6.0;
	assert_false(sw_policy_save(&in, why, sizeof(why)));
}

static void test_better_than_file(void **state)
{
	char why[256];

	(void)state;
	/* Above the limit but better than a worse file: an improvement. */
	assert_true(decide(4, 7.0, true, 4, 9.0, false, why, sizeof(why)));
	assert_non_null(strstr(why, "better"));
	/* Above the limit and worse than the file: no. */
	assert_false(decide(4, 9.5, true, 4, 9.0, false, why, sizeof(why)));
	/* Within the limit and better: yes. */
	assert_true(decide(4, 2.0, true, 4, 4.0, false, why, sizeof(why)));
}

static void test_never_worse_than_good_file(void **state)
{
	char why[256];

	(void)state;
	/* Both within the limit, the new one worse: keep the good file. */
	assert_false(decide(4, 4.5, true, 4, 2.0, false, why, sizeof(why)));
	assert_non_null(strstr(why, "--force"));
	/* Equal: refresh allowed (gyro bias and the rest move on). */
	assert_true(decide(4, 2.0, true, 4, 2.0, false, why, sizeof(why)));
	/* An old file that was never stable is not "good". */
	assert_true(decide(4, 4.5, true, 2, 2.0, false, why, sizeof(why)));
}

/* watch: a good file is replaced only by a margin better score. */
static void test_improve_only(void **state)
{
	struct sw_policy_in in = {
		.level = 4, .has_score = true,
		.max_score = SW_DEFAULT_MAX_SCORE, .have_old = true,
		.old_level = 4, .old_has_score = true,
		.old_score_raw = sw_score_raw(3.0),
		.improve_only = true, .margin = 0.5,
	};
	char why[256];

	(void)state;
	in.score_raw = sw_score_raw(3.0);
	assert_false(sw_policy_save(&in, why, sizeof(why)));
	assert_non_null(strstr(why, "not better than the saved 3.000% by the margin of 0.500 points"));
	in.score_raw = sw_score_raw(2.6);
	assert_false(sw_policy_save(&in, why, sizeof(why)));
	in.score_raw = sw_score_raw(2.5);
	assert_true(sw_policy_save(&in, why, sizeof(why)));
	/* margin 0: better at all, never equal */
	in.margin = 0;
	in.score_raw = sw_score_raw(3.0);
	assert_false(sw_policy_save(&in, why, sizeof(why)));
	in.score_raw = sw_score_raw(2.99);
	assert_true(sw_policy_save(&in, why, sizeof(why)));
	/* a file that is not good is replaced by any good calibration */
	in.margin = 0.5;
	in.old_level = 2;
	in.score_raw = sw_score_raw(3.0);
	assert_true(sw_policy_save(&in, why, sizeof(why)));
	in.old_level = 4;
	in.old_score_raw = sw_score_raw(6.0);
	in.score_raw = sw_score_raw(5.9);
	assert_true(sw_policy_save(&in, why, sizeof(why)));
	/* and not stable is still no */
	in.level = 2;
	in.score_raw = sw_score_raw(1.0);
	assert_false(sw_policy_save(&in, why, sizeof(why)));
}

static void test_force(void **state)
{
	char why[256];

	(void)state;
	assert_true(decide(4, 4.5, true, 4, 2.0, true, why, sizeof(why)));
	assert_non_null(strstr(why, "forced"));
	assert_true(decide(1, 50.0, false, 0, 0, true, why, sizeof(why)));
}

/*
 * The score rule against a file saved by the stable rule (no score): no
 * score to compare with, so an acceptable score replaces it, even in
 * watch; an unacceptable one does not.
 */
static void test_score_over_stable_file(void **state)
{
	struct sw_policy_in in = {
		.level = 4, .has_score = true, .score_raw = sw_score_raw(4.0),
		.max_score = SW_DEFAULT_MAX_SCORE, .have_old = true,
		.old_level = 4, .old_desc = "level 4 (stable), no score",
		.improve_only = true, .margin = 0.5,
	};
	char why[256];

	(void)state;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_BLOB);
	assert_string_equal(why, "score 4.001% is within the limit 5.000%");
	in.score_raw = sw_score_raw(6.0);
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)),
			 SW_SAVE_NOTHING);
}

/*
 * Accel offsets that differ from the saved file's are kept whatever the
 * score: put into the file, or with no usable file, saved with the chip's
 * blob as it is while it is stable. A better calibration still saves
 * everything.
 */
static void test_offsets(void **state)
{
	struct sw_policy_in in = {
		.level = 4, .has_score = true, .score_raw = sw_score_raw(4.5),
		.max_score = SW_DEFAULT_MAX_SCORE, .have_old = true,
		.old_level = 4, .old_has_score = true,
		.old_score_raw = sw_score_raw(2.0),
		.old_desc = "level 4 (stable), score 1.999%",
		.offsets_differ = true,
	};
	char why[320];

	(void)state;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_OFFSETS);
	assert_string_equal(why, "the accel offsets differ from the saved file's; its calibration (level 4 (stable), score 1.999%) is kept: score 4.501% is worse than the saved file's 1.999%; not replacing a good calibration (use --force)");
	/* watch's margin, a calibration not stable: the same */
	in.improve_only = true;
	in.margin = 0.5;
	in.score_raw = sw_score_raw(1.8);
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_OFFSETS);
	in.level = 1;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_OFFSETS);
	/* better by the margin: the whole blob, offsets and all */
	in.level = 4;
	in.score_raw = sw_score_raw(1.0);
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_BLOB);
	/* no usable file: the chip's blob as it is, if stable */
	in.have_old = false;
	in.score_raw = sw_score_raw(30.0);
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_BLOB);
	assert_string_equal(why, "the chip holds accel offsets and no usable file does: saving its calibration as it is, although score 29.999% is above the limit 5.000%");
	/* but never one that is not stable */
	in.level = 2;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_NOTHING);
	assert_non_null(strstr(why, "accel offsets are saved with its calibration once it is stable"));
	/* never from a bad read */
	in.level = 4;
	in.score_raw = 0x0000;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_NOTHING);
	/* the same offsets are no reason */
	in.score_raw = sw_score_raw(30.0);
	in.offsets_differ = false;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_NOTHING);
}

/* The stable rule: no score, so the level and the coefficients decide. */
static struct sw_policy_in stable_in(void)
{
	return (struct sw_policy_in){
		.level = 4, .max_score = SW_DEFAULT_MAX_SCORE, .have_old = true,
		.old_level = 4, .old_desc = "level 4 (stable), no score",
	};
}

static void test_stable_rule(void **state)
{
	struct sw_policy_in in = stable_in();
	char why[256];
	int lv;

	(void)state;
	/* the same coefficients: nothing to write */
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_NOTHING);
	assert_string_equal(why, "stable, and the magnetometer coefficients (parameters 18-23) are within 0.5 % of the saved file's");
	/* one that moved */
	in.mag_moved = 21;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_BLOB);
	assert_string_equal(why, "stable, and parameter 21 (mcoeffs[4]) moved from the saved file's by more than 0.5 %");
	/* not read (watch between two rises): no */
	in.mag_moved = -1;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_NOTHING);
	assert_non_null(strstr(why, "not compared"));
	/* no usable file, or one not saved stable (an import) */
	in.have_old = false;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_BLOB);
	assert_string_equal(why, "stable, and no usable saved calibration");
	in.have_old = true;
	in.old_level = 0;
	in.old_desc = "imported from the board's EEPROM";
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_BLOB);
	assert_string_equal(why, "stable, and the saved calibration (imported from the board's EEPROM) is not");
	/* offsets: with a stable calibration, the whole blob */
	in = stable_in();
	in.offsets_differ = true;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_BLOB);
	assert_string_equal(why, "stable, and the accel offsets differ from the saved file's");
	/* levels 0..3 never save, whatever moved; offsets go into the file */
	for (lv = 0; lv < 4; lv++) {
		in = stable_in();
		in.level = lv;
		in.mag_moved = 18;
		assert_int_equal(sw_policy_save(&in, why, sizeof(why)),
				 SW_SAVE_NOTHING);
		in.have_old = false;
		assert_int_equal(sw_policy_save(&in, why, sizeof(why)),
				 SW_SAVE_NOTHING);
		in.have_old = true;
		in.offsets_differ = true;
		assert_int_equal(sw_policy_save(&in, why, sizeof(why)),
				 SW_SAVE_OFFSETS);
	}
	/* the margin and the score limit are the score rule's */
	in = stable_in();
	in.improve_only = true;
	in.margin = 50;
	in.max_score = 0;
	in.mag_moved = 18;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_BLOB);
	/* --force */
	in = stable_in();
	in.level = 1;
	in.force = true;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_BLOB);
	assert_string_equal(why, "forced (level 1 (unreliable sensor data))");
}

/* |new - old| > 0.005 * max(1, |old|) */
static void test_tolerance(void **state)
{
	uint8_t chip[SW_BLOB_SIZE] = { 0 }, file[SW_BLOB_SIZE] = { 0 };

	(void)state;
	assert_false(sw_param_moved(100.4f, 100.0f));
	assert_true(sw_param_moved(100.6f, 100.0f));
	assert_false(sw_param_moved(-99.6f, -100.0f));
	assert_true(sw_param_moved(-99.4f, -100.0f));
	/* below 1 the tolerance is 0.005 absolute */
	assert_false(sw_param_moved(0.004f, 0.0f));
	assert_true(sw_param_moved(0.006f, 0.0f));
	assert_false(sw_param_moved(0.304f, 0.3f));
	assert_true(sw_param_moved(0.306f, 0.3f));

	sw_blob_set_param(file, 19, 100.0f);
	sw_blob_set_param(chip, 19, 100.4f);
	assert_int_equal(sw_params_moved(chip, file, 18, 23), 0);
	assert_int_equal(sw_blob_restored(chip, file), 0);
	sw_blob_set_param(chip, 23, 1.0f);
	assert_int_equal(sw_params_moved(chip, file, 18, 23), 23);
	assert_int_equal(sw_blob_restored(chip, file), 23);
	sw_blob_set_param(chip, 23, 0.0f);
	/* restored: the accel offsets too (-47 LSB is 0.0229 g) */
	sw_blob_set_param(file, 27, sw_lsb_to_g(-47));
	assert_int_equal(sw_params_moved(chip, file, 18, 23), 0);
	assert_int_equal(sw_blob_restored(chip, file), 27);
	sw_blob_set_param(chip, 27, sw_lsb_to_g(-47));
	assert_int_equal(sw_blob_restored(chip, file), 0);
	/* the rest (gyro bias, 33..35) is learned all the time: not compared */
	sw_blob_set_param(chip, 33, 5.0f);
	assert_int_equal(sw_blob_restored(chip, file), 0);
}

static void test_import(void **state)
{
	struct sw_policy_in in = { .old_desc = "level 4 (stable), score 2.499%" };
	char why[256];

	(void)state;
	/* No usable file: the board's calibration is taken. */
	assert_int_equal(sw_policy_import(&in, why, sizeof(why)), SW_SAVE_BLOB);
	/* A saved one, good or not, is not judged against no score. */
	in.have_old = true;
	assert_int_equal(sw_policy_import(&in, why, sizeof(why)),
			 SW_SAVE_NOTHING);
	assert_non_null(strstr(why, "(level 4 (stable), score 2.499%)"));
	assert_non_null(strstr(why, "--force replaces it"));
	in.force = true;
	assert_int_equal(sw_policy_import(&in, why, sizeof(why)), SW_SAVE_BLOB);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_not_stable_refused),
		cmocka_unit_test(test_limit),
		cmocka_unit_test(test_configurable_limit),
		cmocka_unit_test(test_better_than_file),
		cmocka_unit_test(test_never_worse_than_good_file),
		cmocka_unit_test(test_force),
		cmocka_unit_test(test_improve_only),
		cmocka_unit_test(test_score_over_stable_file),
		cmocka_unit_test(test_offsets),
		cmocka_unit_test(test_stable_rule),
		cmocka_unit_test(test_tolerance),
		cmocka_unit_test(test_import),
	};

	return cmocka_run_group_tests_name("policy", tests, NULL, NULL);
}
