// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: the em7180 driver's interface told by its attributes
 * (abi.c): this release's, an older one's, a newer one's.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>
#include <cmocka.h>

#include "abi.h"

/* A device directory: a NULL-terminated list of names, some left out. */
struct dir {
	const char *const *names;
	const char *without;	/* one name left out, or NULL */
};

static bool has(const char *attr, void *ctx)
{
	const struct dir *d = ctx;
	const char *const *n;

	if (d->without && !strcmp(attr, d->without))
		return false;
	for (n = d->names; *n; n++)
		if (!strcmp(*n, attr))
			return true;
	return false;
}

/* The driver of 1.1.0, as it shows in sysfs (and a few the tool ignores). */
static const char *const current[] = {
	"calibration_data", "product_id", "revision_id", "rom_version",
	"ram_version", "in_magn_calibration_auto_status",
	"in_magn_calibration_score", "in_magn_transient",
	"in_anglvel_calibration_update", "in_magn_calibration_update",
	"in_accel_x_raw", "in_accel_y_raw", "in_accel_z_raw",
	"in_accel_x_calibbias", "in_accel_y_calibbias", "in_accel_z_calibbias",
	"in_magn_x_raw", "in_magn_y_raw", "in_magn_z_raw", "in_magn_scale",
	"in_rot_quaternion_raw", "name", "buffer", NULL,
};

/* The driver with the update counters (before 1.1.0). */
static const char *const counters[] = {
	"calibration_data", "product_id", "revision_id", "rom_version",
	"ram_version", "in_magn_calibration_auto_status",
	"in_magn_calibration_score", "in_magn_transient",
	"in_anglvel_calibration_update_count", "in_magn_calibration_update_count",
	"in_accel_x_raw", "in_accel_y_raw", "in_accel_z_raw",
	"in_accel_x_calibbias", "in_accel_y_calibbias", "in_accel_z_calibbias",
	"in_magn_x_raw", "in_magn_y_raw", "in_magn_z_raw", "in_magn_scale",
	NULL,
};

static void test_current(void **state)
{
	struct dir d = { current, NULL };
	struct sw_err e;

	(void)state;
	sw_err_clear(&e);
	assert_int_equal(sw_abi_check("iio:device0", "1.1.0", has, &d, &e),
			 SW_EXIT_OK);
	assert_string_equal(e.msg, "");
}

/*
 * firmware_source and the feature sensors are optional: a driver before
 * 7.3 (without them, as current[] is) and one with them both pass.
 */
static void test_optional(void **state)
{
	static const char *const with[] = {
		"calibration_data", "product_id", "revision_id", "rom_version",
		"ram_version", "firmware_source",
		"in_magn_calibration_auto_status", "in_magn_calibration_score",
		"in_magn_transient", "in_anglvel_calibration_update",
		"in_magn_calibration_update",
		"in_accel_x_raw", "in_accel_y_raw", "in_accel_z_raw",
		"in_accel_x_calibbias", "in_accel_y_calibbias",
		"in_accel_z_calibbias",
		"in_magn_x_raw", "in_magn_y_raw", "in_magn_z_raw",
		"in_magn_scale", "in_pressure_raw", "in_temp_raw", NULL,
	};
	struct dir d = { with, NULL };
	struct sw_err e;

	(void)state;
	sw_err_clear(&e);
	assert_int_equal(sw_abi_check("iio:device0", "1.1.0", has, &d, &e),
			 SW_EXIT_OK);
	d.without = "firmware_source";
	assert_int_equal(sw_abi_check("iio:device0", "1.1.0", has, &d, &e),
			 SW_EXIT_OK);
	d.names = current;
	d.without = NULL;
	assert_int_equal(has("firmware_source", &d), false);
	assert_int_equal(sw_abi_check("iio:device0", "1.1.0", has, &d, &e),
			 SW_EXIT_OK);
	assert_string_equal(e.msg, "");
}

/* The counters' driver: older, and the message says what to install. */
static void test_older(void **state)
{
	struct dir d = { counters, NULL };
	struct sw_err e;

	(void)state;
	sw_err_clear(&e);
	assert_int_equal(sw_abi_check("iio:device0", "1.1.0", has, &d, &e),
			 SW_EXIT_DRIVER);
	assert_int_equal(SW_EXIT_DRIVER, 78);
	assert_string_equal(e.msg,
			    "iio:device0: the em7180 driver is older than sentral-warmstart 1.1.0: it has in_magn_calibration_update_count (the update counters) and lacks in_anglvel_calibration_update and more; install the em7180 driver of release 1.1.0 (em7180-dkms) and reload it or reboot");
}

/* An attribute renamed by a later release, no older one: newer. */
static void test_newer(void **state)
{
	struct dir d = { current, "in_magn_calibration_update" };
	struct sw_err e;

	(void)state;
	sw_err_clear(&e);
	assert_int_equal(sw_abi_check("iio:device3", "1.1.0", has, &d, &e),
			 SW_EXIT_DRIVER);
	assert_string_equal(e.msg,
			    "iio:device3: the em7180 driver lacks in_magn_calibration_update, which sentral-warmstart 1.1.0 uses, and has no attribute of an earlier interface: it is newer than this tool; install the sentral-warmstart of the driver's release");
}

/* Each attribute the tool uses is checked, not only the newest ones. */
static void test_each_required(void **state)
{
	const char *const *n;
	struct sw_err e;

	(void)state;
	for (n = current; *n; n++) {
		struct dir d = { current, *n };
		int ret;

		sw_err_clear(&e);
		ret = sw_abi_check("iio:device0", "1.1.0", has, &d, &e);
		if (!strcmp(*n, "in_rot_quaternion_raw") || !strcmp(*n, "name") ||
		    !strcmp(*n, "buffer")) {
			assert_int_equal(ret, SW_EXIT_OK);
			continue;
		}
		assert_int_equal(ret, SW_EXIT_DRIVER);
		assert_non_null(strstr(e.msg, *n));
	}
}

/*
 * Firmware not known to report the calibration: none of the five
 * calibration attributes, and that is no driver mismatch.
 */
static const char *const calibration[] = {
	"in_magn_calibration_auto_status", "in_magn_calibration_score",
	"in_magn_transient", "in_anglvel_calibration_update",
	"in_magn_calibration_update", NULL,
};

static bool has_but_calibration(const char *attr, void *ctx)
{
	const char *const *n;

	for (n = calibration; *n; n++)
		if (!strcmp(*n, attr))
			return false;
	return has(attr, ctx);
}

static void test_no_calibration(void **state)
{
	struct dir d = { current, NULL };
	struct dir old = { counters, NULL };
	struct sw_err e;

	(void)state;
	sw_err_clear(&e);
	assert_int_equal(sw_abi_check("iio:device0", "1.1.0",
				      has_but_calibration, &d, &e),
			 SW_EXIT_OK);
	/* one of them missing is still the driver */
	d.without = "in_magn_transient";
	assert_int_equal(sw_abi_check("iio:device0", "1.1.0", has, &d, &e),
			 SW_EXIT_DRIVER);
	assert_non_null(strstr(e.msg, "lacks in_magn_transient,"));
	/* and so is a driver of an earlier interface without them */
	sw_err_clear(&e);
	assert_int_equal(sw_abi_check("iio:device0", "1.1.0",
				      has_but_calibration, &old, &e),
			 SW_EXIT_DRIVER);
	assert_non_null(strstr(e.msg, "is older than"));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_current),
		cmocka_unit_test(test_optional),
		cmocka_unit_test(test_older),
		cmocka_unit_test(test_newer),
		cmocka_unit_test(test_each_required),
		cmocka_unit_test(test_no_calibration),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
