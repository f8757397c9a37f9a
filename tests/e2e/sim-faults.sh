#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# Fault knobs of the simulated EM7180 (nack_at, ack_never, ack_latency_us
# at the reference hosts' 5-10 ms polls and up to 1 s, power_cycle,
# upload_ms, chip_reset with and without INT (reset_int), warm_reboot) and
# ResetRequest.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/sim/testlib.sh"

sim_load
is "load the simulator" $? 0
defaults=$(cat "$SIM_DBG/params")

# nack_at N: exactly the Nth transaction after the write fails, once.
knob stats 0
ok "nack_at 3" knob nack_at 3
is "nack_at reads back" "$(cat "$SIM_DBG/nack_at")" 3
ok "transaction 1 succeeds" sim_wr 0x33 0x11
ok "transaction 2 succeeds" sim_rd 0x33
nok "transaction 3 is NACKed" sim_wr 0x33 0x22
ok "transaction 4 succeeds" sim_rd 0x90
is "nothing of the NACKed write took effect" "$(sim_rd 0x33)" 0x11
is "nack_at fired once and reads 0" "$(cat "$SIM_DBG/nack_at")" 0
is "stats: 5 transactions" "$(dbg_get stats transactions)" 5
is "stats: 1 nack" "$(dbg_get stats nacks)" 1
ok "nack_at 1" knob nack_at 1
nok "the very next transaction fails" sim_rd 0x90
ok "and the one after works" sim_rd 0x90
ok "nack_at 0 is off" knob nack_at 0
ok "transactions work" sim_rd 0x90

# ack_never: requests are never acknowledged.
ok "ack_never 1" knob ack_never 1
ok "begin" param_begin
ok "request param 24" sim_wr 0x64 24
nok "no acknowledge within 300 ms" sim_poll_ack 24 300
is "request still pending" "$(dbg_get state request_pending)" 1
ok "ack_never 0" knob ack_never 0
is "acknowledged once allowed" "$(sim_poll_ack 24 1000)" "0x18 0x00 0x00 0x80 0x3f"
ok "end" param_end

# ack_latency_us: the acknowledge appears that long after the request.
ok "ack_latency_us 1000000" knob ack_latency_us 1000000
knob stats 0
ok "begin" param_begin
ok "request param 24" sim_wr 0x64 24
is "not acknowledged at once" "$(sim_rd 0x3a)" 0x00
ok "acknowledged later" sim_poll_ack 24 5000
ok "end" param_end
el=$(dbg_get stats elapsed_us)
ok "elapsed_us $el >= 1000000" [ "$el" -ge 1000000 ]
bt=$(dbg_get stats bus_time_us)
ok "bus_time_us $bt includes the latency" [ "$bt" -ge 1000000 ]

# The reference hosts poll every 5-10 ms and allow up to 1 s.
ok "ack_latency_us 10000" knob ack_latency_us 10000
knob stats 0
ok "begin" param_begin
is "request param 24 and read 0x3A in one transaction: not yet" \
	"$(sim_xfer w2@$SIM_ADDR 0x64 24 w1@$SIM_ADDR 0x3a r1@$SIM_ADDR)" 0x00
ok "acknowledged, polled every 5 ms" sim_poll_ack1 24 1000
ok "end" param_end
el=$(dbg_get stats elapsed_us)
ok "elapsed_us $el >= 10000" [ "$el" -ge 10000 ]
ok "ack_latency_us takes 10 s" knob ack_latency_us 10000000
nok "and no more" knob ack_latency_us 10000001
knob ack_latency_us 500

# power_cycle: RAM state lost.
ok "rates, events, run" sim_wr 0x55 0x0a 0x0a 0x0a
ok "EnableEvents" sim_wr 0x33 0x3c
ok "run" sim_wr 0x34 0x01
ok "begin" param_begin
ok "write param 27" param_write 27 0x3f000000
ok "end" param_end
ok "motion" knob motion 1
sleep 0.1
set -- $(sim_rd 0x3f 2)
is "linear acceleration x: bias -47 less 0.5 g (1025 LSB) of offset" \
	"$(s16 $1 $2)" -1072
ok "upload_ms 2000" knob upload_ms 2000
ok "power_cycle 1" knob power_cycle 1
is "SentralStatus during the upload: EEPROM detected only" "$(sim_rd 0x37)" 0x01
is "RAMVersion 0 during the upload" "$(sim_rd 0x72 2)" "0x00 0x00"
ok "HostControl write during the upload" sim_wr 0x34 0x01
is "is ignored" "$(sim_rd 0x34)" 0x00
sleep 2.1
is "SentralStatus after the upload" "$(sim_rd 0x37)" 0x0b
is "HostControl 0, EventStatus CPUReset" "$(sim_rd 0x34 2)" "0x00 0x01"
is "EnableEvents 0" "$(sim_rd 0x33)" 0x00
is "rates 0" "$(sim_rd 0x55 3)" "0x00 0x00 0x00"
is "parameters back to defaults" "$(cat "$SIM_DBG/params")" "$defaults"
is "calibration lost: the model's CalStatus 0" "$(dbg_get state cal_status)" 0
is "linear acceleration 0 until an accel sample" "$(sim_rd 0x3f 6)" \
	"0x00 0x00 0x00 0x00 0x00 0x00"
is "motion knob survives (it is the world, not the chip)" "$(cat "$SIM_DBG/motion")" 1
nok "power_cycle accepts only 1" knob power_cycle 2
knob motion 0
knob upload_ms 10

# ResetRequest 0x9B bit 0 does the same from the bus.
ok "write a parameter" param_begin
ok "param 40" param_write 40 0x1234
ok "end" param_end
ok "run" sim_wr 0x34 0x01
ok "ResetRequest" sim_wr 0x9b 0x01
ok "upload done" sim_wait_upload
is "param 40 back to default" "$(param_get 40)" 0x00000000
is "SentralStatus after reset" "$(sim_rd 0x37)" 0x0b
is "EventStatus CPUReset" "$(sim_rd 0x35)" 0x01

# A reset of the chip's own (brown-out, watchdog) clears EnableEvents;
# whether INT still rises for CPUReset is reset_int.
ok "EnableEvents 0x3c" sim_wr 0x33 0x3c
is "reset_int is 1 by default" "$(cat "$SIM_DBG/reset_int")" 1
irq0=$(dbg_get state irqs)
ok "chip_reset" knob chip_reset 1
is "INT rose" "$(dbg_get state irqs)" $((irq0 + 1))
ok "upload done" sim_wait_upload
is "EnableEvents cleared" "$(sim_rd 0x33)" 0x00
is "EventStatus CPUReset" "$(sim_rd 0x35)" 0x01
is "INT low after the read" "$(dbg_get state int)" 0
ok "reset_int 0" knob reset_int 0
ok "EnableEvents 0x3c" sim_wr 0x33 0x3c
irq0=$(dbg_get state irqs)
ok "chip_reset" knob chip_reset 1
is "no edge" "$(dbg_get state irqs)" "$irq0"
is "INT low" "$(dbg_get state int)" 0
ok "upload done" sim_wait_upload
is "CPUReset latched for a host that polls" "$(sim_rd 0x35)" 0x01
ok "reset_int 1" knob reset_int 1

# A warm reboot of the host leaves the chip running; what users saw
# (SentralStatus 3, not 11) only a forced ResetRequest clears.
ok "rates, run" sim_wr 0x55 0x0a 0x0a 0x0a
ok "run" sim_wr 0x34 0x01
is "running: SentralStatus 0x03" "$(sim_rd 0x37)" 0x03
is "warm_reboot reads 0" "$(cat "$SIM_DBG/warm_reboot")" 0
ok "warm_reboot 1" knob warm_reboot 1
is "warm_reboot reads 1" "$(cat "$SIM_DBG/warm_reboot")" 1
ok "HostControl 0, as a host configuring" sim_wr 0x34 0x00
is "SentralStatus stays 0x03: no standby" "$(sim_rd 0x37)" 0x03
ok "HostControl 1" sim_wr 0x34 0x01
is "the algorithm does not run" "$(dbg_get state running)" 0
n=$(dbg_get samples accel)
sleep 0.1
is "no samples" "$(dbg_get samples accel)" "$n"
ok "begin" param_begin
ok "request param 24" sim_wr 0x64 24
nok "no acknowledge within 200 ms" sim_poll_ack1 24 200
ok "end" param_end
nok "warm_reboot accepts only 1" knob warm_reboot 0
ok "power cycle" knob power_cycle 1
ok "upload done" sim_wait_upload
is "a power cycle clears it too" "$(cat "$SIM_DBG/warm_reboot")" 0
ok "warm_reboot 1" knob warm_reboot 1
ok "ResetRequest" sim_wr 0x9b 0x01
ok "upload done" sim_wait_upload
is "the ResetRequest cleared it" "$(cat "$SIM_DBG/warm_reboot")" 0
is "SentralStatus 0x0b" "$(sim_rd 0x37)" 0x0b
ok "rates, run" sim_wr 0x55 0x0a 0x0a 0x0a
ok "run" sim_wr 0x34 0x01
n=$(dbg_get samples accel)
sleep 0.1
ok "samples again" [ "$(dbg_get samples accel)" -gt "$n" ]
ok "stop" sim_wr 0x34 0x00
ok "unload" sim_unload
done_testing
