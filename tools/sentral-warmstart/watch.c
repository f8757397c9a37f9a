// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: watch, the automatic save.
 *
 * Sleeps until the driver reports a change of the calibration status, the
 * score or the magnetic calibration update count, then asks the save
 * policy (the saved file's header and the chip's state only: no parameter
 * transfer) and saves when it says yes, at most once per interval. Nothing
 * here polls the chip: without a write waiting for the interval to pass,
 * the wait has no timeout and only the driver ends it.
 */
#include <string.h>

#include "cmd.h"

struct watch {
	struct sw_backend *b;
	const struct sw_opts *o;
	struct sw_env *env;
	bool written;		/* a save was attempted at last_write */
	uint64_t last_write;	/* ms, env->now_ms */
	bool deferred;		/* told that a save waits for the interval */
};

/*
 * Look at the chip once and save if the policy and the interval allow.
 * Returns how long to wait before the next look (ms), -1 for as long as
 * the driver reports nothing, or an exit code negated.
 */
static int watch_step(struct watch *w, struct sw_err *e)
{
	uint64_t now, since, interval = (uint64_t)w->o->interval_s * 1000u;
	struct sw_cal_state cs;
	struct sw_err se;
	char why[256];
	bool yes;
	int ret;

	ret = w->b->ops->cal_state(w->b, &cs, e);
	if (ret)
		return -ret;
	sw_err_clear(&se);
	/* The state directory or file may be repaired: not the end either. */
	if (sw_save_wanted(w->b, w->o, &cs, &yes, why, sizeof(why), &se)) {
		sw_report(w->env, &se);
		sw_note(w->env, "watch: trying again in %u s", w->o->interval_s);
		return (int)interval;
	}
	if (!yes) {
		w->deferred = false;
		return -1;
	}
	now = w->env->now_ms(w->env->clk);
	since = now - w->last_write;
	if (w->written && since < interval) {
		if (!w->deferred)
			sw_note(w->env,
				"watch: %s has a better calibration (status %d, score %.3f%%), but the last write was %llu s ago: saving it in %llu s unless it changes",
				w->b->name, cs.status,
				sw_score_pct(cs.score_raw),
				(unsigned long long)(since / 1000),
				(unsigned long long)((interval - since + 999) / 1000));
		w->deferred = true;
		return (int)(interval - since);
	}
	w->deferred = false;
	w->written = true;
	w->last_write = now;
	sw_err_clear(&se);
	/* A failed save (a capture running, a full disk) is not the end. */
	if (sw_save_now(w->b, w->o, w->env, NULL, &se)) {
		sw_report(w->env, &se);
		sw_note(w->env, "watch: trying again in %u s", w->o->interval_s);
		return (int)interval;
	}
	return -1;
}

int sw_cmd_watch(struct sw_backend *b, const struct sw_opts *o,
		 struct sw_env *env, struct sw_err *e)
{
	struct sw_opts wo = *o;
	struct watch w = { .b = b, .o = &wo, .env = env };
	char path[4096];
	bool changed;
	int ret = SW_EXIT_OK, timeout;

	if (!b->ops->watch_begin)
		return sw_err_set(e, SW_EXIT_DEVICE,
				  "%s: watch needs the em7180 driver, which wakes it",
				  b->name);
	wo.improve_only = true;
	sw_signals_catch();
	ret = b->ops->watch_begin(b, e);
	if (ret)
		return ret;
	sw_file_path(&wo, b, path, sizeof(path));
	sw_note(env,
		"watching %s: saving to %s when the calibration is complete with a score of at most %.3f%%, and better than a good saved one by %.3f points; at most one write every %u s",
		b->name, path, wo.max_score, wo.margin, wo.interval_s);
	while (!sw_signal_pending()) {
		timeout = watch_step(&w, e);
		if (timeout < -1) {
			ret = -timeout;
			break;
		}
		ret = b->ops->watch_wait(b, timeout, &changed, e);
		if (ret)
			break;
	}
	b->ops->watch_end(b);
	if (!ret)
		sw_note(env, "stopped watching %s", b->name);
	return ret;
}
