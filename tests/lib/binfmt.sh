# SPDX-License-Identifier: GPL-2.0-only
# shellcheck shell=bash
#
# Foreign binaries run through qemu-user, which the kernel starts for them
# (binfmt_misc): dpkg-buildpackage -a runs the tool's unit tests that way,
# and mmdebstrap runs the maintainer scripts of a foreign image.  Needs
# tests/lib/apt.sh.

# binfmt_enable ARCH: the binfmt_misc handler of qemu-user-static for the
# Debian architecture ARCH is registered (the package installed, the file
# system mounted and the handler registered when missing: a host without
# systemd or binfmt-support running registers nothing at boot).
binfmt_enable() {
	local cpu sudo='' dir=/proc/sys/fs/binfmt_misc

	cpu=$(dpkg-architecture -a "$1" -qDEB_HOST_GNU_CPU 2>/dev/null) || return 1
	apt_install_missing "/usr/libexec/qemu-binfmt/$cpu-binfmt-P:qemu-user-static"
	[ "$(id -u)" -eq 0 ] || sudo=sudo
	[ -e "$dir/status" ] || $sudo mount -t binfmt_misc binfmt_misc "$dir" || return 1
	[ -e "$dir/qemu-$cpu" ] ||
		$sudo /lib/systemd/systemd-binfmt "/usr/lib/binfmt.d/qemu-$cpu.conf" || return 1
	[ "$(head -n 1 "$dir/qemu-$cpu")" = enabled ] || {
		echo "binfmt: the qemu-$cpu handler is registered but disabled" >&2
		return 1
	}
}
