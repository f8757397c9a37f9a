#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# A save killed at every step leaves the old file or the new one, never a
# broken one. A save is traced once with strace(1) to list its system
# calls; then, for each call from the first that touches the state
# directory to the last, a save runs under strace with SIGKILL injected on
# entry to that call (the process dies before the call runs, so every
# point between two calls is a kill point), and the state file must be a
# valid file equal to the old one or to a new save.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
key=$(sentral-warmstart key)
f=$STATE/$key.ws
ok "calibrated" calibrate_by_motion
ok "a first save" sentral-warmstart save

# The calls of one save (--force: the policy always says yes), numbered
# per call name as strace's when= counts them. A save rewrites the
# driver's copy in firmware/ only when the chip's calibration changed
# since the last: removed before every save, each makes the same calls.
no_copy() { rm -f "$STATE"/firmware/caldata-*; }
trace=/tmp/save.trace
no_copy
ok "a traced save" strace -qq -o "$trace" -e signal=none \
	sentral-warmstart save --force
old=$(md5sum <"$f")
calls=$(awk -v dir="$STATE" '
	match($0, /^[a-z_0-9]+\(/) {
		name = substr($0, 1, RLENGTH - 1)
		n[name]++
		if (!started && index($0, "\"" dir)) started = 1
		if (started) print name "=" n[name]
	}' "$trace")
total=$(echo "$calls" | wc -l)
echo "# $total calls of a save from the first in $STATE:" $calls
ok "the save's calls from the state directory on were found ($total)" \
	test "$total" -ge 8
for c in openat write fsync rename; do
	like "they include $c" "$calls" "(^|[[:space:]])$c[a-z]*="
done

is_valid() {
	sentral-warmstart show "$f" >/dev/null 2>&1
}

olds=0 news=0 broken=0 lived=0
for c in $calls; do
	name=${c%=*} k=${c#*=}
	sleep 1	# a new save differs from the last in its time
	no_copy
	# (in a subshell: the shell's "Killed" notice goes with its stderr)
	(strace -qq -o /dev/null -e trace="$name" \
		-e inject="$name:signal=KILL:when=$k" \
		sentral-warmstart save --force >/dev/null 2>&1) 2>/dev/null
	rc=$?
	[ "$rc" -eq 0 ] && lived=$((lived + 1))
	if ! is_valid; then
		broken=$((broken + 1))
		echo "# killed at $c: $(sentral-warmstart show "$f" 2>&1 | head -n1)"
	elif [ "$(md5sum <"$f")" = "$old" ]; then
		olds=$((olds + 1))
	else
		news=$((news + 1))
		old=$(md5sum <"$f")
	fi
done
echo "# $total kill points: old file $olds, new file $news, broken $broken, not killed $lived"
is "no kill point leaves a broken file" "$broken" 0
is "every save was killed" "$lived" 0
ok "some kill points leave the old file" test "$olds" -gt 0
ok "and those after the rename the new one" test "$news" -gt 0
ls -A "$STATE" | sed 's/^/# left in the state directory: /'
ok "a save after it all" sentral-warmstart save --force
is "the state directory holds the file, the writers' lock file and the driver's files: no temporary file left" \
	"$(ls -A "$STATE" | tr '\n' ' ')" ".$key.ws.lock $key.ws firmware "
is "and firmware/ the driver's file of this chip alone" \
	"$(ls -A "$STATE/firmware" | sed 's/^caldata-[^.]*\.bin$/caldata/')" caldata

done_testing
