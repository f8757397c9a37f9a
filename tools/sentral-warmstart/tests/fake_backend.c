// SPDX-License-Identifier: GPL-2.0-only
#include <string.h>

#include "fake_backend.h"

static struct fake_be *to_fake(struct sw_backend *b)
{
	return (struct fake_be *)b;
}

static bool gone(struct fake_be *f, struct sw_err *e)
{
	if (!f->gone_ms || f->clk->now_ms < f->gone_ms)
		return false;
	sw_err_set(e, SW_EXIT_DEVICE,
		   "%s is gone (unbound or unplugged): reading in_magn_calibration_auto_status: No such device",
		   f->b.name);
	return true;
}

static int f_chip_info(struct sw_backend *b, struct sw_chip_info *ci,
		       struct sw_err *e)
{
	struct fake_be *f = to_fake(b);

	if (gone(f, e))
		return e->code;
	if (f->on_chip_info)
		f->on_chip_info(f);
	f->chip_infos++;
	*ci = f->chip;
	return SW_EXIT_OK;
}

static void current_state(struct fake_be *f, struct sw_cal_state *cs)
{
	size_t i;

	*cs = f->cs;
	for (i = 0; i < f->nsteps; i++) {
		if (f->script[i].at_ms > f->clk->now_ms)
			break;
		cs->level = f->script[i].level;
		if (cs->has_score)
			cs->score_raw = f->script[i].score_raw;
		/* The driver's flag: set until calibration_data is read. */
		if (cs->has_score && f->script[i].gyro_bias_update &&
		    (!f->flags_cleared ||
		     f->script[i].at_ms > f->flags_cleared_ms))
			cs->gyro_bias_update = 1;
	}
}

static void clear_flags(struct fake_be *f)
{
	f->flags_cleared = true;
	f->flags_cleared_ms = f->clk->now_ms;
	f->cs.gyro_bias_update = 0;
	f->cs.mag_cal_update = 0;
}

static int f_cal_state(struct sw_backend *b, struct sw_cal_state *cs,
		       struct sw_err *e)
{
	struct fake_be *f = to_fake(b);

	if (gone(f, e))
		return e->code;
	f->state_reads++;
	current_state(f, cs);
	if (cs->level == FAKE_GLITCH)
		return sw_err_set(e, SW_EXIT_IO,
				  "%s: reading in_magn_calibration_auto_status: Input/output error",
				  b->name);
	if (!cs->has_score)
		cs->score_raw = 0;
	return SW_EXIT_OK;
}

static int f_read_blob(struct sw_backend *b, uint8_t *blob, struct sw_err *e)
{
	struct fake_be *f = to_fake(b);
	int k;

	if (gone(f, e))
		return e->code;
	if (f->fail_read)
		return sw_err_set(e, f->fail_read, "fake: read failed");
	f->reads++;
	/* The chip holds the accel offsets in parameters 27..29. */
	for (k = 0; k < 3; k++)
		sw_blob_set_param(f->blob, SW_PARAM_ACCEL_X + k,
				  sw_lsb_to_g(f->offset[k]));
	if (f->blob_follows_score) {
		struct sw_cal_state cs;

		current_state(f, &cs);
		sw_blob_set_param(f->blob, 18, cs.has_score ?
				  (float)cs.score_raw : (float)cs.level);
	}
	memcpy(blob, f->blob, SW_BLOB_SIZE);
	clear_flags(f);
	if (f->level_after_read >= 0)
		f->cs.level = f->level_after_read;
	return SW_EXIT_OK;
}

static int f_write_blob(struct sw_backend *b, const struct sw_chip_info *chip,
			const uint8_t *blob, struct sw_err *e)
{
	struct fake_be *f = to_fake(b);
	int k;

	if (f->fail_write)
		return sw_err_set(e, f->fail_write, "fake: write failed");
	/* As the driver checks calibration_data's header: all of it */
	if (b->checks_identity && memcmp(chip, &f->chip, sizeof(*chip)))
		return sw_err_set(e, SW_EXIT_FILE,
				  "fake: the driver refused the calibration: saved on another chip or firmware");
	f->writes++;
	clear_flags(f);
	memcpy(f->blob, blob, SW_BLOB_SIZE);
	for (k = 0; k < 3; k++)
		f->offset[k] = sw_g_to_lsb(sw_blob_param(blob,
							 SW_PARAM_ACCEL_X + k));
	if (f->level_after_write >= 0)
		f->cs.level = f->level_after_write;
	return SW_EXIT_OK;
}

static int f_mag(struct sw_backend *b, double ut[3], struct sw_err *e)
{
	struct fake_be *f = to_fake(b);

	(void)e;
	f->mag_reads++;
	if (f->mag) {
		f->mag(f->clk->now_ms, ut);
	} else {
		ut[0] = 47.2;
		ut[1] = -12.5;
		ut[2] = 87.4;
	}
	return SW_EXIT_OK;
}

static int f_accel_raw(struct sw_backend *b, int xyz[3], struct sw_err *e)
{
	static const int expect[3] = { 0, 0, SW_ACCEL_1G_LSB };
	struct fake_be *f = to_fake(b);
	int k, n = (f->samples_read++ & 1) ? f->noise : -f->noise;

	(void)e;
	for (k = 0; k < 3; k++)
		xyz[k] = expect[k] + f->bias[k] - f->offset[k] + n;
	return SW_EXIT_OK;
}

static int f_offset_get(struct sw_backend *b, int lsb[3], struct sw_err *e)
{
	struct fake_be *f = to_fake(b);

	(void)e;
	memcpy(lsb, f->offset_reported ? f->offset_reported : f->offset,
	       sizeof(f->offset));
	if (f->offset_readback_wrong)
		lsb[0]++;
	return SW_EXIT_OK;
}

static int f_offset_set(struct sw_backend *b, const int lsb[3],
			struct sw_err *e)
{
	(void)e;
	memcpy(to_fake(b)->offset, lsb, sizeof(to_fake(b)->offset));
	return SW_EXIT_OK;
}

static int f_hub_info(struct sw_backend *b, struct sw_hub_info *hi,
		      struct sw_err *e)
{
	struct fake_be *f = to_fake(b);

	if (gone(f, e))
		return e->code;
	if (f->hub_fail)
		return sw_err_set(e, f->hub_fail,
				  "%s: reading in_pressure_raw: Input/output error",
				  b->name);
	*hi = f->hub;
	return SW_EXIT_OK;
}

static void f_close(struct sw_backend *b)
{
	(void)b;
}

static const struct sw_backend_ops fake_ops = {
	.chip_info = f_chip_info,
	.cal_state = f_cal_state,
	.read_blob = f_read_blob,
	.write_blob = f_write_blob,
	.mag = f_mag,
	.accel_raw = f_accel_raw,
	.accel_offset_get = f_offset_get,
	.accel_offset_set = f_offset_set,
	.hub_info = f_hub_info,
	.close = f_close,
};

void fake_fill_blob(uint8_t *blob)
{
	int i;

	for (i = 1; i <= SW_NPARAMS; i++)
		sw_blob_set_param(blob, i, (float)i * 0.5f);
}

uint32_t fake_board_image(uint8_t *img, enum sw_board_layout l)
{
	/* Written independently of board.c: the utilities' own addresses. */
	uint32_t at = l == SW_BOARD_GT ? 0x8000 : 0x7f00;
	static const int16_t acc[6] = { 2049, 2050, 2051, -2047, -2046, -2045 };
	int k;

	memset(img, 0xff, SW_BOARD_EEPROM_SIZE);
	fake_fill_blob(img + at);
	for (k = 0; k < 6; k++)
		sw_put_le16(img + at + 0x8c + 2 * k, (uint16_t)acc[k]);
	if (l == SW_BOARD_GT)
		img[at + 0x98] = 0xaa;
	return at;
}

void fake_init(struct fake_be *f, struct fake_clock *clk)
{
	memset(f, 0, sizeof(*f));
	f->b.ops = &fake_ops;
	f->b.kind = "fake";
	strcpy(f->b.name, "iio:device0");
	strcpy(f->b.key, "platform-sentral-sim-0x28");
	/* The driver backend: the I2C client names the driver's file */
	strcpy(f->b.client, "1-0028");
	f->clk = clk;
	f->chip.product_id = 0x80;
	f->chip.revision_id = 0x02;
	f->chip.rom_version = 0x09e6;
	f->chip.ram_version = 0x0c05;
	f->cs.level = 4;
	f->cs.has_score = true;
	f->cs.score_raw = sw_score_raw(2.5);
	f->level_after_write = 4;
	f->level_after_read = -1;
	fake_fill_blob(f->blob);
	/* The USFS board: barometer and thermometer, firmware from its EEPROM */
	f->hub.fw_source = SW_FW_EEPROM;
	f->hub.nfeatures = 2;
	f->hub.features[0] = (struct sw_feature){
		.kind = SW_FEATURE_PRESSURE, .have_value = true,
		.value = 100.012, .rate_hz = 25,
	};
	f->hub.features[1] = (struct sw_feature){
		.kind = SW_FEATURE_TEMP, .have_value = true,
		.value = 25.03, .rate_hz = 25,
	};
}

static uint64_t f_now(void *clk)
{
	return ((struct fake_clock *)clk)->now_ms;
}

static void f_sleep(void *clk, unsigned int ms)
{
	((struct fake_clock *)clk)->now_ms += ms;
}

static uint64_t f_wall(void *clk)
{
	return ((struct fake_clock *)clk)->wall_s;
}

void fake_env(struct sw_env *env, struct fake_clock *clk, FILE *out,
	      FILE *err)
{
	memset(env, 0, sizeof(*env));
	env->out = out;
	env->err = err;
	env->clk = clk;
	env->now_ms = f_now;
	env->sleep_ms = f_sleep;
	env->nap_ms = f_sleep;
	env->wall_s = f_wall;
}
