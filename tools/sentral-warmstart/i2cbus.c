// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: --i2c BUS, a bus number, an adapter name or a path.
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "i2cbus.h"

/*
 * A path begins with '/' or '.': an adapter's name may hold a '/' (i915
 * names its DP AUX adapters "AUX %s/%s", drivers/gpu/drm/i915/display/
 * intel_dp_aux.c).
 */
static bool is_path(const char *bus)
{
	return bus[0] == '/' || bus[0] == '.';
}

int sw_i2c_bus_check(const char *bus, struct sw_err *e)
{
	unsigned long nr;

	if (!*bus)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "--i2c is empty: give a bus number, an adapter name or a path");
	if (!is_path(bus) &&
	    sw_parse_number(bus, SW_I2C_BUS_MAX, &nr) == ERANGE)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "--i2c: bus '%s' is out of range (0 to %u)",
				  bus, SW_I2C_BUS_MAX);
	return SW_EXIT_OK;
}

/* "i2c-N": N, else -1. */
static long entry_bus(const char *name)
{
	unsigned long nr;

	if (strncmp(name, "i2c-", 4) ||
	    sw_parse_number(name + 4, SW_I2C_BUS_MAX, &nr) ||
	    !strncmp(name + 4, "0x", 2) || !strncmp(name + 4, "0X", 2))
		return -1;
	return (long)nr;
}

static int by_bus(const struct dirent **a, const struct dirent **b)
{
	long x = entry_bus((*a)->d_name), y = entry_bus((*b)->d_name);

	return (x > y) - (x < y);
}

static int is_adapter(const struct dirent *d)
{
	return entry_bus(d->d_name) >= 0;
}

/* The adapter's name from class_dir/i2c-N/name, without its newline. */
static void adapter_name(const char *class_dir, const char *entry, char *buf,
			 size_t len)
{
	char path[512];
	ssize_t n;
	int fd;

	snprintf(path, sizeof(path), "%s/%s/name", class_dir, entry);
	fd = open(path, O_RDONLY | O_CLOEXEC);
	n = fd < 0 ? -1 : read(fd, buf, len - 1);
	if (fd >= 0)
		close(fd);
	if (n < 0)
		n = 0;
	buf[n] = '\0';
	if (n > 0 && buf[n - 1] == '\n')
		buf[n - 1] = '\0';
}

/* Append item to a list for a message; "..." once it is full. */
static void list_add(char *list, size_t len, const char *item)
{
	size_t n = strlen(list);

	if (n + 4 >= len)
		return;
	if ((size_t)snprintf(list + n, len - n, "%s%s", n ? ", " : "",
			     item) >= len - n)
		strcpy(list + len - 4, "...");
}

static int lookup_name(const char *bus, const char *class_dir, char *path,
		       size_t len, struct sw_err *e)
{
	char name[64], item[96], all[320] = "", same[160] = "";
	struct dirent **ents;
	int i, n, matches = 0;
	long found = -1;

	n = scandir(class_dir, &ents, is_adapter, by_bus);
	if (n < 0)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "--i2c '%s': no bus of that name: %s: %s%s",
				  bus, class_dir, strerror(errno),
				  errno == ENOENT ? " (is the i2c-dev module loaded?)" : "");
	for (i = 0; i < n; i++) {
		long nr = entry_bus(ents[i]->d_name);

		adapter_name(class_dir, ents[i]->d_name, name, sizeof(name));
		snprintf(item, sizeof(item), "%ld '%s'", nr, name);
		list_add(all, sizeof(all), item);
		if (!strcmp(name, bus)) {
			matches++;
			found = nr;
			list_add(same, sizeof(same), item);
		}
		free(ents[i]);
	}
	free(ents);
	if (!n)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "--i2c '%s': no bus of that name: there is no I2C adapter at all (%s is empty)",
				  bus, class_dir);
	if (!matches)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "--i2c '%s': no bus of that name; the buses are %s",
				  bus, all);
	if (matches > 1)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "--i2c '%s': %d buses have that name (%s): give the bus number instead",
				  bus, matches, same);
	snprintf(path, len, "/dev/i2c-%ld", found);
	return SW_EXIT_OK;
}

int sw_i2c_bus_path(const char *bus, const char *class_dir, char *path,
		    size_t len, struct sw_err *e)
{
	unsigned long nr;
	int ret;

	ret = sw_i2c_bus_check(bus, e);
	if (ret)
		return ret;
	if (is_path(bus)) {
		if ((size_t)snprintf(path, len, "%s", bus) >= len)
			return sw_err_set(e, SW_EXIT_USAGE,
					  "--i2c: the path is too long");
		return SW_EXIT_OK;
	}
	if (!sw_parse_number(bus, SW_I2C_BUS_MAX, &nr)) {
		snprintf(path, len, "/dev/i2c-%lu", nr);
		return SW_EXIT_OK;
	}
	return lookup_name(bus, class_dir, path, len, e);
}
