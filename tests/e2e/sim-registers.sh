#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# The simulated EM7180's register map: identity, status after power-on,
# clear-on-read, auto-increment block reads and writes, the register
# pointer across a STOP, auto-increment that stops at 0x3A and 0x63
# (autoinc_stop), rates, the identity knobs; a USFS board's linear
# acceleration in 0x3F..0x44 and the knobs for the application note's
# layout (appnote_layout) and AlgorithmStatus bits (algo_status_or).
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

# SMBus hosts write the register number in one transaction and read in
# another: the pointer persists across the STOP.
ok "write the register number 0x90 alone" sim_xfer w1@$SIM_ADDR 0x90
is "a separate read goes on from there" "$(sim_xfer r2@$SIM_ADDR)" "0x80 0x02"
is "and the next one from 0x92 (RunStatus)" "$(sim_xfer r1@$SIM_ADDR)" 0x00
ok "pointer to 0x70" sim_xfer w1@$SIM_ADDR 0x70
is "i2cget without a register (receive byte) reads at the pointer" \
	"$(i2cget -f -y "$SIM_BUS" $SIM_ADDR)" 0xe6

# Auto-increment: no reference host crosses 0x63->0x64 or 0x3A->0x3B in
# one transfer; autoinc_stop plays a chip whose pointer stops there.
is "autoinc_stop is 0 by default" "$(cat "$SIM_DBG/autoinc_stop")" 0
ok "autoinc_stop 1" knob autoinc_stop 1
ok "a 5-byte burst from 0x60" sim_wr 0x60 0x11 0x22 0x33 0x44 0x05
is "the fifth byte landed on 0x63 again" "$(sim_rd 0x60 4)" "0x11 0x22 0x33 0x05"
is "ParamRequest not written" "$(sim_rd 0x64)" 0x00
ok "begin a transfer" sim_wr 0x54 0x80
ok "ParamRequest 24 alone" sim_wr 0x64 24
ok "acknowledged, 0x3A polled alone" sim_poll_ack1 24
is "a burst from 0x3A repeats ParamAcknowledge" "$(sim_rd 0x3a 5)" \
	"0x18 0x18 0x18 0x18 0x18"
is "a block read from 0x3B has the value (1.0f)" "$(sim_rd 0x3b 4)" \
	"0x00 0x00 0x80 0x3f"
ok "end" sim_wr 0x64 0x00
ok "end" sim_wr 0x54 0x00
is "other bursts still increment" "$(sim_rd 0x70 4)" "0xe6 0x09 0x17 0x0d"
ok "autoinc_stop 0" knob autoinc_stop 0
ok "a 5-byte burst from 0x60 again" sim_wr 0x60 0x11 0x22 0x33 0x44 0x05
is "crosses to ParamRequest" "$(sim_rd 0x60 5)" "0x11 0x22 0x33 0x44 0x05"
ok "ParamRequest 0" sim_wr 0x64 0x00
nok "autoinc_stop refuses 2" knob autoinc_stop 2

# Identity knobs: another part or firmware.
ok "product_id 0x81" knob product_id 0x81
ok "revision_id 0x03" knob revision_id 0x03
ok "rom_version 0x07a8 (DI01)" knob rom_version 0x07a8
ok "ram_version 0x0e01" knob ram_version 0x0e01
is "ProductID, RevisionID follow" "$(sim_rd 0x90 2)" "0x81 0x03"
is "ROMVersion, RAMVersion follow" "$(sim_rd 0x70 4)" "0xa8 0x07 0x01 0x0e"
ok "ResetRequest" sim_wr 0x9b 0x01
ok "upload done" sim_wait_upload
is "they survive a reset" "$(sim_rd 0x70 4) $(sim_rd 0x90 2)" \
	"0xa8 0x07 0x01 0x0e 0x81 0x03"
is "product_id reads back" "$(cat "$SIM_DBG/product_id")" 0x81
is "revision_id reads back" "$(cat "$SIM_DBG/revision_id")" 0x03
is "rom_version reads back" "$(cat "$SIM_DBG/rom_version")" 0x07a8
nok "product_id refuses 0x100" knob product_id 0x100
ok "identity back to the defaults" sh -c "echo 0x80 >$SIM_DBG/product_id &&
	echo 2 >$SIM_DBG/revision_id && echo 0x09e6 >$SIM_DBG/rom_version &&
	echo 0x0d17 >$SIM_DBG/ram_version"
is "EventStatus after the reset: CPUReset" "$(sim_rd 0x35)" 0x01
ok "rates again" sim_wr 0x55 0x1e 0x0a 0x14
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

# A USFS board by default: 0x3F..0x44 (GP8..GP13) hold the linear
# acceleration Greg Tomasch's utilities read there, 0x4D..0x4E read 0; the
# application note's calibration registers are the knob appnote_layout.
is "appnote_layout 0 by default" "$(cat "$SIM_DBG/appnote_layout")" 0
is "algo_status_or 0x00 by default" "$(cat "$SIM_DBG/algo_status_or")" 0x00
lin=$(sim_rd 0x3f 6)
ok "linear acceleration ($lin) from the accel samples of the run above" \
	test "$lin" != "0x00 0x00 0x00 0x00 0x00 0x00"
ok "ResetRequest" sim_wr 0x9b 0x01
ok "upload done" sim_wait_upload
is "linear acceleration 0 after a reset, until an accel sample" \
	"$(sim_rd 0x3f 6)" "0x00 0x00 0x00 0x00 0x00 0x00"
is "0x4D..0x4E read 0" "$(sim_rd 0x4d 2)" "0x00 0x00"
ok "gyro bias period 100 ms" knob gbias_period_ms 100
ok "mag, accel and gyro rates" sim_wr 0x55 0x0a 0x0a 0x0a
ok "run" sim_wr 0x34 0x01
sleep 0.35
ok "stop" sim_wr 0x34 0x00
set -- $(sim_rd 0x3f 6)
is "still and level: linear acceleration = the accel bias" \
	"$(s16 $1 $2) $(s16 $3 $4) $(s16 $5 $6)" "-47 -15 46"
is "0x43/0x44 are bytes of z, and a read does not clear 0x44" \
	"$(echo $(sim_xfer w1@$SIM_ADDR 0x43 r2 w1@$SIM_ADDR 0x43 r2))" \
	"0x2e 0x00 0x2e 0x00"
ok "the model learned the gyro bias all the same" \
	[ "$(dbg_get cal_updates gbias)" -ge 1 ]
is "those reads of 0x44 are not reads of its flag" \
	"$(dbg_get cal_updates gbias_read)" 0
ok "mag_transient 2" knob mag_transient 2
is "AlgorithmStatus bit 4 (and still)" "$(sim_rd 0x38)" 0x14
is "0x43 is not touched by it" "$(sim_rd 0x43)" 0x2e
is "0x4D..0x4E still 0" "$(sim_rd 0x4d 2)" "0x00 0x00"

ok "appnote_layout 1: the application note's layout" knob appnote_layout 1
is "0x3F..0x42 read 0" "$(sim_rd 0x3f 4)" "0x00 0x00 0x00 0x00"
is "0x43: CalStatus 0, MagTransient in bits 3:2" "$(sim_rd 0x43)" 0x08
is "0x44: gBiasUpdate latched, cleared when read" \
	"$(echo $(sim_xfer w1@$SIM_ADDR 0x44 r1 w1@$SIM_ADDR 0x44 r1))" "0x02 0x00"
ok "and counted as read" [ "$(dbg_get cal_updates gbias_read)" -ge 1 ]
is "0x4D..0x4E: the score, 50 % at power-on (raw 49152)" "$(sim_rd 0x4d 2)" \
	"0x00 0xc0"
ok "appnote_layout 0" knob appnote_layout 0
is "linear acceleration again" "$(sim_rd 0x3f 6)" \
	"0xd1 0xff 0xf1 0xff 0x2e 0x00"
nok "appnote_layout refuses 2" knob appnote_layout 2
ok "mag_transient 0" knob mag_transient 0

ok "algo_status_or 0x20: unreliable sensor data" knob algo_status_or 0x20
is "AlgorithmStatus: still and bit 5" "$(sim_rd 0x38)" 0x24
is "algo_status_or reads back" "$(cat "$SIM_DBG/algo_status_or")" 0x20
ok "algo_status_or 0xc0: the reserved bits, as a glitch" knob algo_status_or 0xc0
is "AlgorithmStatus: still and bits 7:6" "$(sim_rd 0x38)" 0xc4
ok "algo_status_or 0xff" knob algo_status_or 0xff
is "AlgorithmStatus 0xff, as a bus glitch reads" "$(sim_rd 0x38)" 0xff
nok "algo_status_or refuses 0x100" knob algo_status_or 0x100
is "and keeps its value" "$(cat "$SIM_DBG/algo_status_or")" 0xff
# Only what AlgorithmStatus reads changes: a standby shown by the knob is
# not the chip's.
ok "algo_status_or 0x01, standby_power_loss 1" \
	sh -c "echo 1 >$SIM_DBG/algo_status_or && echo 1 >$SIM_DBG/standby_power_loss"
is "AlgorithmStatus shows standby" "$(sim_rd 0x38)" 0x05
is "the chip is not in standby: it keeps its power" \
	"$(cat "$SIM_DBG/standby_power_loss") $(sim_rd 0x55 3)" "1 0x0a 0x0a 0x0a"
ok "standby_power_loss 0" knob standby_power_loss 0
ok "algo_status_or 0" knob algo_status_or 0
is "AlgorithmStatus: still only" "$(sim_rd 0x38)" 0x04
ok "unload" sim_unload

# Both knobs at load, as a driver would find the chip.
sim_load knobs=appnote_layout=1,algo_status_or=0x20
is "load with knobs=appnote_layout=1,algo_status_or=0x20" $? 0
is "the knobs read back" \
	"$(cat "$SIM_DBG/appnote_layout") $(cat "$SIM_DBG/algo_status_or")" "1 0x20"
is "AlgorithmStatus: still and bit 5" "$(sim_rd 0x38)" 0x24
is "0x43, 0x44 and the score as the application note has them" \
	"$(sim_rd 0x43 2) $(sim_rd 0x4d 2)" "0x00 0x00 0x00 0xc0"
ok "unload" sim_unload
nok "knobs=algo_status_or=0x100 fails the load" \
	insmod "$SIM_KO" knobs=algo_status_or=0x100
nok "and leaves no module" test -d /sys/module/sentral_sim
done_testing
