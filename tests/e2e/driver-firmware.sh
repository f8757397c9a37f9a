#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# Calibration status, score and flags only on firmware known to report
# them: the simulator's client names its RAM version (0x0d17) in
# emmicro,calibration-firmware, as a board's devicetree would. Another RAM
# version binds without the five calibration attributes, logs why once per
# binding, never reads the general-purpose registers, and still streams and
# transfers calibration_data; the module parameter calibration_firmware adds
# it. sentral-warmstart says so and restores without waiting for a status.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

TMP=$(mktemp -d)
CAL="in_magn_calibration_auto_status in_magn_calibration_score in_magn_transient in_anglvel_calibration_update in_magn_calibration_update"
MSG='firmware RAM 0x0e01 is not known to report calibration status and score'
MOD=$SENTRAL_MODROOT

DEV=$(em7180_dir)
ok "em7180 present" test -n "$DEV"
CLIENT=$(basename "$(readlink -f "$DEV/..")")
DRV=/sys/bus/i2c/drivers/em7180

# cal_attrs: how many of the five calibration attributes $DEV has
cal_attrs() {
	local a n=0
	for a in $CAL; do
		[ -e "$DEV/$a" ] && n=$((n + 1))
	done
	echo $n
}

rebind() {
	echo "$CLIENT" >"$DRV/unbind" && echo "$CLIENT" >"$DRV/bind" &&
		DEV=$(em7180_dir)
}

is "RAM 0x0d17, named by the client's property: all five calibration attributes" \
	"$(cal_attrs)" 5
is "nothing logged about the firmware" "$(dmesg | grep -c 'not known to report')" 0

knob ram_version 0x0e01
ok "RAM 0x0e01: bind again" rebind
is "ram_version reads 0x0e01" "$(cat "$DEV/ram_version")" 0x0e01
is "none of the five calibration attributes" "$(cal_attrs)" 0
is "said once at probe" "$(dmesg | grep -c "$MSG")" 1
like "and how to add it" "$(dmesg | grep "$MSG")" \
	'add it to emmicro,calibration-firmware or em7180_core.calibration_firmware'
for a in product_id revision_id rom_version ram_version calibration_data \
	in_accel_x_calibbias; do
	ok "$a still there" test -e "$DEV/$a"
done

# A capture: 40-byte scans of every channel
ok "buffered capture: iio_readdev -b 16 -s 50" \
	sh -c "iio_readdev -b 16 -s 50 em7180 >$TMP/cap.bin"
is "50 scans of 40 bytes" "$(stat -c %s "$TMP/cap.bin")" 2000

# calibration_data both ways, and no read of 0x44 on the way: a gyro bias
# update latched before the transfer stays unread (the old driver's
# transfer took the flags in with its acknowledge read)
knob gbias_period_ms 50
sleep 0.2
before=$(dbg_get cal_updates gbias_read)
ok "calibration_data read" dd if="$DEV/calibration_data" of="$TMP/a.bin" \
	bs=140 count=1 status=none
is "140 bytes" "$(stat -c %s "$TMP/a.bin")" 140
ok "calibration_data write" dd if="$TMP/a.bin" of="$DEV/calibration_data" \
	bs=140 status=none
is "the chip holds them" "$(sim_ws_params)" "$(blob_words <"$TMP/a.bin")"
is "0x44 not read by the transfers" "$(dbg_get cal_updates gbias_read)" "$before"
knob gbias_period_ms 2000
ok "calibbias write" sh -c "echo -47 >$DEV/in_accel_x_calibbias"
is "calibbias read" "$(cat "$DEV/in_accel_x_calibbias")" -47

ok "bind again" rebind
is "said once per binding: twice now" "$(dmesg | grep -c "$MSG")" 2

# sentral-warmstart on that firmware
out=$(sentral-warmstart status 2>&1)
is "status exits 0" $? 0
like "status: not reported by this firmware" "$out" \
	'calibration status: +not reported by this firmware \(RAM 0x0e01\)'
json=$(sentral-warmstart status --json)
like "status --json: null status and score" "$json" \
	'"calibration_status":null,"calibration_score":null,"calibration_score_raw":null,"mag_transient":null,"gyro_bias_update":null,"mag_calibration_update":null,'
out=$(sentral-warmstart save 2>&1)
is "save without --force refuses: exit 78" $? 78
like "and says why" "$out" 'does not report the calibration status'
out=$(timeout 20 sentral-warmstart watch --poll 1 2>&1)
is "watch exits 78 at once" $? 78
like "and says why" "$out" 'does not report the calibration status'
out=$(sentral-warmstart save --force 2>&1)
is "save --force saves: exit 0" $? 0
key=$(sentral-warmstart key)
ok "the file is written" test -f "$STATE/$key.ws"
knob stats 0
out=$(timeout 10 sentral-warmstart restore 2>&1)
is "restore exits 0" $? 0
like "without waiting for a status" "$out" 'restored .* does not report'
ok "restore wrote the blob" [ "$(dbg_get stats params_served)" -ge 35 ]

# The module parameter adds 0x0e01 to the table
ok "unload em7180_i2c and em7180_core" modprobe -d "$MOD" -r em7180_i2c em7180_core

# A value that is no 16-bit RAM version, or more than 8 of them: the module
# does not load with part of the list, and the log names the parameter
for bad in 0x0e01,zz 0x10000 1,2,3,4,5,6,7,8,9; do
	nok "calibration_firmware=$bad: the module does not load" \
		modprobe -d "$MOD" em7180_core "calibration_firmware=$bad"
	nok "  and is not there" test -d /sys/module/em7180_core
	like "  the log names the parameter" "$(dmesg | tail -3)" \
		"invalid for parameter .calibration_firmware"
done
ok "load em7180_core calibration_firmware=0x0e01,0x1234" \
	modprobe -d "$MOD" em7180_core calibration_firmware=0x0e01,0x1234
ok "load em7180_i2c" modprobe -d "$MOD" em7180_i2c
ok "bound" wait_for 5 em7180_dir
DEV=$(em7180_dir)
is "the parameter reads back" \
	"$(cat /sys/module/em7180_core/parameters/calibration_firmware)" "3585,4660"
is "the five calibration attributes are back" "$(cal_attrs)" 5
is "nothing more logged" "$(dmesg | grep -c "$MSG")" 2
is "in_magn_calibration_auto_status reads" \
	"$(cat "$DEV/in_magn_calibration_auto_status")" 0

# The firmware changes under a bound driver (a reset reloads another): the
# attributes stay, read ENODATA, and that is said once
knob ram_version 0x0f02
knob chip_reset 1
ok "recovered with RAM 0x0f02" wait_for 5 \
	sh -c "[ \"\$(cat $DEV/ram_version)\" = 0x0f02 ]"
nok "in_magn_calibration_score: no data" cat "$DEV/in_magn_calibration_score"
like "ENODATA" "$(cat "$DEV/in_magn_calibration_score" 2>&1)" 'No data available'
nok "in_magn_calibration_auto_status: no data" cat "$DEV/in_magn_calibration_auto_status"
is "the change is logged once" \
	"$(dmesg | grep -c 'firmware RAM 0x0f02 is not known to report')" 1
out=$(sentral-warmstart status 2>&1)
like "status: not reported (RAM 0x0f02)" "$out" \
	'calibration status: +not reported by this firmware \(RAM 0x0f02\)'
knob ram_version 0x0e01
knob chip_reset 1
ok "recovered with RAM 0x0e01" wait_for 5 \
	sh -c "[ \"\$(cat $DEV/ram_version)\" = 0x0e01 ]"
ok "the attributes read again" cat "$DEV/in_magn_calibration_score"

# Back as tests/uml/run left it
knob ram_version 0x0d17
modprobe -d "$MOD" -r em7180_i2c em7180_core
ok "reload em7180_i2c" modprobe -d "$MOD" em7180_i2c
ok "bound" wait_for 5 em7180_dir
rm -rf "$TMP"
done_testing
