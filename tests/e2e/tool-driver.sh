#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# sentral-warmstart against the em7180 driver on the simulated chip: status,
# save policy, guided calibration, save, restore after a power cycle, every
# refusal of a bad file with the chip untouched, accel-cal (the seed's
# Table 1 offsets -47, -15, +46), device selection, symlinks; the chip's
# identity comes from the driver's attributes, with i2c-dev out of reach.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
client=$(basename "$(dirname "$(readlink -f "$DEV")")")
bus=$(sim_bus)

out=$(sentral-warmstart status 2>&1)
is "status exits 0" $? 0
like "status names the chip" "$out" "ProductID 0x80, RevisionID 0x02"
echo "$out" | sed 's/^/# /'
json=$(sentral-warmstart status --json)
echo "# $json"
like "status --json" "$json" '^\{"device":"iio:device[0-9]+","backend":"driver",.*"product_id":128,"revision_id":2,'
# Issue 23.6: where the firmware came from, the board's feature sensors
# (the simulated USFS: a barometer at 1000.00 hPa +- 0.50, a thermometer
# at 25.00 C +- 0.20, both at the driver's 25 Hz).
like "status: the firmware came from the board's EEPROM" "$out" \
	"firmware: +from the board's EEPROM"
like "status: the barometer, about 100 kPa, at 25 Hz" "$out" \
	'feature sensors: +pressure (99\.9[5-9]|100\.0[0-5])[0-9] kPa at 25 Hz'
like "status: the thermometer, about 25 C, at 25 Hz" "$out" \
	$'\n +temperature 2[45]\\.[0-9]{2} C at 25 Hz\n'
like "status --json: firmware_source and feature_sensors" "$json" \
	'"ram_version":[0-9]+,"firmware_source":"eeprom","feature_sensors":\[\{"name":"pressure","value":(99\.9[5-9]|100\.0[0-5])[0-9],"unit":"kPa","rate_hz":25\},\{"name":"temperature","value":2[45]\.[0-9]{2},"unit":"C","rate_hz":25\}\],'
is "the driver's firmware_source" "$(cat "$DEV/firmware_source")" eeprom
key=$(echo "$json" | json_field key)
# No udevd here: no ID_PATH, so the adapter (no firmware node) is named by
# its name; never by its number.
is "without udev's database the key is the adapter's name and the address" \
	"$key" adapter-sentral-sim-0x28
is "the key command prints the same" "$(sentral-warmstart key)" "$key"
f=$STATE/$key.ws

# The save policy: nothing worth saving yet.
out=$(sentral-warmstart save 2>&1)
is "save before calibration: the policy says no, exit 0" $? 0
like "and says why" "$out" "not saving .*calibration incomplete"
nok "no file written" test -e "$f"

# (e) accel-cal: the simulator's default bias is the seed's Table 1.
out=$(sentral-warmstart accel-cal --samples 32 2>&1)
is "accel-cal exits 0" $? 0
echo "$out" | sed 's/^/# /'
is "calibbias x y z" "$(cat "$DEV"/in_accel_{x,y,z}_calibbias | tr '\n' ' ')" "-47 -15 46 "
is "parameters 27..29 are Table 1 bit for bit" \
	"$(sim_param 27) $(sim_param 28) $(sim_param 29)" "$TABLE1"
like "output now 0 0 2048 within noise" "$out" \
	'output now -?[0-9]\.[0-9] -?[0-9]\.[0-9] 20[45][0-9]\.[0-9] LSB'
# Nothing saved yet: the offsets go with the chip's blob as it is.
like "accel-cal saves the offsets by itself" "$out" \
	"saved iio:device[0-9]+ calibration to $f: the chip holds accel offsets and no usable file does"
is "the file holds Table 1" "$(words 27 29 "$(file_payload_words "$f")")" "$TABLE1 "
is "and the status it was saved with (incomplete)" "$(od -An -tu1 -j16 -N1 "$f" | tr -d ' ')" 0

# Guided calibration: still (gyro bias), then figure-8 (simulated motion).
knob gbias_period_ms 200
knob cal_duration_ms 1500
(sleep 1; knob motion 1) &
out=$(sentral-warmstart calibrate --timeout 30 2>&1)
rc=$?
wait
knob motion 0
is "calibrate exits 0" $rc 0
echo "$out" | sed 's/^/# /'
like "it waited for the gyro bias" "$out" "Gyro bias learned"
like "plain progress lines (no terminal)" "$out" "calibrate: status 3/3, score [0-9.]+%"
like "and saved" "$out" "saved iio:device[0-9]+ calibration to $f"
ok "file exists" test -f "$f"
is "file mode 0600" "$(stat -c %a "$f")" 600
is "state dir mode 0700" "$(stat -c %a "$STATE")" 700
is "no temporary file left, only the writers' lock file and the driver's files" \
	"$(ls -A "$STATE" | tr '\n' ' ')" ".$key.ws.lock $key.ws firmware "
is "the lock file is 0600" "$(stat -c %a "$STATE/.$key.ws.lock")" 600
ok "show accepts it" sentral-warmstart show "$f"
# The identity comes from the driver's attributes, not from i2c-dev.
is "the file's identity is the driver's attributes" \
	"$(sentral-warmstart show "$f" |
		sed -n 's/^\(ProductID\|RevisionID\|ROM version\|RAM version\): *//p' |
		tr '\n' ' ')" \
	"$(cat "$DEV"/{product_id,revision_id,rom_version,ram_version} | tr '\n' ' ')"
# i2c-dev is built in here: hide its nodes (/dev/null bound over them).
no_i2c_dev() {
	unshare -m sh -c 'for d in /dev/i2c-*; do
		mount --bind /dev/null "$d" || exit 1; done; exec "$@"' sh "$@"
}
ok "status without i2c-dev" no_i2c_dev sentral-warmstart status
ok "save without i2c-dev" no_i2c_dev sentral-warmstart save --force --file /tmp/noi2c.ws
ok "restore without i2c-dev" no_i2c_dev sentral-warmstart restore --file /tmp/noi2c.ws
like "show names the parameters" "$(sentral-warmstart show "$f")" "18  mcoeffs\[1\]"
payload=$(file_payload_words "$f")
is "saved magnetic coefficients equal the chip's" \
	"$(words 18 23 "$payload")" "$(words 18 23 "$(sim_ws_params)")"
is "saved accel offsets are Table 1" "$(words 27 29 "$payload")" "$TABLE1 "

# Restore after a power cycle: calibrated at once, without motion.
knob gbias_period_ms 600000
ok "replug: unbind, power cycle, bind" replug "$client"
DEV=$(em7180_dir)
is "power cycle lost the calibration" "$(cal_status)" 0
out=$(sentral-warmstart restore 2>&1)
is "restore exits 0" $? 0
like "restore reports status 3" "$out" "restored .* status 3"
is "in_magn_calibration_auto_status 3 without motion" "$(cal_status)" 3
is "chip parameters 1..35 equal the saved payload" "$(sim_ws_params)" "$payload"
is "chip blob via sysfs equals the saved payload" \
	"$(blob_words <"$DEV/calibration_data")" "$payload"
is "transfer mode ended" "$(dbg_get state transfer)" 0
is "algorithm running" "$(dbg_get state running)" 1

# Bad files are refused, naming the check, and the chip is not touched.
check_refused() {
	local what=$1 file=$2 before out rc
	before=$(dbg_get stats params_served)
	out=$(sentral-warmstart restore --file "$file" 2>&1)
	rc=$?
	is "$what: exit 65" $rc 65
	like "$what: message names the check" "$out" "refused: $what"
	is "$what: no parameter transferred" "$(dbg_get stats params_served)" "$before"
}
cp "$f" /tmp/bad.ws && flip_byte /tmp/bad.ws 0
check_refused "wrong magic" /tmp/bad.ws
cp "$f" /tmp/bad.ws && flip_byte /tmp/bad.ws 8
check_refused "unknown version" /tmp/bad.ws
cp "$f" /tmp/bad.ws && flip_byte /tmp/bad.ws 100
check_refused "bad CRC" /tmp/bad.ws
head -c 100 "$f" >/tmp/bad.ws
check_refused "truncated" /tmp/bad.ws
cp "$f" /tmp/bad.ws && flip_byte /tmp/bad.ws 28
check_refused "payload size" /tmp/bad.ws
# A NaN with a valid CRC, built with the tool's own layout.
python3 - "$f" /tmp/bad.ws <<'EOF' && check_refused "non-finite float" /tmp/bad.ws
import sys, zlib, struct
b = bytearray(open(sys.argv[1], 'rb').read())
b[32 + 4 * 19:32 + 4 * 20] = struct.pack('<I', 0x7fc00000)
b[172:176] = struct.pack('<I', zlib.crc32(bytes(b[:172])))
open(sys.argv[2], 'wb').write(b)
EOF
# A firmware update: the driver reads the new RAM version when it binds.
ram=$(cat "$SIM_DBG/ram_version")
knob ram_version 0x0bad
ok "replug with a new firmware" replug "$client"
DEV=$(em7180_dir)
is "ram_version shows the new firmware" "$(cat "$DEV/ram_version")" 0x0bad
check_refused "RAM version mismatch" "$f"
out=$(sentral-warmstart restore --force 2>&1)
is "--force restores across a RAM version change" $? 0
knob ram_version "$ram"
ok "replug with the old firmware" replug "$client"
DEV=$(em7180_dir)
is "ram_version shows the old firmware" "$(cat "$DEV/ram_version")" "$ram"
ok "restore after the replug" sentral-warmstart restore
out=$(sentral-warmstart restore --file /tmp/missing.ws 2>&1)
is "missing file: exit 66" $? 66
ok "missing file with --if-present: exit 0" sentral-warmstart restore --if-present --file /tmp/missing.ws

# Never through a symlink.
ln -s /tmp/victim.ws "$STATE/link.ws"
out=$(sentral-warmstart save --force --file "$STATE/link.ws" 2>&1)
is "save through a symlink refused: exit 77" $? 77
nok "symlink target not created" test -e /tmp/victim.ws
rm -f "$STATE/link.ws"

# The policy keeps a good file: same score saves, a worse one does not.
ok "save again at the same score" sentral-warmstart save
python3 - "$f" <<'EOF'
import sys, zlib, struct
b = bytearray(open(sys.argv[1], 'rb').read())
b[18:20] = struct.pack('<H', 32768 + 300)	# the file now claims 0.916 %
b[172:176] = struct.pack('<I', zlib.crc32(bytes(b[:172])))
open(sys.argv[1], 'wb').write(b)
EOF
out=$(sentral-warmstart save 2>&1)
is "a worse calibration does not replace a good file: exit 0" $? 0
like "and says why" "$out" "worse than the saved file's 0.916%"
is "the file is kept" "$(od -An -tu2 -j18 -N2 "$f" | tr -d ' ')" 33068
ok "save --force replaces it" sentral-warmstart save --force
is "with the chip's score" "$(od -An -tu2 -j18 -N2 "$f" | tr -d ' ')" 33653

# --state-dir: created 0700 when missing.
ok "save --state-dir /tmp/sd" sentral-warmstart --state-dir /tmp/sd save
is "file in the other directory" "$(stat -c %a "/tmp/sd/$key.ws")" 600
is "directory created 0700" "$(stat -c %a /tmp/sd)" 700

# While buffered capture runs, the driver refuses blob transfers (-EBUSY).
echo 1 >"$DEV/buffer0/in_accel_x_en"
if echo 1 >"$DEV/buffer0/enable"; then
	out=$(sentral-warmstart restore 2>&1)
	is "restore during buffered capture: exit 74" $? 74
	like "and says what to stop" "$out" \
		"a buffer is enabled on $(basename "$DEV") \(a program is streaming from it, or one that exited without disabling it\): stop it, or write 0 to /sys/bus/iio/devices/$(basename "$DEV")/buffer/enable"
	out=$(sentral-warmstart accel-cal --samples 8 2>&1)
	is "accel-cal during buffered capture: exit 74" $? 74
	like "with the same hint" "$out" "write 0 to /sys/bus/iio/devices/$(basename "$DEV")/buffer/enable"
	out=$(sentral-warmstart save --force --file /tmp/streaming.ws 2>&1)
	is "save reads while it streams: exit 0" $? 0
	ok "and wrote a valid file" sentral-warmstart show /tmp/streaming.ws
	out=$(sentral-warmstart status 2>&1)
	is "status reads while it streams: exit 0" $? 0
	like "the barometer without a value (EBUSY), its rate still" "$out" \
		'feature sensors: +pressure \(no value while a buffer streams\) at 25 Hz'
	like "--json: its value null" "$(sentral-warmstart status --json)" \
		'"feature_sensors":\[\{"name":"pressure","value":null,"unit":"kPa","rate_hz":25\},\{"name":"temperature","value":null,'
	echo 0 >"$DEV/buffer0/enable"
else
	ok "buffer could not be enabled (skipped the -EBUSY check)" false
fi
echo 0 >"$DEV/buffer0/in_accel_x_en"
ok "restore works again afterwards" sentral-warmstart restore

# Device selection.
ok "--device by IIO name" sentral-warmstart --device "$(basename "$DEV")" status
ok "--device by client name" sentral-warmstart --device "$client" status
out=$(sentral-warmstart --device iio:device99 status 2>&1)
is "--device unknown: exit 69" $? 69
ok "--device by key" sentral-warmstart --device "$key" status
out=$(sentral-warmstart --device iio:device99 save --if-present 2>&1)
is "save --if-present of a device that is gone: exit 0" $? 0
like "and says so" "$out" "nothing to save"
out=$(sentral-warmstart --i2c /dev/i2c-"$bus" status 2>&1)
is "--i2c with the driver bound: exit 69" $? 69
like "and says so politely" "$out" "a kernel driver is bound to $client"
out=$(sentral-warmstart bogus 2>&1)
is "usage error: exit 64" $? 64

# A board without feature sensors (FeatureFlags 0) says "none".
ok "unbind" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/unbind"
knob feature_flags 0
ok "bind with FeatureFlags 0" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/bind"
ok "bound" wait_for 5 em7180_dir
like "status: feature sensors none" "$(sentral-warmstart status 2>&1)" \
	$'\nfeature sensors: +none\n'
like "--json: an empty list" "$(sentral-warmstart status --json)" \
	'"firmware_source":"eeprom","feature_sensors":\[\],'

# A board without an EEPROM, its firmware uploaded by the driver from an
# image of tests/refhost/mkfw.py.
T=$(mktemp -d /tmp/tool-driver.XXXXXX)
ok "an image" sh -c "/usr/bin/python3 $SENTRAL_ROOT/tests/refhost/mkfw.py $T/em7180.fw --ram-version 0x0e42 >/dev/null"
echo -n "$T" >/sys/module/firmware_class/parameters/path
ok "unbind" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/unbind"
knob feature_flags 5
knob no_eeprom 1
ok "the ROM's search for an EEPROM is over" wait_for 5 sim_ready
ok "bind: the driver uploads the image" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/bind"
DEV=$(em7180_dir)
is "  the firmware is the image's" "$(cat "$DEV/ram_version")" 0x0e42
out=$(sentral-warmstart status 2>&1)
like "status: uploaded by the host" "$out" $'\nfirmware: +uploaded by the host\n'
like "  with its feature sensors" "$out" 'pressure [0-9.]+ kPa at 25 Hz'
like "--json: firmware_source host" "$(sentral-warmstart status --json)" \
	'"firmware_source":"host",'

# Back as tests/uml/run leaves it, with an EEPROM.
ok "unbind" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/unbind"
knob no_eeprom 0
ok "the EEPROM's firmware is loaded" wait_for 5 sim_ready
ok "bind" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/bind"
echo -n "" >/sys/module/firmware_class/parameters/path
rm -rf "$T"
like "status: from the board's EEPROM again" "$(sentral-warmstart status 2>&1)" \
	"firmware: +from the board's EEPROM"

done_testing
