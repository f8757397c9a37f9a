#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# Calibration on the simulated EM7180: progress while in motion, score,
# latched update flags, gyro bias learned while still, a restored warm start
# complete at once, MagTransient; in the application note's registers
# (appnote_layout 1, set at load), then on the default USFS board, where
# AlgorithmStatus alone shows the same model.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/sim/testlib.sh"

score() {
	set -- $(sim_rd 0x4d 2)
	echo $(($1 | $2 << 8))
}

sim_load knobs=appnote_layout=1
is "load the simulator with the application note's layout" $? 0
is "CalStatus 0 at power-on" "$(sim_rd 0x43)" 0x00
is "score 50% at power-on: 32768 + 50 * 327.68" "$(score)" 49152
is "no update flags" "$(sim_rd 0x44)" 0x00

ok "gyro bias period 100 ms" knob gbias_period_ms 100
# long enough for each CalStatus to be seen even on a loaded host
ok "calibration takes 5000 ms" knob cal_duration_ms 5000
nok "a zero calibration time is refused" knob cal_duration_ms 0
nok "a zero gyro-bias period is refused" knob gbias_period_ms 0
is "and the values stay" "$(cat "$SIM_DBG/cal_duration_ms") $(cat "$SIM_DBG/gbias_period_ms")" "5000 100"
ok "rates and run" sim_wr 0x55 0x1e 0x0a 0x0a
ok "run" sim_wr 0x34 0x01
sleep 0.35
# two reads of 0x44 in one transaction: no time for another update between
is "gBiasUpdate latched while still; 0x44 is clear-on-read" \
	"$(echo $(sim_xfer w1@$SIM_ADDR 0x44 r1 w1@$SIM_ADDR 0x44 r1))" "0x02 0x00"
is "learned gyro bias x (12 LSB in dps)" "$(param_get 33)" 0x3fea6000
is "learned gyro bias y (-7 LSB)" "$(param_get 34)" 0xbf88b800
is "learned gyro bias z (5 LSB)" "$(param_get 35)" 0x3f435000
set -- $(sim_rd 0x22 6)
like "gyro output now bias-free (noise only)" "$(s16 $1 $2) $(s16 $3 $4) $(s16 $5 $6)" \
	'^-?[0-2] -?[0-2] -?[0-2]$'

ok "motion" knob motion 1
seen= flags=0 last_status=
end=$(($(date +%s%N) / 1000000 + 10000))
while [ $(($(date +%s%N) / 1000000)) -lt $end ]; do
	set -- $(sim_rd 0x43 2)
	st=$(($1 & 3))
	[ "$st" != "$last_status" ] && seen="$seen$st" && last_status=$st
	flags=$((flags | $2))
	[ "$st" = 3 ] && break
	sleep 0.1
done
is "CalStatus climbs 0, 1, 2, 3" "$seen" 0123
is "magCalUpdate latched during calibration" $((flags & 1)) 1
is "score at the true coefficients: 2.700% = 32768 + 885" "$(score)" 33653
is "AlgorithmStatus: CalibStable, not still" "$(sim_rd 0x38)" 0x08
is "mcoeff 18 converged to the true gain 0.9" "$(param_get 18)" 0x3f666666
is "mcoeff 22 converged to the true offset -12.5" "$(param_get 22)" 0xc1480000
sleep 0.1
sim_rd 0x44 >/dev/null
sleep 0.2
is "no magCalUpdate once converged" $(( $(sim_rd 0x44) & 1 )) 0
ok "still" knob motion 0
sleep 0.1
set -- $(sim_rd 0x16 2)
is "calibrated mag z = 45 uT" "$(s16 $1 $2)" 1475

saved=$(for n in 18 19 20 21 22 23; do param_get $n; done)
ok "power cycle" knob power_cycle 1
ok "upload done" sim_wait_upload
is "CalStatus 0 after power cycle" "$(sim_rd 0x43)" 0x00
is "score back to 50%" "$(score)" 49152
is "mcoeff 18 back to 1.0" "$(param_get 18)" 0x3f800000

ok "run" sim_wr 0x34 0x01
ok "begin parameter transfer" param_begin
i=18
for v in $saved; do
	param_write $i "$v" || break
	i=$((i + 1))
done
is "6 coefficients restored" $i 24
ok "end parameter transfer" param_end
is "CalStatus 3 at once after the restore" "$(sim_rd 0x43)" 0x03
is "with the score of the restored coefficients" "$(score)" 33653

# A poorer warm start: offsets half way, gains true -> status and score
# computed from the distance to the true coefficients.
ok "begin" param_begin
ok "param 21 = 12.5" param_write 21 0x41480000
ok "param 22 = -6.25" param_write 22 0xc0c80000
ok "param 23 = 20.0" param_write 23 0x41a00000
ok "end" param_end
# error = 38.75 uT of 89 uT -> 2.7 + 47.3 * 38.75 / 89 = 23.294% -> status 1
is "CalStatus 1 for a half-done restore" "$(sim_rd 0x43)" 0x01
is "score 23.294%" "$(score)" $((32768 + (23294 * 32768 + 50000) / 100000))

ok "mag_transient 2" knob mag_transient 2
is "0x43 bits 3:2 carry MagTransient" "$(sim_rd 0x43)" 0x09
is "AlgorithmStatus bit 4" $(( $(sim_rd 0x38) & 0x10 )) 16
nok "mag_transient 4 refused" knob mag_transient 4
ok "mag_transient 0" knob mag_transient 0

# The default board: the same model, seen through AlgorithmStatus bit 3
# (CalibStable) and the warm-start parameters; debugfs state shows its
# status and score.
ok "appnote_layout 0" knob appnote_layout 0
is "the model: status 1, score 23.294 %" \
	"$(dbg_get state cal_status) $(dbg_get state score_raw)" \
	"1 $((32768 + (23294 * 32768 + 50000) / 100000))"
is "AlgorithmStatus: not CalibStable" $(( $(sim_rd 0x38) & 0x08 )) 0
ok "power cycle" knob power_cycle 1
ok "upload done" sim_wait_upload
ok "run" sim_wr 0x34 0x01
ok "begin parameter transfer" param_begin
i=18
for v in $saved; do
	param_write $i "$v" || break
	i=$((i + 1))
done
is "6 coefficients restored" $i 24
ok "end parameter transfer" param_end
is "AlgorithmStatus bit 3 (CalibStable) at once after the warm start" \
	$(( $(sim_rd 0x38) & 0x08 )) 8
is "the model: status 3, the score of the restored coefficients" \
	"$(dbg_get state cal_status) $(dbg_get state score_raw)" "3 33653"
is "0x43..0x44 and 0x4D..0x4E show none of it (no accel rate: 0)" \
	"$(sim_rd 0x43 2) $(sim_rd 0x4d 2)" "0x00 0x00 0x00 0x00"
ok "motion" knob motion 1
ok "mag_transient 1" knob mag_transient 1
is "AlgorithmStatus: CalibStable and MagTransient, not still" \
	"$(sim_rd 0x38)" 0x18
ok "mag_transient 0, still" sh -c "echo 0 >$SIM_DBG/mag_transient && echo 0 >$SIM_DBG/motion"
ok "unload" sim_unload
done_testing
