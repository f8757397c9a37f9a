// SPDX-License-Identifier: GPL-2.0-only
/*
 * PNI SENtral / EM7180: calibration status, score and update flags
 *
 * Registers 0x43 (status), 0x44 (update flags, clear on read) and 0x4D-0x4E
 * (score) are read in one burst that serves every attribute read for
 * EM7180_CAL_MAX_AGE_MS, as hwmon drivers cache readings: a reader of all
 * five costs one transaction. The chip raises no interrupt when they change.
 * They exist only for firmware known to keep the calibration there
 * (em7180_firmware.c).
 */

#include <linux/bitops.h>
#include <linux/device.h>
#include <linux/jiffies.h>
#include <linux/math.h>
#include <linux/mutex.h>
#include <linux/regmap.h>
#include <linux/sysfs.h>

#include <linux/iio/iio.h>
#include <linux/iio/sysfs.h>

#include <kunit/visibility.h>

#include "em7180_core.h"
#include "em7180_compat.h"

#define EM7180_CAL_MAX_AGE_MS	500

/**
 * em7180_score_milli() - the calibration score in thousandths of a percent
 * @raw: CalScore register pair (0x4D | 0x4E << 8)
 *
 * The application note defines the score as (raw - 32768) / 32768 * 100 %.
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
 * em7180_cal_update() - fold one read of the calibration block into @cal
 * @cal: the state last read
 * @regs: registers 0x43..0x4E as read in one burst
 */
void em7180_cal_update(struct em7180_cal *cal, const u8 *regs)
{
	cal->status = regs[0];
	cal->score = get_unaligned_le16(&regs[EM7180_REG_CAL_SCORE -
					      EM7180_REG_CAL_STATUS]);
	cal->flags |= regs[EM7180_REG_CAL_FLAGS - EM7180_REG_CAL_STATUS] &
		      (EM7180_CAL_FLAG_MAG_UPDATE | EM7180_CAL_FLAG_GBIAS_UPDATE);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_cal_update);

/*
 * The read starts at SentralStatus: a chip that reset itself without an
 * interrupt waits in standby for its host. A register pointer that stops
 * at 0x3A needs a read of its own for it.
 */
static int em7180_cal_refresh(struct em7180_data *data)
{
	u8 regs[EM7180_REG_CAL_SCORE + 2 - EM7180_REG_SENTRAL_STATUS];
	u8 *cal = &regs[EM7180_REG_CAL_STATUS - EM7180_REG_SENTRAL_STATUS];
	int ret;

	lockdep_assert_held(&data->lock);

	if (data->cal.valid &&
	    time_before(jiffies, data->cal.read_at +
			msecs_to_jiffies(EM7180_CAL_MAX_AGE_MS)))
		return 0;

	if (data->param_single)
		ret = regmap_bulk_read(data->regmap, EM7180_REG_SENTRAL_STATUS,
				       regs, 1) ?:
		      regmap_bulk_read(data->regmap, EM7180_REG_CAL_STATUS, cal,
				       EM7180_CAL_BLOCK_LEN);
	else
		ret = regmap_bulk_read(data->regmap, EM7180_REG_SENTRAL_STATUS,
				       regs, sizeof(regs));
	data->cal.valid = !ret;
	if (ret)
		return ret;

	em7180_status_seen(data, regs[0]);
	em7180_cal_update(&data->cal, cal);
	data->cal.read_at = jiffies;
	return 0;
}

/**
 * em7180_cal_saved() - the warm start was read or written: no update since
 * @data: driver state, with @data->lock held
 *
 * The flags the transfer read belong to the state it saved or replaced; a
 * restore changes status and score at once, so the next read goes to the chip.
 */
void em7180_cal_saved(struct em7180_data *data)
{
	lockdep_assert_held(&data->lock);
	data->cal.flags = 0;
	data->cal.valid = false;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_cal_saved);

ssize_t em7180_cal_show(struct device *dev, struct device_attribute *attr,
			char *buf)
{
	struct em7180_data *data = iio_priv(dev_to_iio_dev(dev));
	unsigned long mask = to_iio_dev_attr(attr)->address;
	struct em7180_cal cal;
	int ret, milli;

	scoped_guard(mutex, &data->lock) {
		ret = data->cal_reported ? em7180_cal_refresh(data) : -ENODATA;
		cal = data->cal;
	}
	if (ret)
		return ret;

	if (mask)
		return sysfs_emit(buf, "%lu\n",
				  ((cal.flags << 8 | cal.status) & mask) >> __ffs(mask));

	milli = em7180_score_milli(cal.score);
	return sysfs_emit(buf, "%s%d.%03d\n", milli < 0 ? "-" : "",
			  abs(milli) / 1000, abs(milli) % 1000);
}
