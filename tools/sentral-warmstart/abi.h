/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: is the em7180 driver's sysfs interface the one this
 * tool was written for? Told by which attributes the device has: every
 * release that changes the meaning of an attribute renames it, or removes
 * an attribute that only its earlier meaning came with (README.md,
 * Releases), so names are enough and no version attribute is needed in
 * the kernel.
 */
#ifndef SW_ABI_H
#define SW_ABI_H

#include <stdbool.h>

#include "sw.h"

/*
 * Does the device have attr: a file in its sysfs directory, or, for a name
 * that starts with '/', that path (a parameter of the driver's module)?
 */
typedef bool (*sw_abi_has_fn)(const char *attr, void *ctx);

/*
 * SW_EXIT_OK when the device named name has every attribute the tool
 * uses (the score and update flags all or none: only firmware with the
 * application note's layout has them) and none of an earlier interface;
 * else SW_EXIT_DRIVER with a message that says which is missing or left
 * over, whether the driver is older than the tool (it has an attribute of
 * an earlier interface) or newer (it has none), and what to install.
 * version is the tool's.
 */
int sw_abi_check(const char *name, const char *version, sw_abi_has_fn has,
		 void *ctx, struct sw_err *e);

#endif
