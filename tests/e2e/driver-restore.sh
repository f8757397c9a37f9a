#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --caldata
#
# The driver's restore at probe (issue 34 item 3), without udev: each
# "boot" is an unbind, a power cycle of the chip (its RAM lost) and a bind.
# No saved calibration: nothing logged, the offsets read from the chip.
# After a save the tool has written em7180/caldata-CLIENT.bin (the saved
# payload behind the chip's identity, 0600 in a 0700 directory), and the next probe
# restores it before the IIO device appears (its add uevent comes after
# the end of the parameter procedure): the level is 4 without motion, the
# chip holds the payload, calibbias reads the file's offsets, and the
# tool's "restore --if-present" finds it restored and writes nothing. A
# file of the wrong size, one with a NaN, a transfer that times out: one
# warning each, probe goes on, and the tool's restore still works (and
# puts the right file back). A file of another RAM version is not used,
# said once, and the tool's restore replaces it with the right one; the
# version-named file of an older driver is left alone by the driver and
# removed by the tool.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
client=$(basename "$(readlink -f "$DEV/..")")
FW=$STATE/firmware

# The kernel log since the last mark
mark() { LOGMARK=$(dmesg | wc -l); }
since() { dmesg | tail -n +$((LOGMARK + 1)); }

# The driver's lines about its file. Debian's kernels have the firmware
# loader itself log each file it did not find, "firmware: failed to load
# NAME (-2)", and 6.1's each one it loaded, "firmware: direct-loading
# firmware NAME", whatever the driver asked (a patch for its installer).
driver_lines() {
	grep caldata | grep -v ': firmware: '
}

# bind_fresh [KNOB=VALUE...]: unbind, power-cycle the chip, set the knobs,
# bind; the kernel log marked before, the iio add uevents recorded, DEV
# set again (not in a subshell: not through ok).
bind_fresh() {
	local kv mon
	echo "$client" >/sys/bus/i2c/drivers/em7180/unbind || return 1
	knob power_cycle 1 || return 1
	wait_for 5 sim_ready || return 1
	for kv in "$@"; do
		knob "${kv%%=*}" "${kv#*=}" || return 1
	done
	mark
	udevadm monitor --kernel --subsystem-match=iio >/tmp/uevents 2>/dev/null &
	mon=$!
	sleep 0.5
	echo "$client" >/sys/bus/i2c/drivers/em7180/bind
	local rc=$?
	sleep 0.2
	kill "$mon"
	wait "$mon" 2>/dev/null
	[ $rc -eq 0 ] && DEV=$(em7180_dir)
}

# The add uevent of the IIO device, CLOCK_MONOTONIC in microseconds
add_uevent_us() {
	awk '/^KERNEL\[/ && $2 == "add" && $3 ~ /\/iio:device[0-9]+$/ {
		gsub(/^KERNEL\[|\]$/, "", $1); split($1, t, ".");
		print t[1] * 1000000 + t[2]; exit }' /tmp/uevents
}

caldata_size() {
	stat -c %s "$CAL"
}

# --- no saved calibration --------------------------------------------------

is "probe found no file and said nothing about it" \
	"$(dmesg | driver_lines | wc -l)" 0
is "not calibrated" "$(cal_level)" 2
is "the accelerometer offsets read from the chip" "$(cat "$DEV/in_accel_x_calibbias")" 0

# --- saved: the driver's file ----------------------------------------------

ok "simulated figure-8 until calibrated" calibrate_by_motion
ok "accel offsets -47 -15 46" sh -c "echo -47 >$DEV/in_accel_x_calibbias &&
	echo -15 >$DEV/in_accel_y_calibbias && echo 46 >$DEV/in_accel_z_calibbias"
ok "save" sentral-warmstart save
# The chip learns its gyro bias (parameters 33-35) again 2 s after a
# power-on, while still: not while this suite compares parameters.
knob gbias_period_ms 3600000
key=$(sentral-warmstart key)
f=$STATE/$key.ws
name=caldata-$client.bin
CAL=$FW/$name
payload=$(file_payload_words "$f")
ok "the tool wrote $name" test -f "$CAL"
is "it holds the saved payload" "$(blob_words <"$CAL")" "$payload"
is "behind the chip's identity" "$(caldata_header <"$CAL")" "$(sim_caldata_header)"
is "mode 0600 in a directory 0700" "$(stat -c %a "$CAL") $(stat -c %a "$FW")" "600 700"
is "the one file there" "$(ls -A "$FW")" "$name"

# --- restored at probe -----------------------------------------------------

bind_fresh
is "unbind, power cycle, bind" $? 0
like "probe restored it, said once" "$(since)" \
	"em7180.* $client: restored calibration from em7180/$name"
is "one line about it" "$(since | driver_lines | wc -l)" 1
is "level 4 (stable) without motion" "$(cal_level)" 4
is "motion never set since" "$(cat "$SIM_DBG/motion")" 0
is "the chip holds the saved payload" "$(sim_ws_params)" "$payload"
is "calibbias reads the file's offsets" \
	"$(cat "$DEV/in_accel_x_calibbias" "$DEV/in_accel_y_calibbias" "$DEV/in_accel_z_calibbias" | tr '\n' ' ')" \
	"-47 -15 46 "
t_add=$(add_uevent_us)
t_end=$(dbg_get state transfer_ended_us)
ok "the device appeared after the restore ended (add $t_add us, restored $t_end us)" \
	test -n "$t_add" -a "$t_add" -ge "$t_end"
knob stats 0
out=$(sentral-warmstart restore --if-present 2>&1)
is "the tool's restore --if-present: exit 0" $? 0
like "it finds the chip restored" "$out" \
	"iio:device[0-9]+: already restored at probe: it holds the calibration of $f"
is "and writes nothing (35 parameters read, none written)" "$(dbg_get stats params_served)" 35

# --- a bad file: warned about, probe goes on, the tool restores ------------

cp "$CAL" /tmp/good.bin
head -c 147 /tmp/good.bin >"$CAL"
bind_fresh
is "bind with a file of 147 bytes" $? 0
like "warned, with the size" "$(since)" \
	"em7180.* $client: em7180/$name: 147 bytes, not 148: calibration not restored"
ok "the device is there" test -n "$DEV"
is "not restored: level 2" "$(cal_level)" 2
out=$(sentral-warmstart restore --if-present 2>&1)
is "the tool's restore: exit 0" $? 0
like "it restored" "$out" "restored iio:device[0-9]+ calibration from $f"
is "level 4" "$(cal_level)" 4
is "and put the right file back" "$(caldata_size) $(blob_words <"$CAL")" "148 $payload"

# A NaN in parameter 10
{ head -c 44 /tmp/good.bin; printf '\000\000\300\177'; tail -c +49 /tmp/good.bin; } >"$CAL"
is "a file of 148 bytes with a NaN" "$(caldata_size)" 148
bind_fresh
is "bind with it" $? 0
like "warned: not a finite float" "$(since)" \
	"em7180.* $client: em7180/$name: a value is not a finite float: calibration not restored"
is "the chip untouched: level 2" "$(cal_level)" 2
ok "not the file's magnetometer coefficients" \
	test "$(words 18 23 "$(sim_ws_params)")" != "$(words 18 23 "$payload")"
ok "the tool's restore works" sentral-warmstart restore --if-present
is "level 4" "$(cal_level)" 4
is "the right file back" "$(blob_words <"$CAL")" "$payload"

# A transfer that is never acknowledged: 1 s, a warning, probe goes on
bind_fresh ack_never=1
is "bind with the chip never acknowledging a parameter" $? 0
like "warned with the error" "$(since)" \
	"em7180.* $client: em7180/$name: calibration not restored: -110"
ok "the device is there" test -n "$DEV"
is "the transfer ended" "$(dbg_get state transfer)" 0
knob ack_never 0
ok "the tool's restore works" sentral-warmstart restore --if-present
is "level 4" "$(cal_level)" 4

# --- another RAM version's file is not used --------------------------------

# The header of RAM 0x0d18; an older driver's file named by the versions
hdr=$(sim_caldata_header)
{ head -c 6 /tmp/good.bin; printf '\x18\x0d'; tail -c +9 /tmp/good.bin; } >"$CAL"
old=caldata-09e6-0d17-$client.bin
cp /tmp/good.bin "$FW/$old"
bind_fresh
is "bind with a file for RAM 0x0d18" $? 0
like "said once, both identities" "$(since | driver_lines)" \
	"em7180.* $client: em7180/$name of 80/02 ROM 09e6 RAM 0d18 v1 refused: chip 80/02 ROM 09e6 RAM [0-9a-f]{4}"
is "one line about it" "$(since | driver_lines | wc -l)" 1
is "not restored: level 2" "$(cal_level)" 2
is "the offsets read from the chip" "$(cat "$DEV/in_accel_x_calibbias")" 0
ok "the tool's restore works" sentral-warmstart restore --if-present
is "level 4" "$(cal_level)" 4
is "the tool wrote this firmware's file, removed the older driver's" "$(ls -A "$FW")" "$name"
is "holding the payload" "$(blob_words <"$CAL")" "$payload"
is "behind this chip's identity" "$(caldata_header <"$CAL")" "$hdr"

done_testing
