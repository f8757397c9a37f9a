// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: what an errno from the em7180 driver's sysfs means,
 * or from libiio's scan of the IIO devices, as an exit code and a message
 * that says what to do about it.
 */
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <string.h>
#include <sys/stat.h>

#include "backend.h"

int sw_iio_err(struct sw_err *e, const char *name, const char *op,
	       const char *attr, int err, bool dir_gone)
{
	const char *hint = "";

	if (err == ENODEV || dir_gone)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%s is gone (unbound or unplugged): %s %s: %s",
				  name, op, attr, strerror(err));
	if (err == ENOENT)
		return sw_err_set(e, SW_EXIT_DRIVER,
				  "%s: %s %s: the driver has no such attribute: it is older or newer than this tool",
				  name, op, attr);
	/* The driver refuses writes while a buffer runs; nothing ends it for us. */
	if (err == EBUSY)
		return sw_err_set(e, SW_EXIT_IO,
				  "%s: %s %s: %s: a buffer is enabled on %s (a program is streaming from it, or one that exited without disabling it): stop it, or write 0 to /sys/bus/iio/devices/%s/buffer/enable",
				  name, op, attr, strerror(err), name, name);
	if (err == ETIMEDOUT)
		hint = " (the chip did not acknowledge a parameter)";
	else if (err == EINVAL)
		hint = " (the driver refused the value)";
	return sw_err_set(e, SW_EXIT_IO, "%s: %s %s: %s%s", name, op, attr,
			  strerror(err), hint);
}

/*
 * An entry that libiio's scan stats (local.c, foreach_in_dir()): it fails
 * on the first entry stat() fails on, with that errno, and on a directory
 * it cannot open. Returns 0 when path is fine, else the errno, with *link
 * set for a symbolic link that leads nowhere.
 */
static int entry_err(const char *path, bool *link)
{
	struct stat st;
	int err;

	*link = false;
	if (stat(path, &st) == 0)
		return 0;
	err = errno;
	*link = err == ENOENT && lstat(path, &st) == 0 && S_ISLNK(st.st_mode);
	return err;
}

/* A device's directory and the entries in it, as libiio reads them. */
static int device_err(struct sw_err *e, const char *sysfs, const char *dev)
{
	char dir[PATH_MAX], path[PATH_MAX + 256];
	struct dirent *de;
	bool link;
	int err;
	DIR *d;

	snprintf(dir, sizeof(dir), "%s/%s", sysfs, dev);
	err = entry_err(dir, &link);
	if (link)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%s: %s is a broken link: the device went away while the tool looked (unbound or unplugged), or sysfs is damaged",
				  dev, dir);
	if (err)
		return sw_err_set(e, SW_EXIT_DEVICE, "%s: %s: %s", dev, dir,
				  strerror(err));
	d = opendir(dir);
	if (!d)
		return errno == ENOTDIR ? SW_EXIT_OK :
		       sw_err_set(e, SW_EXIT_DEVICE, "%s: cannot list %s: %s",
				  dev, dir, strerror(errno));
	while ((de = readdir(d))) {
		snprintf(path, sizeof(path), "%s/%s", dir, de->d_name);
		err = entry_err(path, &link);
		if (err)
			break;
	}
	closedir(d);
	if (link)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%s: %s is a broken link", dev, path);
	if (err)
		return sw_err_set(e, SW_EXIT_DEVICE, "%s: %s: %s", dev, path,
				  strerror(err));
	return SW_EXIT_OK;
}

int sw_iio_scan_err(struct sw_err *e, const char *sysfs, int err)
{
	struct dirent *de;
	struct stat st;
	int ret = SW_EXIT_OK;
	DIR *d;

	if (err == ENOMEM)
		return sw_err_set(e, SW_EXIT_OSERR,
				  "cannot list the IIO devices: %s", strerror(err));
	if (stat(sysfs, &st) < 0 && errno == ENOENT)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "no IIO devices at all (%s is missing): is the em7180_i2c driver loaded? without a driver use --i2c",
				  sysfs);
	d = opendir(sysfs);
	if (!d)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "cannot list the IIO devices: %s: %s", sysfs,
				  strerror(errno));
	while (!ret && (de = readdir(d)))
		if (de->d_name[0] != '.')
			ret = device_err(e, sysfs, de->d_name);
	closedir(d);
	if (ret)
		return ret;
	/* Gone by now: something changed under libiio's scan. */
	return sw_err_set(e, SW_EXIT_DEVICE,
			  "cannot list the IIO devices in %s: %s (they changed while the tool looked: try again)",
			  sysfs, strerror(err));
}
