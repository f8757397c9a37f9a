#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# Fault knobs of the simulated EM7180 (nack_at, ack_never, ack_latency_us,
# power_cycle, upload_ms) and ResetRequest.
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
knob ack_latency_us 500

# power_cycle: RAM state lost.
ok "rates, events, run" sim_wr 0x55 0x0a 0x0a 0x0a
ok "EnableEvents" sim_wr 0x33 0x3c
ok "run" sim_wr 0x34 0x01
ok "begin" param_begin
ok "write param 27" param_write 27 0x3f000000
ok "end" param_end
ok "motion" knob motion 1
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
is "CalStatus 0" "$(sim_rd 0x43)" 0x00
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
ok "unload" sim_unload
done_testing
