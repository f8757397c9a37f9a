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
/* watch: a look every 30 s notices a new calibration within a minute */
#define SW_DEFAULT_POLL_S 30

/*
 * Without a score, a parameter counts as changed when it moved by more
 * than this part of its saved value (of 1, for a value below 1):
 * |new - old| > 0.005 * max(1, |old|).
 */
#define SW_PARAM_TOLERANCE 0.005
/* The learned magnetometer calibration (the seed's mcoeffs[1..6]). */
#define SW_PARAM_MAG_FIRST 18
#define SW_PARAM_MAG_LAST 23

/* Has a parameter moved from its saved value beyond the tolerance? */
bool sw_param_moved(float now, float saved);

/*
 * The first of parameters first..last (1-based) of blob now that moved
 * from saved's beyond the tolerance, or 0 when none did.
 */
int sw_params_moved(const uint8_t *now, const uint8_t *saved, int first,
		    int last);

/*
 * Does the chip hold the saved calibration (status's "restored")? The
 * first of parameters 18..23 and 27..29 that moved beyond the tolerance,
 * or 0 when none did.
 */
int sw_blob_restored(const uint8_t *chip, const uint8_t *saved);

/* What a save writes. */
enum sw_save_what {
	SW_SAVE_NOTHING,
	SW_SAVE_BLOB,		/* the chip's blob with its level and score */
	/* the saved file's blob and header with the chip's accel offsets */
	SW_SAVE_OFFSETS,
};

struct sw_policy_in {
	int level;		/* current calibration level, 0..4 */
	bool has_score;		/* the chip reports a score: the score rule */
	uint16_t score_raw;	/* current raw score, with has_score */
	double max_score;	/* acceptable score, percent */
	bool have_old;		/* a valid file for this chip exists */
	int old_level;		/* its level (sw_file_level()) */
	bool old_has_score;	/* it was judged by a score */
	uint16_t old_score_raw;
	const char *old_desc;	/* sw_file_describe() of it, for messages */
	/*
	 * The stable rule (no score): the first of parameters 18..23 that
	 * moved from the saved file's beyond the tolerance, 0 when none
	 * did, -1 when the chip's blob was not read.
	 */
	int mag_moved;
	bool force;
	/* a good saved file is replaced only by a score margin points lower */
	bool improve_only;
	double margin;
	/*
	 * The chip's accel offsets (parameters 27..29) are not all zero (the
	 * power-on value, which a chip not restored holds) and differ from
	 * the saved file's, or there is no usable file.
	 */
	bool offsets_differ;
};

/*
 * What to save (SW_SAVE_NOTHING is 0: a truth value). why receives a
 * one-line reason either way. The calibration must be stable (level 4);
 * then, with a score (the score rule), the score must be <= max_score or
 * better (lower) than the existing file's, and a file that is itself
 * stable and acceptable is never replaced by a worse one; with
 * improve_only (watch), such a file is replaced only by a score at least
 * margin points lower: not by an equal one. Without a score (the stable
 * rule) it is saved when no usable file exists, the file was not saved
 * stable, a magnetometer coefficient (18..23) moved beyond the tolerance,
 * or the accel offsets differ. --force overrides all. When those say no,
 * offsets that differ are still kept: put into the saved file
 * (SW_SAVE_OFFSETS), or with no usable file, saved with the chip's blob
 * as it is while it is stable.
 */
enum sw_save_what sw_policy_save(const struct sw_policy_in *in, char *why,
				 size_t len);

/*
 * import-board: may a calibration taken from the board's EEPROM, which
 * records no level or score, be written over the file in? Only where no
 * usable file for this chip is (missing, or failing a check), or with
 * --force: there is nothing to judge it against a saved one by. Uses
 * have_old, old_desc and force; returns
 * SW_SAVE_BLOB or SW_SAVE_NOTHING, why saying why either way.
 */
enum sw_save_what sw_policy_import(const struct sw_policy_in *in, char *why,
				   size_t len);

#endif
