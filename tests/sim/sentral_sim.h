/* SPDX-License-Identifier: GPL-2.0 */
/*
 * Simulated PNI SENtral / EM Microelectronic EM7180 sensor-fusion hub.
 *
 * Shared definitions of the model (sim-model.c), the float32 helpers
 * (sim-float.c), the debugfs knobs (sim-debugfs.c) and the virtual I2C
 * adapter (sim-main.c).
 */
#ifndef SENTRAL_SIM_H
#define SENTRAL_SIM_H

#include <linux/hrtimer.h>
#include <linux/i2c.h>
#include <linux/irq_work.h>
#include <linux/ktime.h>
#include <linux/spinlock.h>
#include <linux/types.h>

#include "sim-motion.h"
#include "sim-usfs.h"

#define SIM_I2C_ADDR		0x28
/* RAMVersion at load */
#define SIM_RAM_VERSION		0x0d17

/* Register addresses, EM7180 register reference §1 */
#define SIM_REG_QX		0x00
#define SIM_REG_QTIME		0x10
#define SIM_REG_MX		0x12
#define SIM_REG_MTIME		0x18
#define SIM_REG_AX		0x1a
#define SIM_REG_ATIME		0x20
#define SIM_REG_GX		0x22
#define SIM_REG_GTIME		0x28
#define SIM_REG_FEATURE0	0x2a	/* feature data slots 0x2a..0x31 */
#define SIM_REG_QRATE_DIVISOR	0x32
#define SIM_REG_ENABLE_EVENTS	0x33
#define SIM_REG_HOST_CONTROL	0x34
#define SIM_REG_EVENT_STATUS	0x35
#define SIM_REG_SENSOR_STATUS	0x36
#define SIM_REG_SENTRAL_STATUS	0x37
#define SIM_REG_ALGO_STATUS	0x38
#define SIM_REG_FEATURE_FLAGS	0x39
#define SIM_REG_PARAM_ACK	0x3a
#define SIM_REG_SAVED_PARAM0	0x3b
#define SIM_REG_SAVED_PARAM3	0x3e
#define SIM_REG_LIN_ACCEL	0x3f	/* USFS: 0x3f..0x44, GP8..GP13 */
#define SIM_REG_CAL_STATUS	0x43
#define SIM_REG_CAL_FLAGS	0x44
#define SIM_REG_ACTUAL_MAG	0x45
#define SIM_REG_ACTUAL_ACCEL	0x46
#define SIM_REG_ACTUAL_GYRO	0x47
#define SIM_REG_ACTUAL_FEATURE0	0x48	/* 0x48..0x4a */
#define SIM_REG_CAL_SCORE_LSB	0x4d
#define SIM_REG_CAL_SCORE_MSB	0x4e
#define SIM_REG_ERROR		0x50
#define SIM_REG_ALGO_CONTROL	0x54
#define SIM_REG_MAG_RATE	0x55
#define SIM_REG_ACCEL_RATE	0x56
#define SIM_REG_GYRO_RATE	0x57
#define SIM_REG_FEATURE_RATE0	0x58	/* 0x58..0x5a, bit 7: report */
#define SIM_REG_LOAD_PARAM0	0x60
#define SIM_REG_LOAD_PARAM3	0x63
#define SIM_REG_PARAM_REQUEST	0x64
#define SIM_REG_ROM_VERSION	0x70
#define SIM_REG_RAM_VERSION	0x72
#define SIM_REG_PRODUCT_ID	0x90
#define SIM_REG_REVISION_ID	0x91
#define SIM_REG_RUN_STATUS	0x92
#define SIM_REG_UPLOAD_ADDR	0x94	/* 0x94..0x95, MSB first */
#define SIM_REG_UPLOAD_DATA	0x96
#define SIM_REG_CRC_HOST	0x97	/* 0x97..0x9a */
#define SIM_REG_RESET_REQUEST	0x9b
#define SIM_REG_PASSTHRU_STATUS	0x9e
#define SIM_REG_PASSTHRU_CTRL	0xa0

#define SIM_EV_CPU_RESET	BIT(0)
#define SIM_EV_ERROR		BIT(1)
#define SIM_EV_QUATERNION	BIT(2)
#define SIM_EV_MAG		BIT(3)
#define SIM_EV_ACCEL		BIT(4)
#define SIM_EV_GYRO		BIT(5)
#define SIM_EV_FEATURE		BIT(6)
#define SIM_EV_DATA		(SIM_EV_QUATERNION | SIM_EV_MAG | \
				 SIM_EV_ACCEL | SIM_EV_GYRO)

#define SIM_HOST_RUN		BIT(0)
#define SIM_HOST_UPLOAD		BIT(1)
#define SIM_ALGO_STANDBY	BIT(0)
#define SIM_ALGO_PARAM_PROC	BIT(7)
#define SIM_PARAM_WRITE		BIT(7)

#define SIM_CAL_MAG_UPDATE	BIT(0)
#define SIM_CAL_GBIAS_UPDATE	BIT(1)

/* What ParamAcknowledge does when a host ends a parameter transfer */
#define SIM_ACK_END_CLEAR	0	/* 0 at once on a stop or bit 7 clear */
#define SIM_ACK_END_SERVED	1	/* a stop is served like a request */
#define SIM_ACK_END_KEPT	2	/* keeps its last echo */
#define SIM_ACK_END_MAX		SIM_ACK_END_KEPT

#define SIM_NPARAMS		128	/* parameters 1..127; 0 means STOP */
#define SIM_NCOEFFS		6	/* mcoeffs, warm-start parameters 18..23 */

enum sim_stream_id {
	SIM_QUAT,
	SIM_MAG,
	SIM_ACCEL,
	SIM_GYRO,
	SIM_NSTREAMS,
};

/*
 * Why a sample was lost after the host had read a data-ready since it came
 * (tests/sim/README.md, "Whose loss a sample is"): the simulator sees every
 * transaction and every sample's time.
 */
enum sim_drop_cause {
	SIM_DROP_PENDING,	/* decided by the host's next transaction */
	SIM_DROP_HELD,		/* the data timer ran half a period late */
	SIM_DROP_IDLE,		/* it or that read came, no data event enabled */
	SIM_DROP_LATE_IRQ,	/* the status read ended after the next was due,
				 * or the sample came half a period late
				 */
	SIM_DROP_LATE_WAKE,	/* the host came back from it too late */
	SIM_DROP_SLOW,		/* its own time to the burst was too long */
	SIM_DROP_UNREAD,	/* its next transaction was not the burst */
	SIM_DROP_NCAUSES,
};

/* What a transaction was to one stream */
enum sim_xfer_kind {
	SIM_XFER_NONE,
	SIM_XFER_BURST,		/* it read the stream's block */
	SIM_XFER_STATUS,	/* it read EventStatus, not the block */
	SIM_XFER_OTHER,
};

/*
 * One such loss and its evidence, in a ring per chip (debugfs drops), and
 * those of the host driver's causes in another (drops_host). The
 * status read is the first that reported a data-ready since the sample
 * came; the host "comes back" from it when the transfer returns to the
 * caller (the wire time modelled, the caller sleeps until its end).
 */
struct sim_drop {
	u8 stream;
	u8 cause;
	u8 next;		/* enum sim_xfer_kind of the next transaction */
	u32 busy;		/* transactions between the sample and the read */
	u64 seen_xfer;		/* the read's number (sim->xfers) */
	u64 period_ns;
	s64 came_late_ns;	/* the sample's timer behind its time */
	s64 inflight_ns;	/* of a transaction on the wire when it came */
	s64 latency_ns;		/* the sample to the status read's start */
	s64 wire_ns;		/* the status read, start to end */
	s64 margin_ns;		/* its end to the next sample's due time */
	s64 wake_ns;		/* its end to the host's return; -1: not yet */
	s64 gap_ns;		/* that return to the next transaction; -1 */
	s64 late_ns;		/* the next sample's timer behind its time */
	ktime_t seen_end;
	ktime_t seen_ret;
};

#define SIM_DROP_LOG		128

/*
 * One output stream. Its TIME register is ts_base + floor(n * 32768 *
 * rate_den / rate_num) (1/32768 s units, EM7180 register reference §1),
 * n counting samples since the stream last (re)started, so a host can
 * tell a missed sample from the timestamps alone.
 */
struct sim_stream {
	u32 rate_num;		/* rate = rate_num / rate_den Hz; 0: off */
	u32 rate_den;
	u64 period_ns;
	u64 tick;		/* next sample is due at epoch + tick * period */
	u32 n;
	u16 ts_base;
	u16 ts;
	bool unread;		/* latest sample not yet read by the host */
	u64 produced;
	u64 read;
	u64 missed;
	u64 read_seq;		/* produced count at the last read; 0: none */
	u64 gaps;		/* samples skipped between two reads */
	u64 held_unread;	/* of the misses since the last read, by a held timer */
	u64 gaps_held;		/* gaps whose sample a held timer replaced */
	u64 drdy_mark;		/* sim->drdy_seen when the latest sample came */
	u64 drops_seen;		/* lost after the host saw a data-ready */
	u64 drops_cause[SIM_DROP_NCAUSES];	/* of those, per cause */
	u64 drops_unseen;	/* lost before the host saw any */
	/* the latest sample's way to the host, for the cause of its loss */
	ktime_t came;
	u64 came_xfer;		/* sim->xfers when it came */
	s64 came_late_ns;
	s64 came_inflight_ns;
	bool came_idle;		/* EnableEvents enabled no data event then */
	ktime_t seen_start;	/* the status read that saw it; 0: none yet */
	ktime_t seen_end;
	ktime_t seen_ret;	/* the host back from it; 0: not yet */
	u64 seen_xfer;
	bool seen_idle;		/* EnableEvents enabled no data event then */
	ktime_t next_start;	/* the host's next transaction; 0: none yet */
	u8 next_kind;
	u64 pending;		/* 1 + its drop_log entry awaiting more; 0 */
};

struct sim_stats {
	u64 transactions;
	u64 bytes;
	u64 bus_ns;
	u64 nacks;
	u64 params_served;
	/* ParamAcknowledge reads while a request still waited: early polls */
	u64 ack_polls_early;
	/* transfers that waited for their wire time, and how late they woke */
	u64 wire_waits;
	u64 wire_late_100us;	/* woke 100 us or more after its end */
	u64 wire_late_1ms;
	s64 wire_late_max_ns;
	/* the host back from a status read that saw data to its next transfer */
	u64 host_gaps;
	u64 host_gap_100us;
	s64 host_gap_max_ns;
	/* the data timer: how far behind a sample's due time it ran, at most */
	s64 timer_late_max_ns;
	ktime_t first;
	ktime_t last;
};

struct sentral_sim {
	/*
	 * Protects everything below. A spinlock because the hrtimer callback
	 * producing samples runs in hard-irq context.
	 */
	spinlock_t lock;
	bool dead;

	u8 regs[256];		/* plain registers and the data image */
	u32 params[SIM_NPARAMS];

	/* Parameter transfer, EM7180 register reference §2 */
	bool req_pending;
	ktime_t req_servable_at;
	u8 param_ack;
	u8 saved_param[4];
	ktime_t transfer_started; /* when bit 7 was last set; 0: never */
	ktime_t transfer_ended;	/* when bit 7 was last cleared; 0: never */
	s64 transfer_longest_us; /* the longest time bit 7 stayed set */

	/* Firmware upload from EEPROM after power-on or reset, §3 */
	ktime_t upload_done_at;

	/* Algorithm clock: running time split into motion and still time */
	ktime_t last_advance;
	u64 cal_ns;
	unsigned int cal_step;
	u64 still_ns;
	s32 coeff[SIM_NCOEFFS];		/* model's mcoeffs, micro-units */
	s32 coeff_from[SIM_NCOEFFS];	/* where the current convergence began */
	/* field directions seen since calibration (re)started */
	DECLARE_BITMAP(cal_seen, SIM_REGIONS);
	u8 cal_flags;			/* latched 0x44 bits */
	/* updates made and their flags read set, [0] mag, [1] gyro bias */
	u64 cal_updates[2];
	u64 cal_updates_read[2];
	u8 event_status;
	u64 drdy_seen;		/* EventStatus reads that reported new data */
	/* the transaction in progress, for the causes of drops */
	u64 xfers;		/* since load, never reset */
	ktime_t xfer_start;
	ktime_t xfer_last_end;	/* of the last one */
	u8 xfer_reads;		/* BIT(stream) of the blocks it read */
	bool xfer_status;	/* it read EventStatus */
	bool xfer_drdy;		/* and that reported new data */
	ktime_t drdy_ret;	/* the host back from such a read; 0: used */
	struct sim_drop drop_log[SIM_DROP_LOG];
	u64 drops_logged;
	/* the host driver's drops apart, kept from the harness's many */
	struct sim_drop host_log[SIM_DROP_LOG];
	u64 host_logged;
	u32 noise_state;

	/* Sample production */
	struct hrtimer timer;
	bool producing;
	ktime_t epoch;
	u32 quat_phase;
	struct sim_stream stream[SIM_NSTREAMS];
	u64 timer_late;

	/* INT pin: high while (EventStatus & EnableEvents) != 0 or latched */
	bool int_high;
	bool int_latched;	/* high until EventStatus is read */
	u64 irqs;
	unsigned int virq;
	bool irq_masked;		/* set by the irq_chip, under its lock */
	struct irq_work irq_work;	/* delivery when unmasked, resent */

	/* Bus */
	u8 pointer;
	u32 bus_khz;		/* 0: no wire time, 400 kHz accounting */
	bool autoinc_stop;	/* no increment 0x3a->0x3b nor 0x63->0x64 */
	struct sim_stats stats;
	u32 nack_at;
	u32 nack_count;
	u32 nack_run;
	u32 nack_left;

	/* The world: orientation and motion (survives resets) */
	struct sim_motion world;
	/* the magnetometer's true coefficients, moved by drift_ms */
	s32 coeff_true[SIM_NCOEFFS];
	u32 score_floor_milli;		/* score at the true coefficients */
	u64 drift_ns;			/* turning time since the last drift */
	u32 drift_rng;

	/* Knobs */
	u32 cal_duration_ms;
	u32 gbias_period_ms;
	u32 drift_ms;			/* 0: the field never changes */
	u8 mag_transient;
	s16 accel_bias[3];
	bool appnote_layout;	/* 0x43/0x44/0x4d as the application note */
	u8 algo_status_or;	/* OR-ed into AlgorithmStatus reads */
	u32 ack_latency_us;
	bool ack_never;
	u8 ack_end;		/* SIM_ACK_END_*: the acknowledge after a stop */
	u32 upload_ms;
	u16 ram_version;
	u16 rom_version;
	u8 product_id;
	u8 revision_id;
	u8 sensor_status;	/* SensorStatus: a sensor that does not answer */
	bool events_gated;	/* EventStatus latches only enabled events */
	bool reset_int;		/* chip_reset raises INT for CPUReset */
	bool wedged;		/* after a host's warm reboot, until a reset */
	bool standby_never;
	bool standby_power_loss;
	bool standby_blocks_params;
	u32 nack_after_reset_ms;
	ktime_t nack_until;	/* NACK everything before this time */

	/* The board: feature sensors, sensor bus, host upload (sim-usfs.c) */
	struct sim_usfs usfs;

	struct fwnode_handle *fwnode;
	struct irq_domain *domain;
	struct dentry *debugfs;
	void *knob_files;		/* sim-debugfs.c's, one per file */
};

/*
 * Registers hold little-endian values at any byte offset. Assembling the
 * bytes here avoids the unaligned.h header move between Linux 6.1 and 6.12.
 */
static inline void sim_put_le16(u16 v, u8 *p)
{
	p[0] = v;
	p[1] = v >> 8;
}

static inline void sim_put_le32(u32 v, u8 *p)
{
	sim_put_le16(v, p);
	sim_put_le16(v >> 16, p + 2);
}

static inline u32 sim_get_le32(const u8 *p)
{
	return p[0] | p[1] << 8 | p[2] << 16 | (u32)p[3] << 24;
}

/* sim-float.c: IEEE-754 binary32 bit patterns with integer math only */
int sim_f32_to_scaled(u32 bits, u32 mul, u32 div, s64 *out);
u32 sim_f32_from_ratio(s64 num, u64 den);

/* sim-model.c: all called with sim->lock held */
void sim_model_init(struct sentral_sim *sim);
void sim_power_on(struct sentral_sim *sim, ktime_t now);
void sim_advance(struct sentral_sim *sim, ktime_t now);
u8 sim_reg_read(struct sentral_sim *sim, u8 reg, ktime_t now, bool peek);
void sim_reg_write(struct sentral_sim *sim, u8 reg, u8 val, ktime_t now);
void sim_schedule(struct sentral_sim *sim, ktime_t now);
bool sim_int_update(struct sentral_sim *sim);
u8 sim_cal_status(struct sentral_sim *sim);
u16 sim_cal_score_raw(struct sentral_sim *sim);
bool sim_in_upload(struct sentral_sim *sim, ktime_t now);
bool sim_algo_running(struct sentral_sim *sim, ktime_t now);
bool sim_nacks(struct sentral_sim *sim, ktime_t now);
void sim_int_stuck(struct sentral_sim *sim);
void sim_event(struct sentral_sim *sim, u8 ev);
void sim_xfer_begin(struct sentral_sim *sim, ktime_t start);
void sim_xfer_end(struct sentral_sim *sim, ktime_t end);
void sim_xfer_return(struct sentral_sim *sim, u64 xfer, ktime_t now);
void sim_error(struct sentral_sim *sim, u8 code);

/* sim-main.c */
void sim_fire_irq(struct sentral_sim *sim);

/* sim-debugfs.c: the chip's knobs in debugfs directory dir */
int sim_debugfs_init(struct sentral_sim *sim, const char *dir);
void sim_debugfs_exit(struct sentral_sim *sim);
int sim_knobs_apply(struct sentral_sim *sim, const char *spec);

#endif /* SENTRAL_SIM_H */
