/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * PNI SENtral / EM Microelectronic EM7180 sensor-fusion hub: what the core
 * files and the KUnit suite share
 *
 * Register and protocol facts follow EM Microelectronic's GPL generic host
 * driver (em718x_registers.h, em718x_core.c), the Sony em718x driver and
 * PNI's warm start application note.
 */
#ifndef _EM7180_CORE_H_
#define _EM7180_CORE_H_

#include <linux/bits.h>
#include <linux/iio/iio.h>
#include <linux/mutex.h>
#include <linux/pm.h>
#include <linux/regmap.h>
#include <linux/types.h>
#include <linux/wait.h>
#include <linux/workqueue.h>

#define EM7180_REG_QX			0x00	/* float32 x, y, z, w */
#define EM7180_REG_GTIME		0x28
#define EM7180_REG_QRATE_DIVISOR	0x32
#define EM7180_REG_ENABLE_EVENTS	0x33
#define EM7180_REG_HOST_CTRL		0x34
#define EM7180_REG_SENTRAL_STATUS	0x37
#define EM7180_REG_ALGO_STATUS		0x38
#define EM7180_REG_PARAM_ACK		0x3A
#define EM7180_REG_SAVED_PARAM		0x3B	/* 0x3B..0x3E, u32 LE */
#define EM7180_REG_CAL_STATUS		0x43
#define EM7180_REG_CAL_FLAGS		0x44	/* latched, may clear on read */
#define EM7180_REG_CAL_SCORE		0x4D	/* 0x4D..0x4E, u16 LE */
#define EM7180_CAL_BLOCK_LEN		(EM7180_REG_CAL_SCORE + 2 - EM7180_REG_CAL_STATUS)
#define EM7180_REG_ALGO_CTRL		0x54
#define EM7180_REG_MAG_RATE		0x55
#define EM7180_REG_ACCEL_RATE		0x56
#define EM7180_REG_GYRO_RATE		0x57
#define EM7180_REG_LOAD_PARAM		0x60	/* 0x60..0x63, u32 LE */
#define EM7180_REG_PARAM_REQ		0x64
#define EM7180_REG_ROM_VERSION		0x70
#define EM7180_REG_RAM_VERSION		0x72

#define EM7180_HOST_CTRL_RUN		BIT(0)

#define EM7180_EVENT_ERROR		BIT(1)

#define EM7180_SENTRAL_UPLOAD_DONE	BIT(1)
#define EM7180_SENTRAL_STANDBY		BIT(3)

#define EM7180_ALGO_CTRL_STANDBY	BIT(0)
#define EM7180_ALGO_CTRL_PARAM_XFER	BIT(7)

#define EM7180_CAL_STATUS_MASK		GENMASK(1, 0)
#define EM7180_CAL_MAG_TRANSIENT_MASK	GENMASK(3, 2)
#define EM7180_CAL_FLAG_MAG_UPDATE	BIT(0)
#define EM7180_CAL_FLAG_GBIAS_UPDATE	BIT(1)

#define EM7180_PARAM_WRITE		BIT(7)
#define EM7180_PARAM_MAX		127

/* Warm start: parameters 1..35, accel offsets (float g) in 27..29 */
#define EM7180_WS_NUM_PARAMS		35
#define EM7180_WS_SIZE			(EM7180_WS_NUM_PARAMS * 4)

enum em7180_scan {
	EM7180_SCAN_QUAT,
	EM7180_SCAN_MAGN_X,
	EM7180_SCAN_MAGN_Y,
	EM7180_SCAN_MAGN_Z,
	EM7180_SCAN_ACCEL_X,
	EM7180_SCAN_ACCEL_Y,
	EM7180_SCAN_ACCEL_Z,
	EM7180_SCAN_ANGLVEL_X,
	EM7180_SCAN_ANGLVEL_Y,
	EM7180_SCAN_ANGLVEL_Z,
	EM7180_SCAN_TIMESTAMP,
};

/*
 * One burst covers quaternion, magnetometer, accelerometer and gyroscope,
 * each followed by its TIME register
 */
#define EM7180_BURST_LEN		(EM7180_REG_GTIME + 2 - EM7180_REG_QX)

/**
 * struct em7180_cal - calibration state as last read from the chip
 * @status: register 0x43, CalStatus in bits 1:0, MagTransient in 3:2
 * @score: raw score, 0x4D | 0x4E << 8
 * @flags: update flags of 0x44 read since the warm start was last
 *	   read or written
 * @valid: the fields above come from a successful read
 * @read_at: jiffies of that read
 */
struct em7180_cal {
	u8 status;
	u16 score;
	u8 flags;
	bool valid;
	unsigned long read_at;
};

struct iio_trigger;

/**
 * struct em7180_data - driver state
 * @dev: parent (bus) device
 * @regmap: register map of the chip
 * @trig: data-ready trigger, NULL without an interrupt line
 * @lock: serialises every chip access and the fields below
 * @irq: interrupt of the INT pin, 0 when not wired
 * @ack_wait_us: wait before the first ParamAcknowledge poll, 0 until learned
 * @ack_min_us: the shortest time an acknowledge was found at after an
 *	        early poll, 0 until one was early
 * @param_single: the chip takes parameters one register per transaction
 * @cal: calibration state last read
 * @product_id: ProductID read at probe
 * @revision_id: RevisionID read at probe
 * @rom_version: ROM version, read at probe
 * @ram_version: RAM (firmware) version, read at probe and after a power loss
 * @cal_fw: RAM versions known to report calibration status, flags and score
 *	    in 0x43, 0x44 and 0x4D-0x4E: the emmicro,calibration-firmware property,
 *	    then the calibration_firmware module parameter
 * @cal_fw_len: entries in @cal_fw
 * @cal_attrs: the calibration attributes exist: @ram_version was in
 *	       @cal_fw at probe
 * @cal_reported: @ram_version is in @cal_fw
 * @ws_valid: @ws holds the last warm start written, read or saved at suspend
 * @ws: warm start to re-apply when the chip lost power during suspend
 * @accel_offset_valid: @accel_offset holds what the chip has
 * @accel_offset: parameters 27..29, the accelerometer offsets in float g
 * @pace_event: the EventStatus bit whose interrupt paces scans, 0 when off
 * @last_error: SensorStatus << 8 | ErrorRegister last reported
 * @recover_work: recovery from a reset of the chip's own, or from a
 *		  parameter transfer that could not be ended
 * @xfer_stuck: that transfer: AlgorithmControl bit 7 may still be set
 * @resets: such resets recovered since probe
 * @recovered_at: jiffies at the last recovery
 * @recover_ret: the result of the last recovery
 * @watch_work: while a buffer runs, a check that the chip still runs, for
 *		a reset that raised no interrupt
 * @watch_scans: @scans when @watch_work last ran
 * @status_at: jiffies of the last SentralStatus read
 * @orientation: mount matrix from firmware
 * @timestamp: time of the last data-ready interrupt, written by the hard handler
 * @scan_ts: time of the interrupt of the scan being captured
 * @scan_fresh: that scan was read and is no repeat: push it
 * @xfer_seq: parameter transfers ended, counted before the algorithm resumes
 * @irq_seq: @xfer_seq at the last data-ready interrupt
 * @poll_seq: @xfer_seq at the last poll of another device's trigger
 * @scans: data-ready interrupts served while the trigger ran
 * @scan_seq: @xfer_seq at the last of them
 * @scan_wq: woken after each of them
 * @burst: raw sensor registers of one scan
 * @last_burst: the registers of the scan pushed last
 * @last_start: first register of @last_burst
 * @last_len: size of @last_burst, 0 when nothing was pushed yet
 * @scan: the channels of one scan, packed in scan order, and room for the
 *	  timestamp that iio_push_to_buffers_with_ts() adds
 */
struct em7180_data {
	struct device *dev;
	struct regmap *regmap;
	struct iio_trigger *trig;
	struct mutex lock;	/* chip access and every field below */
	int irq;
	unsigned int ack_wait_us;
	unsigned int ack_min_us;
	bool param_single;
	struct em7180_cal cal;
	u8 product_id;
	u8 revision_id;
	u16 rom_version;
	u16 ram_version;
	const u32 *cal_fw;
	unsigned int cal_fw_len;
	bool cal_attrs;
	bool cal_reported;
	bool ws_valid;
	u8 ws[EM7180_WS_SIZE];
	bool accel_offset_valid;
	u32 accel_offset[3];
	unsigned int pace_event;
	unsigned int last_error;
	struct delayed_work recover_work;
	bool xfer_stuck;
	unsigned int resets;
	unsigned long recovered_at;
	int recover_ret;
	struct delayed_work watch_work;
	unsigned int watch_scans;
	unsigned long status_at;
	struct iio_mount_matrix orientation;
	s64 timestamp;
	s64 scan_ts;
	bool scan_fresh;
	unsigned int xfer_seq;
	unsigned int irq_seq;
	unsigned int poll_seq;
	unsigned int scans;
	unsigned int scan_seq;
	wait_queue_head_t scan_wq;
	u8 burst[EM7180_BURST_LEN];
	u8 last_burst[EM7180_BURST_LEN];
	unsigned int last_start;
	unsigned int last_len;
	struct {
		s16 chans[4 + 9];	/* quaternion Q14, then le16 words */
		aligned_s64 ts;
	} scan;
};

int em7180_params_read(struct em7180_data *data, unsigned int first,
		       unsigned int count, u32 *vals);
int em7180_params_write(struct em7180_data *data, unsigned int first,
			unsigned int count, const u32 *vals);

bool em7180_float_is_finite(u32 bits);
u32 em7180_lsb_to_float_g(int lsb);
int em7180_float_g_to_lsb(u32 bits, int *lsb);
s32 em7180_float_to_fixed(u32 bits, unsigned int frac_bits);

int em7180_chip_suspend(struct em7180_data *data);
int em7180_chip_resume(struct em7180_data *data);
int em7180_read_calibbias(struct em7180_data *data, unsigned int axis,
			  int *val);
int em7180_write_calibbias(struct em7180_data *data, unsigned int axis,
			   int val);

int em7180_warmstart_check(const u8 *buf, loff_t off, size_t count,
			   bool write);
int em7180_warmstart_restore(struct iio_dev *indio_dev, const u8 *buf,
			     loff_t off, size_t count);
#if IS_ENABLED(CONFIG_KUNIT)
int em7180_warmstart_read(struct em7180_data *data, u8 *buf);
#endif
int em7180_score_milli(u16 raw);
bool em7180_fw_listed(u16 ram, const u32 *table, unsigned int len);

/* Attribute addresses of em7180_cal_show() */
enum em7180_cal_attr {
	EM7180_CAL_ATTR_STATUS,
	EM7180_CAL_ATTR_SCORE,
	EM7180_CAL_ATTR_TRANSIENT,
	EM7180_CAL_ATTR_GYRO_UPDATE,
	EM7180_CAL_ATTR_MAG_UPDATE,
};

ssize_t em7180_cal_show(struct device *dev, struct device_attribute *attr,
			char *buf);
void em7180_cal_update(struct em7180_cal *cal, const u8 *regs);
void em7180_cal_saved(struct em7180_data *data);
void em7180_recover_schedule(struct em7180_data *data);
void em7180_status_seen(struct em7180_data *data, unsigned int status);

#endif /* _EM7180_CORE_H_ */
