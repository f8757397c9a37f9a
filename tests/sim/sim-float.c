// SPDX-License-Identifier: GPL-2.0
/*
 * IEEE-754 binary32 <-> scaled integer conversions for the simulated EM7180.
 *
 * The chip moves quaternions and parameters as little-endian float32
 * (EM7180 register reference §1 and §2). The kernel may not use the FPU, so
 * the model decodes and builds the bit patterns with integer arithmetic.
 */
#include <linux/bitops.h>
#include <linux/errno.h>
#include <linux/math64.h>

#include "sentral_sim.h"

#define F32_SIGN	BIT(31)
#define F32_EXP_SHIFT	23
#define F32_EXP_MASK	0xff
#define F32_MANT_MASK	GENMASK(22, 0)
#define F32_IMPLICIT	BIT(23)
#define F32_BIAS	127

/**
 * sim_f32_to_scaled() - round(value * mul / div) of a float32 bit pattern
 * @bits: the float32 bit pattern
 * @mul: scale numerator
 * @div: scale denominator, not 0
 * @out: the rounded result (halves away from zero)
 *
 * Return: 0, -EINVAL for NaN or infinity, -ERANGE when the result would not
 * fit in about 62 bits.
 */
int sim_f32_to_scaled(u32 bits, u32 mul, u32 div, s64 *out)
{
	u32 exp = (bits >> F32_EXP_SHIFT) & F32_EXP_MASK;
	u64 mant = bits & F32_MANT_MASK;
	u64 q, den, v;
	int e, s;

	if (exp == F32_EXP_MASK)
		return -EINVAL;
	if (!exp) {
		/* zero or subnormal: value = mant * 2^-149 */
		e = 1 - F32_BIAS - F32_EXP_SHIFT;
	} else {
		mant |= F32_IMPLICIT;
		e = (int)exp - F32_BIAS - F32_EXP_SHIFT;
	}

	q = mant * mul;			/* < 2^56 */
	if (e >= 0) {
		if (e > 6)
			return -ERANGE;
		v = div64_u64((q << e) + div / 2, div);
	} else {
		s = -e;
		if (s > 63 - fls(div)) {
			/*
			 * div << s would overflow: drop low bits of q first;
			 * the result is below 2^(56 - 63) * mul / div anyway
			 * for the largest shifts, and exact enough otherwise.
			 */
			int drop = s - (63 - fls(div));

			q = drop >= 64 ? 0 : q >> drop;
			s -= drop;
		}
		den = (u64)div << s;
		v = div64_u64(q + den / 2, den);
	}

	*out = (bits & F32_SIGN) ? -(s64)v : (s64)v;
	return 0;
}

/* round(n * 2^s / den), ties to even as IEEE-754 does */
static u64 sim_scaled_div(u64 n, u64 den, int s)
{
	u64 q, r;

	if (s >= 0)
		n <<= s;
	else
		den <<= -s;
	q = div64_u64_rem(n, den, &r);
	if (r > den - r || (r == den - r && (q & 1)))
		q++;
	return q;
}

/**
 * sim_f32_from_ratio() - the float32 nearest to num / den
 * @num: numerator, |num| < 2^62
 * @den: denominator, 0 < den <= 2^32
 *
 * Rounds to nearest, ties to even. Results below the normal range become
 * zero.
 *
 * Return: the float32 bit pattern.
 */
u32 sim_f32_from_ratio(s64 num, u64 den)
{
	u32 sign = 0;
	int s, exp;
	u64 n, m;

	if (!num)
		return 0;
	if (num < 0) {
		sign = F32_SIGN;
		n = -(u64)num;
	} else {
		n = num;
	}

	/* choose s so that m = round(n * 2^s / den) has 24 significant bits */
	s = F32_EXP_SHIFT + fls64(den) - fls64(n);
	m = sim_scaled_div(n, den, s);
	while (m >= (F32_IMPLICIT << 1)) {
		s--;
		m = sim_scaled_div(n, den, s);
	}
	while (m < F32_IMPLICIT) {
		s++;
		m = sim_scaled_div(n, den, s);
	}
	exp = F32_BIAS + F32_EXP_SHIFT - s;
	if (exp <= 0)
		return sign;
	if (exp >= F32_EXP_MASK)
		return sign | (F32_EXP_MASK << F32_EXP_SHIFT);
	return sign | ((u32)exp << F32_EXP_SHIFT) | (u32)(m & F32_MANT_MASK);
}
