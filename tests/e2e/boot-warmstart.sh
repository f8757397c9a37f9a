#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# Runs on the HOST: six boots of the UML machine sharing one state
# directory (tests/uml/run --udev --caldata --state DIR, the firmware
# loader finding DIR/firmware as em7180/ as through the package's
# /usr/lib/firmware/em7180), like reboots of a real machine:
#   1. calibrate (simulated motion) and save: the saved file, and the
#      driver's firmware/caldata-CLIENT.bin with its payload;
#   2. the driver restores at probe (its kernel log line), before udev's
#      restore, which finds the chip restored and writes nothing:
#      in_magn_calibration_auto_status is 4 (stable) without any motion and
#      the chip's blob equals the saved payload;
#   3. with both files corrupted (the saved file's CRC, the driver's file
#      cut to 147 bytes), the driver warns and restores nothing, udev's
#      restore refuses the saved file (the message is in the kernel log),
#      the chip is left alone and the file is moved aside; the chip
#      calibrates again and the save (the unit's stop action) writes both
#      files anew;
#   4. that new calibration is restored at probe;
#   5. the driver's file with a NaN: warned about, and udev's restore
#      restores from the saved file and writes the driver's file back;
#   6. the driver's file of another RAM version (its header): not used,
#      said once by the driver; udev's restore restores and writes this
#      firmware's file.
# The host script calls itself inside the machine with the boot's name.
set -u
. "$SENTRAL_ROOT/tests/lib/tap.sh"

if [ "${1:-}" = --inside ]; then
	. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"
	# The simulated chip updated its gyro bias more than N times.
	gbias_above() {
		[ "$(dbg_get cal_updates gbias)" -gt "$1" ]
	}
	DEV=$(em7180_dir)
	ok "em7180 probed" test -n "$DEV"
	key=$(sentral-warmstart status --json | json_field key)
	f=$STATE/$key.ws
	client=$(basename "$(readlink -f "$DEV/..")")
	cal=caldata-$client.bin
	case $2 in
	first)
		like "first boot: nothing to restore" "$(dmesg)" "no saved calibration"
		is "not calibrated: 2" "$(cal_level)" 2
		ok "simulated figure-8 until calibrated" calibrate_by_motion
		# Seed step 2: the gyro bias learned while still is part of
		# the warm start (and the next boot re-learns the same one).
		n=$(dbg_get cal_updates gbias)
		ok "gyro bias learned while still" wait_for 10 gbias_above "$n"
		ok "save" sentral-warmstart save
		ok "file saved" test -f "$f"
		is "the driver's file $cal holds its payload" \
			"$(blob_words <"$STATE/firmware/$cal")" "$(file_payload_words "$f")"
		like "status: the chip holds it" "$(sentral-warmstart status)" \
			"saved file: +$f: level 4 \(stable\), no score, saved .*"$'\n'"restored: +yes"
		;;
	second)
		like "the driver restored at probe" "$(dmesg)" \
			"em7180 $client: restored calibration from em7180/$cal"
		like "udev's restore found it restored, wrote nothing" "$(dmesg)" \
			"sentral-warmstart\[[0-9]+\]: iio:device[0-9]+: already restored at probe: it holds the calibration of $f"
		nok "and did not restore" sh -c "dmesg | grep -q 'restored iio:device'"
		is "in_magn_calibration_auto_status 4 (stable) without motion" "$(cal_level)" 4
		is "motion never set this boot" "$(cat "$SIM_DBG/motion")" 0
		is "the chip's blob equals the saved payload" \
			"$(blob_words <"$DEV/calibration_data")" "$(file_payload_words "$f")"
		out=$(sentral-warmstart status 2>&1)
		like "status: the level, stable" "$out" $'\ncalibration level: +4 \\(stable\\)\n'
		like "status: the chip holds the saved calibration" "$out" \
			$'\nrestored: +yes: the chip holds the saved calibration'
		;;
	third)
		like "the driver warned about its file" "$(dmesg)" \
			"em7180 $client: em7180/$cal: 147 bytes, not 148: calibration not restored"
		like "refused at probe, logged with the check" "$(dmesg)" \
			"error: $f: refused: bad CRC.*moved aside to $f.refused"
		is "chip untouched: not calibrated (2)" "$(cal_level)" 2
		ok "chip untouched: magnetic coefficients are not the file's" \
			test "$(words 18 23 "$(sim_ws_params)")" != \
			"$(words 18 23 "$(file_payload_words "$f.refused")")"
		ok "calibrated again" calibrate_by_motion
		ok "the stop action saves the new calibration" \
			sentral-warmstart --device "$key" save --if-present
		ok "a valid file again" sentral-warmstart show "$f"
		is "and the driver's file with its payload" \
			"$(blob_words <"$STATE/firmware/$cal")" "$(file_payload_words "$f")"
		;;
	fourth)
		like "the new calibration restored at probe" "$(dmesg)" \
			"em7180 $client: restored calibration from em7180/$cal"
		like "udev's restore wrote nothing" "$(dmesg)" "already restored at probe"
		is "in_magn_calibration_auto_status 4 (stable) without motion" "$(cal_level)" 4
		is "the chip's blob equals the new file's payload" \
			"$(blob_words <"$DEV/calibration_data")" "$(file_payload_words "$f")"
		;;
	fifth)
		like "the driver warned about its file" "$(dmesg)" \
			"em7180 $client: em7180/$cal: a value is not a finite float: calibration not restored"
		like "udev's restore restored from the saved file" "$(dmesg)" \
			"sentral-warmstart\[[0-9]+\]: restored iio:device[0-9]+ calibration from $f"
		is "in_magn_calibration_auto_status 4 (stable) without motion" "$(cal_level)" 4
		is "the chip's blob equals the saved payload" \
			"$(blob_words <"$DEV/calibration_data")" "$(file_payload_words "$f")"
		is "and the driver's file is whole again" \
			"$(blob_words <"$STATE/firmware/$cal")" "$(file_payload_words "$f")"
		;;
	sixth)
		like "the driver refused its file, naming both firmware" \
			"$(dmesg | grep caldata | grep -v ': firmware: ')" \
			"em7180 $client: em7180/$cal of 80/02 ROM 09e6 RAM beef v1 refused: chip 80/02 ROM 09e6 RAM [0-9a-f]{4}"
		is "said once" "$(dmesg | grep caldata | grep -vc ': firmware: ')" 1
		like "udev's restore restored from the saved file" "$(dmesg)" \
			"sentral-warmstart\[[0-9]+\]: restored iio:device[0-9]+ calibration from $f"
		is "in_magn_calibration_auto_status 4 (stable) without motion" "$(cal_level)" 4
		is "it wrote this firmware's file" "$(ls "$STATE/firmware")" "$cal"
		is "  with this chip's identity" "$(caldata_header <"$STATE/firmware/$cal")" \
			"$(sim_caldata_header)"
		;;
	esac
	done_testing
	exit
fi

kver=${SENTRAL_KVER:-6.12}
state=$(mktemp -d "${TMPDIR:-/tmp}/sentral-boot.XXXXXX")
trap 'rm -rf "$state"' EXIT
chmod 0700 "$state"
# One boot running this script's stage NAME inside; its checks are shown.
# The boots that compare the chip's blob with a file after a restore hold
# the simulator's gyro-bias learning: a still chip learns parameters 33-35
# two seconds after power-on, on a loaded host before the comparison.
boot() {
	local desc=$1 name=$2 out rc knobs=()
	case $name in
	second|fourth|fifth) knobs=(--sim-knobs gbias_period_ms=3600000) ;;
	esac
	out=$("$SENTRAL_ROOT/tests/uml/run" -k "$kver" --udev --caldata --state "$state" \
		"${knobs[@]}" -- \
		"$SENTRAL_ROOT/tests/e2e/boot-warmstart.sh" --inside "$name" 2>&1)
	rc=$?
	sed 's/^/#   /' <<<"$out"
	is "$desc" "$rc" 0
}

boot "boot 1: calibrate and save" first
n=$(ls "$state"/*.ws 2>/dev/null | wc -l)
is "one saved file on the host" "$n" 1
is "one driver's file on the host" "$(ls "$state/firmware" | wc -l)" 1
f=$(ls "$state"/*.ws | head -n1)
cal=$(ls "$state"/firmware/caldata-*.bin | head -n1)
boot "boot 2: restored at probe" second
# Flip one bit of a parameter byte: only the CRC can tell.
b=$(od -An -tu1 -j 100 -N1 "$f" | tr -d ' ')
printf "$(printf '\\%03o' $((b ^ 0x10)))" |
	dd of="$f" bs=1 seek=100 count=1 conv=notrunc status=none
truncate -s 147 "$cal"
boot "boot 3: both files corrupted, refused; a new calibration saved" third
is "the refused file kept on the host, the new one in its place" \
	"$(cd "$state" && ls)" "firmware
$(basename "$f")
$(basename "$f").refused"
boot "boot 4: the new calibration restored" fourth
# A NaN in parameter 10 (bytes 44..47 after the header, little-endian
# 0x7fc00000)
printf '\000\000\300\177' | dd of="$cal" bs=1 seek=44 count=4 conv=notrunc status=none
boot "boot 5: the driver's file with a NaN: the saved file restored" fifth
# RAM version 0xbeef in the header (bytes 6..7)
printf '\357\276' | dd of="$cal" bs=1 seek=6 count=2 conv=notrunc status=none
boot "boot 6: a driver's file of another RAM version not used" sixth
done_testing
