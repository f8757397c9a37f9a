// SPDX-License-Identifier: GPL-2.0
/*
 * The register-level model of the simulated EM7180: register map, parameter
 * transfer, calibration, sensor data and data-ready events.
 *
 * Facts about the chip come from the EM7180 register reference (section
 * numbers below) and the PNI warm-start application note; where the sources
 * are silent the choice made here is documented in tests/sim/README.md.
 *
 * Every function here runs with sim->lock held.
 */
#include <linux/bitmap.h>
#include <linux/bug.h>
#include <linux/kernel.h>
#include <linux/math64.h>
#include <linux/minmax.h>
#include <linux/string.h>

#include "sentral_sim.h"
#include "sim_compat.h"

/* Identity at load (knobs), EM7180 register reference §1 */
#define SIM_PRODUCT_ID		0x80
#define SIM_REVISION_ID		0x02
#define SIM_ROM_VERSION		0x09e6	/* ROM "DI02" */

/* SentralStatus bits, §1 and §3: 0x0b is "good" after reset */
#define SIM_ST_EEPROM		BIT(0)
#define SIM_ST_UPLOAD_DONE	BIT(1)
#define SIM_ST_STANDBY		BIT(3)

/* AlgorithmStatus bits, §1 */
#define SIM_AS_STANDBY		BIT(0)
#define SIM_AS_STILL		BIT(2)
#define SIM_AS_CAL_STABLE	BIT(3)
#define SIM_AS_MAG_TRANSIENT	BIT(4)

/* Rate registers hold Hz (mag) or Hz/10 (accel, gyro), §1; §3 limits */
#define SIM_MAX_RATE_REG	100

/* Warm-start parameter numbers, application note coefficient table */
#define SIM_PARAM_MCOEFF	18	/* 18..20 soft-iron gains, 21..23 offsets */
#define SIM_PARAM_ACCEL_OFFSET	27	/* 27..29, float g */
#define SIM_PARAM_GBIAS		33	/* 33..35, float dps (model's choice) */

#define SIM_MICRO		1000000
#define SIM_COEFF_LIMIT		1000000000	/* |coefficient| <= 1000 */

/* 1 LSB = 0.000488 g exactly (application note, Table 1) */
#define SIM_ACCEL_LSB_UG	488
/* 1 LSB = 5000/32768 dps and 1000/32768 uT (scaled output, §1) */
#define SIM_GYRO_FS_DPS		5000
#define SIM_MAG_FS_PT		1000000000LL
#define SIM_FS_COUNTS		32768

/* Calibration converges in this many coefficient updates */
#define SIM_CAL_STEPS		10
/* Regions of field directions seen for a complete calibration */
#define SIM_COVER_FULL		70
/* Score (percent * 1000) of the true coefficients and of the defaults */
#define SIM_SCORE_FLOOR_MILLI	2700
/* Drift: offsets step by up to 3 uT, stay within 10 uT; floor 1.5-4.5 % */
#define SIM_DRIFT_STEP_PT	3000000
#define SIM_DRIFT_RANGE_PT	10000000
#define SIM_DRIFT_FLOOR_MILLI	1500
#define SIM_DRIFT_FLOOR_SPAN	3001
#define SIM_SCORE_SPAN_MILLI	47300
#define SIM_SCORE_MAX_MILLI	99700
/* gain errors are weighted as if multiplied by a 50 uT field */
#define SIM_GAIN_WEIGHT		50

static const u32 sim_param_defaults[SIM_NPARAMS] = {
	[3] = 0x3f800000,		/* gbias_mode 1, "uint8 saved as float" */
	[4 ... 8] = 0x3c23d70a,		/* GyroThresh: 0.01 */
	[9 ... 17] = 0x3a83126f,	/* noiseLvls: 0.001 */
	[18 ... 20] = 0x3f800000,	/* mcoeffs gains 1.0 */
	[24 ... 26] = 0x3f800000,	/* acoeffs scale 1.0 */
	[30 ... 32] = 0x3f800000,	/* gcoeffs scale 1.0 */
	[52] = 0x3f333333,		/* mag merging rate 0.7, §2 */
	[53] = 0x3f19999a,		/* accel merging rate 0.6, §2 */
	[74] = 0x000803e8,		/* dynamic range: mag 1000 uT, accel 8 g */
	[75] = 0x000007d0,		/* dynamic range: gyro 2000 dps */
};

/* Power-on mcoeffs: unit gains, no offsets (micro-units, pT for offsets) */
static const s32 sim_coeff_default[SIM_NCOEFFS] = {
	SIM_MICRO, SIM_MICRO, SIM_MICRO, 0, 0, 0,
};

/* The simulated magnetometer's true soft-iron gains and hard-iron offsets */
static const s32 sim_coeff_true[SIM_NCOEFFS] = {
	900000, 1080000, 950000, 25000000, -12500000, 40000000,
};

static const s64 sim_gravity[3] = { 0, 0, 2048 };	/* NED, accel LSB */
static const s32 sim_gyro_true_bias[3] = { 12, -7, 5 };	/* LSB */

static const u8 sim_stream_base[SIM_NSTREAMS] = {
	[SIM_QUAT] = SIM_REG_QX,
	[SIM_MAG] = SIM_REG_MX,
	[SIM_ACCEL] = SIM_REG_AX,
	[SIM_GYRO] = SIM_REG_GX,
};

static const u8 sim_stream_event[SIM_NSTREAMS] = {
	[SIM_QUAT] = SIM_EV_QUATERNION,
	[SIM_MAG] = SIM_EV_MAG,
	[SIM_ACCEL] = SIM_EV_ACCEL,
	[SIM_GYRO] = SIM_EV_GYRO,
};

bool sim_in_upload(struct sentral_sim *sim, ktime_t now)
{
	return ktime_before(now, sim->upload_done_at);
}

/* The fusion algorithm executes: running, not in standby, not paused */
bool sim_algo_running(struct sentral_sim *sim, ktime_t now)
{
	u8 algo = sim->regs[SIM_REG_ALGO_CONTROL];

	return !sim_in_upload(sim, now) && !sim->wedged &&
	       (sim->regs[SIM_REG_HOST_CONTROL] & SIM_HOST_RUN) &&
	       !(algo & (SIM_ALGO_STANDBY | SIM_ALGO_PARAM_PROC)) &&
	       /* its sensor bus is the host's (§3 item 9) */
	       !sim_usfs_passthrough(sim);
}

static u64 sim_coeff_error(struct sentral_sim *sim, const s32 *coeff)
{
	u64 err = 0;
	int i;

	for (i = 0; i < SIM_NCOEFFS; i++) {
		u64 d = abs((s64)coeff[i] - sim->coeff_true[i]);

		err += i < 3 ? d * SIM_GAIN_WEIGHT : d;
	}
	return err;
}

/* CalStatus from the remaining error relative to the uncalibrated one */
u8 sim_cal_status(struct sentral_sim *sim)
{
	u64 err = sim_coeff_error(sim, sim->coeff) * 100;
	u64 ref = sim_coeff_error(sim, sim_coeff_default);

	if (err > ref * 70)
		return 0;
	if (err > ref * 35)
		return 1;
	if (err > ref * 5)
		return 2;
	return 3;
}

/* Score registers: raw = 32768 + round(percent * 327.68), seed register map */
u16 sim_cal_score_raw(struct sentral_sim *sim)
{
	u64 err = min_t(u64, sim_coeff_error(sim, sim->coeff), 1ULL << 40);
	u64 ref = sim_coeff_error(sim, sim_coeff_default);
	u64 milli;

	milli = sim->score_floor_milli +
		div64_u64(err * SIM_SCORE_SPAN_MILLI + ref / 2, ref);
	milli = min_t(u64, milli, SIM_SCORE_MAX_MILLI);
	return 32768 + div64_u64(milli * 32768 + 50000, 100000);
}

static s32 sim_decode_coeff(u32 bits)
{
	s64 v;

	if (sim_f32_to_scaled(bits, SIM_MICRO, 1, &v))
		return SIM_COEFF_LIMIT;	/* NaN/Inf/huge: far from any truth */
	return clamp_t(s64, v, -SIM_COEFF_LIMIT, SIM_COEFF_LIMIT);
}

/* Restoring mcoeffs puts them back at once; convergence restarts there */
static void sim_coeff_restored(struct sentral_sim *sim, unsigned int idx)
{
	sim->coeff[idx] = sim_decode_coeff(sim->params[SIM_PARAM_MCOEFF + idx]);
	memcpy(sim->coeff_from, sim->coeff, sizeof(sim->coeff));
	sim->cal_ns = 0;
	sim->cal_step = 0;
	bitmap_zero(sim->cal_seen, SIM_REGIONS);
}

/*
 * Convergence is limited by both the time spent moving and the field
 * directions seen: step k of 10 needs k/10 of cal_duration_ms and k/10
 * of SIM_COVER_FULL regions.
 */
static void sim_cal_progress(struct sentral_sim *sim)
{
	u64 dur = (u64)sim->cal_duration_ms * NSEC_PER_MSEC;
	unsigned int seen = bitmap_weight(sim->cal_seen, SIM_REGIONS);
	bool changed = false;
	unsigned int k;
	int i;

	k = sim->cal_ns >= dur ? SIM_CAL_STEPS :
		div64_u64(sim->cal_ns * SIM_CAL_STEPS, dur);
	k = min(k, min(seen * SIM_CAL_STEPS / SIM_COVER_FULL, SIM_CAL_STEPS));
	if (k <= sim->cal_step)
		return;
	sim->cal_step = k;

	for (i = 0; i < SIM_NCOEFFS; i++) {
		s64 from = sim->coeff_from[i];
		s32 c = from + div_s64((sim->coeff_true[i] - from) * k,
				       SIM_CAL_STEPS);

		if (c == sim->coeff[i])
			continue;
		sim->coeff[i] = c;
		sim->params[SIM_PARAM_MCOEFF + i] = sim_f32_from_ratio(c, SIM_MICRO);
		changed = true;
	}
	if (changed) {
		sim->cal_flags |= SIM_CAL_MAG_UPDATE;
		sim->cal_updates[0]++;
	}
}

/* A fixed LCG (Numerical Recipes): the same drifts after every load */
static u32 sim_drift_next(struct sentral_sim *sim, u32 span)
{
	sim->drift_rng = sim->drift_rng * 1664525 + 1013904223;
	return (u32)(((u64)(sim->drift_rng >> 8) * span) >> 24);
}

/*
 * The magnetic surroundings change: each hard-iron offset steps by up to
 * SIM_DRIFT_STEP_PT, within SIM_DRIFT_RANGE_PT of its original value, the
 * best score reachable takes a new value, and convergence starts again
 * from the coefficients the chip has (the sphere seen stays seen).
 */
static void sim_drift(struct sentral_sim *sim)
{
	int i;

	for (i = 3; i < SIM_NCOEFFS; i++) {
		s64 c = sim->coeff_true[i] - SIM_DRIFT_STEP_PT +
			sim_drift_next(sim, 2 * SIM_DRIFT_STEP_PT + 1);

		sim->coeff_true[i] = clamp_t(s64, c,
					     sim_coeff_true[i] - SIM_DRIFT_RANGE_PT,
					     sim_coeff_true[i] + SIM_DRIFT_RANGE_PT);
	}
	sim->score_floor_milli = SIM_DRIFT_FLOOR_MILLI +
				 sim_drift_next(sim, SIM_DRIFT_FLOOR_SPAN);
	memcpy(sim->coeff_from, sim->coeff, sizeof(sim->coeff));
	sim->cal_ns = 0;
	sim->cal_step = 0;
}

/* While still, the gyro bias is learned: store it and latch gBiasUpdate */
static void sim_learn_gyro_bias(struct sentral_sim *sim)
{
	int i;

	for (i = 0; i < 3; i++)
		sim->params[SIM_PARAM_GBIAS + i] =
			sim_f32_from_ratio((s64)sim_gyro_true_bias[i] *
					   SIM_GYRO_FS_DPS, SIM_FS_COUNTS);
	sim->cal_flags |= SIM_CAL_GBIAS_UPDATE;
	sim->cal_updates[1]++;
}

/*
 * Serve the pending parameter request once AlgorithmControl bit 7 has been
 * set for ack_latency_us (§2: ParamAcknowledge echoes the request once it
 * has been served; SavedParamByte0..3 hold the value).
 */
static void sim_param_poll(struct sentral_sim *sim, ktime_t now)
{
	u8 req = sim->regs[SIM_REG_PARAM_REQUEST];
	unsigned int n = req & ~SIM_PARAM_WRITE;
	u32 val;

	/* no firmware (uploading, or none uploaded): nobody serves */
	if (!sim->req_pending || sim->ack_never ||
	    !sim_usfs_firmware(sim, now) || sim->wedged ||
	    !(sim->regs[SIM_REG_ALGO_CONTROL] & SIM_ALGO_PARAM_PROC))
		return;
	if (sim->standby_blocks_params &&
	    (sim->regs[SIM_REG_ALGO_CONTROL] & SIM_ALGO_STANDBY))
		return;
	if (ktime_us_delta(now, sim->req_servable_at) < sim->ack_latency_us)
		return;

	sim->req_pending = false;
	sim->stats.bus_ns += (u64)sim->ack_latency_us * NSEC_PER_USEC;
	if (!req) {
		/* a stop, served as a request with ack_end "served" */
		sim->param_ack = 0;
		return;
	}
	if (req & SIM_PARAM_WRITE) {
		/* The firmware picks the value up when it serves the request */
		val = sim_get_le32(&sim->regs[SIM_REG_LOAD_PARAM0]);
		if (n) {
			sim->params[n] = val;
			if (n >= SIM_PARAM_MCOEFF &&
			    n < SIM_PARAM_MCOEFF + SIM_NCOEFFS)
				sim_coeff_restored(sim, n - SIM_PARAM_MCOEFF);
		}
	} else {
		val = sim->params[n];
	}
	sim_put_le32(val, sim->saved_param);
	sim->param_ack = req;
	sim->stats.params_served++;
}

void sim_advance(struct sentral_sim *sim, ktime_t now)
{
	s64 delta = ktime_to_ns(ktime_sub(now, sim->last_advance));
	bool running;
	u64 period, moving;

	sim_param_poll(sim, now);
	if (delta <= 0)
		return;
	sim->last_advance = now;
	running = sim_algo_running(sim, now);
	/* the world moves on; the chip sees the field only while it runs */
	moving = sim_motion_advance(&sim->world, now,
				    running ? sim->cal_seen : NULL);
	if (!running)
		return;

	if (moving) {
		sim->cal_ns += moving;
		sim->still_ns = 0;
		sim->drift_ns += moving;
		if (sim->drift_ms &&
		    sim->drift_ns >= (u64)sim->drift_ms * NSEC_PER_MSEC) {
			sim->drift_ns = 0;
			sim_drift(sim);
		}
		sim_cal_progress(sim);
		return;
	}

	sim->still_ns += delta;
	period = (u64)sim->gbias_period_ms * NSEC_PER_MSEC;
	if (sim->still_ns >= period) {
		div64_u64_rem(sim->still_ns, period, &sim->still_ns);
		sim_learn_gyro_bias(sim);
	}
}

static u8 sim_actual_rate(struct sentral_sim *sim, u8 reg)
{
	if (!(sim->regs[SIM_REG_HOST_CONTROL] & SIM_HOST_RUN))
		return 0;
	return min_t(u8, sim->regs[reg], SIM_MAX_RATE_REG);
}

static void sim_stream_rate(struct sentral_sim *sim, enum sim_stream_id id,
			    u32 *num, u32 *den)
{
	*den = 1;
	switch (id) {
	case SIM_MAG:
		*num = sim_actual_rate(sim, SIM_REG_MAG_RATE);
		break;
	case SIM_ACCEL:
		*num = sim_actual_rate(sim, SIM_REG_ACCEL_RATE) * 10;
		break;
	case SIM_GYRO:
		*num = sim_actual_rate(sim, SIM_REG_GYRO_RATE) * 10;
		break;
	default:
		/* quaternion = gyro rate / (1 + QRateDivisor), §3 item 5 */
		*num = sim_actual_rate(sim, SIM_REG_GYRO_RATE) * 10;
		*den = sim->regs[SIM_REG_QRATE_DIVISOR] + 1;
		break;
	}
}

static ktime_t sim_stream_due(struct sentral_sim *sim, struct sim_stream *st)
{
	return ktime_add_ns(sim->epoch, st->tick * st->period_ns);
}

/* First tick strictly after now, on the common epoch so equal rates align */
static void sim_stream_next_tick(struct sentral_sim *sim,
				 struct sim_stream *st, ktime_t now)
{
	st->tick = div64_u64(ktime_to_ns(ktime_sub(now, sim->epoch)),
			     st->period_ns) + 1;
}

static void sim_stream_restart(struct sentral_sim *sim, struct sim_stream *st,
			       u32 num, u32 den, ktime_t now)
{
	st->rate_num = num;
	st->rate_den = den;
	st->ts_base = st->ts;
	st->n = 0;
	if (!num)
		return;
	st->period_ns = div64_u64((u64)NSEC_PER_SEC * den, num);
	sim_stream_next_tick(sim, st, now);
}

static s16 sim_clamp_s16(s64 v)
{
	return clamp_t(s64, v, S16_MIN, S16_MAX);
}

static void sim_put_s16(struct sentral_sim *sim, u8 reg, s64 v)
{
	sim_put_le16((u16)sim_clamp_s16(v), &sim->regs[reg]);
}

/* Deterministic pseudo-noise in [-2, 2] LSB (numerical recipes LCG) */
static s32 sim_noise(struct sentral_sim *sim)
{
	sim->noise_state = sim->noise_state * 1664525 + 1013904223;
	return (s32)((sim->noise_state >> 16) % 5) - 2;
}

/*
 * The accel reading and, as the USFS firmware gives it in GP8..GP13
 * (0x3f..0x44, read by Greg Tomasch's utilities as linear acceleration),
 * the reading minus gravity in the sensor frame, in the same LSB.
 */
static void sim_make_accel(struct sentral_sim *sim)
{
	s64 g[3];
	int i;

	/* gravity as the device sees it; the hand's own acceleration is not modelled */
	sim_motion_to_body(&sim->world, sim_gravity, g);
	for (i = 0; i < 3; i++) {
		s64 off, a;

		/* offsets are float g in warm-start 27..29 (application note) */
		if (sim_f32_to_scaled(sim->params[SIM_PARAM_ACCEL_OFFSET + i],
				      SIM_MICRO, SIM_ACCEL_LSB_UG, &off))
			off = 0;
		a = sim_clamp_s16(g[i] + sim->accel_bias[i] - off);
		sim_put_s16(sim, SIM_REG_AX + 2 * i, a);
		sim_put_s16(sim, SIM_REG_LIN_ACCEL + 2 * i, a - g[i]);
	}
}

static void sim_make_gyro(struct sentral_sim *sim)
{
	int i;

	for (i = 0; i < 3; i++) {
		s64 learned;
		s64 v = sim_gyro_true_bias[i] + sim_noise(sim);

		s64 turn = (s64)sim->world.rate_mdps[i] * SIM_FS_COUNTS;

		if (!sim_f32_to_scaled(sim->params[SIM_PARAM_GBIAS + i],
				       SIM_FS_COUNTS, SIM_GYRO_FS_DPS, &learned))
			v -= learned;
		/* the angular velocity, rounded to LSB */
		turn += turn < 0 ? -SIM_GYRO_FS_DPS * 500 : SIM_GYRO_FS_DPS * 500;
		v += div_s64(turn, SIM_GYRO_FS_DPS * 1000);
		sim_put_s16(sim, SIM_REG_GX + 2 * i, v);
	}
}

static void sim_make_mag(struct sentral_sim *sim)
{
	s64 body[3];
	int i;

	/* the Earth's field in the body frame */
	sim_motion_to_body(&sim->world, sim_earth_field, body);

	for (i = 0; i < 3; i++) {
		/* what the sensor sees, then the model's correction */
		s64 raw = div_s64(body[i] * SIM_MICRO, sim->coeff_true[i]) +
			  sim->coeff_true[3 + i];
		s64 out = div_s64((raw - sim->coeff[3 + i]) * sim->coeff[i],
				  SIM_MICRO);
		s64 lsb = out * SIM_FS_COUNTS;

		lsb += lsb < 0 ? -SIM_MAG_FS_PT / 2 : SIM_MAG_FS_PT / 2;
		sim_put_s16(sim, SIM_REG_MX + 2 * i, div64_s64(lsb, SIM_MAG_FS_PT));
	}
}

static void sim_make_quat(struct sentral_sim *sim)
{
	const s32 *q = sim->world.q;
	int i;

	/* x, y, z, w order, w last (§1): the body to NED rotation */
	for (i = 0; i < 4; i++)
		sim_put_le32(sim_f32_from_ratio(q[(i + 1) % 4], SIM_Q30),
			     &sim->regs[SIM_REG_QX + 4 * i]);
}

/*
 * EventStatus latches every event and EnableEvents gates only the INT pin:
 * hosts run on real boards enable 0x07 and still use the data bits
 * (reference §1, 0x33). events_gated plays the model where it latches
 * only enabled events. CPUReset is latched by sim_power_on() either way.
 */
void sim_event(struct sentral_sim *sim, u8 ev)
{
	if (sim->events_gated)
		ev &= sim->regs[SIM_REG_ENABLE_EVENTS];
	sim->event_status |= ev;
}

/* An error of the firmware: ErrorRegister and the Error event, §1 */
void sim_error(struct sentral_sim *sim, u8 code)
{
	sim->regs[SIM_REG_ERROR] = code;
	if (code)
		sim_event(sim, SIM_EV_ERROR);
}

static struct sim_drop *sim_drop_entry(struct sentral_sim *sim, u64 n)
{
	return &sim->drop_log[n % SIM_DROP_LOG];
}

/* A drop's cause is known: keep the host driver's apart (debugfs drops_host) */
static void sim_drop_decided(struct sentral_sim *sim, const struct sim_drop *d)
{
	if (d->cause == SIM_DROP_SLOW || d->cause == SIM_DROP_UNREAD)
		sim->host_log[sim->host_logged++ % SIM_DROP_LOG] = *d;
}

/*
 * The cause of a sample lost after the host read a data-ready since it came
 * (tests/sim/README.md), decided now that the next one replaces it or, when
 * the host came back from that read in time and made no transaction since,
 * by its next one. In time is before the next sample was due, when a real
 * chip makes it: this timer may run late. The entry awaits the host's
 * return from the read and its next transaction for their times.
 */
static void sim_drop_seen(struct sentral_sim *sim, struct sim_stream *st,
			  ktime_t now, s64 late_ns, bool held)
{
	struct sim_drop *d = sim_drop_entry(sim, sim->drops_logged);
	enum sim_drop_cause cause = SIM_DROP_PENDING;
	ktime_t due = ktime_sub_ns(now, late_ns);

	*d = (struct sim_drop){
		.stream = st - sim->stream,
		.next = st->next_kind,
		.busy = st->seen_xfer - st->came_xfer - 1,
		.seen_xfer = st->seen_xfer,
		.period_ns = st->period_ns,
		.came_late_ns = st->came_late_ns,
		.inflight_ns = st->came_inflight_ns,
		.latency_ns = ktime_to_ns(ktime_sub(st->seen_start, st->came)),
		.wire_ns = ktime_to_ns(ktime_sub(st->seen_end, st->seen_start)),
		.margin_ns = ktime_to_ns(ktime_sub(due, st->seen_end)),
		.wake_ns = -1,
		.gap_ns = -1,
		.late_ns = late_ns,
		.seen_end = st->seen_end,
		.seen_ret = st->seen_ret,
	};
	if (st->seen_ret)
		d->wake_ns = ktime_to_ns(ktime_sub(st->seen_ret, st->seen_end));
	if (st->seen_ret && st->next_start)
		d->gap_ns = ktime_to_ns(ktime_sub(st->next_start, st->seen_ret));

	if (held)
		cause = SIM_DROP_HELD;
	else if (st->came_idle || st->seen_idle)
		cause = SIM_DROP_IDLE;
	else if (ktime_after(st->seen_end, due) ||
		 st->came_late_ns >= st->period_ns / 2)
		cause = SIM_DROP_LATE_IRQ;
	else if (!st->seen_ret || ktime_after(st->seen_ret, due))
		cause = SIM_DROP_LATE_WAKE;
	else if (st->next_start)
		cause = SIM_DROP_UNREAD;
	d->cause = cause;
	st->drops_cause[cause]++;
	sim->drops_logged++;
	if (cause != SIM_DROP_PENDING)
		sim_drop_decided(sim, d);
	st->pending = st->next_start ? 0 : sim->drops_logged;
}

/*
 * A host that came back from the status read before the next sample was due
 * and then read another register was not late: it did not read the data.
 * If it read the data, whose the delay was: would the same time from its
 * return to its burst have fitted before the due time had it come back at
 * the read's end (then its late wake-up lost the sample), or had the read
 * also come at once after the sample (then the late interrupt did)? If
 * not, its own time did.
 */
static u8 sim_drop_late(const struct sim_drop *d, u8 kind)
{
	if (kind != SIM_XFER_BURST)
		return SIM_DROP_UNREAD;
	if (d->gap_ns < d->margin_ns)
		return SIM_DROP_LATE_WAKE;
	if (d->gap_ns < d->latency_ns + d->margin_ns)
		return SIM_DROP_LATE_IRQ;
	return SIM_DROP_SLOW;
}

/* A transaction of the host begins at @start (sim_xfer_end() after it) */
void sim_xfer_begin(struct sentral_sim *sim, ktime_t start)
{
	struct sim_stats *stats = &sim->stats;

	if (sim->drdy_ret) {
		s64 gap = ktime_to_ns(ktime_sub(start, sim->drdy_ret));

		stats->host_gaps++;
		stats->host_gap_100us += gap >= 100 * NSEC_PER_USEC;
		stats->host_gap_max_ns = max(stats->host_gap_max_ns, gap);
		sim->drdy_ret = 0;
	}
	sim->xfers++;
	sim->xfer_start = start;
	sim->xfer_reads = 0;
	sim->xfer_status = false;
	sim->xfer_drdy = false;
}

/*
 * The transaction that began at sim_xfer_begin() ends at @end on the wire:
 * it completes a drop's entry, its cause if pending, is the next
 * transaction after a status read that saw a sample, or is that read.
 */
void sim_xfer_end(struct sentral_sim *sim, ktime_t end)
{
	int id;

	for (id = 0; id < SIM_NSTREAMS; id++) {
		struct sim_stream *st = &sim->stream[id];
		u8 kind = SIM_XFER_OTHER;

		if (sim->xfer_reads & BIT(id))
			kind = SIM_XFER_BURST;
		else if (sim->xfer_status)
			kind = SIM_XFER_STATUS;

		if (st->pending) {
			struct sim_drop *d = sim_drop_entry(sim,
							    st->pending - 1);

			d->next = kind;
			if (d->seen_ret)
				d->gap_ns = ktime_to_ns(ktime_sub(sim->xfer_start,
								  d->seen_ret));
			if (d->cause == SIM_DROP_PENDING) {
				d->cause = sim_drop_late(d, kind);
				st->drops_cause[SIM_DROP_PENDING]--;
				st->drops_cause[d->cause]++;
				sim_drop_decided(sim, d);
			}
			st->pending = 0;
		}
		if (st->seen_start && !st->next_start &&
		    st->seen_xfer != sim->xfers) {
			st->next_start = sim->xfer_start;
			st->next_kind = kind;
		}
		if (sim->xfer_drdy && st->unread && !st->seen_start) {
			st->seen_start = sim->xfer_start;
			st->seen_end = end;
			st->seen_ret = 0;
			st->seen_xfer = sim->xfers;
			st->seen_idle = !(sim->regs[SIM_REG_ENABLE_EVENTS] &
					  SIM_EV_DATA);
		}
	}
	sim->xfer_last_end = end;
}

/* The host is back from transaction @xfer, the last one, at @now */
void sim_xfer_return(struct sentral_sim *sim, u64 xfer, ktime_t now)
{
	int id;

	if (sim->xfer_drdy)
		sim->drdy_ret = now;

	for (id = 0; id < SIM_NSTREAMS; id++) {
		struct sim_stream *st = &sim->stream[id];
		struct sim_drop *d;

		if (st->seen_xfer == xfer && !st->seen_ret)
			st->seen_ret = now;
		if (!st->pending)
			continue;
		d = sim_drop_entry(sim, st->pending - 1);
		if (d->seen_xfer == xfer && !d->seen_ret) {
			d->seen_ret = now;
			d->wake_ns = ktime_to_ns(ktime_sub(now, d->seen_end));
		}
	}
}

/*
 * held: the callback ran half a period or more after the sample was due,
 * late_ns behind it
 */
static void sim_produce(struct sentral_sim *sim, enum sim_stream_id id,
			ktime_t now, s64 late_ns, bool held)
{
	struct sim_stream *st = &sim->stream[id];
	u8 base = sim_stream_base[id];
	u8 time_reg = id == SIM_QUAT ? SIM_REG_QTIME : base + 6;

	switch (id) {
	case SIM_QUAT:
		sim_make_quat(sim);
		break;
	case SIM_MAG:
		sim_make_mag(sim);
		break;
	case SIM_ACCEL:
		sim_make_accel(sim);
		break;
	default:
		sim_make_gyro(sim);
		break;
	}

	st->n++;
	st->ts = st->ts_base + (u16)div64_u64((u64)st->n * SIM_FS_COUNTS *
					      st->rate_den, st->rate_num);
	sim_put_le16(st->ts, &sim->regs[time_reg]);
	if (st->unread) {
		st->missed++;
		if (held)
			st->held_unread++;
		/*
		 * A host streaming this sensor loses the sample. If it read
		 * a data-ready from EventStatus since the sample came, it saw
		 * the data and did not read it in time (unless this timer
		 * was held up: the machine stalled in between); if not, its
		 * interrupt was not even served within a period.
		 */
		if (st->read_seq && sim->drdy_seen != st->drdy_mark) {
			st->drops_seen++;
			sim_drop_seen(sim, st, now, late_ns, held);
		} else if (st->read_seq) {
			st->drops_unseen++;
		}
	}
	st->drdy_mark = sim->drdy_seen;
	st->came = now;
	st->came_xfer = sim->xfers;
	st->came_late_ns = late_ns;
	st->came_idle = !(sim->regs[SIM_REG_ENABLE_EVENTS] & SIM_EV_DATA);
	/* what remains of a transaction on the wire when the sample came */
	st->came_inflight_ns = max_t(s64, 0,
				     ktime_to_ns(ktime_sub(sim->xfer_last_end,
							   now)));
	st->seen_start = 0;
	st->next_start = 0;
	st->unread = true;
	st->produced++;
	sim_event(sim, sim_stream_event[id]);
}

/* Produce the samples of stream id due by now; return its next due time */
static ktime_t sim_stream_tick(struct sentral_sim *sim, enum sim_stream_id id,
			       ktime_t now)
{
	struct sim_stream *st = &sim->stream[id];
	ktime_t due = sim_stream_due(sim, st);
	s64 late_ns;
	bool held;

	if (ktime_after(due, now))
		return due;

	late_ns = ktime_to_ns(ktime_sub(now, due));
	sim->stats.timer_late_max_ns = max(sim->stats.timer_late_max_ns,
					   late_ns);
	held = late_ns >= st->period_ns / 2;
	sim_produce(sim, id, now, late_ns, held);
	if (id == SIM_GYRO &&
	    ++sim->quat_phase > sim->regs[SIM_REG_QRATE_DIVISOR]) {
		sim->quat_phase = 0;
		sim_produce(sim, SIM_QUAT, now, late_ns, held);
	}

	st->tick++;
	if (!ktime_after(sim_stream_due(sim, st), now)) {
		/* the timer came late: one sample per callback, count it */
		sim->timer_late++;
		sim_stream_next_tick(sim, st, now);
	}
	return sim_stream_due(sim, st);
}

static ktime_t sim_next_due(struct sentral_sim *sim)
{
	ktime_t next = 0;
	int id;

	for (id = SIM_MAG; id < SIM_NSTREAMS; id++) {
		struct sim_stream *st = &sim->stream[id];
		ktime_t due;

		if (!st->rate_num)
			continue;
		due = sim_stream_due(sim, st);
		if (!next || ktime_before(due, next))
			next = due;
	}
	return sim_usfs_next_due(sim, next);
}

/*
 * Bring the streams in line with the run state and the rate registers and
 * (re)arm or stop the timer. Called after every change from process context.
 */
void sim_schedule(struct sentral_sim *sim, ktime_t now)
{
	bool prod = !sim->dead && sim_algo_running(sim, now);
	bool start = prod && !sim->producing;
	ktime_t next;
	int id;

	if (start)
		sim->epoch = now;
	for (id = 0; prod && id < SIM_NSTREAMS; id++) {
		struct sim_stream *st = &sim->stream[id];
		u32 num, den;

		sim_stream_rate(sim, id, &num, &den);
		if (sim->producing && num == st->rate_num && den == st->rate_den)
			continue;
		sim_stream_restart(sim, st, num, den, now);
		if (id == SIM_QUAT)
			sim->quat_phase = 0;
	}
	sim_usfs_schedule(sim, prod, start, now);
	sim->producing = prod;

	next = prod ? sim_next_due(sim) : 0;
	if (!next) {
		hrtimer_try_to_cancel(&sim->timer);
		return;
	}
	if (!hrtimer_is_queued(&sim->timer) ||
	    hrtimer_get_expires(&sim->timer) != next)
		hrtimer_start(&sim->timer, next, HRTIMER_MODE_ABS);
}

static enum hrtimer_restart sim_timer_fn(struct hrtimer *timer)
{
	struct sentral_sim *sim = container_of(timer, struct sentral_sim, timer);
	ktime_t now, next = 0;
	unsigned long flags;
	bool fire;
	int id;

	spin_lock_irqsave(&sim->lock, flags);
	/*
	 * If sim_schedule() re-armed the timer while this callback waited for
	 * the lock, that expiry stands: setting ours would corrupt the queue.
	 */
	if (sim->dead || !sim->producing || hrtimer_is_queued(timer)) {
		spin_unlock_irqrestore(&sim->lock, flags);
		return HRTIMER_NORESTART;
	}
	now = ktime_get();
	sim_advance(sim, now);
	for (id = SIM_MAG; id < SIM_NSTREAMS; id++) {
		ktime_t due;

		if (!sim->stream[id].rate_num)
			continue;
		due = sim_stream_tick(sim, id, now);
		if (!next || ktime_before(due, next))
			next = due;
	}
	next = sim_usfs_tick(sim, now, next);
	fire = sim_int_update(sim);
	if (next)
		hrtimer_set_expires(timer, next);
	spin_unlock_irqrestore(&sim->lock, flags);

	if (fire)
		sim_fire_irq(sim);
	return next ? HRTIMER_RESTART : HRTIMER_NORESTART;
}

/*
 * The INT pin is high while an enabled event is pending and drops when
 * EventStatus is read (§3 item 7). The interrupt is edge-triggered, so it
 * is raised on each low-to-high transition only.
 */
bool sim_int_update(struct sentral_sim *sim)
{
	bool high = (sim->event_status & sim->regs[SIM_REG_ENABLE_EVENTS]) ||
		    sim->int_latched;
	bool rising = high && !sim->int_high;

	WRITE_ONCE(sim->int_high, high);
	if (rising)
		sim->irqs++;
	return rising;
}

/* Power-on or ResetRequest: RAM state lost, firmware reloaded (§3) */
void sim_power_on(struct sentral_sim *sim, ktime_t now)
{
	int id;

	memset(sim->regs, 0, sizeof(sim->regs));
	memcpy(sim->params, sim_param_defaults, sizeof(sim->params));
	sim->req_pending = false;
	sim->param_ack = 0;
	memset(sim->saved_param, 0, sizeof(sim->saved_param));
	sim->upload_done_at = ktime_add_ms(now, sim->upload_ms);

	sim->last_advance = now;
	sim->cal_ns = 0;
	sim->cal_step = 0;
	sim->still_ns = 0;
	memcpy(sim->coeff, sim_coeff_default, sizeof(sim->coeff));
	memcpy(sim->coeff_from, sim_coeff_default, sizeof(sim->coeff_from));
	bitmap_zero(sim->cal_seen, SIM_REGIONS);
	sim->cal_flags = 0;
	/* a reset raises CPUReset whatever EnableEvents says (§3 item 2) */
	sim->event_status = SIM_EV_CPU_RESET;
	sim->noise_state = 1;
	WRITE_ONCE(sim->int_high, false);
	sim->int_latched = false;
	sim->wedged = false;
	sim->nack_until = ktime_add_ms(now, sim->nack_after_reset_ms);

	sim->producing = false;
	sim->quat_phase = 0;
	sim_usfs_power_on(sim, now);
	for (id = 0; id < SIM_NSTREAMS; id++) {
		struct sim_stream *st = &sim->stream[id];

		st->rate_num = 0;
		st->rate_den = 1;
		st->ts = 0;
		st->ts_base = 0;
		st->n = 0;
		st->unread = false;
	}
}

void sim_model_init(struct sentral_sim *sim)
{
	spin_lock_init(&sim->lock);
	hrtimer_setup(&sim->timer, sim_timer_fn, CLOCK_MONOTONIC,
		      HRTIMER_MODE_ABS);

	sim->cal_duration_ms = 5000;
	sim->gbias_period_ms = 2000;
	sim->accel_bias[0] = -47;	/* application note, Table 1 */
	sim->accel_bias[1] = -15;
	sim->accel_bias[2] = 46;
	sim->ack_latency_us = 500;
	sim->upload_ms = 10;
	sim->ram_version = SIM_RAM_VERSION;
	sim->rom_version = SIM_ROM_VERSION;
	sim->product_id = SIM_PRODUCT_ID;
	sim->revision_id = SIM_REVISION_ID;
	sim->reset_int = true;
	memcpy(sim->coeff_true, sim_coeff_true, sizeof(sim->coeff_true));
	sim->score_floor_milli = SIM_SCORE_FLOOR_MILLI;
	sim->drift_rng = 1;
	sim_motion_init(&sim->world, ktime_get());
	sim_usfs_init(sim, ktime_get());
	sim_power_on(sim, ktime_get());
}

static void sim_mark_read(struct sentral_sim *sim, u8 reg)
{
	struct sim_stream *st;

	if (reg < SIM_REG_MX)
		st = &sim->stream[SIM_QUAT];
	else if (reg < SIM_REG_AX)
		st = &sim->stream[SIM_MAG];
	else if (reg < SIM_REG_GX)
		st = &sim->stream[SIM_ACCEL];
	else
		st = &sim->stream[SIM_GYRO];
	sim->xfer_reads |= BIT(st - sim->stream);
	if (st->unread) {
		st->unread = false;
		st->read++;
		/* a host that streams sees these as gaps in the sequence */
		if (st->read_seq) {
			st->gaps += st->produced - st->read_seq - 1;
			st->gaps_held += st->held_unread;
		}
		st->read_seq = st->produced;
		st->held_unread = 0;
	}
}

/**
 * sim_reg_read() - the value of one register as the host reads it
 * @sim: the chip
 * @reg: register address
 * @now: time of the access
 * @peek: true for debugfs dumps: no clear-on-read, no read accounting
 *
 * Return: the register value.
 */
u8 sim_reg_read(struct sentral_sim *sim, u8 reg, ktime_t now, bool peek)
{
	bool up = sim_in_upload(sim, now);
	u8 host = sim->regs[SIM_REG_HOST_CONTROL];
	u8 algo = sim->regs[SIM_REG_ALGO_CONTROL];
	u8 v;

	switch (reg) {
	case SIM_REG_QX ... SIM_REG_GTIME + 1:
		if (!peek)
			sim_mark_read(sim, reg);
		return sim->regs[reg];
	case SIM_REG_EVENT_STATUS:
		v = sim->event_status;
		if (peek)
			return v;
		sim->event_status = 0;	/* clear-on-read, §1 */
		sim->int_latched = false;
		sim->xfer_status = true;
		if (v & SIM_EV_DATA) {
			sim->drdy_seen++;
			sim->xfer_drdy = true;
		}
		return v;
	case SIM_REG_SENTRAL_STATUS:
		if (sim->usfs.no_eeprom)
			return sim_usfs_sentral_status(sim, now);
		if (up)
			return SIM_ST_EEPROM;
		/* left running by a host's warm reboot: no standby (§3, §5) */
		if (sim->wedged)
			return SIM_ST_EEPROM | SIM_ST_UPLOAD_DONE;
		/* bit 3 "StandbySt": the CPU is not executing (§1) */
		return SIM_ST_EEPROM | SIM_ST_UPLOAD_DONE |
		       (host & SIM_HOST_RUN ? 0 : SIM_ST_STANDBY);
	case SIM_REG_SENSOR_STATUS:
		return sim->sensor_status;
	case SIM_REG_ALGO_STATUS:
		v = algo & SIM_ALGO_STANDBY && !sim->standby_never ?
			SIM_AS_STANDBY : 0;
		if (!sim_motion_moving(&sim->world))
			v |= SIM_AS_STILL;
		if (sim_cal_status(sim) == 3)
			v |= SIM_AS_CAL_STABLE;
		if (sim->mag_transient)
			v |= SIM_AS_MAG_TRANSIENT;
		if ((v & SIM_AS_STANDBY) && !peek && sim->standby_power_loss) {
			/* the supply goes once the host saw the standby */
			sim->standby_power_loss = false;
			sim_power_on(sim, now);
		}
		/* bit 5 unreliable sensor data, 0xc0 a glitch (§1) */
		return v | sim->algo_status_or;
	case SIM_REG_PARAM_ACK:
		if (!peek && sim->req_pending)
			sim->stats.ack_polls_early++;
		return sim->param_ack;
	case SIM_REG_SAVED_PARAM0 ... SIM_REG_SAVED_PARAM3:
		return sim->saved_param[reg - SIM_REG_SAVED_PARAM0];
	case SIM_REG_LIN_ACCEL ... SIM_REG_CAL_FLAGS:
		/* a USFS: linear acceleration x, y, z (GP8..GP13) */
		if (!sim->appnote_layout)
			return sim->regs[reg];
		if (reg == SIM_REG_CAL_STATUS)
			/* application note: bits 1:0 CalStatus, 3:2 MagTransient */
			return sim_cal_status(sim) | sim->mag_transient << 2;
		if (reg != SIM_REG_CAL_FLAGS)
			return 0;	/* the note defines none of 0x3f..0x42 */
		v = sim->cal_flags;
		if (!peek) {
			sim->cal_flags = 0;	/* latched until read */
			sim->cal_updates_read[0] += v & SIM_CAL_MAG_UPDATE;
			sim->cal_updates_read[1] += !!(v & SIM_CAL_GBIAS_UPDATE);
		}
		return v;
	case SIM_REG_ACTUAL_MAG:
		return sim_actual_rate(sim, SIM_REG_MAG_RATE);
	case SIM_REG_ACTUAL_ACCEL:
		return sim_actual_rate(sim, SIM_REG_ACCEL_RATE);
	case SIM_REG_ACTUAL_GYRO:
		return sim_actual_rate(sim, SIM_REG_GYRO_RATE);
	/* GP22..GP23: the application note's score; the USFS leaves them 0 */
	case SIM_REG_CAL_SCORE_LSB:
		return sim->appnote_layout ? sim_cal_score_raw(sim) & 0xff : 0;
	case SIM_REG_CAL_SCORE_MSB:
		return sim->appnote_layout ? sim_cal_score_raw(sim) >> 8 : 0;
	case SIM_REG_ROM_VERSION:
		return sim->rom_version & 0xff;
	case SIM_REG_ROM_VERSION + 1:
		return sim->rom_version >> 8;
	case SIM_REG_RAM_VERSION:
		return sim_usfs_ram_version(sim, now) & 0xff;
	case SIM_REG_RAM_VERSION + 1:
		return sim_usfs_ram_version(sim, now) >> 8;
	case SIM_REG_PRODUCT_ID:
		return sim->product_id;
	case SIM_REG_REVISION_ID:
		return sim->revision_id;
	case SIM_REG_RUN_STATUS:
		return !up && (host & SIM_HOST_RUN);
	case SIM_REG_PASSTHRU_STATUS:
		return sim->regs[SIM_REG_PASSTHRU_CTRL] & BIT(0);
	default:
		/* the board's: features, upload CRC (sim-usfs.c) */
		if (sim_usfs_reg_read(sim, reg, now, &v))
			return v;
		return sim->regs[reg];
	}
}

static void sim_write_algo_control(struct sentral_sim *sim, u8 val,
				   ktime_t now)
{
	u8 old = sim->regs[SIM_REG_ALGO_CONTROL];

	sim->regs[SIM_REG_ALGO_CONTROL] = val;
	if (!(old & SIM_ALGO_PARAM_PROC) && (val & SIM_ALGO_PARAM_PROC)) {
		/* a request written before bit 7 is served from now on */
		sim->req_pending = sim->regs[SIM_REG_PARAM_REQUEST] != 0;
		sim->req_servable_at = now;
		sim->transfer_started = now;
	} else if ((old & SIM_ALGO_PARAM_PROC) && !(val & SIM_ALGO_PARAM_PROC)) {
		/* end of the procedure (§2 "End") */
		sim->req_pending = false;
		if (sim->ack_end == SIM_ACK_END_CLEAR)
			sim->param_ack = 0;
		sim->transfer_ended = now;
		/* the difference of the times state shows, to the microsecond */
		sim->transfer_longest_us =
			max(sim->transfer_longest_us,
			    ktime_to_us(now) -
			    ktime_to_us(sim->transfer_started));
	}
}

static void sim_write_param_request(struct sentral_sim *sim, u8 val,
				    ktime_t now)
{
	sim->regs[SIM_REG_PARAM_REQUEST] = val;
	if (!val && sim->ack_end != SIM_ACK_END_SERVED) {
		/* 0 = STOP (§2): nothing to serve */
		sim->req_pending = false;
		if (sim->ack_end == SIM_ACK_END_CLEAR)
			sim->param_ack = 0;
		return;
	}
	sim->req_pending = true;
	sim->req_servable_at = now;
}

void sim_reg_write(struct sentral_sim *sim, u8 reg, u8 val, ktime_t now)
{
	switch (reg) {
	case SIM_REG_HOST_CONTROL:
		/* the CPU cannot be started before its firmware is loaded */
		if (!sim_in_upload(sim, now))
			sim->regs[reg] = sim_usfs_host_control(sim, val, now);
		break;
	case SIM_REG_UPLOAD_DATA:
		sim_usfs_upload_byte(sim, val);
		break;
	case SIM_REG_ALGO_CONTROL:
		sim_write_algo_control(sim, val, now);
		break;
	case SIM_REG_PARAM_REQUEST:
		sim_write_param_request(sim, val, now);
		break;
	case SIM_REG_RESET_REQUEST:
		if (val & BIT(0))
			sim_power_on(sim, now);
		break;
	case SIM_REG_QRATE_DIVISOR:
	case SIM_REG_ENABLE_EVENTS:
	case SIM_REG_MAG_RATE ... 0x5f:		/* rates, LPF, GP inputs */
	case SIM_REG_LOAD_PARAM0 ... SIM_REG_LOAD_PARAM3:
	case 0x69 ... 0x6e:			/* GP inputs */
	case 0x94 ... 0x95:			/* UploadAddress */
	case 0x9f:				/* passthrough SCL low cycles */
	case SIM_REG_PASSTHRU_CTRL:
		sim->regs[reg] = val;
		break;
	default:
		/* read-only registers ignore writes */
		break;
	}
}

/* The chip does not acknowledge its address for a while after a reset */
bool sim_nacks(struct sentral_sim *sim, ktime_t now)
{
	return ktime_before(now, sim->nack_until);
}

/*
 * Data events pending and the INT line high, without an edge anyone saw:
 * as when the line rose before the host listened and nobody read
 * EventStatus since. It stays high until EventStatus is read.
 */
void sim_int_stuck(struct sentral_sim *sim)
{
	sim->event_status |= SIM_EV_QUATERNION | SIM_EV_MAG | SIM_EV_ACCEL |
			     SIM_EV_GYRO;
	sim->int_latched = true;
	WRITE_ONCE(sim->int_high, true);
}
