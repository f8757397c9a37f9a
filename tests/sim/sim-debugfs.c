// SPDX-License-Identifier: GPL-2.0
/*
 * debugfs knobs of a simulated EM7180, in its directory (sentral-sim/ for
 * the first chip). Every file is described in tests/sim/README.md.
 */
#include <linux/bitmap.h>
#include <linux/debugfs.h>
#include <linux/fs.h>
#include <linux/kernel.h>
#include <linux/math64.h>
#include <linux/seq_file.h>
#include <linux/slab.h>
#include <linux/string.h>
#include <linux/uaccess.h>

#include "sentral_sim.h"

#define SIM_MAX_MS		3600000		/* one hour */
#define SIM_MAX_LATENCY_US	10000000	/* ten seconds */
#define SIM_MAX_UPLOAD_MS	10000
/* I2C clocks, 10 kHz up to high-speed mode's 3.4 MHz */
#define SIM_MIN_BUS_KHZ		10
#define SIM_MAX_BUS_KHZ		3400

struct sim_knob {
	const char *name;
	umode_t mode;
	/* both called with sim->lock held, after sim_advance() */
	void (*show)(struct seq_file *m, struct sentral_sim *sim, ktime_t now);
	int (*store)(struct sentral_sim *sim, char *buf, ktime_t now);
};

/* What a debugfs file carries: one knob of one chip */
struct sim_knob_file {
	struct sentral_sim *sim;
	const struct sim_knob *knob;
};

static const char * const sim_stream_names[SIM_NSTREAMS] = {
	[SIM_QUAT] = "quaternion",
	[SIM_MAG] = "mag",
	[SIM_ACCEL] = "accel",
	[SIM_GYRO] = "gyro",
};

/* enum sim_drop_cause: each a count next to _drops_seen in samples */
static const char * const sim_drop_causes[SIM_DROP_NCAUSES] = {
	[SIM_DROP_PENDING] = "pending",
	[SIM_DROP_HELD] = "held",
	[SIM_DROP_IDLE] = "idle",
	[SIM_DROP_LATE_IRQ] = "late_irq",
	[SIM_DROP_LATE_WAKE] = "late_wake",
	[SIM_DROP_SLOW] = "slow",
	[SIM_DROP_UNREAD] = "unread",
};

static const char * const sim_xfer_kinds[] = {
	[SIM_XFER_NONE] = "none",
	[SIM_XFER_BURST] = "burst",
	[SIM_XFER_STATUS] = "status",
	[SIM_XFER_OTHER] = "other",
};

static int sim_parse_u32(const char *buf, u32 max, u32 *val)
{
	u32 v;
	int ret;

	ret = kstrtou32(buf, 0, &v);
	if (ret)
		return ret;
	if (v > max)
		return -ERANGE;
	*val = v;
	return 0;
}

/* A duration that something is divided by: 1 ms up to SIM_MAX_MS */
static int sim_parse_period_ms(const char *buf, u32 *val)
{
	u32 v;
	int ret = sim_parse_u32(buf, SIM_MAX_MS, &v);

	if (ret)
		return ret;
	if (!v)
		return -EINVAL;
	*val = v;
	return 0;
}

static void motion_show(struct seq_file *m, struct sentral_sim *sim,
			ktime_t now)
{
	seq_printf(m, "%d\n", sim->world.pattern != SIM_PAT_STILL);
}

/* The shortcut: 1 starts the sphere pattern, 0 puts the device down level */
static int motion_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	static const s64 level[4] = { 1, 0, 0, 0 };
	bool v;
	int ret = kstrtobool(buf, &v);

	if (ret)
		return ret;
	if (!v)
		sim_motion_set_orientation(&sim->world, level, now);
	else if (sim->world.pattern == SIM_PAT_STILL)
		ret = sim_motion_set_pattern(&sim->world, SIM_PAT_SPHERE, now);
	return ret;
}

static void pattern_show(struct seq_file *m, struct sentral_sim *sim,
			 ktime_t now)
{
	seq_printf(m, "%s\n", sim_pattern_name(sim->world.pattern));
}

static int pattern_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	int p;

	for (p = 0; p < SIM_NPATTERNS; p++)
		if (!strcmp(buf, sim_pattern_name(p)))
			return sim_motion_set_pattern(&sim->world, p, now);
	return -EINVAL;
}

static void path_show(struct seq_file *m, struct sentral_sim *sim,
		      ktime_t now)
{
	unsigned int i;

	for (i = 0; i < sim->world.nseg; i++) {
		const struct sim_segment *sg = &sim->world.seg[i];

		seq_printf(m, "%d %d %d %d %u\n", sg->in[0], sg->in[1],
			   sg->in[2], sg->rate_dps, sg->ms);
	}
}

/* Parse n whitespace-separated integers; nothing may follow */
static int sim_parse_ints(char *buf, s64 *v, int n, s64 max)
{
	char *tok;
	int i;

	for (i = 0; i < n; i++) {
		tok = strsep(&buf, " \t");
		while (tok && !*tok)
			tok = strsep(&buf, " \t");
		if (!tok || kstrtos64(tok, 0, &v[i]) || abs(v[i]) > max)
			return -EINVAL;
	}
	if (buf && *skip_spaces(buf))
		return -EINVAL;
	return 0;
}

/* "clear", or a segment "AX AY AZ DPS MS" appended to the path */
static int path_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	s32 axis[3];
	s64 v[5];
	int i, ret;

	if (!strcmp(buf, "clear"))
		return sim_motion_clear_path(&sim->world);
	ret = sim_parse_ints(buf, v, 5, SIM_MAX_MS);
	if (ret)
		return ret;
	for (i = 0; i < 3; i++)
		axis[i] = v[i];
	return sim_motion_add_segment(&sim->world, axis, v[3], v[4]);
}

/* w x y z in millionths */
static void orientation_show(struct seq_file *m, struct sentral_sim *sim,
			     ktime_t now)
{
	const s32 *q = sim->world.q;
	s64 v[4];
	int i;

	for (i = 0; i < 4; i++)
		v[i] = DIV_ROUND_CLOSEST_ULL(abs((s64)q[i]) * 1000000, SIM_Q30) *
		       (q[i] < 0 ? -1 : 1);
	seq_printf(m, "%lld %lld %lld %lld\n", v[0], v[1], v[2], v[3]);
}

static int orientation_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	s64 q[4];
	int ret = sim_parse_ints(buf, q, 4, SIM_Q30);

	if (ret)
		return ret;
	if (!q[0] && !q[1] && !q[2] && !q[3])
		return -EINVAL;
	sim_motion_set_orientation(&sim->world, q, now);
	return 0;
}

static void coverage_show(struct seq_file *m, struct sentral_sim *sim,
			  ktime_t now)
{
	int i;

	seq_printf(m, "regions %d\n", SIM_REGIONS);
	seq_printf(m, "seen %u\n", bitmap_weight(sim->cal_seen, SIM_REGIONS));
	seq_puts(m, "map ");
	for (i = 0; i < SIM_REGIONS; i++)
		seq_putc(m, test_bit(i, sim->cal_seen) ? '1' : '0');
	seq_putc(m, '\n');
}

static void cal_duration_show(struct seq_file *m, struct sentral_sim *sim,
			      ktime_t now)
{
	seq_printf(m, "%u\n", sim->cal_duration_ms);
}

static int cal_duration_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return sim_parse_period_ms(buf, &sim->cal_duration_ms);
}

static void gbias_period_show(struct seq_file *m, struct sentral_sim *sim,
			      ktime_t now)
{
	seq_printf(m, "%u\n", sim->gbias_period_ms);
}

static int gbias_period_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return sim_parse_period_ms(buf, &sim->gbias_period_ms);
}

static void drift_show(struct seq_file *m, struct sentral_sim *sim,
		       ktime_t now)
{
	seq_printf(m, "%u\n", sim->drift_ms);
}

/* 0 turns drift off; the field stays where it has drifted to */
static int drift_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	int ret = sim_parse_u32(buf, SIM_MAX_MS, &sim->drift_ms);

	if (!ret)
		sim->drift_ns = 0;
	return ret;
}

static void cal_updates_show(struct seq_file *m, struct sentral_sim *sim,
			     ktime_t now)
{
	seq_printf(m, "mag %llu\nmag_read %llu\ngbias %llu\ngbias_read %llu\n",
		   sim->cal_updates[0], sim->cal_updates_read[0],
		   sim->cal_updates[1], sim->cal_updates_read[1]);
}

static void mag_transient_show(struct seq_file *m, struct sentral_sim *sim,
			       ktime_t now)
{
	seq_printf(m, "%u\n", sim->mag_transient);
}

static int mag_transient_store(struct sentral_sim *sim, char *buf,
			       ktime_t now)
{
	u32 v;
	int ret = sim_parse_u32(buf, 3, &v);

	if (!ret)
		sim->mag_transient = v;
	return ret;
}

static void appnote_layout_show(struct seq_file *m, struct sentral_sim *sim,
				ktime_t now)
{
	seq_printf(m, "%d\n", sim->appnote_layout);
}

static int appnote_layout_store(struct sentral_sim *sim, char *buf,
				ktime_t now)
{
	return kstrtobool(buf, &sim->appnote_layout);
}

static void algo_status_or_show(struct seq_file *m, struct sentral_sim *sim,
				ktime_t now)
{
	seq_printf(m, "0x%02x\n", sim->algo_status_or);
}

static int algo_status_or_store(struct sentral_sim *sim, char *buf,
				ktime_t now)
{
	return kstrtou8(buf, 0, &sim->algo_status_or);
}

static void accel_bias_show(struct seq_file *m, struct sentral_sim *sim,
			    ktime_t now)
{
	seq_printf(m, "%d %d %d\n", sim->accel_bias[0], sim->accel_bias[1],
		   sim->accel_bias[2]);
}

static int accel_bias_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	s16 v[3];
	char *tok;
	int i;

	for (i = 0; i < 3; i++) {
		tok = strsep(&buf, " \t");
		while (tok && !*tok)
			tok = strsep(&buf, " \t");
		if (!tok || kstrtos16(tok, 0, &v[i]))
			return -EINVAL;
	}
	if (buf && *skip_spaces(buf))
		return -EINVAL;
	memcpy(sim->accel_bias, v, sizeof(v));
	return 0;
}

static void ack_latency_show(struct seq_file *m, struct sentral_sim *sim,
			     ktime_t now)
{
	seq_printf(m, "%u\n", sim->ack_latency_us);
}

static int ack_latency_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return sim_parse_u32(buf, SIM_MAX_LATENCY_US, &sim->ack_latency_us);
}

static void ack_never_show(struct seq_file *m, struct sentral_sim *sim,
			   ktime_t now)
{
	seq_printf(m, "%d\n", sim->ack_never);
}

static int ack_never_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return kstrtobool(buf, &sim->ack_never);
}

static void ack_end_show(struct seq_file *m, struct sentral_sim *sim,
			 ktime_t now)
{
	seq_printf(m, "%u\n", sim->ack_end);
}

static int ack_end_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	u32 v;
	int ret = sim_parse_u32(buf, SIM_ACK_END_MAX, &v);

	if (!ret)
		sim->ack_end = v;
	return ret;
}

static void nack_at_show(struct seq_file *m, struct sentral_sim *sim,
			 ktime_t now)
{
	seq_printf(m, "%u\n", sim->nack_at);
}

static int nack_at_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	int ret = sim_parse_u32(buf, U32_MAX, &sim->nack_at);

	if (!ret) {
		sim->nack_count = 0;
		sim->nack_left = 0;
	}
	return ret;
}

static void nack_run_show(struct seq_file *m, struct sentral_sim *sim,
			  ktime_t now)
{
	seq_printf(m, "%u\n", max(sim->nack_run, 1U));
}

static int nack_run_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return sim_parse_u32(buf, 1000, &sim->nack_run);
}

static void upload_ms_show(struct seq_file *m, struct sentral_sim *sim,
			   ktime_t now)
{
	seq_printf(m, "%u\n", sim->upload_ms);
}

static int upload_ms_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return sim_parse_u32(buf, SIM_MAX_UPLOAD_MS, &sim->upload_ms);
}

static void ram_version_show(struct seq_file *m, struct sentral_sim *sim,
			     ktime_t now)
{
	seq_printf(m, "0x%04x\n", sim->ram_version);
}

static int ram_version_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return kstrtou16(buf, 0, &sim->ram_version);
}

static void rom_version_show(struct seq_file *m, struct sentral_sim *sim,
			     ktime_t now)
{
	seq_printf(m, "0x%04x\n", sim->rom_version);
}

static int rom_version_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return kstrtou16(buf, 0, &sim->rom_version);
}

static void product_id_show(struct seq_file *m, struct sentral_sim *sim,
			    ktime_t now)
{
	seq_printf(m, "0x%02x\n", sim->product_id);
}

static int product_id_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return kstrtou8(buf, 0, &sim->product_id);
}

static void revision_id_show(struct seq_file *m, struct sentral_sim *sim,
			     ktime_t now)
{
	seq_printf(m, "0x%02x\n", sim->revision_id);
}

static int revision_id_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return kstrtou8(buf, 0, &sim->revision_id);
}

static void events_gated_show(struct seq_file *m, struct sentral_sim *sim,
			      ktime_t now)
{
	seq_printf(m, "%d\n", sim->events_gated);
}

static int events_gated_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return kstrtobool(buf, &sim->events_gated);
}

static void error_show(struct seq_file *m, struct sentral_sim *sim,
		       ktime_t now)
{
	seq_printf(m, "0x%02x\n", sim->regs[SIM_REG_ERROR]);
}

/* ErrorRegister = the value; anything but 0 raises the Error event */
static int error_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	u8 v;
	int ret = kstrtou8(buf, 0, &v);

	if (!ret)
		sim_error(sim, v);
	return ret;
}

static void sensor_status_show(struct seq_file *m, struct sentral_sim *sim,
			       ktime_t now)
{
	seq_printf(m, "0x%02x\n", sim->sensor_status);
}

static int sensor_status_store(struct sentral_sim *sim, char *buf,
			       ktime_t now)
{
	return kstrtou8(buf, 0, &sim->sensor_status);
}

static void autoinc_stop_show(struct seq_file *m, struct sentral_sim *sim,
			      ktime_t now)
{
	seq_printf(m, "%d\n", sim->autoinc_stop);
}

static int autoinc_stop_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return kstrtobool(buf, &sim->autoinc_stop);
}

static void reset_int_show(struct seq_file *m, struct sentral_sim *sim,
			   ktime_t now)
{
	seq_printf(m, "%d\n", sim->reset_int);
}

static int reset_int_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return kstrtobool(buf, &sim->reset_int);
}

static void warm_reboot_show(struct seq_file *m, struct sentral_sim *sim,
			     ktime_t now)
{
	seq_printf(m, "%d\n", sim->wedged);
}

/* The host rebooted, the chip did not: only a ResetRequest clears it */
static int warm_reboot_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	if (strcmp(buf, "1"))
		return -EINVAL;
	sim->wedged = true;
	return 0;
}

static void bus_khz_show(struct seq_file *m, struct sentral_sim *sim,
			 ktime_t now)
{
	seq_printf(m, "%u\n", sim->bus_khz);
}

static int bus_khz_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	u32 v;
	int ret = sim_parse_u32(buf, SIM_MAX_BUS_KHZ, &v);

	if (ret)
		return ret;
	if (v && v < SIM_MIN_BUS_KHZ)
		return -ERANGE;
	sim->bus_khz = v;
	return 0;
}

static void standby_never_show(struct seq_file *m, struct sentral_sim *sim,
			       ktime_t now)
{
	seq_printf(m, "%d\n", sim->standby_never);
}

static int standby_never_store(struct sentral_sim *sim, char *buf,
			       ktime_t now)
{
	return kstrtobool(buf, &sim->standby_never);
}

static void standby_power_loss_show(struct seq_file *m,
				    struct sentral_sim *sim, ktime_t now)
{
	seq_printf(m, "%d\n", sim->standby_power_loss);
}

static int standby_power_loss_store(struct sentral_sim *sim, char *buf,
				    ktime_t now)
{
	return kstrtobool(buf, &sim->standby_power_loss);
}

static void standby_blocks_params_show(struct seq_file *m,
				       struct sentral_sim *sim, ktime_t now)
{
	seq_printf(m, "%d\n", sim->standby_blocks_params);
}

static int standby_blocks_params_store(struct sentral_sim *sim, char *buf,
				       ktime_t now)
{
	return kstrtobool(buf, &sim->standby_blocks_params);
}

static void nack_after_reset_show(struct seq_file *m, struct sentral_sim *sim,
				  ktime_t now)
{
	seq_printf(m, "%u\n", sim->nack_after_reset_ms);
}

static int nack_after_reset_store(struct sentral_sim *sim, char *buf,
				  ktime_t now)
{
	return sim_parse_u32(buf, SIM_MAX_UPLOAD_MS, &sim->nack_after_reset_ms);
}

static int int_stuck_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	if (strcmp(buf, "1"))
		return -EINVAL;
	sim_int_stuck(sim);
	return 0;
}

/*
 * INT rises with no event pending, as another device's interrupt on a
 * shared line looks to this chip's host; low again when EventStatus is read
 */
static int int_spurious_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	if (strcmp(buf, "1"))
		return -EINVAL;
	sim->int_latched = true;
	return 0;
}

/* A reset of the chip's own: INT rises for CPUReset unless reset_int 0 */
static int chip_reset_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	if (strcmp(buf, "1"))
		return -EINVAL;
	sim_power_on(sim, now);
	sim->int_latched = sim->reset_int;
	return 0;
}

static int power_cycle_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	if (strcmp(buf, "1"))
		return -EINVAL;
	sim_power_on(sim, now);
	return 0;
}

static s64 sim_ns_to_us(s64 ns)
{
	return div_s64(ns, NSEC_PER_USEC);
}

static void stats_show(struct seq_file *m, struct sentral_sim *sim,
		       ktime_t now)
{
	struct sim_stats *st = &sim->stats;

	seq_printf(m, "transactions %llu\n", st->transactions);
	seq_printf(m, "bytes %llu\n", st->bytes);
	seq_printf(m, "bus_time_us %llu\n",
		   DIV_ROUND_CLOSEST_ULL(st->bus_ns, NSEC_PER_USEC));
	seq_printf(m, "elapsed_us %lld\n",
		   st->transactions ? ktime_us_delta(st->last, st->first) : 0);
	seq_printf(m, "nacks %llu\n", st->nacks);
	seq_printf(m, "params_served %llu\n", st->params_served);
	seq_printf(m, "ack_polls_early %llu\n", st->ack_polls_early);
	seq_printf(m, "wire_waits %llu\n", st->wire_waits);
	seq_printf(m, "wire_late_100us %llu\n", st->wire_late_100us);
	seq_printf(m, "wire_late_1ms %llu\n", st->wire_late_1ms);
	seq_printf(m, "wire_late_max_us %lld\n",
		   sim_ns_to_us(st->wire_late_max_ns));
	seq_printf(m, "host_gaps %llu\n", st->host_gaps);
	seq_printf(m, "host_gap_100us %llu\n", st->host_gap_100us);
	seq_printf(m, "host_gap_max_us %lld\n",
		   sim_ns_to_us(st->host_gap_max_ns));
	seq_printf(m, "timer_late_max_us %lld\n",
		   sim_ns_to_us(st->timer_late_max_ns));
}

static int stats_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	if (strcmp(buf, "0"))
		return -EINVAL;
	memset(&sim->stats, 0, sizeof(sim->stats));
	/* a status read before the reset is not the next transfer's */
	sim->drdy_ret = 0;
	return 0;
}

static void samples_show(struct seq_file *m, struct sentral_sim *sim,
			 ktime_t now)
{
	int id, i;

	for (id = 0; id < SIM_NSTREAMS; id++) {
		const char *name = sim_stream_names[id];
		struct sim_stream *st = &sim->stream[id];

		seq_printf(m, "%s %llu\n", name, st->produced);
		seq_printf(m, "%s_read %llu\n", name, st->read);
		seq_printf(m, "%s_missed %llu\n", name, st->missed);
		seq_printf(m, "%s_gaps %llu\n", name, st->gaps);
		seq_printf(m, "%s_gaps_held %llu\n", name, st->gaps_held);
		seq_printf(m, "%s_drops_seen %llu\n", name, st->drops_seen);
		for (i = 0; i < SIM_DROP_NCAUSES; i++)
			seq_printf(m, "%s_drops_seen_%s %llu\n", name,
				   sim_drop_causes[i], st->drops_cause[i]);
		seq_printf(m, "%s_drops_unseen %llu\n", name, st->drops_unseen);
	}
	seq_printf(m, "timer_late %llu\n", sim->timer_late);
}

/* The last SIM_DROP_LOG of @n drops logged in @log, oldest first */
static void drop_log_show(struct seq_file *m, const struct sim_drop *log,
			  u64 n)
{
	u64 i = n > SIM_DROP_LOG ? n - SIM_DROP_LOG : 0;

	for (; i < n; i++) {
		const struct sim_drop *d = &log[i % SIM_DROP_LOG];

		seq_printf(m, "%s %s period_us %llu came_late_us %lld inflight_us %lld busy %u latency_us %lld wire_us %lld margin_us %lld wake_us %lld gap_us %lld next %s late_us %lld\n",
			   sim_stream_names[d->stream],
			   sim_drop_causes[d->cause],
			   div_u64(d->period_ns, NSEC_PER_USEC),
			   sim_ns_to_us(d->came_late_ns),
			   sim_ns_to_us(d->inflight_ns), d->busy,
			   sim_ns_to_us(d->latency_ns),
			   sim_ns_to_us(d->wire_ns),
			   sim_ns_to_us(d->margin_ns),
			   d->wake_ns < 0 ? -1 : sim_ns_to_us(d->wake_ns),
			   d->gap_ns < 0 ? -1 : sim_ns_to_us(d->gap_ns),
			   sim_xfer_kinds[d->next], sim_ns_to_us(d->late_ns));
	}
}

static void drops_show(struct seq_file *m, struct sentral_sim *sim,
		       ktime_t now)
{
	drop_log_show(m, sim->drop_log, sim->drops_logged);
}

static void drops_host_show(struct seq_file *m, struct sentral_sim *sim,
			    ktime_t now)
{
	drop_log_show(m, sim->host_log, sim->host_logged);
}

static int samples_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	int id;

	if (strcmp(buf, "0"))
		return -EINVAL;
	for (id = 0; id < SIM_NSTREAMS; id++) {
		sim->stream[id].produced = 0;
		sim->stream[id].read = 0;
		sim->stream[id].missed = 0;
		sim->stream[id].read_seq = 0;
		sim->stream[id].gaps = 0;
		sim->stream[id].held_unread = 0;
		sim->stream[id].gaps_held = 0;
		sim->stream[id].drops_seen = 0;
		memset(sim->stream[id].drops_cause, 0,
		       sizeof(sim->stream[id].drops_cause));
		sim->stream[id].drops_unseen = 0;
		sim->stream[id].unread = false;
		sim->stream[id].seen_start = 0;
		sim->stream[id].next_start = 0;
		sim->stream[id].pending = 0;
	}
	sim->timer_late = 0;
	sim->drops_logged = 0;
	sim->host_logged = 0;
	return 0;
}

static void params_show(struct seq_file *m, struct sentral_sim *sim,
			ktime_t now)
{
	int n;

	for (n = 1; n < SIM_NPARAMS; n++)
		seq_printf(m, "%d 0x%08x\n", n, sim->params[n]);
}

static void regs_show(struct seq_file *m, struct sentral_sim *sim,
		      ktime_t now)
{
	u8 row[16];
	int base, i;

	for (base = 0; base < 256; base += 16) {
		for (i = 0; i < 16; i++)
			row[i] = sim_reg_read(sim, base + i, now, true);
		seq_printf(m, "%02x: %*ph\n", base, 16, row);
	}
}

static void state_show(struct seq_file *m, struct sentral_sim *sim,
		       ktime_t now)
{
	u8 algo = sim->regs[SIM_REG_ALGO_CONTROL];

	seq_printf(m, "uploading %d\n", sim_in_upload(sim, now));
	seq_printf(m, "host_run %d\n",
		   !!(sim->regs[SIM_REG_HOST_CONTROL] & SIM_HOST_RUN));
	seq_printf(m, "standby %d\n", !!(algo & SIM_ALGO_STANDBY));
	seq_printf(m, "transfer %d\n", !!(algo & SIM_ALGO_PARAM_PROC));
	seq_printf(m, "running %d\n", sim_algo_running(sim, now));
	seq_printf(m, "request_pending %d\n", sim->req_pending);
	seq_printf(m, "transfer_started_us %lld\n",
		   ktime_to_us(sim->transfer_started));
	seq_printf(m, "transfer_ended_us %lld\n",
		   ktime_to_us(sim->transfer_ended));
	seq_printf(m, "transfer_longest_us %lld\n", sim->transfer_longest_us);
	seq_printf(m, "cal_status %u\n", sim_cal_status(sim));
	seq_printf(m, "score_raw %u\n", sim_cal_score_raw(sim));
	seq_printf(m, "int %d\n", sim->int_high);
	seq_printf(m, "irqs %llu\n", sim->irqs);
	seq_printf(m, "virq %u\n", sim->virq);
}

static const struct sim_knob sim_knobs[] = {
	{ "motion", 0600, motion_show, motion_store },
	{ "pattern", 0600, pattern_show, pattern_store },
	{ "path", 0600, path_show, path_store },
	{ "orientation", 0600, orientation_show, orientation_store },
	{ "coverage", 0400, coverage_show, NULL },
	{ "cal_duration_ms", 0600, cal_duration_show, cal_duration_store },
	{ "gbias_period_ms", 0600, gbias_period_show, gbias_period_store },
	{ "drift_ms", 0600, drift_show, drift_store },
	{ "cal_updates", 0400, cal_updates_show, NULL },
	{ "mag_transient", 0600, mag_transient_show, mag_transient_store },
	{ "appnote_layout", 0600, appnote_layout_show, appnote_layout_store },
	{ "algo_status_or", 0600, algo_status_or_show, algo_status_or_store },
	{ "accel_bias", 0600, accel_bias_show, accel_bias_store },
	{ "ack_latency_us", 0600, ack_latency_show, ack_latency_store },
	{ "ack_never", 0600, ack_never_show, ack_never_store },
	{ "ack_end", 0600, ack_end_show, ack_end_store },
	{ "nack_at", 0600, nack_at_show, nack_at_store },
	{ "nack_run", 0600, nack_run_show, nack_run_store },
	{ "upload_ms", 0600, upload_ms_show, upload_ms_store },
	{ "ram_version", 0600, ram_version_show, ram_version_store },
	{ "rom_version", 0600, rom_version_show, rom_version_store },
	{ "product_id", 0600, product_id_show, product_id_store },
	{ "revision_id", 0600, revision_id_show, revision_id_store },
	{ "events_gated", 0600, events_gated_show, events_gated_store },
	{ "error", 0600, error_show, error_store },
	{ "sensor_status", 0600, sensor_status_show, sensor_status_store },
	{ "autoinc_stop", 0600, autoinc_stop_show, autoinc_stop_store },
	{ "reset_int", 0600, reset_int_show, reset_int_store },
	{ "warm_reboot", 0600, warm_reboot_show, warm_reboot_store },
	{ "bus_khz", 0600, bus_khz_show, bus_khz_store },
	{ "standby_never", 0600, standby_never_show, standby_never_store },
	{ "standby_power_loss", 0600, standby_power_loss_show,
	  standby_power_loss_store },
	{ "standby_blocks_params", 0600, standby_blocks_params_show,
	  standby_blocks_params_store },
	{ "nack_after_reset_ms", 0600, nack_after_reset_show,
	  nack_after_reset_store },
	{ "int_stuck", 0200, NULL, int_stuck_store },
	{ "int_spurious", 0200, NULL, int_spurious_store },
	{ "chip_reset", 0200, NULL, chip_reset_store },
	{ "power_cycle", 0200, NULL, power_cycle_store },
	{ "stats", 0600, stats_show, stats_store },
	{ "samples", 0600, samples_show, samples_store },
	{ "drops", 0400, drops_show, NULL },
	{ "drops_host", 0400, drops_host_show, NULL },
	{ "params", 0400, params_show, NULL },
	{ "regs", 0400, regs_show, NULL },
	{ "state", 0400, state_show, NULL },
	/* the board around the hub, sim-usfs.c */
	{ "feature_flags", 0600, sim_usfs_feature_flags_show,
	  sim_usfs_feature_flags_store },
	{ "baro_rate_half", 0600, sim_usfs_baro_rate_half_show,
	  sim_usfs_baro_rate_half_store },
	{ "no_eeprom", 0600, sim_usfs_no_eeprom_show, sim_usfs_no_eeprom_store },
	{ "crc_wire", 0600, sim_usfs_crc_wire_show, sim_usfs_crc_wire_store },
	{ "eeprom_write_ms", 0600, sim_usfs_eeprom_write_ms_show,
	  sim_usfs_eeprom_write_ms_store },
	{ "board", 0400, sim_usfs_board_show, NULL },
};

static int sim_knob_show(struct seq_file *m, void *unused)
{
	const struct sim_knob_file *kf = m->private;
	const struct sim_knob *knob = kf->knob;
	struct sentral_sim *sim = kf->sim;
	unsigned long flags;
	ktime_t now;

	/* write-only knobs read as empty */
	if (!knob->show)
		return 0;
	spin_lock_irqsave(&sim->lock, flags);
	now = ktime_get();
	sim_advance(sim, now);
	knob->show(m, sim, now);
	spin_unlock_irqrestore(&sim->lock, flags);
	return 0;
}

static int sim_knob_open(struct inode *inode, struct file *file)
{
	return single_open(file, sim_knob_show, inode->i_private);
}

static int sim_knob_store(struct sentral_sim *sim, const struct sim_knob *knob,
			  char *buf)
{
	unsigned long flags;
	ktime_t now;
	bool fire;
	int ret;

	spin_lock_irqsave(&sim->lock, flags);
	now = ktime_get();
	sim_advance(sim, now);
	ret = knob->store(sim, strim(buf), now);
	sim_schedule(sim, now);
	fire = sim_int_update(sim);
	spin_unlock_irqrestore(&sim->lock, flags);

	if (fire)
		sim_fire_irq(sim);
	return ret;
}

static ssize_t sim_knob_write(struct file *file, const char __user *ubuf,
			      size_t count, loff_t *ppos)
{
	const struct sim_knob_file *kf = file_inode(file)->i_private;
	const struct sim_knob *knob = kf->knob;
	char buf[64];
	int ret;

	if (!knob->store)
		return -EPERM;
	if (count >= sizeof(buf))
		return -EINVAL;
	if (copy_from_user(buf, ubuf, count))
		return -EFAULT;
	buf[count] = '\0';

	ret = sim_knob_store(kf->sim, knob, buf);
	return ret ? ret : count;
}

/**
 * sim_knobs_apply() - set knobs as if written to debugfs
 * @sim: the chip
 * @spec: "name=value[,name=value...]", or NULL
 *
 * For the knobs a chip must have before a driver probes it (the knobs
 * module parameter).
 *
 * Return: 0, or -EINVAL for an unknown knob or a value it refuses.
 */
int sim_knobs_apply(struct sentral_sim *sim, const char *spec)
{
	char *dup, *rest, *item, *val;
	int i, ret = 0;

	if (!spec || !*spec)
		return 0;
	dup = kstrdup(spec, GFP_KERNEL);
	if (!dup)
		return -ENOMEM;
	rest = dup;
	while (!ret && (item = strsep(&rest, ",")) != NULL) {
		val = strchr(item, '=');
		if (!val) {
			ret = -EINVAL;
			break;
		}
		*val++ = '\0';
		ret = -EINVAL;
		for (i = 0; i < ARRAY_SIZE(sim_knobs); i++) {
			if (!sim_knobs[i].store || strcmp(sim_knobs[i].name, item))
				continue;
			ret = sim_knob_store(sim, &sim_knobs[i], val) ? -EINVAL : 0;
			break;
		}
	}
	if (ret)
		pr_err("sentral_sim: knobs: cannot set %s\n", item ? item : spec);
	kfree(dup);
	return ret;
}

static const struct file_operations sim_knob_fops = {
	.owner = THIS_MODULE,
	.open = sim_knob_open,
	.read = seq_read,
	.write = sim_knob_write,
	.llseek = seq_lseek,
	.release = single_release,
};

int sim_debugfs_init(struct sentral_sim *sim, const char *dir)
{
	struct sim_knob_file *kf;
	int i;

	kf = kcalloc(ARRAY_SIZE(sim_knobs), sizeof(*kf), GFP_KERNEL);
	if (!kf)
		return -ENOMEM;
	sim->knob_files = kf;
	sim->debugfs = debugfs_create_dir(dir, NULL);
	for (i = 0; i < ARRAY_SIZE(sim_knobs); i++) {
		kf[i].sim = sim;
		kf[i].knob = &sim_knobs[i];
		debugfs_create_file(sim_knobs[i].name, sim_knobs[i].mode,
				    sim->debugfs, &kf[i], &sim_knob_fops);
	}
	sim_usfs_debugfs_init(sim, sim->debugfs);
	return 0;
}

void sim_debugfs_exit(struct sentral_sim *sim)
{
	debugfs_remove_recursive(sim->debugfs);
	kfree(sim->knob_files);
}
