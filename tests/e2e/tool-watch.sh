#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# sentral-warmstart watch against the em7180 driver on the simulated chip:
# it polls (one bus transaction a poll, nothing else), saves a newly
# complete calibration within a poll, only for a real improvement and at
# most once per --interval while the calibration keeps drifting, also while
# a buffer streams; it saves accel offsets written through calibbias; a
# manual watcher next to it changes nothing for it; SIGTERM ends it (it
# dies of the signal); and it exits 69 within a poll of the driver's
# unbind.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
client=$(basename "$(dirname "$(readlink -f "$DEV")")")
key=$(sentral-warmstart key)
f=$STATE/$key.ws
log=/tmp/watch.log

saves() {
	grep -c "saved iio:device[0-9]* calibration" "$log"
}

saves_at_least() {
	[ "$(saves)" -ge "$1" ]
}

now_ms() {
	echo $(($(date +%s%N) / 1000000))
}

# The simulated chip's status is 3 (debugfs: no bus transaction).
sim_complete() {
	[ "$(dbg_get state cal_status)" = 3 ]
}

knob gbias_period_ms 600000
sentral-warmstart watch --poll 2 --interval 6 --margin 0.2 >"$log" 2>&1 &
pid=$!
wait_for 5 grep -q "^watching" "$log"
like "it says what it does" "$(head -n1 "$log")" \
	"^watching iio:device[0-9]+: looking every 2 s; saving to $f when the calibration is complete with a score of at most 5.000%, and better than a good saved one by 0.200 points, or the accel offsets change; at most one write every 6 s$"
nok "the driver has no change event any more" test -e "$DEV/events/in_magn_change_en"
sleep 3
nok "nothing saved while uncalibrated" test -e "$f"

# Calibrate: the watcher saves by itself, within a poll of status 3.
knob cal_duration_ms 1000
knob pattern sphere
ok "the chip calibrates" wait_for 20 sim_complete
t3=$(now_ms)
ok "saved by itself once calibrated" wait_for 10 test -e "$f"
dt=$(($(now_ms) - t3))
ok "within a poll of status 3 (${dt} ms; poll 2 s, 1 s of slack)" test "$dt" -le 3000
knob motion 0
ok "a valid file" sentral-warmstart show "$f"
like "with a message for the journal" "$(cat "$log")" \
	"saved iio:device[0-9]+ calibration to $f: score 2.70[0-9]% is within the limit"
wait_for 3 saves_at_least 1

# Nothing better: no second write, and one bus transaction a poll.
sleep 5
is "the same calibration is not written again" "$(saves)" 1
knob stats 0
sleep 10
t=$(dbg_get stats transactions)
ok "a transaction a poll: $t in 10 s at --poll 2 (5, one more at the edges)" \
	test "$t" -ge 4 -a "$t" -le 6

# The surroundings keep changing every 2 s of turning (each time the best
# score reachable is another), with a buffer streaming: better calibrations
# come, at most one write per 6 s, and only 0.2 points better than the
# saved one.
echo 1 >"$DEV/buffer0/in_accel_x_en"
ok "a buffer streams" sh -c "echo 1 >'$DEV/buffer0/enable'"
knob drift_ms 2000
knob pattern sphere
sleep 30
knob motion 0
knob drift_ms 0
n=$(saves)
echo "# $n saves in 30 s of drift:"
grep -E "saved|not saving|waits|to save|error" "$log" | sed 's/^/#   /'
ok "some drifted calibrations saved while streaming" test "$n" -ge 2
ok "at most one write per 6 s (plus the first)" test "$n" -le 6
ok "every save better than the one before by the margin" awk '
	/saved iio.*calibration/ && match($0, /score [0-9.]+%/) {
		s = substr($0, RSTART + 6, RLENGTH - 7) + 0
		if (n++ && s > prev - 0.2) exit 1
		prev = s
	}' "$log"
nok "no error" grep -q "error" "$log"
echo 0 >"$DEV/buffer0/enable"
echo 0 >"$DEV/buffer0/in_accel_x_en"
ok "the file is valid after it all" sentral-warmstart show "$f"

# A manual watcher next to the unit's: it ends, and the first goes on.
sentral-warmstart watch --poll 1 >/tmp/manual.log 2>&1 &
manual=$!
sleep 3
kill -TERM "$manual"
wait "$manual"
is "the manual watcher dies of SIGTERM (143 in a shell)" $? 143
like "saying so" "$(tail -n1 /tmp/manual.log)" "^stopped watching iio:device[0-9]+$"
ok "the first one still runs" kill -0 "$pid"
# Accel offsets written through calibbias: saved into the file, with its
# calibration and score unchanged.
score=$(od -An -tu2 -j18 -N2 "$f" | tr -d ' ')
sleep 6
echo -47 >"$DEV/in_accel_x_calibbias"
ok "the first watcher saves the new offsets within a poll or two" \
	wait_for 10 grep -q "saved iio:device[0-9]* accel offsets -47 0 0 LSB to $f" "$log"
is "into the file" "$(words 27 27 "$(file_payload_words "$f")")" "0xbcbbe447 "
is "its calibration's score unchanged" "$(od -An -tu2 -j18 -N2 "$f" | tr -d ' ')" "$score"

kill -TERM "$pid"
wait "$pid"
rc=$?
ok "SIGTERM ends it: it dies of the signal ($rc)" test "$rc" -eq 143
like "saying so" "$(tail -n1 "$log")" "^stopped watching iio:device[0-9]+$"
knob stats 0
sleep 3
is "so the bus is quiet" "$(dbg_get stats transactions)" 0

# The driver unbound under it: exit 69 within a poll, saying why.
sentral-warmstart watch --poll 2 >"$log" 2>&1 &
pid=$!
wait_for 5 grep -q "^watching" "$log"
sleep 1
echo "$client" >/sys/bus/i2c/drivers/em7180/unbind
t0=$(now_ms)
wait "$pid"
rc=$?
dt=$(($(now_ms) - t0))
is "unbound: exit 69" $rc 69
ok "within a poll (${dt} ms; poll 2 s, 1 s of slack)" test "$dt" -le 3000
like "saying the device is gone" "$(cat "$log")" \
	"error: iio:device[0-9]+ is gone \(unbound or unplugged\): .*; stopped watching it"
echo "$client" >/sys/bus/i2c/drivers/em7180/bind
ok "bound again" wait_for 5 em7180_dir

out=$(sentral-warmstart --i2c /dev/i2c-0 watch 2>&1)
is "over i2c-dev: refused (exit 64)" $? 64
like "saying why" "$out" "watch needs the em7180 driver"

done_testing
