#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# The feature sensors as IIO channels: the simulated USFS firmware drives a
# barometer and a thermometer (FeatureFlags 0x05), which the driver exposes
# as in_pressure (kPa) and in_temp (milli degrees C) with their rates and
# scan elements; humidity with FeatureFlags 0x07; none and the old channel
# table with FeatureFlags 0; the barometer's rate register in half hertz
# found from the actual rate the chip reports, with nothing configured.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"

TMP=$(mktemp -d)
PY=/usr/bin/python3

mp() {
	modprobe -d "$SENTRAL_MODROOT" "$@"
}

# reprobe [CORE_PARAM...]: unload the driver, then load it again (the probe
# is synchronous) with em7180_core's parameters.
reprobe() {
	mp -r em7180_i2c && mp -r em7180_core && mp em7180_core "$@" &&
		mp em7180_i2c && DEV=$(em7180_dir)
}

# own_trigger: the directory of the device's data-ready trigger
own_trigger() {
	local t
	for t in /sys/bus/iio/devices/trigger*; do
		[ "$(cat "$t/name")" = "em7180-dev${DEV##*iio:device}" ] && echo "$t"
	done
}

# reg ADDR: a register of the simulated chip as the host would read it,
# without side effects, "xx".
reg() {
	awk -v row="$(printf '%02x:' $(($1 & 0xf0)))" -v col=$((($1 & 15) + 2)) \
		'$1 == row { print $col }' "$SIM_DBG/regs"
}

# value CHAN: (raw + offset) * scale, as a user computes it, in integers
# of the channel's unit (milli for temperature and humidity, Pa for kPa).
value() {
	"$PY" - "$DEV" "$1" <<'PYEOF'
import os, sys
from decimal import Decimal
dev, ch = sys.argv[1], sys.argv[2]
def attr(name, default=None):
    p = os.path.join(dev, "in_%s_%s" % (ch, name))
    return Decimal(open(p).read().strip()) if os.path.exists(p) else default
v = (attr("raw") + attr("offset", Decimal(0))) * attr("scale")
print(int(v * 1000) if ch == "pressure" else int(v))
PYEOF
}

# check_scans FILE COUNT FMT: COUNT scans of struct FMT, the last field a
# timestamp; the other fields' ranges as "lo:hi" arguments after FMT.
check_scans() {
	"$PY" - "$@" <<'PYEOF'
import struct, sys
path, count, fmt = sys.argv[1], int(sys.argv[2]), sys.argv[3]
ranges = [tuple(map(int, r.split(":"))) for r in sys.argv[4:]]
data = open(path, "rb").read()
size = struct.calcsize(fmt)
if len(data) != count * size:
    sys.exit("%d bytes, expected %d scans of %d" % (len(data), count, size))
last = None
for i in range(count):
    v = struct.unpack_from(fmt, data, i * size)
    for j, (lo, hi) in enumerate(ranges):
        if not lo <= v[j] <= hi:
            sys.exit("scan %d: field %d = %d, not in %d..%d" % (i, j, v[j], lo, hi))
    ts = v[-1]
    if last is not None and ts <= last:
        sys.exit("scan %d: timestamp %d not after %d" % (i, ts, last))
    last = ts
print("%d scans of %d bytes, last %s" % (count, size, v))
PYEOF
}

DEV=$(em7180_dir)
ok "em7180 present" test -n "$DEV"
N=${DEV##*iio:device}
TRIG=$(own_trigger)

# The tests below need the simulator's default board; booted with
# --sim-knobs feature_flags=0 the device must look as it always did.
if [ "$(cat "$SIM_DBG/feature_flags")" = 0x00 ]; then
	for c in pressure temp humidityrelative; do
		nok "FeatureFlags 0: no in_${c}_raw" test -e "$DEV/in_${c}_raw"
	done
	is "FeatureFlags 0: timestamp scan index 10" \
		"$(cat "$DEV/scan_elements/in_timestamp_index")" 10
	done_testing
	exit
fi

# --- FeatureFlags 0x05: barometer and temperature, the USFS
is "FeatureFlags 0x05 (the simulator's default)" "$(cat "$SIM_DBG/feature_flags")" 0x05
for f in in_pressure_raw in_pressure_scale in_pressure_offset \
	in_pressure_sampling_frequency in_pressure_sampling_frequency_available \
	in_temp_raw in_temp_scale in_temp_sampling_frequency \
	in_temp_sampling_frequency_available; do
	ok "$f exists" test -r "$DEV/$f"
done
nok "no in_temp_offset (milli degrees C from 0)" test -e "$DEV/in_temp_offset"
nok "no humidity channel" test -e "$DEV/in_humidityrelative_raw"
is "in_pressure_scale: 0.01 mbar = 0.001 kPa" "$(cat "$DEV/in_pressure_scale")" 0.001000
is "in_pressure_offset: 1013.25 mbar in raw units" "$(cat "$DEV/in_pressure_offset")" 101325
is "in_temp_scale: 0.01 C = 10 milli C" "$(cat "$DEV/in_temp_scale")" 10
p=$(value pressure)
echo "# pressure $p Pa, raw $(cat "$DEV/in_pressure_raw")"
ok "pressure about 100 kPa (99.4..100.6)" [ "$p" -ge 99400 ] && [ "$p" -le 100600 ]
t=$(value temp)
echo "# temperature $t milli C, raw $(cat "$DEV/in_temp_raw")"
ok "temperature about 25000 milli C (24700..25300)" [ "$t" -ge 24700 ] && [ "$t" -le 25300 ]
is "scan index: pressure after the gyroscope" "$(cat "$DEV/scan_elements/in_pressure_index")" 10
is "scan index: temperature" "$(cat "$DEV/scan_elements/in_temp_index")" 11
is "scan index: timestamp last" "$(cat "$DEV/scan_elements/in_timestamp_index")" 12
is "pressure scan type" "$(cat "$DEV/scan_elements/in_pressure_type")" "le:s16/16>>0"
is "accelerometer index unchanged" "$(cat "$DEV/scan_elements/in_accel_x_index")" 4

# Rates: 25 Hz by default, the listed ones accepted, the others refused
is "pressure rate 25 Hz by default" "$(cat "$DEV/in_pressure_sampling_frequency")" 25
is "temperature rate 25 Hz by default" "$(cat "$DEV/in_temp_sampling_frequency")" 25
is "the rates available" "$(cat "$DEV/in_pressure_sampling_frequency_available")" \
	"1 2 5 10 25 50"
is "BaroRate register: 25, no report bit" "$(reg 0x58)" 19
for hz in 1 2 5 10 25 50; do
	ok "echo $hz > in_pressure_sampling_frequency" \
		sh -c "echo $hz > $DEV/in_pressure_sampling_frequency"
	is "pressure rate reads $hz" "$(cat "$DEV/in_pressure_sampling_frequency")" "$hz"
done
is "the simulated barometer samples at 50 Hz" "$(dbg_get board baro_rate_hz)" 50
for hz in 0 3 100 200 25.5 -25; do
	nok "pressure $hz Hz refused" sh -c "echo $hz > $DEV/in_pressure_sampling_frequency"
done
is "the rate stays 50 Hz" "$(cat "$DEV/in_pressure_sampling_frequency")" 50
ok "echo 10 > in_temp_sampling_frequency" sh -c "echo 10 > $DEV/in_temp_sampling_frequency"
is "the simulated thermometer samples at 10 Hz" "$(dbg_get board temp_rate_hz)" 10
nok "temperature 7 Hz refused" sh -c "echo 7 > $DEV/in_temp_sampling_frequency"
echo 25 >"$DEV/in_pressure_sampling_frequency"
echo 25 >"$DEV/in_temp_sampling_frequency"

# A buffer of pressure, temperature and timestamp through the chip's own
# trigger, paced by the barometer's samples (EventStatus bit 6, with the
# report bit on its rate register only while capturing).
iio_readdev -b 4 -s 0 em7180 pressure >/dev/null &
pid=$!
sleep 0.5
is "pressure alone: the trigger runs at the barometer's 25 Hz" \
	"$(cat "$TRIG/sampling_frequency")" 25
is "BaroRate has the report bit while it paces" "$(reg 0x58)" 99
is "TempRate has not" "$(reg 0x59)" 19
kill "$pid"
wait "$pid" 2>/dev/null
is "report bit cleared after the capture" "$(reg 0x58)" 19

knob stats 0
irqs=$(dbg_get state irqs)
nb=$(dbg_get board baro_samples)
ok "iio_readdev -s 50 em7180 pressure temp timestamp" \
	sh -c "iio_readdev -b 8 -s 50 em7180 pressure temp timestamp > $TMP/pt.bin"
tr=$(dbg_get stats transactions)
irqs=$(($(dbg_get state irqs) - irqs))
nb=$(($(dbg_get board baro_samples) - nb))
out=$(check_scans "$TMP/pt.bin" 50 "<hh4xq" -1425:-1225 2480:2520 2>&1)
is "50 scans of 16 bytes, pressure and temperature plausible" "$?" 0
echo "# $out"
echo "# $irqs interrupts, $tr transactions, $nb barometer samples"
ok "no more scans than barometer samples ($nb)" [ 50 -le $((nb + 2)) ]
# What make demo prints: the harness' reader applies the offset (kPa)
for f in "$DEV"/scan_elements/*_en; do echo 0 >"$f"; done
for c in pressure temp timestamp; do echo 1 >"$DEV/scan_elements/in_${c}_en"; done
out=$("$PY" "$SENTRAL_ROOT/tests/lib/iio_decode.py" "$DEV" "$TMP/pt.bin" | tail -n 1)
for f in "$DEV"/scan_elements/*_en; do echo 0 >"$f"; done
echo "# decoded: $out"
like "decoded: pressure 99.8..100.2 kPa, temperature 24.8..25.2 C in milli C" \
	"$out" '^(99\.[89]|100\.[01])[0-9]* 2(4[89]|5[01])[0-9]{2}\.[0-9]+ '
ok "at most 2 bus transactions per scan ($tr for $irqs)" [ "$tr" -le $((2 * irqs + 6)) ]

# The feature sensors with the others: one burst from the accelerometer to
# the feature block, paced by the faster accelerometer
ok "iio_readdev -s 50 em7180 accel_z pressure timestamp" \
	sh -c "iio_readdev -b 8 -s 50 em7180 accel_z pressure timestamp > $TMP/ap.bin"
out=$(check_scans "$TMP/ap.bin" 50 "<hh4xq" 2090:2098 -1425:-1225 2>&1)
is "50 scans: accel_z = gravity + bias, pressure plausible" "$?" 0
echo "# $out"
iio_readdev -b 8 -s 20 em7180 >"$TMP/all.bin" 2>/dev/null
out=$(check_scans "$TMP/all.bin" 20 "<4h3h3h3hhhxxq" 2>&1)
is "every channel: 20 scans of 40 bytes" "$?" 0
echo "# $out"

# Another trigger, and the harness' reader on the buffer device: an
# hrtimer trigger (left in place: removing a software trigger is a
# use-after-free in Linux 6.12, see driver-buffer.sh)
if mkdir /sys/kernel/config/iio/triggers/hrtimer/feat 2>/dev/null; then
	for t in /sys/bus/iio/devices/trigger*; do
		[ "$(cat "$t/name")" = feat ] && echo 20 >"$t/sampling_frequency"
	done
	echo feat >"$DEV/trigger/current_trigger"
	for f in "$DEV"/scan_elements/*_en; do echo 0 >"$f"; done
	echo 1 >"$DEV/scan_elements/in_temp_en"
	echo 1 >"$DEV/scan_elements/in_timestamp_en"
	echo 16 >"$DEV/buffer/length"
	echo 1 >"$DEV/buffer/enable"
	timeout 5 dd if="/dev/iio:device$N" of="$TMP/ht.bin" bs=16 count=10 \
		iflag=fullblock status=none
	is "hrtimer trigger: 10 temperature scans" "$(stat -c %s "$TMP/ht.bin")" 160
	out=$("$PY" "$SENTRAL_ROOT/tests/lib/iio_decode.py" "$DEV" "$TMP/ht.bin" --raw)
	echo "$out" | tail -n 2 | sed 's/^/# /'
	like "decoded by the harness' reader: raw temperature" "$(echo "$out" | tail -n 1)" \
		'(^|[^0-9-])2[45][0-9]{2}([^0-9]|$)'
	echo 0 >"$DEV/buffer/enable"
	for f in "$DEV"/scan_elements/*_en; do echo 0 >"$f"; done
	echo "em7180-dev$N" >"$DEV/trigger/current_trigger"
else
	ok "hrtimer trigger available" false
fi

# A reset of the chip loses the rates: recovery writes them back
echo 10 >"$DEV/in_pressure_sampling_frequency"
knob chip_reset 1
ok "after a reset of the chip the barometer runs again" \
	wait_for 5 sh -c "[ \"\$(awk '\$1 == \"baro_rate_hz\" { print \$2 }' $SIM_DBG/board)\" = 10 ]"
is "at the rate set before" "$(cat "$DEV/in_pressure_sampling_frequency")" 10

# --- FeatureFlags 0x07: three slots, one TIME for all
knob feature_flags 7
ok "feature_flags 7 and a new probe" reprobe
is "humidity channel" "$(cat "$DEV/scan_elements/in_humidityrelative_index")" 11
is "temperature after it" "$(cat "$DEV/scan_elements/in_temp_index")" 12
is "timestamp last" "$(cat "$DEV/scan_elements/in_timestamp_index")" 13
is "in_humidityrelative_scale: 0.01 % = 10 milli percent" \
	"$(cat "$DEV/in_humidityrelative_scale")" 10
h=$(value humidityrelative)
echo "# humidity $h milli percent"
ok "humidity about 45000 milli percent (43900..46100)" [ "$h" -ge 43900 ] && [ "$h" -le 46100 ]
t=$(value temp)
ok "temperature from the third slot ($t)" [ "$t" -ge 24700 ] && [ "$t" -le 25300 ]
ok "three features and a timestamp stream" \
	sh -c "iio_readdev -b 8 -s 20 em7180 pressure humidityrelative temp timestamp > $TMP/three.bin"
out=$(check_scans "$TMP/three.bin" 20 "<hhh2xq" -1425:-1225 4390:4610 2470:2530 2>&1)
is "20 scans, each value in its range" "$?" 0
echo "# $out"

# --- FeatureFlags 0: the channel table of a chip without feature sensors
knob feature_flags 0
ok "feature_flags 0 and a new probe" reprobe
for c in pressure temp humidityrelative; do
	nok "no in_${c}_raw" test -e "$DEV/in_${c}_raw"
done
is "timestamp scan index 10, as always" "$(cat "$DEV/scan_elements/in_timestamp_index")" 10
ok "every channel streams" sh -c "iio_readdev -b 8 -s 10 em7180 > $TMP/none.bin"
is "10 scans of 40 bytes" "$(stat -c %s "$TMP/none.bin")" 400

# --- The barometer's rate in half hertz (kriswiner's reading): the
# driver finds it from ActualBaroRate, with no parameter
knob feature_flags 5
knob baro_rate_half 1
ok "reprobe on firmware whose BaroRate counts half hertz" reprobe
nok "no module parameter for it" test -e /sys/module/em7180_core/parameters/baro_rate_half
is "pressure rate reads 25, as asked" "$(cat "$DEV/in_pressure_sampling_frequency")" 25
is "BaroRate register 50 for 25 Hz once the actual rate showed 12" "$(reg 0x58)" 32
like "the driver says why, once" "$(dmesg | grep -c 'counts half hertz')" '^[1-9][0-9]*$'
is "TempRate stays in Hz" "$(reg 0x59)" 19
is "the simulated barometer samples at 25 Hz" "$(dbg_get board baro_rate_hz)" 25
ok "echo 10 > in_pressure_sampling_frequency" sh -c "echo 10 > $DEV/in_pressure_sampling_frequency"
is "BaroRate register 20" "$(reg 0x58)" 14
is "the barometer samples at 10 Hz" "$(dbg_get board baro_rate_hz)" 10
is "pressure rate reads 10" "$(cat "$DEV/in_pressure_sampling_frequency")" 10
ok "echo 50 > in_pressure_sampling_frequency" sh -c "echo 50 > $DEV/in_pressure_sampling_frequency"
is "BaroRate register 100" "$(reg 0x58)" 64
is "the barometer samples at 50 Hz" "$(dbg_get board baro_rate_hz)" 50
iio_readdev -b 4 -s 0 em7180 pressure >/dev/null &
pid=$!
sleep 0.5
is "the trigger runs at 50 Hz" "$(cat "$(own_trigger)/sampling_frequency")" 50
is "report bit and 100" "$(reg 0x58)" e4
kill "$pid"
wait "$pid" 2>/dev/null
# A capture started before anything read the rate settles it too
n=$(dmesg | grep -c 'counts half hertz')
ok "reprobe" reprobe
iio_readdev -b 4 -s 0 em7180 pressure >/dev/null &
pid=$!
sleep 0.5
is "a capture of the barometer alone: the trigger at 25 Hz" \
	"$(cat "$(own_trigger)/sampling_frequency")" 25
is "register 50 with the report bit" "$(reg 0x58)" b2
is "said once more, for this binding" "$(dmesg | grep -c 'counts half hertz')" $((n + 1))
kill "$pid"
wait "$pid" 2>/dev/null
knob baro_rate_half 0
ok "reprobe, both in hertz" reprobe
is "pressure rate 25" "$(cat "$DEV/in_pressure_sampling_frequency")" 25
is "BaroRate register 25" "$(reg 0x58)" 19
is "nothing said about half hertz" "$(dmesg | grep -c 'counts half hertz')" $((n + 1))

rm -rf "$TMP"
done_testing
