// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: the em7180 driver's interface told by its attributes
 * (abi.c): this release's, with and without the application note's score,
 * an older one's, a newer one's.
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
	const char *also;	/* one more, or NULL */
};

static bool has(const char *attr, void *ctx)
{
	const struct dir *d = ctx;
	const char *const *n;

	if (d->without && !strcmp(attr, d->without))
		return false;
	if (d->also && !strcmp(attr, d->also))
		return true;
	for (n = d->names; *n; n++)
		if (!strcmp(*n, attr))
			return true;
	return false;
}

/* The driver of this release on firmware with the score, as sysfs shows it. */
static const char *const current[] = {
	"calibration_data", "in_magn_calibration_auto_status",
	"in_magn_calibration_score",
	"in_anglvel_calibration_update", "in_magn_calibration_update",
	"in_accel_x_raw", "in_accel_y_raw", "in_accel_z_raw",
	"in_accel_x_calibbias", "in_accel_y_calibbias", "in_accel_z_calibbias",
	"in_magn_x_raw", "in_magn_y_raw", "in_magn_z_raw", "in_magn_scale",
	"in_rot_quaternion_raw", "name", "buffer", NULL,
};

/* The same driver on any other firmware (a USFS board's): the level only. */
static const char *const level_only[] = {
	"calibration_data", "in_magn_calibration_auto_status",
	"in_accel_x_raw", "in_accel_y_raw", "in_accel_z_raw",
	"in_accel_x_calibbias", "in_accel_y_calibbias", "in_accel_z_calibbias",
	"in_magn_x_raw", "in_magn_y_raw", "in_magn_z_raw", "in_magn_scale",
	"in_pressure_raw", "in_temp_raw", NULL,
};

/*
 * The driver before calibration_data's identity header: the identity and
 * firmware_source as attributes, the level on every firmware.
 */
static const char *const identity_attrs[] = {
	"calibration_data", "product_id", "revision_id", "rom_version",
	"ram_version", "firmware_source", "in_magn_calibration_auto_status",
	"in_accel_x_raw", "in_accel_y_raw", "in_accel_z_raw",
	"in_accel_x_calibbias", "in_accel_y_calibbias", "in_accel_z_calibbias",
	"in_magn_x_raw", "in_magn_y_raw", "in_magn_z_raw", "in_magn_scale",
	NULL,
};

/* The driver of 1.1.0: the application note's status 0..3, transient. */
static const char *const appnote[] = {
	"calibration_data", "product_id", "revision_id", "rom_version",
	"ram_version", "in_magn_calibration_auto_status",
	"in_magn_calibration_score", "in_magn_transient",
	"in_anglvel_calibration_update", "in_magn_calibration_update",
	"in_accel_x_raw", "in_accel_y_raw", "in_accel_z_raw",
	"in_accel_x_calibbias", "in_accel_y_calibbias", "in_accel_z_calibbias",
	"in_magn_x_raw", "in_magn_y_raw", "in_magn_z_raw", "in_magn_scale",
	NULL,
};

/* That driver on firmware it did not know: no calibration attribute. */
static const char *const appnote_unknown_fw[] = {
	"calibration_data", "product_id", "revision_id", "rom_version",
	"ram_version",
	"in_accel_x_raw", "in_accel_y_raw", "in_accel_z_raw",
	"in_accel_x_calibbias", "in_accel_y_calibbias", "in_accel_z_calibbias",
	"in_magn_x_raw", "in_magn_y_raw", "in_magn_z_raw", "in_magn_scale",
	"/sys/module/em7180_core/parameters/calibration_firmware", NULL,
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

static int check(const char *const *names, const char *without,
		 const char *also, struct sw_err *e)
{
	struct dir d = { names, without, also };

	sw_err_clear(e);
	return sw_abi_check("iio:device0", "1.2.0", has, &d, e);
}

/* Both of this release: no exit 78 for a chip with the level only. */
static void test_current(void **state)
{
	struct sw_err e;

	(void)state;
	assert_int_equal(check(current, NULL, NULL, &e), SW_EXIT_OK);
	assert_string_equal(e.msg, "");
	assert_int_equal(check(level_only, NULL, NULL, &e), SW_EXIT_OK);
	/* The backend reads that one's identity attributes and bare blob */
	assert_int_equal(check(identity_attrs, NULL, NULL, &e), SW_EXIT_OK);
	assert_string_equal(e.msg, "");
	/* firmware_source and the feature sensors are optional */
	assert_int_equal(check(level_only, "firmware_source", NULL, &e),
			 SW_EXIT_OK);
	assert_int_equal(check(current, NULL, "firmware_source", &e),
			 SW_EXIT_OK);
}

/*
 * 1.1.0 on the application note's firmware: its auto_status meant the
 * note's status 0..3, in_magn_transient came with it. Older.
 */
static void test_older_appnote(void **state)
{
	struct sw_err e;

	(void)state;
	assert_int_equal(check(appnote, NULL, NULL, &e), SW_EXIT_DRIVER);
	assert_int_equal(SW_EXIT_DRIVER, 78);
	assert_string_equal(e.msg,
			    "iio:device0: the em7180 driver is older than sentral-warmstart 1.2.0: it has in_magn_transient (the application note's status 0-3 in in_magn_calibration_auto_status); install the em7180 driver of release 1.2.0 (em7180-dkms) and reload it or reboot");
}

/*
 * 1.1.0 on other firmware had no calibration attribute at all; its
 * module parameter says it is that driver, not a newer one.
 */
static void test_older_unknown_firmware(void **state)
{
	struct sw_err e;

	(void)state;
	assert_int_equal(check(appnote_unknown_fw, NULL, NULL, &e),
			 SW_EXIT_DRIVER);
	assert_string_equal(e.msg,
			    "iio:device0: the em7180 driver is older than sentral-warmstart 1.2.0: it has /sys/module/em7180_core/parameters/calibration_firmware (the module parameter that listed firmware by RAM version) and lacks in_magn_calibration_auto_status; install the em7180 driver of release 1.2.0 (em7180-dkms) and reload it or reboot");
	/* without the parameter nothing tells an older driver: newer */
	assert_int_equal(check(appnote_unknown_fw,
			       "/sys/module/em7180_core/parameters/calibration_firmware",
			       NULL, &e), SW_EXIT_DRIVER);
	assert_non_null(strstr(e.msg, "lacks in_magn_calibration_auto_status, which sentral-warmstart 1.2.0 uses, and has no attribute of an earlier interface: it is newer than this tool"));
}

/* The counters' driver: older, and the message says what to install. */
static void test_older_counters(void **state)
{
	struct sw_err e;

	(void)state;
	assert_int_equal(check(counters, NULL, NULL, &e), SW_EXIT_DRIVER);
	assert_string_equal(e.msg,
			    "iio:device0: the em7180 driver is older than sentral-warmstart 1.2.0: it has in_magn_calibration_update_count (the update counters) and lacks in_anglvel_calibration_update and more; install the em7180 driver of release 1.2.0 (em7180-dkms) and reload it or reboot");
}

/* An attribute renamed by a later release, no older one: newer. */
static void test_newer(void **state)
{
	struct sw_err e;

	(void)state;
	assert_int_equal(check(level_only, "in_magn_calibration_auto_status",
			       NULL, &e), SW_EXIT_DRIVER);
	assert_string_equal(e.msg,
			    "iio:device0: the em7180 driver lacks in_magn_calibration_auto_status, which sentral-warmstart 1.2.0 uses, and has no attribute of an earlier interface: it is newer than this tool; install the sentral-warmstart of the driver's release");
}

/*
 * Each attribute the tool uses is checked, not only the newest ones; the
 * score and its flags all or none.
 */
static void test_each_required(void **state)
{
	const char *const *n;
	struct sw_err e;

	(void)state;
	for (n = current; *n; n++) {
		int ret = check(current, *n, NULL, &e);

		if (!strcmp(*n, "in_rot_quaternion_raw") || !strcmp(*n, "name") ||
		    !strcmp(*n, "buffer")) {
			assert_int_equal(ret, SW_EXIT_OK);
			continue;
		}
		assert_int_equal(ret, SW_EXIT_DRIVER);
		assert_non_null(strstr(e.msg, *n));
	}
	/* one of the score's three on a driver without the others */
	assert_int_equal(check(level_only, NULL, "in_magn_calibration_update",
			       &e), SW_EXIT_DRIVER);
	assert_non_null(strstr(e.msg, "lacks in_magn_calibration_score and more,"));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_current),
		cmocka_unit_test(test_older_appnote),
		cmocka_unit_test(test_older_unknown_firmware),
		cmocka_unit_test(test_older_counters),
		cmocka_unit_test(test_newer),
		cmocka_unit_test(test_each_required),
	};

	return cmocka_run_group_tests(tests, NULL, NULL);
}
