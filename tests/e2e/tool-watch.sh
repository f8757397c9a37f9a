#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# sentral-warmstart watch against the em7180 driver on the simulated chip:
# it saves by itself once the chip is calibrated, only for a real
# improvement and at most once per --interval while the calibration keeps
# drifting, costs no bus transaction of its own while it sleeps, and on
# SIGTERM stops the driver's change checks and exits.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
key=$(sentral-warmstart key)
f=$STATE/$key.ws
log=/tmp/watch.log

saves() {
	grep -c "saved iio:device[0-9]* calibration" "$log"
}

saves_at_least() {
	[ "$(saves)" -ge "$1" ]
}

knob gbias_period_ms 600000
sentral-warmstart watch --interval 6 --margin 0.2 >"$log" 2>&1 &
pid=$!
wait_for 5 grep -q "^watching" "$log"
like "it says what it does" "$(head -n1 "$log")" \
	"^watching iio:device[0-9]+: saving to $f when the calibration is complete with a score of at most 5.000%, and better than a good saved one by 0.200 points; at most one write every 6 s$"
is "and has the driver check for changes" "$(cat "$DEV/events/in_magn_change_en")" 1
nok "nothing saved while uncalibrated" test -e "$f"

# Calibrate: the watcher saves by itself.
knob cal_duration_ms 1000
knob pattern sphere
ok "saved by itself once calibrated" wait_for 20 test -e "$f"
knob motion 0
ok "a valid file" sentral-warmstart show "$f"
like "with a message for the journal" "$(cat "$log")" \
	"saved iio:device[0-9]+ calibration to $f: score 2.70[0-9]% is within the limit"
wait_for 3 saves_at_least 1
first=$(stat -c %Y "$f")

# Nothing better: no second write, and no bus transaction of its own.
sleep 7
is "the same calibration is not written again" "$(saves)" 1
knob stats 0
sleep 4
t=$(dbg_get stats transactions)
ok "asleep: only the driver's backed-off checks use the bus ($t in 4 s)" \
	test "$t" -le 2

# The surroundings keep changing every 2 s of turning (each time the best
# score reachable is another): better calibrations come, at most one write
# per 6 s, and only 0.2 points better than the saved one.
knob drift_ms 2000
knob pattern sphere
sleep 30
knob motion 0
knob drift_ms 0
n=$(saves)
echo "# $n saves in 30 s of drift:"
grep -E "saved|not saving|waits|better calibration" "$log" | sed 's/^/#   /'
ok "some drifted calibrations saved" test "$n" -ge 2
ok "at most one write per 6 s (plus the first)" test "$n" -le 6
ok "every save better than the one before by the margin" awk '
	/saved iio/ && match($0, /score [0-9.]+%/) {
		s = substr($0, RSTART + 6, RLENGTH - 7) + 0
		if (n++ && s > prev - 0.2) exit 1
		prev = s
	}' "$log"
ok "the file is valid after it all" sentral-warmstart show "$f"

kill -TERM "$pid"
wait "$pid"
rc=$?
ok "SIGTERM ends it (it dies of the signal: $rc)" test "$rc" -eq 143
like "saying so" "$(tail -n1 "$log")" "^stopped watching iio:device[0-9]+$"
is "and the driver's checks are off" "$(cat "$DEV/events/in_magn_change_en")" 0
knob stats 0
sleep 3
is "so the bus is quiet" "$(dbg_get stats transactions)" 0

out=$(sentral-warmstart --i2c /dev/i2c-0 watch 2>&1)
is "over i2c-dev: refused (exit 64)" $? 64
like "saying why" "$out" "watch needs the em7180 driver"

done_testing
