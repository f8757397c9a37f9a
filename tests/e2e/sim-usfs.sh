#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
# uml-args: --no-modules
#
# The simulated EM7180 on a USFS board: feature sensors (FeatureFlags,
# rates with the report bit, data and timestamps, the temperature slot
# filled by each barometer sample as well as at its own rate, both
# readings of the barometer rate, other FeatureFlags) and the hub's
# sensor bus behind
# passthrough (nothing answers while it is off; with it, i2cdetect sees the
# EEPROM, its ID page and the sensors; EEPROM writes, read-back, page
# roll-over, the write cycle, the image set through debugfs; sensor
# identities).
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/sim/testlib.sh"

sim_load
is "load the simulator" $? 0

# within V LO HI (integers)
within() { [ "$1" -ge "$2" ] && [ "$1" -le "$3" ]; }
board() { dbg_get board "$1"; }
# The addresses i2cdetect finds on the simulator's bus ("UU": a client).
detect() {
	i2cdetect -y "$SIM_BUS" |
		awk 'NR > 1 { for (i = 2; i <= NF; i++) if ($i != "--") printf "%s ", $i }'
}
# N bytes of FILE at OFFSET as i2ctransfer prints them.
file_bytes() {
	od -An -v -tx1 -j "$2" -N "$3" "$1" |
		awk '{ for (i = 1; i <= NF; i++) printf "%s0x%s", (n++ ? " " : ""), $i }'
}
eeprom_rd() {	# ADDR N: random read of N bytes from the EEPROM
	sim_xfer w2@0x50 $(($1 >> 8)) $(($1 & 255)) r"$2"@0x50
}
eeprom_wr() {	# ADDR BYTES...: one write (a page at most)
	local a=$1
	shift
	sim_xfer w$(($# + 2))@0x50 $((a >> 8)) $((a & 255)) "$@"
}

# --- Feature sensors --------------------------------------------------------
is "feature_flags: barometer and temperature by default" \
	"$(cat "$SIM_DBG/feature_flags")" 0x05
is "FeatureFlags (0x39) says so" "$(sim_rd 0x39)" 0x05
is "baro in slot 0, temperature in slot 1" \
	"$(board features) $(board baro_slot) $(board temp_slot)" "2 0 1"
is "EventStatus after power-on: CPUReset" "$(sim_rd 0x35)" 0x01
is "feature data 0 before any sample" "$(sim_rd 0x2a 8)" \
	"0x00 0x00 0x00 0x00 0x00 0x00 0x00 0x00"
# As the boards' examples (KW, GT, SL) configure it: BaroRate alone.
ok "BaroRate 25 Hz with the report bit, no TempRate" sim_wr 0x58 0x99 0x00
is "actual rates 0 while HostControl bit 0 is clear" "$(sim_rd 0x48 3)" \
	"0x00 0x00 0x00"
ok "HostControl run" sim_wr 0x34 0x01
is "actual baro and temperature rates: 25 and 0 Hz" "$(sim_rd 0x48 3)" \
	"0x19 0x00 0x00"
sleep 0.3
is "EventStatus: the feature bit (no other sensor has a rate)" \
	"$(sim_rd 0x35)" 0x40
set -- $(sim_rd 0x2a 8)
baro=$(s16 "$1" "$2")
temp=$(s16 "$5" "$6")
ok "pressure raw $baro: 1000 hPa within 1 hPa (raw x 0.01 + 1013.25)" \
	within "$baro" -1425 -1225
ok "temperature raw $temp with the barometer's samples: 25 C within 0.5 C (raw x 0.01)" \
	within "$temp" 2450 2550
ok "stop" sim_wr 0x34 0x00
nb=$(board baro_samples)
ok "$nb baro samples in about 0.3 s" [ "$nb" -ge 5 ]
is "none of the temperature sensor's own" "$(board temp_samples)" 0
set -- $(sim_rd 0x2c 2) $(sim_rd 0x30 2)
is "BaroTIME: n x 32768 / 25 (1/32768 s)" $(($1 | $2 << 8)) \
	$((nb * 32768 / 25 % 65536))
is "TempTIME: the barometer sample's" $(($3 | $4 << 8)) $(($1 | $2 << 8))

# TempRate on its own, the barometer off.
ok "BaroRate 0, TempRate 10 Hz without the report bit" sim_wr 0x58 0x00 0x0a
ok "run" sim_wr 0x34 0x01
is "actual rates: temperature 10 Hz" "$(sim_rd 0x48 3)" "0x00 0x0a 0x00"
sleep 0.3
ok "stop" sim_wr 0x34 0x00
nt=$(board temp_samples)
ok "$nt temperature samples in about 0.3 s" [ "$nt" -ge 2 ]
set -- $(sim_rd 0x2c 2) $(sim_rd 0x2e 4)
is "BaroTIME unchanged" $(($1 | $2 << 8)) $((nb * 32768 / 25 % 65536))
ok "temperature raw $(s16 $3 $4)" within "$(s16 $3 $4)" 2450 2550
is "TempTIME: n x 32768 / 10" $(($5 | $6 << 8)) $((nt * 32768 / 10 % 65536))

# Both: the temperature slot takes either's samples.
ok "BaroRate 25 Hz with the report bit, TempRate 10 Hz without" \
	sim_wr 0x58 0x99 0x0a
ok "run" sim_wr 0x34 0x01
is "actual baro and temperature rates: 25 and 10 Hz" "$(sim_rd 0x48 3)" \
	"0x19 0x0a 0x00"
sleep 0.3
ok "stop" sim_wr 0x34 0x00
nb2=$(board baro_samples)
nt2=$(board temp_samples)
ok "$((nb2 - nb)) baro and $((nt2 - nt)) temperature samples in about 0.3 s" \
	sh -c "[ $((nb2 - nb)) -gt $((nt2 - nt)) ] && [ $((nt2 - nt)) -ge 2 ]"
set -- $(sim_rd 0x2e 2)
ok "temperature raw $(s16 $1 $2)" within "$(s16 $1 $2)" 2450 2550
nb=$nb2
sleep 0.2
is "no samples while stopped" "$(board baro_samples)" "$nb"

ok "BaroRate 25 Hz without the report bit" sim_wr 0x58 0x19
ok "run" sim_wr 0x34 0x01
sim_rd 0x35 >/dev/null
sleep 0.2
is "no feature event without bit 7" "$(sim_rd 0x35)" 0x00
ok "the data still update" sh -c "[ $(board baro_samples) -gt $nb ]"
ok "report again, feature events enabled" sim_wr 0x58 0x99
ok "EnableEvents 0x40" sim_wr 0x33 0x40
irqs=$(dbg_get state irqs)
sim_rd 0x35 >/dev/null
sleep 0.2
ok "the feature event raises INT" sh -c "[ $(dbg_get state irqs) -gt $irqs ]"
is "INT high until EventStatus is read" "$(dbg_get state int)" 1
is "EventStatus: feature" "$(sim_rd 0x35)" 0x40
ok "EnableEvents 0" sim_wr 0x33 0x00

ok "standby" sim_wr 0x54 0x01
sleep 0.05
nb=$(board baro_samples)
sleep 0.2
is "no feature samples in standby" "$(board baro_samples)" "$nb"
ok "out of standby" sim_wr 0x54 0x00

# The barometer rate: Hz (GT, EM, Sony) or twice the rate (KW)
is "baro_rate_half 0 by default" "$(cat "$SIM_DBG/baro_rate_half")" 0
ok "BaroRate 0x80 | 50" sim_wr 0x58 0xb2
is "read as Hz: 50 Hz" "$(sim_rd 0x48)" 0x32
ok "baro_rate_half 1 (KW)" knob baro_rate_half 1
is "read as KW: 25 Hz" "$(sim_rd 0x48)" 0x19
is "the temperature rate is not halved" "$(sim_rd 0x49)" 0x0a
ok "baro_rate_half 0" knob baro_rate_half 0

# Other boards
ok "feature_flags 0: a board without a barometer" knob feature_flags 0
is "FeatureFlags 0" "$(sim_rd 0x39)" 0x00
is "no actual feature rates" "$(sim_rd 0x48 3)" "0x00 0x00 0x00"
sim_rd 0x35 >/dev/null
sleep 0.2
is "no feature events" "$(sim_rd 0x35)" 0x00
ok "feature_flags 7: with humidity" knob feature_flags 7
ok "three rates of 20 Hz with report" sim_wr 0x58 0x94 0x94 0x94
sleep 0.3
is "humidity in slot 1, temperature in slot 2" \
	"$(board features) $(board humidity_slot) $(board temp_slot)" "3 1 2"
set -- $(sim_rd 0x2a 8)
ok "baro raw $(s16 $1 $2) at 0x2A" within "$(s16 $1 $2)" -1425 -1225
ok "humidity raw $(s16 $3 $4) at 0x2C: 45 %" within "$(s16 $3 $4)" 4390 4610
ok "temperature raw $(s16 $5 $6) at 0x2E" within "$(s16 $5 $6)" 2450 2550
ok "one timestamp at 0x30" test $(($7 | $8 << 8)) -ne 0
# The barometer alone fills the temperature, whichever slot it has.
ok "power cycle: feature data 0" knob power_cycle 1
ok "upload done" sim_wait_upload
ok "BaroRate 20 Hz alone" sim_wr 0x58 0x94 0x00 0x00
ok "run" sim_wr 0x34 0x01
sleep 0.3
set -- $(sim_rd 0x2a 8)
ok "temperature raw $(s16 $5 $6) at 0x2E (slot 2)" within "$(s16 $5 $6)" 2450 2550
is "humidity not: 0 at 0x2C" "$(s16 $3 $4)" 0
ok "stop" sim_wr 0x34 0x00
ok "feature_flags 1: a barometer without a temperature slot" \
	knob feature_flags 1
ok "power cycle" knob power_cycle 1
ok "upload done" sim_wait_upload
ok "BaroRate 20 Hz" sim_wr 0x58 0x94
ok "run" sim_wr 0x34 0x01
sleep 0.3
set -- $(sim_rd 0x2a 8)
ok "baro raw $(s16 $1 $2) at 0x2A" within "$(s16 $1 $2)" -1425 -1225
is "0x2E..0x31 untouched" "$5 $6 $7 $8" "0x00 0x00 0x00 0x00"
nok "feature_flags refuses custom sensors (0x08)" knob feature_flags 8
ok "feature_flags 5" knob feature_flags 5
ok "stop" sim_wr 0x34 0x00
ok "feature rates 0" sim_wr 0x58 0x00 0x00 0x00

# --- The sensor bus behind passthrough --------------------------------------
is "i2cdetect without passthrough: the hub alone" "$(detect)" "28 "
nok "no EEPROM at 0x50" i2cget -f -y "$SIM_BUS" 0x50
nok "no MPU9250 at 0x68" i2cget -f -y "$SIM_BUS" 0x68 0x75
nok "no AK8963 at 0x0c" i2cget -f -y "$SIM_BUS" 0x0c 0x00
ok "accel 100 Hz, run" sim_wr 0x56 0x0a
ok "run" sim_wr 0x34 0x01
ok "standby first, as the reference hosts do" sim_wr 0x54 0x01
ok "PassThruControl 1" sim_wr 0xa0 0x01
is "PassThruStatus 1" "$(sim_rd 0x9e)" 0x01
is "i2cdetect: AK8963, hub, EEPROM, ID page, MPU9250, MS5637" "$(detect)" \
	"0c 28 50 58 68 76 "
is "MPU9250 WHO_AM_I (0x75)" "$(i2cget -f -y "$SIM_BUS" 0x68 0x75)" 0x71
is "AK8963 WIA (0x00)" "$(i2cget -f -y "$SIM_BUS" 0x0c 0x00)" 0x48
ok "AK8963 CNTL1 written" i2cset -f -y "$SIM_BUS" 0x0c 0x0a 0x16
is "and read back" "$(i2cget -f -y "$SIM_BUS" 0x0c 0x0a)" 0x16
ok "WIA is read-only" i2cset -f -y "$SIM_BUS" 0x0c 0x00 0x11
is "WIA unchanged" "$(i2cget -f -y "$SIM_BUS" 0x0c 0x00)" 0x48
ok "MS5637 reset" sim_xfer w1@0x76 0x1e
is "MS5637 PROM C1 (0xA2)" "$(sim_xfer w1@0x76 0xa2 r2@0x76)" "0xb5 0x24"
ok "MS5637 convert D1" sim_xfer w1@0x76 0x48
is "MS5637 ADC read" "$(sim_xfer w1@0x76 0x00 r3@0x76)" "0x62 0xa7 0xa4"

# The M24512
is "EEPROM erased at load" "$(eeprom_rd 0x1234 4)" "0xff 0xff 0xff 0xff"
ok "write 4 bytes at 0x1234" eeprom_wr 0x1234 0xde 0xad 0xbe 0xef
sleep 0.02
is "read back" "$(eeprom_rd 0x1234 4)" "0xde 0xad 0xbe 0xef"
is "in the debugfs image" "$(file_bytes "$SIM_DBG/eeprom" $((0x1234)) 4)" \
	"0xde 0xad 0xbe 0xef"
ok "write 4 bytes at 0x007e: the page ends at 0x007f" \
	eeprom_wr 0x007e 0x01 0x02 0x03 0x04
sleep 0.02
is "the first two at 0x007e" "$(eeprom_rd 0x007e 2)" "0x01 0x02"
is "the rest rolled over to 0x0000" "$(eeprom_rd 0x0000 2)" "0x03 0x04"
is "the next page untouched" "$(eeprom_rd 0x0080 1)" 0xff
ok "0x5a at 0xffff through debugfs" sh -c \
	"printf '\\132' | dd of=$SIM_DBG/eeprom bs=1 seek=65535 conv=notrunc 2>/dev/null"
is "a read rolls over the end of the memory" "$(eeprom_rd 0xffff 2)" \
	"0x5a 0x03"
is "a current-address read goes on from there" \
	"$(i2cget -f -y "$SIM_BUS" 0x50)" 0x04
ok "eeprom_write_ms 500" knob eeprom_write_ms 500
ok "write one byte" eeprom_wr 0x2000 0x77
nok "no acknowledge during the write cycle" eeprom_rd 0x2000 1
sleep 0.7
is "then it is written" "$(eeprom_rd 0x2000 1)" 0x77
ok "eeprom_write_ms 5" knob eeprom_write_ms 5
ok "ID page: 2 bytes at 0x0005" sim_xfer w4@0x58 0x00 0x05 0xaa 0xbb
sleep 0.02
is "ID page read back" "$(sim_xfer w2@0x58 0x00 0x05 r2@0x58)" "0xaa 0xbb"
is "the memory's 0x0005 untouched" "$(eeprom_rd 0x0005 1)" 0xff
ok "ID page: 2 bytes at 0x007f" sim_xfer w4@0x58 0x00 0x7f 0x11 0x22
sleep 0.02
is "rolled over within the page" "$(sim_xfer w2@0x58 0x00 0x00 r1@0x58)" 0x22
head -c 4096 /dev/urandom >/tmp/usfs-image
ok "an image written through debugfs at 0x0100" sh -c \
	"dd if=/tmp/usfs-image of=$SIM_DBG/eeprom bs=256 seek=1 conv=notrunc 2>/dev/null"
is "read on the bus at 0x0100" "$(eeprom_rd 0x0100 16)" \
	"$(file_bytes /tmp/usfs-image 0 16)"
is "and at 0x0f00" "$(eeprom_rd 0x1000 8)" "$(file_bytes /tmp/usfs-image $((0x0f00)) 8)"
ok "the whole EEPROM reads back through debugfs" sh -c \
	"[ \$(wc -c <$SIM_DBG/eeprom) -eq 65536 ] &&
	 dd if=$SIM_DBG/eeprom bs=256 skip=1 count=16 2>/dev/null | cmp - /tmp/usfs-image"
ok "sensor-bus transactions counted apart" \
	sh -c "[ $(board bus_transactions) -gt 20 ]"

ok "AlgorithmControl 0 while in passthrough" sim_wr 0x54 0x00
is "the algorithm stays halted: its sensor bus is the host's" \
	"$(dbg_get state running)" 0
ok "PassThruControl 0" sim_wr 0xa0 0x00
is "PassThruStatus 0" "$(sim_rd 0x9e)" 0x00
is "the algorithm runs again" "$(dbg_get state running)" 1
is "i2cdetect: the hub alone again" "$(detect)" "28 "
nok "the EEPROM does not answer" eeprom_rd 0x1234 4
ok "PassThruControl 1" sim_wr 0xa0 0x01
ok "ResetRequest" sim_wr 0x9b 0x01
ok "upload done" sim_wait_upload
is "passthrough off after a reset" "$(sim_rd 0x9e)" 0x00
nok "the MPU9250 does not answer" i2cget -f -y "$SIM_BUS" 0x68 0x75
ok "no_eeprom 1" knob no_eeprom 1
ok "PassThruControl 1" sim_wr 0xa0 0x01
is "a board without EEPROM: the sensors alone" "$(detect)" "0c 28 68 76 "
ok "no_eeprom 0" knob no_eeprom 0
ok "upload done" sim_wait_upload
ok "PassThruControl 1" sim_wr 0xa0 0x01
is "the EEPROM kept its contents over resets" "$(eeprom_rd 0x1234 4)" \
	"0xde 0xad 0xbe 0xef"
ok "PassThruControl 0" sim_wr 0xa0 0x00
ok "unload" sim_unload

# Behind the simulated mux each chip has a sensor bus of its own, on its
# channel.
chan_bus() {
	local d
	for d in /sys/bus/i2c/devices/i2c-*; do
		case $(cat "$d/name") in
		*"(chan_id $1)") echo "${d##*/i2c-}"; return 0 ;;
		esac
	done
	return 1
}
sim_load mux_channels=2
is "load with a mux of two channels" $? 0
c0=$(chan_bus 0)
c1=$(chan_bus 1)
ok "passthrough on channel 1's chip" i2ctransfer -f -y "$c1" w2@0x28 0xa0 0x01
is "channel 1: its MPU9250" "$(i2cget -f -y "$c1" 0x68 0x75)" 0x71
nok "channel 0: its chip is not in passthrough" i2cget -f -y "$c0" 0x68 0x75
nok "nor the first adapter's" i2cget -f -y "$SIM_BUS" 0x68 0x75
is "channel 1's chip counted it" \
	"$(awk '$1 == "bus_transactions" { print $2 }' "$SIM_DBG-mux-1/board")" 1
ok "unload" sim_unload
done_testing
