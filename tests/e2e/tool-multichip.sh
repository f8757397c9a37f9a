#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --udev --no-modules
#
# One chip, one key, one file, one unit, with four simulated chips: two on
# adapters of their own and two at the same address behind a mux (which
# udev's ID_PATH cannot tell apart). Each gets its own key, file and unit
# name, saves and restores its own blob across unbind, power cycle and
# bind; a udevadm trigger changes no key and keeps the systemd properties;
# a file saved under an old key moves to the new one once, unless that old
# key was shared; the i2c-dev backend names a chip as the driver does.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

modprobe -d "$SENTRAL_MODROOT" sentral_sim adapters=2 mux_channels=2 &&
	modprobe -d "$SENTRAL_MODROOT" em7180_i2c
udevadm settle --timeout=30

keys="platform-sentral-sim-0x28 platform-sentral-sim-1-0x28
platform-sentral-sim-mux-mux0x70-ch0-0x28 platform-sentral-sim-mux-mux0x70-ch1-0x28"

# The simulator's debugfs directory of the chip with key $1.
dbg_of() {
	case $1 in
	platform-sentral-sim-mux-mux0x70-ch*) local c=${1#*-ch}; echo "sentral-sim-mux-${c%%-*}" ;;
	platform-sentral-sim-1-0x28) echo sentral-sim-1 ;;
	*) echo sentral-sim ;;
	esac
}
# sysfs directory of the em7180 IIO device whose key is $1.
dev_of() {
	local d
	for d in /sys/bus/iio/devices/iio:device*; do
		[ "$(cat "$d/name" 2>/dev/null)" = em7180 ] || continue
		[ "$(sentral-warmstart --device "${d##*/}" key)" = "$1" ] &&
			{ echo "$d"; return 0; }
	done
	return 1
}
client_of() {
	basename "$(dirname "$(readlink -f "$1")")"
}
udev_prop() {
	udevadm info -q property -p "$(readlink -f "$1")" | sed -n "s/^$2=//p"
}

n=$(for d in /sys/bus/iio/devices/iio:device*; do cat "$d/name"; done | grep -cx em7180)
is "four em7180 devices" "$n" 4
got=$(for d in /sys/bus/iio/devices/iio:device*; do
	sentral-warmstart --device "${d##*/}" key; done | sort | tr '\n' ' ')
is "four keys, one per chip: adapter path, mux channel, address" "$got" \
	"$(echo $keys | tr ' ' '\n' | sort | tr '\n' ' ')"
shared=$(for k in $keys; do udev_prop "$(dev_of "$k")" ID_PATH; done | sort -u | wc -l)
is "(udev's ID_PATH alone names only three)" "$shared" 3
for k in $keys; do
	d=$(dev_of "$k")
	is "$k: the rule's key is the tool's" "$(udev_prop "$d" SENTRAL_WARMSTART_KEY)" "$k"
	like "$k: restore ran at probe under its own file" "$(dmesg)" \
		"no saved calibration for ${d##*/} \\($STATE/$k.ws\\)"
done

# Calibrate each, with an accel offset of its own so that the four blobs
# differ, and save each under its key.
i=0
for k in $keys; do
	i=$((i + 1))
	d=$(dev_of "$k")
	SIM_DBG=/sys/kernel/debug/$(dbg_of "$k")
	knob cal_duration_ms 1000
	knob motion 1
	ok "$k: calibrated by simulated motion" wait_for 30 calibrated_good "$d"
	knob motion 0
	knob gbias_period_ms 600000
	echo $((i * 10)) >"$d/in_accel_x_calibbias"
	ok "$k: save" sentral-warmstart --device "$k" save
	ok "$k: saved as $k.ws" test -f "$STATE/$k.ws"
done
is "four files" "$(ls "$STATE" | grep -c '\.ws$')" 4
is "four different blobs" \
	"$(for k in $keys; do file_payload_words "$STATE/$k.ws" | md5sum; done | sort -u | wc -l)" 4

# Unbind, power cycle, bind each: udev restores each its own blob.
for k in $keys; do
	d=$(dev_of "$k")
	client=$(client_of "$d")
	SIM_DBG=/sys/kernel/debug/$(dbg_of "$k")
	echo "$client" >/sys/bus/i2c/drivers/em7180/unbind
	knob power_cycle 1
	wait_for 5 sim_ready
	is "$k: power cycle lost the calibration" "$(dbg_get state cal_status)" 0
	echo "$client" >/sys/bus/i2c/drivers/em7180/bind
	udevadm settle --timeout=10
	d=$(dev_of "$k")
	is "$k: calibration level 4 (stable) after bind, without motion" \
		"$(cat "$d/in_magn_calibration_auto_status")" 4
	is "$k: the chip holds its own file's blob" "$(sim_ws_params)" \
		"$(file_payload_words "$STATE/$k.ws")"
done

# udevadm trigger ("change") on a running system, as if systemd ran: the
# rule runs again, the key and the systemd properties stay.
mkdir -p /run/systemd/system
udevadm trigger --action=change --subsystem-match=iio --subsystem-match=i2c
udevadm settle --timeout=30
for k in $keys; do
	d=$(dev_of "$k")
	ok "$k: after a change event the tool still finds the chip by its key" \
		sentral-warmstart --device "$k" status
	is "$k: the rule's key is unchanged" "$(udev_prop "$d" SENTRAL_WARMSTART_KEY)" "$k"
	unit=$(udev_prop "$d" SYSTEMD_WANTS)
	is "$k: SYSTEMD_WANTS names its plug unit after the key" "$unit" \
		"sentral-warmstart-plug@$(systemd-escape "$k").service"
	is "$k: the device unit's alias names the key" \
		"$(udev_prop "$d" SYSTEMD_ALIAS)" "/sys/subsystem/sentral-warmstart/$k"
	like "$k: still tagged for systemd" "$(udev_prop "$d" CURRENT_TAGS)" ":systemd:"
done
rmdir /run/systemd/system

# Files saved by an older version under udev's ID_PATH move to the new key
# once; the mux chips shared theirs, so it belongs to neither and stays.
k=platform-sentral-sim-1-0x28
mv "$STATE/$k.ws" "$STATE/platform-sentral-sim-1.ws"
out=$(sentral-warmstart --device "$k" restore 2>&1)
is "$k: restore from the old ID_PATH file: exit 0" $? 0
like "$k: says it migrated the file" "$out" \
	"migrated $STATE/platform-sentral-sim-1.ws to $STATE/$k.ws"
ok "$k: the file is under the new key" test -f "$STATE/$k.ws"
nok "$k: and no longer under the old one" test -e "$STATE/platform-sentral-sim-1.ws"
k=platform-sentral-sim-mux-mux0x70-ch0-0x28
mv "$STATE/$k.ws" "$STATE/platform-sentral-sim-mux.ws"
out=$(sentral-warmstart --device "$k" restore --if-present 2>&1)
like "$k: a shared old ID_PATH file is not taken" "$out" "nothing to restore"
ok "$k: it stays where it was" test -f "$STATE/platform-sentral-sim-mux.ws"
# The I2C client's name, the key without udev before, migrates too.
d=$(dev_of "$k")
mv "$STATE/platform-sentral-sim-mux.ws" "$STATE/$(client_of "$d").ws"
out=$(sentral-warmstart --device "$k" restore 2>&1)
like "$k: the old client-name file migrates" "$out" \
	"migrated $STATE/$(client_of "$d").ws to $STATE/$k.ws"

# The i2c-dev backend names a chip behind the mux as the driver does.
k=platform-sentral-sim-mux-mux0x70-ch1-0x28
d=$(dev_of "$k")
client=$(client_of "$d")
echo "$client" >/sys/bus/i2c/drivers/em7180/unbind
udevadm settle --timeout=10
bus=${client%%-*}
is "$k: --i2c /dev/i2c-$bus key is the same" \
	"$(sentral-warmstart --i2c "/dev/i2c-$bus" key)" "$k"
out=$(sentral-warmstart --device "$k" save --if-present 2>&1)
is "$k: the stop action after an unbind: exit 0" $? 0
like "$k: nothing to save" "$out" "nothing to save"
echo "$client" >/sys/bus/i2c/drivers/em7180/bind
udevadm settle --timeout=10

done_testing
