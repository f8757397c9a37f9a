#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# A chip whose register pointer stops at ParamAcknowledge (0x3A) and
# LoadParamByte3 (0x63) within one transfer (simulator knob autoinc_stop;
# no reference host crosses them, so silicon may not): probe finds it out
# and says so once; calibration_data reads return what the chip holds, not
# the acknowledge byte repeated; a write reaches the chip; both go one
# register per transaction, with no burst waited for.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"

TMP=$(mktemp -d)
knob gbias_period_ms 3600000
knob motion 0
DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
said() { dmesg | grep -c 'register pointer stops at 0x63'; }
# Under the knob matrix's autoinc_stop=1 the chip stopped from the boot on
if [ "$(cat "$SIM_DBG/autoinc_stop")" = 0 ]; then
	is "a chip whose pointer crosses: nothing said" "$(said)" 0
else
	is "a chip whose pointer stops from power-on: probe said so once" "$(said)" 1
fi
said0=$(said)

# rebind: the chip as it would be met at boot, the knob set before probe
CLIENT=$(basename "$(readlink -f "$DEV/..")")
rebind() {
	echo "$CLIENT" >/sys/bus/i2c/drivers/em7180/unbind
	echo "$CLIENT" >/sys/bus/i2c/drivers/em7180/bind
	DEV=$(em7180_dir)
}
knob autoinc_stop 1
rebind
ok "bound with the pointer stopping" test -n "$DEV"
is "probe says so once" "$(said)" $((said0 + 1))

ok "calibration_data read" dd if="$DEV/calibration_data" of="$TMP/a.bin" \
	bs=148 count=1 status=none
is "the read returns the chip's parameters" \
	"$(blob_words <"$TMP/a.bin")" "$(sim_ws_params)"

# The same blob with parameter 33 (a gyro bias) set to 0.1f
{
	head -c 136 "$TMP/a.bin"
	printf '\xcd\xcc\xcc\x3d'
	tail -c 8 "$TMP/a.bin"
} >"$TMP/b.bin"
knob stats 0
ok "calibration_data write" dd if="$TMP/b.bin" of="$DEV/calibration_data" \
	bs=148 status=none
is "the chip holds the written parameters" \
	"$(sim_ws_params)" "$(blob_words <"$TMP/b.bin")"
# A burst never acknowledged would have polled for 1 s
t=$(dbg_get stats transactions)
ok "no burst waited for on the way ($t transactions)" [ "$t" -le $((3 * 35 + 6)) ]

knob stats 0
ok "calibration_data read again" dd if="$DEV/calibration_data" \
	of="$TMP/c.bin" bs=148 count=1 status=none
is "it returns what was written" "$(blob_words <"$TMP/c.bin")" \
	"$(blob_words <"$TMP/b.bin")"
# Request, acknowledge, value per parameter; the echo (and, where the
# firmware keeps the application note's score, its registers) and bit 7 to
# start; ParamRequest and bit 7 to end
note=0
[ -e "$DEV/in_magn_calibration_score" ] && note=1
# An early poll, while the acknowledge wait is learned again after the
# bind (the chip's latency jitters), is one more transaction: the
# simulator counts them apart.
polls() { echo $(($(dbg_get stats transactions) - $(dbg_get stats ack_polls_early))); }
is "one register per transaction: 3 per parameter + $((4 + note)), early polls aside" \
	"$(polls)" $((3 * 35 + 4 + note))

# A chip that crosses again, at the next binding
knob autoinc_stop 0
rebind
ok "bound again" test -n "$DEV"
is "nothing more said" "$(said)" $((said0 + 1))
ok "calibration_data read" dd if="$DEV/calibration_data" of="$TMP/d.bin" \
	bs=148 count=1 status=none
is "it returns what was written" "$(blob_words <"$TMP/d.bin")" \
	"$(blob_words <"$TMP/b.bin")"
# Once the acknowledge wait is learned again: value and request in one
# write, acknowledge and value in one read
knob stats 0
ok "calibration_data read again" dd if="$DEV/calibration_data" \
	of="$TMP/d.bin" bs=148 count=1 status=none
is "two transactions per parameter + 4, early polls aside" "$(polls)" $((2 * 35 + 4))
done_testing
