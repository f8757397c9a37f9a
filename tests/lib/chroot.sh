# SPDX-License-Identifier: GPL-2.0-only
# shellcheck shell=bash
#
# Running commands in an unpacked Debian image (a tree from an mmdebstrap
# tarball).  Needs root.

# in_chroot TREE CMD...: run CMD chrooted in TREE with a clean environment,
# /proc, /sys and /dev mounted in a private mount namespace, so that no
# mount outlives CMD, whatever ends it.
in_chroot() {
	local tree=$1
	shift
	# shellcheck disable=SC2016 # the inner sh expands them
	unshare --mount --fork -- sh -c '
		t=$1; shift
		mount -t proc proc "$t/proc" && mount --rbind /sys "$t/sys" &&
			mount --rbind /dev "$t/dev" &&
			exec chroot "$t" env -i PATH=/usr/sbin:/usr/bin:/sbin:/bin \
				DEBIAN_FRONTEND=noninteractive HOME=/root LC_ALL=C.UTF-8 "$@"' \
		sh "$tree" "$@"
}
