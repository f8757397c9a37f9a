#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0-only
"""Read a guest journal exported with `journalctl -o json`.

usage: journal.py FILE time REGEX        monotonic time (us) of the first
                                         message matching REGEX
       journal.py FILE messages UNITGLOB messages of the matching units
       journal.py FILE after REGEX GLOB  messages after the first one
                                         matching REGEX whose unit, the unit
                                         it is about (systemd's) or syslog
                                         identifier matches GLOB

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


def about(e, glob):
    return any(isinstance(e.get(f), str) and fnmatch.fnmatch(e[f], glob)
               for f in ("_SYSTEMD_UNIT", "UNIT", "SYSLOG_IDENTIFIER"))


def main():
    path, what, arg = sys.argv[1:4]
    if what == "after":
        seen = False
        for e in entries(path):
            if seen and about(e, sys.argv[4]):
                print(e["MESSAGE"])
            seen = seen or bool(re.search(arg, e["MESSAGE"]))
        return 0 if seen else 1
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
