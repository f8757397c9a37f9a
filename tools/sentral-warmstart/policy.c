// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: save policy.
 */
#include "policy.h"

/* The calibration's own case: status and score against the saved file. */
static bool calibration_better(const struct sw_policy_in *in, char *why,
			       size_t len)
{
	double pct = sw_score_pct(in->score_raw);
	double old_pct = sw_score_pct(in->old_score_raw);
	bool have_old = in->have_old && sw_score_raw_valid(in->old_score_raw);
	bool old_good = have_old && in->old_status == 3 &&
			old_pct <= in->max_score;

	if (in->force) {
		snprintf(why, len, "forced (status %d, score %.3f%%)",
			 in->status, pct);
		return true;
	}
	if (in->status != 3) {
		snprintf(why, len,
			 "calibration incomplete (status %d, needs 3); move the device in a figure-8 first",
			 in->status);
		return false;
	}
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

enum sw_save_what sw_policy_save(const struct sw_policy_in *in, char *why,
				 size_t len)
{
	bool have_old = in->have_old && sw_score_raw_valid(in->old_score_raw);
	char cal[256];

	/* Below 0 % is a bad read: it would look better than any calibration. */
	if (!sw_score_raw_valid(in->score_raw)) {
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
	if (have_old) {
		snprintf(why, len,
			 "the accel offsets differ from the saved file's; its calibration (status %d, score %.3f%%) is kept: %s",
			 in->old_status, sw_score_pct(in->old_score_raw), cal);
		return SW_SAVE_OFFSETS;
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
		 "a saved calibration exists (status %d, score %.3f%%) and the board's block carries no status or score to compare it with (--force replaces it)",
		 in->old_status, sw_score_pct(in->old_score_raw));
	return SW_SAVE_NOTHING;
}
