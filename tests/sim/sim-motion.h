/* SPDX-License-Identifier: GPL-2.0 */
/*
 * The world around the simulated EM7180: the device's orientation, driven
 * along a motion pattern or a path of rotations, and the directions of the
 * Earth's field the chip has seen (its calibration coverage). The model is
 * described in tests/sim/README.md, "Motion and coverage".
 */
#ifndef SENTRAL_SIM_MOTION_H
#define SENTRAL_SIM_MOTION_H

#include <linux/bitmap.h>
#include <linux/bits.h>
#include <linux/ktime.h>
#include <linux/types.h>

/* Equal-area regions of the sphere: 1 + 15 + 34 + 34 + 15 + 1 */
#define SIM_REGIONS		100
/* Path segments a test can queue */
#define SIM_PATH_MAX		16
/* Q30 fixed point: quaternions and unit vectors */
#define SIM_Q30			BIT(30)

enum sim_pattern {
	SIM_PAT_STILL,
	SIM_PAT_SPIN,
	SIM_PAT_FIGURE8,
	SIM_PAT_SPHERE,
	SIM_PAT_PATH,
	SIM_NPATTERNS,
};

/* A rotation about a body axis at a constant rate, for a while */
struct sim_segment {
	s32 axis[3];		/* unit vector, Q30 */
	s32 in[3];		/* the axis as written, for reading back */
	s32 rate_dps;
	u32 ms;
};

struct sim_motion {
	enum sim_pattern pattern;
	ktime_t start;		/* when the pattern began */
	ktime_t now;		/* time of q and rate */
	s32 q0[4];		/* orientation at start, Q30 w, x, y, z */
	s32 q[4];		/* orientation now: body to NED */
	s32 rate_mdps[3];	/* angular velocity now, body frame */
	u64 prev_t_ns;		/* time of the last advance, since start */
	u64 next_sample_ns;	/* next coverage sample, since start */

	struct sim_segment seg[SIM_PATH_MAX];
	unsigned int nseg;
	unsigned int cur;	/* segment playing */
	u64 cur_start_ns;	/* its start, since start */
	s32 qseg[4];		/* orientation at its start */
	u64 path_pos_ns;	/* path state is valid at this time */
	u64 path_moving_ns;	/* time spent in turning segments */
};

/* NED Earth field (pT) and gravity (accel LSB) */
extern const s64 sim_earth_field[3];

void sim_motion_init(struct sim_motion *m, ktime_t now);
u64 sim_motion_advance(struct sim_motion *m, ktime_t now, unsigned long *seen);
bool sim_motion_moving(const struct sim_motion *m);
void sim_motion_to_body(const struct sim_motion *m, const s64 world[3],
			s64 body[3]);
int sim_motion_set_pattern(struct sim_motion *m, enum sim_pattern p,
			   ktime_t now);
void sim_motion_set_orientation(struct sim_motion *m, const s64 q[4],
				ktime_t now);
int sim_motion_add_segment(struct sim_motion *m, const s32 axis[3],
			   s32 rate_dps, u32 ms);
int sim_motion_clear_path(struct sim_motion *m);
const char *sim_pattern_name(enum sim_pattern p);
unsigned int sim_region(const s64 v[3]);

#endif /* SENTRAL_SIM_MOTION_H */
