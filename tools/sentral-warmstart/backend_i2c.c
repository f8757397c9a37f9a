// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: i2c-dev backend, the chip's own register protocol.
 *
 * Parameter transfer as EM7180 register reference §2 gives it (sources:
 * [2+] EM generic host driver, Sony em718x), with the seed app note's
 * errors corrected: AlgorithmControl bit 7 is set once per batch; each
 * parameter is written as EM's and Sony's drivers do, LoadParamByte0..3
 * (0x60..0x63) in one write and ParamRequest alone; ParamAcknowledge
 * (0x3A) is polled alone and a value read at 0x3B once acknowledged: no
 * reference host crosses 0x63->0x64 or 0x3A->0x3B in one transfer, so
 * silicon may not. The batch always ends with ParamRequest = 0 and bit 7
 * cleared, on error paths too, so the fusion algorithm is never left
 * paused.
 */
#include <errno.h>
#include <fcntl.h>
#include <libudev.h>
#include <i2c/smbus.h>
#include <limits.h>
#include <linux/i2c-dev.h>
#include <linux/i2c.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <time.h>
#include <unistd.h>

#include "backend.h"
#include "i2cbus.h"
#include "level.h"

#define REG_MAG		0x12
#define REG_ACCEL	0x1a
#define REG_FEATURE0	0x2a	/* feature data and TIME, to 0x31 */
#define FEATURE_DATA_LEN 8
#define REG_SENTRAL_STATUS 0x37
#define STATUS_EEPROM	0x01	/* EEPROM detected */
#define STATUS_NO_EEPROM 0x10
#define REG_FEATURE_FLAGS 0x39
/* bits 0..2 barometer, humidity, temperature; 3..5 custom sensors */
#define FEATURE_FLAGS_MASK 0x3f
#define FEATURE_SLOTS	3
#define REG_FEATURE_RATE0 0x58
#define FEATURE_RATE_MASK 0x7f
#define REG_PARAM_ACK	0x3a
#define REG_SAVED_PARAM	0x3b
#define REG_ALGO_CTRL	0x54
#define ALGO_PARAM_PROC	0x80
#define REG_LOAD_PARAM	0x60
#define REG_PARAM_REQ	0x64
#define PARAM_WRITE	0x80
#define REG_ROM_VERSION	0x70
#define REG_RAM_VERSION	0x72
#define REG_PRODUCT_ID	0x90
#define EM7180_PRODUCT_ID 0x80

/* i2c-dev's character major (Documentation/admin-guide/devices.txt). */
#define I2C_DEV_MAJOR	89
/* The longest text of an int, "-2147483648" */
#define INT_TEXT	(sizeof("-2147483648") - 1)

/* Drivers in the wild allow up to 1 s for an acknowledge. */
#define ACK_TIMEOUT_US	1000000
#define ACK_POLL_US	100

struct i2c_be {
	struct sw_backend b;
	int fd;
	unsigned int addr;
	enum sw_layout layout;	/* of the firmware, as far as seen */
	/* Acknowledge latency seen so far: the first poll waits about that. */
	long ack_us;
};

static uint64_t now_us(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * 1000000u + (uint64_t)ts.tv_nsec / 1000u;
}

static void sleep_us(long us)
{
	struct timespec ts = { us / 1000000, (us % 1000000) * 1000 };

	while (nanosleep(&ts, &ts) < 0 && errno == EINTR)
		;
}

/*
 * SMBus-only adapters cannot do I2C_RDWR: they fall back to libi2c's I2C
 * block transfers, single transactions as well, to the address
 * sw_i2c_open() selected on the descriptor.
 */
/*
 * Combined write-register/read transfers through I2C_RDWR, atomic on the
 * bus, so that a driver bound anyway (--force) is not disturbed.
 */
static int i2c_bus_read(int fd, unsigned int addr, uint8_t reg, uint8_t *buf,
			size_t len)
{
	struct i2c_msg msgs[2] = {
		{ .addr = (uint16_t)addr, .flags = 0, .len = 1, .buf = &reg },
		{ .addr = (uint16_t)addr, .flags = I2C_M_RD,
		  .len = (uint16_t)len, .buf = buf },
	};
	struct i2c_rdwr_ioctl_data xfer = { .msgs = msgs, .nmsgs = 2 };

	if (ioctl(fd, I2C_RDWR, &xfer) == 2)
		return 0;
	if (errno != EOPNOTSUPP || len > I2C_SMBUS_BLOCK_MAX)
		return -1;
	if (i2c_smbus_read_i2c_block_data(fd, reg, (uint8_t)len, buf) !=
	    (int)len) {
		errno = EIO;
		return -1;
	}
	return 0;
}

static int i2c_bus_write(int fd, unsigned int addr, uint8_t reg,
			 const uint8_t *buf, size_t len)
{
	uint8_t tx[1 + I2C_SMBUS_BLOCK_MAX];
	struct i2c_msg msg = {
		.addr = (uint16_t)addr, .flags = 0, .len = (uint16_t)(len + 1),
		.buf = tx,
	};
	struct i2c_rdwr_ioctl_data xfer = { .msgs = &msg, .nmsgs = 1 };

	if (len > I2C_SMBUS_BLOCK_MAX) {
		errno = EINVAL;
		return -1;
	}
	tx[0] = reg;
	memcpy(tx + 1, buf, len);
	if (ioctl(fd, I2C_RDWR, &xfer) == 1)
		return 0;
	if (errno != EOPNOTSUPP)
		return -1;
	return i2c_smbus_write_i2c_block_data(fd, reg, (uint8_t)len, buf) < 0 ?
	       -1 : 0;
}

static int i2c_read_chip_info(int fd, unsigned int addr,
			      struct sw_chip_info *ci)
{
	uint8_t id[2], ver[4];

	if (i2c_bus_read(fd, addr, REG_PRODUCT_ID, id, 2) < 0 ||
	    i2c_bus_read(fd, addr, REG_ROM_VERSION, ver, 4) < 0)
		return -1;
	ci->product_id = id[0];
	ci->revision_id = id[1];
	ci->rom_version = sw_get_le16(ver);
	ci->ram_version = sw_get_le16(ver + 2);
	return 0;
}

static struct i2c_be *to_i2c(struct sw_backend *b)
{
	return (struct i2c_be *)b;
}

static int bus_err(struct i2c_be *ib, const char *what, uint8_t reg,
		   struct sw_err *e)
{
	return sw_err_set(e, SW_EXIT_IO, "%s: %s register 0x%02x failed: %s",
			  ib->b.name, what, reg, strerror(errno));
}

static int interrupted(struct i2c_be *ib, struct sw_err *e)
{
	return sw_err_set(e, SW_EXIT_IO, "%s: interrupted by %s",
			  ib->b.name, strsignal(sw_signal_pending()));
}

/* Wait for ParamAcknowledge == req, then return SavedParamByte0..3. */
static int param_wait_ack(struct i2c_be *ib, uint8_t req, uint8_t *val,
			  struct sw_err *e)
{
	uint64_t start = now_us();
	uint8_t ack;

	if (ib->ack_us > ACK_POLL_US)
		sleep_us(ib->ack_us - ACK_POLL_US);
	for (;;) {
		uint64_t t;

		if (i2c_bus_read(ib->fd, ib->addr, REG_PARAM_ACK, &ack, 1) < 0)
			return bus_err(ib, "reading", REG_PARAM_ACK, e);
		t = now_us() - start;
		if (ack == req) {
			/* Learn the chip's latency: a cheap moving average. */
			ib->ack_us = (ib->ack_us * 3 + (long)t) / 4;
			if (val && i2c_bus_read(ib->fd, ib->addr,
						REG_SAVED_PARAM, val, 4) < 0)
				return bus_err(ib, "reading", REG_SAVED_PARAM, e);
			return SW_EXIT_OK;
		}
		if (sw_signal_pending())
			return interrupted(ib, e);
		if (t > ACK_TIMEOUT_US)
			return sw_err_set(e, SW_EXIT_IO,
					  "%s: parameter %u not acknowledged within %d ms (ParamAcknowledge 0x%02x)",
					  ib->b.name, req & 0x7f,
					  ACK_TIMEOUT_US / 1000, ack);
		sleep_us(ACK_POLL_US);
	}
}

/*
 * A write batch stopped at index i: say what the chip now holds. Parameter
 * first + i may have been taken or not (a lost acknowledge); those before
 * it were acknowledged, those after it were never sent.
 */
static void mixed_note(int first, int count, int i, struct sw_err *e)
{
	int last = first + count - 1, p = first + i;
	/* Room for any two ints: gcc's -Wformat-truncation at -O0 knows no range. */
	char done[2 * INT_TEXT + sizeof("- hold the new values, ")] = "";
	char rest[2 * INT_TEXT + sizeof(", - still the old ones")] = "";

	/* Nothing sent yet, or every parameter acknowledged. */
	if (i < 0 || i >= count)
		return;
	if (p > first)
		snprintf(done, sizeof(done), "%d-%d hold the new values, ",
			 first, p - 1);
	if (p < last)
		snprintf(rest, sizeof(rest), ", %d-%d still the old ones",
			 p + 1, last);
	sw_err_append(e, "; parameters %s%d may or may not%s: %s",
		      done, p, rest,
		      p > first || p < last ?
		      "the chip's calibration is mixed; run the same command again, or power-cycle the chip to start uncalibrated" :
		      "run the same command again");
}

/*
 * Transfer count parameters first..first+count-1. vals holds 4 LE bytes
 * per parameter: the values to write (write) or the values read.
 */
static int param_batch(struct i2c_be *ib, int first, int count, bool write,
		       uint8_t *vals, struct sw_err *e)
{
	uint8_t ac, v, zero = 0;
	int i = -1, ret = SW_EXIT_OK;	/* -1: no parameter sent yet */

	if (i2c_bus_read(ib->fd, ib->addr, REG_ALGO_CTRL, &ac, 1) < 0)
		return bus_err(ib, "reading", REG_ALGO_CTRL, e);
	v = ac | ALGO_PARAM_PROC;
	if (i2c_bus_write(ib->fd, ib->addr, REG_ALGO_CTRL, &v, 1) < 0) {
		ret = bus_err(ib, "writing", REG_ALGO_CTRL, e);
		goto end;
	}
	for (i = 0; i < count; i++) {
		uint8_t req = (uint8_t)(first + i);

		/* A signal ends the batch here, never in the middle of a parameter. */
		if (sw_signal_pending()) {
			ret = interrupted(ib, e);
			goto end;
		}
		if (write) {
			req |= PARAM_WRITE;
			if (i2c_bus_write(ib->fd, ib->addr, REG_LOAD_PARAM,
					     vals + 4 * i, 4) < 0) {
				ret = bus_err(ib, "writing", REG_LOAD_PARAM, e);
				goto end;
			}
		}
		if (i2c_bus_write(ib->fd, ib->addr, REG_PARAM_REQ, &req, 1) < 0) {
			ret = bus_err(ib, "writing", REG_PARAM_REQ, e);
			goto end;
		}
		ret = param_wait_ack(ib, req, write ? NULL : vals + 4 * i, e);
		if (ret)
			goto end;
	}
end:
	if (ret && write)
		mixed_note(first, count, i, e);
	/* Always leave transfer mode and let the algorithm run again. */
	v = ac & (uint8_t)~ALGO_PARAM_PROC;
	if (i2c_bus_write(ib->fd, ib->addr, REG_PARAM_REQ, &zero, 1) < 0)
		ret = ret ? ret : bus_err(ib, "writing", REG_PARAM_REQ, e);
	if (i2c_bus_write(ib->fd, ib->addr, REG_ALGO_CTRL, &v, 1) < 0)
		ret = ret ? ret : bus_err(ib, "writing", REG_ALGO_CTRL, e);
	return ret;
}

static int i2c_chip_info(struct sw_backend *b, struct sw_chip_info *ci,
			 struct sw_err *e)
{
	struct i2c_be *ib = to_i2c(b);

	if (i2c_read_chip_info(ib->fd, ib->addr, ci) < 0)
		return bus_err(ib, "reading", REG_PRODUCT_ID, e);
	return SW_EXIT_OK;
}

/*
 * The level from AlgorithmStatus (0x38) as the driver computes it, and the
 * application note's score and update flags (0x43..0x4E) where the
 * driver's layout check passes (level.h), all in one burst: they describe
 * one moment, and 0x44 clears when read on that firmware, so it is read
 * exactly once.
 */
static int i2c_cal_state(struct sw_backend *b, struct sw_cal_state *cs,
			 struct sw_err *e)
{
	struct i2c_be *ib = to_i2c(b);
	uint8_t r[SW_CAL_REGS_LEN];

	/* Polling loops (calibrate) end here after a signal. */
	if (sw_signal_pending())
		return interrupted(ib, e);
	if (i2c_bus_read(ib->fd, ib->addr, SW_ALGO_STATUS, r, sizeof(r)) < 0)
		return bus_err(ib, "reading", SW_ALGO_STATUS, e);
	if (!sw_cal_state_of_regs(r, &ib->layout, cs))
		return sw_err_set(e, SW_EXIT_IO,
				  "%s: AlgorithmStatus (register 0x%02x) reads 0x%02x, with reserved bits 6-7 set: a glitched read, not trusted",
				  b->name, SW_ALGO_STATUS, r[0]);
	return SW_EXIT_OK;
}

static int i2c_read_blob(struct sw_backend *b, uint8_t *blob,
			 struct sw_err *e)
{
	return param_batch(to_i2c(b), 1, SW_NPARAMS, false, blob, e);
}

/* The identity is the caller's to check: restore reads the registers. */
static int i2c_write_blob(struct sw_backend *b, const struct sw_chip_info *chip,
			  const uint8_t *blob, struct sw_err *e)
{
	uint8_t tmp[SW_BLOB_SIZE];

	(void)chip;
	memcpy(tmp, blob, sizeof(tmp));
	return param_batch(to_i2c(b), 1, SW_NPARAMS, true, tmp, e);
}

static int i2c_accel_raw(struct sw_backend *b, int xyz[3], struct sw_err *e)
{
	struct i2c_be *ib = to_i2c(b);
	uint8_t buf[6];
	int i;

	if (sw_signal_pending())
		return interrupted(ib, e);
	if (i2c_bus_read(ib->fd, ib->addr, REG_ACCEL, buf, 6) < 0)
		return bus_err(ib, "reading", REG_ACCEL, e);
	for (i = 0; i < 3; i++)
		xyz[i] = (int16_t)sw_get_le16(buf + 2 * i);
	return SW_EXIT_OK;
}

/* 1 LSB = 1000/32768 uT (EM7180 register reference §1). */
#define MAG_UT_PER_LSB (1000.0 / 32768)

static int i2c_mag(struct sw_backend *b, double ut[3], struct sw_err *e)
{
	struct i2c_be *ib = to_i2c(b);
	uint8_t buf[6];
	int i;

	/* One burst: the three axes of one sample. */
	if (i2c_bus_read(ib->fd, ib->addr, REG_MAG, buf, 6) < 0)
		return bus_err(ib, "reading", REG_MAG, e);
	for (i = 0; i < 3; i++)
		ut[i] = (int16_t)sw_get_le16(buf + 2 * i) * MAG_UT_PER_LSB;
	return SW_EXIT_OK;
}

static int i2c_accel_offset_get(struct sw_backend *b, int lsb[3],
				struct sw_err *e)
{
	uint8_t vals[12];
	int i, ret;

	ret = param_batch(to_i2c(b), SW_PARAM_ACCEL_X, 3, false, vals, e);
	if (ret)
		return ret;
	for (i = 0; i < 3; i++)
		lsb[i] = sw_g_to_lsb(sw_blob_param(vals, i + 1));
	return SW_EXIT_OK;
}

static int i2c_accel_offset_set(struct sw_backend *b, const int lsb[3],
				struct sw_err *e)
{
	uint8_t vals[12];
	int i;

	for (i = 0; i < 3; i++)
		sw_blob_set_param(vals, i + 1, sw_lsb_to_g(lsb[i]));
	return param_batch(to_i2c(b), SW_PARAM_ACCEL_X, 3, true, vals, e);
}

/*
 * SentralStatus: NoEEPROM means the host uploaded what runs (RAMVersion 0:
 * nothing yet); EEPROM detected, that the ROM loaded it from there. A
 * devicetree's firmware-name replacing the EEPROM's firmware does not show.
 */
static int i2c_fw_source(struct i2c_be *ib, struct sw_hub_info *hi,
			 struct sw_err *e)
{
	uint8_t st, ram[2];

	if (i2c_bus_read(ib->fd, ib->addr, REG_SENTRAL_STATUS, &st, 1) < 0)
		return bus_err(ib, "reading", REG_SENTRAL_STATUS, e);
	if (st & STATUS_NO_EEPROM) {
		if (i2c_bus_read(ib->fd, ib->addr, REG_RAM_VERSION, ram, 2) < 0)
			return bus_err(ib, "reading", REG_RAM_VERSION, e);
		if (sw_get_le16(ram))
			hi->fw_source = SW_FW_HOST;
		else
			snprintf(hi->fw_why, sizeof(hi->fw_why),
				 "the board has no EEPROM and no firmware was uploaded (SentralStatus 0x%02x, RAM version 0)",
				 st);
	} else if (st & STATUS_EEPROM) {
		hi->fw_source = SW_FW_EEPROM;
	} else {
		snprintf(hi->fw_why, sizeof(hi->fw_why),
			 "SentralStatus 0x%02x says neither EEPROM detected nor no EEPROM",
			 st);
	}
	return SW_EXIT_OK;
}

/* USFS firmware: 0.01 per LSB; pressure in mbar from 1013.25, as kPa. */
static double feature_value(enum sw_feature_kind k, int16_t raw)
{
	if (k == SW_FEATURE_PRESSURE)
		return (raw * 0.01 + 1013.25) / 10;
	return raw * 0.01;
}

/*
 * FeatureFlags: the present sensors take slots in bit order, rate register
 * 0x58 + slot; with one or two slots each has data and TIME (data at 0x2A
 * + 4 * slot), with three the data words are packed (0x2A + 2 * slot).
 */
static int i2c_features(struct i2c_be *ib, struct sw_hub_info *hi,
			struct sw_err *e)
{
	uint8_t flags, data[FEATURE_DATA_LEN], rates[FEATURE_SLOTS];
	unsigned int k, slots, step;

	if (i2c_bus_read(ib->fd, ib->addr, REG_FEATURE_FLAGS, &flags, 1) < 0)
		return bus_err(ib, "reading", REG_FEATURE_FLAGS, e);
	flags &= FEATURE_FLAGS_MASK;
	slots = (unsigned int)__builtin_popcount(flags);
	/* More than the slots (the driver ignores them too), or none. */
	if (!slots || slots > FEATURE_SLOTS)
		return SW_EXIT_OK;
	if (i2c_bus_read(ib->fd, ib->addr, REG_FEATURE0, data, sizeof(data)) < 0)
		return bus_err(ib, "reading", REG_FEATURE0, e);
	if (i2c_bus_read(ib->fd, ib->addr, REG_FEATURE_RATE0, rates, slots) < 0)
		return bus_err(ib, "reading", REG_FEATURE_RATE0, e);
	step = slots < FEATURE_SLOTS ? 4 : 2;
	for (k = 0; k < SW_NFEATURES; k++) {
		struct sw_feature *f = &hi->features[hi->nfeatures];

		if (!(flags & (1u << k)))
			continue;
		f->kind = (enum sw_feature_kind)k;
		f->have_value = true;
		f->value = feature_value(f->kind, (int16_t)sw_get_le16(
						data + step * hi->nfeatures));
		f->rate_hz = rates[hi->nfeatures] & FEATURE_RATE_MASK;
		hi->nfeatures++;
	}
	return SW_EXIT_OK;
}

static int i2c_hub_info(struct sw_backend *b, struct sw_hub_info *hi,
			struct sw_err *e)
{
	struct i2c_be *ib = to_i2c(b);
	int ret;

	memset(hi, 0, sizeof(*hi));
	ret = i2c_fw_source(ib, hi, e);
	return ret ? ret : i2c_features(ib, hi, e);
}

static void i2c_close(struct sw_backend *b)
{
	struct i2c_be *ib = to_i2c(b);

	close(ib->fd);
	free(ib);
}

static const struct sw_backend_ops i2c_ops = {
	.chip_info = i2c_chip_info,
	.cal_state = i2c_cal_state,
	.read_blob = i2c_read_blob,
	.write_blob = i2c_write_blob,
	.mag = i2c_mag,
	.accel_raw = i2c_accel_raw,
	.accel_offset_get = i2c_accel_offset_get,
	.accel_offset_set = i2c_accel_offset_set,
	.hub_info = i2c_hub_info,
	.close = i2c_close,
};

/*
 * The key of the chip on the adapter behind the i2c-dev node rdev: udev's
 * ID_PATH of that node is there when the project's rule imported it.
 */
static int adapter_key(dev_t rdev, unsigned int addr, char *key, size_t len,
		       struct sw_err *e)
{
	struct udev_device *node, *adap;
	struct udev *u = udev_new();
	int ret;

	if (!u)
		return sw_err_set(e, SW_EXIT_OSERR, "cannot use libudev: %s",
				  strerror(errno));
	node = udev_device_new_from_devnum(u, 'c', rdev);
	adap = node ? sw_udev_i2c_adapter(node) : NULL;
	if (adap)
		ret = sw_key_of_adapter(adap, addr,
					udev_device_get_property_value(node, "ID_PATH"),
					key, len, e);
	else
		ret = sw_err_set(e, SW_EXIT_DEVICE,
				 "i2c-dev node %u:%u has no I2C adapter in sysfs",
				 major(rdev), minor(rdev));
	udev_device_unref(node);
	udev_unref(u);
	return ret;
}

int sw_i2c_open(const struct sw_i2c_opts *o, struct sw_backend **out,
		struct sw_err *e)
{
	char client[64], dev[PATH_MAX];
	unsigned int bus;
	struct i2c_be *ib;
	struct stat st;
	uint8_t id;
	int fd, ret;

	ret = sw_i2c_bus_path(o->dev, SW_I2C_DEV_CLASS, dev, sizeof(dev), e);
	if (ret)
		return ret;
	fd = open(dev, O_RDWR | O_CLOEXEC);
	if (fd < 0)
		return sw_err_set(e, errno == ENOENT ? SW_EXIT_DEVICE : SW_EXIT_IO,
				  "%s: %s%s", dev, strerror(errno),
				  errno == ENOENT ? " (is the i2c-dev module loaded?)" : "");
	/*
	 * The node's own number, whatever it is called or links to: the
	 * key below comes from it, the same for every way of naming the bus.
	 */
	if (fstat(fd, &st) < 0 || !S_ISCHR(st.st_mode) ||
	    major(st.st_rdev) != I2C_DEV_MAJOR) {
		close(fd);
		return sw_err_set(e, SW_EXIT_USAGE,
				  "--i2c %s: not an i2c-dev character device (major %d)",
				  dev, I2C_DEV_MAJOR);
	}
	bus = minor(st.st_rdev);
	snprintf(client, sizeof(client), "%u-%04x", bus, o->addr);

	/*
	 * Two masters of one chip would corrupt each other's parameter
	 * transfers. The kernel answers EBUSY when a driver is bound to the
	 * address on this adapter or across a mux: leave it alone unless told
	 * otherwise.
	 */
	if (ioctl(fd, I2C_SLAVE, o->addr) < 0) {
		int err = errno;

		if (err != EBUSY || !o->force ||
		    ioctl(fd, I2C_SLAVE_FORCE, o->addr) < 0) {
			close(fd);
			if (err == EBUSY && !o->force)
				return sw_err_set(e, SW_EXIT_DEVICE,
						  "a kernel driver is bound to %s (0x%02x on %s); use the driver (omit --i2c), unbind it with 'echo %s > /sys/bus/i2c/devices/%s/driver/unbind', or pass --force",
						  client, o->addr, dev, client,
						  client);
			return sw_err_set(e, SW_EXIT_IO, "%s: selecting 0x%02x: %s",
					  dev, o->addr, strerror(errno));
		}
	}
	if (i2c_bus_read(fd, o->addr, REG_PRODUCT_ID, &id, 1) < 0) {
		int err = errno;

		close(fd);
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%s: no device answers at 0x%02x: %s", dev,
				  o->addr, strerror(err));
	}
	if (id != EM7180_PRODUCT_ID) {
		close(fd);
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%s: device at 0x%02x is not an EM7180 (ProductID 0x%02x, expected 0x%02x)",
				  dev, o->addr, id, EM7180_PRODUCT_ID);
	}
	ib = calloc(1, sizeof(*ib));
	if (!ib) {
		close(fd);
		return sw_err_set(e, SW_EXIT_OSERR, "out of memory");
	}
	ib->b.ops = &i2c_ops;
	ib->b.kind = "i2c";
	/* Room for "@0x77": a long path is cut, the address never. */
	snprintf(ib->b.name, sizeof(ib->b.name), "%.*s@0x%02x",
		 (int)sizeof(ib->b.name) - 6, dev, o->addr & 0x7f);
	ret = adapter_key(st.st_rdev, o->addr, ib->b.key, sizeof(ib->b.key), e);
	if (ret) {
		close(fd);
		free(ib);
		return ret;
	}
	/* Earlier versions named the file by the kernel's name of the client. */
	sw_sanitize_key(client, ib->b.legacy_key[1], sizeof(ib->b.legacy_key[1]));
	ib->fd = fd;
	ib->addr = o->addr;
	/* From here a signal must not leave the chip in transfer mode. */
	sw_signals_catch();
	*out = &ib->b;
	return SW_EXIT_OK;
}
