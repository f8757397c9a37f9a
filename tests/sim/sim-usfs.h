/* SPDX-License-Identifier: GPL-2.0 */
/*
 * The board around the simulated EM7180, as on the USFS: the feature
 * sensors the firmware reports (barometer, humidity, temperature), the
 * hub's own sensor bus that passthrough connects to the host's (an M24512
 * EEPROM, the MPU9250, its AK8963 and the MS5637) and the host RAM upload
 * of a board without an EEPROM. See tests/sim/README.md.
 */
#ifndef SIM_USFS_H
#define SIM_USFS_H

#include <linux/i2c.h>
#include <linux/ktime.h>
#include <linux/types.h>

struct dentry;
struct sentral_sim;
struct seq_file;

#define SIM_NFEATURES		3	/* feature slots 0..2, rates 0x58..0x5a */
#define SIM_EEPROM_SIZE		65536	/* M24512: 512 Kbit */
#define SIM_EEPROM_PAGE		128	/* its page, and its ID page */
#define SIM_AK8963_NREGS	0x20
#define SIM_MPU9250_NREGS	0x80
/* Upload RAM: 13-bit UploadAddress in 32-bit words (reference §1) */
#define SIM_UPLOAD_RAM_SIZE	32768

/* Where the firmware in the chip's RAM came from */
enum sim_fw_origin {
	SIM_FW_NONE,		/* none: waits for a host upload */
	SIM_FW_EEPROM,		/* loaded by the chip from its EEPROM */
	SIM_FW_HOST,		/* uploaded by the host */
	SIM_FW_BAD,		/* a host upload that was not a well-formed image */
};

/* One feature sensor: its stream, as the other sensors' (sim_stream) */
struct sim_feature {
	u8 flag;		/* FeatureFlags bit: 0 baro, 1 humidity, 2 temp */
	u32 rate;		/* Hz, 0: off */
	u64 period_ns;
	u64 tick;		/* next sample at epoch + tick * period */
	u32 n;
	u16 ts_base;
	u16 ts;
	u64 produced;
};

struct sim_usfs {
	/* Knobs: what the board is (they survive resets) */
	u8 feature_flags;
	bool baro_rate_half;	/* KW: the barometer samples at BaroRate / 2 */
	bool no_eeprom;
	bool crc_wire;		/* CRCHost over the bytes as they crossed */
	u32 eeprom_write_ms;
	ktime_t t0;		/* the world's clock for the weather */

	/* Feature sensors */
	unsigned int nfeat;
	struct sim_feature feat[SIM_NFEATURES];

	/* The sensor bus behind passthrough */
	u8 *eeprom;
	u8 id_page[SIM_EEPROM_PAGE];
	u16 ee_addr;		/* the EEPROM's address counter */
	ktime_t ee_busy_until;	/* internal write cycle: no acknowledge */
	u8 mpu[SIM_MPU9250_NREGS];
	u8 mpu_ptr;
	u8 ak[SIM_AK8963_NREGS];
	u8 ak_ptr;
	u8 ms_cmd;		/* MS5637: the last command */
	u32 ms_adc;		/* the last conversion's result */
	u64 bus_transactions;
	u64 bus_nacks;

	/* Host RAM upload (reference §3 item 3) */
	u8 *ram;
	bool uploading;		/* HostControl bit 1 */
	u32 up_pos;		/* RAM offset of the next byte */
	u32 up_len;		/* bytes received since the upload began */
	u32 up_start;		/* RAM offset the upload began at */
	bool up_overflow;
	u32 up_crc_wire;	/* running CRC over the bytes as received */
	enum sim_fw_origin fw;
	u16 fw_ram_version;	/* from the uploaded image's CDS block */
};

/* sim-usfs.c; all but alloc/free and debugfs called with sim->lock held */
int sim_usfs_alloc(struct sentral_sim *sim);
void sim_usfs_free(struct sentral_sim *sim);
void sim_usfs_init(struct sentral_sim *sim, ktime_t now);
void sim_usfs_power_on(struct sentral_sim *sim, ktime_t now);
bool sim_usfs_firmware(struct sentral_sim *sim, ktime_t now);
u16 sim_usfs_ram_version(struct sentral_sim *sim, ktime_t now);
u8 sim_usfs_sentral_status(struct sentral_sim *sim, ktime_t now);
bool sim_usfs_reg_read(struct sentral_sim *sim, u8 reg, ktime_t now, u8 *val);
u8 sim_usfs_host_control(struct sentral_sim *sim, u8 val, ktime_t now);
void sim_usfs_upload_byte(struct sentral_sim *sim, u8 val);
bool sim_usfs_passthrough(struct sentral_sim *sim);
void sim_usfs_schedule(struct sentral_sim *sim, bool prod, bool restart,
		       ktime_t now);
ktime_t sim_usfs_next_due(struct sentral_sim *sim, ktime_t next);
ktime_t sim_usfs_tick(struct sentral_sim *sim, ktime_t now, ktime_t next);
int sim_usfs_xfer(struct sentral_sim *sim, struct i2c_msg *msgs, int num);
void sim_usfs_debugfs_init(struct sentral_sim *sim, struct dentry *dir);

/* Knobs, in sim-debugfs.c's table */
void sim_usfs_feature_flags_show(struct seq_file *m, struct sentral_sim *sim,
				 ktime_t now);
int sim_usfs_feature_flags_store(struct sentral_sim *sim, char *buf,
				 ktime_t now);
void sim_usfs_baro_rate_half_show(struct seq_file *m, struct sentral_sim *sim,
				  ktime_t now);
int sim_usfs_baro_rate_half_store(struct sentral_sim *sim, char *buf,
				  ktime_t now);
void sim_usfs_no_eeprom_show(struct seq_file *m, struct sentral_sim *sim,
			     ktime_t now);
int sim_usfs_no_eeprom_store(struct sentral_sim *sim, char *buf, ktime_t now);
void sim_usfs_crc_wire_show(struct seq_file *m, struct sentral_sim *sim,
			    ktime_t now);
int sim_usfs_crc_wire_store(struct sentral_sim *sim, char *buf, ktime_t now);
void sim_usfs_eeprom_write_ms_show(struct seq_file *m, struct sentral_sim *sim,
				   ktime_t now);
int sim_usfs_eeprom_write_ms_store(struct sentral_sim *sim, char *buf,
				   ktime_t now);
void sim_usfs_board_show(struct seq_file *m, struct sentral_sim *sim,
			 ktime_t now);

#endif /* SIM_USFS_H */
