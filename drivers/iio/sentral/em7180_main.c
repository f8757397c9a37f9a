// SPDX-License-Identifier: GPL-2.0-only
/*
 * PNI SENtral / EM Microelectronic EM7180 sensor-fusion hub
 *
 * The hub runs its own fusion algorithm and presents scaled accelerometer,
 * gyroscope and magnetometer data plus an orientation quaternion in a
 * register map (the map of EM's generic host driver, em718x_registers.h,
 * and of the Sony em718x driver). It learns a magnetometer
 * calibration and a gyroscope bias while running; the 35 "warm start"
 * parameters that hold them are exposed as one binary attribute so that
 * userspace can save them and restore them at the next boot.
 */

#include <linux/array_size.h>
#include <linux/bitfield.h>
#include <linux/bitmap.h>
#include <linux/bitops.h>
#include <linux/cleanup.h>
#include <linux/debugfs.h>
#include <linux/delay.h>
#include <linux/device.h>
#include <linux/errno.h>
#include <linux/interrupt.h>
#include <linux/iopoll.h>
#include <linux/jiffies.h>
#include <linux/limits.h>
#include <linux/lockdep.h>
#include <linux/math.h>
#include <linux/minmax.h>
#include <linux/module.h>
#include <linux/mutex.h>
#include <linux/pm.h>
#include <linux/property.h>
#include <linux/regmap.h>
#include <linux/regulator/consumer.h>
#include <linux/seq_file.h>
#include <linux/string.h>
#include <linux/sysfs.h>
#include <linux/types.h>
#include <linux/wait.h>
#include <linux/workqueue.h>

#include <linux/iio/buffer.h>
#include <linux/iio/iio.h>
#include <linux/iio/sysfs.h>
#include <linux/iio/trigger.h>
#include <linux/iio/trigger_consumer.h>
#include <linux/iio/triggered_buffer.h>

#include <kunit/visibility.h>

#include "em7180.h"
#include "em7180_compat.h"
#include "em7180_core.h"

#define EM7180_REG_QTIME		0x10	/* u16 LE, 1/32768 s */
#define EM7180_REG_MX			0x12
#define EM7180_REG_MTIME		0x18
#define EM7180_REG_AX			0x1A
#define EM7180_REG_ATIME		0x20
#define EM7180_REG_GX			0x22
#define EM7180_REG_EVENT_STATUS		0x35	/* clear on read */
#define EM7180_REG_ACTUAL_MAG_RATE	0x45
#define EM7180_REG_ACTUAL_ACCEL_RATE	0x46
#define EM7180_REG_ACTUAL_GYRO_RATE	0x47
#define EM7180_REG_SENSOR_STATUS	0x36
#define EM7180_REG_ERROR		0x50
#define EM7180_REG_PRODUCT_ID		0x90
#define EM7180_REG_RUN_STATUS		0x92
#define EM7180_REG_UPLOAD_ADDR		0x94
#define EM7180_REG_UPLOAD_DATA		0x96
#define EM7180_REG_CRC_HOST		0x97
#define EM7180_REG_RESET_REQ		0x9B
#define EM7180_REG_PASSTHRU_STATUS	0x9E
#define EM7180_REG_SCL_LOW_CYCLES	0x9F
#define EM7180_REG_PASSTHRU_CTRL	0xA0
#define EM7180_REG_MAX			EM7180_REG_PASSTHRU_CTRL

#define EM7180_PRODUCT_ID		0x80
#define EM7180_REVISION_ID		0x02

#define EM7180_EVENT_CPU_RESET		BIT(0)
#define EM7180_EVENT_QUAT		BIT(2)
#define EM7180_EVENT_MAG		BIT(3)
#define EM7180_EVENT_ACCEL		BIT(4)
#define EM7180_EVENT_GYRO		BIT(5)
#define EM7180_EVENT_DATA		GENMASK(5, 2)
/* Always enabled: a reset of the chip's own, and firmware errors */
#define EM7180_EVENT_ALWAYS		(EM7180_EVENT_CPU_RESET | EM7180_EVENT_ERROR)

#define EM7180_SENTRAL_UPLOAD_ERR	BIT(2)
#define EM7180_SENTRAL_NO_EEPROM	BIT(4)

#define EM7180_ALGO_STATUS_HALTED	BIT(0)

#define EM7180_RESET_REQ_RESET		BIT(0)

#define EM7180_WS_FIRST_PARAM		1
#define EM7180_ACCEL_OFFSET_PARAM	27

/*
 * Quaternion components in Q14, stored as s16 x 4 as bno055 does. The IIO
 * scale is printed with nine decimals, so 2^-14 = 0.000061035 is exact to
 * 3 ppm where 2^-30 would print as 0; and a scan element larger than the
 * 8-byte timestamp would make the kernel pad scans to 16 bytes, which
 * libiio 0.24 does not expect.
 */
#define EM7180_QUAT_FRAC_BITS		14

/* EM's generic host driver (em718x_core.c) allows 4 s for the upload */
#define EM7180_UPLOAD_POLL_US		10000
#define EM7180_UPLOAD_TIMEOUT_US	4000000
#define EM7180_STANDBY_POLL_US		1000
#define EM7180_STANDBY_TIMEOUT_US	1000000
#define EM7180_ALIVE_TIMEOUT_US		50000
/*
 * Recovery from a reset of the chip's own waits 50 ms, as Sony's driver
 * does, so that a burst of resets is recovered once; and comes at most
 * once a second, so that a chip that keeps resetting does not hold the
 * bus and the lock.
 */
#define EM7180_RECOVER_DELAY_MS		50
#define EM7180_RECOVER_INTERVAL_MS	1000
/*
 * A reset may raise no interrupt (the reset cleared EnableEvents): while a
 * buffer runs and no scan came for this long, SentralStatus is checked.
 */
#define EM7180_WATCH_MS			1000
/* Power-on reset; then the chip may not acknowledge for a while */
#define EM7180_POWER_ON_US		10000
#define EM7180_READY_POLL_US		5000
#define EM7180_READY_TIMEOUT_US		200000

#define EM7180_ACCEL_GYRO_HZ_PER_LSB	10

/* Attempts at the EventStatus read that releases the INT line */
#define EM7180_EVENT_READ_TRIES		3
/* Longest scan period: the magnetometer's slowest rate, 1 Hz */
#define EM7180_SCAN_WAIT_MS		1100
/* Scans a transfer waits for while others take their turn */
#define EM7180_SCAN_WAIT_TRIES		8

static const struct regmap_range em7180_readable_ranges[] = {
	regmap_reg_range(EM7180_REG_QX, EM7180_REG_ERROR),
	regmap_reg_range(EM7180_REG_ALGO_CTRL, EM7180_REG_PARAM_REQ),
	regmap_reg_range(EM7180_REG_ROM_VERSION, EM7180_REG_RAM_VERSION + 1),
	regmap_reg_range(EM7180_REG_PRODUCT_ID, EM7180_REG_RUN_STATUS),
	regmap_reg_range(EM7180_REG_UPLOAD_ADDR, EM7180_REG_UPLOAD_ADDR + 1),
	regmap_reg_range(EM7180_REG_CRC_HOST, EM7180_REG_CRC_HOST + 3),
	regmap_reg_range(EM7180_REG_PASSTHRU_STATUS, EM7180_REG_PASSTHRU_CTRL),
};

static const struct regmap_access_table em7180_readable_table = {
	.yes_ranges = em7180_readable_ranges,
	.n_yes_ranges = ARRAY_SIZE(em7180_readable_ranges),
};

static const struct regmap_range em7180_writeable_ranges[] = {
	regmap_reg_range(EM7180_REG_QRATE_DIVISOR, EM7180_REG_HOST_CTRL),
	regmap_reg_range(EM7180_REG_ALGO_CTRL, EM7180_REG_PARAM_REQ),
	regmap_reg_range(EM7180_REG_UPLOAD_ADDR, EM7180_REG_UPLOAD_DATA),
	regmap_reg_range(EM7180_REG_RESET_REQ, EM7180_REG_RESET_REQ),
	regmap_reg_range(EM7180_REG_SCL_LOW_CYCLES, EM7180_REG_PASSTHRU_CTRL),
};

static const struct regmap_access_table em7180_writeable_table = {
	.yes_ranges = em7180_writeable_ranges,
	.n_yes_ranges = ARRAY_SIZE(em7180_writeable_ranges),
};

/* Only the host's configuration registers keep what was written to them */
static const struct regmap_range em7180_cached_ranges[] = {
	regmap_reg_range(EM7180_REG_QRATE_DIVISOR, EM7180_REG_HOST_CTRL),
	regmap_reg_range(EM7180_REG_ALGO_CTRL, 0x5F),
	regmap_reg_range(EM7180_REG_SCL_LOW_CYCLES, EM7180_REG_PASSTHRU_CTRL),
};

static const struct regmap_access_table em7180_volatile_table = {
	.no_ranges = em7180_cached_ranges,
	.n_no_ranges = ARRAY_SIZE(em7180_cached_ranges),
};

static const struct regmap_range em7180_precious_ranges[] = {
	regmap_reg_range(EM7180_REG_EVENT_STATUS, EM7180_REG_EVENT_STATUS),
	regmap_reg_range(EM7180_REG_CAL_FLAGS, EM7180_REG_CAL_FLAGS),
};

static const struct regmap_access_table em7180_precious_table = {
	.yes_ranges = em7180_precious_ranges,
	.n_yes_ranges = ARRAY_SIZE(em7180_precious_ranges),
};

const struct regmap_config em7180_regmap_config = {
	.name = "em7180",
	.reg_bits = 8,
	.val_bits = 8,
	.max_register = EM7180_REG_MAX,
	.rd_table = &em7180_readable_table,
	.wr_table = &em7180_writeable_table,
	.volatile_table = &em7180_volatile_table,
	.precious_table = &em7180_precious_table,
	/*
	 * The cache holds the configuration a resume after a power loss
	 * writes back. The tree caches drop a register whose write failed,
	 * and its neighbour with it (regmap drops reg..reg + 1), so one bus
	 * error at AlgorithmControl would lose the magnetometer rate; the
	 * flat cache keeps what the driver asked for.
	 */
	.cache_type = REGCACHE_FLAT,
};
EXPORT_SYMBOL_NS_GPL(em7180_regmap_config, "IIO_EM7180");

/* Scaled output units, as EM's driver_ext.h and the USFS host libraries give them */
static const int em7180_accel_scale[] = { 0, 4785645 };	/* 0.000488 g */
static const int em7180_anglvel_scale[] = { 0, 2663372 };	/* 0.1526 dps */
static const int em7180_magn_scale[] = { 0, 305176 };	/* 0.0305176 uT */

static const int em7180_accel_gyro_freq_avail[] = {
	10, 20, 50, 100, 200, 500, 1000,
};

static const int em7180_magn_freq_avail[] = {
	1, 10, 20, 30, 50, 100,
};

static const struct iio_mount_matrix *
em7180_get_mount_matrix(const struct iio_dev *indio_dev,
			const struct iio_chan_spec *chan)
{
	struct em7180_data *data = iio_priv(indio_dev);

	return &data->orientation;
}

static const struct iio_chan_spec_ext_info em7180_ext_info[] = {
	IIO_MOUNT_MATRIX(IIO_SHARED_BY_TYPE, em7180_get_mount_matrix),
	{ }
};

#define EM7180_VEC_CHANNEL(_type, _axis, _reg, _index, _sep)		\
{									\
	.type = _type,							\
	.modified = 1,							\
	.channel2 = IIO_MOD_##_axis,					\
	.address = _reg,						\
	.info_mask_separate = BIT(IIO_CHAN_INFO_RAW) | (_sep),		\
	.info_mask_shared_by_type = BIT(IIO_CHAN_INFO_SCALE) |		\
				    BIT(IIO_CHAN_INFO_SAMP_FREQ),	\
	.info_mask_shared_by_type_available =				\
				    BIT(IIO_CHAN_INFO_SAMP_FREQ),	\
	.scan_index = _index,						\
	.scan_type = {							\
		.sign = 's',						\
		.realbits = 16,						\
		.storagebits = 16,					\
		.endianness = IIO_LE,					\
	},								\
	.ext_info = em7180_ext_info,					\
}

static const struct iio_chan_spec em7180_channels[] = {
	{
		.type = IIO_ROT,
		.modified = 1,
		.channel2 = IIO_MOD_QUATERNION,
		.address = EM7180_REG_QX,
		.info_mask_separate = BIT(IIO_CHAN_INFO_RAW) |
				      BIT(IIO_CHAN_INFO_SCALE),
		.scan_index = EM7180_SCAN_QUAT,
		.scan_type = {
			.sign = 's',
			.realbits = 16,
			.storagebits = 16,
			.endianness = IIO_CPU,
			.repeat = 4,
		},
	},
	EM7180_VEC_CHANNEL(IIO_MAGN, X, EM7180_REG_MX, EM7180_SCAN_MAGN_X, 0),
	EM7180_VEC_CHANNEL(IIO_MAGN, Y, EM7180_REG_MX + 2, EM7180_SCAN_MAGN_Y, 0),
	EM7180_VEC_CHANNEL(IIO_MAGN, Z, EM7180_REG_MX + 4, EM7180_SCAN_MAGN_Z, 0),
	EM7180_VEC_CHANNEL(IIO_ACCEL, X, EM7180_REG_AX, EM7180_SCAN_ACCEL_X,
			   BIT(IIO_CHAN_INFO_CALIBBIAS)),
	EM7180_VEC_CHANNEL(IIO_ACCEL, Y, EM7180_REG_AX + 2, EM7180_SCAN_ACCEL_Y,
			   BIT(IIO_CHAN_INFO_CALIBBIAS)),
	EM7180_VEC_CHANNEL(IIO_ACCEL, Z, EM7180_REG_AX + 4, EM7180_SCAN_ACCEL_Z,
			   BIT(IIO_CHAN_INFO_CALIBBIAS)),
	EM7180_VEC_CHANNEL(IIO_ANGL_VEL, X, EM7180_REG_GX, EM7180_SCAN_ANGLVEL_X, 0),
	EM7180_VEC_CHANNEL(IIO_ANGL_VEL, Y, EM7180_REG_GX + 2, EM7180_SCAN_ANGLVEL_Y, 0),
	EM7180_VEC_CHANNEL(IIO_ANGL_VEL, Z, EM7180_REG_GX + 4, EM7180_SCAN_ANGLVEL_Z, 0),
	IIO_CHAN_SOFT_TIMESTAMP(EM7180_SCAN_TIMESTAMP),
};

/* One quaternion component, float32 from the chip, as Q14 in an s16 */
static s16 em7180_quat_component(const u8 *src)
{
	s32 q = em7180_float_to_fixed(get_unaligned_le32(src),
				      EM7180_QUAT_FRAC_BITS);

	return clamp_t(s32, q, S16_MIN, S16_MAX);
}

/* The rates the attributes advertise and accept, in Hz */
static void em7180_freq_avail(enum iio_chan_type type, const int **vals,
			      int *len)
{
	if (type == IIO_MAGN) {
		*vals = em7180_magn_freq_avail;
		*len = ARRAY_SIZE(em7180_magn_freq_avail);
	} else {
		*vals = em7180_accel_gyro_freq_avail;
		*len = ARRAY_SIZE(em7180_accel_gyro_freq_avail);
	}
}

static int em7180_rate_regs(enum iio_chan_type type, unsigned int *reg,
			    unsigned int *actual, unsigned int *hz_per_lsb)
{
	switch (type) {
	case IIO_MAGN:
		*reg = EM7180_REG_MAG_RATE;
		*actual = EM7180_REG_ACTUAL_MAG_RATE;
		*hz_per_lsb = 1;
		return 0;
	case IIO_ACCEL:
		*reg = EM7180_REG_ACCEL_RATE;
		*actual = EM7180_REG_ACTUAL_ACCEL_RATE;
		*hz_per_lsb = EM7180_ACCEL_GYRO_HZ_PER_LSB;
		return 0;
	case IIO_ANGL_VEL:
		*reg = EM7180_REG_GYRO_RATE;
		*actual = EM7180_REG_ACTUAL_GYRO_RATE;
		*hz_per_lsb = EM7180_ACCEL_GYRO_HZ_PER_LSB;
		return 0;
	default:
		return -EINVAL;
	}
}

/*
 * Report the rate the sensor actually runs at; before the sensor has
 * started, the actual-rate register reads 0 and the requested rate is
 * reported instead.
 */
static int em7180_read_freq(struct em7180_data *data,
			    enum iio_chan_type type, int *val)
{
	unsigned int reg, actual, hz_per_lsb, rate;
	int ret;

	ret = em7180_rate_regs(type, &reg, &actual, &hz_per_lsb);
	if (ret)
		return ret;

	scoped_guard(mutex, &data->lock) {
		ret = regmap_read(data->regmap, actual, &rate);
		if (!ret && !rate)
			ret = regmap_read(data->regmap, reg, &rate);
	}
	if (ret)
		return ret;

	*val = rate * hz_per_lsb;
	return IIO_VAL_INT;
}

/* Only an advertised rate: anything else is refused before the chip is touched */
static int em7180_write_freq(struct em7180_data *data,
			     const struct iio_chan_spec *chan, int val)
{
	unsigned int reg, actual, hz_per_lsb;
	const int *avail;
	int i, n, ret;

	ret = em7180_rate_regs(chan->type, &reg, &actual, &hz_per_lsb);
	if (ret)
		return ret;

	em7180_freq_avail(chan->type, &avail, &n);
	for (i = 0; i < n; i++)
		if (avail[i] == val)
			break;
	if (i == n)
		return -EINVAL;

	guard(mutex)(&data->lock);
	return regmap_write(data->regmap, reg, val / hz_per_lsb);
}

/*
 * Parameters 27..29 change only when the host writes them, so calibbias is
 * served from a copy: a parameter transfer pauses the fusion algorithm,
 * which a reader of the world-readable attribute must not be able to do.
 * The copy is filled by the driver's own transfers only: at probe, by
 * calibbias writes, calibration_data transfers, suspend and resume.
 */
static int em7180_accel_offset_fetch(struct em7180_data *data)
{
	int ret;

	lockdep_assert_held(&data->lock);

	ret = em7180_params_read(data, EM7180_ACCEL_OFFSET_PARAM,
				 ARRAY_SIZE(data->accel_offset),
				 data->accel_offset);
	data->accel_offset_valid = !ret;

	return ret;
}

/*
 * After a transfer that failed with @err the chip may hold other offsets:
 * read them back, unless the firmware did not answer at all, when another
 * transfer would only wait for another timeout.
 */
static void em7180_accel_offset_refresh(struct em7180_data *data, int err)
{
	data->accel_offset_valid = false;
	if (err != -ETIMEDOUT)
		em7180_accel_offset_fetch(data);
}

/* Keep the copy in step with a warm start read from or written to the chip */
static void em7180_accel_offset_set(struct em7180_data *data, const u32 *ws)
{
	memcpy(data->accel_offset,
	       &ws[EM7180_ACCEL_OFFSET_PARAM - EM7180_WS_FIRST_PARAM],
	       sizeof(data->accel_offset));
	data->accel_offset_valid = true;
}

/**
 * em7180_read_calibbias() - an accelerometer offset, from the driver's copy
 * @data: driver state
 * @axis: 0 to 2 for x, y, z
 * @val: where to store the offset in LSB
 *
 * Never touches the bus, and works while a buffer is enabled.
 *
 * Return: 0, or -ENODATA while the copy is unknown (a transfer that would
 * have refreshed it failed), -ERANGE for a value that is no offset.
 */
int em7180_read_calibbias(struct em7180_data *data, unsigned int axis,
			  int *val)
{
	guard(mutex)(&data->lock);
	if (!data->accel_offset_valid)
		return -ENODATA;

	return em7180_float_g_to_lsb(data->accel_offset[axis], val);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_read_calibbias);

/**
 * em7180_write_calibbias() - write an accelerometer offset
 * @data: driver state
 * @axis: 0 to 2 for x, y, z
 * @val: offset in LSB, -32768 to 32767
 *
 * When the copy of the offsets is unknown, or the write failed after the
 * chip may have taken the value, the offsets are read back in a transfer
 * of the driver's own.
 *
 * Return: 0, -EINVAL for a value out of range, or the transfer's error.
 */
int em7180_write_calibbias(struct em7180_data *data, unsigned int axis,
			   int val)
{
	unsigned int param = EM7180_ACCEL_OFFSET_PARAM + axis;
	u32 bits;
	int ret;

	if (val < S16_MIN || val > S16_MAX)
		return -EINVAL;

	bits = em7180_lsb_to_float_g(val);

	guard(mutex)(&data->lock);
	ret = em7180_params_write(data, param, 1, &bits);
	if (!ret && data->accel_offset_valid)
		data->accel_offset[axis] = bits;
	else
		em7180_accel_offset_refresh(data, ret);
	/* Keep the copy re-applied after a power loss in step */
	if (!ret && data->ws_valid)
		put_unaligned_le32(bits, &data->ws[(param - EM7180_WS_FIRST_PARAM) * 4]);

	return ret;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_write_calibbias);

/*
 * A reset that raised no interrupt leaves the data registers as they were:
 * a raw read a second or more after the last look at SentralStatus takes
 * one first.
 */
static void em7180_check_status(struct em7180_data *data)
{
	unsigned int status;

	lockdep_assert_held(&data->lock);

	if (time_before(jiffies, data->status_at +
			msecs_to_jiffies(EM7180_WATCH_MS)))
		return;
	if (!regmap_read(data->regmap, EM7180_REG_SENTRAL_STATUS, &status))
		em7180_status_seen(data, status);
}

static int em7180_read_raw_vec(struct em7180_data *data,
			       const struct iio_chan_spec *chan, int *val)
{
	__le16 raw;
	int ret;

	scoped_guard(mutex, &data->lock) {
		em7180_check_status(data);
		ret = regmap_bulk_read(data->regmap, chan->address, &raw,
				       sizeof(raw));
	}
	if (ret)
		return ret;

	*val = (s16)le16_to_cpu(raw);
	return IIO_VAL_INT;
}

static int em7180_read_quat(struct em7180_data *data, int *vals)
{
	u8 raw[16];
	int i, ret;

	scoped_guard(mutex, &data->lock) {
		em7180_check_status(data);
		ret = regmap_bulk_read(data->regmap, EM7180_REG_QX, raw,
				       sizeof(raw));
	}
	if (ret)
		return ret;

	/* x, y, z, w: register order, which is also the ABI order */
	for (i = 0; i < 4; i++)
		vals[i] = em7180_quat_component(&raw[4 * i]);

	return IIO_VAL_INT_MULTIPLE;
}

static int em7180_read_scale(const struct iio_chan_spec *chan, int *val,
			     int *val2)
{
	const int *scale;

	switch (chan->type) {
	case IIO_ROT:
		*val = 1;
		*val2 = EM7180_QUAT_FRAC_BITS;
		return IIO_VAL_FRACTIONAL_LOG2;
	case IIO_ACCEL:
		scale = em7180_accel_scale;
		break;
	case IIO_ANGL_VEL:
		scale = em7180_anglvel_scale;
		break;
	case IIO_MAGN:
		scale = em7180_magn_scale;
		break;
	default:
		return -EINVAL;
	}

	*val = scale[0];
	*val2 = scale[1];
	return IIO_VAL_INT_PLUS_NANO;
}

static int em7180_read_raw_multi(struct iio_dev *indio_dev,
				 const struct iio_chan_spec *chan,
				 int max_len, int *vals, int *val_len,
				 long mask)
{
	struct em7180_data *data = iio_priv(indio_dev);
	int ret;

	*val_len = 2;

	switch (mask) {
	case IIO_CHAN_INFO_RAW:
		if (chan->type == IIO_ROT && max_len < 4)
			return -EINVAL;
		if (!iio_device_claim_direct(indio_dev))
			return -EBUSY;
		if (chan->type == IIO_ROT) {
			ret = em7180_read_quat(data, vals);
			*val_len = 4;
		} else {
			ret = em7180_read_raw_vec(data, chan, vals);
		}
		iio_device_release_direct(indio_dev);
		return ret;
	case IIO_CHAN_INFO_SCALE:
		return em7180_read_scale(chan, &vals[0], &vals[1]);
	case IIO_CHAN_INFO_SAMP_FREQ:
		return em7180_read_freq(data, chan->type, vals);
	case IIO_CHAN_INFO_CALIBBIAS:
		ret = em7180_read_calibbias(data,
					    (chan->address - EM7180_REG_AX) / 2,
					    vals);
		return ret ?: IIO_VAL_INT;
	default:
		return -EINVAL;
	}
}

static int em7180_read_avail(struct iio_dev *indio_dev,
			     const struct iio_chan_spec *chan,
			     const int **vals, int *type, int *length,
			     long mask)
{
	if (mask != IIO_CHAN_INFO_SAMP_FREQ)
		return -EINVAL;

	*type = IIO_VAL_INT;
	em7180_freq_avail(chan->type, vals, length);

	return IIO_AVAIL_LIST;
}

static int em7180_write_raw(struct iio_dev *indio_dev,
			    const struct iio_chan_spec *chan,
			    int val, int val2, long mask)
{
	struct em7180_data *data = iio_priv(indio_dev);
	int ret;

	if (val2)
		return -EINVAL;

	if (!iio_device_claim_direct(indio_dev))
		return -EBUSY;

	switch (mask) {
	case IIO_CHAN_INFO_SAMP_FREQ:
		ret = em7180_write_freq(data, chan, val);
		break;
	case IIO_CHAN_INFO_CALIBBIAS:
		ret = em7180_write_calibbias(data,
					     (chan->address - EM7180_REG_AX) / 2,
					     val);
		break;
	default:
		ret = -EINVAL;
		break;
	}

	iio_device_release_direct(indio_dev);
	return ret;
}

static int em7180_write_raw_get_fmt(struct iio_dev *indio_dev,
				    struct iio_chan_spec const *chan,
				    long mask)
{
	return IIO_VAL_INT;
}

/**
 * em7180_score_milli() - the calibration score in thousandths of a percent
 * @raw: CalScore register pair (0x4D | 0x4E << 8)
 *
 * The application note defines the score as (raw - 32768) / 32768 * 100
 * percent; the result is rounded to nearest with integer math.
 *
 * Return: the score in 0.001 %, -100000 to 99997.
 */
int em7180_score_milli(u16 raw)
{
	/* 100000 / 32768 = 3125 / 1024; |product| < 2^27 */
	return DIV_ROUND_CLOSEST(((int)raw - 32768) * 3125, 1024);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_score_milli);

/*
 * The firmware (RAM image) decides what the general-purpose registers hold.
 * No public source names the RAM version of a build with the application
 * note's calibration registers: the board says which of its firmware do,
 * in emmicro,calibration-firmware, and this parameter adds more.
 */
#define EM7180_CAL_FW_PROP		"emmicro,calibration-firmware"
#define EM7180_CAL_FW_PARAM_MAX		8

static unsigned short calibration_firmware[EM7180_CAL_FW_PARAM_MAX];
static unsigned int calibration_firmware_count;
module_param_array(calibration_firmware, ushort, &calibration_firmware_count,
		   0444);
MODULE_PARM_DESC(calibration_firmware,
		 "RAM versions reporting calibration as the application note does (up to 8)");

/**
 * em7180_fw_listed() - is a firmware in a table of RAM versions?
 * @ram: RAM version read from the chip
 * @table: RAM versions, as the property and the parameter give them
 * @len: entries in @table
 *
 * Return: true when @table holds @ram.
 */
bool em7180_fw_listed(u16 ram, const u32 *table, unsigned int len)
{
	unsigned int i;

	for (i = 0; i < len; i++)
		if (table[i] == ram)
			return true;

	return false;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_fw_listed);

enum em7180_id_attr {
	EM7180_ID_PRODUCT,
	EM7180_ID_REVISION,
	EM7180_ID_ROM,
	EM7180_ID_RAM,
};

/*
 * A saved warm start only suits the firmware it was read from: userspace
 * compares these with what it stored. Served from the copy read at probe
 * and after a power loss, the only times the firmware can change.
 */
static ssize_t em7180_id_show(struct device *dev,
			      struct device_attribute *attr, char *buf)
{
	struct em7180_data *data = iio_priv(dev_to_iio_dev(dev));

	guard(mutex)(&data->lock);
	switch (to_iio_dev_attr(attr)->address) {
	case EM7180_ID_PRODUCT:
		return sysfs_emit(buf, "0x%02x\n", data->product_id);
	case EM7180_ID_REVISION:
		return sysfs_emit(buf, "0x%02x\n", data->revision_id);
	case EM7180_ID_ROM:
		return sysfs_emit(buf, "0x%04x\n", data->rom_version);
	default:
		return sysfs_emit(buf, "0x%04x\n", data->ram_version);
	}
}

static IIO_DEVICE_ATTR(in_magn_calibration_auto_status, 0444,
		       em7180_cal_show, NULL, EM7180_CAL_ATTR_STATUS);
static IIO_DEVICE_ATTR(in_magn_calibration_score, 0444,
		       em7180_cal_show, NULL, EM7180_CAL_ATTR_SCORE);
static IIO_DEVICE_ATTR(in_magn_transient, 0444,
		       em7180_cal_show, NULL, EM7180_CAL_ATTR_TRANSIENT);
static IIO_DEVICE_ATTR(in_anglvel_calibration_update, 0444,
		       em7180_cal_show, NULL, EM7180_CAL_ATTR_GYRO_UPDATE);
static IIO_DEVICE_ATTR(in_magn_calibration_update, 0444,
		       em7180_cal_show, NULL, EM7180_CAL_ATTR_MAG_UPDATE);
static IIO_DEVICE_ATTR(product_id, 0444, em7180_id_show, NULL,
		       EM7180_ID_PRODUCT);
static IIO_DEVICE_ATTR(revision_id, 0444, em7180_id_show, NULL,
		       EM7180_ID_REVISION);
static IIO_DEVICE_ATTR(rom_version, 0444, em7180_id_show, NULL,
		       EM7180_ID_ROM);
static IIO_DEVICE_ATTR(ram_version, 0444, em7180_id_show, NULL,
		       EM7180_ID_RAM);

/**
 * em7180_warmstart_check() - validate a calibration_data attribute access
 * @buf: the blob, for a write
 * @off: file offset of the access
 * @count: size of the access
 * @write: true for a write, whose payload is checked as well
 *
 * Only whole-blob accesses are allowed: a read must start at offset 0 with
 * room for the whole blob, a write must be exactly the blob and hold 35
 * finite floats. Nothing here touches the chip.
 *
 * Return: 0 or -EINVAL.
 */
int em7180_warmstart_check(const u8 *buf, loff_t off, size_t count,
			   bool write)
{
	unsigned int i;

	if (off || count < EM7180_WS_SIZE)
		return -EINVAL;
	if (!write)
		return 0;

	if (count != EM7180_WS_SIZE)
		return -EINVAL;
	for (i = 0; i < EM7180_WS_SIZE; i += 4)
		if (!em7180_float_is_finite(get_unaligned_le32(&buf[i])))
			return -EINVAL;

	return 0;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_warmstart_check);

/*
 * While the data-ready trigger paces a capture, a transfer starts right
 * after a scan: the algorithm pauses for the transfer (no samples, no
 * interrupts), so no sample from before the pause is left unread and the
 * gap in the stream is the transfer plus at most one period. One transfer
 * per scan: a second one waits for the next scan, so that readers in a
 * loop cannot stop the stream. A stream that brings no scan within the
 * slowest period (1 s) is not waited for.
 *
 * Return: 1 when a scan came, 0 when none is coming or @tries ran out, or
 * the error of an interrupted wait.
 */
static int em7180_wait_scan(struct em7180_data *data, unsigned int *tries)
{
	unsigned int scans = READ_ONCE(data->scans);
	long ret;

	if (!READ_ONCE(data->pace_event) || !*tries)
		return 0;
	(*tries)--;

	ret = wait_event_killable_timeout(data->scan_wq,
					  READ_ONCE(data->scans) != scans ||
					  !READ_ONCE(data->pace_event),
					  msecs_to_jiffies(EM7180_SCAN_WAIT_MS));
	if (ret < 0)
		return ret;

	return ret > 0;
}

/**
 * em7180_warmstart_read() - read the warm start from the chip
 * @data: driver state, with @data->lock held
 * @buf: where to put the 140-byte blob
 *
 * A parameter that is not a finite float would make a blob that the write
 * path refuses, so that it could never be restored: the read fails instead,
 * and the copy re-applied after a power loss stays the last valid one.
 *
 * Return: 0, -EIO when the chip holds a word that is no finite float
 * (logged, @buf unchanged), or the error of the parameter transfer.
 */
VISIBLE_IF_KUNIT int em7180_warmstart_read(struct em7180_data *data, u8 *buf)
{
	u32 vals[EM7180_WS_NUM_PARAMS];
	unsigned int i;
	int ret;

	lockdep_assert_held(&data->lock);

	ret = em7180_params_read(data, EM7180_WS_FIRST_PARAM,
				 EM7180_WS_NUM_PARAMS, vals);
	if (ret)
		return ret;

	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++) {
		if (em7180_float_is_finite(vals[i]))
			continue;
		dev_err_ratelimited(data->dev,
				    "parameter %u holds 0x%08x, not a finite float: calibration not read\n",
				    EM7180_WS_FIRST_PARAM + i, vals[i]);
		return -EIO;
	}

	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		put_unaligned_le32(vals[i], &buf[4 * i]);
	memcpy(data->ws, buf, EM7180_WS_SIZE);
	data->ws_valid = true;
	em7180_accel_offset_set(data, vals);

	return 0;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_warmstart_read);

/*
 * Reads work while a buffer is enabled, so that an application streaming
 * all day never blocks a save: the transfer runs between two scans, unless
 * another transfer came after the scan waited for.
 */
static ssize_t calibration_data_read(struct file *filp, struct kobject *kobj,
				     em7180_bin_attribute *attr, char *buf,
				     loff_t off, size_t count)
{
	struct iio_dev *indio_dev = dev_to_iio_dev(kobj_to_dev(kobj));
	struct em7180_data *data = iio_priv(indio_dev);
	unsigned int tries = EM7180_SCAN_WAIT_TRIES;
	int ret;

	if (off >= EM7180_WS_SIZE)
		return 0;

	ret = em7180_warmstart_check(buf, off, count, false);
	if (ret)
		return ret;

	for (;;) {
		ret = em7180_wait_scan(data, &tries);
		if (ret < 0)
			return ret;

		guard(mutex)(&data->lock);
		if (ret && data->scan_seq != data->xfer_seq)
			continue;

		ret = em7180_warmstart_read(data, buf);
		if (ret)
			return ret;
		em7180_cal_saved(data);
		return EM7180_WS_SIZE;
	}
}

/**
 * em7180_warmstart_restore() - write a warm start blob to the chip
 * @indio_dev: the IIO device
 * @buf: the blob
 * @off: file offset of the write
 * @count: size of the write
 *
 * The write path of the calibration_data attribute. Anything but 35 finite floats
 * at offset 0 is refused before the chip is touched.
 *
 * Refused while a buffer is enabled: restoring replaces the state the
 * fusion algorithm is tracking with, which belongs before the sensors start
 * (at probe, by udev), not under a running capture.
 *
 * Return: 0, -EINVAL for a bad blob, size or offset, -EBUSY while a buffer
 * is enabled, or the error of the parameter transfer.
 */
int em7180_warmstart_restore(struct iio_dev *indio_dev, const u8 *buf,
			     loff_t off, size_t count)
{
	struct em7180_data *data = iio_priv(indio_dev);
	u32 vals[EM7180_WS_NUM_PARAMS];
	unsigned int i;
	int ret;

	ret = em7180_warmstart_check(buf, off, count, true);
	if (ret)
		return ret;

	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		vals[i] = get_unaligned_le32(&buf[4 * i]);

	if (!iio_device_claim_direct(indio_dev))
		return -EBUSY;

	scoped_guard(mutex, &data->lock) {
		ret = em7180_params_write(data, EM7180_WS_FIRST_PARAM,
					  EM7180_WS_NUM_PARAMS, vals);
		if (!ret) {
			memcpy(data->ws, buf, EM7180_WS_SIZE);
			data->ws_valid = true;
			em7180_accel_offset_set(data, vals);
			em7180_cal_saved(data);
		} else {
			/* Some parameters may have been written before the error */
			em7180_accel_offset_refresh(data, ret);
		}
	}

	iio_device_release_direct(indio_dev);

	return ret;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_warmstart_restore);

static ssize_t calibration_data_write(struct file *filp, struct kobject *kobj,
				      em7180_bin_attribute *attr, char *buf,
				      loff_t off, size_t count)
{
	return em7180_warmstart_restore(dev_to_iio_dev(kobj_to_dev(kobj)),
					buf, off, count) ?: count;
}

/*
 * Declared with size 0 so that sysfs passes every access through as it is:
 * with a size it would silently cut a longer write down to a valid-looking
 * 140 bytes.
 */
static BIN_ATTR_ADMIN_RW(calibration_data, 0);

static struct attribute *em7180_attrs[] = {
	&iio_dev_attr_in_magn_calibration_auto_status.dev_attr.attr,
	&iio_dev_attr_in_magn_calibration_score.dev_attr.attr,
	&iio_dev_attr_in_magn_transient.dev_attr.attr,
	&iio_dev_attr_in_anglvel_calibration_update.dev_attr.attr,
	&iio_dev_attr_in_magn_calibration_update.dev_attr.attr,
	&iio_dev_attr_product_id.dev_attr.attr,
	&iio_dev_attr_revision_id.dev_attr.attr,
	&iio_dev_attr_rom_version.dev_attr.attr,
	&iio_dev_attr_ram_version.dev_attr.attr,
	NULL
};

static em7180_bin_attribute *em7180_bin_attrs[] = {
	&bin_attr_calibration_data,
	NULL
};

/*
 * The IIO core copies this group, is_visible included, into the one that
 * also holds the channel attributes; it is asked once, at registration.
 */
static umode_t em7180_attr_is_visible(struct kobject *kobj,
				      struct attribute *attr, int n)
{
	struct em7180_data *data = iio_priv(dev_to_iio_dev(kobj_to_dev(kobj)));
	struct device_attribute *dattr = container_of(attr,
						      struct device_attribute,
						      attr);

	if (dattr->show == em7180_cal_show && !data->cal_attrs)
		return 0;

	return attr->mode;
}

static const struct attribute_group em7180_attr_group = {
	.attrs = em7180_attrs,
	.bin_attrs = em7180_bin_attrs,
	.is_visible = em7180_attr_is_visible,
};

/*
 * Register access for debugging real chips. Reading a clear-on-read
 * register here would take an event or an update flag from the driver, so
 * those are refused.
 */
static int em7180_debugfs_reg_access(struct iio_dev *indio_dev,
				     unsigned int reg, unsigned int writeval,
				     unsigned int *readval)
{
	struct em7180_data *data = iio_priv(indio_dev);

	guard(mutex)(&data->lock);
	if (!readval)
		return regmap_write(data->regmap, reg, writeval);
	if (regmap_reg_in_ranges(reg, em7180_precious_ranges,
				 ARRAY_SIZE(em7180_precious_ranges)))
		return -EPERM;

	return regmap_read(data->regmap, reg, readval);
}

static const struct iio_info em7180_info = {
	.read_raw_multi = em7180_read_raw_multi,
	.read_avail = em7180_read_avail,
	.write_raw = em7180_write_raw,
	.write_raw_get_fmt = em7180_write_raw_get_fmt,
	.debugfs_reg_access = em7180_debugfs_reg_access,
	.attrs = &em7180_attr_group,
};

/* End of the burst whose last channel is @hi: its sensor's TIME included */
static unsigned int em7180_burst_end(const struct iio_chan_spec *hi)
{
	switch (hi->type) {
	case IIO_ROT:
		return EM7180_REG_QTIME + 2;
	case IIO_MAGN:
		return EM7180_REG_MTIME + 2;
	case IIO_ACCEL:
		return EM7180_REG_ATIME + 2;
	default:
		return EM7180_REG_GTIME + 2;
	}
}

/* The registers a scan of @mask reads in one burst: 0 for the timestamp alone */
static unsigned int em7180_scan_span(const unsigned long *mask,
				     unsigned int *start)
{
	unsigned int lo = find_first_bit(mask, EM7180_SCAN_TIMESTAMP);
	unsigned int hi = find_last_bit(mask, EM7180_SCAN_TIMESTAMP);

	if (lo >= EM7180_SCAN_TIMESTAMP)
		return 0;

	*start = em7180_channels[lo].address;
	return em7180_burst_end(&em7180_channels[hi]) - *start;
}

/*
 * Read the registers of a scan of @mask into data->burst. @fresh tells
 * whether they differ from the last scan read with @own, the chip's own
 * trigger: a sample that arrives between the EventStatus read and the
 * burst is read by the burst of the previous interrupt, and its own
 * interrupt then finds the same registers again. The burst includes the
 * TIME register of the last sensor it covers, so unchanged registers mean
 * the same samples, which are not pushed twice. Any other trigger samples
 * whatever the chip holds.
 */
static int em7180_scan_read(struct em7180_data *data,
			    const unsigned long *mask, bool own, bool *fresh)
{
	unsigned int start = 0, len = em7180_scan_span(mask, &start);
	int ret;

	lockdep_assert_held(&data->lock);

	*fresh = true;
	if (!len)
		return 0;

	ret = regmap_bulk_read(data->regmap, start, data->burst, len);
	if (ret || !own)
		return ret;

	*fresh = data->last_len != len || data->last_start != start ||
		 memcmp(data->last_burst, data->burst, len);
	memcpy(data->last_burst, data->burst, len);
	data->last_start = start;
	data->last_len = len;
	return 0;
}

/*
 * Push the enabled channels out of data->burst, in scan order; the
 * quaternion floats become fixed point on the way.
 */
static void em7180_scan_push(struct iio_dev *indio_dev,
			     const unsigned long *mask, s64 ts)
{
	struct em7180_data *data = iio_priv(indio_dev);
	unsigned int bit, start = 0, pos = 0;
	const u8 *src;
	int i;

	em7180_scan_span(mask, &start);
	for_each_set_bit(bit, mask, EM7180_SCAN_TIMESTAMP) {
		src = &data->burst[em7180_channels[bit].address - start];
		if (bit != EM7180_SCAN_QUAT) {
			memcpy(&data->scan.chans[pos++], src, 2);
			continue;
		}
		for (i = 0; i < 4; i++)
			data->scan.chans[pos++] = em7180_quat_component(&src[4 * i]);
	}

	iio_push_to_buffers_with_ts(indio_dev, &data->scan, sizeof(data->scan),
				    ts);
}

/*
 * With the chip's own trigger the scan was read by em7180_irq_thread(),
 * which runs this handler nested, in the same lock section as the
 * EventStatus read. With another trigger it is read here.
 *
 * A parameter transfer that ended after the interrupt or the trigger poll
 * of a scan held it up while the algorithm paused and ran again: the
 * registers may then hold a sample newer than the scan's timestamp, so
 * nothing is pushed (em7180_lock_between_scans() makes that rare).
 */
static irqreturn_t em7180_trigger_handler(int irq, void *p)
{
	struct iio_poll_func *pf = p;
	struct iio_dev *indio_dev = pf->indio_dev;
	struct em7180_data *data = iio_priv(indio_dev);
	const unsigned long *mask = indio_dev->active_scan_mask;
	/*
	 * Not iio_trigger_using_own(): the core marks the trigger as the
	 * device's own only after enabling it, and a scan in between would
	 * take the poll function's time, which nothing set on this path.
	 */
	bool own = data->trig && indio_dev->trig == data->trig;
	unsigned int seq = READ_ONCE(data->poll_seq);
	bool fresh = false;
	int ret = -EAGAIN;

	if (own) {
		if (data->scan_fresh)
			em7180_scan_push(indio_dev, mask, data->scan_ts);
		WRITE_ONCE(data->scans, data->scans + 1);
		wake_up_all(&data->scan_wq);
		goto done;
	}

	scoped_guard(mutex, &data->lock) {
		if (seq == data->xfer_seq)
			ret = em7180_scan_read(data, mask, false, &fresh);
	}
	if (!ret)
		em7180_scan_push(indio_dev, mask, pf->timestamp);

done:
	iio_trigger_notify_done(indio_dev->trig);
	return IRQ_HANDLED;
}

/* Another device's trigger: its poll time, and which transfers it follows */
static irqreturn_t em7180_pollfunc_store(int irq, void *p)
{
	struct iio_poll_func *pf = p;
	struct em7180_data *data = iio_priv(pf->indio_dev);

	pf->timestamp = iio_get_time_ns(pf->indio_dev);
	WRITE_ONCE(data->poll_seq, READ_ONCE(data->xfer_seq));
	return IRQ_WAKE_THREAD;
}

static irqreturn_t em7180_irq_handler(int irq, void *p)
{
	struct iio_dev *indio_dev = p;
	struct em7180_data *data = iio_priv(indio_dev);

	WRITE_ONCE(data->timestamp, iio_get_time_ns(indio_dev));
	WRITE_ONCE(data->irq_seq, READ_ONCE(data->xfer_seq));
	return IRQ_WAKE_THREAD;
}

static int em7180_chip_recover(struct em7180_data *data);

/**
 * em7180_recover_schedule() - recover from a reset of the chip's own, soon
 * @data: driver state, with @data->lock held
 *
 * Out of the interrupt thread, which other events need.
 */
void em7180_recover_schedule(struct em7180_data *data)
{
	unsigned long next = data->recovered_at +
			     msecs_to_jiffies(EM7180_RECOVER_INTERVAL_MS);
	unsigned long delay = msecs_to_jiffies(EM7180_RECOVER_DELAY_MS);

	if (data->resets && time_before(jiffies + delay, next))
		delay = next - jiffies;
	schedule_delayed_work(&data->recover_work, delay);
}

/**
 * em7180_status_seen() - recover soon if SentralStatus shows a reset
 * @data: driver state, with @data->lock held
 * @status: SentralStatus just read
 *
 * A chip that reset waits in standby for its host, whether or not it
 * raised an interrupt.
 */
void em7180_status_seen(struct em7180_data *data, unsigned int status)
{
	lockdep_assert_held(&data->lock);

	data->status_at = jiffies;
	if (status & EM7180_SENTRAL_STANDBY)
		em7180_recover_schedule(data);
}

static void em7180_recover_flush(void *arg)
{
	struct em7180_data *data = arg;

	flush_delayed_work(&data->recover_work);
}

static void em7180_recover_work(struct work_struct *work)
{
	struct em7180_data *data = container_of(to_delayed_work(work),
						struct em7180_data,
						recover_work);
	int ret;

	guard(mutex)(&data->lock);
	if (data->xfer_stuck) {
		data->xfer_stuck = false;
		ret = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, 0);
		if (!ret)
			return;
		dev_warn(data->dev,
			 "cannot end a parameter transfer (%d): resetting the chip\n",
			 ret);
		ret = regmap_write(data->regmap, EM7180_REG_RESET_REQ,
				   EM7180_RESET_REQ_RESET);
		if (ret) {
			dev_err(data->dev, "cannot reset the chip: %d\n", ret);
			return;
		}
	}
	em7180_chip_recover(data);
}

static void em7180_watch_schedule(struct em7180_data *data)
{
	/* Freezable: no check of a chip that system sleep put in standby */
	queue_delayed_work(system_freezable_wq, &data->watch_work,
			   msecs_to_jiffies(EM7180_WATCH_MS));
}

/*
 * With the chip's own trigger, a scan every period shows that the chip
 * runs; with another trigger the registers would only repeat: checked
 * each time.
 */
static void em7180_watch_work(struct work_struct *work)
{
	struct em7180_data *data = container_of(to_delayed_work(work),
						struct em7180_data,
						watch_work);
	unsigned int scans = READ_ONCE(data->scans), status;

	if (!READ_ONCE(data->pace_event) || scans == data->watch_scans) {
		guard(mutex)(&data->lock);
		if (!regmap_read(data->regmap, EM7180_REG_SENTRAL_STATUS,
				 &status))
			em7180_status_seen(data, status);
	}
	data->watch_scans = scans;
	em7180_watch_schedule(data);
}

static int em7180_buffer_postenable(struct iio_dev *indio_dev)
{
	struct em7180_data *data = iio_priv(indio_dev);

	data->watch_scans = READ_ONCE(data->scans);
	em7180_watch_schedule(data);
	return 0;
}

static int em7180_buffer_predisable(struct iio_dev *indio_dev)
{
	struct em7180_data *data = iio_priv(indio_dev);

	cancel_delayed_work_sync(&data->watch_work);
	return 0;
}

static const struct iio_buffer_setup_ops em7180_buffer_ops = {
	.postenable = em7180_buffer_postenable,
	.predisable = em7180_buffer_predisable,
};

/* What recovery did, for a user who wonders why the data paused */
static int em7180_recovery_show(struct seq_file *m, void *unused)
{
	struct em7180_data *data = m->private;

	guard(mutex)(&data->lock);
	seq_printf(m, "resets %u\n", data->resets);
	seq_printf(m, "pending %d\n", delayed_work_pending(&data->recover_work));
	if (data->resets)
		seq_printf(m, "last %u ms ago, result %d\n",
			   jiffies_to_msecs(jiffies - data->recovered_at),
			   data->recover_ret);
	return 0;
}
DEFINE_SHOW_ATTRIBUTE(em7180_recovery);

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

/*
 * An Error event: ErrorRegister and SensorStatus (sensor NACK and ID
 * errors), said once for each new pair, as a dead sensor would otherwise
 * fill the log at every interrupt.
 */
static void em7180_report_error(struct em7180_data *data)
{
	unsigned int err, sensors;
	int ret;

	lockdep_assert_held(&data->lock);

	ret = regmap_read(data->regmap, EM7180_REG_ERROR, &err);
	if (!ret)
		ret = regmap_read(data->regmap, EM7180_REG_SENSOR_STATUS,
				  &sensors);
	if (ret) {
		dev_err_ratelimited(data->dev,
				    "chip error, error registers unreadable: %d\n",
				    ret);
		return;
	}
	if (data->last_error == (sensors << 8 | err))
		return;
	data->last_error = sensors << 8 | err;
	if (err || sensors)
		dev_err(data->dev,
			"chip error 0x%02x (%s), sensor status 0x%02x\n", err,
			err ? em7180_error_name(err) : "none", sensors);
}

/*
 * Reading EventStatus clears it and releases the INT line. The line is a
 * level that only a successful read lowers: on an edge-triggered interrupt
 * a read lost to a bus error would leave it high and no further interrupt
 * would ever come, so the read is retried.
 *
 * The time of the interrupt is taken before that read: once INT is low
 * the next sample can raise a new edge, whose hard handler overwrites
 * data->timestamp before this scan has been captured.
 *
 * CPUReset means the chip reset itself (a brown-out, a watchdog): its
 * configuration and calibration are gone and no data would come any more.
 */
static irqreturn_t em7180_irq_thread(int irq, void *p)
{
	struct iio_dev *indio_dev = p;
	struct em7180_data *data = iio_priv(indio_dev);
	s64 ts = READ_ONCE(data->timestamp);
	unsigned int seq = READ_ONCE(data->irq_seq);
	unsigned int status, pending = 0;
	int ret, scan_ret = -EAGAIN;
	int tries = EM7180_EVENT_READ_TRIES;
	bool scan = false, fresh = false;

	scoped_guard(mutex, &data->lock) {
		do {
			ret = regmap_read(data->regmap, EM7180_REG_EVENT_STATUS,
					  &status);
		} while (ret && --tries);
		/* EventStatus latches every event; INT rises for enabled ones */
		if (!ret)
			pending = status & (EM7180_EVENT_ALWAYS | data->pace_event);
		if (pending & EM7180_EVENT_ERROR)
			em7180_report_error(data);
		if (pending & EM7180_EVENT_CPU_RESET) {
			em7180_recover_schedule(data);
		} else if (pending & EM7180_EVENT_DATA) {
			/* The burst in the same lock section: no transfer in between */
			scan = true;
			data->scan_seq = data->xfer_seq;
			if (seq == data->xfer_seq)
				scan_ret = em7180_scan_read(data,
							    indio_dev->active_scan_mask,
							    true, &fresh);
		}
	}
	if (ret) {
		dev_err_ratelimited(data->dev,
				    "cannot read the event status: %d\n", ret);
		return IRQ_HANDLED;
	}
	/* Not ours: another device on a shared line, or a glitch */
	if (!pending)
		return IRQ_NONE;

	if (scan) {
		/* The trigger handler runs nested, in this thread */
		data->scan_ts = ts ?: iio_get_time_ns(indio_dev);
		data->scan_fresh = !scan_ret && fresh;
		em7180_trigger_poll_nested(data->trig);
	}

	return IRQ_HANDLED;
}

static bool em7180_mask_has(const unsigned long *mask, unsigned int first)
{
	return find_next_bit(mask, first + 3, first) < first + 3;
}

/*
 * One event paces the scans, so that each scan is one step of the chip:
 * the quaternion when it is captured (the fusion step), else the fastest
 * captured sensor, ties going to the gyroscope; the gyroscope for the
 * timestamp alone. A scan holds what the chip has for the other channels,
 * which for a slower sensor is its last sample again.
 */
static unsigned int em7180_pace_event(struct em7180_data *data,
				      const unsigned long *mask)
{
	static const struct {
		unsigned int first;
		unsigned int event;
		enum iio_chan_type type;
	} sensors[] = {
		{ EM7180_SCAN_ANGLVEL_X, EM7180_EVENT_GYRO, IIO_ANGL_VEL },
		{ EM7180_SCAN_ACCEL_X, EM7180_EVENT_ACCEL, IIO_ACCEL },
		{ EM7180_SCAN_MAGN_X, EM7180_EVENT_MAG, IIO_MAGN },
	};
	unsigned int i, reg, actual, hz_per_lsb, rate, best = 0;
	unsigned int event = EM7180_EVENT_GYRO;

	lockdep_assert_held(&data->lock);

	if (test_bit(EM7180_SCAN_QUAT, mask))
		return EM7180_EVENT_QUAT;

	for (i = 0; i < ARRAY_SIZE(sensors); i++) {
		if (!em7180_mask_has(mask, sensors[i].first) ||
		    em7180_rate_regs(sensors[i].type, &reg, &actual,
				     &hz_per_lsb) ||
		    regmap_read(data->regmap, reg, &rate))
			continue;
		if (rate * hz_per_lsb > best) {
			best = rate * hz_per_lsb;
			event = sensors[i].event;
		}
	}

	return event;
}

static int em7180_trigger_set_state(struct iio_trigger *trig, bool state)
{
	struct iio_dev *indio_dev = iio_trigger_get_drvdata(trig);
	struct em7180_data *data = iio_priv(indio_dev);
	const unsigned long *mask = indio_dev->active_scan_mask;
	unsigned int events = EM7180_EVENT_ALWAYS, status;
	int ret, tries = EM7180_EVENT_READ_TRIES;

	scoped_guard(mutex, &data->lock) {
		WRITE_ONCE(data->pace_event,
			   state && mask ? em7180_pace_event(data, mask) : 0);
		events |= data->pace_event;
		/* No scan comes any more: transfers waiting for one go ahead */
		if (!state)
			wake_up_all(&data->scan_wq);
		/* A new capture: nothing pushed yet that a scan could repeat */
		data->last_len = 0;
		ret = regmap_write(data->regmap, EM7180_REG_ENABLE_EVENTS,
				   events);
		if (ret && !state)
			ret = regmap_write(data->regmap,
					   EM7180_REG_ENABLE_EVENTS, events);
		/*
		 * An event left pending keeps INT high, and on an
		 * edge-triggered line no edge, no interrupt and no scan
		 * would ever come: read it.
		 */
		if (!ret && state) {
			do {
				ret = regmap_read(data->regmap,
						  EM7180_REG_EVENT_STATUS,
						  &status);
			} while (ret && --tries);
			if (!ret && (status & EM7180_EVENT_CPU_RESET))
				ret = em7180_chip_recover(data);
		}
	}

	/*
	 * When turning the trigger off fails, the IIO core keeps the poll
	 * function attached but tears the buffer down anyway: the next data
	 * interrupt would then run the trigger handler with no scan mask.
	 * Hence one retry, and a failure is reported here, not to the core.
	 */
	if (ret && !state) {
		dev_err(data->dev, "cannot turn the data interrupts off: %d\n",
			ret);
		return 0;
	}

	return ret;
}

/*
 * The trigger fires once per scan, at the rate of the event pacing the
 * capture; while none runs, at the rate a scan of every channel would get
 * (the quaternion's: the gyroscope rate, QRateDivisor being 0).
 */
static ssize_t sampling_frequency_show(struct device *dev,
				       struct device_attribute *attr,
				       char *buf)
{
	struct iio_dev *indio_dev = iio_trigger_get_drvdata(to_iio_trigger(dev));
	struct em7180_data *data = iio_priv(indio_dev);
	enum iio_chan_type type;
	int ret, hz;

	switch (READ_ONCE(data->pace_event)) {
	case EM7180_EVENT_MAG:
		type = IIO_MAGN;
		break;
	case EM7180_EVENT_ACCEL:
		type = IIO_ACCEL;
		break;
	default:
		type = IIO_ANGL_VEL;
		break;
	}

	ret = em7180_read_freq(data, type, &hz);
	if (ret < 0)
		return ret;

	return sysfs_emit(buf, "%d\n", hz);
}

static DEVICE_ATTR_RO(sampling_frequency);

static struct attribute *em7180_trigger_attrs[] = {
	&dev_attr_sampling_frequency.attr,
	NULL
};
ATTRIBUTE_GROUPS(em7180_trigger);

static const struct iio_trigger_ops em7180_trigger_ops = {
	.set_trigger_state = em7180_trigger_set_state,
	.validate_device = iio_trigger_validate_own_device,
};

static int em7180_trigger_probe(struct iio_dev *indio_dev, int irq)
{
	struct em7180_data *data = iio_priv(indio_dev);
	struct device *dev = data->dev;
	int ret;

	data->trig = devm_iio_trigger_alloc(dev, "%s-dev%d", indio_dev->name,
					    iio_device_id(indio_dev));
	if (!data->trig)
		return -ENOMEM;

	data->trig->ops = &em7180_trigger_ops;
	data->trig->dev.groups = em7180_trigger_groups;
	iio_trigger_set_drvdata(data->trig, indio_dev);

	ret = devm_request_threaded_irq(dev, irq, em7180_irq_handler,
					em7180_irq_thread, IRQF_ONESHOT,
					indio_dev->name, indio_dev);
	if (ret)
		return dev_err_probe(dev, ret, "failed to request irq %d\n", irq);

	ret = devm_iio_trigger_register(dev, data->trig);
	if (ret)
		return dev_err_probe(dev, ret, "failed to register trigger\n");

	indio_dev->trig = iio_trigger_get(data->trig);

	return 0;
}

static int em7180_read_status(struct em7180_data *data, unsigned int *status)
{
	return regmap_read(data->regmap, EM7180_REG_SENTRAL_STATUS, status);
}

/*
 * After power-on or a reset the chip uploads its firmware from EEPROM; a
 * chip found stuck is reset once, as the USFS host libraries do.
 * While it resets it may not acknowledge its address at all (the
 * reference drivers wait about 50 ms): a bus error is one more poll, and
 * only the last one counts. Reports nothing itself: probe and resume word
 * the failure each their own way, from the last SentralStatus in @status.
 *
 * Return: 0, -ENODEV without a firmware EEPROM, -EIO for a failed upload,
 * -ETIMEDOUT, or the bus error.
 */
static int em7180_reset(struct em7180_data *data, const char *why,
			unsigned int status)
{
	dev_warn(data->dev, "%s (SentralStatus 0x%02x): resetting it\n", why,
		 status);
	return regmap_write(data->regmap, EM7180_REG_RESET_REQ,
			    EM7180_RESET_REQ_RESET);
}

static int em7180_wait_firmware(struct em7180_data *data,
				unsigned int *status)
{
	int ret, err, tries;

	for (tries = 0; tries < 2; tries++) {
		if (tries) {
			ret = em7180_reset(data, "firmware upload not done",
					   *status);
			if (ret)
				return ret;
		}

		ret = read_poll_timeout(em7180_read_status, err,
					!err && (*status & (EM7180_SENTRAL_UPLOAD_DONE |
							    EM7180_SENTRAL_UPLOAD_ERR |
							    EM7180_SENTRAL_NO_EEPROM)),
					EM7180_UPLOAD_POLL_US,
					EM7180_UPLOAD_TIMEOUT_US, false, data,
					status);
		if (ret && err)
			return err;
		if (!ret && (*status & EM7180_SENTRAL_UPLOAD_DONE) &&
		    !(*status & EM7180_SENTRAL_UPLOAD_ERR))
			return 0;
	}

	if (ret)
		return ret;
	return *status & EM7180_SENTRAL_NO_EEPROM ? -ENODEV : -EIO;
}

/*
 * A host reboot without a power cycle can leave the chip showing its
 * firmware loaded (SentralStatus 0x03) but idle until a ResetRequest
 * (kriswiner/EM7180_SENtral_sensor_hub issue 52, "should be 11"): a chip
 * that does not enter standby when HostControl is cleared is reset.
 */
static int em7180_check_alive(struct em7180_data *data, unsigned int *status)
{
	int ret;

	ret = regmap_write(data->regmap, EM7180_REG_HOST_CTRL, 0);
	if (ret)
		return ret;
	ret = regmap_read_poll_timeout(data->regmap, EM7180_REG_SENTRAL_STATUS,
				       *status, *status & EM7180_SENTRAL_STANDBY,
				       EM7180_STANDBY_POLL_US,
				       EM7180_ALIVE_TIMEOUT_US);
	if (ret != -ETIMEDOUT)
		return ret;

	ret = em7180_reset(data, "chip idle with its firmware loaded", *status);
	if (ret)
		return ret;
	return em7180_wait_firmware(data, status);
}

/*
 * Configure while HostControl is 0, then run, as em718x_core.c does: the
 * rates and outputs are set before the sensors start. Leaves any
 * parameter transfer an earlier user may have abandoned, and reads
 * EventStatus, which holds the CPUReset of the upload, so that enabling
 * the reset event does not report a reset at once.
 *
 * After a power loss the same registers come from the cache, in the same
 * order: HostControl last.
 */
static int em7180_chip_configure(struct em7180_data *data, bool from_cache)
{
	static const struct reg_sequence init_seq[] = {
		{ EM7180_REG_PARAM_REQ, 0 },
		{ EM7180_REG_ALGO_CTRL, 0 },
		{ EM7180_REG_MAG_RATE, 30 },
		{ EM7180_REG_ACCEL_RATE, 100 / EM7180_ACCEL_GYRO_HZ_PER_LSB },
		{ EM7180_REG_GYRO_RATE, 100 / EM7180_ACCEL_GYRO_HZ_PER_LSB },
		{ EM7180_REG_QRATE_DIVISOR, 0 },
		{ EM7180_REG_ENABLE_EVENTS, EM7180_EVENT_ALWAYS },
		{ EM7180_REG_HOST_CTRL, EM7180_HOST_CTRL_RUN },
	};
	unsigned int status;
	int ret;

	if (!from_cache) {
		ret = regmap_multi_reg_write(data->regmap, init_seq,
					     ARRAY_SIZE(init_seq));
	} else {
		regcache_mark_dirty(data->regmap);
		ret = regmap_write(data->regmap, EM7180_REG_PARAM_REQ, 0);
		if (!ret)
			ret = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, 0);
		if (!ret)
			ret = regcache_sync_region(data->regmap,
						   EM7180_REG_MAG_RATE,
						   EM7180_REG_GYRO_RATE);
		if (!ret)
			ret = regcache_sync_region(data->regmap,
						   EM7180_REG_QRATE_DIVISOR,
						   EM7180_REG_ENABLE_EVENTS);
		if (!ret)
			ret = regcache_sync_region(data->regmap,
						   EM7180_REG_HOST_CTRL,
						   EM7180_REG_HOST_CTRL);
	}
	if (ret)
		return ret;

	return regmap_read(data->regmap, EM7180_REG_EVENT_STATUS, &status);
}

/*
 * Standby, as for system sleep: the fusion algorithm halts. A chip that
 * does not confirm it is not a reason to keep the system awake, nor left
 * halted for good: the caller resumes it whatever happened.
 */
static int em7180_standby(struct em7180_data *data)
{
	unsigned int status;
	int ret;

	ret = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL,
			   EM7180_ALGO_CTRL_STANDBY);
	if (ret)
		ret = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL,
				   EM7180_ALGO_CTRL_STANDBY);
	if (!ret)
		ret = regmap_read_poll_timeout(data->regmap,
					       EM7180_REG_ALGO_STATUS, status,
					       status & EM7180_ALGO_STATUS_HALTED,
					       EM7180_STANDBY_POLL_US,
					       EM7180_STANDBY_TIMEOUT_US);
	if (ret)
		dev_warn(data->dev,
			 "standby not confirmed (%d); resume runs the algorithm again\n",
			 ret);

	return 0;
}

/*
 * Runs on unbind after the IIO device and its interrupt are gone, before
 * devm turns the supplies off. Where those are fixed or shared (most
 * boards) the chip stays powered, and i2c-dev users find it quiet but
 * running, as firmware serves no parameter transfer in standby; where the
 * driver can switch them, the chip is then off and loses its state.
 */
static void em7180_unbind_action(void *arg)
{
	struct em7180_data *data = arg;
	static const struct reg_sequence seq[] = {
		{ EM7180_REG_ENABLE_EVENTS, 0 },
		{ EM7180_REG_PARAM_REQ, 0 },
		{ EM7180_REG_ALGO_CTRL, 0 },
	};

	guard(mutex)(&data->lock);
	if (regmap_multi_reg_write(data->regmap, seq, ARRAY_SIZE(seq)))
		dev_warn(data->dev, "chip not left running\n");
}

/*
 * Another ProductID or RevisionID may be a compatible part the driver was
 * not tested with: say so and go on, as bno055 does. Userspace compares
 * the identity before restoring a saved calibration. The first access
 * after power-on may come while the chip still resets and does not
 * acknowledge its address: it is repeated for a while.
 */
static int em7180_check_id(struct em7180_data *data)
{
	u8 id[2];
	int ret, err;

	ret = read_poll_timeout(regmap_bulk_read, err, !err,
				EM7180_READY_POLL_US, EM7180_READY_TIMEOUT_US,
				false, data->regmap, EM7180_REG_PRODUCT_ID, id,
				sizeof(id));
	if (ret)
		return dev_err_probe(data->dev, err, "failed to read chip ID\n");

	if (id[0] != EM7180_PRODUCT_ID || id[1] != EM7180_REVISION_ID)
		dev_warn(data->dev,
			 "unexpected ProductID 0x%02x RevisionID 0x%02x (expected 0x%02x 0x%02x)\n",
			 id[0], id[1], EM7180_PRODUCT_ID, EM7180_REVISION_ID);

	data->product_id = id[0];
	data->revision_id = id[1];
	return 0;
}

/* ROM and RAM versions, 0x70..0x73 in one burst; valid once uploaded */
static int em7180_read_versions(struct em7180_data *data)
{
	__le16 ver[2];
	int ret;

	ret = regmap_bulk_read(data->regmap, EM7180_REG_ROM_VERSION, ver,
			       sizeof(ver));
	if (ret)
		return ret;

	data->rom_version = le16_to_cpu(ver[0]);
	data->ram_version = le16_to_cpu(ver[1]);
	return 0;
}

/* The property's RAM versions, then the module parameter's */
static int em7180_cal_fw_read(struct em7180_data *data)
{
	struct device *dev = data->dev;
	unsigned int i, n;
	u32 *table;
	int ret;

	/* -EINVAL: no such property */
	ret = device_property_count_u32(dev, EM7180_CAL_FW_PROP);
	if (ret < 0 && ret != -EINVAL)
		return dev_err_probe(dev, ret, "invalid %s\n",
				     EM7180_CAL_FW_PROP);
	n = max(ret, 0);

	table = devm_kcalloc(dev, n + calibration_firmware_count,
			     sizeof(*table), GFP_KERNEL);
	if (!table)
		return -ENOMEM;

	if (n) {
		ret = device_property_read_u32_array(dev, EM7180_CAL_FW_PROP,
						     table, n);
		if (ret)
			return dev_err_probe(dev, ret, "cannot read %s\n",
					     EM7180_CAL_FW_PROP);
	}
	for (i = 0; i < calibration_firmware_count; i++)
		table[n + i] = calibration_firmware[i];

	data->cal_fw = table;
	data->cal_fw_len = n + calibration_firmware_count;
	return 0;
}

/*
 * Whether the firmware now running reports the calibration, said once per
 * change: at probe when it does not, after a power loss when that changed.
 * The attributes are made at probe only: a firmware that comes later does
 * not add them, one that goes makes them read ENODATA.
 */
static void em7180_cal_fw_check(struct em7180_data *data, bool probe)
{
	bool reported = em7180_fw_listed(data->ram_version, data->cal_fw,
					 data->cal_fw_len);

	if (!probe && reported == data->cal_reported)
		return;

	data->cal_reported = reported;
	if (probe) {
		data->cal_attrs = reported;
		if (!reported)
			dev_info(data->dev,
				 "firmware RAM 0x%04x is not known to report calibration status and score (0x43, 0x44, 0x4D-0x4E): those attributes are left out; add it to emmicro,calibration-firmware or em7180_core.calibration_firmware if it does\n",
				 data->ram_version);
	} else if (!reported) {
		dev_info(data->dev,
			 "firmware RAM 0x%04x is not known to report calibration status and score (0x43, 0x44, 0x4D-0x4E): those attributes read ENODATA while it runs\n",
			 data->ram_version);
	} else if (!data->cal_attrs) {
		dev_info(data->dev,
			 "firmware RAM 0x%04x reports calibration status and score: bind the driver again for those attributes\n",
			 data->ram_version);
	}
}

/**
 * em7180_core_probe() - probe an EM7180 behind any bus
 * @dev: the bus device
 * @regmap: register map built with em7180_regmap_config
 * @irq: interrupt of the INT pin, or 0 when not wired
 *
 * Return: 0 or a negative error code.
 */
int em7180_core_probe(struct device *dev, struct regmap *regmap, int irq)
{
	static const char * const regulators[] = { "vdd", "vddio" };
	struct em7180_data *data;
	struct iio_dev *indio_dev;
	unsigned int status = 0;
	int ret;

	indio_dev = devm_iio_device_alloc(dev, sizeof(*data));
	if (!indio_dev)
		return -ENOMEM;

	data = iio_priv(indio_dev);
	data->dev = dev;
	data->regmap = regmap;
	data->irq = max(irq, 0);
	ret = devm_mutex_init(dev, &data->lock);
	if (ret)
		return ret;
	init_waitqueue_head(&data->scan_wq);
	dev_set_drvdata(dev, indio_dev);

	ret = devm_regulator_bulk_get_enable(dev, ARRAY_SIZE(regulators),
					     regulators);
	if (ret)
		return dev_err_probe(dev, ret, "failed to enable regulators\n");
	/* Power-on reset of the chip */
	fsleep(EM7180_POWER_ON_US);

	ret = iio_read_mount_matrix(dev, &data->orientation);
	if (ret)
		return dev_err_probe(dev, ret, "failed to read mount matrix\n");

	ret = em7180_check_id(data);
	if (ret)
		return ret;

	ret = em7180_wait_firmware(data, &status);
	if (!ret)
		ret = em7180_check_alive(data, &status);
	if (ret)
		return dev_err_probe(dev, ret,
				     "firmware not ready (SentralStatus 0x%02x)\n",
				     status);

	ret = em7180_read_versions(data);
	if (ret)
		return dev_err_probe(dev, ret,
				     "failed to read firmware versions\n");

	ret = em7180_cal_fw_read(data);
	if (ret)
		return ret;
	em7180_cal_fw_check(data, true);

	ret = em7180_chip_configure(data, false);
	if (ret)
		return dev_err_probe(dev, ret, "failed to configure the chip\n");

	/* On unbind: after the IIO device and interrupt, before the supplies */
	ret = devm_add_action_or_reset(dev, em7180_unbind_action, data);
	if (ret)
		return ret;

	/* Streaming works without: calibbias reads fail until a transfer */
	scoped_guard(mutex, &data->lock)
		ret = em7180_accel_offset_fetch(data);
	if (ret)
		dev_warn(dev, "cannot read the accelerometer offsets: %d\n",
			 ret);

	indio_dev->name = "em7180";
	indio_dev->info = &em7180_info;
	indio_dev->channels = em7180_channels;
	indio_dev->num_channels = ARRAY_SIZE(em7180_channels);
	indio_dev->modes = INDIO_DIRECT_MODE;

	/*
	 * On unbind after the interrupt is freed: a pending recovery runs, so
	 * that the chip is left running (em7180_unbind_action())
	 */
	INIT_DELAYED_WORK(&data->recover_work, em7180_recover_work);
	INIT_DELAYED_WORK(&data->watch_work, em7180_watch_work);
	ret = devm_add_action_or_reset(dev, em7180_recover_flush, data);
	if (ret)
		return ret;

	if (data->irq) {
		ret = em7180_trigger_probe(indio_dev, data->irq);
		if (ret)
			return ret;
	}

	ret = devm_iio_triggered_buffer_setup(dev, indio_dev,
					      em7180_pollfunc_store,
					      em7180_trigger_handler,
					      &em7180_buffer_ops);
	if (ret)
		return dev_err_probe(dev, ret, "failed to set up buffer\n");

	ret = devm_iio_device_register(dev, indio_dev);
	if (ret)
		return ret;

	debugfs_create_file("recovery", 0400, iio_get_debugfs_dentry(indio_dev),
			    data, &em7180_recovery_fops);
	return 0;
}
EXPORT_SYMBOL_NS_GPL(em7180_core_probe, "IIO_EM7180");

/**
 * em7180_chip_suspend() - keep the calibration and put the algorithm in standby
 * @data: driver state
 *
 * The warm start the chip has learned so far is read first: if the chip
 * loses power while the system sleeps, resume writes it back, not the one
 * of boot time. A failed read keeps the last one known.
 *
 * Return: 0, or the error of the standby request, when the chip still runs.
 */
int em7180_chip_suspend(struct em7180_data *data)
{
	u8 buf[EM7180_WS_SIZE];
	int ret;

	guard(mutex)(&data->lock);
	ret = em7180_warmstart_read(data, buf);
	if (ret)
		dev_warn(data->dev,
			 "cannot read the calibration before sleep: %d\n", ret);

	return em7180_standby(data);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_chip_suspend);

/*
 * The calibration back after a reset, if it suits the firmware now
 * running, as sentral-warmstart checks a saved file: same ROM and RAM
 * versions. Else what is skipped is logged and the offsets are read from
 * the chip, which is what it now holds.
 */
static int em7180_restore_calibration(struct em7180_data *data, u16 rom,
				      u16 ram)
{
	u32 vals[EM7180_WS_NUM_PARAMS];
	unsigned int i;
	int ret;

	if (rom != data->rom_version || ram != data->ram_version) {
		dev_warn(data->dev,
			 "firmware changed (ROM 0x%04x RAM 0x%04x, was 0x%04x 0x%04x): calibration and accelerometer offsets not restored\n",
			 data->rom_version, data->ram_version, rom, ram);
		data->ws_valid = false;
		return em7180_accel_offset_fetch(data);
	}

	if (data->ws_valid) {
		for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
			vals[i] = get_unaligned_le32(&data->ws[4 * i]);
		ret = em7180_params_write(data, EM7180_WS_FIRST_PARAM,
					  EM7180_WS_NUM_PARAMS, vals);
		if (!ret)
			em7180_accel_offset_set(data, vals);
		return ret;
	}

	/* Offsets written while no warm start was known */
	if (data->accel_offset_valid)
		return em7180_params_write(data, EM7180_ACCEL_OFFSET_PARAM,
					   ARRAY_SIZE(data->accel_offset),
					   data->accel_offset);

	return em7180_accel_offset_fetch(data);
}

/*
 * One attempt at em7180_chip_resume(). @lost is set once a power loss has
 * been seen: a failed attempt may have set the chip running already, after
 * which SentralStatus no longer shows it. @rom and @ram hold the versions
 * from before the loss.
 */
static int em7180_chip_restore(struct em7180_data *data, bool *lost,
			       u16 *rom, u16 *ram)
{
	unsigned int status = 0;
	int ret, err;

	/* As at probe: a chip still in its reset does not acknowledge */
	ret = read_poll_timeout(em7180_read_status, err, !err,
				EM7180_READY_POLL_US, EM7180_READY_TIMEOUT_US,
				false, data, &status);
	if (ret)
		return err;

	if (!*lost && !(status & EM7180_SENTRAL_STANDBY))
		return regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, 0);

	if (!*lost) {
		dev_info(data->dev, "chip lost power, restoring its state\n");
		*rom = data->rom_version;
		*ram = data->ram_version;
	}
	*lost = true;
	data->cal.valid = false;
	/* The firmware may be another, with another latency */
	data->ack_min_us = 0;

	ret = em7180_wait_firmware(data, &status);
	if (ret) {
		dev_err(data->dev,
			"firmware not ready after a power loss (SentralStatus 0x%02x): %d\n",
			status, ret);
		return ret;
	}

	/* The firmware was uploaded again, maybe a different one */
	ret = em7180_read_versions(data);
	if (!ret) {
		em7180_cal_fw_check(data, false);
		ret = em7180_chip_configure(data, true);
	}
	if (!ret)
		ret = em7180_restore_calibration(data, *rom, *ram);

	return ret;
}

/*
 * A reset of the chip's own, seen as CPUReset: the same as a power loss,
 * with @data->lock held.
 */
static int em7180_chip_recover(struct em7180_data *data)
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
		dev_err(data->dev, "cannot restore the chip after its reset: %d\n",
			ret);

	return ret;
}

/**
 * em7180_chip_resume() - run again, restoring the chip after a power loss
 * @data: driver state
 *
 * SentralStatus shows the CPU in its standby state only after a reset: a
 * suspended chip keeps executing with just the algorithm halted. After a
 * reset the firmware versions are read again, the configuration written
 * back with HostControl last, and the warm start saved at suspend (or the
 * accelerometer offsets, when none is known) restored if the firmware is
 * the same.
 *
 * A chip left half restored would stay so, maybe not even running, until
 * the next resume: after a bus error the whole sequence, whose steps can
 * all be repeated, is tried once more. A timeout, which already took
 * seconds, is not.
 *
 * Return: 0 or a negative error code.
 */
int em7180_chip_resume(struct em7180_data *data)
{
	u16 rom = 0, ram = 0;
	bool lost = false;
	int ret;

	guard(mutex)(&data->lock);
	ret = em7180_chip_restore(data, &lost, &rom, &ram);
	if (ret && ret != -ETIMEDOUT && ret != -ENODEV)
		ret = em7180_chip_restore(data, &lost, &rom, &ram);

	return ret;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_chip_resume);

/*
 * No interrupt and no trigger across system sleep, as bmi323 does: the
 * chip's data interrupts would come while the bus is suspended.
 */
static int em7180_suspend(struct device *dev)
{
	struct iio_dev *indio_dev = dev_get_drvdata(dev);
	struct em7180_data *data = iio_priv(indio_dev);
	int ret;

	ret = em7180_suspend_triggering(indio_dev);
	if (ret)
		return ret;
	if (data->irq)
		disable_irq(data->irq);
	flush_delayed_work(&data->recover_work);

	ret = em7180_chip_suspend(data);
	if (ret) {
		if (data->irq)
			enable_irq(data->irq);
		em7180_resume_triggering(indio_dev);
	}

	return ret;
}

static int em7180_resume(struct device *dev)
{
	struct iio_dev *indio_dev = dev_get_drvdata(dev);
	struct em7180_data *data = iio_priv(indio_dev);
	int ret;

	ret = em7180_chip_resume(data);
	if (data->irq)
		enable_irq(data->irq);
	em7180_resume_triggering(indio_dev);

	return ret;
}

EXPORT_NS_GPL_SIMPLE_DEV_PM_OPS(em7180_pm_ops, em7180_suspend, em7180_resume,
				IIO_EM7180);

MODULE_AUTHOR("The sentral project");
MODULE_DESCRIPTION("PNI SENtral / EM7180 sensor-fusion hub core driver");
MODULE_LICENSE("GPL");
