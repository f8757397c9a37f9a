# SPDX-License-Identifier: GPL-2.0-only
# shellcheck shell=bash
#
# Helpers shared by the end-to-end scripts (tests/e2e/*.sh) that run inside
# tests/uml/run: the simulator's debugfs knobs, the em7180 device, blobs.

SIM_DBG=/sys/kernel/debug/sentral-sim

# knob NAME VALUE: set a simulator knob.
knob() {
	echo "$2" >"$SIM_DBG/$1"
}

# dbg_get FILE KEY: the value of KEY in a debugfs file of "key value" lines.
dbg_get() {
	awk -v k="$2" '$1 == k { print $2 }' "$SIM_DBG/$1"
}

# read_state: the simulator's state file into ST_transfer and ST_running,
# with shell builtins only: UML forks slowly (tens of ms, more on 6.1 and
# KASAN kernels), and sweeps check the chip once per step.
read_state() {
	local k v
	while read -r k v; do
		case $k in
		transfer) ST_transfer=$v ;;
		running) ST_running=$v ;;
		esac
	done <"$SIM_DBG/state"
}

# chip_idle: no parameter transfer open, and the algorithm running.
chip_idle() {
	read_state
	[ "$ST_transfer" = 0 ] && [ "$ST_running" = 1 ]
}

# in_transfer: a parameter transfer open (AlgorithmControl bit 7).
in_transfer() {
	read_state
	[ "$ST_transfer" = 1 ]
}

# wait_for SECONDS COMMAND...: poll until COMMAND succeeds or time is up.
wait_for() {
	local end=$(($(date +%s%N) / 1000000 + $1 * 1000))
	shift
	until "$@"; do
		[ $(($(date +%s%N) / 1000000)) -ge $end ] && return 1
		sleep 0.05
	done
}

# The em7180 IIO device directory.
em7180_dir() {
	local d
	for d in /sys/bus/iio/devices/iio:device*; do
		[ "$(cat "$d/name" 2>/dev/null)" = em7180 ] || continue
		echo "$d"
		return 0
	done
	return 1
}

# The driver's debugfs firmware_version of the device in DEV: "ProductID
# 0x80 RevisionID 0x02 ROM 0x09e6 RAM 0x0d17 eeprom".
driver_fw_version() {
	cat "/sys/kernel/debug/iio/${DEV##*/}/firmware_version"
}

# The RAM version the driver holds, "0x0d17".
driver_ram_version() {
	driver_fw_version | awk '{ print $8 }'
}

# ram_is VERSION: the driver holds that RAM version.
ram_is() {
	[ "$(driver_ram_version)" = "$1" ]
}

# The I2C bus number of the simulator's adapter.
sim_bus() {
	local d
	for d in /sys/bus/i2c/devices/i2c-*; do
		[ "$(cat "$d/name" 2>/dev/null)" = sentral-sim ] || continue
		echo "${d##*/i2c-}"
		return 0
	done
	return 1
}

# The 35 warm-start parameters the simulated chip holds, "0x%08x ...".
sim_ws_params() {
	awk '$1 >= 1 && $1 <= 35 { printf "%s ", $2 }' "$SIM_DBG/params"
}

# calibration_data: an 8-byte identity header, then the 140-byte payload
CALDATA_SIZE=148

# A payload (140 bytes) or a calibration_data blob (148, its header left
# out) on stdin as 35 little-endian words, "0x%08x ..." (the host and UML
# are little-endian, so od's native order is the chip's).
blob_words() {
	local t
	t=$(mktemp)
	cat >"$t"
	if [ "$(stat -c %s "$t")" = "$CALDATA_SIZE" ]; then
		tail -c +9 "$t"
	else
		cat "$t"
	fi | od -An -v -tx4 -w4 | awk '{ printf "0x%s ", $1 }'
	rm -f "$t"
}

# The header calibration_data has on the simulated chip: format 1,
# ProductID, RevisionID, 0, ROM and RAM versions little-endian, as hex
# bytes "01 80 02 00 e6 09 17 0d".
sim_caldata_header() {
	local pid rev rom ram
	pid=$(cat "$SIM_DBG/product_id") rev=$(cat "$SIM_DBG/revision_id")
	rom=$(cat "$SIM_DBG/rom_version") ram=$(cat "$SIM_DBG/ram_version")
	printf '01 %02x %02x 00 %02x %02x %02x %02x' "$pid" "$rev" \
		$((rom & 0xff)) $((rom >> 8)) $((ram & 0xff)) $((ram >> 8))
}

# caldata_payloads FILE: the payloads of a file of whole calibration_data
# blobs (several saves appended), concatenated.
caldata_payloads() {
	local i n
	n=$(($(stat -c %s "$1") / CALDATA_SIZE))
	for ((i = 0; i < n; i++)); do
		dd if="$1" iflag=skip_bytes skip=$((i * CALDATA_SIZE + 8)) bs=140 \
			count=1 status=none
	done
}

# caldata_header <FILE: a blob's header, as sim_caldata_header prints it.
caldata_header() {
	head -c 8 | od -An -v -tx1 | xargs
}

# with_header HEX <PAYLOAD >BLOB: a payload behind the header HEX (as
# sim_caldata_header prints it), the blob calibration_data takes.
with_header() {
	local b
	for b in $1; do
		printf "\\x$b"
	done
	cat
}
