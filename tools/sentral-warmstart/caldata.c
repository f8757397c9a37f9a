// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: the file the em7180 driver restores at probe.
 */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "caldata.h"
#include "wsfile.h"

#define PREFIX "caldata-"
#define SUFFIX ".bin"

bool sw_caldata_name(const struct sw_chip_info *chip, const char *dev,
		     char *out, size_t len)
{
	int n = snprintf(out, len, PREFIX "%04x-%04x-%s" SUFFIX,
			 chip->rom_version, chip->ram_version, dev);

	return n > 0 && (size_t)n < len;
}

static bool is_hex4(const char *s)
{
	int i;

	for (i = 0; i < 4; i++)
		if (!((s[i] >= '0' && s[i] <= '9') || (s[i] >= 'a' && s[i] <= 'f')))
			return false;
	return true;
}

/* "caldata-HHHH-HHHH-DEV.bin" for this DEV, whatever the versions. */
static bool is_caldata_of(const char *name, const char *dev)
{
	size_t pl = strlen(PREFIX), dl = strlen(dev), sl = strlen(SUFFIX);
	const char *v = name + pl;

	return strlen(name) == pl + 10 + dl + sl && !strncmp(name, PREFIX, pl) &&
	       is_hex4(v) && v[4] == '-' && is_hex4(v + 5) && v[9] == '-' &&
	       !strncmp(v + 10, dev, dl) && !strcmp(v + 10 + dl, SUFFIX);
}

/* The other versions' files of dev in dir, all of them tried. */
static int remove_others(const char *dir, const char *keep, const char *dev,
			 struct sw_err *e)
{
	struct dirent *de;
	DIR *d;
	int fd, ret = SW_EXIT_OK;

	fd = open(dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
	d = fd < 0 ? NULL : fdopendir(fd);
	if (!d) {
		ret = sw_err_set(e, SW_EXIT_IO, "%s: %s", dir, strerror(errno));
		if (fd >= 0)
			close(fd);
		return ret;
	}
	while ((de = readdir(d))) {
		if (!is_caldata_of(de->d_name, dev) || !strcmp(de->d_name, keep))
			continue;
		/* A symlink goes itself: unlinkat never follows one. */
		if (unlinkat(fd, de->d_name, 0) < 0 && errno != ENOENT && !ret)
			ret = sw_err_set(e, SW_EXIT_IO,
					 "%s/%s: cannot remove this calibration of another firmware: %s",
					 dir, de->d_name, strerror(errno));
	}
	closedir(d);
	return ret;
}

int sw_caldata_write(const char *state_dir, const struct sw_chip_info *chip,
		     const char *dev, const uint8_t *blob, bool *wrote,
		     struct sw_err *e)
{
	uint8_t now[SW_FILE_MAX_READ + 1];
	char dir[4096], name[256], path[4400];
	struct sw_err re;
	size_t len;
	int ret;

	if (wrote)
		*wrote = false;
	if (!sw_caldata_name(chip, dev, name, sizeof(name)))
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%s: device name too long for a calibration file name",
				  dev);
	snprintf(dir, sizeof(dir), "%s/" SW_CALDATA_DIR, state_dir);
	snprintf(path, sizeof(path), "%s/%s", dir, name);
	/* Written only when it changes: flash wears with each write. */
	sw_err_clear(&re);
	if (sw_file_read(path, SW_READ_STATE, now, &len, NULL, &re) ||
	    len != SW_BLOB_SIZE || memcmp(now, blob, SW_BLOB_SIZE)) {
		ret = sw_file_write_atomic(path, blob, SW_BLOB_SIZE, true, e);
		if (ret)
			return ret;
		if (wrote)
			*wrote = true;
	} else {
		/* A save killed while it wrote the file left its temp file */
		sw_file_remove_stale_temps(path);
	}
	return remove_others(dir, name, dev, e);
}
