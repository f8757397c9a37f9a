// SPDX-License-Identifier: GPL-2.0-only
/*
 * KUnit tests for the EM7180 driver, most against an emulated register map
 * on a custom regmap bus: the parameter transfer (exact bus sequences,
 * batches, acknowledge latency, timeouts, bus errors), float conversions,
 * warm start blob validation, the calibration_data attribute's write path
 * fed with random blobs, sizes and offsets, and the other helpers and bus
 * sequences of the driver.
 */

#include <kunit/test.h>
#include <linux/cleanup.h>
#include <linux/completion.h> /* upstream: passthru */
#include <linux/delay.h> /* upstream: health */
#include <linux/device.h>
#include <linux/errno.h>
#include <linux/firmware.h> /* upstream: upload */
#include <linux/i2c-mux.h> /* upstream: passthru */
#include <linux/ktime.h>
#include <linux/limits.h>
#include <linux/module.h>
#include <linux/mutex.h>
#include <linux/prandom.h>
#include <linux/regmap.h>
#include <linux/string.h>
#include <linux/workqueue.h> /* upstream: health */

#include "em7180.h"
#include "em7180_core.h"
#include "em7180_compat.h"

#define EMU_LOG_MAX		256

struct emu_xfer {
	bool write;
	u8 reg;
	u8 len;
	u8 data[8];
};

/* What ParamAcknowledge does when a transfer ends, as tests/sim knob ack_end */
enum emu_ack_end {
	EMU_ACK_END_CLEAR,	/* 0 at once on a stop or bit 7 clear */
	EMU_ACK_END_SERVED,	/* a stop is served like a request */
	EMU_ACK_END_KEPT,	/* keeps its last echo */
};

/* Just enough of the chip for the parameter procedure */
struct em7180_emu {
	u8 regs[256];
	u32 params[EM7180_PARAM_MAX + 1];
	struct emu_xfer log[EMU_LOG_MAX];
	unsigned int n_log;
	unsigned int transactions;
	unsigned int nack_at;		/* fail this transaction (1-based) */
	/* upstream: health { */
	unsigned int end_nacks;		/* fail this many ends of bit 7 */
	/* upstream: } */
	bool ack_never;
	enum emu_ack_end ack_end;
	bool standby_stuck;		/* AlgorithmStatus never shows standby */
	bool autoinc_stop;		/* the pointer stops at 0x3A and 0x63 */
	/* upstream: passthru { */
	bool passthru_stuck;		/* PassThruStatus never clears */
	/* upstream: } */
	u8 algo_status;			/* AlgorithmStatus but bit 0 */ /* upstream: cal */
	unsigned int ack_latency_us;
	bool pending;
	ktime_t req_time;
	/* upstream: upload { */
	/* What UploadData received, the register pointer staying on it */
	u8 upload[256];
	unsigned int upload_len;
	/* upstream: } */
};

struct em7180_test {
	struct device *dev;
	struct em7180_emu emu;
	struct iio_dev *indio_dev;
	struct em7180_data *data;
};

static void emu_log(struct em7180_emu *emu, bool write, u8 reg,
		    const u8 *data, size_t len)
{
	struct emu_xfer *x;

	if (emu->n_log >= EMU_LOG_MAX)
		return;
	x = &emu->log[emu->n_log++];
	x->write = write;
	x->reg = reg;
	x->len = len;
	if (data)
		memcpy(x->data, data, min(len, sizeof(x->data)));
}

/* A request is served while AlgorithmControl bit 7 is set */
static void emu_request_written(struct em7180_emu *emu)
{
	if (!emu->regs[EM7180_REG_PARAM_REQ] &&
	    emu->ack_end != EMU_ACK_END_SERVED) {
		emu->pending = false;
		if (emu->ack_end == EMU_ACK_END_CLEAR)
			emu->regs[EM7180_REG_PARAM_ACK] = 0;
		return;
	}
	emu->pending = true;
	emu->req_time = ktime_get();
}

static void emu_algo_written(struct em7180_emu *emu, u8 old)
{
	u8 new = emu->regs[EM7180_REG_ALGO_CTRL];

	if (!(old & EM7180_ALGO_CTRL_PARAM_XFER) &&
	    (new & EM7180_ALGO_CTRL_PARAM_XFER)) {
		emu->pending = emu->regs[EM7180_REG_PARAM_REQ] != 0;
		emu->req_time = ktime_get();
	} else if ((old & EM7180_ALGO_CTRL_PARAM_XFER) &&
		   !(new & EM7180_ALGO_CTRL_PARAM_XFER)) {
		emu->pending = false;
		if (emu->ack_end == EMU_ACK_END_CLEAR)
			emu->regs[EM7180_REG_PARAM_ACK] = 0;
	}
}

static void emu_serve(struct em7180_emu *emu)
{
	u8 req = emu->regs[EM7180_REG_PARAM_REQ];
	u8 n = req & ~EM7180_PARAM_WRITE;

	if (!emu->pending || emu->ack_never ||
	    !(emu->regs[EM7180_REG_ALGO_CTRL] & EM7180_ALGO_CTRL_PARAM_XFER) ||
	    ktime_us_delta(ktime_get(), emu->req_time) < emu->ack_latency_us)
		return;

	if (req & EM7180_PARAM_WRITE)
		emu->params[n] = get_unaligned_le32(&emu->regs[EM7180_REG_LOAD_PARAM]);
	else if (req)
		put_unaligned_le32(emu->params[n],
				   &emu->regs[EM7180_REG_SAVED_PARAM]);
	emu->regs[EM7180_REG_PARAM_ACK] = req;
	emu->pending = false;
}

/* The register pointer after one byte at @reg */
static u8 emu_next(const struct em7180_emu *emu, u8 reg)
{
	if (emu->autoinc_stop && (reg == EM7180_REG_PARAM_ACK ||
				  reg == EM7180_REG_PARAM_REQ - 1))
		return reg;
	return reg + 1;
}

static int emu_write(void *context, const void *buf, size_t count)
{
	struct em7180_emu *emu = context;
	u8 old_algo = emu->regs[EM7180_REG_ALGO_CTRL];
	const u8 *b = buf;
	bool req = false, algo = false;
	unsigned int i;
	u8 reg;

	if (++emu->transactions == emu->nack_at)
		return -EIO;
	/* upstream: health { */
	if (emu->end_nacks && b[0] == EM7180_REG_ALGO_CTRL && count == 2 &&
	    (old_algo & ~b[1] & EM7180_ALGO_CTRL_PARAM_XFER)) {
		emu->end_nacks--;
		return -EIO;
	}
	/* upstream: } */

	emu_log(emu, true, b[0], b + 1, count - 1);
	/* upstream: upload { */
	if (b[0] == EM7180_REG_UPLOAD_DATA) {
		for (i = 1; i < count; i++)
			if (emu->upload_len < sizeof(emu->upload))
				emu->upload[emu->upload_len++] = b[i];
		return 0;
	}
	/* upstream: } */
	for (i = 1, reg = b[0]; i < count; i++, reg = emu_next(emu, reg)) {
		emu->regs[reg] = b[i];
		req |= reg == EM7180_REG_PARAM_REQ;
		algo |= reg == EM7180_REG_ALGO_CTRL;
	}
	if (req)
		emu_request_written(emu);
	if (algo)
		emu_algo_written(emu, old_algo);

	return 0;
}

static int emu_read(void *context, const void *reg_buf, size_t reg_size,
		    void *val_buf, size_t val_size)
{
	struct em7180_emu *emu = context;
	u8 p, reg = *(const u8 *)reg_buf;
	unsigned int i;

	if (++emu->transactions == emu->nack_at)
		return -EIO;

	emu_serve(emu);
	emu->regs[EM7180_REG_ALGO_STATUS] = emu->standby_stuck ? 0 :
		emu->regs[EM7180_REG_ALGO_CTRL] & EM7180_ALGO_CTRL_STANDBY;
	emu->regs[EM7180_REG_ALGO_STATUS] |= emu->algo_status; /* upstream: cal */
	/* upstream: passthru { */
	emu->regs[EM7180_REG_PASSTHRU_STATUS] = emu->passthru_stuck ?
		EM7180_PASSTHRU_ON :
		emu->regs[EM7180_REG_PASSTHRU_CTRL] & EM7180_PASSTHRU_ON;
	/* upstream: } */
	/* upstream: health { */
	/* Once uploaded, the CPU is in standby until the host runs it */
	if (emu->regs[EM7180_REG_SENTRAL_STATUS] & EM7180_SENTRAL_UPLOAD_DONE) {
		if (emu->regs[EM7180_REG_HOST_CTRL] & EM7180_HOST_CTRL_RUN)
			emu->regs[EM7180_REG_SENTRAL_STATUS] &= ~EM7180_SENTRAL_STANDBY;
		else
			emu->regs[EM7180_REG_SENTRAL_STATUS] |= EM7180_SENTRAL_STANDBY;
	}
	/* upstream: } */
	for (i = 0, p = reg; i < val_size; i++, p = emu_next(emu, p))
		((u8 *)val_buf)[i] = emu->regs[p];
	emu_log(emu, false, reg, val_buf, val_size);
	/* upstream: cal { */
	/* The update flags latch until read */
	for (i = 0, p = reg; i < val_size; i++, p = emu_next(emu, p))
		if (p == EM7180_REG_CAL_FLAGS)
			emu->regs[EM7180_REG_CAL_FLAGS] = 0;
	/* upstream: } */

	return 0;
}

static const struct regmap_bus emu_bus = {
	.write = emu_write,
	.read = emu_read,
};

/* upstream: health { */
static void emu_no_recovery(struct work_struct *work)
{
}

/* upstream: } */
static int em7180_test_init(struct kunit *test)
{
	struct em7180_test *t;
	struct regmap *map;

	t = kunit_kzalloc(test, sizeof(*t), GFP_KERNEL);
	KUNIT_ASSERT_NOT_NULL(test, t);

	/*
	 * KUnit unregisters the device after the case's exit and after the
	 * devices the case registers: the regmap and the driver's state that
	 * hang on it outlive theirs.
	 */
	t->dev = kunit_device_register(test, "em7180-kunit");
	KUNIT_ASSERT_NOT_ERR_OR_NULL(test, t->dev);

	map = devm_regmap_init(t->dev, &emu_bus, &t->emu, &em7180_regmap_config);
	KUNIT_ASSERT_NOT_ERR_OR_NULL(test, map);
	/* The driver's state in an unregistered IIO device, as probe has it */
	t->indio_dev = devm_iio_device_alloc(t->dev, sizeof(*t->data));
	KUNIT_ASSERT_NOT_NULL(test, t->indio_dev);
	t->data = iio_priv(t->indio_dev);
	dev_set_drvdata(t->dev, t->indio_dev);

	t->data->dev = t->dev;
	t->data->regmap = map;
	/* upstream: cal { */
	/* Probe found firmware with the calibration registers */
	t->data->appnote_attrs = true;
	t->data->appnote = true;
	/* upstream: } */
	mutex_init(&t->data->lock);
	init_waitqueue_head(&t->data->wq);
	/* upstream: health { */
	/* A transfer that cannot be ended asks for a recovery: none here */
	INIT_DELAYED_WORK(&t->data->recover_work, emu_no_recovery);
	/* upstream: } */
	test->priv = t;

	return 0;
}

/* upstream: health { */
static void em7180_test_exit(struct kunit *test)
{
	struct em7180_test *t = test->priv;

	/* init stopped at an assertion: KUnit frees what it made */
	if (!t)
		return;

	cancel_delayed_work_sync(&t->data->recover_work);
}

/* upstream: } */
static void expect_xfer(struct kunit *test, const struct em7180_emu *emu,
			unsigned int i, bool write, u8 reg, const u8 *data,
			u8 len)
{
	const struct emu_xfer *x = &emu->log[i];

	KUNIT_ASSERT_LT(test, i, emu->n_log);
	KUNIT_EXPECT_EQ_MSG(test, x->write, write, "transaction %u", i);
	KUNIT_EXPECT_EQ_MSG(test, x->reg, reg, "transaction %u", i);
	KUNIT_EXPECT_EQ_MSG(test, x->len, len, "transaction %u", i);
	if (write && data)
		KUNIT_EXPECT_TRUE_MSG(test, !memcmp(x->data, data, len),
				      "transaction %u: %*ph", i, len, x->data);
}

/* How every transfer must end, error or not: ParamRequest = 0, bit 7 clear */
static void expect_ended(struct kunit *test, const struct em7180_emu *emu)
{
	static const u8 zero;

	KUNIT_ASSERT_GE(test, emu->n_log, 2U);
	expect_xfer(test, emu, emu->n_log - 2, true, EM7180_REG_PARAM_REQ,
		    &zero, 1);
	expect_xfer(test, emu, emu->n_log - 1, true, EM7180_REG_ALGO_CTRL,
		    &zero, 1);
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_PARAM_REQ], 0);
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_ALGO_CTRL], 0);
}

/* A transfer's first read, from ParamAcknowledge on */
#define TEST_BEGIN_LEN	(EM7180_REG_CAL_SCORE + 2 - EM7180_REG_PARAM_ACK) /* upstream: cal */
/* upstream: !cal: #define TEST_BEGIN_LEN	1 */

static int test_params_read(struct em7180_test *t, unsigned int first,
			    unsigned int count, u32 *vals)
{
	guard(mutex)(&t->data->lock);
	return em7180_params_read(t->data, first, count, vals);
}

static int test_params_write(struct em7180_test *t, unsigned int first,
			     unsigned int count, const u32 *vals)
{
	guard(mutex)(&t->data->lock);
	return em7180_params_write(t->data, first, count, vals);
}

static void em7180_test_param_read_sequence(struct kunit *test)
{
	static const u8 start = EM7180_ALGO_CTRL_PARAM_XFER, req = 5;
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 val = 0;

	emu->params[5] = 0x12345678;

	KUNIT_ASSERT_EQ(test, test_params_read(t, 5, 1, &val), 0);
	KUNIT_EXPECT_EQ(test, val, 0x12345678U);

	/*
	 * The echo read first, the request, then bit 7 as the reference
	 * drivers do, one poll with the value
	 */
	KUNIT_ASSERT_EQ(test, emu->n_log, 6U);
	expect_xfer(test, emu, 0, false, EM7180_REG_PARAM_ACK, NULL, TEST_BEGIN_LEN);
	expect_xfer(test, emu, 1, true, EM7180_REG_PARAM_REQ, &req, 1);
	expect_xfer(test, emu, 2, true, EM7180_REG_ALGO_CTRL, &start, 1);
	expect_xfer(test, emu, 3, false, EM7180_REG_PARAM_ACK, NULL, 5);
	expect_ended(test, emu);
}

static void em7180_test_param_write_sequence(struct kunit *test)
{
	static const u8 start = EM7180_ALGO_CTRL_PARAM_XFER;
	/* Table 1: -0.022936 g = BC BB E4 47, sent least significant first */
	static const u8 burst[] = { 0x47, 0xE4, 0xBB, 0xBC, 27 | 0x80 };
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 val = 0xBCBBE447;

	KUNIT_ASSERT_EQ(test, test_params_write(t, 27, 1, &val), 0);
	KUNIT_EXPECT_EQ(test, emu->params[27], 0xBCBBE447U);

	/* a write polls the acknowledge byte alone */
	KUNIT_ASSERT_EQ(test, emu->n_log, 6U);
	expect_xfer(test, emu, 0, false, EM7180_REG_PARAM_ACK, NULL, TEST_BEGIN_LEN);
	expect_xfer(test, emu, 1, true, EM7180_REG_LOAD_PARAM, burst, 5);
	expect_xfer(test, emu, 2, true, EM7180_REG_ALGO_CTRL, &start, 1);
	expect_xfer(test, emu, 3, false, EM7180_REG_PARAM_ACK, NULL, 1);
	expect_ended(test, emu);
}

/* The bursts of a write, in order, wherever the polls fall */
static void expect_bursts(struct kunit *test, const struct em7180_emu *emu,
			  const u32 *in, unsigned int count)
{
	unsigned int i, n = 0;
	u8 burst[5];

	for (i = 0; i < emu->n_log; i++) {
		if (!emu->log[i].write || emu->log[i].reg != EM7180_REG_LOAD_PARAM)
			continue;
		KUNIT_ASSERT_LT(test, n, count);
		put_unaligned_le32(in[n], burst);
		burst[4] = (n + 1) | EM7180_PARAM_WRITE;
		expect_xfer(test, emu, i, true, EM7180_REG_LOAD_PARAM, burst, 5);
		n++;
	}
	KUNIT_EXPECT_EQ(test, n, count);
}

static void em7180_test_param_batch(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 in[EM7180_WS_NUM_PARAMS], out[EM7180_WS_NUM_PARAMS];
	unsigned int i;

	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		in[i] = 0x3F800000 + i;

	KUNIT_ASSERT_EQ(test, test_params_write(t, 1, EM7180_WS_NUM_PARAMS, in), 0);
	KUNIT_EXPECT_EQ(test, emu->transactions, 2 * EM7180_WS_NUM_PARAMS + 4);
	expect_bursts(test, emu, in, EM7180_WS_NUM_PARAMS);
	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		KUNIT_EXPECT_EQ(test, emu->params[i + 1], in[i]);
	expect_ended(test, emu);

	emu->n_log = 0;
	emu->transactions = 0;
	KUNIT_ASSERT_EQ(test, test_params_read(t, 1, EM7180_WS_NUM_PARAMS, out), 0);
	KUNIT_EXPECT_EQ(test, emu->transactions, 2 * EM7180_WS_NUM_PARAMS + 4);
	KUNIT_EXPECT_TRUE(test, !memcmp(out, in, sizeof(in)));
	expect_ended(test, emu);
}

/*
 * A firmware that keeps its last echo when a transfer ends, or serves the
 * stop only after its latency: the same parameter written twice in a row
 * must hold the second value, and read twice, the value it has then.
 */
static void em7180_test_param_stale_ack(struct kunit *test)
{
	static const enum emu_ack_end modes[] = {
		EMU_ACK_END_SERVED, EMU_ACK_END_KEPT, EMU_ACK_END_CLEAR,
	};
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 a = 0xBCBBE447, b = 0x3CB7E4DE, val;
	unsigned int i, round;

	emu->ack_latency_us = 3000;
	for (i = 0; i < ARRAY_SIZE(modes); i++) {
		emu->ack_end = modes[i];
		for (round = 0; round < 2; round++) {
			KUNIT_ASSERT_EQ(test, test_params_write(t, 27, 1, &a), 0);
			KUNIT_ASSERT_EQ(test, test_params_write(t, 27, 1, &b), 0);
			KUNIT_EXPECT_EQ_MSG(test, emu->params[27], b,
					    "ack_end %d round %u", modes[i], round);
			KUNIT_ASSERT_EQ(test, test_params_read(t, 27, 1, &val), 0);
			emu->params[27] = a;
			/*
			 * The log holds 256 transactions: on a slow host the
			 * polls of the rounds before would fill it, and the
			 * end checked would not be this transfer's.
			 */
			emu->n_log = 0;
			KUNIT_ASSERT_EQ(test, test_params_read(t, 27, 1, &val), 0);
			KUNIT_EXPECT_EQ_MSG(test, val, a, "ack_end %d round %u",
					    modes[i], round);
			expect_ended(test, emu);
		}
	}
}

/*
 * Nothing known about ParamAcknowledge (another user had the chip): it is
 * read first, and an echo equal to the first request is changed by a read
 * of another parameter before the request goes out.
 */
static void em7180_test_param_unknown_ack(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 val = 0x3F800000;

	emu->ack_end = EMU_ACK_END_KEPT;
	emu->ack_latency_us = 3000;
	emu->regs[EM7180_REG_PARAM_ACK] = 28 | EM7180_PARAM_WRITE;

	KUNIT_ASSERT_EQ(test, test_params_write(t, 28, 1, &val), 0);
	KUNIT_EXPECT_EQ(test, emu->params[28], val);
	expect_xfer(test, emu, 0, false, EM7180_REG_PARAM_ACK, NULL, TEST_BEGIN_LEN);
	/* the read of parameter 29 that changes the echo */
	expect_xfer(test, emu, 1, true, EM7180_REG_PARAM_REQ, NULL, 1);
	KUNIT_EXPECT_EQ(test, emu->log[1].data[0], 29);
	expect_ended(test, emu);
}

/*
 * The first round learns the wait (it shrinks from 1 ms until a poll comes
 * early); later rounds poll once per parameter. The emulator's latency runs
 * on its own clock: on a loaded host the driver's view of the time a
 * request was sent lags it, and a few polls can still come early. Without
 * the learned wait every parameter would cost at least one more poll.
 */
static void em7180_test_param_latency(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 vals[EM7180_WS_NUM_PARAMS];
	unsigned int round, floor = 2 * EM7180_WS_NUM_PARAMS + 4;

	emu->ack_latency_us = 500;
	for (round = 0; round < 3; round++) {
		emu->transactions = 0;
		KUNIT_ASSERT_EQ(test, test_params_read(t, 1, EM7180_WS_NUM_PARAMS,
						       vals), 0);
		if (round)
			KUNIT_EXPECT_LE_MSG(test, emu->transactions, floor + 3,
					    "round %u", round);
		emu->transactions = 0;
		KUNIT_ASSERT_EQ(test, test_params_write(t, 1, EM7180_WS_NUM_PARAMS,
							vals), 0);
		KUNIT_EXPECT_LE_MSG(test, emu->transactions, floor + 3,
				    "round %u", round);
	}
	KUNIT_EXPECT_GT(test, t->data->ack_min_us, 0U);
}

/*
 * The least wait an early poll teaches is the time of the last poll that
 * came early, raised by 1/8: not below a time seen too short (the first
 * wait asked for, 400 us, is far below it), and under 9/8 of the latency,
 * whatever a sleep overran by. The polls come at 1/8 of the time spent,
 * so the last early one is within about 1/8 of the latency.
 */
static void em7180_test_param_ack_least(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 val;

	/* early even where a sleep lasts a 10 ms tick */
	emu->ack_latency_us = 50000;
	t->data->ack_wait_us = 400;
	KUNIT_ASSERT_EQ(test, test_params_read(t, 3, 1, &val), 0);
	KUNIT_EXPECT_GE(test, t->data->ack_min_us, 50000U / 2);
	KUNIT_EXPECT_LT(test, t->data->ack_min_us, 50000U + 50000U / 8);
	KUNIT_EXPECT_GE(test, t->data->ack_wait_us, 50000U - 50000U / 8);
}

static void em7180_test_param_slow_ack(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 val;

	emu->params[3] = 42;
	emu->ack_latency_us = 20000;
	KUNIT_ASSERT_EQ(test, test_params_read(t, 3, 1, &val), 0);
	KUNIT_EXPECT_EQ(test, val, 42U);
	expect_ended(test, emu);
}

static void em7180_test_param_timeout(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 val = 0;

	emu->ack_never = true;
	KUNIT_EXPECT_EQ(test, test_params_write(t, 28, 1, &val), -ETIMEDOUT);
	expect_ended(test, emu);

	/* The next transfer works */
	emu->ack_never = false;
	emu->params[28] = 7;
	KUNIT_EXPECT_EQ(test, test_params_read(t, 28, 1, &val), 0);
	KUNIT_EXPECT_EQ(test, val, 7U);
}

/* A bus error at every transaction of a 3-parameter write, in turn */
static void em7180_test_param_nack(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	static const u32 vals[] = { 1, 2, 3 };
	unsigned int n, clean;
	u32 back[3];
	int ret;

	KUNIT_ASSERT_EQ(test, test_params_write(t, 27, 3, vals), 0);
	clean = emu->transactions;
	KUNIT_ASSERT_EQ(test, clean, 10U);

	for (n = 1; n <= clean; n++) {
		emu->regs[EM7180_REG_PARAM_ACK] = 0;
		emu->transactions = 0;
		emu->n_log = 0;
		emu->nack_at = n;
		t->data->xfer_stuck = false; /* upstream: health */
		ret = test_params_write(t, 27, 3, vals);
		KUNIT_EXPECT_EQ_MSG(test, ret, -EIO, "NACK at %u", n);
		/* Both ends are written */
		if (n == clean) {
			/* upstream: health { */
			/* bit 7 left set asks for a recovery */
			KUNIT_EXPECT_TRUE(test, t->data->xfer_stuck);
			/* upstream: } */
			/* upstream: !health: KUNIT_EXPECT_EQ(test, */
			/* upstream: !health:		emu->regs[EM7180_REG_PARAM_REQ], 0); */
			emu->regs[EM7180_REG_ALGO_CTRL] = 0;
		} else if (n == clean - 1) {
			KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_ALGO_CTRL], 0);
		} else {
			expect_ended(test, emu);
		}

		emu->nack_at = 0;
		KUNIT_EXPECT_EQ(test, test_params_read(t, 27, 3, back), 0);
		KUNIT_EXPECT_TRUE(test, !memcmp(back, vals, sizeof(vals)));
	}
}

/* The pointer check writes two bytes at 0x63, and reads 0x63 back */
static int test_pointer(struct em7180_test *t)
{
	guard(mutex)(&t->data->lock);
	return em7180_param_pointer(t->data);
}

/*
 * A register pointer that stops at 0x3A and 0x63, found at probe: reads
 * in the reference hosts' order return the right values.
 */
static void em7180_test_param_autoinc_read(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 vals[EM7180_WS_NUM_PARAMS];
	unsigned int i;

	emu->autoinc_stop = true;
	KUNIT_ASSERT_EQ(test, test_pointer(t), 0);
	KUNIT_EXPECT_TRUE(test, t->data->ptr_stops);
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_PARAM_REQ], 0);
	/* upstream: cal { */
	/* The calibration flags are not taken from a repeated byte */
	emu->regs[EM7180_REG_PARAM_ACK] = EM7180_CAL_FLAG_MAG_UPDATE |
					  EM7180_CAL_FLAG_GBIAS_UPDATE;
	/* upstream: } */
	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		emu->params[i + 1] = 0x3F800000 + i;

	for (i = 0; i < 2; i++) {
		emu->transactions = 0;
		KUNIT_ASSERT_EQ(test, test_params_read(t, 1, EM7180_WS_NUM_PARAMS,
						       vals), 0);
		KUNIT_EXPECT_TRUE(test, !memcmp(vals, &emu->params[1],
						sizeof(vals)));
		expect_ended(test, emu);
	}
	KUNIT_EXPECT_EQ(test, t->data->cal.flags, 0); /* upstream: cal */
	/* request, poll, value: one more per parameter */
	/* upstream: cal { */
	/* and the calibration registers, read apart from the echo */
	KUNIT_EXPECT_EQ(test, emu->transactions, 3 * EM7180_WS_NUM_PARAMS + 5);
	/* upstream: } */
	/* upstream: !cal: KUNIT_EXPECT_EQ(test, emu->transactions, */
	/* upstream: !cal:		3 * EM7180_WS_NUM_PARAMS + 4); */
}

/*
 * A pointer that stops at 0x63: writes go one register at a time, with no
 * burst waiting for an acknowledge that cannot come, and the chip holds
 * every value.
 */
static void em7180_test_param_autoinc_write(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 in[EM7180_WS_NUM_PARAMS];
	unsigned int i;

	emu->autoinc_stop = true;
	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		in[i] = 0xBC000000 + i;

	KUNIT_ASSERT_EQ(test, test_pointer(t), 0);
	emu->transactions = 0;
	KUNIT_ASSERT_EQ(test, test_params_write(t, 1, EM7180_WS_NUM_PARAMS, in), 0);
	KUNIT_EXPECT_TRUE(test, !memcmp(in, &emu->params[1], sizeof(in)));
	KUNIT_EXPECT_LE(test, emu->transactions, 3 * EM7180_WS_NUM_PARAMS + 5);
	expect_ended(test, emu);

	emu->n_log = 0;
	in[0] = 0x3F800000;
	KUNIT_ASSERT_EQ(test, test_params_write(t, 1, 1, in), 0);
	KUNIT_EXPECT_EQ(test, emu->params[1], in[0]);
	/* upstream: cal { */
	/* after the echo and the calibration registers */
	expect_xfer(test, emu, 2, true, EM7180_REG_LOAD_PARAM, NULL, 4);
	expect_xfer(test, emu, 3, true, EM7180_REG_PARAM_REQ, NULL, 1);
	/* upstream: } */
	/* upstream: !cal: expect_xfer(test, emu, 1, true, EM7180_REG_LOAD_PARAM, NULL, 4); */
	/* upstream: !cal: expect_xfer(test, emu, 2, true, EM7180_REG_PARAM_REQ, NULL, 1); */
}

/* A pointer that crosses: one burst each way, even for an echo-like value */
static void em7180_test_param_echo_value(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 val;

	KUNIT_ASSERT_EQ(test, test_pointer(t), 0);
	KUNIT_EXPECT_FALSE(test, t->data->ptr_stops);
	emu->params[3] = 0x03030303;
	emu->transactions = 0;
	KUNIT_ASSERT_EQ(test, test_params_read(t, 3, 1, &val), 0);
	KUNIT_EXPECT_EQ(test, val, 0x03030303U);
	KUNIT_EXPECT_EQ(test, emu->transactions, 2 + 4U);
}

static void em7180_test_param_range(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	u32 val;

	KUNIT_EXPECT_EQ(test, test_params_read(t, 0, 1, &val), -EINVAL);
	KUNIT_EXPECT_EQ(test, test_params_read(t, 127, 2, &val), -EINVAL);
	KUNIT_EXPECT_EQ(test, test_params_read(t, 1, 0, &val), -EINVAL);
	KUNIT_EXPECT_EQ(test, t->emu.transactions, 0U);
}

static void em7180_test_float_table1(struct kunit *test)
{
	int lsb;

	KUNIT_EXPECT_EQ(test, em7180_lsb_to_float_g(-47), 0xBCBBE447U);
	KUNIT_EXPECT_EQ(test, em7180_lsb_to_float_g(-15), 0xBBEFDC9CU);
	KUNIT_EXPECT_EQ(test, em7180_lsb_to_float_g(46), 0x3CB7E4DEU);

	KUNIT_EXPECT_EQ(test, em7180_float_g_to_lsb(0xBCBBE447, &lsb), 0);
	KUNIT_EXPECT_EQ(test, lsb, -47);
	KUNIT_EXPECT_EQ(test, em7180_float_g_to_lsb(0xBBEFDC9C, &lsb), 0);
	KUNIT_EXPECT_EQ(test, lsb, -15);
	KUNIT_EXPECT_EQ(test, em7180_float_g_to_lsb(0x3CB7E4DE, &lsb), 0);
	KUNIT_EXPECT_EQ(test, lsb, 46);
}

static void em7180_test_float_lsb(struct kunit *test)
{
	int lsb, back;

	KUNIT_EXPECT_EQ(test, em7180_lsb_to_float_g(0), 0U);
	KUNIT_EXPECT_EQ(test, em7180_lsb_to_float_g(1), 0x39FFDA40U);
	KUNIT_EXPECT_EQ(test, em7180_lsb_to_float_g(-1), 0xB9FFDA40U);
	KUNIT_EXPECT_EQ(test, em7180_lsb_to_float_g(S16_MAX), 0x417FD841U);
	KUNIT_EXPECT_EQ(test, em7180_lsb_to_float_g(S16_MIN), 0xC17FDA40U);

	for (lsb = S16_MIN; lsb <= S16_MAX; lsb++) {
		back = lsb + 1;
		if (em7180_float_g_to_lsb(em7180_lsb_to_float_g(lsb), &back) ||
		    back != lsb) {
			KUNIT_FAIL(test, "%d LSB came back as %d", lsb, back);
			break;
		}
	}
}

static void em7180_test_float_rounding(struct kunit *test)
{
	static const struct {
		u32 bits;
		int lsb;
	} cases[] = {
		{ 0x397ECDD1, 0 },	/* 0.000243 g = 0.498 LSB */
		{ 0x39807358, 1 },	/* 0.000245 g = 0.502 LSB */
		{ 0xB9807358, -1 },
		{ 0x3A3FE3B0, 1 },	/* 1.49999997 LSB */
		{ 0x3A3FEA66, 2 },	/* 1.5002 LSB */
		{ 0x3F800000, 2049 },	/* 1 g = 2049.18 LSB */
		{ 0x80000000, 0 },	/* -0 */
		{ 0x00000001, 0 },	/* smallest subnormal */
	};
	static const u32 bad[] = {
		0x7FC00000, 0xFFC00000, 0x7F800001,	/* NaN */
		0x7F800000, 0xFF800000,			/* +-Inf */
		0x49000000, 0xC9000000,			/* +-2^19 g */
	};
	unsigned int i;
	int lsb;

	for (i = 0; i < ARRAY_SIZE(cases); i++) {
		KUNIT_EXPECT_EQ(test, em7180_float_g_to_lsb(cases[i].bits, &lsb), 0);
		KUNIT_EXPECT_EQ_MSG(test, lsb, cases[i].lsb, "0x%08x", cases[i].bits);
	}
	for (i = 0; i < ARRAY_SIZE(bad); i++)
		KUNIT_EXPECT_EQ_MSG(test, em7180_float_g_to_lsb(bad[i], &lsb),
				    -ERANGE, "0x%08x", bad[i]);
}

static void em7180_test_float_fixed(struct kunit *test)
{
	/* Q30: the full precision of a float32 near 1 */
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x3F800000, 30), 1 << 30);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0xBF800000, 30), -(1 << 30));
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x3F000000, 30), 1 << 29);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x3F7FFFFF, 30), (1 << 30) - 64);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x3F3504F3, 30), 759250112);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x30000000, 30), 1);	/* 2^-31 */
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x2F800000, 30), 0);	/* 2^-32 */
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x40000000, 30), S32_MAX);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0xFF800000, 30), S32_MIN);

	/* Q14, the driver's quaternion format */
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x3F800000, 14), 16384);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0xBF800000, 14), -16384);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x3F3504F3, 14), 11585);	/* 0.7071 */
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0xBF3504F3, 14), -11585);
	/* 2^-15 is half an LSB: rounded away from zero */
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x38000000, 14), 1);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0xB8000000, 14), -1);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x37FFFFFF, 14), 0);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x46FFFE00, 14), 32767 << 14);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x47FFFFFF, 14), S32_MAX - 127);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x48000000, 14), S32_MAX);	/* 2^17 */
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0xC8000000, 14), S32_MIN);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x7F800000, 14), S32_MAX);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x00000000, 14), 0);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x80000000, 14), 0);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x00000001, 14), 0);
	KUNIT_EXPECT_EQ(test, em7180_float_to_fixed(0x7FC00000, 14), 0);	/* NaN */
}

/* upstream: cal { */
static void em7180_test_score(struct kunit *test)
{
	static const struct {
		u16 raw;
		int milli;
	} cases[] = {
		{ 0x0000, -100000 },
		{ 0x8000, 0 },
		{ 0xFFFF, 99997 },
		{ 0x83BC, 2917 },
		{ 0x7FFF, -3 },
		{ 0x8001, 3 },
		{ 0xBFFF, 49997 },	/* 49.99695: rounded up */
	};
	unsigned int i;

	for (i = 0; i < ARRAY_SIZE(cases); i++)
		KUNIT_EXPECT_EQ_MSG(test, em7180_score_milli(cases[i].raw),
				    cases[i].milli, "raw 0x%04x", cases[i].raw);
}

/* upstream: } */
/* The header of a blob read from ProductID 0x80 RevisionID 0x02 ROM 0x09E6 RAM 0x0D17 */
static const u8 test_caldata_id[] = { 1, 0x80, 0x02, 0, 0xE6, 0x09, 0x17, 0x0D };

/* The driver holds the identity test_caldata_id has */
static void test_identity(struct em7180_data *data)
{
	data->product_id = 0x80;
	data->revision_id = 0x02;
	data->rom_version = 0x09E6;
	data->ram_version = 0x0D17;
}

static void em7180_test_warmstart_check(struct kunit *test)
{
	static const u32 bad[] = {
		0x7FC00000, 0xFFFFFFFF, 0x7F800001, 0x7F800000, 0xFF800000,
	};
	u8 *blob;
	size_t size;
	unsigned int i, p;

	blob = kunit_kzalloc(test, 256, GFP_KERNEL);
	KUNIT_ASSERT_NOT_NULL(test, blob);

	KUNIT_EXPECT_EQ(test, EM7180_CALDATA_SIZE, 148);
	for (size = 0; size <= 200; size++) {
		KUNIT_EXPECT_EQ_MSG(test, em7180_warmstart_check(blob, 0, size, true),
				    size == EM7180_CALDATA_SIZE ? 0 : -EINVAL,
				    "write of %zu bytes", size);
		KUNIT_EXPECT_EQ_MSG(test, em7180_warmstart_check(NULL, 0, size, false),
				    size >= EM7180_CALDATA_SIZE ? 0 : -EINVAL,
				    "read of %zu bytes", size);
	}

	for (p = 1; p <= EM7180_CALDATA_SIZE; p += 19) {
		KUNIT_EXPECT_EQ(test, em7180_warmstart_check(blob, p, EM7180_CALDATA_SIZE, true),
				-EINVAL);
		KUNIT_EXPECT_EQ(test, em7180_warmstart_check(NULL, p, EM7180_CALDATA_SIZE, false),
				-EINVAL);
	}

	/* Largest finite, subnormal, -0 and 1.0 are all fine; the header any */
	memset(blob, 0xFF, sizeof(struct em7180_caldata_id));
	put_unaligned_le32(0x7F7FFFFF, &blob[8]);
	put_unaligned_le32(0x00000001, &blob[12]);
	put_unaligned_le32(0x80000000, &blob[16]);
	put_unaligned_le32(0x3F800000, &blob[144]);
	size = EM7180_CALDATA_SIZE;
	KUNIT_EXPECT_EQ(test, em7180_warmstart_check(blob, 0, size, true), 0);

	for (p = 0; p < EM7180_WS_NUM_PARAMS; p++) {
		for (i = 0; i < ARRAY_SIZE(bad); i++) {
			u32 old = get_unaligned_le32(&blob[8 + 4 * p]);

			put_unaligned_le32(bad[i], &blob[8 + 4 * p]);
			KUNIT_EXPECT_EQ_MSG(test,
					    em7180_warmstart_check(blob, 0, size, true),
					    -EINVAL, "param %u = 0x%08x", p + 1, bad[i]);
			put_unaligned_le32(old, &blob[8 + 4 * p]);
		}
	}
}

#define WS_FUZZ_SEED		0x7180
#define WS_FUZZ_ROUNDS		400
#define WS_FUZZ_BUF		(2 * EM7180_CALDATA_SIZE + 64)

enum ws_fuzz_kind {
	WS_FUZZ_VALID,
	WS_FUZZ_SIZE,
	WS_FUZZ_OFFSET,
	WS_FUZZ_NOT_FINITE,
	WS_FUZZ_IDENTITY,
	WS_FUZZ_KINDS
};

/* A random float32 that is not NaN or infinite: any sign, exponent 0..254 */
static u32 ws_fuzz_finite(struct rnd_state *rnd)
{
	u32 v = prandom_u32_state(rnd);

	if ((v & 0x7F800000) == 0x7F800000)
		v &= ~BIT(23 + prandom_u32_state(rnd) % 8);
	return v;
}

/* NaN (quiet or signalling) or an infinity of either sign */
static u32 ws_fuzz_not_finite(struct rnd_state *rnd)
{
	u32 v = prandom_u32_state(rnd);

	switch (v % 3) {
	case 0:
		return (v & BIT(31)) | 0x7F800000;
	case 1:
		return v | 0x7FC00000;
	default:
		return v | 0x7F800001;
	}
}

/*
 * The warmstart write path with a fixed-seed sequence of blobs: valid ones,
 * wrong sizes, wrong offsets, non-finite values and another chip's or
 * firmware's header. A refused write must not reach the bus at all; an
 * accepted one must leave exactly the blob in parameters 1..35 and the
 * chip out of transfer mode.
 */
static void em7180_test_warmstart_fuzz(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	unsigned int round, i, n, kinds[WS_FUZZ_KINDS] = { };
	u32 before[EM7180_PARAM_MAX + 1];
	struct em7180_data *data;
	struct iio_dev *indio_dev;
	struct rnd_state rnd;
	enum ws_fuzz_kind kind;
	size_t count;
	loff_t off;
	u8 *buf;
	int ret;

	buf = kunit_kzalloc(test, WS_FUZZ_BUF, GFP_KERNEL);
	KUNIT_ASSERT_NOT_NULL(test, buf);

	/* An unregistered IIO device around the emulated chip's regmap */
	indio_dev = devm_iio_device_alloc(t->dev, sizeof(*data));
	KUNIT_ASSERT_NOT_NULL(test, indio_dev);
	data = iio_priv(indio_dev);
	data->dev = t->dev;
	data->regmap = t->data->regmap;
	test_identity(data);
	mutex_init(&data->lock);

	prandom_seed_state(&rnd, WS_FUZZ_SEED);
	for (round = 0; round < WS_FUZZ_ROUNDS; round++) {
		kind = prandom_u32_state(&rnd) % WS_FUZZ_KINDS;
		kinds[kind]++;
		count = EM7180_CALDATA_SIZE;
		off = 0;
		for (i = 0; i + 4 <= WS_FUZZ_BUF; i += 4)
			put_unaligned_le32(ws_fuzz_finite(&rnd), &buf[i]);
		memcpy(buf, test_caldata_id, sizeof(test_caldata_id));

		switch (kind) {
		case WS_FUZZ_SIZE:
			/* Near the right size half of the time, else anywhere */
			if (prandom_u32_state(&rnd) & 1)
				count = EM7180_CALDATA_SIZE - 8 +
					prandom_u32_state(&rnd) % 17;
			else
				count = prandom_u32_state(&rnd) % WS_FUZZ_BUF;
			if (count == EM7180_CALDATA_SIZE)
				count++;
			break;
		case WS_FUZZ_OFFSET:
			off = 1 + prandom_u32_state(&rnd) % (4 * EM7180_CALDATA_SIZE);
			if (prandom_u32_state(&rnd) & 1)
				count = 1 + prandom_u32_state(&rnd) %
					    (WS_FUZZ_BUF - 1);
			break;
		case WS_FUZZ_NOT_FINITE:
			n = 1 + prandom_u32_state(&rnd) % 3;
			while (n--)
				put_unaligned_le32(ws_fuzz_not_finite(&rnd),
						   &buf[8 + 4 * (prandom_u32_state(&rnd) %
								 EM7180_WS_NUM_PARAMS)]);
			break;
		case WS_FUZZ_IDENTITY:
			/* Any bit of the header, reserved byte included */
			n = prandom_u32_state(&rnd) % (8 * sizeof(test_caldata_id));
			buf[n / 8] ^= BIT(n % 8);
			break;
		default:
			break;
		}

		memcpy(before, emu->params, sizeof(before));
		emu->transactions = 0;
		emu->n_log = 0;
		ret = em7180_warmstart_restore(indio_dev, buf, off, count);

		if (kind != WS_FUZZ_VALID) {
			KUNIT_EXPECT_EQ_MSG(test, ret, -EINVAL,
					    "round %u: kind %d, %zu bytes at %lld",
					    round, kind, count, off);
			KUNIT_EXPECT_EQ_MSG(test, emu->transactions, 0U,
					    "round %u: refused write reached the bus",
					    round);
			KUNIT_EXPECT_TRUE_MSG(test,
					      !memcmp(before, emu->params, sizeof(before)),
					      "round %u: parameters changed", round);
			continue;
		}

		KUNIT_EXPECT_EQ_MSG(test, ret, 0, "round %u", round);
		KUNIT_EXPECT_LE_MSG(test, emu->transactions,
				    2 * EM7180_WS_NUM_PARAMS + 4, "round %u", round);
		for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
			KUNIT_EXPECT_EQ_MSG(test, emu->params[i + 1],
					    get_unaligned_le32(&buf[8 + 4 * i]),
					    "round %u: parameter %u", round, i + 1);
		KUNIT_EXPECT_TRUE_MSG(test,
				      !memcmp(&before[EM7180_WS_NUM_PARAMS + 1],
					      &emu->params[EM7180_WS_NUM_PARAMS + 1],
					      sizeof(before) - sizeof(before[0]) *
					      (EM7180_WS_NUM_PARAMS + 1)),
				      "round %u: a parameter beyond 35 changed", round);
		KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_ALGO_CTRL], 0);
		KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_PARAM_REQ], 0);
		KUNIT_EXPECT_TRUE(test, data->ws_valid &&
				  !memcmp(data->ws, &buf[8], EM7180_WS_SIZE));
	}

	/* The seed gives every kind of input a fair share */
	for (i = 0; i < WS_FUZZ_KINDS; i++)
		KUNIT_EXPECT_GE_MSG(test, kinds[i], WS_FUZZ_ROUNDS / 8,
				    "kind %u", i);
}

/* Configuration as probe leaves it, through the register cache */
static void test_configure(struct kunit *test, struct em7180_test *t)
{
	static const struct reg_sequence cfg[] = {
		{ EM7180_REG_MAG_RATE, 30 },
		{ EM7180_REG_ACCEL_RATE, 10 },
		{ EM7180_REG_GYRO_RATE, 20 },
		{ EM7180_REG_QRATE_DIVISOR, 0 },
		{ EM7180_REG_ENABLE_EVENTS, EM7180_EVENT_ERROR },
		{ EM7180_REG_HOST_CTRL, EM7180_HOST_CTRL_RUN },
		{ EM7180_REG_ALGO_CTRL, 0 },
	};
	unsigned int i;

	KUNIT_ASSERT_EQ(test, regmap_multi_reg_write(t->data->regmap, cfg,
						     ARRAY_SIZE(cfg)), 0);
	/* The chip holds, and the driver knows, a restored warm start */
	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++) {
		put_unaligned_le32(0x3F800000 + i, &t->data->ws[4 * i]);
		t->emu.params[i + 1] = 0x3F800000 + i;
	}
	t->data->ws_valid = true;
	test_identity(t->data);
	/* Running: upload done, CPU executing */
	t->emu.regs[EM7180_REG_SENTRAL_STATUS] = 0x03;
}

/*
 * A standby the chip never confirms: suspend does not fail with the
 * algorithm halted (the PM core would not resume it); resume runs it.
 */
static void em7180_test_pm_standby_stuck(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	int ret;

	test_configure(test, t);
	emu->standby_stuck = true;
	ret = em7180_chip_suspend(t->data);
	if (ret)
		KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_ALGO_CTRL], 0);
	else
		KUNIT_EXPECT_EQ(test, em7180_chip_resume(t->data), 0);
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_ALGO_CTRL], 0);
}

/* calibbias reads never reach the bus, and fail while the copy is unknown */
static void em7180_test_calibbias_copy(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	int lsb;

	t->data->accel_offset_valid = false;
	KUNIT_EXPECT_EQ(test, em7180_read_calibbias(t->data, 1, &lsb), -ENODATA);
	KUNIT_EXPECT_EQ(test, emu->transactions, 0U);

	/* A write while the copy is unknown reads the offsets back */
	emu->params[29] = 0x3CB7E4DE;
	KUNIT_ASSERT_EQ(test, em7180_write_calibbias(t->data, 0, -47), 0);
	emu->transactions = 0;
	KUNIT_ASSERT_EQ(test, em7180_read_calibbias(t->data, 0, &lsb), 0);
	KUNIT_EXPECT_EQ(test, lsb, -47);
	KUNIT_ASSERT_EQ(test, em7180_read_calibbias(t->data, 2, &lsb), 0);
	KUNIT_EXPECT_EQ(test, lsb, 46);
	KUNIT_EXPECT_EQ(test, emu->transactions, 0U);
}

/*
 * A calibration_data read never returns a blob that the write path
 * refuses: a non-finite parameter fails it with -EIO, leaving the caller's
 * buffer and the driver's valid copy as they were; a finite one succeeds.
 */
static void em7180_test_ws_read_nonfinite(struct kunit *test)
{
	static const u32 bad[] = { 0x7FC00000, 0x7F800000, 0xFF800000,
				   0xFFFFFFFF };
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u8 buf[EM7180_CALDATA_SIZE], ws[EM7180_WS_SIZE];
	unsigned int i, n;
	int ret;

	test_configure(test, t);
	memcpy(ws, t->data->ws, sizeof(ws));
	for (i = 0; i < ARRAY_SIZE(bad); i++) {
		n = 1 + 17 * i % EM7180_WS_NUM_PARAMS;
		emu->params[n] = bad[i];
		emu->n_log = 0;
		memset(buf, 0xAA, sizeof(buf));
		scoped_guard(mutex, &t->data->lock)
			ret = em7180_warmstart_read(t->data, (void *)buf);
		KUNIT_EXPECT_EQ_MSG(test, ret, -EIO, "0x%08x", bad[i]);
		KUNIT_EXPECT_NULL(test, memchr_inv(buf, 0xAA, sizeof(buf)));
		KUNIT_EXPECT_TRUE(test, t->data->ws_valid);
		KUNIT_EXPECT_EQ(test, memcmp(t->data->ws, ws, sizeof(ws)), 0);
		expect_ended(test, emu);
		emu->params[n] = 0x3F800000 + n - 1;
	}

	emu->params[35] = 0x80000001;	/* -0 and subnormals are finite */
	scoped_guard(mutex, &t->data->lock)
		ret = em7180_warmstart_read(t->data, (void *)buf);
	KUNIT_ASSERT_EQ(test, ret, 0);
	KUNIT_EXPECT_EQ(test, em7180_warmstart_check(buf, 0, sizeof(buf), true), 0);
	KUNIT_EXPECT_EQ(test, get_unaligned_le32(&buf[8 + 4 * 34]), 0x80000001U);
	KUNIT_EXPECT_EQ(test, memcmp(t->data->ws, &buf[8], EM7180_WS_SIZE), 0);
}

/* upstream: health { */
/* Power lost: registers and parameters gone, CPU in standby */
static void test_power_loss(struct em7180_emu *emu)
{
	memset(emu->regs, 0, sizeof(emu->regs));
	memset(emu->params, 0, sizeof(emu->params));
	emu->regs[EM7180_REG_SENTRAL_STATUS] = 0x0B;
	/* The firmware uploaded again may be another one */
	emu->regs[EM7180_REG_ROM_VERSION] = 0xE6;
	emu->regs[EM7180_REG_ROM_VERSION + 1] = 0x09;
	emu->regs[EM7180_REG_RAM_VERSION] = 0x17;
	emu->regs[EM7180_REG_RAM_VERSION + 1] = 0x0D;
}

/* The state test_configure() set up, back on the chip */
static void expect_restored(struct kunit *test, struct em7180_test *t,
			    unsigned int nack)
{
	struct em7180_emu *emu = &t->emu;
	unsigned int i;

	KUNIT_EXPECT_EQ_MSG(test, emu->regs[EM7180_REG_MAG_RATE], 30, "NACK at %u", nack);
	KUNIT_EXPECT_EQ_MSG(test, emu->regs[EM7180_REG_ACCEL_RATE], 10, "NACK at %u", nack);
	KUNIT_EXPECT_EQ_MSG(test, emu->regs[EM7180_REG_GYRO_RATE], 20, "NACK at %u", nack);
	KUNIT_EXPECT_EQ_MSG(test, emu->regs[EM7180_REG_ENABLE_EVENTS],
			    EM7180_EVENT_ERROR, "NACK at %u", nack);
	KUNIT_EXPECT_EQ_MSG(test, emu->regs[EM7180_REG_HOST_CTRL],
			    EM7180_HOST_CTRL_RUN, "NACK at %u", nack);
	KUNIT_EXPECT_EQ_MSG(test, emu->regs[EM7180_REG_ALGO_CTRL], 0, "NACK at %u", nack);
	KUNIT_EXPECT_EQ_MSG(test, emu->regs[EM7180_REG_PARAM_REQ], 0, "NACK at %u", nack);
	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		KUNIT_EXPECT_EQ_MSG(test, emu->params[i + 1], 0x3F800000 + i,
				    "NACK at %u: parameter %u", nack, i + 1);
}

static void em7180_test_pm_power_loss(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;

	test_configure(test, t);

	KUNIT_ASSERT_EQ(test, em7180_chip_suspend(t->data), 0);
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_ALGO_CTRL],
			EM7180_ALGO_CTRL_STANDBY);

	test_power_loss(emu);

	KUNIT_ASSERT_EQ(test, em7180_chip_resume(t->data), 0);
	KUNIT_EXPECT_EQ(test, t->data->rom_version, 0x09E6);
	KUNIT_EXPECT_EQ(test, t->data->ram_version, 0x0D17);
	expect_restored(test, t, 0);
	expect_ended(test, emu);
}

/*
 * A bus error at each transaction of a resume after a power loss, in turn:
 * the resume is retried once, so each single error is recovered.
 */
static void em7180_test_pm_power_loss_nack(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	unsigned int n, clean = 0;

	test_configure(test, t);
	KUNIT_ASSERT_EQ(test, em7180_chip_suspend(t->data), 0);

	for (n = 0; n <= clean; n++) {
		test_power_loss(emu);
		emu->transactions = 0;
		emu->nack_at = n;
		KUNIT_EXPECT_EQ_MSG(test, em7180_chip_resume(t->data), 0,
				    "NACK at %u", n);
		expect_restored(test, t, n);
		emu->n_log = 0;
		if (!n)
			clean = emu->transactions;
		KUNIT_ASSERT_LT(test, n, 200U);
	}
	KUNIT_EXPECT_GT(test, clean, 2 * EM7180_WS_NUM_PARAMS + 3);
}

/* What the chip learned since boot is what comes back after a power loss */
static void em7180_test_pm_live_calibration(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;

	test_configure(test, t);
	emu->params[18] = 0x3F666666;	/* a learned soft-iron gain */

	KUNIT_ASSERT_EQ(test, em7180_chip_suspend(t->data), 0);
	test_power_loss(emu);
	KUNIT_ASSERT_EQ(test, em7180_chip_resume(t->data), 0);
	KUNIT_EXPECT_EQ(test, emu->params[18], 0x3F666666U);
	KUNIT_EXPECT_EQ(test, emu->params[19], 0x3F800000U + 18);
	expect_ended(test, emu);
}

/*
 * Offsets written while no warm start is known (its read at suspend
 * failed) come back too.
 */
static void em7180_test_pm_offsets_without_ws(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	int lsb;

	test_configure(test, t);
	t->data->ws_valid = false;
	t->data->accel_offset_valid = true;
	KUNIT_ASSERT_EQ(test, em7180_write_calibbias(t->data, 0, -47), 0);

	emu->ack_never = true;
	KUNIT_EXPECT_EQ(test, em7180_chip_suspend(t->data), 0);
	emu->ack_never = false;
	test_power_loss(emu);
	KUNIT_ASSERT_EQ(test, em7180_chip_resume(t->data), 0);
	KUNIT_EXPECT_EQ(test, emu->params[27], 0xBCBBE447U);
	KUNIT_ASSERT_EQ(test, em7180_read_calibbias(t->data, 0, &lsb), 0);
	KUNIT_EXPECT_EQ(test, lsb, -47);
}

/* Configure while HostControl is 0: the rates before HostControl = RUN */
static void em7180_test_pm_restore_order(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	unsigned int i, run = 0, last_rate = 0;

	test_configure(test, t);
	KUNIT_ASSERT_EQ(test, em7180_chip_suspend(t->data), 0);
	test_power_loss(emu);
	emu->n_log = 0;
	KUNIT_ASSERT_EQ(test, em7180_chip_resume(t->data), 0);

	for (i = 0; i < emu->n_log; i++) {
		const struct emu_xfer *x = &emu->log[i];

		if (!x->write)
			continue;
		if (x->reg <= EM7180_REG_HOST_CTRL &&
		    x->reg + x->len > EM7180_REG_HOST_CTRL)
			run = i;
		if (x->reg <= EM7180_REG_GYRO_RATE &&
		    x->reg + x->len > EM7180_REG_MAG_RATE)
			last_rate = i;
	}
	KUNIT_EXPECT_GT(test, run, 0U);
	KUNIT_EXPECT_GT(test, last_rate, 0U);
	KUNIT_EXPECT_LT(test, last_rate, run);
	expect_restored(test, t, 0);
}

/*
 * A power loss that brings other firmware: the warm start of the old one
 * is not written (sentral-warmstart refuses such a file too).
 */
static void em7180_test_pm_firmware_changed(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	unsigned int i;

	test_configure(test, t);
	KUNIT_ASSERT_EQ(test, em7180_chip_suspend(t->data), 0);
	test_power_loss(emu);
	emu->regs[EM7180_REG_RAM_VERSION] = 0x18;

	KUNIT_ASSERT_EQ(test, em7180_chip_resume(t->data), 0);
	KUNIT_EXPECT_EQ(test, t->data->ram_version, 0x0D18);
	for (i = 1; i <= EM7180_WS_NUM_PARAMS; i++)
		KUNIT_EXPECT_EQ_MSG(test, emu->params[i], 0U, "parameter %u", i);
	KUNIT_EXPECT_FALSE(test, t->data->ws_valid);
	/* all zero 0x43-0x4E is no score: the attributes stay, read ENODATA */
	KUNIT_EXPECT_FALSE(test, t->data->appnote);
	KUNIT_EXPECT_TRUE(test, t->data->appnote_attrs);
	/* configured and running all the same */
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_HOST_CTRL], EM7180_HOST_CTRL_RUN);
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_MAG_RATE], 30);
}

/*
 * A recovery whose transfer cannot be ended queues another. The teardown
 * of unbind runs the pending one and leaves none to run after the device
 * is freed: nothing pending, no bus access after it.
 */
static void em7180_test_recover_teardown(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_data *data = t->data;
	struct em7180_emu *emu = &t->emu;
	struct device *dev;
	unsigned int seen;

	dev = kunit_device_register(test, "em7180-kunit-health");
	KUNIT_ASSERT_NOT_ERR_OR_NULL(test, dev);
	dev_set_drvdata(dev, t->indio_dev);
	data->dev = dev;
	KUNIT_ASSERT_EQ(test, em7180_health_init(data), 0);

	test_configure(test, t);
	test_power_loss(emu);
	emu->end_nacks = UINT_MAX;
	scoped_guard(mutex, &data->lock)
		em7180_recover_schedule(data);

	/* Runs the device's devm actions, as unbind does */
	kunit_device_unregister(test, dev);
	data->dev = t->dev;
	seen = emu->transactions;
	KUNIT_EXPECT_GE(test, data->resets, 1U);
	KUNIT_EXPECT_TRUE(test, data->xfer_stuck);
	KUNIT_EXPECT_FALSE(test, delayed_work_pending(&data->recover_work));
	/* The one it would have queued: 50 ms later */
	msleep(200);
	KUNIT_EXPECT_EQ(test, emu->transactions, seen);
}

/*
 * The same across system sleep: suspend runs the recovery pending, which
 * queues another; none runs while asleep, where it would end the standby,
 * and recoveries are queued again after the resume.
 */
static void em7180_test_recover_suspend(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	struct em7180_data *data;
	struct iio_dev *indio_dev;
	struct device *dev;
	unsigned int seen;

	if (!IS_ENABLED(CONFIG_PM_SLEEP))
		kunit_skip(test, "no system sleep in this kernel");

	test_configure(test, t);
	dev = kunit_device_register(test, "em7180-kunit-pm");
	KUNIT_ASSERT_NOT_ERR_OR_NULL(test, dev);
	/* The driver's state in an IIO device, as probe leaves it */
	indio_dev = devm_iio_device_alloc(dev, sizeof(*data));
	KUNIT_ASSERT_NOT_NULL(test, indio_dev);
	data = iio_priv(indio_dev);
	data->dev = dev;
	data->regmap = t->data->regmap;
	data->appnote_attrs = true;
	data->appnote = true;
	memcpy(data->ws, t->data->ws, sizeof(data->ws));
	data->ws_valid = true;
	data->rom_version = t->data->rom_version;
	data->ram_version = t->data->ram_version;
	mutex_init(&data->lock);
	dev_set_drvdata(dev, indio_dev);
	KUNIT_EXPECT_EQ(test, em7180_health_init(data), 0);

	test_power_loss(emu);
	/* The end of the restore's transfer */
	emu->end_nacks = 1;
	scoped_guard(mutex, &data->lock)
		em7180_recover_schedule(data);
	KUNIT_EXPECT_EQ(test, em7180_pm_ops.suspend(dev), 0);
	seen = emu->transactions;
	KUNIT_EXPECT_EQ(test, data->resets, 1U);
	KUNIT_EXPECT_TRUE(test, data->xfer_stuck);
	KUNIT_EXPECT_FALSE(test, delayed_work_pending(&data->recover_work));
	/* The one it would have queued: 50 ms later */
	msleep(200);
	KUNIT_EXPECT_EQ(test, emu->transactions, seen);
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_ALGO_CTRL],
			EM7180_ALGO_CTRL_STANDBY);

	KUNIT_EXPECT_EQ(test, em7180_pm_ops.resume(dev), 0);
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_ALGO_CTRL], 0);
	/* Ended: a later reset gets a whole recovery, not just that end */
	KUNIT_EXPECT_FALSE(test, data->xfer_stuck);
	scoped_guard(mutex, &data->lock)
		em7180_recover_schedule(data);
	KUNIT_EXPECT_TRUE(test, delayed_work_pending(&data->recover_work));
}

/*
 * A parameter that is no finite float, met at suspend, does not replace
 * the last valid warm start: that one comes back after a power loss.
 */
static void em7180_test_pm_nonfinite_keeps_ws(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;

	test_configure(test, t);
	emu->params[10] = 0x7FC00000;	/* NaN */

	KUNIT_ASSERT_EQ(test, em7180_chip_suspend(t->data), 0);
	KUNIT_EXPECT_TRUE(test, t->data->ws_valid);
	test_power_loss(emu);
	KUNIT_ASSERT_EQ(test, em7180_chip_resume(t->data), 0);
	expect_restored(test, t, 0);
	expect_ended(test, emu);
}

static void em7180_test_pm_no_power_loss(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	static const u8 run;

	test_configure(test, t);

	KUNIT_ASSERT_EQ(test, em7180_chip_suspend(t->data), 0);
	emu->n_log = 0;
	emu->transactions = 0;
	KUNIT_ASSERT_EQ(test, em7180_chip_resume(t->data), 0);

	/* SentralStatus, then the algorithm out of standby: nothing else */
	KUNIT_ASSERT_EQ(test, emu->transactions, 2U);
	expect_xfer(test, emu, 0, false, EM7180_REG_SENTRAL_STATUS, NULL, 1);
	expect_xfer(test, emu, 1, true, EM7180_REG_ALGO_CTRL, &run, 1);
}

/* upstream: } */
static int test_caldata_apply(struct em7180_test *t, const u8 *blob,
			      size_t size)
{
	guard(mutex)(&t->data->lock);
	return em7180_caldata_apply(t->data, blob, size, "caldata-kunit.bin");
}

/*
 * A saved blob of the chip the driver holds: parameter n is 2.0 + n,
 * Table 1's offsets in 27..29
 */
static void test_caldata_blob(struct em7180_test *t, u8 *blob)
{
	static const u32 table1[] = { 0xBCBBE447, 0xBBEFDC9C, 0x3CB7E4DE };
	unsigned int i;

	test_identity(t->data);
	memcpy(blob, test_caldata_id, sizeof(test_caldata_id));
	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		put_unaligned_le32(0x40000000 + i, &blob[8 + 4 * i]);
	for (i = 0; i < ARRAY_SIZE(table1); i++)
		put_unaligned_le32(table1[i], &blob[8 + 4 * (26 + i)]);
}

/*
 * The restore at probe: one parameter write of all 35 and nothing else
 * (the offsets come from the blob, not from a read), kept for a power
 * loss.
 */
static void em7180_test_caldata_apply(struct kunit *test)
{
	static const int lsb[] = { -47, -15, 46 };
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u32 vals[EM7180_WS_NUM_PARAMS];
	u8 blob[EM7180_CALDATA_SIZE];
	unsigned int i;
	int val;

	test_caldata_blob(t, blob);
	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		vals[i] = get_unaligned_le32(&blob[8 + 4 * i]);
	/* upstream: cal { */
	/* The update flags go with the state replaced */
	t->data->cal.flags = EM7180_CAL_FLAG_MAG_UPDATE;
	t->data->cal.valid = true;
	/* upstream: } */

	KUNIT_ASSERT_EQ(test, test_caldata_apply(t, blob, sizeof(blob)), 0);
	KUNIT_EXPECT_EQ(test, emu->transactions, 2 * EM7180_WS_NUM_PARAMS + 4);
	expect_bursts(test, emu, vals, EM7180_WS_NUM_PARAMS);
	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		KUNIT_EXPECT_EQ_MSG(test, emu->params[i + 1], vals[i],
				    "parameter %u", i + 1);
	expect_ended(test, emu);

	KUNIT_EXPECT_TRUE(test, t->data->ws_valid);
	KUNIT_EXPECT_EQ(test, memcmp(t->data->ws, &blob[8], EM7180_WS_SIZE), 0);
	/* upstream: cal { */
	KUNIT_EXPECT_EQ(test, t->data->cal.flags, 0);
	KUNIT_EXPECT_FALSE(test, t->data->cal.valid);
	/* upstream: } */

	/* calibbias from the blob, without the bus */
	emu->transactions = 0;
	for (i = 0; i < ARRAY_SIZE(lsb); i++) {
		KUNIT_ASSERT_EQ(test, em7180_read_calibbias(t->data, i, &val), 0);
		KUNIT_EXPECT_EQ(test, val, lsb[i]);
	}
	KUNIT_EXPECT_EQ(test, emu->transactions, 0U);
}

/*
 * A file calibration_data would refuse (a size other than 148, a value
 * that is no finite float) is refused before the chip is touched; the
 * 140 bytes of the blob without its header too.
 */
static void em7180_test_caldata_refused(struct kunit *test)
{
	static const size_t sizes[] = { 0, 4, EM7180_WS_SIZE,
					EM7180_CALDATA_SIZE - 1,
					EM7180_CALDATA_SIZE + 1,
					2 * EM7180_CALDATA_SIZE };
	static const u32 bad[] = { 0x7FC00000, 0x7F800000, 0xFF800000 };
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u8 blob[2 * EM7180_CALDATA_SIZE];
	unsigned int i;

	test_caldata_blob(t, blob);
	test_caldata_blob(t, &blob[EM7180_CALDATA_SIZE]);
	for (i = 0; i < ARRAY_SIZE(sizes); i++)
		KUNIT_EXPECT_EQ_MSG(test, test_caldata_apply(t, blob, sizes[i]),
				    -EINVAL, "%zu bytes", sizes[i]);
	for (i = 0; i < ARRAY_SIZE(bad); i++) {
		test_caldata_blob(t, blob);
		put_unaligned_le32(bad[i], &blob[8 + 4 * (11 * i + 4)]);
		KUNIT_EXPECT_EQ_MSG(test, test_caldata_apply(t, blob, EM7180_CALDATA_SIZE),
				    -EINVAL, "0x%08x", bad[i]);
	}
	KUNIT_EXPECT_EQ(test, emu->transactions, 0U);
	KUNIT_EXPECT_FALSE(test, t->data->ws_valid);
	KUNIT_EXPECT_FALSE(test, t->data->accel_offset_valid);
}

/*
 * A transfer that fails: nothing kept for a power loss; after a bus error
 * the offsets are read back (the chip may hold some of the new ones),
 * after a timeout they stay unknown.
 */
static void em7180_test_caldata_fails(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u8 blob[EM7180_CALDATA_SIZE];
	int val;

	test_caldata_blob(t, blob);
	emu->ack_never = true;
	KUNIT_EXPECT_EQ(test, test_caldata_apply(t, blob, sizeof(blob)),
			-ETIMEDOUT);
	/* Ended; two seconds of polls may have filled the log */
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_PARAM_REQ], 0);
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_ALGO_CTRL], 0);
	KUNIT_EXPECT_FALSE(test, t->data->ws_valid);
	KUNIT_EXPECT_EQ(test, em7180_read_calibbias(t->data, 0, &val), -ENODATA);

	emu->ack_never = false;
	emu->transactions = 0;
	emu->n_log = 0;
	emu->nack_at = 20;
	KUNIT_EXPECT_EQ(test, test_caldata_apply(t, blob, sizeof(blob)), -EIO);
	expect_ended(test, emu);
	KUNIT_EXPECT_FALSE(test, t->data->ws_valid);
	KUNIT_ASSERT_EQ(test, em7180_read_calibbias(t->data, 0, &val), 0);
	KUNIT_EXPECT_EQ(test, val, 0);
}

/*
 * Another chip's or firmware's blob, a byte of the header changed in turn
 * (format, ProductID, RevisionID, the reserved byte, the ROM and RAM
 * versions): neither the file at probe nor a calibration_data write is
 * applied, and neither reaches the bus. Probe then reads the offsets.
 */
static void em7180_test_caldata_identity(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	u8 blob[EM7180_CALDATA_SIZE];
	unsigned int i;

	for (i = 0; i < sizeof(struct em7180_caldata_id); i++) {
		test_caldata_blob(t, blob);
		blob[i] ^= 0x01;
		KUNIT_EXPECT_EQ_MSG(test, test_caldata_apply(t, blob, sizeof(blob)),
				    -EINVAL, "header byte %u", i);
		KUNIT_EXPECT_EQ_MSG(test,
				    em7180_warmstart_restore(t->indio_dev, blob, 0,
							     sizeof(blob)),
				    -EINVAL, "header byte %u", i);
	}
	KUNIT_EXPECT_EQ(test, emu->transactions, 0U);
	KUNIT_EXPECT_FALSE(test, t->data->ws_valid);
	KUNIT_EXPECT_FALSE(test, t->data->accel_offset_valid);

	/* The same blob of this chip's identity is applied */
	test_caldata_blob(t, blob);
	KUNIT_EXPECT_EQ(test, em7180_warmstart_restore(t->indio_dev, blob, 0,
						       sizeof(blob)), 0);
	KUNIT_EXPECT_EQ(test, emu->params[1], 0x40000000U);
	KUNIT_EXPECT_TRUE(test, t->data->ws_valid);
}

/*
 * A calibration read carries the identity the driver holds in its 8-byte
 * header, without a bus transaction of its own: the parameter read alone,
 * as make bench counts a save. The blob read writes back as it is.
 */
static void em7180_test_caldata_read_header(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	struct em7180_caldata cal;
	u8 *buf = (u8 *)&cal;
	unsigned int i, reads;
	int ret;

	test_configure(test, t);
	emu->transactions = 0;
	emu->n_log = 0;
	memset(&cal, 0xAA, sizeof(cal));
	scoped_guard(mutex, &t->data->lock)
		ret = em7180_warmstart_read(t->data, &cal);
	KUNIT_ASSERT_EQ(test, ret, 0);
	KUNIT_EXPECT_EQ(test, memcmp(buf, test_caldata_id, sizeof(test_caldata_id)), 0);
	for (i = 0; i < EM7180_WS_NUM_PARAMS; i++)
		KUNIT_EXPECT_EQ_MSG(test, get_unaligned_le32(&buf[8 + 4 * i]),
				    0x3F800000 + i, "parameter %u", i + 1);
	reads = emu->transactions;
	KUNIT_EXPECT_EQ(test, reads, 2 * EM7180_WS_NUM_PARAMS + 4);

	/* Another firmware after a reset: the header follows at once */
	t->data->ram_version = 0x0D18;
	emu->transactions = 0;
	scoped_guard(mutex, &t->data->lock)
		ret = em7180_warmstart_read(t->data, &cal);
	KUNIT_ASSERT_EQ(test, ret, 0);
	KUNIT_EXPECT_EQ(test, get_unaligned_le16(&buf[6]), 0x0D18);
	KUNIT_EXPECT_EQ(test, emu->transactions, reads);
	t->data->ram_version = 0x0D17;

	scoped_guard(mutex, &t->data->lock)
		ret = em7180_warmstart_read(t->data, &cal);
	KUNIT_ASSERT_EQ(test, ret, 0);
	KUNIT_EXPECT_EQ(test, test_caldata_apply(t, buf, sizeof(cal)), 0);
}

/* upstream: upload { */
/* A .fw image of @len bytes of text 0x00, 0x01, ... and its CRC field */
static struct firmware *test_upload_image(struct kunit *test, u16 len,
					  u32 crc)
{
	struct firmware *fw = kunit_kzalloc(test, sizeof(*fw), GFP_KERNEL);
	u8 *img = kunit_kzalloc(test, 16 + len, GFP_KERNEL);
	unsigned int i;

	KUNIT_ASSERT_NOT_NULL(test, fw);
	KUNIT_ASSERT_NOT_NULL(test, img);
	put_unaligned_le16(0x652a, &img[0]);
	put_unaligned_le32(crc, &img[4]);
	put_unaligned_le16(len, &img[12]);
	for (i = 0; i < len; i++)
		img[16 + i] = i;
	fw->data = img;
	fw->size = 16 + len;
	return fw;
}

static int test_upload(struct em7180_test *t, int ret)
{
	guard(mutex)(&t->data->lock);
	return em7180_upload(t->data, ret);
}

/*
 * UploadAddress 0 MSB first, HostControl upload, the text in 64-byte
 * chunks with each word's bytes reversed, CRCHost, HostControl 0; the
 * register cache keeps the HostControl that resume writes back.
 */
static void em7180_test_upload_sequence(struct kunit *test)
{
	static const u8 addr[] = { 0x00, 0x00 }, upload = 0x02, stop;
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	unsigned int i, val;

	t->data->fw = test_upload_image(test, 136, 0xc0ffee01);
	t->data->fw_name = "em7180.fw";
	KUNIT_ASSERT_EQ(test, regmap_write(t->data->regmap, EM7180_REG_HOST_CTRL,
					   EM7180_HOST_CTRL_RUN), 0);
	put_unaligned_le32(0xc0ffee01, &emu->regs[EM7180_REG_CRC_HOST]);
	emu->n_log = 0;

	KUNIT_EXPECT_EQ(test, test_upload(t, -ENODEV), 0);
	KUNIT_ASSERT_EQ(test, emu->n_log, 7U);
	expect_xfer(test, emu, 0, true, EM7180_REG_UPLOAD_ADDR, addr, 2);
	expect_xfer(test, emu, 1, true, EM7180_REG_HOST_CTRL, &upload, 1);
	expect_xfer(test, emu, 2, true, EM7180_REG_UPLOAD_DATA, NULL, 64);
	expect_xfer(test, emu, 3, true, EM7180_REG_UPLOAD_DATA, NULL, 64);
	expect_xfer(test, emu, 4, true, EM7180_REG_UPLOAD_DATA, NULL, 8);
	expect_xfer(test, emu, 5, false, EM7180_REG_CRC_HOST, NULL, 4);
	expect_xfer(test, emu, 6, true, EM7180_REG_HOST_CTRL, &stop, 1);
	KUNIT_ASSERT_EQ(test, emu->upload_len, 136U);
	for (i = 0; i < 136; i++)
		KUNIT_EXPECT_EQ_MSG(test, emu->upload[i], i ^ 3, "byte %u", i);

	KUNIT_EXPECT_EQ(test, regmap_read(t->data->regmap, EM7180_REG_HOST_CTRL,
					  &val), 0);
	KUNIT_EXPECT_EQ(test, val, EM7180_HOST_CTRL_RUN);
}

/* A CRC mismatch and a bus error end upload mode all the same */
static void em7180_test_upload_errors(struct kunit *test)
{
	static const u8 stop;
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	unsigned int val;

	/* No image: a board with an EEPROM, nothing sent */
	KUNIT_EXPECT_EQ(test, test_upload(t, 0), 0);
	KUNIT_EXPECT_EQ(test, test_upload(t, -ENODEV), -ENODEV);
	KUNIT_EXPECT_EQ(test, emu->n_log, 0U);

	t->data->fw = test_upload_image(test, 256, 0xc0ffee01);
	t->data->fw_name = "em7180.fw";
	KUNIT_ASSERT_EQ(test, regmap_write(t->data->regmap, EM7180_REG_HOST_CTRL,
					   EM7180_HOST_CTRL_RUN), 0);
	put_unaligned_le32(0xc0ffee02, &emu->regs[EM7180_REG_CRC_HOST]);
	emu->n_log = 0;
	KUNIT_EXPECT_EQ(test, test_upload(t, -ENODEV), -EBADMSG);
	KUNIT_EXPECT_EQ(test, emu->n_log, 2U + 4 + 1 + 1);
	expect_xfer(test, emu, emu->n_log - 1, true, EM7180_REG_HOST_CTRL,
		    &stop, 1);

	/* The second chunk fails: no more chunks, no CRC, upload mode ends */
	emu->n_log = 0;
	emu->upload_len = 0;
	emu->nack_at = emu->transactions + 4;
	KUNIT_EXPECT_EQ(test, test_upload(t, 0), -EIO);
	KUNIT_EXPECT_EQ(test, emu->n_log, 4U);
	expect_xfer(test, emu, 3, true, EM7180_REG_HOST_CTRL, &stop, 1);
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_HOST_CTRL], 0);

	/* The end of upload mode fails: that is the error */
	emu->n_log = 0;
	emu->nack_at = emu->transactions + 2 + 4 + 1 + 1;
	KUNIT_EXPECT_EQ(test, test_upload(t, 0), -EIO);
	KUNIT_EXPECT_EQ(test, emu->n_log, 2U + 4 + 1);

	KUNIT_EXPECT_EQ(test, regmap_read(t->data->regmap, EM7180_REG_HOST_CTRL,
					  &val), 0);
	KUNIT_EXPECT_EQ(test, val, EM7180_HOST_CTRL_RUN);
}

/* upstream: } */
/* upstream: passthru { */
struct test_locker {
	struct work_struct work;
	struct em7180_data *data;
	struct completion locked;
};

static void test_locker_fn(struct work_struct *work)
{
	struct test_locker *l = container_of(work, struct test_locker, work);

	em7180_lock(l->data);
	mutex_unlock(&l->data->lock);
	complete(&l->locked);
}

/*
 * One transfer on the sensor bus: standby, passthrough and its status; then
 * passthrough off, fusion on, EventStatus read to lower INT. No lock is
 * held in between, but em7180_lock() waits for the deselect, and a scan
 * announced before it is not pushed.
 */
static void em7180_test_passthru_sequence(struct kunit *test)
{
	static const u8 on = 1, off;
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	struct i2c_mux_core muxc = { .priv = t->data };
	s64 resumed = t->data->resumed;
	struct test_locker l = { .data = t->data };

	KUNIT_ASSERT_EQ(test, em7180_passthru_select(&muxc, 0), 0);
	KUNIT_EXPECT_FALSE(test, mutex_is_locked(&t->data->lock));
	KUNIT_EXPECT_TRUE(test, t->data->passthru);
	KUNIT_ASSERT_EQ(test, emu->n_log, 3U);
	expect_xfer(test, emu, 0, true, EM7180_REG_ALGO_CTRL, &on, 1);
	expect_xfer(test, emu, 1, true, EM7180_REG_PASSTHRU_CTRL, &on, 1);
	expect_xfer(test, emu, 2, false, EM7180_REG_PASSTHRU_STATUS, NULL, 1);

	/* The stream's and the transfers' lock waits for the deselect */
	INIT_WORK_ONSTACK(&l.work, test_locker_fn);
	init_completion(&l.locked);
	schedule_work(&l.work);
	KUNIT_EXPECT_EQ(test, wait_for_completion_timeout(&l.locked,
							  msecs_to_jiffies(50)), 0);

	emu->regs[EM7180_REG_EVENT_STATUS] = 0;
	KUNIT_EXPECT_EQ(test, em7180_passthru_deselect(&muxc, 0), 0);
	KUNIT_EXPECT_FALSE(test, t->data->passthru);
	KUNIT_EXPECT_NE(test, wait_for_completion_timeout(&l.locked, HZ), 0);
	flush_work(&l.work);
	destroy_work_on_stack(&l.work);
	KUNIT_EXPECT_FALSE(test, mutex_is_locked(&t->data->lock));
	KUNIT_EXPECT_GT(test, t->data->resumed, resumed);
	KUNIT_ASSERT_EQ(test, emu->n_log, 8U);
	expect_xfer(test, emu, 3, true, EM7180_REG_PASSTHRU_CTRL, &off, 1);
	expect_xfer(test, emu, 4, false, EM7180_REG_PASSTHRU_STATUS, NULL, 1);
	expect_xfer(test, emu, 5, true, EM7180_REG_ALGO_CTRL, &off, 1);
	expect_xfer(test, emu, 6, false, EM7180_REG_ALGO_STATUS, NULL, 1);
	expect_xfer(test, emu, 7, false, EM7180_REG_EVENT_STATUS, NULL, 1);
	KUNIT_EXPECT_FALSE(test, delayed_work_pending(&t->data->recover_work));
}

/*
 * A chip that reset in passthrough is recovered; one that cannot leave it
 * is reset and recovered. The lock is released either way.
 */
static void em7180_test_passthru_recover(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_emu *emu = &t->emu;
	struct i2c_mux_core muxc = { .priv = t->data };

	KUNIT_ASSERT_EQ(test, em7180_passthru_select(&muxc, 0), 0);
	emu->regs[EM7180_REG_EVENT_STATUS] = EM7180_EVENT_CPU_RESET;
	KUNIT_EXPECT_EQ(test, em7180_passthru_deselect(&muxc, 0), 0);
	KUNIT_EXPECT_FALSE(test, mutex_is_locked(&t->data->lock));
	KUNIT_EXPECT_TRUE(test, delayed_work_pending(&t->data->recover_work));
	cancel_delayed_work_sync(&t->data->recover_work);

	KUNIT_ASSERT_EQ(test, em7180_passthru_select(&muxc, 0), 0);
	emu->passthru_stuck = true;
	KUNIT_EXPECT_EQ(test, em7180_passthru_deselect(&muxc, 0), -ETIMEDOUT);
	KUNIT_EXPECT_FALSE(test, mutex_is_locked(&t->data->lock));
	KUNIT_EXPECT_EQ(test, emu->regs[EM7180_REG_RESET_REQ],
			EM7180_RESET_REQ_RESET);
	KUNIT_EXPECT_TRUE(test, delayed_work_pending(&t->data->recover_work));
}

/* upstream: } */
static struct kunit_case em7180_param_cases[] = {
	KUNIT_CASE(em7180_test_param_read_sequence),
	KUNIT_CASE(em7180_test_upload_sequence), /* upstream: upload */
	KUNIT_CASE(em7180_test_upload_errors), /* upstream: upload */
	/* upstream: passthru { */
	KUNIT_CASE(em7180_test_passthru_sequence),
	KUNIT_CASE_SLOW(em7180_test_passthru_recover),
	/* upstream: } */
	KUNIT_CASE(em7180_test_param_write_sequence),
	KUNIT_CASE(em7180_test_param_batch),
	KUNIT_CASE(em7180_test_param_stale_ack),
	KUNIT_CASE(em7180_test_param_unknown_ack),
	KUNIT_CASE(em7180_test_param_latency),
	KUNIT_CASE(em7180_test_param_ack_least),
	KUNIT_CASE(em7180_test_param_slow_ack),
	KUNIT_CASE_SLOW(em7180_test_param_timeout),
	KUNIT_CASE(em7180_test_param_nack),
	KUNIT_CASE(em7180_test_param_autoinc_read),
	KUNIT_CASE(em7180_test_param_autoinc_write),
	KUNIT_CASE(em7180_test_param_echo_value),
	KUNIT_CASE(em7180_test_param_range),
	KUNIT_CASE(em7180_test_pm_power_loss), /* upstream: health */
	KUNIT_CASE(em7180_test_pm_power_loss_nack), /* upstream: health */
	KUNIT_CASE(em7180_test_pm_no_power_loss), /* upstream: health */
	KUNIT_CASE(em7180_test_pm_nonfinite_keeps_ws), /* upstream: health */
	KUNIT_CASE(em7180_test_ws_read_nonfinite),
	KUNIT_CASE(em7180_test_pm_live_calibration), /* upstream: health */
	KUNIT_CASE_SLOW(em7180_test_pm_offsets_without_ws), /* upstream: health */
	KUNIT_CASE(em7180_test_pm_restore_order), /* upstream: health */
	KUNIT_CASE_SLOW(em7180_test_pm_standby_stuck),
	KUNIT_CASE(em7180_test_pm_firmware_changed), /* upstream: health */
	KUNIT_CASE(em7180_test_recover_teardown), /* upstream: health */
	KUNIT_CASE(em7180_test_recover_suspend), /* upstream: health */
	KUNIT_CASE(em7180_test_calibbias_copy),
	KUNIT_CASE(em7180_test_warmstart_fuzz),
	KUNIT_CASE(em7180_test_caldata_apply),
	KUNIT_CASE(em7180_test_caldata_refused),
	KUNIT_CASE_SLOW(em7180_test_caldata_fails),
	KUNIT_CASE(em7180_test_caldata_identity),
	KUNIT_CASE(em7180_test_caldata_read_header),
	{ }
};

static struct kunit_suite em7180_param_suite = {
	.name = "em7180_param",
	.init = em7180_test_init,
	.exit = em7180_test_exit, /* upstream: health */
	.test_cases = em7180_param_cases,
};

/* upstream: feature { */
struct em7180_test_layout {
	unsigned int flags;
	int n;
	struct em7180_feature feat[EM7180_FEATURE_MAX];	/* without scan_index */
};

/* Slots in FeatureFlags' bit order; the data layout by the number of slots */
static void em7180_test_feature_layout(struct kunit *test)
{
	static const struct em7180_test_layout cases[] = {
		{ 0x00, 0 },
		/* the USFS: Baro 0x2A, BaroTIME 0x2C, Temp 0x2E, TempTIME 0x30 */
		{ 0x05, 2, { { IIO_PRESSURE, 0, 0x2A, 0x2E },
			     { IIO_TEMP, 1, 0x2E, 0x32 } } },
		{ 0x04, 1, { { IIO_TEMP, 0, 0x2A, 0x2E } } },
		/* three slots: three data words, one TIME at 0x30 */
		{ 0x07, 3, { { IIO_PRESSURE, 0, 0x2A, 0x32 },
			     { IIO_HUMIDITYRELATIVE, 1, 0x2C, 0x32 },
			     { IIO_TEMP, 2, 0x2E, 0x32 } } },
		/* a custom sensor takes a slot after them, and no channel */
		{ 0x09, 1, { { IIO_PRESSURE, 0, 0x2A, 0x2E } } },
		{ 0x0D, 2, { { IIO_PRESSURE, 0, 0x2A, 0x32 },
			     { IIO_TEMP, 1, 0x2C, 0x32 } } },
		/* bits 6 and 7 are no sensors */
		{ 0xC5, 2, { { IIO_PRESSURE, 0, 0x2A, 0x2E },
			     { IIO_TEMP, 1, 0x2E, 0x32 } } },
		{ 0x0F, -E2BIG },
		{ 0x3F, -E2BIG },
	};
	struct em7180_feature feat[EM7180_FEATURE_MAX];
	const struct em7180_test_layout *c;
	int i, n;

	for (c = cases; c < cases + ARRAY_SIZE(cases); c++) {
		memset(feat, 0, sizeof(feat));
		n = em7180_feature_layout(c->flags, feat);
		KUNIT_EXPECT_EQ_MSG(test, n, c->n, "flags 0x%02x", c->flags);
		for (i = 0; i < c->n; i++) {
			KUNIT_EXPECT_EQ_MSG(test, feat[i].type, c->feat[i].type,
					    "flags 0x%02x #%d", c->flags, i);
			KUNIT_EXPECT_EQ_MSG(test, feat[i].slot, c->feat[i].slot,
					    "flags 0x%02x #%d", c->flags, i);
			KUNIT_EXPECT_EQ_MSG(test, feat[i].data_reg,
					    c->feat[i].data_reg,
					    "flags 0x%02x #%d", c->flags, i);
			KUNIT_EXPECT_EQ_MSG(test, feat[i].end_reg,
					    c->feat[i].end_reg,
					    "flags 0x%02x #%d", c->flags, i);
		}
	}
}

/* The feature channels go between the others and the timestamp */
static void em7180_test_feature_channels(struct kunit *test)
{
	static const struct iio_chan_spec base[] = {
		{ .type = IIO_ACCEL, .address = 0x1A, .scan_index = 0 },
		{ .type = IIO_ACCEL, .address = 0x1C, .scan_index = 1 },
		IIO_CHAN_SOFT_TIMESTAMP(2),
	};
	struct iio_chan_spec chans[ARRAY_SIZE(base) + EM7180_FEATURE_MAX];
	struct em7180_feature feat[EM7180_FEATURE_MAX];
	int n = em7180_feature_layout(0x05, feat);

	KUNIT_ASSERT_EQ(test, n, 2);
	em7180_feature_channels(base, ARRAY_SIZE(base), feat, n, chans);

	KUNIT_EXPECT_EQ(test, chans[0].address, 0x1A);
	KUNIT_EXPECT_EQ(test, chans[1].scan_index, 1);

	KUNIT_EXPECT_EQ(test, chans[2].type, IIO_PRESSURE);
	KUNIT_EXPECT_EQ(test, chans[2].address, 0x2A);
	KUNIT_EXPECT_EQ(test, chans[2].scan_index, 2);
	KUNIT_EXPECT_TRUE(test, chans[2].info_mask_separate &
			  BIT(IIO_CHAN_INFO_OFFSET));
	KUNIT_EXPECT_TRUE(test, chans[2].info_mask_separate_available &
			  BIT(IIO_CHAN_INFO_SAMP_FREQ));
	KUNIT_EXPECT_EQ(test, chans[2].scan_type.sign, 's');
	KUNIT_EXPECT_EQ(test, chans[2].scan_type.storagebits, 16);
	KUNIT_EXPECT_EQ(test, chans[2].scan_type.endianness, IIO_LE);

	KUNIT_EXPECT_EQ(test, chans[3].type, IIO_TEMP);
	KUNIT_EXPECT_EQ(test, chans[3].address, 0x2E);
	KUNIT_EXPECT_EQ(test, chans[3].scan_index, 3);
	KUNIT_EXPECT_FALSE(test, chans[3].info_mask_separate &
			   BIT(IIO_CHAN_INFO_OFFSET));

	KUNIT_EXPECT_EQ(test, chans[4].type, IIO_TIMESTAMP);
	KUNIT_EXPECT_EQ(test, chans[4].scan_index, 4);
	KUNIT_EXPECT_EQ(test, chans[4].scan_type.storagebits, 64);
}

/* upstream: } */
/* upstream: upload { */
/* A .fw image: the 16-byte header, then text_len bytes of text */
static u8 *test_fw_image(struct kunit *test, u16 magic, u16 flags,
			 u16 text_len, size_t size)
{
	u8 *img = kunit_kzalloc(test, max_t(size_t, size, 16), GFP_KERNEL);

	KUNIT_ASSERT_NOT_NULL(test, img);
	put_unaligned_le16(magic, &img[0]);
	put_unaligned_le16(flags, &img[2]);
	put_unaligned_le32(0x12345678, &img[4]);
	put_unaligned_le16(text_len, &img[12]);
	return img;
}

#define TEST_FW_CHECK(img, size, rom, ret, msg) do {			\
	char why[96] = "";						\
	KUNIT_EXPECT_EQ(test, em7180_fw_check(img, size, rom, why,	\
					      sizeof(why)), ret);	\
	KUNIT_EXPECT_STREQ(test, why, msg);				\
} while (0)

static void em7180_test_fw_check(struct kunit *test)
{
	const u16 di01 = 0x07a8, di02 = 0x09e6;
	u8 *img;
	size_t size;

	/* ROM code in flags bits 14:11: 0 any, 1 DI01, 2 DI02 */
	img = test_fw_image(test, 0x652a, 2 << 11, 2048, 16 + 2048);
	TEST_FW_CHECK(img, 16 + 2048, di02, 0, "");
	/* bytes after the text are not sent, as em718x_core.c does */
	TEST_FW_CHECK(img, 16 + 2048 + 4, di02, 0, "");
	TEST_FW_CHECK(img, 16 + 2048, di01, -EINVAL,
		      "built for ROM DI02 (0x09e6), the chip has ROM 0x07a8");
	/* no_exec, the I2C clock and bit 15 do not matter */
	img = test_fw_image(test, 0x652a, 0x8701 | 1 << 11, 64, 16 + 64);
	TEST_FW_CHECK(img, 16 + 64, di01, 0, "");
	TEST_FW_CHECK(img, 16 + 64, di02, -EINVAL,
		      "built for ROM DI01 (0x07a8), the chip has ROM 0x09e6");
	img = test_fw_image(test, 0x652a, 0, 64, 16 + 64);
	TEST_FW_CHECK(img, 16 + 64, 0x1234, 0, "");
	img = test_fw_image(test, 0x652a, 3 << 11, 64, 16 + 64);
	TEST_FW_CHECK(img, 16 + 64, di02, -EINVAL,
		      "built for unknown ROM code 3, the chip has ROM 0x09e6");

	img = test_fw_image(test, 0x2a65, 2 << 11, 64, 16 + 64);
	TEST_FW_CHECK(img, 16 + 64, di02, -EINVAL,
		      "bad magic 0x2a65 (expected 0x652a): not a SENtral .fw image");

	/* Every size short of the text, the header's included */
	img = test_fw_image(test, 0x652a, 2 << 11, 64, 16 + 64);
	for (size = 0; size < 16; size++) {
		char msg[64];

		snprintf(msg, sizeof(msg),
			 "%zu bytes, shorter than the 16-byte header", size);
		TEST_FW_CHECK(img, size, di02, -EINVAL, msg);
	}
	for (size = 16; size < 16 + 64; size++) {
		char msg[64];

		snprintf(msg, sizeof(msg),
			 "truncated: %zu bytes of text, the header says 64",
			 size - 16);
		TEST_FW_CHECK(img, size, di02, -EINVAL, msg);
	}

	img = test_fw_image(test, 0x652a, 2 << 11, 0, 16);
	TEST_FW_CHECK(img, 16, di02, -EINVAL,
		      "text length 0 is not a whole number of 32-bit words");
	img = test_fw_image(test, 0x652a, 2 << 11, 62, 16 + 62);
	TEST_FW_CHECK(img, 16 + 62, di02, -EINVAL,
		      "text length 62 is not a whole number of 32-bit words");
	/* The largest text a u16 length gives */
	img = test_fw_image(test, 0x652a, 2 << 11, 0xfffc, 16 + 0xfffc);
	TEST_FW_CHECK(img, 16 + 0xfffc, di02, 0, "");
}

/* upstream: } */
static struct kunit_case em7180_format_cases[] = {
	KUNIT_CASE(em7180_test_feature_layout), /* upstream: feature */
	KUNIT_CASE(em7180_test_feature_channels), /* upstream: feature */
	KUNIT_CASE(em7180_test_float_table1),
	KUNIT_CASE(em7180_test_float_lsb),
	KUNIT_CASE(em7180_test_float_rounding),
	KUNIT_CASE(em7180_test_float_fixed),
	KUNIT_CASE(em7180_test_score), /* upstream: cal */
	KUNIT_CASE(em7180_test_warmstart_check),
	KUNIT_CASE(em7180_test_fw_check), /* upstream: upload */
	{ }
};

static struct kunit_suite em7180_format_suite = {
	.name = "em7180_format",
	.test_cases = em7180_format_cases,
};

/* upstream: cal { */
/* Registers 0x43..0x4E with CalStatus, the 0x44 flags and the score */
static void test_cal_block(u8 *regs, u8 status, u8 flags, u16 score)
{
	memset(regs, 0, EM7180_CAL_BLOCK_LEN);
	regs[0] = status;
	regs[EM7180_REG_CAL_FLAGS - EM7180_REG_CAL_STATUS] = flags;
	regs[EM7180_REG_CAL_SCORE - EM7180_REG_CAL_STATUS] = score & 0xff;
	regs[EM7180_REG_CAL_SCORE + 1 - EM7180_REG_CAL_STATUS] = score >> 8;
}

/* AlgorithmStatus graded as bno055 grades its calibration: 0, then 1..4 */
static void em7180_test_cal_level(struct kunit *test)
{
	static const struct {
		u8 algo;
		int level;
	} cases[] = {
		{ 0x00, 2 },		/* running, not stable */
		{ 0x04, 2 },		/* still */
		{ 0x08, 4 },		/* CalibStable */
		{ 0x0c, 4 },		/* stable and still */
		{ 0x18, 3 },		/* stable, magnetic transient */
		{ 0x10, 2 },		/* transient, not stable */
		{ 0x28, 1 },		/* stable but unreliable sensor data */
		{ 0x20, 1 },
		{ 0x01, 0 },		/* halted */
		{ 0x3f, 0 },
		{ 0x02, 2 },		/* slowdown */
	};
	unsigned int i;

	for (i = 0; i < ARRAY_SIZE(cases); i++)
		KUNIT_EXPECT_EQ_MSG(test, em7180_cal_level(cases[i].algo),
				    cases[i].level, "AlgorithmStatus 0x%02x",
				    cases[i].algo);
}

/*
 * The calibration registers, against what a USFS board keeps there
 * (linear acceleration in 0x3F-0x44, 0x4D-0x4E not a score)
 */
static void em7180_test_cal_layout(struct kunit *test)
{
	u8 regs[EM7180_CAL_BLOCK_LEN];

	/* complete, stable; calibrating, not stable; with a transient */
	test_cal_block(regs, 3, 0, 0x8384);
	KUNIT_EXPECT_TRUE(test, em7180_cal_layout(0x08, regs, true));
	test_cal_block(regs, 1, EM7180_CAL_FLAG_GBIAS_UPDATE, 0xc000);
	KUNIT_EXPECT_TRUE(test, em7180_cal_layout(0x04, regs, true));
	test_cal_block(regs, 2 << 2 | 3, 0, 0x8000);
	KUNIT_EXPECT_TRUE(test, em7180_cal_layout(0x18, regs, true));
	/* status and transient against AlgorithmStatus */
	test_cal_block(regs, 3, 0, 0x8384);
	KUNIT_EXPECT_FALSE(test, em7180_cal_layout(0x00, regs, true));
	KUNIT_EXPECT_TRUE(test, em7180_cal_layout(0x00, regs, false));
	test_cal_block(regs, 1, 0, 0x8384);
	KUNIT_EXPECT_FALSE(test, em7180_cal_layout(0x08, regs, true));
	KUNIT_EXPECT_FALSE(test, em7180_cal_layout(0x10, regs, true));
	test_cal_block(regs, 1 << 2, 0, 0x8384);
	KUNIT_EXPECT_FALSE(test, em7180_cal_layout(0x00, regs, true));
	/* bits the note does not define; a negative score */
	test_cal_block(regs, 0x12, 0, 0x8384);
	KUNIT_EXPECT_FALSE(test, em7180_cal_layout(0, regs, false));
	test_cal_block(regs, 1, 0x04, 0x8384);
	KUNIT_EXPECT_FALSE(test, em7180_cal_layout(0, regs, false));
	test_cal_block(regs, 1, 0, 0x7fff);
	KUNIT_EXPECT_FALSE(test, em7180_cal_layout(0, regs, false));
	/* a still USFS board: linear acceleration z 0x002e, GP22/23 zero */
	test_cal_block(regs, 0x2e, 0x00, 0);
	KUNIT_EXPECT_FALSE(test, em7180_cal_layout(0, regs, false));
	/* z = -2: 0xfffe */
	test_cal_block(regs, 0xfe, 0xff, 0x8000);
	KUNIT_EXPECT_FALSE(test, em7180_cal_layout(0, regs, false));
	/* nothing yet */
	test_cal_block(regs, 0, 0, 0);
	KUNIT_EXPECT_FALSE(test, em7180_cal_layout(0, regs, false));
}

/*
 * Detection on the chip: one read of AlgorithmStatus and 0x43..0x4E; the
 * flags that read cleared are kept.
 */
static void em7180_test_cal_detect(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_data *data = t->data;
	u8 *regs = &t->emu.regs[EM7180_REG_CAL_STATUS];

	guard(mutex)(&data->lock);
	test_cal_block(regs, 3, EM7180_CAL_FLAG_GBIAS_UPDATE, 0x8384);
	t->emu.algo_status = 0x08;
	KUNIT_ASSERT_EQ(test, em7180_cal_detect(data), 0);
	KUNIT_EXPECT_TRUE(test, data->appnote);
	KUNIT_EXPECT_EQ(test, data->cal.score, 0x8384);
	KUNIT_EXPECT_EQ(test, data->cal.flags, EM7180_CAL_FLAG_GBIAS_UPDATE);

	/* a USFS board: linear acceleration */
	test_cal_block(regs, 0x2e, 0, 0);
	KUNIT_ASSERT_EQ(test, em7180_cal_detect(data), 0);
	KUNIT_EXPECT_FALSE(test, data->appnote);

	/* a bus error: not reported */
	test_cal_block(regs, 3, 0, 0x8384);
	t->emu.nack_at = t->emu.transactions + 1;
	KUNIT_EXPECT_EQ(test, em7180_cal_detect(data), -EIO);
	KUNIT_EXPECT_FALSE(test, data->appnote);
}

/*
 * A read the note's layout cannot hold ends the reporting; all zero, as
 * right after a reset, does not.
 */
static void em7180_test_cal_demote(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_data *data = t->data;
	u8 regs[EM7180_CAL_BLOCK_LEN];

	guard(mutex)(&data->lock);
	test_cal_block(regs, 0, 0, 0);
	em7180_cal_update(data, regs);
	KUNIT_EXPECT_TRUE(test, data->appnote);
	test_cal_block(regs, 2, 0, 0xa000);
	em7180_cal_update(data, regs);
	KUNIT_EXPECT_TRUE(test, data->appnote);
	KUNIT_EXPECT_EQ(test, data->cal.score, 0xa000);
	test_cal_block(regs, 0xe4, 0xff, 0xa000);
	em7180_cal_update(data, regs);
	KUNIT_EXPECT_FALSE(test, data->appnote);
	KUNIT_EXPECT_EQ(test, data->cal.flags, 0);
	/* for good: a read that fits again does not bring it back */
	test_cal_block(regs, 3, EM7180_CAL_FLAG_MAG_UPDATE, 0x8100);
	em7180_cal_update(data, regs);
	KUNIT_EXPECT_FALSE(test, data->appnote);
	KUNIT_EXPECT_EQ(test, data->cal.score, 0xa000);
}

/* A read folds the update flags in, until the warm start is transferred */
static void em7180_test_cal_fold(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_data *data = t->data;
	u8 regs[EM7180_CAL_BLOCK_LEN];

	guard(mutex)(&data->lock);
	test_cal_block(regs, 3 | 2 << 2, EM7180_CAL_FLAG_GBIAS_UPDATE, 0x8384);
	em7180_cal_update(data, regs);
	KUNIT_EXPECT_EQ(test, data->cal.score, 0x8384);
	KUNIT_EXPECT_EQ(test, data->cal.flags, EM7180_CAL_FLAG_GBIAS_UPDATE);
	/* cleared on the chip by that read: the flag stays */
	test_cal_block(regs, 2, 0, 0x8000);
	em7180_cal_update(data, regs);
	KUNIT_EXPECT_EQ(test, data->cal.flags, EM7180_CAL_FLAG_GBIAS_UPDATE);
	test_cal_block(regs, 2, EM7180_CAL_FLAG_MAG_UPDATE, 0x8000);
	em7180_cal_update(data, regs);
	KUNIT_EXPECT_EQ(test, data->cal.flags, EM7180_CAL_FLAG_GBIAS_UPDATE |
			EM7180_CAL_FLAG_MAG_UPDATE);
	em7180_cal_saved(data);
	KUNIT_EXPECT_EQ(test, data->cal.flags, 0);
	KUNIT_EXPECT_FALSE(test, data->cal.valid);
}

/*
 * The flags stay set until the warm start is read or written; one the chip
 * latched before that is taken in by the transfer's first poll, in the
 * same transaction, and cleared with it.
 */
static void em7180_test_cal_flags_until_saved(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_data *data = t->data;
	unsigned int before;
	u32 val;

	guard(mutex)(&data->lock);
	test_cal_block(&t->emu.regs[EM7180_REG_CAL_STATUS], 3,
		       EM7180_CAL_FLAG_GBIAS_UPDATE, 0x8384);
	before = t->emu.transactions;
	KUNIT_ASSERT_EQ(test, em7180_params_read(data, 1, 1, &val), 0);
	/* request, bit 7, one poll, the stop and its poll, bit 7 clear */
	KUNIT_EXPECT_EQ(test, t->emu.transactions - before, 6U);
	KUNIT_EXPECT_EQ(test, t->emu.regs[EM7180_REG_CAL_FLAGS], 0);
	KUNIT_EXPECT_EQ(test, data->cal.flags, EM7180_CAL_FLAG_GBIAS_UPDATE);
	KUNIT_EXPECT_EQ(test, data->cal.score, 0x8384);
	em7180_cal_saved(data);
	KUNIT_EXPECT_EQ(test, data->cal.flags, 0);

	/* a write takes them in too */
	t->emu.regs[EM7180_REG_CAL_FLAGS] = EM7180_CAL_FLAG_MAG_UPDATE;
	KUNIT_ASSERT_EQ(test, em7180_params_write(data, 1, 1, &val), 0);
	KUNIT_EXPECT_EQ(test, t->emu.regs[EM7180_REG_CAL_FLAGS], 0);
	KUNIT_EXPECT_EQ(test, data->cal.flags, EM7180_CAL_FLAG_MAG_UPDATE);
}

/*
 * Firmware without the note's registers: a transfer reads the echo alone,
 * never 0x44, which may be another sensor's data
 */
static void em7180_test_cal_standard_firmware(struct kunit *test)
{
	struct em7180_test *t = test->priv;
	struct em7180_data *data = t->data;
	unsigned int before, i;
	u32 val;

	guard(mutex)(&data->lock);
	data->appnote = false;
	test_cal_block(&t->emu.regs[EM7180_REG_CAL_STATUS], 3,
		       EM7180_CAL_FLAG_GBIAS_UPDATE, 0x8384);
	t->emu.n_log = 0;
	before = t->emu.transactions;
	KUNIT_ASSERT_EQ(test, em7180_params_read(data, 1, 1, &val), 0);
	KUNIT_EXPECT_EQ(test, t->emu.transactions - before, 6U);
	for (i = 0; i < t->emu.n_log; i++)
		if (!t->emu.log[i].write)
			KUNIT_EXPECT_LT_MSG(test,
					    t->emu.log[i].reg + t->emu.log[i].len,
					    EM7180_REG_CAL_STATUS,
					    "read %u", i);
	KUNIT_EXPECT_EQ(test, t->emu.regs[EM7180_REG_CAL_FLAGS],
			EM7180_CAL_FLAG_GBIAS_UPDATE);
	KUNIT_EXPECT_EQ(test, data->cal.flags, 0);
	KUNIT_EXPECT_EQ(test, data->cal.score, 0);
}

static struct kunit_case em7180_cal_cases[] = {
	KUNIT_CASE(em7180_test_cal_level),
	KUNIT_CASE(em7180_test_cal_layout),
	KUNIT_CASE(em7180_test_cal_detect),
	KUNIT_CASE(em7180_test_cal_demote),
	KUNIT_CASE(em7180_test_cal_fold),
	KUNIT_CASE(em7180_test_cal_flags_until_saved),
	KUNIT_CASE(em7180_test_cal_standard_firmware),
	{ }
};

static struct kunit_suite em7180_cal_suite = {
	.name = "em7180_cal",
	.init = em7180_test_init,
	.exit = em7180_test_exit, /* upstream: health */
	.test_cases = em7180_cal_cases,
};

/* upstream: } */
/* upstream: cal { */
kunit_test_suites(&em7180_param_suite, &em7180_format_suite,
		  &em7180_cal_suite);
/* upstream: } */
/* upstream: !cal: kunit_test_suites(&em7180_param_suite, &em7180_format_suite); */

MODULE_DESCRIPTION("KUnit tests for the EM7180 driver");
MODULE_LICENSE("GPL");
MODULE_IMPORT_NS("EXPORTED_FOR_KUNIT_TESTING");
MODULE_IMPORT_NS("IIO_EM7180");
