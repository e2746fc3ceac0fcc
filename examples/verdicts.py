#!/usr/bin/env python3
"""Loads the per-ray verdicts of `octrace certify --verdicts PREFIX` with numpy and prints, per
set of the ray file's manifest, how many rays fell in each class, the leaks, and the rows of
one reason (docs/CERTIFY.md, "Per-ray verdicts").

Usage: verdicts.py PREFIX R.json [REASON]      (apt-get install python3-numpy)
  PREFIX.class.npy    uint8 (N,): 0 agree, 1 tie, 2 ambiguous, 3 wrong, 4 unverified
  PREFIX.reasons.npy  uint32 (N,): bit i set = reason i below
  PREFIX.leak.npy     uint8 (N,): 0 sealed, 1 leak, 2 not a target, 3 unsealed, 4 unverified
"""
import json
import sys

import numpy as np

CLASSES = ["agree", "tie", "ambiguous", "wrong", "unverified"]
REASONS = ["edge_or_vertex", "grazing", "degenerate", "tangent", "range_end", "reference_off",
           "terminator", "not_rechecked", "invalid_hit", "missed_hit", "false_hit",
           "t_outside_range", "off_surface"]
LEAK, UNSEALED = 1, 3


def main():
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    prefix, manifest = sys.argv[1], sys.argv[2]
    cls = np.load(prefix + ".class.npy")
    reasons = np.load(prefix + ".reasons.npy")
    leak = np.load(prefix + ".leak.npy")
    sets = json.load(open(manifest))["sets"]
    print(f"{'set':12s}" + "".join(f"{c:>11s}" for c in CLASSES) + f"{'leaks':>8s}{'unsealed':>9s}")
    for s in sets:
        rows = slice(s["begin"], s["begin"] + s["count"])
        counts = np.bincount(cls[rows], minlength=len(CLASSES))
        print(f"{s['name']:12s}" + "".join(f"{n:11d}" for n in counts) +
              f"{np.count_nonzero(leak[rows] == LEAK):8d}"
              f"{np.count_nonzero(leak[rows] == UNSEALED):9d}")
    leaks = np.flatnonzero(leak == LEAK)
    print(f"leak rows: {leaks[:10].tolist()}{' ...' if leaks.size > 10 else ''}")
    if len(sys.argv) == 4:
        bit = REASONS.index(sys.argv[3])
        rows = np.flatnonzero(reasons & np.uint32(1 << bit))
        print(f"{sys.argv[3]} rows ({rows.size}): {rows[:10].tolist()}"
              f"{' ...' if rows.size > 10 else ''}")


if __name__ == "__main__":
    main()
