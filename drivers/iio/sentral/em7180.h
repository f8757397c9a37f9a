/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * PNI SENtral / EM Microelectronic EM7180 sensor-fusion hub: what the bus
 * glue needs of the core
 */
#ifndef _EM7180_H_
#define _EM7180_H_

#include <linux/pm.h>
#include <linux/regmap.h>

struct device;
struct i2c_adapter; /* upstream: passthru */

extern const struct regmap_config em7180_regmap_config;
extern const struct dev_pm_ops em7180_pm_ops;

int em7180_core_probe(struct device *dev, struct regmap *regmap, int irq);
int em7180_passthru_probe(struct device *dev, struct i2c_adapter *parent); /* upstream: passthru */

#endif /* _EM7180_H_ */
