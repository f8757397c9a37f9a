#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# sentral-warmstart watch against the em7180 driver on the simulated chip.
# First a USFS board's firmware, which reports the calibration level alone
# (the stable rule): the watcher polls (one bus transaction a poll, nothing
# else), saves within a poll once the level reaches 4 with no file, and
# again when the level comes back to 4 with magnetometer coefficients that
# differ from the file's; nothing below level 4 (unreliable sensor data, a
# magnetic transient), nothing for coefficients within the tolerance; a
# glitched read is reported once, not saved; it saves while a buffer
# streams, and accel offsets written through calibbias, also below level 4
# (keeping the file's calibration); a manual watcher next to it changes
# nothing for it; SIGTERM ends it (it dies of the signal). A save that the
# write interval holds back is made once allowed while the level stays 4,
# and not while it is below; so is a save that failed (a full disk). Then
# the application note's layout (found by the driver at a bind, the score
# rule): a score saved over the file without one at the first look, then
# only a real improvement, at most once per --interval while the
# calibration keeps drifting, also while a buffer streams. It exits 69
# within a poll of the driver's unbind.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
client=$(basename "$(dirname "$(readlink -f "$DEV")")")
key=$(sentral-warmstart key)
f=$STATE/$key.ws
log=/tmp/watch.log

# Lines of the log matching ERE; at least N of them.
count() {
	grep -cE "$1" "$log"
}
logged() {
	[ "$(count "$2")" -ge "$1" ]
}
SAVED="saved iio:device[0-9]+ calibration"
saves() {
	count "$SAVED"
}

now_ms() {
	echo $(($(date +%s%N) / 1000000))
}
# When FILE was last written, in ms: a save's own time, where noticing the
# save in the log comes up to a poll of wait_for later
mtime_ms() {
	local t
	t=$(stat -c %.3Y "$1")
	echo $((10#${t/./}))
}

# The simulated chip's calibration is stable (debugfs: no bus transaction).
sim_stable() {
	[ "$(dbg_get state cal_status)" = 3 ]
}

# transient SECONDS: a magnetic transient (level 3) for SECONDS, then level
# 4 again: a rise to 4 for the watcher to see.
transient() {
	knob mag_transient 1
	sleep "$1"
	knob mag_transient 0
}

# A copy of the file with parameter 21 (a hard-iron offset, 25 uT) moved by
# 2 uT (8 %, beyond the tolerance) or 0.1 uT (0.4 %, within).
differs() {
	ws_edit "$f" /tmp/differs.ws '112:<f:+=2.0'
}
within() {
	ws_edit "$f" /tmp/within.ws '112:<f:+=0.1'
}
holds_chip() {
	[ "$(words 18 23 "$(file_payload_words "$f")")" = "$(words 18 23 "$(sim_ws_params)")" ]
}

knob gbias_period_ms 600000
sentral-warmstart watch --poll 2 --interval 6 --margin 0.2 >"$log" 2>&1 &
pid=$!
wait_for 5 grep -q "^watching" "$log"
like "it says what it does" "$(head -n1 "$log")" \
	"^watching iio:device[0-9]+: looking every 2 s; saving to $f when the calibration is stable \(level 4\) and, with a score, the score is at most 5\.000% and better than a good saved one by 0\.200 points, without one, its coefficients differ from the saved ones; or when the accel offsets change; at most one write every 6 s$"
nok "the driver has no change event any more" test -e "$DEV/events/in_magn_change_en"
sleep 3
nok "nothing saved while uncalibrated" test -e "$f"

# Calibrate: the watcher saves by itself, within a poll of level 4.
knob cal_duration_ms 1000
knob pattern sphere
ok "the chip calibrates" wait_for 20 sim_stable
t4=$(now_ms)
ok "saved by itself once stable" wait_for 10 test -e "$f"
dt=$(($(now_ms) - t4))
ok "within a poll of level 4 (${dt} ms; poll 2 s, 1 s of slack)" test "$dt" -le 3000
knob motion 0
ok "a valid file" sentral-warmstart show "$f"
like "with a message for the journal" "$(cat "$log")" \
	"$SAVED to $f: stable, and no usable saved calibration"
is "judged stable, no score" "$(ws_header "$f")" "2 4 2 0"
wait_for 3 logged 1 "$SAVED"

# Nothing new: no second write, and one bus transaction a poll.
sleep 5
is "the same calibration is not written again" "$(saves)" 1
knob stats 0
sleep 10
t=$(dbg_get stats transactions)
ok "a transaction a poll: $t in 10 s at --poll 2 (5, one more at the edges)" \
	test "$t" -ge 4 -a "$t" -le 6

# The level drops while the file's coefficients differ from the chip's:
# nothing is saved below level 4. Back at 4 the watcher reads the blob once
# and saves within a poll.
differs
knob algo_status_or 0x20
sleep 1
cp /tmp/differs.ws "$f"
sleep 4
ok "unreliable sensor data (level 1): nothing saved over the file" cmp "$f" /tmp/differs.ws
# Level 3 next, without a look at level 4 in between.
knob mag_transient 1
knob algo_status_or 0
sleep 4
ok "a magnetic transient (level 3): nothing saved over the file" cmp "$f" /tmp/differs.ws
is "no save below level 4" "$(saves)" 1
knob mag_transient 0
t4=$(now_ms)
ok "back at level 4: the moved coefficients are saved" wait_for 10 logged 2 "$SAVED"
dt=$(($(now_ms) - t4))
ok "within a poll (${dt} ms; poll 2 s, 1 s of slack)" test "$dt" -le 3000
like "saying which moved" "$(cat "$log")" \
	"$SAVED to $f: stable, and parameter 21 \(mcoeffs\[4\]\) moved from the saved file's by more than 0\.5 %"
ok "the file holds the chip's coefficients again" holds_chip

# Back at 4 with coefficients within the tolerance: the blob is read, once,
# and nothing written.
sleep 6
within
cp /tmp/within.ws "$f"
transient 3
ok "back at level 4 within the tolerance: the watcher looked" \
	wait_for 5 logged 1 "not saving .*: stable, and the magnetometer coefficients \(parameters 18-23\) are within 0\.5 % of the saved file's"
sleep 4
ok "and wrote nothing" cmp "$f" /tmp/within.ws
is "said once" "$(count "within 0\.5 %")" 1

# A glitched read (AlgorithmStatus bits 7:6) is an error, not a level: said
# once, nothing saved, and the watch goes on.
differs
cp /tmp/differs.ws "$f"
knob algo_status_or 0xc0
sleep 5
knob algo_status_or 0
like "a glitched read is reported" "$(cat "$log")" \
	"error: iio:device[0-9]+: reading in_magn_calibration_auto_status: Input/output error \(AlgorithmStatus read with a reserved bit set: a glitched read, not trusted\)"$'\n'"watch: looking again every 2 s"
is "once, though two polls or more failed" "$(count "reserved bit set")" 1
ok "nothing saved" cmp "$f" /tmp/differs.ws
ok "the watcher goes on" kill -0 "$pid"

# While a buffer streams: a level back at 4 with moved coefficients saved.
echo 1 >"$DEV/buffer0/in_accel_x_en"
ok "a buffer streams" sh -c "echo 1 >'$DEV/buffer0/enable'"
n=$(saves)
transient 3
ok "saved while it streams" wait_for 5 logged $((n + 1)) "$SAVED"
ok "the chip's coefficients" holds_chip
is "the buffer stayed enabled" "$(cat "$DEV/buffer0/enable")" 1
echo 0 >"$DEV/buffer0/enable"
echo 0 >"$DEV/buffer0/in_accel_x_en"
nok "no error but the glitch" sh -c "grep error '$log' | grep -qv 'reserved bit set'"

# A manual watcher next to the unit's: it ends, and the first goes on.
sentral-warmstart watch --poll 1 >/tmp/manual.log 2>&1 &
manual=$!
sleep 3
kill -TERM "$manual"
wait "$manual"
is "the manual watcher dies of SIGTERM (143 in a shell)" $? 143
like "saying so" "$(tail -n1 /tmp/manual.log)" "^stopped watching iio:device[0-9]+$"
ok "the first one still runs" kill -0 "$pid"
# Accel offsets written through calibbias: saved with the chip's
# calibration while it is stable, into the file's (kept) below level 4.
payload=$(file_payload_words "$f")
sleep 6
echo -47 >"$DEV/in_accel_x_calibbias"
ok "the first watcher saves the new offsets within a poll or two" \
	wait_for 10 grep -q "saved iio:device[0-9]* calibration to $f: stable, and the accel offsets differ from the saved file's" "$log"
is "into the file" "$(words 27 27 "$(file_payload_words "$f")")" "0xbcbbe447 "
is "its coefficients unchanged" "$(words 18 23 "$(file_payload_words "$f")")" "$(words 18 23 "$payload")"
sleep 6
knob mag_transient 1
sleep 3
echo -15 >"$DEV/in_accel_y_calibbias"
ok "at level 3 too, the offsets into the saved file" \
	wait_for 10 grep -q "saved iio:device[0-9]* accel offsets -47 -15 0 LSB to $f: the accel offsets differ from the saved file's; its calibration (level 4 (stable), no score) is kept: calibration not stable (level 3" "$log"
is "into the file" "$(words 27 28 "$(file_payload_words "$f")")" "0xbcbbe447 0xbbefdc9c "
is "its level, judgement and coefficients kept" \
	"$(ws_header "$f") $(words 18 23 "$(file_payload_words "$f")")" "2 4 2 0 $(words 18 23 "$payload")"
knob mag_transient 0

kill -TERM "$pid"
wait "$pid"
rc=$?
ok "SIGTERM ends it: it dies of the signal ($rc)" test "$rc" -eq 143
like "saying so" "$(tail -n1 "$log")" "^stopped watching iio:device[0-9]+$"
knob stats 0
sleep 3
is "so the bus is quiet" "$(dbg_get stats transactions)" 0

# A save that the write interval holds back: made at the first poll once
# allowed while the level stays 4; not while it is below.
sentral-warmstart watch --poll 1 --interval 8 >"$log" 2>&1 &
pid=$!
ok "a watcher that finds level 4 at its first look reads the blob" \
	wait_for 5 logged 1 "not saving .*within 0\.5 % of the saved file's"
differs
cp /tmp/differs.ws "$f"
transient 1.5
ok "a rise to 4 with moved coefficients: saved" wait_for 5 logged 1 "$SAVED"
t0=$(mtime_ms "$f")
differs
cp /tmp/differs.ws "$f"
transient 1.5
ok "the next one within the interval waits" \
	wait_for 5 logged 1 "watch: iio:device[0-9]+ has a calibration to save \(level 4, stable, and parameter 21 \(mcoeffs\[4\]\) moved .*\), but the last write was [0-9]+ s ago: saving it in [0-9]+ s unless it changes"
ok "and is saved once the interval has passed" wait_for 12 logged 2 "$SAVED"
dt=$(($(mtime_ms "$f") - t0))
ok "not before (${dt} ms; interval 8 s, a poll of 1 s)" test "$dt" -ge 7500 -a "$dt" -le 10000
ok "the chip's coefficients" holds_chip
differs
cp /tmp/differs.ws "$f"
transient 1.5
wait_for 5 logged 2 "has a calibration to save"
knob mag_transient 1
sleep 10
ok "a held save is not made while the level is below 4" cmp "$f" /tmp/differs.ws
is "(2 saves)" "$(saves)" 2
knob mag_transient 0
ok "back at 4, it is" wait_for 5 logged 3 "$SAVED"
ok "the chip's coefficients" holds_chip
kill -TERM "$pid"
wait "$pid"

# A save that fails (a full file system) is tried again once the interval
# has passed, while the level stays 4.
mkdir -p /tmp/full
mount -t tmpfs -o size=8k,mode=0700 tmpfs /tmp/full
differs
cp /tmp/differs.ws /tmp/full/cal.ws
dd if=/dev/zero of=/tmp/full/filler bs=1k count=64 status=none 2>/dev/null
sentral-warmstart watch --poll 1 --interval 4 --file /tmp/full/cal.ws >"$log" 2>&1 &
pid=$!
ok "a save on a full file system fails" wait_for 5 logged 1 "No space left on device"
like "and is to be tried again" "$(cat "$log")" "watch: trying again in 4 s"
rm /tmp/full/filler
ok "tried again once there is space" \
	wait_for 8 logged 1 "$SAVED to /tmp/full/cal.ws: stable, and parameter 21"
is "the chip's coefficients" "$(words 18 23 "$(file_payload_words /tmp/full/cal.ws)")" \
	"$(words 18 23 "$(sim_ws_params)")"
kill -TERM "$pid"
wait "$pid"
umount /tmp/full

# The application note's layout, found by the driver at the next bind: the
# score rule.
ok "bind with the application note's layout" set_layout 1 "$client"
DEV=$(em7180_dir)
ok "with its score" test -e "$DEV/in_magn_calibration_score"
sentral-warmstart watch --poll 2 --interval 6 --margin 0.2 >"$log" 2>&1 &
pid=$!
ok "a score saved at the first look over the file without one" \
	wait_for 5 grep -qE "$SAVED to $f: score 2\.70[0-9]% is within the limit" "$log"
is "judged by the score" "$(ws_header "$f" | cut -d' ' -f1-3)" "2 4 1"
sleep 5
is "the same calibration is not written again" "$(saves)" 1
knob stats 0
sleep 10
t=$(dbg_get stats transactions)
ok "a transaction a poll: $t in 10 s at --poll 2 (5, one more at the edges)" \
	test "$t" -ge 4 -a "$t" -le 6

# The surroundings keep changing every 3 s of turning (each time the best
# score reachable is another), with a buffer streaming: better calibrations
# come, at most one write per 6 s, and only 0.2 points better than the
# saved one. The chip converges in 1 s (cal_duration_ms), so each drift is
# stable for 2 s: one poll of every 2 s sees each (a drift period of 2 s,
# the poll's, let the polls fall in the converging second every time). The
# simulator's drifts are the same after every load: the 6th and 8th make a
# score 0.2 points better than the first save's, within 30 s.
echo 1 >"$DEV/buffer0/in_accel_x_en"
ok "a buffer streams" sh -c "echo 1 >'$DEV/buffer0/enable'"
knob drift_ms 3000
knob pattern sphere
sleep 36
knob motion 0
knob drift_ms 0
n=$(saves)
echo "# $n saves in 36 s of drift:"
grep -E "saved|not saving|waits|to save|error" "$log" | sed 's/^/#   /'
ok "some drifted calibrations saved while streaming" test "$n" -ge 2
ok "at most one write per 6 s (plus the first)" test "$n" -le 7
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
kill -TERM "$pid"
wait "$pid"

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
