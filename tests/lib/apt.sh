# SPDX-License-Identifier: GPL-2.0-only
# shellcheck shell=bash
#
# apt_install_missing NEED...: each NEED is "command-or-file:package"; the
# packages of the needs not met are installed with apt (as root or sudo).
# With APT_TARGET=SUITE they come from that suite (apt_backports_source),
# and only they: the install stops before it would upgrade a package or
# take any other one from there.

apt_install_missing() {
	local n what pkg sudo='' missing=() target=() sim

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
	if [ -n "${APT_TARGET:-}" ]; then
		apt_backports_source "$APT_TARGET" || return 1
		target=(-t "$APT_TARGET")
	fi
	# Others may hold the dpkg lock (unattended upgrades, a parallel build).
	$sudo apt-get -o DPkg::Lock::Timeout=600 update -qq
	if [ -n "${APT_TARGET:-}" ]; then
		sim=$(apt-get -s "${target[@]}" install --no-install-recommends "${missing[@]}" |
			awk -v t="$APT_TARGET" -v want=" ${missing[*]} " '
				$1 == "Inst" && ($3 ~ /^\[/ || (index($0, ":" t " ") &&
					!index(want, " " $2 " "))) { print }')
		if [ -n "$sim" ]; then
			printf 'prepare: %s would also change:\n%s\n' "$APT_TARGET" "$sim" >&2
			return 1
		fi
	fi
	DEBIAN_FRONTEND=noninteractive $sudo apt-get -o DPkg::Lock::Timeout=600 \
		install -y -qq --no-install-recommends "${target[@]}" "${missing[@]}" >/dev/null
}

# apt_backports_source SUITE: make the apt suite SUITE (trixie-backports)
# available, from the mirror and with the keyring of the entry for this
# system's release, pinned at priority 1 so that nothing installed is ever
# upgraded from it or from its base release: only what is installed from it
# by name (apt-get install -t SUITE PACKAGE) comes from there.
apt_backports_source() {
	local suite=$1 base=${1%-backports} codename uri key
	local list=/etc/apt/sources.list.d/sentral-$1.sources
	local pref=/etc/apt/preferences.d/sentral-$1
	local sudo=''

	[ "$(id -u)" -eq 0 ] || sudo=sudo
	if [ ! -f "$pref" ]; then
		printf 'Package: *\nPin: release n=%s\nPin-Priority: 1\n\n' \
			"$base" "$suite" | $sudo tee "$pref" >/dev/null
	fi
	[ -f "$list" ] && return 0
	# shellcheck disable=SC1091
	codename=$(. /etc/os-release && echo "$VERSION_CODENAME")
	read -r uri key < <(apt_machine_entry "$codename") || return 1
	key=${key:-/usr/share/keyrings/debian-archive-keyring.gpg}
	printf 'Types: deb\nURIs: %s\nSuites: %s\nComponents: main\nSigned-By: %s\n' \
		"$uri" "$suite" "$key" | $sudo tee "$list" >/dev/null
}

# apt_machine_entry SUITE: "URI KEYRING" of this machine's enabled apt
# entry (deb822 first, then one-line) for the suite SUITE, e.g. bookworm or
# bookworm-security: the mirror this machine uses for it and the keyring
# it names, if any. Fails when there is none.
apt_machine_entry() {
	local want=$1 entry='' f

	for f in /etc/apt/sources.list.d/*.sources; do
		[ -f "$f" ] || continue
		entry=$(awk -v want="$want" '
			function flush() {
				if (deb && has && !off && uri != "") { print uri, key; found = 1; exit }
				deb = has = off = 0; uri = key = ""
			}
			/^[[:space:]]*$/ { flush(); next }
			/^#/ { next }
			tolower($1) == "enabled:" && tolower($2) == "no" { off = 1 }
			tolower($1) == "types:" { for (i = 2; i <= NF; i++) if ($i == "deb") deb = 1 }
			tolower($1) == "uris:" { uri = $2 }
			tolower($1) == "suites:" { for (i = 2; i <= NF; i++) if ($i == want) has = 1 }
			tolower($1) == "signed-by:" { key = $2 }
			END { if (!found) flush() }' "$f") || true
		[ -z "$entry" ] || break
	done
	if [ -z "$entry" ]; then
		for f in /etc/apt/sources.list /etc/apt/sources.list.d/*.list; do
			[ -f "$f" ] || continue
			entry=$(awk -v want="$want" '
				$1 != "deb" { next }
				{
					key = ""; i = 2
					if ($2 ~ /^\[/) {
						for (; i <= NF; i++) {
							if ($i ~ /^\[?signed-by=/) {
								key = $i; sub(/^\[?signed-by=/, "", key); sub(/\]$/, "", key)
							}
							if ($i ~ /\]$/) { i++; break }
						}
					}
					if ($(i + 1) == want) { print $i, key; exit }
				}' "$f") || true
			[ -z "$entry" ] || break
		done
	fi
	if [ -z "$entry" ]; then
		echo "apt: no apt source for $want on this machine to take a mirror from" >&2
		return 1
	fi
	echo "$entry"
}

# apt_machine_uri SUITE: the URI of apt_machine_entry SUITE.
apt_machine_uri() {
	local entry
	entry=$(apt_machine_entry "$1") || return 1
	echo "${entry%% *}"
}

# apt_release_sources RELEASE: one-line sources of the Debian release
# RELEASE (main, its updates and its security suite; mmdebstrap takes them)
# from the mirrors this machine uses for its own release and that
# release's security suite, so that what builds an image follows whatever
# mirror the machine is configured with.
apt_release_sources() {
	local rel=$1 codename uri sec
	# shellcheck disable=SC1091
	codename=$(. /etc/os-release && echo "$VERSION_CODENAME")
	uri=$(apt_machine_uri "$codename") || return 1
	sec=$(apt_machine_uri "$codename-security") || return 1
	printf 'deb %s %s main\n' "$uri" "$rel" "$uri" "$rel-updates" "$sec" "$rel-security"
}
