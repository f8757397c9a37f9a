// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: the em7180 driver's calibration_data blob and the
 * file the driver restores at probe (caldata.h).
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

/* The header's fields (caldata.h) */
enum {
	HDR_FORMAT,
	HDR_PRODUCT,
	HDR_REVISION,
	HDR_RESERVED,
	HDR_ROM,		/* u16 LE */
	HDR_RAM = HDR_ROM + 2,	/* u16 LE */
};

static void put_le16(uint8_t *p, uint16_t v)
{
	p[0] = (uint8_t)v;
	p[1] = (uint8_t)(v >> 8);
}

static uint16_t get_le16(const uint8_t *p)
{
	return (uint16_t)(p[0] | p[1] << 8);
}

void sw_caldata_encode(const struct sw_chip_info *chip, const uint8_t *payload,
		       uint8_t out[SW_CALDATA_SIZE])
{
	out[HDR_FORMAT] = SW_CALDATA_FORMAT;
	out[HDR_PRODUCT] = chip->product_id;
	out[HDR_REVISION] = chip->revision_id;
	out[HDR_RESERVED] = 0;
	put_le16(&out[HDR_ROM], chip->rom_version);
	put_le16(&out[HDR_RAM], chip->ram_version);
	memcpy(&out[SW_CALDATA_HDR_SIZE], payload, SW_BLOB_SIZE);
}

bool sw_caldata_decode(const uint8_t in[SW_CALDATA_SIZE],
		       struct sw_chip_info *chip, uint8_t *payload)
{
	if (in[HDR_FORMAT] != SW_CALDATA_FORMAT || in[HDR_RESERVED])
		return false;
	chip->product_id = in[HDR_PRODUCT];
	chip->revision_id = in[HDR_REVISION];
	chip->rom_version = get_le16(&in[HDR_ROM]);
	chip->ram_version = get_le16(&in[HDR_RAM]);
	memcpy(payload, &in[SW_CALDATA_HDR_SIZE], SW_BLOB_SIZE);
	return true;
}

bool sw_caldata_name(const char *dev, char *out, size_t len)
{
	int n = snprintf(out, len, PREFIX "%s" SUFFIX, dev);

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

/* "caldata-HHHH-HHHH-DEV.bin" for this DEV: what drivers before 1.2.0 read */
static bool is_versioned_of(const char *name, const char *dev)
{
	size_t pl = strlen(PREFIX), dl = strlen(dev), sl = strlen(SUFFIX);
	const char *v = name + pl;

	return strlen(name) == pl + 10 + dl + sl && !strncmp(name, PREFIX, pl) &&
	       is_hex4(v) && v[4] == '-' && is_hex4(v + 5) && v[9] == '-' &&
	       !strncmp(v + 10, dev, dl) && !strcmp(v + 10 + dl, SUFFIX);
}

/* The versioned files of dev in dir, all of them tried. */
static int remove_versioned(const char *dir, const char *dev, struct sw_err *e)
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
		if (!is_versioned_of(de->d_name, dev))
			continue;
		/* A symlink goes itself: unlinkat never follows one. */
		if (unlinkat(fd, de->d_name, 0) < 0 && errno != ENOENT && !ret)
			ret = sw_err_set(e, SW_EXIT_IO,
					 "%s/%s: cannot remove this file of an older driver: %s",
					 dir, de->d_name, strerror(errno));
	}
	closedir(d);
	return ret;
}

int sw_caldata_write(const char *state_dir, const struct sw_chip_info *chip,
		     const char *dev, const uint8_t *payload, bool *wrote,
		     struct sw_err *e)
{
	uint8_t now[SW_FILE_MAX_READ + 1], blob[SW_CALDATA_SIZE];
	char dir[4096], name[256], path[4400];
	struct sw_err re;
	size_t len;
	int ret;

	if (wrote)
		*wrote = false;
	sw_caldata_encode(chip, payload, blob);
	if (!sw_caldata_name(dev, name, sizeof(name)))
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%s: device name too long for a calibration file name",
				  dev);
	snprintf(dir, sizeof(dir), "%s/" SW_CALDATA_DIR, state_dir);
	snprintf(path, sizeof(path), "%s/%s", dir, name);
	/* Written only when it changes: flash wears with each write. */
	sw_err_clear(&re);
	if (sw_file_read(path, SW_READ_STATE, now, &len, NULL, &re) ||
	    len != SW_CALDATA_SIZE || memcmp(now, blob, SW_CALDATA_SIZE)) {
		ret = sw_file_write_atomic(path, blob, SW_CALDATA_SIZE, true, e);
		if (ret)
			return ret;
		if (wrote)
			*wrote = true;
	} else {
		/* A save killed while it wrote the file left its temp file */
		sw_file_remove_stale_temps(path);
	}
	return remove_versioned(dir, dev, e);
}
