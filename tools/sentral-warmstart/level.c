// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: the calibration level and the application note's
 * register layout (see level.h).
 */
#include <string.h>

#include "level.h"

#define ALGO_HALTED	0x01
#define ALGO_STABLE	0x08
#define ALGO_TRANSIENT	0x10
#define ALGO_UNRELIABLE	0x20
#define ALGO_RESERVED	0xc0

const char *sw_level_name(int level)
{
	static const char *const names[] = {
		[SW_LEVEL_HALTED] = "halted",
		[SW_LEVEL_UNRELIABLE] = "unreliable sensor data",
		[SW_LEVEL_CALIBRATING] = "calibrating",
		[SW_LEVEL_TRANSIENT] = "stable with a magnetic transient",
		[SW_LEVEL_STABLE] = "stable",
	};

	if (level < 0 || level > SW_LEVEL_MAX)
		return "out of range";
	return names[level];
}

int sw_level_of_algo_status(uint8_t algo)
{
	if (algo & ALGO_RESERVED)
		return -1;
	if (algo & ALGO_HALTED)
		return SW_LEVEL_HALTED;
	if (algo & ALGO_UNRELIABLE)
		return SW_LEVEL_UNRELIABLE;
	if (!(algo & ALGO_STABLE))
		return SW_LEVEL_CALIBRATING;
	if (algo & ALGO_TRANSIENT)
		return SW_LEVEL_TRANSIENT;
	return SW_LEVEL_STABLE;
}

bool sw_cal_state_check(const struct sw_cal_state *cs, char *why, size_t len)
{
	if (cs->level < 0 || cs->level > SW_LEVEL_MAX)
		snprintf(why, len, "calibration level %d is not 0..4", cs->level);
	else if (!cs->has_score)
		return true;
	else if (cs->gyro_bias_update < 0 || cs->gyro_bias_update > 1 ||
		 cs->mag_cal_update < 0 || cs->mag_cal_update > 1)
		snprintf(why, len, "update flags %d %d are not 0 or 1",
			 cs->gyro_bias_update, cs->mag_cal_update);
	else if (!sw_score_raw_valid(cs->score_raw))
		snprintf(why, len, "calibration score %.3f%% is below 0 %%",
			 sw_score_pct(cs->score_raw));
	else
		return true;
	return false;
}

/* Offsets in the 0x43..0x4E burst. */
#define R_STATUS	0
#define R_FLAGS		1
#define R_SCORE		(0x4d - SW_APPNOTE_FIRST)

bool sw_appnote_layout(uint8_t algo, const uint8_t *regs, bool full)
{
	bool transient = regs[R_STATUS] & 0x0c;
	bool complete = (regs[R_STATUS] & 3) == 3;

	if ((regs[R_STATUS] & 0xf0) || (regs[R_FLAGS] & 0xfc) ||
	    !sw_score_raw_valid(sw_get_le16(regs + R_SCORE)))
		return false;
	if (!full)
		return true;
	return transient == !!(algo & ALGO_TRANSIENT) &&
	       complete == !!(algo & ALGO_STABLE);
}

bool sw_cal_state_of_regs(const uint8_t *regs, enum sw_layout *layout,
			  struct sw_cal_state *cs)
{
	const uint8_t *an = regs + SW_APPNOTE_FIRST - SW_ALGO_STATUS;
	uint8_t algo = regs[0];

	memset(cs, 0, sizeof(*cs));
	cs->level = sw_level_of_algo_status(algo);
	if (cs->level < 0)
		return false;
	if (*layout == SW_LAYOUT_UNKNOWN && cs->level != SW_LEVEL_HALTED)
		*layout = sw_appnote_layout(algo, an, true) ?
			  SW_LAYOUT_APPNOTE : SW_LAYOUT_OTHER;
	else if (*layout == SW_LAYOUT_APPNOTE &&
		 !sw_appnote_layout(algo, an, false))
		*layout = SW_LAYOUT_OTHER;
	if (*layout != SW_LAYOUT_APPNOTE)
		return true;
	cs->has_score = true;
	cs->score_raw = sw_get_le16(an + R_SCORE);
	cs->mag_cal_update = an[R_FLAGS] & 1;
	cs->gyro_bias_update = (an[R_FLAGS] >> 1) & 1;
	return true;
}
