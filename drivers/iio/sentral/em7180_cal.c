// SPDX-License-Identifier: GPL-2.0-only
/*
 * PNI SENtral / EM7180: the state of the calibration
 *
 * Every firmware reports it in AlgorithmStatus (0x38), part of the chip's
 * fixed host interface (EM's em718x_registers.h; the USFS host libraries
 * judge calibration by its CalibStable bit). Some firmware adds a status
 * (0x43), update flags (0x44, clear on read) and a score (0x4D-0x4E) in
 * general-purpose registers, which other firmware uses for other data: the
 * USFS utilities read linear acceleration from 0x3F-0x44 (Greg Tomasch's
 * EM7180_SENtral_Calibration). So those are reported only while they read
 * in that layout, and agree with AlgorithmStatus.
 *
 * One read serves every attribute read for EM7180_CAL_MAX_AGE_MS, as hwmon
 * drivers cache readings. The chip raises no interrupt when they change.
 */

#include <linux/bitfield.h>
#include <linux/bitops.h>
#include <linux/device.h>
#include <linux/jiffies.h>
#include <linux/lockdep.h>
#include <linux/math.h>
#include <linux/mutex.h>
#include <linux/regmap.h>
#include <linux/string.h>
#include <linux/sysfs.h>

#include <linux/iio/iio.h>
#include <linux/iio/sysfs.h>

#include <kunit/visibility.h>

#include "em7180_core.h"
#include "em7180_compat.h"

#define EM7180_CAL_MAX_AGE_MS	500

#define EM7180_ALGO_STATUS_STABLE	BIT(3)
#define EM7180_ALGO_STATUS_TRANSIENT	BIT(4)
#define EM7180_ALGO_STATUS_UNRELIABLE	BIT(5)
/* Undefined: a bus that reads all ones sets them */
#define EM7180_ALGO_STATUS_RESERVED	GENMASK(7, 6)

#define EM7180_CAL_STATUS_MASK		GENMASK(1, 0)
#define EM7180_CAL_STATUS_COMPLETE	3
#define EM7180_CAL_TRANSIENT_MASK	GENMASK(3, 2)
#define EM7180_CAL_FLAGS_MASK		(EM7180_CAL_FLAG_MAG_UPDATE | \
					 EM7180_CAL_FLAG_GBIAS_UPDATE)
/* A score is a fit error, 0 % or more: raw 0x8000 and up */
#define EM7180_CAL_SCORE_ZERO		0x8000

/* Registers 0x37..0x4E: SentralStatus, AlgorithmStatus, then 0x43.. */
#define EM7180_CAL_READ_LEN	(EM7180_REG_CAL_SCORE + 2 - EM7180_REG_SENTRAL_STATUS)
#define EM7180_CAL_OFF		(EM7180_REG_CAL_STATUS - EM7180_REG_SENTRAL_STATUS)

/**
 * em7180_score_milli() - the calibration score in thousandths of a percent
 * @raw: CalScore register pair (0x4D | 0x4E << 8)
 *
 * The score is (raw - 32768) / 32768 * 100 %.
 *
 * Return: the score in 0.001 %, rounded to nearest, -100000 to 99997.
 */
int em7180_score_milli(u16 raw)
{
	/* 100000 / 32768 = 3125 / 1024; |product| < 2^27 */
	return DIV_ROUND_CLOSEST(((int)raw - 32768) * 3125, 1024);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_score_milli);

/**
 * em7180_cal_level() - the calibration state as bno055 grades it
 * @algo: AlgorithmStatus
 *
 * 0 while the fusion is halted (no calibration runs, bno055's "not
 * enabled"), then from worst to best: 1 unreliable sensor data, 2 not
 * stable yet, 3 stable but in a magnetic transient, 4 stable.
 *
 * Return: 0 to 4.
 */
int em7180_cal_level(u8 algo)
{
	if (algo & EM7180_ALGO_STATUS_HALTED)
		return 0;
	if (algo & EM7180_ALGO_STATUS_UNRELIABLE)
		return 1;
	if (!(algo & EM7180_ALGO_STATUS_STABLE))
		return 2;
	return algo & EM7180_ALGO_STATUS_TRANSIENT ? 3 : 4;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_cal_level);

/**
 * em7180_cal_layout() - do 0x43..0x4E read as the calibration registers?
 * @algo: AlgorithmStatus of the same read
 * @regs: registers 0x43..0x4E
 * @agree: also require that status and transient agree with @algo
 *
 * The layout defines bits 3:0 of 0x43 and 1:0 of 0x44, and a score of 0 % or
 * more; complete means stable, and both registers carry MagTransient. All
 * zero is nothing yet, not a score.
 *
 * Return: true when they do.
 */
bool em7180_cal_layout(u8 algo, const u8 *regs, bool agree)
{
	u8 status = regs[0];
	u8 flags = regs[EM7180_REG_CAL_FLAGS - EM7180_REG_CAL_STATUS];
	u16 score = get_unaligned_le16(&regs[EM7180_REG_CAL_SCORE - EM7180_REG_CAL_STATUS]);

	if (!memchr_inv(regs, 0, EM7180_CAL_BLOCK_LEN) ||
	    status & ~(EM7180_CAL_STATUS_MASK | EM7180_CAL_TRANSIENT_MASK) ||
	    flags & ~EM7180_CAL_FLAGS_MASK || score < EM7180_CAL_SCORE_ZERO)
		return false;
	if (!agree)
		return true;

	return !(status & EM7180_CAL_TRANSIENT_MASK) ==
	       !(algo & EM7180_ALGO_STATUS_TRANSIENT) &&
	       (FIELD_GET(EM7180_CAL_STATUS_MASK, status) == EM7180_CAL_STATUS_COMPLETE) ==
	       !!(algo & EM7180_ALGO_STATUS_STABLE);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_cal_layout);

/**
 * em7180_cal_update() - fold one read of registers 0x43..0x4E in
 * @data: driver state, with @data->lock held
 * @regs: the registers, as read in one burst
 *
 * The update flags latch until the next warm start transfer. A read that
 * the layout cannot hold ends their reporting for this firmware.
 */
void em7180_cal_update(struct em7180_data *data, const u8 *regs)
{
	lockdep_assert_held(&data->lock);

	/* Nothing computed yet, as right after a reset */
	if (!data->appnote || !memchr_inv(regs, 0, EM7180_CAL_BLOCK_LEN))
		return;
	if (!em7180_cal_layout(0, regs, false)) {
		data->appnote = false;
		dev_warn(data->dev,
			 "0x43-0x4E read %*ph: not the calibration score, no longer reported\n",
			 EM7180_CAL_BLOCK_LEN, regs);
		return;
	}
	data->cal.score = get_unaligned_le16(&regs[EM7180_REG_CAL_SCORE - EM7180_REG_CAL_STATUS]);
	data->cal.flags |= regs[EM7180_REG_CAL_FLAGS - EM7180_REG_CAL_STATUS];
}
EXPORT_SYMBOL_IF_KUNIT(em7180_cal_update);

/*
 * SentralStatus and AlgorithmStatus, with @block 0x43..0x4E too, in one
 * burst unless the register pointer may stop at 0x3A (@split, or found so).
 * SentralStatus because a chip that reset itself without an interrupt
 * waits in standby.
 */
static int em7180_cal_read(struct em7180_data *data, u8 *regs, bool block, bool split)
{
	int ret;

	if (!block || split || data->ptr_stops) {
		ret = regmap_bulk_read(data->regmap, EM7180_REG_SENTRAL_STATUS, regs, 2);
		if (ret || !block)
			return ret;
		return regmap_bulk_read(data->regmap, EM7180_REG_CAL_STATUS, &regs[EM7180_CAL_OFF],
					EM7180_CAL_BLOCK_LEN);
	}

	return regmap_bulk_read(data->regmap, EM7180_REG_SENTRAL_STATUS, regs, EM7180_CAL_READ_LEN);
}

/**
 * em7180_cal_detect() - does the firmware running have the calibration registers?
 * @data: driver state, with @data->lock held, the chip running
 *
 * Asked at probe, before any parameter transfer has shown how the register
 * pointer moves, and when a power loss brought other firmware.
 *
 * Return: 0 or the bus error (then they are not reported).
 */
int em7180_cal_detect(struct em7180_data *data)
{
	u8 regs[EM7180_CAL_READ_LEN];
	int ret;

	lockdep_assert_held(&data->lock);

	data->appnote = false;
	ret = em7180_cal_read(data, regs, true, true);
	if (ret)
		return ret;

	data->appnote = em7180_cal_layout(regs[1], &regs[EM7180_CAL_OFF], true);
	em7180_cal_update(data, &regs[EM7180_CAL_OFF]);
	return 0;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_cal_detect);

static int em7180_cal_refresh(struct em7180_data *data)
{
	u8 regs[EM7180_CAL_READ_LEN];
	int ret;

	lockdep_assert_held(&data->lock);

	if (data->cal.valid &&
	    time_before(jiffies, data->cal.read_at + msecs_to_jiffies(EM7180_CAL_MAX_AGE_MS)))
		return 0;

	data->cal.valid = false;
	ret = em7180_cal_read(data, regs, data->appnote, false);
	if (ret)
		return ret;

	em7180_status_seen(data, regs[0]); /* upstream: health */
	/* A glitch is not a state: not kept either */
	if (regs[1] & EM7180_ALGO_STATUS_RESERVED)
		return -EIO;

	data->cal.algo = regs[1];
	em7180_cal_update(data, &regs[EM7180_CAL_OFF]);
	data->cal.valid = true;
	data->cal.read_at = jiffies;
	return 0;
}

/**
 * em7180_cal_saved() - the warm start was read or written: no update since
 * @data: driver state, with @data->lock held
 *
 * The flags the transfer read belong to the state it saved or replaced; a
 * restore changes the state at once, so the next read goes to the chip.
 */
void em7180_cal_saved(struct em7180_data *data)
{
	lockdep_assert_held(&data->lock);
	data->cal.flags = 0;
	data->cal.valid = false;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_cal_saved);

ssize_t em7180_cal_show(struct device *dev, struct device_attribute *attr, char *buf)
{
	struct em7180_data *data = iio_priv(dev_to_iio_dev(dev));
	unsigned int what = to_iio_dev_attr(attr)->address;
	struct em7180_cal cal;
	int ret, milli;

	scoped_guard(em7180, data) {
		ret = em7180_cal_refresh(data);
		if (!ret && what != EM7180_CAL_ATTR_LEVEL && !data->appnote)
			ret = -ENODATA;
		cal = data->cal;
	}
	if (ret)
		return ret;

	switch (what) {
	case EM7180_CAL_ATTR_LEVEL:
		return sysfs_emit(buf, "%d\n", em7180_cal_level(cal.algo));
	case EM7180_CAL_ATTR_SCORE:
		milli = em7180_score_milli(cal.score);
		return sysfs_emit(buf, "%s%d.%03d\n", milli < 0 ? "-" : "",
				  abs(milli) / 1000, abs(milli) % 1000);
	case EM7180_CAL_ATTR_MAG_UPDATE:
		return sysfs_emit(buf, "%d\n", !!(cal.flags & EM7180_CAL_FLAG_MAG_UPDATE));
	default:
		return sysfs_emit(buf, "%d\n", !!(cal.flags & EM7180_CAL_FLAG_GBIAS_UPDATE));
	}
}
