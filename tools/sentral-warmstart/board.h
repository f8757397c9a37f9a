/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: the calibration block that the USFS boards' Arduino
 * and Teensy utilities keep in the board's M24512 EEPROM (I2C 0x50, 128-byte
 * pages, two address bytes), found in an image of that EEPROM: at24's nvmem
 * file or a dump. Sources and how well each fact is confirmed:
 * tests/sim/README.md, "A USFS board's EEPROM: the utilities' calibration
 * block".
 *
 *   layout  parameters 1..35       accel cal (12 bytes)   marker
 *   gt      0x8000..0x808b         0x808c..0x8097         0xaa at 0x8098
 *   kw      0x7f00..0x7f8b         0x7f8c..0x7f97         none
 *
 * gt: gregtomasch/EM7180_SENtral_Calibration, EM7180.cpp readSenParams(),
 * writeSenParams(), readAccelCal() (every variant of the utility).
 * kw: kriswiner/EM7180_SENtral_sensor_hub, WarmStartandAccelCal/ and
 * WarmStart/ sketches, readSenParams(), readAccelCal().
 *
 * Each parameter is the four bytes SavedParamByte0..3 gave, as they came:
 * a little-endian float32, as in our own blob. The accel cal is accZero_max
 * x, y, z then accZero_min x, y, z, int16 little-endian each, in 1/2048 g.
 */
#ifndef SW_BOARD_H
#define SW_BOARD_H

#include "sw.h"

/* An M24512: 64 KiB. An image may stop after the block; never longer. */
#define SW_BOARD_EEPROM_SIZE 65536
#define SW_BOARD_ACCEL_SIZE 12
/* gt's "valid warm start" byte */
#define SW_BOARD_MARKER 0xaa

enum sw_board_layout {
	SW_BOARD_GT,
	SW_BOARD_KW,
};

/* The checks, each with a stable name used in messages and tests. */
enum sw_board_check {
	SW_BOARD_OK = 0,
	SW_BOARD_TOO_LARGE,
	SW_BOARD_SHORT,
	SW_BOARD_BLANK,
	SW_BOARD_MARKER_BAD,
	SW_BOARD_NONFINITE,
};

struct sw_board_cal {
	enum sw_board_layout layout;
	uint32_t params_at;		/* EEPROM address of parameter 1 */
	uint8_t blob[SW_BLOB_SIZE];	/* parameters 1..35, as our blob */
	/* the accel cal's 12 bytes are not all erased (0xff) */
	bool accel_present;
	/* each max within 1800..2240 and each min within -2240..-1800 LSB */
	bool accel_in_range;
	int16_t acc_max[3], acc_min[3];
};

const char *sw_board_layout_name(enum sw_board_layout l);
/* "gt" or "kw"; false for anything else. */
bool sw_board_layout_parse(const char *s, enum sw_board_layout *l);
const char *sw_board_check_name(enum sw_board_check c);

/*
 * Find and check the block of layout l in an EEPROM image of len bytes
 * (from address 0). On failure returns the failed check and describes it
 * in detail; cal is then not to be used.
 */
enum sw_board_check sw_board_parse(const uint8_t *img, size_t len,
				   enum sw_board_layout l,
				   struct sw_board_cal *cal, char *detail,
				   size_t detail_len);

#endif
