// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: driver backend (the em7180 IIO driver's sysfs ABI).
 *
 * libiio finds the device; every attribute is then read and written with
 * plain open/read/write on sysfs, because libiio 0.24's local backend
 * overwrites the last byte of what it reads (it assumes a trailing
 * newline), which would corrupt the binary calibration_data attribute.
 */
#include <errno.h>
#include <fcntl.h>
#include <iio.h>
#include <libudev.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "abi.h"
#include "backend.h"
#include "caldata.h"

#define IIO_SYSFS "/sys/bus/iio/devices"

struct iio_be {
	struct sw_backend b;
	char dir[PATH_MAX];	/* /sys/bus/iio/devices/iio:deviceN */
	char parent[64];	/* the I2C client, e.g. "0-0028" */
	double magn_ut;		/* in_magn_scale in uT per LSB, 0: not read yet */
	char id_path[256];	/* udev's ID_PATH, "" when none */
	/* b.checks_identity: that of the last blob read, when have_id */
	bool have_id;
	struct sw_chip_info id;
};

/* Copy with truncation; the callers' buffers are far larger than the data. */
static void copy_str(char *dst, size_t len, const char *src)
{
	size_t n = strnlen(src, len - 1);

	memcpy(dst, src, n);
	dst[n] = '\0';
}

static struct iio_be *to_iio(struct sw_backend *b)
{
	return (struct iio_be *)b;
}

static int read_text(const char *path, char *buf, size_t len)
{
	ssize_t n;
	int fd;

	fd = open(path, O_RDONLY | O_CLOEXEC);
	if (fd < 0)
		return -1;
	n = read(fd, buf, len - 1);
	close(fd);
	if (n < 0)
		return -1;
	buf[n] = '\0';
	while (n > 0 && (buf[n - 1] == '\n' || buf[n - 1] == ' '))
		buf[--n] = '\0';
	return 0;
}

/* For sw_abi_check(): ctx is the struct iio_be. */
static bool attr_exists(const char *attr, void *ctx)
{
	struct iio_be *ib = ctx;
	char path[PATH_MAX + 64];

	if (attr[0] == '/')
		return access(attr, F_OK) == 0;
	snprintf(path, sizeof(path), "%s/%s", ib->dir, attr);
	return access(path, F_OK) == 0;
}

/* A failed access: the device may have gone (unbound, unplugged). */
static int attr_err(struct iio_be *ib, const char *op, const char *attr,
		    int err, struct sw_err *e)
{
	return sw_iio_err(e, ib->b.name, op, attr, err,
			  access(ib->dir, F_OK) < 0 && errno == ENOENT);
}

static int attr_read(struct iio_be *ib, const char *attr, char *buf,
		     size_t len, struct sw_err *e)
{
	char path[PATH_MAX + 64];

	snprintf(path, sizeof(path), "%s/%s", ib->dir, attr);
	if (read_text(path, buf, len) < 0)
		return attr_err(ib, "reading", attr, errno, e);
	return SW_EXIT_OK;
}

/*
 * An attribute the device may lack or refuse: *err is 0 when it was read,
 * ENOENT when the device has no such attribute, EBUSY when the driver
 * refused while a buffer streams. Any other failure is returned.
 */
static int attr_read_soft(struct iio_be *ib, const char *attr, char *buf,
			  size_t len, int *err, struct sw_err *e)
{
	char path[PATH_MAX + 64];

	snprintf(path, sizeof(path), "%s/%s", ib->dir, attr);
	*err = 0;
	if (read_text(path, buf, len) == 0)
		return SW_EXIT_OK;
	*err = errno;
	if (*err == EBUSY || (*err == ENOENT && access(ib->dir, F_OK) == 0))
		return SW_EXIT_OK;
	return attr_err(ib, "reading", attr, *err, e);
}

static int parse_int(struct iio_be *ib, const char *attr, const char *buf,
		     int *val, struct sw_err *e)
{
	char *end;
	long v;

	errno = 0;
	v = strtol(buf, &end, 10);
	if (errno || end == buf || *end || v < INT_MIN || v > INT_MAX)
		return sw_err_set(e, SW_EXIT_IO, "%s: %s: unexpected value \"%s\"",
				  ib->b.name, attr, buf);
	*val = (int)v;
	return SW_EXIT_OK;
}

static int attr_read_int(struct iio_be *ib, const char *attr, int *val,
			 struct sw_err *e)
{
	char buf[64];
	int ret;

	ret = attr_read(ib, attr, buf, sizeof(buf), e);
	return ret ? ret : parse_int(ib, attr, buf, val, e);
}

/* A scale or an offset: a finite decimal number. */
static int parse_double(struct iio_be *ib, const char *attr, const char *buf,
			double *val, struct sw_err *e)
{
	char *end;

	errno = 0;
	*val = strtod(buf, &end);
	if (errno || end == buf || *end || !isfinite(*val))
		return sw_err_set(e, SW_EXIT_IO, "%s: %s: unexpected value \"%s\"",
				  ib->b.name, attr, buf);
	return SW_EXIT_OK;
}

static int attr_write_int(struct iio_be *ib, const char *attr, int val,
			  struct sw_err *e)
{
	char path[PATH_MAX + 64], buf[32];
	ssize_t n;
	int fd, len;

	snprintf(path, sizeof(path), "%s/%s", ib->dir, attr);
	len = snprintf(buf, sizeof(buf), "%d\n", val);
	fd = open(path, O_WRONLY | O_CLOEXEC);
	if (fd < 0)
		return attr_err(ib, "opening", attr, errno, e);
	n = write(fd, buf, (size_t)len);
	if (n != len) {
		int err = n < 0 ? errno : EIO;

		close(fd);
		return attr_err(ib, "writing to", attr, err, e);
	}
	close(fd);
	return SW_EXIT_OK;
}

/* An identity attribute: hexadecimal with "0x", at most max. */
static int attr_read_hex(struct iio_be *ib, const char *attr,
			 unsigned int max, unsigned int *val, struct sw_err *e)
{
	char buf[64], *end;
	unsigned long v;
	int ret;

	ret = attr_read(ib, attr, buf, sizeof(buf), e);
	if (ret)
		return ret;
	errno = 0;
	v = strtoul(buf, &end, 16);
	if (errno || strncmp(buf, "0x", 2) || *end || v > max)
		return sw_err_set(e, SW_EXIT_IO, "%s: %s: unexpected value \"%s\"",
				  ib->b.name, attr, buf);
	*val = (unsigned int)v;
	return SW_EXIT_OK;
}

static int iio_read_blob(struct sw_backend *b, uint8_t *blob,
			 struct sw_err *e);

/*
 * The identity a saved file is checked against: ProductID, RevisionID and
 * the ROM/RAM versions, as the driver read them from the chip: in the
 * header of calibration_data, from the read of it that a save or status
 * made already, else from one read now; from attributes before 1.2.0.
 */
static int iio_chip_info(struct sw_backend *b, struct sw_chip_info *ci,
			 struct sw_err *e)
{
	struct iio_be *ib = to_iio(b);
	unsigned int pid = 0, rev = 0, rom = 0, ram = 0;
	uint8_t blob[SW_BLOB_SIZE];
	int ret;

	if (b->checks_identity) {
		ret = ib->have_id ? SW_EXIT_OK : iio_read_blob(b, blob, e);
		if (!ret)
			*ci = ib->id;
		return ret;
	}

	ret = attr_read_hex(ib, "product_id", 0xff, &pid, e);
	ret = ret ? ret : attr_read_hex(ib, "revision_id", 0xff, &rev, e);
	ret = ret ? ret : attr_read_hex(ib, "rom_version", 0xffff, &rom, e);
	ret = ret ? ret : attr_read_hex(ib, "ram_version", 0xffff, &ram, e);
	if (ret)
		return ret;
	ci->product_id = (uint8_t)pid;
	ci->revision_id = (uint8_t)rev;
	ci->rom_version = (uint16_t)rom;
	ci->ram_version = (uint16_t)ram;
	return SW_EXIT_OK;
}

/* in_magn_calibration_auto_status: the level, on every firmware. */
static int iio_level(struct iio_be *ib, int *level, struct sw_err *e)
{
	static const char attr[] = "in_magn_calibration_auto_status";
	char path[PATH_MAX + 64], buf[64];

	snprintf(path, sizeof(path), "%s/%s", ib->dir, attr);
	if (read_text(path, buf, sizeof(buf)) < 0) {
		int err = errno, ret = attr_err(ib, "reading", attr, err, e);

		/* The driver's answer to reserved bits in AlgorithmStatus. */
		if (err == EIO)
			sw_err_append(e, " (AlgorithmStatus read with a reserved bit set: a glitched read, not trusted)");
		return ret;
	}
	return parse_int(ib, attr, buf, level, e);
}

/*
 * A score attribute the driver may not have: *absent when the device has
 * no such attribute (firmware without the application note's layout at
 * probe) or it reads ENODATA (the layout is gone since).
 */
static int iio_score_attr(struct iio_be *ib, const char *attr, char *buf,
			  size_t len, bool *absent, struct sw_err *e)
{
	char path[PATH_MAX + 64];
	int err;

	snprintf(path, sizeof(path), "%s/%s", ib->dir, attr);
	*absent = false;
	if (read_text(path, buf, len) == 0)
		return SW_EXIT_OK;
	err = errno;
	if (err == ENODATA || (err == ENOENT && access(ib->dir, F_OK) == 0)) {
		*absent = true;
		return SW_EXIT_OK;
	}
	return attr_err(ib, "reading", attr, err, e);
}

/* A flag attribute: "0" or "1". */
static int parse_flag(struct iio_be *ib, const char *attr, const char *buf,
		      int *val, struct sw_err *e)
{
	int ret = parse_int(ib, attr, buf, val, e);

	if (!ret && *val != 0 && *val != 1)
		return sw_err_set(e, SW_EXIT_IO, "%s: %s: unexpected value %d",
				  ib->b.name, attr, *val);
	return ret;
}

/*
 * Score and update flags, where the driver has them (cs->has_score).
 * They read ENODATA from the moment the driver finds the layout gone.
 */
static int iio_score(struct iio_be *ib, struct sw_cal_state *cs,
		     struct sw_err *e)
{
	static const char *const flags[2] = {
		"in_anglvel_calibration_update", "in_magn_calibration_update",
	};
	int *flag[2] = { &cs->gyro_bias_update, &cs->mag_cal_update };
	char score[64], buf[64];
	bool absent;
	int i, ret;

	cs->has_score = false;
	ret = iio_score_attr(ib, "in_magn_calibration_score", score,
			     sizeof(score), &absent, e);
	for (i = 0; i < 2 && !ret && !absent; i++) {
		ret = iio_score_attr(ib, flags[i], buf, sizeof(buf), &absent,
				     e);
		if (!ret && !absent)
			ret = parse_flag(ib, flags[i], buf, flag[i], e);
	}
	if (ret || absent) {
		cs->gyro_bias_update = cs->mag_cal_update = 0;
		return ret;
	}
	/* 3 decimals resolve the 100/32768 % steps: the raw value is exact. */
	if (!sw_parse_score(score, &cs->score_raw))
		return sw_err_set(e, SW_EXIT_IO,
				  "%s: in_magn_calibration_score: unexpected value \"%s\" (not a percentage from -100 to 100)",
				  ib->b.name, score);
	cs->has_score = true;
	return SW_EXIT_OK;
}

/*
 * The level alone where the firmware has no score: one bus transaction.
 * With a score, the driver serves score and flags from one burst read of
 * the chip for 500 ms. They need not come from the level's read: save
 * and calibrate judge a blob by the states read before and after it.
 */
static int iio_cal_state(struct sw_backend *b, struct sw_cal_state *cs,
			 struct sw_err *e)
{
	struct iio_be *ib = to_iio(b);
	int ret;

	memset(cs, 0, sizeof(*cs));
	ret = iio_level(ib, &cs->level, e);
	return ret ? ret : iio_score(ib, cs, e);
}

static int blob_err(struct iio_be *ib, const char *op, int err,
		    struct sw_err *e)
{
	return attr_err(ib, op, "calibration_data", err, e);
}

/* The blob's size: with its identity header since 1.2.0 (caldata.h). */
static size_t blob_size(const struct iio_be *ib)
{
	return ib->b.checks_identity ? SW_CALDATA_SIZE : SW_BLOB_SIZE;
}

static int iio_read_blob(struct sw_backend *b, uint8_t *blob,
			 struct sw_err *e)
{
	struct iio_be *ib = to_iio(b);
	char path[PATH_MAX + 24];
	uint8_t buf[SW_CALDATA_SIZE];
	size_t size = blob_size(ib);
	ssize_t n;
	int fd, err;

	snprintf(path, sizeof(path), "%s/calibration_data", ib->dir);
	fd = open(path, O_RDONLY | O_CLOEXEC);
	if (fd < 0)
		return blob_err(ib, "opening", errno, e);
	/* Whole blob in one read at offset 0, as the ABI requires. */
	n = read(fd, buf, size);
	err = n < 0 ? errno : EIO;
	close(fd);
	if (n < 0 || (size_t)n != size)
		return blob_err(ib, "reading", err, e);
	if (!b->checks_identity) {
		memcpy(blob, buf, SW_BLOB_SIZE);
		return SW_EXIT_OK;
	}
	if (!sw_caldata_decode(buf, &ib->id, blob))
		return sw_err_set(e, SW_EXIT_DRIVER,
				  "%s: calibration_data starts %02x %02x %02x %02x, not the header of format %d: a driver newer than this tool; install the sentral-warmstart of the driver's release",
				  b->name, buf[0], buf[1], buf[2], buf[3],
				  SW_CALDATA_FORMAT);
	ib->have_id = true;
	return SW_EXIT_OK;
}

static int iio_write_blob(struct sw_backend *b, const struct sw_chip_info *chip,
			  const uint8_t *blob, struct sw_err *e)
{
	struct iio_be *ib = to_iio(b);
	char path[PATH_MAX + 24];
	uint8_t buf[SW_CALDATA_SIZE];
	size_t size = blob_size(ib);
	ssize_t n;
	int fd, err;

	if (b->checks_identity)
		sw_caldata_encode(chip, blob, buf);
	else
		memcpy(buf, blob, SW_BLOB_SIZE);
	/* The chip's identity is read again after a write, refused or not */
	ib->have_id = false;
	snprintf(path, sizeof(path), "%s/calibration_data", ib->dir);
	fd = open(path, O_WRONLY | O_CLOEXEC);
	if (fd < 0)
		return blob_err(ib, "opening", errno, e);
	n = write(fd, buf, size);
	err = n < 0 ? errno : EIO;
	if (close(fd) < 0 && n >= 0 && (size_t)n == size) {
		n = -1;
		err = errno;
	}
	/* The payload was checked finite: the header is what it refused */
	if (n < 0 && err == EINVAL && b->checks_identity)
		return sw_err_set(e, SW_EXIT_FILE,
				  "%s: the driver refused the calibration of ProductID 0x%02x, RevisionID 0x%02x, ROM 0x%04x, RAM 0x%04x: saved on another chip or firmware",
				  b->name, chip->product_id, chip->revision_id,
				  chip->rom_version, chip->ram_version);
	if (n < 0 || (size_t)n != size)
		return blob_err(ib, "writing", err, e);
	return SW_EXIT_OK;
}

static const char *const axes[3] = { "x", "y", "z" };

static int iio_accel_raw(struct sw_backend *b, int xyz[3], struct sw_err *e)
{
	char attr[32];
	int i, ret;

	for (i = 0; i < 3; i++) {
		snprintf(attr, sizeof(attr), "in_accel_%s_raw", axes[i]);
		ret = attr_read_int(to_iio(b), attr, &xyz[i], e);
		if (ret)
			return ret;
	}
	return SW_EXIT_OK;
}

static int iio_mag(struct sw_backend *b, double ut[3], struct sw_err *e)
{
	struct iio_be *ib = to_iio(b);
	char attr[32], buf[64], *end;
	int raw[3], i, ret;

	if (!ib->magn_ut) {
		ret = attr_read(ib, "in_magn_scale", buf, sizeof(buf), e);
		if (ret)
			return ret;
		/* IIO magnetometers are in gauss: 1 G = 100 uT. */
		ib->magn_ut = strtod(buf, &end) * 100;
		if (end == buf || *end || !(ib->magn_ut > 0))
			return sw_err_set(e, SW_EXIT_IO,
					  "%s: in_magn_scale: unexpected value \"%s\"",
					  b->name, buf);
	}
	for (i = 0; i < 3; i++) {
		snprintf(attr, sizeof(attr), "in_magn_%s_raw", axes[i]);
		ret = attr_read_int(ib, attr, &raw[i], e);
		if (ret)
			return ret;
	}
	for (i = 0; i < 3; i++)
		ut[i] = raw[i] * ib->magn_ut;
	return SW_EXIT_OK;
}

static int iio_accel_offset_get(struct sw_backend *b, int lsb[3],
				struct sw_err *e)
{
	char attr[32];
	int i, ret;

	for (i = 0; i < 3; i++) {
		snprintf(attr, sizeof(attr), "in_accel_%s_calibbias", axes[i]);
		ret = attr_read_int(to_iio(b), attr, &lsb[i], e);
		if (ret)
			return ret;
	}
	return SW_EXIT_OK;
}

static int iio_accel_offset_set(struct sw_backend *b, const int lsb[3],
				struct sw_err *e)
{
	char attr[32];
	int i, ret;

	for (i = 0; i < 3; i++) {
		snprintf(attr, sizeof(attr), "in_accel_%s_calibbias", axes[i]);
		ret = attr_write_int(to_iio(b), attr, lsb[i], e);
		if (ret)
			return ret;
	}
	return SW_EXIT_OK;
}

/*
 * firmware_source: "eeprom" or "host", in the drivers before 1.2.0 that
 * have it; later ones say it in the kernel log at probe and in debugfs
 * (firmware_version), which are no interface: status says unknown.
 */
static int iio_fw_source(struct iio_be *ib, struct sw_hub_info *hi,
			 struct sw_err *e)
{
	static const char attr[] = "firmware_source";
	char buf[64];
	int err, ret;

	ret = attr_read_soft(ib, attr, buf, sizeof(buf), &err, e);
	if (ret)
		return ret;
	if (err)
		snprintf(hi->fw_why, sizeof(hi->fw_why),
			 "not in the em7180 driver's sysfs; its probe line in the kernel log says");
	else if (!strcmp(buf, "eeprom"))
		hi->fw_source = SW_FW_EEPROM;
	else if (!strcmp(buf, "host"))
		hi->fw_source = SW_FW_HOST;
	else
		snprintf(hi->fw_why, sizeof(hi->fw_why),
			 "%s reads \"%.60s\"", attr, buf);
	return SW_EXIT_OK;
}

/* The channel of each feature sensor, and its IIO unit per the tool's. */
static const struct {
	const char *chan;	/* in_<chan>_raw */
	double per_unit;
} iio_features[SW_NFEATURES] = {
	[SW_FEATURE_PRESSURE] = { "pressure", 1 },		/* kPa */
	[SW_FEATURE_HUMIDITY] = { "humidityrelative", 1000 },	/* milli % */
	[SW_FEATURE_TEMP] = { "temp", 1000 },			/* milli C */
};

/* (raw + offset) * scale, offset 0 when the channel has none. */
static int iio_feature_value(struct iio_be *ib, const char *chan, int raw,
			     double per_unit, double *val, struct sw_err *e)
{
	char attr[64], buf[64];
	double scale, offset = 0;
	int err, ret;

	snprintf(attr, sizeof(attr), "in_%s_scale", chan);
	ret = attr_read(ib, attr, buf, sizeof(buf), e);
	ret = ret ? ret : parse_double(ib, attr, buf, &scale, e);
	if (ret)
		return ret;
	snprintf(attr, sizeof(attr), "in_%s_offset", chan);
	ret = attr_read_soft(ib, attr, buf, sizeof(buf), &err, e);
	if (!ret && !err)
		ret = parse_double(ib, attr, buf, &offset, e);
	if (ret)
		return ret;
	*val = (raw + offset) * scale / per_unit;
	return SW_EXIT_OK;
}

/*
 * Feature sensor k, when the driver has its channel (*present). Its raw
 * value reads EBUSY while a buffer streams: shown without a value then.
 */
static int iio_feature(struct iio_be *ib, enum sw_feature_kind k,
		       struct sw_feature *f, bool *present, struct sw_err *e)
{
	const char *chan = iio_features[k].chan;
	char attr[64], buf[64];
	int err, raw = 0, ret;

	snprintf(attr, sizeof(attr), "in_%s_raw", chan);
	ret = attr_read_soft(ib, attr, buf, sizeof(buf), &err, e);
	*present = !ret && err != ENOENT;
	if (!*present)
		return ret;
	memset(f, 0, sizeof(*f));
	f->kind = k;
	f->have_value = !err;
	if (f->have_value)
		ret = parse_int(ib, attr, buf, &raw, e);
	snprintf(attr, sizeof(attr), "in_%s_sampling_frequency", chan);
	ret = ret ? ret : attr_read_int(ib, attr, &f->rate_hz, e);
	if (ret || !f->have_value)
		return ret;
	return iio_feature_value(ib, chan, raw, iio_features[k].per_unit,
				 &f->value, e);
}

static int iio_hub_info(struct sw_backend *b, struct sw_hub_info *hi,
			struct sw_err *e)
{
	struct iio_be *ib = to_iio(b);
	bool present;
	int k, ret;

	memset(hi, 0, sizeof(*hi));
	ret = iio_fw_source(ib, hi, e);
	for (k = 0; k < SW_NFEATURES && !ret; k++) {
		ret = iio_feature(ib, (enum sw_feature_kind)k,
				  &hi->features[hi->nfeatures], &present, e);
		if (present)
			hi->nfeatures++;
	}
	return ret;
}

static void iio_close(struct sw_backend *b)
{
	free(to_iio(b));
}

static const struct sw_backend_ops iio_ops = {
	.chip_info = iio_chip_info,
	.cal_state = iio_cal_state,
	.read_blob = iio_read_blob,
	.write_blob = iio_write_blob,
	.mag = iio_mag,
	.accel_raw = iio_accel_raw,
	.accel_offset_get = iio_accel_offset_get,
	.accel_offset_set = iio_accel_offset_set,
	.hub_info = iio_hub_info,
	.close = iio_close,
};

/*
 * The udev view of an IIO device: from the environment when udev runs us
 * for this very device (its database entry is written only after the
 * event), else from sysfs and udev's database.
 */
static struct udev_device *udev_view(struct udev *u, const char *syspath)
{
	const char *devpath = getenv("DEVPATH");
	char evpath[PATH_MAX];

	if (devpath && getenv("ACTION") && getenv("SUBSYSTEM") &&
	    snprintf(evpath, sizeof(evpath), "/sys%s", devpath) < (int)sizeof(evpath) &&
	    !strcmp(evpath, syspath))
		return udev_device_new_from_environment(u);
	return udev_device_new_from_syspath(u, syspath);
}

/*
 * Key, client name and ID_PATH of an em7180 IIO device (see devkey.h).
 * Without an I2C client (not expected of em7180_i2c) the key is the
 * device's own name.
 */
static int device_key(struct udev *u, struct iio_be *ib, struct sw_err *e)
{
	struct udev_device *dev, *client;
	char syspath[PATH_MAX];
	const char *idp;
	int ret = SW_EXIT_OK;

	if (!realpath(ib->dir, syspath) || !(dev = udev_view(u, syspath)))
		return sw_err_set(e, SW_EXIT_DEVICE, "%s: cannot look it up in sysfs: %s",
				  ib->b.name, strerror(errno));
	idp = udev_device_get_property_value(dev, "ID_PATH");
	copy_str(ib->id_path, sizeof(ib->id_path), idp ? idp : "");
	/* The device the driver probed: its name is the driver's dev_name() */
	if (udev_device_get_parent(dev))
		copy_str(ib->b.client, sizeof(ib->b.client),
			 udev_device_get_sysname(udev_device_get_parent(dev)));
	client = sw_udev_i2c_client(udev_device_get_parent(dev));
	if (client) {
		copy_str(ib->parent, sizeof(ib->parent),
			 udev_device_get_sysname(client));
		ret = sw_key_of_client(client, ib->id_path, ib->b.key,
				       sizeof(ib->b.key), e);
	} else {
		sw_sanitize_key(ib->b.name, ib->b.key, sizeof(ib->b.key));
	}
	udev_device_unref(dev);
	/* What earlier versions named the file: ID_PATH, else the client. */
	if (ib->id_path[0])
		sw_sanitize_key(ib->id_path, ib->b.legacy_key[0],
				sizeof(ib->b.legacy_key[0]));
	if (ib->parent[0])
		sw_sanitize_key(ib->parent, ib->b.legacy_key[1],
				sizeof(ib->b.legacy_key[1]));
	return ret;
}

static bool device_matches(const char *want, const struct iio_device *dev,
			   const struct iio_be *cand)
{
	const char *label = iio_device_get_label(dev);
	char sane[SW_KEY_MAX];

	if (!want)
		return true;
	sw_sanitize_key(want, sane, sizeof(sane));
	return !strcmp(want, iio_device_get_id(dev)) ||
	       !strcmp(want, "em7180") ||
	       (label && !strcmp(want, label)) ||
	       !strcmp(want, cand->parent) || !strcmp(want, cand->b.key) ||
	       !strcmp(sane, cand->b.key);
}

/*
 * Earlier versions keyed files by ID_PATH, which chips on one controller
 * share: such a file belongs to none of them in particular, so it is not
 * migrated when another em7180 has the same ID_PATH.
 */
static void drop_shared_legacy(struct udev *u, struct iio_context *ctx,
			       struct iio_be *found)
{
	unsigned int i, n = iio_context_get_devices_count(ctx), same = 0;

	if (!found->id_path[0])
		return;
	for (i = 0; i < n; i++) {
		const struct iio_device *dev = iio_context_get_device(ctx, i);
		const char *name = iio_device_get_name(dev), *idp;
		char dir[PATH_MAX], syspath[PATH_MAX];
		struct udev_device *ud;

		if (!name || strcmp(name, "em7180"))
			continue;
		snprintf(dir, sizeof(dir), IIO_SYSFS "/%s", iio_device_get_id(dev));
		if (!realpath(dir, syspath) || !(ud = udev_view(u, syspath)))
			continue;
		idp = udev_device_get_property_value(ud, "ID_PATH");
		if (idp && !strcmp(idp, found->id_path))
			same++;
		udev_device_unref(ud);
	}
	if (same > 1)
		found->b.legacy_key[0][0] = '\0';
}

int sw_iio_open(const struct sw_iio_opts *o, struct sw_backend **out,
		struct sw_err *e)
{
	struct iio_be *found = NULL;
	struct iio_context *ctx;
	struct udev *u;
	char list[512] = "";
	unsigned int i, n, matches = 0;
	int ret = SW_EXIT_OK;

	*out = NULL;
	ctx = iio_create_local_context();
	if (!ctx)
		return sw_iio_scan_err(e, IIO_SYSFS, errno);
	u = udev_new();
	if (!u) {
		iio_context_destroy(ctx);
		return sw_err_set(e, SW_EXIT_OSERR, "cannot use libudev: %s",
				  strerror(errno));
	}
	n = iio_context_get_devices_count(ctx);
	for (i = 0; i < n && !ret; i++) {
		const struct iio_device *dev = iio_context_get_device(ctx, i);
		const char *name = iio_device_get_name(dev);
		const char *id = iio_device_get_id(dev);
		struct iio_be *cand;

		if (!name || strcmp(name, "em7180"))
			continue;
		cand = calloc(1, sizeof(*cand));
		if (!cand) {
			ret = sw_err_set(e, SW_EXIT_OSERR, "out of memory");
			break;
		}
		cand->b.ops = &iio_ops;
		cand->b.kind = "driver";
		snprintf(cand->b.name, sizeof(cand->b.name), "%s", id);
		snprintf(cand->dir, sizeof(cand->dir), IIO_SYSFS "/%s", id);
		ret = device_key(u, cand, e);
		if (ret || !device_matches(o->device, dev, cand)) {
			free(cand);
			continue;
		}
		matches++;
		snprintf(list + strlen(list), sizeof(list) - strlen(list),
			 "%s%s (%s, key %s)", matches > 1 ? ", " : "", id,
			 cand->parent, cand->b.key);
		if (found)
			free(cand);
		else
			found = cand;
	}
	if (!ret && matches == 1)
		drop_shared_legacy(u, ctx, found);
	udev_unref(u);
	iio_context_destroy(ctx);
	if (ret || matches != 1)
		free(found);
	if (ret)
		return ret;
	if (!matches && o->gone_ok)
		return SW_EXIT_OK;
	if (!matches) {
		if (o->device)
			return sw_err_set(e, SW_EXIT_DEVICE,
					  "no em7180 IIO device matches '%s'",
					  o->device);
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "no em7180 IIO device found (is the em7180_i2c driver loaded and bound? without a driver use --i2c)");
	}
	if (matches > 1)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%u em7180 devices found: %s; choose one with --device",
				  matches, list);
	if (o->check_abi) {
		ret = sw_abi_check(found->b.name, o->version, attr_exists,
				   found, e);
		if (ret) {
			free(found);
			return ret;
		}
	}
	/* Drivers before 1.2.0: identity attributes, a blob without header */
	found->b.checks_identity = !attr_exists("rom_version", found);
	*out = &found->b;
	return SW_EXIT_OK;
}
