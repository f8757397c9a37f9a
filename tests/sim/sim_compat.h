/* SPDX-License-Identifier: GPL-2.0 */
/*
 * The kernel API differences between Linux 6.1, 6.12 and 7.2 that the
 * simulator meets, in one place (as em7180_compat.h does for the driver).
 */
#ifndef SIM_COMPAT_H
#define SIM_COMPAT_H

#include <linux/version.h>

/* The single-argument i2c probe callback was .probe_new before 6.3 */
#if KERNEL_VERSION(6, 3, 0) <= LINUX_VERSION_CODE
#define SIM_I2C_PROBE		probe
#else
#define SIM_I2C_PROBE		probe_new
#endif

/* A mux channel took an adapter class until 6.10 */
#if KERNEL_VERSION(6, 10, 0) <= LINUX_VERSION_CODE
#define sim_mux_add_adapter(muxc, chan)	i2c_mux_add_adapter(muxc, 0, chan)
#else
#define sim_mux_add_adapter(muxc, chan)	i2c_mux_add_adapter(muxc, 0, chan, 0)
#endif

/*
 * hrtimer_setup() came in 6.13 and replaced hrtimer_init(), which later
 * kernels no longer have.
 */
#if KERNEL_VERSION(6, 13, 0) > LINUX_VERSION_CODE
#include <linux/hrtimer.h>

static inline void hrtimer_setup(struct hrtimer *timer,
				 enum hrtimer_restart (*function)(struct hrtimer *),
				 clockid_t clock_id, enum hrtimer_mode mode)
{
	hrtimer_init(timer, clock_id, mode);
	timer->function = function;
}
#endif

/* The typed allocators came in 7.0; checkpatch asks for them since */
#include <linux/slab.h>
#ifndef kzalloc_obj
#define kzalloc_obj(obj, gfp)	kzalloc(sizeof(obj), gfp)
#endif

#endif /* SIM_COMPAT_H */
