// SPDX-License-Identifier: GPL-2.0-only
/*
 * sentral-warmstart: option parsing and --help.
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
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

static const struct option long_opts[] = {
	{ "device", required_argument, NULL, OPT_DEVICE },
	{ "i2c", required_argument, NULL, OPT_I2C },
	{ "address", required_argument, NULL, OPT_ADDRESS },
	{ "state-dir", required_argument, NULL, OPT_STATE_DIR },
	{ "file", required_argument, NULL, OPT_FILE },
	{ "force", no_argument, NULL, OPT_FORCE },
	{ "if-present", no_argument, NULL, OPT_IF_PRESENT },
	{ "json", no_argument, NULL, OPT_JSON },
	{ "max-score", required_argument, NULL, OPT_MAX_SCORE },
	{ "target-score", required_argument, NULL, OPT_TARGET_SCORE },
	{ "timeout", required_argument, NULL, OPT_TIMEOUT },
	{ "samples", required_argument, NULL, OPT_SAMPLES },
	{ "udev", no_argument, NULL, OPT_UDEV },
	{ "interval", required_argument, NULL, OPT_INTERVAL },
	{ "margin", required_argument, NULL, OPT_MARGIN },
	{ "poll", required_argument, NULL, OPT_POLL },
	{ "no-save", no_argument, NULL, OPT_NO_SAVE },
	{ "daemon", no_argument, NULL, OPT_DAEMON },
	{ "layout", required_argument, NULL, OPT_LAYOUT },
	{ "help", no_argument, NULL, OPT_HELP },
	{ "version", no_argument, NULL, OPT_VERSION },
	{ NULL, 0, NULL, 0 },
};

static const struct {
	const char *name;
	enum sw_command cmd;
} commands[] = {
	{ "status", SW_CMD_STATUS },
	{ "save", SW_CMD_SAVE },
	{ "restore", SW_CMD_RESTORE },
	{ "calibrate", SW_CMD_CALIBRATE },
	{ "accel-cal", SW_CMD_ACCEL_CAL },
	{ "show", SW_CMD_SHOW },
	{ "key", SW_CMD_KEY },
	{ "watch", SW_CMD_WATCH },
	{ "import-board", SW_CMD_IMPORT_BOARD },
};

void sw_usage(FILE *f)
{
	fputs("Usage: sentral-warmstart [--device NAME | --i2c /dev/i2c-N [--address 0x28]]\n"
	      "                         [--state-dir DIR] COMMAND [OPTIONS]\n"
	      "\n"
	      "Save and restore the warm-start calibration of a PNI SENtral / EM7180.\n"
	      "\n"
	      "Commands:\n"
	      "  status [--json] [--file F]      calibration state of the chip and its saved file\n"
	      "  save [--file F] [--force] [--max-score S] [--if-present]\n"
	      "                                  save the calibration if the save policy allows\n"
	      "                                  (stable, level 4; with a score, good enough;\n"
	      "                                  without, different from the saved one)\n"
	      "  restore [--file F] [--if-present] [--force]\n"
	      "                                  write the saved calibration back to the chip\n"
	      "  calibrate [--timeout SEC] [--target-score S] [--max-score S] [--file F] [--force]\n"
	      "            [--json]              guided magnetic calibration with a map of the\n"
	      "                                  directions covered, then save\n"
	      "  accel-cal [--samples N] [--no-save] [--file F]\n"
	      "                                  one-point accelerometer calibration (Z down),\n"
	      "                                  then save the offsets\n"
	      "  show FILE                       decode and check a saved file\n"
	      "  key [--udev]                    print the chip's key (names its file and units)\n"
	      "  watch [--poll SEC] [--interval SEC] [--margin M] [--max-score S] [--file F]\n"
	      "        [--daemon]\n"
	      "                                  stay running and save whenever the calibration\n"
	      "                                  becomes stable and better than (with a score) or\n"
	      "                                  different from (without) the saved one, or the\n"
	      "                                  accel offsets change\n"
	      "  import-board IMAGE [--layout gt|kw] [--file F] [--force]\n"
	      "                                  save the calibration that the USFS utilities\n"
	      "                                  stored in the board's EEPROM (IMAGE: at24's\n"
	      "                                  nvmem file or a dump) for the chip present\n"
	      "\n"
	      "Options:\n"
	      "  -d, --device NAME     em7180 IIO device: iio:deviceN, label, I2C client name\n"
	      "                        (0-0028) or key (default: the only one present)\n"
	      "      --i2c DEV         talk to the chip over i2c-dev (no driver bound)\n"
	      "      --address ADDR    7-bit I2C address with --i2c (default 0x28)\n"
	      "      --state-dir DIR   saved files (default " SW_STATE_DIR ")\n"
	      "  -f, --file F          saved file (default DIR/KEY.ws)\n"
	      "      --force           save a worse calibration, restore a file made for\n"
	      "                        another chip version, import over a saved file,\n"
	      "                        use --i2c with a driver bound\n"
	      "      --if-present      restore: a missing file is not an error;\n"
	      "                        save: a device that is gone is not an error\n"
	      "      --json            status, calibrate: machine-readable output\n"
	      "      --udev            key: udev properties for IMPORT{program}\n"
	      "      --max-score S     acceptable score in percent (default 5.0), where the\n"
	      "                        firmware reports a score\n"
	      "      --target-score S  calibrate: stop at this score (default 3.0); without\n"
	      "                        a score it stops once the calibration is stable\n"
	      "      --timeout SEC     calibrate: give up after SEC seconds (default 120)\n"
	      "      --samples N       accel-cal: samples to average (default 64)\n"
	      "      --no-save         accel-cal: leave the offsets unsaved\n"
	      "      --poll SEC        watch: read the calibration state every SEC seconds,\n"
	      "                        1 to 3600 (default 30)\n"
	      "      --interval SEC    watch: at most one write every SEC seconds (default 300)\n"
	      "      --daemon          watch: detach (the udev rule without systemd); one\n"
	      "                        watcher per chip, the newest replaces an older one\n"
	      "      --margin M        watch: replace a good saved calibration only with a\n"
	      "                        score at least M points lower (default 0.5)\n"
	      "      --layout L        import-board: gt (Greg Tomasch's utility, the default)\n"
	      "                        or kw (Kris Winer's sketches)\n"
	      "  -h, --help            this help\n"
	      "  -V, --version         print the version\n"
	      "\n"
	      "Exit status (sysexits.h; the save policy saying no is a success):\n"
	      "  0 success   64 usage error   65 saved file or EEPROM image refused by a check\n"
	      "  66 saved file or EEPROM image missing   69 no, several, unusable or (watch) vanished device\n"
	      "  71 out of memory   72 state directory missing   74 I/O or bus error\n"
	      "  75 calibration incomplete, timed out or unverified\n"
	      "  77 refused: owner, mode or symbolic link of a file or directory\n"
	      "  78 the em7180 driver is older or newer than this tool\n"
	      "\n"
	      "See sentral-warmstart(8).\n", f);
}

static int parse_double(const char *opt, const char *s, double lo, double hi,
			double *out, struct sw_err *e)
{
	char *end;
	double v;

	errno = 0;
	v = strtod(s, &end);
	if (errno || end == s || *end || !isfinite(v) || v < lo || v > hi)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "%s: '%s' is not a number between %g and %g",
				  opt, s, lo, hi);
	*out = v;
	return SW_EXIT_OK;
}

static int parse_uint(const char *opt, const char *s, unsigned long lo,
		      unsigned long hi, unsigned int *out, struct sw_err *e)
{
	unsigned long v;
	char *end;

	errno = 0;
	v = strtoul(s, &end, 0);
	if (errno || end == s || *end || *s == '-' || v < lo || v > hi)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "%s: '%s' is not a number between %lu and %lu",
				  opt, s, lo, hi);
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
	size_t i;

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
	for (i = 0; long_opts[i].name; i++)
		if (long_opts[i].val == optopt)
			return sw_err_set(e, SW_EXIT_USAGE,
					  "option '--%s' takes no argument",
					  long_opts[i].name);
	if (ch > ' ' && ch < 0x7f)
		return sw_err_set(e, SW_EXIT_USAGE, "unknown option '-%c'", ch);
	return sw_err_set(e, SW_EXIT_USAGE, "unknown option '-\\x%02x'", ch);
}

static const char *command_name(enum sw_command cmd)
{
	size_t i;

	for (i = 0; i < sizeof(commands) / sizeof(commands[0]); i++)
		if (commands[i].cmd == cmd)
			return commands[i].name;
	return "?";
}

/* Which command accepts which command-specific option. */
static int check_option_use(const struct sw_opts *o, const bool *seen,
			    struct sw_err *e)
{
	static const struct {
		int opt;
		const char *name;
		unsigned int cmds;	/* bit per enum sw_command */
	} rules[] = {
		{ OPT_JSON, "--json", 1u << SW_CMD_STATUS |
				      1u << SW_CMD_CALIBRATE },
		{ OPT_IF_PRESENT, "--if-present", 1u << SW_CMD_RESTORE |
						    1u << SW_CMD_SAVE },
		{ OPT_UDEV, "--udev", 1u << SW_CMD_KEY },
		{ OPT_FILE, "--file", 1u << SW_CMD_SAVE | 1u << SW_CMD_RESTORE |
					1u << SW_CMD_CALIBRATE |
					1u << SW_CMD_STATUS |
					1u << SW_CMD_WATCH |
					1u << SW_CMD_ACCEL_CAL |
					1u << SW_CMD_IMPORT_BOARD },
		{ OPT_MAX_SCORE, "--max-score", 1u << SW_CMD_SAVE |
						  1u << SW_CMD_CALIBRATE |
						  1u << SW_CMD_WATCH |
						  1u << SW_CMD_ACCEL_CAL },
		{ OPT_INTERVAL, "--interval", 1u << SW_CMD_WATCH },
		{ OPT_MARGIN, "--margin", 1u << SW_CMD_WATCH },
		{ OPT_POLL, "--poll", 1u << SW_CMD_WATCH },
		{ OPT_DAEMON, "--daemon", 1u << SW_CMD_WATCH },
		{ OPT_NO_SAVE, "--no-save", 1u << SW_CMD_ACCEL_CAL },
		{ OPT_LAYOUT, "--layout", 1u << SW_CMD_IMPORT_BOARD },
		{ OPT_TARGET_SCORE, "--target-score", 1u << SW_CMD_CALIBRATE },
		{ OPT_TIMEOUT, "--timeout", 1u << SW_CMD_CALIBRATE },
		{ OPT_SAMPLES, "--samples", 1u << SW_CMD_ACCEL_CAL },
	};
	size_t i;

	for (i = 0; i < sizeof(rules) / sizeof(rules[0]); i++) {
		if (seen[rules[i].opt] &&
		    !(rules[i].cmds & 1u << o->cmd))
			return sw_err_set(e, SW_EXIT_USAGE,
					  "%s is not an option of '%s'",
					  rules[i].name, command_name(o->cmd));
	}
	if (o->force && !o->i2c_dev && o->cmd != SW_CMD_SAVE &&
	    o->cmd != SW_CMD_RESTORE && o->cmd != SW_CMD_CALIBRATE &&
	    o->cmd != SW_CMD_IMPORT_BOARD)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "--force is not an option of '%s'",
				  command_name(o->cmd));
	if (o->cmd == SW_CMD_SHOW && (o->device || o->i2c_dev))
		return sw_err_set(e, SW_EXIT_USAGE,
				  "show reads a file only; --device, --i2c and --address do not apply");
	return SW_EXIT_OK;
}

/* A non-option: the command, show's FILE or import-board's IMAGE. */
static int operand(const char *arg, struct sw_opts *o, const char **show_file,
		   struct sw_err *e)
{
	size_t i;

	if (o->cmd == SW_CMD_NONE) {
		for (i = 0; i < sizeof(commands) / sizeof(commands[0]); i++)
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

int sw_parse_args(int argc, char **argv, struct sw_opts *o, struct sw_err *e)
{
	bool seen[OPT_LAST + 1] = { false };
	const char *show_file = NULL;
	int c, next, ret;

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

	/* Re-initialise getopt: the parser may run more than once (tests). */
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
			for (next++; next < argc; next++) {
				ret = operand(argv[next], o, &show_file, e);
				if (ret)
					return ret;
			}
			break;
		}
		c = getopt_long(argc, argv, "+:d:f:hV", long_opts, NULL);
		if (c == -1) {
			/* "+": getopt stops at the first non-option. */
			if (optind >= argc)
				break;
			ret = operand(argv[optind++], o, &show_file, e);
			if (ret)
				return ret;
			continue;
		}
		if (c > 0 && c <= OPT_LAST)
			seen[c] = true;
		ret = SW_EXIT_OK;
		switch (c) {
		case OPT_DEVICE:
			o->device = optarg;
			break;
		case OPT_I2C:
			o->i2c_dev = optarg;
			break;
		case OPT_ADDRESS:
			ret = parse_uint("--address", optarg, 0x03, 0x77,
					 &o->address, e);
			break;
		case OPT_STATE_DIR:
			o->state_dir = optarg;
			break;
		case OPT_FILE:
			o->file = optarg;
			break;
		case OPT_FORCE:
			o->force = true;
			break;
		case OPT_IF_PRESENT:
			o->if_present = true;
			break;
		case OPT_JSON:
			o->json = true;
			break;
		case OPT_UDEV:
			o->udev = true;
			break;
		case OPT_MAX_SCORE:
			ret = parse_double("--max-score", optarg, 0, 100,
					   &o->max_score, e);
			break;
		case OPT_TARGET_SCORE:
			ret = parse_double("--target-score", optarg, 0, 100,
					   &o->target_score, e);
			break;
		case OPT_TIMEOUT:
			ret = parse_uint("--timeout", optarg, 1, 86400,
					 &o->timeout_s, e);
			break;
		case OPT_SAMPLES:
			ret = parse_uint("--samples", optarg, 1, 10000,
					 &o->samples, e);
			break;
		case OPT_INTERVAL:
			ret = parse_uint("--interval", optarg, 1, 86400,
					 &o->interval_s, e);
			break;
		case OPT_MARGIN:
			ret = parse_double("--margin", optarg, 0, 100,
					   &o->margin, e);
			break;
		case OPT_POLL:
			ret = parse_uint("--poll", optarg, 1, 3600, &o->poll_s,
					 e);
			break;
		case OPT_NO_SAVE:
			o->no_save = true;
			break;
		case OPT_DAEMON:
			o->daemon = true;
			break;
		case OPT_LAYOUT:
			if (!sw_board_layout_parse(optarg, &o->layout))
				ret = sw_err_set(e, SW_EXIT_USAGE,
						 "--layout: '%s' is neither gt nor kw",
						 optarg);
			break;
		case OPT_HELP:
			o->help = true;
			break;
		case OPT_VERSION:
			o->version = true;
			break;
		default:
			return bad_option(c, argv, e);
		}
		if (ret)
			return ret;
	}

	if (o->help || o->version)
		return SW_EXIT_OK;
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
	if (o->cmd == SW_CMD_WATCH && o->i2c_dev)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "watch needs the em7180 driver: over --i2c each look at the accel offsets would be a parameter transfer, which pauses the chip's algorithm");
	if (o->udev && o->i2c_dev)
		return sw_err_set(e, SW_EXIT_USAGE,
				  "key --udev names an IIO device, not an --i2c one");
	if (o->file && !*o->file)
		return sw_err_set(e, SW_EXIT_USAGE, "--file is empty");
	return SW_EXIT_OK;
}
