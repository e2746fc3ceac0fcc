"""Reading `octrace bench` results and the numbers the paper's claims are checked with.

Shared by bench/plot.py (figures) and bench/make_results.py (docs/RESULTS.md). Standard library
only, so it also runs under a Python without matplotlib.

A results folder holds bench.csv (one row per case) and bench.json (the same rows plus the
machine and the configuration); optionally micro.json from octrace_micro --benchmark_out.

Format octrace-bench/2 names the boxes tested boxes_per_pixel and boxes_per_ray (the words of
docs/TEACHING.md, "Words"); format 1 (the committed results under bench/results/) named them
nodes_per_pixel and nodes_per_ray. read_csv renames the old columns, so both read the same.
"""

import csv
import json
import math
import os

INT_FIELDS = {
    "n", "primitives", "vertices", "faces", "grid_depth", "primary_rays", "shadow_rays",
    "layout_bytes", "octree_nodes", "octree_depth", "octree_faces", "width", "height", "warmup",
    "repeats",
}
FLOAT_FIELDS = {
    "load_s", "tree_build_s", "convert_s", "build_s", "frame_s_median", "frame_s_min",
    "frame_s_max", "upload_s", "mrays_per_s", "ratio_to_embree", "boxes_per_pixel",
    "prims_per_pixel", "boxes_per_ray", "prims_per_ray",
}

# Format 1's column names and their format 2 names.
RENAMED = {"nodes_per_pixel": "boxes_per_pixel", "nodes_per_ray": "boxes_per_ray"}

EMBREE = "embree-bvh"


class Run:
    """One results folder: rows (dicts, numbers parsed, empty cells None), machine, config."""

    def __init__(self, folder):
        self.folder = folder
        self.rows = read_csv(os.path.join(folder, "bench.csv"))
        meta_path = os.path.join(folder, "bench.json")
        meta = {}
        if os.path.exists(meta_path):
            with open(meta_path) as f:
                meta = json.load(f)
        self.machine = meta.get("machine", {})
        self.config = meta.get("config", {})
        self.complete = meta.get("complete", True)
        micro_path = os.path.join(folder, "micro.json")
        self.micro = None
        if os.path.exists(micro_path):
            with open(micro_path) as f:
                self.micro = json.load(f)

    def layouts(self):
        """The layouts this run measured, in the order octrace bench ran them (its registry's)."""
        named = self.config.get("layouts")
        if named:
            return list(named)
        seen = []
        for r in self.rows:
            if r["layout"] not in (EMBREE, "-") and r["backend"] != "embree" and r["layout"] not in seen:
                seen.append(r["layout"])
        return seen

    def octrees(self):
        """The measured layouts converted from the octree: rows that report octree nodes."""
        tree = {r["layout"] for r in self.rows if r.get("octree_nodes") is not None}
        return [l for l in self.layouts() if l in tree]

    def backends(self):
        """Our backends present in the rows (cpu, cuda), in a fixed order."""
        present = {r["backend"] for r in self.rows}
        return [b for b in ("cpu", "cuda") if b in present]

    def has_embree(self):
        return any(r["backend"] == "embree" for r in self.rows)

    def select(self, scene_type=None, layout=None, backend=None, status=None):
        out = []
        for r in self.rows:
            if scene_type and r["scene_type"] != scene_type:
                continue
            if layout and r["layout"] != layout:
                continue
            if backend and r["backend"] != backend:
                continue
            if status and r["status"] != status:
                continue
            out.append(r)
        return out

    def cloud_sizes(self):
        return sorted({r["n"] for r in self.rows if r["scene_type"] == "cloud"})

    def meshes(self):
        """Mesh scene names, ascending in triangles (then name)."""
        seen = {}
        for r in self.rows:
            if r["scene_type"] == "mesh":
                seen.setdefault(r["scene"], r["primitives"] or 0)
        return sorted(seen, key=lambda s: (seen[s], s))

    def find(self, scene, layout, backend):
        for r in self.rows:
            if r["scene"] == scene and r["layout"] == layout and r["backend"] == backend:
                return r
        return None

    def cloud_row(self, n, layout, backend):
        for r in self.rows:
            if (r["scene_type"] == "cloud" and r["n"] == n and r["layout"] == layout
                    and r["backend"] == backend):
                return r
        return None


def parse_value(key, text):
    if text == "":
        return None
    if key in INT_FIELDS:
        return int(float(text))
    if key in FLOAT_FIELDS:
        return float(text)
    return text


def read_csv(path):
    with open(path, newline="") as f:
        return [{RENAMED.get(k, k): parse_value(RENAMED.get(k, k), v) for k, v in row.items()}
                for row in csv.DictReader(f)]


def series(run, layout, backend, scene_type="cloud"):
    """[(N, median, min, max)] of the measured (status ok) cases, ascending in N."""
    pts = []
    for r in run.select(scene_type=scene_type, layout=layout, backend=backend, status="ok"):
        pts.append((r["n"], r["frame_s_median"], r["frame_s_min"], r["frame_s_max"]))
    return sorted(pts)


def loglog_fit(points, lo=None, hi=None):
    """Least-squares slope and intercept of log(t) against log(N) for (N, t) with lo <= N <= hi.
    Returns (slope, intercept, count) or None with fewer than two points."""
    pts = [(n, t) for n, t in points if t and t > 0 and (lo is None or n >= lo)
           and (hi is None or n <= hi)]
    if len(pts) < 2:
        return None
    xs = [math.log(n) for n, _ in pts]
    ys = [math.log(t) for _, t in pts]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    if sxx == 0:
        return None
    slope = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    return slope, my - slope * mx, len(pts)


def crossover(exhaustive, octree):
    """Where the octree's frame time drops below exhaustive tracing.

    exhaustive, octree: [(N, t)]. Uses the sizes measured for both. Returns a dict:
      kind: 'between' (crossover interpolated in log-log between two sizes), 'below' (the octree
            is already faster at the smallest common size), 'none' (never faster), 'unknown'
            (fewer than one common size);
      n: the interpolated N for 'between', else the bounding size;
      lo, hi: the bracketing sizes; common: the sizes compared.
    The first size from which the octree stays faster is used, so noise at small N that makes
    the curves touch more than once does not move the answer below a later re-crossing.
    """
    e = dict(exhaustive)
    o = dict(octree)
    common = sorted(set(e) & set(o))
    if not common:
        return {"kind": "unknown", "n": None, "lo": None, "hi": None, "common": []}
    # d > 0: the octree is faster.
    d = [(n, math.log(e[n]) - math.log(o[n])) for n in common]
    last_slower = None
    for i, (n, v) in enumerate(d):
        if v <= 0:
            last_slower = i
    if last_slower is None:
        return {"kind": "below", "n": common[0], "lo": None, "hi": common[0], "common": common}
    if last_slower == len(d) - 1:
        return {"kind": "none", "n": common[-1], "lo": common[-1], "hi": None, "common": common}
    (n0, v0), (n1, v1) = d[last_slower], d[last_slower + 1]
    x0, x1 = math.log(n0), math.log(n1)
    x = x0 + (0 - v0) * (x1 - x0) / (v1 - v0) if v1 != v0 else x0
    return {"kind": "between", "n": math.exp(x), "lo": n0, "hi": n1, "common": common}


def ratios(run, num_layout, den_layout, backend, scene_type):
    """[(scene, N, t_num / t_den)] for scenes where both layouts were measured."""
    out = []
    for r in run.select(scene_type=scene_type, layout=den_layout, backend=backend, status="ok"):
        other = run.find(r["scene"], num_layout, backend)
        if other and other["status"] == "ok" and r["frame_s_median"]:
            out.append((r["scene"], r["n"], other["frame_s_median"] / r["frame_s_median"]))
    return sorted(out, key=lambda x: x[1])


def median(values):
    v = sorted(values)
    if not v:
        return None
    m = len(v) // 2
    return v[m] if len(v) % 2 else 0.5 * (v[m - 1] + v[m])


def human_count(n):
    if n is None:
        return "-"
    if n >= 1000000 and n % 1000000 == 0:
        return "%dM" % (n // 1000000)
    if n >= 1000 and n % 1000 == 0:
        return "%dk" % (n // 1000)
    return str(n)


def human_bytes(b):
    if b is None:
        return "-"
    for unit, scale in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if b >= scale:
            return "%.1f %s" % (b / scale, unit)
    return "%d B" % b


def ms(t):
    if t is None:
        return "-"
    v = t * 1e3
    if v >= 100:
        return "%.0f" % v
    if v >= 10:
        return "%.1f" % v
    return "%.2f" % v
