// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: save and restore the warm-start calibration of a
 * PNI SENtral / EM7180 sensor-fusion hub. See sentral-warmstart.8.
 */
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include "cmd.h"
#include "daemon.h"

static int run(const struct sw_opts *o, struct sw_env *env, struct sw_err *e)
{
	struct sw_backend *b = NULL;
	int ret;

	if (o->cmd == SW_CMD_SHOW)
		return sw_cmd_show(o, env, e);

	if (o->i2c_dev) {
		struct sw_i2c_opts io = {
			.dev = o->i2c_dev, .addr = o->address, .force = o->force,
		};

		ret = sw_i2c_open(&io, &b, e);
	} else {
		struct sw_iio_opts io = {
			.device = o->device,
			/* The unit's stop action after an unbind or unplug. */
			.gone_ok = o->cmd == SW_CMD_SAVE && o->if_present,
			/*
			 * Not for key: udev names the device and its units
			 * with it whatever the driver (the units then say).
			 */
			.check_abi = o->cmd != SW_CMD_KEY,
			.version = SW_VERSION,
		};

		ret = sw_iio_open(&io, &b, e);
		if (!ret && !b) {
			sw_note(env, "no em7180 IIO device matches '%s' any more (unbound or unplugged); nothing to save",
				o->device ? o->device : "em7180");
			return SW_EXIT_OK;
		}
	}
	if (ret)
		return ret;

	switch (o->cmd) {
	case SW_CMD_STATUS:
		ret = sw_cmd_status(b, o, env, e);
		break;
	case SW_CMD_SAVE:
		ret = sw_cmd_save(b, o, env, e);
		break;
	case SW_CMD_RESTORE:
		ret = sw_cmd_restore(b, o, env, e);
		break;
	case SW_CMD_CALIBRATE:
		ret = sw_cmd_calibrate(b, o, env, e);
		break;
	case SW_CMD_ACCEL_CAL:
		ret = sw_cmd_accel_cal(b, o, env, e);
		break;
	case SW_CMD_KEY:
		ret = sw_cmd_key(b, o, env, e);
		break;
	case SW_CMD_IMPORT_BOARD:
		ret = sw_cmd_import_board(b, o, env, e);
		break;
	case SW_CMD_WATCH:
		if (o->daemon)
			ret = sw_daemon_start(SW_RUN_DIR, b->key, env, e);
		ret = ret ? ret : sw_cmd_watch(b, o, env, e);
		break;
	default:
		ret = sw_err_set(e, SW_EXIT_USAGE, "no command given");
		break;
	}
	b->ops->close(b);
	return ret;
}

int main(int argc, char **argv)
{
	struct sw_env env;
	struct sw_opts o;
	struct sw_err e;
	int ret;

	sw_err_clear(&e);
	sw_env_init(&env, stdout, stderr);
	env.tty = isatty(STDOUT_FILENO);
	/* Started by udev (RUN+=): its log is the kernel's. */
	env.kmsg = getenv("SEQNUM") && getenv("ACTION") && !env.tty;

	ret = sw_parse_args(argc, argv, &o, &e);
	if (ret) {
		sw_report(&env, &e);
		fprintf(stderr, "Try 'sentral-warmstart %s%s--help'.\n",
			o.cmd ? sw_command_name(o.cmd) : "", o.cmd ? " " : "");
		return ret;
	}
	if (o.help || o.version) {
		if (o.help)
			sw_usage(stdout, o.cmd);
		else
			printf("sentral-warmstart %s\n", SW_VERSION);
		return fflush(stdout) ? SW_EXIT_IO : SW_EXIT_OK;
	}
	ret = run(&o, &env, &e);
	if (ret)
		sw_report(&env, &e);
	if (fflush(stdout) != 0 && !ret)
		ret = SW_EXIT_IO;
	/* The chip is left running: now die of the signal, as the caller expects. */
	if (sw_signal_pending()) {
		signal(sw_signal_pending(), SIG_DFL);
		raise(sw_signal_pending());
	}
	return ret;
}
