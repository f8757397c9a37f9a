#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-only
"""A reference host for the EM7180 over i2c-dev, for tests.

It does what the hosts that others ran on real boards do, in their order
(EM7180 register reference: §3 startup, §2 parameter transfer, §3 item 9
passthrough), and not what our driver does: one register per SMBus
transaction, a multi-byte value read as the Raspberry Pi library reads it
(the register number written, then one receive-byte transaction per byte,
the chip's pointer moving on between them), LoadParamByte0..3 written one
by one, then ParamRequest, then AlgorithmControl, ParamAcknowledge polled
alone. Polls are bounded (5 ms steps, 1 s like EM's host driver) where the
libraries loop forever. The data are read as the USFS boards' examples read
them: the linear acceleration where Greg Tomasch's utilities read it
(0x3F..0x44), and on a barometer event Baro and Temp (0x2A, 0x2E) with only
BaroRate set, as Kris Winer's, Greg Tomasch's and Simon D. Levy's code do.

It prints what it saw as "key value" lines for the test to judge, and
exits 1 with a message on stderr when the chip did not answer as the
protocol says (a poll timed out, a transfer failed).

Usage: em7180_refhost.py /dev/i2c-N
"""
import fcntl
import math
import os
import struct
import sys
import time

I2C_SLAVE = 0x0703          # linux/i2c-dev.h
ADDRESS = 0x28

# Registers, reference §1
QX, AX, GX, MX = 0x00, 0x1A, 0x22, 0x12
BARO, TEMP = 0x2A, 0x2E                 # the USFS's feature slots
QRATE_DIVISOR = 0x32
ENABLE_EVENTS = 0x33
HOST_CONTROL = 0x34
EVENT_STATUS = 0x35
SENSOR_STATUS = 0x36
SENTRAL_STATUS = 0x37
ALGORITHM_STATUS = 0x38
FEATURE_FLAGS = 0x39
PARAM_ACK = 0x3A
SAVED_PARAM0 = 0x3B
LIN_ACCEL = 0x3F            # GP8..GP13 on the USFS (GT's LIN_ACC_getADC)
ACTUAL_MAG_RATE = 0x45
ERROR_REGISTER = 0x50
ALGORITHM_CONTROL = 0x54
MAG_RATE, ACCEL_RATE, GYRO_RATE, BARO_RATE = 0x55, 0x56, 0x57, 0x58
ACC_LPF_BW, GYRO_LPF_BW = 0x5B, 0x5C
LOAD_PARAM0 = 0x60
PARAM_REQUEST = 0x64
ROM_VERSION = 0x70
RAM_VERSION = 0x72
PRODUCT_ID, REVISION_ID = 0x90, 0x91
RESET_REQUEST = 0x9B
PASSTHRU_STATUS = 0x9E
PASSTHRU_CONTROL = 0xA0

ACCEL_G_PER_LSB = 0.000488  # scaled output, reference §1 units
POLL_S = 0.005
ACK_TIMEOUT_S = 1.0         # EM's host driver
UPLOAD_TIMEOUT_S = 4.0      # EM's host driver, EEPROM_UPLOAD_TIME_MS


class ProtocolError(Exception):
    pass


class Host:
    def __init__(self, dev):
        self.fd = os.open(dev, os.O_RDWR)
        fcntl.ioctl(self.fd, I2C_SLAVE, ADDRESS)
        self.transactions = 0

    # SMBus write byte data: register number and value, one transaction
    def write(self, reg, val):
        self.transactions += 1
        os.write(self.fd, bytes([reg, val]))

    # SMBus write byte (the register number), then one receive byte per
    # register, as the Raspberry Pi library reads any register
    def read(self, reg, count=1):
        self.transactions += 1
        os.write(self.fd, bytes([reg]))
        out = []
        for _ in range(count):
            self.transactions += 1
            out.append(os.read(self.fd, 1)[0])
        return out

    def read1(self, reg):
        return self.read(reg)[0]

    def poll(self, what, cond, timeout_s=ACK_TIMEOUT_S):
        end = time.monotonic() + timeout_s
        while True:
            try:
                v = cond()
                if v is not None:
                    return v
            except OSError:
                pass    # still in reset: the address is not acknowledged
            if time.monotonic() >= end:
                raise ProtocolError(f"{what}: no answer within {timeout_s} s")
            time.sleep(POLL_S)

    # §3 item 2: ResetRequest, then SentralStatus until the upload is done
    # and the CPU is in standby
    def reset(self):
        self.write(RESET_REQUEST, 0x01)
        time.sleep(0.05)    # Sony's driver waits 50 ms

        def ready():
            st = self.read1(SENTRAL_STATUS)
            if st & 0x08 and st & (0x02 | 0x04 | 0x10):
                return st
            return None
        return self.poll("SentralStatus after reset", ready, UPLOAD_TIMEOUT_S)

    def wait_bit(self, what, reg, mask, want):
        return self.poll(what, lambda: True
                         if bool(self.read1(reg) & mask) == want else None)

    # §2: the request written, then bit 7, then ParamAcknowledge polled
    def wait_ack(self, req):
        self.poll(f"ParamAcknowledge 0x{req:02x}",
                  lambda: True if self.read1(PARAM_ACK) == req else None)

    def param_end(self):
        self.write(PARAM_REQUEST, 0x00)
        self.write(ALGORITHM_CONTROL, 0x00)

    def param_write(self, n, value):
        for i in range(4):
            self.write(LOAD_PARAM0 + i, (value >> (8 * i)) & 0xFF)
        self.write(PARAM_REQUEST, n | 0x80)
        self.write(ALGORITHM_CONTROL, 0x80)
        self.wait_ack(n | 0x80)
        self.param_end()

    # Several reads in one procedure: the next ParamRequest while bit 7
    # stays set (§2 step 5), each SavedParamByte read alone
    def param_read(self, numbers):
        out = []
        for k, n in enumerate(numbers):
            self.write(PARAM_REQUEST, n)
            if not k:
                self.write(ALGORITHM_CONTROL, 0x80)
            self.wait_ack(n)
            b = [self.read1(SAVED_PARAM0 + i) for i in range(4)]
            out.append(b[0] | b[1] << 8 | b[2] << 16 | b[3] << 24)
        self.param_end()
        return out

    # §3 item 4, in the Pi library's order: run disabled, out of
    # passthrough, algorithm running, LPF before the rates, baro enabled
    # with bit 7, scaled output, events 0x07, run
    def master_mode_setup(self):
        self.write(HOST_CONTROL, 0x00)
        self.write(PASSTHRU_CONTROL, 0x00)
        self.wait_bit("passthrough off", PASSTHRU_STATUS, 0x01, False)
        self.write(ALGORITHM_CONTROL, 0x00)
        self.wait_bit("algorithm running", ALGORITHM_STATUS, 0x01, False)
        self.write(HOST_CONTROL, 0x01)
        self.write(HOST_CONTROL, 0x00)
        self.write(ACC_LPF_BW, 0x03)            # 41 Hz
        self.write(GYRO_LPF_BW, 0x03)
        self.write(QRATE_DIVISOR, 0x01)         # half the gyro rate
        self.write(MAG_RATE, 100)               # Hz
        self.write(ACCEL_RATE, 200 // 10)       # Hz/10
        self.write(GYRO_RATE, 200 // 10)
        self.write(BARO_RATE, 0x80 | 50)
        self.write(ALGORITHM_CONTROL, 0x00)
        self.write(ENABLE_EVENTS, 0x07)         # reset, error, quaternion
        self.write(HOST_CONTROL, 0x01)
        time.sleep(0.1)

    def passthrough_on(self):
        self.write(ALGORITHM_CONTROL, 0x01)     # standby first
        time.sleep(0.005)
        self.write(PASSTHRU_CONTROL, 0x01)
        self.wait_bit("passthrough ready", PASSTHRU_STATUS, 0x01, True)

    # GT's resume: passthrough off, algorithm on, EventStatus read
    def passthrough_off(self):
        self.write(PASSTHRU_CONTROL, 0x00)
        self.wait_bit("passthrough off", PASSTHRU_STATUS, 0x01, False)
        self.write(ALGORITHM_CONTROL, 0x00)
        self.wait_bit("algorithm running", ALGORITHM_STATUS, 0x01, False)
        return self.read1(EVENT_STATUS)

    def quaternion(self):
        q = struct.unpack("<4f", bytes(self.read(QX, 16)))
        return q[3], q[0], q[1], q[2]           # w stored last

    def three_axis(self, reg):
        return struct.unpack("<3h", bytes(self.read(reg, 6)))

    # The boards' examples (SL's Interrupt, KW's and GT's sketches): on
    # each EventStatus with the barometer's bit (6), Baro and then Temp,
    # each a signed 16-bit value; pressure in mbar = raw * 0.01 + 1013.25,
    # temperature in C = raw * 0.01
    def barometer_event(self):
        self.poll("a barometer event", lambda: True
                  if self.read1(EVENT_STATUS) & 0x40 else None)
        p, = struct.unpack("<h", bytes(self.read(BARO, 2)))
        t, = struct.unpack("<h", bytes(self.read(TEMP, 2)))
        return p * 0.01 + 1013.25, t * 0.01


def main():
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-1], file=sys.stderr)
        return 2
    h = Host(sys.argv[1])

    def put(key, val):
        print(key, val, flush=True)

    put("product_id", f"0x{h.read1(PRODUCT_ID):02x}")
    put("revision_id", f"0x{h.read1(REVISION_ID):02x}")
    b = h.read(ROM_VERSION, 4)
    put("rom_version", f"0x{b[0] | b[1] << 8:04x}")
    put("ram_version", f"0x{b[2] | b[3] << 8:04x}")

    put("sentral_status_after_reset", f"0x{h.reset():02x}")
    put("event_status_after_reset", f"0x{h.read1(EVENT_STATUS):02x}")

    h.master_mode_setup()
    put("sensor_status", f"0x{h.read1(SENSOR_STATUS):02x}")
    put("sentral_status_running", f"0x{h.read1(SENTRAL_STATUS):02x}")
    put("actual_rates", " ".join(f"0x{v:02x}"
                                 for v in h.read(ACTUAL_MAG_RATE, 3)))

    # Disable stillness mode, as the libraries do after setup: param 73 = 0
    h.param_write(73, 0)
    mag_acc, gyro = h.param_read([74, 75])
    put("fs_mag_ut", mag_acc & 0xFFFF)
    put("fs_accel_g", mag_acc >> 16)
    put("fs_gyro_dps", gyro & 0xFFFF)
    # A full-scale write: accel 16 g, mag as it was; then read back
    h.param_write(74, (16 << 16) | (mag_acc & 0xFFFF))
    mag_acc2, = h.param_read([74])
    put("fs_written", f"0x{(16 << 16) | (mag_acc & 0xFFFF):08x}")
    put("fs_read_back", f"0x{mag_acc2:08x}")
    # A float parameter: mag merging rate 52, written 0.5, read back
    merge, = h.param_read([52])
    put("param52_before", f"{struct.unpack('<f', struct.pack('<I', merge))[0]:.4f}")
    h.param_write(52, struct.unpack("<I", struct.pack("<f", 0.5))[0])
    merge2, = h.param_read([52])
    put("param52_after", f"{struct.unpack('<f', struct.pack('<I', merge2))[0]:.4f}")

    # One EventStatus read after the setup, as a polling host's first:
    # every sensor the chip runs has its bit (the baro's only if the
    # FeatureFlags say there is one)
    h.read1(EVENT_STATUS)
    time.sleep(0.1)
    put("feature_flags", f"0x{h.read1(FEATURE_FLAGS):02x}")
    put("event_status", f"0x{h.read1(EVENT_STATUS):02x}")
    put("error_register", f"0x{h.read1(ERROR_REGISTER):02x}")

    w, x, y, z = h.quaternion()
    put("quat_wxyz", f"{w:.5f} {x:.5f} {y:.5f} {z:.5f}")
    put("quat_norm", f"{math.sqrt(w * w + x * x + y * y + z * z):.5f}")
    a = h.three_axis(AX)
    put("accel_lsb", " ".join(str(v) for v in a))
    put("accel_g", f"{math.sqrt(sum(v * v for v in a)) * ACCEL_G_PER_LSB:.4f}")
    lin = h.three_axis(LIN_ACCEL)
    put("lin_accel_lsb", " ".join(str(v) for v in lin))
    put("lin_accel_g",
        f"{math.sqrt(sum(v * v for v in lin)) * ACCEL_G_PER_LSB:.4f}")

    # The barometer, configured as the examples do (BaroRate only, no
    # TempRate), on a board whose FeatureFlags have one
    if h.read1(FEATURE_FLAGS) & 0x01:
        pressure, temperature = h.barometer_event()
        put("pressure_mbar", f"{pressure:.2f}")
        put("temperature_c", f"{temperature:.2f}")

    h.passthrough_on()
    put("passthru_status_on", f"0x{h.read1(PASSTHRU_STATUS):02x}")
    put("algorithm_status_on", f"0x{h.read1(ALGORITHM_STATUS):02x}")
    h.read1(EVENT_STATUS)
    time.sleep(0.1)
    put("event_status_in_passthrough", f"0x{h.read1(EVENT_STATUS):02x}")
    h.passthrough_off()
    put("passthru_status_off", f"0x{h.read1(PASSTHRU_STATUS):02x}")
    put("algorithm_status_off", f"0x{h.read1(ALGORITHM_STATUS):02x}")
    time.sleep(0.1)
    put("event_status_after_passthrough", f"0x{h.read1(EVENT_STATUS):02x}")
    put("transactions", h.transactions)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (ProtocolError, OSError) as e:
        print(f"em7180_refhost: {e}", file=sys.stderr)
        sys.exit(1)
