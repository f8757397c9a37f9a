// SPDX-License-Identifier: GPL-2.0-only
/*
 * PNI SENtral / EM7180: the sensor bus behind the hub as an I2C adapter
 *
 * The hub reads its sensors, and at power-on its firmware EEPROM (an
 * M24512 at 0x50, identification page at 0x58), on a bus of its own. In
 * passthrough it connects that bus to the host's (EM's em718x_core.c and
 * em718x_registers.h; kriswiner/EM7180_SENtral_sensor_hub issue 62). A
 * one-channel gate of the i2c-mux core, as mpu3050 and inv_mpu6050 make
 * for their auxiliary buses, turns it into an adapter of its own: at24
 * reads and writes the EEPROM through nvmem, i2c-dev reaches the sensors.
 *
 * Each transfer on that adapter enters passthrough and leaves it as the
 * reference hosts do (gregtomasch/USFS, EM's em718x_core.c): the algorithm
 * in standby first, and after passthrough fusion running again and
 * EventStatus read, which lowers INT. Standby keeps the fusion state.
 *
 * The gate is mux-locked: select and deselect talk to the hub through the
 * parent adapter, and the i2c-mux core serialises the transfers on the
 * gate's adapter. While the hub is in passthrough (data->passthru, set in
 * select, cleared in deselect, which the core calls in the same task
 * whatever select returned) em7180_lock() waits: the stream, parameter
 * transfers and recovery never find the hub there, and a scan announced
 * before its end is not pushed (em7180_resumed()). No lock is held from
 * select to deselect: the interrupt thread only reads EventStatus
 * meanwhile, for a reset or an error, as the reference hosts read it
 * during passthrough.
 */

#include <linux/device.h>
#include <linux/errno.h>
#include <linux/i2c.h>
#include <linux/i2c-mux.h>
#include <linux/mutex.h>
#include <linux/regmap.h>
#include <linux/wait.h>

#include <kunit/visibility.h>

#include <linux/iio/iio.h>

#include "em7180.h"
#include "em7180_compat.h"
#include "em7180_core.h"

/* EM's em718x_core.c waits up to 1 s for each state */
#define EM7180_PASSTHRU_POLL_US		1000
#define EM7180_PASSTHRU_TIMEOUT_US	1000000

static int em7180_passthru_wait(struct em7180_data *data, unsigned int reg,
				unsigned int bit, bool set)
{
	unsigned int val;

	return regmap_read_poll_timeout(data->regmap, reg, val, !(val & bit) == !set,
					EM7180_PASSTHRU_POLL_US, EM7180_PASSTHRU_TIMEOUT_US);
}

/* Passthrough until em7180_passthru_deselect(), whatever this returns */
VISIBLE_IF_KUNIT int em7180_passthru_select(struct i2c_mux_core *muxc, u32 chan_id)
{
	struct em7180_data *data = i2c_mux_priv(muxc);
	int ret;

	guard(em7180)(data);
	WRITE_ONCE(data->passthru, true);

	ret = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, EM7180_ALGO_CTRL_STANDBY) ?:
	      regmap_write(data->regmap, EM7180_REG_PASSTHRU_CTRL, EM7180_PASSTHRU_ON) ?:
	      em7180_passthru_wait(data, EM7180_REG_PASSTHRU_STATUS, EM7180_PASSTHRU_ON, true);
	if (ret)
		dev_err_ratelimited(data->dev, "cannot enter passthrough: %d\n", ret);

	return ret;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_passthru_select);

/*
 * Leave passthrough and run fusion again, on every path. A hub that stays
 * in passthrough or standby is reset and recovered, as after a reset of
 * its own. Events that came before: a reset or an error is handled as the
 * interrupt thread does; data is not pushed.
 */
VISIBLE_IF_KUNIT int em7180_passthru_deselect(struct i2c_mux_core *muxc, u32 chan_id)
{
	struct em7180_data *data = i2c_mux_priv(muxc);
	unsigned int status;
	int ret;

	guard(mutex)(&data->lock);
	ret = regmap_write(data->regmap, EM7180_REG_PASSTHRU_CTRL, 0) ?:
	      em7180_passthru_wait(data, EM7180_REG_PASSTHRU_STATUS, EM7180_PASSTHRU_ON, false);
	if (!ret)
		ret = regmap_write(data->regmap, EM7180_REG_ALGO_CTRL, 0) ?:
		      em7180_passthru_wait(data, EM7180_REG_ALGO_STATUS,
					   EM7180_ALGO_STATUS_HALTED, false);
	if (!ret)
		ret = regmap_read(data->regmap, EM7180_REG_EVENT_STATUS, &status);

	if (ret) {
		dev_err_ratelimited(data->dev,
				    "cannot leave passthrough (%d): resetting the chip\n", ret);
		if (!regmap_write(data->regmap, EM7180_REG_RESET_REQ, EM7180_RESET_REQ_RESET))
			em7180_recover_schedule(data);
	} else {
		if (status & EM7180_EVENT_ERROR)
			em7180_report_error(data);
		if (status & EM7180_EVENT_CPU_RESET)
			em7180_recover_schedule(data);
	}

	em7180_resumed(data);
	WRITE_ONCE(data->passthru, false);
	wake_up_all(&data->wq);
	return ret;
}
EXPORT_SYMBOL_IF_KUNIT(em7180_passthru_deselect);

static void em7180_passthru_remove(void *muxc)
{
	i2c_mux_del_adapters(muxc);
}

/**
 * em7180_passthru_probe() - add the sensor bus behind the hub as an adapter
 * @dev: the hub's I2C client device, probed by em7180_core_probe()
 * @parent: the adapter the hub is on
 *
 * The adapter takes the devicetree node "i2c-gate" under the hub's node,
 * with the devices on the sensor bus, when there is one; else clients are
 * made through its new_device file. It is removed on unbind, before the
 * rest of the driver. An adapter that cannot be added is only warned
 * of: the hub's own channels do not need it.
 *
 * Return: 0, or -ENOMEM or the error of registering the removal.
 */
int em7180_passthru_probe(struct device *dev, struct i2c_adapter *parent)
{
	struct em7180_data *data = iio_priv(dev_get_drvdata(dev));
	struct i2c_mux_core *muxc;
	int ret;

	muxc = i2c_mux_alloc(parent, dev, 1, 0, I2C_MUX_LOCKED | I2C_MUX_GATE,
			     em7180_passthru_select, em7180_passthru_deselect);
	if (!muxc)
		return -ENOMEM;
	muxc->priv = data;

	/* The hub works without it, as mpu3050 does without its gate */
	ret = em7180_i2c_mux_add_adapter(muxc, 0, 0);
	if (ret) {
		dev_warn(dev, "no adapter for the sensor bus: %d\n", ret);
		return 0;
	}

	return devm_add_action_or_reset(dev, em7180_passthru_remove, muxc);
}
EXPORT_SYMBOL_NS_GPL(em7180_passthru_probe, "IIO_EM7180");
