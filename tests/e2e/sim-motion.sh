#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# Motion on the simulated EM7180: an orientation set or driven along a path
# moves gravity, the Earth's field, the gyro and the quaternion together;
# calibration needs coverage of the sphere: a spin about Z alone never
# completes it, a figure-8 and the sphere pattern do; the motion shortcut
# still calibrates and puts the device back down level.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/sim/testlib.sh"

now_ms() {
	echo $(($(date +%s%N) / 1000000))
}

vec() {
	set -- $(sim_rd "$1" 6)
	echo "$(s16 $1 $2) $(s16 $3 $4) $(s16 $5 $6)"
}

# The model's CalStatus (debugfs: the default board reports no number)
cal_status() {
	dbg_get state cal_status
}

# What a host sees: AlgorithmStatus bit 3, CalibStable
calibrated() {
	[ $(($(sim_rd 0x38) & 8)) = 8 ]
}

# Run PATTERN from level, power-on coefficients, until CalStatus 3 or
# LIMIT seconds; prints "SECONDS_TO_3|never SEEN_REGIONS STATUS".
run_pattern() {
	local pattern=$1 limit=$2 start t=never st
	knob motion 0
	knob power_cycle 1
	sim_wait_upload
	sim_wr 0x55 0x1e 0x0a 0x0a
	sim_wr 0x34 0x01
	knob pattern "$pattern"
	start=$(now_ms)
	while [ $(($(now_ms) - start)) -lt $((limit * 1000)) ]; do
		st=$(cal_status)
		if [ "$st" = 3 ]; then
			t=$(awk -v ms=$(($(now_ms) - start)) 'BEGIN { printf "%.1f", ms / 1000 }')
			break
		fi
		sleep 0.1
	done
	echo "$t $(dbg_get coverage seen) $(cal_status)"
}

sim_load
is "load the simulator" $? 0
ok "rates and run" sim_wr 0x55 0x1e 0x0a 0x0a
ok "run" sim_wr 0x34 0x01
is "pattern still at load" "$(cat "$SIM_DBG/pattern")" still
is "level orientation: identity (millionths w x y z)" "$(cat "$SIM_DBG/orientation")" "1000000 0 0 0"
is "100 regions, none seen" "$(sed -n 1,2p "$SIM_DBG/coverage" | tr '\n' ' ')" "regions 100 seen 0 "

# Upside down: half a turn about X.
ok "orientation upside down" knob orientation "0 1 0 0"
sleep 0.15
is "accel: gravity on -Z, plus the bias (-47, -15, +46)" "$(vec 0x1a)" "-47 -15 -2002"
is "linear acceleration in the sensor frame: gravity gone, the bias stays" \
	"$(vec 0x3f)" "-47 -15 46"
# body field (20, 0, -45) uT -> raw = field / gain + offset -> LSB
is "mag: the field upside down through the uncalibrated sensor" "$(vec 0x12)" "1547 -410 -241"
set -- $(sim_rd 0x00 16)
is "quaternion (1, 0, 0, 0): x = 1.0f" "$(bytes_le32 $1 $2 $3 $4) $(bytes_le32 ${13} ${14} ${15} ${16})" \
	"0x3f800000 0x00000000"
is "AlgorithmStatus: still" $(($(sim_rd 0x38) & 4)) 4
nok "a zero quaternion is refused" knob orientation "0 0 0 0"
nok "three numbers are refused" knob orientation "1 0 0"

# A path: 45 dps about X for 4 s brings it back level; then it holds.
# Long segments: a slow machine (UML on 6.1) takes most of a second per
# command.
ok "path cleared" knob path clear
ok "segment: X at 45 dps for 4000 ms" knob path "1 0 0 45 4000"
ok "segment: hold for 20000 ms" knob path "1 0 0 0 20000"
is "path reads back" "$(cat "$SIM_DBG/path" | tr '\n' ';')" "1 0 0 45 4000;1 0 0 0 20000;"
nok "rate above 720 dps refused" knob path "0 0 1 800 100"
nok "duration below 10 ms refused" knob path "0 0 1 90 5"
nok "zero axis refused" knob path "0 0 0 90 100"
ok "play the path" knob pattern path
start=$(now_ms)
nok "no change while it plays" knob path clear
sleep 0.3
# gyro and AlgorithmStatus in one transaction
set -- $(sim_xfer w1@$SIM_ADDR 0x22 r6 w1@$SIM_ADDR 0x38 r1)
gx=$(s16 $1 $2)
if [ $(($(now_ms) - start)) -lt 4000 ]; then
	# 45 dps = 295 LSB, + bias 12 unless learned, + noise
	ok "gyro x ~ 45 dps while turning ($gx LSB)" test "$gx" -ge 293 -a "$gx" -le 309
	is "not still while turning" $(($7 & 4)) 0
else
	ok "the machine took 4 s to read the gyro: turning not checked" false
fi
while [ $(($(now_ms) - start)) -lt 4300 ]; do sleep 0.1; done
is "level again after the turn: accel" "$(vec 0x1a)" "-47 -15 2094"
is "still while the path holds" $(($(sim_rd 0x38) & 4)) 4
ok "pattern still" knob pattern still
nok "an unknown pattern is refused" knob pattern zigzag

# The spin: 90 dps about Z, as the old motion switch did.
knob orientation "1 0 0 0"
knob pattern spin
sleep 0.3
set -- $(sim_rd 0x22 6)
gz=$(s16 $5 $6)
ok "spin: gyro z ~ 590 LSB (+ bias 5 unless learned) ($gz)" test "$gz" -ge 588 -a "$gz" -le 597
set -- $(sim_rd 0x1a 6)
is "spin keeps gravity on Z" "$(s16 $5 $6)" 2094
is "and no linear acceleration but the bias (the hand's is not modelled)" \
	"$(vec 0x3f)" "-47 -15 46"

# Calibration needs coverage: each pattern from power-on coefficients.
knob cal_duration_ms 1000
set -- $(run_pattern spin 8)
echo "# spin: to status 3: $1 s, regions seen $2, status $3"
is "spin about Z never completes the calibration" "$1" never
ok "spin sees one ring of directions ($2 regions)" test "$2" -le 20
ok "and stays at status 0 or 1" test "$3" -le 1
set -- $(run_pattern figure8 20)
echo "# figure8: to status 3: $1 s, regions seen $2"
nok "figure-8 completes the calibration" test "$1" = never
ok "having seen at least 70 regions ($2)" test "$2" -ge 70
set -- $(run_pattern sphere 20)
echo "# sphere: to status 3: $1 s, regions seen $2"
nok "sphere completes the calibration" test "$1" = never
ok "having seen at least 70 regions ($2)" test "$2" -ge 70

# The motion shortcut: sphere while 1, down level when 0.
knob motion 0
knob power_cycle 1
sim_wait_upload
sim_wr 0x55 0x1e 0x0a 0x0a
sim_wr 0x34 0x01
ok "motion 1" knob motion 1
is "is the sphere pattern" "$(cat "$SIM_DBG/pattern")" sphere
ok "CalibStable (AlgorithmStatus bit 3) within 15 s" wait_for 15 calibrated
is "the model's CalStatus 3" "$(cal_status)" 3
ok "motion 0" knob motion 0
is "still" "$(cat "$SIM_DBG/pattern")" still
is "level" "$(cat "$SIM_DBG/orientation")" "1000000 0 0 0"
sleep 0.15
is "calibrated mag z = 45 uT" "$(vec 0x12 | cut -d' ' -f3)" 1475

ok "unload" sim_unload
done_testing
