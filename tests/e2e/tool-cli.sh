#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# sentral-warmstart's command line with the manners of i2c-tools and
# coreutils (issue 33, item 3):
# - --help and --version win over the rest of the line, and exit 0; each
#   command's help lists its options, within 80 columns;
# - numbers are decimal, hexadecimal only after 0x;
# - --i2c takes a bus number, the adapter's name or a path, and each gives
#   the chip the same key; a name no adapter has, or several have, lists
#   the buses;
# - addresses from 0x08 to 0x77, and their errors, in hexadecimal;
# - a broken link under /sys/bus/iio/devices, a missing directory and one
#   the user may not read are told apart;
# - show and key print JSON.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "the driver is bound" test -n "$DEV"
bus=$(sim_bus)
name=$(cat "/sys/class/i2c-dev/i2c-$bus/name")
is "the simulator's adapter is named sentral-sim" "$name" sentral-sim
driver_key=$(sentral-warmstart key)

# --help and --version win, anywhere on the line, and exit 0.
out=$(sentral-warmstart --version extra 2>&1)
is "--version extra: exit 0" $? 0
like "and the version" "$out" '^sentral-warmstart [0-9]'
out=$(sentral-warmstart status --bogus --timeout x --help 2>&1)
is "status --bogus --timeout x --help: exit 0" $? 0
like "status's help" "$out" '^Usage: sentral-warmstart .* status \[--file F\] \[--json\]'
out=$(sentral-warmstart show -- --help 2>&1)
is "after --, --help is show's FILE: exit 66" $? 66
out=$(sentral-warmstart accel-cal --help)
like "accel-cal --help: its synopsis has --max-score" \
	"$(echo "$out" | sed '/^$/q')" 'accel-cal .*\[--max-score S\]'
like "and its options --max-score, described" "$out" \
	$'\n      --max-score S     acceptable score'
wide=
for c in "" status save restore calibrate accel-cal show key watch import-board; do
	# shellcheck disable=SC2086
	wide+=$(sentral-warmstart $c --help | awk -v c="${c:-all}" \
		'length > 80 { print c ": " length ": " $0 }')
done
is "every help within 80 columns" "$wide" ""
sentral-warmstart --help >/dev/full 2>/dev/null
is "--help into a full disk: exit 74" $? 74
out=$(sentral-warmstart status --force 2>&1)
is "status --force without --i2c: exit 64" $? 64
like "said so, and what to try" "$out" \
	"--force is an option of 'status' only with --i2c.*Try 'sentral-warmstart status --help'"

# Numbers: decimal, a leading 0 no octal; hex after 0x.
out=$(sentral-warmstart calibrate --timeout 08 --target-score 101 2>&1)
is "--timeout 08 is taken (the error is the next option's): exit 64" $? 64
like "naming --target-score" "$out" "--target-score: '101' is out of range \(0 to 100\)"
# (bounded: a tool that took "+5" would watch for ever)
out=$(timeout 10 sentral-warmstart watch --poll +5 2>&1)
like "--poll +5: refused, naming the option" "$out" \
	"--poll: '\+5' is not a number \(decimal, or hexadecimal after 0x\)"

# --i2c BUS: a number, a name, a path; the key is the driver's whatever the form.
for form in "$bus" "0$bus" "$name" "/dev/i2c-$bus"; do
	out=$(sentral-warmstart --i2c "$form" --force key 2>&1)
	is "--i2c '$form': the driver's key" "$out" "$driver_key"
done
mknod /tmp/i2c-node c 89 "$bus"
is "--i2c a node of another name: the same key" \
	"$(sentral-warmstart --i2c /tmp/i2c-node --force key 2>&1)" "$driver_key"
json=$(sentral-warmstart --i2c "$name" --force status --json)
is "status over --i2c $name: exit 0" $? 0
like "the i2c backend on /dev/i2c-$bus" "$json" \
	"^\\{\"device\":\"/dev/i2c-$bus@0x28\",\"backend\":\"i2c\","
out=$(sentral-warmstart --i2c sentral --force status 2>&1)
is "a name no adapter has (a prefix is no match): exit 69" $? 69
like "listing the buses" "$out" \
	"--i2c 'sentral': no bus of that name; the buses are .*$bus 'sentral-sim'"
out=$(sentral-warmstart --i2c 4242 --force status 2>&1)
is "a bus number without a node: exit 69" $? 69
like "naming the node" "$out" "/dev/i2c-4242: No such file or directory"
out=$(sentral-warmstart --i2c 1048576 status 2>&1)
is "a bus number past i2c-dev's minors: exit 64" $? 64
# Two adapters of one name, in a mount namespace of this command's own.
out=$(unshare -m sh -c '
	mount -t tmpfs cli /sys/class/i2c-dev &&
	mkdir /sys/class/i2c-dev/i2c-'"$bus"' /sys/class/i2c-dev/i2c-99 &&
	echo sentral-sim >/sys/class/i2c-dev/i2c-'"$bus"'/name &&
	echo sentral-sim >/sys/class/i2c-dev/i2c-99/name &&
	exec sentral-warmstart --i2c sentral-sim --force status' 2>&1)
is "a name two adapters have: exit 69" $? 69
like "which, and what to do" "$out" \
	"--i2c 'sentral-sim': 2 buses have that name \($bus 'sentral-sim', 99 'sentral-sim'\): give the bus number instead"

# Addresses: 0x08 to 0x77, the errors in hexadecimal.
out=$(sentral-warmstart --i2c "$bus" --address 0x80 status 2>&1)
is "--address 0x80: exit 64" $? 64
like "out of range, in hex" "$out" "--address: 0x80 is out of range \(0x08-0x77\)"
out=$(sentral-warmstart --i2c "$bus" --address 128 status 2>&1)
like "--address 128: in hex too" "$out" "--address: 128 \(0x80\) is out of range \(0x08-0x77\)"
out=$(sentral-warmstart --i2c "$bus" --address 7 status 2>&1)
like "--address 7, reserved: refused" "$out" "--address: 7 \(0x07\) is out of range \(0x08-0x77\)"
out=$(sentral-warmstart --i2c "$bus" --address 0x29 --force status 2>&1)
is "--address 0x29, nothing there: exit 69" $? 69
like "said in hex" "$out" "no device answers at 0x29"
out=$(sentral-warmstart --i2c "$bus" --address 40 --force status --json)
is "--address 40 is 0x28: exit 0" $? 0
like "the chip at 0x28" "$out" "\"device\":\"/dev/i2c-$bus@0x28\""

# Why the IIO devices cannot be listed, each in a mount namespace.
out=$(unshare -m sh -c '
	mount -t tmpfs cli /sys/bus/iio/devices &&
	ln -s ../../../devices/gone/iio:device0 /sys/bus/iio/devices/iio:device0 &&
	exec sentral-warmstart status' 2>&1)
is "a broken link under /sys/bus/iio/devices: exit 69" $? 69
like "named as such" "$out" \
	"iio:device0: /sys/bus/iio/devices/iio:device0 is a broken link"
out=$(unshare -m sh -c '
	mount -t tmpfs cli /sys/bus/iio && exec sentral-warmstart status' 2>&1)
is "no /sys/bus/iio/devices: exit 69" $? 69
like "said to be missing" "$out" \
	"no IIO devices at all \(/sys/bus/iio/devices is missing\)"
out=$(unshare -m sh -c '
	mount -t tmpfs -o mode=0700 cli /sys/bus/iio/devices &&
	exec setpriv --reuid=65534 --regid=65534 --clear-groups \
		sentral-warmstart status' 2>&1)
is "a directory the user may not read: exit 69" $? 69
like "said so" "$out" \
	"cannot list the IIO devices: /sys/bus/iio/devices: Permission denied"
ok "with the real sysfs, status works" sentral-warmstart status

# show --json and key --json.
like "key --help: --json" "$(sentral-warmstart key --help)" $'\n      --json  '
ok "save a file" sentral-warmstart save --force --file /tmp/cli.ws
json=$(sentral-warmstart show --json /tmp/cli.ws)
is "show --json: exit 0" $? 0
is "one line" "$(echo "$json" | wc -l)" 1
is "its members, the parameters as the file holds them" "$(python3 -c '
import json, sys
d = json.loads(sys.argv[1])
print(d["file"], d["version"], d["size"], d["product_id"], d["judgement"],
      len(d["parameters"]), d["parameters"][26]["number"],
      "accel_lsb" in d["parameters"][26], "accel_lsb" in d["parameters"][0])
print(" ".join("0x%08x" % p["raw"] for p in d["parameters"]))' "$json")" \
	"/tmp/cli.ws 2 176 128 $(sentral-warmstart show /tmp/cli.ws |
		sed -n 's/^judgement: *\([a-z]*\) .*/\1/p') 35 27 True False
$(file_payload_words /tmp/cli.ws | sed 's/ $//')"
truncate -s 150 /tmp/cli.ws
out=$(sentral-warmstart show --json /tmp/cli.ws 2>/dev/null)
is "a refused file: exit 65" $? 65
is "and nothing on standard output" "$out" ""
json=$(sentral-warmstart key --json)
is "key --json: exit 0" $? 0
is "device, backend, key, unit and file" "$json" \
	"{\"device\":\"$(basename "$DEV")\",\"backend\":\"driver\",\"key\":\"$driver_key\",\"unit\":\"$(systemd-escape "$driver_key" | sed 's/\\/\\\\/g')\",\"file\":\"/var/lib/sentral-warmstart/$driver_key.ws\"}"
json=$(sentral-warmstart --i2c "$bus" --force key --json)
like "over --i2c: the i2c backend, the same key" "$json" \
	"^\\{\"device\":\"/dev/i2c-$bus@0x28\",\"backend\":\"i2c\",\"key\":\"$driver_key\","
out=$(sentral-warmstart key --json --udev 2>&1)
is "key --json --udev: exit 64" $? 64

done_testing
