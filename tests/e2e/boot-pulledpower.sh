#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# Runs on the HOST: power pulled under an application that streams. Two
# boots of the UML machine sharing one state directory (tests/uml/run
# --udev --caldata --state DIR, the firmware loader finding DIR/firmware
# as em7180/ as through the package's /usr/lib/firmware/em7180):
#   1. an application streams (iio_readdev through the driver's trigger)
#      from before the calibration to the end; sentral-warmstart watch runs
#      (as sentral-warmstart@.service runs it); the chip is calibrated by
#      simulated motion and the watcher saves by itself while the stream
#      runs; then the machine is killed (SIGKILL to the UML processes): no
#      shutdown, no stop action, no sync;
#   2. the driver restores at probe, from the file the watcher wrote with
#      its save, and udev's restore finds the chip restored:
#      in_magn_calibration_auto_status is 4 (stable) without any motion and
#      the chip's blob equals the saved payload; the application streams
#      again.
# The host script calls itself inside the machine with the boot's name.
set -u
. "$SENTRAL_ROOT/tests/lib/tap.sh"

MARK="pull the plug now"

if [ "${1:-}" = --inside ]; then
	. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"
	DEV=$(em7180_dir)
	ok "em7180 probed" test -n "$DEV"
	key=$(sentral-warmstart key)
	f=$STATE/$key.ws
	case $2 in
	first)
		iio_readdev -b 16 -s 0 em7180 rot_quaternion accel_x accel_y \
			accel_z timestamp >/tmp/stream.bin 2>/tmp/stream.err &
		spid=$!
		ok "an application streams" wait_for 10 grep -qx 1 "$DEV/buffer/enable"
		sentral-warmstart --device "$key" watch --poll 1 >/tmp/watch.log 2>&1 &
		ok "the watcher runs" wait_for 5 grep -q "^watching" /tmp/watch.log
		ok "simulated figure-8 until calibrated" calibrate_by_motion
		ok "the watcher saved by itself while the stream ran" \
			wait_for 10 grep -q "saved iio:device[0-9]* calibration" /tmp/watch.log
		sed 's/^/#   watch: /' /tmp/watch.log
		ok "a valid file" sentral-warmstart show "$f"
		is "and the driver's file, with its payload" \
			"$(cat "$STATE"/firmware/caldata-*.bin | blob_words)" \
			"$(file_payload_words "$f")"
		is "the buffer stayed enabled" "$(cat "$DEV/buffer/enable")" 1
		n=$(dbg_get samples quaternion_read)
		sleep 0.5
		ok "the application still streams (the driver reads samples)" \
			test "$(dbg_get samples quaternion_read)" -gt "$n"
		ok "and iio_readdev still runs" kill -0 "$spid"
		# No shutdown from here on: the host kills the machine.
		echo "$MARK"
		sleep 600
		;;
	second)
		client=$(basename "$(readlink -f "$DEV/..")")
		like "the driver restored at probe" "$(dmesg)" \
			"em7180 $client: restored calibration from em7180/caldata-$client.bin"
		like "udev's restore found it restored" "$(dmesg)" \
			"sentral-warmstart\[[0-9]+\]: iio:device[0-9]+: already restored at probe: it holds the calibration of $f"
		is "in_magn_calibration_auto_status 4 (stable) without motion" "$(cal_level)" 4
		is "motion never set this boot" "$(cat "$SIM_DBG/motion")" 0
		# Parameters 33..35 are the gyro bias, which the chip learns
		# again within gbias_period_ms of standing still: boot 1 saved
		# while moving, before it had learned one.
		is "the chip's blob equals the saved payload (but the gyro bias)" \
			"$(words 1 32 "$(blob_words <"$DEV/calibration_data")")" \
			"$(words 1 32 "$(file_payload_words "$f")")"
		like "status: the chip holds the saved calibration" "$(sentral-warmstart status)" \
			$'\ncalibration level: +4 \\(stable\\)\n.*\nrestored: +yes: '
		ok "the application streams again" sh -c "iio_readdev -b 16 -s 100 \
			em7180 rot_quaternion timestamp >/tmp/stream.bin"
		is "100 scans" "$(stat -c %s /tmp/stream.bin)" 1600
		done_testing
		;;
	esac
	exit
fi

kver=${SENTRAL_KVER:-6.12}
state=$(mktemp -d "${TMPDIR:-/tmp}/sentral-pulled.XXXXXX")
out=$(mktemp "${TMPDIR:-/tmp}/sentral-pulled-out.XXXXXX")
trap 'rm -rf "$state" "$out"' EXIT
chmod 0700 "$state"

# Boot 1 in the background; once it has saved, kill every process of the
# virtual machine: the UML kernel, a child of tests/uml/run, makes a
# session and process group of its own. They are stopped first, so that
# none can notice another's death and start a shutdown.
"$SENTRAL_ROOT/tests/uml/run" -k "$kver" --udev --caldata --state "$state" -- \
	"$SENTRAL_ROOT/tests/e2e/boot-pulledpower.sh" --inside first >"$out" 2>&1 &
run=$!
for _ in $(seq 600); do
	grep -q "^$MARK" "$out" && break
	kill -0 "$run" 2>/dev/null || break
	sleep 0.5
done
pulled=0
if grep -q "^$MARK" "$out"; then
	vm=$(pgrep -P "$run" -x linux)
	[ -n "$vm" ] && kill -STOP -- "-$vm" && kill -KILL -- "-$vm" && pulled=1
fi
wait "$run"
sed 's/^/#   /' "$out"
is "boot 1: calibrated, saved by the watcher, then the power pulled" "$pulled" 1
ok "boot 1's checks passed before it was killed" grep -q "^ok .* - and iio_readdev still runs" "$out"
nok "and none failed" grep -q "^not ok" "$out"
nok "boot 1 never shut down" grep -q "reboot: Power down" "$out"
n=$(ls "$state"/*.ws 2>/dev/null | wc -l)
is "one saved file on the host" "$n" 1
is "one driver's file on the host" "$(ls "$state/firmware" | wc -l)" 1
nok "no temporary file left" sh -c "find '$state' -name '*tmp*' | grep -q ."

boot_out=$("$SENTRAL_ROOT/tests/uml/run" -k "$kver" --udev --caldata --state "$state" -- \
	"$SENTRAL_ROOT/tests/e2e/boot-pulledpower.sh" --inside second 2>&1)
rc=$?
sed 's/^/#   /' <<<"$boot_out"
is "boot 2: restored at probe" "$rc" 0
done_testing
