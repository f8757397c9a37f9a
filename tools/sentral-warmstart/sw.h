/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: shared definitions (exit codes, error reporting,
 * chip facts used by every part of the tool).
 */
#ifndef SW_H
#define SW_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <sysexits.h>

/*
 * Exit codes, documented in sentral-warmstart.8 and --help. They come from
 * sysexits.h so that systemd names them right ("65/DATAERR"); its names
 * for 1..7 are the LSB init-script meanings, which would mislead. "The
 * save policy said no" is a success: nothing went wrong.
 */
enum sw_exit {
	SW_EXIT_OK = 0,
	SW_EXIT_USAGE = EX_USAGE,	/* 64: bad command line */
	SW_EXIT_FILE = EX_DATAERR,	/* 65: saved file failed a check */
	SW_EXIT_NOFILE = EX_NOINPUT,	/* 66: saved file missing */
	SW_EXIT_DEVICE = EX_UNAVAILABLE, /* 69: no device, several, wrong chip, driver bound, gone */
	SW_EXIT_OSERR = EX_OSERR,	/* 71: out of memory */
	SW_EXIT_STATEDIR = EX_OSFILE,	/* 72: state directory missing */
	SW_EXIT_IO = EX_IOERR,		/* 74: sysfs, i2c bus or file system error */
	SW_EXIT_CAL = EX_TEMPFAIL,	/* 75: calibration incomplete, timed out or unverified */
	SW_EXIT_PERM = EX_NOPERM,	/* 77: refused: owner, mode or symlink */
	SW_EXIT_DRIVER = EX_CONFIG,	/* 78: driver too old or too new for the tool */
};

/* Warm-start parameters 1..35, one little-endian float32 each. */
#define SW_NPARAMS 35
#define SW_BLOB_SIZE (SW_NPARAMS * 4)

/* Accelerometer offsets live in warm-start parameters 27..29. */
#define SW_PARAM_ACCEL_X 27
/* Seed app note: 1 LSB = 0.000488 g exactly (not 1/2048). */
#define SW_G_PER_LSB 0.000488
/* Scaled accel output expected with Z down (NED): 0, 0, +1 g. */
#define SW_ACCEL_1G_LSB 2048

/* Default location of saved files. */
#define SW_STATE_DIR "/var/lib/sentral-warmstart"

/* Percent score from the raw 16-bit register pair (seed register map). */
static inline double sw_score_pct(uint16_t raw)
{
	return ((double)raw - 32768.0) / 32768.0 * 100.0;
}

/* Inverse of the above, rounding to the nearest raw value. */
uint16_t sw_score_raw(double pct);

/*
 * calibration_score as the driver prints it ("2.747"): plain decimals from
 * -100 to 100 only, never "nan", "inf" or hex. False when it is not.
 */
bool sw_parse_score(const char *text, uint16_t *raw);

/*
 * A whole number as a user writes it on the command line: decimal, or
 * hexadecimal after "0x" (a leading 0 is decimal, not octal); no sign,
 * space or suffix. Returns 0, EINVAL when s is no such number, ERANGE when
 * it is above max.
 */
int sw_parse_number(const char *s, unsigned long max, unsigned long *out);

/* A score is a fit error: 0 % or more. A raw value below 0x8000 is a bad read. */
static inline bool sw_score_raw_valid(uint16_t raw)
{
	return raw >= 0x8000;
}

struct sw_err {
	int code;		/* enum sw_exit, SW_EXIT_OK when nothing failed */
	char msg[512];
};

/* Record the first failure; later calls do not overwrite it. */
int sw_err_set(struct sw_err *e, int code, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));
void sw_err_clear(struct sw_err *e);
/* Add to the message of a failure already recorded. */
void sw_err_append(struct sw_err *e, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

/*
 * SIGINT, SIGTERM and SIGHUP only note the signal (sw_signal_pending());
 * the i2c-dev backend then ends transfer mode and fails, and main() dies of
 * the signal once the chip is left running. Installed by that backend only:
 * the driver's sysfs writes are whole in the kernel.
 */
void sw_signals_catch(void);
int sw_signal_pending(void);

/* Identity of the chip, compared against a saved file before a restore. */
struct sw_chip_info {
	uint8_t product_id;	/* reg 0x90 */
	uint8_t revision_id;	/* reg 0x91 */
	uint16_t rom_version;	/* regs 0x70-0x71 */
	uint16_t ram_version;	/* regs 0x72-0x73 */
};

/*
 * Calibration state. Every firmware has the level; the score and update
 * flags are the application note's registers, which only some firmware
 * has (the driver makes their attributes only then, see level.h).
 */
struct sw_cal_state {
	int level;		/* enum sw_level, 0..4, 4 = stable */
	bool has_score;		/* the three fields below were read */
	uint16_t score_raw;	/* regs 0x4D | 0x4E << 8; 0 without a score */
	/*
	 * 0/1: the chip reported an update in reg 0x44 (bit 1 gyro bias,
	 * bit 0 magnetic calibration). The driver's flags stay 1 until
	 * calibration_data is read or written; over i2c-dev 0x44 clears when
	 * read, so they say "since the last read of 0x44 by anyone".
	 */
	int gyro_bias_update;
	int mag_cal_update;
};

/* Where the firmware the chip runs came from. */
enum sw_fw_source {
	SW_FW_UNKNOWN,		/* an older driver, or the chip does not say */
	SW_FW_EEPROM,		/* the board's EEPROM, at power-on or reset */
	SW_FW_HOST,		/* uploaded by the host: needed again after a reset */
};

/* The feature sensors, in FeatureFlags bit order (reg 0x39 bits 0..2). */
enum sw_feature_kind {
	SW_FEATURE_PRESSURE,	/* kPa */
	SW_FEATURE_HUMIDITY,	/* % relative humidity */
	SW_FEATURE_TEMP,	/* degrees C */
	SW_NFEATURES,
};

struct sw_feature {
	enum sw_feature_kind kind;
	/* false: the value could not be read (EBUSY while a buffer streams) */
	bool have_value;
	double value;		/* in the kind's unit above */
	int rate_hz;
};

/* What the hub runs and drives besides the fusion: status shows it. */
struct sw_hub_info {
	enum sw_fw_source fw_source;
	char fw_why[160];	/* SW_FW_UNKNOWN: why, else "" */
	unsigned int nfeatures;	/* 0: the board has none */
	struct sw_feature features[SW_NFEATURES];	/* in slot order */
};

/* Little-endian helpers: the file format and the bus are both LE. */
static inline void sw_put_le16(uint8_t *p, uint16_t v)
{
	p[0] = v & 0xff;
	p[1] = v >> 8;
}

static inline void sw_put_le32(uint8_t *p, uint32_t v)
{
	sw_put_le16(p, v & 0xffff);
	sw_put_le16(p + 2, v >> 16);
}

static inline void sw_put_le64(uint8_t *p, uint64_t v)
{
	sw_put_le32(p, v & 0xffffffffu);
	sw_put_le32(p + 4, v >> 32);
}

static inline uint16_t sw_get_le16(const uint8_t *p)
{
	return (uint16_t)(p[0] | p[1] << 8);
}

static inline uint32_t sw_get_le32(const uint8_t *p)
{
	return sw_get_le16(p) | (uint32_t)sw_get_le16(p + 2) << 16;
}

static inline uint64_t sw_get_le64(const uint8_t *p)
{
	return sw_get_le32(p) | (uint64_t)sw_get_le32(p + 4) << 32;
}

/* Parameter n (1-based) of a blob as a host float, independent of host order. */
float sw_blob_param(const uint8_t *blob, int n);
void sw_blob_set_param(uint8_t *blob, int n, float v);

/* Float g <-> accelerometer LSB with the seed's 0.000488 g/LSB. */
float sw_lsb_to_g(int lsb);
int sw_g_to_lsb(float g);

#endif
