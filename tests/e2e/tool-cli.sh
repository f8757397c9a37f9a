#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# sentral-warmstart's command line with the manners of i2c-tools and
# coreutils (issue 33, item 3):
# - --help and --version win over the rest of the line, and exit 0; each
#   command's help lists its options, within 80 columns;
# - numbers are decimal, hexadecimal only after 0x.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "the driver is bound" test -n "$DEV"
bus=$(sim_bus)
name=$(cat "/sys/class/i2c-dev/i2c-$bus/name")
is "the simulator's adapter is named sentral-sim" "$name" sentral-sim
driver_key=$(sentral-warmstart key)

# --help and --version win, anywhere on the line, and exit 0.
out=$(sentral-warmstart --version extra 2>&1)
is "--version extra: exit 0" $? 0
like "and the version" "$out" '^sentral-warmstart [0-9]'
out=$(sentral-warmstart status --bogus --timeout x --help 2>&1)
is "status --bogus --timeout x --help: exit 0" $? 0
like "status's help" "$out" '^Usage: sentral-warmstart .* status \[--file F\] \[--json\]'
out=$(sentral-warmstart show -- --help 2>&1)
is "after --, --help is show's FILE: exit 66" $? 66
out=$(sentral-warmstart accel-cal --help)
like "accel-cal --help: its synopsis has --max-score" \
	"$(echo "$out" | sed '/^$/q')" 'accel-cal .*\[--max-score S\]'
like "and its options --max-score, described" "$out" \
	$'\n      --max-score S     acceptable score'
wide=
for c in "" status save restore calibrate accel-cal show key watch import-board; do
	# shellcheck disable=SC2086
	wide+=$(sentral-warmstart $c --help | awk -v c="${c:-all}" \
		'length > 80 { print c ": " length ": " $0 }')
done
is "every help within 80 columns" "$wide" ""
sentral-warmstart --help >/dev/full 2>/dev/null
is "--help into a full disk: exit 74" $? 74
out=$(sentral-warmstart status --force 2>&1)
is "status --force without --i2c: exit 64" $? 64
like "said so, and what to try" "$out" \
	"--force is an option of 'status' only with --i2c.*Try 'sentral-warmstart status --help'"

# Numbers: decimal, a leading 0 no octal; hex after 0x.
out=$(sentral-warmstart calibrate --timeout 08 --target-score 101 2>&1)
is "--timeout 08 is taken (the error is the next option's): exit 64" $? 64
like "naming --target-score" "$out" "--target-score: '101' is out of range \(0 to 100\)"
# (bounded: a tool that took "+5" would watch for ever)
out=$(timeout 10 sentral-warmstart watch --poll +5 2>&1)
like "--poll +5: refused, naming the option" "$out" \
	"--poll: '\+5' is not a number \(decimal, or hexadecimal after 0x\)"

done_testing
