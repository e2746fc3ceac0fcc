#!/usr/bin/python3
"""Turns `octrace bench` results into PNG figures matching the paper's (Barboza & Clua 2011).

Usage:  /usr/bin/python3 bench/plot.py RESULTS_DIR [--out FIG_DIR]

Reads RESULTS_DIR/bench.csv (and bench.json for the machine); writes into FIG_DIR (default
RESULTS_DIR/figures), one set per backend that ran our layouts (cpu, cuda):
  clouds_time_paper_<b>.png   frame time (ms) vs points, linear axes, the paper's 1k..64k range
  clouds_time_loglog_<b>.png  the same, log-log, every size, min..max bars, N and N^0.25 guides
  crossover_<b>.png           exhaustive vs the two octrees, the crossover marked
  meshes_<b>.png              the mesh comparison as grouped bars (log scale)
  memory.png                  layout bytes vs points (linear and hash)
  cost_<b>.png                boxes tested and primitives tested per pixel vs points
Run with Debian's python3 (/usr/bin/python3), which has python3-matplotlib.
"""

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_data as bd  # noqa: E402

STYLE = {
    "exhaustive": dict(color="#c0392b", marker="s"),
    "linear": dict(color="#2471a3", marker="o"),
    "hash": dict(color="#229954", marker="^"),
    bd.EMBREE: dict(color="#7f8c8d", marker="D", linestyle="--"),
}
LABEL = {"exhaustive": "exhaustive", "linear": "linear octree", "hash": "hash octree",
         bd.EMBREE: "Embree BVH (reference)"}
BASE_STYLES = set(STYLE)
PAPER_MAX_N = 64000
EXTRA_STYLES = [dict(color="#8e44ad", marker="v"), dict(color="#d68910", marker="P"),
                dict(color="#17a589", marker="X")]


def label_of(layout):
    """The legend name of a layout; layouts beyond this table (read from the results) by name."""
    return LABEL.get(layout, layout)


def style_of(layout):
    """The marker and colour of a layout; others get the next spare style, stable per name."""
    if layout not in STYLE:
        STYLE[layout] = EXTRA_STYLES[len([k for k in STYLE if k not in BASE_STYLES]) %
                                     len(EXTRA_STYLES)]
    return STYLE[layout]


def machine_note(run, backend):
    m = run.machine
    if backend == "cuda" and m.get("cuda_device"):
        return "GPU: %s" % m["cuda_device"]
    cpu = m.get("cpu_model", "unknown CPU")
    return "CPU: %s, %s OpenMP threads" % (cpu, m.get("omp_threads", "?"))


def size_note(run):
    size = run.config.get("size")
    if size:
        return "%dx%d, primary + shadow rays" % (size[0], size[1])
    return ""


def finish(fig, ax, run, backend, path, title):
    ax.set_title(title, fontsize=11)
    fig.text(0.99, 0.01, "%s; %s" % (machine_note(run, backend), size_note(run)),
             ha="right", va="bottom", fontsize=7, color="#555555")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def layouts_for(run, backend):
    out = [l for l in run.layouts() if bd.series(run, l, backend)]
    if backend == "cpu" and bd.series(run, bd.EMBREE, "embree"):
        out.append(bd.EMBREE)
    return out


def backend_of(layout, backend):
    return "embree" if layout == bd.EMBREE else backend


def plot_time_paper(run, backend, path):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    drawn = False
    for layout in layouts_for(run, backend):
        pts = [p for p in bd.series(run, layout, backend_of(layout, backend))
               if p[0] <= PAPER_MAX_N]
        if not pts:
            continue
        drawn = True
        ax.plot([p[0] / 1000 for p in pts], [p[1] * 1e3 for p in pts], label=label_of(layout),
                **style_of(layout))
    if not drawn:
        plt.close(fig)
        return False
    ax.set_xlabel("points (thousands)")
    ax.set_ylabel("frame time (ms)")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    finish(fig, ax, run, backend, path,
           "Grid clouds, the paper's axes (%s backend, N <= 64k)" % backend)
    return True


def plot_time_loglog(run, backend, path):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    drawn = False
    for layout in layouts_for(run, backend):
        pts = bd.series(run, layout, backend_of(layout, backend))
        if not pts:
            continue
        drawn = True
        xs = [p[0] for p in pts]
        ys = [p[1] * 1e3 for p in pts]
        lo = [(p[1] - p[2]) * 1e3 for p in pts]
        hi = [(p[3] - p[1]) * 1e3 for p in pts]
        style = dict(style_of(layout))
        ax.errorbar(xs, ys, yerr=[lo, hi], label=label_of(layout), capsize=2, **style)
    if not drawn:
        plt.close(fig)
        return False
    # Guides through the first exhaustive and linear points: the paper's two scaling claims.
    for layout, slope, text in (("exhaustive", 1.0, "~N (doubles per 2x)"),
                                ("linear", 0.25, "~N^0.25 (doubles per 16x)")):
        pts = bd.series(run, layout, backend)
        if len(pts) >= 2:
            n0, t0 = pts[0][0], pts[0][1] * 1e3
            n1 = pts[-1][0]
            ax.plot([n0, n1], [t0, t0 * (n1 / n0) ** slope], color=style_of(layout)["color"],
                    linestyle=":", linewidth=1, label=text)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("points N")
    ax.set_ylabel("frame time (ms), median, bars min..max")
    finish(fig, ax, run, backend, path, "Grid clouds, log-log (%s backend)" % backend)
    return True


def plot_crossover(run, backend, path):
    exh = bd.series(run, "exhaustive", backend)
    if not exh:
        return False
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.plot([p[0] for p in exh], [p[1] * 1e3 for p in exh], label=LABEL["exhaustive"],
            **STYLE["exhaustive"])
    notes = []
    for layout in run.octrees():
        pts = bd.series(run, layout, backend)
        if not pts:
            continue
        ax.plot([p[0] for p in pts], [p[1] * 1e3 for p in pts], label=label_of(layout),
                **style_of(layout))
        c = bd.crossover([(p[0], p[1]) for p in exh], [(p[0], p[1]) for p in pts])
        if c["kind"] == "between":
            ax.axvline(c["n"], color=style_of(layout)["color"], linestyle="--", linewidth=1)
            notes.append("%s: crossover N ~ %.0f" % (layout, c["n"]))
        elif c["kind"] == "below":
            ax.axvline(c["n"], color=style_of(layout)["color"], linestyle="--", linewidth=1)
            notes.append("%s faster already at N = %s" % (layout, bd.human_count(c["n"])))
        elif c["kind"] == "none":
            notes.append("%s never faster up to N = %s" % (layout, bd.human_count(c["n"])))
    if notes:
        ax.text(0.02, 0.98, "\n".join(notes), transform=ax.transAxes, va="top", fontsize=8,
                bbox=dict(facecolor="white", alpha=0.8, edgecolor="#cccccc"))
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("points N")
    ax.set_ylabel("frame time (ms)")
    finish(fig, ax, run, backend, path,
           "Exhaustive vs octree, crossover marked (%s backend)" % backend)
    return True


def plot_meshes(run, backend, path):
    meshes = run.meshes()
    if not meshes:
        return False
    layouts = [l for l in run.layouts() if run.select(scene_type="mesh", layout=l, backend=backend)]
    if backend == "cpu" and run.has_embree():
        layouts.append(bd.EMBREE)
    if not layouts:
        return False
    fig, ax = plt.subplots(figsize=(max(6.4, 1.0 * len(meshes) + 2), 4.6))
    width = 0.8 / len(layouts)
    for i, layout in enumerate(layouts):
        xs, ys, skipped = [], [], []
        for j, mesh in enumerate(meshes):
            r = run.find(mesh, layout, backend_of(layout, backend))
            x = j - 0.4 + width * (i + 0.5)
            if r and r["status"] == "ok":
                xs.append(x)
                ys.append(r["frame_s_median"] * 1e3)
            elif r:
                skipped.append(x)
        style = style_of(layout)
        ax.bar(xs, ys, width=width, color=style["color"], label=label_of(layout),
               alpha=0.6 if layout == bd.EMBREE else 0.9)
        # A skipped case: its name at the foot of the empty slot (x in data, y in axes units).
        for x in skipped:
            ax.text(x, 0.02, "skipped", rotation=90, ha="center", va="bottom", fontsize=6,
                    color=style["color"], transform=ax.get_xaxis_transform())
    ax.set_yscale("log")
    labels = []
    for mesh in meshes:
        r = next((r for r in run.rows if r["scene"] == mesh), None)
        labels.append("%s\n%s tris" % (mesh.rsplit(".", 1)[0], bd.human_count(r["primitives"])))
    ax.set_xticks(range(len(meshes)))
    ax.set_xticklabels(labels, fontsize=7, rotation=30, ha="right")
    ax.set_ylabel("frame time (ms), log scale; missing bar = skipped")
    finish(fig, ax, run, backend, path, "Meshes (%s backend)" % backend)
    return True


def plot_memory(run, path):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    drawn = False
    for layout in run.octrees():
        # Bytes do not depend on the backend: take any row that built the layout.
        pts = {}
        for r in run.select(scene_type="cloud", layout=layout):
            if r["layout_bytes"]:
                pts[r["n"]] = r["layout_bytes"]
        if not pts:
            continue
        drawn = True
        ns = sorted(pts)
        ax.plot(ns, [pts[n] / 2**20 for n in ns], label=label_of(layout), **style_of(layout))
    if not drawn:
        plt.close(fig)
        return False
    prims = sorted({(r["n"], r["primitives"]) for r in run.select(scene_type="cloud")})
    if prims:
        ax.plot([n for n, _ in prims], [p * 16 / 2**20 for _, p in prims], color="#999999",
                linestyle=":", label="the spheres themselves (16 B each)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("points N")
    ax.set_ylabel("layout memory (MiB): nodes + leaf index array")
    finish(fig, ax, run, "cpu", path, "Memory vs N (grid clouds)")
    return True


def plot_cost(run, backend, path):
    fig, axes = plt.subplots(1, 2, figsize=(9.6, 4.0))
    drawn = False
    for key, ax, title in (("boxes_per_pixel", axes[0], "boxes tested per pixel"),
                           ("prims_per_pixel", axes[1], "primitives tested per pixel")):
        for layout in run.layouts():
            rows = sorted(run.select(scene_type="cloud", layout=layout, backend=backend,
                                     status="ok"), key=lambda r: r["n"])
            pts = [(r["n"], r[key]) for r in rows if r[key]]
            if not pts:
                continue
            drawn = True
            ax.plot([p[0] for p in pts], [p[1] for p in pts], label=label_of(layout),
                    **style_of(layout))
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("points N")
        ax.set_title(title + " (primary + shadow ray)", fontsize=10)
        ax.grid(True, which="both", alpha=0.3)
        if ax.lines:
            ax.legend(fontsize=8)
    if not drawn:
        plt.close(fig)
        return False
    fig.text(0.99, 0.01, machine_note(run, backend), ha="right", va="bottom", fontsize=7,
             color="#555555")
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def make_figures(run, out_dir):
    """Writes every figure the run's data supports; returns {name: path}."""
    os.makedirs(out_dir, exist_ok=True)
    made = {}

    def attempt(name, fn, *args):
        path = os.path.join(out_dir, name + ".png")
        if fn(*args, path):
            made[name] = path

    for b in run.backends():
        attempt("clouds_time_paper_" + b, plot_time_paper, run, b)
        attempt("clouds_time_loglog_" + b, plot_time_loglog, run, b)
        attempt("crossover_" + b, plot_crossover, run, b)
        attempt("meshes_" + b, plot_meshes, run, b)
        attempt("cost_" + b, plot_cost, run, b)
    attempt("memory", plot_memory, run)
    return made


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("results", help="folder with bench.csv (and bench.json)")
    ap.add_argument("--out", help="figure folder (default RESULTS/figures)")
    a = ap.parse_args()
    run = bd.Run(a.results)
    made = make_figures(run, a.out or os.path.join(a.results, "figures"))
    for name, path in made.items():
        print("wrote", path)
    if not made:
        print("plot.py: no measured cases to plot in", a.results, file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
