#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# The em7180 IIO driver on the simulated chip: probe, every attribute read
# with cat, calibbias and sampling_frequency written with echo, a calibration_data
# round trip with dd, refusals before any bus traffic, and the bus cost of a
# 35-parameter save and restore measured with the simulator's stats.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"
# param_begin, param_end, sim_wr: a parameter transfer over i2c-dev
. "$SENTRAL_ROOT/tests/sim/testlib.sh"

TABLE1="0xbcbbe447 0xbbefdc9c 0x3cb7e4de"
TMP=$(mktemp -d)

# Replace 32-bit word N (1-based) of blob FILE by the bytes of VALUE.
set_word() {
	local v=$(($3))
	printf "$(printf '\\%03o\\%03o\\%03o\\%03o' $((v & 255)) $((v >> 8 & 255)) \
		$((v >> 16 & 255)) $((v >> 24 & 255)))" |
		dd of="$1" bs=1 seek=$((8 + 4 * ($2 - 1))) count=4 conv=notrunc status=none
}

DEV=$(em7180_dir)
ok "probe: an IIO device named em7180" test -n "$DEV"
like "bound to the I2C client at 0x28" "$(readlink -f "$DEV/..")" '/[0-9]+-0028$'
ok "algorithm running, not in transfer mode" chip_idle
N=${DEV##*iio:device}

trig=
for t in /sys/bus/iio/devices/trigger*; do
	[ "$(cat "$t/name")" = "em7180-dev$N" ] && trig=$t
done
ok "data-ready trigger em7180-dev$N registered" test -n "$trig"
is "and it is the default trigger" "$(cat "$DEV/trigger/current_trigger")" "em7180-dev$N"

# cat of every attribute
n=0
for f in "$DEV"/* "$DEV"/scan_elements/* "$DEV"/buffer/*; do
	[ -f "$f" ] && [ -r "$f" ] || continue
	ok "cat ${f#"$DEV"/}" sh -c 'cat "$1" >/dev/null' sh "$f"
	n=$((n + 1))
done
ok "read $n attributes" [ "$n" -ge 40 ]
is "calibration_data mode 0600" "$(stat -c %a "$DEV/calibration_data")" 600

is "in_magn_calibration_auto_status at power-on: 2, calibrating" \
	"$(cat "$DEV/in_magn_calibration_auto_status")" 2
knob algo_status_or 0x20
is "within 0.5 s of the last read: the same read's" \
	"$(cat "$DEV/in_magn_calibration_auto_status")" 2
# The calibration attributes share one read of the chip for 0.5 s
sleep 0.6
is "unreliable sensor data (AlgorithmStatus bit 5): 1" \
	"$(cat "$DEV/in_magn_calibration_auto_status")" 1
knob algo_status_or 0
# A USFS board's firmware keeps no score: the simulator's default; the
# application note's layout has one (the knob matrix of tests/run-suites).
if [ "$(cat "$SIM_DBG/appnote_layout")" = 1 ]; then
	ok "in_magn_calibration_score on the application note's firmware" \
		test -e "$DEV/in_magn_calibration_score"
else
	nok "no in_magn_calibration_score on this firmware" test -e "$DEV/in_magn_calibration_score"
fi

# The identity a saved warm start is checked against, read at probe: in
# debugfs and the probe's log line, as bno055's firmware_version, and in
# calibration_data's header (below); no attribute without a mainline
# precedent.
id="ProductID 0x80 RevisionID 0x02 ROM 0x09e6 RAM $(cat "$SIM_DBG/ram_version") eeprom"
t=$(dbg_get stats transactions)
is "debugfs firmware_version: the chip, its firmware and where it came from" \
	"$(cat "/sys/kernel/debug/iio/iio:device$N/firmware_version")" "$id"
is "... read without a bus transaction" "$(dbg_get stats transactions)" "$t"
is "... mode 0400" "$(stat -c %a "/sys/kernel/debug/iio/iio:device$N/firmware_version")" 400
like "the probe's log line says the same" "$(dmesg)" "em7180 [0-9]+-0028: firmware $id"
for a in product_id revision_id rom_version ram_version firmware_source; do
	nok "no attribute $a" test -e "$DEV/$a"
done

# debugfs register access (IIO's direct_reg_access), for debugging real chips
REG=/sys/kernel/debug/iio/iio:device$N/direct_reg_access
knob product_id 0x81
echo 0x90 >"$REG"
is "direct_reg_access reads ProductID from the chip" "$(cat "$REG")" 0x81
knob product_id 0x80
rate=$(cat "$DEV/in_magn_sampling_frequency")
echo "0x55 0x1e" >"$REG"
is "direct_reg_access writes MagRate to the chip" \
	"$(awk '$1 == "50:" { print $7 }' "$SIM_DBG/regs")" 1e
is "... which runs the magnetometer at 30 Hz" "$(cat "$DEV/in_magn_sampling_frequency")" 30
echo "$rate" >"$DEV/in_magn_sampling_frequency"
echo 0x35 >"$REG"
nok "direct_reg_access refuses EventStatus, which a read clears" cat "$REG"

is "accel raw = gravity + Table 1 bias" \
	"$(cat "$DEV"/in_accel_{x,y,z}_raw | tr '\n' ' ')" "-47 -15 2094 "
is "in_accel_scale (0.000488 g in m/s^2)" "$(cat "$DEV/in_accel_scale")" 0.004785645
is "in_anglvel_scale (0.1526 dps in rad/s)" "$(cat "$DEV/in_anglvel_scale")" 0.002663372
is "in_magn_scale (0.0305176 uT in gauss)" "$(cat "$DEV/in_magn_scale")" 0.000305176
is "in_rot_quaternion_raw: identity, x y z w" "$(cat "$DEV/in_rot_quaternion_raw")" "0 0 0 16384 "
is "in_rot_quaternion_scale 2^-14" "$(cat "$DEV/in_rot_quaternion_scale")" 0.000061035
like "magn raw" "$(cat "$DEV"/in_magn_{x,y,z}_raw | tr '\n' ' ')" '^-?[0-9]+ -?[0-9]+ -?[0-9]+ $'
like "gyro raw" "$(cat "$DEV/in_anglvel_x_raw")" '^-?[0-9]+$'
is "mount matrix (identity)" "$(cat "$DEV/in_accel_mount_matrix")" "1, 0, 0; 0, 1, 0; 0, 0, 1"

# sampling_frequency
is "accel rate 100 Hz" "$(cat "$DEV/in_accel_sampling_frequency")" 100
is "gyro rate 100 Hz" "$(cat "$DEV/in_anglvel_sampling_frequency")" 100
is "magn rate 30 Hz" "$(cat "$DEV/in_magn_sampling_frequency")" 30
is "accel/gyro rates available" "$(cat "$DEV/in_accel_sampling_frequency_available")" \
	"10 20 50 100 200 500 1000"
is "magn rates available" "$(cat "$DEV/in_magn_sampling_frequency_available")" "1 10 20 30 50 100"
ok "echo 200 > in_accel_sampling_frequency" sh -c "echo 200 > $DEV/in_accel_sampling_frequency"
is "accel actual rate 200" "$(cat "$DEV/in_accel_sampling_frequency")" 200
ok "echo 1000 > in_anglvel_sampling_frequency" sh -c "echo 1000 > $DEV/in_anglvel_sampling_frequency"
is "gyro actual rate 1000" "$(cat "$DEV/in_anglvel_sampling_frequency")" 1000
ok "echo 50 > in_magn_sampling_frequency" sh -c "echo 50 > $DEV/in_magn_sampling_frequency"
is "magn actual rate 50" "$(cat "$DEV/in_magn_sampling_frequency")" 50
nok "accel 5 Hz refused" sh -c "echo 5 > $DEV/in_accel_sampling_frequency"
nok "accel 2000 Hz refused" sh -c "echo 2000 > $DEV/in_accel_sampling_frequency"
nok "magn 0 Hz refused" sh -c "echo 0 > $DEV/in_magn_sampling_frequency"
nok "fractional rate refused" sh -c "echo 100.5 > $DEV/in_accel_sampling_frequency"
# Only the advertised rates: a value between two of them is refused, not
# rounded, and nothing reaches the chip.
knob stats 0
for w in accel:15 accel:150 anglvel:999 anglvel:11 magn:25 magn:2; do
	nok "${w%%:*} ${w#*:} Hz (not advertised) refused" \
		sh -c "echo ${w#*:} > $DEV/in_${w%%:*}_sampling_frequency"
done
is "refused rates: no bus transaction" "$(dbg_get stats transactions)" 0
is "rates unchanged by the refusals" \
	"$(cat "$DEV"/in_{accel,anglvel,magn}_sampling_frequency | tr '\n' ' ')" "200 1000 50 "
for t in accel anglvel magn; do
	bad=
	for r in $(cat "$DEV/in_${t}_sampling_frequency_available"); do
		echo "$r" >"$DEV/in_${t}_sampling_frequency" &&
			[ "$(cat "$DEV/in_${t}_sampling_frequency")" = "$r" ] || bad+=" $r"
	done
	is "every advertised $t rate accepted and in effect" "$bad" ""
done
for t in accel anglvel; do echo 100 >"$DEV/in_${t}_sampling_frequency"; done
echo 30 >"$DEV/in_magn_sampling_frequency"
is "rates back to the defaults" "$(cat "$DEV"/in_{accel,anglvel,magn}_sampling_frequency | tr '\n' ' ')" \
	"100 100 30 "

# calibbias: LSB <-> float g in parameters 27..29, Table 1 bit for bit
is "calibbias 0 at power-on" "$(cat "$DEV"/in_accel_{x,y,z}_calibbias | tr '\n' ' ')" "0 0 0 "
ok "echo -47 > in_accel_x_calibbias" sh -c "echo -47 > $DEV/in_accel_x_calibbias"
ok "echo -15 > in_accel_y_calibbias" sh -c "echo -15 > $DEV/in_accel_y_calibbias"
ok "echo 46 > in_accel_z_calibbias" sh -c "echo 46 > $DEV/in_accel_z_calibbias"
is "calibbias reads back" "$(cat "$DEV"/in_accel_{x,y,z}_calibbias | tr '\n' ' ')" "-47 -15 46 "
is "parameters 27..29 are Table 1" \
	"$(dbg_get params 27) $(dbg_get params 28) $(dbg_get params 29)" "$TABLE1"
is "accel output now 0 0 2048" "$(cat "$DEV"/in_accel_{x,y,z}_raw | tr '\n' ' ')" "0 0 2048 "
# Transactions per parameter: request and acknowledge, and one more where
# the register pointer stops at 0x3A and 0x63 (knob autoinc_stop, under
# which make check-long runs this suite): the value, or LoadParam apart.
# The start reads the echo and the calibration registers (one more read
# then) and sets bit 7; ParamRequest = 0 and bit 7 clear end.
single=$(cat "$SIM_DBG/autoinc_stop")
xfer_max() {
	echo $(((2 + single) * $1 + 4 + single + 1))
}
# One verified parameter write, measured; one more when the learned
# acknowledge wait was shortened and the poll came early; and where the
# firmware keeps its last echo past the end of a transfer (knob ack_end),
# the read of another parameter (a request and its poll) that changes the
# echo of this same parameter's write just before.
[ "$(cat "$SIM_DBG/ack_end")" = 0 ] && stale=0 || stale=2
knob stats 0
ok "echo 46 > in_accel_z_calibbias again" sh -c "echo 46 > $DEV/in_accel_z_calibbias"
t=$(dbg_get stats transactions)
echo "# one calibbias write: $t transactions, bus_time_us $(dbg_get stats bus_time_us)"
ok "one parameter write: at most $(($(xfer_max 1) + stale)) transactions ($t)" \
	[ "$t" -le $(($(xfer_max 1) + stale)) ]

# Firmware that keeps its last acknowledge when a transfer ends (ack_end 2)
# or serves the stop only after its latency (1): the acknowledge of the
# first request of the next transfer must not be taken from the last one.
for mode in 1 2; do
	knob ack_end $mode
	knob ack_latency_us 20000
	echo -47 >"$DEV/in_accel_x_calibbias"
	echo 46 >"$DEV/in_accel_x_calibbias"
	is "ack_end $mode: the same parameter written twice holds the second value" \
		"$(dbg_get params 27)" 0x3cb7e4de
	echo -47 >"$DEV/in_accel_x_calibbias"
	is "ack_end $mode: and again the first" "$(dbg_get params 27)" 0xbcbbe447
	ok "ack_end $mode: chip left running" chip_idle
done
knob ack_end 0
knob ack_latency_us 500
nok "calibbias 40000 refused" sh -c "echo 40000 > $DEV/in_accel_x_calibbias"
nok "calibbias 1.5 refused" sh -c "echo 1.5 > $DEV/in_accel_x_calibbias"
nok "calibbias garbage refused" sh -c "echo abc > $DEV/in_accel_x_calibbias"
ok "chip left running after calibbias" chip_idle

# calibration_data: save with dd, measured
knob stats 0
ok "dd calibration_data out (save)" dd if="$DEV/calibration_data" of="$TMP/a" bs=4096 status=none
is "save: 148 bytes" "$(stat -c %s "$TMP/a")" 148
is "its header: format 1, the chip's identity" "$(caldata_header <"$TMP/a")" "$(sim_caldata_header)"
save_t=$(dbg_get stats transactions)
save_bus=$(dbg_get stats bus_time_us)
save_el=$(dbg_get stats elapsed_us)
echo "# save of 35 parameters: $save_t transactions, bus_time_us $save_bus, elapsed_us $save_el"
ok "save: at most $(xfer_max 35) transactions ($save_t)" [ "$save_t" -le "$(xfer_max 35)" ]
is "save: 35 requests served" "$(dbg_get stats params_served)" 35
is "blob equals the chip's parameters" "$(blob_words <"$TMP/a")" "$(sim_ws_params)"
ok "chip left running after save" chip_idle

# restore of a changed blob, measured
cp "$TMP/a" "$TMP/b"
set_word "$TMP/b" 24 0x40000000
set_word "$TMP/b" 1 0x3fc00000
knob stats 0
ok "dd calibration_data in (restore)" dd if="$TMP/b" of="$DEV/calibration_data" bs=148 status=none
rest_t=$(dbg_get stats transactions)
rest_bus=$(dbg_get stats bus_time_us)
rest_el=$(dbg_get stats elapsed_us)
echo "# restore of 35 parameters: $rest_t transactions, bus_time_us $rest_bus, elapsed_us $rest_el"
ok "restore: at most $(xfer_max 35) transactions ($rest_t)" [ "$rest_t" -le "$(xfer_max 35)" ]
is "restore: 35 requests served" "$(dbg_get stats params_served)" 35
is "chip holds the written blob" "$(sim_ws_params)" "$(blob_words <"$TMP/b")"
ok "chip left running after restore" chip_idle
ok "dd calibration_data out again" dd if="$DEV/calibration_data" of="$TMP/c" bs=148 count=1 status=none
ok "round trip: read equals written" cmp "$TMP/b" "$TMP/c"
ok "restore the original blob" dd if="$TMP/a" of="$DEV/calibration_data" bs=148 status=none
is "and the chip has it again" "$(sim_ws_params)" "$(blob_words <"$TMP/a")"

# Refusals: nothing reaches the bus
refused() {
	knob stats 0
	"$@" 2>/dev/null && return 1
	[ "$(dbg_get stats transactions)" = 0 ]
}
ok "read of 100 bytes refused, no bus traffic" \
	refused dd if="$DEV/calibration_data" of=/dev/null bs=100 count=1 status=none
ok "read at offset 4 refused" \
	refused dd if="$DEV/calibration_data" of=/dev/null bs=4 skip=1 count=1 status=none
head -c 147 "$TMP/a" >"$TMP/short"
ok "write of 147 bytes refused, no bus traffic" \
	refused dd if="$TMP/short" of="$DEV/calibration_data" bs=4096 status=none
{ cat "$TMP/a"; printf 'x'; } >"$TMP/long"
ok "write of 149 bytes refused, no bus traffic" \
	refused dd if="$TMP/long" of="$DEV/calibration_data" bs=4096 status=none
tail -c +9 "$TMP/a" >"$TMP/bare"
ok "the 140 bytes without the header refused, no bus traffic" \
	refused dd if="$TMP/bare" of="$DEV/calibration_data" bs=4096 status=none
ok "write at offset 148 refused" \
	refused dd if="$TMP/a" of="$DEV/calibration_data" bs=148 seek=1 status=none
for v in 0x7fc00000 0x7f800000 0xff800000 0xffffffff; do
	cp "$TMP/a" "$TMP/bad"
	set_word "$TMP/bad" 20 $v
	ok "blob with $v refused, no bus traffic" \
		refused dd if="$TMP/bad" of="$DEV/calibration_data" bs=148 status=none
done
# Another chip's or firmware's blob: each byte of the header in turn
for i in 0 1 2 3 4 5 6 7; do
	cp "$TMP/a" "$TMP/other"
	printf '\x5a' | dd of="$TMP/other" bs=1 seek=$i count=1 conv=notrunc status=none
	ok "header byte $i changed: refused, no bus traffic" \
		refused dd if="$TMP/other" of="$DEV/calibration_data" bs=148 status=none
done
like "the kernel log names both identities" "$(dmesg | tail -n 20)" \
	"em7180 [0-9]+-0028: calibration_data of [0-9a-f]{2}/[0-9a-f]{2} ROM [0-9a-f]{4} RAM [0-9a-f]{4} v[0-9]+ refused: chip 80/02 ROM 09e6 RAM [0-9a-f]{4}"
ok "chip unchanged by the refusals" test "$(sim_ws_params)" = "$(blob_words <"$TMP/a")"

# Errors from the chip are passed up and transfer mode still ends
knob ack_never 1
out=$(dd if="$TMP/a" of="$DEV/calibration_data" bs=148 2>&1)
like "no acknowledge: timed out" "$out" "timed out"
knob ack_never 0
ok "chip left running after the timeout" chip_idle
knob nack_at 3
out=$(dd if="$DEV/calibration_data" of=/dev/null bs=4096 2>&1)
like "NACK during save: I/O error" "$out" "(Input/output error|No such device)"
ok "chip left running after the NACK" chip_idle
ok "next save works" dd if="$DEV/calibration_data" of=/dev/null bs=4096 status=none

# A parameter the write path would refuse, put in the chip behind the
# driver's back (i2c-dev, as another bus user or a firmware fault could):
# a save must fail rather than hand out a blob no restore accepts, and
# must not drop the driver's copy of the last valid calibration, which is
# what it writes back when the chip resets itself.
ok "restore blob b" dd if="$TMP/b" of="$DEV/calibration_data" bs=148 status=none
SIM_BUS=$(sim_bus)
# In the reference hosts' order, which works whatever the register pointer
# does
ok "NaN written to parameter 10 over i2c-dev" \
	eval 'param_begin && sim_wr 0x60 $(le32_bytes 0x7fc00000) &&
		sim_wr 0x64 0x8a && sim_poll_ack1 0x8a && param_end'
is "the chip holds the NaN" "$(dbg_get params 10)" 0x7fc00000
out=$(dd if="$DEV/calibration_data" of="$TMP/nan" bs=4096 2>&1)
like "save with a non-finite parameter: I/O error" "$out" "Input/output error"
ok "and no blob" test ! -s "$TMP/nan"
like "the kernel log names the parameter" "$(dmesg | tail -n 20)" "em7180.*parameter 10.*0x7fc00000"
ok "chip left running after the refused save" chip_idle
# Parameters 1, 10 and 24 as the chip holds them, and as blob b has them
words_1_10_24() {
	awk '$1 == 1 || $1 == 10 || $1 == 24 { printf "%s ", $2 }' "$SIM_DBG/params"
}
want="$(blob_words <"$TMP/b" | awk '{ printf "%s %s %s ", $1, $10, $24 }')"
b_restored() {
	[ "$(words_1_10_24)" = "$want" ]
}
knob chip_reset 1
ok "after the chip's own reset the driver restores the last valid blob" wait_for 5 b_restored
is "parameters 1, 10, 24" "$(words_1_10_24)" "$want"
ok "chip running after the reset" wait_for 5 chip_idle

# Unbinding leaves the chip running, out of transfer mode, data interrupts
# off: sentral-warmstart --i2c can then save, also on firmware that serves
# no parameter request while the algorithm is in standby.
DRV=/sys/bus/i2c/drivers/em7180
CLIENT=$(basename "$(readlink -f "$DEV/..")")
knob standby_blocks_params 1
ok "unbind" sh -c "echo $CLIENT > $DRV/unbind"
ok "unbound: algorithm running, not in transfer mode" chip_idle
is "unbound: not in standby" "$(dbg_get state standby)" 0
reg=$(awk '$1 == "30:" { print $5 }' "$SIM_DBG/regs")
is "unbound: data interrupts off (EnableEvents)" "$reg" 00
ok "unbound: sentral-warmstart --i2c save" \
	sentral-warmstart --i2c "/dev/i2c-$(sim_bus)" save --force --file "$TMP/i2c.ws"
# Judged by the score where the firmware has the application note's layout
# (the knob matrix of tests/run-suites), else by the level alone.
judged=stable
[ "$(cat "$SIM_DBG/appnote_layout")" = 1 ] && judged=score
like "a valid file, judged by the $judged" \
	"$(sentral-warmstart show "$TMP/i2c.ws" 2>&1)" $'\njudgement: +'"$judged "
knob standby_blocks_params 0
ok "bind again" sh -c "echo $CLIENT > $DRV/bind"
ok "bound again" wait_for 5 em7180_dir

rm -rf "$TMP"
done_testing
