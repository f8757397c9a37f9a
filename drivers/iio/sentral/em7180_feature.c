// SPDX-License-Identifier: GPL-2.0-only
/*
 * PNI SENtral / EM7180: the feature sensors
 *
 * Besides its accelerometer, gyroscope and magnetometer, the hub's firmware
 * may drive up to three "feature sensors" and says which in FeatureFlags
 * (0x39): bit 0 barometer, bit 1 humidity, bit 2 temperature, bits 3 to 5
 * custom sensors (EM's em718x_registers.h, Sony's em718x driver). Each
 * present one takes a slot in bit order: its rate register 0x58 + slot, its
 * actual rate 0x48 + slot, and its data in 0x2A..0x31 (EM's em718x_core.c):
 * with one or two slots data and TIME per slot (on the USFS board Baro
 * 0x2A, BaroTIME 0x2C, Temp 0x2E, TempTIME 0x30, as kriswiner's and
 * gregtomasch's USFS code read them), with three the three data words and
 * one TIME at 0x30.
 *
 * The USFS firmware's conversions (kriswiner, gregtomasch): pressure in
 * mbar = raw * 0.01 + 1013.25, temperature in degrees C = raw * 0.01; EM's
 * driver_ext.h gives humidity 0.01 % per LSB.
 */

#include <linux/array_size.h>
#include <linux/bitmap.h>
#include <linux/bitops.h>
#include <linux/cleanup.h>
#include <linux/device.h>
#include <linux/errno.h>
#include <linux/lockdep.h>
#include <linux/mutex.h>
#include <linux/regmap.h>
#include <linux/slab.h>
#include <linux/string.h>
#include <linux/types.h>

#include <linux/iio/iio.h>

#include <kunit/visibility.h>

#include "em7180_compat.h"
#include "em7180_core.h"

#define EM7180_FEATURE_RATE_MASK	GENMASK(6, 0)
/* Each sample sets EventStatus bit 6 (and raises INT if enabled) */
#define EM7180_FEATURE_RATE_REPORT	BIT(7)
#define EM7180_FEATURE_FLAGS_MASK	GENMASK(5, 0)
#define EM7180_FEATURE_DEFAULT_HZ	25

/* Pressure in kPa = (raw + 101325) * 0.001 */
#define EM7180_PRESSURE_OFFSET		101325
#define EM7180_PRESSURE_SCALE_MICRO	1000
/* Milli degrees C, milli percent: 0.01 per LSB */
#define EM7180_TEMP_HUMIDITY_SCALE	10

/*
 * kriswiner's USFS code writes 0x32 for a 25 Hz barometer ("sample rate of
 * barometer is baroRt/2"); gregtomasch's writes 0x19 for 25 Hz, and EM's
 * and Sony's drivers write every feature rate in Hz and read it back with
 * divisor 1. The rate register is taken as Hz until the chip's actual rate
 * (0x48 + slot, in Hz) shows half of it: the register then counts half
 * hertz (em7180_feature_settle()).
 */
/* 50 Hz at most: twice that still fits the 7 bits of the register */
static const int em7180_feature_freq_avail[] = { 1, 2, 5, 10, 25, 50 };

static const enum iio_chan_type em7180_feature_types[] = {
	IIO_PRESSURE,		/* FeatureFlags bit 0 */
	IIO_HUMIDITYRELATIVE,	/* bit 1 */
	IIO_TEMP,		/* bit 2 */
};

/**
 * em7180_feature_layout() - where the feature sensors of FeatureFlags are
 * @flags: FeatureFlags
 * @feat: filled with the barometer, humidity and temperature present, in
 *	slot order (the custom sensors take the slots after them)
 *
 * Return: the number of entries filled, or -E2BIG when @flags announces
 * more sensors than there are slots.
 */
int em7180_feature_layout(unsigned int flags, struct em7180_feature *feat)
{
	unsigned int bit, slots, n = 0;

	flags &= EM7180_FEATURE_FLAGS_MASK;
	slots = hweight8(flags);
	if (slots > EM7180_FEATURE_MAX)
		return -E2BIG;

	for (bit = 0; bit < ARRAY_SIZE(em7180_feature_types); bit++) {
		if (!(flags & BIT(bit)))
			continue;
		feat[n].type = em7180_feature_types[bit];
		feat[n].slot = n;
		if (slots < EM7180_FEATURE_MAX) {
			feat[n].data_reg = EM7180_REG_FEATURE0 + 4 * n;
			feat[n].end_reg = feat[n].data_reg + 4;
		} else {
			feat[n].data_reg = EM7180_REG_FEATURE0 + 2 * n;
			feat[n].end_reg = EM7180_REG_FEATURE0 + 8;
		}
		n++;
	}

	return n;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_feature_layout);

/**
 * em7180_feature_channels() - the channel table with the feature sensors
 * @base: the channels of every chip, the soft timestamp last
 * @n_base: entries in @base
 * @feat: the feature sensors, from em7180_feature_layout()
 * @n_feat: entries in @feat
 * @chans: filled with @n_base + @n_feat entries: @base but its timestamp,
 *	the feature sensors, then the timestamp with the last scan index
 */
void em7180_feature_channels(const struct iio_chan_spec *base, unsigned int n_base,
			     const struct em7180_feature *feat, unsigned int n_feat,
			     struct iio_chan_spec *chans)
{
	struct iio_chan_spec *c;
	unsigned int i;

	memcpy(chans, base, (n_base - 1) * sizeof(*chans));
	for (i = 0; i < n_feat; i++) {
		c = &chans[n_base - 1 + i];
		*c = (struct iio_chan_spec) {
			.type = feat[i].type,
			.address = feat[i].data_reg,
			.info_mask_separate = BIT(IIO_CHAN_INFO_RAW) |
					      BIT(IIO_CHAN_INFO_SCALE) |
					      BIT(IIO_CHAN_INFO_SAMP_FREQ),
			.info_mask_separate_available =
					      BIT(IIO_CHAN_INFO_SAMP_FREQ),
			.scan_index = base[n_base - 1].scan_index + i,
			.scan_type = {
				.sign = 's',
				.realbits = 16,
				.storagebits = 16,
				.endianness = IIO_LE,
			},
		};
		if (feat[i].type == IIO_PRESSURE)
			c->info_mask_separate |= BIT(IIO_CHAN_INFO_OFFSET);
	}
	chans[n_base - 1 + n_feat] = base[n_base - 1];
	chans[n_base - 1 + n_feat].scan_index += n_feat;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_feature_channels);

/**
 * em7180_feature_probe() - find the feature sensors and their channels
 * @indio_dev: the IIO device, its firmware running
 * @base: the channels of every chip, the soft timestamp last
 * @n_base: entries in @base
 *
 * Without feature sensors the device has @base, as it always had.
 *
 * Return: 0 or a negative error code.
 */
int em7180_feature_probe(struct iio_dev *indio_dev,
			 const struct iio_chan_spec *base, unsigned int n_base)
{
	struct em7180_data *data = iio_priv(indio_dev);
	struct iio_chan_spec *chans;
	unsigned int flags, i;
	int ret, n;

	indio_dev->channels = base;
	indio_dev->num_channels = n_base;
	data->n_features = 0;

	ret = regmap_read(data->regmap, EM7180_REG_FEATURE_FLAGS, &flags);
	if (ret)
		return dev_err_probe(data->dev, ret, "failed to read FeatureFlags\n");

	n = em7180_feature_layout(flags, data->features);
	if (n < 0) {
		dev_warn(data->dev,
			 "FeatureFlags 0x%02x: more sensors than slots, feature sensors ignored\n",
			 flags);
		return 0;
	}
	if (!n)
		return 0;

	chans = devm_kcalloc(data->dev, n_base + n, sizeof(*chans), GFP_KERNEL);
	if (!chans)
		return -ENOMEM;

	em7180_feature_channels(base, n_base, data->features, n, chans);
	for (i = 0; i < n; i++)
		data->features[i].scan_index = chans[n_base - 1 + i].scan_index;
	indio_dev->channels = chans;
	indio_dev->num_channels = n_base + n;
	data->n_features = n;

	return 0;
}

/* Hz to the rate register and back, the report bit apart */
static unsigned int em7180_feature_div(struct em7180_data *data, const struct em7180_feature *f)
{
	return f->type == IIO_PRESSURE && data->baro_half ? 2 : 1;
}

/*
 * Once the barometer runs, its actual rate tells the unit of its rate
 * register: a register of R giving R / 2 Hz counts half hertz, and is
 * written again for the rate asked. Returns 1 then: @actual is stale.
 */
static int em7180_feature_settle(struct em7180_data *data, const struct em7180_feature *f,
				 unsigned int actual)
{
	unsigned int reg, hz;
	int ret;

	lockdep_assert_held(&data->lock);

	if (f->type != IIO_PRESSURE || data->baro_settled || !actual)
		return 0;

	ret = regmap_read(data->regmap, EM7180_REG_FEATURE_RATE0 + f->slot, &reg);
	if (ret)
		return ret;

	data->baro_settled = true;
	hz = reg & EM7180_FEATURE_RATE_MASK;
	if (actual >= hz || abs((int)(2 * actual) - (int)hz) > 1)
		return 0;

	data->baro_half = true;
	dev_info(data->dev, "BaroRate %u runs the barometer at %u Hz: it counts half hertz\n",
		 hz, actual);
	return regmap_update_bits(data->regmap, EM7180_REG_FEATURE_RATE0 + f->slot,
				  EM7180_FEATURE_RATE_MASK, 2 * hz) ?: 1;
}

/**
 * em7180_feature_configure() - set the feature sensors' rates
 * @data: driver state
 * @from_cache: write back what the register cache holds (after a power
 *	loss), not the defaults
 *
 * The present features take the first slots: one burst writes their rates.
 *
 * Return: 0 or a negative error code.
 */
int em7180_feature_configure(struct em7180_data *data, bool from_cache)
{
	u8 rates[EM7180_FEATURE_MAX];
	unsigned int i;
	int ret;

	if (!data->n_features)
		return 0;

	if (from_cache) {
		ret = regmap_bulk_read(data->regmap, EM7180_REG_FEATURE_RATE0,
				       rates, data->n_features);
		if (ret)
			return ret;
	} else {
		for (i = 0; i < data->n_features; i++)
			rates[i] = EM7180_FEATURE_DEFAULT_HZ *
				   em7180_feature_div(data, &data->features[i]);
	}

	return regmap_bulk_write(data->regmap, EM7180_REG_FEATURE_RATE0, rates, data->n_features);
}

/**
 * em7180_feature_find() - the feature sensor of a channel type
 * @data: driver state
 * @type: the channel's type
 *
 * Return: the feature sensor, NULL for another channel.
 */
const struct em7180_feature *em7180_feature_find(struct em7180_data *data, enum iio_chan_type type)
{
	unsigned int i;

	for (i = 0; i < data->n_features; i++)
		if (data->features[i].type == type)
			return &data->features[i];

	return NULL;
}

/* The requested rate in Hz, with data->lock held */
static int em7180_feature_rate(struct em7180_data *data,
			       const struct em7180_feature *f, unsigned int *hz)
{
	unsigned int reg;
	int ret;

	lockdep_assert_held(&data->lock);

	if (f->type == IIO_PRESSURE && !data->baro_settled) {
		ret = regmap_read(data->regmap, EM7180_REG_ACTUAL_FEATURE0 + f->slot, &reg) ?:
		      em7180_feature_settle(data, f, reg);
		if (ret < 0)
			return ret;
	}
	ret = regmap_read(data->regmap, EM7180_REG_FEATURE_RATE0 + f->slot, &reg);
	if (ret)
		return ret;

	*hz = (reg & EM7180_FEATURE_RATE_MASK) / em7180_feature_div(data, f);
	return 0;
}

/**
 * em7180_feature_read_freq() - a feature sensor's rate
 * @data: driver state
 * @f: the feature sensor
 * @hz: where to store the rate in Hz
 *
 * The actual rate the chip reports (in Hz, whatever the rate register
 * counts); the requested one until the sensor has started.
 *
 * Return: IIO_VAL_INT or a negative error code.
 */
int em7180_feature_read_freq(struct em7180_data *data, const struct em7180_feature *f, int *hz)
{
	unsigned int rate;
	int ret;

	scoped_guard(em7180, data) {
		ret = regmap_read(data->regmap, EM7180_REG_ACTUAL_FEATURE0 + f->slot, &rate);
		if (!ret)
			ret = em7180_feature_settle(data, f, rate);
		if (ret > 0 || (!ret && !rate))
			ret = em7180_feature_rate(data, f, &rate);
	}
	if (ret)
		return ret;

	*hz = rate;
	return IIO_VAL_INT;
}

/**
 * em7180_feature_write_freq() - set a feature sensor's rate
 * @data: driver state
 * @f: the feature sensor
 * @hz: one of the advertised rates
 *
 * Return: 0, -EINVAL for a rate not advertised, or the bus error.
 */
int em7180_feature_write_freq(struct em7180_data *data, const struct em7180_feature *f, int hz)
{
	unsigned int i;

	for (i = 0; i < ARRAY_SIZE(em7180_feature_freq_avail); i++)
		if (em7180_feature_freq_avail[i] == hz)
			break;
	if (i == ARRAY_SIZE(em7180_feature_freq_avail))
		return -EINVAL;

	guard(em7180)(data);
	return regmap_update_bits(data->regmap, EM7180_REG_FEATURE_RATE0 + f->slot,
				  EM7180_FEATURE_RATE_MASK, hz * em7180_feature_div(data, f));
}

/**
 * em7180_feature_read_info() - scale, offset and rate of a feature sensor
 * @data: driver state
 * @f: the feature sensor
 * @vals: where to store the value
 * @mask: IIO_CHAN_INFO_SCALE, _OFFSET or _SAMP_FREQ
 *
 * Return: the IIO value type or a negative error code.
 */
int em7180_feature_read_info(struct em7180_data *data, const struct em7180_feature *f, int *vals,
			     long mask)
{
	switch (mask) {
	case IIO_CHAN_INFO_SCALE:
		if (f->type != IIO_PRESSURE) {
			vals[0] = EM7180_TEMP_HUMIDITY_SCALE;
			return IIO_VAL_INT;
		}
		vals[0] = 0;
		vals[1] = EM7180_PRESSURE_SCALE_MICRO;
		return IIO_VAL_INT_PLUS_MICRO;
	case IIO_CHAN_INFO_OFFSET:
		if (f->type != IIO_PRESSURE)
			return -EINVAL;
		vals[0] = EM7180_PRESSURE_OFFSET;
		return IIO_VAL_INT;
	case IIO_CHAN_INFO_SAMP_FREQ:
		return em7180_feature_read_freq(data, f, vals);
	default:
		return -EINVAL;
	}
}

/**
 * em7180_feature_read_avail() - the rates a feature sensor accepts
 * @vals: where to store the list
 * @type: where to store its type
 * @length: where to store its length
 *
 * Return: IIO_AVAIL_LIST.
 */
int em7180_feature_read_avail(const int **vals, int *type, int *length)
{
	*type = IIO_VAL_INT;
	*vals = em7180_feature_freq_avail;
	*length = ARRAY_SIZE(em7180_feature_freq_avail);
	return IIO_AVAIL_LIST;
}

/**
 * em7180_feature_pace() - let a captured feature sensor pace the scans
 * @data: driver state, with @data->lock held
 * @mask: the scan mask
 * @best: the fastest rate in Hz of the other captured sensors
 *
 * A captured feature sensor faster than @best paces the scans, with
 * EventStatus bit 6: it is then @data->pace_feature.
 *
 * Return: true when one does.
 */
bool em7180_feature_pace(struct em7180_data *data, const unsigned long *mask, unsigned int best)
{
	const struct em7180_feature *f;
	unsigned int hz;

	lockdep_assert_held(&data->lock);

	data->pace_feature = NULL;
	for (f = data->features; f < data->features + data->n_features; f++) {
		if (!test_bit(f->scan_index, mask) ||
		    em7180_feature_rate(data, f, &hz) || hz <= best)
			continue;
		best = hz;
		data->pace_event = EM7180_EVENT_FEATURE;
		data->pace_feature = f;
	}

	return data->pace_feature;
}

/**
 * em7180_feature_report() - the report bit for the pacing feature sensor
 * @data: driver state, with @data->lock held and @data->pace_event set
 *
 * Without the report bit (rate register bit 7) a feature sensor's data
 * still update, silently; with it each sample sets EventStatus bit 6 (EM's
 * em718x_core.c sets it for custom sensors, Sony's driver sets and clears
 * it). It is set only on the feature sensor that paces a capture of the
 * chip's own trigger, so that bit 6 means that sensor's sample, and
 * cleared on the others and when the capture ends.
 *
 * Return: 0 or a negative error code.
 */
int em7180_feature_report(struct em7180_data *data)
{
	const struct em7180_feature *f;
	unsigned int report;
	int ret;

	lockdep_assert_held(&data->lock);

	for (f = data->features; f < data->features + data->n_features; f++) {
		report = data->pace_event == EM7180_EVENT_FEATURE &&
			 f == data->pace_feature ? EM7180_FEATURE_RATE_REPORT : 0;
		ret = regmap_update_bits(data->regmap, EM7180_REG_FEATURE_RATE0 + f->slot,
					 EM7180_FEATURE_RATE_REPORT, report);
		if (ret)
			return ret;
	}

	return 0;
}
