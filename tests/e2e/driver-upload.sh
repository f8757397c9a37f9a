#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --sim-knobs no_eeprom=1
#
# A board without an EEPROM (the simulator's no_eeprom): the driver uploads
# the firmware image em7180.fw with request_firmware, from a directory this
# test names in firmware_class.path. Images come from tests/refhost/mkfw.py
# (pseudo-random text, a CDS block with the RAM version). A missing file, a
# bad magic, a truncated image, one built for another ROM, one whose text
# does not give the header's CRC, and a bus that garbles the CRC (crc_wire)
# each fail probe with a message naming the file and the check, leave the
# chip out of upload mode, and a bind with a good image works after them.
# The RAM version is the image's, data streams, the warm start transfers;
# after a reset of the chip's own and a power loss in system sleep the
# driver uploads again. With an EEPROM nothing is uploaded, unless the
# client's firmware-name names an image, which then replaces the EEPROM's
# firmware.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"

PY=/usr/bin/python3
MKFW=$SENTRAL_ROOT/tests/refhost/mkfw.py
FWPATH=/sys/module/firmware_class/parameters/path
DRV=/sys/bus/i2c/drivers/em7180
T=$(mktemp -d /tmp/driver-upload.XXXXXX)
FW=$T/em7180.fw
UPLOADED='em7180 .*: firmware em7180.fw uploaded'

BUS=$(sim_bus)
CLIENT=$BUS-0028
ok "the simulator's client $CLIENT" test -e "/sys/bus/i2c/devices/$CLIENT"

bound() { test -e "$DRV/$CLIENT"; }
unbind() { ! bound || echo "$CLIENT" >"$DRV/unbind"; }
# bind: 0 when the driver probes; the probe's error otherwise
bind() { echo "$CLIENT" >"$DRV/bind"; }
# The kernel log since the last mark
mark() { dmesg | wc -l >"$T/mark"; }
since() { dmesg | tail -n +"$(($(cat "$T/mark") + 1))"; }
uploads() { dmesg | grep -c "$UPLOADED"; }
chip_quiet() {	# out of upload mode, not running, nothing pending
	echo "$(dbg_get board uploading) $(dbg_get state running)"
}
sim_ready() { grep -qx 'uploading 0' "$SIM_DBG/state"; }
mkfw() { $PY "$MKFW" "$FW" "$@" >"$T/mkfw.out"; }
fw_crc() { awk '$1 == "text_crc" { print $2 }' "$T/mkfw.out"; }
# failing_bind DESC PATTERN: bind fails and the log says PATTERN
failing_bind() {
	mark
	nok "$1: bind fails" bind
	like "  the log names the file and the check" "$(since | grep em7180)" "$2"
	is "  the chip is out of upload mode, not running" "$(chip_quiet)" "0 0"
	nok "  no IIO device" em7180_dir
}

# The harness loaded the simulator with no_eeprom=1 and the driver before
# there was any image: probe failed. Run alone, start from there.
if [ "$(cat "$SIM_DBG/no_eeprom")" = 1 ]; then
	ok "the first probe failed: no image" wait_for 10 \
		sh -c "dmesg | grep -q 'em7180.*cannot load firmware em7180.fw'"
	nok "  not bound" bound
else
	unbind
	knob no_eeprom 1
fi
ok "the ROM's search for an EEPROM is over" wait_for 5 sim_ready
is "SentralStatus: no EEPROM, standby" "$(dbg_get board firmware)" none

echo -n "$T" >"$FWPATH"
is "firmware_class.path names the test's directory" "$(cat "$FWPATH")" "$T"

failing_bind "no em7180.fw" \
	'cannot load firmware em7180.fw, needed as the board has no EEPROM: install it in the firmware directory'

mkfw --ram-version 0x0e42
printf '\x52\x46' | dd of="$FW" bs=1 seek=0 conv=notrunc status=none
failing_bind "a bad magic" \
	'firmware em7180.fw: bad magic 0x4652 \(expected 0x652a\): not a SENtral .fw image'

mkfw --ram-version 0x0e42 --truncate 100
failing_bind "a truncated image" \
	'firmware em7180.fw: truncated: 100 bytes of text, the header says 2048'

mkfw --ram-version 0x0e42 --rom-exp 1
failing_bind "an image for ROM DI01 on a DI02 chip" \
	'firmware em7180.fw: built for ROM DI01 \(0x07a8\), the chip has ROM 0x09e6'

mkfw --ram-version 0x0e42 --corrupt 100
crc=$(fw_crc)
failing_bind "a corrupted text" \
	"firmware em7180.fw: CRC mismatch: the chip computed 0x[0-9a-f]{8} over the text it received, the header says $crc"
is "  the chip received the whole text" "$(dbg_get board upload_bytes)" 2048

mkfw --ram-version 0x0e42
crc=$(fw_crc)
knob crc_wire 1
failing_bind "crc_wire: the chip's CRC over the bytes as they crossed the bus" \
	"firmware em7180.fw: CRC mismatch: the chip computed 0x[0-9a-f]{8} over the text it received, the header says $crc"
knob crc_wire 0

# A good image
mark
ok "a good image: bind" bind
DEV=$(em7180_dir)
ok "an IIO device" test -n "$DEV"
like "the log says what was uploaded" "$(since | grep em7180)" \
	"firmware em7180.fw uploaded \(2048 bytes, CRC $crc\)"
# (but the firmware loader's own line of Debian's kernels for the saved
# calibration the driver looks for at probe, which there is none of here)
is "nothing refused" "$(since | grep -v 'failed to load em7180/caldata-' |
	grep -c 'em7180.*\(error\|fail\|mismatch\)')" 0
like "firmware_version: the image's RAM version, from the host" \
	"$(driver_fw_version)" "ROM 0x09e6 RAM 0x0e42 host$"
is "firmware from the host, running" \
	"$(dbg_get board firmware) $(dbg_get state running)" "host 1"
ok "buffered capture: iio_readdev -b 16 -s 50" \
	sh -c "iio_readdev -b 16 -s 50 em7180 >$T/cap.bin"
is "50 scans of 40 bytes" "$(stat -c %s "$T/cap.bin")" 2000
ok "calibration_data read" dd if="$DEV/calibration_data" of="$T/ws.bin" \
	bs=148 count=1 status=none
is "148 bytes" "$(stat -c %s "$T/ws.bin")" 148
ok "calibbias write" sh -c "echo -47 >$DEV/in_accel_x_calibbias"

# A reset of the chip's own loses the RAM: recovery uploads again
n=$(uploads)
mark
knob chip_reset 1
ok "after chip_reset the driver uploads again" wait_for 10 \
	sh -c "[ \$(dmesg | grep -c '$UPLOADED') -gt $n ]"
ok "and the chip runs" wait_for 5 \
	sh -c "[ \"\$(awk '\$1 == \"running\" { print \$2 }' $SIM_DBG/state)\" = 1 ]"
is "the same firmware" "$(driver_ram_version) $(dbg_get board firmware)" \
	"0x0e42 host"
is "the offset written back" "$(cat "$DEV/in_accel_x_calibbias")" -47
is "recovery reports no error" \
	"$(since | grep -c 'em7180.*\(cannot restore\|not ready\|mismatch\)')" 0
ok "capture after the reset" \
	sh -c "iio_readdev -b 16 -s 50 em7180 >$T/cap2.bin"
is "50 scans" "$(stat -c %s "$T/cap2.bin")" 2000

# A power loss in system sleep: resume uploads again
n=$(uploads)
knob standby_power_loss 1
ok "a system sleep in which the chip loses power" sh -c \
	"echo devices >/sys/power/pm_test &&
	 echo 1 >/sys/module/suspend/parameters/pm_test_delay &&
	 echo freeze >/sys/power/state"
is "the power loss happened" "$(cat "$SIM_DBG/standby_power_loss")" 0
is "resume uploaded again" "$(uploads)" $((n + 1))
is "the chip runs the image's firmware" \
	"$(dbg_get state running) $(dbg_get board ram_version)" "1 0x0e42"
is "the offset written back" "$(dbg_get params 27)" 0xbcbbe447

# A reset whose upload fails (the image's CRC no longer comes out): the
# error is said and the chip is not left in upload mode
mark
knob crc_wire 1
knob chip_reset 1
ok "recovery with crc_wire: a CRC mismatch is logged" wait_for 10 \
	sh -c "dmesg | tail -n +$(($(cat "$T/mark") + 1)) | grep -q 'em7180.*CRC mismatch'"
ok "  out of upload mode" wait_for 5 \
	sh -c "[ \"\$(awk '\$1 == \"uploading\" { print \$2 }' $SIM_DBG/board)\" = 0 ]"
knob crc_wire 0

# Bound again over a chip that runs the uploaded firmware
ok "unbind" unbind
mark
ok "bind again" bind
ok "uploaded again" sh -c "dmesg | tail -n +$(($(cat "$T/mark") + 1)) | grep -q '$UPLOADED'"
DEV=$(em7180_dir)
is "RAM version" "$(driver_ram_version)" 0x0e42
ok "capture" sh -c "iio_readdev -b 16 -s 20 em7180 >$T/cap3.bin"
is "20 scans" "$(stat -c %s "$T/cap3.bin")" 800

# With an EEPROM nothing is uploaded, even with em7180.fw in the path
ok "unbind" unbind
knob no_eeprom 0
ok "the EEPROM's firmware is loaded" wait_for 5 sim_ready
n=$(uploads)
ok "bind with an EEPROM" bind
DEV=$(em7180_dir)
is "nothing uploaded" "$(uploads)" "$n"
is "the EEPROM's firmware" \
	"$(driver_ram_version) $(dbg_get board firmware)" "0x0d17 eeprom"
like "firmware_version: from the EEPROM" "$(driver_fw_version)" "RAM 0x0d17 eeprom$"
ok "capture" sh -c "iio_readdev -b 16 -s 20 em7180 >$T/cap4.bin"
is "20 scans" "$(stat -c %s "$T/cap4.bin")" 800

# A devicetree's firmware-name (the simulator's firmware_name parameter):
# with an EEPROM the named image replaces the EEPROM's firmware
MOD=$SENTRAL_MODROOT
ok "unload the driver and the simulator" \
	modprobe -d "$MOD" -r em7180_i2c em7180_core sentral_sim
mark
ok "load the simulator, firmware_name=board.fw" \
	modprobe -d "$MOD" sentral_sim firmware_name=board.fw
ok "load the driver" modprobe -d "$MOD" em7180_i2c
ok "no board.fw: probe fails" wait_for 10 sh -c \
	"dmesg | tail -n +$(($(cat "$T/mark") + 1)) | grep -q 'em7180 .*cannot load firmware board.fw'"
like "  the log names the file and the property" "$(since | grep em7180)" \
	'cannot load firmware board.fw \(firmware-name\): install it in the firmware directory'
$PY "$MKFW" "$T/board.fw" --ram-version 0x0e43 --size 1024 --seed 7 >"$T/mkfw.out"
crc=$(fw_crc)
mark
ok "board.fw installed: bind" bind
DEV=$(em7180_dir)
like "board.fw uploaded over the EEPROM's firmware" "$(since | grep em7180)" \
	"firmware board.fw uploaded \(1024 bytes, CRC $crc\)"
like "firmware_version: board.fw's RAM version, from the host over the EEPROM's" \
	"$(driver_fw_version)" "RAM 0x0e43 host$"
is "firmware from the host" "$(dbg_get board firmware)" host
ok "capture" sh -c "iio_readdev -b 16 -s 20 em7180 >$T/cap5.bin"
is "20 scans" "$(stat -c %s "$T/cap5.bin")" 800
n=$(dmesg | grep -c 'firmware board.fw uploaded')
knob chip_reset 1
ok "after a reset (the EEPROM's firmware again) board.fw is uploaded again" \
	wait_for 10 sh -c "[ \$(dmesg | grep -c 'firmware board.fw uploaded') -gt $n ]"
ok "and the chip runs" wait_for 5 \
	sh -c "[ \"\$(awk '\$1 == \"running\" { print \$2 }' $SIM_DBG/state)\" = 1 ]"
is "board.fw's firmware" "$(driver_ram_version) $(dbg_get board firmware)" \
	"0x0e43 host"

# Back as tests/uml/run leaves it, with an EEPROM
ok "unload" modprobe -d "$MOD" -r em7180_i2c em7180_core sentral_sim
ok "reload the simulator" modprobe -d "$MOD" sentral_sim
ok "reload the driver" modprobe -d "$MOD" em7180_i2c
ok "bound" wait_for 10 em7180_dir
echo -n "" >"$FWPATH"
rm -rf "$T"
done_testing
