#!/usr/bin/python3
"""Writes docs/RESULTS.md from `octrace bench` results: figures, tables and the paper's claims
checked against the numbers, all computed from the files, none typed by hand.

Usage:
  /usr/bin/python3 bench/make_results.py RESULTS_DIR [RESULTS_DIR ...] [--doc docs/RESULTS.md]

Each RESULTS_DIR is one `octrace bench --out RESULTS_DIR` run (bench.csv, bench.json, and
optionally micro.json from `octrace_micro --benchmark_out=RESULTS_DIR/micro.json
--benchmark_out_format=json`). Figures are written to RESULTS_DIR/figures (bench/plot.py) and
linked from the page. Give the CPU run first; a run with the cuda backend (a GPU machine) gets
its own section.
"""

import argparse
import math
import os
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_data as bd  # noqa: E402

try:
    import plot  # noqa: E402  (needs matplotlib)
except ImportError as e:  # pragma: no cover
    plot = None
    PLOT_ERROR = str(e)

PAPER = ("Barboza & Clua, \"A GPU-Based Data Structure for a Parallel Ray Tracing "
         "Illumination Algorithm\", SBGames 2011")


def rel(path, doc_dir):
    return os.path.relpath(path, doc_dir).replace(os.sep, "/")


def table(header, rows, align=None):
    align = align or ["---"] * len(header)
    out = ["| " + " | ".join(header) + " |", "|" + "|".join(align) + "|"]
    for r in rows:
        out.append("| " + " | ".join(str(c) for c in r) + " |")
    return "\n".join(out)


def cell_time(r):
    """'median (min-max)' in ms, or the status."""
    if r is None:
        return "-"
    if r["status"] != "ok":
        return "*%s*" % r["status"]
    return "%s (%s–%s)" % (bd.ms(r["frame_s_median"]), bd.ms(r["frame_s_min"]),
                           bd.ms(r["frame_s_max"]))


def fmt_ratio(x):
    return "-" if x is None else "%.2f×" % x


# --- the paper's claims --------------------------------------------------------------------


def claim_crossover(run, backend):
    exh = [(n, t) for n, t, _, _ in bd.series(run, "exhaustive", backend)]
    lines = []
    if not exh:
        return ["- No exhaustive case was measured on %s, so no crossover can be placed." %
                backend]
    for layout in run.octrees():
        pts = [(n, t) for n, t, _, _ in bd.series(run, layout, backend)]
        if not pts:
            continue
        c = bd.crossover(exh, pts)
        common = c["common"]
        span = ("%s..%s" % (bd.human_count(common[0]), bd.human_count(common[-1]))
                if common else "-")
        if c["kind"] == "between":
            lines.append(
                "- **%s octree**: overtakes exhaustive between N = %s and N = %s; the log-log "
                "interpolated crossover is **N ≈ %s** (sizes compared: %s)." %
                (layout, bd.human_count(c["lo"]), bd.human_count(c["hi"]),
                 "{:,}".format(int(round(c["n"]))), span))
        elif c["kind"] == "below":
            e, o = dict(exh)[c["n"]], dict(pts)[c["n"]]
            lines.append(
                "- **%s octree**: already faster than exhaustive at the smallest size measured, "
                "N = %s (%.1f× faster there), so the crossover lies **below N = %s** and is "
                "not resolved by this sweep (sizes compared: %s)." %
                (layout, bd.human_count(c["n"]), e / o, bd.human_count(c["n"]), span))
        elif c["kind"] == "none":
            lines.append("- **%s octree**: never faster than exhaustive up to N = %s: the "
                         "claim **does not hold** in this range." %
                         (layout, bd.human_count(c["n"])))
        else:
            lines.append("- **%s octree**: no size measured for both." % layout)
    if not lines:
        lines.append("- No octree case was measured on %s, so no crossover can be placed." %
                     backend)
    # How far apart they end up.
    for layout in run.octrees():
        pts = dict((n, t) for n, t, _, _ in bd.series(run, layout, backend))
        common = sorted(set(pts) & set(dict(exh)))
        if common:
            n = common[-1]
            lines.append("  At the largest size measured for both (N = %s) exhaustive takes "
                         "%.1f× the %s octree's time." %
                         (bd.human_count(n), dict(exh)[n] / pts[n], layout))
    return lines


def claim_linear_vs_hash(run, backend):
    lines = []
    for scene_type, what in (("cloud", "grid clouds"), ("mesh", "meshes")):
        rs = bd.ratios(run, "hash", "linear", backend, scene_type)
        if not rs:
            continue
        vals = [x for _, _, x in rs]
        faster = sum(1 for v in vals if v > 1.0)
        med = bd.median(vals)
        largest = rs[-1]
        verdict = ("holds" if faster == len(vals) else
                   "holds mostly" if faster * 2 > len(vals) else "does not hold")
        lines.append(
            "- **%s** (%d measured with both): hash time / linear time has median "
            "**%.2f×** (range %.2f×–%.2f×); linear is faster on %d of %d: the claim **%s**. "
            "At the largest (%s) the ratio is %.2f×." %
            (what, len(vals), med, min(vals), max(vals), faster, len(vals), verdict,
             largest[0], largest[2]))
    # Only the memory limit: cases skipped by the time guard say nothing about the layout.
    skipped_linear = [r for r in run.select(layout="linear", backend=backend)
                      if r["status"] == "skipped" and ("linear octree" in r["reason"]
                                                       or "memory" in r["reason"])]
    if skipped_linear:
        lines.append("- The linear octree was **skipped** for %s (e.g. %s): the complete "
                     "array grows as 8^depth, the paper's memory caveat." %
                     (", ".join(r["scene"] for r in skipped_linear),
                      skipped_linear[0]["reason"]))
    # The other half of the claim: linear needs more memory.
    mem = []
    for r in run.select(layout="hash", backend=backend):
        lin = run.find(r["scene"], "linear", backend)
        if r["layout_bytes"] and lin and lin["layout_bytes"]:
            mem.append(lin["layout_bytes"] / r["layout_bytes"])
    if mem:
        lines.append("- Memory: linear bytes / hash bytes has median **%.2f×** (range "
                     "%.2f×–%.2f×) over %d scene%s; the linear layout is larger on %d." %
                     (bd.median(mem), min(mem), max(mem), len(mem),
                      "" if len(mem) == 1 else "s", sum(1 for m in mem if m > 1.0)))
    if not lines:
        lines.append("- Linear and hash were not both measured on any scene.")
    return lines


def slope_lines(run, backend, layout, claim_factor, per, label):
    """Fits log t = s log N + c over all sizes and over the paper's 1k..64k; reports per^s."""
    pts = [(n, t) for n, t, _, _ in bd.series(run, layout, backend)]
    out = []
    fits = [("all sizes measured", bd.loglog_fit(pts)),
            ("the paper's range 1k..64k", bd.loglog_fit(pts, 1000, 64000))]
    shown = set()
    for where, fit in fits:
        if not fit:
            continue
        slope, _, count = fit
        key = (round(slope, 6), count)
        if key in shown:
            continue
        shown.add(key)
        factor = per ** slope
        close = abs(factor - claim_factor) / claim_factor <= 0.3
        # The sizes the fit used: all of them, or those inside the paper's 1k..64k.
        used = [n for n, t in pts if t and t > 0
                and (where.startswith("all") or 1000 <= n <= 64000)]
        lo_n, hi_n = min(used), max(used)
        out.append(
            "- %s, %s (%d sizes, N = %s..%s): time ∝ N^**%.2f**, i.e. ×**%.2f** per %d× data "
            "(claim: ×%g) → the claim **%s**." %
            (label, where, count, bd.human_count(lo_n), bd.human_count(hi_n), slope, factor,
             per, claim_factor, "holds (within 30%)" if close else "does not hold"))
    if not out:
        out.append("- %s: fewer than two sizes measured; no slope." % label)
    return out


def claims_section(run, backend):
    parts = ["#### 1. The octree overtakes exhaustive tracing past a crossover"]
    parts += claim_crossover(run, backend)
    parts += ["", "#### 2. The linear octree is faster than the hash octree"]
    parts += claim_linear_vs_hash(run, backend)
    parts += ["", "#### 3. Exhaustive time doubles as the data doubles"]
    parts += slope_lines(run, backend, "exhaustive", 2.0, 2, "Exhaustive")
    parts += ["", "#### 4. Linear-octree time doubles per 16× data"]
    parts += slope_lines(run, backend, "linear", 2.0, 16, "Linear octree")
    parts += slope_lines(run, backend, "hash", 2.0, 16, "Hash octree (for comparison)")
    return "\n".join(parts)


# --- tables --------------------------------------------------------------------------------


def clouds_table(run, backend):
    sizes = run.cloud_sizes()
    if not sizes:
        return None
    embree = backend == "cpu" and run.has_embree()
    header = ["N", "depth"] + ["%s ms" % l for l in run.layouts()]
    if embree:
        header += ["Embree ms"] + ["%s ×Embree" % l for l in run.octrees()]
    header += ["hash / linear", "exhaustive / linear", "Mrays/s (linear)"]
    rows = []
    for n in sizes:
        r = {l: run.cloud_row(n, l, backend) for l in run.layouts()}
        any_row = next((x for x in r.values() if x), None) or run.cloud_row(n, bd.EMBREE,
                                                                            "embree")
        line = [bd.human_count(n), any_row["grid_depth"] if any_row else "-"]
        line += [cell_time(r[l]) for l in run.layouts()]
        if embree:
            e = run.cloud_row(n, bd.EMBREE, "embree")
            line += [cell_time(e)]
            line += [fmt_ratio(r[l]["ratio_to_embree"]) if r[l] else "-" for l in run.octrees()]

        def ratio(a, b):
            ra, rb = r.get(a), r.get(b)  # a run may leave a layout out (--accel)
            if ra and rb and ra["status"] == "ok" and rb["status"] == "ok":
                return fmt_ratio(ra["frame_s_median"] / rb["frame_s_median"])
            return "-"

        line += [ratio("hash", "linear"), ratio("exhaustive", "linear")]
        lin = r.get("linear")
        line += ["%.2f" % lin["mrays_per_s"] if lin and lin["status"] == "ok" else "-"]
        rows.append(line)
    return table(header, rows)


def meshes_table(run, backend):
    meshes = run.meshes()
    if not meshes:
        return None
    embree = backend == "cpu" and run.has_embree()
    header = ["mesh", "triangles"] + ["%s ms" % l for l in run.layouts()]
    if embree:
        header += ["Embree ms"] + ["%s ×Embree" % l for l in run.octrees()]
    header += ["hash / linear", "Mrays/s (linear)"]
    rows = []
    for m in meshes:
        r = {l: run.find(m, l, backend) for l in run.layouts()}
        any_row = next((x for x in run.rows if x["scene"] == m), None)
        line = [m, "{:,}".format(any_row["primitives"] or 0)]
        line += [cell_time(r[l]) for l in run.layouts()]
        if embree:
            line += [cell_time(run.find(m, bd.EMBREE, "embree"))]
            line += [fmt_ratio(r[l]["ratio_to_embree"]) if r[l] else "-" for l in run.octrees()]
        ok = lambda x: x and x["status"] == "ok"  # noqa: E731
        line += [fmt_ratio(r["hash"]["frame_s_median"] / r["linear"]["frame_s_median"])
                 if ok(r.get("hash")) and ok(r.get("linear")) else "-"]
        line += ["%.2f" % r["linear"]["mrays_per_s"] if ok(r.get("linear")) else "-"]
        rows.append(line)
    return table(header, rows)


def table1(run):
    """The paper's Table 1 for our meshes: vertices, faces, octree faces."""
    meshes = run.meshes()
    if not meshes:
        return None
    header = ["mesh", "vertices", "faces (file)", "triangles", "octree faces",
              "octree faces / triangles", "octree nodes", "depth", "linear bytes",
              "hash bytes"]
    rows = []
    for m in meshes:
        rs = [r for r in run.rows if r["scene"] == m]
        base = rs[0]
        tree = next((r for r in rs if r["octree_faces"] is not None), None)
        lin = next((r for r in rs if r["layout"] == "linear" and r["layout_bytes"]), None)
        hsh = next((r for r in rs if r["layout"] == "hash" and r["layout_bytes"]), None)
        tris = base["primitives"] or 0
        rows.append([
            m, "{:,}".format(base["vertices"] or 0), "{:,}".format(base["faces"] or 0),
            "{:,}".format(tris),
            "{:,}".format(tree["octree_faces"]) if tree else "-",
            "%.2f" % (tree["octree_faces"] / tris) if tree and tris else "-",
            "{:,}".format(tree["octree_nodes"]) if tree else "-",
            tree["octree_depth"] if tree else "-",
            bd.human_bytes(lin["layout_bytes"]) if lin else "-",
            bd.human_bytes(hsh["layout_bytes"]) if hsh else "-",
        ])
    return table(header, rows)


def memory_table(run):
    sizes = run.cloud_sizes()
    if not sizes:
        return None
    rows = []
    for n in sizes:
        rs = [r for r in run.rows if r["scene_type"] == "cloud" and r["n"] == n]
        tree = next((r for r in rs if r["octree_nodes"] is not None), None)
        cells = []
        for layout in run.octrees():
            r = next((r for r in rs if r["layout"] == layout and r["layout_bytes"]), None)
            s = next((r for r in rs if r["layout"] == layout and r["status"] == "skipped"), None)
            cells.append(bd.human_bytes(r["layout_bytes"]) if r else
                         ("*skipped*" if s else "-"))
        rows.append([bd.human_count(n), tree["octree_depth"] if tree else "-",
                     "{:,}".format(tree["octree_nodes"]) if tree else "-"] + cells +
                    [bd.human_bytes(16 * (rs[0]["primitives"] or 0))])
    return table(["N", "depth", "octree nodes"] + list(run.octrees()) + ["spheres"], rows)


def layouts_vs_reference_table(run, backend):
    """Every octree layout of the run against Embree (time) and the linear layout (bytes),
    per scene: the targets of layouts beyond the paper are ratios, read off here."""
    if backend != "cpu" or not run.has_embree() or len(run.octrees()) < 2:
        return None
    scenes = []
    for r in run.rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    octs = list(run.octrees())
    rows = []
    for sc in scenes:
        e = run.find(sc, bd.EMBREE, "embree")
        lin = run.find(sc, "linear", backend)
        line = [sc]
        for layout in octs:
            r = run.find(sc, layout, backend)
            ok = r and r["status"] == "ok" and e and e["status"] == "ok"
            line.append(fmt_ratio(r["frame_s_median"] / e["frame_s_median"]) if ok else "-")
        for layout in octs:
            if layout == "linear":
                continue
            r = run.find(sc, layout, backend)
            ok = r and lin and r["layout_bytes"] and lin["layout_bytes"]
            q = lin["layout_bytes"] / r["layout_bytes"] if ok else None
            line.append(("1/%.0f" if q >= 10 else "1/%.2g") % q if ok else "-")
        rows.append(line)
    header = ["scene"] + ["%s ×Embree" % l for l in octs] + [
        "%s bytes / linear" % l for l in octs if l != "linear"]
    return table(header, rows)


def cost_table(run, backend):
    sizes = run.cloud_sizes()
    rows = []
    for n in sizes:
        line = [bd.human_count(n)]
        for layout in run.layouts():
            r = run.cloud_row(n, layout, backend)
            if r and r["status"] == "ok":
                line.append("%.1f / %.1f" % (r["boxes_per_pixel"] or 0, r["prims_per_pixel"]))
            else:
                line.append("-")
        rows.append(line)
    if not rows:
        return None
    return table(["N"] + ["%s boxes / prims" % l for l in run.layouts()], rows)


def build_table(run, backend):
    rows = []
    for r in run.rows:
        if r["backend"] != backend or r["layout"] not in run.octrees() or r["tree_build_s"] is None:
            continue
        rows.append([r["scene"], r["layout"], "%.3f" % r["tree_build_s"],
                     "%.3f" % r["convert_s"] if r["convert_s"] is not None else "-",
                     r["status"]])
    if not rows:
        return None
    return table(["scene", "layout", "octree build s", "conversion s", "status"], rows)


def skipped_list(run):
    out = []
    for r in run.rows:
        if r["status"] != "ok":
            out.append("- `%s` %s on %s: **%s**: %s" % (r["scene"], r["layout"], r["backend"],
                                                       r["status"], r["reason"]))
    return out


def micro_table(run):
    if not run.micro:
        return None
    rows = []
    for b in run.micro.get("benchmarks", []):
        if b.get("run_type") == "aggregate":
            continue
        unit = b.get("time_unit", "ns")
        extra = ", ".join("%s=%s" % (k, ("%.3g" % b[k]) if isinstance(b[k], float) else b[k])
                          for k in ("hit_rate", "found_rate", "buckets_m", "max_bucket")
                          if k in b)
        rows.append([b["name"], "%.2f %s" % (b["cpu_time"], unit),
                     "%.0f M/s" % (b.get("items_per_second", 0) / 1e6), b.get("label", ""),
                     extra])
    return table(["benchmark", "CPU time per op", "ops/s", "label", "counters"], rows)


# --- the page ------------------------------------------------------------------------------


def machine_lines(run):
    m, c = run.machine, run.config
    build = m.get("build", {})
    lines = [
        "- CPU: **%s**, %s logical cores, %s OpenMP threads, %s memory" %
        (m.get("cpu_model", "?"), m.get("logical_cores", "?"), m.get("omp_threads", "?"),
         bd.human_bytes(m.get("memory_bytes"))),
        "- OS: %s; compiler: %s; optimised build: %s (NDEBUG: %s); CUDA in the build: %s" %
        (m.get("os", "?"), m.get("compiler", "?"), build.get("optimized", "?"),
         build.get("ndebug", "?"), build.get("cuda", "?")),
        "- Embree %s (reference)" % m.get("embree_version", "?"),
    ]
    loads = [m.get("load_average_start"), m.get("load_average_end")]
    if any(loads):
        lines.append("- Load average (1, 5, 15 min) at the start: %s; at the end: %s" %
                     tuple(", ".join("%.2f" % x for x in l) if l else "-" for l in loads))
        # The load at the end includes the sweep's own threads, busy for its last minute; only
        # what is beyond them is other work. The load at the start lags: it still holds the
        # minute before the sweep (a build just finished, say), so it is shown, not judged.
        cores = m.get("logical_cores") or 1
        own = m.get("omp_threads") or cores
        end = loads[1]
        other = end[0] - own if end else None
        if other is not None and other > 0.25 * cores:
            lines.append("- **Warning:** the machine was busy with other work during the run "
                         "(1-minute load %.2f at the end, %d of it the sweep's own threads, on "
                         "%d cores); timings, small frames above all, are noisy. Rerun on an "
                         "idle machine for numbers to quote." % (end[0], own, cores))
    if m.get("cuda_device"):
        lines.append("- GPU: **%s**" % m["cuda_device"])
    size = c.get("size", ["?", "?"])
    lines += [
        "- Run: %s; %sx%s pixels, one primary and at most one shadow ray per pixel; "
        "%s warm-up frame(s), median of %s timed frames (min–max in brackets); at most "
        "%s s per case (fewer frames, or skipped, when the estimate is longer)" %
        (m.get("date_utc", "?"), size[0], size[1], c.get("warmup", "?"), c.get("repeats", "?"),
         c.get("max_seconds", "?")),
        "- Octrees: grid clouds split down to the grid depth with at most %s sphere per leaf "
        "(the paper's clouds: one point per deepest cell); meshes max depth %s, split above %s "
        "triangles; hash buckets of %s slots; linear layouts above %s are refused (skipped)" %
        (c.get("cloud_octree", {}).get("max_prims", "?"),
         c.get("mesh_octree", {}).get("max_depth", "?"),
         c.get("mesh_octree", {}).get("max_prims", "?"), c.get("hash_slots", "?"),
         bd.human_bytes(c.get("linear_budget_bytes"))),
        "- Results: `%s/bench.csv`, `%s/bench.json`" % (run.folder, run.folder),
    ]
    return lines


def run_section(run, doc_dir, figures, title):
    out = ["## " + title, ""]
    if run.config.get("quick"):
        out += ["> **Smoke-test data.** This run used `octrace bench --quick` (tiny images, "
                "three small clouds, two meshes). Its numbers show the page's format, not "
                "the paper's experiment: regenerate from a full sweep (see the end of this "
                "page).", ""]
    if not run.complete:
        out += ["> **Incomplete run**: bench.json says the sweep did not finish; the tables "
                "hold the cases measured so far.", ""]
    out += ["### Machine and method", ""] + machine_lines(run) + [""]

    def fig(name, caption):
        if name in figures:
            out.extend(["![%s](%s)" % (caption, rel(figures[name], doc_dir)), ""])

    for backend in run.backends():
        b = backend.upper() if backend == "cuda" else "CPU (OpenMP)"
        out += ["### The paper's claims, checked (%s)" % b, "", claims_section(run, backend), ""]
        out += ["### Grid clouds (%s)" % b, ""]
        fig("clouds_time_paper_" + backend, "frame time vs N, the paper's axes")
        fig("clouds_time_loglog_" + backend, "frame time vs N, log-log")
        fig("crossover_" + backend, "exhaustive vs octree with the crossover")
        t = clouds_table(run, backend)
        if t:
            out += ["Frame time in ms: median (min–max). ×Embree: our frame time over "
                    "Embree's on the same rays, same shading.", "", t, ""]
        t = cost_table(run, backend)
        if t:
            out += ["Work per pixel (primary + shadow ray): boxes tested / primitives "
                    "tested.", "", t, ""]
        fig("cost_" + backend, "traversal cost per pixel")
        out += ["### Meshes (%s)" % b, ""]
        fig("meshes_" + backend, "mesh comparison")
        t = meshes_table(run, backend)
        if t:
            out += [t, ""]
        t = layouts_vs_reference_table(run, backend)
        if t:
            out += ["### Every layout against Embree and the linear layout (%s)" % b, "",
                    "Frame time over Embree's (same rays, same shading, same run), and layout "
                    "bytes (nodes and leaf index) over the linear layout's.", "", t, ""]
        t = build_table(run, backend)
        if t and backend == "cpu":
            out += ["<details><summary>Build times (host builder)</summary>", "",
                    t, "", "</details>", ""]

    t = table1(run)
    if t:
        out += ["### Table 1: our meshes", "",
                "As the paper's Table 1: vertices and faces as read from the file, and the "
                "octree faces, the sum of the leaves' primitive lists (a triangle crossing "
                "leaves is counted once per leaf).", "", t, ""]
    out += ["### Memory", ""]
    fig("memory", "memory vs N")
    t = memory_table(run)
    if t:
        out += ["Layout bytes (node records of 48 B plus the 4 B leaf index entries) for the "
                "grid clouds; the linear layout holds every position of the complete tree, "
                "(8^(d+1) − 1)/7 nodes.", "", t, ""]
    t = micro_table(run)
    if t:
        out += ["### Micro-benchmarks (Google Benchmark, one core)", "", t, ""]
    sk = skipped_list(run)
    if sk:
        out += ["### Cases not measured", ""] + sk + [""]
    fewer = ["- `%s` %s on %s: %s" % (r["scene"], r["layout"], r["backend"], r["reason"])
             for r in run.rows if r["status"] == "ok" and r["reason"]]
    if fewer:
        out += ["### Cases measured with fewer frames", ""] + fewer + [""]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", nargs="+", help="results folders (bench.csv, bench.json)")
    ap.add_argument("--doc", default=os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                  "..", "docs", "RESULTS.md"))
    a = ap.parse_args()
    if plot is None:
        print("make_results.py: matplotlib is missing (%s); run with /usr/bin/python3 after "
              "apt-get install python3-matplotlib" % PLOT_ERROR, file=sys.stderr)
        return 1
    doc = os.path.normpath(a.doc)
    doc_dir = os.path.dirname(doc) or "."
    runs = [bd.Run(folder) for folder in a.results]

    out = ["# octrace results", "",
           "<!-- Generated by bench/make_results.py from %s; do not edit by hand. -->" %
           ", ".join("`%s`" % f for f in a.results), "",
           "The experiment of %s, section 6, repeated with octrace: generated grid clouds of N "
           "spheres (one per deepest octree cell) and real meshes, traced with one "
           "thread per pixel (primary ray, Phong shading, shadow ray) by exhaustive testing, "
           "the linear octree (complete array, children of p at 8p+1..8p+8) and the hash "
           "octree (Morton keys, h(k) = k mod m, fixed-size buckets). Embree traces the same "
           "rays as a modern reference. Every number below is read from the results files." %
           PAPER, ""]
    out += ["**The paper's claims** (checked per run below): (1) octrees beat exhaustive "
            "tracing as the scene grows, past a crossover; (2) the linear octree is faster "
            "than the hash octree but needs more memory; (3) exhaustive time doubles as the "
            "data doubles; (4) the linear octree's time doubles per 16× more data.", ""]
    for i, run in enumerate(runs):
        figures = plot.make_figures(run, os.path.join(run.folder, "figures"))
        kind = "GPU" if "cuda" in run.backends() else "CPU"
        where = run.machine.get("cuda_device") if kind == "GPU" else run.machine.get(
            "cpu_model", "?")
        out += run_section(run, doc_dir, figures, "%s results: %s" % (kind, where))
    if not any("cuda" in r.backends() for r in runs):
        out += ["## GPU results", "",
                "None yet: no session with a GPU has run the sweep. On a CUDA machine, "
                "`octrace bench` adds the cuda backend (CUDA events, warm-up, median of "
                "repeats) and the 4M and 16M clouds by default.", ""]
    out += ["## Reproducing", "", "```sh",
            "cmake -S . -B build && cmake --build build -j --target octrace octrace_micro",
            "build/octrace bench --out bench/results/cpu        # full sweep (see --help)",
            "build/octrace_micro --benchmark_out=bench/results/cpu/micro.json "
            "--benchmark_out_format=json",
            "/usr/bin/python3 bench/make_results.py bench/results/cpu [bench/results/gpu]",
            "```", ""]
    with open(doc, "w") as f:
        f.write("\n".join(out))
    print("wrote", doc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
