#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# The em7180 driver going away and coming back: unbind during a capture (the
# reader ends, the device returns and captures again), what an unbind
# leaves (the chip quiet and running where its supplies stay on, also when
# the unbind waits for the restore of a chip that reset itself, or when
# that restore fails and asks for another), unbind while a
# 35-parameter calibration_data read or write is in flight (the chip is left out of
# parameter-transfer mode; save and restore work after the rebind), files
# held open across an unload, the simulated bus unloaded under a capture, and
# 50 unloads and reloads of em7180_i2c and em7180_core, with no leak: the same
# IIO device and trigger numbers, interrupts, open files and kmalloc usage
# as before, and (on a kernel with kmemleak) no unreferenced object.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"
# param_begin, param_read, param_end: a parameter transfer over i2c-dev
. "$SENTRAL_ROOT/tests/sim/testlib.sh"

CHANNELS="rot_quaternion accel_x accel_y accel_z anglvel_x anglvel_y anglvel_z timestamp"
CYCLES=50
# kmalloc snapshots at a fifth, three fifths and the end: a leak of one
# object per cycle grows a cache by STRETCH in both stretches.
FIRST=$((CYCLES / 5)) MIDDLE=$((CYCLES * 3 / 5)) STRETCH=$((CYCLES * 2 / 5))
T=$(mktemp -d)

now_ms() {
	echo $((${EPOCHREALTIME/./} / 1000))
}

# AlgorithmControl (0x54) as the chip holds it, "0xXX".
algo_ctrl() {
	awk '$1 == "50:" { print "0x" $6 }' "$SIM_DBG/regs"
}

transfer_mode_off() {
	[ "$(dbg_get state transfer)" = 0 ] && [ $(($(algo_ctrl) & 0x80)) = 0 ]
}

# ends DESC PID SECONDS: whether a background job of this shell ends in time;
# its exit status in RC (not through ok: that runs its command in a subshell).
ends() {
	local desc=$1 pid=$2 secs=$3
	RC=
	if wait_for "$secs" sh -c "! kill -0 $pid 2>/dev/null"; then
		wait "$pid"
		RC=$?
		_tap_result 1 "$desc"
	else
		_tap_result 0 "$desc"
		echo "#   still running after $secs s"
		kill "$pid"
		wait "$pid"
	fi
}

# A device that is there and answers: accel Z reads about 1 g.  Builtins
# only: forks are slow in UML, and this runs in the reload loop.
device_reads() {
	local d n v
	for d in /sys/bus/iio/devices/iio:device*; do
		read -r n <"$d/name" 2>/dev/null && [ "$n" = em7180 ] || continue
		read -r v <"$d/in_accel_z_raw" 2>/dev/null || return 1
		[ "$v" -gt 1900 ] && [ "$v" -lt 2200 ]
		return
	done
	return 1
}

DEV=$(em7180_dir)
ok "em7180 present" test -n "$DEV"
CLIENT=$(basename "$(readlink -f "$DEV/..")")
DRV=$(readlink -f "/sys/bus/i2c/devices/$CLIENT/driver")
like "bound to the em7180 driver" "$DRV" '/drivers/em7180'
N=${DEV##*iio:device}

# -- Unbind during a capture ------------------------------------------------
# shellcheck disable=SC2086
iio_readdev -b 16 -s 0 em7180 $CHANNELS >"$T/s.bin" 2>"$T/s.err" &
pid=$!
wait_for 5 test -s "$T/s.bin"
ok "capturing" test -s "$T/s.bin"
t0=$(now_ms)
ok "unbind during the capture" sh -c "echo $CLIENT > $DRV/unbind"
echo "# unbind took $(($(now_ms) - t0)) ms"
ends "iio_readdev ends within 10 s" $pid 10
echo "# iio_readdev ended after $(($(now_ms) - t0)) ms, status $RC:"
sed 's/^/#   /' "$T/s.err" | grep -v 'channel\[' | head -n 5
like "and says why" "$(cat "$T/s.err")" "(Unable|ERROR|No such device)"
is "it wrote whole scans" "$(($(stat -c %s "$T/s.bin") % 32))" 0
nok "the IIO device is gone" em7180_dir
ok "so is the trigger" sh -c "! grep -qx em7180-dev$N /sys/bus/iio/devices/trigger*/name"
ok "transfer mode not entered" transfer_mode_off
ok "rebind" sh -c "echo $CLIENT > $DRV/bind"
ok "the device is back and reads" wait_for 5 device_reads
DEV=$(em7180_dir)
is "with the same number" "${DEV##*iio:device}" "$N"
is "and its trigger" "$(cat "$DEV/trigger/current_trigger")" "em7180-dev$N"
# shellcheck disable=SC2086
ok "it captures again" sh -c "iio_readdev -b 16 -s 50 em7180 $CHANNELS > $T/s2.bin"
is "50 scans" "$(stat -c %s "$T/s2.bin")" 1600

# The same with a plain blocking read of the character device (the buffer
# enabled through sysfs): the read returns an error at once.
echo 1 >"$DEV/scan_elements/in_accel_x_en"
echo 1 >"$DEV/buffer/enable"
dd if="/dev/iio:device$N" of="$T/raw" bs=64 status=none 2>"$T/raw.err" &
pid=$!
wait_for 5 test -s "$T/raw"
ok "blocking read capturing" test -s "$T/raw"
t0=$(now_ms)
ok "unbind during the blocking read" sh -c "echo $CLIENT > $DRV/unbind"
ends "the read ends within 2 s" $pid 2
echo "# the read ended after $(($(now_ms) - t0)) ms, status $RC: $(cat "$T/raw.err")"
like "with an error" "$RC $(cat "$T/raw.err")" "^[1-9].*No such device"
ok "rebind" sh -c "echo $CLIENT > $DRV/bind"
ok "the device is back and reads" wait_for 5 device_reads
DEV=$(em7180_dir)
is "buffer disabled on the new device" "$(cat "$DEV/buffer/enable")" 0

# -- What unbinding leaves ----------------------------------------------------
# The driver releases the chip's supplies on unbind (devm); before that it
# leaves the chip quiet and running. The simulated board's supplies are
# not switchable (no regulator is described), so the chip keeps its power,
# as on breakout boards fed from the header, and an i2c-dev user finds it
# running, with no interrupt pending, serving parameter transfers.
SIM_BUS=$(sim_bus)
enable_events() {
	awk '$1 == "30:" { print $5 }' "$SIM_DBG/regs"
}
ok "unbind" sh -c "echo $CLIENT > $DRV/unbind"
ok "unbound: algorithm running, not in transfer mode" chip_idle
is "unbound: not in standby" "$(dbg_get state standby)" 0
is "unbound: no event enabled (EnableEvents)" "$(enable_events)" 00
is "unbound: INT low" "$(dbg_get state int)" 0
# In the reference hosts' order, which works whatever the register pointer
# does (simulator knob autoinc_stop)
is "unbound: a parameter read over i2c-dev" \
	"$(eval 'param_begin && sim_wr 0x64 30 && sim_poll_ack1 30 &&
		bytes_le32 $(sim_rd 0x3b 4) && param_end')" "$(dbg_get params 30)"
ok "rebind" sh -c "echo $CLIENT > $DRV/bind"
ok "the device is back and reads" wait_for 5 device_reads
DEV=$(em7180_dir)

# -- Unbind during a calibration_data transfer --------------------------------------
ok "save a reference blob" dd if="$DEV/calibration_data" of="$T/ref" bs=4096 status=none
# 100 ms per acknowledge: a transfer of 35 parameters takes 3.5 s, long
# enough for the check below to see it begin on a loaded machine (with 20 ms
# it missed the 0.7 s window in 2 of 10 runs on UML 6.1 at a host load of 12).
knob ack_latency_us 100000

# unbind_during WHAT CMD...: start CMD, unbind once the chip is in transfer
# mode, and check what is left; then bind again (answering parameter
# requests: the probe reads some). A transfer that ended before the first
# look (a machine starved of CPU) is started again, up to three times.
unbind_during() {
	local what=$1 pid try seen=0
	shift
	for try in 1 2 3; do
		"$@" >"$T/out" 2>"$T/err" &
		pid=$!
		if wait_for 5 in_transfer; then
			seen=1
			break
		fi
		wait "$pid"
		echo "# $what: the transfer ended before it was seen (try $try)"
	done
	ok "$what: chip in transfer mode" [ $seen = 1 ]
	t0=$(now_ms)
	ok "$what: unbind" sh -c "echo $CLIENT > $DRV/unbind"
	ends "$what: the transfer ends" $pid 10
	echo "# $what: unbind took $(($(now_ms) - t0)) ms; transfer status $RC $(head -c 200 "$T/err")"
	ok "$what: transfer mode ended (AlgorithmControl $(algo_ctrl))" transfer_mode_off
	# The probe reads parameters too.
	knob ack_never 0
	ok "$what: rebind" sh -c "echo $CLIENT > $DRV/bind"
	ok "$what: the device is back and reads" wait_for 5 device_reads
	DEV=$(em7180_dir)
	ok "$what: chip running, not in transfer mode" chip_idle
}

# The unbind waits for the sysfs access in flight (the attribute is removed
# only when no one is inside it): the save completes, dd's next read finds
# the device gone.
unbind_during "save" sh -c "dd if=$DEV/calibration_data bs=4096 status=none"
if [ -s "$T/out" ]; then
	ok "the save that completed is the chip's blob" cmp "$T/out" "$T/ref"
else
	ok "or the save returned nothing" test "$RC" != 0
fi
unbind_during "restore" dd if="$T/ref" of="$DEV/calibration_data" bs=148 status=none
knob ack_never 1
unbind_during "unacknowledged save" dd if="$DEV/calibration_data" of=/dev/null bs=4096 status=none
like "which timed out" "$(cat "$T/err")" "timed out"
knob ack_latency_us 500

ok "save after the rebinds" dd if="$DEV/calibration_data" of="$T/a" bs=4096 status=none
is "save: 148 bytes" "$(stat -c %s "$T/a")" 148
ok "restore after the rebinds" dd if="$T/a" of="$DEV/calibration_data" bs=148 status=none
is "the chip holds the blob" "$(sim_ws_params)" "$(blob_words <"$T/a")"
ok "chip idle" chip_idle

# -- Unload with files held open ---------------------------------------------
# The character device and a sysfs attribute stay open across the unbind and
# the unload of em7180_i2c; using them afterwards fails cleanly, and closing
# them lets em7180_core go (a use after free here is what KASAN would see).
exec 3<"/dev/iio:device$N" 4<"$DEV/calibration_data" 5<"$DEV/in_accel_x_raw"
ok "unload em7180_i2c with files open" modprobe -d "$SENTRAL_MODROOT" -r em7180_i2c
nok "the device is gone" em7180_dir
nok "reading the character device fails" dd bs=32 count=1 status=none <&3
nok "reading calibration_data fails" dd bs=4096 count=1 status=none <&4
nok "reading accel fails" dd bs=64 count=1 status=none <&5
exec 3<&- 4<&- 5<&-
ok "em7180_core unloads once they are closed" wait_for 5 modprobe -d "$SENTRAL_MODROOT" -r em7180_core
nok "no em7180 module left" grep -q '^em7180' /proc/modules
ok "reload" modprobe -d "$SENTRAL_MODROOT" em7180_i2c
ok "the device is back and reads" wait_for 5 device_reads
DEV=$(em7180_dir)

# -- The bus goes away under a capture --------------------------------------
# Unloading the simulator unregisters the I2C client (the driver is unbound)
# and then the adapter and the interrupt domain.
# shellcheck disable=SC2086
iio_readdev -b 16 -s 0 em7180 $CHANNELS >"$T/s3.bin" 2>"$T/s3.err" &
pid=$!
wait_for 5 test -s "$T/s3.bin"
ok "capturing" test -s "$T/s3.bin"
ok "unload sentral_sim during the capture" modprobe -d "$SENTRAL_MODROOT" -r sentral_sim
ends "iio_readdev ends within 10 s" $pid 10
nok "the IIO device is gone" em7180_dir
ok "load sentral_sim again" modprobe -d "$SENTRAL_MODROOT" sentral_sim
ok "the driver binds to the new client and reads" wait_for 5 device_reads
fail=0
for i in $(seq 10); do
	modprobe -d "$SENTRAL_MODROOT" -r sentral_sim &&
		modprobe -d "$SENTRAL_MODROOT" sentral_sim && wait_for 5 device_reads ||
		{ fail=$i; break; }
done
is "10 more simulator reloads under the bound driver" "$fail" 0
DEV=$(em7180_dir)
# shellcheck disable=SC2086
ok "it captures" sh -c "iio_readdev -b 16 -s 20 em7180 $CHANNELS > $T/s4.bin"
is "20 scans" "$(stat -c %s "$T/s4.bin")" 640

# -- 50 unloads and reloads -------------------------------------------------
# Counters a leak would move.  Objects in use per kmalloc cache come from
# SLUB's exact counts after the CPU slabs are flushed.  Besides the driver's,
# they move by themselves, in steps of up to a few dozen (the shell, libiio,
# modprobe), so they are taken after cycles 10, 30 and 50: a leak of one
# object per cycle grows a cache by 20 in both stretches, a step in one only.
# The reclaimable caches (dentries' names and the like) are not the driver's.
kmalloc_objects() {
	local c n
	for c in /sys/kernel/slab/kmalloc-[0-9]*; do
		echo 1 >"$c/shrink" 2>/dev/null
		read -r n _ <"$c/objects"
		echo "${c##*/} $n"
	done
}
snapshot() {
	echo "iio_devices $(ls /sys/bus/iio/devices | grep -c '^iio:device')"
	echo "triggers $(ls /sys/bus/iio/devices | grep -c '^trigger')"
	echo "interrupts $(wc -l </proc/interrupts)"
	echo "modules $(wc -l </proc/modules)"
	echo "i2c_clients $(ls /sys/bus/i2c/devices | wc -l)"
	echo "device $(em7180_dir)"
	echo "trigger $(cat "$(em7180_dir)/trigger/current_trigger")"
}
mp() {
	modprobe -d "$SENTRAL_MODROOT" "$@"
}

# No em7180 module loaded.
unloaded() {
	local m
	while read -r m _; do
		[[ $m == em7180_* ]] && return 1
	done </proc/modules
	return 0
}

# The probe is synchronous: the device is there when modprobe returns.
reload() {
	mp -r em7180_i2c && unloaded && mp em7180_i2c &&
		{ device_reads || wait_for 5 device_reads; }
}

for i in 1 2 3; do reload; done
before=$(snapshot)
files0=$(cut -f1 /proc/sys/fs/file-nr)
t0=$(now_ms)
fail=0
for i in $(seq "$CYCLES"); do
	reload || { fail=$i; break; }
	case $i in
	"$FIRST" | "$MIDDLE" | "$CYCLES") kmalloc_objects | sort >"$T/kmalloc.$i" ;;
	esac
done
t=$(($(now_ms) - t0))
is "$CYCLES unloads and reloads, the device reads each time" "$fail" 0
echo "# $CYCLES cycles in $t ms"
is "counts as before" "$(snapshot)" "$before"
files=$(cut -f1 /proc/sys/fs/file-nr)
echo "# allocated files $files0 -> $files"
ok "no file leak ($files0 -> $files)" [ $((files - files0)) -lt "$CYCLES" ]
join "$T/kmalloc.$FIRST" "$T/kmalloc.$MIDDLE" | join - "$T/kmalloc.$CYCLES" >"$T/kmalloc"
grown=$(awk '$4 != $2 { printf "%s %+d %+d, ", $1, $3 - $2, $4 - $3 }' "$T/kmalloc")
echo "# kmalloc objects, cycles $FIRST..$MIDDLE and $MIDDLE..$CYCLES: ${grown:-unchanged}"
min=$((STRETCH * 3 / 4))
is "no kmalloc cache grew by $min objects in both $STRETCH-cycle stretches" \
	"$(awk -v min=$min '$3 - $2 >= min && $4 - $3 >= min' "$T/kmalloc")" ""
DEV=$(em7180_dir)
ok "save after the reloads" dd if="$DEV/calibration_data" of="$T/b" bs=4096 status=none
ok "chip idle" chip_idle

# -- Unbind while the chip resets itself -------------------------------------
# Last: the chip loses what it learned since power-on.
# Teardown: an unbind while the driver restores a chip that reset itself
# (a 1.5 s firmware upload) returns only once the restore is done (the
# unbind waits for the recovery's work item), and the quieting comes after
# the restore: nothing the recovery does outlives the unbind or undoes it,
# and nothing is logged amiss.
CLIENT=$(basename "$(readlink -f "$DEV/..")")
knob upload_ms 1500
dmesg -c >/dev/null
knob chip_reset 1
t0=$(now_ms)
ok "unbind while the chip's own reset is being handled" \
	sh -c "echo $CLIENT > $DRV/unbind"
echo "# unbind took $(($(now_ms) - t0)) ms"
log=$(dmesg)
like "the reset was being handled" "$log" "the chip reset itself"
is "and nothing amiss logged" "$(grep -E 'cannot restore|WARNING|BUG|Oops|lockdep' <<<"$log")" ""
ok "unbound after the reset: running, not in transfer mode" chip_idle
is "unbound after the reset: HostControl run" "$(dbg_get state host_run)" 1
is "unbound after the reset: no event enabled" "$(enable_events)" 00
is "unbound after the reset: INT low" "$(dbg_get state int)" 0
knob upload_ms 10
ok "rebind" sh -c "echo $CLIENT > $DRV/bind"
ok "the device is back and reads" wait_for 5 device_reads
DEV=$(em7180_dir)

# -- Unbind while a recovery queues another ---------------------------------
# A restore whose parameter transfer cannot be ended asks for one more
# recovery, to end it. Unbound meanwhile, the driver waits for the restore
# in progress and leaves none to run after the device is freed: nothing
# touches the chip once the unbind returned (a use after free would; the
# harness fails on a WARNING, an oops or a KASAN report too).
# A warm start known to the driver: the restore writes 35 parameters,
# 3.5 s at 100 ms each (the offsets alone took too short a time to arm
# the NACKs in, on a loaded machine).
ok "a save" dd if="$DEV/calibration_data" of=/dev/null bs=4096 status=none
latency=$(cat "$SIM_DBG/ack_latency_us")
knob upload_ms 2000
knob ack_latency_us 100000
dmesg -c >/dev/null
knob chip_reset 1
# The recovery waits for the firmware upload; the unbind waits for it.
sleep 0.5
sh -c "echo $CLIENT > $DRV/unbind" &
pid=$!
ok "the recovery's restore transfer begins" wait_for 10 in_transfer
ok "while the unbind waits" kill -0 $pid
# Its next transaction and the two that end the transfer
knob nack_run 3
knob nack_at 1
ends "the unbind returns" $pid 15
is "the NACKs fired" "$(cat "$SIM_DBG/nack_at")" 0
knob nack_run 1
like "the restore failed" "$(dmesg)" "cannot restore the chip after its reset: -6"
t0=$(dbg_get stats transactions)
# The recovery it asked for would come 50 ms to 1 s later
sleep 2
is "no bus access after the unbind" "$(dbg_get stats transactions)" "$t0"
is "nothing amiss logged" "$(dmesg | grep -E 'WARNING|BUG|Oops|ODEBUG|KASAN')" ""
ok "unbound: running, not in transfer mode" chip_idle
knob upload_ms 10
knob ack_latency_us "$latency"
ok "rebind" sh -c "echo $CLIENT > $DRV/bind"
ok "the device is back and reads" wait_for 5 device_reads
DEV=$(em7180_dir)

# A host reboot that left the chip idle with its firmware loaded
# (SentralStatus 0x03, nothing runs until a ResetRequest): probe resets it.
ok "unbind" sh -c "echo $CLIENT > $DRV/unbind"
knob warm_reboot 1
ok "rebind onto a chip left idle by a warm reboot" sh -c "echo $CLIENT > $DRV/bind"
ok "the device is back and reads" wait_for 5 device_reads
DEV=$(em7180_dir)
like "probe said so" "$(dmesg | grep em7180 | tail -n 5)" \
	"chip idle with its firmware loaded \(SentralStatus 0x03\): resetting it"
is "the chip is out of that state" "$(cat "$SIM_DBG/warm_reboot")" 0
ok "the algorithm runs" chip_idle
ok "a parameter transfer is served" dd if="$DEV/calibration_data" of=/dev/null \
	bs=148 count=1 status=none

kmemleak=/sys/kernel/debug/kmemleak
if [ -w $kmemleak ]; then
	# Only objects older than 5 s are reported.
	sleep 5
	echo scan >$kmemleak
	echo scan >$kmemleak
	leaks=$(grep -cE 'em7180|sentral|iio' $kmemleak)
	is "kmemleak: nothing of em7180, sentral or iio" "$leaks" 0
	[ "$leaks" = 0 ] || head -n 40 $kmemleak | sed 's/^/#   /'
else
	echo "# no kmemleak in this kernel"
fi

rm -rf "$T"
done_testing
