# SPDX-License-Identifier: GPL-2.0-only
# shellcheck shell=bash
#
# What the kernel-side suites keep between checkouts.  build/ is thrown
# away with the checkout; what is costly to derive and depends only on
# inputs that rarely change lives in the user's cache directory instead,
# under a name carrying a hash of those inputs, so that a stale entry is
# never used and a missing one is made again.  Needs $root, the checkout.

SENTRAL_CACHE=${XDG_CACHE_HOME:-$HOME/.cache}/sentral

# cache_key INPUT...: 16 hex digits hashing each INPUT, a file's content or
# else the string itself (a version, a path, a command line).
cache_key() {
	local i
	for i in "$@"; do
		if [ -f "$i" ]; then
			printf 'file %s\n' "$(sha256sum <"$i" | cut -c1-64)"
		else
			printf 'string %s\n' "$i"
		fi
	done | sha256sum | cut -c1-16
}

# use_ccache: set CCACHE to "ccache " when ccache is installed (else
# empty), to prefix the compilers given to make, and make the paths it
# hashes relative to the checkout, so that a fresh clone hits.  Debug
# information may name another clone's directory: these builds are
# checked, never run.
use_ccache() {
	CCACHE=
	command -v ccache >/dev/null 2>&1 || return 0
	CCACHE="ccache "
	export CCACHE_BASEDIR=$root CCACHE_NOHASHDIR=1
}

# tree_key TREE: 16 hex digits identifying a kernel source tree extracted
# by tests/kernel/prepare: the content of its Kconfig files and makefiles
# (prepare edits some), the path, size and time of every other file (tar
# keeps the times, so another extraction of the same tarball matches).
tree_key() {
	local build=( \( -name 'Kconfig*' -o -name 'Makefile*' -o -name Kbuild \) )
	(cd "$1" && {
		find . -type f "${build[@]}" -print0 | sort -z | xargs -0 sha256sum
		find . -type f ! "${build[@]}" -printf '%P %s %T@\n' | sort
	}) | sha256sum | cut -c1-16
}

# cached_tarball NAME KEY MAKE...: print the path of
# $SENTRAL_CACHE/NAME-KEY.tar, made first when missing by MAKE... run with
# the path to write appended (moved into place only when MAKE succeeds, its
# output on stderr). One maker at a time: a second waits for the lock, then
# finds the file. The files of NAME under other keys are deleted: nothing
# made now uses them.
cached_tarball() {
	local name=$1 key=$2 file
	shift 2
	file=$SENTRAL_CACHE/$name-$key.tar
	if [ ! -s "$file" ]; then
		mkdir -p "$SENTRAL_CACHE" || return 1
		(
			flock 9
			[ -s "$file" ] && exit 0
			"$@" "$file.tmp" >&2 || { rm -f "$file.tmp"; exit 1; }
			mv "$file.tmp" "$file" &&
				find "$SENTRAL_CACHE" -maxdepth 1 -name "$name-????????????????.tar" \
					! -name "${file##*/}" -delete
		) 9>"$SENTRAL_CACHE/$name.lock" || return 1
	fi
	echo "$file"
}
