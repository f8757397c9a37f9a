#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# Parameter transfer on the simulated EM7180 done with i2ctransfer exactly
# as the protocol says (EM7180 register reference §2): AlgorithmControl
# bit 7 set, one 5-byte burst 0x60..0x64 per write (ParamRequest alone for a
# read), ParamAcknowledge polled with 5-byte bursts 0x3A..0x3E, end with
# ParamRequest = 0 and bit 7 clear. Checked against debugfs params.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/sim/testlib.sh"

sim_load
is "load the simulator" $? 0
is "debugfs lists parameters 1..127" "$(wc -l <"$SIM_DBG/params")" 127
is "default param 24 (acoeffs 1.0f)" "$(param_get 24)" 0x3f800000
is "default param 74 (mag 1000 uT, accel 8 g)" "$(param_get 74)" 0x000803e8
is "default param 75 (gyro 2000 dps)" "$(param_get 75)" 0x000007d0

is "state: no transfer started yet" "$(dbg_get state transfer_started_us)" 0
is "state: no transfer ended yet" "$(dbg_get state transfer_ended_us)" 0
is "state: no transfer length yet" "$(dbg_get state transfer_longest_us)" 0
knob stats 0
ok "set AlgorithmControl bit 7" param_begin
ok "state: transfer_started_us set" [ "$(dbg_get state transfer_started_us)" -gt 0 ]
is "state: in transfer mode" "$(dbg_get state transfer)" 1
ok "request param 18 (read)" sim_wr 0x64 18
out=$(sim_poll_ack 18)
is "ack + SavedParam burst: 18, 1.0f little-endian" "$out" "0x12 0x00 0x00 0x80 0x3f"
is "param 75 read with the helper" "$(param_read 75)" 0x000007d0

ok "write param 40 = 0x12345678 in one burst" \
	sim_wr 0x60 0x78 0x56 0x34 0x12 0xa8
out=$(sim_poll_ack 0xa8)
is "write ack echoes 0xa8 and SavedParam holds the value" "$out" \
	"0xa8 0x78 0x56 0x34 0x12"
is "debugfs params shows the write" "$(param_get 40)" 0x12345678
is "read back through the protocol" "$(param_read 40)" 0x12345678
ok "write param 1 = -1.5f" param_write 1 0xbfc00000
is "debugfs params 1" "$(param_get 1)" 0xbfc00000
mono_us() { python3 -c 'import time; print(time.monotonic_ns() // 1000)'; }
t0=$(mono_us)
ok "end: ParamRequest 0, bit 7 clear" param_end
is "state: transfer mode ended" "$(dbg_get state transfer)" 0
t1=$(dbg_get state transfer_ended_us) t2=$(mono_us)
ok "state: transfer_ended_us on CLOCK_MONOTONIC, when bit 7 was cleared" \
	[ "$t0" -le "$t1" -a "$t1" -le "$t2" ]
ok "state: the transfer started before it ended" \
	[ "$(dbg_get state transfer_started_us)" -lt "$t0" ]
is "state: transfer_longest_us is this transfer's length" \
	"$(dbg_get state transfer_longest_us)" \
	$((t1 - $(dbg_get state transfer_started_us)))
is "ack reads 0 after the end" "$(sim_rd 0x3a)" 0x00
is "AlgorithmControl 0" "$(sim_rd 0x54)" 0x00
is "parameters served" "$(dbg_get stats params_served)" 5

# A request written before bit 7 is served once bit 7 is set.
knob ack_latency_us 0
ok "ParamRequest 40 with bit 7 clear" sim_wr 0x64 40
sleep 0.05
is "not served without bit 7" "$(sim_rd 0x3a 5)" "0x00 0x00 0x00 0xc0 0xbf"
ok "set bit 7" sim_wr 0x54 0x80
is "served once bit 7 is set" "$(sim_rd 0x3a 5)" "0x28 0x78 0x56 0x34 0x12"
ok "end" param_end

# A write's value is taken when the request is served, not when written.
knob ack_latency_us 1000000
ok "begin" param_begin
ok "write param 41 = 1" sim_wr 0x60 0x01 0x00 0x00 0x00 0xa9
ok "change LoadParamByte0 before the ack" sim_wr 0x60 0x02
ok "ack" sim_poll_ack 0xa9 5000
is "param 41 holds the bytes present when served" "$(param_get 41)" 0x00000002
ok "end" param_end

# Parameters 1..35 round trip: write all, read all.
knob ack_latency_us 500
ok "begin" param_begin
fail=0
for n in $(seq 1 35); do
	param_write "$n" $((0x40000000 + n)) || fail=1
done
is "35 writes acknowledged" $fail 0
bad=0
for n in $(seq 1 35); do
	[ "$(param_read "$n")" = "$(printf '0x%08x' $((0x40000000 + n)))" ] || bad=$((bad + 1))
done
is "35 reads return what was written" $bad 0
ok "end" param_end
is "debugfs param 35" "$(param_get 35)" 0x40000023
ok "unload" sim_unload
done_testing
