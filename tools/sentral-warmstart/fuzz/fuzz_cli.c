// SPDX-License-Identifier: GPL-2.0-only
/*
 * libFuzzer target: command-line parsing.
 *
 * The input is an argument vector: arguments separated by NUL bytes
 * (argv[0] is always "sentral-warmstart"). Each argument is a separate
 * allocation of exactly its length so that ASan sees any read past its
 * end. Properties checked:
 *  - sw_parse_args() returns SW_EXIT_OK or SW_EXIT_USAGE, with a message
 *    exactly when it fails, and never exits, prints or leaks;
 *  - it does not reorder or change argv, and every string it keeps points
 *    into argv (or is the built-in state directory);
 *  - a successful parse is complete: a command (unless --help or
 *    --version, of which only one is set), show's FILE, values inside
 *    their documented ranges (addresses 0x08-0x77), no watch over --i2c,
 *    each option only with a command that takes it (--no-save with
 *    accel-cal, --json with status, calibrate, show and key, not with
 *    --udev; --force without --i2c with save, restore, calibrate and
 *    import-board; nothing of show's but FILE and --json);
 *  - a second parse of the same argv gives the same result (getopt's
 *    hidden state is reset);
 *  - a message about an option names the option ("-x", "--name"), not
 *    the program or a command.
 */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#define MAX_ARGS 64

static bool in_argv(const char *s, int argc, char **argv)
{
	int i;

	for (i = 1; i < argc; i++)
		if (s >= argv[i] && s <= argv[i] + strlen(argv[i]))
			return true;
	return false;
}

static void check_opts(const struct sw_opts *o, int argc, char **argv)
{
	if (o->device && !in_argv(o->device, argc, argv))
		abort();
	if (o->i2c_dev && !in_argv(o->i2c_dev, argc, argv))
		abort();
	if (o->file && !in_argv(o->file, argc, argv))
		abort();
	if (o->image && !in_argv(o->image, argc, argv))
		abort();
	if (strcmp(o->state_dir, SW_STATE_DIR) != 0 &&
	    !in_argv(o->state_dir, argc, argv))
		abort();
	/* --help and --version skip the checks: nothing else runs. */
	if (o->help && o->version)
		abort();
	if (o->help || o->version)
		return;
	if (!*o->state_dir || (o->file && !*o->file))
		abort();
	if (o->cmd == SW_CMD_NONE || o->cmd > SW_CMD_IMPORT_BOARD)
		abort();
	/* import-board, and only it, reads an IMAGE */
	if ((o->cmd == SW_CMD_IMPORT_BOARD) != (o->image && *o->image))
		abort();
	/* over i2c-dev each look at the offsets would be a parameter transfer */
	if (o->cmd == SW_CMD_WATCH && o->i2c_dev)
		abort();
	if (o->no_save && o->cmd != SW_CMD_ACCEL_CAL)
		abort();
	if (o->udev && (o->cmd != SW_CMD_KEY || o->i2c_dev))
		abort();
	if (o->cmd == SW_CMD_SHOW && (!o->file || o->device || o->i2c_dev))
		abort();
	if (o->device && o->i2c_dev)
		abort();
	if (o->i2c_dev && !*o->i2c_dev)
		abort();
	if (o->address < 0x08 || o->address > 0x77)
		abort();
	if (o->json && (o->udev || (o->cmd != SW_CMD_STATUS &&
				    o->cmd != SW_CMD_CALIBRATE &&
				    o->cmd != SW_CMD_SHOW &&
				    o->cmd != SW_CMD_KEY)))
		abort();
	if (o->force && !o->i2c_dev && o->cmd != SW_CMD_SAVE &&
	    o->cmd != SW_CMD_RESTORE && o->cmd != SW_CMD_CALIBRATE &&
	    o->cmd != SW_CMD_IMPORT_BOARD)
		abort();
	if (o->cmd == SW_CMD_SHOW && in_argv(o->state_dir, argc, argv))
		abort();
	if (!(o->max_score >= 0 && o->max_score <= 100) ||
	    !(o->target_score >= 0 && o->target_score <= 100))
		abort();
	if (o->timeout_s < 1 || o->timeout_s > 86400 ||
	    o->samples < 1 || o->samples > 10000 ||
	    o->interval_s < 1 || o->interval_s > 86400 ||
	    o->poll_s < 1 || o->poll_s > 3600 ||
	    !(o->margin >= 0 && o->margin <= 100))
		abort();
}

static void check_message(const struct sw_err *e)
{
	static const char *const prefixes[] = {
		"unknown option '", "option '",
	};
	size_t i, n;

	if (!e->msg[0] || !memchr(e->msg, '\0', sizeof(e->msg)))
		abort();
	for (i = 0; i < sizeof(prefixes) / sizeof(prefixes[0]); i++) {
		n = strlen(prefixes[i]);
		if (!strncmp(e->msg, prefixes[i], n) && e->msg[n] != '-')
			abort();
	}
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	char *argv[MAX_ARGS + 1], *saved[MAX_ARGS + 1];
	struct sw_opts o, o2;
	struct sw_err e, e2;
	int argc = 1, i, ret, ret2;
	size_t pos = 0;

	argv[0] = strdup("sentral-warmstart");
	while (pos < size && argc < MAX_ARGS) {
		const uint8_t *nul = memchr(data + pos, '\0', size - pos);
		size_t n = nul ? (size_t)(nul - data) - pos : size - pos;

		argv[argc] = malloc(n + 1);
		memcpy(argv[argc], data + pos, n);
		argv[argc][n] = '\0';
		argc++;
		pos += n + 1;
	}
	argv[argc] = NULL;
	memcpy(saved, argv, sizeof(argv[0]) * (argc + 1));

	sw_err_clear(&e);
	ret = sw_parse_args(argc, argv, &o, &e);
	if (memcmp(saved, argv, sizeof(argv[0]) * (argc + 1)) != 0)
		abort();
	if (ret == SW_EXIT_OK) {
		if (e.code != SW_EXIT_OK || e.msg[0])
			abort();
		check_opts(&o, argc, argv);
	} else if (ret == SW_EXIT_USAGE) {
		if (e.code != SW_EXIT_USAGE)
			abort();
		check_message(&e);
	} else {
		abort();
	}

	sw_err_clear(&e2);
	ret2 = sw_parse_args(argc, argv, &o2, &e2);
	if (ret2 != ret || strcmp(e.msg, e2.msg) != 0 ||
	    (ret == SW_EXIT_OK && memcmp(&o, &o2, sizeof(o)) != 0))
		abort();

	for (i = 0; i < argc; i++)
		free(argv[i]);
	return 0;
}
