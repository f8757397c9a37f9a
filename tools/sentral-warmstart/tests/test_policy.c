// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: the save policy's decisions.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>
#include <cmocka.h>

#include "policy.h"

static bool decide(int status, double pct, bool have_old, int old_status,
		   double old_pct, bool force, char *why, size_t len)
{
	struct sw_policy_in in = {
		.status = status, .score_raw = sw_score_raw(pct),
		.max_score = SW_DEFAULT_MAX_SCORE, .have_old = have_old,
		.old_status = old_status, .old_score_raw = sw_score_raw(old_pct),
		.force = force,
	};

	return sw_policy_save(&in, why, len);
}

static void test_incomplete_refused(void **state)
{
	char why[256];
	int st;

	(void)state;
	for (st = 0; st < 3; st++) {
		assert_false(decide(st, 1.0, false, 0, 0, false, why, sizeof(why)));
		assert_non_null(strstr(why, "incomplete"));
	}
	/* Not even when better than a file. */
	assert_false(decide(2, 1.0, true, 3, 9.0, false, why, sizeof(why)));
}

static void test_limit(void **state)
{
	char why[256];

	(void)state;
	assert_true(decide(3, 2.9, false, 0, 0, false, why, sizeof(why)));
	assert_true(decide(3, 5.0, false, 0, 0, false, why, sizeof(why)));
	assert_false(decide(3, 5.01, false, 0, 0, false, why, sizeof(why)));
	assert_non_null(strstr(why, "above the limit"));
}

static void test_configurable_limit(void **state)
{
	struct sw_policy_in in = {
		.status = 3, .score_raw = sw_score_raw(6.5), .max_score = 7.0,
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
	assert_true(decide(3, 7.0, true, 3, 9.0, false, why, sizeof(why)));
	assert_non_null(strstr(why, "better"));
	/* Above the limit and worse than the file: no. */
	assert_false(decide(3, 9.5, true, 3, 9.0, false, why, sizeof(why)));
	/* Within the limit and better: yes. */
	assert_true(decide(3, 2.0, true, 3, 4.0, false, why, sizeof(why)));
}

static void test_never_worse_than_good_file(void **state)
{
	char why[256];

	(void)state;
	/* Both within the limit, the new one worse: keep the good file. */
	assert_false(decide(3, 4.5, true, 3, 2.0, false, why, sizeof(why)));
	assert_non_null(strstr(why, "--force"));
	/* Equal: refresh allowed (gyro bias and the rest move on). */
	assert_true(decide(3, 2.0, true, 3, 2.0, false, why, sizeof(why)));
	/* An old file that was never complete is not "good". */
	assert_true(decide(3, 4.5, true, 2, 2.0, false, why, sizeof(why)));
}

/* watch: a good file is replaced only by a margin better score. */
static void test_improve_only(void **state)
{
	struct sw_policy_in in = {
		.status = 3, .max_score = SW_DEFAULT_MAX_SCORE, .have_old = true,
		.old_status = 3, .old_score_raw = sw_score_raw(3.0),
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
	in.old_status = 2;
	in.score_raw = sw_score_raw(3.0);
	assert_true(sw_policy_save(&in, why, sizeof(why)));
	in.old_status = 3;
	in.old_score_raw = sw_score_raw(6.0);
	in.score_raw = sw_score_raw(5.9);
	assert_true(sw_policy_save(&in, why, sizeof(why)));
	/* and incomplete is still no */
	in.status = 2;
	in.score_raw = sw_score_raw(1.0);
	assert_false(sw_policy_save(&in, why, sizeof(why)));
}

static void test_force(void **state)
{
	char why[256];

	(void)state;
	assert_true(decide(3, 4.5, true, 3, 2.0, true, why, sizeof(why)));
	assert_non_null(strstr(why, "forced"));
	assert_true(decide(1, 50.0, false, 0, 0, true, why, sizeof(why)));
}

/*
 * Accel offsets that differ from the saved file's are kept whatever the
 * score: put into the file, or with no usable file, saved with the chip's
 * blob as it is. A better calibration still saves everything.
 */
static void test_offsets(void **state)
{
	struct sw_policy_in in = {
		.status = 3, .score_raw = sw_score_raw(4.5),
		.max_score = SW_DEFAULT_MAX_SCORE, .have_old = true,
		.old_status = 3, .old_score_raw = sw_score_raw(2.0),
		.offsets_differ = true,
	};
	char why[256];

	(void)state;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_OFFSETS);
	assert_string_equal(why, "the accel offsets differ from the saved file's; its calibration (status 3, score 1.999%) is kept: score 4.501% is worse than the saved file's 1.999%; not replacing a good calibration (use --force)");
	/* watch's margin, an incomplete calibration: the same */
	in.improve_only = true;
	in.margin = 0.5;
	in.score_raw = sw_score_raw(1.8);
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_OFFSETS);
	in.status = 1;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_OFFSETS);
	/* better by the margin: the whole blob, offsets and all */
	in.status = 3;
	in.score_raw = sw_score_raw(1.0);
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_BLOB);
	/* no usable file: the chip's blob as it is */
	in.have_old = false;
	in.status = 1;
	in.score_raw = sw_score_raw(30.0);
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_BLOB);
	assert_non_null(strstr(why, "saving its calibration as it is, although calibration incomplete (status 1"));
	/* never from a bad read */
	in.score_raw = 0x0000;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_NOTHING);
	/* the same offsets are no reason */
	in.score_raw = sw_score_raw(30.0);
	in.offsets_differ = false;
	assert_int_equal(sw_policy_save(&in, why, sizeof(why)), SW_SAVE_NOTHING);
}

static void test_import(void **state)
{
	struct sw_policy_in in = { .old_status = 3,
				   .old_score_raw = sw_score_raw(2.5) };
	char why[256];

	(void)state;
	/* No usable file: the board's calibration is taken. */
	assert_int_equal(sw_policy_import(&in, why, sizeof(why)), SW_SAVE_BLOB);
	/* A saved one, good or not, is not judged against no score. */
	in.have_old = true;
	assert_int_equal(sw_policy_import(&in, why, sizeof(why)),
			 SW_SAVE_NOTHING);
	assert_non_null(strstr(why, "(status 3, score 2.4"));
	assert_non_null(strstr(why, "--force replaces it"));
	in.old_status = 0;
	in.old_score_raw = 0xffff;
	assert_int_equal(sw_policy_import(&in, why, sizeof(why)),
			 SW_SAVE_NOTHING);
	in.force = true;
	assert_int_equal(sw_policy_import(&in, why, sizeof(why)), SW_SAVE_BLOB);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_incomplete_refused),
		cmocka_unit_test(test_limit),
		cmocka_unit_test(test_configurable_limit),
		cmocka_unit_test(test_better_than_file),
		cmocka_unit_test(test_never_worse_than_good_file),
		cmocka_unit_test(test_force),
		cmocka_unit_test(test_improve_only),
		cmocka_unit_test(test_offsets),
		cmocka_unit_test(test_import),
	};

	return cmocka_run_group_tests_name("policy", tests, NULL, NULL);
}
