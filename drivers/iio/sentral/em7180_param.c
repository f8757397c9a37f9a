// SPDX-License-Identifier: GPL-2.0-only
/*
 * EM7180 parameter transfer and IEEE-754 single precision helpers.
 *
 * Protocol (EM's generic host driver, em718x_core.c, and the Sony em718x
 * driver): with AlgorithmControl bit 7 set, a write of
 * ParamRequest = n (read) or n | 0x80 (write, value in LoadParamByte0..3)
 * is served by the firmware, which then echoes the request in
 * ParamAcknowledge and, for a read, puts the value in SavedParamByte0..3.
 * ParamRequest = 0 and AlgorithmControl bit 7 clear end the procedure.
 *
 * The kernel may not use the FPU: floats are handled as their bit patterns.
 */

#include <linux/bits.h>
#include <linux/delay.h>
#include <linux/dev_printk.h>
#include <linux/errno.h>
#include <linux/ktime.h>
#include <linux/limits.h>
#include <linux/lockdep.h>
#include <linux/math.h>
#include <linux/math64.h>
#include <linux/minmax.h>
#include <linux/regmap.h>
#include <linux/types.h>

#include <kunit/visibility.h>

#include "em7180.h"
#include "em7180_compat.h"

#define EM7180_F32_SIGN			BIT(31)
#define EM7180_F32_EXP_MASK		GENMASK(30, 23)
#define EM7180_F32_FRAC_MASK		GENMASK(22, 0)
#define EM7180_F32_BIAS			127
#define EM7180_F32_FRAC_BITS		23

/*
 * The firmware acknowledge latency is not documented; drivers in the wild
 * allow up to 1 s (EM generic host driver). The first guess is refined
 * while a batch runs.
 */
#define EM7180_ACK_TIMEOUT_US		1000000
#define EM7180_ACK_WAIT_INIT_US		1000
#define EM7180_ACK_WAIT_MAX_US		100000U
#define EM7180_ACK_STEP_MIN_US		50
#define EM7180_ACK_STEP_MAX_US		10000

/* 1 LSB of accelerometer offset = 0.000488 g = 61 / 125000 g exactly */
#define EM7180_G_PER_LSB_NUM		61
#define EM7180_G_PER_LSB_DEN		125000

/**
 * em7180_float_is_finite() - tell whether a float32 is neither NaN nor ±Inf
 * @bits: IEEE-754 single precision bit pattern
 *
 * Return: true for zero, subnormal and normal numbers.
 */
bool em7180_float_is_finite(u32 bits)
{
	return (bits & EM7180_F32_EXP_MASK) != EM7180_F32_EXP_MASK;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_float_is_finite);

/**
 * em7180_lsb_to_float_g() - accelerometer offset in LSB to float32 in g
 * @lsb: offset in accelerometer LSB (1 LSB = 0.000488 g)
 *
 * Computes the float32 nearest to @lsb * 0.000488 (ties to even) with
 * integer arithmetic only, as the PNI application note's Table 1 expects:
 * -47 gives 0xBCBBE447.
 *
 * Return: the IEEE-754 single precision bit pattern.
 */
u32 em7180_lsb_to_float_g(int lsb)
{
	u64 num = (u64)abs((s64)lsb) * EM7180_G_PER_LSB_NUM;
	u64 den = EM7180_G_PER_LSB_DEN;
	int k = 0;
	u64 mant;
	u64 rem;

	if (!lsb)
		return 0;

	/* Scale num / den into [2^23, 2^24): value = num / den * 2^-k */
	while (num < den << EM7180_F32_FRAC_BITS) {
		num <<= 1;
		k++;
	}
	while (num >= den << (EM7180_F32_FRAC_BITS + 1)) {
		den <<= 1;
		k--;
	}

	mant = div64_u64_rem(num, den, &rem);
	if (2 * rem > den || (2 * rem == den && (mant & 1)))
		mant++;
	if (mant == BIT_ULL(EM7180_F32_FRAC_BITS + 1)) {
		mant >>= 1;
		k--;
	}

	/* |lsb| < 2^31 keeps the exponent well inside the normal range */
	return (lsb < 0 ? EM7180_F32_SIGN : 0) |
	       (u32)(EM7180_F32_BIAS + EM7180_F32_FRAC_BITS - k) << EM7180_F32_FRAC_BITS |
	       ((u32)mant & EM7180_F32_FRAC_MASK);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_lsb_to_float_g);

/**
 * em7180_float_g_to_lsb() - float32 in g to accelerometer offset in LSB
 * @bits: IEEE-754 single precision bit pattern of the offset in g
 * @lsb: where to store the offset in LSB (1 LSB = 0.000488 g)
 *
 * Rounds to the nearest LSB, halves away from zero.
 *
 * Return: 0, or -ERANGE for NaN, ±Inf and magnitudes of 2^19 g or more.
 */
int em7180_float_g_to_lsb(u32 bits, int *lsb)
{
	int e = (bits & EM7180_F32_EXP_MASK) >> EM7180_F32_FRAC_BITS;
	u64 mant = bits & EM7180_F32_FRAC_MASK;
	u64 num, den;
	int shift;
	s64 val;

	if (!em7180_float_is_finite(bits) || e >= EM7180_F32_BIAS + 19)
		return -ERANGE;

	if (e)
		mant |= BIT_ULL(EM7180_F32_FRAC_BITS);
	else
		e = 1;	/* subnormal */

	/* value = mant * 2^(e - 150); lsb = value * 125000 / 61 */
	shift = EM7180_F32_BIAS + EM7180_F32_FRAC_BITS - e;
	num = mant * EM7180_G_PER_LSB_DEN;
	if (shift > 50) {
		/* num < 2^41 is then far below half of the divisor */
		val = 0;
	} else {
		den = (u64)EM7180_G_PER_LSB_NUM << shift;
		val = div64_u64(num + den / 2, den);
	}

	*lsb = bits & EM7180_F32_SIGN ? -val : val;
	return 0;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_float_g_to_lsb);

/**
 * em7180_float_to_fixed() - float32 to signed fixed point
 * @bits: IEEE-754 single precision bit pattern
 * @frac_bits: number of fraction bits of the result, 0..30
 *
 * Used for the quaternion components, whose magnitude is at most 1.
 * Rounds to nearest, halves away from zero; saturates to the s32 range,
 * which also covers ±Inf; NaN gives 0.
 *
 * Return: round(value * 2^frac_bits), saturated.
 */
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

/**
 * em7180_param_init() - set the initial parameter acknowledge estimate
 * @data: driver state
 *
 * Also forgets what ParamAcknowledge holds: the next transfer reads it
 * before its first request.
 */
void em7180_param_init(struct em7180_data *data)
{
	data->ack_wait_us = EM7180_ACK_WAIT_INIT_US;
	data->ack_good_us = 0;
	data->ack_known = false;
	data->stop_unacked = false;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_param_init);

static void em7180_param_sleep(unsigned int us)
{
	if (us >= 10)
		usleep_range(us, us + us / 16 + 5);
	else if (us)
		udelay(us);
}

/**
 * struct em7180_batch - acknowledge timing learned within one transfer
 * @missed: a poll of this batch came before the acknowledge
 * @best_us: shortest time after a request at which an acknowledge was seen
 * @cal_read: a poll of this batch read the calibration registers
 */
struct em7180_batch {
	bool missed;
	unsigned int best_us;
	bool cal_read;
};

/* ParamAcknowledge through the calibration score: 0x3A..0x4E */
#define EM7180_ACK_CAL_LEN	(EM7180_REG_CAL_SCORE + 2 - EM7180_REG_PARAM_ACK)

/*
 * Poll ParamAcknowledge. For a read (val not NULL) one burst also returns
 * SavedParam; a write needs the acknowledge byte only, which saves 4 of
 * the 6 bytes of each poll (36 bit times at 400 kHz per parameter).
 *
 * The first poll comes after the wait that sufficed for the previous
 * parameter. While no poll of the batch has come too early, that wait is
 * shortened by 1/8 after each success, so the driver converges on the
 * firmware's latency instead of sleeping a fixed amount. After one early
 * poll it polls again once the shortest time that sufficed in this batch
 * has passed, and keeps that wait for the rest of the batch: a converged
 * batch costs one early poll in all. Only times that actually passed count
 * as sufficient (a sleep may overrun, so a poll planned too early can still
 * succeed), and taking the shortest keeps one overrun from slowing down
 * the rest of the batch.
 *
 * The first poll of a transfer reads on through the calibration registers
 * (em7180_cal_update()): the algorithm is paused, so every update flag the
 * chip latched before the transfer is taken in, in the same transaction.
 */
static int em7180_param_ack(struct em7180_data *data, u8 req, u32 *val,
			    struct em7180_batch *batch)
{
	ktime_t start = ktime_get();
	unsigned int wait = data->ack_wait_us;
	unsigned int waited;
	bool first = true;
	u8 ack[EM7180_ACK_CAL_LEN];
	size_t len;
	int ret;

	for (;;) {
		em7180_param_sleep(wait);
		waited = min_t(s64, ktime_us_delta(ktime_get(), start),
			       EM7180_ACK_TIMEOUT_US);
		if (batch && !batch->cal_read)
			len = EM7180_ACK_CAL_LEN;
		else
			len = val ? 5 : 1;
		ret = regmap_bulk_read(data->regmap, EM7180_REG_PARAM_ACK, ack,
				       len);
		if (ret)
			return ret;
		if (len == EM7180_ACK_CAL_LEN) {
			em7180_cal_update(&data->cal, &ack[EM7180_REG_CAL_STATUS -
							   EM7180_REG_PARAM_ACK]);
			batch->cal_read = true;
		}
		if (ack[0] == req)
			break;
		if (waited >= EM7180_ACK_TIMEOUT_US)
			return -ETIMEDOUT;

		first = false;
		if (data->ack_good_us > waited)
			wait = data->ack_good_us - waited;
		else
			wait = clamp_t(unsigned int, waited / 4,
				       EM7180_ACK_STEP_MIN_US,
				       EM7180_ACK_STEP_MAX_US);
	}

	if (val)
		*val = get_unaligned_le32(&ack[1]);
	/* The stop's latency is not a parameter's: learn nothing from it */
	if (!batch)
		return 0;

	batch->best_us = min3(batch->best_us, waited, EM7180_ACK_WAIT_MAX_US);
	data->ack_good_us = batch->best_us;
	if (!first) {
		batch->missed = true;
		data->ack_wait_us = batch->best_us;
	} else if (!batch->missed) {
		data->ack_wait_us -= data->ack_wait_us / 8;
	}

	return 0;
}

/*
 * End the procedure and leave the algorithm running. Written with explicit
 * values, never read-modify-write, so a retry after a failed write still
 * reaches the chip.
 *
 * After a clean transfer the stop is waited for: a firmware that serves
 * ParamRequest = 0 like a request echoes 0 once it is done, and a host
 * that clears bit 7 before then leaves the last request's echo in 0x3A.
 * A firmware that never echoes the stop is waited for once; after that
 * 0x3A is taken to keep the last request's echo. Either way the driver
 * knows which stale echo the next transfer may meet.
 */
static int em7180_param_end(struct em7180_data *data, bool clean, u8 last)
{
	int ret, ret2, err;

	ret = regmap_write(data->regmap, EM7180_REG_PARAM_REQ, 0);
	if (ret)
		ret = regmap_write(data->regmap, EM7180_REG_PARAM_REQ, 0);

	data->ack_known = false;
	if (!ret && clean && !data->stop_unacked) {
		/* After a bus error here 0x3A is unknown, and read next time */
		err = em7180_param_ack(data, 0, NULL, NULL);
		if (!err) {
			data->ack_stale = 0;
			data->ack_known = true;
		} else if (err == -ETIMEDOUT) {
			dev_info(data->dev,
				 "the firmware does not acknowledge the end of a parameter transfer\n");
			data->stop_unacked = true;
		}
	}
	if (!ret && clean && data->stop_unacked) {
		/* What it echoed last; or 0, which no request equals */
		data->ack_stale = last;
		data->ack_known = true;
	}

	/*
	 * A data-ready interrupt from before this point may find newer data
	 * than it announced once the algorithm runs again: its scan is not
	 * pushed (em7180_trigger_handler()).
	 */
	WRITE_ONCE(data->xfer_seq, data->xfer_seq + 1);
	ret2 = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, 0);
	if (ret2)
		ret2 = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, 0);

	return ret ?: ret2;
}

/*
 * One request: the value and ParamRequest in one burst for a write, the
 * request alone for a read, then its acknowledge. As in the reference
 * drivers, bit 7 is set after the first request: the procedure never
 * starts on a request somebody else left in ParamRequest.
 */
static int em7180_param_request(struct em7180_data *data, u8 req, u32 in,
				u32 *out, bool *started,
				struct em7180_batch *batch)
{
	u8 buf[5];
	int ret;

	if (req & EM7180_PARAM_WRITE) {
		put_unaligned_le32(in, buf);
		buf[4] = req;
		ret = regmap_bulk_write(data->regmap, EM7180_REG_LOAD_PARAM, buf,
					sizeof(buf));
	} else {
		ret = regmap_write(data->regmap, EM7180_REG_PARAM_REQ, req);
	}
	if (!ret && !*started) {
		ret = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL,
				   EM7180_ALGO_CTRL_PARAM_XFER);
		*started = true;
	}
	if (ret)
		return ret;

	return em7180_param_ack(data, req, out, batch);
}

/*
 * An acknowledge equal to the request only proves the request was served
 * if 0x3A held something else before: a firmware may keep its last echo
 * from an earlier transfer (the reference only says it "echoes the
 * ParamRequest value once served"). When what it holds is unknown it is
 * read; when it equals the first request, a read of another parameter
 * changes it first.
 */
static int em7180_param_unstale(struct em7180_data *data, u8 first_req,
				bool *started, struct em7180_batch *batch)
{
	unsigned int n = first_req & ~EM7180_PARAM_WRITE;
	unsigned int ack;
	u32 dummy;
	int ret;

	if (!data->ack_known) {
		ret = regmap_read(data->regmap, EM7180_REG_PARAM_ACK, &ack);
		if (ret)
			return ret;
		data->ack_stale = ack;
	}
	if (data->ack_stale != first_req)
		return 0;

	return em7180_param_request(data, n % EM7180_PARAM_MAX + 1, 0, &dummy,
				    started, batch);
}

static int em7180_param_xfer(struct em7180_data *data, unsigned int first,
			     unsigned int count, const u32 *in, u32 *out)
{
	struct em7180_batch batch = { .best_us = UINT_MAX };
	u8 write = in ? EM7180_PARAM_WRITE : 0;
	bool started = false;
	unsigned int i;
	int ret, end;
	u8 req = 0;

	lockdep_assert_held(&data->lock);

	if (!count || !first || first + count - 1 > EM7180_PARAM_MAX)
		return -EINVAL;

	ret = em7180_param_unstale(data, first | write, &started, &batch);

	for (i = 0; !ret && i < count; i++) {
		req = (first + i) | write;
		ret = em7180_param_request(data, req, in ? in[i] : 0,
					   out ? &out[i] : NULL, &started,
					   &batch);
	}

	end = em7180_param_end(data, !ret, req);

	return ret ?: end;
}

/**
 * em7180_params_read() - read consecutive parameters in one transfer
 * @data: driver state, with @data->lock held
 * @first: first parameter number, 1..127
 * @count: number of parameters
 * @vals: where to store the raw 32-bit values
 *
 * Costs one ParamRequest write and normally one acknowledge poll per
 * parameter, one transaction to start and three to end (the stop, its
 * acknowledge, bit 7 clear). The transfer is ended and the algorithm left
 * running on every path.
 *
 * Return: 0, -EINVAL for a bad range, -ETIMEDOUT when a parameter is not
 * acknowledged within 1 s, or the bus error.
 */
int em7180_params_read(struct em7180_data *data, unsigned int first,
		       unsigned int count, u32 *vals)
{
	return em7180_param_xfer(data, first, count, NULL, vals);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_params_read);

/**
 * em7180_params_write() - write consecutive parameters in one transfer
 * @data: driver state, with @data->lock held
 * @first: first parameter number, 1..127
 * @count: number of parameters
 * @vals: raw 32-bit values to write
 *
 * Each parameter is one 5-byte burst (LoadParamByte0..3 and ParamRequest)
 * followed by normally one acknowledge poll, which cannot be a stale echo
 * of an earlier transfer. The transfer is ended and the algorithm left
 * running on every path.
 *
 * Return: 0, -EINVAL for a bad range, -ETIMEDOUT when a parameter is not
 * acknowledged within 1 s, or the bus error.
 */
int em7180_params_write(struct em7180_data *data, unsigned int first,
			unsigned int count, const u32 *vals)
{
	return em7180_param_xfer(data, first, count, vals, NULL);
}
EXPORT_SYMBOL_IF_KUNIT(em7180_params_write);
