// SPDX-License-Identifier: GPL-2.0-only
/*
 * Unit tests: composing a chip's key and escaping it as a systemd unit
 * instance name (the sysfs walk itself runs in the end-to-end tests).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <string.h>
#include <cmocka.h>

#include "devkey.h"

static void expect_key(const struct sw_key_parts *p, const char *want)
{
	char key[SW_KEY_MAX];

	assert_true(sw_key_compose(p, key, sizeof(key)));
	assert_string_equal(key, want);
}

static void test_compose(void **state)
{
	struct sw_key_parts p = { .addr = 0x28 };

	(void)state;
	strcpy(p.root, "of/soc/i2c@7e804000");
	expect_key(&p, "of-soc-i2c_7e804000-0x28");
	strcpy(p.root, "acpi-_SB_.PCI0.I2C1");
	expect_key(&p, "acpi-_SB_.PCI0.I2C1-0x28");
	strcpy(p.root, "pci-0000:00:14.0-usb-0:2:1.0");
	p.addr = 0x29;
	expect_key(&p, "pci-0000_00_14.0-usb-0_2_1.0-0x29");
	/* Mux channels, the one nearest the root first. */
	strcpy(p.root, "platform-sentral-sim-mux");
	p.nhops = 2;
	strcpy(p.hop[0].mux, "0x70");
	p.hop[0].chan = 1;
	strcpy(p.hop[1].mux, "i2c-mux-gpio.0");
	p.hop[1].chan = 3;
	p.addr = 0x28;
	expect_key(&p, "platform-sentral-sim-mux-mux0x70-ch1-muxi2c-mux-gpio.0-ch3-0x28");
	/* An adapter without a parent: its name, never its number. */
	p.nhops = 0;
	strcpy(p.root, "adapter-SMBus I801 adapter at efa0");
	expect_key(&p, "adapter-SMBus_I801_adapter_at_efa0-0x28");
}

static void test_compose_too_long(void **state)
{
	struct sw_key_parts p = { .addr = 0x28 };
	char key[SW_KEY_MAX];
	int i;

	(void)state;

	memset(p.root, 'a', sizeof(p.root) - 1);
	p.nhops = SW_KEY_MAX_HOPS;
	for (i = 0; i < p.nhops; i++)
		strcpy(p.hop[i].mux, "0x70");
	assert_false(sw_key_compose(&p, key, sizeof(key)));
	assert_false(sw_key_compose(&p, key, 20));
}

static void test_sanitize(void **state)
{
	char out[16];

	(void)state;
	sw_sanitize_key("a/b:c@d", out, sizeof(out));
	assert_string_equal(out, "a_b_c_d");
	sw_sanitize_key("..", out, sizeof(out));
	assert_string_equal(out, "_.");
	sw_sanitize_key("", out, sizeof(out));
	assert_string_equal(out, "unknown");
}

/* systemd-escape: only "-" needs escaping in a key. */
static void test_unit_escape(void **state)
{
	char out[64];

	(void)state;
	assert_true(sw_key_unit_escape("platform-sentral-sim-0x28", out,
				       sizeof(out)));
	assert_string_equal(out, "platform\\x2dsentral\\x2dsim\\x2d0x28");
	assert_true(sw_key_unit_escape("of_soc.x", out, sizeof(out)));
	assert_string_equal(out, "of_soc.x");
	assert_false(sw_key_unit_escape("a-b", out, 5));
	assert_true(sw_key_unit_escape("a-b", out, 7));
}

int main(void)
{
	const struct CMUnitTest tests[] = {
		cmocka_unit_test(test_compose),
		cmocka_unit_test(test_compose_too_long),
		cmocka_unit_test(test_sanitize),
		cmocka_unit_test(test_unit_escape),
	};

	return cmocka_run_group_tests_name("devkey", tests, NULL, NULL);
}
