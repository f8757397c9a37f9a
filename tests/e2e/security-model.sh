#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --sim-knobs appnote_layout=1
#
# The threat model of Documentation/iio/sentral.rst ("Security"), one check
# per claim: who may read and write each attribute and device node, what an
# unprivileged user (uid 65534 through setpriv) can and cannot do, how the
# tool treats its state directory and files (modes, symlinks at the file and
# at its temporary name, ownership, sizes, FIFOs, atomic replace), what a
# forged file can and cannot do, and what a lying chip can do to the driver.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

NOBODY=(setpriv --reuid=65534 --regid=65534 --clear-groups)
as_nobody() {
	"${NOBODY[@]}" "$@"
}
served() {
	dbg_get stats params_served
}
# The stat mode, owner and group of a path.
perm() {
	stat -c '%a %U %G' "$1"
}

ok "setpriv is available" command -v setpriv
is "setpriv drops to uid 65534" "$(as_nobody id -u)" 65534
DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
client=$(basename "$(dirname "$(readlink -f "$DEV")")")
bus=$(sim_bus)
key=$(sentral-warmstart status --json | json_field key)
f=$STATE/$key.ws

# --- Attribute and node modes --------------------------------------------
is "calibration_data is 0600 root" "$(perm "$DEV/calibration_data")" "600 root root"
for a in in_magn_calibration_auto_status in_magn_calibration_score \
	in_anglvel_calibration_update in_magn_calibration_update; do
	is "$a is 0444" "$(perm "$DEV/$a")" "444 root root"
done
for a in in_accel_x_calibbias in_accel_sampling_frequency \
	in_magn_sampling_frequency buffer0/enable buffer0/in_accel_x_en \
	trigger/current_trigger; do
	is "$a is 0644 root" "$(perm "$DEV/$a")" "644 root root"
done
is "/dev/iio:device is 0600 root" "$(perm "/dev/$(basename "$DEV")")" \
	"600 root root"
is "/dev/i2c-$bus is 0600 root" "$(perm "/dev/i2c-$bus")" "600 root root"
is "debugfs is 0700 root" "$(perm /sys/kernel/debug)" "700 root root"
nok "the udev rule sets no device node mode" \
	grep -qE '^[^#]*(MODE|OWNER|GROUP)' "$SENTRAL_ROOT"/tools/sentral-warmstart/udev/*.rules*

# Register access for debugging (IIO's direct_reg_access) and the
# recoveries from resets: root's alone
reg_access=/sys/kernel/debug/iio/$(basename "$DEV")/direct_reg_access
recovery=/sys/kernel/debug/iio/$(basename "$DEV")/recovery
is "the driver's debugfs files: register access, the firmware, recoveries" \
	"$(ls "$(dirname "$reg_access")" | tr '\n' ' ')" "direct_reg_access firmware_version recovery "
is "firmware_version: 0400 root" "$(perm "$(dirname "$reg_access")/firmware_version")" "400 root root"
is "register access: 0644 root" "$(perm "$reg_access")" "644 root root"
is "recoveries: 0400 root" "$(perm "$recovery")" "400 root root"
nok "nobody cannot read registers through it" as_nobody cat "$reg_access"
# The IIO core makes every info attribute root-writable; only
# sampling_frequency and calibbias take a write, within their range.
knob stats 0
nok "root: writing in_accel_x_raw fails" sh -c "echo 1 >$DEV/in_accel_x_raw"
nok "root: writing in_accel_scale fails" sh -c "echo 1 >$DEV/in_accel_scale"
nok "root: calibbias out of range fails" sh -c "echo 40000 >$DEV/in_accel_x_calibbias"
is "none of them reached the chip" "$(dbg_get stats transactions)" 0

# --- What an unprivileged user cannot do ---------------------------------
knob stats 0
nok "nobody cannot read calibration_data" as_nobody dd if="$DEV/calibration_data" of=/dev/null bs=4096 count=1
head -c 148 /dev/zero >/tmp/zero.blob
nok "nobody cannot write calibration_data" as_nobody dd if=/tmp/zero.blob of="$DEV/calibration_data" bs=148 count=1
is "no parameter transferred" "$(served)" 0
bias=$(cat "$DEV/in_accel_x_calibbias")
freq=$(cat "$DEV/in_accel_sampling_frequency")
nok "nobody cannot write calibbias" as_nobody sh -c "echo 7 >$DEV/in_accel_x_calibbias"
is "calibbias unchanged" "$(cat "$DEV/in_accel_x_calibbias")" "$bias"
nok "nobody cannot write sampling_frequency" \
	as_nobody sh -c "echo 50 >$DEV/in_accel_sampling_frequency"
is "sampling_frequency unchanged" "$(cat "$DEV/in_accel_sampling_frequency")" "$freq"
nok "nobody cannot enable a scan element" as_nobody sh -c "echo 1 >$DEV/buffer0/in_accel_x_en"
nok "nobody cannot enable the buffer" as_nobody sh -c "echo 1 >$DEV/buffer0/enable"
nok "nobody cannot set the trigger" as_nobody sh -c "echo x >$DEV/trigger/current_trigger"
nok "nobody cannot open the IIO character device" \
	as_nobody dd if="/dev/$(basename "$DEV")" of=/dev/null bs=1 count=1
nok "nobody cannot open i2c-dev" as_nobody dd if="/dev/i2c-$bus" of=/dev/null bs=1 count=1
nok "nobody cannot reach debugfs (simulator, regmap)" as_nobody ls /sys/kernel/debug/
nok "nobody cannot unbind the driver" \
	as_nobody sh -c "echo $client >/sys/bus/i2c/drivers/em7180/unbind"
ok "the driver is still bound" test -e "$DEV/name"

# --- What an unprivileged user can do ------------------------------------
ok "nobody can read in_magn_calibration_auto_status" as_nobody cat "$DEV/in_magn_calibration_auto_status"
ok "nobody can read in_magn_calibration_score" as_nobody cat "$DEV/in_magn_calibration_score"
nok "nobody cannot read the chip identity (debugfs, as bno055's firmware_version)" \
	as_nobody cat "/sys/kernel/debug/iio/${DEV##*/}/firmware_version"
knob stats 0
ok "nobody can read a raw sample" as_nobody cat "$DEV/in_accel_z_raw"
ok "which is a bus transaction" test "$(dbg_get stats transactions)" -gt 0
echo 1 >"$DEV/buffer0/in_accel_x_en"
echo 1 >"$DEV/buffer0/enable"
out=$(as_nobody cat "$DEV/in_accel_z_raw" 2>&1)
like "during buffered capture it fails with EBUSY" "$out" "busy"
echo 0 >"$DEV/buffer0/enable"
echo 0 >"$DEV/buffer0/in_accel_x_en"
knob stats 0
ok "nobody can read calibbias" as_nobody cat "$DEV/in_accel_x_calibbias"
is "an unprivileged calibbias read transfers no parameter (fusion not paused)" \
	"$(served)" 0
# An unprivileged reader consumes no update: the flags are everyone's
# until root reads or writes the warm start. No update of the chip's own
# (one every 2 s while still) between the read and the check; then latch
# one, and stop further ones.
knob gbias_period_ms 600000
dd if="$DEV/calibration_data" of=/dev/null bs=148 count=1 status=none
is "no gyro bias update since the warm start was read" \
	"$(cat "$DEV/in_anglvel_calibration_update")" 0
knob gbias_period_ms 100
sleep 0.5
cat "$SIM_DBG/state" >/dev/null
knob gbias_period_ms 600000
is "nobody sees the latched gyro bias update" \
	"$(as_nobody cat "$DEV/in_anglvel_calibration_update")" 1
sleep 0.6
is "and root sees it after that read" "$(cat "$DEV/in_anglvel_calibration_update")" 1

# --- State directory and files -------------------------------------------
# Created 0700 / 0600 whatever the umask.
rm -rf "$STATE"
ok "save with umask 000" sh -c 'umask 000; exec sentral-warmstart save --force'
is "state dir created 0700 root" "$(perm "$STATE")" "700 root root"
is "state file created 0600 root" "$(perm "$f")" "600 root root"
nok "nobody cannot list the state dir" as_nobody ls "$STATE"
nok "nobody cannot read the state file" as_nobody cat "$f"
# A directory open to others is refused, never chmod'ed: with --state-dir
# /var/lib the tool would otherwise change a directory other services own.
chmod 0755 "$STATE"
out=$(sentral-warmstart save --force 2>&1)
is "save into a root-owned 0755 state dir: refused, exit 77" $? 77
like "saying what to do" "$out" "group or others have access \(mode 0755\).*chmod 0700"
is "its mode is left alone" "$(perm "$STATE")" "755 root root"
mkdir -p /tmp/shared && chmod 0755 /tmp/shared
out=$(sentral-warmstart --state-dir /tmp/shared save --force 2>&1)
is "--state-dir naming a shared directory: exit 77" $? 77
is "which keeps its mode" "$(stat -c %a /tmp/shared)" 755
chmod 0700 "$STATE"

# The tool gives an unprivileged user nothing: it is not setuid.
is "the tool is not setuid or setgid" \
	"$(find "$(command -v sentral-warmstart)" -perm /6000 | wc -l)" 0
knob stats 0
nok "nobody: save fails" as_nobody sentral-warmstart save --force --file /tmp/nobody.ws
nok "and writes no file" test -e /tmp/nobody.ws
nok "nobody: restore fails" as_nobody sentral-warmstart restore
is "and transfers no parameter" "$(served)" 0
# The chip's attributes are world-readable: status shows them to anyone.
out=$(as_nobody sentral-warmstart status 2>&1)
is "nobody: status exits 0" $? 0
like "with the chip's part" "$out" \
	$'\ncalibration level: +[0-4] \\([a-z ]+\\)\ncalibration score: +[0-9.]+%\n'
nok "and no restored line: that needs the file" grep -q '^restored:' <<<"$out"
like "and says the file needs root" "$out" "saved file: .*needs root"

# A real calibration to work with.
ok "calibrate by simulated motion" calibrate_by_motion
ok "save it" sentral-warmstart save --force
is "judged by the score (the application note's layout)" "$(ws_header "$f" | cut -d' ' -f3)" 1
cp -p "$f" /tmp/good.ws

# restore_refused DESC EXIT ARGS...: the tool exits EXIT within 20 s, and
# no parameter reaches the chip. READS=35: a file of another chip or
# firmware, whose identity the driver refuses: the tool reads the blob
# once to name the difference, and writes nothing.
restore_refused() {
	local desc=$1 want=$2 before out rc params
	shift 2
	before=$(served)
	params=$(sim_ws_params)
	out=$(timeout 20 sentral-warmstart restore "$@" 2>&1)
	rc=$?
	is "$desc: exit $want" "$rc" "$want"
	if [ "${READS:-0}" = 0 ]; then
		is "$desc: the chip is not touched" "$(served)" "$before"
	else
		is "$desc: one read of the blob, nothing written" \
			"$(served) $(sim_ws_params)" "$((before + READS)) $params"
	fi
	[ "$rc" = "$want" ] || echo "$out" | sed 's/^/#   /'
}

# Symlinks at the state file path: never followed, on save or on restore.
echo precious >/tmp/victim
rm -f "$f"
ln -s /tmp/victim "$f"
out=$(sentral-warmstart save --force 2>&1)
is "save through a symlink at the state path: exit 77" $? 77
is "the link target is untouched" "$(cat /tmp/victim)" precious
ok "the link is still a link" test -L "$f"
rm -f "$f"
ln -s /tmp/good.ws "$f"
restore_refused "restore through a symlink to a valid file" 77
rm -f "$f"
ln -s /tmp/absent.ws "$f"
out=$(sentral-warmstart save --force 2>&1)
is "save through a dangling symlink: exit 77" $? 77
nok "its target is not created" test -e /tmp/absent.ws
rm -f "$f"
cp -p /tmp/good.ws "$f"

# A symlink planted at the temporary file's name. The name is random: a
# getrandom() shim makes the first N calls return zeros, so the name is
# known (".KEY.ws.00000000.tmp").
cat >/tmp/zero-rand.c <<'EOF'
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

ssize_t getrandom(void *buf, size_t len, unsigned int flags)
{
	static ssize_t (*real)(void *, size_t, unsigned int);
	static int calls;
	const char *n = getenv("ZERO_RAND_CALLS");

	if (calls++ < (n ? atoi(n) : 0)) {
		memset(buf, 0, len);
		return (ssize_t)len;
	}
	if (!real)
		real = (ssize_t (*)(void *, size_t, unsigned int))
			dlsym(RTLD_NEXT, "getrandom");
	return real(buf, len, flags);
}
EOF
ok "build the getrandom shim" cc -shared -fPIC -o /tmp/zero-rand.so /tmp/zero-rand.c -ldl
tmpname=$STATE/.$key.ws.00000000.tmp
ln -s /tmp/victim "$tmpname"
out=$(LD_PRELOAD=/tmp/zero-rand.so ZERO_RAND_CALLS=1000 sentral-warmstart save --force 2>&1)
is "the shim pins the name: every attempt collides, save fails (exit 74)" $? 74
like "with EEXIST" "$out" "temporary file: File exists"
out=$(LD_PRELOAD=/tmp/zero-rand.so ZERO_RAND_CALLS=1 sentral-warmstart save --force 2>&1)
is "a symlink at the first temporary name: save takes another name (exit 0)" $? 0
is "the link target is untouched" "$(cat /tmp/victim)" precious
ok "the planted link is left alone" test -L "$tmpname"
tail -c +33 "$f" | head -c 140 >/tmp/saved.blob
dd if="$DEV/calibration_data" bs=4096 count=1 status=none | tail -c +9 >/tmp/chip.blob
ok "the state file holds the chip's blob" cmp /tmp/saved.blob /tmp/chip.blob
rm -f "$tmpname"
rm -f /tmp/victim

# Atomic replace: a reader of the old file keeps a complete old file.
cp "$f" /tmp/old.ws
ino=$(stat -c %i "$f")
exec 3<"$f"
ok "save --force over an existing file" sentral-warmstart save --force
ok "an open reader still sees the complete old file" cmp - /tmp/old.ws <&3
exec 3<&-
ok "the file was replaced, not rewritten in place" test "$(stat -c %i "$f")" != "$ino"
is "nothing but the state file, the writers' lock and the driver's files: no temporary file" \
	"$(ls -A "$STATE" | tr '\n' ' ')" ".$key.ws.lock $key.ws firmware "
is "the writers' lock is root's, 0600, a regular file" \
	"$(stat -c '%a %U %F' "$STATE/.$key.ws.lock")" "600 root regular empty file"
# A save killed between its temporary file and the rename leaves the file;
# the next save removes it (ours by name, unlocked, older than 2 s).
cp "$f" "$STATE/.$key.ws.0badf00d.tmp"
touch -d '-1 minute' "$STATE/.$key.ws.0badf00d.tmp"
ok "save after a killed save" sentral-warmstart save --force
is "the killed save's temporary file is gone" \
	"$(ls -A "$STATE" | tr '\n' ' ')" ".$key.ws.lock $key.ws firmware "
# A write that fails (ENOSPC) leaves the old file as it was.
mkdir -p /tmp/full
mount -t tmpfs -o size=8k,mode=0700 tmpfs /tmp/full
ok "save into a small state dir" sentral-warmstart --state-dir /tmp/full save --force
cp "/tmp/full/$key.ws" /tmp/full-old.ws
dd if=/dev/zero of=/tmp/full/filler bs=1k count=64 status=none 2>/dev/null
out=$(sentral-warmstart --state-dir /tmp/full save --force 2>&1)
is "save on a full file system: exit 74" $? 74
ok "the old file is intact" cmp "/tmp/full/$key.ws" /tmp/full-old.ws
is "no temporary file left" "$(ls -A /tmp/full | grep -c '\.tmp$')" 0
umount /tmp/full

# Ownership and mode of what is read back: only root's own, private files.
cp -p /tmp/good.ws "$f"
ok "the good file restores" sentral-warmstart restore
chown 65534:65534 "$f"
restore_refused "a state file owned by another user" 77
out=$(sentral-warmstart status 2>&1)
is "status refuses it too: exit 77" $? 77
chown 0:0 "$f"
chmod 0666 "$f"
restore_refused "a world-writable state file" 77
chmod 0620 "$f"
restore_refused "a group-writable state file" 77
chmod 0600 "$f"
chown 65534:65534 "$STATE"
restore_refused "a state dir owned by another user" 77
out=$(sentral-warmstart save --force 2>&1)
is "save into a state dir owned by another user: exit 77" $? 77
chown 0:0 "$STATE"
chmod 0777 "$STATE"
restore_refused "a world-writable state dir" 77
out=$(sentral-warmstart save --force 2>&1)
is "save into a world-writable state dir: exit 77" $? 77
chmod 0700 "$STATE"
cp -p /tmp/good.ws /tmp/other.ws
chown 65534 /tmp/other.ws
restore_refused "a --file file owned by another user" 77 --file /tmp/other.ws
chown 0 /tmp/other.ws
chmod 0666 /tmp/other.ws
restore_refused "a world-writable --file file" 77 --file /tmp/other.ws
ok "save --file into /tmp" sentral-warmstart save --force --file /tmp/mine.ws
is "leaves the mode of /tmp alone" "$(stat -c %a /tmp)" 1777
mv "$STATE" /var/lib/sw.real
mkdir -m 0700 /tmp/evil
cp -p /tmp/good.ws /tmp/evil/
mv "/tmp/evil/good.ws" "/tmp/evil/$key.ws"
ln -s /tmp/evil "$STATE"
restore_refused "a state dir that is a symlink" 77
out=$(sentral-warmstart save --force 2>&1)
is "save through a state dir that is a symlink: exit 77" $? 77
# A trailing slash made the kernel follow the link despite O_NOFOLLOW.
restore_refused "a symlinked state dir named with a trailing slash" 77 \
	--state-dir "$STATE/"
out=$(sentral-warmstart --state-dir "$STATE/" save --force 2>&1)
is "save through it: exit 77" $? 77
ok "the file behind the link is untouched" cmp "/tmp/evil/$key.ws" /tmp/good.ws
nok "and not moved aside" test -e "/tmp/evil/$key.ws.refused"
restore_refused "a --file in a symlinked directory" 77 --file "$STATE/$key.ws"
rm "$STATE"
mv /var/lib/sw.real "$STATE"
ok "the good file restores again" sentral-warmstart restore

# Wrong sizes and types: refused at once, at most 4 KiB read.
truncate -s 1T /tmp/huge.ws
restore_refused "a 1 TiB sparse file" 65 --file /tmp/huge.ws
: >/tmp/empty.ws
restore_refused "an empty file" 65 --file /tmp/empty.ws
restore_refused "/dev/zero" 65 --file /dev/zero
restore_refused "a directory" 65 --file /tmp/evil
mkfifo -m 0600 /tmp/fifo.ws
restore_refused "a FIFO with no writer" 65 --file /tmp/fifo.ws
mv "$f" /tmp/good2.ws
mkfifo -m 0600 "$f"
restore_refused "a FIFO at the state path" 65
out=$(timeout 20 sentral-warmstart save --force 2>&1)
is "save over a FIFO at the state path: exit 65" $? 65
ok "the FIFO is left alone" test -p "$f"
rm -f "$f"
mkdir -m 0700 "$f"
out=$(timeout 20 sentral-warmstart save --force 2>&1)
is "save over a directory at the state path: exit 65" $? 65
rmdir "$f"
mv /tmp/good2.ws "$f"

# forge FILE OFFSET STRUCT-FORMAT VALUE: the saved file with a field
# rewritten and the CRC fixed, as anyone who can write the file can.
forge() {
	ws_edit "$f" "$1" "$2:$3:$4"
}
# Checked fields: refused with a valid CRC, nothing written. (The file is
# judged by the score: the firmware has the application note's layout.)
for case in "magic:0:<B:0" "version 3:8:<H:3" "payload size 139:28:<H:139" \
	"reserved bytes 30-31:30:<H:1" "param 1 +Inf:32:<I:0x7f800000" "param 20 signalling NaN:108:<I:0x7f800001" \
	"param 35 -Inf:168:<I:0xff800000" "ProductID 0x81:10:<B:0x81" \
	"ROM version 0x1234:12:<H:0x1234" "RAM version 0x1234:14:<H:0x1234" "calibration level 5:16:<B:5" \
	"judgement 3:17:<B:3" "a score below 0 %:18:<H:0x7fff"; do
	IFS=: read -r desc off fmt val <<<"$case"
	forge /tmp/forged.ws "$off" "$fmt" "$val"
	reads=0
	case $desc in ProductID* | ROM* | RAM*) reads=35 ;; esac
	READS=$reads restore_refused "$desc with a valid CRC" 65 --file /tmp/forged.ws
done
ws_edit "$f" /tmp/forged.ws '8:<H:1' '17:<B:2'
restore_refused "version 1 with byte 17 set, with a valid CRC" 65 --file /tmp/forged.ws
forge /tmp/forged.ws 32 '<I' 0x7f800000
restore_refused "--force does not override the file checks" 65 --file /tmp/forged.ws --force
forge /tmp/forged.ws 10 '<B' 0x81
before=$(served)
out=$(sentral-warmstart restore --file /tmp/forged.ws --force 2>&1)
ok "--force overrides the identity check" test "$(served)" -gt "$before"
# The driver refuses a non-finite blob itself, before any bus transaction.
tail -c +33 /tmp/good.ws | head -c 140 | with_header "$(sim_caldata_header)" >/tmp/inf.blob
printf '\x00\x00\x80\x7f' | dd of=/tmp/inf.blob bs=1 seek=84 conv=notrunc status=none
tail -c +33 /tmp/good.ws | head -c 140 | with_header "$(sim_caldata_header)" >/tmp/nan.blob
printf '\x01\x00\xc0\xff' | dd of=/tmp/nan.blob bs=1 seek=144 conv=notrunc status=none
knob stats 0
nok "root: a calibration_data write with +Inf fails" dd if=/tmp/inf.blob of="$DEV/calibration_data" bs=148 count=1
nok "root: a calibration_data write with a NaN fails" dd if=/tmp/nan.blob of="$DEV/calibration_data" bs=148 count=1
is "and no bus transaction happened" "$(dbg_get stats transactions)" 0
# What a forged but well-formed file can do: any finite parameters 1..35,
# nothing else.
params=$(cat "$SIM_DBG/params")
forge /tmp/forged.ws 104 '<I' 0x7e967699   # param 19 = 1e38
out=$(sentral-warmstart restore --file /tmp/forged.ws 2>&1)
is "a forged finite calibration is written (CRC is no authentication)" \
	"$(sim_param 19)" 0x7e967699
is "parameters outside 1..35 are never written" \
	"$(awk '$1 > 35' "$SIM_DBG/params")" "$(awk '$1 > 35' <<<"$params")"
forge /tmp/forged.ws 136 '<I' 0xbcbbe447   # param 27: -47 LSB (Table 1)
out=$(sentral-warmstart restore --file /tmp/forged.ws 2>&1)
knob stats 0
is "after a restore, calibbias shows the restored offset" \
	"$(as_nobody cat "$DEV/in_accel_x_calibbias")" -47
is "without a parameter transfer" "$(served)" 0
ok "the good file restores again" sentral-warmstart restore --file /tmp/good.ws
is "calibbias follows" "$(cat "$DEV/in_accel_x_calibbias")" 0

# --- A lying chip --------------------------------------------------------
# Never acknowledges: each access ends within about 1 s, chip running.
knob ack_never 1
t0=$(date +%s%N)
out=$(dd if="$DEV/calibration_data" of=/dev/null bs=4096 count=1 2>&1)
ms=$((($(date +%s%N) - t0) / 1000000))
like "calibration_data read with a chip that never acknowledges: ETIMEDOUT" "$out" \
	"Connection timed out"
ok "within 3 s ($ms ms)" test "$ms" -lt 3000
is "transfer mode ended" "$(dbg_get state transfer)" 0
is "algorithm running" "$(dbg_get state running)" 1
t0=$(date +%s%N)
out=$(timeout 20 sentral-warmstart restore --file /tmp/good.ws 2>&1)
is "restore with a chip that never acknowledges: exit 74" $? 74
ms=$((($(date +%s%N) - t0) / 1000000))
ok "within 3 s ($ms ms)" test "$ms" -lt 3000
knob ack_never 0
# NACKs: an error, never a hang.
knob nack_at 1
nok "calibration_data read with a NACK fails" dd if="$DEV/calibration_data" of=/dev/null bs=4096 count=1
is "transfer mode ended" "$(dbg_get state transfer)" 0
# A chip that hands out a NaN: the driver refuses the read (the write path
# would refuse that blob, so it could never be restored) and says which
# parameter; the tool saves nothing.
i2ctransfer -f -y "$bus" w2@0x28 0x54 0x80
i2ctransfer -f -y "$bus" w6@0x28 0x60 0x00 0x00 0xc0 0x7f 0x94
sleep 0.1
i2ctransfer -f -y "$bus" w2@0x28 0x64 0x00
i2ctransfer -f -y "$bus" w2@0x28 0x54 0x00
is "the chip now holds a NaN in parameter 20" "$(sim_param 20)" 0x7fc00000
like "the driver refuses to hand it out: EIO" \
	"$(dd if="$DEV/calibration_data" bs=4096 count=1 status=none 2>&1)" \
	"Input/output error"
like "and logs the parameter" "$(dmesg | tail -n 5)" \
	"parameter 20 holds 0x7fc00000, not a finite float"
out=$(sentral-warmstart save --force --file /tmp/nan.ws 2>&1)
is "save of a NaN read from the chip: exit 74" $? 74
like "and says why" "$out" "calibration_data"
nok "no file written" test -e /tmp/nan.ws
# A firmware upload that never completes: probe gives up in bounded time.
echo "$client" >/sys/bus/i2c/drivers/em7180/unbind
knob upload_ms 10000
knob power_cycle 1
t0=$(date +%s%N)
nok "bind while the upload never completes fails" \
	sh -c "echo $client >/sys/bus/i2c/drivers/em7180/bind"
ms=$((($(date +%s%N) - t0) / 1000000))
ok "within 12 s ($ms ms)" test "$ms" -lt 12000
ok "after two waits of 4 s" test "$ms" -ge 7900
like "with one reset in between" "$(dmesg | tail -n 20)" "firmware upload not done.*resetting"
nok "no IIO device" em7180_dir
knob upload_ms 10
knob power_cycle 1
ok "the chip uploads again" wait_for 5 sim_ready
ok "bind works again" sh -c "echo $client >/sys/bus/i2c/drivers/em7180/bind"
ok "and the device is back" wait_for 5 em7180_dir
DEV=$(em7180_dir)
ok "root writes calibbias" sh -c "echo 12 >$DEV/in_accel_x_calibbias"
knob stats 0
is "nobody reads the written value" "$(as_nobody cat "$DEV/in_accel_x_calibbias")" 12
is "without a parameter transfer" "$(served)" 0
is "the chip holds it" "$(sim_param 27)" "$(printf '0x%08x' "$(python3 -c 'import struct; print(struct.unpack("<I", struct.pack("<f", 12 * 0.000488))[0])')")"

done_testing
