/* SPDX-License-Identifier: GPL-2.0-only */
/*
 * sentral-warmstart: command line.
 */
#ifndef SW_CLI_H
#define SW_CLI_H

#include "board.h"
#include "sw.h"

enum sw_command {
	SW_CMD_NONE,
	SW_CMD_STATUS,
	SW_CMD_SAVE,
	SW_CMD_RESTORE,
	SW_CMD_CALIBRATE,
	SW_CMD_ACCEL_CAL,
	SW_CMD_SHOW,
	SW_CMD_KEY,
	SW_CMD_WATCH,
	SW_CMD_IMPORT_BOARD,
	SW_NCMDS
};

struct sw_opts {
	enum sw_command cmd;
	const char *device;	/* --device */
	const char *i2c_dev;	/* --i2c BUS as given (i2cbus.h) */
	unsigned int address;	/* --address, 0x08..0x77, default 0x28 */
	const char *state_dir;	/* --state-dir */
	const char *file;	/* --file, or show's FILE */
	const char *image;	/* import-board's IMAGE */
	enum sw_board_layout layout;	/* import-board --layout */
	bool force;
	bool if_present;
	bool json;
	bool udev;		/* key: print udev properties */
	double max_score;	/* --max-score, percent */
	double target_score;	/* --target-score, percent */
	unsigned int timeout_s;	/* --timeout */
	unsigned int samples;	/* --samples */
	unsigned int interval_s; /* watch --interval: seconds between writes */
	unsigned int poll_s;	/* watch --poll: seconds between looks */
	bool no_save;		/* accel-cal --no-save */
	bool daemon;		/* watch --daemon: detach, one watcher per key */
	double margin;		/* watch --margin: improvement, percent points */
	/* set by watch: a good saved file is replaced only by margin better */
	bool improve_only;
	bool help;		/* --help: the command's help, or all (no command) */
	bool version;		/* --version; of the two only the first is set */
};

/*
 * Parse argv into o. Returns SW_EXIT_OK, or SW_EXIT_USAGE with e->msg
 * saying what is wrong. Options may come before or after the command.
 * --help and --version anywhere before "--" win over anything else on the
 * line, even what is wrong with it: then SW_EXIT_OK, o->help or o->version
 * set (the first of them given), and o->cmd the command, if one was named
 * before anything went wrong.
 */
int sw_parse_args(int argc, char **argv, struct sw_opts *o, struct sw_err *e);

/*
 * --help: all commands and options (SW_CMD_NONE), or one command's
 * synopsis and every option it takes, within 80 columns.
 */
void sw_usage(FILE *f, enum sw_command cmd);

/* "status", "accel-cal", ...; "?" for SW_CMD_NONE. */
const char *sw_command_name(enum sw_command cmd);

#endif
