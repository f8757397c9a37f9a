#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# The calibration update counters and the change reports of the em7180
# driver on the simulated chip: two programs reading the counters at once
# both see every update (register 0x44 clears when read, so the counters
# are the driver's, not a reader's); a reader asleep in poll() is woken
# when the status, score or counters change; the magnetometer change event;
# no bus transaction while nobody asks, and the checks' back-off while the
# event is enabled and nothing changes.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"

WAIT=$SENTRAL_ROOT/tests/lib/iio_wait.py
DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
G=$DEV/in_anglvel_calibration_update_count
M=$DEV/in_magn_calibration_update_count
EN=$DEV/events/in_magn_change_en

# reader FILE OUT SECONDS: read FILE as fast as a shell can for SECONDS,
# one value a line into OUT.
reader() {
	local end=$(($(date +%s) + $3))
	while [ "$(date +%s)" -lt "$end" ]; do
		cat "$1"
	done >"$2"
}

# first, last and whether the lines only grow: "FIRST LAST ok|bad"
seen() {
	awk 'NR == 1 { first = $1 } $1 < prev { bad = 1 } { prev = $1 }
	     END { printf "%s %s %s", first, prev, bad ? "bad" : "ok" }' "$1"
}

# Two readers of FILE for the whole of a run of updates: both read before
# the first update and after the last, so each must have seen all of them.
# check_readers DESC FILE C0 C1
check_readers() {
	local r
	for r in a b; do
		is "reader $r saw every $1 ($3 before, $4 after)" \
			"$(seen /tmp/$r)" "$3 $4 ok"
	done
}

# --- Two readers of the gyro bias counter, device still ----------------
knob motion 0
knob gbias_period_ms 600000
cat "$G" >/dev/null
c0=$(cat "$G")
r0=$(dbg_get cal_updates gbias_read)
reader "$G" /tmp/a 6 &
reader "$G" /tmp/b 6 &
sleep 1
knob gbias_period_ms 50
sleep 3
knob gbias_period_ms 600000
wait
c1=$(cat "$G")
r1=$(dbg_get cal_updates gbias_read)
echo "# reads: $(wc -l </tmp/a) and $(wc -l </tmp/b)"
ok "gyro bias updates happened while the readers ran ($((c1 - c0)))" \
	test $((c1 - c0)) -ge 10
is "every gBiasUpdate flag the driver read is counted once" \
	$((c1 - c0)) $((r1 - r0))
check_readers "gyro bias update" "$G" "$c0" "$c1"

# --- The magnetic calibration counter, device turning -----------------
knob cal_duration_ms 2000
c0=$(cat "$M")
r0=$(dbg_get cal_updates mag_read)
reader "$M" /tmp/a 7 &
reader "$M" /tmp/b 7 &
sleep 1
knob pattern sphere
sleep 5
knob motion 0
wait
c1=$(cat "$M")
r1=$(dbg_get cal_updates mag_read)
# The chip's 10 calibration steps each latch magCalUpdate; two steps
# between two reads of 0x44 are one flag read (a loaded machine reads less
# often), so the count is of the flags the driver read.
ok "magnetic calibration updates happened while the readers ran ($((c1 - c0)))" \
	test $((c1 - c0)) -ge 5
is "every magCalUpdate flag read is counted once" $((c1 - c0)) $((r1 - r0))
check_readers "magnetic calibration update" "$M" "$c0" "$c1"
is "calibration complete" "$(cat "$DEV/in_magn_calibration_auto_status")" 3

# --- Nobody asks: no bus transaction ----------------------------------
knob gbias_period_ms 100
is "the change event is off by default" "$(cat "$EN")" 0
knob stats 0
sleep 3
is "3 s with nobody reading: no bus transaction" "$(dbg_get stats transactions)" 0
knob stats 0
cat "$G" >/dev/null
is "one read of a counter is one bus transaction" "$(dbg_get stats transactions)" 1

# --- Woken in poll() ----------------------------------------------------
# A reader of the attribute wakes a sleeper on the counter it moved.
( sleep 1; cat "$DEV/in_magn_calibration_score" >/dev/null ) &
out=$("$WAIT" sysfs 5 "$G" "$M")
is "a sleeper on the gyro counter is woken by another's read" "$out" "$G"
wait
knob gbias_period_ms 600000
cat "$G" >/dev/null
# With the event enabled the driver looks by itself, with no reader at all:
# the magnetic surroundings drift while the device turns.
echo 1 >"$EN"
is "the change event enabled" "$(cat "$EN")" 1
knob drift_ms 300
knob pattern sphere
out=$(timeout 10 "$WAIT" sysfs 5 "$DEV/in_magn_calibration_score")
is "a drifting calibration wakes the score sleeper" "$out" \
	"$DEV/in_magn_calibration_score"
node=/dev/$(basename "$DEV")
out=$(timeout 10 "$WAIT" event 5 "$node")
like "and pushes the magnetometer change event (magn, change, none)" "$out" \
	'^0x0503000500000000 [0-9]+$'
knob motion 0
knob drift_ms 0

# --- Enabled, nothing changing: the checks back off ---------------------
knob gbias_period_ms 600000
sleep 2
knob stats 0
sleep 20
t=$(dbg_get stats transactions)
# 1, 2, 4, 8, 16 s apart after the last change: at most 4 in 20 s
ok "20 s without a change cost $t bus transactions (1, 2, 4, 8, 16 s apart)" \
	test "$t" -le 4
echo 0 >"$EN"
knob stats 0
sleep 3
is "disabled again: no bus transaction" "$(dbg_get stats transactions)" 0

done_testing
