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

# 140 bytes on stdin as 35 little-endian words, "0x%08x ..." (the host and
# UML are little-endian, so od's native order is the chip's).
blob_words() {
	od -An -v -tx4 -w4 | awk '{ printf "0x%s ", $1 }'
}
