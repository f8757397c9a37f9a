#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# The simulated EM7180's register map: identity, status after power-on,
# clear-on-read, auto-increment block reads and writes, rates.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/sim/testlib.sh"

sim_load
is "load the simulator" $? 0
like "adapter sentral-sim has a bus number" "$SIM_BUS" '^[0-9]+$'
is "client em7180 at 0x28" "$(cat /sys/bus/i2c/devices/$SIM_BUS-0028/name)" em7180

is "ProductID, RevisionID in one read" "$(sim_rd 0x90 2)" "0x80 0x02"
is "i2cget ProductID (SMBus emulation)" "$(i2cget -f -y "$SIM_BUS" 0x28 0x90)" 0x80
is "ROMVersion, RAMVersion little-endian" "$(sim_rd 0x70 4)" "0xe6 0x09 0x17 0x0d"
is "SentralStatus after upload: EEPROM, upload done, standby" "$(sim_rd 0x37)" 0x0b
is "EventStatus after power-on: CPUReset" "$(sim_rd 0x35)" 0x01
is "EventStatus is clear-on-read" "$(sim_rd 0x35)" 0x00
nok "address 0x29 does not answer" i2cget -f -y "$SIM_BUS" 0x29 0x90
nok "a transaction mixing 0x28 and 0x29 fails" \
	sim_xfer w1@0x28 0x90 r1@0x29

# auto-increment across registers, reads that wrap at 0xff
ok "burst write rates 0x55..0x57" sim_wr 0x55 0x1e 0x0a 0x14
is "burst read-back of the rate registers" "$(sim_rd 0x55 3)" "0x1e 0x0a 0x14"
is "actual rates are 0 while the CPU is not running" "$(sim_rd 0x45 3)" "0x00 0x00 0x00"
is "read wraps from 0xff to 0x00" "$(sim_rd 0xff 2)" "0x00 0x00"
ok "read-only ProductID ignores writes" sim_wr 0x90 0x12
is "ProductID unchanged" "$(sim_rd 0x90)" 0x80

ok "HostControl run" sim_wr 0x34 0x01
is "SentralStatus running: standby bit 3 clear" "$(sim_rd 0x37)" 0x03
is "RunStatus bit 0" "$(sim_rd 0x92)" 0x01
is "actual mag Hz, accel and gyro Hz/10" "$(sim_rd 0x45 3)" "0x1e 0x0a 0x14"
ok "request beyond the limits" sim_wr 0x55 0xff 0xc8 0x65
is "actual rates clamped to 100 Hz / 1000 Hz" "$(sim_rd 0x45 3)" "0x64 0x64 0x64"
ok "stop" sim_wr 0x34 0x00
is "SentralStatus back in standby" "$(sim_rd 0x37)" 0x0b

ok "AlgorithmControl standby request" sim_wr 0x54 0x01
like "AlgorithmStatus bit 0 follows it (still, bit 2, too)" "$(sim_rd 0x38)" '^0x05$'
ok "AlgorithmControl 0" sim_wr 0x54 0x00
is "AlgorithmStatus standby clear" "$(sim_rd 0x38)" 0x04

ok "ParamRequest echoes at once" sim_wr 0x64 0x05
is "0x64 reads back" "$(sim_rd 0x64)" 0x05
is "no acknowledge without AlgorithmControl bit 7" "$(sim_rd 0x3a)" 0x00
ok "ParamRequest 0" sim_wr 0x64 0x00

is "regs dump line 0x90" "$(grep '^90:' "$SIM_DBG/regs")" \
	"90: 80 02 00 00 00 00 00 00 00 00 00 00 00 00 00 00"
ok "unload" sim_unload
done_testing
