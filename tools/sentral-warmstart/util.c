// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: small helpers shared by every part of the tool.
 */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sw.h"

int sw_err_set(struct sw_err *e, int code, const char *fmt, ...)
{
	va_list ap;

	if (!e)
		return code;
	/* The first failure is the cause; later ones are consequences. */
	if (e->code != SW_EXIT_OK)
		return e->code;
	e->code = code;
	va_start(ap, fmt);
	vsnprintf(e->msg, sizeof(e->msg), fmt, ap);
	va_end(ap);
	return code;
}

void sw_err_append(struct sw_err *e, const char *fmt, ...)
{
	size_t n = strlen(e->msg);
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(e->msg + n, sizeof(e->msg) - n, fmt, ap);
	va_end(ap);
}

/* The one piece of state a signal handler can share: which signal came. */
static volatile sig_atomic_t caught_signal;

static void on_signal(int sig)
{
	caught_signal = sig;
}

void sw_signals_catch(void)
{
	static const int sigs[] = { SIGINT, SIGTERM, SIGHUP };
	struct sigaction sa;
	size_t i;

	memset(&sa, 0, sizeof(sa));
	sa.sa_handler = on_signal;
	sigemptyset(&sa.sa_mask);
	/* A signal ignored on entry (nohup, a background job) stays ignored. */
	for (i = 0; i < sizeof(sigs) / sizeof(sigs[0]); i++) {
		struct sigaction old;

		if (sigaction(sigs[i], NULL, &old) == 0 &&
		    old.sa_handler != SIG_IGN)
			sigaction(sigs[i], &sa, NULL);
	}
}

int sw_signal_pending(void)
{
	return caught_signal;
}

void sw_err_clear(struct sw_err *e)
{
	e->code = SW_EXIT_OK;
	e->msg[0] = '\0';
}

uint16_t sw_score_raw(double pct)
{
	double raw = round(pct * 32768.0 / 100.0) + 32768.0;

	/* Raw 0 (-100 %) is out of range for sw_score_raw_valid(). */
	if (isnan(raw) || raw < 0)
		return 0;
	if (raw > 65535)
		return 65535;
	return (uint16_t)raw;
}

bool sw_parse_score(const char *text, uint16_t *raw)
{
	const char *p = text;
	double pct;

	/* Plain decimals only: strtod would take "nan", "inf" and hex. */
	if (*p == '-')
		p++;
	if (*p < '0' || *p > '9')
		return false;
	while (*p >= '0' && *p <= '9')
		p++;
	if (*p == '.') {
		p++;
		if (*p < '0' || *p > '9')
			return false;
		while (*p >= '0' && *p <= '9')
			p++;
	}
	if (*p || p - text > 20)
		return false;
	pct = strtod(text, NULL);
	if (pct < -100.0 || pct >= 100.0)
		return false;
	*raw = sw_score_raw(pct);
	return true;
}

int sw_parse_number(const char *s, unsigned long max, unsigned long *out)
{
	unsigned long v = 0, base = 10, d;
	const char *p = s;
	bool over = false;

	if (p[0] == '0' && (p[1] == 'x' || p[1] == 'X')) {
		base = 16;
		p += 2;
	}
	if (!*p)
		return EINVAL;
	for (; *p; p++) {
		if (*p >= '0' && *p <= '9')
			d = (unsigned long)(*p - '0');
		else if (base == 16 && *p >= 'a' && *p <= 'f')
			d = (unsigned long)(*p - 'a' + 10);
		else if (base == 16 && *p >= 'A' && *p <= 'F')
			d = (unsigned long)(*p - 'A' + 10);
		else
			return EINVAL;
		/* Past max, only the syntax of the rest still matters. */
		if (over || d > max || v > (max - d) / base)
			over = true;
		else
			v = v * base + d;
	}
	if (over)
		return ERANGE;
	*out = v;
	return 0;
}

float sw_blob_param(const uint8_t *blob, int n)
{
	uint32_t u = sw_get_le32(blob + 4 * (n - 1));
	float f;

	memcpy(&f, &u, sizeof(f));
	return f;
}

void sw_blob_set_param(uint8_t *blob, int n, float v)
{
	uint32_t u;

	memcpy(&u, &v, sizeof(u));
	sw_put_le32(blob + 4 * (n - 1), u);
}

/*
 * Computed in double and rounded once to float: this gives the seed's
 * Table 1 bit patterns exactly (-47 -> 0xBCBBE447, -15 -> 0xBBEFDC9C,
 * +46 -> 0x3CB7E4DE).
 */
float sw_lsb_to_g(int lsb)
{
	return (float)(lsb * SW_G_PER_LSB);
}

int sw_g_to_lsb(float g)
{
	double lsb = round((double)g / SW_G_PER_LSB);

	/*
	 * A file or a chip can hold any float here: saturate, where lround()
	 * would return an unspecified value and a cast would be undefined.
	 */
	if (isnan(lsb))
		return 0;
	if (lsb >= (double)INT_MAX)
		return INT_MAX;
	if (lsb <= (double)INT_MIN)
		return INT_MIN;
	return (int)lsb;
}
