/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: the calibration level every firmware reports, and the
 * application note's registers only some firmware has.
 */
#ifndef SW_LEVEL_H
#define SW_LEVEL_H

#include "sw.h"

/*
 * in_magn_calibration_auto_status, computed by the driver (and by the
 * i2c-dev backend) from AlgorithmStatus (register 0x38), first match
 * wins. Greater is better, 0 = calibration not running, as the bno055
 * driver gives it. The tool saves only at SW_LEVEL_STABLE.
 */
enum sw_level {
	SW_LEVEL_HALTED = 0,		/* bit 0: fusion halted or in standby */
	SW_LEVEL_UNRELIABLE = 1,	/* bit 5: unreliable sensor data */
	SW_LEVEL_CALIBRATING = 2,	/* bit 3 (CalibStable) clear */
	SW_LEVEL_TRANSIENT = 3,		/* bits 3 and 4 (MagTransient) */
	SW_LEVEL_STABLE = 4,		/* bit 3, bit 4 clear */
};

#define SW_LEVEL_MAX SW_LEVEL_STABLE

/* "halted", ..., "stable"; "out of range" for anything but 0..4. */
const char *sw_level_name(int level);

/*
 * The level of an AlgorithmStatus value, or -1 when its reserved bits 6
 * or 7 are set: a bus glitch reads 0xff, and the driver fails such a read
 * with EIO.
 */
int sw_level_of_algo_status(uint8_t algo);

/*
 * Values read from the chip are input, not truth: true when every field of
 * cs is in range (the level 0..4; with a score, the flags 0 or 1 and the
 * score 0 % or more), else false with why saying which is not.
 */
bool sw_cal_state_check(const struct sw_cal_state *cs, char *why, size_t len);

/* Registers 0x43..0x4E as one burst reads them. */
#define SW_APPNOTE_FIRST 0x43
#define SW_APPNOTE_LEN 12

/*
 * Do AlgorithmStatus algo and registers 0x43..0x4E (regs) hold the
 * application note's layout (status, update flags, score)? The rule the
 * driver uses: (a) 0x43 uses bits 3:0 only, (b) 0x44 bits 1:0 only, (c)
 * the score is 0 % or more, and, with full (the first look),
 * (d) MagTransient in 0x43 agrees with AlgorithmStatus bit 4 and (e)
 * status 3 (complete) with bit 3 (stable). Later reads re-check (a) to (c)
 * only: the two registers are not updated at the same instant. A USFS
 * board keeps linear acceleration in 0x3F..0x44, which fails (a) or (b)
 * as soon as it has any magnitude or sign.
 */
bool sw_appnote_layout(uint8_t algo, const uint8_t *regs, bool full);

/* Has the firmware the application note's registers? */
enum sw_layout {
	SW_LAYOUT_UNKNOWN,	/* not looked at while the chip ran yet */
	SW_LAYOUT_APPNOTE,
	SW_LAYOUT_OTHER,	/* for good, as the driver decides */
};

/* AlgorithmStatus (0x38) to 0x4E: one burst read of the chip. */
#define SW_ALGO_STATUS 0x38
#define SW_CAL_REGS_LEN (SW_APPNOTE_FIRST + SW_APPNOTE_LEN - SW_ALGO_STATUS)

/*
 * The calibration state of regs (registers 0x38..0x4E read in one burst,
 * SW_CAL_REGS_LEN bytes) as the driver gives it: the level from
 * AlgorithmStatus, and score and update flags while *layout is
 * SW_LAYOUT_APPNOTE. *layout is decided at the first read while the chip
 * runs (not halted) with the full check, and demoted for good by a later
 * read that fails the partial one. False for a glitched read (reserved
 * bits of AlgorithmStatus set): nothing is decided from it.
 */
bool sw_cal_state_of_regs(const uint8_t *regs, enum sw_layout *layout,
			  struct sw_cal_state *cs);

#endif
