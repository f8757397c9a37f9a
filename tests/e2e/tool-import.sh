#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# sentral-warmstart import-board against the em7180 driver on the simulated
# chip: an image of a USFS board's EEPROM in Greg Tomasch's utility's layout
# (warm-start parameters 1..35 at 0x8000, accel calibration at 0x808c,
# marker 0xaa at 0x8098; Documentation/iio/sentral.rst) is imported, and
# restore writes its parameters to the chip bit for bit; a blank EEPROM and
# a damaged marker are refused with nothing written. The import records no
# level or score, so the next save of a stable calibration replaces it.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
key=$(sentral-warmstart key)
f=$STATE/$key.ws
work=$(mktemp -d)

# make_image OUT [MARKER]: a 64 KiB image, erased but for the block. The
# magnetometer coefficients (18..23) are the simulated sensor's true ones
# (tests/sim/README.md): restored, they make the calibration stable.
make_image() {
	python3 - "$1" "${2:-0xaa}" <<'PY'
import struct, sys
p = [0.001] * 17 + [0.90, 1.08, 0.95, 25.0, -12.5, 40.0] + [1.0] * 3 + \
    [-0.022936, -0.00732, 0.022448] + [1.0] * 3 + [0.1, -0.05, 0.02]
img = bytearray(b"\xff" * 65536)
img[0x8000:0x808c] = struct.pack("<35f", *p)
img[0x808c:0x8098] = struct.pack("<6h", 2049, 2050, 2051, -2047, -2046, -2045)
img[0x8098] = int(sys.argv[2], 0)
open(sys.argv[1], "wb").write(img)
PY
}

make_image "$work/eeprom"
want=$(dd if="$work/eeprom" bs=1 skip=$((0x8000)) count=140 status=none | blob_words)
is "before: the chip is not calibrated (level 2)" "$(cal_level)" 2

# A blank EEPROM (the utilities never saved here): refused, nothing written.
python3 -c 'open("'"$work/blank"'", "wb").write(b"\xff" * 65536)'
out=$(sentral-warmstart import-board "$work/blank" 2>&1)
is "a blank EEPROM: exit 65" $? 65
like "and says why" "$out" "refused: no calibration saved \(erased\).*nothing written"
nok "no file written" test -e "$f"

# The marker damaged: refused.
make_image "$work/bad" 0x2a
out=$(sentral-warmstart import-board "$work/bad" 2>&1)
is "a damaged marker: exit 65" $? 65
like "names the byte" "$out" "no valid-block marker \(byte 0x8098 is 0x2a, not 0xaa\)"
nok "no file written" test -e "$f"

out=$(sentral-warmstart import-board "$work/eeprom" 2>&1)
is "import-board exits 0" $? 0
echo "$out" | sed 's/^/# /'
like "says what it imported" "$out" "imported iio:device[0-9]+'s calibration from the board's EEPROM \(gt layout, parameters at 0x8000\) to $f"
like "and that the accel calibration stays behind" "$out" "x 2049/-2047.*is not imported"
is "the file holds the board's parameters" "$(file_payload_words "$f")" "$want"
is "file mode 0600" "$(stat -c %a "$f")" 600
is "recorded as version 2 without a level, judgement or score (the board keeps none)" \
	"$(ws_header "$f")" "2 0 0 0"
like "show says it was imported" "$(sentral-warmstart show "$f")" \
	$'\njudgement: +none \\(imported'
like "and so does status, with the chip not holding it yet" "$(sentral-warmstart status)" \
	"imported from the board's EEPROM.*"$'\n'"restored: +no: parameter 18 "
is "the chip's identity, as save records it" \
	"$(sentral-warmstart show "$f" |
		sed -n 's/^\(ProductID\|RevisionID\|ROM version\|RAM version\): *//p' |
		tr '\n' ' ')" \
	"$(driver_fw_version | awk '{ printf "%s %s %s %s ", $2, $4, $6, $8 }')"

# An import does not replace a saved file without --force.
cp "$f" "$work/saved"
make_image "$work/other"
printf '\x00\x00\x80\x3f' | dd of="$work/other" bs=1 seek=$((0x8000)) conv=notrunc status=none
out=$(sentral-warmstart import-board "$work/other" 2>&1)
is "a second import without --force: exit 0" $? 0
like "says it keeps the saved one" "$out" "not importing .*--force replaces it"
ok "the file is unchanged" cmp -s "$f" "$work/saved"

# The chip learns its gyro bias (33..35) every 2 s while still: not now.
knob gbias_period_ms 600000
out=$(sentral-warmstart restore 2>&1)
is "restore exits 0" $? 0
echo "$out" | sed 's/^/# /'
got=""
for n in $(seq 1 35); do
	got="$got$(sim_param "$n") "
done
is "the chip holds the board's 35 parameters bit for bit" "$got" "$want"
ok "and its calibration is stable (level 4)" wait_for 3 sh -c '[ "$(cat '"$DEV"'/in_magn_calibration_auto_status)" = 4 ]'
like "restore says what the file held" "$out" \
	"restored iio:device[0-9]+ calibration from $f: level 4 \(stable\) \(saved: imported from the board's EEPROM\)"
is "accel offsets from parameters 27..29" \
	"$(cat "$DEV"/in_accel_{x,y,z}_calibbias | tr '\n' ' ')" "-47 -15 46 "
like "status: the chip holds the imported calibration" "$(sentral-warmstart status)" \
	$'\nrestored: +yes: the chip holds the saved calibration'

# A stable calibration replaces the import: it records none to judge by.
out=$(sentral-warmstart save 2>&1)
like "the next save replaces the import" "$out" \
	"saved iio:device[0-9]+ calibration to $f: stable, and the saved calibration \(imported from the board's EEPROM\) is not"
is "now judged stable, at level 4, with no score" "$(ws_header "$f")" "2 4 2 0"

rm -rf "$work"
done_testing
