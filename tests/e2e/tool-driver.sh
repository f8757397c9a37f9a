#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# sentral-warmstart against the em7180 driver on the simulated chip, a USFS
# board whose firmware reports the calibration level alone: status (the
# level, whether the chip holds the saved file), the stable rule (saved
# when the magnetometer coefficients moved beyond the tolerance, never
# below level 4, a glitched read an error), guided calibration, save,
# restore after a power cycle (also of a version 1 file), every refusal of
# a bad file with the chip untouched, accel-cal (the seed's Table 1 offsets
# -47, -15, +46), device selection, symlinks; the chip's identity comes
# from the driver's attributes, with i2c-dev out of reach. Then the same
# chip with the application note's layout (the driver finds it at the next
# bind): the score and update flags, the score rule, the gyro bias step of
# calibrate, the stable rule's file restored; and back.
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
like "status: the level, calibrating" "$out" $'\ncalibration level: +2 \\(calibrating\\)\n'
like "status: no score on this firmware" "$out" \
	$'\ncalibration score: +not reported by this firmware \\(saved by the level alone\\)\n'
json=$(sentral-warmstart status --json)
echo "# $json"
like "status --json" "$json" '^\{"device":"iio:device[0-9]+","backend":"driver",.*"product_id":128,"revision_id":2,'
like "status --json: the level, no score, no file" "$json" \
	'"level":2,"level_name":"calibrating","calibration_score":null,"calibration_score_raw":null,"gyro_bias_update":null,"mag_calibration_update":null,.*"saved":null,.*"judgement":null,"restored":null\}$'
# Issue 23.6: where the firmware came from, the board's feature sensors
# (the simulated USFS: a barometer at 1000.00 hPa +- 0.50, a thermometer
# at 25.00 C +- 0.20, both at the driver's 25 Hz).
like "status: the firmware's origin unknown (not in the driver's sysfs)" "$out" \
	"firmware: +unknown \\(not in the em7180 driver's sysfs; its probe line in the kernel log says\\)"
like "status: the barometer, about 100 kPa, at 25 Hz" "$out" \
	'feature sensors: +pressure (99\.9[5-9]|100\.0[0-5])[0-9] kPa at 25 Hz'
like "status: the thermometer, about 25 C, at 25 Hz" "$out" \
	$'\n +temperature 2[45]\\.[0-9]{2} C at 25 Hz\n'
like "status --json: firmware_source and feature_sensors" "$json" \
	'"ram_version":[0-9]+,"firmware_source":null,"feature_sensors":\[\{"name":"pressure","value":(99\.9[5-9]|100\.0[0-5])[0-9],"unit":"kPa","rate_hz":25\},\{"name":"temperature","value":2[45]\.[0-9]{2},"unit":"C","rate_hz":25\}\],'
like "the driver's debugfs says the EEPROM" "$(driver_fw_version)" " eeprom$"
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
like "and says why" "$out" \
	"not saving .*: calibration not stable \(level 2 \(calibrating\); needs 4\): move the device in a figure-8 first"
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
# Nothing saved yet and nothing stable: the offsets go with the first
# stable calibration (checked after calibrate below).
like "accel-cal keeps the offsets for the first stable calibration" "$out" \
	"not saving iio:device[0-9]+ calibration to $f: calibration not stable .*; the chip's accel offsets are saved with its calibration once it is stable"
nok "no file written below level 4" test -e "$f"

# Guided calibration: figure-8 (simulated motion) to level 4; no gyro bias
# step, which needs the update flags this firmware does not report.
knob gbias_period_ms 200
knob cal_duration_ms 1500
(sleep 1; knob motion 1) &
out=$(sentral-warmstart calibrate --timeout 30 2>&1)
rc=$?
wait
knob motion 0
is "calibrate exits 0" $rc 0
echo "$out" | sed 's/^/# /'
nok "no gyro bias step" grep -q "Step 1/2" <<<"$out"
like "plain progress lines (no terminal)" "$out" "calibrate: level 4/4 \(stable\), coverage [0-9]+%"
like "it stops at the first stable calibration" "$out" \
	"Calibration stable: [0-9]+% of the sphere covered\."
like "and saved" "$out" "saved iio:device[0-9]+ calibration to $f: stable, and no usable saved calibration"
ok "file exists" test -f "$f"
is "version 2, level 4, judged stable (2), no score" "$(ws_header "$f")" "2 4 2 0"
is "file mode 0600" "$(stat -c %a "$f")" 600
is "state dir mode 0700" "$(stat -c %a "$STATE")" 700
is "no temporary file left, only the writers' lock file and the driver's files" \
	"$(ls -A "$STATE" | tr '\n' ' ')" ".$key.ws.lock $key.ws firmware "
is "the lock file is 0600" "$(stat -c %a "$STATE/.$key.ws.lock")" 600
ok "show accepts it" sentral-warmstart show "$f"
# The identity comes from calibration_data's header, not from i2c-dev.
is "the file's identity is the driver's" \
	"$(sentral-warmstart show "$f" |
		sed -n 's/^\(ProductID\|RevisionID\|ROM version\|RAM version\): *//p' |
		tr '\n' ' ')" \
	"$(driver_fw_version | awk '{ printf "%s %s %s %s ", $2, $4, $6, $8 }')"
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
out=$(sentral-warmstart status 2>&1)
like "status: level 4" "$out" $'\ncalibration level: +4 \\(stable\\)\n'
like "status: the file, stable, no score" "$out" \
	"saved file: +$f: level 4 \(stable\), no score, saved "
like "status: the chip holds it" "$out" \
	$'\nrestored: +yes: the chip holds the saved calibration \\(parameters 18-23 and 27-29 within 0\\.5 %\\)'
like "status --json: judged stable, restored" "$(sentral-warmstart status --json)" \
	'"level":4,"level_name":"stable",.*"saved":\{"version":2,"level":4,"level_name":"stable","calibration_score":null,"calibration_score_raw":null,"saved_at":[0-9]+\},"judgement":"stable","restored":true\}$'

# Restore after a power cycle: calibrated at once, without motion.
knob gbias_period_ms 600000
ok "replug: unbind, power cycle, bind" replug "$client"
DEV=$(em7180_dir)
is "power cycle lost the calibration: level 2 (calibrating)" "$(cal_level)" 2
is "(the chip's own calibration status 0)" "$(dbg_get state cal_status)" 0
out=$(sentral-warmstart status 2>&1)
like "status: the chip does not hold the file" "$out" \
	$'\nrestored: +no: parameter 18 \\(mcoeffs\\[1\\]\\) is 1 on the chip, 0\\.9[0-9]* in the file'
like "status --json: restored false" "$(sentral-warmstart status --json)" '"judgement":"stable","restored":false\}$'
out=$(sentral-warmstart restore 2>&1)
is "restore exits 0" $? 0
like "restore reports level 4 and what the file held" "$out" \
	"restored iio:device[0-9]+ calibration from $f: level 4 \(stable\) \(saved: level 4 \(stable\), no score\)"
is "in_magn_calibration_auto_status 4 (stable) without motion" "$(cal_level)" 4
like "status: restored: yes" "$(sentral-warmstart status)" \
	$'\nrestored: +yes: the chip holds the saved calibration'
is "chip parameters 1..35 equal the saved payload" "$(sim_ws_params)" "$payload"
is "chip blob via sysfs equals the saved payload" \
	"$(blob_words <"$DEV/calibration_data")" "$payload"
is "transfer mode ended" "$(dbg_get state transfer)" 0
is "algorithm running" "$(dbg_get state running)" 1

# Bad files are refused, naming the check, and the chip is not touched.
# check_refused CHECK FILE [CASE]: restore of FILE refused by CHECK.
# check_refused WHAT FILE [DESC [READS]]: READS parameters may be read (the
# identity the driver refused, named from one read of the blob), none
# written.
check_refused() {
	local what=$1 file=$2 desc=${3:-$1} reads=${4:-0} before out rc params
	before=$(dbg_get stats params_served)
	params=$(sim_ws_params)
	out=$(sentral-warmstart restore --file "$file" 2>&1)
	rc=$?
	is "$desc: exit 65" $rc 65
	like "$desc: message names the check" "$out" "refused: $what"
	is "$desc: $reads parameters transferred" "$(dbg_get stats params_served)" \
		$((before + reads))
	is "$desc: the chip's parameters unchanged" "$(sim_ws_params)" "$params"
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
# With a valid CRC: a NaN in parameter 20, header fields out of range.
ws_edit "$f" /tmp/bad.ws '108:<I:0x7fc00000' && check_refused "non-finite float" /tmp/bad.ws
ws_edit "$f" /tmp/bad.ws '16:<B:5' &&
	check_refused "invalid header field" /tmp/bad.ws "level 5"
ws_edit "$f" /tmp/bad.ws '17:<B:3' &&
	check_refused "invalid header field" /tmp/bad.ws "judgement 3"
ws_edit "$f" /tmp/bad.ws '18:<H:33653' &&
	check_refused "invalid header field" /tmp/bad.ws "a score in a file judged stable"
# A firmware update: the driver reads the new RAM version when it binds.
ram=$(cat "$SIM_DBG/ram_version")
knob ram_version 0x0bad
ok "replug with a new firmware" replug "$client"
DEV=$(em7180_dir)
is "the driver holds the new firmware" "$(driver_ram_version)" 0x0bad
# The driver refuses the file's identity; one read of the blob names it
check_refused "RAM version mismatch" "$f" "" 35
like "  saved on another chip or firmware" "$(sentral-warmstart restore --file "$f" 2>&1)" \
	"RAM version mismatch \\(file $ram, chip 0x0bad\\): saved on another chip or firmware"
out=$(sentral-warmstart restore --force 2>&1)
is "--force restores across a RAM version change" $? 0
knob ram_version "$ram"
ok "replug with the old firmware" replug "$client"
DEV=$(em7180_dir)
is "the driver holds the old firmware" "$(driver_ram_version)" "$ram"
ok "restore after the replug" sentral-warmstart restore

# A version 1 file (the application note's status and score, before the
# level) restores on this firmware too: its status 3 counts as stable.
ws_v1 "$f" /tmp/v1.ws
like "show reads version 1" "$(sentral-warmstart show /tmp/v1.ws)" \
	$'version 1, .*\ncalibration status: +3 \\(complete: stable\\)\njudgement: +score'
ok "replug" replug "$client"
DEV=$(em7180_dir)
is "the calibration lost: level 2" "$(cal_level)" 2
out=$(sentral-warmstart restore --file /tmp/v1.ws 2>&1)
is "a version 1 file restores: exit 0" $? 0
like "saying what it held" "$out" \
	"restored iio:device[0-9]+ calibration from /tmp/v1.ws: level 4 \(stable\) \(saved: version 1: status 3, score 2\.70[01]%\)"
is "level 4 without motion" "$(cal_level)" 4
is "the chip holds its parameters" "$(sim_ws_params)" "$payload"
out=$(sentral-warmstart restore --file /tmp/missing.ws 2>&1)
is "missing file: exit 66" $? 66
ok "missing file with --if-present: exit 0" sentral-warmstart restore --if-present --file /tmp/missing.ws

# Never through a symlink.
ln -s /tmp/victim.ws "$STATE/link.ws"
out=$(sentral-warmstart save --force --file "$STATE/link.ws" 2>&1)
is "save through a symlink refused: exit 77" $? 77
nok "symlink target not created" test -e /tmp/victim.ws
rm -f "$STATE/link.ws"

# The stable rule: a calibration the file holds is not written again;
# magnetometer coefficients beyond the tolerance are.
cp "$f" /tmp/before.ws
out=$(sentral-warmstart save 2>&1)
is "save of the calibration the file holds: exit 0" $? 0
like "not written again, and why" "$out" \
	"not saving .*: stable, and the magnetometer coefficients \(parameters 18-23\) are within 0\.5 % of the saved file's"
ok "the file is untouched" cmp "$f" /tmp/before.ws
# Parameter 21 (a hard-iron offset, 25 uT) 0.1 uT off in the file: 0.4 %.
ws_edit /tmp/before.ws "$f" '112:<f:+=0.1'
cp "$f" /tmp/within.ws
out=$(sentral-warmstart save 2>&1)
like "0.4 % off: within the tolerance, not saved" "$out" "not saving .*within 0\.5 % of the saved file's"
ok "the file is untouched" cmp "$f" /tmp/within.ws
# 2 uT off (8 %): the chip's calibration replaces the file's.
ws_edit /tmp/before.ws "$f" '112:<f:+=2.0'
out=$(sentral-warmstart save 2>&1)
like "2 uT off: saved, saying which moved" "$out" \
	"saved iio:device[0-9]+ calibration to $f: stable, and parameter 21 \(mcoeffs\[4\]\) moved from the saved file's by more than 0\.5 %"
is "the file holds the chip's coefficients" \
	"$(words 18 23 "$(file_payload_words "$f")")" "$(words 18 23 "$(sim_ws_params)")"

# Below level 4 nothing is saved, not even a calibration that differs from
# the file's; a glitched read is an error. (The driver serves a state read
# within 500 ms from its copy: each change waits that long.)
ws_edit "$f" /tmp/differs.ws '112:<f:+=2.0'
cp /tmp/differs.ws "$f"
knob algo_status_or 0x20
sleep 0.6
is "AlgorithmStatus bit 5: level 1" "$(cal_level)" 1
out=$(sentral-warmstart save 2>&1)
is "unreliable sensor data: save exits 0" $? 0
like "not saving, and why" "$out" \
	"not saving .*: calibration not stable \(level 1 \(unreliable sensor data\); needs 4\): the sensor data is unreliable"
ok "the file is untouched" cmp "$f" /tmp/differs.ws
knob algo_status_or 0
knob mag_transient 1
sleep 0.6
is "a magnetic transient: level 3" "$(cal_level)" 3
out=$(sentral-warmstart save 2>&1)
is "a magnetic transient: save exits 0" $? 0
like "not saving, and why" "$out" \
	"not saving .*: calibration not stable \(level 3 \(stable with a magnetic transient\); needs 4\): a magnetic transient: keep the device away from magnets and steel"
ok "the file is untouched" cmp "$f" /tmp/differs.ws
knob mag_transient 0
knob algo_status_or 0xc0
sleep 0.6
out=$(sentral-warmstart save 2>&1)
is "a glitched read (AlgorithmStatus bits 7:6): save exits 74" $? 74
like "an error naming the glitch" "$out" \
	"error: iio:device[0-9]+: reading in_magn_calibration_auto_status: Input/output error \(AlgorithmStatus read with a reserved bit set: a glitched read, not trusted\)"
ok "the file is untouched" cmp "$f" /tmp/differs.ws
out=$(sentral-warmstart status 2>&1)
is "status of a glitched read: exit 74" $? 74
knob algo_status_or 0
sleep 0.6
is "level 4 again" "$(cal_level)" 4
out=$(sentral-warmstart save --force 2>&1)
is "save --force: exit 0" $? 0
like "saying so" "$out" "saved iio:device[0-9]+ calibration to $f: forced \(level 4 \(stable\)\)"
is "the file holds the chip's coefficients" \
	"$(words 18 23 "$(file_payload_words "$f")")" "$(words 18 23 "$(sim_ws_params)")"
# restore waits for level 3 or 4 after a file saved stable: a magnetic
# transient is no failure (the coefficients are taken), unreliable sensor
# data is.
knob mag_transient 1
out=$(sentral-warmstart restore 2>&1)
is "restore in a magnetic transient: exit 0" $? 0
like "at level 3" "$out" "restored iio:device[0-9]+ calibration from $f: level 3 \(stable with a magnetic transient\)"
knob mag_transient 0
knob algo_status_or 0x20
out=$(sentral-warmstart restore 2>&1)
is "restore with unreliable sensor data: exit 75" $? 75
like "saying at which level" "$out" \
	"wrote $f \(level 4 \(stable\), no score\) but the calibration level is 1 \(unreliable sensor data\), not 4 \(stable\)"
knob algo_status_or 0
sleep 0.6

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

# The application note's layout: the driver finds it at the next bind (the
# chip powered off, as after a firmware change), and the tool judges by the
# score. The file saved by the stable rule restores here too.
knob appnote_layout 1
ok "replug with the application note's layout" replug "$client"
DEV=$(em7180_dir)
out=$(sentral-warmstart status 2>&1)
like "status: the score and update flags" "$out" \
	$'\ncalibration level: +2 \\(calibrating\\)\ncalibration score: +50\\.000%\ngyro bias update: +[01]\nmag cal update: +[01]\n'
like "status --json: the score" "$(sentral-warmstart status --json)" \
	'"level":2,"level_name":"calibrating","calibration_score":50\.000,"calibration_score_raw":49152,"gyro_bias_update":[01],"mag_calibration_update":[01],'
out=$(sentral-warmstart restore 2>&1)
is "the stable rule's file restores: exit 0" $? 0
like "with the chip's score, and what the file held" "$out" \
	"restored iio:device[0-9]+ calibration from $f: level 4 \(stable\), score 2\.70[0-9]% \(saved: level 4 \(stable\), no score\)"
is "level 4 without motion" "$(cal_level)" 4
is "the chip holds the file's parameters" "$(sim_ws_params)" "$(file_payload_words "$f")"
# The score rule saves an acceptable score over a file that has none.
out=$(sentral-warmstart save 2>&1)
like "the score rule: saved over the file without a score" "$out" \
	"saved iio:device[0-9]+ calibration to $f: score 2\.70[0-9]% is within the limit 5\.000%"
is "judged by the score, raw 33653 (2.700 %)" "$(ws_header "$f")" "2 4 1 33653"
# The policy keeps a good file: same score saves, a worse one does not.
out=$(sentral-warmstart save 2>&1)
like "save again at the same score" "$out" "saved .*: score 2\.70[0-9]% is within the limit"
ws_edit "$f" "$f" '18:<H:33068'	# the file now claims 0.916 %
out=$(sentral-warmstart save 2>&1)
is "a worse calibration does not replace a good file: exit 0" $? 0
like "and says why" "$out" "worse than the saved file's 0.916%"
is "the file is kept" "$(od -An -tu2 -j18 -N2 "$f" | tr -d ' ')" 33068
ok "save --force replaces it" sentral-warmstart save --force
is "with the chip's score" "$(od -An -tu2 -j18 -N2 "$f" | tr -d ' ')" 33653
# calibrate: the gyro bias first (the update flags), then the figure-8 to
# the target score.
knob gbias_period_ms 200
ok "replug: uncalibrated" replug "$client"
(sleep 1; knob motion 1) &
out=$(sentral-warmstart calibrate --timeout 30 --file /tmp/score.ws 2>&1)
rc=$?
wait
knob motion 0
knob gbias_period_ms 600000
is "calibrate with a score exits 0" $rc 0
echo "$out" | sed 's/^/# /'
like "it waited for the gyro bias" "$out" "Step 1/2: keep the device still.*Gyro bias learned"
like "progress lines with the score" "$out" "calibrate: level 4/4 \(stable\), score [0-9.]+%, best [0-9.]+%"
like "it stops at the target score" "$out" \
	"Calibration stable: score [0-9.]+%, [0-9]+% of the sphere covered\."
like "and saved by the score" "$out" "saved iio:device[0-9]+ calibration to /tmp/score.ws: score [0-9.]+% is within the limit"
# The registers change under the driver (other firmware, no reset seen):
# the score reads ENODATA from the driver's next read, the tool goes by
# the level alone.
ok "restore the score's file" sentral-warmstart restore
knob appnote_layout 0
sleep 0.6
like "status: the score gone, the level stays" "$(sentral-warmstart status 2>&1)" \
	$'\ncalibration level: +4 \\(stable\\)\ncalibration score: +not reported by this firmware'
# Back to the USFS firmware at power-on: the stable rule compares the
# coefficients of a file with a score.
ok "replug with the USFS firmware again" replug "$client"
DEV=$(em7180_dir)
out=$(sentral-warmstart restore 2>&1)
like "the score's file restores: level 4" "$out" \
	"restored iio:device[0-9]+ calibration from $f: level 4 \(stable\) \(saved: level 4 \(stable\), score 2\.70[0-9]%\)"
out=$(sentral-warmstart save 2>&1)
like "and the stable rule keeps it: the coefficients are the same" "$out" \
	"not saving .*: stable, and the magnetometer coefficients \(parameters 18-23\) are within 0\.5 % of the saved file's"
is "the file still has its score" "$(ws_header "$f")" "2 4 1 33653"

# A board without feature sensors (FeatureFlags 0) says "none".
ok "unbind" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/unbind"
knob feature_flags 0
ok "bind with FeatureFlags 0" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/bind"
ok "bound" wait_for 5 em7180_dir
like "status: feature sensors none" "$(sentral-warmstart status 2>&1)" \
	$'\nfeature sensors: +none\n'
like "--json: an empty list" "$(sentral-warmstart status --json)" \
	'"firmware_source":null,"feature_sensors":\[\],'

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
like "  the firmware is the image's, from the host (debugfs)" "$(driver_fw_version)" \
	"RAM 0x0e42 host$"
out=$(sentral-warmstart status 2>&1)
like "status: the chip's RAM version from calibration_data's header" "$out" \
	'chip: +ProductID 0x80, RevisionID 0x02, ROM 0x09e6, RAM 0x0e42'
like "  with its feature sensors" "$out" 'pressure [0-9.]+ kPa at 25 Hz'

# Back as tests/uml/run leaves it, with an EEPROM.
ok "unbind" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/unbind"
knob no_eeprom 0
ok "the EEPROM's firmware is loaded" wait_for 5 sim_ready
ok "bind" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/bind"
echo -n "" >/sys/module/firmware_class/parameters/path
rm -rf "$T"
DEV=$(em7180_dir)
like "from the board's EEPROM again (debugfs)" "$(driver_fw_version)" "RAM 0x0d17 eeprom$"

done_testing
