// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: the seed app note's calibration procedures, guided.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cmd.h"
#include "coverage.h"
#include "level.h"

#define GBIAS_POLL_MS 50
#define CAL_POLL_MS 250
/* The magnetometer is sampled this often: above its 30 Hz default rate. */
#define MAG_POLL_MS 25
/* Without a terminal, print a line on change or at least this often. */
#define CAL_LINE_MS 5000
/* Lines of the in-place terminal view (see draw_tty). */
#define TTY_LINES (SW_COV_BANDS + 3)
/* Looks in a row that may fail (a glitched read) before calibrate gives up. */
#define CAL_GLITCHES 4

struct cal_run {
	struct sw_env *env;
	FILE *out;		/* progress: a terminal, lines or JSON */
	const struct sw_opts *o;
	struct sw_cov cov;
	struct sw_cal_state cs, best;
	bool have_best;
	unsigned int glitches;	/* failed looks in a row */
	uint64_t start, deadline;
	bool drawn;		/* the terminal view is on screen */
};

static unsigned int coverage_pct(const struct cal_run *r)
{
	return sw_cov_seen(&r->cov) * 100 / SW_COV_REGIONS;
}

static unsigned int left_s(const struct cal_run *r, uint64_t now)
{
	return now >= r->deadline ? 0 :
	       (unsigned int)((r->deadline - now + 999) / 1000);
}

static const char *fit_name(enum sw_fit f)
{
	return f == SW_FIT_SPHERE ? "sphere" :
	       f == SW_FIT_PLANAR ? "planar" : "few";
}

/* A score as JSON: null when the firmware reports none. */
static void json_score(FILE *out, const struct sw_cal_state *cs)
{
	if (cs->has_score)
		fprintf(out, "%.3f", sw_score_pct(cs->score_raw));
	else
		fputs("null", out);
}

/* "level 4/4 (stable), score 2.747%, best 2.747%" or without a score. */
static void state_text(const struct cal_run *r, char *buf, size_t len)
{
	int n = snprintf(buf, len, "level %d/4 (%s)", r->cs.level,
			 sw_level_name(r->cs.level));

	if (n < 0 || (size_t)n >= len || !r->cs.has_score)
		return;
	n += snprintf(buf + n, len - (size_t)n, ", score %.3f%%",
		      sw_score_pct(r->cs.score_raw));
	if ((size_t)n >= len)
		return;
	if (r->have_best)
		snprintf(buf + n, len - (size_t)n, ", best %.3f%%",
			 sw_score_pct(r->best.score_raw));
	else
		snprintf(buf + n, len - (size_t)n, ", best -");
}

static void json_progress(struct cal_run *r, const char *event, uint64_t now)
{
	enum sw_axis miss[SW_NAXES];
	char hint[256];
	int i, n = sw_cov_missing(&r->cov, miss);
	const char *h;

	sw_cov_hint(&r->cov, hint, sizeof(hint));
	fprintf(r->out, "{\"event\":\"%s\",\"elapsed_ms\":%llu,\"level\":%d,\"level_name\":\"%s\",\"score\":",
		event, (unsigned long long)(now - r->start), r->cs.level,
		sw_level_name(r->cs.level));
	json_score(r->out, &r->cs);
	fputs(",\"best_score\":", r->out);
	if (r->have_best)
		json_score(r->out, &r->best);
	else
		fputs("null", r->out);
	fprintf(r->out, ",\"coverage\":%u,\"samples\":%u,\"fit\":\"%s\",\"regions\":\"",
		coverage_pct(r), r->cov.samples, fit_name(r->cov.fit));
	for (i = 0; i < SW_COV_REGIONS; i++)
		fputc(r->cov.seen[i] ? '1' : '0', r->out);
	fputs("\",\"missing\":[", r->out);
	for (i = 0; i < n; i++)
		fprintf(r->out, "%s\"%s\"", i ? "," : "", sw_axis_name(miss[i]));
	/* The hint is plain ASCII without quotes or backslashes. */
	fputs("],\"hint\":\"", r->out);
	for (h = hint; *h; h++)
		if (*h != '"' && *h != '\\')
			fputc(*h, r->out);
	fputs("\"}\n", r->out);
	fflush(r->out);
}

/*
 * The sphere as six bands of regions, north (+Z) on top, each region '#'
 * when seen; then the chip's state and the hint. Redrawn in place.
 */
static void draw_tty(struct cal_run *r, uint64_t now)
{
	int b, k, width = sw_cov_band_size(2);
	char hint[256], state[128];

	if (r->drawn)
		fprintf(r->out, "\033[%dA", TTY_LINES);
	r->drawn = true;
	fprintf(r->out, "sphere coverage %3u%%  (%u samples)\033[K\n",
		coverage_pct(r), r->cov.samples);
	for (b = 0; b < SW_COV_BANDS; b++) {
		int first = sw_cov_band_first(b), n = sw_cov_band_size(b);

		fprintf(r->out, "  %s %*s", b == 0 ? "+Z" : b == 5 ? "-Z" : "  ",
			(width - n) / 2, "");
		for (k = 0; k < n; k++)
			fputc(r->cov.seen[first + k] ? '#' : '.', r->out);
		fputs("\033[K\n", r->out);
	}
	state_text(r, state, sizeof(state));
	fprintf(r->out, "%s, %u s left\033[K\n", state, left_s(r, now));
	sw_cov_hint(&r->cov, hint, sizeof(hint));
	fprintf(r->out, "hint: %s\033[K\n", hint);
	fflush(r->out);
}

static void print_line(struct cal_run *r, uint64_t now)
{
	char hint[256], state[128];

	state_text(r, state, sizeof(state));
	sw_cov_hint(&r->cov, hint, sizeof(hint));
	fprintf(r->out, "calibrate: %s, coverage %u%%, %u s left; %s\n", state,
		coverage_pct(r), left_s(r, now), hint);
	fflush(r->out);
}

/*
 * Step 1: the gyro bias is learned while the device is still. The update
 * flag may be 1 from any time before: a read of the blob clears the
 * driver's (until then it stays 1, so the first look may be skipped
 * without losing an update), and over i2c-dev that first look at 0x44
 * clears it. A later look that reads 1 is an update made since. Firmware
 * without the application note's registers reports no update: no step 1.
 */
static int wait_gyro_bias(struct sw_backend *b, struct cal_run *r,
			  struct sw_err *e)
{
	struct sw_env *env = r->env;
	uint8_t blob[SW_BLOB_SIZE];
	bool first = true;
	int ret;

	ret = b->ops->cal_state(b, &r->cs, e);
	if (ret || !r->cs.has_score)
		return ret;
	sw_note(env, "Step 1/2: keep the device still while the gyro bias is learned...");
	ret = b->ops->read_blob(b, blob, e);
	if (ret)
		return ret;
	for (;; first = false) {
		ret = b->ops->cal_state(b, &r->cs, e);
		if (ret)
			return ret;
		if (!first && r->cs.gyro_bias_update == 1)
			break;
		if (env->now_ms(env->clk) >= r->deadline)
			return sw_err_set(e, SW_EXIT_CAL,
					  "gyro bias not learned within %u s: keep the device still and retry",
					  r->o->timeout_s);
		env->sleep_ms(env->clk, GBIAS_POLL_MS);
	}
	sw_note(env, "Gyro bias learned.");
	return SW_EXIT_OK;
}

/*
 * A look that failed the way a glitched read does (SW_EXIT_IO: the
 * driver's EIO for a reserved bit of AlgorithmStatus, a bus error) is
 * skipped, the next look decides, unless CAL_GLITCHES in a row failed.
 */
static int glitch(struct cal_run *r, int ret, const struct sw_err *ge,
		  struct sw_err *e)
{
	if (ret != SW_EXIT_IO || ++r->glitches >= CAL_GLITCHES)
		return sw_err_set(e, ret, "%s", ge->msg);
	return SW_EXIT_OK;
}

/* Would a stable state cs be a better calibration than the best so far? */
static bool better(const struct cal_run *r, const struct sw_cal_state *cs)
{
	return cs->level == SW_LEVEL_STABLE &&
	       (!r->have_best ||
		(cs->has_score && cs->score_raw < r->best.score_raw));
}

/*
 * One look at the chip: keep a snapshot of the best calibration seen. A
 * value out of range (a score below 0 %, a level above 4) would look
 * better than any calibration: skipped, as a glitched read is.
 */
static int poll_chip(struct sw_backend *b, struct cal_run *r,
		     uint8_t *best_blob, struct sw_err *e)
{
	uint8_t blob[SW_BLOB_SIZE];
	struct sw_cal_state cs;
	struct sw_err ge;
	char why[128];
	int ret;

	sw_err_clear(&ge);
	ret = b->ops->cal_state(b, &cs, &ge);
	if (ret)
		return glitch(r, ret, &ge, e);
	if (!sw_cal_state_check(&cs, why, sizeof(why)))
		return SW_EXIT_OK;
	r->cs = cs;
	if (!better(r, &cs)) {
		r->glitches = 0;
		return SW_EXIT_OK;
	}
	/*
	 * The chip's calibration keeps moving; snapshot the coefficients
	 * at the best state seen (stable before and after the read), so
	 * that the saved file is that one, not whatever the end brings.
	 */
	ret = sw_read_snapshot(b, &cs, blob, &ge);
	if (ret)
		return glitch(r, ret, &ge, e);
	r->glitches = 0;
	if (!better(r, &cs))
		return SW_EXIT_OK;
	memcpy(best_blob, blob, SW_BLOB_SIZE);
	r->best = cs;
	r->have_best = true;
	return SW_EXIT_OK;
}

/* Done: a stable snapshot, and with a score, one at the target. */
static bool reached(const struct cal_run *r)
{
	return r->have_best && (!r->best.has_score ||
		sw_score_pct(r->best.score_raw) <= r->o->target_score);
}

int sw_cmd_calibrate(struct sw_backend *b, const struct sw_opts *o,
		     struct sw_env *env, struct sw_err *e)
{
	struct cal_run run, *r = &run;
	struct sw_env notes = *env;
	uint8_t best_blob[SW_BLOB_SIZE];
	uint64_t now, next_poll, last_line = 0;
	int shown_level = -1, shown_best = -1, ret;
	unsigned int shown_cov = 0;
	char hint[256], path[4096], score[32] = "";
	bool saved;
	double ut[3];

	memset(r, 0, sizeof(*r));
	sw_cov_init(&r->cov);
	r->env = env;
	r->out = env->out;
	r->o = o;
	/* With --json, stdout carries JSON only: the messages go to stderr. */
	if (o->json) {
		notes.out = env->err;
		r->env = &notes;
	}
	r->start = env->now_ms(env->clk);
	r->deadline = r->start + (uint64_t)o->timeout_s * 1000u;

	ret = wait_gyro_bias(b, r, e);
	if (ret)
		return ret;
	if (r->cs.has_score)
		sw_note(r->env, "Step 2/2: rotate the device slowly in a figure-8, covering every direction, pivoting about its centre (target score %.1f%%, up to %u s)...",
			o->target_score, o->timeout_s);
	else
		sw_note(r->env, "Rotate the device slowly in a figure-8, covering every direction, pivoting about its centre, until the calibration is stable (level 4; this firmware reports no score; up to %u s)...",
			o->timeout_s);

	next_poll = env->now_ms(env->clk);
	for (;;) {
		ret = b->ops->mag(b, ut, e);
		if (ret)
			return ret;
		sw_cov_add(&r->cov, ut);
		now = env->now_ms(env->clk);
		if (now >= next_poll) {
			next_poll = now + CAL_POLL_MS;
			ret = poll_chip(b, r, best_blob, e);
			if (ret)
				return ret;
			if (o->json) {
				json_progress(r, "progress", now);
			} else if (env->tty) {
				draw_tty(r, now);
			} else if (r->cs.level != shown_level ||
				   (r->have_best &&
				    r->best.score_raw != shown_best) ||
				   coverage_pct(r) >= shown_cov + 10 ||
				   now - last_line >= CAL_LINE_MS) {
				/* Plain lines only when there is news. */
				print_line(r, now);
				last_line = now;
				shown_level = r->cs.level;
				shown_best = r->best.score_raw;
				shown_cov = coverage_pct(r) / 10 * 10;
			}
			if (reached(r) || now >= r->deadline)
				break;
		}
		env->sleep_ms(env->clk, MAG_POLL_MS);
	}

	sw_cov_hint(&r->cov, hint, sizeof(hint));
	if (o->json)
		json_progress(r, reached(r) ? "complete" : "timeout", now);
	if (!r->have_best)
		return sw_err_set(e, SW_EXIT_CAL,
				  "calibration did not become stable within %u s (level %d of 4, %s; %u%% of the sphere covered; %s); nothing saved",
				  o->timeout_s, r->cs.level,
				  sw_level_name(r->cs.level), coverage_pct(r),
				  hint);
	if (r->best.has_score)
		snprintf(score, sizeof(score), "score %.3f%%, ",
			 sw_score_pct(r->best.score_raw));
	if (reached(r))
		sw_note(r->env, "Calibration stable: %s%u%% of the sphere covered.",
			score, coverage_pct(r));
	else
		sw_note(r->env, "Timed out after %u s; keeping the best score reached, %.3f%% (target %.1f%%); %u%% of the sphere covered; %s.",
			o->timeout_s, sw_score_pct(r->best.score_raw),
			o->target_score, coverage_pct(r), hint);
	ret = sw_save_snapshot(b, o, r->env, &r->best, best_blob, &saved, e);
	if (o->json) {
		sw_file_path(o, b, path, sizeof(path));
		fprintf(r->out, "{\"event\":\"%s\",\"level\":%d,\"score\":",
			saved ? "saved" : "not_saved", r->best.level);
		json_score(r->out, &r->best);
		fputs(",\"file\":", r->out);
		sw_json_str(r->out, path);
		fputs("}\n", r->out);
		fflush(r->out);
	}
	return ret;
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
			/* The output registers are 16 bits wide. */
			if (xyz[k] < INT16_MIN || xyz[k] > INT16_MAX)
				return sw_err_set(e, SW_EXIT_IO,
						  "%s: accelerometer %c reads %d LSB, out of range for a 16-bit output",
						  b->name, 'x' + k, xyz[k]);
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
	if (ret)
		return ret;
	/* calibbias takes 16-bit values: anything else did not come from there. */
	for (k = 0; k < 3; k++)
		if (old[k] < INT16_MIN || old[k] > INT16_MAX)
			return sw_err_set(e, SW_EXIT_IO,
					  "%s: the current accel %c offset reads %d LSB, out of range (-32768..32767); not calibrating",
					  b->name, 'x' + k, old[k]);
	ret = accel_measure(b, o->samples, env, &st, e);
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
	sw_note(env, "accel offsets %d %d %d LSB written and verified; output now %.1f %.1f %.1f LSB%s",
		off[0], off[1], off[2], after.mean[0], after.mean[1],
		after.mean[2], o->no_save ? ". Run 'save' to keep them." : "");
	if (o->no_save)
		return SW_EXIT_OK;
	/* The save policy keeps offsets that differ from the saved file's. */
	return sw_save_now(b, o, env, NULL, e);
}
