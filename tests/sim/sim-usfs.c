// SPDX-License-Identifier: GPL-2.0
/*
 * The simulated EM7180 as the USFS board carries it: the feature sensors
 * its firmware reports (FeatureFlags 0x39, rates 0x58..0x5a, data
 * 0x2a..0x31), the hub's own sensor bus that passthrough (0x9e/0xa0)
 * connects to the host's (M24512 EEPROM at 0x50 with its ID page at 0x58,
 * MPU9250 at 0x68, AK8963 at 0x0c, MS5637 at 0x76) and the host RAM upload
 * of a board without an EEPROM (HostControl bit 1, UploadAddress 0x94,
 * UploadData 0x96, CRCHost 0x97).
 *
 * Facts come from the EM7180 register reference (§ numbers below); the
 * choices where it is silent or its sources disagree are listed in
 * tests/sim/README.md. Everything but allocation and the debugfs files
 * runs with sim->lock held.
 */
#include <linux/crc32.h>
#include <linux/debugfs.h>
#include <linux/fs.h>
#include <linux/kernel.h>
#include <linux/math64.h>
#include <linux/minmax.h>
#include <linux/mm.h>
#include <linux/seq_file.h>
#include <linux/slab.h>
#include <linux/string.h>
#include <linux/uaccess.h>

#include "sentral_sim.h"

/* FeatureFlags bits, §1 */
#define SIM_FEAT_BARO		0
#define SIM_FEAT_HUMIDITY	1
#define SIM_FEAT_TEMP		2
#define SIM_FEAT_MODELLED	(BIT(SIM_FEAT_BARO) | BIT(SIM_FEAT_HUMIDITY) | \
				 BIT(SIM_FEAT_TEMP))
/* The USFS: barometer and temperature (KW, GT) */
#define SIM_FEAT_DEFAULT	(BIT(SIM_FEAT_BARO) | BIT(SIM_FEAT_TEMP))
#define SIM_FEAT_REPORT		BIT(7)	/* rate register: EventStatus bit 6 */
#define SIM_FEAT_MAX_HZ		100

/* SentralStatus bits, §1 */
#define SIM_ST_STANDBY		BIT(3)
#define SIM_ST_NO_EEPROM	BIT(4)

/* The sensor bus, §3 item 9 and the USFS parts */
#define SIM_ADDR_AK8963		0x0c
#define SIM_ADDR_EEPROM		0x50
#define SIM_ADDR_EEPROM_ID	0x58
#define SIM_ADDR_MPU9250	0x68
#define SIM_ADDR_MS5637		0x76
#define SIM_AK8963_WIA		0x00
#define SIM_AK8963_ID		0x48
#define SIM_AK8963_CNTL1	0x0a	/* the first writable register */
#define SIM_MPU9250_PWR_MGMT_1	0x6b
#define SIM_MPU9250_WHO_AM_I	0x75
#define SIM_MPU9250_ID		0x71
#define SIM_EEPROM_WRITE_MS	5	/* M24512 datasheet: tW 5 ms */
#define SIM_EEPROM_MAX_WRITE_MS	1000

/* MS5637 commands and fixed coefficients and conversions */
#define SIM_MS5637_RESET	0x1e
#define SIM_MS5637_ADC_READ	0x00
#define SIM_MS5637_PROM		0xa0	/* 0xa0..0xae */
static const u16 sim_ms5637_coeff[6] = {
	46372, 43981, 29059, 27842, 31553, 28165,
};

#define SIM_MS5637_D1		6465444
#define SIM_MS5637_D2		8077636

/* The CDS block ends the uploaded text (§3 item 3; Sony's struct fw_cds) */
#define SIM_CDS_SIZE		44
#define SIM_CDS_RAM_VER		8

static struct sim_usfs *usfs(struct sentral_sim *sim)
{
	return &sim->usfs;
}

int sim_usfs_alloc(struct sentral_sim *sim)
{
	struct sim_usfs *u = usfs(sim);

	u->eeprom = kvmalloc(SIM_EEPROM_SIZE, GFP_KERNEL);
	u->ram = kvzalloc(SIM_UPLOAD_RAM_SIZE, GFP_KERNEL);
	if (!u->eeprom || !u->ram) {
		sim_usfs_free(sim);
		return -ENOMEM;
	}
	/* an erased EEPROM until a test writes an image */
	memset(u->eeprom, 0xff, SIM_EEPROM_SIZE);
	memset(u->id_page, 0xff, sizeof(u->id_page));
	return 0;
}

void sim_usfs_free(struct sentral_sim *sim)
{
	struct sim_usfs *u = usfs(sim);

	kvfree(u->eeprom);
	kvfree(u->ram);
	u->eeprom = NULL;
	u->ram = NULL;
}

static void sim_usfs_layout(struct sim_usfs *u)
{
	unsigned int bit;

	u->nfeat = 0;
	for (bit = 0; bit < SIM_NFEATURES; bit++)
		if (u->feature_flags & BIT(bit))
			u->feat[u->nfeat++].flag = bit;
}

/* Before the first power-on: the board's defaults and its other chips */
void sim_usfs_init(struct sentral_sim *sim, ktime_t now)
{
	struct sim_usfs *u = usfs(sim);

	u->feature_flags = SIM_FEAT_DEFAULT;
	u->eeprom_write_ms = SIM_EEPROM_WRITE_MS;
	u->t0 = now;
	sim_usfs_layout(u);
	u->mpu[SIM_MPU9250_PWR_MGMT_1] = 0x01;
	u->mpu[SIM_MPU9250_WHO_AM_I] = SIM_MPU9250_ID;
	u->ak[SIM_AK8963_WIA] = SIM_AK8963_ID;
}

/* Power-on or reset of the hub: RAM lost, the EEPROM and sensors stay */
void sim_usfs_power_on(struct sentral_sim *sim, ktime_t now)
{
	struct sim_usfs *u = usfs(sim);
	int i;

	u->uploading = false;
	u->up_pos = 0;
	u->up_len = 0;
	u->up_start = 0;
	u->up_overflow = false;
	u->up_crc_wire = ~0U;
	u->fw = u->no_eeprom ? SIM_FW_NONE : SIM_FW_EEPROM;
	u->fw_ram_version = 0;
	if (u->ram)
		memset(u->ram, 0, SIM_UPLOAD_RAM_SIZE);
	for (i = 0; i < SIM_NFEATURES; i++) {
		u->feat[i].rate = 0;
		u->feat[i].n = 0;
		u->feat[i].ts = 0;
		u->feat[i].ts_base = 0;
	}
}

/* Firmware in RAM that the CPU can run */
bool sim_usfs_firmware(struct sentral_sim *sim, ktime_t now)
{
	enum sim_fw_origin fw = usfs(sim)->fw;

	return !sim_in_upload(sim, now) &&
	       (fw == SIM_FW_EEPROM || fw == SIM_FW_HOST);
}

/* RAMVersion: the firmware's, 0 without any (§1) */
u16 sim_usfs_ram_version(struct sentral_sim *sim, ktime_t now)
{
	struct sim_usfs *u = usfs(sim);

	if (sim_in_upload(sim, now))
		return 0;
	switch (u->fw) {
	case SIM_FW_EEPROM:
		return sim->ram_version;
	case SIM_FW_HOST:
		return u->fw_ram_version;
	default:
		return 0;
	}
}

/*
 * SentralStatus of a board without an EEPROM: nothing while the ROM looks
 * for one, then NoEEPROM, and StandbySt while the CPU does not execute,
 * which is what EM's host driver waits for after a reset (§3 item 2).
 */
u8 sim_usfs_sentral_status(struct sentral_sim *sim, ktime_t now)
{
	if (sim_in_upload(sim, now))
		return 0;
	if (sim->wedged)
		return SIM_ST_NO_EEPROM;
	return SIM_ST_NO_EEPROM |
	       (sim->regs[SIM_REG_HOST_CONTROL] & SIM_HOST_RUN ?
		0 : SIM_ST_STANDBY);
}

bool sim_usfs_passthrough(struct sentral_sim *sim)
{
	return sim->regs[SIM_REG_PASSTHRU_CTRL] & BIT(0);
}

/* The feature rate in Hz the slot's sensor samples at, 0: off */
static u32 sim_feature_rate(struct sentral_sim *sim, unsigned int i)
{
	struct sim_usfs *u = usfs(sim);
	u32 rate;

	if (i >= u->nfeat || !(sim->regs[SIM_REG_HOST_CONTROL] & SIM_HOST_RUN))
		return 0;
	rate = sim->regs[SIM_REG_FEATURE_RATE0 + i] & ~SIM_FEAT_REPORT;
	/* KW: "sample rate of barometer is baroRt/2"; GT: the rate in Hz */
	if (u->feat[i].flag == SIM_FEAT_BARO && u->baro_rate_half)
		rate /= 2;
	return min_t(u32, rate, SIM_FEAT_MAX_HZ);
}

/* The CRC-32 (IEEE 802.3, as zlib's crc32()) the chip reports */
static u32 sim_upload_crc(struct sim_usfs *u)
{
	u32 len;

	if (u->crc_wire)
		return ~u->up_crc_wire;
	if (u->up_start >= SIM_UPLOAD_RAM_SIZE)
		return 0;	/* nothing landed in RAM */
	/* whole words received, in RAM (the image file's) byte order */
	len = min_t(u32, u->up_len & ~3U, SIM_UPLOAD_RAM_SIZE - u->up_start);
	return ~crc32_le(~0U, u->ram + u->up_start, len);
}

bool sim_usfs_reg_read(struct sentral_sim *sim, u8 reg, ktime_t now, u8 *val)
{
	struct sim_usfs *u = usfs(sim);

	switch (reg) {
	case SIM_REG_FEATURE_FLAGS:
		*val = sim_usfs_firmware(sim, now) ? u->feature_flags : 0;
		return true;
	case SIM_REG_ACTUAL_FEATURE0 ... SIM_REG_ACTUAL_FEATURE0 + 2:
		*val = sim_feature_rate(sim, reg - SIM_REG_ACTUAL_FEATURE0);
		return true;
	case SIM_REG_UPLOAD_DATA:
		*val = 0;
		return true;
	case SIM_REG_CRC_HOST ... SIM_REG_CRC_HOST + 3:
		*val = sim_upload_crc(u) >> (8 * (reg - SIM_REG_CRC_HOST));
		return true;
	default:
		return false;
	}
}

/* The end of an upload: the CDS block at the end of the text, §3 item 3 */
static void sim_upload_end(struct sim_usfs *u)
{
	const u8 *cds;

	u->fw = SIM_FW_BAD;
	if (u->up_overflow || u->up_len < SIM_CDS_SIZE || u->up_len % 4)
		return;
	cds = u->ram + u->up_start + u->up_len - SIM_CDS_SIZE;
	u->fw_ram_version = cds[SIM_CDS_RAM_VER] | cds[SIM_CDS_RAM_VER + 1] << 8;
	u->fw = SIM_FW_HOST;
}

/*
 * A HostControl write (outside the EEPROM upload): bit 1 set starts a host
 * upload at UploadAddress, cleared ends it. The CPU runs (bit 0) only with
 * firmware and not while an upload is in progress. Returns what the
 * register then holds.
 */
u8 sim_usfs_host_control(struct sentral_sim *sim, u8 val, ktime_t now)
{
	struct sim_usfs *u = usfs(sim);
	bool up = val & SIM_HOST_UPLOAD;

	if (up && !u->uploading) {
		/* UploadAddress: 13 bits, MSB first, in 32-bit words (§1) */
		u->up_start = ((sim->regs[SIM_REG_UPLOAD_ADDR] & 0x1f) << 8 |
			       sim->regs[SIM_REG_UPLOAD_ADDR + 1]) * 4;
		u->up_pos = u->up_start;
		u->up_len = 0;
		u->up_overflow = u->up_start >= SIM_UPLOAD_RAM_SIZE;
		u->up_crc_wire = ~0U;
		u->fw = SIM_FW_NONE;
	} else if (!up && u->uploading) {
		sim_upload_end(u);
	}
	u->uploading = up;
	if (up || !sim_usfs_firmware(sim, now))
		val &= ~SIM_HOST_RUN;
	return val;
}

/* One byte written to UploadData: 32-bit words arrive byte-swapped */
void sim_usfs_upload_byte(struct sentral_sim *sim, u8 val)
{
	struct sim_usfs *u = usfs(sim);

	if (!u->uploading)
		return;
	u->up_crc_wire = crc32_le(u->up_crc_wire, &val, 1);
	if (u->up_pos >= SIM_UPLOAD_RAM_SIZE)
		u->up_overflow = true;
	else
		u->ram[u->up_pos ^ 3] = val;
	u->up_pos++;
	u->up_len++;
}

/* A slow, plausible drift: a triangle wave of amplitude amp */
static s32 sim_tri(u64 t_ms, u32 period_ms, s32 amp)
{
	u32 x;
	s64 v;

	div_u64_rem(t_ms, period_ms, &x);
	v = div_u64((u64)4 * amp * x, period_ms);	/* 0..4 amp */
	if (v > 2 * amp)
		v = 4 * amp - v;
	return v - amp;
}

/*
 * USFS conversions (KW, GT, SL): pressure_mbar = raw * 0.01 + 1013.25,
 * temperature_C = raw * 0.01; humidity 0.01 %/LSB (EMEXT).
 */
static s16 sim_feature_value(struct sentral_sim *sim, u8 flag, ktime_t now)
{
	u64 t = max_t(s64, ktime_ms_delta(now, usfs(sim)->t0), 0);

	switch (flag) {
	case SIM_FEAT_BARO:	/* 1000.00 hPa, +-0.5 hPa over 2 minutes */
		return 100000 + sim_tri(t, 120000, 50) - 101325;
	case SIM_FEAT_HUMIDITY:	/* 45.00 %, +-1 % over 200 s */
		return 4500 + sim_tri(t, 200000, 100);
	default:		/* 25.00 C, +-0.2 C over 5 minutes */
		return 2500 + sim_tri(t, 300000, 20);
	}
}

/*
 * Slot layout (EMREG, EMCORE): one feature: data0, ts0; two: data0, ts0,
 * data1, ts1 (USFS: Baro 0x2a, BaroTIME 0x2c, Temp 0x2e, TempTIME 0x30);
 * three: data0, data1, data2, one timestamp.
 */
static void sim_feature_put(struct sentral_sim *sim, unsigned int i, s16 val,
			    u16 ts)
{
	struct sim_usfs *u = usfs(sim);
	u8 data, time;

	if (u->nfeat < 3) {
		data = SIM_REG_FEATURE0 + 4 * i;
		time = data + 2;
	} else {
		data = SIM_REG_FEATURE0 + 2 * i;
		time = SIM_REG_FEATURE0 + 6;
	}
	sim_put_le16(val, &sim->regs[data]);
	sim_put_le16(ts, &sim->regs[time]);
}

static void sim_feature_produce(struct sentral_sim *sim, unsigned int i,
				ktime_t now)
{
	struct sim_usfs *u = usfs(sim);
	struct sim_feature *f = &u->feat[i];
	unsigned int t;

	f->n++;
	f->ts = f->ts_base + (u16)div_u64((u64)f->n * 32768, f->rate);
	sim_feature_put(sim, i, sim_feature_value(sim, f->flag, now), f->ts);
	f->produced++;
	if (sim->regs[SIM_REG_FEATURE_RATE0 + i] & SIM_FEAT_REPORT)
		sim_event(sim, SIM_EV_FEATURE);
	if (f->flag != SIM_FEAT_BARO)
		return;
	/*
	 * The MS5637 measures temperature for every pressure (its D2
	 * conversion), and the USFS firmware fills the temperature slot with
	 * it: KW's, GT's and SL's examples set only BaroRate and read Temp on
	 * every barometer event.
	 */
	for (t = 0; t < u->nfeat; t++)
		if (u->feat[t].flag == SIM_FEAT_TEMP)
			sim_feature_put(sim, t,
					sim_feature_value(sim, SIM_FEAT_TEMP, now),
					f->ts);
}

static ktime_t sim_feature_due(struct sentral_sim *sim, struct sim_feature *f)
{
	return ktime_add_ns(sim->epoch, f->tick * f->period_ns);
}

static void sim_feature_next_tick(struct sentral_sim *sim,
				  struct sim_feature *f, ktime_t now)
{
	f->tick = div64_u64(ktime_to_ns(ktime_sub(now, sim->epoch)),
			    f->period_ns) + 1;
}

/*
 * As the other streams: (re)started on the common epoch when production
 * starts (restart) or the rate changes; called from sim_schedule().
 */
void sim_usfs_schedule(struct sentral_sim *sim, bool prod, bool restart,
		       ktime_t now)
{
	struct sim_usfs *u = usfs(sim);
	unsigned int i;

	if (!prod)
		return;
	for (i = 0; i < SIM_NFEATURES; i++) {
		struct sim_feature *f = &u->feat[i];
		u32 rate = sim_feature_rate(sim, i);

		if (!restart && rate == f->rate)
			continue;
		f->rate = rate;
		f->ts_base = f->ts;
		f->n = 0;
		if (!rate)
			continue;
		f->period_ns = div_u64(NSEC_PER_SEC, rate);
		sim_feature_next_tick(sim, f, now);
	}
}

ktime_t sim_usfs_next_due(struct sentral_sim *sim, ktime_t next)
{
	struct sim_usfs *u = usfs(sim);
	unsigned int i;

	for (i = 0; i < SIM_NFEATURES; i++) {
		ktime_t due;

		if (!u->feat[i].rate)
			continue;
		due = sim_feature_due(sim, &u->feat[i]);
		if (!next || ktime_before(due, next))
			next = due;
	}
	return next;
}

/* From the data timer: the samples due by now, one per stream at most */
ktime_t sim_usfs_tick(struct sentral_sim *sim, ktime_t now, ktime_t next)
{
	struct sim_usfs *u = usfs(sim);
	unsigned int i;

	for (i = 0; i < SIM_NFEATURES; i++) {
		struct sim_feature *f = &u->feat[i];

		if (!f->rate || ktime_after(sim_feature_due(sim, f), now))
			continue;
		sim_feature_produce(sim, i, now);
		f->tick++;
		if (!ktime_after(sim_feature_due(sim, f), now))
			sim_feature_next_tick(sim, f, now);
	}
	return sim_usfs_next_due(sim, next);
}

/* The sensor bus: who acknowledges its address now */
static bool sim_bus_present(struct sentral_sim *sim, u16 addr, ktime_t now)
{
	struct sim_usfs *u = usfs(sim);

	if (!sim_usfs_passthrough(sim))
		return false;
	switch (addr) {
	case SIM_ADDR_EEPROM:
	case SIM_ADDR_EEPROM_ID:
		/* no acknowledge during the internal write cycle */
		return !u->no_eeprom && !ktime_before(now, u->ee_busy_until);
	case SIM_ADDR_AK8963:
	case SIM_ADDR_MPU9250:
	case SIM_ADDR_MS5637:
		return true;
	default:
		return false;
	}
}

/*
 * M24512: two address bytes, then data written within the 128-byte page
 * (rolling over at its end); a read goes on from the address counter
 * (rolling over at the end of the memory). The ID page at 0x58 is one
 * such page.
 */
static bool sim_eeprom_msg(struct sim_usfs *u, struct i2c_msg *msg, bool id)
{
	u16 page, i;

	if (msg->flags & I2C_M_RD) {
		for (i = 0; i < msg->len; i++) {
			if (id) {
				msg->buf[i] = u->id_page[u->ee_addr % SIM_EEPROM_PAGE];
				page = u->ee_addr & ~(SIM_EEPROM_PAGE - 1);
				u->ee_addr = page | ((u->ee_addr + 1) %
						     SIM_EEPROM_PAGE);
			} else {
				msg->buf[i] = u->eeprom[u->ee_addr++];
			}
		}
		return false;
	}
	if (msg->len < 2)
		return false;	/* acknowledge polling, or half an address */
	u->ee_addr = msg->buf[0] << 8 | msg->buf[1];
	page = u->ee_addr & ~(SIM_EEPROM_PAGE - 1);
	for (i = 2; i < msg->len; i++) {
		if (id)
			u->id_page[u->ee_addr % SIM_EEPROM_PAGE] = msg->buf[i];
		else
			u->eeprom[u->ee_addr] = msg->buf[i];
		u->ee_addr = page | ((u->ee_addr + 1) % SIM_EEPROM_PAGE);
	}
	return msg->len > 2;
}

/* A register-pointer device (MPU9250, AK8963); first writable register */
static void sim_regdev_msg(u8 *regs, unsigned int n, u8 *ptr, u8 first_rw,
			   u8 ro, struct i2c_msg *msg)
{
	u16 i;

	if (msg->flags & I2C_M_RD) {
		for (i = 0; i < msg->len; i++) {
			msg->buf[i] = regs[*ptr];
			*ptr = (*ptr + 1) % n;
		}
		return;
	}
	if (!msg->len)
		return;
	*ptr = msg->buf[0] % n;
	for (i = 1; i < msg->len; i++) {
		if (*ptr >= first_rw && *ptr != ro)
			regs[*ptr] = msg->buf[i];
		*ptr = (*ptr + 1) % n;
	}
}

/* MS5637 PROM CRC-4, polynomial 0x3 on a 16-bit remainder (datasheet) */
static u16 sim_ms5637_prom(unsigned int w)
{
	u16 prom[8] = { 0 }, rem = 0;
	int i, b;

	memcpy(&prom[1], sim_ms5637_coeff, sizeof(sim_ms5637_coeff));
	for (i = 0; i < 16; i++) {
		rem ^= i & 1 ? prom[i / 2] & 0xff : prom[i / 2] >> 8;
		for (b = 0; b < 8; b++)
			rem = rem & 0x8000 ? (rem << 1) ^ 0x3000 : rem << 1;
	}
	prom[0] = ((rem >> 12) & 0xf) << 12;
	return prom[w];
}

static void sim_ms5637_msg(struct sim_usfs *u, struct i2c_msg *msg)
{
	u16 i, word;

	if (!(msg->flags & I2C_M_RD)) {
		for (i = 0; i < msg->len; i++) {
			u->ms_cmd = msg->buf[i];
			if (u->ms_cmd == SIM_MS5637_RESET)
				u->ms_adc = 0;
			else if ((u->ms_cmd & 0xf0) == 0x40)
				u->ms_adc = SIM_MS5637_D1;
			else if ((u->ms_cmd & 0xf0) == 0x50)
				u->ms_adc = SIM_MS5637_D2;
		}
		return;
	}
	if (u->ms_cmd == SIM_MS5637_ADC_READ) {
		for (i = 0; i < msg->len; i++)
			msg->buf[i] = i < 3 ? u->ms_adc >> (16 - 8 * i) : 0;
		u->ms_adc = 0;	/* read once */
		return;
	}
	word = (u->ms_cmd & 0xf0) == SIM_MS5637_PROM ?
		sim_ms5637_prom((u->ms_cmd >> 1) & 7) : 0;
	for (i = 0; i < msg->len; i++)
		msg->buf[i] = i < 2 ? word >> (8 - 8 * i) : 0;
}

/**
 * sim_usfs_xfer() - a transfer to the hub's sensor bus through passthrough
 * @sim: the chip whose bus it is
 * @msgs: messages, none to the hub itself
 * @num: how many
 *
 * While PassThruControl bit 0 is set the sensor bus is connected to the
 * host's: its devices answer at their addresses. Otherwise, or for an
 * address nobody has, the address is not acknowledged. Not counted in the
 * hub's bus statistics (another device's traffic) and without wire time.
 *
 * Return: @num, or -ENXIO at the first message nobody acknowledged.
 */
int sim_usfs_xfer(struct sentral_sim *sim, struct i2c_msg *msgs, int num)
{
	struct sim_usfs *u = usfs(sim);
	unsigned long flags;
	bool wrote = false;
	ktime_t now;
	int i, ret = num;

	for (i = 0; i < num; i++) {
		if (msgs[i].flags & I2C_M_TEN)
			return -ENXIO;
		if (msgs[i].flags & I2C_M_RECV_LEN)
			return -EOPNOTSUPP;
	}

	spin_lock_irqsave(&sim->lock, flags);
	now = ktime_get();
	u->bus_transactions++;
	for (i = 0; i < num; i++) {
		struct i2c_msg *msg = &msgs[i];

		if (!sim_bus_present(sim, msg->addr, now)) {
			u->bus_nacks++;
			ret = -ENXIO;
			break;
		}
		switch (msg->addr) {
		case SIM_ADDR_EEPROM:
		case SIM_ADDR_EEPROM_ID:
			wrote |= sim_eeprom_msg(u, msg,
						msg->addr == SIM_ADDR_EEPROM_ID);
			break;
		case SIM_ADDR_MPU9250:
			sim_regdev_msg(u->mpu, SIM_MPU9250_NREGS, &u->mpu_ptr,
				       0, SIM_MPU9250_WHO_AM_I, msg);
			break;
		case SIM_ADDR_AK8963:
			sim_regdev_msg(u->ak, SIM_AK8963_NREGS, &u->ak_ptr,
				       SIM_AK8963_CNTL1, SIM_AK8963_WIA, msg);
			break;
		default:
			sim_ms5637_msg(u, msg);
			break;
		}
	}
	/* the write cycle starts at the stop */
	if (wrote)
		u->ee_busy_until = ktime_add_ms(now, u->eeprom_write_ms);
	spin_unlock_irqrestore(&sim->lock, flags);
	return ret;
}

/* debugfs "eeprom": the M24512's 64 KiB, read and written at any offset */
static ssize_t sim_eeprom_read(struct file *file, char __user *ubuf,
			       size_t count, loff_t *ppos)
{
	struct sentral_sim *sim = file_inode(file)->i_private;
	unsigned long flags;
	ssize_t done = 0;
	u8 chunk[256];

	while (count && *ppos >= 0 && *ppos < SIM_EEPROM_SIZE) {
		size_t n = min3(count, sizeof(chunk),
				(size_t)(SIM_EEPROM_SIZE - *ppos));

		spin_lock_irqsave(&sim->lock, flags);
		memcpy(chunk, usfs(sim)->eeprom + *ppos, n);
		spin_unlock_irqrestore(&sim->lock, flags);
		if (copy_to_user(ubuf + done, chunk, n))
			return done ? done : -EFAULT;
		*ppos += n;
		done += n;
		count -= n;
	}
	return done;
}

static ssize_t sim_eeprom_write(struct file *file, const char __user *ubuf,
				size_t count, loff_t *ppos)
{
	struct sentral_sim *sim = file_inode(file)->i_private;
	unsigned long flags;
	ssize_t done = 0;
	u8 chunk[256];

	if (count && (*ppos < 0 || *ppos >= SIM_EEPROM_SIZE))
		return -ENOSPC;
	while (count && *ppos < SIM_EEPROM_SIZE) {
		size_t n = min3(count, sizeof(chunk),
				(size_t)(SIM_EEPROM_SIZE - *ppos));

		if (copy_from_user(chunk, ubuf + done, n))
			return done ? done : -EFAULT;
		spin_lock_irqsave(&sim->lock, flags);
		memcpy(usfs(sim)->eeprom + *ppos, chunk, n);
		spin_unlock_irqrestore(&sim->lock, flags);
		*ppos += n;
		done += n;
		count -= n;
	}
	return done;
}

static const struct file_operations sim_eeprom_fops = {
	.owner = THIS_MODULE,
	.open = simple_open,
	.read = sim_eeprom_read,
	.write = sim_eeprom_write,
	.llseek = default_llseek,
};

void sim_usfs_debugfs_init(struct sentral_sim *sim, struct dentry *dir)
{
	debugfs_create_file_size("eeprom", 0600, dir, sim, &sim_eeprom_fops,
				 SIM_EEPROM_SIZE);
}

/* Knobs */
void sim_usfs_feature_flags_show(struct seq_file *m, struct sentral_sim *sim,
				 ktime_t now)
{
	seq_printf(m, "0x%02x\n", usfs(sim)->feature_flags);
}

/* Barometer, humidity and temperature (bits 0..2) are modelled */
int sim_usfs_feature_flags_store(struct sentral_sim *sim, char *buf,
				 ktime_t now)
{
	u8 v;
	int ret = kstrtou8(buf, 0, &v);

	if (ret)
		return ret;
	if (v & ~SIM_FEAT_MODELLED)
		return -EINVAL;
	usfs(sim)->feature_flags = v;
	sim_usfs_layout(usfs(sim));
	return 0;
}

void sim_usfs_baro_rate_half_show(struct seq_file *m, struct sentral_sim *sim,
				  ktime_t now)
{
	seq_printf(m, "%d\n", usfs(sim)->baro_rate_half);
}

int sim_usfs_baro_rate_half_store(struct sentral_sim *sim, char *buf,
				  ktime_t now)
{
	return kstrtobool(buf, &usfs(sim)->baro_rate_half);
}

void sim_usfs_no_eeprom_show(struct seq_file *m, struct sentral_sim *sim,
			     ktime_t now)
{
	seq_printf(m, "%d\n", usfs(sim)->no_eeprom);
}

/* Another board: the chip powers on again on it */
int sim_usfs_no_eeprom_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	bool v;
	int ret = kstrtobool(buf, &v);

	if (ret)
		return ret;
	if (v != usfs(sim)->no_eeprom) {
		usfs(sim)->no_eeprom = v;
		sim_power_on(sim, now);
	}
	return 0;
}

void sim_usfs_crc_wire_show(struct seq_file *m, struct sentral_sim *sim,
			    ktime_t now)
{
	seq_printf(m, "%d\n", usfs(sim)->crc_wire);
}

int sim_usfs_crc_wire_store(struct sentral_sim *sim, char *buf, ktime_t now)
{
	return kstrtobool(buf, &usfs(sim)->crc_wire);
}

void sim_usfs_eeprom_write_ms_show(struct seq_file *m, struct sentral_sim *sim,
				   ktime_t now)
{
	seq_printf(m, "%u\n", usfs(sim)->eeprom_write_ms);
}

int sim_usfs_eeprom_write_ms_store(struct sentral_sim *sim, char *buf,
				   ktime_t now)
{
	u32 v;
	int ret = kstrtou32(buf, 0, &v);

	if (ret)
		return ret;
	if (v > SIM_EEPROM_MAX_WRITE_MS)
		return -ERANGE;
	usfs(sim)->eeprom_write_ms = v;
	return 0;
}

static const char * const sim_feature_names[SIM_NFEATURES] = {
	[SIM_FEAT_BARO] = "baro",
	[SIM_FEAT_HUMIDITY] = "humidity",
	[SIM_FEAT_TEMP] = "temp",
};

static const char * const sim_fw_names[] = {
	[SIM_FW_NONE] = "none",
	[SIM_FW_EEPROM] = "eeprom",
	[SIM_FW_HOST] = "host",
	[SIM_FW_BAD] = "bad",
};

/* debugfs "board": what the board around the hub is doing */
void sim_usfs_board_show(struct seq_file *m, struct sentral_sim *sim,
			 ktime_t now)
{
	struct sim_usfs *u = usfs(sim);
	unsigned int i;

	seq_printf(m, "features %u\n", u->nfeat);
	for (i = 0; i < u->nfeat; i++) {
		const char *name = sim_feature_names[u->feat[i].flag];

		seq_printf(m, "%s_slot %u\n", name, i);
		seq_printf(m, "%s_rate_hz %u\n", name, sim_feature_rate(sim, i));
		seq_printf(m, "%s_samples %llu\n", name, u->feat[i].produced);
	}
	seq_printf(m, "passthrough %d\n", sim_usfs_passthrough(sim));
	seq_printf(m, "bus_transactions %llu\n", u->bus_transactions);
	seq_printf(m, "bus_nacks %llu\n", u->bus_nacks);
	seq_printf(m, "firmware %s\n", sim_fw_names[u->fw]);
	seq_printf(m, "uploading %d\n", u->uploading);
	seq_printf(m, "upload_bytes %u\n", u->up_len);
	seq_printf(m, "upload_crc 0x%08x\n", sim_upload_crc(u));
	seq_printf(m, "ram_version 0x%04x\n", sim_usfs_ram_version(sim, now));
}
