/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * A fake EM7180 behind the backend interface, with a fake clock, for the
 * unit tests of the commands and the policy.
 */
#ifndef SW_FAKE_BACKEND_H
#define SW_FAKE_BACKEND_H

#include "board.h"
#include "cmd.h"

struct fake_clock {
	uint64_t now_ms;
	uint64_t wall_s;
};

/* A level that reads as the driver's EIO for a glitch (AlgorithmStatus 0xff). */
#define FAKE_GLITCH (-1)

/*
 * From at_ms on, cal_state reports this (a calibration script); score_raw
 * and the flag only where cs.has_score says the firmware has them.
 */
struct fake_step {
	uint64_t at_ms;
	int level;		/* or FAKE_GLITCH */
	uint16_t score_raw;
	int gyro_bias_update;	/* 1: the chip reports an update at at_ms */
};

struct fake_be {
	struct sw_backend b;
	struct fake_clock *clk;
	struct sw_chip_info chip;
	/* when there is no script; cs.has_score: the firmware has a score */
	struct sw_cal_state cs;
	const struct fake_step *script;
	size_t nsteps;
	int level_after_write;		/* -1: a restore changes nothing */
	/* the level the chip is at after a read of the blob, -1: as before */
	int level_after_read;
	uint8_t blob[SW_BLOB_SIZE];
	/* blob param 18 = current score (the level without one) */
	bool blob_follows_score;
	int writes, reads;
	int fail_write;			/* exit code write_blob returns */
	int fail_read;			/* exit code read_blob returns */
	/*
	 * accel: output = bias + expected - offset (+ alternating noise);
	 * offset is parameters 27..29 of the blob the fake reads and writes
	 */
	int bias[3];
	int offset[3];
	int noise;
	bool offset_readback_wrong;
	const int *offset_reported;	/* what a lying driver reports */
	unsigned int samples_read;
	/* the magnetometer at a time: NULL reads a device at rest */
	void (*mag)(uint64_t now_ms, double ut[3]);
	unsigned int mag_reads;
	/* cal_state calls; the driver's flags were cleared at flags_cleared_ms */
	unsigned int state_reads;
	bool flags_cleared;
	uint64_t flags_cleared_ms;
	/* from gone_ms on (when not 0) the device is gone: unbound, unplugged */
	uint64_t gone_ms;
	/* firmware origin and feature sensors; hub_fail: hub_info's exit code */
	struct sw_hub_info hub;
	int hub_fail;
	/* called at each chip_info (the save policy's first look) */
	void (*on_chip_info)(struct fake_be *f);
	unsigned int chip_infos;	/* chip_info calls */
	void *data;		/* the hook's */
};

void fake_init(struct fake_be *f, struct fake_clock *clk);
void fake_env(struct sw_env *env, struct fake_clock *clk, FILE *out,
	      FILE *err);
/* The parameters of a plausible blob: i * 0.5 for parameter i. */
void fake_fill_blob(uint8_t *blob);

/*
 * A 64 KiB M24512 image as the USFS utilities leave it (board.h): erased
 * (0xff) but for the block of layout l, holding fake_fill_blob()'s
 * parameters, an accel cal of max 2049 2050 2051 and min -2047 -2046
 * -2045 LSB, and for gt the marker. Returns the block's first address.
 */
uint32_t fake_board_image(uint8_t *img, enum sw_board_layout l);

#endif
