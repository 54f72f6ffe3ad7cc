#!/usr/bin/python3
"""Plot the CSV of `accelbench reproduce havran` as PNG figures.

Reads havran.csv (the run CSV's columns preceded by table, variant and
grid_res; one row per table, variant, scene and workload) and writes, next
to it (or in --out):

  havran_grids.png    time D1/D20 per scene, ours next to Havran and Sixta's
  havran_octrees.png  time against maximum depth per scene, O84-C and O84-A,
                      each over the scene's best O84-C, ours (solid) next to
                      Havran's (dashed)
  havran_across.png   every technique's time over the D = 20 grid's per
                      scene, ours next to theirs where they measured it
                      (log scale)

An image's time is the sum of its rows' trace_ms over workloads (primary,
shadow, reflection); every ratio between two of our measurements is the
ratio of their times over the Embree samples paired with each (embree_ms),
as in the printed tables. Their numbers come from
data/havran_figures.csv, which accelbench's report reads too. Only ratios
are plotted: their seconds and our milliseconds are not comparable. A table
missing from the CSV is skipped. Exit status 2 for a missing file or
missing columns.
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PROG = "plot_havran.py"
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot as common  # noqa: E402
import plot_reproduce  # noqa: E402
from plot_reproduce import REQUIRED, footer, images  # noqa: E402

common.PROG = PROG
save = common.save


def their_number(figs, table, row, quantity):
    """A figure of theirs as a float, or None when the file has none."""
    value = figs.get(table, {}).get(row, {}).get(quantity)
    return float(value) if value not in (None, "") else None


def scene_names(im):
    """The measured scenes in order, and their names in the figures file (spd:balls -> balls)."""
    scenes = list(dict.fromkeys(scene for _, scene in im))
    return scenes, [s.split(":")[1] if s.startswith("spd:") else s for s in scenes]


def relative(a, b):
    """a's time over b's through their Embree-paired ratios (as the printed tables), or None."""
    return a.vs_embree / b.vs_embree if a.vs_embree and b.vs_embree else None


def bars(ax, labels, series, title, ylabel):
    """Grouped bars: series is [(name, values, style)]; None values are left out."""
    width = 0.8 / len(series)
    for k, (name, values, hatch) in enumerate(series):
        xs = [i + (k - (len(series) - 1) / 2) * width for i in range(len(labels))]
        pts = [(x, v) for x, v in zip(xs, values) if v is not None]
        ax.bar([p[0] for p in pts], [p[1] for p in pts], width, label=name, color=f"C{k // 2 if hatch else k}",
               hatch="//" if hatch else None, alpha=0.6 if hatch else 1.0)
    ax.set_xticks(range(len(labels)))
    ax.set_xticklabels(labels, rotation=30, ha="right")
    ax.set_title(title)
    ax.set_ylabel(ylabel)


def plot_grids(rows, figs, path, written):
    """D1/D20 time per scene, ours and theirs."""
    im = images(rows, "grids")
    if not im:
        return
    scenes, names = scene_names(im)
    ours = [relative(im[("D1", s)], im[("D20", s)]) for s in scenes]
    theirs = []
    for n in names:
        d1, d20 = their_number(figs, "grids", n, "d1_trace"), their_number(figs, "grids", n, "d20_trace")
        theirs.append(d1 / d20 if d1 and d20 else None)
    fig, ax = plt.subplots(figsize=(9, 4.8))
    bars(ax, scenes, [("ours", ours, False), ("Havran & Sixta (RTN 12(1))", theirs, True)],
         "Uniform grid: time at D = 1 over time at D = 20 (above 1: D = 20 faster)", "time D1 / time D20")
    ax.axhline(1.0, color="0.3", lw=0.8)
    ax.legend()
    footer(fig, rows)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    save(fig, path, written)


def plot_octrees(rows, figs, path, written):
    """Time against maximum depth, O84-C and O84-A, over the scene's best O84-C."""
    im = images(rows, "octrees")
    if not im:
        return
    scenes, names = scene_names(im)
    cols = 4
    fig, axes = plt.subplots((len(scenes) + cols - 1) // cols, cols, figsize=(14, 7), squeeze=False)
    for i, (scene, name) in enumerate(zip(scenes, names)):
        ax = axes[i // cols][i % cols]
        for k, kind in enumerate(("O84-C", "O84-A")):
            pts = sorted((int(v.split("@")[1]), img.vs_embree) for (v, s), img in im.items()
                         if s == scene and v.startswith(kind))
            best_c = min(img.vs_embree for (v, s), img in im.items() if s == scene and v.startswith("O84-C"))
            ax.plot([p[0] for p in pts], [p[1] / best_c for p in pts], marker="o", color=f"C{k}", label=f"{kind} ours")
            key = "o84c" if kind == "O84-C" else "o84a"
            theirs = [(d, their_number(figs, "octrees", name, f"{key}_d{d}")) for d, _ in pts]
            their_c = [their_number(figs, "octrees", name, f"o84c_d{d}") for d, _ in pts]
            their_best = min(v for v in their_c if v) if any(their_c) else None
            if their_best:
                ax.plot([d for d, v in theirs if v], [v / their_best for d, v in theirs if v], marker="s", ls="--",
                        color=f"C{k}", alpha=0.6, label=f"{kind} Havran")
        ax.set_title(scene)
        ax.set_yscale("log")
        ax.set_xlabel("maximum depth")
        if i % cols == 0:
            ax.set_ylabel("time / best O84-C time")
    for j in range(len(scenes), axes.size):
        axes[j // cols][j % cols].axis("off")
    axes[0][0].legend(fontsize=7)
    fig.suptitle("Octrees: centre (O84-C) and cost-based (O84-A) subdivision by maximum depth; ours solid, "
                 "Havran's (RTN 12(2)) dashed")
    footer(fig, rows)
    fig.tight_layout(rect=(0, 0.03, 1, 0.95))
    save(fig, path, written)


def plot_across(rows, figs, path, written):
    """Every technique over D20 per scene (octrees at their best depth), ours and theirs."""
    tables = {}
    for table in ("grids", "octrees", "bsp"):
        tables.update(images(rows, table))
    if not any(v == "D20" for v, _ in tables):
        return
    scenes, names = scene_names(tables)

    def best(scene, prefix):
        ms = [img.vs_embree for (v, s), img in tables.items() if s == scene and v.startswith(prefix)]
        return min(ms) if ms else None

    def their_best(name, key):
        vals = [their_number(figs, "octrees", name, f"{key}_d{d}") for d in range(0, 32)]
        vals = [v for v in vals if v]
        return min(vals) if vals else None

    series = []
    for tech, prefix, their in (("D1", "D1", "d1"), ("O84-C", "O84-C", "o84c"), ("O84-A", "O84-A", "o84a"),
                                ("BSP-seq", "BSP-seq", None), ("BSP-rec", "BSP-rec", None),
                                ("BSP-SAH", "BSP-SAH", None)):
        ours = []
        theirs = []
        for scene, name in zip(scenes, names):
            d20, mine = best(scene, "D20"), best(scene, prefix)
            ours.append(mine / d20 if mine and d20 else None)
            their_d20 = their_number(figs, "grids", name, "d20_trace")
            if their == "d1":
                v = their_number(figs, "grids", name, "d1_trace")
            else:
                v = their_best(name, their) if their else None
            theirs.append(v / their_d20 if v and their_d20 else None)
        series.append((tech, ours, theirs))
    fig, ax = plt.subplots(figsize=(14, 5.5))
    n = sum(2 if any(t) else 1 for _, _, t in series)
    width = 0.85 / n
    k = 0
    for c, (tech, ours, theirs) in enumerate(series):
        for vals, label, hatch in ((ours, f"{tech} ours", False), (theirs, f"{tech} Havran", True)):
            if hatch and not any(vals):
                continue
            xs = [i + (k - (n - 1) / 2) * width for i in range(len(scenes))]
            pts = [(x, v) for x, v in zip(xs, vals) if v]
            ax.bar([p[0] for p in pts], [p[1] for p in pts], width, color=f"C{c}", label=label,
                   hatch="//" if hatch else None, alpha=0.5 if hatch else 1.0)
            k += 1
    ax.axhline(1.0, color="0.3", lw=0.8)
    ax.set_yscale("log")
    ax.set_xticks(range(len(scenes)))
    ax.set_xticklabels(scenes, rotation=30, ha="right")
    ax.set_ylabel("time / time of the D = 20 grid")
    ax.set_title("Every technique against the D = 20 grid (octrees at their best depth; below 1: faster)")
    common.outside_legend(ax)
    footer(fig, rows)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    save(fig, path, written)


def main(argv=None):
    """Load the CSV and write all plots."""
    args = common.parse_args(argv, PROG, __doc__, REQUIRED, "havran.csv written by accelbench reproduce havran")
    rows, out = common.rows_and_folder(args, REQUIRED)
    if not rows:
        return 0
    figs = plot_reproduce.load_figures("havran")
    written = []
    plot_grids(rows, figs, os.path.join(out, "havran_grids.png"), written)
    plot_octrees(rows, figs, os.path.join(out, "havran_octrees.png"), written)
    plot_across(rows, figs, os.path.join(out, "havran_across.png"), written)
    if not args.quiet:
        print("\n".join(written))
    return 0


if __name__ == "__main__":
    sys.exit(main())
