# SPDX-License-Identifier: GPL-2.0-only
"""Apply Raspberry Pi overlay parameters to a .dtbo, as the firmware's
dtoverlay=NAME,PARAM=VALUE does before it merges the overlay.

Only what sentral's overlay declares is implemented: integer parameters
("<&label>,\"prop:offset\"", a 32-bit cell at a byte offset), with the
firmware's rule that writing "reg" also renames the node's unit address.
Anything else is refused, so that a declaration this does not understand
fails the test instead of being skipped.

Usage: python3 dtparam.py IN.dtbo OUT.dtbo NAME=VALUE...
"""

import struct
import sys

import libfdt


def targets(fdt, name):
    """The (phandle, property, offset) list of parameter NAME."""
    overrides = fdt.path_offset('/__overrides__')
    raw = bytes(fdt.getprop(overrides, name))
    out = []
    while raw:
        phandle = struct.unpack('>I', raw[:4])[0]
        spec, _, raw = raw[4:].partition(b'\0')
        spec = spec.decode()
        prop, sep, offset = spec.partition(':')
        if not sep or not offset.isdigit() or '=' in spec:
            sys.exit(f'dtparam: {name}: unsupported declaration "{spec}"')
        out.append((phandle, prop, int(offset)))
    return out


def rename(fdt, node, addr):
    """Give NODE the unit address ADDR, and update the overlay's own records
    of its path: its label in __symbols__, its references in __fixups__, and
    its twin under __local_fixups__ (that tree mirrors the overlay's paths:
    Raspberry Pi's own overlays rename nodes that refer to the overlay's
    labels, as mcp23017's addr does)."""
    old = fdt.get_path(node)
    base = fdt.get_name(node).split('@')[0]
    twin = fdt.path_offset('/__local_fixups__' + old, libfdt.QUIET_NOTFOUND)
    if twin >= 0:
        fdt.set_name(twin, f'{base}@{addr:x}')
        node = fdt.path_offset(old)
    fdt.set_name(node, f'{base}@{addr:x}')
    new = fdt.get_path(node)
    for table in ('/__symbols__', '/__fixups__'):
        parent = fdt.path_offset(table, libfdt.QUIET_NOTFOUND)
        if parent < 0:
            continue
        names = []
        offset = fdt.first_property_offset(parent, libfdt.QUIET_NOTFOUND)
        while offset >= 0:
            names.append(fdt.get_property_by_offset(offset).name)
            offset = fdt.next_property_offset(offset, libfdt.QUIET_NOTFOUND)
        for name in names:
            entries = bytes(fdt.getprop(parent, name)).split(b'\0')[:-1]
            fixed = [new.encode() + e[len(old):]
                     if e == old.encode() or e.startswith(old.encode() + b':') else e
                     for e in entries]
            fdt.setprop(parent, name, b'\0'.join(fixed) + b'\0')


def main():
    src, dst, params = sys.argv[1], sys.argv[2], sys.argv[3:]
    with open(src, 'rb') as f:
        fdt = libfdt.Fdt(f.read())
    fdt.resize(fdt.totalsize() + 4096)
    for param in params:
        name, _, value = param.partition('=')
        for phandle, prop, offset in targets(fdt, name):
            node = fdt.node_offset_by_phandle(phandle)
            cells = bytearray(fdt.getprop(node, prop))
            if offset + 4 > len(cells):
                sys.exit(f'dtparam: {name}: {prop} has no cell at {offset}')
            cells[offset:offset + 4] = struct.pack('>I', int(value, 0))
            fdt.setprop(node, prop, bytes(cells))
            if prop == 'reg':
                rename(fdt, node, int(value, 0))
    fdt.pack()
    with open(dst, 'wb') as f:
        f.write(fdt.as_bytearray())


if __name__ == '__main__':
    main()
