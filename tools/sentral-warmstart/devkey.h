/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: the key that names a chip's saved file and its
 * systemd units, stable across boots, udev events and driver rebinds:
 *
 *   KEY = ROOT { "-mux" MUX "-ch" N } "-0x" AA
 *
 * ROOT names the I2C adapter the chip (or its mux) hangs off, from the
 * most stable source the system has: the adapter's devicetree node
 * ("of-soc-i2c_7e804000"), its ACPI path ("acpi-_SB_.PCI0.I2C1"), udev's
 * ID_PATH of its controller ("pci-0000_00_14.0-usb-0_2_1.0") or, for an
 * adapter with no parent device, its name ("adapter-NAME"). Each mux
 * channel without a firmware node of its own adds the mux (its address
 * "0x70", or its device name) and the channel number; AA is the chip's
 * 7-bit address. Adapter numbers (i2c-N) never appear: they can change
 * from boot to boot. The man page's KEY section is the user's version.
 */
#ifndef SW_DEVKEY_H
#define SW_DEVKEY_H

#include <stdbool.h>
#include <stddef.h>

#include "sw.h"

/* systemd unit names are at most 255 bytes; "-" escapes to 4 bytes. */
#define SW_KEY_MAX 200
#define SW_KEY_MAX_HOPS 4

struct sw_key_parts {
	char root[160];		/* "of-/soc/i2c@7e804000", an ID_PATH, ... */
	struct {
		char mux[64];	/* "0x70" or the mux device's name */
		unsigned int chan;
	} hop[SW_KEY_MAX_HOPS];	/* the mux nearest the root first */
	int nhops;
	unsigned int addr;
};

/* Keep [A-Za-z0-9._-], replace anything else by '_'; never empty. */
void sw_sanitize_key(const char *in, char *out, size_t len);

/* The key of parts; false when it would not fit in len. */
bool sw_key_compose(const struct sw_key_parts *p, char *key, size_t len);

/*
 * The key as a systemd unit instance name (systemd-escape KEY): "-"
 * becomes "\x2d". False when it would not fit in len.
 */
bool sw_key_unit_escape(const char *key, char *out, size_t len);

struct udev;
struct udev_device;

/* The I2C client d is or sits below (it belongs to d), or NULL. */
struct udev_device *sw_udev_i2c_client(struct udev_device *d);
/* The I2C adapter d is or sits below (it belongs to d), or NULL. */
struct udev_device *sw_udev_i2c_adapter(struct udev_device *d);

/*
 * The key of the chip at addr on adapter (an I2C adapter device).
 * id_path is udev's ID_PATH of a device below that adapter's controller
 * (NULL when udev has none). Returns SW_EXIT_OK or SW_EXIT_DEVICE.
 */
int sw_key_of_adapter(struct udev_device *adapter, unsigned int addr,
		      const char *id_path, char *key, size_t len,
		      struct sw_err *e);

/* The key of an I2C client device ("N-00AA"). */
int sw_key_of_client(struct udev_device *client, const char *id_path,
		     char *key, size_t len, struct sw_err *e);

#endif
