#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# Loading the simulated EM7180 with create=0, clients added through
# new_device, knobs set at load (the knobs parameter), and 50 load/unload
# cycles with the data timer running.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/sim/testlib.sh"

sim_load create=0
is "load with create=0" $? 0
like "adapter present" "$SIM_BUS" '^[0-9]+$'
nok "no client at 0x28" test -e "/sys/bus/i2c/devices/$SIM_BUS-0028"
is "the model answers at 0x28 anyway" "$(sim_rd 0x90)" 0x80
ok "new_device em7180 0x28" sh -c "echo em7180 0x28 >/sys/bus/i2c/devices/i2c-$SIM_BUS/new_device"
is "client created" "$(cat "/sys/bus/i2c/devices/$SIM_BUS-0028/name")" em7180
is "still answering" "$(sim_rd 0x91)" 0x02
ok "run with data at 1 kHz" sim_wr 0x55 0x64 0x64 0x64
ok "run" sim_wr 0x34 0x01
ok "unload with a sysfs-created client and the timer running" sim_unload
nok "adapter gone" sim_bus

# Knobs at load, before any driver could probe the client.
sim_load adapters=2 knobs=autoinc_stop=1,bus_khz=400,product_id=0x81,warm_reboot=1
is "load with knobs" $? 0
is "autoinc_stop set" "$(cat "$SIM_DBG/autoinc_stop")" 1
is "bus_khz set" "$(cat "$SIM_DBG/bus_khz")" 400
is "warm_reboot set" "$(cat "$SIM_DBG/warm_reboot")" 1
is "ProductID 0x81 from the first transaction" "$(sim_rd 0x90)" 0x81
is "on every chip" "$(cat "$SIM_DBG-1/product_id") $(cat "$SIM_DBG-1/bus_khz")" "0x81 400"
ok "unload" sim_unload
nok "an unknown knob fails the load" insmod "$SIM_KO" knobs=no_such_knob=1
nok "a value a knob refuses fails the load" insmod "$SIM_KO" knobs=bus_khz=5
nok "a knob without a value fails the load" insmod "$SIM_KO" knobs=bus_khz
nok "module not loaded" grep -q '^sentral_sim ' /proc/modules

fail=0
for i in $(seq 50); do
	sim_load || { fail=$i; break; }
	sim_wr 0x55 0x64 0x64 0x64 >/dev/null && sim_wr 0x33 0x3c >/dev/null &&
		sim_wr 0x34 0x01 >/dev/null || { fail=$i; break; }
	sim_unload || { fail=$i; break; }
done
is "50 load/unload cycles" "$fail" 0
nok "module gone" grep -q '^sentral_sim ' /proc/modules
done_testing
