#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-only
"""Wait the way a program woken by the driver waits, without polling.

usage: iio_wait.py sysfs SECONDS FILE...
       iio_wait.py event SECONDS /dev/iio:deviceN

sysfs: read each attribute FILE once, then sleep in poll() (POLLPRI) until
the driver notifies one of them (sysfs_notify); print the names of those
that woke, one a line.  event: take the device's IIO event file
(IIO_GET_EVENT_FD_IOCTL) and print the first event as "ID TIMESTAMP" (ID in
hexadecimal).  Exit status 0 when woken, 1 when SECONDS passed first.
"""
import array
import fcntl
import os
import select
import struct
import sys

IIO_GET_EVENT_FD_IOCTL = 0x80046990     # _IOR('i', 0x90, int)


def wait_sysfs(timeout, files):
    fds = {}
    poller = select.poll()
    for name in files:
        fd = os.open(name, os.O_RDONLY)
        os.read(fd, 4096)
        fds[fd] = name
        poller.register(fd, select.POLLPRI | select.POLLERR)
    woke = poller.poll(timeout * 1000)
    for fd, _ in woke:
        print(fds[fd])
    return 0 if woke else 1


def wait_event(timeout, node):
    dev = os.open(node, os.O_RDONLY)
    arg = array.array('i', [0])
    fcntl.ioctl(dev, IIO_GET_EVENT_FD_IOCTL, arg, True)
    efd = arg[0]
    ready, _, _ = select.select([efd], [], [], timeout)
    if not ready:
        return 1
    ev_id, ts = struct.unpack('<Qq', os.read(efd, 16))
    print('0x%016x %d' % (ev_id, ts))
    return 0


def main(argv):
    if len(argv) < 4 or argv[1] not in ('sysfs', 'event'):
        sys.stderr.write(__doc__)
        return 2
    timeout = float(argv[2])
    if argv[1] == 'sysfs':
        return wait_sysfs(timeout, argv[3:])
    return wait_event(timeout, argv[3])


if __name__ == '__main__':
    sys.exit(main(sys.argv))
