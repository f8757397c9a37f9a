#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# Sensor data of the simulated EM7180: accel gravity + bias and the seed's
# Table 1 offsets, linear acceleration (the USFS's 0x3F..0x44), gyro bias
# + noise, mag field, quaternion, timestamps counting samples, EventStatus
# bits for enabled events, sample accounting
# (read, missed, gaps, and whose loss a lost sample is); EventStatus latching
# every event while EnableEvents gates the INT pin (and the gated model as
# the events_gated knob); the Error event with ErrorRegister and
# SensorStatus.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/sim/testlib.sh"

sim_load
is "load the simulator" $? 0
is "data registers are 0 before the first sample" "$(sim_rd 0x1a 6)" \
	"0x00 0x00 0x00 0x00 0x00 0x00"
is "linear acceleration (0x3F..0x44) too" "$(sim_rd 0x3f 6)" \
	"0x00 0x00 0x00 0x00 0x00 0x00"

ok "accel 100 Hz, gyro 100 Hz, mag 10 Hz, quaternion divisor 1" \
	sim_wr 0x55 0x0a 0x0a 0x0a
ok "QRateDivisor 1" sim_wr 0x32 0x01
ok "EnableEvents: accel only" sim_wr 0x33 0x10
ok "clear CPUReset" sim_rd 0x35
knob samples 0
t0=$(date +%s%N)
ok "run" sim_wr 0x34 0x01
sleep 0.5
ok "stop" sim_wr 0x34 0x00
ms=$((($(date +%s%N) - t0) / 1000000))
is "EventStatus latches every data event, not only the enabled accel" \
	"$(sim_rd 0x35)" 0x3c

accel=$(dbg_get samples accel)
gyro=$(dbg_get samples gyro)
quat=$(dbg_get samples quaternion)
mag=$(dbg_get samples mag)
ok "$accel accel samples at 100 Hz in $ms ms" \
	test "$accel" -ge 25 -a "$accel" -le $((ms / 10 + 1))
is "quaternion every second gyro sample" "$quat" $((gyro / 2))
is "accel samples never read: all but the last missed" \
	"$(dbg_get samples accel_missed)" $((accel - 1))

set -- $(sim_rd 0x1a 8)
is "accel = gravity (0, 0, 2048) + bias (-47, -15, 46)" \
	"$(s16 $1 $2) $(s16 $3 $4) $(s16 $5 $6)" "-47 -15 2094"
is "ATIME = floor(n * 32768 / 100) mod 65536" $(( $7 | $8 << 8 )) \
	"$(( (accel * 32768 / 100) & 0xffff ))"
is "reading the accel block counts as read" "$(dbg_get samples accel_read)" 1
set -- $(sim_rd 0x3f 6)
is "linear acceleration = the reading less gravity: the bias" \
	"$(s16 $1 $2) $(s16 $3 $4) $(s16 $5 $6)" "-47 -15 46"

set -- $(sim_rd 0x00 18)
is "quaternion identity x, y, z = 0, w = 1.0f (w last)" "$*" \
	"0x00 0x00 0x00 0x00 0x00 0x00 0x00 0x00 0x00 0x00 0x00 0x00 0x00 0x00 0x80 0x3f ${17} ${18}"
is "QTIME at half the gyro rate" $(( ${17} | ${18} << 8 )) \
	"$(( (quat * 32768 * 2 / 100) & 0xffff ))"

set -- $(sim_rd 0x12 8)
is "mag = true field through the uncalibrated model" \
	"$(s16 $1 $2) $(s16 $3 $4) $(s16 $5 $6)" "1547 -410 2863"
is "MTIME" $(( $7 | $8 << 8 )) "$(( (mag * 32768 / 10) & 0xffff ))"

set -- $(sim_rd 0x22 8)
gx=$(s16 $1 $2) gy=$(s16 $3 $4) gz=$(s16 $5 $6)
like "gyro x = bias 12 + noise" "$gx" '^(1[0-4])$'
like "gyro y = bias -7 + noise" "$gy" '^-([5-9])$'
like "gyro z = bias 5 + noise" "$gz" '^[3-7]$'
is "GTIME" $(( $7 | $8 << 8 )) "$(( (gyro * 32768 / 100) & 0xffff ))"

# Table 1 of the application note: offsets in params 27..29 as float g.
ok "begin parameter transfer" param_begin
ok "param 27 = -0.022936 g (BC BB E4 47)" param_write 27 0xbcbbe447
ok "param 28 = -0.00732 g (BB EF DC 9C)" param_write 28 0xbbefdc9c
ok "param 29 = 0.022448 g (3C B7 E4 DE)" param_write 29 0x3cb7e4de
ok "end parameter transfer" param_end
ok "run" sim_wr 0x34 0x01
sleep 0.1
set -- $(sim_rd 0x1a 6)
is "accel with Table 1 offsets = 0, 0, 2048" \
	"$(s16 $1 $2) $(s16 $3 $4) $(s16 $5 $6)" "0 0 2048"
is "and no linear acceleration" "$(sim_rd 0x3f 6)" \
	"0x00 0x00 0x00 0x00 0x00 0x00"

ok "accel_bias knob" knob accel_bias "100 -200 0"
is "accel_bias reads back" "$(cat "$SIM_DBG/accel_bias")" "100 -200 0"
nok "accel_bias refuses two values" knob accel_bias "1 2"
sleep 0.1
set -- $(sim_rd 0x1a 6)
is "accel follows the bias minus the offsets" \
	"$(s16 $1 $2) $(s16 $3 $4) $(s16 $5 $6)" "147 -185 2002"
set -- $(sim_rd 0x3f 6)
is "linear acceleration follows with each accel sample" \
	"$(s16 $1 $2) $(s16 $3 $4) $(s16 $5 $6)" "147 -185 -46"

# The algorithm pauses during a parameter transfer: no samples.
ok "begin parameter transfer" param_begin
before=$(dbg_get samples accel)
sleep 0.2
is "no accel samples while in transfer mode" "$(dbg_get samples accel)" "$before"
ok "end parameter transfer" param_end
sleep 0.1
ok "samples counted again after the transfer" [ "$(dbg_get samples accel)" -gt "$before" ]

# 1 kHz accel + gyro. A late timer (loaded host) produces one sample per
# stream per callback and skips the ticks it missed: fewer samples, never a
# burst, so never more samples than milliseconds elapsed.
knob samples 0
t0=$(date +%s%N)
ok "accel and gyro 1000 Hz" sim_wr 0x56 0x64 0x64
sleep 1
ok "stop" sim_wr 0x34 0x00
ms=$((($(date +%s%N) - t0) / 1000000))
n=$(dbg_get samples accel) late=$(dbg_get samples timer_late)
ok "$n accel samples in $ms ms: no more than one per ms" [ "$n" -le $((ms + 1)) ]
ok "at least half the nominal rate" [ "$n" -ge 500 ]
ok "accel and gyro produced together" [ "$(dbg_get samples gyro)" = "$n" ]
echo "# 1 kHz for $ms ms: $n accel samples, $late late timer callbacks"

# Gaps: the samples a streaming host skipped between two reads of a block,
# not those made before its first read after a reset.
knob samples 0
ok "run" sim_wr 0x34 0x01
sleep 0.1
ok "stop" sim_wr 0x34 0x00
ok "read the accel block" sim_rd 0x1a 6
is "no gap counted before the first read" "$(dbg_get samples accel_gaps)" 0
n=$(dbg_get samples accel)
ok "run" sim_wr 0x34 0x01
sleep 0.1
ok "stop" sim_wr 0x34 0x00
ok "read the accel block again" sim_rd 0x1a 6
is "gaps = samples produced between the two reads" \
	"$(dbg_get samples accel_gaps)" $(($(dbg_get samples accel) - n - 1))
ok "gaps_held, those a late timer made, are part of the gaps" \
	[ "$(dbg_get samples accel_gaps_held)" -le "$(dbg_get samples accel_gaps)" ]

# INT pin: high while an enabled event is pending, cleared by reading
# EventStatus; the interrupt line gets one rising edge per low-to-high change.
ok "accel 100 Hz, EnableEvents accel" sim_wr 0x56 0x0a 0x0a
ok "EnableEvents accel" sim_wr 0x33 0x10
ok "clear EventStatus" sim_rd 0x35
irq0=$(dbg_get state irqs)
ok "run" sim_wr 0x34 0x01
sleep 0.2
ok "stop" sim_wr 0x34 0x00
is "one edge while EventStatus is never read" "$(dbg_get state irqs)" $((irq0 + 1))
is "INT still high" "$(dbg_get state int)" 1
ok "read EventStatus" sim_rd 0x35
is "INT low after reading EventStatus" "$(dbg_get state int)" 0
ok "run" sim_wr 0x34 0x01
for i in 1 2 3 4 5; do
	sleep 0.05
	sim_rd 0x35 >/dev/null
done
sleep 0.05
ok "stop" sim_wr 0x34 0x00
is "one edge per EventStatus read followed by a sample" \
	"$(dbg_get state irqs)" $((irq0 + 7))

# Whose loss a sample is: lost after the host read a data event from
# EventStatus (seen: the driver's doing) or before (unseen: its interrupt
# was not served in time). One EventStatus read, then two more samples.
accel_at_least() { [ "$(dbg_get samples accel)" -ge "$1" ]; }
ok "accel 10 Hz" sim_wr 0x56 0x01
knob samples 0
ok "run" sim_wr 0x34 0x01
ok "a first sample" wait_for 2 accel_at_least 1
ok "its EventStatus" sim_rd 0x35
ok "read it" sim_rd 0x1a 8
n=$(dbg_get samples accel)
ok "a second sample" wait_for 2 accel_at_least $((n + 1))
ev=$(sim_rd 0x35)
is "EventStatus reports it ($ev)" $((ev & 0x10)) 16
ok "two more samples, no read" wait_for 2 accel_at_least $((n + 3))
ok "stop" sim_wr 0x34 0x00
ok "read the accel block" sim_rd 0x1a 8
seen=$(dbg_get samples accel_drops_seen) unseen=$(dbg_get samples accel_drops_unseen)
is "one sample lost after a data-ready was seen" "$seen" 1
ok "the later ones lost unseen ($unseen)" [ "$unseen" -ge 1 ]
is "seen + unseen = gaps" $((seen + unseen)) "$(dbg_get samples accel_gaps)"
ok "drops_seen_held, those a late timer made, are part of drops_seen" \
	[ "$(dbg_get samples accel_drops_seen_held)" -le "$seen" ]
# Its cause: the host read EventStatus and then wrote HostControl, not
# the data (unless the machine stalled: the next sample's timer held)
causes=$(grep '^accel_drops_seen_' "$SIM_DBG/samples" | awk '{ n += $2 } END { print n }')
is "its causes add up to drops_seen" "$causes" "$seen"
cause=$(awk '{ print $2 }' "$SIM_DBG/drops")
ok "the host read EventStatus and not the data ($cause)" \
	sh -c "[ '$cause' = unread ] || [ '$cause' = held ]"
like "its evidence: the next transaction was not the burst" \
	"$(cat "$SIM_DBG/drops")" '^accel [a-z]+ period_us 100000 .* next other '

# A sample that came while EnableEvents enabled no data event is nobody's
# loss when a host starting to stream finds it in EventStatus (the
# magnetometer at 1 Hz: time for the steps between two samples, which at
# 2 Hz a loaded host took longer than, shifting them by a sample)
mag_at_least() { [ "$(dbg_get samples mag)" -ge "$1" ]; }
ok "mag 1 Hz" sim_wr 0x55 0x01
ok "EnableEvents: none" sim_wr 0x33 0x00
knob samples 0
ok "run" sim_wr 0x34 0x01
ok "a first sample" wait_for 3 mag_at_least 1
ok "read it" sim_rd 0x12 8
ok "another" wait_for 3 mag_at_least 2
ok "EnableEvents mag" sim_wr 0x33 0x08
ok "its EventStatus" sim_rd 0x35
ok "a third sample" wait_for 3 mag_at_least 3
ok "read it" sim_rd 0x12 8
ok "stop" sim_wr 0x34 0x00
is "the second was lost seen" "$(dbg_get samples mag_drops_seen)" 1
# (or held: the machine stalled the timer that made the next one)
idle=$(dbg_get samples mag_drops_seen_idle)
held=$(dbg_get samples mag_drops_seen_held)
is "it came before the host streamed: idle ($idle, held $held)" \
	$((idle + held)) 1
[ $((idle + held)) = 1 ] || sed 's/^/#   /' "$SIM_DBG/drops"

# A host that came back from the status read in time and read the data a
# period after the next sample, later than an interrupt served and a thread
# woken at once would excuse: slow
ok "EnableEvents accel" sim_wr 0x33 0x10
knob samples 0
ok "run" sim_wr 0x34 0x01
ok "a first sample" wait_for 2 accel_at_least 1
ok "read it" sim_rd 0x1a 8
n=$(dbg_get samples accel)
ok "a second sample" wait_for 2 accel_at_least $((n + 1))
ok "its EventStatus" sim_rd 0x35
ok "two more samples" wait_for 2 accel_at_least $((n + 3))
ok "read the block" sim_rd 0x1a 8
ok "stop" sim_wr 0x34 0x00
is "the second was lost seen" "$(dbg_get samples accel_drops_seen)" 1
held=$(dbg_get samples accel_drops_seen_held)
is "by the host's own time between its two reads (or a held timer)" \
	"$(($(dbg_get samples accel_drops_seen_slow) + held))" 1
like "its evidence: the next transaction was the burst" \
	"$(cat "$SIM_DBG/drops")" '^accel (slow|held) .* next burst '
slow=$(cat "$SIM_DBG/drops_host")
is "drops_host keeps the host's own drops apart" \
	"$(grep -c . "$SIM_DBG/drops_host")" \
	"$(dbg_get samples accel_drops_seen_slow)"

# A loaded machine's many losses do not push the host's out of drops_host:
# 150 status reads of a 1000 Hz stream while no data event is enabled,
# each sample seen and replaced unread (idle)
ok "accel 1000 Hz" sim_wr 0x56 0x64
ok "EnableEvents: none" sim_wr 0x33 0x00
ok "run" sim_wr 0x34 0x01
for i in $(seq 150); do sim_rd 0x35 >/dev/null; done
ok "stop" sim_wr 0x34 0x00
ok "more than 128 idle drops ($(dbg_get samples accel_drops_seen_idle))" \
	[ "$(dbg_get samples accel_drops_seen_idle)" -gt 128 ]
is "drops keeps the last 128" "$(grep -c . "$SIM_DBG/drops")" 128
is "drops_host still has the host's" "$(cat "$SIM_DBG/drops_host")" "$slow"

# EventStatus latches every event; EnableEvents gates only the INT pin, as
# on silicon (hosts tested on boards enable 0x07 and use the data bits).
ok "rates: mag 10 Hz, accel and gyro 100 Hz" sim_wr 0x55 0x0a 0x0a 0x0a
ok "QRateDivisor 0" sim_wr 0x32 0x00
is "events_gated is 0 by default" "$(cat "$SIM_DBG/events_gated")" 0
ok "EnableEvents 0x07: reset, error, quaternion" sim_wr 0x33 0x07
ok "clear EventStatus" sim_rd 0x35
irq0=$(dbg_get state irqs)
ok "run" sim_wr 0x34 0x01
sleep 0.3
ok "stop" sim_wr 0x34 0x00
is "INT rose for the quaternion" "$(dbg_get state int)" 1
is "EventStatus: quaternion, mag, accel and gyro all latched" "$(sim_rd 0x35)" 0x3c
is "one edge" "$(dbg_get state irqs)" $((irq0 + 1))
ok "EnableEvents 0" sim_wr 0x33 0x00
irq0=$(dbg_get state irqs)
ok "run" sim_wr 0x34 0x01
sleep 0.3
ok "stop" sim_wr 0x34 0x00
is "nothing enabled: INT stays low" "$(dbg_get state int)" 0
is "no edge" "$(dbg_get state irqs)" "$irq0"
is "and still every data event latched" "$(sim_rd 0x35)" 0x3c

# The old model as a knob: only enabled events latch.
ok "events_gated 1" knob events_gated 1
ok "EnableEvents accel" sim_wr 0x33 0x10
ok "run" sim_wr 0x34 0x01
sleep 0.3
ok "stop" sim_wr 0x34 0x00
is "gated: EventStatus holds the accel event only" "$(sim_rd 0x35)" 0x10
ok "error 0x11 while gated and not enabled" knob error 0x11
is "gated: no Error bit" "$(sim_rd 0x35)" 0x00
ok "events_gated 0" knob events_gated 0
nok "events_gated refuses 2" knob events_gated 2

# Error event: ErrorRegister (0x50) holds the code, EventStatus bit 1.
ok "EnableEvents 0x03: reset, error" sim_wr 0x33 0x03
ok "clear EventStatus" sim_rd 0x35
irq0=$(dbg_get state irqs)
ok "error 0x21 (mag init failed)" knob error 0x21
is "error reads back" "$(cat "$SIM_DBG/error")" 0x21
is "ErrorRegister 0x21" "$(sim_rd 0x50)" 0x21
is "INT rose for the enabled Error event" "$(dbg_get state irqs)" $((irq0 + 1))
is "EventStatus: Error" "$(sim_rd 0x35)" 0x02
is "INT low after the read" "$(dbg_get state int)" 0
is "ErrorRegister stays after EventStatus is read" "$(sim_rd 0x50)" 0x21
ok "sensor_status 0x11: mag NACK, mag ID error" knob sensor_status 0x11
is "SensorStatus 0x36" "$(sim_rd 0x36)" 0x11
ok "EnableEvents 0" sim_wr 0x33 0x00
irq0=$(dbg_get state irqs)
ok "error 0x80 (invalid sample rate), Error not enabled" knob error 0x80
is "no edge" "$(dbg_get state irqs)" "$irq0"
is "Error latched all the same" "$(sim_rd 0x35)" 0x02
ok "error 0 clears ErrorRegister" knob error 0
is "without an event" "$(sim_rd 0x35 2)" "0x00 0x11"
ok "error 0x30" knob error 0x30
ok "ResetRequest" sim_wr 0x9b 0x01
ok "upload done" sim_wait_upload
is "a reset clears ErrorRegister" "$(sim_rd 0x50)" 0x00
is "SensorStatus stays: the sensor is still dead" "$(sim_rd 0x36)" 0x11
is "EventStatus after the reset: CPUReset only" "$(sim_rd 0x35)" 0x01
ok "sensor_status 0" knob sensor_status 0
nok "error refuses 256" knob error 256
ok "unload" sim_unload
done_testing
