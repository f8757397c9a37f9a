/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: the em7180 driver's calibration_data blob, and the
 * file the driver restores at probe.
 *
 * calibration_data (since 1.2.0) is an 8-byte header, then the 140-byte
 * payload (parameters 1..35, float32 LE): byte 0 the format (1), byte 1
 * ProductID, byte 2 RevisionID, byte 3 zero, bytes 4-5 the ROM version,
 * bytes 6-7 the RAM version, both LE. A read fills the header from the
 * chip the driver runs; a write whose header is not exactly that chip's is
 * refused (EINVAL) before the chip is touched.
 *
 * At probe the driver asks the kernel's firmware loader for
 * em7180/caldata-DEV.bin, DEV the name of its device (the I2C client,
 * "1-0028"), the content the blob as calibration_data reads it, checked
 * as a write. The package links /usr/lib/firmware/em7180 to
 * STATE_DIR/firmware, where the tool keeps that file equal to the payload
 * of the chip's saved file, with the saved file's identity.
 */
#ifndef SW_CALDATA_H
#define SW_CALDATA_H

#include <stdbool.h>
#include <stddef.h>

#include "sw.h"

/* The directory below the state directory. */
#define SW_CALDATA_DIR "firmware"

#define SW_CALDATA_FORMAT 1
#define SW_CALDATA_HDR_SIZE 8
#define SW_CALDATA_SIZE (SW_CALDATA_HDR_SIZE + SW_BLOB_SIZE)

/* The blob of chip with payload, as calibration_data reads it. */
void sw_caldata_encode(const struct sw_chip_info *chip, const uint8_t *payload,
		       uint8_t out[SW_CALDATA_SIZE]);

/*
 * The identity and payload of such a blob; false (nothing set) when its
 * header is not format 1 with byte 3 zero.
 */
bool sw_caldata_decode(const uint8_t in[SW_CALDATA_SIZE],
		       struct sw_chip_info *chip, uint8_t *payload);

/* "caldata-DEV.bin"; false when it would not fit in len. */
bool sw_caldata_name(const char *dev, char *out, size_t len);

/*
 * Make STATE_DIR/firmware/caldata-DEV.bin hold the blob of chip and
 * payload: written atomically (sw_file_write_atomic(), mode 0600, the
 * directory 0700 and created when missing, never through a symlink) unless
 * it holds it already (then a killed save's temporary file of it is
 * removed); then the files of DEV that drivers before 1.2.0 read,
 * caldata-RRRR-MMMM-DEV.bin (RRRR and MMMM the ROM and RAM versions), are
 * removed. *wrote (may be NULL) says whether the file was written.
 * Returns SW_EXIT_OK or an exit code with e->msg set.
 */
int sw_caldata_write(const char *state_dir, const struct sw_chip_info *chip,
		     const char *dev, const uint8_t *payload, bool *wrote,
		     struct sw_err *e);

#endif
