#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# Writers of one saved file take turns. Three simulated chips: A holds a
# good calibration (G), B and C a worse one (W, restored from A's with a
# hard-iron offset 2 uT off). A watcher of A (--poll 1 --interval 1
# --margin 0) and two loops saving B's and C's calibration into A's file
# through the save policy (save --file), B's renaming 300 ms late, race
# for it. Each round puts a
# mediocre file (M, 4.5 %, which both G and W beat) in place under the
# writers' lock; then exactly one writer may replace it: whoever comes
# second must see the first one's file, not M. A writer that judged by M
# after another had replaced it would say so ("better than the saved
# 4.501%") a second time in the round, and could leave W over G. At the
# end of every round the file is G. The chips have the application note's
# layout: the order of calibrations is the score's (without a score every
# stable calibration that differs from the file's replaces it, and the
# writers would take turns replacing each other's).
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

ROUNDS=30
modprobe -d "$SENTRAL_MODROOT" sentral_sim adapters=3 knobs=appnote_layout=1 &&
	modprobe -d "$SENTRAL_MODROOT" em7180_i2c

# The IIO device of the chip on the adapter named $1 (sentral-sim-1...).
dev_on() {
	local a d
	for a in /sys/bus/i2c/devices/i2c-*; do
		[ "$(cat "$a/name" 2>/dev/null)" = "$1" ] || continue
		for d in /sys/bus/iio/devices/iio:device*; do
			case $(readlink -f "$d") in
			*/"${a##*/i2c-}-0028"/*) echo "${d##*/}"; return 0 ;;
			esac
		done
	done
	return 1
}
# The file's raw score, as a number.
score_of() {
	od -An -tu2 -j18 -N2 "$1" | tr -d ' '
}
# The state file holds G; it no longer holds M.
holds_g() {
	[ "$(score_of "$f")" = "$G" ]
}
not_m() {
	[ "$(score_of "$f")" != "$M" ]
}
# A copy of file $1 at $2 with the header's raw score $3, CRC fixed.
with_score() {
	ws_edit "$1" "$2" "18:<H:$3"
}

A=$(dev_on sentral-sim)
B=$(dev_on sentral-sim-1)
C=$(dev_on sentral-sim-2)
ok "three chips: $A, $B, $C" test -n "$A" -a -n "$B" -a -n "$C"
key=$(sentral-warmstart --device "$A" key)
f=$STATE/$key.ws
lock=$STATE/.$key.ws.lock

ok "A calibrated by simulated motion" calibrate_by_motion
ok "A's calibration saved" sentral-warmstart --device "$A" save
is "judged by its score" "$(ws_header "$f" | cut -d' ' -f3)" 1
G=$(score_of "$f")
# W: A's coefficients with parameter 21 (a hard-iron offset) 2 uT off.
ws_edit "$f" /tmp/w.ws '112:<f:+=2.0'
for d in "$B" "$C"; do
	ok "$d: W restored" sentral-warmstart --device "$d" restore --file /tmp/w.ws
done
W=$(sentral-warmstart --device "$B" status --json |
	sed -n 's/.*"calibration_score_raw":\([0-9]*\).*/\1/p')
M=34243	# 4.501 %
echo "# raw scores: G $G, W $W, M $M"
ok "G better than W better than M" test "$G" -lt "$W" -a "$W" -lt "$M"
with_score "$f" /tmp/m.ws "$M"


sentral-warmstart --device "$A" watch --poll 1 --interval 1 --margin 0 >>/tmp/race-a.log 2>&1 &
watcher=$!
# B's saves rename 300 ms late (strace delays the call): the window
# between a writer's look at the file and its rename, a few microseconds
# on one CPU, is then wide enough for the others to come in, every round.
slow="strace -qq -o /dev/null -e trace=rename,renameat,renameat2
	-e inject=rename,renameat,renameat2:delay_enter=300000"
for d in "$B" "$C"; do
	[ "$d" = "$B" ] && pre=$slow || pre=
	(
		while [ ! -e /tmp/race-stop ]; do
			$pre sentral-warmstart --device "$d" save --file "$f"
		done
	) >>"/tmp/race-$d.log" 2>&1 &
done
wait_for 5 grep -q "^watching" /tmp/race-a.log

logs=(/tmp/race-a.log "/tmp/race-$B.log" "/tmp/race-$C.log")
# Replacements of M, and W left at the end of a round.
twice=0 worse=0 unchanged=0
for r in $(seq 1 "$ROUNDS"); do
	for l in "${logs[@]}"; do echo "round $r" >>"$l"; done
	flock -w 30 "$lock" sh -c "cp /tmp/m.ws '$STATE/.m.tmp' && mv -f '$STATE/.m.tmp' '$f'"
	wait_for 10 not_m || unchanged=$((unchanged + 1))
	# A W that came first is replaced by the watcher within a poll and
	# an interval; then nobody may put W back.
	wait_for 6 holds_g
	sleep 1
	holds_g || { worse=$((worse + 1)); echo "# round $r ends with raw score $(score_of "$f")"; }
	n=$(cat "${logs[@]}" | awk -v r="round $r" '$0 == r { on = 1; next } /^round / { on = 0 }
		on && /^saved .*than the saved 4\.501%/' | wc -l)
	[ "$n" -le 1 ] || { twice=$((twice + 1)); echo "# round $r: $n writers replaced M"; }
done
touch /tmp/race-stop
kill -TERM "$watcher"
wait
echo "# $(cat "${logs[@]}" | grep -c '^saved ') saves in $ROUNDS rounds, $(cat "${logs[@]}" | grep -c '^not saving') refusals"
grep -h "error" "${logs[@]}" | sort | uniq -c | sed 's/^/# /'
is "M replaced in every round" "$unchanged" 0
is "no round where two writers replaced M (each judged by the file the other had replaced)" "$twice" 0
is "no round ends with W over G" "$worse" 0
ok "the file is valid" sentral-warmstart show "$f"
nok "no writer failed" grep -q "error" "${logs[@]}"

done_testing
