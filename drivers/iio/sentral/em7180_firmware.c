// SPDX-License-Identifier: GPL-2.0-only
/*
 * PNI SENtral / EM7180: firmware known to report the calibration
 *
 * Status, flags and score live in general-purpose registers (0x43, 0x44,
 * 0x4D-0x4E) that other firmware builds use for other things (Sony's packs
 * a status and score into 0x4D). No public source names a RAM version with
 * the application note's layout: the board lists its own in
 * emmicro,calibration-firmware, and the calibration_firmware parameter
 * adds more.
 */

#include <linux/device.h>
#include <linux/minmax.h>
#include <linux/module.h>
#include <linux/property.h>

#include <kunit/visibility.h>

#include "em7180_core.h"

#define EM7180_CAL_FW_PROP	"emmicro,calibration-firmware"

static unsigned short calibration_firmware[8];
static unsigned int calibration_firmware_count;
module_param_array(calibration_firmware, ushort, &calibration_firmware_count,
		   0444);
MODULE_PARM_DESC(calibration_firmware,
		 "RAM versions reporting calibration as the application note does (up to 8)");

/**
 * em7180_fw_listed() - is a firmware in a table of RAM versions?
 * @ram: RAM version read from the chip
 * @table: RAM versions, as the property and the parameter give them
 * @len: entries in @table
 *
 * Return: true when @table holds @ram.
 */
bool em7180_fw_listed(u16 ram, const u32 *table, unsigned int len)
{
	while (len--)
		if (table[len] == ram)
			return true;

	return false;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_fw_listed);

/* The property's RAM versions, then the module parameter's */
int em7180_cal_fw_read(struct em7180_data *data)
{
	struct device *dev = data->dev;
	unsigned int i, n;
	u32 *table;
	int ret;

	ret = device_property_count_u32(dev, EM7180_CAL_FW_PROP);
	if (ret < 0 && ret != -EINVAL)	/* -EINVAL: no such property */
		return dev_err_probe(dev, ret, "invalid %s\n",
				     EM7180_CAL_FW_PROP);
	n = max(ret, 0);

	table = devm_kcalloc(dev, n + calibration_firmware_count,
			     sizeof(*table), GFP_KERNEL);
	if (!table)
		return -ENOMEM;

	if (n) {
		ret = device_property_read_u32_array(dev, EM7180_CAL_FW_PROP,
						     table, n);
		if (ret)
			return dev_err_probe(dev, ret, "cannot read %s\n",
					     EM7180_CAL_FW_PROP);
	}
	for (i = 0; i < calibration_firmware_count; i++)
		table[n + i] = calibration_firmware[i];

	data->cal_fw = table;
	data->cal_fw_len = n + calibration_firmware_count;
	return 0;
}

/*
 * Said once per change. The attributes are made at probe only: firmware
 * that comes with a power loss does not add them, and makes them read
 * ENODATA if it does not report the calibration.
 */
void em7180_cal_fw_check(struct em7180_data *data, bool probe)
{
	bool reported = em7180_fw_listed(data->ram_version, data->cal_fw,
					 data->cal_fw_len);

	if (!probe && reported == data->cal_reported)
		return;

	data->cal_reported = reported;
	if (probe) {
		data->cal_attrs = reported;
		if (!reported)
			dev_info(data->dev,
				 "firmware RAM 0x%04x is not known to report calibration status and score (0x43, 0x44, 0x4D-0x4E): those attributes are left out; add it to emmicro,calibration-firmware or em7180_core.calibration_firmware if it does\n",
				 data->ram_version);
	} else if (!reported) {
		dev_info(data->dev,
			 "firmware RAM 0x%04x is not known to report calibration status and score (0x43, 0x44, 0x4D-0x4E): those attributes read ENODATA while it runs\n",
			 data->ram_version);
	} else if (!data->cal_attrs) {
		dev_info(data->dev,
			 "firmware RAM 0x%04x reports calibration status and score: bind the driver again for those attributes\n",
			 data->ram_version);
	}
}
