/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * PNI SENtral / EM7180: registers as EM's GPL host driver (em718x_registers.h)
 * and the Sony em718x driver have them
 */
#ifndef _EM7180_CORE_H_
#define _EM7180_CORE_H_

#include <linux/bits.h>
#include <linux/cleanup.h>
#include <linux/iio/iio.h>
#include <linux/mutex.h>
#include <linux/pm.h>
#include <linux/regmap.h>
#include <linux/types.h>
#include <linux/wait.h> /* upstream: param */
#include <linux/workqueue.h> /* upstream: health */

#include "em7180_compat.h"

#define EM7180_REG_QX			0x00	/* float32 x, y, z, w */
#define EM7180_REG_FEATURE0		0x2A	/* feature data and TIME, to 0x31 */
#define EM7180_REG_QRATE_DIVISOR	0x32
#define EM7180_REG_ENABLE_EVENTS	0x33
#define EM7180_REG_HOST_CTRL		0x34
#define EM7180_REG_EVENT_STATUS		0x35	/* clear on read */
#define EM7180_REG_SENTRAL_STATUS	0x37
#define EM7180_REG_ALGO_STATUS		0x38
#define EM7180_REG_FEATURE_FLAGS	0x39 /* upstream: feature */
#define EM7180_REG_PARAM_ACK		0x3A /* upstream: param */
#define EM7180_REG_SAVED_PARAM		0x3B	/* 0x3B..0x3E, u32 LE */ /* upstream: param */
#define EM7180_REG_CAL_STATUS		0x43 /* upstream: param */
#define EM7180_REG_CAL_FLAGS		0x44	/* latched, clear on read */
#define EM7180_REG_CAL_SCORE		0x4D	/* 0x4D..0x4E, u16 LE */ /* upstream: param */
/* upstream: param { */
#define EM7180_CAL_BLOCK_LEN		(EM7180_REG_CAL_SCORE + 2 - EM7180_REG_CAL_STATUS)
/* upstream: } */
#define EM7180_REG_ACTUAL_FEATURE0	0x48	/* 0x48..0x4A, Hz */ /* upstream: feature */
#define EM7180_REG_ERROR		0x50
#define EM7180_REG_ALGO_CTRL		0x54
#define EM7180_REG_MAG_RATE		0x55
#define EM7180_REG_ACCEL_RATE		0x56
#define EM7180_REG_GYRO_RATE		0x57
#define EM7180_REG_FEATURE_RATE0	0x58	/* 0x58..0x5A */ /* upstream: feature */
#define EM7180_REG_LOAD_PARAM		0x60	/* 0x60..0x63, u32 LE */ /* upstream: param */
#define EM7180_REG_PARAM_REQ		0x64
#define EM7180_REG_ROM_VERSION		0x70
#define EM7180_REG_RAM_VERSION		0x72
/* upstream: upload { */
#define EM7180_REG_UPLOAD_ADDR		0x94	/* 0x94..0x95, u16 BE */
#define EM7180_REG_UPLOAD_DATA		0x96
#define EM7180_REG_CRC_HOST		0x97	/* 0x97..0x9A, u32 LE */
/* upstream: } */
#define EM7180_REG_RESET_REQ		0x9B
/* upstream: passthru { */
#define EM7180_REG_PASSTHRU_STATUS	0x9E
#define EM7180_REG_PASSTHRU_CTRL	0xA0
/* upstream: } */

#define EM7180_HOST_CTRL_RUN		BIT(0)
#define EM7180_HOST_CTRL_UPLOAD		BIT(1) /* upstream: upload */
#define EM7180_EVENT_CPU_RESET		BIT(0)
#define EM7180_EVENT_ERROR		BIT(1)
#define EM7180_EVENT_FEATURE		BIT(6) /* upstream: feature */
#define EM7180_SENTRAL_UPLOAD_DONE	BIT(1)
#define EM7180_SENTRAL_STANDBY		BIT(3)
#define EM7180_ALGO_STATUS_HALTED	BIT(0)
#define EM7180_ALGO_CTRL_STANDBY	BIT(0)
#define EM7180_ALGO_CTRL_PARAM_XFER	BIT(7) /* upstream: param */
#define EM7180_RESET_REQ_RESET		BIT(0)
/* upstream: passthru { */
#define EM7180_PASSTHRU_ON		BIT(0)	/* control: enable; status: ready */
/* upstream: } */

#define EM7180_CAL_FLAG_MAG_UPDATE	BIT(0) /* upstream: cal */
#define EM7180_CAL_FLAG_GBIAS_UPDATE	BIT(1) /* upstream: cal */

#define EM7180_F32_SIGN			BIT(31)
#define EM7180_F32_EXP_MASK		GENMASK(30, 23)
#define EM7180_F32_FRAC_MASK		GENMASK(22, 0)
#define EM7180_F32_BIAS			127
#define EM7180_F32_FRAC_BITS		23

#define EM7180_PARAM_WRITE		BIT(7) /* upstream: param */
#define EM7180_PARAM_MAX		127 /* upstream: param */

/* upstream: param { */
/* Warm start: parameters 1..35, accel offsets (float g) in 27..29 */
#define EM7180_WS_NUM_PARAMS		35
#define EM7180_WS_SIZE			(EM7180_WS_NUM_PARAMS * 4)
/* upstream: } */

/* upstream: param { */
/*
 * calibration_data, and the file restored at probe: the chip and firmware
 * the warm start was read from, then parameters 1..35 as float32. A warm
 * start suits only the firmware that wrote it.
 */
#define EM7180_CALDATA_FORMAT		1

struct em7180_caldata_id {
	u8 format;
	u8 product_id;
	u8 revision_id;
	u8 reserved;
	__le16 rom_version;
	__le16 ram_version;
} __packed;

struct em7180_caldata {
	struct em7180_caldata_id id;
	__le32 params[EM7180_WS_NUM_PARAMS];
} __packed;

#define EM7180_CALDATA_SIZE		sizeof(struct em7180_caldata)
/* upstream: } */

/* Quaternion, magnetometer, accelerometer, gyroscope, features, each with TIME */
#define EM7180_BURST_LEN		(EM7180_REG_FEATURE0 + 8)
#define EM7180_FEATURE_MAX		3

/* upstream: feature { */
/* A feature sensor: barometer, humidity or temperature (em7180_feature.c) */
struct em7180_feature {
	enum iio_chan_type type;
	u8 slot;		/* rate 0x58 + slot, actual rate 0x48 + slot */
	u8 data_reg;
	u8 end_reg;		/* after its data and TIME */
	unsigned int scan_index;
};

/* upstream: } */
/* upstream: cal { */
/* The calibration as last read: AlgorithmStatus, 0x4D | 0x4E << 8, 0x44 */
struct em7180_cal {
	u8 algo;
	u16 score;
	u8 flags;		/* latched until the warm start is read or written */
	bool valid;
	unsigned long read_at;	/* jiffies */
};

/* What a calibration attribute shows (em7180_cal_show()) */
enum em7180_cal_attr {
	EM7180_CAL_ATTR_LEVEL,
	EM7180_CAL_ATTR_SCORE,
	EM7180_CAL_ATTR_MAG_UPDATE,
	EM7180_CAL_ATTR_GBIAS_UPDATE,
};

/* upstream: } */
struct firmware; /* upstream: upload */
struct iio_trigger;

struct em7180_data {
	struct device *dev;
	struct regmap *regmap;
	struct iio_trigger *trig;	/* NULL without an INT line */
	struct mutex lock;	/* chip access and every field below */
	/* upstream: passthru { */
	/* A transfer on the sensor bus behind the hub (em7180_passthru.c) */
	bool passthru;
	/* upstream: } */
	int irq;
	/* upstream: param { */
	/* Parameter transfer: learned acknowledge wait, register order */
	unsigned int ack_wait_us;
	unsigned int ack_min_us;
	bool ptr_stops;		/* em7180_param_pointer() */
	/* upstream: } */
	struct em7180_cal cal; /* upstream: cal */
	u8 product_id;
	u8 revision_id;
	u16 rom_version;
	u16 ram_version;
	/* upstream: cal { */
	/* The calibration registers 0x43, 0x44, 0x4D-0x4E */
	bool appnote_attrs;	/* at probe: the attributes exist */
	bool appnote;		/* the firmware running has them */
	/* upstream: } */
	/* upstream: param { */
	/* Warm start to re-apply after a power loss or a reset */
	bool ws_valid;
	u8 ws[EM7180_WS_SIZE];
	/* Parameters 27..29, as the chip has them */
	bool accel_offset_valid;
	u32 accel_offset[3];
	/* upstream: } */
	unsigned int pace_event;	/* the EventStatus bit pacing scans */
	unsigned int pace_time;		/* the TIME register of its sensor */
	/* upstream: feature { */
	const struct em7180_feature *pace_feature;	/* for bit 6 */
	/* The feature sensors FeatureFlags announced at probe, slot order */
	struct em7180_feature features[EM7180_FEATURE_MAX];
	unsigned int n_features;
	bool baro_settled;	/* the unit of the barometer's rate register: */
	bool baro_half;		/* half hertz (em7180_feature.c) */
	/* upstream: } */
	/* upstream: health { */
	unsigned int last_error;	/* SensorStatus << 8 | ErrorRegister */
	struct delayed_work recover_work;
	bool xfer_stuck;		/* AlgorithmControl bit 7 may be set */
	unsigned int resets;
	unsigned long recovered_at;
	int recover_ret;
	struct delayed_work watch_work;
	s64 watch_ts;
	unsigned long status_at;	/* last SentralStatus read */
	/* upstream: } */
	struct iio_mount_matrix orientation;
	/* upstream: upload { */
	/* RAM firmware the host uploads (no EEPROM, or firmware-name) */
	const struct firmware *fw;
	const char *fw_name;
	/* upstream: } */
	wait_queue_head_t wq;		/* scans and the end of passthrough */ /* upstream: param */
	s64 timestamp;			/* of the last interrupt */
	/* upstream: param { */
	s64 scan_ts;			/* of the last scan the trigger paced */
	/* upstream: } */
	s64 resumed;			/* when the last pause ended */ /* upstream: param */
	int last_time;			/* that scan's TIME, -1 for none */
	u8 burst[EM7180_BURST_LEN];
	union {
		struct {
			IIO_DECLARE_QUATERNION(s16, quat);	/* Q14 */
			__le16 words[9 + EM7180_FEATURE_MAX];
			aligned_s64 ts;
		} q;	/* the quaternion, when enabled, comes first */
		IIO_DECLARE_BUFFER_WITH_TS(__le16, words, 9 + EM7180_FEATURE_MAX);
	} scan;
};

void em7180_lock(struct em7180_data *data);
DEFINE_GUARD(em7180, struct em7180_data *, em7180_lock(_T), mutex_unlock(&_T->lock))
s32 em7180_float_to_fixed(u32 bits, unsigned int frac_bits);
int em7180_chip_suspend(struct em7180_data *data);
int em7180_chip_resume(struct em7180_data *data);
/* upstream: health { */
int em7180_chip_restore(struct em7180_data *data, bool *lost, u16 *rom, u16 *ram);
/* upstream: } */

#define EM7180_ID_LINE_LEN		64
void em7180_id_line(struct em7180_data *data, char *buf, size_t len);
/* upstream: param { */
void em7180_resumed(struct em7180_data *data);

int em7180_param_pointer(struct em7180_data *data);
int em7180_params_read(struct em7180_data *data, unsigned int first, unsigned int count, u32 *vals);
int em7180_params_write(struct em7180_data *data, unsigned int first,
			unsigned int count, const u32 *vals);

bool em7180_float_is_finite(u32 bits);
u32 em7180_lsb_to_float_g(int lsb);
int em7180_float_g_to_lsb(u32 bits, int *lsb);

int em7180_read_calibbias(struct em7180_data *data, unsigned int axis, int *val);
int em7180_write_calibbias(struct em7180_data *data, unsigned int axis, int val);

int em7180_warmstart_check(const u8 *buf, loff_t off, size_t count, bool write);
int em7180_warmstart_restore(struct iio_dev *indio_dev, const u8 *buf, loff_t off, size_t count);
#if IS_ENABLED(CONFIG_KUNIT)
int em7180_warmstart_read(struct em7180_data *data, struct em7180_caldata *cal);
int em7180_caldata_apply(struct em7180_data *data, const u8 *blob, size_t size, const char *name);
#endif

/* upstream: } */
/* upstream: cal { */
/* Attribute address: enum em7180_cal_attr */
ssize_t em7180_cal_show(struct device *dev, struct device_attribute *attr, char *buf);
int em7180_score_milli(u16 raw);
int em7180_cal_level(u8 algo);
bool em7180_cal_layout(u8 algo, const u8 *regs, bool agree);
int em7180_cal_detect(struct em7180_data *data);
void em7180_cal_update(struct em7180_data *data, const u8 *regs);
void em7180_cal_saved(struct em7180_data *data);
/* upstream: } */

/* upstream: health { */
/* em7180_health.c: resets, recovery and error reports */
int em7180_watch_start(struct iio_dev *indio_dev);
int em7180_watch_stop(struct iio_dev *indio_dev);
int em7180_health_init(struct em7180_data *data);
void em7180_health_debugfs(struct iio_dev *indio_dev);
void em7180_status_seen(struct em7180_data *data, unsigned int status);
void em7180_check_status(struct em7180_data *data);
void em7180_recover_schedule(struct em7180_data *data);
void em7180_recover_stop(struct em7180_data *data);
void em7180_recover_start(struct em7180_data *data);
int em7180_chip_recover(struct em7180_data *data);
void em7180_report_error(struct em7180_data *data);
/* upstream: } */

/* upstream: feature { */
/* em7180_feature.c: barometer, humidity and temperature */
int em7180_feature_layout(unsigned int flags, struct em7180_feature *feat);
void em7180_feature_channels(const struct iio_chan_spec *base, unsigned int n_base,
			     const struct em7180_feature *feat, unsigned int n_feat,
			     struct iio_chan_spec *chans);
int em7180_feature_probe(struct iio_dev *indio_dev,
			 const struct iio_chan_spec *base, unsigned int n_base);
int em7180_feature_configure(struct em7180_data *data, bool from_cache);
const struct em7180_feature *em7180_feature_find(struct em7180_data *data, enum iio_chan_type type);
int em7180_feature_read_info(struct em7180_data *data, const struct em7180_feature *f, int *vals,
			     long mask);
int em7180_feature_read_freq(struct em7180_data *data, const struct em7180_feature *f, int *hz);
int em7180_feature_write_freq(struct em7180_data *data, const struct em7180_feature *f, int hz);
int em7180_feature_read_avail(const int **vals, int *type, int *length);
bool em7180_feature_pace(struct em7180_data *data, const unsigned long *mask, unsigned int best);
int em7180_feature_report(struct em7180_data *data);
/* upstream: } */

/* upstream: passthru { */
/* em7180_passthru.c: the sensor bus behind the hub */
#if IS_ENABLED(CONFIG_KUNIT)
struct i2c_mux_core;
int em7180_passthru_select(struct i2c_mux_core *muxc, u32 chan_id);
int em7180_passthru_deselect(struct i2c_mux_core *muxc, u32 chan_id);
#endif
/* upstream: } */

/* upstream: upload { */
/* em7180_upload.c: firmware from the host */
int em7180_fw_check(const u8 *image, size_t size, u16 rom, char *why, size_t len);
int em7180_upload_probe(struct em7180_data *data, bool no_eeprom);
int em7180_upload(struct em7180_data *data, int ret);
/* upstream: } */

#endif /* _EM7180_CORE_H_ */
