/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: watch --daemon, the watcher that the udev rule starts
 * where systemd is absent.
 */
#ifndef SW_DAEMON_H
#define SW_DAEMON_H

#include "cmd.h"

/* Where the watchers' locks live: KEY.watch, holding the watcher's pid. */
#define SW_RUN_DIR "/run/sentral-warmstart"

/*
 * Detach from the caller (udev kills what a RUN+= program leaves in its
 * process group or holding its pipes once the event is done or timed
 * out): fork, a new session, fork again, "/" as working directory,
 * /dev/null as standard input and output; messages go to the kernel log
 * (env->kmsg). The caller's process exits 0 once the watcher is detached;
 * the watcher returns SW_EXIT_OK from here, holding the lock of key in
 * run_dir. An older watcher of the same key holding it is told to stop
 * (SIGTERM) and its lock taken over, so that one watcher per chip runs
 * however often the device is added. Anything else is an exit code with
 * e set.
 */
int sw_daemon_start(const char *run_dir, const char *key, struct sw_env *env,
		    struct sw_err *e);

#endif
