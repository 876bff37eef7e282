#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Write the plan harness's seeds of chains of short moves.

Zigzags, S-bends and spirals of short G1 moves at F24000 under G64 P Q0,
as bench/lcnc-compare/families.py makes them (its program(), cut to the
first N moves so that a seed is planned whole within the harness's 2000
points): random mutation seldom makes dozens of regular alternating short
moves, the shape where the planner's per-junction bounds are weakest
(docs/planner.md "Known limits"). Only members within the limits on main
are listed (every committed seed must pass the harness; check a new one
with build/fuzz/tests/fuzz/fuzz_plan FILE before adding it here).

    tests/fuzz/chain_seeds.py        rewrite tests/fuzz/corpus/plan/G-chain-*
"""
import importlib.util
import os

HERE = os.path.dirname(os.path.abspath(__file__))
FAMILIES = os.path.join(HERE, "..", "..", "bench", "lcnc-compare",
                        "families.py")

# (pattern, turn in degrees, move length in mm, G64 P, moves)
SEEDS = (
    ("zig", 10, 0.2, "0.1", 80),
    ("zig", 30, 0.6, "0.01", 60),
    ("zig", 45, 0.1, "0.01", 80),
    ("zig", 90, 0.4, "0.01", 60),
    ("zig", 135, 1.2, "0.1", 40),
    ("s", 10, 0.2, "0.01", 80),
    ("s", 30, 0.4, "0.1", 60),
    ("s", 60, 0.1, "0.01", 60),
    ("s", 135, 0.6, "0.1", 40),
    ("spiral", 10, 0.1, "0.01", 80),
    ("spiral", 30, 0.2, "0.1", 60),
    ("spiral", 45, 0.6, "0.1", 60),
    ("spiral", 60, 0.4, "0.01", 60),
    ("spiral", 135, 3.0, "0.1", 40),
)


def families():
    spec = importlib.util.spec_from_file_location("families", FAMILIES)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def seed(fam, pattern, theta, length, tol, moves):
    """The harness input: 'G' (the G-code reader), then the program."""
    lines = fam.program(pattern, theta, length, tol).splitlines()
    # two lines of set-up, then one G1 a move; M2 ends it
    return "G" + "\n".join(lines[:2 + moves] + ["M2"]) + "\n"


def main():
    fam = families()
    out = os.path.join(HERE, "corpus", "plan")
    for name in os.listdir(out):
        if name.startswith("G-chain-"):
            os.remove(os.path.join(out, name))
    for s in SEEDS:
        name = "G-chain-%s-%d-%gmm-P%s-%d.ngc" % s
        with open(os.path.join(out, name), "w") as f:
            f.write(seed(fam, *s))


if __name__ == "__main__":
    main()
