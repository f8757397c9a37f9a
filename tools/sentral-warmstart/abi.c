// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: the em7180 driver's sysfs interface, checked by the
 * names of its attributes (see abi.h).
 */
#include <stddef.h>

#include "abi.h"

/*
 * Every attribute of the IIO device that the driver backend reads or writes,
 * but the optional ones, which are not listed here: the identity and
 * firmware_source of the drivers before 1.2.0 (later ones have the
 * identity in calibration_data's header, caldata.h, and status says the
 * firmware's origin is unknown), the feature sensors' channels (only on
 * boards that have them) and the score below.
 */
static const char *const required[] = {
	"calibration_data",
	/* the calibration level, 0..4, on every firmware */
	"in_magn_calibration_auto_status",
	"in_accel_x_raw", "in_accel_y_raw", "in_accel_z_raw",
	"in_accel_x_calibbias", "in_accel_y_calibbias", "in_accel_z_calibbias",
	"in_magn_x_raw", "in_magn_y_raw", "in_magn_z_raw", "in_magn_scale",
};

/*
 * The application note's score and update flags: all or none, as the
 * driver makes them only for firmware that has its layout.
 */
static const char *const score[] = {
	"in_magn_calibration_score",
	"in_anglvel_calibration_update", "in_magn_calibration_update",
};

/*
 * What earlier interfaces had and this one has not: a driver with one is
 * older, whatever else it has.
 */
static const struct {
	const char *attr;
	const char *until;	/* the last interface that had it */
} older[] = {
	/* update counters, between 1.0.0 and 1.1.0 */
	{ "in_magn_calibration_update_count", "the update counters" },
	{ "in_anglvel_calibration_update_count", "the update counters" },
	/*
	 * Until the level: in_magn_calibration_auto_status was the
	 * application note's status (0..3) beside this, both made only for
	 * firmware listed by RAM version in the module parameter below or
	 * the devicetree; without them, the parameter tells that driver.
	 */
	{ "in_magn_transient",
	  "the application note's status 0-3 in in_magn_calibration_auto_status" },
	{ "/sys/module/em7180_core/parameters/calibration_firmware",
	  "the module parameter that listed firmware by RAM version" },
};

#define N(a) (sizeof(a) / sizeof((a)[0]))

/* The first attribute of an earlier interface the device has, or -1. */
static int older_attr(sw_abi_has_fn has, void *ctx)
{
	unsigned int i;

	for (i = 0; i < N(older); i++)
		if (has(older[i].attr, ctx))
			return (int)i;
	return -1;
}

/* How many of @list the device lacks; *first: the first of them, or NULL. */
static unsigned int count_missing(const char *const *list, unsigned int len,
				  sw_abi_has_fn has, void *ctx,
				  const char **first)
{
	unsigned int i, n = 0;

	*first = NULL;
	for (i = 0; i < len; i++) {
		if (has(list[i], ctx))
			continue;
		if (!*first)
			*first = list[i];
		n++;
	}
	return n;
}

int sw_abi_check(const char *name, const char *version, sw_abi_has_fn has,
		 void *ctx, struct sw_err *e)
{
	const char *missing, *score_missing;
	unsigned int n = count_missing(required, N(required), has, ctx, &missing);
	unsigned int score_n = count_missing(score, N(score), has, ctx,
					     &score_missing);
	int old = older_attr(has, ctx);

	/* None of them is firmware without the layout; some is the driver. */
	if (score_n && score_n < N(score)) {
		if (!missing)
			missing = score_missing;
		n += score_n;
	}
	if (old >= 0)
		return sw_err_set(e, SW_EXIT_DRIVER,
				  "%s: the em7180 driver is older than sentral-warmstart %s: it has %s (%s)%s%s%s; install the em7180 driver of release %s (em7180-dkms) and reload it or reboot",
				  name, version, older[old].attr,
				  older[old].until, missing ? " and lacks " : "",
				  missing ? missing : "",
				  n > 1 ? " and more" : "", version);
	if (!missing)
		return SW_EXIT_OK;
	return sw_err_set(e, SW_EXIT_DRIVER,
			  "%s: the em7180 driver lacks %s%s, which sentral-warmstart %s uses, and has no attribute of an earlier interface: it is newer than this tool; install the sentral-warmstart of the driver's release",
			  name, missing, n > 1 ? " and more" : "", version);
}
