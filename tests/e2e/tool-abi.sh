#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# sentral-warmstart against an em7180 driver older or newer than itself:
# the device's directory is replaced (a bind mount of a copy) by one whose
# attributes are an earlier release's (the update counters instead of the
# update flags; in_magn_transient beside the application note's status) or
# lack one the tool uses without any earlier one (the level, or some of the
# score's three attributes). The simulated chip is a USFS board, whose
# firmware reports the level alone: no mismatch. Every
# command but key and show then exits 78 before touching anything, with a
# message that says older or newer and what to install; key still names
# the device for udev; the watcher's unit does not restart on 78 and has a
# start limit. This release's driver has the chip's identity in
# calibration_data's header and no firmware_source: status shows the
# identity and says the firmware's origin is unknown. The driver before
# the header (identity attributes, firmware_source, a 140-byte blob) still
# works. With the real directory back, everything works again.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
real=$(readlink -f "$DEV")
out=$(sentral-warmstart status 2>&1)
is "status exits 0 with this release's driver" $? 0
like "on firmware that reports the level alone: no mismatch" "$out" \
	$'\ncalibration level: +[0-4] \\([a-z ]+\\)\ncalibration score: +not reported by this firmware'
version=$(sentral-warmstart --version | sed 's/.* //')
key=$(sentral-warmstart key)

# fake_dir DIR DROP... ADD...: a copy of the device's directory (its links as
# they are, for libudev; its files as plain files), without the DROP ones
# (names starting with -) and with ADD.
fake_dir() {
	local dir=$1 a
	shift
	rm -rf "$dir" && mkdir -p "$dir"
	for a in "$real"/*; do
		if [ -L "$a" ]; then
			cp -P "$a" "$dir/"
		elif [ -d "$a" ]; then
			mkdir -p "$dir/${a##*/}"
		elif [ -f "$a" ]; then
			cat "$a" >"$dir/${a##*/}" 2>/dev/null || : >"$dir/${a##*/}"
		fi
	done
	for a in "$@"; do
		case $a in
		-*) rm -f "$dir/${a#-}" ;;
		*) echo 0 >"$dir/$a" ;;
		esac
	done
}

# with_dir DIR CMD...: CMD run with DIR in place of the device's directory,
# in the environment of a udev event for the device (as the rule runs the
# tool): libudev then takes the device from it, where it would refuse a
# directory that is not sysfs.
with_dir() {
	local dir=$1 rc
	shift
	mount --bind "$dir" "$real" || return 125
	SEQNUM=1 ACTION=add SUBSYSTEM=iio DEVPATH=${real#/sys} "$@"
	rc=$?
	umount "$real"
	return $rc
}

# The update counters' driver (between 1.0.0 and 1.1.0): the score with
# the counters instead of the flags.
fake_dir /tmp/older -in_anglvel_calibration_update -in_magn_calibration_update \
	in_magn_calibration_score in_anglvel_calibration_update_count \
	in_magn_calibration_update_count
out=$(with_dir /tmp/older sentral-warmstart status 2>&1)
is "an older driver: status exits 78" $? 78
is "saying so, with what to install" "$out" \
	"sentral-warmstart: error: ${DEV##*/}: the em7180 driver is older than sentral-warmstart $version: it has in_magn_calibration_update_count (the update counters) and lacks in_anglvel_calibration_update and more; install the em7180 driver of release $version (em7180-dkms) and reload it or reboot"
out=$(with_dir /tmp/older sentral-warmstart watch --poll 1 2>&1)
is "watch exits 78 at once, not a loop" $? 78
is "with one message" "$(grep -c 'error:' <<<"$out")" 1
nok "it never started watching" grep -q '^watching' <<<"$out"
out=$(with_dir /tmp/older sentral-warmstart restore --if-present 2>&1)
is "restore exits 78 too, the chip untouched" $? 78
out=$(with_dir /tmp/older sentral-warmstart key 2>&1)
is "key still names the device (udev's rule needs it)" "$out" "$key"

# The driver before the level: the application note's status 0-3 in
# in_magn_calibration_auto_status, with in_magn_transient beside it.
fake_dir /tmp/status in_magn_transient in_magn_calibration_score \
	in_anglvel_calibration_update in_magn_calibration_update
out=$(with_dir /tmp/status sentral-warmstart save 2>&1)
is "the driver of the application note's status: save exits 78" $? 78
is "saying it is older" "$out" \
	"sentral-warmstart: error: ${DEV##*/}: the em7180 driver is older than sentral-warmstart $version: it has in_magn_transient (the application note's status 0-3 in in_magn_calibration_auto_status); install the em7180 driver of release $version (em7180-dkms) and reload it or reboot"

# A driver that renamed an attribute the tool uses: newer.
fake_dir /tmp/newer -in_magn_calibration_auto_status
out=$(with_dir /tmp/newer sentral-warmstart save 2>&1)
is "a newer driver: save exits 78" $? 78
like "saying so" "$out" \
	"the em7180 driver lacks in_magn_calibration_auto_status, which sentral-warmstart $version uses, .*: it is newer than this tool; install the sentral-warmstart of the driver's release"
# The score's attributes come all three or none.
fake_dir /tmp/partial in_magn_calibration_score
out=$(with_dir /tmp/partial sentral-warmstart status 2>&1)
is "the score without the update flags: status exits 78" $? 78
like "saying which is missing" "$out" \
	"the em7180 driver lacks in_anglvel_calibration_update and more, which sentral-warmstart $version uses, .*: it is newer than this tool"

# This release's driver: the identity from calibration_data's header, the
# firmware's origin said only in the kernel log and debugfs.
out=$(sentral-warmstart status 2>&1)
like "the chip's identity from calibration_data's header" "$out" \
	'chip: +ProductID 0x80, RevisionID 0x02, ROM 0x09e6, RAM 0x[0-9a-f]{4}'
like "the firmware's origin unknown, and why" "$out" \
	"firmware: +unknown \\(not in the em7180 driver's sysfs; its probe line in the kernel log says\\)"
like "the feature sensors still shown" "$out" 'feature sensors: +pressure [0-9.]+ kPa at 25 Hz'
like "--json: the identity, firmware_source null" "$(sentral-warmstart status --json 2>&1)" \
	'"product_id":128,"revision_id":2,"rom_version":2534,"ram_version":[0-9]+,"firmware_source":null,"feature_sensors":\[\{"name":"pressure",'

# The driver before the header: the identity and firmware_source as
# attributes, calibration_data the 140-byte payload alone.
fake_dir /tmp/pre-header product_id revision_id rom_version ram_version \
	firmware_source
echo 0x80 >/tmp/pre-header/product_id
echo 0x02 >/tmp/pre-header/revision_id
echo 0x09e6 >/tmp/pre-header/rom_version
echo 0x0d17 >/tmp/pre-header/ram_version
echo eeprom >/tmp/pre-header/firmware_source
dd if="$real/calibration_data" bs=148 status=none | tail -c +9 >/tmp/pre-header/calibration_data
out=$(with_dir /tmp/pre-header sentral-warmstart status 2>&1)
is "the driver before the header: status exits 0" $? 0
like "the identity from its attributes" "$out" \
	'chip: +ProductID 0x80, RevisionID 0x02, ROM 0x09e6, RAM 0x0d17'
like "the firmware's origin from firmware_source" "$out" "firmware: +from the board's EEPROM"
ok "save works with it" with_dir /tmp/pre-header sentral-warmstart save --force --file /tmp/pre-header.ws
is "saving its 140 bytes" "$(file_payload_words /tmp/pre-header.ws)" \
	"$(blob_words </tmp/pre-header/calibration_data)"

ok "the real directory back: status exits 0" sentral-warmstart status
unit=$SENTRAL_ROOT/tools/sentral-warmstart/systemd/sentral-warmstart@.service.in
like "the watcher's unit does not restart on 69 or 78" "$(cat "$unit")" \
	"(^|"$'\n'")RestartPreventExitStatus=69 78($|"$'\n'")"
like "and gives up after a burst of failed starts" "$(cat "$unit")" \
	"StartLimitIntervalSec=[0-9]+min"$'\n'"StartLimitBurst=[0-9]+"

done_testing
