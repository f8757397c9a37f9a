// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: watch, the automatic save.
 *
 * The chip raises no interrupt when its calibration changes and the driver
 * wakes nobody: every poll interval the watcher reads the calibration
 * state (the level, one bus transaction; with a score, one burst read of
 * the chip that the driver serves the rest from), asks the save policy
 * (the saved file's header and the driver's copy of the accel offsets: no
 * bus transaction) and saves when it says yes, at most once per write
 * interval. Without a score the policy needs the magnetometer
 * coefficients, so the blob is read when the level rises to 4 (or is 4 at
 * the first look): never while it stays where it is. It keeps no state
 * anywhere but in this process, so that any number of watchers can run
 * side by side.
 */
#include <string.h>

#include "cmd.h"
#include "level.h"

struct watch {
	struct sw_backend *b;
	const struct sw_opts *o;
	struct sw_env *env;
	bool written;		/* a save was written or failed at last_write */
	uint64_t last_write;	/* ms, env->now_ms */
	bool pending;		/* a save waits for the interval (told once) */
	int last_level;		/* of the last look, -1 before the first */
	char failed[512];	/* the failure of the last look, "" when none */
};

/* A look that failed: said once while it fails the same way. */
static void look_failed(struct watch *w, const struct sw_err *se)
{
	if (!strcmp(se->msg, w->failed))
		return;
	sw_report(w->env, se);
	sw_note(w->env, "watch: looking again every %u s", w->o->poll_s);
	snprintf(w->failed, sizeof(w->failed), "%s", se->msg);
}

/*
 * Without a score, is a stable calibration worth a save? Only the blob
 * tells (its coefficients against the saved file's): read once.
 */
static int look_at_blob(struct watch *w, bool *yes, char *why, size_t len,
			struct sw_err *se)
{
	uint8_t blob[SW_BLOB_SIZE];
	struct sw_cal_state cs;
	int ret;

	ret = sw_read_snapshot(w->b, &cs, blob, se);
	return ret ? ret : sw_save_wanted(w->b, w->o, &cs, blob, yes, why,
					  len, se);
}

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
	bool yes = false, rose, held;
	bool saved;
	int ret;

	now = w->env->now_ms(w->env->clk);
	since = now - w->last_write;
	held = w->written && since < interval;
	sw_err_clear(&se);
	ret = w->b->ops->cal_state(w->b, &cs, &se);
	rose = !ret && cs.level == SW_LEVEL_STABLE &&
	       w->last_level != SW_LEVEL_STABLE;
	if (!ret)
		w->last_level = cs.level;
	ret = ret ? ret : sw_save_wanted(w->b, w->o, &cs, NULL, &yes, why,
					 sizeof(why), &se);
	/*
	 * Without a score a stable calibration is judged by its
	 * coefficients: when the level rose to 4, read them now if a save
	 * would be held back (to know whether one waits), else let the save
	 * read and judge them; a save held back waits while the level stays.
	 */
	if (!ret && !yes && !cs.has_score && cs.level == SW_LEVEL_STABLE) {
		if (rose && held)
			ret = look_at_blob(w, &yes, why, sizeof(why), &se);
		else
			yes = rose || w->pending;
	}
	if (ret == SW_EXIT_DEVICE)
		return sw_err_set(e, ret, "%s", se.msg);
	if (ret) {
		/* A rise not judged yet (the blob unread): at the next look. */
		if (rose)
			w->last_level = -1;
		look_failed(w, &se);
		return SW_EXIT_OK;
	}
	w->failed[0] = '\0';
	if (!yes) {
		w->pending = false;
		return SW_EXIT_OK;
	}
	if (held) {
		if (!w->pending)
			sw_note(w->env,
				"watch: %s has a calibration to save (level %d, %s), but the last write was %llu s ago: saving it in %llu s unless it changes",
				w->b->name, cs.level, why,
				(unsigned long long)(since / 1000),
				(unsigned long long)((interval - since + 999) / 1000));
		w->pending = true;
		return SW_EXIT_OK;
	}
	w->pending = false;
	sw_err_clear(&se);
	ret = sw_save_now(w->b, w->o, w->env, &saved, &se);
	if (ret == SW_EXIT_DEVICE)
		return sw_err_set(e, ret, "%s", se.msg);
	/* A save the policy declined (coefficients unchanged) is no write. */
	if (saved || ret) {
		w->written = true;
		w->last_write = now;
	}
	/*
	 * A failed save (a full disk, another writer) is not the end: it
	 * waits for the interval as a save held back does (without a score
	 * nothing else would bring it back while the level stays 4).
	 */
	if (ret) {
		w->pending = true;
		sw_report(w->env, &se);
		sw_note(w->env, "watch: trying again in %u s", w->o->interval_s);
	}
	return SW_EXIT_OK;
}

int sw_cmd_watch(struct sw_backend *b, const struct sw_opts *o,
		 struct sw_env *env, struct sw_err *e)
{
	struct sw_opts wo = *o;
	struct watch w = { .b = b, .o = &wo, .env = env, .last_level = -1 };
	char path[4096];
	int ret = SW_EXIT_OK;

	wo.improve_only = true;
	sw_signals_catch();
	sw_file_path(&wo, b, path, sizeof(path));
	sw_note(env,
		"watching %s: looking every %u s; saving to %s when the calibration is stable (level 4) and, with a score, the score is at most %.3f%% and better than a good saved one by %.3f points, without one, its coefficients differ from the saved ones; or when the accel offsets change; at most one write every %u s",
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
