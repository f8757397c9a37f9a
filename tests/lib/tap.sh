# SPDX-License-Identifier: GPL-2.0-only
# shellcheck shell=bash
#
# Minimal TAP producer for the end-to-end scripts.  Source it, call the
# checks, end with done_testing.  Every check prints "ok N - DESC" or
# "not ok N - DESC" followed by what was expected.

_tap_n=0
_tap_fail=0

_tap_result() {
	local passed=$1 desc=$2
	_tap_n=$((_tap_n + 1))
	if [ "$passed" -eq 1 ]; then
		echo "ok $_tap_n - $desc"
	else
		_tap_fail=$((_tap_fail + 1))
		echo "not ok $_tap_n - $desc"
	fi
}

# ok DESC CMD...: CMD exits 0.
ok() {
	local desc=$1 out
	shift
	if out=$("$@" 2>&1); then
		_tap_result 1 "$desc"
	else
		_tap_result 0 "$desc"
		echo "#   command failed ($?): $*"
		[ -n "$out" ] && sed 's/^/#   /' <<<"$out" | head -n 20
	fi
	return 0
}

# nok DESC CMD...: CMD exits non-zero.
nok() {
	local desc=$1 out
	shift
	if out=$("$@" 2>&1); then
		_tap_result 0 "$desc"
		echo "#   command succeeded but should have failed: $*"
		[ -n "$out" ] && sed 's/^/#   /' <<<"$out" | head -n 20
	else
		_tap_result 1 "$desc"
	fi
	return 0
}

# is DESC ACTUAL EXPECTED
is() {
	if [ "$2" = "$3" ]; then
		_tap_result 1 "$1"
	else
		_tap_result 0 "$1"
		printf '#   got:      %s\n#   expected: %s\n' "$2" "$3"
	fi
}

# like DESC ACTUAL ERE
like() {
	if [[ $2 =~ $3 ]]; then
		_tap_result 1 "$1"
	else
		_tap_result 0 "$1"
		printf '#   got:         %s\n#   to match:    %s\n' "$2" "$3"
	fi
}

# Print the plan and a summary line; exit 1 when a check failed or none ran.
done_testing() {
	echo "1..$_tap_n"
	echo "$((_tap_n - _tap_fail)) passed, $_tap_fail failed"
	[ "$_tap_n" -gt 0 ] && [ "$_tap_fail" -eq 0 ]
	exit
}
