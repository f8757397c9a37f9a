// SPDX-License-Identifier: GPL-2.0-only
/*
 * PNI SENtral / EM7180: calibration state
 *
 * Registers 0x43 (CalStatus, MagTransient), 0x44 (update flags) and
 * 0x4D/0x4E (score) are read in one 12-byte burst. The chip raises no
 * interrupt when they change: userspace polls the attributes. A burst
 * serves every attribute read within EM7180_CAL_MAX_AGE_MS of it, as hwmon
 * drivers cache their readings, so that a reader of all five costs one bus
 * transaction and sees status and score from the same read.
 *
 * The two flags of 0x44 latch an update each and clear when read. The
 * driver keeps them set until the warm start is next read or written: a
 * flag then says "the chip learned something since the calibration was
 * last saved or restored", whoever read the registers and how often.
 *
 * Other firmware builds use these general-purpose registers for other
 * things (Sony's packs a status and score of its own into 0x4D): the
 * attributes exist only for firmware known to follow the application
 * note's layout (struct em7180_data, @cal_fw), and read ENODATA while the
 * chip runs another after a power loss.
 */

#include <linux/bitfield.h>
#include <linux/bits.h>
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
 * em7180_cal_update() - fold one read of the calibration block into @cal
 * @cal: the state last read
 * @regs: registers 0x43..0x4E as read in one burst
 */
void em7180_cal_update(struct em7180_cal *cal, const u8 *regs)
{
	u8 flags = regs[EM7180_REG_CAL_FLAGS - EM7180_REG_CAL_STATUS];

	cal->status = regs[0];
	cal->score = get_unaligned_le16(&regs[EM7180_REG_CAL_SCORE -
					      EM7180_REG_CAL_STATUS]);
	cal->flags |= flags & (EM7180_CAL_FLAG_MAG_UPDATE |
			       EM7180_CAL_FLAG_GBIAS_UPDATE);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_cal_update);

/*
 * Read the block unless the last read is younger than EM7180_CAL_MAX_AGE_MS;
 * a failed read leaves nothing to serve later.
 *
 * The same read starts at SentralStatus: a chip that reset itself waits
 * in standby for its host, and a board without an INT line, or firmware
 * that raises none for the reset, would never tell. On a chip whose
 * register pointer stops at 0x3A, SentralStatus is a read of its own.
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
 * The transfer took in the flags the chip had latched (em7180_param_ack()):
 * those updates belong to the state it saved or replaced. A restore
 * changes status and score at once: the next attribute read reads the
 * chip again.
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
	struct em7180_cal cal;
	int ret, milli;

	scoped_guard(mutex, &data->lock) {
		ret = data->cal_reported ? em7180_cal_refresh(data) : -ENODATA;
		cal = data->cal;
	}
	if (ret)
		return ret;

	switch (to_iio_dev_attr(attr)->address) {
	case EM7180_CAL_ATTR_STATUS:
		return sysfs_emit(buf, "%lu\n",
				  FIELD_GET(EM7180_CAL_STATUS_MASK, cal.status));
	case EM7180_CAL_ATTR_SCORE:
		milli = em7180_score_milli(cal.score);
		return sysfs_emit(buf, "%s%d.%03d\n", milli < 0 ? "-" : "",
				  abs(milli) / 1000, abs(milli) % 1000);
	case EM7180_CAL_ATTR_TRANSIENT:
		return sysfs_emit(buf, "%lu\n",
				  FIELD_GET(EM7180_CAL_MAG_TRANSIENT_MASK,
					    cal.status));
	case EM7180_CAL_ATTR_GYRO_UPDATE:
		return sysfs_emit(buf, "%d\n",
				  !!(cal.flags & EM7180_CAL_FLAG_GBIAS_UPDATE));
	default:
		return sysfs_emit(buf, "%d\n",
				  !!(cal.flags & EM7180_CAL_FLAG_MAG_UPDATE));
	}
}
