// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: composing a chip's key and escaping it for systemd.
 */
#include <stdio.h>
#include <string.h>

#include "devkey.h"

void sw_sanitize_key(const char *in, char *out, size_t len)
{
	size_t i;

	for (i = 0; in[i] && i + 1 < len; i++) {
		char c = in[i];
		bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') ||
			  (c >= '0' && c <= '9') || c == '.' || c == '_' ||
			  c == '-';

		out[i] = ok ? c : '_';
	}
	out[i] = '\0';
	/* Never an empty name, never a hidden file or "." / "..". */
	if (!out[0] || out[0] == '.') {
		if (len > 1 && out[0] == '.')
			out[0] = '_';
		else
			snprintf(out, len, "unknown");
	}
}

bool sw_key_compose(const struct sw_key_parts *p, char *key, size_t len)
{
	char raw[SW_KEY_MAX * 2], *c;
	size_t n;
	int i;

	n = (size_t)snprintf(raw, sizeof(raw), "%s", p->root);
	for (c = raw; *c; c++)
		if (*c == '/')
			*c = '-';
	for (i = 0; i < p->nhops && n < sizeof(raw); i++)
		n += (size_t)snprintf(raw + n, sizeof(raw) - n, "-mux%s-ch%u",
				      p->hop[i].mux, p->hop[i].chan);
	if (n < sizeof(raw))
		n += (size_t)snprintf(raw + n, sizeof(raw) - n, "-0x%02x",
				      p->addr);
	if (n >= len || n >= sizeof(raw))
		return false;
	sw_sanitize_key(raw, key, len);
	return true;
}

bool sw_key_unit_escape(const char *key, char *out, size_t len)
{
	size_t n = 0;

	for (; *key; key++) {
		const char *s = *key == '-' ? "\\x2d" : NULL;
		size_t sl = s ? 4 : 1;

		if (n + sl >= len)
			return false;
		if (s)
			memcpy(out + n, s, 4);
		else
			out[n] = *key;
		n += sl;
	}
	out[n] = '\0';
	return true;
}
