#!/bin/bash
# SPDX-License-Identifier: GPL-2.0-only
#
# The em7180 driver's interrupt on the simulated chip, as the reference
# hosts see EventStatus on silicon (every event latched, INT for the
# enabled ones): an interrupt with no enabled event pending is not the
# driver's (IRQ_NONE, so that the kernel can tell a line that fires for
# nobody); an Error event is reported once per ErrorRegister and
# SensorStatus pair, decoded.
. "$SENTRAL_ROOT/tests/lib/tap.sh"
. "$SENTRAL_ROOT/tests/lib/em7180.sh"

DEV=$(em7180_dir)
ok "an em7180 IIO device is present" test -n "$DEV"
VIRQ=$(dbg_get state virq)
SPURIOUS=/proc/irq/$VIRQ/spurious
ok "the interrupt's spurious counters are readable" test -r "$SPURIOUS"
unhandled() {
	awk '$1 == "unhandled" { print $2 }' "$SPURIOUS"
}
errors() {
	dmesg | grep -c "em7180.*chip error"
}

# --- Not ours --------------------------------------------------------------
u0=$(unhandled)
i0=$(dbg_get state irqs)
for _ in 1 2 3 4 5; do
	knob int_spurious 1
done
is "five rising edges with nothing pending" "$(($(dbg_get state irqs) - i0))" 5
# The kernel accounts a threaded handler's answer at the next interrupt of
# the line: the first four of the five so far.
is "each one unhandled for the kernel (IRQ_NONE)" "$(($(unhandled) - u0))" 4
is "INT low again" "$(dbg_get state int)" 0

# --- Errors ------------------------------------------------------------------
e0=$(errors)
knob sensor_status 0x01
knob error 0x21
ok "the Error event read" wait_for 2 sh -c "[ \$(dmesg | grep -c 'em7180.*chip error') -gt $e0 ]"
like "decoded, with SensorStatus" "$(dmesg | grep 'em7180.*chip error' | tail -n 1)" \
	"chip error 0x21 \\(magnetometer initialization failed\\), sensor status 0x01"
knob error 0x21
sleep 0.2
is "the same error again: not said again" "$(($(errors) - e0))" 1
knob sensor_status 0x00
knob error 0x30
ok "another error is said" wait_for 2 sh -c "[ \$(dmesg | grep -c 'em7180.*chip error') -gt $((e0 + 1)) ]"
like "decoded" "$(dmesg | grep 'em7180.*chip error' | tail -n 1)" \
	"chip error 0x30 \\(math error\\), sensor status 0x00"
knob error 0
done_testing
