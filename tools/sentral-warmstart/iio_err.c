// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: what an errno from the em7180 driver's sysfs means,
 * as an exit code and a message that says what to do about it.
 */
#include <errno.h>
#include <string.h>

#include "backend.h"

int sw_iio_err(struct sw_err *e, const char *name, const char *op,
	       const char *attr, int err, bool dir_gone)
{
	const char *hint = "";

	if (err == ENODEV || dir_gone)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%s is gone (unbound or unplugged): %s %s: %s",
				  name, op, attr, strerror(err));
	if (err == ENOENT)
		return sw_err_set(e, SW_EXIT_DRIVER,
				  "%s: %s %s: the driver has no such attribute: it is older or newer than this tool",
				  name, op, attr);
	/* The driver refuses writes while a buffer runs; nothing ends it for us. */
	if (err == EBUSY)
		return sw_err_set(e, SW_EXIT_IO,
				  "%s: %s %s: %s: a buffer is enabled on %s (a program is streaming from it, or one that exited without disabling it): stop it, or write 0 to /sys/bus/iio/devices/%s/buffer/enable",
				  name, op, attr, strerror(err), name, name);
	if (err == ETIMEDOUT)
		hint = " (the chip did not acknowledge a parameter)";
	else if (err == EINVAL)
		hint = " (the driver refused the value)";
	return sw_err_set(e, SW_EXIT_IO, "%s: %s %s: %s%s", name, op, attr,
			  strerror(err), hint);
}
