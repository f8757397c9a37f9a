/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * The few kernel API differences between Linux 6.1, 6.12 and 7.2 that the
 * EM7180 driver meets. The driver is written for 7.2; this file gives older
 * kernels what they lack. A mainline submission drops it and keeps the 7.2
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

/*
 * sysfs passes binary attributes as const since 6.16: to the read and write
 * callbacks, and in an attribute group's list, itself const.
 */
#if KERNEL_VERSION(6, 16, 0) <= LINUX_VERSION_CODE
#define em7180_bin_attribute	const struct bin_attribute
#define em7180_bin_attr_const	const
#else
#define em7180_bin_attribute	struct bin_attribute
#define em7180_bin_attr_const
#endif

/* Symbol namespaces are string literals since 6.13 (commit cdd30ebb1b9f) */
#if KERNEL_VERSION(6, 13, 0) > LINUX_VERSION_CODE
#include <linux/export.h>
#include <linux/module.h>

#undef EXPORT_SYMBOL_NS_GPL
#undef MODULE_IMPORT_NS
#if KERNEL_VERSION(6, 5, 0) <= LINUX_VERSION_CODE
#define EXPORT_SYMBOL_NS_GPL(sym, ns)	__EXPORT_SYMBOL(sym, "GPL", ns)
#else
#define EXPORT_SYMBOL_NS_GPL(sym, ns)	__EXPORT_SYMBOL(sym, "_gpl", ns)
#endif
#define MODULE_IMPORT_NS(ns)		MODULE_INFO(import_ns, ns)
#endif

/*
 * The bool-returning pair that sparse can check came in 6.15; it replaced
 * iio_device_claim_direct_mode(), which later kernels no longer have.
 */
#if KERNEL_VERSION(6, 15, 0) > LINUX_VERSION_CODE
#include <linux/iio/iio.h>

static inline bool iio_device_claim_direct(struct iio_dev *indio_dev)
{
	if (iio_device_claim_direct_mode(indio_dev))
		return false;
	__acquire(indio_dev);
	return true;
}

static inline void iio_device_release_direct(struct iio_dev *indio_dev)
{
	iio_device_release_direct_mode(indio_dev);
	__release(indio_dev);
}
#endif

/* 6.16 added the push that checks the scan's storage against scan_bytes */
#if KERNEL_VERSION(6, 16, 0) > LINUX_VERSION_CODE
#include <linux/iio/buffer.h>

static inline int iio_push_to_buffers_with_ts(struct iio_dev *indio_dev,
					      void *data, size_t data_total_len,
					      s64 timestamp)
{
	if (unlikely(data_total_len < indio_dev->scan_bytes))
		return -ENOSPC;
	return iio_push_to_buffers_with_timestamp(indio_dev, data, timestamp);
}
#endif

/*
 * Mainline's typed scan buffer declarations, where the kernel's iio.h has
 * them not yet: tested by name, not by a version that might miss one.
 */
#include <linux/iio/iio.h>
#ifndef IIO_DECLARE_BUFFER_WITH_TS
#define IIO_DECLARE_BUFFER_WITH_TS(type, name, count)			\
	type name[ALIGN((count), sizeof(s64) / sizeof(type)) +		\
		  sizeof(s64) / sizeof(type)] __aligned(sizeof(s64))
#endif
#ifndef IIO_DECLARE_QUATERNION
#define IIO_DECLARE_QUATERNION(type, name)				\
	type name[4] __aligned(sizeof(type) * 4)
#endif

/* i2c_mux_add_adapter() lost its class argument in 6.10 (fec1982d7072) */
#if KERNEL_VERSION(6, 10, 0) <= LINUX_VERSION_CODE
#define em7180_i2c_mux_add_adapter(muxc, nr, chan)	i2c_mux_add_adapter(muxc, nr, chan)
#else
#define em7180_i2c_mux_add_adapter(muxc, nr, chan)	i2c_mux_add_adapter(muxc, nr, chan, 0)
#endif

/*
 * Work items can be disabled since 6.10. Before, a cancel is the nearest:
 * it refuses the queueing of the work item it waits for, but not a later
 * one. The driver disables its recovery where little else queues it: on
 * unbind, once the interrupt, the IIO device and the sensor bus adapter
 * are gone, and for system sleep, with the interrupt off and tasks frozen
 * (a transfer on the sensor bus could still ask for one there).
 */
#if KERNEL_VERSION(6, 10, 0) > LINUX_VERSION_CODE
#include <linux/workqueue.h>

static inline bool disable_delayed_work_sync(struct delayed_work *dwork)
{
	return cancel_delayed_work_sync(dwork);
}

static inline bool enable_delayed_work(struct delayed_work *dwork)
{
	return true;
}
#endif

/*
 * KUnit-managed devices came in 6.8: before, a root device that a KUnit
 * resource unregisters when the case ends. It names no module: 6.1 runs
 * the KUnit suites of a module while it is still coming, before the sysfs
 * directory such a link would point to exists.
 */
#if KERNEL_VERSION(6, 8, 0) <= LINUX_VERSION_CODE
#include <kunit/device.h>
#else
#include <kunit/resource.h>
#include <linux/device.h>

static inline void em7180_kunit_device_free(struct kunit_resource *res)
{
	root_device_unregister(res->data);
}

static inline struct device *kunit_device_register(struct kunit *test,
						   const char *name)
{
	struct device *dev = __root_device_register(name, NULL);

	if (IS_ERR(dev))
		return dev;
	if (!kunit_alloc_resource(test, NULL, em7180_kunit_device_free,
				  GFP_KERNEL, dev)) {
		root_device_unregister(dev);
		return ERR_PTR(-ENOMEM);
	}
	return dev;
}

static inline bool em7180_kunit_device_match(struct kunit *test,
					     struct kunit_resource *res,
					     void *dev)
{
	return res->free == em7180_kunit_device_free && res->data == dev;
}

static inline void kunit_device_unregister(struct kunit *test,
					   struct device *dev)
{
	kunit_destroy_resource(test, em7180_kunit_device_match, dev);
}

/* KUNIT_CASE_SLOW came a release or two before 6.8: tested by name */
#ifndef KUNIT_CASE_SLOW
#define KUNIT_CASE_SLOW(test_name)	KUNIT_CASE(test_name)
#endif
#endif

#endif /* _EM7180_COMPAT_H_ */
