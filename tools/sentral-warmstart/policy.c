// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: save policy.
 */
#include <math.h>

#include "level.h"
#include "policy.h"
#include "wsfile.h"

bool sw_param_moved(float now, float saved)
{
	double old = saved, tol = SW_PARAM_TOLERANCE * fmax(1.0, fabs(old));

	return fabs((double)now - old) > tol;
}

int sw_params_moved(const uint8_t *now, const uint8_t *saved, int first,
		    int last)
{
	int n;

	for (n = first; n <= last; n++)
		if (sw_param_moved(sw_blob_param(now, n),
				   sw_blob_param(saved, n)))
			return n;
	return 0;
}

int sw_blob_restored(const uint8_t *chip, const uint8_t *saved)
{
	int n = sw_params_moved(chip, saved, SW_PARAM_MAG_FIRST,
				SW_PARAM_MAG_LAST);

	return n ? n : sw_params_moved(chip, saved, SW_PARAM_ACCEL_X,
				       SW_PARAM_ACCEL_X + 2);
}

/* What the chip's state is now, for messages. */
static void describe(const struct sw_policy_in *in, char *buf, size_t len)
{
	if (in->has_score)
		snprintf(buf, len, "level %d (%s), score %.3f%%", in->level,
			 sw_level_name(in->level), sw_score_pct(in->score_raw));
	else
		snprintf(buf, len, "level %d (%s)", in->level,
			 sw_level_name(in->level));
}

/* Why a level below 4 is no calibration to keep, and what to do. */
static const char *not_stable_hint(int level)
{
	switch (level) {
	case SW_LEVEL_HALTED:
		return "the fusion algorithm is halted (standby)";
	case SW_LEVEL_UNRELIABLE:
		return "the sensor data is unreliable";
	case SW_LEVEL_TRANSIENT:
		return "a magnetic transient: keep the device away from magnets and steel";
	default:
		return "move the device in a figure-8 first";
	}
}

/* The score rule: the score against the saved file's. */
static bool score_better(const struct sw_policy_in *in, char *why,
			 size_t len)
{
	double pct = sw_score_pct(in->score_raw);
	double old_pct = sw_score_pct(in->old_score_raw);
	bool have_old = in->have_old && in->old_has_score &&
			sw_score_raw_valid(in->old_score_raw);
	bool old_good = have_old && in->old_level == SW_LEVEL_STABLE &&
			old_pct <= in->max_score;

	/* In raw steps of 100/32768 %: exact where percentages round. */
	if (in->improve_only && old_good &&
	    (in->score_raw >= in->old_score_raw ||
	     (double)in->old_score_raw - in->score_raw + 0.5 <
	     in->margin * 32768.0 / 100.0)) {
		snprintf(why, len,
			 "score %.3f%% is not better than the saved %.3f%% by the margin of %.3f points",
			 pct, old_pct, in->margin);
		return false;
	}
	if (have_old && pct < old_pct) {
		snprintf(why, len, "score %.3f%% is better than the saved %.3f%%",
			 pct, old_pct);
		return true;
	}
	if (have_old && pct > old_pct && old_good) {
		snprintf(why, len,
			 "score %.3f%% is worse than the saved file's %.3f%%; not replacing a good calibration (use --force)",
			 pct, old_pct);
		return false;
	}
	if (pct <= in->max_score) {
		snprintf(why, len, "score %.3f%% is within the limit %.3f%%",
			 pct, in->max_score);
		return true;
	}
	if (have_old)
		snprintf(why, len,
			 "score %.3f%% is above the limit %.3f%% and not better than the saved %.3f%%",
			 pct, in->max_score, old_pct);
	else
		snprintf(why, len, "score %.3f%% is above the limit %.3f%%",
			 pct, in->max_score);
	return false;
}

/*
 * The stable rule: without a score, a stable calibration is as good as
 * any other; it is worth a write only when it differs from the saved one.
 */
static bool stable_differs(const struct sw_policy_in *in, char *why,
			   size_t len)
{
	if (!in->have_old) {
		snprintf(why, len, "stable, and no usable saved calibration");
		return true;
	}
	if (in->old_level != SW_LEVEL_STABLE) {
		snprintf(why, len, "stable, and the saved calibration (%s) is not",
			 in->old_desc ? in->old_desc : "");
		return true;
	}
	if (in->mag_moved > 0) {
		snprintf(why, len,
			 "stable, and parameter %d (%s) moved from the saved file's by more than %.1f %%",
			 in->mag_moved, sw_param_name(in->mag_moved),
			 SW_PARAM_TOLERANCE * 100);
		return true;
	}
	if (in->offsets_differ) {
		snprintf(why, len,
			 "stable, and the accel offsets differ from the saved file's");
		return true;
	}
	if (in->mag_moved < 0)
		snprintf(why, len,
			 "stable; the magnetometer coefficients were not compared with the saved file's");
	else
		snprintf(why, len,
			 "stable, and the magnetometer coefficients (parameters %d-%d) are within %.1f %% of the saved file's",
			 SW_PARAM_MAG_FIRST, SW_PARAM_MAG_LAST,
			 SW_PARAM_TOLERANCE * 100);
	return false;
}

/* The calibration's own case: its level, then the score or stable rule. */
static bool calibration_better(const struct sw_policy_in *in, char *why,
			       size_t len)
{
	char now[96];

	describe(in, now, sizeof(now));
	if (in->force) {
		snprintf(why, len, "forced (%s)", now);
		return true;
	}
	if (in->level != SW_LEVEL_STABLE) {
		snprintf(why, len, "calibration not stable (%s; needs 4): %s",
			 now, not_stable_hint(in->level));
		return false;
	}
	return in->has_score ? score_better(in, why, len) :
	       stable_differs(in, why, len);
}

enum sw_save_what sw_policy_save(const struct sw_policy_in *in, char *why,
				 size_t len)
{
	char cal[320];

	/* Below 0 % is a bad read: it would look better than any calibration. */
	if (in->has_score && !sw_score_raw_valid(in->score_raw)) {
		snprintf(why, len, "score %.3f%% is out of range (a bad read?)",
			 sw_score_pct(in->score_raw));
		return SW_SAVE_NOTHING;
	}
	if (calibration_better(in, why, len))
		return SW_SAVE_BLOB;
	if (!in->offsets_differ)
		return SW_SAVE_NOTHING;
	/* The accel offsets are the user's work: never lost to the score. */
	snprintf(cal, sizeof(cal), "%s", why);
	if (in->have_old) {
		snprintf(why, len,
			 "the accel offsets differ from the saved file's; its calibration (%s) is kept: %s",
			 in->old_desc ? in->old_desc : "", cal);
		return SW_SAVE_OFFSETS;
	}
	if (in->level != SW_LEVEL_STABLE) {
		snprintf(why, len,
			 "%s; the chip's accel offsets are saved with its calibration once it is stable",
			 cal);
		return SW_SAVE_NOTHING;
	}
	snprintf(why, len,
		 "the chip holds accel offsets and no usable file does: saving its calibration as it is, although %s",
		 cal);
	return SW_SAVE_BLOB;
}

enum sw_save_what sw_policy_import(const struct sw_policy_in *in, char *why,
				   size_t len)
{
	if (in->force) {
		snprintf(why, len, "forced");
		return SW_SAVE_BLOB;
	}
	if (!in->have_old) {
		snprintf(why, len, "no usable saved calibration for this chip");
		return SW_SAVE_BLOB;
	}
	snprintf(why, len,
		 "a saved calibration exists (%s) and the board's block carries no level or score to compare it with (--force replaces it)",
		 in->old_desc ? in->old_desc : "");
	return SW_SAVE_NOTHING;
}
