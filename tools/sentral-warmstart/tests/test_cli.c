// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: command-line parsing, good and bad.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
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

static void test_errors(void **state)
{
	(void)state;
	expect_usage("no command", NULL);
	expect_usage("--interval is not an option of 'save'", "save",
		     "--interval", "60", NULL);
	expect_usage("--margin is not an option of 'calibrate'", "calibrate",
		     "--margin", "1", NULL);
	expect_usage("--interval: '0' is not a number between 1 and 86400",
		     "watch", "--interval", "0", NULL);
	expect_usage("--margin: '-1' is not a number between 0 and 100",
		     "watch", "--margin", "-1", NULL);
	expect_usage("--poll: '0' is not a number between 1 and 3600",
		     "watch", "--poll", "0", NULL);
	expect_usage("--poll: '3601' is not a number between 1 and 3600",
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
	 * reported as the previous argument (here the program name).
	 */
	expect_usage("unknown option '-Z'", "-hZ", "status", NULL);
	expect_usage("unknown option '--'", "-h-hV", NULL);
	expect_usage("unknown option '-j'", "status", "-jh", NULL);
	expect_usage("unknown option '-\\x01'", "status", "-h\x01", NULL);
	expect_usage("option '-f' needs an argument", "show", "x", "-hf", NULL);
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
	expect_usage("--force is not an option of 'status'", "status", "--force", NULL);
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
	expect_usage("--state-dir is empty", "--state-dir", "", "status", NULL);
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_defaults),
		cmocka_unit_test(test_good),
		cmocka_unit_test(test_end_of_options),
		cmocka_unit_test(test_errors),
	};

	return cmocka_run_group_tests_name("cli", tests, NULL, NULL);
}
