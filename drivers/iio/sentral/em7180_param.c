// SPDX-License-Identifier: GPL-2.0-only
/*
 * EM7180 parameter transfer (EM's em718x_core.c, Sony's em718x driver): with
 * AlgorithmControl bit 7 set, ParamRequest = n (read) or n | 0x80 (write,
 * value in LoadParam) is echoed in ParamAcknowledge once served, a read's
 * value in SavedParam. ParamRequest = 0 and bit 7 clear end it.
 * No FPU in the kernel: floats are handled as bit patterns.
 */

#include <linux/bits.h>
#include <linux/delay.h>
#include <linux/dev_printk.h>
#include <linux/errno.h>
#include <linux/ktime.h>
#include <linux/lockdep.h>
#include <linux/math.h>
#include <linux/math64.h>
#include <linux/minmax.h>
#include <linux/regmap.h>
#include <linux/string.h>
#include <linux/types.h>

#include <kunit/visibility.h>

#include "em7180_core.h"
#include "em7180_compat.h"

/* No document gives the acknowledge latency; EM's driver allows 1 s */
#define EM7180_ACK_TIMEOUT_US		1000000U
#define EM7180_ACK_WAIT_INIT_US		1000U
#define EM7180_ACK_WAIT_MAX_US		100000U
#define EM7180_ACK_STEP_MIN_US		25U
#define EM7180_ACK_STEP_MAX_US		10000U

/* ParamAcknowledge through the calibration score: 0x3A..0x4E */
#define EM7180_ACK_CAL_LEN	(EM7180_REG_CAL_SCORE + 2 - EM7180_REG_PARAM_ACK)

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
 * Nearest float32 to @lsb * 0.000488, ties to even: -47 gives 0xBCBBE447.
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

/*
 * Poll ParamAcknowledge (@len bytes: 5 take SavedParam along) until it
 * echoes @req. No public source gives the latency, and EM's driver allows
 * 1 s: it is learned, so that a steady firmware costs one poll per
 * parameter. The first poll waits the time learned so far; one in time
 * shrinks it by 1/8, not below the least. After an early one, polls
 * follow at 1/8 of the time spent; the last early poll's time raised by
 * 1/8 becomes the least, and the time it took the next wait. A time seen
 * too short is below the latency: the least stays under 9/8 of it, and is
 * never a wait already found too short. (A wait requested below the
 * latency is often in time through its sleep's overrun alone; learnt from
 * such waits, the least can settle just below the latency, where a poll
 * comes early only now and then, at any later transfer.)
 */
static int em7180_param_ack(struct em7180_data *data, u8 req, u8 *buf, size_t len)
{
	unsigned int first = data->ack_wait_us ?: EM7180_ACK_WAIT_INIT_US;
	unsigned int wait = first;
	ktime_t start = ktime_get();
	unsigned int took, early = 0;
	int ret;

	for (;;) {
		usleep_range(wait, wait + wait / 16 + 5);
		took = min_t(s64, ktime_us_delta(ktime_get(), start), EM7180_ACK_TIMEOUT_US);
		ret = regmap_bulk_read(data->regmap, EM7180_REG_PARAM_ACK, buf, len);
		if (ret)
			return ret;
		if (buf[0] == req)
			break;
		if (took >= EM7180_ACK_TIMEOUT_US)
			return -ETIMEDOUT;
		early = took;
		wait = clamp(took / 8, EM7180_ACK_STEP_MIN_US, EM7180_ACK_STEP_MAX_US);
	}

	if (early) {
		data->ack_min_us = min(max(data->ack_min_us, early + early / 8),
				       EM7180_ACK_WAIT_MAX_US);
		data->ack_wait_us = clamp(took, data->ack_min_us, EM7180_ACK_WAIT_MAX_US);
	} else {
		data->ack_wait_us = max(first - first / 8, data->ack_min_us);
	}
	return 0;
}

/**
 * em7180_param_pointer() - does the register pointer cross 0x63 and 0x3A?
 * @data: driver state, with @data->lock held, no transfer running
 *
 * No public host writes across 0x63->0x64 or reads across 0x3A->0x3B in
 * one message (EM's em718x_core.c, the USFS host libraries), so whether
 * the pointer increments there is unknown. Where it does, a parameter
 * costs two transactions: its value and request in one write, its
 * acknowledge and value in one read; where it stops, three, one register
 * per message as those hosts send them. Two bytes written at 0x63 land on
 * 0x63 and 0x64 (a stop request, harmless here) or both on 0x63.
 *
 * Return: 0 or the bus error.
 */
int em7180_param_pointer(struct em7180_data *data)
{
	static const u8 probe[] = { 0x5a, 0 };
	unsigned int val;
	int ret;

	lockdep_assert_held(&data->lock);

	ret = regmap_bulk_write(data->regmap, EM7180_REG_LOAD_PARAM + 3, probe, sizeof(probe)) ?:
	      regmap_read(data->regmap, EM7180_REG_LOAD_PARAM + 3, &val);
	if (ret)
		return ret;

	data->ptr_stops = val != probe[0];
	if (data->ptr_stops)
		dev_info(data->dev, "register pointer stops at 0x63: one register per message\n");
	return 0;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_param_pointer);

/* One request and its acknowledge; bit 7 set after the first (@start) */
static int em7180_param_request(struct em7180_data *data, u8 req, u32 in, u32 *out, bool start)
{
	bool stops = data->ptr_stops;
	u8 buf[5];
	int ret;

	if (req & EM7180_PARAM_WRITE) {
		put_unaligned_le32(in, buf);
		buf[4] = req;
		ret = regmap_bulk_write(data->regmap, EM7180_REG_LOAD_PARAM, buf, stops ? 4 : 5);
		if (!ret && stops)
			ret = regmap_write(data->regmap, EM7180_REG_PARAM_REQ, req);
	} else {
		ret = regmap_write(data->regmap, EM7180_REG_PARAM_REQ, req);
	}
	/* Never start on a request another user left behind */
	if (!ret && start)
		ret = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, EM7180_ALGO_CTRL_PARAM_XFER);
	if (!ret)
		ret = em7180_param_ack(data, req, buf, out && !stops ? 5 : 1);
	if (!ret && out && stops)
		ret = regmap_bulk_read(data->regmap, EM7180_REG_SAVED_PARAM, &buf[1], 4);
	if (!ret && out)
		*out = get_unaligned_le32(&buf[1]);

	return ret;
}

/*
 * Some firmware keeps the last echo after a transfer, which would pass for
 * the acknowledge of an equal first request: read it, and request another
 * parameter first if so. The read takes the latched calibration flags
 * along (they belong to the state saved or replaced), on firmware that
 * keeps them there.
 */
static int em7180_param_begin(struct em7180_data *data, u8 first_req, bool *started)
{
	u8 regs[EM7180_ACK_CAL_LEN];
	/* upstream: cal { */
	u8 *cal = &regs[EM7180_REG_CAL_STATUS - EM7180_REG_PARAM_ACK];
	bool stops = data->ptr_stops;
	bool flags = data->appnote;
	/* upstream: } */
	u32 dummy;
	int ret;

	/* upstream: cal { */
	ret = regmap_bulk_read(data->regmap, EM7180_REG_PARAM_ACK, regs,
			       stops || !flags ? 1 : sizeof(regs));
	if (!ret && stops && flags)
		ret = regmap_bulk_read(data->regmap, EM7180_REG_CAL_STATUS, cal,
				       EM7180_CAL_BLOCK_LEN);
	/* upstream: } */
	/* upstream: !cal: ret = regmap_bulk_read(data->regmap, EM7180_REG_PARAM_ACK, regs, 1); */
	if (ret)
		return ret;
	/* upstream: cal { */
	if (flags)
		em7180_cal_update(data, cal);
	/* upstream: } */
	if (regs[0] != first_req)
		return 0;

	*started = true;
	return em7180_param_request(data, (first_req & ~EM7180_PARAM_WRITE) % EM7180_PARAM_MAX + 1,
				    0, &dummy, true);
}

/* End the transfer on every path */
static int em7180_param_end(struct em7180_data *data)
{
	int ret, ret2;

	ret = regmap_write(data->regmap, EM7180_REG_PARAM_REQ, 0);
	/*
	 * Before the write that resumes the fusion: a sample that comes right
	 * after it has a later interrupt time and is pushed, not taken for
	 * one from before the pause.
	 */
	em7180_resumed(data);
	ret2 = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, 0);
	/* upstream: health { */
	/* Bit 7 would keep fusion paused: try again later, then reset */
	if (ret2) {
		data->xfer_stuck = true;
		em7180_recover_schedule(data);
	}
	/* upstream: } */

	return ret ?: ret2;
}

static int em7180_param_xfer(struct em7180_data *data, unsigned int first,
			     unsigned int count, const u32 *in, u32 *out)
{
	u8 write = in ? EM7180_PARAM_WRITE : 0;
	bool started = false;
	unsigned int i;
	int ret, end;

	lockdep_assert_held(&data->lock);

	if (!count || !first || first + count - 1 > EM7180_PARAM_MAX)
		return -EINVAL;

	ret = em7180_param_begin(data, first | write, &started);
	for (i = 0; !ret && i < count; i++) {
		ret = em7180_param_request(data, (first + i) | write, in ? in[i] : 0,
					   out ? &out[i] : NULL, !started);
		started = true;
	}
	end = em7180_param_end(data);

	return ret ?: end;
}

/**
 * em7180_params_read() - read consecutive parameters in one transfer
 * @data: driver state, with @data->lock held
 * @first: first parameter number, 1..127
 * @count: number of parameters
 * @vals: where to store the raw 32-bit values
 *
 * Costs 2 * @count + 4 transactions (one more per parameter where the
 * register pointer stops, em7180_param_pointer()); the algorithm runs on
 * return.
 *
 * Return: 0, -EINVAL for a bad range, -ETIMEDOUT when a parameter is not
 * acknowledged within 1 s, or the bus error.
 */
int em7180_params_read(struct em7180_data *data, unsigned int first, unsigned int count, u32 *vals)
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
 * Costs as em7180_params_read(); the algorithm runs on return.
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
