#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# The calibration state on every firmware, with nothing configured: the
# simulator's default is a USFS board whose firmware keeps linear
# acceleration in 0x3F-0x44 (tests/sim/README.md), where the driver reports
# in_magn_calibration_auto_status from AlgorithmStatus alone and never the
# application note's score and flags. With the note's layout
# (appnote_layout=1) it finds them at probe by itself; firmware that stops
# holding them (another image after a reset, or other data after all) makes
# them read ENODATA, said once. No devicetree property, no module parameter.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"

TMP=$(mktemp -d)
NOTE="in_magn_calibration_score in_anglvel_calibration_update in_magn_calibration_update"

DEV=$(em7180_dir)
ok "em7180 present" test -n "$DEV"
CLIENT=$(basename "$(readlink -f "$DEV/..")")
DRV=/sys/bus/i2c/drivers/em7180

# note_attrs: how many of the application note's attributes $DEV has
note_attrs() {
	local a n=0
	for a in $NOTE; do
		[ -e "$DEV/$a" ] && n=$((n + 1))
	done
	echo $n
}

rebind() {
	echo "$CLIENT" >"$DRV/unbind" && echo "$CLIENT" >"$DRV/bind" &&
		DEV=$(em7180_dir)
}

level() {
	cat "$DEV/in_magn_calibration_auto_status"
}

# level_is N: the level reads N (past the driver's 0.5 s cache)
level_is() {
	[ "$(level)" = "$1" ]
}

# --- A USFS board as it comes: the level, nothing else ------------------
# The knob matrix's appnote_layout=1 booted the note's layout: this suite
# plays both layouts itself, from a USFS board's
if [ "$(cat "$SIM_DBG/appnote_layout")" != 0 ]; then
	knob appnote_layout 0
	rebind
fi
is "the simulator plays a USFS board" "$(cat "$SIM_DBG/appnote_layout")" 0
ok "in_magn_calibration_auto_status exists" test -e "$DEV/in_magn_calibration_auto_status"
is "none of the application note's attributes" "$(note_attrs)" 0
nok "no in_magn_transient" test -e "$DEV/in_magn_transient"
nok "no module parameter for it" test -e /sys/module/em7180_core/parameters/calibration_firmware
like "the probe line names the firmware" \
	"$(dmesg | grep "$CLIENT")" \
	'firmware ProductID 0x80 RevisionID 0x02 ROM 0x09e6 RAM 0x[0-9a-f]{4} eeprom'

knob motion 0
knob stats 0
is "level 2 at power-on: calibrating" "$(level)" 2
is "one bus transaction: SentralStatus and AlgorithmStatus" \
	"$(dbg_get stats transactions)" 1
is "of 2 bytes" "$(dbg_get stats bytes)" 3
knob cal_duration_ms 2000
knob pattern sphere
ok "motion: level 4, stable" wait_for 10 level_is 4
knob motion 0
knob mag_transient 1
ok "a magnetic transient: level 3" wait_for 2 level_is 3
knob mag_transient 0
knob algo_status_or 0x20
ok "unreliable sensor data: level 1" wait_for 2 level_is 1
knob algo_status_or 0xc0
sleep 0.6
nok "an AlgorithmStatus with undefined bits (a glitch) fails the read" level
like "with EIO" "$(cat "$DEV/in_magn_calibration_auto_status" 2>&1)" \
	'Input/output error'
knob algo_status_or 0
ok "and the next read is a state again" wait_for 2 level_is 4

# Streaming, transfers and calibbias work as before
ok "buffered capture: iio_readdev -b 16 -s 50" \
	sh -c "iio_readdev -b 16 -s 50 em7180 >$TMP/cap.bin"
ok "it captured" test -s "$TMP/cap.bin"
knob gbias_period_ms 50
sleep 0.2
ok "calibration_data read" dd if="$DEV/calibration_data" of="$TMP/a.bin" \
	bs=148 count=1 status=none
ok "calibration_data write" dd if="$TMP/a.bin" of="$DEV/calibration_data" \
	bs=148 status=none
is "the chip holds them" "$(sim_ws_params)" "$(blob_words <"$TMP/a.bin")"
knob gbias_period_ms 2000
ok "level 4 after the restore" wait_for 2 level_is 4

# --- The application note's layout: found at probe ----------------------
knob appnote_layout 1
ok "bind again" rebind
is "all three of the note's attributes" "$(note_attrs)" 3
like "in_magn_calibration_score reads a percentage" \
	"$(cat "$DEV/in_magn_calibration_score")" '^[0-9]+\.[0-9]{3}$'
is "the level from AlgorithmStatus as before" "$(level)" 4
knob stats 0
sleep 0.6
cat "$DEV"/in_magn_calibration_auto_status "$DEV/in_magn_calibration_score" \
	"$DEV/in_magn_calibration_update" >/dev/null
reads=$((1 + $(cat "$SIM_DBG/autoinc_stop")))
is "all of them in $reads bus transaction(s)" "$(dbg_get stats transactions)" "$reads"

# Other data after all: the layout breaks, the note's attributes go ENODATA
knob appnote_layout 0
sleep 0.6
nok "in_magn_calibration_score: no data once 0x43-0x4E hold other data" \
	cat "$DEV/in_magn_calibration_score"
like "ENODATA" "$(cat "$DEV/in_magn_calibration_score" 2>&1)" 'No data available'
is "said once" "$(dmesg | grep -c "$CLIENT.*not the calibration score")" 1
ok "the level still reads" level
knob appnote_layout 1
sleep 0.6
nok "for good, while that firmware runs" cat "$DEV/in_magn_calibration_score"

# Another firmware after a reset: looked at again
ok "bind again" rebind
is "the note's attributes again" "$(note_attrs)" 3
knob appnote_layout 0
knob ram_version 0x0f02
knob chip_reset 1
ok "recovered with RAM 0x0f02" wait_for 5 ram_is 0x0f02
nok "its score: no data" cat "$DEV/in_magn_calibration_score"
is "the change is logged once" \
	"$(dmesg | grep -c 'firmware RAM 0x0f02: calibration score not reported')" 1
knob appnote_layout 1
knob ram_version 0x0e01
knob chip_reset 1
ok "recovered with RAM 0x0e01, which has them" wait_for 5 ram_is 0x0e01
ok "the score reads again" wait_for 2 cat "$DEV/in_magn_calibration_score"
like "logged" "$(dmesg | grep 'firmware RAM 0x0e01')" 'score reported again'

# Back as tests/uml/run left it
knob appnote_layout 0
knob ram_version "$(printf '0x%04x' "$((0x0d17))")"
ok "bind again" rebind
is "the USFS board: none of the note's attributes" "$(note_attrs)" 0
rm -rf "$TMP"
done_testing
