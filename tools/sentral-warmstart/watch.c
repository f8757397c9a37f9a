// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: watch, the automatic save.
 *
 * The chip raises no interrupt when its calibration changes and the driver
 * wakes nobody: every poll interval the watcher reads the calibration
 * state (one burst read of the chip, the driver serves the rest from it),
 * asks the save policy (the saved file's header and the driver's copy of
 * the accel offsets: no bus transaction) and saves when it says yes, at
 * most once per write interval. It keeps no state anywhere but in this
 * process, so that any number of watchers can run side by side.
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
	char failed[512];	/* the failure of the last look, "" when none */
};

/*
 * Look at the chip once and save if the policy and the interval allow.
 * Returns SW_EXIT_OK to go on, or the exit code that ends the watch: the
 * device is gone. Anything else (a bus error, a full disk, a state
 * directory being repaired) is reported and looked at again at the next
 * poll; a look failing the same way again is not reported again.
 */
static int watch_step(struct watch *w, struct sw_err *e)
{
	uint64_t now, since, interval = (uint64_t)w->o->interval_s * 1000u;
	struct sw_cal_state cs;
	struct sw_err se;
	char why[512];
	bool yes;
	int ret;

	sw_err_clear(&se);
	ret = w->b->ops->cal_state(w->b, &cs, &se);
	/* Nothing to judge a save by: said once, and the watch ends */
	if (!ret && !cs.reported)
		return sw_err_not_reported(w->b,
					   "not watching it (save --force saves anyway)",
					   e);
	ret = ret ? ret : sw_save_wanted(w->b, w->o, &cs, &yes, why,
					 sizeof(why), &se);
	if (ret == SW_EXIT_DEVICE)
		return sw_err_set(e, ret, "%s", se.msg);
	if (ret) {
		if (strcmp(se.msg, w->failed)) {
			sw_report(w->env, &se);
			sw_note(w->env, "watch: looking again every %u s",
				w->o->poll_s);
			snprintf(w->failed, sizeof(w->failed), "%s", se.msg);
		}
		return SW_EXIT_OK;
	}
	w->failed[0] = '\0';
	if (!yes) {
		w->deferred = false;
		return SW_EXIT_OK;
	}
	now = w->env->now_ms(w->env->clk);
	since = now - w->last_write;
	if (w->written && since < interval) {
		if (!w->deferred)
			sw_note(w->env,
				"watch: %s has a calibration to save (status %d, score %.3f%%), but the last write was %llu s ago: saving it in %llu s unless it changes",
				w->b->name, cs.status,
				sw_score_pct(cs.score_raw),
				(unsigned long long)(since / 1000),
				(unsigned long long)((interval - since + 999) / 1000));
		w->deferred = true;
		return SW_EXIT_OK;
	}
	w->deferred = false;
	w->written = true;
	w->last_write = now;
	sw_err_clear(&se);
	ret = sw_save_now(w->b, w->o, w->env, NULL, &se);
	if (ret == SW_EXIT_DEVICE)
		return sw_err_set(e, ret, "%s", se.msg);
	/* A failed save (a full disk, another writer) is not the end. */
	if (ret) {
		sw_report(w->env, &se);
		sw_note(w->env, "watch: trying again in %u s", w->o->interval_s);
	}
	return SW_EXIT_OK;
}

int sw_cmd_watch(struct sw_backend *b, const struct sw_opts *o,
		 struct sw_env *env, struct sw_err *e)
{
	struct sw_opts wo = *o;
	struct watch w = { .b = b, .o = &wo, .env = env };
	char path[4096];
	int ret = SW_EXIT_OK;

	wo.improve_only = true;
	sw_signals_catch();
	sw_file_path(&wo, b, path, sizeof(path));
	sw_note(env,
		"watching %s: looking every %u s; saving to %s when the calibration is complete with a score of at most %.3f%%, and better than a good saved one by %.3f points, or the accel offsets change; at most one write every %u s",
		b->name, wo.poll_s, path, wo.max_score, wo.margin,
		wo.interval_s);
	while (!sw_signal_pending()) {
		ret = watch_step(&w, e);
		if (ret)
			break;
		env->nap_ms(env->clk, wo.poll_s * 1000u);
	}
	if (ret == SW_EXIT_DEVICE)
		sw_err_append(e, "; stopped watching it");
	else
		sw_note(env, "stopped watching %s", b->name);
	return ret;
}
