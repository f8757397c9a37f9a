// SPDX-License-Identifier: GPL-2.0-only
/*
 * PNI SENtral / EM7180: resets of the chip's own and error reports
 *
 * A reset (a brown-out, the watchdog) loses the configuration and the
 * calibration, and may raise no interrupt: the reset clears EnableEvents.
 * The chip then waits in standby, which any SentralStatus read shows: one
 * is taken while a buffer runs without scans, and before a raw read after
 * a long idle. Recovery runs from a work item, as Sony's driver does.
 */

#include <linux/cleanup.h>
#include <linux/debugfs.h>
#include <linux/device.h>
#include <linux/devm-helpers.h>
#include <linux/jiffies.h>
#include <linux/lockdep.h>
#include <linux/mutex.h>
#include <linux/regmap.h>
#include <linux/seq_file.h>
#include <linux/workqueue.h>

#include <linux/iio/iio.h>

#include <kunit/visibility.h>

#include "em7180_compat.h"
#include "em7180_core.h"

#define EM7180_REG_SENSOR_STATUS	0x36

/* 50 ms coalesce a burst of resets (Sony's driver); then one a second */
#define EM7180_RECOVER_DELAY_MS		50
#define EM7180_RECOVER_INTERVAL_MS	1000
#define EM7180_WATCH_MS			1000

/* Rate-limited, out of the interrupt thread, which other events need */
void em7180_recover_schedule(struct em7180_data *data)
{
	unsigned long next = data->recovered_at +
			     msecs_to_jiffies(EM7180_RECOVER_INTERVAL_MS);
	unsigned long delay = msecs_to_jiffies(EM7180_RECOVER_DELAY_MS);

	if (data->resets && time_before(jiffies + delay, next))
		delay = next - jiffies;
	schedule_delayed_work(&data->recover_work, delay);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_recover_schedule);

/* SentralStatus was just read: a chip in standby has reset */
void em7180_status_seen(struct em7180_data *data, unsigned int status)
{
	lockdep_assert_held(&data->lock);

	data->status_at = jiffies;
	if (status & EM7180_SENTRAL_STANDBY)
		em7180_recover_schedule(data);
}

/* Before a raw read: data registers keep their values across a reset */
void em7180_check_status(struct em7180_data *data)
{
	unsigned int status;

	lockdep_assert_held(&data->lock);

	if (time_before(jiffies, data->status_at + msecs_to_jiffies(EM7180_WATCH_MS)))
		return;
	if (!regmap_read(data->regmap, EM7180_REG_SENTRAL_STATUS, &status))
		em7180_status_seen(data, status);
}

/* A reset, or a transfer that could not be ended: as after a power loss */
int em7180_chip_recover(struct em7180_data *data)
{
	u16 rom = data->rom_version, ram = data->ram_version;
	bool lost = true;
	int ret;

	lockdep_assert_held(&data->lock);

	data->resets++;
	dev_warn(data->dev,
		 "the chip reset itself (%u since probe); restoring its configuration and calibration\n",
		 data->resets);
	ret = em7180_chip_restore(data, &lost, &rom, &ram);
	data->recovered_at = jiffies;
	data->recover_ret = ret;
	if (ret)
		dev_err(data->dev, "cannot restore the chip after its reset: %d\n", ret);

	return ret;
}

static void em7180_recover_work(struct work_struct *work)
{
	struct em7180_data *data = container_of(to_delayed_work(work), struct em7180_data,
						recover_work);
	int ret;

	guard(em7180)(data);
	if (data->xfer_stuck) {
		data->xfer_stuck = false;
		ret = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, 0);
		if (!ret)
			return;
		dev_warn(data->dev, "cannot end a parameter transfer (%d): resetting the chip\n",
			 ret);
		ret = regmap_write(data->regmap, EM7180_REG_RESET_REQ, EM7180_RESET_REQ_RESET);
		if (ret) {
			dev_err(data->dev, "cannot reset the chip: %d\n", ret);
			return;
		}
	}
	em7180_chip_recover(data);
}

/*
 * A pending recovery runs now, so that the chip is left running; then none
 * runs any more: a restore whose transfer cannot be ended queues another
 * (em7180_param_end()), which would otherwise run after the device is freed
 * or put to sleep. Disabled, the work item refuses that queueing.
 */
void em7180_recover_stop(struct em7180_data *data)
{
	flush_delayed_work(&data->recover_work);
	disable_delayed_work_sync(&data->recover_work);
}

/* After system sleep, before the interrupt and the chip's restore */
void em7180_recover_start(struct em7180_data *data)
{
	enable_delayed_work(&data->recover_work);
}

static void em7180_recover_teardown(void *arg)
{
	em7180_recover_stop(arg);
}

static void em7180_watch_schedule(struct em7180_data *data)
{
	/* Freezable: no check of a chip that system sleep put in standby */
	queue_delayed_work(system_freezable_wq, &data->watch_work,
			   msecs_to_jiffies(EM7180_WATCH_MS));
}

/* A second without a scan of the chip's own trigger, or any other trigger */
static void em7180_watch_work(struct work_struct *work)
{
	struct em7180_data *data = container_of(to_delayed_work(work), struct em7180_data,
						watch_work);
	s64 ts = READ_ONCE(data->scan_ts);
	unsigned int status;

	if (!READ_ONCE(data->pace_event) || ts == data->watch_ts) {
		guard(em7180)(data);
		if (!regmap_read(data->regmap, EM7180_REG_SENTRAL_STATUS, &status))
			em7180_status_seen(data, status);
	}
	data->watch_ts = ts;
	em7180_watch_schedule(data);
}

int em7180_watch_start(struct iio_dev *indio_dev)
{
	struct em7180_data *data = iio_priv(indio_dev);

	data->watch_ts = READ_ONCE(data->scan_ts);
	em7180_watch_schedule(data);
	return 0;
}

int em7180_watch_stop(struct iio_dev *indio_dev)
{
	struct em7180_data *data = iio_priv(indio_dev);

	cancel_delayed_work_sync(&data->watch_work);
	return 0;
}

/**
 * em7180_health_init() - set up recovery and the watch of a running buffer
 * @data: driver state
 *
 * Called before the first transfer that can ask for a recovery. On unbind
 * the teardown runs in reverse: after the IIO device and the interrupt are
 * gone, which ask for recoveries, the watch stops (it asks for them too),
 * then recovery (em7180_recover_stop()).
 *
 * Return: 0 or a negative error code.
 */
int em7180_health_init(struct em7180_data *data)
{
	int ret;

	INIT_DELAYED_WORK(&data->recover_work, em7180_recover_work);
	ret = devm_add_action_or_reset(data->dev, em7180_recover_teardown, data);
	if (ret)
		return ret;

	return devm_delayed_work_autocancel(data->dev, &data->watch_work, em7180_watch_work);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_health_init);

/* What recovery did, for a user who wonders why the data paused */
static int em7180_recovery_show(struct seq_file *m, void *unused)
{
	struct em7180_data *data = m->private;

	guard(em7180)(data);
	seq_printf(m, "resets %u\n", data->resets);
	seq_printf(m, "pending %d\n", delayed_work_pending(&data->recover_work));
	if (data->resets)
		seq_printf(m, "last %u ms ago, result %d\n",
			   jiffies_to_msecs(jiffies - data->recovered_at), data->recover_ret);
	return 0;
}
DEFINE_SHOW_ATTRIBUTE(em7180_recovery);

/* The chip and firmware running, which a recovery may have changed */
static int em7180_firmware_version_show(struct seq_file *m, void *unused)
{
	char id[EM7180_ID_LINE_LEN];

	scoped_guard(em7180, m->private)
		em7180_id_line(m->private, id, sizeof(id));
	seq_printf(m, "%s\n", id);
	return 0;
}
DEFINE_SHOW_ATTRIBUTE(em7180_firmware_version);

void em7180_health_debugfs(struct iio_dev *indio_dev)
{
	struct dentry *dir = iio_get_debugfs_dentry(indio_dev);

	debugfs_create_file("recovery", 0400, dir, iio_priv(indio_dev), &em7180_recovery_fops);
	debugfs_create_file("firmware_version", 0400, dir, iio_priv(indio_dev),
			    &em7180_firmware_version_fops);
}

/* ErrorRegister values that the reference hosts decode */
static const char *em7180_error_name(unsigned int err)
{
	switch (err) {
	case 0x11: return "magnetometer rate failure";
	case 0x12: return "accelerometer rate failure";
	case 0x14: return "gyroscope rate failure";
	case 0x21: return "magnetometer initialization failed";
	case 0x22: return "accelerometer initialization failed";
	case 0x24: return "gyroscope initialization failed";
	case 0x30: return "math error";
	case 0x80: return "invalid sample rate";
	default: return "internal error";
	}
}

/* An Error event, said once per new value: a dead sensor raises it often */
void em7180_report_error(struct em7180_data *data)
{
	unsigned int err, sensors;
	int ret;

	lockdep_assert_held(&data->lock);

	ret = regmap_read(data->regmap, EM7180_REG_ERROR, &err);
	if (!ret)
		ret = regmap_read(data->regmap, EM7180_REG_SENSOR_STATUS, &sensors);
	if (ret) {
		dev_err_ratelimited(data->dev, "chip error, error registers unreadable: %d\n", ret);
		return;
	}
	if (data->last_error == (sensors << 8 | err))
		return;
	data->last_error = sensors << 8 | err;
	if (err || sensors)
		dev_err(data->dev, "chip error 0x%02x (%s), sensor status 0x%02x\n", err,
			err ? em7180_error_name(err) : "none", sensors);
}
