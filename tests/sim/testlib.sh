# SPDX-License-Identifier: GPL-2.0-only
# Helpers for the simulator's own end-to-end tests (tests/e2e/sim-*.sh).
# Source after tests/lib/tap.sh, inside tests/uml/run.

. "$SENTRAL_ROOT/tests/lib/em7180.sh"

SIM_KO=$SENTRAL_MODDIR/drivers/misc/sentral-sim/sentral_sim.ko
SIM_ADDR=0x28

# Load the simulator alone (the test boots with --no-modules so that no
# driver binds to the client and changes the chip behind the test's back).
sim_load() {
	insmod "$SIM_KO" "$@" || return 1
	SIM_BUS=$(sim_bus) || return 1
	sim_wait_upload
}

sim_unload() {
	rmmod sentral_sim
}

# Wait until the simulated EEPROM upload is done (SentralStatus bit 1).
sim_wait_upload() {
	local i
	for i in $(seq 100); do
		grep -qx 'uploading 0' "$SIM_DBG/state" && return 0
		sleep 0.01
	done
	return 1
}

# i2ctransfer on the simulator; prints the bytes read, space-separated.
sim_xfer() {
	i2ctransfer -f -y "$SIM_BUS" "$@"
}

# Read N (default 1) registers from REG in one transaction.
sim_rd() {
	sim_xfer w1@$SIM_ADDR "$1" r"${2:-1}"
}

# Write bytes from REG in one transaction.
sim_wr() {
	local reg=$1
	shift
	sim_xfer w$(($# + 1))@$SIM_ADDR "$reg" "$@"
}

param_get() {
	dbg_get params "$1"
}

# 32-bit value as four little-endian bytes "0x.. 0x.. 0x.. 0x..".
le32_bytes() {
	local v=$(($1))
	printf '0x%02x 0x%02x 0x%02x 0x%02x' $((v & 255)) $((v >> 8 & 255)) \
		$((v >> 16 & 255)) $((v >> 24 & 255))
}

# Four bytes "0x.. 0x.. 0x.. 0x.." (little-endian) as 0xXXXXXXXX.
bytes_le32() {
	printf '0x%02x%02x%02x%02x' $(($4)) $(($3)) $(($2)) $(($1))
}

# Poll ParamAcknowledge with 0x3A..0x3E bursts until it equals WANT or
# TIMEOUT_MS passes; prints the five bytes of the last poll.
sim_poll_ack() {
	local want=$(($1)) timeout_ms=${2:-1000} out end
	end=$(($(date +%s%N) / 1000000 + timeout_ms))
	while :; do
		out=$(sim_rd 0x3a 5) || return 1
		set -- $out
		if [ $(($1)) -eq "$want" ]; then
			echo "$out"
			return 0
		fi
		if [ $(($(date +%s%N) / 1000000)) -ge $end ]; then
			echo "$out"
			return 1
		fi
	done
}

# Poll ParamAcknowledge alone (one register per transaction, as the
# reference hosts do) until it equals WANT or TIMEOUT_MS passes.
sim_poll_ack1() {
	local want=$(($1)) end=$(($(date +%s%N) / 1000000 + ${2:-1000}))
	while [ $(($(sim_rd 0x3a))) -ne "$want" ]; do
		[ $(($(date +%s%N) / 1000000)) -ge $end ] && return 1
		sleep 0.005
	done
}

# The documented parameter protocol (EM7180 register reference §2):
# AlgorithmControl bit 7 set, per parameter one burst, ack polled on 0x3A,
# end with ParamRequest = 0 and bit 7 clear.
param_begin() {
	sim_wr 0x54 0x80
}

param_end() {
	sim_wr 0x64 0x00 && sim_wr 0x54 0x00
}

# Read parameter N inside a transfer; prints its value as 0xXXXXXXXX.
param_read() {
	local out
	sim_wr 0x64 "$1" || return 1
	out=$(sim_poll_ack "$1") || return 1
	set -- $out
	bytes_le32 "$2" "$3" "$4" "$5"
}

# Write parameter N = VALUE inside a transfer: one 5-byte burst 0x60..0x64.
param_write() {
	local req=$(($1 | 0x80))
	sim_wr 0x60 $(le32_bytes "$2") "$req" || return 1
	sim_poll_ack "$req" >/dev/null
}

# Signed 16-bit little-endian value from two bytes.
s16() {
	local v=$(($1 | $2 << 8))
	[ $v -ge 32768 ] && v=$((v - 65536))
	echo $v
}
