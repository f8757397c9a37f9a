# SPDX-License-Identifier: GPL-2.0-only
# Helpers for the sentral-warmstart end-to-end tests (tests/e2e/tool-*.sh,
# tests/e2e/boot-*.sh), sourced inside tests/uml/run after tests/lib/tap.sh.

. "$SENTRAL_ROOT/tests/lib/em7180.sh"

SIM_KO=$SENTRAL_MODDIR/drivers/misc/sentral-sim/sentral_sim.ko
STATE=/var/lib/sentral-warmstart
# Table 1 of the seed app note: -47, -15, +46 LSB as float g.
TABLE1="0xbcbbe447 0xbbefdc9c 0x3cb7e4de"

sim_ready() {
	grep -qx 'uploading 0' "$SIM_DBG/state"
}

sim_param() {
	dbg_get params "$1"
}

file_payload_words() {
	dd if="$1" bs=1 skip=32 count=140 status=none | blob_words
}

# Words FIRST..LAST (1-based) of a word list.
words() {
	echo "$3" | awk -v a="$1" -v b="$2" '{ for (i = a; i <= b; i++) printf "%s ", $i }'
}

# Flip one bit of FILE at OFFSET, in place.
flip_byte() {
	local b
	b=$(od -An -tu1 -j "$2" -N1 "$1" | tr -d ' ')
	printf "$(printf '\\%03o' $((b ^ 0x10)))" |
		dd of="$1" bs=1 seek="$2" count=1 conv=notrunc status=none
}

# "key" from status --json.
json_field() {
	sed -n "s/.*\"$1\":\"\\([^\"]*\\)\".*/\\1/p"
}

# The calibration level, in_magn_calibration_auto_status (4: stable).
cal_level() {
	cat "$(em7180_dir)/in_magn_calibration_auto_status"
}

# Stable (level 4) and, where the firmware has a score, 3% or better: the
# em7180 device DIR (default: the only one).
calibrated_good() {
	local d=${1:-}
	[ -n "$d" ] || d=$(em7180_dir) || return 1
	[ "$(cat "$d/in_magn_calibration_auto_status")" = 4 ] || return 1
	[ ! -e "$d/in_magn_calibration_score" ] ||
		awk '{ exit !($1 <= 3.0) }' "$d/in_magn_calibration_score"
}

# Simulated figure-8 motion until calibrated, then still again.
calibrate_by_motion() {
	local rc
	knob cal_duration_ms 1000
	knob motion 1
	wait_for 30 calibrated_good
	rc=$?
	knob motion 0
	return $rc
}

# Unbind the driver, power-cycle the chip (RAM state lost, as at power-off)
# and bind again: a reboot as far as the chip and the driver can tell.
replug() {
	local client=$1
	echo "$client" >/sys/bus/i2c/drivers/em7180/unbind || return 1
	knob power_cycle 1 || return 1
	wait_for 5 sim_ready || return 1
	echo "$client" >/sys/bus/i2c/drivers/em7180/bind || return 1
	wait_for 5 em7180_dir >/dev/null
}

# Start the chip by hand the way a host does (rates, scaled NED output out
# of standby, then run), for tests with no driver bound: a driver that is
# unbound leaves the chip stopped.
chip_run() {
	local bus=$1
	i2ctransfer -f -y "$bus" w4@0x28 0x55 0x1e 0x0a 0x0a &&
		i2ctransfer -f -y "$bus" w2@0x28 0x54 0x00 &&
		i2ctransfer -f -y "$bus" w2@0x28 0x34 0x01
}

# The firmware with (1) or without (0, a USFS board's) the application
# note's calibration registers, as the driver finds it when it binds to
# the I2C client CLIENT: unbind, set the simulator's knob, bind.
set_layout() {
	local client=$2
	echo "$client" >/sys/bus/i2c/drivers/em7180/unbind || return 1
	knob appnote_layout "$1" || return 1
	echo "$client" >/sys/bus/i2c/drivers/em7180/bind || return 1
	wait_for 5 em7180_dir >/dev/null
}

# The header of saved file FILE: "VERSION LEVEL JUDGEMENT RAW-SCORE"
# (bytes 8-9, 16, 17 and 18-19: sentral-warmstart.8, FILE FORMAT).
ws_header() {
	python3 -c 'import struct, sys
print(*struct.unpack_from("<H6xBBH", open(sys.argv[1], "rb").read(), 8))' "$1"
}

# ws_edit SRC DST OFFSET:FORMAT:VALUE...: a copy of saved file SRC at DST
# with the field at each OFFSET (a struct format: <B, <H, <f...) set to
# VALUE, or changed by it with +=VALUE, and the CRC fixed: what anyone who
# may write the file can do. Parameter N is at offset 32 + 4 * (N - 1).
ws_edit() {
	python3 -c 'import struct, sys, zlib
b = bytearray(open(sys.argv[1], "rb").read())
for field in sys.argv[3:]:
    off, fmt, val = field.split(":")
    rel = val.startswith("+=")
    val = val[2:] if rel else val
    v = float(val) if fmt[-1] in "fd" else int(val, 0)
    if rel:
        v += struct.unpack_from(fmt, b, int(off))[0]
    struct.pack_into(fmt, b, int(off), v)
b[172:176] = struct.pack("<I", zlib.crc32(bytes(b[:172])))
open(sys.argv[2], "wb").write(b)' "$@"
}

# ws_v1 SRC DST: saved file SRC as version 1 of the format has it (before
# the level): calibration status 3 (complete), byte 17 0 and a score, here
# 2.700 % (raw 33653, the simulated chip's at its true coefficients).
ws_v1() {
	ws_edit "$1" "$2" '8:<H:1' '16:<B:3' '17:<B:0' '18:<H:33653'
}
