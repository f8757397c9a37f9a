// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: the seed app note's calibration procedures, guided.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cmd.h"

#define GBIAS_POLL_MS 50
#define CAL_POLL_MS 250
/* Without a terminal, print a line on change or at least this often. */
#define CAL_LINE_MS 5000
#define BAR_WIDTH 30

/* A fraction for the bar: status 0..3 first, then the score to target. */
static double cal_progress(const struct sw_cal_state *cs, double target)
{
	double pct = sw_score_pct(cs->score_raw), f;

	if (cs->status < 3)
		return cs->status * 0.25;
	/* Scores start around 10-20% once complete; 10% maps to 75%. */
	f = (10.0 - pct) / (10.0 - target);
	if (f < 0)
		f = 0;
	if (f > 1)
		f = 1;
	return 0.75 + 0.25 * f;
}

static void show_progress(struct sw_env *env, const struct sw_cal_state *cs,
			  bool have_best, double best, double target,
			  unsigned int left_s)
{
	char bestbuf[32];

	if (have_best)
		snprintf(bestbuf, sizeof(bestbuf), "%.3f%%", best);
	else
		snprintf(bestbuf, sizeof(bestbuf), "-");
	if (env->tty) {
		char bar[BAR_WIDTH + 1];
		int i, fill = (int)(cal_progress(cs, target) * BAR_WIDTH + 0.5);

		for (i = 0; i < BAR_WIDTH; i++)
			bar[i] = i < fill ? '#' : '-';
		bar[BAR_WIDTH] = '\0';
		fprintf(env->out,
			"\r[%s] status %d/3  score %8.3f%%  best %-9s %4u s left ",
			bar, cs->status, sw_score_pct(cs->score_raw), bestbuf,
			left_s);
	} else {
		fprintf(env->out,
			"calibrate: status %d/3, score %.3f%%, best %s, %u s left\n",
			cs->status, sw_score_pct(cs->score_raw), bestbuf, left_s);
	}
	fflush(env->out);
}

int sw_cmd_calibrate(struct sw_backend *b, const struct sw_opts *o,
		     struct sw_env *env, struct sw_err *e)
{
	uint64_t start = env->now_ms(env->clk), now, last_line = 0;
	uint64_t deadline = start + (uint64_t)o->timeout_s * 1000u;
	struct sw_cal_state cs, best = { 0 };
	int shown_status = -1, shown_best = -1;
	uint8_t blob[SW_BLOB_SIZE], best_blob[SW_BLOB_SIZE];
	bool have_best = false, reached = false;
	int ret;

	sw_note(env, "Step 1/2: keep the device still while the gyro bias is learned...");
	for (;;) {
		ret = b->ops->cal_state(b, &cs, e);
		if (ret)
			return ret;
		if (cs.gyro_bias_update)
			break;
		if (env->now_ms(env->clk) >= deadline)
			return sw_err_set(e, SW_EXIT_CAL,
					  "gyro bias not learned within %u s: keep the device still and retry",
					  o->timeout_s);
		env->sleep_ms(env->clk, GBIAS_POLL_MS);
	}
	sw_note(env, "Gyro bias learned.");
	sw_note(env, "Step 2/2: rotate the device slowly in a figure-8, covering every direction, pivoting about its centre (target score %.1f%%, up to %u s)...",
		o->target_score, o->timeout_s);

	for (;;) {
		ret = b->ops->cal_state(b, &cs, e);
		if (ret)
			return ret;
		if (cs.status == 3 &&
		    (!have_best || cs.score_raw < best.score_raw)) {
			/*
			 * The chip's calibration keeps moving; snapshot the
			 * coefficients at the best score seen so the saved
			 * file is that one, not whatever the end brings.
			 */
			ret = b->ops->read_blob(b, blob, e);
			if (ret)
				return ret;
			memcpy(best_blob, blob, sizeof(blob));
			best = cs;
			have_best = true;
		}
		now = env->now_ms(env->clk);
		/* A bar redraws in place; plain lines only when news. */
		if (env->tty || cs.status != shown_status ||
		    (have_best && best.score_raw != shown_best) ||
		    now - last_line >= CAL_LINE_MS) {
			show_progress(env, &cs, have_best,
				      sw_score_pct(best.score_raw),
				      o->target_score,
				      now >= deadline ? 0 :
				      (unsigned int)((deadline - now + 999) / 1000));
			last_line = now;
			shown_status = cs.status;
			shown_best = best.score_raw;
		}
		if (have_best && sw_score_pct(best.score_raw) <= o->target_score) {
			reached = true;
			break;
		}
		if (now >= deadline)
			break;
		env->sleep_ms(env->clk, CAL_POLL_MS);
	}
	if (env->tty)
		fputc('\n', env->out);

	if (!have_best)
		return sw_err_set(e, SW_EXIT_CAL,
				  "calibration did not complete within %u s (status %d of 3); nothing saved",
				  o->timeout_s, cs.status);
	if (reached)
		sw_note(env, "Calibration complete: score %.3f%%.",
			sw_score_pct(best.score_raw));
	else
		sw_note(env, "Timed out after %u s; keeping the best score reached, %.3f%% (target %.1f%%).",
			o->timeout_s, sw_score_pct(best.score_raw),
			o->target_score);
	return sw_save_snapshot(b, o, env, &best, best_blob, e);
}

struct accel_stats {
	double mean[3];
	double sd[3];
};

static int accel_measure(struct sw_backend *b, unsigned int n,
			 struct sw_env *env, struct accel_stats *st,
			 struct sw_err *e)
{
	double sum[3] = { 0 }, sq[3] = { 0 };
	unsigned int i;
	int xyz[3], k, ret;

	for (i = 0; i < n; i++) {
		ret = b->ops->accel_raw(b, xyz, e);
		if (ret)
			return ret;
		for (k = 0; k < 3; k++) {
			sum[k] += xyz[k];
			sq[k] += (double)xyz[k] * xyz[k];
		}
		/* Fresh samples: the accelerometer runs at 100 Hz or more. */
		env->sleep_ms(env->clk, 10);
	}
	for (k = 0; k < 3; k++) {
		double var;

		st->mean[k] = sum[k] / n;
		var = sq[k] / n - st->mean[k] * st->mean[k];
		st->sd[k] = var > 0 ? sqrt(var) : 0;
	}
	return SW_EXIT_OK;
}

/* Seed: more than this and the device was moving or not resting flat. */
#define ACCEL_MAX_SD_LSB 20.0
/* Output periods at the slowest accelerometer rate (10 Hz) and then some. */
#define ACCEL_SETTLE_MS 250
/* An offset above a quarter g means Z is not facing down. */
#define ACCEL_MAX_OFFSET_LSB 512

int sw_cmd_accel_cal(struct sw_backend *b, const struct sw_opts *o,
		     struct sw_env *env, struct sw_err *e)
{
	static const int expect[3] = { 0, 0, SW_ACCEL_1G_LSB };
	int old[3], off[3], back[3], k, ret;
	struct accel_stats st, after;

	sw_note(env, "Place the device flat, Z axis facing down, and keep it still; averaging %u samples...",
		o->samples);
	ret = b->ops->accel_offset_get(b, old, e);
	ret = ret ? ret : accel_measure(b, o->samples, env, &st, e);
	if (ret)
		return ret;
	for (k = 0; k < 3; k++) {
		if (st.sd[k] > ACCEL_MAX_SD_LSB)
			return sw_err_set(e, SW_EXIT_CAL,
					  "the device moved while sampling (axis %c varies by %.1f LSB); keep it still and retry",
					  'x' + k, st.sd[k]);
		/*
		 * Output = sensor - offset (seed: offset = initial -
		 * expected), so with the current offsets applied the new
		 * offset is current + measured - expected.
		 */
		off[k] = old[k] + (int)lround(st.mean[k] - expect[k]);
		if (abs(off[k]) > ACCEL_MAX_OFFSET_LSB)
			return sw_err_set(e, SW_EXIT_CAL,
					  "measured %.1f %.1f %.1f LSB: the device is not lying flat with Z facing down (expected 0 0 %d)",
					  st.mean[0], st.mean[1], st.mean[2],
					  SW_ACCEL_1G_LSB);
	}
	sw_note(env, "measured %.1f %.1f %.1f LSB; offsets %d %d %d -> %d %d %d LSB (%.6f %.6f %.6f g)",
		st.mean[0], st.mean[1], st.mean[2], old[0], old[1], old[2],
		off[0], off[1], off[2], (double)sw_lsb_to_g(off[0]),
		(double)sw_lsb_to_g(off[1]), (double)sw_lsb_to_g(off[2]));

	ret = b->ops->accel_offset_set(b, off, e);
	ret = ret ? ret : b->ops->accel_offset_get(b, back, e);
	if (ret)
		return ret;
	if (memcmp(off, back, sizeof(off)))
		return sw_err_set(e, SW_EXIT_CAL,
				  "offsets read back as %d %d %d, written %d %d %d",
				  back[0], back[1], back[2], off[0], off[1],
				  off[2]);

	/*
	 * Seed step 7: the output should now be (close to) 0, 0, 2048. The
	 * data registers still hold samples taken before the write: let a
	 * few output periods pass first.
	 */
	env->sleep_ms(env->clk, ACCEL_SETTLE_MS);
	ret = accel_measure(b, o->samples, env, &after, e);
	if (ret)
		return ret;
	for (k = 0; k < 3; k++) {
		double tol = 2.0 + 3.0 * st.sd[k];

		if (fabs(after.mean[k] - expect[k]) > tol)
			return sw_err_set(e, SW_EXIT_CAL,
					  "offsets written, but the output is %.1f %.1f %.1f LSB, not 0 0 %d",
					  after.mean[0], after.mean[1],
					  after.mean[2], SW_ACCEL_1G_LSB);
	}
	sw_note(env, "accel offsets %d %d %d LSB written and verified; output now %.1f %.1f %.1f LSB. Run 'save' to keep them.",
		off[0], off[1], off[2], after.mean[0], after.mean[1],
		after.mean[2]);
	return SW_EXIT_OK;
}
