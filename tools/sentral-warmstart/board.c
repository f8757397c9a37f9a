// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: the calibration block of the USFS utilities in an
 * image of the board's EEPROM (see board.h).
 */
#include <string.h>

#include "board.h"
#include "wsfile.h"

struct layout {
	const char *name;
	uint32_t params;	/* parameters 1..35 */
	uint32_t accel;		/* accel cal, 12 bytes */
	bool marker;		/* SW_BOARD_MARKER right after the accel cal */
};

static const struct layout layouts[] = {
	[SW_BOARD_GT] = { "gt", 0x8000, 0x808c, true },
	[SW_BOARD_KW] = { "kw", 0x7f00, 0x7f8c, false },
};

/* gt's initSensors(): outside these, it loads no accel cal at all. */
#define ACC_LIMIT_LO 1800
#define ACC_LIMIT_HI 2240

static const char *const check_names[] = {
	[SW_BOARD_OK] = "ok",
	[SW_BOARD_TOO_LARGE] = "larger than the EEPROM",
	[SW_BOARD_SHORT] = "image too short",
	[SW_BOARD_BLANK] = "no calibration saved (erased)",
	[SW_BOARD_MARKER_BAD] = "no valid-block marker",
	[SW_BOARD_NONFINITE] = "non-finite float",
};

const char *sw_board_layout_name(enum sw_board_layout l)
{
	return layouts[l].name;
}

bool sw_board_layout_parse(const char *s, enum sw_board_layout *l)
{
	size_t i;

	for (i = 0; i < sizeof(layouts) / sizeof(layouts[0]); i++)
		if (!strcmp(s, layouts[i].name)) {
			*l = (enum sw_board_layout)i;
			return true;
		}
	return false;
}

const char *sw_board_check_name(enum sw_board_check c)
{
	return check_names[c];
}

static bool erased(const uint8_t *p, size_t n)
{
	while (n--)
		if (*p++ != 0xff)
			return false;
	return true;
}

static void parse_accel(const uint8_t *p, struct sw_board_cal *cal)
{
	int k;

	cal->accel_present = !erased(p, SW_BOARD_ACCEL_SIZE);
	cal->accel_in_range = cal->accel_present;
	for (k = 0; k < 3; k++) {
		cal->acc_max[k] = (int16_t)sw_get_le16(p + 2 * k);
		cal->acc_min[k] = (int16_t)sw_get_le16(p + 6 + 2 * k);
		if (cal->acc_max[k] < ACC_LIMIT_LO ||
		    cal->acc_max[k] > ACC_LIMIT_HI ||
		    cal->acc_min[k] < -ACC_LIMIT_HI ||
		    cal->acc_min[k] > -ACC_LIMIT_LO)
			cal->accel_in_range = false;
	}
}

enum sw_board_check sw_board_parse(const uint8_t *img, size_t len,
				   enum sw_board_layout l,
				   struct sw_board_cal *cal, char *detail,
				   size_t detail_len)
{
	const struct layout *ly = &layouts[l];
	const struct layout *kw = &layouts[SW_BOARD_KW];
	size_t end = ly->accel + SW_BOARD_ACCEL_SIZE + (ly->marker ? 1 : 0);
	const uint8_t *p = img + ly->params;
	const char *hint = "";
	int bad;

	memset(cal, 0, sizeof(*cal));
	if (len > SW_BOARD_EEPROM_SIZE) {
		snprintf(detail, detail_len,
			 "more than the M24512's %d bytes: not an image of it",
			 SW_BOARD_EEPROM_SIZE);
		return SW_BOARD_TOO_LARGE;
	}
	if (len < end) {
		snprintf(detail, detail_len,
			 "%zu bytes; the %s block needs bytes 0x%04x..0x%04zx",
			 len, ly->name, ly->params, end - 1);
		return SW_BOARD_SHORT;
	}
	/* gt's place empty or unmarked: point at kw's when it holds something. */
	if (ly->marker && len >= kw->params + SW_BLOB_SIZE &&
	    !erased(img + kw->params, SW_BLOB_SIZE))
		hint = "; bytes at 0x7f00 may be a block saved by Kris Winer's sketches, which write no marker: --layout kw";
	if (erased(p, SW_BLOB_SIZE) &&
	    (!ly->marker || img[end - 1] == 0xff)) {
		snprintf(detail, detail_len,
			 "bytes 0x%04x..0x%04x are all 0xff%s", ly->params,
			 ly->params + SW_BLOB_SIZE - 1, hint);
		return SW_BOARD_BLANK;
	}
	if (ly->marker && img[end - 1] != SW_BOARD_MARKER) {
		snprintf(detail, detail_len,
			 "byte 0x%04zx is 0x%02x, not 0x%02x%s", end - 1,
			 img[end - 1], SW_BOARD_MARKER, hint);
		return SW_BOARD_MARKER_BAD;
	}
	bad = sw_blob_nonfinite(p);
	if (bad) {
		snprintf(detail, detail_len,
			 "parameter %d (%s) at 0x%04x is NaN or infinite", bad,
			 sw_param_name(bad), ly->params + 4 * (bad - 1));
		return SW_BOARD_NONFINITE;
	}
	cal->layout = l;
	cal->params_at = ly->params;
	memcpy(cal->blob, p, SW_BLOB_SIZE);
	parse_accel(img + ly->accel, cal);
	return SW_BOARD_OK;
}
