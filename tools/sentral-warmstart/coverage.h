/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: where the magnetometer has been. Samples are binned
 * by their direction from the centre of a sphere fitted to them, on 100
 * equal-area regions of the sphere, to show how much of it a calibration
 * motion has covered and which directions are still missing.
 */
#ifndef SW_COVERAGE_H
#define SW_COVERAGE_H

#include <stdbool.h>
#include <stddef.h>

/*
 * Bands by z of the unit vector: a cap above 0.98 (region 0), 15 regions
 * above 0.68, 34 above 0, 34 above -0.68, 15 above -0.98 and the cap
 * below (region 99); longitude sectors from atan2(y, x) = 0. Every
 * region is 1/100 of the sphere, as in the simulator (tests/sim).
 */
#define SW_COV_REGIONS 100
#define SW_COV_BANDS 6
/* Samples kept for the sphere fit: a few seconds of motion. */
#define SW_COV_WINDOW 64
/* Samples waiting for a fit before they can be binned. */
#define SW_COV_PENDING 512

/* The six directions of the sensor's axes, in the order of enum sw_axis. */
enum sw_axis { SW_PX, SW_NX, SW_PY, SW_NY, SW_PZ, SW_NZ, SW_NAXES };

enum sw_fit {
	SW_FIT_FEW,	/* not enough samples */
	SW_FIT_PLANAR,	/* the samples lie in a plane: a turn about one axis */
	SW_FIT_SPHERE,	/* a centre from a sphere fit */
};

struct sw_cov {
	double win[SW_COV_WINDOW][3];	/* latest samples, a ring */
	unsigned int nwin, head;
	double pending[SW_COV_PENDING][3];
	unsigned int npending;
	double last[3];
	unsigned int samples;		/* samples kept (moved enough) */
	bool seen[SW_COV_REGIONS];
	enum sw_fit fit;
	double center[3], radius;
	bool have_center;
};

/* Region of a direction (any length, not zero), 0..99. */
int sw_cov_region(const double v[3]);
/* Band of a region (0: +Z cap .. 5: -Z cap), its first region and size. */
int sw_cov_band(int region);
int sw_cov_band_first(int band);
int sw_cov_band_size(int band);

void sw_cov_init(struct sw_cov *c);
/*
 * One magnetometer sample, uT. Samples within 1% of the field
 * strength of the last one kept are dropped: a device at rest adds
 * nothing. Returns whether it was kept.
 */
bool sw_cov_add(struct sw_cov *c, const double v[3]);
unsigned int sw_cov_seen(const struct sw_cov *c);
/* Fraction of an axis's regions seen, 0..1 (a region belongs to its
 * nearest axis direction). */
double sw_cov_axis(const struct sw_cov *c, enum sw_axis a);
const char *sw_axis_name(enum sw_axis a);
/*
 * The axis directions less than half seen, worst first; returns how many.
 */
int sw_cov_missing(const struct sw_cov *c, enum sw_axis *out);
/*
 * The axis the device has only been turned about while the fit is
 * planar, or -1.
 */
int sw_cov_turned_about(const struct sw_cov *c);
/* What motion is missing, one line for a person. */
void sw_cov_hint(const struct sw_cov *c, char *buf, size_t len);

#endif
