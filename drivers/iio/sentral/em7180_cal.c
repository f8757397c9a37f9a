// SPDX-License-Identifier: GPL-2.0-only
/*
 * PNI SENtral / EM7180: calibration state and its change reports
 *
 * Registers 0x43 (CalStatus, MagTransient), 0x44 (update flags) and
 * 0x4D/0x4E (score) are read together in one 12-byte burst. The two flags
 * of 0x44 latch an update each and the firmware may clear them when they
 * are read, so they are folded into counters that only grow: whoever
 * triggers a read, every reader sees every update through the counters.
 *
 * The chip has no interrupt for calibration events, so the driver reads
 * the block only when asked: at each read of a calibration attribute, and
 * while userspace has the magnetometer change event enabled, from a work
 * item whose period starts at EM7180_CAL_PERIOD_MIN_MS after a change and
 * doubles up to EM7180_CAL_PERIOD_MAX_MS while nothing changes. Each read
 * that finds a change notifies pollers of the attributes that changed and
 * pushes the change event. Nothing reads the chip when no one asks.
 */

#include <linux/bitfield.h>
#include <linux/bits.h>
#include <linux/device.h>
#include <linux/kernel.h>
#include <linux/minmax.h>
#include <linux/mutex.h>
#include <linux/regmap.h>
#include <linux/sysfs.h>
#include <linux/workqueue.h>

#include <linux/iio/events.h>
#include <linux/iio/iio.h>
#include <linux/iio/sysfs.h>

#include <kunit/visibility.h>

#include "em7180.h"
#include "em7180_compat.h"

#define EM7180_CAL_BLOCK_LEN	(EM7180_REG_CAL_SCORE + 2 - EM7180_REG_CAL_STATUS)

/* What a change of the magnetic calibration is reported for */
#define EM7180_CAL_CH_MAGN_EVENT	(EM7180_CAL_CH_STATUS | \
					 EM7180_CAL_CH_SCORE | \
					 EM7180_CAL_CH_MAG_UPDATE)

/**
 * em7180_cal_update() - fold one read of the calibration block into @cal
 * @cal: the state last read
 * @regs: registers 0x43..0x4E as read in one burst
 *
 * Return: the EM7180_CAL_CH_* bits of what changed.
 */
unsigned int em7180_cal_update(struct em7180_cal *cal, const u8 *regs)
{
	u8 status = regs[0];
	u8 flags = regs[EM7180_REG_CAL_FLAGS - EM7180_REG_CAL_STATUS];
	u16 score = get_unaligned_le16(&regs[EM7180_REG_CAL_SCORE -
					     EM7180_REG_CAL_STATUS]);
	unsigned int changed = 0;

	if ((status ^ cal->status) & EM7180_CAL_STATUS_MASK)
		changed |= EM7180_CAL_CH_STATUS;
	if ((status ^ cal->status) & EM7180_CAL_MAG_TRANSIENT_MASK)
		changed |= EM7180_CAL_CH_TRANSIENT;
	if (score != cal->score)
		changed |= EM7180_CAL_CH_SCORE;
	if (flags & EM7180_CAL_FLAG_GBIAS_UPDATE) {
		cal->gyro_updates++;
		changed |= EM7180_CAL_CH_GYRO_UPDATE;
	}
	if (flags & EM7180_CAL_FLAG_MAG_UPDATE) {
		cal->mag_updates++;
		changed |= EM7180_CAL_CH_MAG_UPDATE;
	}
	cal->status = status;
	cal->score = score;

	return changed;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_cal_update);

/**
 * em7180_cal_next_period() - period of the change check after a check
 * @period_ms: the period that led to this check
 * @changed: EM7180_CAL_CH_* bits the check found
 *
 * A change of the magnetic calibration brings the period down to its
 * minimum; otherwise it doubles up to the maximum. Gyroscope bias updates,
 * which come every few seconds while the device is still, do not count:
 * they would keep a still device at the fastest rate.
 *
 * Return: the next period in ms.
 */
unsigned int em7180_cal_next_period(unsigned int period_ms,
				    unsigned int changed)
{
	if (changed & (EM7180_CAL_CH_MAGN_EVENT | EM7180_CAL_CH_TRANSIENT))
		return EM7180_CAL_PERIOD_MIN_MS;

	return clamp(period_ms * 2, EM7180_CAL_PERIOD_MIN_MS,
		     EM7180_CAL_PERIOD_MAX_MS);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_cal_next_period);

/* One burst read of the block; @changed gets what differs from the last */
static int em7180_cal_refresh(struct em7180_data *data, unsigned int *changed)
{
	u8 regs[EM7180_CAL_BLOCK_LEN];
	int ret;

	lockdep_assert_held(&data->lock);

	ret = regmap_bulk_read(data->regmap, EM7180_REG_CAL_STATUS, regs,
			       sizeof(regs));
	if (ret)
		return ret;

	*changed = em7180_cal_update(&data->cal, regs);
	return 0;
}

static void em7180_cal_notify(struct iio_dev *indio_dev, unsigned int changed)
{
	struct em7180_data *data = iio_priv(indio_dev);
	struct kobject *kobj = &indio_dev->dev.kobj;

	if (changed & EM7180_CAL_CH_STATUS)
		sysfs_notify(kobj, NULL, "in_magn_calibration_auto_status");
	if (changed & EM7180_CAL_CH_SCORE)
		sysfs_notify(kobj, NULL, "in_magn_calibration_score");
	if (changed & EM7180_CAL_CH_TRANSIENT)
		sysfs_notify(kobj, NULL, "in_magn_transient");
	if (changed & EM7180_CAL_CH_GYRO_UPDATE)
		sysfs_notify(kobj, NULL, "in_anglvel_calibration_update_count");
	if (changed & EM7180_CAL_CH_MAG_UPDATE)
		sysfs_notify(kobj, NULL, "in_magn_calibration_update_count");

	if ((changed & EM7180_CAL_CH_MAGN_EVENT) && READ_ONCE(data->cal_watch))
		iio_push_event(indio_dev,
			       IIO_UNMOD_EVENT_CODE(IIO_MAGN, 0,
						    IIO_EV_TYPE_CHANGE,
						    IIO_EV_DIR_NONE),
			       iio_get_time_ns(indio_dev));
}

static void em7180_cal_work(struct work_struct *work)
{
	struct em7180_data *data = container_of(to_delayed_work(work),
						struct em7180_data, cal_work);
	struct iio_dev *indio_dev = data->cal_indio_dev;
	unsigned int changed = 0;
	int ret;

	mutex_lock(&data->lock);
	ret = em7180_cal_refresh(data, &changed);
	/* After a bus error, look again as soon as after a change */
	data->cal_period_ms = ret ? EM7180_CAL_PERIOD_MIN_MS :
			      em7180_cal_next_period(data->cal_period_ms,
						     changed);
	if (data->cal_watch)
		queue_delayed_work(system_freezable_wq, &data->cal_work,
				   msecs_to_jiffies(data->cal_period_ms));
	mutex_unlock(&data->lock);

	if (!ret)
		em7180_cal_notify(indio_dev, changed);
}

/*
 * The calibration attributes: each value comes from a fresh read of the
 * chip, which also updates the counters every other reader sees.
 */
ssize_t em7180_cal_show(struct device *dev, struct device_attribute *attr,
			char *buf)
{
	struct iio_dev *indio_dev = dev_to_iio_dev(dev);
	struct em7180_data *data = iio_priv(indio_dev);
	unsigned int changed = 0;
	struct em7180_cal cal;
	int ret, milli;

	mutex_lock(&data->lock);
	ret = em7180_cal_refresh(data, &changed);
	cal = data->cal;
	mutex_unlock(&data->lock);
	if (ret)
		return ret;

	em7180_cal_notify(indio_dev, changed);

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
	case EM7180_CAL_ATTR_GYRO_UPDATES:
		return sysfs_emit(buf, "%llu\n", cal.gyro_updates);
	default:
		return sysfs_emit(buf, "%llu\n", cal.mag_updates);
	}
}

const struct iio_event_spec em7180_magn_event = {
	.type = IIO_EV_TYPE_CHANGE,
	.dir = IIO_EV_DIR_NONE,
	.mask_shared_by_type = BIT(IIO_EV_INFO_ENABLE),
};

int em7180_read_event_config(struct iio_dev *indio_dev,
			     const struct iio_chan_spec *chan,
			     enum iio_event_type type,
			     enum iio_event_direction dir)
{
	struct em7180_data *data = iio_priv(indio_dev);

	return READ_ONCE(data->cal_watch);
}

/*
 * Enabling starts the change checks at once, at the fastest period:
 * whoever enables them wants to hear soon.
 */
int em7180_write_event_config(struct iio_dev *indio_dev,
			      const struct iio_chan_spec *chan,
			      enum iio_event_type type,
			      enum iio_event_direction dir, int state)
{
	struct em7180_data *data = iio_priv(indio_dev);

	mutex_lock(&data->lock);
	WRITE_ONCE(data->cal_watch, !!state);
	if (state) {
		data->cal_period_ms = EM7180_CAL_PERIOD_MIN_MS;
		mod_delayed_work(system_freezable_wq, &data->cal_work, 0);
	}
	mutex_unlock(&data->lock);

	/* The work requeues itself only while enabled */
	if (!state)
		cancel_delayed_work_sync(&data->cal_work);

	return 0;
}

static void em7180_cal_stop(void *arg)
{
	struct em7180_data *data = arg;

	WRITE_ONCE(data->cal_watch, false);
	cancel_delayed_work_sync(&data->cal_work);
}

/**
 * em7180_cal_init() - set up the change checks of a device being probed
 * @indio_dev: the IIO device
 *
 * Return: 0 or a negative error code.
 */
int em7180_cal_init(struct iio_dev *indio_dev)
{
	struct em7180_data *data = iio_priv(indio_dev);

	data->cal_indio_dev = indio_dev;
	data->cal_period_ms = EM7180_CAL_PERIOD_MIN_MS;
	INIT_DELAYED_WORK(&data->cal_work, em7180_cal_work);

	return devm_add_action_or_reset(data->dev, em7180_cal_stop, data);
}
