/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: the interface both backends implement.
 *
 * "driver" talks to the em7180 IIO driver through sysfs; "i2c" speaks the
 * chip's register protocol itself over /dev/i2c-N when no driver is bound.
 * Every operation returns SW_EXIT_OK or an exit code with e->msg set.
 */
#ifndef SW_BACKEND_H
#define SW_BACKEND_H

#include "devkey.h"
#include "sw.h"

struct sw_backend;

struct sw_backend_ops {
	int (*chip_info)(struct sw_backend *b, struct sw_chip_info *ci,
			 struct sw_err *e);
	int (*cal_state)(struct sw_backend *b, struct sw_cal_state *cs,
			 struct sw_err *e);
	int (*read_blob)(struct sw_backend *b, uint8_t *blob,
			 struct sw_err *e);
	/*
	 * chip: the identity the blob was saved with. A backend that
	 * checks_identity refuses another chip's or firmware's blob with
	 * SW_EXIT_FILE before the chip is touched.
	 */
	int (*write_blob)(struct sw_backend *b, const struct sw_chip_info *chip,
			  const uint8_t *blob, struct sw_err *e);
	/* One sample of the magnetometer output, uT. */
	int (*mag)(struct sw_backend *b, double ut[3], struct sw_err *e);
	/* One sample of the scaled accelerometer output, LSB. */
	int (*accel_raw)(struct sw_backend *b, int xyz[3], struct sw_err *e);
	/* Accelerometer offsets (parameters 27..29) in LSB. */
	int (*accel_offset_get)(struct sw_backend *b, int lsb[3],
				struct sw_err *e);
	int (*accel_offset_set)(struct sw_backend *b, const int lsb[3],
				struct sw_err *e);
	/*
	 * Firmware origin and feature sensors. A value the driver refuses
	 * while a buffer streams (EBUSY) is left out (have_value false),
	 * never an error.
	 */
	int (*hub_info)(struct sw_backend *b, struct sw_hub_info *hi,
			struct sw_err *e);
	void (*close)(struct sw_backend *b);
};

/* Saved-file keys of older versions, moved to the new key once. */
#define SW_NLEGACY 2

struct sw_backend {
	const struct sw_backend_ops *ops;
	const char *kind;	/* "driver" or "i2c" */
	char name[128];		/* "iio:device0" or "/dev/i2c-0@0x28" */
	char key[SW_KEY_MAX];	/* saved-file key, see devkey.h */
	/*
	 * The driver's device, the I2C client ("1-0028"), which names the
	 * file the driver restores at probe (caldata.h); "" for i2c-dev
	 */
	char client[64];
	/* "" when none; an old key shared by two chips is not listed */
	char legacy_key[SW_NLEGACY][SW_KEY_MAX];
	/*
	 * The driver (1.2.0 on) has the chip's identity in the blob's
	 * header (caldata.h), not in attributes: chip_info then costs a read
	 * of the blob unless one was read since the last write, and a write
	 * checks the identity itself.
	 */
	bool checks_identity;
};

struct sw_iio_opts {
	const char *device;	/* --device, NULL: the single em7180 */
	/* No matching device is a success with *out = NULL (save --if-present). */
	bool gone_ok;
	/* The driver's attributes checked against the tool's (abi.h), at open. */
	bool check_abi;
	const char *version;	/* the tool's, for the messages of that check */
};

/*
 * A failed access to attribute attr of the IIO device name, errno err, as
 * an exit code and a message saying what to do: the device gone (ENODEV,
 * or dir_gone: its sysfs directory vanished) is SW_EXIT_DEVICE, a missing
 * attribute (an older or newer driver) SW_EXIT_DRIVER; EBUSY names the
 * buffer to stop.
 */
int sw_iio_err(struct sw_err *e, const char *name, const char *op,
	       const char *attr, int err, bool dir_gone);

/*
 * libiio failed to list the IIO devices in sysfs (/sys/bus/iio/devices but
 * in tests) with errno err: say which of them, and why, from a look of our
 * own at what libiio reads: the directory missing, an entry that is a
 * broken link or cannot be read (SW_EXIT_DEVICE, or SW_EXIT_OSERR).
 */
int sw_iio_scan_err(struct sw_err *e, const char *sysfs, int err);

int sw_iio_open(const struct sw_iio_opts *o, struct sw_backend **out,
		struct sw_err *e);

struct sw_i2c_opts {
	const char *dev;	/* --i2c BUS: a number, a name or a path (i2cbus.h) */
	unsigned int addr;	/* 7-bit, default 0x28 */
	bool force;		/* even when a kernel driver is bound */
};

int sw_i2c_open(const struct sw_i2c_opts *o, struct sw_backend **out,
		struct sw_err *e);

#endif
