/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: the file the em7180 driver restores at probe.
 *
 * At probe the driver asks the kernel's firmware loader for
 * em7180/caldata-RRRR-MMMM-DEV.bin: RRRR and MMMM the ROM and RAM versions
 * (4 lowercase hex digits), DEV the name of its device (the I2C client,
 * "1-0028"), the content the 140-byte blob as calibration_data reads it.
 * The package links /usr/lib/firmware/em7180 to STATE_DIR/firmware, where
 * the tool keeps that file equal to the payload of the chip's saved file.
 */
#ifndef SW_CALDATA_H
#define SW_CALDATA_H

#include <stdbool.h>
#include <stddef.h>

#include "sw.h"

/* The directory below the state directory. */
#define SW_CALDATA_DIR "firmware"

/* "caldata-RRRR-MMMM-DEV.bin"; false when it would not fit in len. */
bool sw_caldata_name(const struct sw_chip_info *chip, const char *dev,
		     char *out, size_t len);

/*
 * Make STATE_DIR/firmware/caldata-RRRR-MMMM-DEV.bin hold blob: written
 * atomically (sw_file_write_atomic(), mode 0600, the directory 0700 and
 * created when missing, never through a symlink) unless it holds blob
 * already (then a killed save's temporary file of it is removed); then every
 * caldata-*-DEV.bin of other versions for the same DEV is removed. *wrote (may be NULL) says whether the file was written.
 * Returns SW_EXIT_OK or an exit code with e->msg set.
 */
int sw_caldata_write(const char *state_dir, const struct sw_chip_info *chip,
		     const char *dev, const uint8_t *blob, bool *wrote,
		     struct sw_err *e);

#endif
