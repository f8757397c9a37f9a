// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: sphere regions, the centre fit, coverage and the hint of
 * what motion is missing.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "coverage.h"

/* The simulator's hard-iron offset (uT): the data sphere is not at 0. */
static const double offset[3] = { 25.0, -12.5, 40.0 };
#define FIELD 49.24

static void dir_at(double z, double lon, double r, double v[3])
{
	double s = sqrt(1 - z * z);

	v[0] = offset[0] + r * s * cos(lon);
	v[1] = offset[1] + r * s * sin(lon);
	v[2] = offset[2] + r * z;
}

static void test_regions(void **state)
{
	static const struct {
		double v[3];
		int region;
	} cases[] = {
		{ { 0, 0, 1 }, 0 },
		{ { 0, 0, -1 }, 99 },
		{ { 1, 0, 0 }, 16 },		/* z = 0 is north of the equator */
		{ { 0, 1, 0 }, 24 },		/* 90 degrees: sector 8 of 34 */
		{ { 1, -0.001, -0.1 }, 83 },	/* just below the equator, last sector */
		{ { 0.5, 0, 0.85 }, 1 },
		{ { -0.5, 0, -0.85 }, 91 },	/* 180 degrees: sector 7 of 15 */
	};
	size_t i;

	(void)state;
	for (i = 0; i < sizeof(cases) / sizeof(cases[0]); i++)
		assert_int_equal(sw_cov_region(cases[i].v), cases[i].region);
	assert_int_equal(sw_cov_band(0), 0);
	assert_int_equal(sw_cov_band(15), 1);
	assert_int_equal(sw_cov_band(16), 2);
	assert_int_equal(sw_cov_band(99), 5);
}

/* Uniform directions (z and longitude uniform) fill every region equally. */
static void test_regions_equal_area(void **state)
{
	static unsigned int count[SW_COV_REGIONS];
	uint32_t lcg = 1;
	int i, r;

	(void)state;
	for (i = 0; i < 200000; i++) {
		double v[3], z, lon;

		lcg = lcg * 1664525u + 1013904223u;
		z = (lcg >> 8) / 8388608.0 - 1.0;
		lcg = lcg * 1664525u + 1013904223u;
		lon = (lcg >> 8) / 16777216.0 * 2 * M_PI;
		v[0] = sqrt(1 - z * z) * cos(lon);
		v[1] = sqrt(1 - z * z) * sin(lon);
		v[2] = z;
		count[sw_cov_region(v)]++;
	}
	for (r = 0; r < SW_COV_REGIONS; r++) {
		assert_in_range(count[r], 1800, 2200);
	}
}

/* A golden-angle spiral over the whole sphere around an offset centre. */
static void test_full_sphere(void **state)
{
	static struct sw_cov c;
	enum sw_axis miss[SW_NAXES];
	char hint[256];
	int i, a;

	(void)state;
	sw_cov_init(&c);
	for (i = 0; i < 400; i++) {
		double v[3];

		dir_at(1 - 2.0 * i / 399, i * 2.39996, FIELD, v);
		sw_cov_add(&c, v);
	}
	assert_int_equal(c.fit, SW_FIT_SPHERE);
	for (a = 0; a < 3; a++)
		assert_true(fabs(c.center[a] - offset[a]) < 0.01);
	assert_true(fabs(c.radius - FIELD) < 0.01);
	assert_int_equal(sw_cov_seen(&c), SW_COV_REGIONS);
	assert_int_equal(sw_cov_missing(&c, miss), 0);
	for (a = 0; a < SW_NAXES; a++)
		assert_true(sw_cov_axis(&c, (enum sw_axis)a) == 1.0);
	sw_cov_hint(&c, hint, sizeof(hint));
	assert_non_null(strstr(hint, "every direction"));
}

/* A turn about Z alone: the samples are a ring, no centre can be found. */
static void test_spin_about_z(void **state)
{
	static struct sw_cov c;
	char hint[256];
	int i;

	(void)state;
	sw_cov_init(&c);
	for (i = 0; i < 400; i++) {
		double v[3];

		dir_at(0.91, i * 0.1, FIELD, v);
		sw_cov_add(&c, v);
	}
	assert_int_equal(c.fit, SW_FIT_PLANAR);
	assert_int_equal(sw_cov_seen(&c), 0);
	assert_int_equal(sw_cov_turned_about(&c), 2);
	sw_cov_hint(&c, hint, sizeof(hint));
	assert_non_null(strstr(hint, "only turned about its Z axis"));
	assert_non_null(strstr(hint, "tilt"));
}

/*
 * The chip updates its calibration during a spin: its output moves by the
 * change, and two rings at different heights fit a sphere, a small one.
 * The Earth's field is not that small: still a turn about Z.
 */
static void test_spin_with_update(void **state)
{
	static struct sw_cov c;
	char hint[256];
	int i;

	(void)state;
	sw_cov_init(&c);
	for (i = 0; i < 80; i++) {
		double v[3];

		dir_at(0.91, i * 0.1, FIELD, v);
		v[2] -= i < 40 ? 0 : 8.0;	/* a fifth of the Z offset learned */
		sw_cov_add(&c, v);
	}
	assert_int_equal(c.fit, SW_FIT_PLANAR);
	assert_int_equal(sw_cov_seen(&c), 0);
	assert_int_equal(sw_cov_turned_about(&c), 2);
	sw_cov_hint(&c, hint, sizeof(hint));
	assert_non_null(strstr(hint, "only turned about its Z axis"));
}

/* The upper half only: the -Z side is missing, the +Z side is not. */
static void test_upper_half(void **state)
{
	static struct sw_cov c;
	enum sw_axis miss[SW_NAXES];
	char hint[256];
	int i, n;

	(void)state;
	sw_cov_init(&c);
	for (i = 0; i < 300; i++) {
		double v[3];

		dir_at(1 - 1.2 * i / 299, i * 2.39996, FIELD, v);
		sw_cov_add(&c, v);
	}
	n = sw_cov_missing(&c, miss);
	assert_int_equal(n, 1);
	assert_int_equal(miss[0], SW_NZ);
	assert_true(sw_cov_axis(&c, SW_PZ) == 1.0);
	assert_true(sw_cov_axis(&c, SW_NZ) < 0.5);
	/* down to z = -0.2: the caps, the +Z band and both tropics */
	assert_int_equal(sw_cov_seen(&c), 1 + 15 + 34 + 34);
	sw_cov_hint(&c, hint, sizeof(hint));
	assert_string_equal(hint, "missing: upside down (-Z down)");
}

/* The worst-covered direction comes first. */
static void test_missing_order(void **state)
{
	static struct sw_cov c;
	enum sw_axis miss[SW_NAXES];
	int i, n;

	(void)state;
	sw_cov_init(&c);
	/* A cap around +X, 60 degrees wide, a little of -Z. */
	for (i = 0; i < 2000; i++) {
		double v[3], lon = i * 0.37, z = 0.5 * cos(i * 0.011);

		v[0] = offset[0] + FIELD * cos(lon * 0.15) * sqrt(1 - z * z);
		v[1] = offset[1] + FIELD * sin(lon * 0.15) * sqrt(1 - z * z);
		v[2] = offset[2] + FIELD * z;
		sw_cov_add(&c, v);
	}
	n = sw_cov_missing(&c, miss);
	assert_true(n >= 2);
	for (i = 1; i < n; i++)
		assert_true(sw_cov_axis(&c, miss[i - 1]) <=
			    sw_cov_axis(&c, miss[i]));
}

/* A device at rest adds one sample, however long it is read. */
static void test_still(void **state)
{
	static struct sw_cov c;
	double v[3] = { 30, -10, 80 };
	char hint[256];
	int i;

	(void)state;
	sw_cov_init(&c);
	for (i = 0; i < 100; i++)
		sw_cov_add(&c, v);
	assert_int_equal(c.samples, 1);
	assert_int_equal(c.fit, SW_FIT_FEW);
	sw_cov_hint(&c, hint, sizeof(hint));
	assert_string_equal(hint, "turn the device slowly in every direction");
}

/* Samples taken before a fit was possible are binned once it is. */
static void test_pending_binned(void **state)
{
	static struct sw_cov c;
	int i;

	(void)state;
	sw_cov_init(&c);
	/* a ring first: nothing can be binned */
	for (i = 0; i < 70; i++) {
		double v[3];

		dir_at(0.3, i * 0.1, FIELD, v);
		sw_cov_add(&c, v);
	}
	assert_int_equal(sw_cov_seen(&c), 0);
	assert_int_equal(c.npending, 70);
	/* then a tilt out of that plane */
	for (i = 0; i < 30; i++) {
		double v[3];

		dir_at(0.9 - i * 0.05, i * 0.5, FIELD, v);
		sw_cov_add(&c, v);
	}
	assert_int_equal(c.fit, SW_FIT_SPHERE);
	assert_int_equal(c.npending, 0);
	/* the ring's 34 regions north of the equator */
	for (i = 16; i < 50; i++)
		assert_true(c.seen[i]);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_regions),
		cmocka_unit_test(test_regions_equal_area),
		cmocka_unit_test(test_full_sphere),
		cmocka_unit_test(test_spin_about_z),
		cmocka_unit_test(test_spin_with_update),
		cmocka_unit_test(test_upper_half),
		cmocka_unit_test(test_missing_order),
		cmocka_unit_test(test_still),
		cmocka_unit_test(test_pending_binned),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
