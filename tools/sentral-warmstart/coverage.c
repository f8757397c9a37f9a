// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: magnetometer coverage of the sphere (see coverage.h).
 *
 * The chip's magnetometer output carries a hard-iron offset until it is
 * calibrated, so directions are taken from the centre of a sphere fitted
 * to the latest samples (x^2 + y^2 + z^2 = 2ax + 2by + 2cz + d, linear
 * least squares). Samples that lie in a plane, as a turn about one axis
 * gives, cannot place that centre: until a motion has given the fit a
 * third dimension they wait; afterwards the last centre found is used.
 * When the chip's calibration changes, its output moves; the window is
 * short (a few seconds) so that the fit follows.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "coverage.h"

/* z boundaries of the bands (equal areas: 1, 15, 34, 34, 15, 1 in 100). */
static const double band_top[SW_COV_BANDS] = { 1.0, 0.98, 0.68, 0.0, -0.68, -0.98 };
static const int band_n[SW_COV_BANDS] = { 1, 15, 34, 34, 15, 1 };
static const int band_first[SW_COV_BANDS] = { 0, 1, 16, 50, 84, 99 };

/* Keep a sample once it is this far (relative) from the last one kept. */
#define MIN_STEP 0.01
/* Samples before the first fit is tried. */
#define MIN_FIT 12
/* Smallest pivot of the normalised fit, relative: less is a plane. */
#define MIN_PIVOT 0.01
/*
 * The Earth's field is 25 to 65 uT; with soft iron, a sphere outside this
 * range is not the field: typically two turns about one axis, apart by a
 * change of the chip's calibration, which always fit some sphere.
 */
#define MIN_RADIUS_UT 25.0
#define MAX_RADIUS_UT 100.0
/* An axis direction less covered than this is missing. */
#define AXIS_SEEN 0.5

int sw_cov_band_first(int band)
{
	return band_first[band];
}

int sw_cov_band_size(int band)
{
	return band_n[band];
}

int sw_cov_band(int region)
{
	int b;

	for (b = SW_COV_BANDS - 1; b > 0; b--)
		if (region >= band_first[b])
			return b;
	return 0;
}

int sw_cov_region(const double v[3])
{
	double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	double z = n > 0 ? v[2] / n : 1.0;
	double lon = atan2(v[1], v[0]);
	int b, k;

	if (lon < 0)
		lon += 2 * M_PI;
	if (z > 0.98)
		b = 0;
	else if (z > 0.68)
		b = 1;
	else if (z >= 0)
		b = 2;
	else if (z >= -0.68)
		b = 3;
	else if (z >= -0.98)
		b = 4;
	else
		b = 5;
	k = (int)(lon * band_n[b] / (2 * M_PI));
	if (k >= band_n[b])
		k = band_n[b] - 1;
	return band_first[b] + k;
}

/* The centre direction of a region. */
static void region_center(int r, double d[3])
{
	int b = sw_cov_band(r), k = r - band_first[b];
	double lo = b == SW_COV_BANDS - 1 ? -1.0 : band_top[b + 1];
	double z = (band_top[b] + lo) / 2, lon = (k + 0.5) * 2 * M_PI / band_n[b];
	double s = sqrt(1 - z * z);

	d[0] = s * cos(lon);
	d[1] = s * sin(lon);
	d[2] = z;
}

/* The axis direction nearest to d. */
static enum sw_axis nearest_axis(const double d[3])
{
	int i, best = 0;

	for (i = 1; i < 3; i++)
		if (fabs(d[i]) > fabs(d[best]))
			best = i;
	return (enum sw_axis)(2 * best + (d[best] < 0));
}

const char *sw_axis_name(enum sw_axis a)
{
	static const char *const names[SW_NAXES] = {
		"+X", "-X", "+Y", "-Y", "+Z", "-Z",
	};

	return names[a];
}

void sw_cov_init(struct sw_cov *c)
{
	memset(c, 0, sizeof(*c));
}

static double dist(const double a[3], const double b[3])
{
	double d0 = a[0] - b[0], d1 = a[1] - b[1], d2 = a[2] - b[2];

	return sqrt(d0 * d0 + d1 * d1 + d2 * d2);
}

/*
 * Solve the 4x4 system m x = r by Gaussian elimination with partial
 * pivoting. Returns the smallest pivot relative to the largest diagonal
 * element: near 0 when the system is (nearly) singular.
 */
static double solve4(double m[4][5], double x[4])
{
	double maxdiag = 0, minpiv = INFINITY;
	int i, j, k;

	for (i = 0; i < 4; i++)
		if (fabs(m[i][i]) > maxdiag)
			maxdiag = fabs(m[i][i]);
	if (maxdiag == 0)
		return 0;
	for (i = 0; i < 4; i++) {
		int p = i;

		for (j = i + 1; j < 4; j++)
			if (fabs(m[j][i]) > fabs(m[p][i]))
				p = j;
		if (p != i)
			for (k = 0; k < 5; k++) {
				double t = m[i][k];

				m[i][k] = m[p][k];
				m[p][k] = t;
			}
		if (fabs(m[i][i]) < minpiv)
			minpiv = fabs(m[i][i]);
		if (m[i][i] == 0)
			return 0;
		for (j = i + 1; j < 4; j++) {
			double f = m[j][i] / m[i][i];

			for (k = i; k < 5; k++)
				m[j][k] -= f * m[i][k];
		}
	}
	for (i = 3; i >= 0; i--) {
		double s = m[i][4];

		for (j = i + 1; j < 4; j++)
			s -= m[i][j] * x[j];
		x[i] = s / m[i][i];
	}
	return minpiv / maxdiag;
}

/* Fit a sphere to the window; sets fit, center and radius. */
static void fit(struct sw_cov *c)
{
	double mean[3] = { 0 }, s = 0, m[4][5] = { { 0 } }, x[4], r2;
	unsigned int i, n = c->nwin;
	int j, k;

	if (n < MIN_FIT) {
		c->fit = SW_FIT_FEW;
		return;
	}
	for (i = 0; i < n; i++)
		for (j = 0; j < 3; j++)
			mean[j] += c->win[i][j] / n;
	for (i = 0; i < n; i++)
		s += pow(dist(c->win[i], mean), 2) / n;
	s = sqrt(s);
	if (s == 0) {
		c->fit = SW_FIT_FEW;
		return;
	}
	/* Normalised: p = (v - mean) / s; row (2p, 1), target |p|^2. */
	for (i = 0; i < n; i++) {
		double row[5];

		for (j = 0; j < 3; j++)
			row[j] = 2 * (c->win[i][j] - mean[j]) / s;
		row[3] = 1;
		row[4] = (row[0] * row[0] + row[1] * row[1] + row[2] * row[2]) / 4;
		for (j = 0; j < 4; j++)
			for (k = 0; k < 5; k++)
				m[j][k] += row[j] * row[k];
	}
	if (solve4(m, x) < MIN_PIVOT) {
		c->fit = SW_FIT_PLANAR;
		return;
	}
	r2 = x[3] + x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
	/* A tiny cap of a sphere fits any huge sphere: no better than a plane. */
	if (r2 <= 0 || sqrt(r2) > 10 || s * sqrt(r2) < MIN_RADIUS_UT ||
	    s * sqrt(r2) > MAX_RADIUS_UT) {
		c->fit = SW_FIT_PLANAR;
		return;
	}
	for (j = 0; j < 3; j++)
		c->center[j] = mean[j] + s * x[j];
	c->radius = s * sqrt(r2);
	c->have_center = true;
	c->fit = SW_FIT_SPHERE;
}

static void bin(struct sw_cov *c, const double v[3])
{
	double d[3];
	int j;

	for (j = 0; j < 3; j++)
		d[j] = v[j] - c->center[j];
	if (d[0] == 0 && d[1] == 0 && d[2] == 0)
		return;
	c->seen[sw_cov_region(d)] = true;
}

bool sw_cov_add(struct sw_cov *c, const double v[3])
{
	double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	unsigned int i;

	if (c->samples && dist(v, c->last) <= MIN_STEP * n)
		return false;
	memcpy(c->last, v, sizeof(c->last));
	c->samples++;
	memcpy(c->win[c->head], v, sizeof(c->win[0]));
	c->head = (c->head + 1) % SW_COV_WINDOW;
	if (c->nwin < SW_COV_WINDOW)
		c->nwin++;
	fit(c);
	if (!c->have_center) {
		/* Binned once a fit can place the centre; the oldest go first. */
		if (c->npending == SW_COV_PENDING) {
			memmove(c->pending[0], c->pending[1],
				sizeof(c->pending[0]) * (SW_COV_PENDING - 1));
			c->npending--;
		}
		memcpy(c->pending[c->npending++], v, sizeof(c->pending[0]));
		return true;
	}
	for (i = 0; i < c->npending; i++)
		bin(c, c->pending[i]);
	c->npending = 0;
	bin(c, v);
	return true;
}

unsigned int sw_cov_seen(const struct sw_cov *c)
{
	unsigned int n = 0;
	int r;

	for (r = 0; r < SW_COV_REGIONS; r++)
		n += c->seen[r];
	return n;
}

double sw_cov_axis(const struct sw_cov *c, enum sw_axis a)
{
	int r, all = 0, seen = 0;
	double d[3];

	for (r = 0; r < SW_COV_REGIONS; r++) {
		region_center(r, d);
		if (nearest_axis(d) != a)
			continue;
		all++;
		seen += c->seen[r];
	}
	return all ? (double)seen / all : 0;
}

int sw_cov_missing(const struct sw_cov *c, enum sw_axis *out)
{
	double f[SW_NAXES];
	int a, i, n = 0;

	for (a = 0; a < SW_NAXES; a++) {
		f[a] = sw_cov_axis(c, (enum sw_axis)a);
		if (f[a] >= AXIS_SEEN)
			continue;
		/* insertion sort, least seen first */
		for (i = n; i > 0 && f[out[i - 1]] > f[a]; i--)
			out[i] = out[i - 1];
		out[i] = (enum sw_axis)a;
		n++;
	}
	return n;
}

int sw_cov_turned_about(const struct sw_cov *c)
{
	double lo[3], hi[3], range[3], max = 0;
	unsigned int i;
	int j, best = 0;

	if (c->fit != SW_FIT_PLANAR)
		return -1;
	for (j = 0; j < 3; j++) {
		lo[j] = INFINITY;
		hi[j] = -INFINITY;
	}
	for (i = 0; i < c->nwin; i++)
		for (j = 0; j < 3; j++) {
			lo[j] = fmin(lo[j], c->win[i][j]);
			hi[j] = fmax(hi[j], c->win[i][j]);
		}
	for (j = 0; j < 3; j++) {
		range[j] = hi[j] - lo[j];
		max = fmax(max, range[j]);
		if (range[j] < range[best])
			best = j;
	}
	/*
	 * Turning about an axis leaves that component of the field alone
	 * (but for the chip's calibration updates meanwhile).
	 */
	return range[best] < 0.35 * max ? best : -1;
}

/* How to put the field along a direction: it points down (and north). */
static const char *const axis_motion[SW_NAXES] = {
	"nose down (+X down)", "nose up (-X down)",
	"right side down (+Y down)", "left side down (-Y down)",
	"flat (+Z down)", "upside down (-Z down)",
};

void sw_cov_hint(const struct sw_cov *c, char *buf, size_t len)
{
	enum sw_axis miss[SW_NAXES];
	size_t used;
	int i, n, about;

	if (c->fit == SW_FIT_FEW && !sw_cov_seen(c)) {
		snprintf(buf, len, "turn the device slowly in every direction");
		return;
	}
	about = sw_cov_turned_about(c);
	if (about >= 0 && !sw_cov_seen(c)) {
		snprintf(buf, len,
			 "it has only turned about its %c axis: also tilt it nose up and down and roll it left and right",
			 'X' + about);
		return;
	}
	if (c->fit == SW_FIT_PLANAR && !sw_cov_seen(c)) {
		snprintf(buf, len,
			 "it has only turned in one plane: turn it about its other axes too");
		return;
	}
	n = sw_cov_missing(c, miss);
	if (!n) {
		snprintf(buf, len,
			 "every direction has been seen: keep turning slowly until the chip is done");
		return;
	}
	used = (size_t)snprintf(buf, len, "missing: ");
	for (i = 0; i < n && used < len; i++)
		used += (size_t)snprintf(buf + used, len - used, "%s%s",
					 i ? ", " : "", axis_motion[miss[i]]);
}
