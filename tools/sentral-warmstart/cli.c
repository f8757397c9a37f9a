// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: option parsing and --help, both from one table of the
 * options and the commands that take them.
 */
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "i2cbus.h"
#include "policy.h"

enum {
	OPT_DEVICE = 'd',
	OPT_FILE = 'f',
	OPT_HELP = 'h',
	OPT_VERSION = 'V',
	OPT_I2C = 256,
	OPT_ADDRESS,
	OPT_STATE_DIR,
	OPT_FORCE,
	OPT_IF_PRESENT,
	OPT_JSON,
	OPT_MAX_SCORE,
	OPT_TARGET_SCORE,
	OPT_TIMEOUT,
	OPT_SAMPLES,
	OPT_UDEV,
	OPT_INTERVAL,
	OPT_MARGIN,
	OPT_POLL,
	OPT_NO_SAVE,
	OPT_DAEMON,
	OPT_LAYOUT,
	OPT_LAST = OPT_LAYOUT,
};

/* A set of commands: one bit per enum sw_command. */
#define CMD(c)		(1u << (c))
#define ALL_CMDS	((1u << SW_NCMDS) - 1 - CMD(SW_CMD_NONE))
/* The commands that talk to a chip: all but show. */
#define CHIP_CMDS	(ALL_CMDS & ~CMD(SW_CMD_SHOW))
/* ... and over i2c-dev too: all but watch, which needs the driver. */
#define I2C_CMDS	(CHIP_CMDS & ~CMD(SW_CMD_WATCH))
#define SAVING_CMDS	(CMD(SW_CMD_SAVE) | CMD(SW_CMD_CALIBRATE) | \
			 CMD(SW_CMD_WATCH) | CMD(SW_CMD_ACCEL_CAL))

/* Help layout: the width, and where an option's text begins. */
#define WIDTH		80
#define TEXT_COL	24

static const struct {
	const char *name;
	enum sw_command cmd;
	const char *operand;	/* show's FILE, import-board's IMAGE */
	const char *help;	/* lines of at most 74 columns */
} commands[] = {
	{ "status", SW_CMD_STATUS, NULL,
	  "calibration state of the chip and its saved file" },
	{ "save", SW_CMD_SAVE, NULL,
	  "save the calibration if the save policy allows (stable, level 4; with a\n"
	  "score, good enough; without, different from the saved one)" },
	{ "restore", SW_CMD_RESTORE, NULL,
	  "write the saved calibration back to the chip" },
	{ "calibrate", SW_CMD_CALIBRATE, NULL,
	  "guided magnetic calibration with a map of the directions covered, then\n"
	  "save" },
	{ "accel-cal", SW_CMD_ACCEL_CAL, NULL,
	  "one-point accelerometer calibration (Z down), then save the offsets" },
	{ "show", SW_CMD_SHOW, "FILE", "decode and check a saved file" },
	{ "key", SW_CMD_KEY, NULL,
	  "print the chip's key, which names its saved file and its units" },
	{ "watch", SW_CMD_WATCH, NULL,
	  "stay running and save whenever the calibration becomes stable and better\n"
	  "than (with a score) or different from (without) the saved one, or the\n"
	  "accel offsets change" },
	{ "import-board", SW_CMD_IMPORT_BOARD, "IMAGE",
	  "save the calibration that the USFS utilities stored in the board's\n"
	  "EEPROM (IMAGE: at24's nvmem file or a dump) for the chip present" },
};

/*
 * Every option, the commands that take it, and its help: the parser, the
 * synopses and each command's help all come from here, in this order: the
 * options common to the commands first, then the commands' own in the order
 * of their synopses, --help and --version last. A text beginning
 * "COMMAND: " loses that in COMMAND's own help.
 */
static const struct opt {
	int val;
	char letter;		/* short option, or 0 */
	const char *name;
	const char *arg;	/* NULL: takes no argument */
	unsigned int cmds;	/* the commands that take it */
	unsigned int i2c_cmds;	/* ... and those that take it with --i2c */
	bool common;		/* not in a command's synopsis */
	const char *help;	/* lines of at most WIDTH - TEXT_COL columns */
} opts[] = {
	{ OPT_DEVICE, 'd', "device", "NAME", CHIP_CMDS, 0, true,
	  "em7180 IIO device: iio:deviceN, label, I2C client name\n"
	  "(0-0028) or key (default: the only one present)" },
	{ OPT_I2C, 0, "i2c", "BUS", I2C_CMDS, 0, true,
	  "talk to the chip over i2c-dev (no driver bound); BUS:\n"
	  "a number (1), an adapter name or a path (/dev/i2c-1)" },
	{ OPT_ADDRESS, 0, "address", "ADDR", I2C_CMDS, 0, true,
	  "7-bit I2C address with --i2c, 0x08 to 0x77\n"
	  "(default 0x28)" },
	{ OPT_STATE_DIR, 0, "state-dir", "DIR", CHIP_CMDS, 0, true,
	  "saved files (default " SW_STATE_DIR ")" },
	{ OPT_FILE, 'f', "file", "F",
	  CHIP_CMDS & ~CMD(SW_CMD_KEY), 0, false,
	  "saved file (default DIR/KEY.ws)" },
	{ OPT_FORCE, 0, "force", NULL,
	  CMD(SW_CMD_SAVE) | CMD(SW_CMD_RESTORE) | CMD(SW_CMD_CALIBRATE) |
	  CMD(SW_CMD_IMPORT_BOARD), I2C_CMDS, false,
	  "save a worse calibration, restore a file made for\n"
	  "another chip version, import over a saved file,\n"
	  "use --i2c while a kernel driver is bound" },
	{ OPT_JSON, 0, "json", NULL,
	  CMD(SW_CMD_STATUS) | CMD(SW_CMD_CALIBRATE) | CMD(SW_CMD_SHOW) |
	  CMD(SW_CMD_KEY), 0, false,
	  "status, show, key: one JSON object instead of text;\n"
	  "calibrate: one per line" },
	{ OPT_IF_PRESENT, 0, "if-present", NULL,
	  CMD(SW_CMD_RESTORE) | CMD(SW_CMD_SAVE), 0, false,
	  "restore: a missing file is not an error;\n"
	  "save: a device that is gone is not an error" },
	{ OPT_MAX_SCORE, 0, "max-score", "S", SAVING_CMDS, 0, false,
	  "acceptable score in percent, 0 to 100 (default 5.0),\n"
	  "where the firmware reports a score" },
	{ OPT_TARGET_SCORE, 0, "target-score", "S", CMD(SW_CMD_CALIBRATE), 0,
	  false,
	  "calibrate: stop at this score, 0 to 100 (default\n"
	  "3.0); without a score at the first stable calibration" },
	{ OPT_TIMEOUT, 0, "timeout", "SEC", CMD(SW_CMD_CALIBRATE), 0, false,
	  "calibrate: give up after SEC seconds, 1 to 86400\n"
	  "(default 120)" },
	{ OPT_SAMPLES, 0, "samples", "N", CMD(SW_CMD_ACCEL_CAL), 0, false,
	  "accel-cal: samples to average, 1 to 10000 (default 64)" },
	{ OPT_NO_SAVE, 0, "no-save", NULL, CMD(SW_CMD_ACCEL_CAL), 0, false,
	  "accel-cal: leave the offsets unsaved" },
	{ OPT_POLL, 0, "poll", "SEC", CMD(SW_CMD_WATCH), 0, false,
	  "watch: read the calibration state every SEC seconds,\n"
	  "1 to 3600 (default 30)" },
	{ OPT_INTERVAL, 0, "interval", "SEC", CMD(SW_CMD_WATCH), 0, false,
	  "watch: at most one write every SEC seconds, 1 to\n"
	  "86400 (default 300)" },
	{ OPT_MARGIN, 0, "margin", "M", CMD(SW_CMD_WATCH), 0, false,
	  "watch: replace a good saved calibration only with a\n"
	  "score at least M points lower, 0 to 100 (default 0.5)" },
	{ OPT_DAEMON, 0, "daemon", NULL, CMD(SW_CMD_WATCH), 0, false,
	  "watch: detach (the udev rule without systemd); one\n"
	  "watcher per chip, the newest replaces an older one" },
	{ OPT_LAYOUT, 0, "layout", "gt|kw", CMD(SW_CMD_IMPORT_BOARD), 0, false,
	  "import-board: gt (Greg Tomasch's utility, the\n"
	  "default) or kw (Kris Winer's sketches)" },
	{ OPT_UDEV, 0, "udev", NULL, CMD(SW_CMD_KEY), 0, false,
	  "key: udev properties for IMPORT{program}" },
	{ OPT_HELP, 'h', "help", NULL, ALL_CMDS, 0, true,
	  "this help; COMMAND --help: that command's" },
	{ OPT_VERSION, 'V', "version", NULL, ALL_CMDS, 0, true,
	  "print the version" },
};

#define NOPTS (sizeof(opts) / sizeof(opts[0]))
#define NCOMMANDS (sizeof(commands) / sizeof(commands[0]))

/*
 * A command's own text for an option, where the general one would mislead:
 * the first row for the command.
 */
static const struct {
	int val;
	unsigned int cmds;
	const char *help;
} cmd_help[] = {
	{ OPT_FORCE, CMD(SW_CMD_SAVE) | CMD(SW_CMD_CALIBRATE),
	  "save even a worse calibration; with --i2c, also\n"
	  "while a kernel driver is bound" },
	{ OPT_FORCE, CMD(SW_CMD_RESTORE),
	  "restore a file made for another chip version; with\n"
	  "--i2c, also while a kernel driver is bound" },
	{ OPT_FORCE, CMD(SW_CMD_IMPORT_BOARD),
	  "import over a saved file; with --i2c, also while a\n"
	  "kernel driver is bound" },
	{ OPT_FORCE, I2C_CMDS,
	  "with --i2c: use the chip while a kernel driver is\n"
	  "bound" },
	{ OPT_JSON, CMD(SW_CMD_CALIBRATE),
	  "JSON instead of text: one object per line" },
	{ OPT_JSON, ALL_CMDS, "one JSON object instead of text" },
	{ OPT_IF_PRESENT, CMD(SW_CMD_RESTORE),
	  "a missing saved file is not an error" },
	{ OPT_IF_PRESENT, CMD(SW_CMD_SAVE),
	  "a device that is gone (unbound or unplugged) is not\n"
	  "an error" },
	{ OPT_HELP, ALL_CMDS, "this help" },
};

const char *sw_command_name(enum sw_command cmd)
{
	size_t i;

	for (i = 0; i < NCOMMANDS; i++)
		if (commands[i].cmd == cmd)
			return commands[i].name;
	return "?";
}

static const struct opt *opt_of(int val)
{
	size_t i;

	for (i = 0; i < NOPTS; i++)
		if (opts[i].val == val)
			return &opts[i];
	return NULL;
}

/* Lines of text, each indented by col, the first after what is printed. */
static void put_lines(FILE *f, int col, const char *text, int at)
{
	const char *nl;

	for (;;) {
		fprintf(f, "%*s", at < col ? col - at : 0, "");
		nl = strchr(text, '\n');
		fprintf(f, "%.*s\n", nl ? (int)(nl - text) : (int)strlen(text),
			text);
		if (!nl)
			return;
		text = nl + 1;
		at = 0;
	}
}

/* "-d, --device NAME" or "    --i2c BUS", as the option's help row begins. */
static int opt_spec(FILE *f, const struct opt *op)
{
	if (op->letter)
		return fprintf(f, "  -%c, --%s%s%s", op->letter, op->name,
			       op->arg ? " " : "", op->arg ? op->arg : "");
	return fprintf(f, "      --%s%s%s", op->name, op->arg ? " " : "",
		       op->arg ? op->arg : "");
}

/* Words wrapped within WIDTH: the first at column at, the rest at indent. */
static void put_words(FILE *f, const char *const *words, size_t n, int at,
		      int indent)
{
	size_t i;

	for (i = 0; i < n; i++) {
		int len = (int)strlen(words[i]);

		if (i && at + 1 + len > WIDTH) {
			fprintf(f, "\n%*s", indent, "");
			at = indent;
		} else if (i) {
			fputc(' ', f);
			at++;
		}
		fputs(words[i], f);
		at += len;
	}
	fputc('\n', f);
}

/*
 * The words of cmd's synopsis: with prefix, the options common to the
 * commands that talk to a chip first. buf holds the "[--name ARG]" words.
 */
static size_t synopsis(enum sw_command cmd, bool prefix, const char **words,
		       char (*buf)[40])
{
	const char *operand = NULL;
	size_t i, n = 0, nb = 0;

	for (i = 0; i < NCOMMANDS; i++)
		if (commands[i].cmd == cmd)
			operand = commands[i].operand;
	if (prefix && opt_of(OPT_DEVICE)->cmds & CMD(cmd))
		words[n++] = opt_of(OPT_I2C)->cmds & CMD(cmd) ?
			     "[--device NAME | --i2c BUS [--address ADDR]]" :
			     "[--device NAME]";
	if (prefix && opt_of(OPT_STATE_DIR)->cmds & CMD(cmd))
		words[n++] = "[--state-dir DIR]";
	words[n++] = sw_command_name(cmd);
	if (operand)
		words[n++] = operand;
	for (i = 0; i < NOPTS; i++) {
		if (opts[i].common || !(opts[i].cmds & CMD(cmd)))
			continue;
		snprintf(buf[nb], sizeof(buf[nb]), "[--%s%s%s]", opts[i].name,
			 opts[i].arg ? " " : "", opts[i].arg ? opts[i].arg : "");
		words[n++] = buf[nb++];
	}
	return n;
}

static const char exit_status[] =
	"Exit status (sysexits.h; the save policy saying no is a success):\n"
	"  0 success   64 usage error\n"
	"  65 saved file or EEPROM image refused by a check\n"
	"  66 saved file or EEPROM image missing\n"
	"  69 no, several, unusable or (watch) vanished device or I2C bus\n"
	"  71 out of memory   72 state directory missing   74 I/O or bus error\n"
	"  75 calibration incomplete, timed out or unverified\n"
	"  77 refused: owner, mode or symbolic link of a file or directory\n"
	"  78 the em7180 driver is older or newer than this tool\n";

static void usage_all(FILE *f)
{
	const char *words[NOPTS + 4];
	char buf[NOPTS][40];
	size_t i, n;

	fputs("Usage: sentral-warmstart [--device NAME | --i2c BUS [--address ADDR]]\n"
	      "                         [--state-dir DIR] COMMAND [OPTIONS]\n"
	      "       sentral-warmstart [COMMAND] --help\n"
	      "\n"
	      "Save and restore the warm-start calibration of a PNI SENtral / EM7180.\n"
	      "\n"
	      "Commands:\n", f);
	for (i = 0; i < NCOMMANDS; i++) {
		n = synopsis(commands[i].cmd, false, words, buf);
		fputs("  ", f);
		put_words(f, words, n, 2, 3 + (int)strlen(commands[i].name));
		put_lines(f, 4, commands[i].help, 0);
	}
	fputs("\nOptions:\n", f);
	for (i = 0; i < NOPTS; i++)
		put_lines(f, TEXT_COL, opts[i].help, opt_spec(f, &opts[i]));
	fputs("\n"
	      "Numbers are decimal, or hexadecimal after 0x; S and M are decimal (2.5).\n"
	      "\n", f);
	fputs(exit_status, f);
	fputs("\nSee sentral-warmstart(8).\n", f);
}

/* The option's text in cmd's help. */
static const char *opt_help(const struct opt *op, enum sw_command cmd)
{
	const char *name = sw_command_name(cmd);
	size_t i, len = strlen(name);

	for (i = 0; i < sizeof(cmd_help) / sizeof(cmd_help[0]); i++)
		if (cmd_help[i].val == op->val && cmd_help[i].cmds & CMD(cmd))
			return cmd_help[i].help;
	if (!strncmp(op->help, name, len) && !strncmp(op->help + len, ": ", 2))
		return op->help + len + 2;
	return op->help;
}

static void usage_cmd(FILE *f, enum sw_command cmd)
{
	const char *words[NOPTS + 4];
	char buf[NOPTS][40];
	size_t i, n;
	int common;

	fputs("Usage: sentral-warmstart ", f);
	n = synopsis(cmd, true, words, buf);
	put_words(f, words, n, 25, 25);
	fputc('\n', f);
	for (i = 0; i < NCOMMANDS; i++)
		if (commands[i].cmd == cmd)
			put_lines(f, 2, commands[i].help, 0);
	for (common = 0; common < 2; common++) {
		fputs(common ? "\nCommon options:\n" : "\nOptions:\n", f);
		for (i = 0; i < NOPTS; i++)
			if (opts[i].common == common &&
			    (opts[i].cmds | opts[i].i2c_cmds) & CMD(cmd))
				put_lines(f, TEXT_COL, opt_help(&opts[i], cmd),
					  opt_spec(f, &opts[i]));
	}
	fputs("\nExit status: see sentral-warmstart --help, or sentral-warmstart(8).\n",
	      f);
}

void sw_usage(FILE *f, enum sw_command cmd)
{
	if (cmd == SW_CMD_NONE)
		usage_all(f);
	else
		usage_cmd(f, cmd);
}

/*
 * A decimal number for a percentage: digits with at most one '.', nothing
 * else (strtod would also take " 5", "0x5", "1e1", "inf").
 */
static int parse_double(const char *opt, const char *s, double lo, double hi,
			double *out, struct sw_err *e)
{
	size_t digits = strspn(s, "0123456789");
	const char *p = s + digits;
	double v;

	if (*p == '.') {
		p++;
		digits += strspn(p, "0123456789");
		p += strspn(p, "0123456789");
	}
	if (!digits || *p)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "%s: '%s' is not a decimal number", opt, s);
	v = strtod(s, NULL);
	if (v < lo || v > hi)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "%s: '%s' is out of range (%g to %g)", opt, s,
				  lo, hi);
	*out = v;
	return SW_EXIT_OK;
}

static int parse_uint(const char *opt, const char *s, unsigned long lo,
		      unsigned long hi, unsigned int *out, struct sw_err *e)
{
	unsigned long v;
	int err = sw_parse_number(s, hi, &v);

	if (err == EINVAL)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "%s: '%s' is not a number (decimal, or hexadecimal after 0x)",
				  opt, s);
	if (err || v < lo)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "%s: '%s' is out of range (%lu to %lu)", opt, s,
				  lo, hi);
	*out = (unsigned int)v;
	return SW_EXIT_OK;
}

/*
 * A 7-bit address as i2c-tools check one (i2cbusses.c, check_address()):
 * 0x08 to 0x77, the addresses the I2C specification leaves to devices; the
 * errors in hexadecimal, as addresses are written.
 */
static int parse_address(const char *s, unsigned int *out, struct sw_err *e)
{
	unsigned long v;
	int err = sw_parse_number(s, UINT_MAX, &v);

	if (err == EINVAL)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "--address: '%s' is not an address (hexadecimal after 0x, such as 0x28, else decimal)",
				  s);
	if (err || v < 0x08 || v > 0x77) {
		if (!err && strncmp(s, "0x", 2) && strncmp(s, "0X", 2))
			return sw_err_set(e, SW_EXIT_USAGE,
					  "--address: %s (0x%02lx) is out of range (0x08-0x77)",
					  s, v);
		return sw_err_set(e, SW_EXIT_USAGE,
				  "--address: %s is out of range (0x08-0x77)",
				  s);
	}
	*out = (unsigned int)v;
	return SW_EXIT_OK;
}

/*
 * getopt's complaint, naming the option itself. argv[optind - 1] is the
 * offending argument only when getopt has finished with it, which a long
 * option always is but an unknown letter inside a cluster ("-hx") is not:
 * then it may be the previous argument or the program name, and optopt
 * is the letter.
 */
static int bad_option(int c, char **argv, struct sw_err *e)
{
	const char *arg = argv[optind - 1];
	unsigned char ch = (unsigned char)optopt;
	const struct opt *op;

	/* Past the end of the last argument: that argument is the option. */
	if (c == ':') {
		if (!strncmp(arg, "--", 2))
			return sw_err_set(e, SW_EXIT_USAGE,
					  "option '%s' needs an argument", arg);
		return sw_err_set(e, SW_EXIT_USAGE,
				  "option '-%c' needs an argument", ch);
	}
	/* optopt is 0 for an unknown or ambiguous long option. */
	if (!optopt)
		return sw_err_set(e, SW_EXIT_USAGE, "unknown option '%s'", arg);
	/* A known option's value: "--name=ARG" on an option without one. */
	op = opt_of(optopt);
	if (op)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "option '--%s' takes no argument", op->name);
	if (ch > ' ' && ch < 0x7f)
		return sw_err_set(e, SW_EXIT_USAGE, "unknown option '-%c'", ch);
	return sw_err_set(e, SW_EXIT_USAGE, "unknown option '-\\x%02x'", ch);
}

/* Which command takes which option, from opts[]. */
static int check_option_use(const struct sw_opts *o, const bool *seen,
			    struct sw_err *e)
{
	unsigned int cmd = CMD(o->cmd);
	size_t i;

	/* Those with more to say than "not an option" first. */
	if (o->cmd == SW_CMD_SHOW && (o->device || o->i2c_dev))
		return sw_err_set(e, SW_EXIT_USAGE,
				  "show reads a file only; --device, --i2c and --address do not apply");
	if (o->cmd == SW_CMD_WATCH && o->i2c_dev)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "watch needs the em7180 driver: over --i2c each look at the accel offsets would be a parameter transfer, which pauses the chip's algorithm");
	if (o->udev && o->i2c_dev)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "key --udev names an IIO device, not an --i2c one");
	for (i = 0; i < NOPTS; i++) {
		unsigned int cmds = opts[i].cmds;

		if (o->i2c_dev)
			cmds |= opts[i].i2c_cmds;
		if (!seen[opts[i].val] || cmds & cmd)
			continue;
		if (opts[i].i2c_cmds & cmd)
			return sw_err_set(e, SW_EXIT_USAGE,
					  "--%s is an option of '%s' only with --i2c",
					  opts[i].name, sw_command_name(o->cmd));
		return sw_err_set(e, SW_EXIT_USAGE,
				  "--%s is not an option of '%s'",
				  opts[i].name, sw_command_name(o->cmd));
	}
	if (o->json && o->udev)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "key: --json and --udev exclude each other");
	return SW_EXIT_OK;
}

/* A non-option: the command, show's FILE or import-board's IMAGE. */
static int operand(const char *arg, struct sw_opts *o, const char **show_file,
		   struct sw_err *e)
{
	size_t i;

	if (o->cmd == SW_CMD_NONE) {
		for (i = 0; i < NCOMMANDS; i++)
			if (!strcmp(arg, commands[i].name))
				o->cmd = commands[i].cmd;
		if (o->cmd == SW_CMD_NONE)
			return sw_err_set(e, SW_EXIT_USAGE,
					  "unknown command '%s'", arg);
	} else if ((o->cmd == SW_CMD_SHOW || o->cmd == SW_CMD_IMPORT_BOARD) &&
		   !*show_file) {
		*show_file = arg;
	} else {
		return sw_err_set(e, SW_EXIT_USAGE, "unexpected argument '%s'",
				  arg);
	}
	return SW_EXIT_OK;
}

/* One option of opts[] and its value into o. */
static int option(int c, struct sw_opts *o, struct sw_err *e)
{
	switch (c) {
	case OPT_DEVICE:
		o->device = optarg;
		return SW_EXIT_OK;
	case OPT_I2C:
		o->i2c_dev = optarg;
		return sw_i2c_bus_check(optarg, e);
	case OPT_ADDRESS:
		return parse_address(optarg, &o->address, e);
	case OPT_STATE_DIR:
		o->state_dir = optarg;
		return SW_EXIT_OK;
	case OPT_FILE:
		o->file = optarg;
		return SW_EXIT_OK;
	case OPT_FORCE:
		o->force = true;
		return SW_EXIT_OK;
	case OPT_IF_PRESENT:
		o->if_present = true;
		return SW_EXIT_OK;
	case OPT_JSON:
		o->json = true;
		return SW_EXIT_OK;
	case OPT_UDEV:
		o->udev = true;
		return SW_EXIT_OK;
	case OPT_MAX_SCORE:
		return parse_double("--max-score", optarg, 0, 100,
				    &o->max_score, e);
	case OPT_TARGET_SCORE:
		return parse_double("--target-score", optarg, 0, 100,
				    &o->target_score, e);
	case OPT_TIMEOUT:
		return parse_uint("--timeout", optarg, 1, 86400, &o->timeout_s,
				  e);
	case OPT_SAMPLES:
		return parse_uint("--samples", optarg, 1, 10000, &o->samples,
				  e);
	case OPT_INTERVAL:
		return parse_uint("--interval", optarg, 1, 86400,
				  &o->interval_s, e);
	case OPT_MARGIN:
		return parse_double("--margin", optarg, 0, 100, &o->margin, e);
	case OPT_POLL:
		return parse_uint("--poll", optarg, 1, 3600, &o->poll_s, e);
	case OPT_NO_SAVE:
		o->no_save = true;
		return SW_EXIT_OK;
	case OPT_DAEMON:
		o->daemon = true;
		return SW_EXIT_OK;
	case OPT_LAYOUT:
		if (!sw_board_layout_parse(optarg, &o->layout))
			return sw_err_set(e, SW_EXIT_USAGE,
					  "--layout: '%s' is neither gt nor kw",
					  optarg);
		return SW_EXIT_OK;
	case OPT_HELP:
		/* The first of --help and --version wins, as in coreutils. */
		o->help = !o->version;
		return SW_EXIT_OK;
	case OPT_VERSION:
		o->version = !o->help;
		return SW_EXIT_OK;
	}
	/* Every option of opts[] has its case above. */
	return SW_EXIT_OK;
}

/* What is left to check once the whole line is read. */
static int check_complete(struct sw_opts *o, const bool *seen,
			  const char *show_file, struct sw_err *e)
{
	int ret;

	if (o->cmd == SW_CMD_NONE)
		return sw_err_set(e, SW_EXIT_USAGE, "no command given");
	if (o->device && o->i2c_dev)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "--device and --i2c exclude each other");
	if (seen[OPT_ADDRESS] && !o->i2c_dev)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "--address is only meaningful with --i2c");
	ret = check_option_use(o, seen, e);
	if (ret)
		return ret;
	if (o->cmd == SW_CMD_SHOW) {
		if (!show_file)
			return sw_err_set(e, SW_EXIT_USAGE,
					  "show needs a FILE");
		o->file = show_file;
	}
	if (o->cmd == SW_CMD_IMPORT_BOARD) {
		if (!show_file || !*show_file)
			return sw_err_set(e, SW_EXIT_USAGE,
					  "import-board needs the EEPROM IMAGE (at24's nvmem file or a dump)");
		o->image = show_file;
	}
	if (!*o->state_dir)
		return sw_err_set(e, SW_EXIT_USAGE, "--state-dir is empty");
	if (o->file && !*o->file)
		return sw_err_set(e, SW_EXIT_USAGE, "--file is empty");
	return SW_EXIT_OK;
}

int sw_parse_args(int argc, char **argv, struct sw_opts *o, struct sw_err *e)
{
	struct option long_opts[NOPTS + 1];
	char short_opts[2 + 2 * NOPTS + 1] = "+:";
	bool seen[OPT_LAST + 1] = { false };
	const char *show_file = NULL;
	int c, next, ret, err = SW_EXIT_OK;
	size_t i, n = 2;

	memset(o, 0, sizeof(*o));
	o->address = 0x28;
	o->state_dir = SW_STATE_DIR;
	o->max_score = SW_DEFAULT_MAX_SCORE;
	o->target_score = SW_DEFAULT_TARGET_SCORE;
	o->timeout_s = 120;
	o->samples = 64;
	o->interval_s = SW_DEFAULT_INTERVAL_S;
	o->margin = SW_DEFAULT_MARGIN;
	o->poll_s = SW_DEFAULT_POLL_S;

	memset(long_opts, 0, sizeof(long_opts));
	for (i = 0; i < NOPTS; i++) {
		long_opts[i].name = opts[i].name;
		long_opts[i].has_arg = opts[i].arg ? required_argument :
					no_argument;
		long_opts[i].val = opts[i].val;
		if (opts[i].letter) {
			short_opts[n++] = opts[i].letter;
			if (opts[i].arg)
				short_opts[n++] = ':';
		}
	}
	short_opts[n] = '\0';

	/*
	 * Re-initialise getopt: the parser may run more than once (tests).
	 * A mistake does not end the parse: --help or --version further on
	 * still wins, so only the first mistake is kept (sw_err_set()).
	 */
	optind = 0;
	opterr = 0;
	for (;;) {
		/*
		 * "--" is handled here, not by getopt: getopt ends its scan at
		 * it, but the next call after an operand would go on parsing
		 * options, and a second "--" makes it reorder argv even in
		 * "+" mode. optind only ever points at a whole argument here
		 * (inside a cluster it points at the cluster, never "--").
		 */
		next = optind ? optind : 1;
		if (next >= argc)
			break;
		if (!strcmp(argv[next], "--")) {
			for (next++; next < argc && !err; next++)
				err = operand(argv[next], o, &show_file, e);
			break;
		}
		c = getopt_long(argc, argv, short_opts, long_opts, NULL);
		if (c == -1) {
			/* "+": getopt stops at the first non-option. */
			if (optind >= argc)
				break;
			ret = err ? SW_EXIT_OK :
			      operand(argv[optind], o, &show_file, e);
			optind++;
		} else if (c > 0 && c <= OPT_LAST && opt_of(c)) {
			seen[c] = true;
			ret = option(c, o, e);
		} else {
			ret = bad_option(c, argv, e);
		}
		err = err ? err : ret;
	}

	if (o->help || o->version) {
		sw_err_clear(e);
		return SW_EXIT_OK;
	}
	return err ? err : check_complete(o, seen, show_file, e);
}
