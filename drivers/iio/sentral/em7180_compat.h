/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * The few kernel API differences between Linux 6.1 and 6.12 that the EM7180
 * driver meets. A mainline submission drops this file and keeps the 6.12
 * spelling of each item.
 */
#ifndef _EM7180_COMPAT_H_
#define _EM7180_COMPAT_H_

#include <linux/version.h>

#if KERNEL_VERSION(6, 12, 0) <= LINUX_VERSION_CODE
#include <linux/unaligned.h>
#else
#include <asm/unaligned.h>
#endif

/* iio_trigger_poll_chained() was renamed in 6.4 */
#if KERNEL_VERSION(6, 4, 0) <= LINUX_VERSION_CODE
#define em7180_trigger_poll_nested(trig)	iio_trigger_poll_nested(trig)
#else
#define em7180_trigger_poll_nested(trig)	iio_trigger_poll_chained(trig)
#endif

/* The single-argument i2c probe callback was .probe_new before 6.3 */
#if KERNEL_VERSION(6, 3, 0) <= LINUX_VERSION_CODE
#define EM7180_I2C_PROBE_MEMBER		probe
#else
#define EM7180_I2C_PROBE_MEMBER		probe_new
#endif

/*
 * iio_device_suspend_triggering() came in 6.12; before it, a trigger of
 * another driver feeding the device during system sleep is not stopped.
 */
#if KERNEL_VERSION(6, 12, 0) <= LINUX_VERSION_CODE
#define em7180_suspend_triggering(indio_dev)	iio_device_suspend_triggering(indio_dev)
#define em7180_resume_triggering(indio_dev)	iio_device_resume_triggering(indio_dev)
#else
struct iio_dev;

static inline int em7180_suspend_triggering(struct iio_dev *indio_dev)
{
	return 0;
}

static inline int em7180_resume_triggering(struct iio_dev *indio_dev)
{
	return 0;
}
#endif

#endif /* _EM7180_COMPAT_H_ */
