#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# sentral-warmstart's i2c-dev backend with the em7180 driver unbound: the
# polite refusal while it is bound (the kernel's own check, on the node's
# device number whatever its name), calibrate and save over i2c-dev, a
# power cycle, restore, the chip's parameters equal to the file, transfer
# mode ended on every path (acknowledge never comes, NACK, SIGTERM, SIGHUP)
# with a message saying what a failed restore left in the chip, accel-cal
# writing parameters 27..29 as the seed's Table 1 floats. The level comes
# from AlgorithmStatus, the score only where the registers have the
# application note's layout (the driver's rule), a glitched AlgorithmStatus
# is an error.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "the driver is bound at first" test -n "$DEV"
client=$(basename "$(dirname "$(readlink -f "$DEV")")")
bus=$(sim_bus)
i2c="--i2c /dev/i2c-$bus"

out=$(sentral-warmstart $i2c status 2>&1)
is "refused while the driver is bound: exit 69" $? 69
like "naming the client and the way out" "$out" \
	"a kernel driver is bound to $client .*unbind.*--force"
ok "--force overrides (status only reads)" sentral-warmstart $i2c --force status
driver_key=$(sentral-warmstart key)
# The bus is the node's device number, not a number in its name.
mknod /tmp/i2c-7 c 89 "$bus"
out=$(sentral-warmstart --i2c /tmp/i2c-7 status 2>&1)
is "a node named i2c-7 for bus $bus: still refused, exit 69" $? 69
like "naming the real client" "$out" "a kernel driver is bound to $client "
ln -s "/dev/i2c-$bus" /tmp/sim-bus
out=$(sentral-warmstart --i2c /tmp/sim-bus status 2>&1)
is "a symlink to the node: refused the same way, exit 69" $? 69
like "naming the client" "$out" "a kernel driver is bound to $client "
out=$(sentral-warmstart --i2c /dev/null status 2>&1)
is "not an i2c-dev node: exit 64" $? 64
like "and says so" "$out" "not an i2c-dev character device"

ok "unbind the driver" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/unbind"
nok "no em7180 IIO device any more" em7180_dir
out=$(sentral-warmstart status 2>&1)
is "driver backend without a device: exit 69" $? 69
like "and says to use --i2c" "$out" "no em7180 IIO device found.*--i2c"

json=$(sentral-warmstart $i2c status --json)
is "status over i2c-dev: exit 0" $? 0
like "reads the identity" "$json" '"backend":"i2c",.*"product_id":128,"revision_id":2,'
is "the key over i2c-dev is the driver's key" \
	"$(echo "$json" | json_field key)" "$driver_key"
out=$(sentral-warmstart $i2c --address 0x29 status 2>&1)
is "nothing at 0x29: exit 69" $? 69

# The driver stopped the chip when it was unbound: start it as a host does.
ok "start the chip (rates, run)" chip_run "$bus"
is "algorithm running" "$(dbg_get state running)" 1

# The calibration level from AlgorithmStatus; the score where 0x43-0x4E
# hold the application note's layout, not the USFS board's linear
# acceleration.
out=$(sentral-warmstart $i2c status 2>&1)
like "the level over i2c-dev" "$out" $'\ncalibration level: +2 \\(calibrating\\)\n'
like "no score on the USFS firmware" "$out" $'\ncalibration score: +not reported by this firmware'
like "--json: level, no score" "$(sentral-warmstart $i2c status --json)" \
	'"level":2,"level_name":"calibrating","calibration_score":null,'
knob appnote_layout 1
like "with the application note's layout: the score" "$(sentral-warmstart $i2c status --json)" \
	'"level":2,"level_name":"calibrating","calibration_score":50\.000,"calibration_score_raw":49152,'
knob appnote_layout 0
knob algo_status_or 0xc0
out=$(sentral-warmstart $i2c save --force --file /tmp/glitch.ws 2>&1)
is "a glitched AlgorithmStatus: save exits 74" $? 74
like "saying so" "$out" \
	"AlgorithmStatus \(register 0x38\) reads 0x[cC][0-9a-fA-F], with reserved bits 6-7 set: a glitched read, not trusted"
nok "nothing saved" test -e /tmp/glitch.ws
knob algo_status_or 0x20
like "bit 5: unreliable sensor data (level 1)" "$(sentral-warmstart $i2c status 2>&1)" \
	$'\ncalibration level: +1 \\(unreliable sensor data\\)\n'
knob algo_status_or 0

# Issue 23.6: the firmware's origin from SentralStatus, the feature sensors
# from FeatureFlags, their rate registers and data slots (the simulated
# USFS: barometer in slot 0 at 1000.00 hPa +- 0.50, thermometer in slot 1
# at 25.00 C +- 0.20), the USFS firmware's conversions.
ok "feature rates 10 and 5 Hz" i2ctransfer -y "$bus" w3@0x28 0x58 0x0a 0x05
sleep 0.5
out=$(sentral-warmstart $i2c status 2>&1)
is "status over i2c-dev: exit 0" $? 0
like "firmware from the board's EEPROM (SentralStatus bit 0)" "$out" \
	"firmware: +from the board's EEPROM"
like "the barometer, about 100 kPa, at 10 Hz" "$out" \
	'feature sensors: +pressure (99\.9[5-9]|100\.0[0-5])[0-9] kPa at 10 Hz'
like "the thermometer, about 25 C, at 5 Hz" "$out" \
	$'\n +temperature 2[45]\\.[0-9]{2} C at 5 Hz\n'
like "--json" "$(sentral-warmstart $i2c status --json)" \
	'"firmware_source":"eeprom","feature_sensors":\[\{"name":"pressure","value":(99\.9[5-9]|100\.0[0-5])[0-9],"unit":"kPa","rate_hz":10\},\{"name":"temperature","value":2[45]\.[0-9]{2},"unit":"C","rate_hz":5\}\],'
knob feature_flags 7
sleep 0.5
like "FeatureFlags 7: three slots, the data packed, humidity about 45 %" \
	"$(sentral-warmstart $i2c status 2>&1)" \
	$'feature sensors: +pressure (99\\.9[5-9]|100\\.0[0-5])[0-9] kPa at 10 Hz\n +humidity 4[456]\\.[0-9]{2} % at 5 Hz\n +temperature -?[0-9.]+ C at 0 Hz\n'
knob feature_flags 0
like "FeatureFlags 0: none" "$(sentral-warmstart $i2c status 2>&1)" \
	$'\nfeature sensors: +none\n'
like "--json: an empty list" "$(sentral-warmstart $i2c status --json)" \
	'"feature_sensors":\[\],'
knob feature_flags 5
ok "feature rates back to the driver's 25 Hz" \
	i2ctransfer -y "$bus" w3@0x28 0x58 0x19 0x19

# Calibrate over i2c-dev.
knob gbias_period_ms 200
knob cal_duration_ms 1500
(sleep 1; knob motion 1) &
out=$(sentral-warmstart $i2c calibrate --timeout 30 --file /tmp/i2c.ws 2>&1)
rc=$?
wait
knob motion 0
is "calibrate over i2c-dev: exit 0" $rc 0
echo "$out" | sed 's/^/# /'
is "transfer mode ended" "$(dbg_get state transfer)" 0
is "algorithm running" "$(dbg_get state running)" 1
ok "the file is valid" sentral-warmstart show /tmp/i2c.ws

knob gbias_period_ms 600000
ok "save --force over i2c-dev" sentral-warmstart $i2c save --force --file /tmp/i2c.ws
payload=$(file_payload_words /tmp/i2c.ws)
is "saved payload equals the chip's parameters 1..35" "$payload" "$(sim_ws_params)"

# Power cycle: the chip forgets; a host starts it again; restore.
knob power_cycle 1
ok "chip back after the power cycle" wait_for 5 sim_ready
ok "start it (rates, run)" chip_run "$bus"
is "calibration lost" "$(dbg_get state cal_status)" 0
knob stats 0
out=$(sentral-warmstart $i2c restore --file /tmp/i2c.ws 2>&1)
is "restore over i2c-dev: exit 0" $? 0
echo "$out" | sed 's/^/# /'
is "calibration complete at once" "$(dbg_get state cal_status)" 3
like "restore says so: level 4" "$out" \
	"restored /dev/i2c-[0-9]+@0x28 calibration from /tmp/i2c.ws: level 4 \(stable\) \(saved: level 4 \(stable\), no score\)"
is "chip parameters 1..35 equal the file" "$(sim_ws_params)" "$payload"
is "transfer mode ended" "$(dbg_get state transfer)" 0
is "AlgorithmControl bit 7 clear" "$(i2ctransfer -f -y "$bus" w1@0x28 0x54 r1)" 0x00
echo "# restore over i2c-dev, whole command: $(tr '\n' ' ' <"$SIM_DBG/stats")"

# (d) round trip: the file read back from the chip equals what was written.
ok "save --force after restore" sentral-warmstart $i2c save --force --file /tmp/i2c2.ws
is "round trip payload identical" "$(file_payload_words /tmp/i2c2.ws)" "$payload"

# accel-cal over i2c-dev: parameters 27..29 as float g, Table 1 exactly.
out=$(sentral-warmstart $i2c accel-cal --samples 32 --file /tmp/i2c-accel.ws 2>&1)
is "accel-cal over i2c-dev: exit 0" $? 0
echo "$out" | sed 's/^/# /'
is "parameters 27..29 are Table 1 bit for bit" \
	"$(sim_param 27) $(sim_param 28) $(sim_param 29)" "$TABLE1"
like "and saved by itself" "$out" "saved /dev/i2c-[0-9]+@0x28 .*to /tmp/i2c-accel.ws"
is "the saved file holds them" "$(words 27 29 "$(file_payload_words /tmp/i2c-accel.ws)")" "$TABLE1 "

# Faults: the transfer is always ended.
knob ack_never 1
out=$(sentral-warmstart $i2c save --force --file /tmp/x.ws 2>&1)
is "acknowledge never comes: exit 74" $? 74
like "says which parameter" "$out" "parameter 1 not acknowledged"
is "transfer mode ended anyway" "$(dbg_get state transfer)" 0
is "algorithm running" "$(dbg_get state running)" 1
nok "no file written" test -e /tmp/x.ws
knob ack_never 0
knob ack_latency_us 500
knob nack_at 40
out=$(sentral-warmstart $i2c restore --file /tmp/i2c.ws 2>&1)
is "NACK in the middle of a restore: exit 74" $? 74
knob nack_at 0
echo "$out" | sed 's/^/# /'
like "says what the chip now holds and what to do" "$out" \
	"parameters 1-[0-9]+ hold the new values, [0-9]+ may or may not, [0-9]+-35 still the old ones: the chip's calibration is mixed; run the same command again, or power-cycle"
is "transfer mode ended after the NACK" "$(dbg_get state transfer)" 0
ok "and the next restore works" sentral-warmstart $i2c restore --file /tmp/i2c.ws

# A signal in the middle of a transfer: the batch stops between parameters,
# transfer mode ends, then the tool dies of the signal.
knob ack_latency_us 100000
sentral-warmstart $i2c restore --file /tmp/i2c.ws >/tmp/sig.out 2>&1 &
pid=$!
wait_for 5 grep -qx 'transfer 1' "$SIM_DBG/state"
sleep 0.5
kill -TERM $pid
wait $pid
is "SIGTERM during a restore: the tool dies of it (128 + 15)" $? 143
like "after saying so" "$(cat /tmp/sig.out)" "interrupted by Terminated.*mixed"
is "transfer mode ended" "$(dbg_get state transfer)" 0
is "AlgorithmControl bit 7 clear" "$(i2ctransfer -f -y "$bus" w1@0x28 0x54 r1)" 0x00
is "algorithm running" "$(dbg_get state running)" 1
sentral-warmstart $i2c save --force --file /tmp/sig.ws >/tmp/sig.out 2>&1 &
pid=$!
wait_for 5 grep -qx 'transfer 1' "$SIM_DBG/state"
sleep 0.5
kill -HUP $pid
wait $pid
is "SIGHUP during a save: the tool dies of it (128 + 1)" $? 129
is "transfer mode ended" "$(dbg_get state transfer)" 0
nok "no file written" test -e /tmp/sig.ws
knob ack_latency_us 500
ok "and the next restore works" sentral-warmstart $i2c restore --file /tmp/i2c.ws

# A board without an EEPROM: nothing runs until the host uploads (unknown),
# then the firmware is the host's (SentralStatus bit 4, a RAM version).
knob no_eeprom 1
ok "no EEPROM: the ROM's search for it is over" wait_for 5 sim_ready
out=$(sentral-warmstart $i2c status 2>&1)
is "status with nothing uploaded: exit 0" $? 0
like "firmware unknown: nothing uploaded" "$out" \
	'firmware: +unknown \(the board has no EEPROM and no firmware was uploaded \(SentralStatus 0x18, RAM version 0\)\)'
like "no feature sensors without firmware" "$out" 'feature sensors: +none'
like "--json: firmware_source null" "$(sentral-warmstart $i2c status --json)" \
	'"firmware_source":null,"feature_sensors":\[\],'
T=$(mktemp -d /tmp/tool-i2c.XXXXXX)
ok "an image" sh -c "/usr/bin/python3 $SENTRAL_ROOT/tests/refhost/mkfw.py $T/em7180.fw --ram-version 0x0e42 >/dev/null"
echo -n "$T" >/sys/module/firmware_class/parameters/path
ok "the driver binds and uploads it" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/bind"
is "  the firmware is the host's" "$(dbg_get board firmware)" host
ok "unbind the driver" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/unbind"
out=$(sentral-warmstart $i2c status 2>&1)
like "status over i2c-dev: uploaded by the host" "$out" \
	$'\nfirmware: +uploaded by the host\n'
like "--json: firmware_source host" "$(sentral-warmstart $i2c status --json)" \
	'"firmware_source":"host",'
knob no_eeprom 0
ok "the EEPROM's firmware is loaded" wait_for 5 sim_ready
echo -n "" >/sys/module/firmware_class/parameters/path
rm -rf "$T"

ok "bind the driver again" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/bind"
ok "the driver backend sees it" wait_for 5 em7180_dir

done_testing
