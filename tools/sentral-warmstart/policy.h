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

/* What a save writes. */
enum sw_save_what {
	SW_SAVE_NOTHING,
	SW_SAVE_BLOB,		/* the chip's blob with its status and score */
	/* the saved file's blob and header with the chip's accel offsets */
	SW_SAVE_OFFSETS,
};

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
	/*
	 * The chip's accel offsets (parameters 27..29) are not all zero (the
	 * power-on value, which a chip not restored holds) and differ from
	 * the saved file's, or there is no usable file.
	 */
	bool offsets_differ;
};

/*
 * What to save (SW_SAVE_NOTHING is 0: a truth value). why receives a
 * one-line reason either way. Rules: status must be 3; then the score must
 * be <= max_score or better (lower) than the existing file's; a file that
 * is itself complete and acceptable is never replaced by a worse one.
 * --force overrides all. With improve_only (watch), a complete and
 * acceptable file is replaced only by a score at least margin points
 * lower: not by an equal one. When those say no, offsets that differ are
 * still kept: put into the saved file (SW_SAVE_OFFSETS), or with no usable
 * file, saved with the chip's blob as it is.
 */
enum sw_save_what sw_policy_save(const struct sw_policy_in *in, char *why,
				 size_t len);

/*
 * import-board: may a calibration taken from the board's EEPROM, which
 * records no status or score, be written over the file in? Only where no
 * usable file for this chip is (missing, or failing a check), or with
 * --force: there is nothing to judge it against a saved one by. Uses
 * have_old, old_status, old_score_raw and force; returns SW_SAVE_BLOB or
 * SW_SAVE_NOTHING, why saying why either way.
 */
enum sw_save_what sw_policy_import(const struct sw_policy_in *in, char *why,
				   size_t len);

#endif
