// SPDX-License-Identifier: GPL-2.0
/*
 * sentral_sim: a simulated PNI SENtral / EM Microelectronic EM7180 on a
 * virtual I2C adapter, for testing the em7180 IIO driver and its tools
 * without hardware.
 *
 * The adapter "sentral-sim" answers at 0x28 only (EM7180 register reference
 * §1). One "em7180" client with a data-ready interrupt from an irq_sim
 * domain is created at load unless create=0. Knobs and statistics live in
 * debugfs under sentral-sim/; see tests/sim/README.md.
 */
#include <linux/debugfs.h>
#include <linux/i2c.h>
#include <linux/interrupt.h>
#include <linux/irq.h>
#include <linux/irq_sim.h>
#include <linux/irq_work.h>
#include <linux/irqdomain.h>
#include <linux/module.h>
#include <linux/slab.h>

#include "sentral_sim.h"

static bool create = true;
module_param(create, bool, 0444);
MODULE_PARM_DESC(create, "create the em7180 client at 0x28 on load (default 1)");

static struct sentral_sim *sim_chip;

/* One bit time at 400 kHz, in ns */
#define SIM_BIT_NS	2500

/* Bits of one message: start (or repeated start), address and data bytes
 * at 9 bits each (8 + ACK)
 */
static u64 sim_msg_bits(u16 len)
{
	return 1 + 9 * ((u64)len + 1);
}

void sim_fire_irq(struct sentral_sim *sim)
{
	unsigned long flags;

	/*
	 * irq_sim raises the line only if a handler has it unmasked, and
	 * delivers it from an irq_work. UML has no irq_work interrupt: queued
	 * work waits for the next tick (HZ=100), which would cap the data-ready
	 * rate at 100/s. Run it now, as irq_work_run() requires, with local
	 * interrupts off; on other architectures this only runs it earlier.
	 */
	local_irq_save(flags);
	irq_set_irqchip_state(sim->virq, IRQCHIP_STATE_PENDING, true);
	irq_work_run();
	local_irq_restore(flags);
}

static void sim_msg_read(struct sentral_sim *sim, struct i2c_msg *msg,
			 ktime_t now)
{
	u16 i;

	for (i = 0; i < msg->len; i++)
		msg->buf[i] = sim_reg_read(sim, sim->pointer++, now, false);
}

/* The first byte of a write sets the register pointer; the rest is data */
static void sim_msg_write(struct sentral_sim *sim, struct i2c_msg *msg,
			  ktime_t now)
{
	u16 i;

	if (!msg->len)
		return;
	sim->pointer = msg->buf[0];
	for (i = 1; i < msg->len; i++)
		sim_reg_write(sim, sim->pointer++, msg->buf[i], now);
}

static int sim_xfer(struct i2c_adapter *adap, struct i2c_msg *msgs, int num)
{
	struct sentral_sim *sim = i2c_get_adapdata(adap);
	unsigned long flags;
	u64 bits = 1;		/* the stop condition */
	ktime_t now;
	bool fire;
	int i;

	for (i = 0; i < num; i++) {
		if (msgs[i].addr != SIM_I2C_ADDR ||
		    (msgs[i].flags & I2C_M_TEN))
			return -ENXIO;
		if (msgs[i].flags & I2C_M_RECV_LEN)
			return -EOPNOTSUPP;
	}

	spin_lock_irqsave(&sim->lock, flags);
	now = ktime_get();
	sim_advance(sim, now);

	if (!sim->stats.transactions)
		sim->stats.first = now;
	sim->stats.transactions++;

	if (sim->nack_at && ++sim->nack_count == sim->nack_at) {
		/* the address byte is not acknowledged: nothing happens */
		sim->nack_at = 0;
		sim->stats.nacks++;
		sim->stats.bus_ns += (sim_msg_bits(0) + bits) * SIM_BIT_NS;
		sim->stats.last = ktime_get();
		spin_unlock_irqrestore(&sim->lock, flags);
		return -ENXIO;
	}

	for (i = 0; i < num; i++) {
		/* a request may become served between two messages */
		now = ktime_get();
		sim_advance(sim, now);
		if (msgs[i].flags & I2C_M_RD)
			sim_msg_read(sim, &msgs[i], now);
		else
			sim_msg_write(sim, &msgs[i], now);
		sim->stats.bytes += msgs[i].len;
		bits += sim_msg_bits(msgs[i].len);
	}
	sim->stats.bus_ns += bits * SIM_BIT_NS;

	sim_schedule(sim, now);
	fire = sim_int_update(sim);
	sim->stats.last = ktime_get();
	spin_unlock_irqrestore(&sim->lock, flags);

	if (fire)
		sim_fire_irq(sim);
	return num;
}

static u32 sim_functionality(struct i2c_adapter *adap)
{
	return I2C_FUNC_I2C | I2C_FUNC_SMBUS_EMUL;
}

static const struct i2c_algorithm sim_algo = {
	.master_xfer = sim_xfer,
	.functionality = sim_functionality,
};

static int sim_irq_init(struct sentral_sim *sim)
{
	int ret;

	sim->fwnode = irq_domain_alloc_named_fwnode("sentral-sim");
	if (!sim->fwnode)
		return -ENOMEM;

	sim->domain = irq_domain_create_sim(sim->fwnode, 1);
	if (IS_ERR(sim->domain)) {
		ret = PTR_ERR(sim->domain);
		goto err_fwnode;
	}

	sim->virq = irq_create_mapping(sim->domain, 0);
	if (!sim->virq) {
		ret = -ENXIO;
		goto err_domain;
	}
	/* the INT pin is active high; hosts trigger on the rising edge (§3) */
	ret = irq_set_irq_type(sim->virq, IRQ_TYPE_EDGE_RISING);
	if (ret)
		goto err_mapping;
	return 0;

err_mapping:
	irq_dispose_mapping(sim->virq);
err_domain:
	irq_domain_remove_sim(sim->domain);
err_fwnode:
	irq_domain_free_fwnode(sim->fwnode);
	return ret;
}

static void sim_irq_exit(struct sentral_sim *sim)
{
	irq_dispose_mapping(sim->virq);
	irq_domain_remove_sim(sim->domain);
	irq_domain_free_fwnode(sim->fwnode);
}

static void sim_stop(struct sentral_sim *sim)
{
	unsigned long flags;

	spin_lock_irqsave(&sim->lock, flags);
	sim->dead = true;
	spin_unlock_irqrestore(&sim->lock, flags);
	hrtimer_cancel(&sim->timer);
}

static int __init sim_init(void)
{
	struct i2c_board_info info = {
		I2C_BOARD_INFO("em7180", SIM_I2C_ADDR),
	};
	struct sentral_sim *sim;
	int ret;

	sim = kzalloc(sizeof(*sim), GFP_KERNEL);
	if (!sim)
		return -ENOMEM;
	sim_model_init(sim);

	ret = sim_irq_init(sim);
	if (ret)
		goto err_free;

	sim->adap.owner = THIS_MODULE;
	sim->adap.algo = &sim_algo;
	strscpy(sim->adap.name, "sentral-sim", sizeof(sim->adap.name));
	i2c_set_adapdata(&sim->adap, sim);
	ret = i2c_add_adapter(&sim->adap);
	if (ret)
		goto err_irq;

	sim->debugfs = debugfs_create_dir("sentral-sim", NULL);
	sim_debugfs_init(sim);

	if (create) {
		info.irq = sim->virq;
		sim->client = i2c_new_client_device(&sim->adap, &info);
		if (IS_ERR(sim->client)) {
			ret = PTR_ERR(sim->client);
			goto err_adapter;
		}
	}

	sim_chip = sim;
	return 0;

err_adapter:
	debugfs_remove_recursive(sim->debugfs);
	i2c_del_adapter(&sim->adap);
	sim_stop(sim);
err_irq:
	sim_irq_exit(sim);
err_free:
	kfree(sim);
	return ret;
}
module_init(sim_init);

static void __exit sim_exit(void)
{
	struct sentral_sim *sim = sim_chip;

	debugfs_remove_recursive(sim->debugfs);
	i2c_unregister_device(sim->client);
	/* also removes clients added through new_device */
	i2c_del_adapter(&sim->adap);
	sim_stop(sim);
	sim_irq_exit(sim);
	kfree(sim);
}
module_exit(sim_exit);

MODULE_DESCRIPTION("Simulated PNI SENtral / EM7180 sensor hub on a virtual I2C adapter");
MODULE_LICENSE("GPL");
