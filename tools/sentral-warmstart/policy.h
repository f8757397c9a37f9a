/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: when is a calibration worth saving?
 */
#ifndef SW_POLICY_H
#define SW_POLICY_H

#include "sw.h"

/* Seed app note: "acceptable when the score is about 5, best about 3". */
#define SW_DEFAULT_MAX_SCORE 5.0
#define SW_DEFAULT_TARGET_SCORE 3.0
/* watch: a flash write at most every 5 minutes, for a gain of 0.5 points */
#define SW_DEFAULT_INTERVAL_S 300
#define SW_DEFAULT_MARGIN 0.5

struct sw_policy_in {
	int status;		/* current calibration status */
	uint16_t score_raw;	/* current raw score */
	double max_score;	/* acceptable score, percent */
	bool have_old;		/* a valid file for this chip exists */
	int old_status;
	uint16_t old_score_raw;
	bool force;
	/* a good saved file is replaced only by a score margin points lower */
	bool improve_only;
	double margin;
};

/*
 * Returns true to save. why receives a one-line reason either way.
 * Rules: status must be 3; then the score must be <= max_score or better
 * (lower) than the existing file's; a file that is itself complete and
 * acceptable is never replaced by a worse one. --force overrides all.
 * With improve_only (watch), a complete and acceptable file is replaced
 * only by a score at least margin points lower: not by an equal one.
 */
bool sw_policy_save(const struct sw_policy_in *in, char *why, size_t len);

#endif
