#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# Fault sweep of the em7180 driver on the simulated chip (DESIGN §6): for
# probe, save (calibration_data read) and restore (calibration_data write) the simulator
# NACKs transaction 1, then 2, 3, ... until the operation runs clean. Every
# faulted run must fail, leave the chip out of parameter-transfer mode with
# the algorithm running (a transfer whose end was NACKed within a second:
# the driver's recovery ends it), and the next run must succeed. Then the same with a chip that never acknowledges a parameter
# (-ETIMEDOUT after 1 s) and one that acknowledges slowly (must succeed),
# and a NACK at each transaction of a buffered capture.
# The kernel log is checked for oopses and warnings by the harness.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"

TMP=$(mktemp -d)
DRV=/sys/bus/i2c/drivers/em7180
# A sweep longer than this means nack_at never stopped firing
MAX_INDEX=300

# Without a learned gyro bias arriving mid-test the chip's parameters only
# change when the driver writes them.
knob gbias_period_ms 3600000
knob motion 0

DEV=$(em7180_dir)
ok "probe: an IIO device named em7180" test -n "$DEV"
CLIENT=$(basename "$(readlink -f "$DEV/..")")
like "bound to the I2C client at 0x28" "$CLIENT" '^[0-9]+-0028$'

# The checks made once per sweep step read debugfs with shell builtins
# only (read_state, tests/lib/em7180.sh).

not_transfer() {
	read_state
	[ "$ST_transfer" = 0 ]
}

# The armed NACK was used: nack_at reads 0 once it fired.
nack_fired() {
	local v
	read -r v <"$SIM_DBG/nack_at"
	[ "$v" = 0 ]
}

# Parameters 1..35 of the chip into CHIP, as sim_ws_params prints them.
chip_words() {
	local k v
	CHIP=
	while read -r k v; do
		[ "$k" -ge 1 ] && [ "$k" -le 35 ] && CHIP+="$v "
	done <"$SIM_DBG/params"
}

# Register R into REG as the host would read it ("xx"), from the regs file.
reg_get() {
	local row col line
	printf -v row '%02x:' $(($1 & ~15))
	col=$((($1 & 15) + 1))
	REG=
	while read -r -a line; do
		[ "${line[0]}" = "$row" ] && REG=${line[$col]} && return
	done <"$SIM_DBG/regs"
}

# A line of the last operation's error output matches ERE.
err_like() {
	local e
	while read -r e; do
		[[ $e =~ $1 ]] && return 0
	done <"$TMP/err"
	return 1
}

# The words of each blob file, computed once.
declare -A WORDS
words_of() {
	[ -n "${WORDS[$1]}" ] || WORDS[$1]=$(blob_words <"$1")
}

save() {
	dd if="$DEV/calibration_data" of="$TMP/saved" bs=4096 status=none 2>"$TMP/err"
}

# Two forks (od, awk); a short or long blob gives a different word list.
saved_ok() {
	chip_words
	[ "$(blob_words <"$TMP/saved")" = "$CHIP" ]
}

restore() {
	dd if="$1" of="$DEV/calibration_data" bs=148 status=none 2>"$TMP/err"
}

restored_ok() {
	words_of "$1"
	chip_words
	[ "$CHIP" = "${WORDS[$1]}" ]
}

# The em7180 IIO device into DEV, without a fork per device.
find_dev() {
	local d name
	DEV=
	for d in /sys/bus/iio/devices/iio:device*; do
		[ -r "$d/name" ] && read -r name <"$d/name" || continue
		[ "$name" = em7180 ] && DEV=$d && return 0
	done
	return 1
}

# Replace 32-bit word N (1-based) of blob FILE by the bytes of VALUE.
set_word() {
	local v=$(($3))
	printf "$(printf '\\%03o\\%03o\\%03o\\%03o' $((v & 255)) $((v >> 8 & 255)) \
		$((v >> 16 & 255)) $((v >> 24 & 255)))" |
		dd of="$1" bs=1 seek=$((8 + 4 * ($2 - 1))) count=4 conv=notrunc status=none
}

knob stats 0
ok "initial save" save
ok "initial save equals the chip" saved_ok
ok "chip running, not in transfer mode" chip_idle
cp "$TMP/saved" "$TMP/orig"
# Two blobs that differ in the first and last parameters and in between, so
# that each restore of the sweep changes what the chip holds.
cp "$TMP/orig" "$TMP/blob0"
cp "$TMP/orig" "$TMP/blob1"
set_word "$TMP/blob0" 1 0x3fc00000
set_word "$TMP/blob0" 18 0x3f8ccccd
set_word "$TMP/blob0" 35 0x3f435000
set_word "$TMP/blob1" 1 0x40400000
set_word "$TMP/blob1" 18 0x3f666666
set_word "$TMP/blob1" 35 0xbf88b800
for b in orig blob0 blob1; do words_of "$TMP/$b"; done

nacks=0

# sweep_xfer NAME: NACK each transaction of a save or a restore in turn.
sweep_xfer() {
	local what=$1 n=1 rc fired faults=0 succeeded=0 fail= blob
	while [ $n -le $MAX_INDEX ]; do
		blob=$TMP/blob$((n & 1))
		knob nack_at $n
		if [ "$what" = save ]; then
			save
		else
			restore "$blob"
		fi
		rc=$?
		if ! nack_fired; then
			knob nack_at 0
			break
		fi
		faults=$((faults + 1))
		if [ $rc = 0 ]; then
			succeeded=$((succeeded + 1))
			if [ "$what" = save ]; then
				saved_ok || fail+=" $n:wrong-blob"
			else
				restored_ok "$blob" || fail+=" $n:wrong-params"
			fi
		elif ! err_like 'No such device or address|Input/output error'; then
			fail+=" $n:error($(<"$TMP/err"))"
		fi
		# The end of the transfer NACKed: the recovery ends it
		chip_idle || wait_for 1 chip_idle || {
			not_transfer || fail+=" $n:left-in-transfer"
			chip_idle || fail+=" $n:algorithm-stopped"
		}
		if [ "$what" = save ]; then
			# Checked all at once after the sweep
			dd if="$DEV/calibration_data" of="$TMP/next" bs=4096 status=none \
				oflag=append conv=notrunc || fail+=" $n:next-save-failed"
		else
			{ restore "$blob" && restored_ok "$blob"; } ||
				fail+=" $n:next-restore-failed"
		fi
		n=$((n + 1))
	done
	if [ "$what" = save ]; then
		chip_words
		is "save: each save after a faulted one equals the chip" \
			"$(caldata_payloads "$TMP/next" | blob_words | sed "s/$CHIP//g")" ""
		is "save: $faults of them" "$(stat -c %s "$TMP/next")" $((CALDATA_SIZE * faults))
	fi
	nacks=$((nacks + faults))
	echo "# $what: $faults NACKs injected, $succeeded recovered, clean at transaction $n (${SECONDS} s)"
	ok "$what: the sweep ended with a clean run" [ $n -le $MAX_INDEX ]
	ok "$what: a NACK at each of at least 73 transactions ($faults)" [ $faults -ge 73 ]
	# No write is retried: a NACK anywhere is an error.
	is "$what: none recovered" "$succeeded" 0
	is "$what: every faulted run failed or succeeded whole, chip idle, next run good" \
		"$fail" ""
	ok "$what: chip running, not in transfer mode" chip_idle
}

sweep_xfer save
sweep_xfer restore
ok "restore the original blob" restore "$TMP/orig"
ok "and the chip has it" restored_ok "$TMP/orig"

# Probe: unbind, arm the NACK, bind.
bound() {
	[ -e "$DRV/$CLIENT" ] && find_dev
}

bind() {
	echo "$CLIENT" >"$DRV/bind" 2>"$TMP/err"
}

unbind() {
	echo "$CLIENT" >"$DRV/unbind"
}

ok "unbind" unbind
nok "unbound: no IIO device" em7180_dir
n=1
faults=0
succeeded=0
fail=
while [ $n -le $MAX_INDEX ]; do
	knob nack_at $n
	bind
	rc=$?
	if ! nack_fired; then
		knob nack_at 0
		break
	fi
	faults=$((faults + 1))
	if [ $rc = 0 ]; then
		# The first accesses are repeated while the chip may still
		# reset, the firmware wait polls on, the recovery ends a
		# transfer whose end was NACKed, and the offsets are not
		# needed to bind.
		succeeded=$((succeeded + 1))
		{ bound && wait_for 1 chip_idle; } || fail+=" $n:bound-but-not-running"
		unbind
	elif [ -e "$DRV/$CLIENT" ]; then
		fail+=" $n:driver-bound"
		unbind
	fi
	find_dev && fail+=" $n:iio-device-left"
	not_transfer || fail+=" $n:left-in-transfer"
	if bind && bound && chip_idle; then
		unbind
	else
		fail+=" $n:next-probe-failed"
		[ -e "$DRV/$CLIENT" ] && unbind
	fi
	n=$((n + 1))
done
nacks=$((nacks + faults))
echo "# probe: $faults NACKs injected, $succeeded recovered, clean at transaction $n (${SECONDS} s)"
ok "probe: the sweep ended with a clean bind" [ $n -le $MAX_INDEX ]
is "probe: and that bind succeeded" "$rc" 0
# ID, status, versions, 8 configuration writes, the offsets' transfer
ok "probe: a NACK at each of at least 20 transactions ($faults)" [ $faults -ge 20 ]
ok "probe: the configuration writes are not recovered ($succeeded of $faults)" \
	[ $succeeded -lt $faults ]
is "probe: every faulted probe failed (or bound whole), chip not in transfer mode, next probe good" \
	"$fail" ""
ok "bound after the sweep" bound
find_dev
ok "chip running after the sweep" chip_idle

# The write that ends probe's parameter transfer (the offsets' read, last
# of probe's transactions: bit 7 clear) NACKed, and the recovery's first
# try too: the transfer is left open and asks for a recovery from inside
# probe: its work item must be ready by then, and end the transfer. The
# NACK's place is counted on a clean probe: with an acknowledge latency
# (the knob matrix's 8 ms) the driver's polls vary in number from probe to
# probe, so none here, as for the calibbias write below.
lat=$(cat "$SIM_DBG/ack_latency_us")
knob ack_latency_us 0
ok "unbind" unbind
t0=$(dbg_get stats transactions)
ok "a clean probe" bind
last=$(($(dbg_get stats transactions) - t0))
ok "unbind" unbind
dmesg -c >/dev/null
knob nack_run 2
knob nack_at "$last"
ok "probe with its transfer's end NACKed binds" bind
ok "the NACKs fired" nack_fired
knob nack_run 1
knob ack_latency_us "$lat"
nacks=$((nacks + 2))
like "the offsets' read failed" "$(dmesg)" "cannot read the accelerometer offsets: -6"
ok "the recovery ends the transfer: chip running" wait_for 5 chip_idle
is "nothing amiss logged" "$(dmesg | grep -E 'WARNING|BUG|ODEBUG|Oops')" ""
find_dev
ok "a save works" save
ok "and is right" saved_ok

# The same through a module reload
ok "unload em7180_i2c" modprobe -d "$SENTRAL_MODROOT" -r em7180_i2c
knob nack_at 1
ok "load em7180_i2c with the first transaction NACKed" \
	modprobe -d "$SENTRAL_MODROOT" em7180_i2c
ok "the NACK fired" nack_fired
nacks=$((nacks + 1))
# The first access may meet a chip still in its reset: it is repeated
ok "probe repeated the ID read: bound" wait_for 5 bound
ok "unload again" modprobe -d "$SENTRAL_MODROOT" -r em7180_i2c
ok "load em7180_i2c" modprobe -d "$SENTRAL_MODROOT" em7180_i2c
ok "bound after the reload" wait_for 5 bound
find_dev
ok "chip running" chip_idle
ok "save works" save
ok "and is right" saved_ok

# A chip that never acknowledges a parameter
timeouts=0
knob ack_never 1
for what in save restore; do
	t0=$(date +%s%N)
	if [ $what = save ]; then
		nok "ack_never: save fails" save
	else
		nok "ack_never: restore fails" restore "$TMP/blob0"
	fi
	ms=$((($(date +%s%N) - t0) / 1000000))
	timeouts=$((timeouts + 1))
	like "ack_never: $what timed out" "$(cat "$TMP/err")" "timed out"
	ok "ack_never: $what gave up after the 1 s timeout ($ms ms)" \
		test $ms -ge 1000 -a $ms -lt 10000
	ok "ack_never: chip left running, not in transfer mode" chip_idle
done
ok "unbind" unbind
ok "ack_never: probe binds without the offsets" bind
timeouts=$((timeouts + 1))
ok "bound" bound
find_dev
ok "chip running, not in transfer mode" chip_idle
nok "calibbias unknown: its read fails" cat "$DEV/in_accel_x_calibbias"
knob ack_never 0
ok "a calibration_data read refreshes the copy" save
is "calibbias known again" "$(cat "$DEV/in_accel_x_calibbias")" 0
ok "unbind" unbind
ok "bind again" bind
ok "bound again" bound
find_dev
ok "chip running" chip_idle

# A chip that does not acknowledge its address for a while after a reset
# (the reference drivers wait about 50 ms): probe waits for it.
ok "unbind" unbind
knob nack_after_reset_ms 100
knob power_cycle 1
ok "probe during 100 ms of NACKs after a reset" bind
knob nack_after_reset_ms 0
ok "bound" bound
find_dev
ok "chip running" chip_idle
nacks=$(dbg_get stats nacks)

# A write whose acknowledge poll fails: the chip may or may not have taken
# the value, and calibbias must then read what the chip has.
ok "calibbias x 0" sh -c "echo 0 >$DEV/in_accel_x_calibbias"
knob nack_at 3
nok "calibbias x -47, the acknowledge poll NACKed" sh -c "echo -47 >$DEV/in_accel_x_calibbias"
ok "the NACK fired" nack_fired
nacks=$((nacks + 1))
# The driver read the offsets back after the failed write
case $(dbg_get params 27) in
0xbcbbe447) want=-47 ;;
0x00000000) want=0 ;;
*) want="param 27 $(dbg_get params 27)" ;;
esac
is "calibbias reads what the chip holds" "$(cat "$DEV/in_accel_x_calibbias")" "$want"
ok "calibbias x 0" sh -c "echo 0 >$DEV/in_accel_x_calibbias"
ok "after ack_never: restore works" restore "$TMP/blob1"
ok "and the chip holds the blob" restored_ok "$TMP/blob1"
ok "after ack_never: save works" save
ok "and is right" saved_ok

# A slow acknowledge below the timeout: 0.9 s for one parameter and for
# each of the 3 a probe reads, 20 ms for each of a whole blob.
knob ack_latency_us 900000
ok "ack 0.9 s: write calibbias" sh -c "echo -47 >$DEV/in_accel_x_calibbias"
is "ack 0.9 s: calibbias reads back" "$(cat "$DEV/in_accel_x_calibbias")" -47
is "parameter 27 is Table 1's" "$(dbg_get params 27)" 0xbcbbe447
ok "chip running" chip_idle
ok "unbind" unbind
ok "ack 0.9 s: probe" bind
ok "bound" bound
find_dev
ok "chip running" chip_idle
is "calibbias read at probe" "$(cat "$DEV/in_accel_x_calibbias")" -47
ok "calibbias x 0 again" sh -c "echo 0 >$DEV/in_accel_x_calibbias"
knob ack_latency_us 20000
ok "ack 20 ms: restore" restore "$TMP/blob0"
ok "and the chip holds the blob" restored_ok "$TMP/blob0"
ok "ack 20 ms: save" save
ok "and is right" saved_ok
ok "chip running" chip_idle
slow=5
knob ack_latency_us 500
ok "ack 500 us again: restore" restore "$TMP/orig"
ok "and the chip holds the blob" restored_ok "$TMP/orig"

# Streaming: every transaction of a short capture in turn, then the write
# that turns the data interrupts off. Only a successful EventStatus read
# lowers the INT line, and the interrupt is edge-triggered. The enable
# reads EventStatus (retried), then writes EnableEvents: only a NACK of
# that write, the second transaction, fails the capture.
# 10 scans of accel_x (2 bytes each), appended to $TMP/cap. iio_readdev
# reports a stalled capture ("Unable to refill buffer") but exits 0.
capture() {
	iio_readdev -T 3000 -b 4 -s 10 em7180 accel_x >>"$TMP/cap" 2>"$TMP/err" &&
		! err_like '^Unable'
}

n=1
faults=0
delivered=0
fail=
: >"$TMP/cap"
while [ $n -le $MAX_INDEX ]; do
	knob nack_at $n
	capture
	rc=$?
	if ! nack_fired; then
		knob nack_at 0
		[ $rc = 0 ] && delivered=$((delivered + 1))
		break
	fi
	faults=$((faults + 1))
	if [ $rc = 0 ]; then
		delivered=$((delivered + 1))
	elif [ $n != 2 ]; then
		fail+=" $n:capture-failed($(<"$TMP/err"))"
	fi
	reg_get 0x33
	[ "$REG" = 03 ] || fail+=" $n:events-left-on($REG)"
	chip_idle || fail+=" $n:chip-not-idle"
	n=$((n + 1))
done
nacks=$((nacks + faults))
echo "# capture: $faults NACKs injected, clean at transaction $n (${SECONDS} s)"
ok "capture: the sweep ended with a clean run" [ $n -le $MAX_INDEX ]
is "capture: and that run delivered" "$rc" 0
ok "capture: a NACK at each of at least 20 transactions ($faults)" [ $faults -ge 20 ]
is "capture: only the enable failed; every capture delivered, events off after" "$fail" ""
is "capture: 10 scans from each of the $delivered that did not fail" \
	"$(stat -c %s "$TMP/cap")" $((20 * delivered))
: >"$TMP/cap"
ok "capture: 10 scans without a fault" capture
is "capture: 20 bytes" "$(stat -c %s "$TMP/cap")" 20

# The write that ends the data interrupts, NACKed: at 10 Hz nothing else
# is likely to use the bus in between.
echo 10 >"$DEV/in_accel_sampling_frequency"
for f in "$DEV"/scan_elements/*_en; do echo 0 >"$f"; done
echo 1 >"$DEV/scan_elements/in_accel_x_en"
ok "buffer enabled" sh -c "echo 1 >$DEV/buffer/enable"
sleep 0.35
reg_get 0x33
is "data interrupts on" "$REG" 13
knob nack_at 1
echo 0 >"$DEV/buffer/enable"
ok "the NACK fired" nack_fired
nacks=$((nacks + 1))
is "buffer disabled" "$(cat "$DEV/buffer/enable")" 0
reg_get 0x33
is "data interrupts off despite the NACK" "$REG" 03
irqs=$(dbg_get state irqs)
sleep 0.3
is "no interrupt after the capture" "$(dbg_get state irqs)" "$irqs"
echo 100 >"$DEV/in_accel_sampling_frequency"
: >"$TMP/cap"
ok "capture works" capture
is "10 scans" "$(stat -c %s "$TMP/cap")" 20

# A transfer whose end cannot be written: ParamRequest = 0 and the
# AlgorithmControl bit 7 clear NACKed. The driver tries again later; that
# try NACKed too, it resets the chip, which is restored.
knob ack_latency_us 0
# Three axes in turn: no write starts on the echo of the one before, which
# a firmware that keeps its last echo (ack_end) would make a longer one.
echo 0 >"$DEV/in_accel_x_calibbias"
t0=$(dbg_get stats transactions)
ok "calibbias write" sh -c "echo -47 > $DEV/in_accel_y_calibbias"
clean=$(($(dbg_get stats transactions) - t0))
# 6 (ParamAcknowledge read, LoadParam0..3 with ParamRequest, bit 7 set,
# the acknowledge, then the end's ParamRequest = 0 and bit 7 clear). Where
# the register pointer stops at 0x63 (autoinc_stop) ParamRequest is written
# apart, and on firmware with the application note's registers the
# calibration block is read apart from ParamAcknowledge: 1 more each.
single=$(cat "$SIM_DBG/autoinc_stop")
cost=$((6 + single * (1 + $(cat "$SIM_DBG/appnote_layout"))))
is "costs $cost transactions" "$clean" "$cost"
# 6 NACKs: the write's 2 end writes; the read of the offsets that follows
# a failed write (its start, its 2 end writes); the later try.
knob nack_run 6
knob nack_at $((clean - 1))
nok "calibbias write with its end NACKed: an error" \
	sh -c "echo 46 > $DEV/in_accel_z_calibbias"
nacks=$((nacks + 6))
ok "the driver resets the chip" wait_for 5 sh -c \
	"dmesg | grep -q 'cannot end a parameter transfer (-6): resetting the chip'"
ok "and restores it: running, out of transfer mode" wait_for 5 chip_idle
ok "calibbias reads again" cat "$DEV/in_accel_z_calibbias"
knob nack_run 1
knob ack_latency_us 500
echo 0 >"$DEV/in_accel_y_calibbias"
echo 0 >"$DEV/in_accel_z_calibbias"

is "the simulator counted every NACK" "$(dbg_get stats nacks)" $nacks
total=$((nacks + timeouts + slow))
echo "# faults injected: $total ($nacks NACKs, $timeouts never acknowledged, $slow slow acknowledges; ${SECONDS} s)"
ok "faults injected: $total" [ $nacks -ge $((73 + 73 + 20 + 1 + 1 + 20 + 1)) ]

rm -rf "$TMP"
done_testing
