#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# The em7180 driver's interrupt on the simulated chip, as the reference
# hosts see EventStatus on silicon (every event latched, INT for the
# enabled ones): an interrupt with no enabled event pending is not the
# driver's (IRQ_NONE, so that the kernel can tell a line that fires for
# nobody); an Error event is reported once per ErrorRegister and
# SensorStatus pair, decoded; resets of the chip's own are recovered out of
# the interrupt thread, a burst of them once, and at most once a second;
# one that raised no INT is found by the next calibration read or, while a
# buffer runs, within a second, or by a raw read; debugfs shows the
# recoveries.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
VIRQ=$(dbg_get state virq)
SPURIOUS=/proc/irq/$VIRQ/spurious
ok "the interrupt's spurious counters are readable" test -r "$SPURIOUS"
unhandled() {
	awk '$1 == "unhandled" { print $2 }' "$SPURIOUS"
}
errors() {
	dmesg | grep -c "em7180.*chip error"
}

# --- Not ours --------------------------------------------------------------
u0=$(unhandled)
i0=$(dbg_get state irqs)
for _ in 1 2 3 4 5; do
	knob int_spurious 1
done
is "five rising edges with nothing pending" "$(($(dbg_get state irqs) - i0))" 5
# The kernel accounts a threaded handler's answer at the next interrupt of
# the line: the first four of the five so far.
is "each one unhandled for the kernel (IRQ_NONE)" "$(($(unhandled) - u0))" 4
is "INT low again" "$(dbg_get state int)" 0

# --- Errors ------------------------------------------------------------------
e0=$(errors)
knob sensor_status 0x01
knob error 0x21
ok "the Error event read" wait_for 2 sh -c "[ \$(dmesg | grep -c 'em7180.*chip error') -gt $e0 ]"
like "decoded, with SensorStatus" "$(dmesg | grep 'em7180.*chip error' | tail -n 1)" \
	"chip error 0x21 \\(magnetometer initialization failed\\), sensor status 0x01"
knob error 0x21
sleep 0.2
is "the same error again: not said again" "$(($(errors) - e0))" 1
knob sensor_status 0x00
knob error 0x30
ok "another error is said" wait_for 2 sh -c "[ \$(dmesg | grep -c 'em7180.*chip error') -gt $((e0 + 1)) ]"
like "decoded" "$(dmesg | grep 'em7180.*chip error' | tail -n 1)" \
	"chip error 0x30 \\(math error\\), sensor status 0x00"
knob error 0

# --- No scan for an error-only interrupt ----------------------------------
# The magnetometer alone is captured at 1 Hz and paces the scans; the
# accelerometer runs at 1000 Hz, so its EventStatus bit is set whenever
# the chip is read. An Error raised just after a magnetometer sample is
# answered with three one-byte reads (EventStatus, ErrorRegister,
# SensorStatus) and no read of the data registers. The counters are taken
# in one read, and a window in which a magnetometer sample came (a loaded
# host stretches it towards the next one) is measured again, 5 times at
# most (three UML boots on two cores missed 3 in a row).
mag_made() {
	dbg_get samples mag
}
echo 1000 >"$DEV/in_accel_sampling_frequency"
echo 1 >"$DEV/in_magn_sampling_frequency"
iio_readdev -T 20000 -b 1 -s 0 em7180 magn_x magn_y magn_z >/dev/null &
reader=$!
clean=0
for try in 1 2 3 4 5; do
	m0=$(mag_made)
	wait_for 3 sh -c "[ \$(awk '\$1 == \"mag\" { print \$2 }' $SIM_DBG/samples) -gt $m0 ]" || break
	m1=$(mag_made)
	knob stats 0
	knob error 0x14
	sleep 0.3
	counters=$(cat "$SIM_DBG/stats")
	m2=$(mag_made)
	knob error 0
	if [ "$m2" = "$m1" ]; then
		clean=1
		break
	fi
done
ok "a window between two magnetometer samples (try $try)" [ "$clean" = 1 ]
is "an Error between two samples: three reads" \
	"$(awk '$1 == "transactions" { print $2 }' <<<"$counters")" 3
is "of one register each (1 address byte, 1 data byte)" \
	"$(awk '$1 == "bytes" { print $2 }' <<<"$counters")" 6
ok "the capture still runs" kill "$reader"
wait "$reader" 2>/dev/null

# --- Resets of the chip's own ---------------------------------------------
resets() {
	dmesg | grep -c "em7180.*reset itself"
}
r0=$(resets)
knob chip_reset 1
knob chip_reset 1
knob chip_reset 1
ok "three resets in a row are recovered" wait_for 5 sh -c "[ \$(dmesg | grep -c 'em7180.*reset itself') -gt $r0 ]"
sleep 0.5
is "once" "$(($(resets) - r0))" 1
ok "the algorithm runs" chip_idle
knob chip_reset 1
ok "another reset soon after is recovered" wait_for 5 sh -c "[ \$(dmesg | grep -c 'em7180.*reset itself') -gt $((r0 + 1)) ]"
gap=$(dmesg | grep "em7180.*reset itself" | tail -n 2 |
	sed 's/^\[ *\([0-9.]*\)\].*/\1/' | awk 'NR == 1 { a = $1 } NR == 2 { printf "%d", ($1 - a) * 1000 }')
ok "a second after the one before at the earliest (${gap} ms)" [ "$gap" -ge 990 ]
like "the log counts them" "$(dmesg | grep 'em7180.*reset itself' | tail -n 1)" "\\(2 since probe\\)"
ok "the algorithm runs" chip_idle

# A reset that raises no INT (no line wired, or firmware that does not
# raise it with EnableEvents cleared): the next calibration read, as the
# watcher makes every 30 s, finds the chip waiting in standby.
knob reset_int 0
r1=$(resets)
knob chip_reset 1
sleep 0.6
cat "$DEV/in_magn_calibration_auto_status" >/dev/null
ok "a reset without INT is recovered after a calibration read" \
	wait_for 5 sh -c "[ \$(dmesg | grep -c 'em7180.*reset itself') -gt $r1 ]"
ok "the algorithm runs" wait_for 5 chip_idle
is "HostControl run" "$(dbg_get state host_run)" 1

# The same reset while a capture runs: no INT comes any more, and no user
# reads the calibration. With the chip's own trigger the driver finds no
# scan for a second; with another (an hrtimer's) the data registers only
# stop changing, and the driver checks SentralStatus every second. Either
# way it finds the chip waiting in standby and recovers it.
above() {
	[ "$(dbg_get samples "$1")" -gt "$2" ]
}
resets_above() {
	[ "$(resets)" -gt "$1" ]
}
# reset_while_streaming LABEL [IIO_READDEV_OPTION...]
reset_while_streaming() {
	local label=$1 reader a r
	shift
	iio_readdev "$@" -T 20000 -b 1 -s 0 em7180 accel_x >/dev/null &
	reader=$!
	a=$(dbg_get samples accel_read)
	ok "$label: the accelerometer is captured" wait_for 3 above accel_read "$a"
	r=$(resets)
	knob chip_reset 1
	ok "$label: a reset without INT is recovered" wait_for 5 resets_above "$r"
	a=$(dbg_get samples accel_read)
	ok "$label: the capture goes on" wait_for 3 above accel_read "$a"
	ok "$label: the capture still runs" kill "$reader"
	wait "$reader" 2>/dev/null
}
reset_while_streaming "own trigger"
if mkdir /sys/kernel/config/iio/triggers/hrtimer/watch 2>/dev/null; then
	reset_while_streaming "hrtimer trigger" -t watch
	# The trigger stays: removing a software trigger is a use-after-free
	# in Linux 6.12 itself (see driver-buffer).
else
	ok "hrtimer trigger available" false
fi

# No capture and no calibration read: a raw read a second or more after the
# driver last looked at SentralStatus looks first.
r4=$(resets)
knob chip_reset 1
sleep 1.1
cat "$DEV/in_accel_x_raw" >/dev/null
ok "a reset without INT is recovered after a raw read" wait_for 3 resets_above "$r4"
knob reset_int 1
cat "$DEV/in_accel_x_raw" >/dev/null
knob stats 0
cat "$DEV/in_accel_x_raw" "$DEV/in_accel_y_raw" >/dev/null
is "two raw reads within a second: one transaction each" "$(dbg_get stats transactions)" 2
sleep 1.1
knob stats 0
cat "$DEV/in_accel_x_raw" >/dev/null
is "a raw read a second later: SentralStatus first" "$(dbg_get stats transactions)" 2

# What recovery did, readable in debugfs
REC=/sys/kernel/debug/iio/${DEV##*/}/recovery
ok "debugfs has the recovery state" test -r "$REC"
is "the resets counted" "$(awk '$1 == "resets" { print $2 }' "$REC")" "$(resets)"
is "none pending" "$(awk '$1 == "pending" { print $2 }' "$REC")" 0
like "the last one succeeded" "$(grep '^last' "$REC")" "^last [0-9]+ ms ago, result 0\$"
done_testing
