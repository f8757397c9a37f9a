#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# Bus accounting of the simulated EM7180: the stats formula, exactly.
# Each message costs 1 start bit + 9 bits per byte including the address
# byte; each transaction 1 stop bit; 2.5 us per bit at 400 kHz; plus
# ack_latency_us per parameter request served; total rounded to 1 us.
# With bus_khz the bit time is that clock's, and the adapter takes that
# long in real time.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/sim/testlib.sh"

sim_load
is "load the simulator" $? 0

knob stats 0
is "reset stats" "$(cat "$SIM_DBG/stats")" "transactions 0
bytes 0
bus_time_us 0
elapsed_us 0
nacks 0
params_served 0
ack_polls_early 0
wire_waits 0
wire_late_100us 0
wire_late_1ms 0
wire_late_max_us 0
host_gaps 0
host_gap_100us 0
host_gap_max_us 0
timer_late_max_us 0"

sim_rd 0x90 2 >/dev/null
is "w1 + r2: 1 transaction" "$(dbg_get stats transactions)" 1
is "w1 + r2: 3 bytes" "$(dbg_get stats bytes)" 3
is "w1 + r2: (1 + 19) + (1 + 27) + 1 = 48 bits = 120 us" "$(dbg_get stats bus_time_us)" 120

knob stats 0
i2cget -f -y "$SIM_BUS" 0x28 0x90 >/dev/null
is "i2cget: 39 bits = 97.5 us, rounded to 98" "$(dbg_get stats bus_time_us)" 98
is "i2cget: 2 bytes" "$(dbg_get stats bytes)" 2

knob stats 0
sim_wr 0x60 0 0 0 0 0 >/dev/null
is "6-byte write: 1 + 63 + 1 = 65 bits = 162.5 -> 163 us" "$(dbg_get stats bus_time_us)" 163

knob stats 0
sim_rd 0x90 >/dev/null
sim_wr 0x60 0 0 0 0 0 >/dev/null
is "totals are rounded once: 97.5 + 162.5 = 260 us" "$(dbg_get stats bus_time_us)" 260

# A parameter read: begin, request, k polls (w1 + r5), end (2 writes).
knob ack_latency_us 500
knob stats 0
ok "begin" param_begin
ok "request" sim_wr 0x64 24
ok "poll" sim_poll_ack 24
ok "end" param_end
t=$(dbg_get stats transactions)
k=$((t - 4))
bits=$((4 * 29 + k * 75))
is "parameter read: one request served" "$(dbg_get stats params_served)" 1
is "parameter read: the polls before the acknowledge counted early" \
	"$(dbg_get stats ack_polls_early)" $((k - 1))
is "parameter read: bytes" "$(dbg_get stats bytes)" $((4 * 2 + k * 6))
is "parameter read: $bits bits * 2.5 us + 500 us" "$(dbg_get stats bus_time_us)" \
	$(( (bits * 2500 + 500000 + 500) / 1000 ))

el=$(dbg_get stats elapsed_us)
ok "elapsed_us $el covers the latency" [ "$el" -ge 500 ]
nok "stats accepts only 0" knob stats 1

# bus_khz: the bit time of that clock, in the stats and in real time.
is "bus_khz 0 by default" "$(cat "$SIM_DBG/bus_khz")" 0
for khz in 100 400 1000; do
	ok "bus_khz $khz" knob bus_khz $khz
	knob stats 0
	sim_rd 0x90 2 >/dev/null
	us=$((48 * 1000 / khz))
	is "$khz kHz: w1 + r2, 48 bits = $us us" "$(dbg_get stats bus_time_us)" $us
	el=$(dbg_get stats elapsed_us)
	ok "$khz kHz: the transaction took $el >= $us us" [ "$el" -ge $us ]
done
ok "bus_khz 100" knob bus_khz 100
knob stats 0
t0=$(date +%s%N)
sim_rd 0x00 255 >/dev/null
ms=$((($(date +%s%N) - t0) / 1000000))
# (1 + 18) + (1 + 9 * 256) + 1 = 2325 bits at 10 us
is "100 kHz: w1 + r255 = 2325 bits = 23250 us" "$(dbg_get stats bus_time_us)" 23250
ok "it took $ms >= 23 ms of real time" [ "$ms" -ge 23 ]
is "one transfer waited for its wire time" "$(dbg_get stats wire_waits)" 1
late=$(dbg_get stats wire_late_max_us)
ok "how late it woke, $late us, is within the real time it took" \
	[ $((late >= 0 && late <= ms * 1000 - 23250)) = 1 ]
knob stats 0
ok "nack_at 1" knob nack_at 1
nok "a NACKed transaction" sim_rd 0x90
is "100 kHz: NACK, 11 bits = 110 us" "$(dbg_get stats bus_time_us)" 110
ok "bus_khz 0" knob bus_khz 0
knob stats 0
t0=$(date +%s%N)
sim_rd 0x00 255 >/dev/null
is "bus_khz 0: accounted at 400 kHz, 5812.5 -> 5813 us" \
	"$(dbg_get stats bus_time_us)" 5813
el=$(dbg_get stats elapsed_us)
ok "and no wire time ($el us)" [ "$el" -lt 5000 ]
nok "bus_khz refuses 5" knob bus_khz 5
nok "bus_khz refuses 3401" knob bus_khz 3401
ok "unload" sim_unload
done_testing
