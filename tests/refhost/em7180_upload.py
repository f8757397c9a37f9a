#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-only
"""A reference host's RAM upload to an EM7180 over i2c-dev, for tests.

It does what EM's generic host driver (em718x_core.c) and Sony's em718x.c
do to a chip without an EEPROM (EM7180 register reference §3 item 3), not
what our driver does: check the .fw header (magic, length), UploadAddress
0 (two bytes at 0x94, MSB first), HostControl = 0x02, the text streamed to
UploadData 0x96 in chunks (EM: 64 bytes; Sony: 32, an SMBus block), every
32-bit word byte-swapped, CRCHost (0x97, 4 bytes, little-endian) read and
compared with the header's text_crc, HostControl = 0. EM reads CRCHost
before it clears HostControl, Sony after: --crc-after-stop plays Sony.

Prints "key value" lines: crc_chip, crc_header, crc_sent (the CRC-32 of
the text bytes actually sent, as in the image), crc_wire (of the bytes as
they crossed the bus) and match (1 when crc_chip equals crc_header).
Exits 0 when they match, 1 on a mismatch, 2 on a bad image or bus error.

Usage: em7180_upload.py /dev/i2c-N IMAGE [--chunk N] [--crc-after-stop]
                        [--no-stop]
"""
import argparse
import fcntl
import os
import struct
import sys
import zlib

I2C_SLAVE = 0x0703          # linux/i2c-dev.h
ADDRESS = 0x28
HOST_CONTROL = 0x34
UPLOAD_ADDRESS = 0x94
UPLOAD_DATA = 0x96
CRC_HOST = 0x97
MAGIC = 0x652A
HEADER = struct.Struct("<HHIIHH")


def swab32(data):
    out = bytearray()
    for i in range(0, len(data), 4):
        out += data[i:i + 4][::-1]
    return bytes(out)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("dev")
    p.add_argument("image")
    p.add_argument("--chunk", type=int, default=64)
    p.add_argument("--crc-after-stop", action="store_true")
    p.add_argument("--no-stop", action="store_true",
                   help="leave HostControl bit 1 set (upload not ended)")
    a = p.parse_args()

    with open(a.image, "rb") as f:
        data = f.read()
    if len(data) < HEADER.size:
        print("em7180_upload: image shorter than its header", file=sys.stderr)
        return 2
    magic, _flags, text_crc, _r1, text_length, _r2 = HEADER.unpack_from(data)
    if magic != MAGIC:
        print(f"em7180_upload: bad magic 0x{magic:04x}", file=sys.stderr)
        return 2
    # Sony sends everything after the header, EM text_length bytes: the
    # same for a well-formed file; a truncated one is sent as it is
    text = data[HEADER.size:HEADER.size + text_length]

    fd = os.open(a.dev, os.O_RDWR)
    fcntl.ioctl(fd, I2C_SLAVE, ADDRESS)
    os.write(fd, bytes([UPLOAD_ADDRESS, 0x00, 0x00]))
    os.write(fd, bytes([HOST_CONTROL, 0x02]))
    wire = swab32(text)
    for i in range(0, len(wire), a.chunk):
        os.write(fd, bytes([UPLOAD_DATA]) + wire[i:i + a.chunk])

    def read_crc():
        os.write(fd, bytes([CRC_HOST]))
        return struct.unpack("<I", os.read(fd, 4))[0]

    if a.crc_after_stop and not a.no_stop:
        os.write(fd, bytes([HOST_CONTROL, 0x00]))
        crc = read_crc()
    else:
        crc = read_crc()
        if not a.no_stop:
            os.write(fd, bytes([HOST_CONTROL, 0x00]))
    os.close(fd)

    print(f"crc_chip 0x{crc:08x}")
    print(f"crc_header 0x{text_crc:08x}")
    print(f"crc_sent 0x{zlib.crc32(text):08x}")
    print(f"crc_wire 0x{zlib.crc32(wire):08x}")
    print(f"match {int(crc == text_crc)}")
    return 0 if crc == text_crc else 1


if __name__ == "__main__":
    try:
        sys.exit(main())
    except OSError as e:
        print(f"em7180_upload: {e}", file=sys.stderr)
        sys.exit(2)
