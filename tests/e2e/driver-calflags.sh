#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --sim-knobs appnote_layout=1
#
# The calibration update flags of the em7180 driver on the simulated chip
# with the application note's layout (the driver finds it at probe):
# set when the chip reported an update since the warm start was last read
# or written, whoever read the registers and how often; an update the chip
# latched before a save does not show after it; one bus transaction serves
# every calibration attribute read together; nothing reads the chip while
# nobody asks, and no change event or kernel polling is left.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
G=$DEV/in_anglvel_calibration_update
M=$DEV/in_magn_calibration_update
CAL="$DEV/in_magn_calibration_auto_status $DEV/in_magn_calibration_score $G $M"

save() {
	dd if="$DEV/calibration_data" of=/dev/null bs=148 count=1 status=none
}

# The simulated chip updated its gyro bias more than N times.
gbias_above() {
	[ "$(dbg_get cal_updates gbias)" -gt "$1" ]
}

# The calibration is stable.
complete() {
	[ "$(cat "$DEV/in_magn_calibration_auto_status")" = 4 ]
}

# reader FILE OUT SECONDS: read FILE as fast as a shell can for SECONDS.
reader() {
	local end=$(($(date +%s) + $3))
	while [ "$(date +%s)" -lt "$end" ]; do
		cat "$1"
	done >"$2"
}

# --- The flags stay set until the warm start is read ---------------------
knob motion 0
knob gbias_period_ms 600000
ok "calibration_data read" save
is "no gyro bias update since the read" "$(cat "$G")" 0
is "no magnetic calibration update since the read" "$(cat "$M")" 0
g0=$(dbg_get cal_updates gbias)
reader "$G" /tmp/a 5 &
reader "$G" /tmp/b 5 &
sleep 1
knob gbias_period_ms 50
wait_for 3 gbias_above "$g0"
knob gbias_period_ms 600000
wait
ok "the chip updated its gyro bias while two programs read the flag" \
	test "$(dbg_get cal_updates gbias)" -gt "$g0"
for r in a b; do
	# 0 until the first update, then 1 for good: both saw it, and their
	# reads of the clear-on-read register took it from neither
	is "reader $r saw 0 then 1, never 0 again" \
		"$(uniq /tmp/$r | tr '\n' ' ')" "0 1 "
done
is "still 1 after the readers" "$(cat "$G")" 1
ok "calibration_data read again" save
is "the read cleared it" "$(cat "$G")" 0

# --- An update latched on the chip before a save is not one since -------
# Nobody reads the flags while the chip latches an update, then the
# warm start is read: the save holds that update, so the flag stays 0.
knob stats 0
g0=$(dbg_get cal_updates gbias)
knob gbias_period_ms 50
wait_for 3 gbias_above "$g0"
knob gbias_period_ms 600000
ok "an update came while nobody read the flags" \
	test "$(dbg_get cal_updates gbias)" -gt "$g0"
ok "calibration_data read" save
is "the update the save took in does not show after it" "$(cat "$G")" 0

# --- The magnetic calibration flag --------------------------------------
knob cal_duration_ms 2000
knob pattern sphere
wait_for 10 complete
knob motion 0
is "calibration stable" "$(cat "$DEV/in_magn_calibration_auto_status")" 4
is "the magnetic calibration flag is set" "$(cat "$M")" 1
ok "calibration_data read" save
is "and cleared by the save" "$(cat "$M")" 0

# --- Bus cost -----------------------------------------------------------
knob gbias_period_ms 100
knob stats 0
sleep 3
is "3 s with nobody reading: no bus transaction" \
	"$(dbg_get stats transactions)" 0
# One read from SentralStatus through the score; two where the register
# pointer stops at 0x3A (knob autoinc_stop, as check-long runs this suite).
reads=$((1 + $(cat "$SIM_DBG/autoinc_stop")))
knob stats 0
# shellcheck disable=SC2086
cat $CAL >/dev/null
is "status, score and both flags read together: $reads bus transaction(s)" \
	"$(dbg_get stats transactions)" "$reads"
sleep 1
knob stats 0
cat "$G" >/dev/null
is "a read after the shared one aged: as many again" "$(dbg_get stats transactions)" "$reads"
nok "no calibration change event left" test -e "$DEV/events/in_magn_change_en"
nok "no update counter left" test -e "$DEV/in_magn_calibration_update_count"

done_testing
