#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# A reference host against the simulated EM7180 over i2c-dev, no driver
# bound: tests/refhost/em7180_refhost.py, written from the register
# reference's sequences (one register per SMBus transaction, in the order
# of the hosts that others ran on real boards), not from our driver. Reset
# and status, master-mode setup with the LPF before the rates, events 0x07,
# parameter reads and writes, full-scale parameters 74/75, linear
# acceleration where GT reads it, a barometer event read as the boards'
# examples read it (BaroRate set, TempRate not: Baro, then Temp at 0x2E),
# passthrough on and off; on the USFS board (barometer reported) and on one
# without a barometer. It must see what those hosts see on silicon: every
# data bit in EventStatus after the setup, a unit quaternion, |a| of about
# 1 g with gravity gone from the linear acceleration, a room temperature,
# the written parameters read back. Run under the default knobs and with
# autoinc_stop (no auto-increment across 0x3A->0x3B, 0x63->0x64), which no
# reference host needs; under events_gated it must fail.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/sim/testlib.sh"

PY=/usr/bin/python3
REFHOST=$SENTRAL_ROOT/tests/refhost/em7180_refhost.py

sim_load
is "load the simulator" $? 0
client=/sys/bus/i2c/devices/$SIM_BUS-0028
is "the em7180 client exists" "$(cat $client/name)" em7180
nok "no driver bound to it" test -e $client/driver

# r KEY: a value the reference host printed
r() { awk -v k="$1" '$1 == k { $1 = ""; sub(/^ /, ""); print }' <<<"$out"; }
# within VALUE LOW HIGH (decimal fractions)
within() { awk -v v="$1" -v lo="$2" -v hi="$3" 'BEGIN { exit !(v >= lo && v <= hi) }'; }

refhost_run() {
	local label=$1
	out=$($PY "$REFHOST" "/dev/i2c-$SIM_BUS" 2>/tmp/refhost.err)
	is "$label: the reference host completes" $? 0
	sed 's/^/# /' /tmp/refhost.err
	is "$label: ProductID, RevisionID" "$(r product_id) $(r revision_id)" "0x80 0x02"
	is "$label: ROM, RAM version" "$(r rom_version) $(r ram_version)" "0x09e6 0x0d17"
	is "$label: SentralStatus after the reset: 0x0b (should be 11)" \
		"$(r sentral_status_after_reset)" 0x0b
	is "$label: CPUReset in EventStatus after the reset" \
		"$(r event_status_after_reset)" 0x01
	is "$label: SensorStatus 0 after the setup" "$(r sensor_status)" 0x00
	is "$label: SentralStatus running" "$(r sentral_status_running)" 0x03
	is "$label: actual rates mag 100 Hz, accel and gyro 200 Hz" \
		"$(r actual_rates)" "0x64 0x14 0x14"
	is "$label: full scale read: mag 1000 uT, accel 8 g, gyro 2000 dps" \
		"$(r fs_mag_ut) $(r fs_accel_g) $(r fs_gyro_dps)" "1000 8 2000"
	is "$label: parameter 74 written (accel 16 g) reads back" \
		"$(r fs_read_back)" "$(r fs_written)"
	is "$label: the chip holds it" "$(param_get 74)" "$(r fs_written)"
	is "$label: parameter 52 0.7 written 0.5 reads back" \
		"$(r param52_before) $(r param52_after)" "0.7000 0.5000"
	is "$label: parameter 73 (stillness) written 0" "$(param_get 73)" 0x00000000
	is "$label: FeatureFlags $want_ff" "$(r feature_flags)" "$want_ff"
	is "$label: EventStatus: every sensor's bit ($want_ev) although only 0x07 is enabled" \
		"$(r event_status)" "$want_ev"
	is "$label: no error" "$(r error_register)" 0x00
	ok "$label: quaternion norm $(r quat_norm) within 1e-4 of 1" \
		within "$(r quat_norm)" 0.9999 1.0001
	ok "$label: |a| $(r accel_g) g within 5% of 1 g" \
		within "$(r accel_g)" 0.95 1.05
	ok "$label: linear acceleration $(r lin_accel_lsb) LSB, $(r lin_accel_g) g: gravity removed" \
		within "$(r lin_accel_g)" 0 0.05
	if [ "$want_ff" = 0x05 ]; then
		ok "$label: pressure $(r pressure_mbar) mbar on a barometer event: 1000 within 1" \
			within "$(r pressure_mbar)" 999 1001
		ok "$label: temperature $(r temperature_c) C from 0x2E with no TempRate: the MS5637's 25 C within 0.5" \
			within "$(r temperature_c)" 24.5 25.5
	else
		is "$label: no barometer to read" "$(r temperature_c)" ""
	fi
	is "$label: passthrough on: PassThruStatus 1" "$(r passthru_status_on)" 0x01
	is "$label: algorithm in standby (still)" "$(r algorithm_status_on)" 0x05
	is "$label: no data while in passthrough" "$(r event_status_in_passthrough)" 0x00
	is "$label: passthrough off" "$(r passthru_status_off)" 0x00
	is "$label: algorithm running again (still)" "$(r algorithm_status_off)" 0x04
	is "$label: data again after passthrough" \
		"$(r event_status_after_passthrough)" "$want_ev"
	is "$label: chip left out of transfer mode" "$(dbg_get state transfer)" 0
	echo "# $label: $(r transactions) transactions; quaternion $(r quat_wxyz); accel $(r accel_lsb) LSB"
}

# The USFS board: barometer and temperature in FeatureFlags; the host
# enables the barometer with 0x80 | rate, so its bit (6) joins the
# quaternion, mag, accel and gyro bits.
want_ff=0x05
want_ev=0x7c

# A device turned away from level, so that the quaternion is not the
# identity and gravity is spread over the axes.
ok "orientation w 0.9 x 0.3 y 0.2 z 0.245" knob orientation "900000 300000 200000 245000"
refhost_run "defaults"

ok "autoinc_stop 1" knob autoinc_stop 1
refhost_run "autoinc_stop"
ok "autoinc_stop 0" knob autoinc_stop 0

ok "bus_khz 100" knob bus_khz 100
refhost_run "100 kHz"
ok "bus_khz 0" knob bus_khz 0

# A board without a barometer: the host's BaroRate write has no effect.
ok "feature_flags 0" knob feature_flags 0
want_ff=0x00
want_ev=0x3c
refhost_run "no barometer"
ok "feature_flags 5" knob feature_flags 5

# The old model, EventStatus gated by EnableEvents, is not what the hosts
# on real boards see: with it they lose every sensor but the quaternion.
ok "events_gated 1" knob events_gated 1
out=$($PY "$REFHOST" "/dev/i2c-$SIM_BUS" 2>/dev/null)
is "events_gated: the host sees only the quaternion bit" "$(r event_status)" 0x04
ok "events_gated 0" knob events_gated 0
ok "unload" sim_unload
done_testing
