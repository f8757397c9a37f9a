#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# System sleep of the em7180 driver on the simulated chip, through
# /sys/power/pm_test "devices" (the devices suspend and resume, no wake-up
# source needed): the algorithm running after a sleep, the calibration
# learned since boot and the offsets back after a power loss in sleep, a
# standby the chip never confirms, other firmware after the sleep, a
# capture that goes on across one, and a recovery in progress when the
# system goes to sleep.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"

TMP=$(mktemp -d)

# One system sleep: the devices suspend, 1 s passes, they resume.
system_sleep() {
	echo devices >/sys/power/pm_test &&
		echo 1 >/sys/module/suspend/parameters/pm_test_delay &&
		echo freeze >/sys/power/state
}

DEV=$(em7180_dir)
ok "em7180 present" test -n "$DEV"
knob gbias_period_ms 3600000

ok "a system sleep" system_sleep
ok "the algorithm runs after it" chip_idle
is "not in standby" "$(dbg_get state standby)" 0

# The chip learns after boot; nothing read the warm start through the
# driver. A power loss in sleep must not lose what it learned.
knob cal_duration_ms 300
knob motion 1
ok "calibrated by motion" wait_for 10 \
	sh -c "[ \$(cat $DEV/in_magn_calibration_auto_status) = 4 ]"
knob motion 0
echo -47 >"$DEV/in_accel_x_calibbias"
echo 200 >"$DEV/in_accel_sampling_frequency"
before=$(sim_ws_params)
knob standby_power_loss 1
ok "a system sleep in which the chip loses power" system_sleep
is "the power loss happened" "$(cat "$SIM_DBG/standby_power_loss")" 0
like "the kernel log says so" "$(dmesg | grep em7180 | tail -n 5)" "lost power"
ok "the algorithm runs after it" chip_idle
is "the learned calibration is back: level 4, stable" \
	"$(cat "$DEV/in_magn_calibration_auto_status")" 4
is "every warm-start parameter as before the sleep" "$(sim_ws_params)" "$before"
is "the offset written since boot" "$(dbg_get params 27)" 0xbcbbe447
is "calibbias reads it" "$(cat "$DEV/in_accel_x_calibbias")" -47
is "the accelerometer rate" "$(cat "$DEV/in_accel_sampling_frequency")" 200
echo 100 >"$DEV/in_accel_sampling_frequency"

# A chip that never confirms the standby: the sleep goes on, and the
# algorithm runs after it.
knob standby_never 1
ok "a system sleep with a standby never confirmed" system_sleep
knob standby_never 0
ok "the algorithm runs after it" chip_idle
like "logged" "$(dmesg | grep em7180 | tail -n 5)" "standby not confirmed"

# Other firmware after a power loss in sleep: the warm start of the old one
# is not written (sentral-warmstart would refuse such a file too).
ok "a warm start known to the driver" \
	dd if="$DEV/calibration_data" of="$TMP/ws" bs=4096 status=none
ram=$(cat "$SIM_DBG/ram_version")
knob ram_version 0x0bad
knob standby_power_loss 1
ok "a system sleep with a power loss and a firmware update" system_sleep
knob ram_version "$ram"
is "the driver shows the new firmware" "$(driver_ram_version)" 0x0bad
like "and logs what it skipped" "$(dmesg | grep em7180 | tail -n 5)" \
	"firmware changed .*not restored"
is "the old calibration was not written: status 0" \
	"$(dbg_get state cal_status)" 0
is "the level says so: calibrating" \
	"$(cat "$DEV/in_magn_calibration_auto_status")" 2
is "nor the offsets" "$(dbg_get params 27)" 0x00000000
is "calibbias reads what the chip holds" "$(cat "$DEV/in_accel_x_calibbias")" 0
ok "the algorithm runs" chip_idle

# A capture across a sleep: the interrupt is off while asleep and the
# stream goes on after.
iio_readdev -T 5000 -b 16 -s 300 em7180 accel_x accel_y accel_z timestamp \
	>"$TMP/cap.bin" 2>"$TMP/err" &
pid=$!
sleep 1
ok "a system sleep while capturing" system_sleep
wait "$pid"
is "300 scans across the sleep" "$(stat -c %s "$TMP/cap.bin")" $((300 * 16))

# One NACK anywhere in a sleep, transaction 1, 2, ... of the suspend and
# the resume: the system sleeps and wakes (a chip that cannot confirm its
# standby is no reason to keep the system awake), and the algorithm runs.
echo devices >/sys/power/pm_test
echo 0 >/sys/module/suspend/parameters/pm_test_delay
knob stats 0
sh -c "echo freeze >/sys/power/state"
clean=$(dbg_get stats transactions)
echo "# a sleep: $clean transactions"
failed=
for n in $(seq 1 "$clean"); do
	knob stats 0
	knob nack_at "$n"
	if ! err=$(sh -c "echo freeze >/sys/power/state" 2>&1) || ! chip_idle; then
		failed="$failed $n"
		# Whether the sleep failed, what it did (its transactions may
		# differ from the clean one's), and the kernel's last words,
		# the PM core's among them
		read_state
		echo "# NACK at $n: sleep ${err:-done}," \
			"$(dbg_get stats transactions) transactions," \
			"$(dbg_get stats ack_polls_early) early acknowledge polls," \
			"transfer $ST_transfer, running $ST_running"
		dmesg | tail -n 12 | sed 's/^/#   /'
	fi
	knob nack_at 0
done
is "one NACK at each of the $clean transactions: every sleep done, chip running" \
	"$failed" ""

# Resume as soon as the devices are suspended (no delay) after a power loss
# in sleep, with a chip that NACKs for a while after its power-on: resume
# waits for it as probe does, and restores it.
# (first a power loss that brings the driver back to the firmware it had)
knob standby_power_loss 1
ok "a system sleep with a power loss, back to the first firmware" system_sleep
echo 0 >/sys/module/suspend/parameters/pm_test_delay
echo -47 >"$DEV/in_accel_x_calibbias"
knob nack_after_reset_ms 100
knob standby_power_loss 1
ok "a system sleep with a power loss, the chip NACKing 100 ms after" \
	sh -c "echo devices >/sys/power/pm_test && echo freeze >/sys/power/state"
knob nack_after_reset_ms 0
ok "the algorithm runs after it" chip_idle
is "the offset is back" "$(dbg_get params 27)" 0xbcbbe447

echo 0 >"$DEV/in_accel_x_calibbias"

# A system sleep while the driver restores a chip that reset itself, the
# restore's parameter transfer failing so that it cannot be ended: that
# recovery asks for another. The suspend waits for the one in progress;
# none may run until the resume, where it would take the chip out of
# standby (on a bus that may be asleep too). Asleep for 3 s, a chip left
# in standby makes no accelerometer sample at 100 Hz: those counted come
# from the time after the resume, read without a fork.
accel_made() {
	local k v
	while read -r k v; do
		[ "$k" = accel ] && ACCEL=$v
	done <"$SIM_DBG/samples"
}

echo 100 >"$DEV/in_accel_sampling_frequency"
echo devices >/sys/power/pm_test
echo 3 >/sys/module/suspend/parameters/pm_test_delay
echo 1 >/sys/power/pm_print_times
# A warm start known to the driver: the restore writes 35 parameters, 3.5 s
ok "a save" dd if="$DEV/calibration_data" of=/dev/null bs=4096 status=none
latency=$(cat "$SIM_DBG/ack_latency_us")
knob ack_latency_us 100000
dmesg -c >/dev/null
knob chip_reset 1
ok "the recovery's restore transfer begins" wait_for 5 in_transfer
# A transaction of the transfer about 2 s later and the two that end it
# NACKed: by then the suspend waits for the recovery.
knob nack_run 3
knob nack_at 50
accel_made
s0=$ACCEL
slept=no
echo freeze >/sys/power/state && slept=yes
accel_made
made=$((ACCEL - s0))
is "a system sleep during the recovery" "$slept" yes
is "the NACKs fired" "$(cat "$SIM_DBG/nack_at")" 0
knob nack_run 1
knob ack_latency_us "$latency"
echo 0 >/sys/power/pm_print_times
echo 0 >/sys/module/suspend/parameters/pm_test_delay
like "the restore failed while the suspend waited for it" "$(dmesg)" \
	"calling em7180_suspend.*cannot restore the chip after its reset: -6.*em7180_suspend.* returned 0"
echo "# accelerometer samples made across the sleep: $made"
ok "none while asleep: fewer than 50 ($made)" [ "$made" -lt 50 ]
ok "the algorithm runs after it" chip_idle
ok "a save works" dd if="$DEV/calibration_data" of=/dev/null bs=4096 status=none

rm -rf "$TMP"
done_testing
