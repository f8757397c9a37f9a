#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# Loading the simulated EM7180 with create=0, clients added through
# new_device, and 50 load/unload cycles with the data timer running.
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
