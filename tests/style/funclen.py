#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""No function longer than LIMIT lines in the libraries and the tools.

A function is a line "{" at column 0 after its signature up to the next
"}" at column 0 (kernel style, which the tree follows). Long functions are
where jobs get mixed; the limit keeps each one readable on a screen or two.
Usage: funclen.py LIMIT DIR... ; prints every offender and exits 1 if any.
"""
import os
import re
import sys


def functions(path):
    with open(path, errors="replace") as f:
        lines = f.read().split("\n")
    start = None
    for i, line in enumerate(lines):
        if line == "{":
            j = i - 1
            while j >= 0 and "(" not in lines[j]:
                j -= 1
            m = re.search(r"(\w+)\s*\(", lines[j]) if j >= 0 else None
            start = (i, m.group(1) if m else "?")
        elif line.startswith("}") and start:
            yield start[1], start[0] + 1, i - start[0] + 1
            start = None


def main():
    limit = int(sys.argv[1])
    bad = 0
    for top in sys.argv[2:]:
        for root, _, files in os.walk(top):
            for name in sorted(files):
                if not name.endswith(".c"):
                    continue
                path = os.path.join(root, name)
                for fn, line, n in functions(path):
                    if n > limit:
                        print(f"{path}:{line}: {fn}() is {n} lines (limit {limit})")
                        bad += 1
    print(f"{bad} function(s) over {limit} lines")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
