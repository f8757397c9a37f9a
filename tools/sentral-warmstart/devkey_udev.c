// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: the parts of a chip's key, found in sysfs and udev
 * through libudev (see devkey.h).
 */
#include <dirent.h>
#include <limits.h>
#include <libudev.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "devkey.h"

/* realpath of DIR/NAME when it is a symlink, else false. */
static bool link_target(const char *dir, const char *name, char *out)
{
	char path[PATH_MAX];

	if (snprintf(path, sizeof(path), "%s/%s", dir, name) >= (int)sizeof(path))
		return false;
	return realpath(path, out) != NULL;
}

/* The adapter's devicetree node, "of/soc/i2c@7e804000", if any. */
static bool adapter_of_node(const char *syspath, char *root, size_t len)
{
	char target[PATH_MAX];
	const char *p;

	if (!link_target(syspath, "of_node", target))
		return false;
	p = strstr(target, "/devicetree/base");
	if (!p)
		return false;
	p += strlen("/devicetree/base");
	snprintf(root, len, "of%s", *p ? p : "/");
	return true;
}

/* The adapter's ACPI path without its leading backslash, if any. */
static bool adapter_acpi_path(struct udev_device *adap, char *root,
			      size_t len)
{
	const char *path = udev_device_get_sysattr_value(adap,
							 "firmware_node/path");

	if (!path || !*path)
		return false;
	while (*path == '\\')
		path++;
	snprintf(root, len, "acpi-%.*s", (int)strcspn(path, "\n"), path);
	return true;
}

/* 7-bit address of an I2C client named "N-00AA", or -1. */
static int client_addr(const char *sysname)
{
	const char *dash = strchr(sysname, '-');
	unsigned long a;
	char *end;

	if (!dash || dash == sysname || strlen(dash + 1) != 4)
		return -1;
	a = strtoul(dash + 1, &end, 16);
	if (*end || a > 0x7f)
		return -1;
	return (int)a;
}

/*
 * I2C adapters and clients share the "i2c" subsystem and have no DEVTYPE:
 * the kernel names adapters "i2c-N" and clients "N-00AA".
 */
static bool is_i2c(struct udev_device *d)
{
	const char *sub = udev_device_get_subsystem(d);

	return sub && !strcmp(sub, "i2c");
}

static bool is_adapter(struct udev_device *d)
{
	return is_i2c(d) && !strncmp(udev_device_get_sysname(d), "i2c-", 4);
}

static bool is_client(struct udev_device *d)
{
	return is_i2c(d) && client_addr(udev_device_get_sysname(d)) >= 0;
}

/* The nearest ancestor that is an I2C adapter; it belongs to d. */
static struct udev_device *parent_adapter(struct udev_device *d)
{
	while ((d = udev_device_get_parent(d)))
		if (is_adapter(d))
			return d;
	return NULL;
}

/*
 * A mux channel adapter: which mux ("0x70" for a mux chip on the bus, else
 * the mux device's name) and which of its channels.
 */
static bool adapter_mux_hop(struct udev *u, const char *syspath,
			    char *mux, size_t mux_len, unsigned int *chan)
{
	char muxpath[PATH_MAX], self[PATH_MAX], target[PATH_MAX];
	struct udev_device *md;
	struct dirent *de;
	bool found = false;
	DIR *d;
	int a;

	if (!link_target(syspath, "mux_device", muxpath) ||
	    !realpath(syspath, self))
		return false;
	d = opendir(muxpath);
	if (!d)
		return false;
	while (!found && (de = readdir(d))) {
		unsigned int n;
		char tail;

		if (sscanf(de->d_name, "channel-%u%c", &n, &tail) != 1)
			continue;
		if (link_target(muxpath, de->d_name, target) &&
		    !strcmp(target, self)) {
			*chan = n;
			found = true;
		}
	}
	closedir(d);
	if (!found)
		return false;
	md = udev_device_new_from_syspath(u, muxpath);
	if (!md)
		return false;
	a = is_client(md) ? client_addr(udev_device_get_sysname(md)) : -1;
	if (a >= 0)
		snprintf(mux, mux_len, "0x%02x", a);
	else
		snprintf(mux, mux_len, "%s", udev_device_get_sysname(md));
	udev_device_unref(md);
	return true;
}

int sw_key_of_adapter(struct udev_device *adapter, unsigned int addr,
		      const char *id_path, char *key, size_t len,
		      struct sw_err *e)
{
	struct udev_device *adap = udev_device_ref(adapter), *up;
	struct udev *u = udev_device_get_udev(adapter);
	struct sw_key_parts p;
	int i;

	memset(&p, 0, sizeof(p));
	p.addr = addr;
	/* Up through mux channels until an adapter names itself. */
	for (;;) {
		const char *syspath = udev_device_get_syspath(adap);
		const char *name;
		char mux[64];
		unsigned int chan;

		if (adapter_of_node(syspath, p.root, sizeof(p.root)) ||
		    adapter_acpi_path(adap, p.root, sizeof(p.root)))
			break;
		if (p.nhops < SW_KEY_MAX_HOPS &&
		    adapter_mux_hop(u, syspath, mux, sizeof(mux), &chan)) {
			up = parent_adapter(adap);
			if (up) {
				/* Hops are found leaf first; the key lists them root first. */
				for (i = p.nhops; i > 0; i--)
					p.hop[i] = p.hop[i - 1];
				snprintf(p.hop[0].mux, sizeof(p.hop[0].mux), "%s", mux);
				p.hop[0].chan = chan;
				p.nhops++;
				/* The parent belongs to adap: keep our own reference. */
				udev_device_ref(up);
				udev_device_unref(adap);
				adap = up;
				continue;
			}
		}
		if (id_path && *id_path) {
			snprintf(p.root, sizeof(p.root), "%s", id_path);
			break;
		}
		name = udev_device_get_sysattr_value(adap, "name");
		snprintf(p.root, sizeof(p.root), "adapter-%s", name ? name : "");
		break;
	}
	udev_device_unref(adap);
	if (!sw_key_compose(&p, key, len))
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "the key of the chip at 0x%02x on %s is longer than %zu characters",
				  addr, udev_device_get_sysname(adapter), len - 1);
	return SW_EXIT_OK;
}

int sw_key_of_client(struct udev_device *client, const char *id_path,
		     char *key, size_t len, struct sw_err *e)
{
	struct udev_device *adap = is_client(client) ? parent_adapter(client) : NULL;

	if (!adap)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%s is not a 7-bit I2C client on an adapter",
				  udev_device_get_syspath(client));
	return sw_key_of_adapter(adap, (unsigned int)client_addr(
					 udev_device_get_sysname(client)),
				 id_path, key, len, e);
}

struct udev_device *sw_udev_i2c_client(struct udev_device *d)
{
	while (d && !is_client(d))
		d = udev_device_get_parent(d);
	return d;
}

struct udev_device *sw_udev_i2c_adapter(struct udev_device *d)
{
	return is_adapter(d) ? d : parent_adapter(d);
}
