#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# The em7180 driver under concurrent use for 30 s: iio_readdev captures
# accel, gyro and quaternion through the driver's own trigger, run after run,
# while parallel readers and writers hammer calibration_data (complete blobs from a
# small known set), in_accel_*_calibbias and the sampling frequencies.  Every
# access either succeeds or is refused with EBUSY (a write while a capture
# runs; reads of calibration_data work then);
# every calibration_data read is one complete written blob, never a mix; every
# value read was written; every capture ends well; the device works after.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"

DURATION=30
CALIBBIAS="0 -47 46 123 -300"
RATES="50 100 200"
MAGN_RATES="10 30"
CHANNELS="rot_quaternion accel_x accel_y accel_z anglvel_x anglvel_y anglvel_z timestamp"
T=$(mktemp -d)
PY=/usr/bin/python3

# pick WORDS...: set P to one of the words, at random (no subshell: forks
# are slow in UML and the point is many accesses).
pick() {
	local a=("$@")
	P=${a[RANDOM % ${#a[@]}]}
}

# Each worker appends one line per access to $T/log.NAME: "ok", "busy" or
# "err MESSAGE" (anything else the kernel said), until the deadline.
# result STATUS NAME: classify an access whose stderr is in $T/e.NAME.
result() {
	local msg=
	if [ "$1" = 0 ]; then
		echo ok
		return
	fi
	read -r msg <"$T/e.$2"
	if [[ $msg == *"resource busy"* ]]; then
		echo busy
	else
		echo "err $msg"
	fi
}

ws_writer() {
	while ((EPOCHSECONDS < END)); do
		pick 1 2 3
		dd if="$T/blob.$P" of="$DEV/calibration_data" bs=148 status=none 2>"$T/e.$1"
		result $? "$1"
	done >"$T/log.$1"
}

# What is read is appended to $T/reads.NAME, checked afterwards (a refused
# read adds nothing; anything but whole blobs fails the check).
# Reads work while a capture runs: each pauses the chip's algorithm for a
# transfer (about 30 ms, longer in UML), so back-to-back readers would leave
# the stream few samples; they read twice a second each, far more often than
# any saver does.
ws_reader() {
	while ((EPOCHSECONDS < END)); do
		dd if="$DEV/calibration_data" bs=4096 status=none 2>"$T/e.$1" >>"$T/reads.$1"
		result $? "$1"
		sleep 0.5
	done >"$T/log.$1"
}

cb_writer() {
	local v
	while ((EPOCHSECONDS < END)); do
		# shellcheck disable=SC2086
		pick $CALIBBIAS
		v=$P
		pick x y z
		echo "$v" 2>"$T/e.$1" >"$DEV/in_accel_${P}_calibbias"
		result $? "$1"
	done >"$T/log.$1"
}

# Values read go to $T/vals.NAME.
cb_reader() {
	local v
	while ((EPOCHSECONDS < END)); do
		pick x y z
		read -r v 2>"$T/e.$1" <"$DEV/in_accel_${P}_calibbias"
		result $? "$1"
		[ -n "$v" ] && echo "$v" >>"$T/vals.$1"
	done >"$T/log.$1"
}

sf_writer() {
	local t
	while ((EPOCHSECONDS < END)); do
		pick accel anglvel magn
		t=$P
		# shellcheck disable=SC2086
		if [ "$t" = magn ]; then pick $MAGN_RATES; else pick $RATES; fi
		echo "$P" 2>"$T/e.$1" >"$DEV/in_${t}_sampling_frequency"
		result $? "$1"
	done >"$T/log.$1"
}

sf_reader() {
	local v
	while ((EPOCHSECONDS < END)); do
		pick accel anglvel magn
		read -r v 2>"$T/e.$1" <"$DEV/in_${P}_sampling_frequency"
		result $? "$1"
		[ -n "$v" ] && echo "$v" >>"$T/vals.$1"
	done >"$T/log.$1"
}

# Captures of 150 and 40 scans in turn, back to back with a short pause in
# which the other workers get the device (the readers' transfers pause the
# stream meanwhile: a refill of 16 scans may take over libiio's default
# second, the stall check below is the bound); one line per capture in
# $T/streams: "SCANS STATUS BYTES START_MS END_MS".
streamer() {
	local i=0 n rc t0
	while ((EPOCHSECONDS < END)); do
		n=$((i % 2 ? 40 : 150))
		t0=${EPOCHREALTIME/./}
		# shellcheck disable=SC2086
		timeout 20 iio_readdev -T 5000 -b 16 -s $n em7180 $CHANNELS \
			>"$T/s.$i" 2>"$T/s.$i.err"
		rc=$?
		echo "$n $rc $(stat -c %s "$T/s.$i") $((t0 / 1000)) $((${EPOCHREALTIME/./} / 1000))"
		i=$((i + 1))
		sleep 0.2
	done >"$T/streams"
}

# count NAME WHAT: lines of $T/log.NAME that start with WHAT.
count() {
	grep -c "^$2" "$T/log.$1"
}

DEV=$(em7180_dir)
ok "em7180 present" test -n "$DEV"
N=${DEV##*iio:device}
is "captures use the driver's own trigger" "$(cat "$DEV/trigger/current_trigger")" "em7180-dev$N"

# The learned gyro bias would change parameters 33..35 under the readers.
knob gbias_period_ms 3600000
knob motion 0

# The encoding of each calibbias value in parameters 27..29 (float g).
enc=
declare -A ENC
for v in $CALIBBIAS; do
	echo "$v" >"$DEV/in_accel_x_calibbias"
	ENC[$v]=$(dbg_get params 27)
	enc="$enc ${ENC[$v]}"
done
echo 0 >"$DEV/in_accel_x_calibbias"

# Three valid blobs that differ from each other in every parameter except
# 27..29, which the calibbias writers change and which stay as read.
ok "initial blob read" dd if="$DEV/calibration_data" of="$T/blob.0" bs=4096 status=none
"$PY" - "$T" <<'PYEOF'
import struct, sys
t = sys.argv[1]
init = open(t + "/blob.0", "rb").read()
for k in (1, 2, 3):
    words = [init[:8]]  # the chip's identity header
    for i in range(1, 36):
        if 27 <= i <= 29:
            words.append(init[4 * (i + 1):4 * (i + 2)])
        else:
            words.append(struct.pack("<f", k + i / 64.0))
    open("%s/blob.%d" % (t, k), "wb").write(b"".join(words))
PYEOF
is "three test blobs of 148 bytes" "$(stat -c %s "$T"/blob.[123] | tr '\n' ' ')" "148 148 148 "

knob samples 0
irqs0=$(dbg_get state irqs)
END=$((EPOCHSECONDS + DURATION))
streamer &
pids=$!
for w in ws_writer.a ws_writer.b ws_reader.a ws_reader.b cb_writer.a cb_reader.a \
	sf_writer.a sf_reader.a; do
	${w%.*} "$w" &
	pids="$pids $!"
done
# shellcheck disable=SC2086
wait $pids
echo "# $(($(dbg_get state irqs) - irqs0)) data-ready interrupts in ${DURATION} s"

# Captures: all ended well, each delivered every scan without a stall, and
# they covered the whole time (a capture waits for at most one transfer).
runs=$(wc -l <"$T/streams")
echo "# $runs captures"
ok "at least 5 captures in ${DURATION} s" [ "$runs" -ge 5 ]
bad=$(awk '$2 != 0' "$T/streams")
is "every iio_readdev exited 0" "$bad" ""
[ -n "$bad" ] && cat "$T"/s.*.err | sort | uniq -c | sed 's/^/#   /' | head
short=$(awk '$3 != $1 * 32' "$T/streams")
is "every capture delivered all its scans (32 bytes each)" "$short" ""
[ -n "$short" ] && cat "$T"/s.*.err | sort | uniq -c | sed 's/^/#   /' | head
gap=$(awk 'NR > 1 { g = $4 - e; if (g > m) m = g } { e = $5 } END { print m + 0 }' "$T/streams")
first=$(head -n 1 "$T/streams" | awk '{ print $4 }')
last=$(tail -n 1 "$T/streams" | awk '{ print $5 }')
echo "# longest pause between captures ${gap} ms; capturing from ${first} to ${last} ms"
# iio_readdev takes a while to start in UML (KASAN: more): a bound that
# still catches a device held for seconds.
ok "no pause between captures over 5 s (${gap} ms)" [ "$gap" -le 5000 ]
ok "captures lasted the ${DURATION} s" [ $((last - first)) -ge $((DURATION * 1000 - 2000)) ]
# A read pauses the stream for one transfer and a second reader waits for
# the next scan, so no gap may exceed the longest transfer by more than
# two periods of the slowest rate (50 Hz) and UML's scheduling (250 ms):
# a stream held across two transfers, or by the lock, exceeds it.
longest=$(dbg_get state transfer_longest_us)
out=$("$PY" - "$T" "$longest" <<'PYEOF'
import glob, struct, sys
bound = int(sys.argv[2]) * 1000 + 2 * 20000000 + 250000000
fmt = "<4h3h3h4xq"
size = struct.calcsize(fmt)
worst = 0
n = 0
for path in glob.glob(sys.argv[1] + "/s.*"):
    if path.endswith(".err"):
        continue
    data = open(path, "rb").read()
    last = None
    for off in range(0, len(data) - size + 1, size):
        v = struct.unpack_from(fmt, data, off)
        q, ts = v[0:4], v[10]
        n2 = sum(c * c for c in q)
        if abs(n2 - 16384 * 16384) > 16384 * 16384 // 1000:
            sys.exit("%s: scan %d: quaternion %s is not a unit" % (path, off // size, q))
        if last is not None:
            if ts <= last:
                sys.exit("%s: scan %d: timestamp %d after %d" %
                         (path, off // size, ts, last))
            worst = max(worst, ts - last)
        last = ts
        n += 1
print("%d scans, longest gap between scans %d ms, longest transfer %d ms" %
      (n, worst // 1000000, int(sys.argv[2]) // 1000))
if worst > bound:
    sys.exit("a capture stalled for %d ms" % (worst // 1000000))
PYEOF
)
is "scans well formed, none stalled" "$?" 0
echo "# $out"

# Accesses: each one succeeded or met a running capture; both happened.
for w in ws_writer.a ws_writer.b ws_reader.a ws_reader.b cb_writer.a cb_reader.a \
	sf_writer.a sf_reader.a; do
	echo "# $w: $(count "$w" ok) done, $(count "$w" busy) busy, $(count "$w" err) errors"
	is "$w: no error but EBUSY" "$(grep '^err' "$T/log.$w" | sort | uniq -c | head -n 3)" ""
	ok "$w: some accesses succeeded" [ "$(count "$w" ok)" -gt 0 ]
done
ws_busy=$(($(count ws_writer.a busy) + $(count ws_reader.a busy)))
ok "calibration_data accesses met running captures ($ws_busy EBUSY)" [ "$ws_busy" -gt 0 ]

# No torn blob: parameters 1..26 and 30..35 of every read are those of one
# blob, 27..29 each one of the calibbias encodings.
out=$("$PY" - "$T" $enc <<'PYEOF'
import glob, sys
t, enc = sys.argv[1], {int(e, 16) for e in sys.argv[2:]}
def words(b):
    return [int.from_bytes(b[i:i + 4], "little") for i in range(8, 148, 4)]
blobs = [words(open("%s/blob.%d" % (t, k), "rb").read()) for k in range(4)]
enc |= set(blobs[0][26:29])
keep = [i for i in range(35) if not 26 <= i <= 28]
n = 0
seen = set()
for path in glob.glob(t + "/reads.*"):
    data = open(path, "rb").read()
    if len(data) % 148:
        sys.exit("%s: %d bytes, not whole blobs" % (path, len(data)))
    for off in range(0, len(data), 148):
        w = words(data[off:off + 148])
        k = [k for k, b in enumerate(blobs) if all(w[i] == b[i] for i in keep)]
        if not k:
            sys.exit("read %d is not one written blob: %s" %
                     (n, " ".join("%08x" % x for x in w)))
        bad = [x for x in w[26:29] if x not in enc]
        if bad:
            sys.exit("read %d: calibbias words %s never written" % (n, bad))
        seen.add(k[0])
        n += 1
print("%d blobs read, all complete; blobs seen: %s" % (n, sorted(seen)))
if n < 2:
    sys.exit("too few reads")
PYEOF
)
is "no torn calibration_data blob" "$?" 0
echo "# $out"

# shellcheck disable=SC2086
is "calibbias reads are values written" \
	"$(sort -u "$T/vals.cb_reader.a" | grep -vxF -e ${CALIBBIAS// / -e })" ""
# shellcheck disable=SC2086
is "sampling_frequency reads are rates written" \
	"$(sort -u "$T/vals.sf_reader.a" | grep -vxF -e ${RATES// / -e } -e ${MAGN_RATES// / -e })" ""

# What the driver reports as calibbias is what the chip holds.
for a in x y z; do
	v=$(cat "$DEV/in_accel_${a}_calibbias")
	p=$(dbg_get params $((27 + $(expr index xyz $a) - 1)))
	is "calibbias $a ($v) is the chip's parameter ($p)" "${ENC[$v]:-not written}" "$p"
done

# The device still works: capture, restore, save, read.
ok "chip idle after the storm" chip_idle
# shellcheck disable=SC2086
ok "a capture after the storm" sh -c "iio_readdev -b 16 -s 20 em7180 $CHANNELS > $T/after.bin"
is "20 scans" "$(stat -c %s "$T/after.bin")" 640
ok "restore the initial blob" dd if="$T/blob.0" of="$DEV/calibration_data" bs=148 status=none
is "the chip has it" "$(sim_ws_params)" "$(blob_words <"$T/blob.0")"
ok "save" dd if="$DEV/calibration_data" of="$T/saved" bs=4096 status=none
ok "save equals the restored blob" cmp "$T/blob.0" "$T/saved"
like "accel reads" "$(cat "$DEV"/in_accel_{x,y,z}_raw | tr '\n' ' ')" '^-?[0-9]+ -?[0-9]+ -?[0-9]+ $'
ok "chip idle at the end" chip_idle
knob gbias_period_ms 2000

rm -rf "$T"
done_testing
