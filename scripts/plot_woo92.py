#!/usr/bin/python3
"""Plot the CSV of `accelbench reproduce woo92` as PNG figures.

Reads woo92.csv (the run CSV's columns preceded by table, variant and
grid_res; one row per table, variant, scene and workload) and writes, next
to it (or in --out):

  woo92_table1.png    Table 1: trace time and tests/ray vs grid resolution,
                      ray box vs raw traversal (min-max error bars)
  woo92_table2.png    Table 2: new time / old time per image, ours next to Woo's
  woo92_table3.png    Table 3: old / tri / new time vs samples per pixel, and
                      the % improvement next to Woo's
  woo92_table4.png    Table 4: time and grid memory vs grid resolution
  woo92_ablation.png  the ablation: % time saved vs old after each switch,
                      one line per image

An image's time is the sum of its rows' trace_ms over workloads (primary +
reflection), as in the printed tables. Woo's numbers come from
data/woo92_figures.csv, which accelbench's report reads too. A table missing
from the CSV is skipped. Exit status 2 for a missing file or missing columns.
"""
import os
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PROG = "plot_woo92.py"

# The CSV reader, number parsing, errors and figure saving are plot.py's.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot as common  # noqa: E402
from plot_reproduce import REQUIRED, figure_value, footer, images  # noqa: E402
import plot_reproduce  # noqa: E402

common.PROG = PROG
fail, num, save = common.fail, common.num, common.save

ABL_ORDER = ("old", "+woo90", "+mtf=hit", "+mtf=almost", "+dynbox", "+voxbox", "+beta=0.75",
             "+tclip", "+eyeorigin", "+rayid=twopass")


def woo_table2(figs):
    """{image: (old seconds, new seconds)} of Woo's Table 2, in his row order."""
    return {image: (figure_value(q["old_time"]), figure_value(q["new_time"])) for image, q in figs["table2"].items()}


def woo_table3(figs, quantity):
    """One %Improve column of Woo's Table 3 (tri_improve or new_improve), in his row order."""
    return tuple(figure_value(q[quantity]) for q in figs["table3"].values())


def plot_table1(rows, path, written):
    """Time and tests/ray vs grid resolution, ray box vs raw."""
    im = images(rows, "table1")
    if not im:
        return
    series = {}
    for (variant, _), img in im.items():
        kind, _, res = variant.partition("@")
        series.setdefault(kind, []).append((int(res), img))
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    labels = {"raybox": "Ray Box (grid-raybox, raybox only)", "raw": "Raw Traversal (grid)"}
    for i, kind in enumerate(("raybox", "raw")):
        pts = sorted(series.get(kind, []), key=lambda p: p[0])
        if not pts:
            continue
        xs = [p[0] for p in pts]
        errs = [p[1].err() for p in pts]
        axes[0].errorbar(xs, [p[1].ms for p in pts], yerr=[[e[0] for e in errs], [e[1] for e in errs]],
                         marker="o", color=f"C{i}", label=labels[kind], capsize=3)
        axes[1].plot(xs, [p[1].tests for p in pts], marker="o", color=f"C{i}",
                     label=f"{labels[kind]}: primitive tests")
        if kind == "raybox":
            axes[1].plot(xs, [p[1].boxes for p in pts], marker="s", ls="--", color=f"C{i}",
                         label=f"{labels[kind]}: box tests")
    first = next(iter(im.values()))
    img_res = first.rows[0].get("res", "?")
    axes[0].set_title(f"Table 1: trace time — {first.scene}, {img_res} primary")
    axes[0].set_xlabel("grid resolution (N³)")
    axes[0].set_ylabel("trace time [ms] (median, min–max)")
    axes[1].set_title("Table 1: tests per ray")
    axes[1].set_xlabel("grid resolution (N³)")
    axes[1].set_ylabel("per ray")
    axes[1].set_yscale("log")
    for ax in axes:
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=8)
    footer(fig, rows)
    save(fig, path, written)


def plot_table2(rows, figs, path, written):
    """New / old time per image, ours next to Woo's."""
    im = images(rows, "table2")
    scenes = list(dict.fromkeys(s for (_, s) in im))
    if not scenes:
        return
    woo_t2 = woo_table2(figs)
    names = list(woo_t2)
    fig, ax = plt.subplots(figsize=(8, 4.8))
    xs = range(len(scenes))
    ours = [im[("new", s)].ms / im[("old", s)].ms if ("new", s) in im and ("old", s) in im else 0 for s in scenes]
    woo = [woo_t2[names[i]][1] / woo_t2[names[i]][0] if i < len(names) else 0 for i in xs]
    b1 = ax.bar([x - 0.2 for x in xs], ours, 0.4, color="C0", label="ours: new / old")
    b2 = ax.bar([x + 0.2 for x in xs], woo, 0.4, color="C7", label="Woo 1992: new / old")
    for bars in (b1, b2):
        for b in bars:
            ax.annotate(f"{b.get_height():.2f}", (b.get_x() + b.get_width() / 2, b.get_height()),
                        ha="center", va="bottom", fontsize=8)
    ax.axhline(1.0, color="0.3", lw=0.8)
    ax.set_ylim(0, 1.2 * max([1.0] + ours + woo))
    ax.set_xticks(list(xs), [f"{names[i] if i < len(names) else ''}\n{s}" for i, s in enumerate(scenes)])
    ax.set_ylabel("time relative to old (< 1: new is faster)")
    ax.set_title("Table 2: all of Woo's switches (new) vs Snyder-Barr alone (old)")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=8)
    footer(fig, rows)
    save(fig, path, written)


def plot_table3(rows, figs, path, written):
    """Old/tri/new time vs spp, and % improvement vs Woo's."""
    im = images(rows, "table3")
    if not im:
        return
    series = {}
    for (variant, _), img in im.items():
        kind, _, spp = variant.partition("@spp")
        series.setdefault(kind, {})[int(spp)] = img
    spps = sorted(series.get("old", {}))
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    for i, kind in enumerate(("old", "tri", "new")):
        pts = [series.get(kind, {}).get(s) for s in spps]
        if any(p is None for p in pts):
            continue
        errs = [p.err() for p in pts]
        axes[0].errorbar(spps, [p.ms for p in pts], yerr=[[e[0] for e in errs], [e[1] for e in errs]],
                         marker="o", color=f"C{i}", label=kind, capsize=3)
        if kind != "old":
            imp = [100 * (series["old"][s].ms - p.ms) / series["old"][s].ms for s, p in zip(spps, pts)]
            axes[1].plot(spps, imp, marker="o", color=f"C{i}", label=f"ours: {kind}")
            woo = woo_table3(figs, f"{kind}_improve")
            axes[1].plot(spps[:len(woo)], woo[:len(spps)], marker="x", ls="--", color=f"C{i}", alpha=0.6,
                         label=f"Woo 1992: {kind}")
    scene = next(iter(im.values())).scene
    axes[0].set_title(f"Table 3: trace time vs samples — {scene}")
    axes[0].set_ylabel("trace time [ms] (primary + reflection)")
    axes[1].set_title("Table 3: % time saved vs old")
    axes[1].set_ylabel("% improve")
    axes[1].axhline(0, color="0.3", lw=0.8)
    for ax in axes:
        ax.set_xlabel("samples per pixel")
        ax.set_xticks(spps)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    footer(fig, rows)
    save(fig, path, written)


def plot_table4(rows, path, written):
    """Time and grid memory vs resolution."""
    im = images(rows, "table4")
    if not im:
        return
    imgs = list(im.values())
    labels = [("auto " if v.endswith("@auto") else "") + img.grid for (v, _), img in im.items()]
    fig, ax = plt.subplots(figsize=(8, 4.8))
    xs = range(len(imgs))
    errs = [i.err() for i in imgs]
    ax.bar(list(xs), [i.ms for i in imgs], 0.6, color="C0", label="trace time [ms]",
           yerr=[[e[0] for e in errs], [e[1] for e in errs]], capsize=3)
    ax.set_ylabel("trace time [ms] (median, min–max)")
    ax2 = ax.twinx()
    ax2.plot(list(xs), [i.mem for i in imgs], marker="o", color="C3", label="grid memory [bytes]")
    ax2.set_ylabel("grid memory [bytes]")
    ax2.set_yscale("log")
    ax.set_xticks(list(xs), labels)
    ax.set_xlabel("grid resolution")
    ax.set_title(f"Table 4: subdivision — {imgs[0].scene}, new")
    ax.grid(axis="y", alpha=0.3)
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, fontsize=8, loc="upper center")
    footer(fig, rows)
    save(fig, path, written)


def plot_ablation(rows, path, written):
    """% time saved vs old after each cumulative switch, one line per image."""
    im = images(rows, "ablation")
    if not im:
        return
    scenes = list(dict.fromkeys(s for (_, s) in im))
    steps = [s for s in ABL_ORDER if any((s, sc) in im for sc in scenes)]
    steps += [v for v in dict.fromkeys(v for (v, _) in im) if v not in steps]
    fig, ax = plt.subplots(figsize=(11, 5))
    for i, sc in enumerate(scenes):
        old = im.get(("old", sc))
        if not old:
            continue
        ys = [100 * (old.ms - im[(s, sc)].ms) / old.ms if (s, sc) in im else float("nan") for s in steps]
        ax.plot(range(len(steps)), ys, marker="o", color=f"C{i}", label=f"{sc} (grid {old.grid})")
    ax.axhline(0, color="0.3", lw=0.8)
    ax.set_xticks(range(len(steps)), steps, rotation=30, ha="right")
    ax.set_ylabel("% time saved vs old (cumulative switches)")
    ax.set_xlabel("switch added (each row keeps the ones to its left)")
    ax.set_title("Ablation: Woo's switches added one at a time (primary + reflection)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    footer(fig, rows)
    save(fig, path, written)


def parse_args(argv):
    """Command-line interface: plot.py's, with this file's columns."""
    return common.parse_args(argv, PROG, __doc__, REQUIRED, "woo92.csv written by accelbench reproduce woo92")


def main(argv=None):
    """Load the CSV and write all plots."""
    args = parse_args(argv)
    rows, out = common.rows_and_folder(args, REQUIRED)
    if not rows:
        return 0
    figs = plot_reproduce.load_figures("woo92")
    written = []
    plot_table1(rows, os.path.join(out, "woo92_table1.png"), written)
    plot_table2(rows, figs, os.path.join(out, "woo92_table2.png"), written)
    plot_table3(rows, figs, os.path.join(out, "woo92_table3.png"), written)
    plot_table4(rows, os.path.join(out, "woo92_table4.png"), written)
    plot_ablation(rows, os.path.join(out, "woo92_ablation.png"), written)
    if not args.quiet:
        print("\n".join(written))
    return 0


if __name__ == "__main__":
    sys.exit(main())
