// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: finding things in sysfs, on fake trees: the bus of --i2c
 * BUS (i2cbus.h) and why libiio could not list the IIO devices
 * (sw_iio_scan_err()).
 */
#include <errno.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <cmocka.h>

#include "backend.h"
#include "i2cbus.h"

struct tree {
	char root[64];
};

static int setup(void **state)
{
	struct tree *t = calloc(1, sizeof(*t));

	strcpy(t->root, "/tmp/sw-sysfs-XXXXXX");
	if (!t || !mkdtemp(t->root))
		return -1;
	*state = t;
	return 0;
}

static int teardown(void **state)
{
	struct tree *t = *state;
	char cmd[256];

	snprintf(cmd, sizeof(cmd), "chmod -R u+rwx '%s'; rm -rf '%s'", t->root,
		 t->root);
	if (system(cmd) != 0)
		return -1;
	free(t);
	return 0;
}

static const char *at(struct tree *t, const char *rel)
{
	static char path[4][256];
	static int i;

	i = (i + 1) % 4;
	snprintf(path[i], sizeof(path[i]), "%s/%s", t->root, rel);
	return path[i];
}

static void mkdir_p(struct tree *t, const char *rel)
{
	char cmd[512];

	snprintf(cmd, sizeof(cmd), "mkdir -p '%s'", at(t, rel));
	assert_int_equal(system(cmd), 0);
}

static void write_file(struct tree *t, const char *rel, const char *text)
{
	FILE *f = fopen(at(t, rel), "w");

	assert_non_null(f);
	fputs(text, f);
	assert_int_equal(fclose(f), 0);
}

/* An i2c-dev class directory: adapter i2c-N named name. */
static void adapter(struct tree *t, int nr, const char *name)
{
	char rel[64], text[128];

	snprintf(rel, sizeof(rel), "class/i2c-%d", nr);
	mkdir_p(t, rel);
	snprintf(rel, sizeof(rel), "class/i2c-%d/name", nr);
	snprintf(text, sizeof(text), "%s\n", name);
	write_file(t, rel, text);
}

static int bus_path(struct tree *t, const char *bus, char *path,
		    struct sw_err *e)
{
	sw_err_clear(e);
	path[0] = '\0';
	return sw_i2c_bus_path(bus, at(t, "class"), path, 256, e);
}

/*
 * Issue 33.3: --i2c takes a bus as i2c-tools do, a number or an adapter's
 * exact name, and a path as before. Before, "--i2c 1" opened a file "1".
 */
static void test_i2c_bus(void **state)
{
	struct tree *t = *state;
	char path[256];
	struct sw_err e;

	adapter(t, 0, "sentral-sim");
	adapter(t, 1, "i2c-0-mux (chan_id 0)");
	adapter(t, 3, "AUX B/DDI B/PHY B");
	adapter(t, 10, "sentral-sim-1");
	mkdir_p(t, "class/not-an-adapter");

	assert_int_equal(bus_path(t, "1", path, &e), SW_EXIT_OK);
	assert_string_equal(path, "/dev/i2c-1");
	/* decimal: a leading 0 is no octal */
	assert_int_equal(bus_path(t, "010", path, &e), SW_EXIT_OK);
	assert_string_equal(path, "/dev/i2c-10");
	assert_int_equal(bus_path(t, "0x1f", path, &e), SW_EXIT_OK);
	assert_string_equal(path, "/dev/i2c-31");
	/* a number needs no adapter in sysfs: the node decides */
	assert_int_equal(bus_path(t, "1048575", path, &e), SW_EXIT_OK);
	assert_string_equal(path, "/dev/i2c-1048575");
	assert_int_equal(bus_path(t, "sentral-sim", path, &e), SW_EXIT_OK);
	assert_string_equal(path, "/dev/i2c-0");
	assert_int_equal(bus_path(t, "sentral-sim-1", path, &e), SW_EXIT_OK);
	assert_string_equal(path, "/dev/i2c-10");
	assert_int_equal(bus_path(t, "i2c-0-mux (chan_id 0)", path, &e),
			 SW_EXIT_OK);
	assert_string_equal(path, "/dev/i2c-1");
	/* a name with a '/' is a name */
	assert_int_equal(bus_path(t, "AUX B/DDI B/PHY B", path, &e),
			 SW_EXIT_OK);
	assert_string_equal(path, "/dev/i2c-3");
	assert_int_equal(bus_path(t, "/dev/i2c-7", path, &e), SW_EXIT_OK);
	assert_string_equal(path, "/dev/i2c-7");
	assert_int_equal(bus_path(t, "./i2c-7", path, &e), SW_EXIT_OK);
	assert_string_equal(path, "./i2c-7");

	/* exact names only, and what there is in the message */
	assert_int_equal(bus_path(t, "sentral", path, &e), SW_EXIT_DEVICE);
	assert_string_equal(e.msg,
			    "--i2c 'sentral': no bus of that name; the buses are 0 'sentral-sim', 1 'i2c-0-mux (chan_id 0)', 3 'AUX B/DDI B/PHY B', 10 'sentral-sim-1'");
	assert_string_equal(path, "");
	assert_int_equal(bus_path(t, "i2c-1", path, &e), SW_EXIT_DEVICE);
	assert_int_equal(bus_path(t, "1048576", path, &e), SW_EXIT_USAGE);
	assert_string_equal(e.msg,
			    "--i2c: bus '1048576' is out of range (0 to 1048575)");
	assert_int_equal(bus_path(t, "", path, &e), SW_EXIT_USAGE);

	/* i2cbusses.c's "not unique": say which, and what to do */
	adapter(t, 2, "sentral-sim");
	assert_int_equal(bus_path(t, "sentral-sim", path, &e), SW_EXIT_DEVICE);
	assert_string_equal(e.msg,
			    "--i2c 'sentral-sim': 2 buses have that name (0 'sentral-sim', 2 'sentral-sim'): give the bus number instead");
	assert_string_equal(path, "");
}

static void test_i2c_bus_no_class(void **state)
{
	struct tree *t = *state;
	char path[256];
	struct sw_err e;

	assert_int_equal(bus_path(t, "sentral-sim", path, &e), SW_EXIT_DEVICE);
	assert_non_null(strstr(e.msg, "--i2c 'sentral-sim': no bus of that name: "));
	assert_non_null(strstr(e.msg, "/class: No such file or directory (is the i2c-dev module loaded?)"));
	mkdir_p(t, "class");
	assert_int_equal(bus_path(t, "sentral-sim", path, &e), SW_EXIT_DEVICE);
	assert_non_null(strstr(e.msg, "there is no I2C adapter at all"));
	/* a number or a path does without */
	assert_int_equal(bus_path(t, "2", path, &e), SW_EXIT_OK);
}

/* Many adapters: the list ends in "..." within the message. */
static void test_i2c_bus_long_list(void **state)
{
	struct tree *t = *state;
	char path[256];
	struct sw_err e;
	int i;

	for (i = 0; i < 40; i++)
		adapter(t, i, "Synopsys DesignWare I2C adapter");
	assert_int_equal(bus_path(t, "x", path, &e), SW_EXIT_DEVICE);
	assert_non_null(strstr(e.msg, "the buses are 0 'Synopsys DesignWare I2C adapter', 1 "));
	assert_string_equal(e.msg + strlen(e.msg) - 3, "...");
	assert_int_equal(bus_path(t, "Synopsys DesignWare I2C adapter", path,
				  &e), SW_EXIT_DEVICE);
	assert_non_null(strstr(e.msg, "40 buses have that name (0 'Synopsys"));
}

static int scan_err(struct tree *t, const char *rel, int err,
		    struct sw_err *e)
{
	sw_err_clear(e);
	return sw_iio_scan_err(e, at(t, rel), err);
}

/*
 * Issue 33.3: why libiio could not list the devices. Before, any ENOENT
 * was "/sys/bus/iio/devices is missing", also for a broken link in it.
 */
static void test_iio_scan_err(void **state)
{
	struct tree *t = *state;
	char want[512];
	struct sw_err e;

	assert_int_equal(scan_err(t, "devices", ENOENT, &e), SW_EXIT_DEVICE);
	snprintf(want, sizeof(want),
		 "no IIO devices at all (%s is missing): is the em7180_i2c driver loaded? without a driver use --i2c",
		 at(t, "devices"));
	assert_string_equal(e.msg, want);

	mkdir_p(t, "devices/iio:device0");
	write_file(t, "devices/iio:device0/name", "em7180\n");
	assert_int_equal(symlink("../../gone/iio:device1",
				 at(t, "devices/iio:device1")), 0);
	assert_int_equal(scan_err(t, "devices", ENOENT, &e), SW_EXIT_DEVICE);
	snprintf(want, sizeof(want),
		 "iio:device1: %s is a broken link: the device went away while the tool looked (unbound or unplugged), or sysfs is damaged",
		 at(t, "devices/iio:device1"));
	assert_string_equal(e.msg, want);
	assert_int_equal(unlink(at(t, "devices/iio:device1")), 0);

	/* libiio stats every entry of a device's directory too */
	assert_int_equal(symlink("../../gone/of_node",
				 at(t, "devices/iio:device0/of_node")), 0);
	assert_int_equal(scan_err(t, "devices", ENOENT, &e), SW_EXIT_DEVICE);
	snprintf(want, sizeof(want), "iio:device0: %s is a broken link",
		 at(t, "devices/iio:device0/of_node"));
	assert_string_equal(e.msg, want);
	assert_int_equal(unlink(at(t, "devices/iio:device0/of_node")), 0);

	/* nothing wrong now: it changed under libiio */
	assert_int_equal(scan_err(t, "devices", ENOENT, &e), SW_EXIT_DEVICE);
	snprintf(want, sizeof(want),
		 "cannot list the IIO devices in %s: No such file or directory (they changed while the tool looked: try again)",
		 at(t, "devices"));
	assert_string_equal(e.msg, want);
	assert_int_equal(scan_err(t, "devices", ENOMEM, &e), SW_EXIT_OSERR);
}

/*
 * Permission: as a user that may not read a device's directory (root may
 * read anything, so a child becomes nobody when run by root).
 */
static void test_iio_scan_err_permission(void **state)
{
	struct tree *t = *state;
	char want[2][512], got[512] = "";
	int fds[2], status, i;
	struct sw_err e;
	ssize_t n;
	pid_t pid;

	assert_int_equal(chmod(t->root, 0755), 0);
	mkdir_p(t, "devices/iio:device0");
	mkdir_p(t, "locked");
	assert_int_equal(chmod(at(t, "devices/iio:device0"), 0), 0);
	assert_int_equal(chmod(at(t, "locked"), 0), 0);
	snprintf(want[0], sizeof(want[0]),
		 "iio:device0: cannot list %s: Permission denied",
		 at(t, "devices/iio:device0"));
	snprintf(want[1], sizeof(want[1]),
		 "cannot list the IIO devices: %s: Permission denied",
		 at(t, "locked"));
	for (i = 0; i < 2; i++) {
		assert_int_equal(pipe(fds), 0);
		pid = fork();
		assert_true(pid >= 0);
		if (!pid) {
			close(fds[0]);
			if (geteuid() == 0 &&
			    (setgid(65534) < 0 || setuid(65534) < 0))
				_exit(2);
			scan_err(t, i ? "locked" : "devices", EACCES, &e);
			_exit(write(fds[1], e.msg, strlen(e.msg)) < 0);
		}
		close(fds[1]);
		n = read(fds[0], got, sizeof(got) - 1);
		close(fds[0]);
		assert_int_equal(waitpid(pid, &status, 0), pid);
		assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
		assert_true(n > 0);
		got[n] = '\0';
		assert_string_equal(got, want[i]);
	}
}

int main(void)
{
#define T(f) cmocka_unit_test_setup_teardown(f, setup, teardown)
	const struct CMUnitTest tests[] = {
		T(test_i2c_bus),
		T(test_i2c_bus_no_class),
		T(test_i2c_bus_long_list),
		T(test_iio_scan_err),
		T(test_iio_scan_err_permission),
	};

	return cmocka_run_group_tests_name("sysfs", tests, NULL, NULL);
}
