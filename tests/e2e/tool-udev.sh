#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --udev
#
# The udev rule (no systemd: RUN+= path) in one boot: nothing to restore at
# the first probe; after calibrate + save, a re-probe of a power-cycled chip
# restores it (level 4, stable, without motion, parameters equal to the
# file, and status says the chip holds it); a
# corrupted file is refused at probe with the message in the kernel log,
# the chip left alone and the file moved aside, after which the next good
# calibration is saved and restored. The rule starts no watcher; one started
# by hand (watch --daemon): detached, one per chip, saves a new calibration
# by itself, exits when the device goes. With systemd (simulated): the device
# names its units by the key and binds them through an alias whose name
# matches the units' BindsTo=; the units pass systemd-analyze verify.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tools/sentral-warmstart/tests/e2e-lib.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
client=$(basename "$(dirname "$(readlink -f "$DEV")")")
ok "the rule is installed" test -f /etc/udev/rules.d/60-sentral-warmstart.rules
like "the rule ran at probe: nothing to restore yet" "$(dmesg)" \
	"sentral-warmstart\[[0-9]+\]: no saved calibration for iio:device"

props() {
	udevadm info -q property -p "$(readlink -f "$(em7180_dir)")"
}
key=$(sentral-warmstart status --json | json_field key)
is "the key: the controller's ID_PATH and the address" "$key" platform-sentral-sim-0x28
like "the rule computed the same key" "$(props)" "SENTRAL_WARMSTART_KEY=$key"
f=$STATE/$key.ws

knob gbias_period_ms 600000
ok "simulated figure-8 until calibrated" calibrate_by_motion
ok "save" sentral-warmstart save
ok "saved as $f" test -f "$f"
payload=$(file_payload_words "$f")

ok "replug (power cycle + bind): udev restores at probe" replug "$client"
udevadm settle --timeout=10
is "in_magn_calibration_auto_status 4 (stable) without motion" "$(cal_level)" 4
is "chip parameters 1..35 equal the saved payload" "$(sim_ws_params)" "$payload"
like "the kernel log tells it" "$(dmesg)" \
	"sentral-warmstart\[[0-9]+\]: restored iio:device[0-9]+ calibration from $f: level 4 \(stable\) \(saved: level 4 \(stable\), no score\)"
like "status: the chip holds the saved calibration" "$(sentral-warmstart status)" \
	$'\nrestored: +yes: the chip holds the saved calibration'

# Issue 12.3: a refused file must not end saving.
cp "$f" /tmp/good.ws
flip_byte "$f" 100
cp "$f" /tmp/corrupt.ws
ok "replug with a corrupted file" replug "$client"
udevadm settle --timeout=10
like "refused at probe, the check named in the kernel log" "$(dmesg)" \
	"sentral-warmstart\[[0-9]+\]: error: $f: refused: bad CRC .*; the chip was not touched; moved aside to $f.refused for inspection"
is "chip untouched: not calibrated (level 2)" "$(cal_level)" 2
is "(the chip's own calibration status 0: nothing learned)" "$(dbg_get state cal_status)" 0
isnt_payload=$(words 18 23 "$(sim_ws_params)")
ok "chip untouched: magnetic coefficients are not the file's" \
	test "$isnt_payload" != "$(words 18 23 "$payload")"
ok "the refused file is kept, byte for byte" cmp "$f.refused" /tmp/corrupt.ws
nok "and no longer in the way" test -e "$f"
out=$(sentral-warmstart save 2>&1)
is "before calibration, the stop action's save: the policy says no, exit 0" $? 0
like "saying why" "$out" "not saving .*calibration not stable \(level 2 \(calibrating\); needs 4\)"
ok "the chip learns a new calibration" calibrate_by_motion
ok "the stop action's save writes it" sentral-warmstart --device "$key" save --if-present
ok "a new, valid file in its place" sentral-warmstart show "$f"
ok "replug: the new calibration is restored at probe" replug "$client"
udevadm settle --timeout=10
is "level 4 (stable) without motion" "$(cal_level)" 4
is "the chip holds the new file's payload" "$(sim_ws_params)" "$(file_payload_words "$f")"

# Without systemd the rule restores and starts nothing else: udev(7)
# forbids long-running processes from RUN. A watcher started by hand
# (watch --daemon): detached, one per chip (a second replaces the first),
# saves a new calibration by itself, exits when the device goes and on
# SIGTERM.
watchfile=/run/sentral-warmstart/$key.watch
watcher() { cat "$watchfile" 2>/dev/null; }
alive() { [ -n "$1" ] && kill -0 "$1" 2>/dev/null; }
gone() { ! alive "$1"; }
watchers() { ps -eo args | grep -c '[s]entral-warmstart .*watch'; }
mv "$f" /tmp/before-watch.ws
ok "replug with no saved file: the chip starts uncalibrated" replug "$client"
udevadm settle --timeout=10
# A watcher the rule started would hold its lock after udev is done.
sleep 2
is "the rule started no watcher at the five probes" "$(watchers)" 0
nok "... nor left a watcher's lock" test -e "$watchfile"
is "the chip is calibrating (level 2)" "$(cal_level)" 2
ok "watch --daemon by hand returns at once" \
	timeout 10 sentral-warmstart --device "$key" watch --daemon
# The watcher writes its pid once it holds the lock.
new_watcher() { [ "$(watcher)" != "$1" ] && alive "$(watcher)"; }
ok "a watcher holds the lock $watchfile" wait_for 10 new_watcher ""
w1=$(watcher)
is "detached: its parent is init" "$(ps -o ppid= -p "$w1" | tr -d ' ')" 1
is "one watcher for the chip" "$(watchers)" 1
ok "watch --daemon again" sentral-warmstart --device "$key" watch --daemon
ok "a new watcher holds the lock" wait_for 10 new_watcher "$w1"
w2=$(watcher)
like "replacing the old one" "$(dmesg)" \
	"sentral-warmstart\[$w2\]: watch: replacing the watcher of $key \(pid $w1\)"
ok "the old one stopped" wait_for 10 gone "$w1"
is "still one watcher for the chip" "$(watchers)" 1
nok "nothing saved before the calibration is stable" test -e "$f"
ok "the chip learns a calibration" calibrate_by_motion
ok "the watcher saves it by itself within a poll (30 s)" wait_for 45 test -s "$f"
ok "a valid file" sentral-warmstart show "$f"
like "the watcher says so in the kernel log" "$(dmesg)" \
	"sentral-warmstart\[$w2\]: saved iio:device[0-9]+ calibration to $f"
echo "$client" >/sys/bus/i2c/drivers/em7180/unbind
ok "unbound: the watcher exits at its next poll" wait_for 45 gone "$w2"
like "saying why" "$(dmesg)" "sentral-warmstart\[$w2\]: error: .*stopped watching it"
echo "$client" >/sys/bus/i2c/drivers/em7180/bind
wait_for 5 em7180_dir >/dev/null
udevadm settle --timeout=10
restored() { [ "$(cal_level)" = 4 ]; }
ok "bound again: restored at probe" wait_for 5 restored
sleep 2
is "and no watcher started by the rule" "$(watchers)" 0
ok "watch --daemon by hand again" sentral-warmstart --device "$key" watch --daemon
ok "a watcher holds the lock" wait_for 10 new_watcher "$w2"
w3=$(watcher)
kill "$w3"
ok "a watcher stops on SIGTERM" wait_for 10 gone "$w3"
is "none left" "$(watchers)" 0

# With systemd running, the rule hands over to the units instead.
mkdir -p /run/systemd/system
before=$(dmesg | grep -c 'sentral-warmstart\[')
ok "replug as if systemd were running" replug "$client"
udevadm settle --timeout=10
unit=sentral-warmstart@$(systemd-escape "$key").service
plug=sentral-warmstart-plug@$(systemd-escape "$key").service
like "SYSTEMD_WANTS names the unit that starts the chip's units after the key" "$(props)" \
	"SYSTEMD_WANTS=$(sed 's/\\/\\\\/g' <<<"$plug")"
like "tagged for systemd" "$(props)" "CURRENT_TAGS=.*:systemd:"
alias=$(props | sed -n 's/^SYSTEMD_ALIAS=//p')
is "the device unit's alias is named by the key" "$alias" "/sys/subsystem/sentral-warmstart/$key"
is "the tool was not run directly" "$(dmesg | grep -c 'sentral-warmstart\[')" "$before"
udevadm trigger --action=change "$(readlink -f "$(em7180_dir)")"
udevadm settle --timeout=10
like "after a change event: still the same unit" "$(props)" \
	"SYSTEMD_WANTS=$(sed 's/\\/\\\\/g' <<<"$plug")"
like "still tagged for systemd (else systemd would stop the units)" "$(props)" \
	"CURRENT_TAGS=.*:systemd:"
is "the tool was not run directly" "$(dmesg | grep -c 'sentral-warmstart\[')" "$before"
rmdir /run/systemd/system

# The units: what udev names is what they bind to and pass to the tool.
units=/tmp/units
mkdir -p $units
for u in "$SENTRAL_ROOT"/tools/sentral-warmstart/systemd/*.service.in; do
	sed "s|@SBINDIR@|$SENTRAL_ROOT/tools/sentral-warmstart|g" "$u" \
		>"$units/$(basename "$u" .in)"
done
inst=${unit#sentral-warmstart@}
inst=${inst%.service}
out=$(cd $units && systemd-analyze verify --man=no "$units/$unit" \
	"$units/sentral-warmstart-restore@$inst.service" "$units/$plug" 2>&1)
is "systemd-analyze verify: clean" "$out" ""
for u in sentral-warmstart@.service sentral-warmstart-restore@.service \
	sentral-warmstart-plug@.service; do
	binds=$(sed -n 's/^BindsTo=//p' "$units/$u")
	is "$u binds to the device's alias" "${binds//%i/$inst}" \
		"$(systemd-escape --path --suffix=device "$alias")"
done
for u in sentral-warmstart@.service sentral-warmstart-restore@.service; do
	like "$u passes the key to the tool (%I unescapes the instance)" \
		"$(grep '^Exec' "$units/$u")" "--device %I "
done
# systemd starts what a device wants with a job that gives way to a stop
# job (systemd issue 11526): the device wants a unit that has none, which
# restarts the two, the restore first, and stays active (no second start
# for another "add" of the device).
is "the plug unit restarts the restore and the saving unit of its instance" \
	"$(grep -E '^(Type|RemainAfterExit|ExecStart)=' "$units/sentral-warmstart-plug@.service")" \
	"Type=oneshot"$'\n'"RemainAfterExit=yes"$'\n'"ExecStart=/bin/systemctl --no-block restart sentral-warmstart-restore@%i.service sentral-warmstart@%i.service"
is "... and stops nothing itself" \
	"$(grep -E '^ExecStop' "$units/sentral-warmstart-plug@.service")" ""
is "the instance unescaped is the key" "$(systemd-escape --unescape "$inst")" "$key"
like "the saving unit wants the restoring one" \
	"$(grep '^Wants=' "$units/sentral-warmstart@.service")" \
	"(^|"$'\n'")Wants=sentral-warmstart-restore@%i.service($|"$'\n'")"
is "and requires nothing" \
	"$(grep -E '^(Requires|Requisite)=' "$units/sentral-warmstart@.service")" ""
like "the restore runs at start, fails on a refused file" \
	"$(grep '^Exec' "$units/sentral-warmstart-restore@.service")" \
	"^ExecStart=[^-].* restore --if-present$"
like "the watcher is the saving unit's main process, started again after a failure" \
	"$(grep -E '^(Type|ExecStart|Restart)=' "$units/sentral-warmstart@.service")" \
	"^Type=simple"$'\n'"ExecStart=[^-].* watch"$'\n'"Restart=on-failure$"
like "the save runs at stop and a failure shows (no '-')" \
	"$(grep '^ExecStop' "$units/sentral-warmstart@.service")" \
	"^ExecStop=[^-].* save --if-present$"
# The directives; the comments say what each unit's tool needs.
sandbox() { sed -n '/^StateDirectory=/,$p' "$units/$1" | grep -v '^#' | md5sum; }
is "both units have the same sandbox" \
	"$(sandbox sentral-warmstart@.service)" "$(sandbox sentral-warmstart-restore@.service)"

done_testing
