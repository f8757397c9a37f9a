// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: command-line parsing, good and bad.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <cmocka.h>

#include "cli.h"

#define MAXARGS 16

static int parse(struct sw_opts *o, struct sw_err *e, ...)
{
	char *argv[MAXARGS + 1] = { "sentral-warmstart" };
	int argc = 1;
	va_list ap;
	char *a;

	va_start(ap, e);
	while ((a = va_arg(ap, char *)) && argc < MAXARGS)
		argv[argc++] = a;
	va_end(ap);
	argv[argc] = NULL;
	sw_err_clear(e);
	return sw_parse_args(argc, argv, o, e);
}

static void test_defaults(void **state)
{
	struct sw_opts o;
	struct sw_err e;

	(void)state;
	assert_int_equal(parse(&o, &e, "status", NULL), SW_EXIT_OK);
	assert_int_equal(o.cmd, SW_CMD_STATUS);
	assert_null(o.device);
	assert_null(o.i2c_dev);
	assert_int_equal(o.address, 0x28);
	assert_string_equal(o.state_dir, "/var/lib/sentral-warmstart");
	assert_true(o.max_score == 5.0);
	assert_true(o.target_score == 3.0);
	assert_int_equal(o.timeout_s, 120);
	assert_int_equal(o.samples, 64);
	assert_int_equal(o.interval_s, 300);
	assert_int_equal(o.poll_s, 30);
	assert_true(o.margin == 0.5);
	assert_false(o.no_save);
}

static void test_good(void **state)
{
	struct sw_opts o;
	struct sw_err e;

	(void)state;
	assert_int_equal(parse(&o, &e, "--device", "iio:device1", "status",
			       "--json", NULL), SW_EXIT_OK);
	assert_string_equal(o.device, "iio:device1");
	assert_true(o.json);
	assert_int_equal(parse(&o, &e, "--i2c", "/dev/i2c-3", "--address",
			       "0x29", "save", "--file", "/tmp/x.ws", "--force",
			       NULL), SW_EXIT_OK);
	assert_int_equal(o.cmd, SW_CMD_SAVE);
	assert_string_equal(o.i2c_dev, "/dev/i2c-3");
	assert_int_equal(o.address, 0x29);
	assert_string_equal(o.file, "/tmp/x.ws");
	assert_true(o.force);
	assert_int_equal(parse(&o, &e, "import-board",
			       "/sys/bus/nvmem/devices/0-00500/nvmem", "--layout",
			       "kw", "--file", "/tmp/x.ws", "--force", NULL),
			 SW_EXIT_OK);
	assert_int_equal(o.cmd, SW_CMD_IMPORT_BOARD);
	assert_string_equal(o.image, "/sys/bus/nvmem/devices/0-00500/nvmem");
	assert_int_equal(o.layout, SW_BOARD_KW);
	assert_string_equal(o.file, "/tmp/x.ws");
	assert_true(o.force);
	assert_int_equal(parse(&o, &e, "import-board", "img", NULL), SW_EXIT_OK);
	assert_int_equal(o.layout, SW_BOARD_GT);
	assert_null(o.file);
	assert_int_equal(parse(&o, &e, "restore", "--if-present", "--state-dir",
			       "/s", NULL), SW_EXIT_OK);
	assert_true(o.if_present);
	assert_string_equal(o.state_dir, "/s");
	assert_int_equal(parse(&o, &e, "--device", "k", "save", "--if-present",
			       NULL), SW_EXIT_OK);
	assert_true(o.if_present);
	assert_int_equal(parse(&o, &e, "--device", "iio:device0", "key", "--udev",
			       NULL), SW_EXIT_OK);
	assert_int_equal(o.cmd, SW_CMD_KEY);
	assert_true(o.udev);
	assert_int_equal(parse(&o, &e, "show", "a.ws", NULL), SW_EXIT_OK);
	assert_int_equal(o.cmd, SW_CMD_SHOW);
	assert_string_equal(o.file, "a.ws");
	assert_int_equal(parse(&o, &e, "calibrate", "--timeout", "30",
			       "--target-score", "2.5", "--max-score", "4",
			       NULL), SW_EXIT_OK);
	assert_int_equal(o.timeout_s, 30);
	assert_true(o.target_score == 2.5);
	assert_true(o.max_score == 4.0);
	assert_int_equal(parse(&o, &e, "accel-cal", "--samples", "16", NULL),
			 SW_EXIT_OK);
	assert_int_equal(o.samples, 16);
	assert_int_equal(parse(&o, &e, "accel-cal", "--no-save", NULL),
			 SW_EXIT_OK);
	assert_true(o.no_save);
	assert_int_equal(parse(&o, &e, "--device", "iio:device0", "watch",
			       "--interval", "60", "--margin", "0.25",
			       "--max-score", "4", "--poll", "3600", NULL),
			 SW_EXIT_OK);
	assert_int_equal(o.cmd, SW_CMD_WATCH);
	assert_int_equal(o.interval_s, 60);
	assert_int_equal(o.poll_s, 3600);
	assert_true(o.margin == 0.25);
	assert_true(o.max_score == 4.0);
	assert_false(o.improve_only);
	assert_int_equal(parse(&o, &e, "--help", NULL), SW_EXIT_OK);
	assert_true(o.help);
	assert_int_equal(parse(&o, &e, "-V", NULL), SW_EXIT_OK);
	assert_true(o.version);
	/* Parsing twice in one process works (getopt is re-initialised). */
	assert_int_equal(parse(&o, &e, "-d", "em7180", "save", NULL),
			 SW_EXIT_OK);
	assert_string_equal(o.device, "em7180");
}

/*
 * "--" ends the options. Found by fuzz/fuzz_cli: options after an operand
 * that followed "--" were still parsed, and a second "--" made getopt
 * reorder argv.
 */
static void test_end_of_options(void **state)
{
	char *argv[] = { "sentral-warmstart", "show", "--", "a", "--", "b",
			 NULL };
	char *copy[sizeof(argv) / sizeof(argv[0])];
	struct sw_opts o;
	struct sw_err e;

	(void)state;
	assert_int_equal(parse(&o, &e, "show", "--", "--json", NULL),
			 SW_EXIT_OK);
	assert_string_equal(o.file, "--json");
	assert_false(o.json);
	assert_int_equal(parse(&o, &e, "--", "status", NULL), SW_EXIT_OK);
	assert_int_equal(o.cmd, SW_CMD_STATUS);
	assert_int_equal(parse(&o, &e, "-d", "--", "status", NULL), SW_EXIT_OK);
	assert_string_equal(o.device, "--");
	assert_int_equal(parse(&o, &e, "show", "--", "a", "--json", NULL),
			 SW_EXIT_USAGE);
	assert_string_equal(e.msg, "unexpected argument '--json'");

	memcpy(copy, argv, sizeof(argv));
	sw_err_clear(&e);
	assert_int_equal(sw_parse_args(6, argv, &o, &e), SW_EXIT_USAGE);
	assert_string_equal(e.msg, "unexpected argument '--'");
	assert_memory_equal(copy, argv, sizeof(argv));
}

static void expect_usage(const char *want, ...)
{
	char *argv[MAXARGS + 1] = { "sentral-warmstart" };
	struct sw_opts o;
	struct sw_err e;
	int argc = 1;
	va_list ap;
	char *a;

	va_start(ap, want);
	while ((a = va_arg(ap, char *)) && argc < MAXARGS)
		argv[argc++] = a;
	va_end(ap);
	argv[argc] = NULL;
	sw_err_clear(&e);
	assert_int_equal(sw_parse_args(argc, argv, &o, &e), SW_EXIT_USAGE);
	if (!strstr(e.msg, want))
		fail_msg("message \"%s\" lacks \"%s\"", e.msg, want);
}

/*
 * Issue 33.3: numbers are decimal, hexadecimal only after 0x. strtoul's
 * base 0 refused "--timeout 08" and read "--poll 010" as 8 s, and took
 * " 5" and "+5".
 */
static void test_numbers(void **state)
{
	struct sw_opts o;
	struct sw_err e;

	(void)state;
	assert_int_equal(parse(&o, &e, "calibrate", "--timeout", "08", NULL),
			 SW_EXIT_OK);
	assert_int_equal(o.timeout_s, 8);
	assert_int_equal(parse(&o, &e, "watch", "--poll", "010", "--interval",
			       "0x3c", NULL), SW_EXIT_OK);
	assert_int_equal(o.poll_s, 10);
	assert_int_equal(o.interval_s, 60);
	assert_int_equal(parse(&o, &e, "accel-cal", "--samples", "0X10",
			       "--max-score", "05", NULL), SW_EXIT_OK);
	assert_int_equal(o.samples, 16);
	assert_true(o.max_score == 5.0);
	assert_int_equal(parse(&o, &e, "watch", "--margin", ".5", NULL),
			 SW_EXIT_OK);
	assert_true(o.margin == 0.5);
	assert_int_equal(parse(&o, &e, "calibrate", "--target-score", "2.",
			 NULL), SW_EXIT_OK);
	assert_true(o.target_score == 2.0);

	expect_usage("--timeout: ' 5' is not a number (decimal, or hexadecimal after 0x)",
		     "calibrate", "--timeout", " 5", NULL);
	expect_usage("--timeout: '+5' is not a number", "calibrate",
		     "--timeout", "+5", NULL);
	expect_usage("--timeout: '-5' is not a number", "calibrate",
		     "--timeout", "-5", NULL);
	expect_usage("--timeout: '5s' is not a number", "calibrate",
		     "--timeout", "5s", NULL);
	expect_usage("--timeout: '0x' is not a number", "calibrate",
		     "--timeout", "0x", NULL);
	expect_usage("--timeout: '' is not a number", "calibrate",
		     "--timeout", "", NULL);
	expect_usage("--poll: '08.5' is not a number", "watch", "--poll",
		     "08.5", NULL);
	expect_usage("--samples: '99999999999999999999999' is out of range (1 to 10000)",
		     "accel-cal", "--samples", "99999999999999999999999", NULL);
	expect_usage("--interval: '0x100000000' is out of range (1 to 86400)",
		     "watch", "--interval", "0x100000000", NULL);
	expect_usage("--max-score: '0x5' is not a decimal number", "save",
		     "--max-score", "0x5", NULL);
	expect_usage("--max-score: '1e1' is not a decimal number", "save",
		     "--max-score", "1e1", NULL);
	expect_usage("--max-score: 'inf' is not a decimal number", "save",
		     "--max-score", "inf", NULL);
	expect_usage("--max-score: ' 5' is not a decimal number", "save",
		     "--max-score", " 5", NULL);
	expect_usage("--max-score: '.' is not a decimal number", "save",
		     "--max-score", ".", NULL);
	expect_usage("--target-score: '100.5' is out of range (0 to 100)",
		     "calibrate", "--target-score", "100.5", NULL);
	expect_usage("--margin: '1000000000000000000000000000000000000000' is out of range (0 to 100)",
		     "watch", "--margin",
		     "1000000000000000000000000000000000000000", NULL);
}

/*
 * Issue 33.3: addresses as i2c-tools take them, 0x08 to 0x77, and the
 * errors in hexadecimal; 0x28 and 0x29 (the EM7180's two) still work.
 */
static void test_address(void **state)
{
	static const struct {
		const char *arg;
		unsigned int addr;
	} good[] = {
		{ "0x28", 0x28 }, { "0x29", 0x29 }, { "40", 0x28 },
		{ "041", 0x29 }, { "0X08", 0x08 }, { "0x77", 0x77 },
		{ "8", 0x08 },
	};
	struct sw_opts o;
	struct sw_err e;
	size_t i;

	(void)state;
	for (i = 0; i < sizeof(good) / sizeof(good[0]); i++) {
		assert_int_equal(parse(&o, &e, "--i2c", "1", "--address",
				       good[i].arg, "status", NULL),
				 SW_EXIT_OK);
		assert_int_equal(o.address, good[i].addr);
	}
	expect_usage("--address: 0x80 is out of range (0x08-0x77)", "--i2c",
		     "1", "--address", "0x80", "status", NULL);
	expect_usage("--address: 128 (0x80) is out of range (0x08-0x77)",
		     "--i2c", "1", "--address", "128", "status", NULL);
	expect_usage("--address: 0x03 is out of range (0x08-0x77)", "--i2c",
		     "1", "--address", "0x03", "status", NULL);
	expect_usage("--address: 7 (0x07) is out of range (0x08-0x77)",
		     "--i2c", "1", "--address", "7", "status", NULL);
	expect_usage("--address: 0x78 is out of range (0x08-0x77)", "--i2c",
		     "1", "--address", "0x78", "status", NULL);
	expect_usage("--address: 0x100000028 is out of range (0x08-0x77)",
		     "--i2c", "1", "--address", "0x100000028", "status", NULL);
	expect_usage("--address: 'zz' is not an address (hexadecimal after 0x, such as 0x28, else decimal)",
		     "--i2c", "1", "--address", "zz", "status", NULL);
	expect_usage("--address: '28h' is not an address", "--i2c", "1",
		     "--address", "28h", "status", NULL);
}

/*
 * Issue 33.3: --i2c takes a bus number, a name or a path; the parser
 * refuses only what no bus can be (i2cbus.h looks the name up).
 */
static void test_i2c_bus(void **state)
{
	struct sw_opts o;
	struct sw_err e;

	(void)state;
	assert_int_equal(parse(&o, &e, "--i2c", "1", "status", NULL),
			 SW_EXIT_OK);
	assert_string_equal(o.i2c_dev, "1");
	assert_int_equal(parse(&o, &e, "--i2c", "i2c-tiny-usb at bus 001 device 005",
			       "key", NULL), SW_EXIT_OK);
	assert_int_equal(parse(&o, &e, "--i2c", "1048575", "status", NULL),
			 SW_EXIT_OK);
	expect_usage("--i2c: bus '1048576' is out of range (0 to 1048575)",
		     "--i2c", "1048576", "status", NULL);
	expect_usage("--i2c is empty", "--i2c", "", "status", NULL);
}

/*
 * Issue 33.3: --help and --version win over anything else on the line, as
 * in coreutils, even over a mistake; the first of them given wins. Before,
 * "--version extra" was "unknown command 'extra'", exit 64.
 */
static void test_help_wins(void **state)
{
	struct sw_opts o;
	struct sw_err e;

	(void)state;
	assert_int_equal(parse(&o, &e, "--version", "extra", NULL), SW_EXIT_OK);
	assert_true(o.version);
	assert_false(o.help);
	assert_string_equal(e.msg, "");
	assert_int_equal(parse(&o, &e, "extra", "--version", NULL), SW_EXIT_OK);
	assert_true(o.version);
	assert_int_equal(parse(&o, &e, "status", "--bogus", "--timeout", "x",
			       "--help", NULL), SW_EXIT_OK);
	assert_true(o.help);
	assert_int_equal(o.cmd, SW_CMD_STATUS);
	assert_int_equal(parse(&o, &e, "--help", "accel-cal", NULL), SW_EXIT_OK);
	assert_int_equal(o.cmd, SW_CMD_ACCEL_CAL);
	/* A command after a mistake is not taken: the whole help then. */
	assert_int_equal(parse(&o, &e, "frobnicate", "status", "-h", NULL),
			 SW_EXIT_OK);
	assert_true(o.help);
	assert_int_equal(o.cmd, SW_CMD_NONE);
	assert_int_equal(parse(&o, &e, "--help", "--version", NULL), SW_EXIT_OK);
	assert_true(o.help);
	assert_false(o.version);
	assert_int_equal(parse(&o, &e, "-V", "-h", NULL), SW_EXIT_OK);
	assert_true(o.version);
	assert_false(o.help);
	assert_int_equal(parse(&o, &e, "-hZ", "status", NULL), SW_EXIT_OK);
	assert_true(o.help);
	assert_int_equal(parse(&o, &e, "--i2c", "", "--address", "0x80", "watch",
			       "-V", NULL), SW_EXIT_OK);
	assert_true(o.version);
	/* Not an option: an option's value, or past "--". */
	assert_int_equal(parse(&o, &e, "save", "--file", "--help", NULL),
			 SW_EXIT_OK);
	assert_false(o.help);
	assert_string_equal(o.file, "--help");
	assert_int_equal(parse(&o, &e, "show", "--", "--version", NULL),
			 SW_EXIT_OK);
	assert_false(o.version);
	assert_string_equal(o.file, "--version");
	expect_usage("unexpected argument '--help'", "show", "a", "--",
		     "--help", NULL);
}

/* Each help text as --help prints it. */
static char *help_text(enum sw_command cmd)
{
	char *buf = NULL;
	size_t len = 0;
	FILE *f = open_memstream(&buf, &len);

	assert_non_null(f);
	sw_usage(f, cmd);
	assert_int_equal(fclose(f), 0);
	return buf;
}

/*
 * Issue 33.3: every help text within 80 columns, in plain ASCII. Before,
 * five lines of --help passed 80.
 */
static void test_help_width(void **state)
{
	int cmd;

	(void)state;
	for (cmd = SW_CMD_NONE; cmd < SW_NCMDS; cmd++) {
		char *text = help_text((enum sw_command)cmd), *line, *next;

		for (line = text; *line; line = next + 1) {
			const char *c;

			next = strchr(line, '\n');
			assert_non_null(next);
			for (c = line; c < next; c++)
				if (*c < ' ' || *c > '~')
					fail_msg("%s --help: not ASCII: %.*s",
						 sw_command_name(cmd),
						 (int)(next - line), line);
			if (next - line > 80)
				fail_msg("%s --help: %d columns: %.*s",
					 sw_command_name(cmd),
					 (int)(next - line),
					 (int)(next - line), line);
		}
		free(text);
	}
}

/* Every option, with a value the parser takes. */
static const struct {
	const char *opt;
	const char *arg;
	bool common;		/* not in the synopsis of a command */
} all_opts[] = {
	{ "--device", "x", true }, { "--i2c", "1", true },
	{ "--address", "0x29", true }, { "--state-dir", "/s", true },
	{ "--help", NULL, true }, { "--version", NULL, true },
	{ "--file", "f", false }, { "--force", NULL, false },
	{ "--json", NULL, false }, { "--if-present", NULL, false },
	{ "--max-score", "4", false }, { "--target-score", "2", false },
	{ "--timeout", "30", false }, { "--samples", "16", false },
	{ "--no-save", NULL, false }, { "--poll", "5", false },
	{ "--interval", "60", false }, { "--margin", "1", false },
	{ "--daemon", NULL, false }, { "--layout", "kw", false },
	{ "--udev", NULL, false },
};

/* How cmd takes option i, as the parser says: by itself, with --i2c. */
#define BY_ITSELF 1
#define WITH_I2C 2

static int takes(enum sw_command cmd, size_t i)
{
	char *argv[8] = { "sentral-warmstart" };
	struct sw_opts o;
	struct sw_err e;
	int argc, with_i2c, how = 0;

	for (with_i2c = 0; with_i2c < 2; with_i2c++) {
		argc = 1;
		if (with_i2c) {
			argv[argc++] = "--i2c";
			argv[argc++] = "1";
		}
		argv[argc++] = (char *)sw_command_name(cmd);
		if (cmd == SW_CMD_SHOW || cmd == SW_CMD_IMPORT_BOARD)
			argv[argc++] = "x";
		argv[argc++] = (char *)all_opts[i].opt;
		if (all_opts[i].arg)
			argv[argc++] = (char *)all_opts[i].arg;
		argv[argc] = NULL;
		sw_err_clear(&e);
		if (sw_parse_args(argc, argv, &o, &e) == SW_EXIT_OK)
			how |= with_i2c ? WITH_I2C : BY_ITSELF;
	}
	return how;
}

static size_t opt_index(const char *name)
{
	size_t i;

	for (i = 0; strcmp(all_opts[i].opt, name); i++)
		;
	return i;
}

/* The part of the whole help about cmd: its synopsis and description. */
static char *cmd_block(const char *text, enum sw_command cmd)
{
	char want[32], *start, *end;

	snprintf(want, sizeof(want), "\n  %s ", sw_command_name(cmd));
	start = strstr(text, want);
	assert_non_null(start);
	start += 3;
	for (end = strchr(start, '\n'); end[1] == ' ' && end[2] == ' ' &&
	     (end[3] == ' ' || end[3] == '['); end = strchr(end + 1, '\n'))
		;
	return strndup(start, (size_t)(end - start));
}

/*
 * Issue 33.3: each command's help lists every option it takes and no
 * other, as the parser takes them: the whole help's synopsis of the
 * command its own options, COMMAND --help every option with its text.
 * Before, accel-cal's synopsis lacked --max-score.
 */
static void test_help_lists_options(void **state)
{
	char *all = help_text(SW_CMD_NONE), *text, *block;
	char row[40], row_short[40];
	int cmd;
	size_t i;

	(void)state;
	for (cmd = SW_CMD_STATUS; cmd < SW_NCMDS; cmd++) {
		text = help_text((enum sw_command)cmd);
		block = cmd_block(all, (enum sw_command)cmd);
		for (i = 0; i < sizeof(all_opts) / sizeof(all_opts[0]); i++) {
			const char *name = all_opts[i].opt;
			int how = takes((enum sw_command)cmd, i);
			bool take = how, alone = how & BY_ITSELF;
			char syn[40];

			snprintf(row, sizeof(row), "\n      %s", name);
			snprintf(row_short, sizeof(row_short), "\n  -%c, %s",
				 name[2] == 'v' ? 'V' : name[2], name);
			if (take != (strstr(text, row) || strstr(text, row_short)))
				fail_msg("%s: parser %s %s, its --help %s",
					 sw_command_name(cmd),
					 take ? "takes" : "refuses", name,
					 take ? "omits it" : "lists it");
			if (all_opts[i].common)
				continue;
			/* Only with --i2c (--force of status): --i2c's business. */
			snprintf(syn, sizeof(syn), "[%s", name);
			if (alone != !!strstr(block, syn))
				fail_msg("%s: parser %s %s, the synopsis in --help %s",
					 sw_command_name(cmd),
					 alone ? "takes" : "refuses", name,
					 alone ? "omits it" : "lists it");
		}
		free(block);
		free(text);
	}
	free(all);
	/* What the issue named, in so many words. */
	assert_int_equal(takes(SW_CMD_ACCEL_CAL, opt_index("--max-score")),
			 BY_ITSELF | WITH_I2C);
	assert_int_equal(takes(SW_CMD_SHOW, opt_index("--json")), BY_ITSELF);
	assert_int_equal(takes(SW_CMD_KEY, opt_index("--json")),
			 BY_ITSELF | WITH_I2C);
	assert_int_equal(takes(SW_CMD_STATUS, opt_index("--force")), WITH_I2C);
	assert_int_equal(takes(SW_CMD_WATCH, opt_index("--i2c")), 0);
}

static void test_errors(void **state)
{
	(void)state;
	expect_usage("no command", NULL);
	expect_usage("--interval is not an option of 'save'", "save",
		     "--interval", "60", NULL);
	expect_usage("--margin is not an option of 'calibrate'", "calibrate",
		     "--margin", "1", NULL);
	expect_usage("--interval: '0' is out of range (1 to 86400)",
		     "watch", "--interval", "0", NULL);
	expect_usage("--margin: '-1' is not a decimal number",
		     "watch", "--margin", "-1", NULL);
	expect_usage("--poll: '0' is out of range (1 to 3600)",
		     "watch", "--poll", "0", NULL);
	expect_usage("--poll: '3601' is out of range (1 to 3600)",
		     "watch", "--poll", "3601", NULL);
	expect_usage("--poll is not an option of 'save'", "save", "--poll",
		     "5", NULL);
	expect_usage("--no-save is not an option of 'calibrate'", "calibrate",
		     "--no-save", NULL);
	expect_usage("watch needs the em7180 driver", "--i2c", "/dev/i2c-0",
		     "watch", NULL);
	expect_usage("no command", "--device", "x", NULL);
	expect_usage("unknown command 'frobnicate'", "frobnicate", NULL);
	expect_usage("import-board needs the EEPROM IMAGE", "import-board",
		     NULL);
	expect_usage("--layout: 'ab' is neither gt nor kw", "import-board",
		     "x", "--layout", "ab", NULL);
	expect_usage("--layout is not an option of 'save'", "save",
		     "--layout", "gt", NULL);
	expect_usage("unexpected argument 'y'", "import-board", "x", "y",
		     NULL);
	expect_usage("unknown option '--bogus'", "status", "--bogus", NULL);
	expect_usage("needs an argument", "status", "--device", NULL);
	/*
	 * Found by fuzz/fuzz_cli: an unknown letter inside a cluster was
	 * reported as the previous argument (here the program name). A
	 * cluster holds -h or -V, which now win (test_help_wins).
	 */
	expect_usage("unknown option '-Z'", "-Z", "status", NULL);
	expect_usage("unknown option '-j'", "status", "-j", NULL);
	expect_usage("unknown option '-\\x01'", "status", "-\x01", NULL);
	expect_usage("option '-f' needs an argument", "show", "x", "-f", NULL);
	expect_usage("option '--file' needs an argument", "save", "--file",
		     NULL);
	expect_usage("option '--force' takes no argument", "--force=1", "save",
		     NULL);
	expect_usage("unknown option '--f'", "--f", "save", NULL);
	expect_usage("exclude each other", "--device", "a", "--i2c",
		     "/dev/i2c-0", "status", NULL);
	expect_usage("--address is only meaningful", "--address", "0x28",
		     "status", NULL);
	expect_usage("--address", "--i2c", "/dev/i2c-0", "--address", "0x80",
		     "status", NULL);
	expect_usage("--address", "--i2c", "/dev/i2c-0", "--address", "zz",
		     "status", NULL);
	expect_usage("--json is not an option of 'save'", "save", "--json", NULL);
	expect_usage("--if-present is not an option", "accel-cal",
		     "--if-present", NULL);
	expect_usage("--udev is not an option of 'status'", "status", "--udev",
		     NULL);
	expect_usage("key --udev names an IIO device", "--i2c", "/dev/i2c-0",
		     "key", "--udev", NULL);
	expect_usage("--timeout is not an option", "save", "--timeout", "3",
		     NULL);
	expect_usage("--samples is not an option", "calibrate", "--samples",
		     "3", NULL);
	expect_usage("--force is an option of 'status' only with --i2c",
		     "status", "--force", NULL);
	expect_usage("--force is not an option of 'watch'", "watch", "--force",
		     NULL);
	expect_usage("--timeout", "calibrate", "--timeout", "0", NULL);
	expect_usage("--timeout", "calibrate", "--timeout", "-5", NULL);
	expect_usage("--max-score", "save", "--max-score", "nan", NULL);
	expect_usage("--max-score", "save", "--max-score", "101", NULL);
	expect_usage("--samples", "accel-cal", "--samples", "0", NULL);
	expect_usage("show needs a FILE", "show", NULL);
	expect_usage("unexpected argument 'b.ws'", "show", "a.ws", "b.ws", NULL);
	expect_usage("unexpected argument 'extra'", "status", "extra", NULL);
	expect_usage("show reads a file only", "--device", "x", "show", "a.ws",
		     NULL);
	expect_usage("--state-dir is not an option of 'show'", "show", "a.ws",
		     "--state-dir", "/s", NULL);
	expect_usage("key: --json and --udev exclude each other", "key",
		     "--json", "--udev", NULL);
	expect_usage("--state-dir is empty", "--state-dir", "", "status", NULL);
}

/* s with each '-' as troff writes it, "\-". */
static void troff_dashes(const char *s, char *out, size_t len)
{
	size_t n = 0;

	for (; *s && n + 3 < len; s++) {
		if (*s == '-')
			out[n++] = '\\';
		out[n++] = *s;
	}
	out[n] = '\0';
}

/* The heading (the line after .TP) in the man page that begins with what. */
static char *man_heading(const char *man, const char *section, const char *what)
{
	const char *start = strstr(man, section), *end, *p;
	size_t n = strlen(what);

	assert_non_null(start);
	end = strstr(start + 1, "\n.SH ");
	for (p = start; (p = strstr(p, "\n.TP\n.B")) && p < end; p += 4) {
		const char *line = p + 5, *word = strchr(line, ' ');
		const char *eol = strchr(line, '\n');

		if (word && word < eol && !strncmp(word + 1, what, n) &&
		    strchr(" \"\n", word[1 + n]))
			return strndup(line, (size_t)(eol - line));
	}
	return NULL;
}

/*
 * Issue 33.3: the man page in step with the parser: each command's
 * heading under COMMANDS names the options it takes by itself, and OPTIONS
 * has an entry for every option. Before, show's and key's headings lacked
 * --json (they took none).
 */
static void test_man_page_lists_options(void **state)
{
	char *man = NULL, name[64], opt[64], *heading;
	size_t len = 0, i;
	int cmd;
	FILE *f = fopen("sentral-warmstart.8", "r");

	(void)state;
	if (!f)
		fail_msg("sentral-warmstart.8: run from tools/sentral-warmstart (make check)");
	assert_true(getdelim(&man, &len, '\0', f) > 0);
	fclose(f);
	for (cmd = SW_CMD_STATUS; cmd < SW_NCMDS; cmd++) {
		troff_dashes(sw_command_name(cmd), name, sizeof(name));
		heading = man_heading(man, "\n.SH COMMANDS\n", name);
		if (!heading)
			fail_msg("sentral-warmstart.8: no heading for %s",
				 sw_command_name(cmd));
		for (i = 0; i < sizeof(all_opts) / sizeof(all_opts[0]); i++) {
			bool alone;

			if (all_opts[i].common)
				continue;
			alone = takes((enum sw_command)cmd, i) & BY_ITSELF;
			troff_dashes(all_opts[i].opt, opt, sizeof(opt));
			if (alone != !!strstr(heading, opt))
				fail_msg("sentral-warmstart.8: %s %s %s, its heading %s",
					 sw_command_name(cmd),
					 alone ? "takes" : "refuses",
					 all_opts[i].opt,
					 alone ? "omits it" : "names it");
		}
		free(heading);
	}
	for (i = 0; i < sizeof(all_opts) / sizeof(all_opts[0]); i++) {
		troff_dashes(all_opts[i].opt, opt, sizeof(opt));
		heading = man_heading(man, "\n.SH OPTIONS\n", opt);
		if (!heading) {
			char both[80];

			/* "-d, --device": the short form first */
			snprintf(both, sizeof(both), "\\-%c \", \" %s",
				 opt[4] == 'v' ? 'V' : opt[4], opt);
			heading = man_heading(man, "\n.SH OPTIONS\n", both);
		}
		if (!heading)
			fail_msg("sentral-warmstart.8: OPTIONS lacks %s",
				 all_opts[i].opt);
		free(heading);
	}
	free(man);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_defaults),
		cmocka_unit_test(test_good),
		cmocka_unit_test(test_end_of_options),
		cmocka_unit_test(test_errors),
		cmocka_unit_test(test_numbers),
		cmocka_unit_test(test_address),
		cmocka_unit_test(test_i2c_bus),
		cmocka_unit_test(test_help_wins),
		cmocka_unit_test(test_help_width),
		cmocka_unit_test(test_help_lists_options),
		cmocka_unit_test(test_man_page_lists_options),
	};

	return cmocka_run_group_tests_name("cli", tests, NULL, NULL);
}
