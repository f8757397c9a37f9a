// SPDX-License-Identifier: GPL-2.0
/*
 * The world around the simulated EM7180: where the device points, how it
 * turns, and which directions of the Earth's field its magnetometer has
 * seen. The model (patterns, regions, formulas) is documented in
 * tests/sim/README.md, "Motion and coverage".
 *
 * Integer arithmetic only: quaternions and unit vectors are Q30, angles
 * are binary (2^32 is one turn, so they wrap by themselves). Called with
 * the simulator's lock held.
 */
#include <linux/bitops.h>
#include <linux/errno.h>
#include <linux/math.h>
#include <linux/kernel.h>
#include <linux/math64.h>
#include <linux/minmax.h>
#include <linux/string.h>

#include "sim-motion.h"

#define SIM_ONE			((s64)SIM_Q30)
#define SIM_PI_Q30		3373259426LL	/* pi * 2^30 */
#define SIM_QUARTER_TURN	BIT(30)
#define SIM_HALF_TURN		BIT(31)

/* Region bands: z of the unit vector, Q30 (0.98 and 0.68: equal areas) */
#define SIM_Z_CAP		1052266988LL
#define SIM_Z_TEMPERATE		730144440LL

/* The coverage sampling grid and how far back a late advance looks */
#define SIM_SAMPLE_NS		(10 * NSEC_PER_MSEC)
#define SIM_SAMPLE_SPAN_NS	(60ULL * NSEC_PER_SEC)
/* Finite-difference step for the angular velocity of a pattern */
#define SIM_RATE_STEP_NS	NSEC_PER_MSEC

/* Pattern rates in millidegrees per second, amplitudes in degrees */
#define SIM_SPIN_MDPS		90000	/* the old "motion": 90 dps about Z */
#define SIM_F8_YAW_MDPS		36000	/* one turn of heading in 10 s */
#define SIM_F8_ROLL_MDPS	108000	/* roll swings at 0.3 Hz */
#define SIM_F8_PITCH_MDPS	216000	/* pitch at 0.6 Hz: a figure-8 */
#define SIM_F8_AMP_DEG		75
#define SIM_SPHERE_SPIN_MDPS	300000	/* spin about the body Z axis */
#define SIM_SPHERE_TILT_MDPS	36000	/* tilt 0 -> 180 -> 0 degrees in 10 s */

/* Earth field in NED, pT: 20 uT north, 45 uT down */
const s64 sim_earth_field[3] = { 20000000, 0, 45000000 };

static const char * const sim_pattern_names[SIM_NPATTERNS] = {
	[SIM_PAT_STILL] = "still",
	[SIM_PAT_SPIN] = "spin",
	[SIM_PAT_FIGURE8] = "figure8",
	[SIM_PAT_SPHERE] = "sphere",
	[SIM_PAT_PATH] = "path",
};

const char *sim_pattern_name(enum sim_pattern p)
{
	return sim_pattern_names[p];
}

static s64 sim_mul30(s64 a, s64 b)
{
	return (a * b) >> 30;
}

/* sin and cos of a binary angle, Q30 (Taylor series within 45 degrees) */
static void sim_sincos(u32 a, s32 *sin, s32 *cos)
{
	u32 b = a & (SIM_QUARTER_TURN - 1);
	bool mirror = b > SIM_QUARTER_TURN / 2;
	s64 x, x2, s, c;

	if (mirror)
		b = SIM_QUARTER_TURN - b;
	x = ((u64)b * SIM_PI_Q30) >> 31;	/* radians, Q30 */
	x2 = sim_mul30(x, x);
	s = SIM_ONE - div_s64(x2, 72);
	s = SIM_ONE - div_s64(sim_mul30(x2, s), 42);
	s = SIM_ONE - div_s64(sim_mul30(x2, s), 20);
	s = sim_mul30(x, SIM_ONE - div_s64(sim_mul30(x2, s), 6));
	c = SIM_ONE - div_s64(x2, 90);
	c = SIM_ONE - div_s64(sim_mul30(x2, c), 56);
	c = SIM_ONE - div_s64(sim_mul30(x2, c), 30);
	c = SIM_ONE - div_s64(sim_mul30(x2, c), 12);
	c = SIM_ONE - div_s64(sim_mul30(x2, c), 2);
	if (mirror)
		swap(s, c);

	switch (a >> 30) {
	case 0:
		*sin = s;
		*cos = c;
		break;
	case 1:
		*sin = c;
		*cos = -s;
		break;
	case 2:
		*sin = -s;
		*cos = -c;
		break;
	default:
		*sin = -c;
		*cos = s;
		break;
	}
}

/* atan(t), 0 <= t <= 1 (Q30), radians Q30; |error| < 1e-5 (A&S 4.4.49) */
static s64 sim_atan_q30(s64 t)
{
	static const s32 k[] = {
		22371518, -91410863, 193424926, -354656388, 1073597943,
	};
	s64 t2 = sim_mul30(t, t), p = k[0];
	int i;

	for (i = 1; i < ARRAY_SIZE(k); i++)
		p = sim_mul30(p, t2) + k[i];
	return sim_mul30(p, t);
}

/* The angle of (x, y), [0, 2^32); |x|, |y| < 2^32 */
static u32 sim_atan2(s64 y, s64 x)
{
	u64 ax = abs(x), ay = abs(y);
	u32 a;

	if (!ax && !ay)
		return 0;
	/* radians to binary angle: * 2^31 / pi */
	if (ay <= ax)
		a = div64_u64((u64)sim_atan_q30(div64_u64(ay << 30, ax)) << 31,
			      SIM_PI_Q30);
	else
		a = SIM_QUARTER_TURN -
		    div64_u64((u64)sim_atan_q30(div64_u64(ax << 30, ay)) << 31,
			      SIM_PI_Q30);
	if (x < 0)
		a = SIM_HALF_TURN - a;
	if (y < 0)
		a = -a;
	return a;
}

/**
 * sim_region() - the region of the sphere a direction falls in
 * @v: the direction, any length below 2^31
 *
 * Bands by z of the unit vector: cap z > 0.98 (region 0), 15 regions for
 * 0.68 < z <= 0.98 (1-15), 34 for 0 <= z <= 0.68 (16-49), 34 for
 * -0.68 <= z < 0 (50-83), 15 for -0.98 <= z < -0.68 (84-98) and the cap
 * z < -0.98 (99); within a band, equal sectors of longitude atan2(y, x)
 * from 0. All 100 regions have the same area.
 *
 * Return: 0..99.
 */
unsigned int sim_region(const s64 v[3])
{
	u64 n = int_sqrt64(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	u64 lon = sim_atan2(v[1], v[0]);
	s64 z;

	if (!n)
		return 0;
	z = div64_s64(v[2] * SIM_ONE, n);
	if (z > SIM_Z_CAP)
		return 0;
	if (z < -SIM_Z_CAP)
		return SIM_REGIONS - 1;
	if (z > SIM_Z_TEMPERATE)
		return 1 + ((lon * 15) >> 32);
	if (z < -SIM_Z_TEMPERATE)
		return 84 + ((lon * 15) >> 32);
	if (z >= 0)
		return 16 + ((lon * 34) >> 32);
	return 50 + ((lon * 34) >> 32);
}

/* The angle turned at rate_mdps (millidegrees/s) in t_ns, binary */
static u32 sim_turn(s64 rate_mdps, u64 t_ns)
{
	s64 per_s = div_s64(rate_mdps * (1LL << 32), 360000);
	u32 rem;
	u64 sec = div_u64_rem(t_ns, NSEC_PER_SEC, &rem);

	return (u32)(sec * per_s + div_s64(rem * per_s, NSEC_PER_SEC));
}

/* amp_deg * sin(phase), binary */
static u32 sim_swing(u32 amp_deg, u32 phase)
{
	s64 amp = div_u64((u64)amp_deg << 32, 360);
	s32 s, c;

	sim_sincos(phase, &s, &c);
	return (u32)sim_mul30(amp, s);
}

static void sim_qmul(const s32 *a, const s32 *b, s32 *r)
{
	s64 w = (s64)a[0] * b[0] - (s64)a[1] * b[1] - (s64)a[2] * b[2] -
		(s64)a[3] * b[3];
	s64 x = (s64)a[0] * b[1] + (s64)a[1] * b[0] + (s64)a[2] * b[3] -
		(s64)a[3] * b[2];
	s64 y = (s64)a[0] * b[2] - (s64)a[1] * b[3] + (s64)a[2] * b[0] +
		(s64)a[3] * b[1];
	s64 z = (s64)a[0] * b[3] + (s64)a[1] * b[2] - (s64)a[2] * b[1] +
		(s64)a[3] * b[0];

	r[0] = w >> 30;
	r[1] = x >> 30;
	r[2] = y >> 30;
	r[3] = z >> 30;
}

/* Scale to unit length, Q30; false for the zero vector */
static bool sim_qnorm(const s64 *in, s32 *out, int len)
{
	u64 n2 = 0;
	u64 n;
	int i;

	for (i = 0; i < len; i++)
		n2 += in[i] * in[i];
	n = int_sqrt64(n2);
	if (!n)
		return false;
	for (i = 0; i < len; i++)
		out[i] = div64_s64(in[i] * SIM_ONE, n);
	return true;
}

static void sim_qrenorm(s32 *q)
{
	s64 v[4] = { q[0], q[1], q[2], q[3] };

	sim_qnorm(v, q, 4);
}

/* Rotation by angle about a unit axis (Q30) */
static void sim_axis_angle(const s32 *axis, u32 angle, s32 *q)
{
	s32 s, c;

	sim_sincos(angle >> 1, &s, &c);
	q[0] = c;
	q[1] = sim_mul30(axis[0], s);
	q[2] = sim_mul30(axis[1], s);
	q[3] = sim_mul30(axis[2], s);
}

static const s32 sim_axes[3][3] = {
	{ SIM_Q30, 0, 0 }, { 0, SIM_Q30, 0 }, { 0, 0, SIM_Q30 },
};

/* The rotation of a named pattern t_ns after it began (identity at 0) */
static void sim_pattern_at(enum sim_pattern p, u64 t, s32 *q)
{
	s32 a[4], b[4], c[4], s, co;
	u32 theta;

	switch (p) {
	case SIM_PAT_SPIN:
		sim_axis_angle(sim_axes[2], sim_turn(SIM_SPIN_MDPS, t), q);
		return;
	case SIM_PAT_FIGURE8:
		/* heading turns slowly; roll and pitch trace a figure 8 */
		sim_axis_angle(sim_axes[2], sim_turn(SIM_F8_YAW_MDPS, t), a);
		sim_axis_angle(sim_axes[1],
			       sim_swing(SIM_F8_AMP_DEG,
					 sim_turn(SIM_F8_PITCH_MDPS, t)), b);
		sim_qmul(a, b, c);
		sim_axis_angle(sim_axes[0],
			       sim_swing(SIM_F8_AMP_DEG,
					 sim_turn(SIM_F8_ROLL_MDPS, t)), a);
		sim_qmul(c, a, q);
		return;
	case SIM_PAT_SPHERE:
		/*
		 * Spin about Z while Z tilts from the field's side to the
		 * other and back: the field seen by the sensor spirals over
		 * the whole sphere.
		 */
		sim_sincos(sim_turn(SIM_SPHERE_TILT_MDPS, t), &s, &co);
		theta = SIM_QUARTER_TURN - (u32)sim_mul30(SIM_QUARTER_TURN, co);
		sim_axis_angle(sim_axes[1], -theta, a);
		sim_axis_angle(sim_axes[2],
			       -sim_turn(SIM_SPHERE_SPIN_MDPS, t), b);
		sim_qmul(a, b, q);
		return;
	default:
		q[0] = SIM_Q30;
		q[1] = 0;
		q[2] = 0;
		q[3] = 0;
		return;
	}
}

/* Play the path forward to t_ns; the state only ever moves forward */
static void sim_path_seek(struct sim_motion *m, u64 t)
{
	while (m->path_pos_ns < t) {
		const struct sim_segment *sg = &m->seg[m->cur];
		u64 len = (u64)sg->ms * NSEC_PER_MSEC;
		u64 end = m->cur_start_ns + len;
		u64 until = min(end, t);
		s32 r[4], n[4];

		if (sg->rate_dps)
			m->path_moving_ns += until - m->path_pos_ns;
		m->path_pos_ns = until;
		if (until < end)
			break;
		sim_axis_angle(sg->axis, sim_turn(sg->rate_dps * 1000LL, len), r);
		sim_qmul(m->qseg, r, n);
		memcpy(m->qseg, n, sizeof(n));
		sim_qrenorm(m->qseg);
		m->cur_start_ns = end;
		m->cur = (m->cur + 1) % m->nseg;
	}
}

/* Orientation t_ns after the pattern began (paths: t never decreases) */
static void sim_orientation_at(struct sim_motion *m, u64 t, s32 *q)
{
	s32 p[4];

	if (m->pattern == SIM_PAT_PATH) {
		const struct sim_segment *sg;

		sim_path_seek(m, t);
		sg = &m->seg[m->cur];
		sim_axis_angle(sg->axis,
			       sim_turn(sg->rate_dps * 1000LL, t - m->cur_start_ns),
			       p);
		sim_qmul(m->qseg, p, q);
	} else {
		sim_pattern_at(m->pattern, t, p);
		sim_qmul(m->q0, p, q);
	}
	sim_qrenorm(q);
}

/* Angular velocity in the body frame, millidegrees per second */
static void sim_rate_at(const struct sim_motion *m, u64 t, s32 *mdps)
{
	s32 a[4], b[4], d[4];
	int i;

	if (m->pattern == SIM_PAT_PATH) {
		const struct sim_segment *sg = &m->seg[m->cur];

		for (i = 0; i < 3; i++)
			mdps[i] = sim_mul30((s64)sg->rate_dps * 1000, sg->axis[i]);
		return;
	}
	/* body increment d = p(t0)^-1 p(t1) ~ (1, w h / 2) */
	if (t < SIM_RATE_STEP_NS)
		t += SIM_RATE_STEP_NS;
	sim_pattern_at(m->pattern, t - SIM_RATE_STEP_NS, a);
	sim_pattern_at(m->pattern, t, b);
	a[1] = -a[1];
	a[2] = -a[2];
	a[3] = -a[3];
	sim_qmul(a, b, d);
	for (i = 0; i < 3; i++) {
		s64 v = d[0] < 0 ? -d[i + 1] : d[i + 1];

		/* 2 v / h rad/s in mdps: v * 2 * 180e3 / (pi * h) */
		mdps[i] = div64_s64(v * 360000 *
				    (NSEC_PER_SEC / SIM_RATE_STEP_NS),
				    SIM_PI_Q30);
	}
}

/* body = R(q)^T world, R the rotation from the body frame to NED */
static void sim_rotate_to_body(const s32 *q, const s64 *world, s64 *body)
{
	s64 w = q[0], x = q[1], y = q[2], z = q[3];
	/* Q30 */
	s64 r[3][3] = {
		{ SIM_ONE - 2 * sim_mul30(y, y) - 2 * sim_mul30(z, z),
		  2 * (sim_mul30(x, y) - sim_mul30(w, z)),
		  2 * (sim_mul30(x, z) + sim_mul30(w, y)) },
		{ 2 * (sim_mul30(x, y) + sim_mul30(w, z)),
		  SIM_ONE - 2 * sim_mul30(x, x) - 2 * sim_mul30(z, z),
		  2 * (sim_mul30(y, z) - sim_mul30(w, x)) },
		{ 2 * (sim_mul30(x, z) - sim_mul30(w, y)),
		  2 * (sim_mul30(y, z) + sim_mul30(w, x)),
		  SIM_ONE - 2 * sim_mul30(x, x) - 2 * sim_mul30(y, y) },
	};
	int i;

	for (i = 0; i < 3; i++)
		body[i] = (r[0][i] * world[0] + r[1][i] * world[1] +
			   r[2][i] * world[2]) >> 30;
}

/**
 * sim_motion_to_body() - a world (NED) vector in the device's frame
 * @m: the world
 * @world: the vector in NED, |v| < 2^32
 * @body: the same vector seen by the sensors
 */
void sim_motion_to_body(const struct sim_motion *m, const s64 world[3],
			s64 body[3])
{
	sim_rotate_to_body(m->q, world, body);
}

/* Sample the field direction on the 10 ms grid in (from, t] */
static void sim_motion_sample(struct sim_motion *m, u64 t, unsigned long *seen)
{
	u64 g = m->next_sample_ns;
	s64 body[3];
	s32 q[4];

	if (t > SIM_SAMPLE_SPAN_NS && g < t - SIM_SAMPLE_SPAN_NS)
		/* roundup() of a u64 would need libgcc on 32-bit machines */
		g = div64_u64(t - SIM_SAMPLE_SPAN_NS + SIM_SAMPLE_NS - 1,
			      SIM_SAMPLE_NS) * SIM_SAMPLE_NS;
	for (; g <= t; g += SIM_SAMPLE_NS) {
		sim_orientation_at(m, g, q);
		sim_rotate_to_body(q, sim_earth_field, body);
		__set_bit(sim_region(body), seen);
	}
}

/**
 * sim_motion_advance() - move the world on to now
 * @m: the world
 * @now: the time
 * @seen: the chip's coverage to mark while its algorithm runs, or NULL
 *
 * Return: the nanoseconds since the last advance that the device spent
 * turning.
 */
u64 sim_motion_advance(struct sim_motion *m, ktime_t now, unsigned long *seen)
{
	u64 t, before, moving;

	if (!ktime_after(now, m->now))
		return 0;
	m->now = now;
	if (m->pattern == SIM_PAT_STILL)
		return 0;

	t = ktime_to_ns(ktime_sub(now, m->start));
	before = m->path_moving_ns;
	if (seen)
		sim_motion_sample(m, t, seen);
	m->next_sample_ns = (div64_u64(t, SIM_SAMPLE_NS) + 1) * SIM_SAMPLE_NS;
	sim_orientation_at(m, t, m->q);
	sim_rate_at(m, t, m->rate_mdps);

	if (m->pattern == SIM_PAT_PATH)
		moving = m->path_moving_ns - before;
	else
		moving = t - m->prev_t_ns;
	m->prev_t_ns = t;
	return moving;
}

/* The device is turning right now */
bool sim_motion_moving(const struct sim_motion *m)
{
	if (m->pattern == SIM_PAT_PATH)
		return m->seg[m->cur].rate_dps != 0;
	return m->pattern != SIM_PAT_STILL;
}

/**
 * sim_motion_set_pattern() - start a pattern from the current orientation
 * @m: the world, advanced to now
 * @p: the pattern
 * @now: the time
 *
 * Return: 0, or -EINVAL for a path without segments.
 */
int sim_motion_set_pattern(struct sim_motion *m, enum sim_pattern p,
			   ktime_t now)
{
	if (p == SIM_PAT_PATH && !m->nseg)
		return -EINVAL;
	m->pattern = p;
	m->start = now;
	m->now = now;
	m->prev_t_ns = 0;
	m->next_sample_ns = 0;
	memcpy(m->q0, m->q, sizeof(m->q0));
	memcpy(m->qseg, m->q, sizeof(m->qseg));
	m->cur = 0;
	m->cur_start_ns = 0;
	m->path_pos_ns = 0;
	m->path_moving_ns = 0;
	memset(m->rate_mdps, 0, sizeof(m->rate_mdps));
	if (p != SIM_PAT_STILL)
		sim_rate_at(m, 0, m->rate_mdps);
	return 0;
}

/**
 * sim_motion_set_orientation() - put the device down in an orientation
 * @m: the world
 * @q: w, x, y, z of a quaternion of any length (not zero), |q[i]| <= 2^30
 * @now: the time
 *
 * The pattern becomes still.
 */
void sim_motion_set_orientation(struct sim_motion *m, const s64 q[4],
				ktime_t now)
{
	if (sim_qnorm(q, m->q, 4))
		sim_motion_set_pattern(m, SIM_PAT_STILL, now);
}

/**
 * sim_motion_add_segment() - queue a rotation at the end of the path
 * @m: the world
 * @axis: body axis, any length (not zero), |axis[i]| <= 2^30
 * @rate_dps: rate about it, -720..720 degrees per second (0: hold)
 * @ms: duration, 10..3600000 ms
 *
 * Return: 0, -EINVAL for bad values, -ENOSPC when the path is full, -EBUSY
 * while the path plays.
 */
int sim_motion_add_segment(struct sim_motion *m, const s32 axis[3],
			   s32 rate_dps, u32 ms)
{
	s64 v[3] = { axis[0], axis[1], axis[2] };
	struct sim_segment *sg;

	if (m->pattern == SIM_PAT_PATH)
		return -EBUSY;
	if (abs(rate_dps) > 720 || ms < 10 || ms > 3600000)
		return -EINVAL;
	if (m->nseg == SIM_PATH_MAX)
		return -ENOSPC;
	sg = &m->seg[m->nseg];
	if (!sim_qnorm(v, sg->axis, 3))
		return -EINVAL;
	memcpy(sg->in, axis, sizeof(sg->in));
	sg->rate_dps = rate_dps;
	sg->ms = ms;
	m->nseg++;
	return 0;
}

/* Return: 0, or -EBUSY while the path plays */
int sim_motion_clear_path(struct sim_motion *m)
{
	if (m->pattern == SIM_PAT_PATH)
		return -EBUSY;
	m->nseg = 0;
	return 0;
}

void sim_motion_init(struct sim_motion *m, ktime_t now)
{
	memset(m, 0, sizeof(*m));
	m->q[0] = SIM_Q30;
	sim_motion_set_pattern(m, SIM_PAT_STILL, now);
}
