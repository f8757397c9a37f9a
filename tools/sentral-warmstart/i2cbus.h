/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: the bus of --i2c BUS, as i2c-tools take one
 * (i2cbusses.c, lookup_i2c_bus()): a bus number, or an adapter's name
 * matched exactly; and, as this tool always took it, a path to an i2c-dev
 * node under any name (the adapter is the node's device number).
 */
#ifndef SW_I2CBUS_H
#define SW_I2CBUS_H

#include "sw.h"

/* i2c-dev's minor numbers: 20 bits, as i2c-tools allow. */
#define SW_I2C_BUS_MAX 0xfffff
/* Where i2c-dev lists its adapters, each i2c-N with a "name". */
#define SW_I2C_DEV_CLASS "/sys/class/i2c-dev"

/*
 * Check BUS as the command line gives it: a number must be in range, and
 * BUS is not empty. SW_EXIT_OK or SW_EXIT_USAGE.
 */
int sw_i2c_bus_check(const char *bus, struct sw_err *e);

/*
 * The i2c-dev node of BUS: a path as it is, a number N as /dev/i2c-N, a
 * name as /dev/i2c-N of the one adapter i2c-N under class_dir
 * (SW_I2C_DEV_CLASS but in tests) whose name it is. No adapter, or
 * several, of that name is SW_EXIT_DEVICE, with the adapters present in
 * the message.
 */
int sw_i2c_bus_path(const char *bus, const char *class_dir, char *path,
		    size_t len, struct sw_err *e);

#endif
