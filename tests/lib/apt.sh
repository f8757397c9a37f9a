# SPDX-License-Identifier: GPL-2.0-only
# shellcheck shell=bash
#
# apt_install_missing NEED...: each NEED is "command-or-file:package"; the
# packages of the needs not met are installed with apt (as root or sudo).

apt_install_missing() {
	local n what pkg sudo= missing=()

	for n in "$@"; do
		what=${n%%:*} pkg=${n#*:}
		if [[ $what == /* ]]; then
			[ -e "$what" ] || missing+=("$pkg")
		else
			command -v "$what" >/dev/null 2>&1 || [ -x "/usr/sbin/$what" ] ||
				[ -x "/sbin/$what" ] || missing+=("$pkg")
		fi
	done
	[ ${#missing[@]} -gt 0 ] || return 0
	# shellcheck disable=SC2207
	missing=($(printf '%s\n' "${missing[@]}" | sort -u))
	echo "prepare: installing ${missing[*]}"
	[ "$(id -u)" -eq 0 ] || sudo=sudo
	# Others may hold the dpkg lock (unattended upgrades, a parallel build).
	$sudo apt-get -o DPkg::Lock::Timeout=600 update -qq
	DEBIAN_FRONTEND=noninteractive $sudo apt-get -o DPkg::Lock::Timeout=600 \
		install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}
