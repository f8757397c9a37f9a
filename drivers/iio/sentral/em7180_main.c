// SPDX-License-Identifier: GPL-2.0-only
/*
 * PNI SENtral / EM Microelectronic EM7180 sensor-fusion hub: quaternion and
 * scaled data in a register map (EM's em718x_registers.h, Sony's em718x).
 */

#include <linux/array_size.h>
#include <linux/bitmap.h>
#include <linux/bitops.h>
#include <linux/cleanup.h>
#include <linux/delay.h>
#include <linux/device.h>
#include <linux/errno.h>
#include <linux/firmware.h> /* upstream: param */
#include <linux/interrupt.h>
#include <linux/iopoll.h>
#include <linux/jiffies.h> /* upstream: param */
#include <linux/limits.h>
#include <linux/lockdep.h>
#include <linux/math.h>
#include <linux/minmax.h>
#include <linux/module.h>
#include <linux/mutex.h>
#include <linux/pm.h>
#include <linux/regmap.h>
#include <linux/regulator/consumer.h>
#include <linux/slab.h> /* upstream: param */
#include <linux/string.h>
#include <linux/sysfs.h>
#include <linux/types.h>
#include <linux/wait.h> /* upstream: param */

#include <linux/iio/buffer.h>
#include <linux/iio/iio.h>
#include <linux/iio/sysfs.h> /* upstream: cal */
#include <linux/iio/trigger.h>
#include <linux/iio/trigger_consumer.h>
#include <linux/iio/triggered_buffer.h>

#include <kunit/visibility.h>

#include "em7180.h"
#include "em7180_compat.h"
#include "em7180_core.h"

#define EM7180_REG_QTIME		0x10
#define EM7180_REG_MX			0x12
#define EM7180_REG_AX			0x1A
#define EM7180_REG_GX			0x22
#define EM7180_REG_ACTUAL_MAG_RATE	0x45
#define EM7180_REG_ACTUAL_ACCEL_RATE	0x46
#define EM7180_REG_ACTUAL_GYRO_RATE	0x47
#define EM7180_REG_PRODUCT_ID		0x90
#define EM7180_REG_RUN_STATUS		0x92
#define EM7180_REG_SCL_LOW_CYCLES	0x9F /* upstream: passthru */

#define EM7180_PRODUCT_ID		0x80
#define EM7180_REVISION_ID		0x02

#define EM7180_EVENT_QUAT		BIT(2)
#define EM7180_EVENT_MAG		BIT(3)
#define EM7180_EVENT_ACCEL		BIT(4)
#define EM7180_EVENT_GYRO		BIT(5)
#define EM7180_EVENT_DATA		GENMASK(6, 2)
#define EM7180_EVENT_ALWAYS		(EM7180_EVENT_CPU_RESET | EM7180_EVENT_ERROR)

#define EM7180_SENTRAL_UPLOAD_ERR	BIT(2)
#define EM7180_SENTRAL_NO_EEPROM	BIT(4)

/* upstream: param { */
#define EM7180_WS_FIRST_PARAM		1
#define EM7180_ACCEL_OFFSET_PARAM	27
/* upstream: } */

/* Q14 in s16, as bno055: IIO prints nine decimals, 2^-30 would be 0 */
#define EM7180_QUAT_FRAC_BITS		14

/* EM's em718x_core.c allows 4 s for the firmware upload */
#define EM7180_UPLOAD_POLL_US		10000
#define EM7180_UPLOAD_TIMEOUT_US	4000000
#define EM7180_STANDBY_POLL_US		1000
#define EM7180_STANDBY_TIMEOUT_US	1000000
#define EM7180_ALIVE_TIMEOUT_US		50000 /* upstream: health */
/* Power-on reset; then the chip may not acknowledge for a while */
#define EM7180_POWER_ON_US		10000
#define EM7180_READY_POLL_US		5000
#define EM7180_READY_TIMEOUT_US		200000
#define EM7180_EVENT_READ_TRIES		3
/* upstream: param { */
/* The slowest scan period (magnetometer at 1 Hz), and scans to wait for */
#define EM7180_SCAN_WAIT_MS		1100
#define EM7180_SCAN_WAIT_TRIES		8
/* upstream: } */

enum em7180_scan {
	EM7180_SCAN_QUAT,
	EM7180_SCAN_MAGN_X, EM7180_SCAN_MAGN_Y, EM7180_SCAN_MAGN_Z,
	EM7180_SCAN_ACCEL_X, EM7180_SCAN_ACCEL_Y, EM7180_SCAN_ACCEL_Z,
	EM7180_SCAN_ANGLVEL_X, EM7180_SCAN_ANGLVEL_Y, EM7180_SCAN_ANGLVEL_Z,
	/* Feature sensors (em7180_feature.c) from here, then the timestamp */
	EM7180_SCAN_TIMESTAMP,
};

static const struct regmap_range em7180_readable_ranges[] = {
	regmap_reg_range(EM7180_REG_QX, EM7180_REG_ERROR),
	regmap_reg_range(EM7180_REG_ALGO_CTRL, EM7180_REG_PARAM_REQ),
	regmap_reg_range(EM7180_REG_ROM_VERSION, EM7180_REG_RAM_VERSION + 1),
	regmap_reg_range(EM7180_REG_PRODUCT_ID, EM7180_REG_RUN_STATUS),
	/* upstream: upload { */
	/* UploadData too: regmap writes only readable registers noinc */
	regmap_reg_range(EM7180_REG_UPLOAD_ADDR, EM7180_REG_CRC_HOST + 3),
	/* upstream: } */
	/* upstream: passthru { */
	regmap_reg_range(EM7180_REG_PASSTHRU_STATUS, EM7180_REG_PASSTHRU_CTRL),
	/* upstream: } */
};

static const struct regmap_access_table em7180_readable_table = {
	.yes_ranges = em7180_readable_ranges,
	.n_yes_ranges = ARRAY_SIZE(em7180_readable_ranges),
};

static const struct regmap_range em7180_writeable_ranges[] = {
	regmap_reg_range(EM7180_REG_QRATE_DIVISOR, EM7180_REG_HOST_CTRL),
	regmap_reg_range(EM7180_REG_ALGO_CTRL, EM7180_REG_PARAM_REQ),
	regmap_reg_range(EM7180_REG_UPLOAD_ADDR, EM7180_REG_UPLOAD_DATA), /* upstream: upload */
	regmap_reg_range(EM7180_REG_RESET_REQ, EM7180_REG_RESET_REQ),
	/* upstream: passthru { */
	regmap_reg_range(EM7180_REG_SCL_LOW_CYCLES, EM7180_REG_PASSTHRU_CTRL),
	/* upstream: } */
};

static const struct regmap_access_table em7180_writeable_table = {
	.yes_ranges = em7180_writeable_ranges,
	.n_yes_ranges = ARRAY_SIZE(em7180_writeable_ranges),
};

/* upstream: upload { */
/* The firmware upload streams its text into UploadData */
static const struct regmap_range em7180_noinc_ranges[] = {
	regmap_reg_range(EM7180_REG_UPLOAD_DATA, EM7180_REG_UPLOAD_DATA),
};

static const struct regmap_access_table em7180_noinc_table = {
	.yes_ranges = em7180_noinc_ranges,
	.n_yes_ranges = ARRAY_SIZE(em7180_noinc_ranges),
};

/* upstream: } */
/* Only the host's configuration registers keep what was written to them */
static const struct regmap_range em7180_cached_ranges[] = {
	regmap_reg_range(EM7180_REG_QRATE_DIVISOR, EM7180_REG_HOST_CTRL),
	regmap_reg_range(EM7180_REG_ALGO_CTRL, 0x5F),
	/* upstream: passthru { */
	regmap_reg_range(EM7180_REG_SCL_LOW_CYCLES, EM7180_REG_PASSTHRU_CTRL),
	/* upstream: } */
};

static const struct regmap_access_table em7180_volatile_table = {
	.no_ranges = em7180_cached_ranges,
	.n_no_ranges = ARRAY_SIZE(em7180_cached_ranges),
};

static const struct regmap_range em7180_precious_ranges[] = {
	regmap_reg_range(EM7180_REG_EVENT_STATUS, EM7180_REG_EVENT_STATUS),
	regmap_reg_range(EM7180_REG_CAL_FLAGS, EM7180_REG_CAL_FLAGS),
	regmap_reg_range(EM7180_REG_UPLOAD_DATA, EM7180_REG_UPLOAD_DATA), /* upstream: upload */
};

static const struct regmap_access_table em7180_precious_table = {
	.yes_ranges = em7180_precious_ranges,
	.n_yes_ranges = ARRAY_SIZE(em7180_precious_ranges),
};

const struct regmap_config em7180_regmap_config = {
	.name = "em7180",
	.reg_bits = 8,
	.val_bits = 8,
	.max_register = EM7180_REG_PASSTHRU_CTRL, /* upstream: passthru */
	/* upstream: !passthru: .max_register = EM7180_REG_RESET_REQ, */
	.rd_table = &em7180_readable_table,
	.wr_table = &em7180_writeable_table,
	.wr_noinc_table = &em7180_noinc_table, /* upstream: upload */
	.volatile_table = &em7180_volatile_table,
	.precious_table = &em7180_precious_table,
	/* The tree caches drop a register whose write failed, and its neighbour */
	.cache_type = REGCACHE_FLAT,
};
EXPORT_SYMBOL_NS_GPL(em7180_regmap_config, "IIO_EM7180");

static const int em7180_accel_gyro_freq_avail[] = { 10, 20, 50, 100, 200, 500, 1000 };
static const int em7180_magn_freq_avail[] = { 1, 10, 20, 30, 50, 100 };

struct em7180_sensor {
	enum iio_chan_type type;
	unsigned int rate_reg;
	unsigned int actual_reg;
	unsigned int hz_per_lsb;
	unsigned int event;
	unsigned int scan_first;
	int scale_nano;
	const int *freq_avail;
	int n_freq_avail;
};

/* Scales as EM's driver_ext.h and the USFS host libraries have them */
static const struct em7180_sensor em7180_sensors[] = {
	/* The gyroscope first: it wins a tie for pacing the scans */
	{ IIO_ANGL_VEL, EM7180_REG_GYRO_RATE, EM7180_REG_ACTUAL_GYRO_RATE, 10,
	  EM7180_EVENT_GYRO, EM7180_SCAN_ANGLVEL_X, 2663372,	/* 0.1526 dps */
	  em7180_accel_gyro_freq_avail, ARRAY_SIZE(em7180_accel_gyro_freq_avail) },
	{ IIO_ACCEL, EM7180_REG_ACCEL_RATE, EM7180_REG_ACTUAL_ACCEL_RATE, 10,
	  EM7180_EVENT_ACCEL, EM7180_SCAN_ACCEL_X, 4785645,	/* 0.000488 g */
	  em7180_accel_gyro_freq_avail, ARRAY_SIZE(em7180_accel_gyro_freq_avail) },
	{ IIO_MAGN, EM7180_REG_MAG_RATE, EM7180_REG_ACTUAL_MAG_RATE, 1,
	  EM7180_EVENT_MAG, EM7180_SCAN_MAGN_X, 305176,		/* 0.0305 uT */
	  em7180_magn_freq_avail, ARRAY_SIZE(em7180_magn_freq_avail) },
};

static const struct em7180_sensor *em7180_sensor_of(enum iio_chan_type type)
{
	unsigned int i;

	for (i = 0; i < ARRAY_SIZE(em7180_sensors) - 1; i++)
		if (em7180_sensors[i].type == type)
			break;

	return &em7180_sensors[i];
}

static const struct iio_mount_matrix *
em7180_get_mount_matrix(const struct iio_dev *indio_dev, const struct iio_chan_spec *chan)
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
	.info_mask_shared_by_type = BIT(IIO_CHAN_INFO_SCALE) | BIT(IIO_CHAN_INFO_SAMP_FREQ), \
	.info_mask_shared_by_type_available = BIT(IIO_CHAN_INFO_SAMP_FREQ),	\
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
		.info_mask_separate = BIT(IIO_CHAN_INFO_RAW) | BIT(IIO_CHAN_INFO_SCALE),
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
			   BIT(IIO_CHAN_INFO_CALIBBIAS)), /* upstream: param */
			   /* upstream: !param: 0), */
	EM7180_VEC_CHANNEL(IIO_ACCEL, Y, EM7180_REG_AX + 2, EM7180_SCAN_ACCEL_Y,
			   BIT(IIO_CHAN_INFO_CALIBBIAS)), /* upstream: param */
			   /* upstream: !param: 0), */
	EM7180_VEC_CHANNEL(IIO_ACCEL, Z, EM7180_REG_AX + 4, EM7180_SCAN_ACCEL_Z,
			   BIT(IIO_CHAN_INFO_CALIBBIAS)), /* upstream: param */
			   /* upstream: !param: 0), */
	EM7180_VEC_CHANNEL(IIO_ANGL_VEL, X, EM7180_REG_GX, EM7180_SCAN_ANGLVEL_X, 0),
	EM7180_VEC_CHANNEL(IIO_ANGL_VEL, Y, EM7180_REG_GX + 2, EM7180_SCAN_ANGLVEL_Y, 0),
	EM7180_VEC_CHANNEL(IIO_ANGL_VEL, Z, EM7180_REG_GX + 4, EM7180_SCAN_ANGLVEL_Z, 0),
	IIO_CHAN_SOFT_TIMESTAMP(EM7180_SCAN_TIMESTAMP),
};

/* round(float32 * 2^frac_bits), halves away from zero, saturated; NaN 0 */
s32 em7180_float_to_fixed(u32 bits, unsigned int frac_bits)
{
	int e = (bits & EM7180_F32_EXP_MASK) >> EM7180_F32_FRAC_BITS;
	bool neg = bits & EM7180_F32_SIGN;
	u32 mant = bits & EM7180_F32_FRAC_MASK;
	u32 val;
	int shift;

	if (e == 0xff && mant)
		return 0;
	/* |value| >= 2^(31 - frac_bits) does not fit */
	if (e >= EM7180_F32_BIAS + 31 - (int)frac_bits)
		return neg ? S32_MIN : S32_MAX;
	if (!e)
		return 0;	/* below 2^-126 */

	/* value * 2^frac_bits = mant * 2^-shift with the hidden bit in mant */
	mant |= BIT(EM7180_F32_FRAC_BITS);
	shift = EM7180_F32_BIAS + EM7180_F32_FRAC_BITS - (int)frac_bits - e;
	if (shift <= 0)
		val = mant << -shift;
	else if (shift > 25)
		val = 0;
	else
		val = (mant + BIT(shift - 1)) >> shift;

	return neg ? -(s32)val : (s32)val;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_float_to_fixed);

/* One quaternion component, float32 from the chip, as Q14 in an s16 */
static s16 em7180_quat_component(const u8 *src)
{
	s32 q = em7180_float_to_fixed(get_unaligned_le32(src), EM7180_QUAT_FRAC_BITS);

	return clamp_t(s32, q, S16_MIN, S16_MAX);
}

/* The driver's lock, once a transfer behind the hub has ended */
void em7180_lock(struct em7180_data *data)
{
	mutex_lock(&data->lock);
	/* upstream: passthru { */
	while (data->passthru) {
		mutex_unlock(&data->lock);
		wait_event(data->wq, !READ_ONCE(data->passthru));
		mutex_lock(&data->lock);
	}
	/* upstream: } */
}
EXPORT_SYMBOL_IF_KUNIT(em7180_lock);

/* upstream: param { */
/**
 * em7180_resumed() - the chip runs again after a pause
 * @data: driver state, with @data->lock held
 *
 * A parameter transfer or passthrough paused the fusion: a scan stamped
 * before now may find a newer sample (em7180_scan()).
 */
void em7180_resumed(struct em7180_data *data)
{
	lockdep_assert_held(&data->lock);
	data->resumed = iio_get_time_ns(dev_get_drvdata(data->dev));
}

/* upstream: } */

/* The actual rate; the requested one until the sensor has started */
static int em7180_read_freq(struct em7180_data *data, const struct em7180_sensor *s, int *val)
{
	unsigned int rate;
	int ret;

	scoped_guard(em7180, data) {
		ret = regmap_read(data->regmap, s->actual_reg, &rate);
		if (!ret && !rate)
			ret = regmap_read(data->regmap, s->rate_reg, &rate);
	}
	if (ret)
		return ret;

	*val = rate * s->hz_per_lsb;
	return IIO_VAL_INT;
}

static int em7180_write_freq(struct em7180_data *data, const struct em7180_sensor *s, int val)
{
	int i;

	for (i = 0; i < s->n_freq_avail; i++)
		if (s->freq_avail[i] == val)
			break;
	if (i == s->n_freq_avail)
		return -EINVAL;

	guard(em7180)(data);
	return regmap_write(data->regmap, s->rate_reg, val / s->hz_per_lsb);
}

/* upstream: param { */
/*
 * Parameters 27..29 change only when the host writes them: calibbias is
 * served from a copy, so that a reader of the world-readable attribute
 * cannot pause the fusion algorithm with a parameter transfer.
 */
static int em7180_accel_offset_fetch(struct em7180_data *data)
{
	int ret;

	lockdep_assert_held(&data->lock);

	ret = em7180_params_read(data, EM7180_ACCEL_OFFSET_PARAM, ARRAY_SIZE(data->accel_offset),
				 data->accel_offset);
	data->accel_offset_valid = !ret;

	return ret;
}

/* After a failed transfer the chip may hold other offsets; not after a timeout */
static void em7180_accel_offset_refresh(struct em7180_data *data, int err)
{
	data->accel_offset_valid = false;
	if (err != -ETIMEDOUT)
		em7180_accel_offset_fetch(data);
}

/* A warm start the chip now has: kept for a power loss, offsets with it */
static void em7180_ws_set(struct em7180_data *data, const u32 *vals)
{
	unsigned int i;

	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		put_unaligned_le32(vals[i], &data->ws[4 * i]);
	data->ws_valid = true;
	memcpy(data->accel_offset, &vals[EM7180_ACCEL_OFFSET_PARAM - EM7180_WS_FIRST_PARAM],
	       sizeof(data->accel_offset));
	data->accel_offset_valid = true;
}

/**
 * em7180_read_calibbias() - an accelerometer offset, from the driver's copy
 * @data: driver state
 * @axis: 0 to 2 for x, y, z
 * @val: where to store the offset in LSB
 *
 * Return: 0, -ENODATA while the copy is unknown, -ERANGE for a value that
 * is no offset.
 */
int em7180_read_calibbias(struct em7180_data *data, unsigned int axis, int *val)
{
	guard(em7180)(data);
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
 * The offsets are read back when the copy is unknown or the write failed.
 *
 * Return: 0, -EINVAL for a value out of range, or the transfer's error.
 */
int em7180_write_calibbias(struct em7180_data *data, unsigned int axis, int val)
{
	unsigned int param = EM7180_ACCEL_OFFSET_PARAM + axis;
	u32 bits;
	int ret;

	if (val < S16_MIN || val > S16_MAX)
		return -EINVAL;

	bits = em7180_lsb_to_float_g(val);

	guard(em7180)(data);
	ret = em7180_params_write(data, param, 1, &bits);
	if (!ret && data->accel_offset_valid)
		data->accel_offset[axis] = bits;
	else
		em7180_accel_offset_refresh(data, ret);
	if (!ret && data->ws_valid)
		put_unaligned_le32(bits, &data->ws[(param - EM7180_WS_FIRST_PARAM) * 4]);

	return ret;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_write_calibbias);

/* upstream: } */
static int em7180_read_raw(struct em7180_data *data, const struct iio_chan_spec *chan, int *vals)
{
	bool quat = chan->type == IIO_ROT;
	u8 raw[16];
	int i, ret;

	scoped_guard(em7180, data) {
		em7180_check_status(data); /* upstream: health */
		ret = regmap_bulk_read(data->regmap, chan->address, raw, quat ? 16 : 2);
	}
	if (ret)
		return ret;

	if (!quat) {
		vals[0] = (s16)get_unaligned_le16(raw);
		return IIO_VAL_INT;
	}
	/* x, y, z, w: register order, which is also the ABI order */
	for (i = 0; i < 4; i++)
		vals[i] = em7180_quat_component(&raw[4 * i]);

	return IIO_VAL_INT_MULTIPLE;
}

static int em7180_read_raw_multi(struct iio_dev *indio_dev, const struct iio_chan_spec *chan,
				 int max_len, int *vals, int *val_len, long mask)
{
	struct em7180_data *data = iio_priv(indio_dev);
	/* upstream: feature { */
	const struct em7180_feature *f = em7180_feature_find(data, chan->type);
	/* upstream: } */
	int ret;

	*val_len = 2;
	/* upstream: feature { */
	if (f && mask != IIO_CHAN_INFO_RAW)
		return em7180_feature_read_info(data, f, vals, mask);
	/* upstream: } */

	switch (mask) {
	case IIO_CHAN_INFO_RAW:
		if (chan->type == IIO_ROT) {
			if (max_len < 4)
				return -EINVAL;
			*val_len = 4;
		}
		if (!iio_device_claim_direct(indio_dev))
			return -EBUSY;
		ret = em7180_read_raw(data, chan, vals);
		iio_device_release_direct(indio_dev);
		return ret;
	case IIO_CHAN_INFO_SCALE:
		if (chan->type == IIO_ROT) {
			vals[0] = 1;
			vals[1] = EM7180_QUAT_FRAC_BITS;
			return IIO_VAL_FRACTIONAL_LOG2;
		}
		vals[0] = 0;
		vals[1] = em7180_sensor_of(chan->type)->scale_nano;
		return IIO_VAL_INT_PLUS_NANO;
	case IIO_CHAN_INFO_SAMP_FREQ:
		return em7180_read_freq(data, em7180_sensor_of(chan->type), vals);
	/* upstream: param { */
	case IIO_CHAN_INFO_CALIBBIAS:
		ret = em7180_read_calibbias(data, (chan->address - EM7180_REG_AX) / 2, vals);
		return ret ?: IIO_VAL_INT;
	/* upstream: } */
	default:
		return -EINVAL;
	}
}

static int em7180_read_avail(struct iio_dev *indio_dev, const struct iio_chan_spec *chan,
			     const int **vals, int *type, int *length, long mask)
{
	const struct em7180_sensor *s = em7180_sensor_of(chan->type);

	if (mask != IIO_CHAN_INFO_SAMP_FREQ)
		return -EINVAL;
	/* upstream: feature { */
	if (em7180_feature_find(iio_priv(indio_dev), chan->type))
		return em7180_feature_read_avail(vals, type, length);
	/* upstream: } */

	*type = IIO_VAL_INT;
	*vals = s->freq_avail;
	*length = s->n_freq_avail;
	return IIO_AVAIL_LIST;
}

static int em7180_write_raw(struct iio_dev *indio_dev, const struct iio_chan_spec *chan, int val,
			    int val2, long mask)
{
	struct em7180_data *data = iio_priv(indio_dev);
	/* upstream: feature { */
	const struct em7180_feature *f = em7180_feature_find(data, chan->type);
	/* upstream: } */
	int ret;

	if (val2)
		return -EINVAL;

	if (!iio_device_claim_direct(indio_dev))
		return -EBUSY;

	switch (mask) {
	case IIO_CHAN_INFO_SAMP_FREQ:
		/* upstream: feature { */
		ret = f ? em7180_feature_write_freq(data, f, val) :
		      em7180_write_freq(data, em7180_sensor_of(chan->type), val);
		/* upstream: } */
		/* upstream: !feature: ret = em7180_write_freq(data, */
		/* upstream: !feature:			em7180_sensor_of(chan->type), val); */
		break;
	/* upstream: param { */
	case IIO_CHAN_INFO_CALIBBIAS:
		ret = em7180_write_calibbias(data, (chan->address - EM7180_REG_AX) / 2, val);
		break;
	/* upstream: } */
	default:
		ret = -EINVAL;
		break;
	}

	iio_device_release_direct(indio_dev);
	return ret;
}

static int em7180_write_raw_get_fmt(struct iio_dev *indio_dev, struct iio_chan_spec const *chan,
				    long mask)
{
	return IIO_VAL_INT;
}

/* As bno055's firmware_version: in debugfs and once at probe */
void em7180_id_line(struct em7180_data *data, char *buf, size_t len)
{
	scnprintf(buf, len,
		  "ProductID 0x%02x RevisionID 0x%02x ROM 0x%04x RAM 0x%04x %s",
		  data->product_id, data->revision_id, data->rom_version,
		  data->ram_version, data->fw ? "host" : "eeprom"); /* upstream: upload */
		  /* upstream: !upload: data->ram_version, "eeprom"); */
}

/* upstream: param { */
static void em7180_caldata_id(struct em7180_data *data, struct em7180_caldata_id *id)
{
	*id = (struct em7180_caldata_id) {
		.format = EM7180_CALDATA_FORMAT,
		.product_id = data->product_id,
		.revision_id = data->revision_id,
		.rom_version = cpu_to_le16(data->rom_version),
		.ram_version = cpu_to_le16(data->ram_version),
	};
}

/*
 * A warm start of other firmware would mislead the fusion: refused before
 * the chip is touched, both identities said. @src names the blob's origin.
 */
static int em7180_caldata_match(struct em7180_data *data, const struct em7180_caldata *cal,
				const char *src)
{
	struct em7180_caldata_id id;

	lockdep_assert_held(&data->lock);

	em7180_caldata_id(data, &id);
	if (!memcmp(&cal->id, &id, sizeof(id)))
		return 0;

	dev_warn_ratelimited(data->dev,
			     "%s of %02x/%02x ROM %04x RAM %04x v%u refused: chip %02x/%02x ROM %04x RAM %04x\n",
			     src, cal->id.product_id, cal->id.revision_id,
			     le16_to_cpu(cal->id.rom_version),
			     le16_to_cpu(cal->id.ram_version), cal->id.format,
			     id.product_id, id.revision_id, data->rom_version,
			     data->ram_version);
	return -EINVAL;
}

/* A checked blob to the chip, if its own: kept for a power loss once written */
static int em7180_caldata_write(struct em7180_data *data, const struct em7180_caldata *cal,
				const char *src)
{
	u32 vals[EM7180_WS_NUM_PARAMS];
	unsigned int i;
	int ret;

	ret = em7180_caldata_match(data, cal, src);
	if (ret)
		return ret;

	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		vals[i] = le32_to_cpu(cal->params[i]);
	ret = em7180_params_write(data, EM7180_WS_FIRST_PARAM, EM7180_WS_NUM_PARAMS, vals);
	if (ret) {
		em7180_accel_offset_refresh(data, ret);
		return ret;
	}

	em7180_ws_set(data, vals);
	em7180_cal_saved(data); /* upstream: cal */
	return 0;
}

/* upstream: } */
/* upstream: cal { */
static IIO_DEVICE_ATTR(in_magn_calibration_auto_status, 0444,
		       em7180_cal_show, NULL, EM7180_CAL_ATTR_LEVEL);
static IIO_DEVICE_ATTR(in_magn_calibration_score, 0444,
		       em7180_cal_show, NULL, EM7180_CAL_ATTR_SCORE);
static IIO_DEVICE_ATTR(in_anglvel_calibration_update, 0444, em7180_cal_show,
		       NULL, EM7180_CAL_ATTR_GBIAS_UPDATE);
static IIO_DEVICE_ATTR(in_magn_calibration_update, 0444, em7180_cal_show,
		       NULL, EM7180_CAL_ATTR_MAG_UPDATE);
/* upstream: } */

/* upstream: param { */
/**
 * em7180_warmstart_check() - validate a calibration_data attribute access
 * @buf: the blob, for a write
 * @off: file offset of the access
 * @count: size of the access
 * @write: true for a write, whose payload is checked as well
 *
 * A read must start at 0 with room for the whole blob; a write must be the
 * whole blob with 35 finite floats. Its identity is the caller's to check.
 *
 * Return: 0 or -EINVAL.
 */
int em7180_warmstart_check(const u8 *buf, loff_t off, size_t count, bool write)
{
	const struct em7180_caldata *cal = (const void *)buf;
	unsigned int i;

	if (off || count < EM7180_CALDATA_SIZE || (write && count != EM7180_CALDATA_SIZE))
		return -EINVAL;
	for (i = 0; write && i < EM7180_WS_NUM_PARAMS; i++)
		if (!em7180_float_is_finite(le32_to_cpu(cal->params[i])))
			return -EINVAL;

	return 0;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_warmstart_check);

/**
 * em7180_warmstart_read() - read the warm start from the chip
 * @data: driver state, with @data->lock held
 * @cal: where to put it, with the identity the driver holds
 *
 * A word that is no finite float would make a blob the write path refuses:
 * the read fails instead, and the copy kept for a power loss stays valid.
 *
 * Return: 0, -EIO for such a word (logged), or the transfer's error.
 */
VISIBLE_IF_KUNIT int em7180_warmstart_read(struct em7180_data *data, struct em7180_caldata *cal)
{
	u32 vals[EM7180_WS_NUM_PARAMS];
	unsigned int i;
	int ret;

	lockdep_assert_held(&data->lock);

	ret = em7180_params_read(data, EM7180_WS_FIRST_PARAM, EM7180_WS_NUM_PARAMS, vals);
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

	em7180_ws_set(data, vals);
	em7180_caldata_id(data, &cal->id);
	memcpy(cal->params, data->ws, EM7180_WS_SIZE);
	return 0;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_warmstart_read);

/*
 * Works while a buffer runs, so that streaming never blocks a save. While
 * the chip's own trigger paces the capture the transfer starts right after
 * a scan, so that its pause falls between two samples and loses none, and
 * again after the next scan when another pause came since.
 */
static ssize_t calibration_data_read(struct file *filp, struct kobject *kobj,
				     em7180_bin_attribute *attr, char *buf,
				     loff_t off, size_t count)
{
	struct iio_dev *indio_dev = dev_to_iio_dev(kobj_to_dev(kobj));
	struct em7180_data *data = iio_priv(indio_dev);
	unsigned int tries = EM7180_SCAN_WAIT_TRIES;
	long ret;
	s64 ts;

	if (off >= EM7180_CALDATA_SIZE)
		return 0;

	ret = em7180_warmstart_check(buf, off, count, false);
	if (ret)
		return ret;

	for (;;) {
		ts = READ_ONCE(data->scan_ts);
		ret = wait_event_killable_timeout(data->wq,
						  READ_ONCE(data->scan_ts) != ts ||
						  !READ_ONCE(data->pace_event),
						  msecs_to_jiffies(EM7180_SCAN_WAIT_MS));
		if (ret < 0)
			return ret;

		guard(em7180)(data);
		if (data->pace_event && data->resumed > data->scan_ts && --tries)
			continue;

		ret = em7180_warmstart_read(data, (void *)buf);
		if (ret)
			return ret;
		em7180_cal_saved(data); /* upstream: cal */
		return EM7180_CALDATA_SIZE;
	}
}

/**
 * em7180_warmstart_restore() - write a warm start blob to the chip
 * @indio_dev: the IIO device
 * @buf: the blob
 * @off: file offset of the write
 * @count: size of the write
 *
 * Refused while a buffer runs: a restore replaces the state the fusion is
 * tracking with, which belongs before the sensors start, as at probe.
 *
 * Return: 0, -EINVAL for a bad blob, size or offset or another chip's or
 * firmware's blob, -EBUSY while a buffer is enabled, or the error of the
 * parameter transfer.
 */
int em7180_warmstart_restore(struct iio_dev *indio_dev, const u8 *buf, loff_t off, size_t count)
{
	struct em7180_data *data = iio_priv(indio_dev);
	int ret;

	ret = em7180_warmstart_check(buf, off, count, true);
	if (ret)
		return ret;

	if (!iio_device_claim_direct(indio_dev))
		return -EBUSY;

	scoped_guard(em7180, data)
		ret = em7180_caldata_write(data, (const void *)buf, "calibration_data");

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

/* Size 0: sysfs would cut a longer write down to a valid-looking blob */
static BIN_ATTR_ADMIN_RW(calibration_data, 0);

/* upstream: } */
/* upstream: cal { */
static struct attribute *em7180_attrs[] = {
	&iio_dev_attr_in_magn_calibration_auto_status.dev_attr.attr,
	&iio_dev_attr_in_magn_calibration_score.dev_attr.attr,
	&iio_dev_attr_in_anglvel_calibration_update.dev_attr.attr,
	&iio_dev_attr_in_magn_calibration_update.dev_attr.attr,
	NULL
};

/* upstream: } */
/* upstream: param { */
static em7180_bin_attribute *em7180_bin_attr_const em7180_bin_attrs[] = {
	&bin_attr_calibration_data,
	NULL
};

/* upstream: } */
/* upstream: cal { */
/* Asked once, at registration: the calibration registers, per firmware */
static umode_t em7180_attr_is_visible(struct kobject *kobj, struct attribute *attr, int n)
{
	struct em7180_data *data = iio_priv(dev_to_iio_dev(kobj_to_dev(kobj)));
	struct device_attribute *dattr = container_of(attr, struct device_attribute, attr);

	if (dattr->show == em7180_cal_show && !data->appnote_attrs &&
	    to_iio_dev_attr(dattr)->address != EM7180_CAL_ATTR_LEVEL)
		return 0;

	return attr->mode;
}

/* upstream: } */
/* upstream: param { */
static const struct attribute_group em7180_attr_group = {
	.attrs = em7180_attrs, /* upstream: cal */
	.bin_attrs = em7180_bin_attrs,
	.is_visible = em7180_attr_is_visible, /* upstream: cal */
};

/* upstream: } */

/* A read of a clear-on-read register would take an event or a flag away */
static int em7180_debugfs_reg_access(struct iio_dev *indio_dev, unsigned int reg,
				     unsigned int writeval, unsigned int *readval)
{
	struct em7180_data *data = iio_priv(indio_dev);

	guard(em7180)(data);
	if (!readval)
		return regmap_write(data->regmap, reg, writeval);
	if (regmap_reg_in_ranges(reg, em7180_precious_ranges, ARRAY_SIZE(em7180_precious_ranges)))
		return -EPERM;

	return regmap_read(data->regmap, reg, readval);
}

static const struct iio_info em7180_info = {
	.read_raw_multi = em7180_read_raw_multi,
	.read_avail = em7180_read_avail,
	.write_raw = em7180_write_raw,
	.write_raw_get_fmt = em7180_write_raw_get_fmt,
	.debugfs_reg_access = em7180_debugfs_reg_access,
	.attrs = &em7180_attr_group, /* upstream: param */
};

/* One burst up to the last sensor's TIME; 0 for the timestamp alone */
static unsigned int em7180_scan_span(struct iio_dev *indio_dev, const unsigned long *mask,
				     unsigned int *start)
{
	struct em7180_data *data = iio_priv(indio_dev); /* upstream: feature */
	const struct iio_chan_spec *chans = indio_dev->channels;
	unsigned int n = EM7180_SCAN_TIMESTAMP + data->n_features; /* upstream: feature */
	/* upstream: !feature: unsigned int n = EM7180_SCAN_TIMESTAMP; */
	unsigned int lo = find_first_bit(mask, n);
	unsigned int hi = find_last_bit(mask, n);
	unsigned int end = EM7180_REG_MX;

	if (lo >= n)
		return 0;

	/* upstream: feature { */
	if (hi >= EM7180_SCAN_TIMESTAMP)
		end = em7180_feature_find(data, chans[hi].type)->end_reg;
	else if (hi != EM7180_SCAN_QUAT)
	/* upstream: } */
	/* upstream: !feature: if (hi != EM7180_SCAN_QUAT) */
		end += round_up(chans[hi].address + 1 - EM7180_REG_MX, 8);
	*start = chans[lo].address;
	return end - *start;
}

/*
 * With the chip's own trigger (@own) a sample that came between the
 * EventStatus read and the burst is found again by its own interrupt, TIME
 * included: it is not pushed twice.
 */
static void em7180_scan(struct iio_dev *indio_dev, s64 ts, bool own)
{
	struct em7180_data *data = iio_priv(indio_dev);
	const unsigned long *mask = indio_dev->active_scan_mask;
	unsigned int bit, start = 0, len, at = data->pace_time;
	const u8 *src;
	__le16 *word;
	int i;

	lockdep_assert_held(&data->lock);

	/* upstream: param { */
	if (ts < data->resumed)
		return;
	/* upstream: } */
	len = em7180_scan_span(indio_dev, mask, &start);
	if (len && regmap_bulk_read(data->regmap, start, data->burst, len))
		return;
	if (own && at >= start && at + 2 <= start + len) {
		i = get_unaligned_le16(&data->burst[at - start]);
		if (i == data->last_time)
			return;
		data->last_time = i;
	}

	word = test_bit(EM7180_SCAN_QUAT, mask) ? data->scan.q.words :
						  data->scan.words;
	/* upstream: feature { */
	for_each_set_bit(bit, mask, EM7180_SCAN_TIMESTAMP + data->n_features) {
	/* upstream: } */
	/* upstream: !feature: for_each_set_bit(bit, mask, EM7180_SCAN_TIMESTAMP) { */
		src = &data->burst[indio_dev->channels[bit].address - start];
		if (bit != EM7180_SCAN_QUAT) {
			memcpy(word++, src, sizeof(*word));
			continue;
		}
		for (i = 0; i < 4; i++)
			data->scan.q.quat[i] = em7180_quat_component(&src[4 * i]);
	}
	iio_push_to_buffers_with_ts(indio_dev, &data->scan, sizeof(data->scan), ts);
	/* upstream: param { */
	if (own)
		WRITE_ONCE(data->scan_ts, ts);
	/* upstream: } */
}

/* With the chip's own trigger, nested in em7180_irq_thread(): lock held */
static irqreturn_t em7180_trigger_handler(int irq, void *p)
{
	struct iio_poll_func *pf = p;
	struct iio_dev *indio_dev = pf->indio_dev;
	struct em7180_data *data = iio_priv(indio_dev);

	/* Not iio_trigger_using_own(): the core sets that after enabling */
	if (data->trig && indio_dev->trig == data->trig) {
		em7180_scan(indio_dev, data->timestamp, true);
		wake_up_all(&data->wq); /* upstream: param */
	} else {
		scoped_guard(em7180, data)
			em7180_scan(indio_dev, pf->timestamp, false);
	}

	iio_trigger_notify_done(indio_dev->trig);
	return IRQ_HANDLED;
}

static irqreturn_t em7180_irq_handler(int irq, void *p)
{
	struct iio_dev *indio_dev = p;
	struct em7180_data *data = iio_priv(indio_dev);

	data->timestamp = iio_get_time_ns(indio_dev);
	return IRQ_WAKE_THREAD;
}

/* A lost read would leave an edge-triggered INT high for good: retried */
static int em7180_read_events(struct em7180_data *data, unsigned int *status)
{
	int ret, tries = EM7180_EVENT_READ_TRIES;

	do {
		ret = regmap_read(data->regmap, EM7180_REG_EVENT_STATUS, status);
	} while (ret && --tries);

	return ret;
}

static irqreturn_t em7180_irq_thread(int irq, void *p)
{
	struct iio_dev *indio_dev = p;
	struct em7180_data *data = iio_priv(indio_dev);
	unsigned int status;
	int ret;

	guard(mutex)(&data->lock);
	ret = em7180_read_events(data, &status);
	if (ret) {
		dev_err_ratelimited(data->dev, "cannot read EventStatus: %d\n", ret);
		return IRQ_HANDLED;
	}
	status &= EM7180_EVENT_ALWAYS | data->pace_event;
	if (!status)
		return IRQ_NONE;

	/* upstream: health { */
	if (status & EM7180_EVENT_ERROR)
		em7180_report_error(data);
	if (status & EM7180_EVENT_CPU_RESET)
		em7180_recover_schedule(data);
	else if (status & EM7180_EVENT_DATA && !data->passthru) /* upstream: passthru */
	/* upstream: !passthru: else if (status & EM7180_EVENT_DATA) */
	/* upstream: } */
	/* upstream: !health: if (status & EM7180_EVENT_DATA) */
		em7180_trigger_poll_nested(data->trig);

	return IRQ_HANDLED;
}

/* One scan per step: of the quaternion, else the fastest sensor captured */
static void em7180_pace(struct iio_dev *indio_dev, const unsigned long *mask)
{
	struct em7180_data *data = iio_priv(indio_dev);
	const struct em7180_sensor *s, *pace = em7180_sensors;
	unsigned int rate, best = 0;

	lockdep_assert_held(&data->lock);

	data->pace_event = EM7180_EVENT_QUAT;
	data->pace_time = EM7180_REG_QTIME;
	if (test_bit(EM7180_SCAN_QUAT, mask))
		return;

	for (s = em7180_sensors; s < em7180_sensors + ARRAY_SIZE(em7180_sensors); s++) {
		if (find_next_bit(mask, s->scan_first + 3, s->scan_first) >= s->scan_first + 3 ||
		    regmap_read(data->regmap, s->rate_reg, &rate) || rate * s->hz_per_lsb <= best)
			continue;
		best = rate * s->hz_per_lsb;
		pace = s;
	}
	data->pace_event = pace->event;
	data->pace_time = indio_dev->channels[pace->scan_first].address + 6;
	/* upstream: feature { */
	if (em7180_feature_pace(data, mask, best))
		data->pace_time = data->pace_feature->end_reg - 2;
	/* upstream: } */
}

static int em7180_trigger_set_state(struct iio_trigger *trig, bool state)
{
	struct iio_dev *indio_dev = iio_trigger_get_drvdata(trig);
	struct em7180_data *data = iio_priv(indio_dev);
	unsigned int status;
	int ret;

	scoped_guard(em7180, data) {
		data->pace_event = 0;
		data->last_time = -1;
		if (state)
			em7180_pace(indio_dev, indio_dev->active_scan_mask);
		/* upstream: param { */
		/* No scan comes any more: transfers waiting for one go ahead */
		else
			wake_up_all(&data->wq);
		/* upstream: } */
		ret = em7180_feature_report(data); /* upstream: feature */
		/* upstream: !feature: ret = 0; */
		/* A pending event keeps INT high: read before enabling */
		/* upstream: health { */
		if (!ret && state) {
			ret = em7180_read_events(data, &status);
			if (!ret && (status & EM7180_EVENT_CPU_RESET))
				ret = em7180_chip_recover(data);
		}
		/* upstream: } */
		/* upstream: !health: if (!ret && state) */
		/* upstream: !health:	ret = em7180_read_events(data, &status); */
		ret = ret ?: regmap_write(data->regmap, EM7180_REG_ENABLE_EVENTS,
					  EM7180_EVENT_ALWAYS | data->pace_event);
		/* Unhandled data interrupts get the line disabled: ask again */
		if (ret && !state)
			ret = regmap_write(data->regmap, EM7180_REG_ENABLE_EVENTS,
					   EM7180_EVENT_ALWAYS);
	}

	/* The core would keep the poll function: reported here */
	if (ret && !state) {
		dev_err(data->dev, "cannot turn the data interrupts off: %d\n", ret);
		return 0;
	}

	return ret;
}

static ssize_t sampling_frequency_show(struct device *dev, struct device_attribute *attr, char *buf)
{
	struct iio_dev *indio_dev = iio_trigger_get_drvdata(to_iio_trigger(dev));
	struct em7180_data *data = iio_priv(indio_dev);
	unsigned int i, event = READ_ONCE(data->pace_event);
	int ret, hz;

	for (i = ARRAY_SIZE(em7180_sensors) - 1; i; i--)
		if (em7180_sensors[i].event == event)
			break;

	/* upstream: feature { */
	if (event == EM7180_EVENT_FEATURE)
		ret = em7180_feature_read_freq(data, data->pace_feature, &hz);
	else
		ret = em7180_read_freq(data, &em7180_sensors[i], &hz);
	/* upstream: } */
	/* upstream: !feature: ret = em7180_read_freq(data, &em7180_sensors[i], &hz); */
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

	ret = devm_request_threaded_irq(dev, irq, em7180_irq_handler, em7180_irq_thread,
					IRQF_ONESHOT, indio_dev->name, indio_dev);
	if (ret)
		return dev_err_probe(dev, ret, "failed to request irq %d\n", irq);

	ret = devm_iio_trigger_register(dev, data->trig);
	if (ret)
		return dev_err_probe(dev, ret, "failed to register trigger\n");

	indio_dev->trig = iio_trigger_get(data->trig);

	return 0;
}

/* upstream: param { */
/* current_timestamp_clock may have changed since the last pause */
static int em7180_buffer_preenable(struct iio_dev *indio_dev)
{
	struct em7180_data *data = iio_priv(indio_dev);

	guard(em7180)(data);
	data->resumed = 0;
	return 0;
}

static const struct iio_buffer_setup_ops em7180_buffer_ops = {
	.preenable = em7180_buffer_preenable,
	.postenable = em7180_watch_start, /* upstream: health */
	.predisable = em7180_watch_stop, /* upstream: health */
};

/* upstream: } */
static int em7180_read_status(struct em7180_data *data, unsigned int *status)
{
	return regmap_read(data->regmap, EM7180_REG_SENTRAL_STATUS, status);
}

/* A resetting chip may not acknowledge: a bus error is one more poll */
static int em7180_wait_firmware(struct em7180_data *data, unsigned int *status)
{
	int ret, err;

	ret = read_poll_timeout(em7180_read_status, err,
				!err && (*status & (EM7180_SENTRAL_UPLOAD_DONE |
						    EM7180_SENTRAL_UPLOAD_ERR |
						    EM7180_SENTRAL_NO_EEPROM)),
				EM7180_UPLOAD_POLL_US, EM7180_UPLOAD_TIMEOUT_US, false, data,
				status);
	if (ret)
		return err ?: ret;
	if (*status & EM7180_SENTRAL_NO_EEPROM)
		return -ENODEV;
	return *status & EM7180_SENTRAL_UPLOAD_ERR ? -EIO : 0;
}

/* upstream: health { */
static int em7180_reset(struct em7180_data *data, const char *why, unsigned int status)
{
	dev_warn(data->dev, "%s (SentralStatus 0x%02x): resetting it\n", why, status);
	return regmap_write(data->regmap, EM7180_REG_RESET_REQ, EM7180_RESET_REQ_RESET);
}

/* The upload from EEPROM, reset once when it fails, as the USFS host libraries do */
static int em7180_wait_boot(struct em7180_data *data, unsigned int *status)
{
	int ret = em7180_wait_firmware(data, status);

	if (ret != -ETIMEDOUT && (ret != -EIO || !(*status & EM7180_SENTRAL_UPLOAD_ERR)))
		return ret;
	ret = em7180_reset(data, "firmware upload not done", *status);
	return ret ?: em7180_wait_firmware(data, status);
}

/*
 * A host reboot without a power cycle can leave the chip idle with its
 * firmware loaded until a ResetRequest (kriswiner/EM7180_SENtral_sensor_hub
 * issue 52): a chip that does not enter standby when HostControl is
 * cleared is reset.
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
	return em7180_wait_boot(data, status);
}

/* upstream: } */
/*
 * As em718x_core.c: configure with HostControl 0, then run. EventStatus
 * holds the upload's CPUReset: read, lest enabling it report a reset.
 */
static int em7180_chip_configure(struct em7180_data *data, bool from_cache)
{
	static const struct reg_sequence seq[] = {
		{ EM7180_REG_PARAM_REQ, 0 },
		{ EM7180_REG_ALGO_CTRL, 0 },
		{ EM7180_REG_MAG_RATE, 30 },
		{ EM7180_REG_ACCEL_RATE, 10 },		/* 100 Hz */
		{ EM7180_REG_GYRO_RATE, 10 },		/* 100 Hz */
		{ EM7180_REG_QRATE_DIVISOR, 0 },
		{ EM7180_REG_ENABLE_EVENTS, EM7180_EVENT_ALWAYS },
		{ EM7180_REG_HOST_CTRL, EM7180_HOST_CTRL_RUN },
	};
	unsigned int i, val;
	int ret;

	ret = em7180_feature_configure(data, from_cache); /* upstream: feature */
	/* upstream: !feature: ret = 0; */
	for (i = 0; i < ARRAY_SIZE(seq) && !ret; i++) {
		val = seq[i].def;
		if (from_cache && i >= 2)
			ret = regmap_read(data->regmap, seq[i].reg, &val);
		if (!ret)
			ret = regmap_write(data->regmap, seq[i].reg, val);
	}
	if (ret)
		return ret;

	return regmap_read(data->regmap, EM7180_REG_EVENT_STATUS, &val);
}

/* upstream: param { */
/* Supplies that stay on leave i2c-dev users the chip quiet but running */
static void em7180_unbind_action(void *arg)
{
	struct em7180_data *data = arg;
	static const struct reg_sequence seq[] = {
		{ EM7180_REG_ENABLE_EVENTS, 0 },
		{ EM7180_REG_PARAM_REQ, 0 },
		{ EM7180_REG_ALGO_CTRL, 0 },
	};

	guard(em7180)(data);
	if (regmap_multi_reg_write(data->regmap, seq, ARRAY_SIZE(seq)))
		dev_warn(data->dev, "chip not left running\n");
}

/**
 * em7180_caldata_apply() - restore a saved calibration file's blob
 * @data: driver state, with @data->lock held
 * @blob: the file's content: the blob as calibration_data reads it
 * @size: its size
 * @name: the file's name, for the warnings
 *
 * Checked as a calibration_data write before the chip is touched, a
 * refusal said once; once written it is the warm start a power loss
 * brings back, and its parameters 27..29 are the accelerometer offsets.
 *
 * Return: 0, -EINVAL for a blob calibration_data would refuse, or the
 * error of the parameter transfer.
 */
VISIBLE_IF_KUNIT int em7180_caldata_apply(struct em7180_data *data, const u8 *blob, size_t size,
					  const char *name)
{
	lockdep_assert_held(&data->lock);

	if (size != EM7180_CALDATA_SIZE) {
		dev_warn(data->dev, "%s: %zu bytes, not %zu: calibration not restored\n",
			 name, size, EM7180_CALDATA_SIZE);
		return -EINVAL;
	}
	if (em7180_warmstart_check(blob, 0, size, true)) {
		dev_warn(data->dev, "%s: a value is not a finite float: calibration not restored\n",
			 name);
		return -EINVAL;
	}

	return em7180_caldata_write(data, (const void *)blob, name);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_caldata_apply);

/*
 * The calibration sentral-warmstart saved for this chip and its firmware,
 * restored before the device is registered, so that no consumer ever sees
 * the chip uncalibrated; bno055 loads its calibration file the same way.
 * The file's header keeps another chip's or firmware's away. No file is
 * the first boot; a bad one, or a failed transfer, is said and probe goes
 * on. Without a restore the offsets are read: calibbias reads fail until
 * a transfer brings them, streaming works without.
 */
static void em7180_caldata_restore(struct em7180_data *data)
{
	struct device *dev = data->dev;
	const struct firmware *fw;
	int ret = -ENOMEM;

	char *name __free(kfree) = kasprintf(GFP_KERNEL, "em7180/caldata-%s.bin", dev_name(dev));
	if (name)
		ret = firmware_request_nowarn(&fw, name, dev);
	if (ret == -ENOENT)
		dev_dbg(dev, "no saved calibration %s\n", name);
	else if (ret && name)
		dev_warn(dev, "cannot load %s: %d\n", name, ret);
	if (!ret) {
		scoped_guard(em7180, data)
			ret = em7180_caldata_apply(data, fw->data, fw->size, name);
		if (!ret)
			dev_info(dev, "restored calibration from %s\n", name);
		else if (ret != -EINVAL)
			dev_warn(dev, "%s: calibration not restored: %d\n", name, ret);
		release_firmware(fw);
		/* After a failed transfer the offsets were read back */
		if (ret != -EINVAL)
			return;
	}

	guard(em7180)(data);
	ret = em7180_accel_offset_fetch(data);
	if (ret)
		dev_warn(dev, "cannot read the accelerometer offsets: %d\n", ret);
}

/* upstream: } */
/*
 * Another ID may be a compatible part: say so and go on, as bno055 does.
 * The first access after power-on may come while the chip still resets.
 */
static int em7180_check_id(struct em7180_data *data)
{
	u8 id[2];
	int ret, err;

	ret = read_poll_timeout(regmap_bulk_read, err, !err, EM7180_READY_POLL_US,
				EM7180_READY_TIMEOUT_US, false, data->regmap, EM7180_REG_PRODUCT_ID,
				id, sizeof(id));
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

static int em7180_read_versions(struct em7180_data *data)
{
	__le16 ver[2];
	int ret;

	ret = regmap_bulk_read(data->regmap, EM7180_REG_ROM_VERSION, ver, sizeof(ver));
	if (ret)
		return ret;

	data->rom_version = le16_to_cpu(ver[0]);
	data->ram_version = le16_to_cpu(ver[1]);
	return 0;
}

int em7180_core_probe(struct device *dev, struct regmap *regmap, int irq)
{
	static const char * const regulators[] = { "vdd", "vddio" };
	char id[EM7180_ID_LINE_LEN];
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
	init_waitqueue_head(&data->wq); /* upstream: param */
	dev_set_drvdata(dev, indio_dev);

	ret = devm_regulator_bulk_get_enable(dev, ARRAY_SIZE(regulators), regulators);
	if (ret)
		return dev_err_probe(dev, ret, "failed to enable regulators\n");
	fsleep(EM7180_POWER_ON_US);

	ret = iio_read_mount_matrix(dev, &data->orientation);
	if (ret)
		return dev_err_probe(dev, ret, "failed to read mount matrix\n");

	ret = em7180_check_id(data);
	if (ret)
		return ret;

	ret = em7180_wait_boot(data, &status); /* upstream: health */
	/* upstream: !health: ret = em7180_wait_firmware(data, &status); */
	if (!ret) /* upstream: health */
		ret = em7180_check_alive(data, &status); /* upstream: health */
	if (ret && ret != -ENODEV) /* upstream: upload */
	/* upstream: !upload: if (ret) */
		return dev_err_probe(dev, ret, "firmware not ready (SentralStatus 0x%02x)\n",
				     status);

	/* upstream: upload { */
	/* Without an EEPROM, or with a firmware-name: from the host */
	ret = em7180_upload_probe(data, ret == -ENODEV);
	if (ret)
		return ret;
	/* upstream: } */

	ret = em7180_read_versions(data);
	if (ret)
		return dev_err_probe(dev, ret, "failed to read firmware versions\n");

	/* upstream: feature { */
	ret = em7180_feature_probe(indio_dev, em7180_channels, ARRAY_SIZE(em7180_channels));
	if (ret)
		return ret;
	/* upstream: } */
	/* upstream: !feature: indio_dev->channels = em7180_channels; */
	/* upstream: !feature: indio_dev->num_channels = ARRAY_SIZE(em7180_channels); */

	ret = em7180_chip_configure(data, false);
	if (ret)
		return dev_err_probe(dev, ret, "failed to configure the chip\n");

	/* upstream: param { */
	ret = devm_add_action_or_reset(dev, em7180_unbind_action, data);
	if (ret)
		return ret;

	/* upstream: } */

	/* upstream: health { */
	/*
	 * Before the first parameter transfer, whose end may fail and ask
	 * for a recovery; its teardown runs before the unbind action, which
	 * a recovery would undo.
	 */
	ret = em7180_health_init(data);
	if (ret)
		return ret;

	/* upstream: } */
	/* upstream: param { */
	scoped_guard(em7180, data)
		ret = em7180_param_pointer(data);
	if (ret)
		return dev_err_probe(dev, ret, "failed to probe the register pointer\n");

	/* upstream: } */
	/* upstream: cal { */
	/* Streaming works without: the score is left out */
	scoped_guard(em7180, data) {
		ret = em7180_cal_detect(data);
		if (ret)
			dev_warn(dev, "cannot read the calibration registers: %d\n", ret);
		data->appnote_attrs = data->appnote;
	}
	/* upstream: } */
	em7180_id_line(data, id, sizeof(id));
	dev_info(dev, "firmware %s\n", id);
	em7180_caldata_restore(data); /* upstream: param */

	indio_dev->name = "em7180";
	indio_dev->info = &em7180_info;
	indio_dev->modes = INDIO_DIRECT_MODE;

	if (data->irq) {
		ret = em7180_trigger_probe(indio_dev, data->irq);
		if (ret)
			return ret;
	}

	ret = devm_iio_triggered_buffer_setup(dev, indio_dev,
					      iio_pollfunc_store_time,
					      em7180_trigger_handler,
					      &em7180_buffer_ops); /* upstream: param */
					      /* upstream: !param: NULL); */
	if (ret)
		return dev_err_probe(dev, ret, "failed to set up buffer\n");

	ret = devm_iio_device_register(dev, indio_dev);
	if (ret)
		return ret;

	em7180_health_debugfs(indio_dev); /* upstream: health */
	return 0;
}
EXPORT_SYMBOL_NS_GPL(em7180_core_probe, "IIO_EM7180");

/* Not confirmed is no reason to keep the system awake: 0 */
int em7180_chip_suspend(struct em7180_data *data)
{
	struct em7180_caldata cal; /* upstream: param */
	unsigned int status;
	int ret;

	guard(em7180)(data);
	/* upstream: param { */
	/* The warm start read, for resume to write back after a power loss */
	ret = em7180_warmstart_read(data, &cal);
	if (ret)
		dev_warn(data->dev, "cannot read the calibration before sleep: %d\n", ret);
	/* upstream: } */
	ret = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, EM7180_ALGO_CTRL_STANDBY);
	if (!ret)
		ret = regmap_read_poll_timeout(data->regmap, EM7180_REG_ALGO_STATUS, status,
					       status & EM7180_ALGO_STATUS_HALTED,
					       EM7180_STANDBY_POLL_US, EM7180_STANDBY_TIMEOUT_US);
	if (ret)
		dev_warn(data->dev, "standby not confirmed (%d); resume runs the algorithm again\n",
			 ret);

	return 0;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_chip_suspend);

/* upstream: health { */
/*
 * The calibration back after a reset if the firmware is the same (as
 * sentral-warmstart checks a saved file), else the chip's offsets read.
 */
static int em7180_restore_calibration(struct em7180_data *data, u16 rom, u16 ram)
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
		ret = em7180_params_write(data, EM7180_WS_FIRST_PARAM, EM7180_WS_NUM_PARAMS, vals);
		if (!ret)
			em7180_ws_set(data, vals);
		return ret;
	}

	/* Offsets written while no warm start was known */
	if (data->accel_offset_valid)
		return em7180_params_write(data, EM7180_ACCEL_OFFSET_PARAM,
					   ARRAY_SIZE(data->accel_offset), data->accel_offset);

	return em7180_accel_offset_fetch(data);
}

/*
 * One attempt at resuming or recovering. @lost stays set once a power loss
 * was seen; @rom and @ram are the versions before it.
 */
int em7180_chip_restore(struct em7180_data *data, bool *lost, u16 *rom, u16 *ram)
{
	unsigned int status = 0;
	bool appnote; /* upstream: cal */
	int ret, err;

	ret = read_poll_timeout(em7180_read_status, err, !err, EM7180_READY_POLL_US,
				EM7180_READY_TIMEOUT_US, false, data, &status);
	if (ret)
		return err;

	/* Only a reset shows standby: a suspended chip only halts fusion */
	if (!*lost && !(status & EM7180_SENTRAL_STANDBY))
		return regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, 0);

	if (!*lost) {
		dev_info(data->dev, "chip lost power, restoring its state\n");
		*rom = data->rom_version;
		*ram = data->ram_version;
	}
	*lost = true;
	data->cal.valid = false; /* upstream: cal */
	/* upstream: param { */
	/* The firmware may be another, with another latency */
	data->ack_min_us = 0;
	/* upstream: } */

	ret = em7180_wait_boot(data, &status);
	/* upstream: upload { */
	if (!ret || ret == -ENODEV)
		ret = em7180_upload(data, ret);
	/* upstream: } */
	if (ret) {
		dev_err(data->dev,
			"firmware not ready after a power loss (SentralStatus 0x%02x): %d\n",
			status, ret);
		return ret;
	}

	ret = em7180_read_versions(data);
	if (ret)
		return ret;
	/* upstream: cal { */
	/* Other firmware may keep other things in 0x43-0x4E */
	appnote = data->appnote;
	if (*ram != data->ram_version)
		data->appnote = false;
	/* upstream: } */
	ret = em7180_chip_configure(data, true);
	/* upstream: param { */
	if (!ret)
		ret = em7180_restore_calibration(data, *rom, *ram);
	/* upstream: } */
	/* upstream: !cal: return ret; */
/* upstream: !cal: } */
	/* upstream: cal { */
	if (ret || *ram == data->ram_version)
		return ret;

	ret = em7180_cal_detect(data);
	if (!ret && data->appnote != appnote)
		dev_info(data->dev, "firmware RAM 0x%04x: calibration %s\n",
			 data->ram_version,
			 !data->appnote ? "score not reported" :
			 data->appnote_attrs ? "score reported again" :
			 "score reported after a rebind");

	return ret;
}

/* upstream: } */
/* upstream: } */

int em7180_chip_resume(struct em7180_data *data)
{
	u16 rom = 0, ram = 0; /* upstream: health */
	bool lost = false; /* upstream: health */
	int ret;

	guard(em7180)(data);
	/* upstream: health { */
	/* Once more after a bus error, not after a timeout, which took seconds */
	ret = em7180_chip_restore(data, &lost, &rom, &ram);
	if (ret && ret != -ETIMEDOUT && ret != -ENODEV)
		ret = em7180_chip_restore(data, &lost, &rom, &ram);
	/*
	 * Its last write ended any transfer left open, which the recovery
	 * dropped at suspend was to end: the next recovery owes it nothing.
	 */
	if (!ret)
		data->xfer_stuck = false;
	/* upstream: } */
	/* upstream: !health: ret = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, 0); */

	return ret;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_chip_resume);

/* No interrupt and no trigger across system sleep, as bmi323 does */
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
	em7180_recover_stop(data); /* upstream: health */

	return em7180_chip_suspend(data);
}

static int em7180_resume(struct device *dev)
{
	struct iio_dev *indio_dev = dev_get_drvdata(dev);
	struct em7180_data *data = iio_priv(indio_dev);
	int ret;

	/* upstream: health { */
	/* A restore that fails asks for a recovery */
	em7180_recover_start(data);
	/* upstream: } */
	ret = em7180_chip_resume(data);
	if (data->irq)
		enable_irq(data->irq);
	em7180_resume_triggering(indio_dev);

	return ret;
}

EXPORT_NS_GPL_SIMPLE_DEV_PM_OPS(em7180_pm_ops, em7180_suspend, em7180_resume, IIO_EM7180);

MODULE_AUTHOR("The sentral project");
MODULE_DESCRIPTION("PNI SENtral / EM7180 sensor-fusion hub core driver");
MODULE_LICENSE("GPL");
