#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-only
"""Decode an IIO buffer stream (e.g. iio_readdev's output) with the layout
the device describes in scan_elements/, and print one line per scan.

usage: iio_decode.py DEVICE_DIR [FILE] [--raw] [--csv]

DEVICE_DIR is /sys/bus/iio/devices/iio:deviceN.  FILE defaults to stdin.
The enabled channels describe the layout; when none is enabled (iio_readdev
disables them as it exits), all of them.  Values are multiplied by the
channel's _scale attribute, after adding its _offset (the IIO rule:
(raw + offset) * scale), unless --raw.
Exit status 1 when the input is not a whole number of scans.
"""
import os
import re
import struct
import sys

TYPE_RE = re.compile(r'^(le|be):([su])(\d+)/(\d+)(?:X(\d+))?>>(\d+)$')


def read(path):
    with open(path) as f:
        return f.read().strip()


def channels(dev):
    scan = os.path.join(dev, 'scan_elements')
    names = [n for n in os.listdir(scan) if n.endswith('_en')]
    enabled = [n for n in names if read(os.path.join(scan, n)) == '1']
    chans = []
    # iio_readdev enables every channel when given none, and disables them
    # again when it exits: with none enabled, decode as if all were.
    for name in enabled or names:
        base = name[:-3]
        m = TYPE_RE.match(read(os.path.join(scan, base + '_type')))
        if not m:
            sys.exit('cannot parse %s_type' % base)
        endian, sign, realbits, storagebits, repeat, shift = m.groups()
        chans.append({
            'name': base,
            'index': int(read(os.path.join(scan, base + '_index'))),
            'endian': '<' if endian == 'le' else '>',
            'signed': sign == 's',
            'realbits': int(realbits),
            'bytes': int(storagebits) // 8,
            'repeat': int(repeat or 1),
            'shift': int(shift),
            'scale': attr_of(dev, base, 'scale'),
            'offset': attr_of(dev, base, 'offset') or 0.0,
        })
    chans.sort(key=lambda c: c['index'])
    return chans


def attr_of(dev, base, what):
    # in_accel_x -> in_accel_x_scale, then the shared in_accel_scale.
    parts = base.split('_')
    for n in range(len(parts), 1, -1):
        path = os.path.join(dev, '_'.join(parts[:n]) + '_' + what)
        if os.path.exists(path):
            return float(read(path))
    return None


def layout(chans):
    # Same rule as the kernel's iio_compute_scan_bytes(): each channel is
    # aligned to its own size, the scan to the largest channel.
    offset = largest = 0
    for c in chans:
        size = c['bytes'] * c['repeat']
        offset = (offset + size - 1) // size * size
        c['at'] = offset
        offset += size
        largest = max(largest, size)
    return (offset + largest - 1) // largest * largest if largest else 0


def value(c, raw_bytes):
    fmt = {1: 'B', 2: 'H', 4: 'I', 8: 'Q'}[c['bytes']]
    v = struct.unpack(c['endian'] + fmt, raw_bytes)[0] >> c['shift']
    v &= (1 << c['realbits']) - 1
    if c['signed'] and v & (1 << (c['realbits'] - 1)):
        v -= 1 << c['realbits']
    return v


def main():
    args = [a for a in sys.argv[1:] if not a.startswith('--')]
    raw = '--raw' in sys.argv
    sep = ',' if '--csv' in sys.argv else ' '
    if not args:
        sys.exit(__doc__)
    chans = channels(args[0])
    size = layout(chans)
    data = open(args[1], 'rb').read() if len(args) > 1 else sys.stdin.buffer.read()
    if size == 0 or len(data) % size:
        sys.stderr.write('%d bytes is not a whole number of %d-byte scans\n'
                         % (len(data), size))
        return 1
    header = []
    for c in chans:
        n = c['name'].replace('in_', '', 1)
        header += [n] if c['repeat'] == 1 else ['%s[%d]' % (n, i) for i in range(c['repeat'])]
    print(sep.join(header))
    for s in range(0, len(data), size):
        row = []
        for c in chans:
            for i in range(c['repeat']):
                at = s + c['at'] + i * c['bytes']
                v = value(c, data[at:at + c['bytes']])
                if raw or c['scale'] is None:
                    row.append(str(v))
                else:
                    row.append('%.6f' % ((v + c['offset']) * c['scale']))
        print(sep.join(row))
    return 0


if __name__ == '__main__':
    sys.exit(main())
