#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --udev
#
# The udev rule (no systemd: RUN+= path) in one boot: nothing to restore at
# the first probe; after calibrate + save, a re-probe of a power-cycled chip
# restores it (status 3 without motion, parameters equal to the file); a
# corrupted file is refused at probe with the message in the kernel log and
# the chip left alone.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
client=$(basename "$(dirname "$(readlink -f "$DEV")")")
ok "the rule is installed" test -f /etc/udev/rules.d/60-sentral-warmstart.rules
like "the rule ran at probe: nothing to restore yet" "$(dmesg)" \
	"sentral-warmstart\[[0-9]+\]: no saved calibration for iio:device"

idpath=$(udevadm info -q property -p "$(readlink -f "$DEV")" | sed -n 's/^ID_PATH=//p')
key=$(sentral-warmstart status --json | json_field key)
if [ -n "$idpath" ]; then
	is "the key is udev's ID_PATH" "$key" "$(echo "$idpath" | tr -c 'A-Za-z0-9._\n-' _)"
else
	is "no ID_PATH: the key is the client name" "$key" "$client"
fi
f=$STATE/$key.ws

knob gbias_period_ms 600000
ok "simulated figure-8 until calibrated" calibrate_by_motion
ok "save" sentral-warmstart save
ok "saved as $f" test -f "$f"
payload=$(file_payload_words "$f")

ok "replug (power cycle + bind): udev restores at probe" replug "$client"
udevadm settle --timeout=10
is "in_magn_calibration_auto_status 3 without motion" "$(cal_status)" 3
is "chip parameters 1..35 equal the saved payload" "$(sim_ws_params)" "$payload"
like "the kernel log tells it" "$(dmesg)" \
	"sentral-warmstart\[[0-9]+\]: restored iio:device[0-9]+ calibration from $f"

flip_byte "$f" 100
ok "replug with a corrupted file" replug "$client"
udevadm settle --timeout=10
like "refused at probe, the check named in the kernel log" "$(dmesg)" \
	"sentral-warmstart\[[0-9]+\]: error: $f: refused: bad CRC"
is "chip untouched: not calibrated" "$(cal_status)" 0
isnt_payload=$(words 18 23 "$(sim_ws_params)")
ok "chip untouched: magnetic coefficients are not the file's" \
	test "$isnt_payload" != "$(words 18 23 "$payload")"

# With systemd running, the rule hands over to the template unit instead.
mkdir -p /run/systemd/system
before=$(dmesg | grep -c 'sentral-warmstart\[')
ok "replug as if systemd were running" replug "$client"
udevadm settle --timeout=10
props=$(udevadm info -q property -p "$(readlink -f "$(em7180_dir)")")
like "SYSTEMD_WANTS names the unit after the key" "$props" \
	"SYSTEMD_WANTS=sentral-warmstart@${idpath:-$key}\.service"
like "tagged for systemd" "$props" "TAGS=.*:systemd:"
is "the tool was not run directly" "$(dmesg | grep -c 'sentral-warmstart\[')" "$before"
rmdir /run/systemd/system

done_testing
