#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-only
"""Read a guest journal exported with `journalctl -o json`.

usage: journal.py FILE time REGEX        monotonic time (us) of the first
                                         message matching REGEX
       journal.py FILE messages UNITGLOB messages of the matching units

A kernel message carries the time the kernel logged it
(_SOURCE_MONOTONIC_TIMESTAMP); other messages the time journald got them.
"""
import fnmatch
import json
import re
import sys


def entries(path):
    with open(path, errors="replace") as f:
        for line in f:
            try:
                e = json.loads(line)
            except ValueError:
                continue
            if isinstance(e.get("MESSAGE"), str):
                yield e


def main():
    path, what, arg = sys.argv[1:4]
    for e in entries(path):
        if what == "time" and re.search(arg, e["MESSAGE"]):
            print(e.get("_SOURCE_MONOTONIC_TIMESTAMP",
                        e["__MONOTONIC_TIMESTAMP"]))
            return 0
        if what == "messages" and fnmatch.fnmatch(e.get("_SYSTEMD_UNIT", ""),
                                                  arg):
            print(e["MESSAGE"])
    return 1 if what == "time" else 0


if __name__ == "__main__":
    sys.exit(main())
