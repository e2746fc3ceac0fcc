#!/usr/bin/env python3
"""A plain Moller-Trumbore brute-force tracer: the textbook test (Moller & Trumbore 1997, "Fast,
minimum storage ray-triangle intersection") in float32 with its determinant epsilon, every ray
against every triangle. A third-party tracer to certify with `octrace certify` (docs/CERTIFY.md).

usage: python3 moller_trumbore.py T.npy R.npy PREFIX
  T.npy  float32 (M, 9): v0 v1 v2 per triangle, in octrace's primitive order (octrace rays
         --triangles T.npy writes it)
  R.npy  float32 (N, 8): ox oy oz dx dy dz tmin tmax (docs/TRACE_FORMAT.md)
writes PREFIX.t.npy float32 (N,), +inf on a miss, and PREFIX.prim.npy int32 (N,), -1 on a miss.
Needs numpy (Debian: apt-get install python3-numpy, then /usr/bin/python3).
"""
import sys

import numpy as np

EPS = np.float32(1e-7)  # the textbook's threshold: |det| below it is a parallel ray; t above it


def trace(tri, rays):
    v0, e1, e2 = tri[:, 0:3], tri[:, 3:6] - tri[:, 0:3], tri[:, 6:9] - tri[:, 0:3]
    t_out = np.full(len(rays), np.inf, np.float32)
    p_out = np.full(len(rays), -1, np.int32)
    chunk = max(1, (1 << 21) // len(tri))  # rays per step: about 2M ray-triangle pairs
    for s in range(0, len(rays), chunk):
        r = rays[s:s + chunk]
        o, d = r[:, None, 0:3], r[:, None, 3:6]
        p = np.cross(d, e2[None])  # P = D x E2
        det = np.einsum("rmk,mk->rm", p, e1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = np.float32(1) / det
            tv = o - v0[None]  # T = O - V0
            u = np.einsum("rmk,rmk->rm", tv, p) * inv
            q = np.cross(tv, e1[None])  # Q = T x E1
            v = np.einsum("rmk,rk->rm", q, r[:, 3:6]) * inv
            t = np.einsum("rmk,mk->rm", q, e2) * inv
            ok = (np.abs(det) > EPS) & (u >= 0) & (u <= 1) & (v >= 0) & (u + v <= 1)
            ok &= (t > EPS) & (t >= r[:, 6:7]) & (t <= r[:, 7:8])
        t = np.where(ok, t, np.float32(np.inf))
        best = np.argmin(t, axis=1)  # the first of equal t: the lowest id, as octrace's
        tb = t[np.arange(len(r)), best]
        t_out[s:s + chunk] = tb
        p_out[s:s + chunk] = np.where(np.isfinite(tb), best, -1)
    return t_out, p_out


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    tri, rays = np.load(sys.argv[1]), np.load(sys.argv[2])
    if tri.dtype != np.float32 or tri.ndim != 2 or tri.shape[1] != 9:
        sys.exit(f"{sys.argv[1]}: expected float32 (M, 9), got {tri.dtype} {tri.shape}")
    if rays.dtype != np.float32 or rays.ndim != 2 or rays.shape[1] != 8:
        sys.exit(f"{sys.argv[2]}: expected float32 (N, 8), got {rays.dtype} {rays.shape}")
    t, prim = trace(tri, rays)
    np.save(sys.argv[3] + ".t.npy", t)
    np.save(sys.argv[3] + ".prim.npy", prim)
    print(f"{len(rays)} rays, {int((prim >= 0).sum())} hits -> {sys.argv[3]}.{{t,prim}}.npy")


if __name__ == "__main__":
    main()
