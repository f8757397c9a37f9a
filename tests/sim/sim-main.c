// SPDX-License-Identifier: GPL-2.0
/*
 * sentral_sim: a simulated PNI SENtral / EM Microelectronic EM7180 on a
 * virtual I2C adapter, for testing the em7180 IIO driver and its tools
 * without hardware.
 *
 * The adapter "sentral-sim" answers at 0x28 only (EM7180 register reference
 * §1). One "em7180" client with a data-ready interrupt from an interrupt
 * domain of the simulator's own is created at load unless create=0. Knobs
 * and statistics live in debugfs under sentral-sim/; see tests/sim/README.md.
 *
 * For tests of several chips, adapters=N adds adapters "sentral-sim-1"...
 * with a chip each, and mux_channels=N one more adapter "sentral-sim-mux"
 * with a simulated I2C mux at 0x70 and a chip at 0x28 behind each channel.
 * Every adapter has a platform device of its own as parent, as a real
 * controller has.
 */
#include <linux/i2c.h>
#include <linux/i2c-mux.h>
#include <linux/interrupt.h>
#include <linux/irq.h>
#include <linux/irqdomain.h>
#include <linux/module.h>
#include <linux/platform_device.h>
#include <linux/property.h>
#include <linux/sched.h>
#include <linux/slab.h>

#include "sentral_sim.h"
#include "sim_compat.h"

#define SIM_MAX_ADAPTERS	4
#define SIM_MAX_CHANNELS	4
#define SIM_MUX_ADDR		0x70

static bool create = true;
module_param(create, bool, 0444);
MODULE_PARM_DESC(create, "create the em7180 clients at 0x28 on load (default 1)");

static unsigned int adapters = 1;
module_param(adapters, uint, 0444);
MODULE_PARM_DESC(adapters, "adapters with a chip each (1-4, default 1)");

static unsigned int mux_channels;
module_param(mux_channels, uint, 0444);
MODULE_PARM_DESC(mux_channels, "channels of a mux at 0x70 on one more adapter, a chip behind each (0-4, default 0)");

static char *knobs;
module_param(knobs, charp, 0444);
MODULE_PARM_DESC(knobs, "debugfs knobs set on every chip before its client is created: name=value[,name=value...]");

static char *firmware_name;
module_param(firmware_name, charp, 0444);
MODULE_PARM_DESC(firmware_name, "a firmware-name property for the em7180 clients, as a board's devicetree would give");

/*
 * One adapter: a chip at 0x28, or a mux at 0x70 whose selected channel
 * (sel, under the adapter's bus lock) leads to chip[sel].
 */
struct sim_bus {
	struct platform_device *pdev;
	struct i2c_adapter adap;
	struct sentral_sim *chip[SIM_MAX_CHANNELS];
	unsigned int nchips;
	struct i2c_client *client;	/* the em7180, or the mux */
	bool mux;
	int sel;			/* -1: no channel connected */
};

static struct sim_bus *sim_buses[SIM_MAX_ADAPTERS + 1];

/* One bit time at 400 kHz, in ns: the accounting without bus_khz */
#define SIM_BIT_NS	2500

/* Bits of one message: start (or repeated start), address and data bytes
 * at 9 bits each (8 + ACK)
 */
static u64 sim_msg_bits(u16 len)
{
	return 1 + 9 * ((u64)len + 1);
}

/*
 * The INT pin's interrupt: a one-line domain with a chip of the simulator's
 * own (irq_sim is not built into stock distribution kernels). A rising edge
 * is delivered at once, synchronously, in the context that raised it (the
 * data timer or a bus transaction). An edge while the line is masked (no
 * handler, or the core masked it) is not lost: a line still high when it is
 * unmasked fires then, as a latched edge or a level input would.
 */
void sim_fire_irq(struct sentral_sim *sim)
{
	if (!READ_ONCE(sim->irq_masked))
		generic_handle_irq_safe(sim->virq);
}

/* Deferred delivery: the chip callbacks run under the descriptor's lock */
static void sim_irq_work_fn(struct irq_work *work)
{
	struct sentral_sim *sim = container_of(work, struct sentral_sim,
					       irq_work);

	generic_handle_irq_safe(sim->virq);
}

static void sim_irq_mask(struct irq_data *d)
{
	struct sentral_sim *sim = irq_data_get_irq_chip_data(d);

	WRITE_ONCE(sim->irq_masked, true);
}

static void sim_irq_unmask(struct irq_data *d)
{
	struct sentral_sim *sim = irq_data_get_irq_chip_data(d);

	WRITE_ONCE(sim->irq_masked, false);
	if (READ_ONCE(sim->int_high))
		irq_work_queue(&sim->irq_work);
}

/* The core resends an edge that arrived while the line was disabled */
static int sim_irq_retrigger(struct irq_data *d)
{
	struct sentral_sim *sim = irq_data_get_irq_chip_data(d);

	irq_work_queue(&sim->irq_work);
	return 1;
}

/* The INT pin is active high; hosts trigger on the rising edge (§3) */
static int sim_irq_set_type(struct irq_data *d, unsigned int type)
{
	return type == IRQ_TYPE_EDGE_RISING ? 0 : -EINVAL;
}

static struct irq_chip sim_irq_chip = {
	.name = "sentral-sim",
	.irq_mask = sim_irq_mask,
	.irq_unmask = sim_irq_unmask,
	.irq_retrigger = sim_irq_retrigger,
	.irq_set_type = sim_irq_set_type,
	.flags = IRQCHIP_SKIP_SET_WAKE,
};

static int sim_irq_map(struct irq_domain *domain, unsigned int virq,
		       irq_hw_number_t hwirq)
{
	irq_set_chip_data(virq, domain->host_data);
	irq_set_chip_and_handler(virq, &sim_irq_chip, handle_simple_irq);
	irq_modify_status(virq, IRQ_NOREQUEST | IRQ_NOAUTOEN, IRQ_NOPROBE);
	return 0;
}

static void sim_irq_unmap(struct irq_domain *domain, unsigned int virq)
{
	irq_set_chip_and_handler(virq, NULL, NULL);
	irq_set_chip_data(virq, NULL);
}

static const struct irq_domain_ops sim_irq_domain_ops = {
	.map = sim_irq_map,
	.unmap = sim_irq_unmap,
};

/*
 * The register pointer increments after each byte. No reference host
 * crosses 0x63->0x64 or 0x3a->0x3b in one transfer (register reference
 * §2), so whether the silicon does is unknown: with autoinc_stop the
 * pointer stays on 0x3a or 0x63, and further bytes of the message read
 * or write that register again.
 */
static void sim_pointer_next(struct sentral_sim *sim)
{
	if (sim->autoinc_stop && (sim->pointer == SIM_REG_PARAM_ACK ||
				  sim->pointer == SIM_REG_LOAD_PARAM3))
		return;
	sim->pointer++;
}

static void sim_msg_read(struct sentral_sim *sim, struct i2c_msg *msg,
			 ktime_t now)
{
	u16 i;

	for (i = 0; i < msg->len; i++) {
		msg->buf[i] = sim_reg_read(sim, sim->pointer, now, false);
		sim_pointer_next(sim);
	}
}

/* The first byte of a write sets the register pointer; the rest is data */
static void sim_msg_write(struct sentral_sim *sim, struct i2c_msg *msg,
			  ktime_t now)
{
	u16 i;

	if (!msg->len)
		return;
	sim->pointer = msg->buf[0];
	for (i = 1; i < msg->len; i++) {
		sim_reg_write(sim, sim->pointer, msg->buf[i], now);
		/* UploadData takes a stream of bytes (reference §3 item 3) */
		if (sim->pointer != SIM_REG_UPLOAD_DATA)
			sim_pointer_next(sim);
	}
}

/*
 * With bus_khz the transfer lasts as long as its bits take on the wire
 * (start, address and data bytes with their acknowledge bits, stop), as
 * a real controller's does: a Raspberry Pi's bus runs at 100 kHz unless
 * told otherwise. Sleeps until @end; the bus is the caller's meanwhile.
 */
static void sim_wire_wait(ktime_t end)
{
	/* a transfer in atomic context (shutdown) cannot sleep */
	if (!in_task() || irqs_disabled())
		return;
	while (ktime_before(ktime_get(), end)) {
		set_current_state(TASK_UNINTERRUPTIBLE);
		schedule_hrtimeout_range(&end, 0, HRTIMER_MODE_ABS);
	}
}

/*
 * The caller is back from transaction @xfer, which had waited for its wire
 * time until @end if @waited: when, for the causes of drops, and how late
 * the wait woke (the machine's timers and scheduling, not the host driver)
 */
static void sim_returned(struct sentral_sim *sim, u64 xfer, ktime_t end,
			 bool waited)
{
	struct sim_stats *st = &sim->stats;
	unsigned long flags;
	ktime_t now;
	s64 late;

	spin_lock_irqsave(&sim->lock, flags);
	now = ktime_get();
	sim_xfer_return(sim, xfer, now);
	late = ktime_to_ns(ktime_sub(now, end));
	if (waited) {
		st->wire_waits++;
		st->wire_late_100us += late >= 100 * NSEC_PER_USEC;
		st->wire_late_1ms += late >= NSEC_PER_MSEC;
		st->wire_late_max_ns = max(st->wire_late_max_ns, late);
	}
	spin_unlock_irqrestore(&sim->lock, flags);
}

/* nack_at fires at the Nth transaction, and nack_run - 1 more after it */
static bool sim_nack_armed(struct sentral_sim *sim)
{
	if (sim->nack_left) {
		sim->nack_left--;
		return true;
	}
	if (!sim->nack_at || ++sim->nack_count != sim->nack_at)
		return false;
	sim->nack_at = 0;
	sim->nack_left = max(sim->nack_run, 1U) - 1;
	return true;
}

static int sim_xfer(struct i2c_adapter *adap, struct i2c_msg *msgs, int num)
{
	struct sim_bus *bus = i2c_get_adapdata(adap);
	struct sentral_sim *sim;
	unsigned long flags;
	u64 bits = 1;		/* the stop condition */
	u64 bit_ns, wire_ns;
	u32 khz;
	ktime_t start = ktime_get(), now, end;
	u64 xfer;
	bool fire;
	int i;

	/* Behind a mux, only the connected channel's chip answers. */
	if (bus->mux && bus->sel < 0)
		return -ENXIO;
	sim = bus->chip[bus->mux ? bus->sel : 0];
	/*
	 * Any other address: the hub's sensor bus, through passthrough, as
	 * long on the wire as the hub's transactions (the whole transfer's
	 * bits, a NACK included)
	 */
	if (num && msgs[0].addr != SIM_I2C_ADDR) {
		int ret = sim_usfs_xfer(sim, msgs, num);

		khz = READ_ONCE(sim->bus_khz);
		if (!khz)
			return ret;
		for (i = 0; i < num; i++)
			bits += sim_msg_bits(msgs[i].len);
		sim_wire_wait(ktime_add_ns(start, bits *
					   DIV_ROUND_CLOSEST(NSEC_PER_MSEC, khz)));
		return ret;
	}
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
	sim_xfer_begin(sim, now);
	xfer = sim->xfers;
	khz = sim->bus_khz;
	bit_ns = khz ? DIV_ROUND_CLOSEST(NSEC_PER_MSEC, khz) : SIM_BIT_NS;

	if (!sim->stats.transactions)
		sim->stats.first = start;
	sim->stats.transactions++;

	if (sim_nacks(sim, now) || sim_nack_armed(sim)) {
		/* the address byte is not acknowledged: nothing happens */
		sim->stats.nacks++;
		wire_ns = (sim_msg_bits(0) + bits) * bit_ns;
		sim->stats.bus_ns += wire_ns;
		end = ktime_add_ns(start, khz ? wire_ns : 0);
		sim->stats.last = ktime_after(end, ktime_get()) ? end : ktime_get();
		sim_xfer_end(sim, sim->stats.last);
		spin_unlock_irqrestore(&sim->lock, flags);
		if (khz)
			sim_wire_wait(end);
		sim_returned(sim, xfer, end, khz);
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
	wire_ns = bits * bit_ns;
	sim->stats.bus_ns += wire_ns;

	sim_schedule(sim, now);
	fire = sim_int_update(sim);
	/* the transaction ends when its stop is on the wire */
	end = ktime_add_ns(start, khz ? wire_ns : 0);
	sim->stats.last = ktime_after(end, ktime_get()) ? end : ktime_get();
	sim_xfer_end(sim, sim->stats.last);
	spin_unlock_irqrestore(&sim->lock, flags);

	if (khz)
		sim_wire_wait(end);
	sim_returned(sim, xfer, end, khz);
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

	/* until a handler is requested, the line is masked */
	sim->irq_masked = true;
	init_irq_work(&sim->irq_work, sim_irq_work_fn);

	sim->fwnode = irq_domain_alloc_named_fwnode("sentral-sim");
	if (!sim->fwnode)
		return -ENOMEM;

	sim->domain = irq_domain_create_linear(sim->fwnode, 1,
					       &sim_irq_domain_ops, sim);
	if (!sim->domain) {
		ret = -ENOMEM;
		goto err_fwnode;
	}

	sim->virq = irq_create_mapping(sim->domain, 0);
	if (!sim->virq) {
		ret = -ENXIO;
		goto err_domain;
	}
	ret = irq_set_irq_type(sim->virq, IRQ_TYPE_EDGE_RISING);
	if (ret)
		goto err_mapping;
	return 0;

err_mapping:
	irq_dispose_mapping(sim->virq);
err_domain:
	irq_domain_remove(sim->domain);
err_fwnode:
	irq_domain_free_fwnode(sim->fwnode);
	return ret;
}

static void sim_irq_exit(struct sentral_sim *sim)
{
	irq_work_sync(&sim->irq_work);
	irq_dispose_mapping(sim->virq);
	irq_domain_remove(sim->domain);
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

static struct sentral_sim *sim_chip_new(const char *dir)
{
	struct sentral_sim *sim;
	int ret;

	sim = kzalloc_obj(*sim, GFP_KERNEL);
	if (!sim)
		return ERR_PTR(-ENOMEM);
	ret = sim_usfs_alloc(sim);
	if (ret) {
		kfree(sim);
		return ERR_PTR(ret);
	}
	sim_model_init(sim);
	ret = sim_irq_init(sim);
	if (ret) {
		sim_usfs_free(sim);
		kfree(sim);
		return ERR_PTR(ret);
	}
	ret = sim_debugfs_init(sim, dir);
	if (!ret) {
		ret = sim_knobs_apply(sim, knobs);
		if (ret)
			sim_debugfs_exit(sim);
	}
	if (ret) {
		sim_stop(sim);
		sim_irq_exit(sim);
		sim_usfs_free(sim);
		kfree(sim);
		return ERR_PTR(ret);
	}
	return sim;
}

static void sim_chip_free(struct sentral_sim *sim)
{
	sim_debugfs_exit(sim);
	sim_stop(sim);
	sim_irq_exit(sim);
	sim_usfs_free(sim);
	kfree(sim);
}

/*
 * The client's properties, as a board's devicetree gives them: the image
 * to upload, if the parameter names one. The node is shared, counted by
 * the driver core.
 */
static struct property_entry sim_em7180_props[] = {
	{ },	/* firmware-name, if the parameter gives one */
	{ }
};

static const struct software_node sim_em7180_swnode = {
	.properties = sim_em7180_props,
};

static struct i2c_client *sim_em7180_new(struct i2c_adapter *adap,
					 struct sentral_sim *sim)
{
	struct i2c_board_info info = {
		I2C_BOARD_INFO("em7180", SIM_I2C_ADDR),
		.irq = sim->virq,
		.swnode = &sim_em7180_swnode,
	};

	return i2c_new_client_device(adap, &info);
}

/* The mux: channel chan connects chip[chan]; idle, none is connected. */
static int sim_mux_select(struct i2c_mux_core *muxc, u32 chan)
{
	struct sim_bus *bus = i2c_mux_priv(muxc);

	bus->sel = chan;
	return 0;
}

static int sim_mux_deselect(struct i2c_mux_core *muxc, u32 chan)
{
	struct sim_bus *bus = i2c_mux_priv(muxc);

	bus->sel = -1;
	return 0;
}

static void sim_mux_del(void *muxc)
{
	i2c_mux_del_adapters(muxc);
}

static int sim_mux_probe(struct i2c_client *client)
{
	struct sim_bus *bus = i2c_get_adapdata(client->adapter);
	struct i2c_mux_core *muxc;
	unsigned int i;
	int ret;

	muxc = i2c_mux_alloc(client->adapter, &client->dev, bus->nchips, 0, 0,
			     sim_mux_select, sim_mux_deselect);
	if (!muxc)
		return -ENOMEM;
	muxc->priv = bus;
	ret = devm_add_action(&client->dev, sim_mux_del, muxc);
	if (ret)
		return ret;
	for (i = 0; i < bus->nchips; i++) {
		ret = sim_mux_add_adapter(muxc, i);
		if (ret)
			return ret;
		/* Removed with its channel's adapter. */
		if (create &&
		    IS_ERR(sim_em7180_new(muxc->adapter[i], bus->chip[i])))
			return -ENODEV;
	}
	return 0;
}

static const struct i2c_device_id sim_mux_id[] = {
	{ "sentral-sim-mux" },
	{ }
};

static struct i2c_driver sim_mux_driver = {
	.driver = { .name = "sentral-sim-mux" },
	.SIM_I2C_PROBE = sim_mux_probe,
	.id_table = sim_mux_id,
};

static void sim_bus_free(struct sim_bus *bus)
{
	unsigned int i;

	i2c_unregister_device(bus->client);
	/* also removes clients added through new_device */
	i2c_del_adapter(&bus->adap);
	platform_device_unregister(bus->pdev);
	for (i = 0; i < bus->nchips; i++)
		sim_chip_free(bus->chip[i]);
	kfree(bus);
}

/*
 * Adapter n (0: "sentral-sim", as with one chip), or with mux the mux
 * adapter. Debugfs: sentral-sim, sentral-sim-N, sentral-sim-mux-CHANNEL.
 */
static struct sim_bus *sim_bus_new(unsigned int n, bool mux)
{
	struct i2c_board_info mux_info = {
		I2C_BOARD_INFO("sentral-sim-mux", SIM_MUX_ADDR),
	};
	char name[32];
	struct sim_bus *bus;
	unsigned int i;
	int ret;

	bus = kzalloc_obj(*bus, GFP_KERNEL);
	if (!bus)
		return ERR_PTR(-ENOMEM);
	bus->mux = mux;
	bus->sel = -1;
	bus->nchips = mux ? mux_channels : 1;
	for (i = 0; i < bus->nchips; i++) {
		if (mux)
			snprintf(name, sizeof(name), "sentral-sim-mux-%u", i);
		else if (n)
			snprintf(name, sizeof(name), "sentral-sim-%u", n);
		else
			strscpy(name, "sentral-sim", sizeof(name));
		bus->chip[i] = sim_chip_new(name);
		if (IS_ERR(bus->chip[i])) {
			ret = PTR_ERR(bus->chip[i]);
			bus->nchips = i;
			goto err;
		}
	}

	if (mux)
		strscpy(name, "sentral-sim-mux", sizeof(name));
	else if (n)
		snprintf(name, sizeof(name), "sentral-sim-%u", n);
	else
		strscpy(name, "sentral-sim", sizeof(name));
	bus->pdev = platform_device_register_simple(name, PLATFORM_DEVID_NONE,
						    NULL, 0);
	if (IS_ERR(bus->pdev)) {
		ret = PTR_ERR(bus->pdev);
		bus->pdev = NULL;
		goto err;
	}
	bus->adap.owner = THIS_MODULE;
	bus->adap.algo = &sim_algo;
	bus->adap.dev.parent = &bus->pdev->dev;
	strscpy(bus->adap.name, name, sizeof(bus->adap.name));
	i2c_set_adapdata(&bus->adap, bus);
	ret = i2c_add_adapter(&bus->adap);
	if (ret)
		goto err_pdev;

	if (mux)
		bus->client = i2c_new_client_device(&bus->adap, &mux_info);
	else if (create)
		bus->client = sim_em7180_new(&bus->adap, bus->chip[0]);
	if (IS_ERR(bus->client)) {
		ret = PTR_ERR(bus->client);
		bus->client = NULL;
		i2c_del_adapter(&bus->adap);
		goto err_pdev;
	}
	return bus;

err_pdev:
	platform_device_unregister(bus->pdev);
err:
	for (i = 0; i < bus->nchips; i++)
		sim_chip_free(bus->chip[i]);
	kfree(bus);
	return ERR_PTR(ret);
}

static void sim_buses_free(void)
{
	int i;

	for (i = ARRAY_SIZE(sim_buses) - 1; i >= 0; i--) {
		if (sim_buses[i])
			sim_bus_free(sim_buses[i]);
		sim_buses[i] = NULL;
	}
}

static int __init sim_init(void)
{
	unsigned int i;
	int ret;

	if (adapters < 1 || adapters > SIM_MAX_ADAPTERS ||
	    mux_channels > SIM_MAX_CHANNELS)
		return -EINVAL;
	if (firmware_name)
		sim_em7180_props[0] = PROPERTY_ENTRY_STRING("firmware-name",
							    firmware_name);
	ret = i2c_add_driver(&sim_mux_driver);
	if (ret)
		return ret;
	for (i = 0; i < adapters + !!mux_channels; i++) {
		sim_buses[i] = sim_bus_new(i, i == adapters);
		if (IS_ERR(sim_buses[i])) {
			ret = PTR_ERR(sim_buses[i]);
			sim_buses[i] = NULL;
			sim_buses_free();
			i2c_del_driver(&sim_mux_driver);
			return ret;
		}
	}
	return 0;
}
module_init(sim_init);

static void __exit sim_exit(void)
{
	sim_buses_free();
	i2c_del_driver(&sim_mux_driver);
}
module_exit(sim_exit);

MODULE_DESCRIPTION("Simulated PNI SENtral / EM7180 sensor hub on a virtual I2C adapter");
MODULE_LICENSE("GPL");
