// SPDX-License-Identifier: GPL-2.0-only
/*
 * PNI SENtral / EM7180 sensor-fusion hub, I2C bus glue
 */

#include <linux/i2c.h>
#include <linux/mod_devicetable.h>
#include <linux/module.h>
#include <linux/pm.h>
#include <linux/regmap.h>

#include "em7180.h"
#include "em7180_compat.h"

static int em7180_i2c_probe(struct i2c_client *client)
{
	struct regmap *regmap;
	int ret;

	regmap = devm_regmap_init_i2c(client, &em7180_regmap_config);
	if (IS_ERR(regmap))
		return dev_err_probe(&client->dev, PTR_ERR(regmap),
				     "failed to initialize regmap\n");

	ret = em7180_core_probe(&client->dev, regmap, client->irq);
	/* upstream: passthru { */
	if (ret)
		return ret;

	/* The hub's sensor bus, reached in passthrough */
	return em7180_passthru_probe(&client->dev, client->adapter);
	/* upstream: } */
	/* upstream: !passthru: return ret; */
}

static const struct i2c_device_id em7180_i2c_id[] = {
	{ "em7180" },
	{ }
};
MODULE_DEVICE_TABLE(i2c, em7180_i2c_id);

static const struct of_device_id em7180_of_match[] = {
	{ .compatible = "emmicro,em7180" },
	{ }
};
MODULE_DEVICE_TABLE(of, em7180_of_match);

static struct i2c_driver em7180_i2c_driver = {
	.driver = {
		.name = "em7180",
		.of_match_table = em7180_of_match,
		.pm = pm_sleep_ptr(&em7180_pm_ops),
		/* Probe may wait seconds for the firmware upload */
		.probe_type = PROBE_PREFER_ASYNCHRONOUS,
	},
	.EM7180_I2C_PROBE_MEMBER = em7180_i2c_probe,
	.id_table = em7180_i2c_id,
};
module_i2c_driver(em7180_i2c_driver);

MODULE_AUTHOR("The sentral project");
MODULE_DESCRIPTION("PNI SENtral / EM7180 sensor-fusion hub I2C driver");
MODULE_LICENSE("GPL");
MODULE_IMPORT_NS("IIO_EM7180");
