#!/usr/bin/python3
# SPDX-License-Identifier: GPL-2.0-only
"""Generate a test firmware image in the SENtral .fw format.

The layout is the one the public host drivers read (EM7180 register
reference §3 item 3: EM's generic host driver em718x_core.c and Sony's
em718x.c): a 16-byte little-endian header

    u16 magic 0x652A, u16 flags {no_exec:1, rsvd:7, i2c_clk:3, rom_ver_exp:4},
    u32 text_crc, u32 reserved, u16 text_length, u16 reserved

then text_length bytes of text, whose last 44 bytes are the CDS block
(Sony's struct fw_cds: u16 signature, 6 reserved bytes, u16 ram_ver at
offset 8, u8 cds_ver, 8 pin and 8 pull selections, a 16-byte device name).
text_crc is the standard CRC-32 (zlib.crc32) of the text.

The text is pseudo-random bytes from a seed: no vendor code, nothing that
would run on a chip. Only for the simulator's tests.

Usage: mkfw.py OUT [--ram-version V] [--size N] [--rom-exp E] [--seed S]
               [--corrupt OFFSET] [--truncate N]
  --size N        text length in bytes (a multiple of 4, at least 44)
  --rom-exp E     expected ROM: 0 any, 1 DI01, 2 DI02
  --corrupt OFF   flip bit 0 of text byte OFF after the CRC was computed
  --truncate N    write only the first N bytes of the text (header kept)
Prints "text_crc 0x..." and "text_length N".
"""
import argparse
import random
import struct
import sys
import zlib

MAGIC = 0x652A
HEADER = struct.Struct("<HHIIHH")
CDS_SIZE = 44
CDS_RAM_VER = 8


def build(size, ram_version, rom_exp, seed):
    if size % 4 or size < CDS_SIZE:
        raise ValueError("the text is whole 32-bit words, CDS included")
    rng = random.Random(seed)
    body = bytes(rng.randrange(256) for _ in range(size - CDS_SIZE))
    cds = bytearray(CDS_SIZE)
    struct.pack_into("<H", cds, CDS_RAM_VER, ram_version)
    cds[10] = 1                                     # cds_ver
    name = b"sentral-sim-test"
    cds[CDS_SIZE - 16 - 1:CDS_SIZE - 1] = name       # dev_name[16]
    text = body + bytes(cds)
    flags = (rom_exp & 0xF) << 11
    header = HEADER.pack(MAGIC, flags, zlib.crc32(text), 0, len(text), 0)
    return header, text


def main():
    p = argparse.ArgumentParser()
    p.add_argument("out")
    p.add_argument("--ram-version", type=lambda s: int(s, 0), default=0x0E42)
    p.add_argument("--size", type=int, default=2048)
    p.add_argument("--rom-exp", type=int, default=2)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--corrupt", type=int)
    p.add_argument("--truncate", type=int)
    a = p.parse_args()
    header, text = build(a.size, a.ram_version, a.rom_exp, a.seed)
    text = bytearray(text)
    if a.corrupt is not None:
        text[a.corrupt] ^= 0x01
    if a.truncate is not None:
        text = text[:a.truncate]
    with open(a.out, "wb") as f:
        f.write(header + text)
    print(f"text_crc 0x{HEADER.unpack(header)[2]:08x}")
    print(f"text_length {HEADER.unpack(header)[4]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
