#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --udev
#
# The bus behind the hub (drivers/iio/sentral/em7180_passthru.c): the
# driver's I2C gate, whose transfers put the simulated hub in passthrough,
# reaches its sensor bus (tests/sim/README.md, "The sensor bus behind
# passthrough"). i2cdetect sees the EEPROM, its ID page and the sensors;
# at24 binds to the EEPROM and its nvmem file reads, backs up, changes and
# restores it byte for byte; the stream of a buffer pauses for passthrough
# and resumes with the fusion state kept; a parameter transfer waits for a
# long transfer on the sensor bus; sentral-warmstart import-board reads the
# board's calibration block through nvmem and the file restores at the next
# probe; unbinding the driver takes the adapter and at24 away.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

TMP=$(mktemp -d)
PY=/usr/bin/python3

mp() {
	modprobe -d "$SENTRAL_MODROOT" "$@"
}

# The hub's sensor bus: the adapter of the gate's channel 0
child_bus() {
	local l=/sys/bus/i2c/devices/$CLIENT/channel-0
	[ -e "$l" ] || return 1
	l=$(basename "$(readlink -f "$l")")
	echo "${l#i2c-}"
}

# detected BUS: what i2cdetect -y finds, "addr=cell ..." (UU: in use)
detected() {
	i2cdetect -y "$1" | "$PY" -c '
import sys
out = []
for line in sys.stdin.read().splitlines()[1:]:
    base = int(line[:2], 16)
    for c in range(16):
        cell = line[4 + 3 * c:6 + 3 * c].strip()
        if cell not in ("", "--"):
            out.append("%02x=%s" % (base + c, cell))
print(" ".join(out))'
}

# now_us: CLOCK_MONOTONIC in microseconds, the simulator's clock
now_us() {
	"$PY" -c 'import time; print(time.monotonic_ns() // 1000)'
}

# check_scans FILE COUNT: COUNT scans of accel x, y, z and a timestamp,
# gravity (the warm start's offsets cancel the simulator's bias),
# timestamps increasing; prints the longest gap between two scans in ms.
check_scans() {
	"$PY" - "$@" <<'PYEOF'
import struct, sys
path, count = sys.argv[1], int(sys.argv[2])
data = open(path, "rb").read()
size = struct.calcsize("<3h2xq")
if len(data) != count * size:
    sys.exit("%d bytes, expected %d scans of %d" % (len(data), count, size))
want, last, gap = (0, 0, 2048), None, 0
for i in range(count):
    v = struct.unpack_from("<3h2xq", data, i * size)
    if any(abs(x - w) > 2 for x, w in zip(v[:3], want)):
        sys.exit("scan %d: accel %s, expected %s within 2 LSB" % (i, v[:3], want))
    if last is not None:
        if v[3] <= last:
            sys.exit("scan %d: timestamp %d not after %d" % (i, v[3], last))
        gap = max(gap, v[3] - last)
    last = v[3]
print(gap // 1000000)
PYEOF
}

DEV=$(em7180_dir)
ok "em7180 present" test -n "$DEV"
B=$(sim_bus)
CLIENT=$B-0028
knob gbias_period_ms 600000

# --- the adapter
N=$(child_bus)
ok "the hub has a child adapter (channel-0 of $CLIENT)" test -n "$N"
is "named by the i2c-mux core" "$(cat "/sys/bus/i2c/devices/i2c-$N/name")" \
	"i2c-$B-mux (chan_id 0)"
is "its mux_device is the hub" \
	"$(basename "$(readlink "/sys/bus/i2c/devices/i2c-$N/mux_device")")" "$CLIENT"
ok "/dev/i2c-$N exists" wait_for 5 test -c "/dev/i2c-$N"
like "the kernel log announces it" "$(dmesg)" "i2c-$B: Added multiplexed i2c bus $N"

# --- i2cdetect: the sensor bus only through the gate
is "i2cdetect -y $N: EEPROM, ID page, AK8963, MPU9250, MS5637; the hub in use" \
	"$(detected "$N")" "0c=0c 28=UU 50=50 58=58 68=68 76=76"
is "i2cdetect -y $B: the parent bus has the hub alone" "$(detected "$B")" "28=UU"
is "passthrough ended" "$(dbg_get board passthrough)" 0
is "the algorithm runs again" "$(dbg_get state running) $(dbg_get state standby)" "1 0"
is "AK8963 WIA through the gate" "$(i2cget -y "$N" 0x0c 0x00)" 0x48
is "MPU9250 WHO_AM_I through the gate" "$(i2cget -y "$N" 0x68 0x75)" 0x71

# --- at24 and nvmem
"$PY" -c 'import sys; sys.stdout.buffer.write(bytes((i * 7 + (i >> 8)) & 0xff for i in range(65536)))' \
	>"$TMP/image"
cat "$TMP/image" >"$SIM_DBG/eeprom"
ok "modprobe at24" mp at24
ok "echo 24c512 0x50 > i2c-$N/new_device" \
	sh -c "echo 24c512 0x50 > /sys/bus/i2c/devices/i2c-$N/new_device"
NV=/sys/bus/nvmem/devices/$N-00500/nvmem
ok "at24's nvmem file $NV" wait_for 5 test -e "$NV"
is "bound to at24" "$(basename "$(readlink "/sys/bus/i2c/devices/$N-0050/driver")")" at24
is "64 KiB" "$(stat -c %s "$NV")" 65536
ok "dd of the nvmem file: a backup" dd if="$NV" of="$TMP/backup" bs=4096 status=none
ok "the backup is the EEPROM's contents (debugfs eeprom)" cmp "$TMP/backup" "$TMP/image"

# A change of 256 bytes at the calibration block's address, through the
# EEPROM's 5 ms write cycle (eeprom_write_ms), which at24 polls for
is "eeprom_write_ms 5 (the M24512's)" "$(cat "$SIM_DBG/eeprom_write_ms")" 5
head -c 256 /dev/urandom >"$TMP/change"
ok "dd of 256 bytes into the nvmem file at 0x8000" \
	dd if="$TMP/change" of="$NV" bs=256 seek=128 count=1 conv=notrunc status=none
ok "the EEPROM holds them" cmp -n 256 -i 0:$((0x8000)) "$TMP/change" "$SIM_DBG/eeprom"
ok "nvmem reads them back" cmp -n 256 -i 0:$((0x8000)) "$TMP/change" "$NV"
ok "the rest is unchanged" cmp -n $((0x8000)) "$TMP/backup" "$SIM_DBG/eeprom"

# The whole image back; at24 writes a byte per transfer without a pagesize
# from the devicetree, so the write cycle is made short for this.
knob eeprom_write_ms 0
t0=$(now_us)
ok "dd of the backup into the nvmem file: restore" \
	dd if="$TMP/backup" of="$NV" bs=4096 status=none
echo "# restore of 64 KiB, one byte per transfer: $((($(now_us) - t0) / 1000)) ms"
knob eeprom_write_ms 5
ok "the EEPROM is the backup, byte for byte" cmp "$TMP/backup" "$SIM_DBG/eeprom"
ok "and reads so through nvmem" cmp "$TMP/backup" "$NV"
is "passthrough ended" "$(dbg_get board passthrough)" 0

# --- passthrough while a buffer streams: the stream pauses and resumes,
# the fusion state is kept. A good warm start first (the magnetometer's
# true coefficients: the calibration is stable at once).
"$PY" -c '
import struct, sys
p = [0.001] * 17 + [0.90, 1.08, 0.95, 25.0, -12.5, 40.0] + [1.0] * 3 + \
    [-0.022936, -0.00732, 0.022448] + [1.0] * 3 + [0.1, -0.05, 0.02]
sys.stdout.buffer.write(struct.pack("<35f", *p))' | with_header "$(sim_caldata_header)" >"$TMP/ws"
ok "a warm start restored" dd if="$TMP/ws" of="$DEV/calibration_data" bs=148 status=none
ok "calibration stable (level 4)" wait_for 3 sh -c "[ \"\$(cat $DEV/in_magn_calibration_auto_status)\" = 4 ]"
dd if="$DEV/calibration_data" of="$TMP/ws.before" bs=4096 status=none
# The model's score (debugfs): the USFS firmware reports none.
score=$(dbg_get state score_raw)
irqs=$(dbg_get state irqs)
knob samples 0
iio_readdev -T 10000 -b 16 -s 300 em7180 accel_x accel_y accel_z timestamp \
	>"$TMP/stream.bin" 2>"$TMP/stream.err" &
pid=$!
sleep 0.5
t0=$(now_us)
ok "while streaming: a dump of the EEPROM through nvmem" \
	dd if="$NV" of="$TMP/dump" bs=4096 status=none
ok "and i2cdetect" sh -c "i2cdetect -y $N >/dev/null"
echo "# passthrough while streaming: $((($(now_us) - t0) / 1000)) ms"
wait "$pid"
is "the stream goes on: iio_readdev gets its 300 scans" "$?" 0
sed 's/^/# /' "$TMP/stream.err"
gap=$(check_scans "$TMP/stream.bin" 300 2>&1)
ok "300 well-formed scans, timestamps increasing" test "$gap" -ge 0
echo "# longest gap between scans: $gap ms; $(($(dbg_get state irqs) - irqs)) data-ready interrupts"
# The chip makes no sample in passthrough (its algorithm in standby): no
# scan is lost beyond that pause, none whose data-ready the driver saw and
# lost by its own cause (the simulator's slow, unread and pending, as make
# bench counts: the others are the machine's, tests/sim/README.md)
drops=$(($(dbg_get samples accel_drops_seen_slow) +
	$(dbg_get samples accel_drops_seen_unread) +
	$(dbg_get samples accel_drops_seen_pending)))
echo "# samples: $(grep '^accel' "$SIM_DBG/samples" | tr '\n' ' ')"
is "no sample the driver saw and did not read" "$drops" 0
[ "$drops" = 0 ] || sed 's/^/#   /' "$SIM_DBG/drops_host"
ok "the dump is the EEPROM" cmp "$TMP/dump" "$TMP/backup"
is "the calibration is still stable" "$(cat "$DEV/in_magn_calibration_auto_status")" 4
is "with its score" "$(dbg_get state score_raw)" "$score"
dd if="$DEV/calibration_data" of="$TMP/ws.after" bs=4096 status=none
ok "and the warm start parameters are the same" cmp "$TMP/ws.before" "$TMP/ws.after"
is "passthrough ended, the algorithm runs" \
	"$(dbg_get board passthrough) $(dbg_get state running) $(dbg_get state standby)" "0 1 0"
is "INT low: no event left pending" "$(dbg_get state int)" 0

# The same with nothing streaming, then a stream: its interrupts come
ok "a read through the gate" i2cget -y "$N" 0x68 0x75
out=$(iio_readdev -T 3000 -b 4 -s 20 em7180 accel_x 2>&1 >"$TMP/after.bin")
is "a stream after passthrough: 20 scans" "$(stat -c %s "$TMP/after.bin")" 40

# --- a parameter transfer during a long transfer on the sensor bus: it
# waits for the end of the transfer, then succeeds. 8 KiB at 100 kHz take
# about 0.74 s on the wire.
knob bus_khz 100
t0=$(now_us)
# -f: at24 has the address
i2ctransfer -f -y "$N" w2@0x50 0x00 0x00 r8192 >"$TMP/long.txt" &
pid=$!
sleep 0.2
ok "calibration_data read during the long transfer" \
	dd if="$DEV/calibration_data" of="$TMP/ws.during" bs=4096 status=none
wait "$pid"
is "the long transfer succeeds" "$?" 0
knob bus_khz 0
started=$(dbg_get state transfer_started_us)
echo "# parameter transfer began $(((started - t0) / 1000)) ms after the long transfer was started"
ok "the parameter transfer began after the long transfer (>= 700 ms)" \
	test $((started - t0)) -ge 700000
ok "and read the same warm start" cmp "$TMP/ws.before" "$TMP/ws.during"
is "the long transfer read the EEPROM" \
	"$(tr ' ' '\n' <"$TMP/long.txt" | grep -c .)" 8192
is "its first bytes" "$(head -c 24 "$TMP/long.txt")" "0x00 0x07 0x0e 0x15 0x1c"

# --- import-board through nvmem: the GT utility's block (parameters 1..35
# at 0x8000, accel calibration at 0x808c, marker 0xaa at 0x8098) written
# through at24, imported, and restored at the next probe
key=$(sentral-warmstart key)
f=$STATE/$key.ws
rm -f "$f"
"$PY" - "$TMP/block" <<'PYEOF'
import struct, sys
p = [0.002] * 17 + [0.90, 1.08, 0.95, 25.0, -12.5, 40.0] + [1.0] * 3 + \
    [-0.022936, -0.00732, 0.022448] + [1.0] * 3 + [0.2, -0.1, 0.04]
blk = struct.pack("<35f", *p) + struct.pack("<6h", 2049, 2050, 2051, -2047, -2046, -2045) + b"\xaa"
open(sys.argv[1], "wb").write(blk)
PYEOF
ok "the calibration block written through at24" \
	dd if="$TMP/block" of="$NV" bs=153 seek=$((0x8000)) oflag=seek_bytes count=1 conv=notrunc status=none
want=$(head -c 140 "$TMP/block" | blob_words)
out=$(sentral-warmstart import-board "$NV" 2>&1)
is "sentral-warmstart import-board $NV exits 0" $? 0
echo "$out" | sed 's/^/# /'
like "says what it imported" "$out" "gt layout, parameters at 0x8000"
is "the file holds the block's parameters" "$(file_payload_words "$f")" "$want"
ok "replug (power cycle + bind): udev restores at probe" replug "$CLIENT"
udevadm settle --timeout=10
DEV=$(em7180_dir)
is "the chip holds the board's parameters" "$(sim_ws_params)" "$want"
is "calibration stable (level 4) without motion" "$(cal_level)" 4
N2=$(child_bus)
ok "the child adapter is back" test -n "$N2"

# --- unbind: the adapter and at24 go, cleanly, an nvmem file held open
N=$N2
ok "at24 on the new adapter" \
	sh -c "echo 24c512 0x50 > /sys/bus/i2c/devices/i2c-$N/new_device"
NV=/sys/bus/nvmem/devices/$N-00500/nvmem
ok "its nvmem file" wait_for 5 test -e "$NV"
exec 3<"$NV"
ok "unbind the driver" timeout 30 sh -c "echo $CLIENT > /sys/bus/i2c/drivers/em7180/unbind"
nok "the child adapter is gone" test -e "/sys/bus/i2c/devices/i2c-$N"
nok "the EEPROM client is gone" test -e "/sys/bus/i2c/devices/$N-0050"
nok "the nvmem device is gone" test -e "$NV"
nok "a read of the nvmem file held open fails" dd bs=16 count=1 status=none <&3
exec 3<&-
nok "no em7180 device" em7180_dir
ok "bind again" sh -c "echo $CLIENT > /sys/bus/i2c/drivers/em7180/bind"
ok "the device is back" wait_for 5 em7180_dir
ok "and its child adapter" child_bus
ok "unbind with nothing on the adapter" \
	sh -c "echo $CLIENT > /sys/bus/i2c/drivers/em7180/unbind"
# The watcher the udev rule started leaves when its device goes
ok "rmmod em7180_i2c em7180_core" wait_for 10 mp -r em7180_i2c em7180_core
ok "modprobe em7180_i2c: probes again" sh -c "modprobe -d $SENTRAL_MODROOT em7180_i2c && sleep 0.5"
ok "the device is back" wait_for 5 em7180_dir
ok "with the child adapter" wait_for 5 child_bus
like "no warning in the kernel log" "$(dmesg | grep -c 'WARNING\|BUG\|Oops')" "^0$"

rm -rf "$TMP"
done_testing
