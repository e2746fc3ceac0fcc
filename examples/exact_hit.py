#!/usr/bin/env python3
"""The exact closest hit of single rays, in rational arithmetic: an independent check, by hand,
of a verdict of `octrace certify` (docs/CERTIFY.md). Every float32 is an exact rational, so
solving o + t d = v0 + u e1 + v e2 with Python's fractions (Cramer's rule) decides hit or miss
of the closed triangle, and t, with no rounding at all. numpy in float64 only preselects the
triangles near the ray (generously); the decision is exact.

usage: python3 exact_hit.py T.npy R.npy ROW [ROW ...]
  T.npy  float32 (M, 9) triangles (octrace rays --triangles); R.npy float32 (N, 8) rays
prints per row: the exact closest hit (t to 9 digits, primitive) and every hit within 1e-4 in t
after it, each saying whether the ray meets the triangle inside or exactly on an edge or a
vertex (an exactly zero barycentric), or "miss".
"""
import sys
from fractions import Fraction as F

import numpy as np


def exact_hits(tri, ray, candidates):
    o = [F(float(x)) for x in ray[0:3]]
    d = [F(float(x)) for x in ray[3:6]]
    tmin, tmax = F(float(ray[6])), ray[7]
    hits = []
    for i in candidates:
        a = [F(float(x)) for x in tri[i, 0:3]]
        e1 = [F(float(tri[i, 3 + k])) - a[k] for k in range(3)]
        e2 = [F(float(tri[i, 6 + k])) - a[k] for k in range(3)]
        p = [d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2], d[0] * e2[1] - d[1] * e2[0]]
        det = sum(e1[k] * p[k] for k in range(3))
        if det == 0:
            continue  # the ray is parallel to the plane: no single crossing point
        tv = [o[k] - a[k] for k in range(3)]
        q = [tv[1] * e1[2] - tv[2] * e1[1], tv[2] * e1[0] - tv[0] * e1[2],
             tv[0] * e1[1] - tv[1] * e1[0]]
        u = sum(tv[k] * p[k] for k in range(3)) / det
        v = sum(d[k] * q[k] for k in range(3)) / det
        t = sum(e2[k] * q[k] for k in range(3)) / det
        inside = u >= 0 and v >= 0 and u + v <= 1
        if inside and t >= tmin and (np.isinf(tmax) or t <= F(float(tmax))):
            hits.append((t, int(i), (1 - u - v, u, v)))
    return sorted(hits)


def near(tri, ray, slack=1e-3):
    """Triangles whose float64 barycentrics along the ray are within `slack` of the triangle."""
    o, d = ray[0:3].astype(np.float64), ray[3:6].astype(np.float64)
    v0 = tri[:, 0:3].astype(np.float64)
    e1, e2 = tri[:, 3:6] - v0, tri[:, 6:9] - v0
    p = np.cross(d, e2)
    det = np.einsum("mk,mk->m", e1, p)
    with np.errstate(divide="ignore", invalid="ignore"):
        tv = o - v0
        u = np.einsum("mk,mk->m", tv, p) / det
        v = np.einsum("mk,mk->m", np.cross(tv, e1), np.broadcast_to(d, tv.shape)) / det
    return np.nonzero((u >= -slack) & (v >= -slack) & (u + v <= 1 + slack))[0]


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    tri, rays = np.load(sys.argv[1]), np.load(sys.argv[2])
    for row in map(int, sys.argv[3:]):
        hits = exact_hits(tri, rays[row], near(tri, rays[row]))
        if not hits:
            print(f"row {row}: miss")
            continue
        t0 = hits[0][0]
        close = [f"#{i} t={float(t):.9g} {where(b)}" for t, i, b in hits if t - t0 <= F(1, 10000)]
        print(f"row {row}: closest t={float(t0):.9g} #{hits[0][1]} (exact); within 1e-4: "
              + ", ".join(close))


def where(bary):
    """Where the ray meets the closed triangle: inside, or exactly on an edge or a vertex."""
    zeros = sum(1 for b in bary if b == 0)
    return ["inside", "exactly on an edge", "exactly at a vertex"][min(zeros, 2)]


if __name__ == "__main__":
    main()
