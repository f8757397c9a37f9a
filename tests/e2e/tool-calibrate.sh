#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# Guided calibration driven by each motion pattern of the simulator, through
# the driver and over i2c-dev: with a figure-8 or the sphere pattern
# `calibrate --json` ends at level 4 (stable), saves and reports the sphere
# covered: on a USFS board's firmware (no score) at the first stable
# calibration, without a gyro bias step, and not again over a file that
# holds the same coefficients; with the application note's layout after
# the gyro bias step, at the target score. With a spin about Z alone it
# times out and says that the device has only turned about its Z axis.
# Prints the figures of the guidance: seconds from the start of the motion
# to level 4, coverage at the end and how many of the regions the tool
# shows the chip has seen. Then accel-cal saves its offsets, which a power
# cycle and a restore bring back.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
client=$(basename "$(dirname "$(readlink -f "$DEV")")")
bus=$(sim_bus)

# field NAME: NAME's value in the JSON object on stdin (numbers, strings).
field() {
	python3 -c 'import json, sys
v = json.loads(sys.stdin.read())[sys.argv[1]]
print(" ".join(v) if isinstance(v, list) else v)' "$1"
}

# calibrate MODE PATTERN LAYOUT TIMEOUT [TOOL OPTIONS...]: a fresh
# (power-cycled) chip whose firmware has the application note's layout
# (LAYOUT 1) or not (0), still until the tool asks for the motion (after
# the gyro bias, where the firmware reports it), then PATTERN, saving to
# /tmp/MODE-PATTERN.ws. Sets rc, out (stdout, JSON), err and last (the
# last object before the save).
calibrate() {
	local mode=$1 pattern=$2 layout=$3 timeout=$4
	shift 4
	knob motion 0
	knob appnote_layout "$layout"
	if [ "$mode" = driver ]; then
		replug "$client" || return 1
	else
		knob power_cycle 1
		wait_for 5 sim_ready
		chip_run "$bus"
	fi
	knob gbias_period_ms 200
	# Short enough that coverage, not time, is what calibration waits for.
	knob cal_duration_ms 1000
	rm -f /tmp/err
	(
		wait_for 10 grep -qi "rotate the device slowly" /tmp/err
		knob pattern "$pattern"
	) &
	out=$(sentral-warmstart "$@" calibrate --json --timeout "$timeout" \
		--file "/tmp/$mode-$pattern.ws" 2>/tmp/err)
	rc=$?
	wait
	knob motion 0
	err=$(cat /tmp/err)
	last=$(echo "$out" | grep -v '"event":"\(saved\|not_saved\)"' | tail -n 1)
}

# completes MODE PATTERN LAYOUT AGREE: a pattern that must reach level 4,
# with at least AGREE % of the tool's regions among those the chip saw.
completes() {
	local mode=$1 pattern=$2 layout=$3 agree=$4 secs cov moved
	local ws=/tmp/$mode-$pattern.ws
	shift 4
	calibrate "$mode" "$pattern" "$layout" 40 "$@"
	is "$mode, $pattern: exit 0" $rc 0
	is "$mode, $pattern: ends with the complete event" "$(echo "$last" | field event)" complete
	is "$mode, $pattern: level 4 (stable)" \
		"$(echo "$last" | field level) $(echo "$last" | field level_name)" "4 stable"
	is "$mode, $pattern: then saved" "$(echo "$out" | tail -n 1 | field event)" saved
	ok "$mode, $pattern: the file is valid" sentral-warmstart show "$ws"
	if [ "$layout" = 1 ]; then
		like "$mode, $pattern: the gyro bias first" "$err" \
			"Step 1/2: keep the device still.*Gyro bias learned.*Step 2/2: rotate"
		ok "$mode, $pattern: score at the target" \
			awk -v s="$(echo "$last" | field score)" 'BEGIN { exit !(s <= 3.0) }'
		like "$mode, $pattern: says what it did" "$err" \
			"Calibration stable: score [0-9.]+%, [0-9]+% of the sphere covered.*saved .* to $ws: score [0-9.]+% is within the limit"
		is "$mode, $pattern: the file judged by the score" \
			"$(ws_header "$ws" | cut -d' ' -f1-3)" "2 4 1"
	else
		nok "$mode, $pattern: no gyro bias step (no update flags)" \
			grep -q "Step 1/2" <<<"$err"
		is "$mode, $pattern: no score" "$(echo "$last" | field score)" None
		like "$mode, $pattern: says what it did" "$err" \
			"Calibration stable: [0-9]+% of the sphere covered.*saved .* to $ws: stable, and no usable saved calibration"
		is "$mode, $pattern: the file judged stable, no score" \
			"$(ws_header "$ws")" "2 4 2 0"
	fi
	cov=$(echo "$last" | field coverage)
	is "$mode, $pattern: from a sphere fit" "$(echo "$last" | field fit)" sphere
	# The tool's map against the regions the chip has seen (same layout).
	set -- $(python3 -c 'import sys
tool, chip = sys.argv[1], sys.argv[2]
both = sum(t == "1" and c == "1" for t, c in zip(tool, chip))
print(tool.count("1"), chip.count("1"), both)' \
		"$(echo "$last" | field regions)" "$(dbg_get coverage map)")
	ok "$mode, $pattern: the map shows at least 40% of the sphere ($1 regions)" test "$1" -ge 40
	ok "$mode, $pattern: $agree% of its regions were seen by the chip ($3 of $1)" \
		test $(($3 * 100)) -ge $(($1 * agree))
	# From the first update with the device moving, as its user sees it.
	moved=$(echo "$out" | grep '"event":"progress"' |
		grep -v '"samples":[01],' | head -n 1 | field elapsed_ms)
	secs=$(awk -v e="$(echo "$last" | field elapsed_ms)" -v m="$moved" \
		'BEGIN { printf "%.1f", (e - m) / 1000 }')
	echo "# figure: $mode, $pattern (layout $layout): level 4 after $secs s of motion; the tool's map: $cov% of the sphere, $3 of its $1 regions among the chip's $2; $(echo "$last" | field samples) samples kept"
}

# check MODE: the spin, which must not complete and must say why.
spin_times_out() {
	local mode=$1 cov
	shift
	calibrate "$mode" spin 0 12 "$@"
	is "$mode, spin: times out, exit 75" $rc 75
	is "$mode, spin: the last event is a timeout" "$(echo "$last" | field event)" timeout
	ok "$mode, spin: level below 4" test "$(echo "$last" | field level)" -lt 4
	is "$mode, spin: the samples lie in a plane" "$(echo "$last" | field fit)" planar
	like "$mode, spin: the hint names the missing motion" "$(echo "$last" | field hint)" \
		"only turned about its Z axis: also tilt it nose up and down and roll it left and right"
	like "$mode, spin: and so does the error" "$err" \
		"did not become stable within 12 s \(level [0-3] of 4, [a-z ]+; 0% of the sphere covered; it has only turned about its Z axis.*nothing saved"
	nok "$mode, spin: nothing saved" test -e "/tmp/$mode-spin.ws"
	cov=$(echo "$last" | field coverage)
	echo "# figure: $mode, spin: no level 4 in 12 s (chip level $(echo "$last" | field level)), coverage $cov%"
	# one object per update: 4 a second
	ok "$mode, spin: about 4 updates a second ($(echo "$out" | wc -l) in 12 s)" \
		test "$(echo "$out" | wc -l)" -ge 30
}

# A figure-8 is a user's motion; the sphere pattern is fast (300 dps, 10
# samples per turn at the driver's 30 Hz) and its calibration moves the
# output's centre 10 times in 3 s, which the tool's fit follows late.
completes driver figure8 0 90
completes driver sphere 1 50
spin_times_out driver

# The same coefficients again, without a score: the file already holds them.
calibrate driver figure8 0 40
is "driver, figure8 again: exit 0" $rc 0
is "driver, figure8 again: stable, not saved" "$(echo "$out" | tail -n 1 | field event)" not_saved
like "driver, figure8 again: says why" "$err" \
	"not saving .* to /tmp/driver-figure8.ws: stable, and the magnetometer coefficients \(parameters 18-23\) are within 0.5 % of the saved file's"

# i2c-dev: the magnetometer registers, read in one burst.
ok "unbind the driver" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/unbind"
completes i2c figure8 0 90 --i2c "/dev/i2c-$bus"
completes i2c sphere 1 50 --i2c "/dev/i2c-$bus"
spin_times_out i2c --i2c "/dev/i2c-$bus"
is "transfer mode ended" "$(dbg_get state transfer)" 0
ok "bind the driver again" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/bind"

# accel-cal saves by itself: its offsets survive a power cycle, restored
# with the rest of the warm start.
ok "the driver is back" wait_for 5 em7180_dir
DEV=$(em7180_dir)
f=$STATE/$(sentral-warmstart key).ws
ok "calibrated by simulated motion" calibrate_by_motion
ok "and saved" sentral-warmstart save
out=$(sentral-warmstart accel-cal --samples 32 2>&1)
is "accel-cal: exit 0" $? 0
echo "$out" | sed 's/^/# /'
like "it saved by itself" "$out" "saved iio:device[0-9]+ .*to $f"
is "the file holds the offsets (Table 1)" "$(words 27 29 "$(file_payload_words "$f")")" "$TABLE1 "
ok "replug: unbind, power cycle, bind" replug "$client"
DEV=$(em7180_dir)
is "power cycle lost the offsets" "$(cat "$DEV"/in_accel_{x,y,z}_calibbias | tr '\n' ' ')" "0 0 0 "
ok "restore" sentral-warmstart restore
is "the offsets are back" "$(cat "$DEV"/in_accel_{x,y,z}_calibbias | tr '\n' ' ')" "-47 -15 46 "
out=$(sentral-warmstart accel-cal --samples 32 --no-save 2>&1)
like "accel-cal --no-save says how to keep them" "$out" "Run 'save' to keep them\.$"
nok "and saved nothing" grep -q "^saved" <<<"$out"

done_testing
