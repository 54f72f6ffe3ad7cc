#!/usr/bin/python3
"""Plot an accelbench results CSV as PNG figures.

Reads the tidy CSV written by the C harness (one row per scene, accelerator
with params, workload and thread count) and writes, for every scene:

  <scene>__mrays.png      Mrays/s per workload and accelerator, with min/max
                          error bars from trace_ms_min / trace_ms_max
  <scene>__tests.png      tests_per_ray per workload (plus steps_per_ray when
                          any accelerator reports steps); accelerators with
                          empty counter fields (e.g. embree) are left out
  <scene>__build_mem.png  build_ms and bytes_per_prim per accelerator

and once for the whole file:

  overview__ratio.png     geometric mean over workloads of ratio_vs_embree,
                          scene x accelerator (>1 = slower than Embree)

Scene names are made file-name safe (':' '/' etc. become '_'). A bar is
labelled "accel" when that accel has a single params string in the file,
else "accel[params]" (and "@<n>t" when several thread counts occur).
Rows with fewer fields than the header (an interrupted run) are skipped
with a warning. Exit status 2 for a missing file or missing columns.
"""
import argparse
import csv
import math
import os
import re
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402

REQUIRED = ("scene", "accel", "workload", "rays", "trace_ms", "mrays_per_s")
WORKLOAD_ORDER = ("primary", "shadow", "reflection", "diffuse", "random")
LOG_SPAN = 20.0      # use a log axis when max/min exceeds this
MAX_PARAMS = 24      # longest params string shown in a label
DPI = 110
PROG = "plot.py"


def fail(msg):
    """Print a one-line error and exit with status 2."""
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    sys.exit(2)


def num(value):
    """Parse a CSV field as float; empty or malformed fields give None."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def load_rows(path):
    """Read the CSV into a list of dicts, skipping short/long rows."""
    if not os.path.isfile(path):
        fail(f"{path}: no such file")
    with open(path, newline="", encoding="utf-8", errors="replace") as f:
        reader = csv.reader(f)
        header = [h.strip() for h in next(reader, [])]
        missing = [c for c in REQUIRED if c not in header]
        if missing:
            fail(f"{path}: missing required column(s): {', '.join(missing)}")
        rows = []
        for rec in reader:
            if not rec:
                continue
            if len(rec) != len(header):
                print(f"{PROG}: warning: {path}:{reader.line_num}: "
                      f"{len(rec)} fields, expected {len(header)}; row skipped",
                      file=sys.stderr)
                continue
            rows.append(dict(zip(header, rec)))
    return rows


def short_params(params):
    """Shorten a long params string for use in a legend label."""
    return params if len(params) <= MAX_PARAMS else params[:MAX_PARAMS - 1] + "…"


def config_labels(rows):
    """Map each (accel, params, threads) config to its display label."""
    params_of, threads_of = {}, {}
    for r in rows:
        params_of.setdefault(r["accel"], set()).add(r.get("params", ""))
        threads_of.setdefault((r["accel"], r.get("params", "")), set()).add(
            r.get("threads", ""))
    labels = {}
    for r in rows:
        key = config_key(r)
        accel, params, threads = key
        label = accel
        if len(params_of[accel]) > 1:
            label += f"[{short_params(params)}]"
        if len(threads_of[(accel, params)]) > 1:
            label += f"@{threads}t"
        labels.setdefault(key, label)
    return labels


def config_key(row):
    """The identity of one accelerator configuration."""
    return (row["accel"], row.get("params", ""), row.get("threads", ""))


def ordered(values, preferred=()):
    """Unique values, preferred ones first, the rest in first-seen order."""
    seen = list(dict.fromkeys(values))
    return [v for v in preferred if v in seen] + [v for v in seen if v not in preferred]


def safe_name(name):
    """Turn a scene name into a file-name-safe stem."""
    return re.sub(r"[^A-Za-z0-9.+-]+", "_", name).strip("._") or "scene"


def footer(fig, rows):
    """Small footer with machine/cpu, threads and git revision."""
    def uniq(col):
        return ", ".join(v for v in dict.fromkeys(r.get(col, "") for r in rows) if v) or "?"
    fig.text(0.01, 0.005, f"machine: {uniq('machine')} | cpu: {uniq('cpu')} | "
             f"threads: {uniq('threads')} | git: {uniq('git_rev')}",
             fontsize=7, color="0.35", ha="left", va="bottom")


def save(fig, path, written):
    """Lay out, write and close a figure; record the path."""
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    fig.savefig(path, dpi=DPI, metadata={"Software": None})
    plt.close(fig)
    written.append(path)


def maybe_log(ax, values):
    """Switch the y axis to log scale when positive values span > LOG_SPAN."""
    pos = [v for v in values if v is not None and v > 0]
    if pos and max(pos) / min(pos) > LOG_SPAN:
        ax.set_yscale("log")


def mrays_errors(row, mrays):
    """Lower/upper error bar lengths in Mrays/s from trace_ms_max/min."""
    rays, tmin, tmax = num(row.get("rays")), num(row.get("trace_ms_min")), num(row.get("trace_ms_max"))
    if not rays or not tmin or not tmax:
        return 0.0, 0.0
    return max(0.0, mrays - rays / tmax / 1000.0), max(0.0, rays / tmin / 1000.0 - mrays)


def grouped_bars(ax, table, workloads, configs, labels, errors=None):
    """Draw one bar group per workload, one bar per config; return values drawn."""
    width = 0.8 / max(1, len(configs))
    drawn = []
    for i, cfg in enumerate(configs):
        xs, ys, lo, hi = [], [], [], []
        for j, wl in enumerate(workloads):
            v = table.get((cfg, wl))
            if v is None:
                continue
            xs.append(j - 0.4 + width * (i + 0.5))
            ys.append(v)
            e = errors.get((cfg, wl), (0.0, 0.0)) if errors else (0.0, 0.0)
            lo.append(e[0])
            hi.append(e[1])
        drawn += ys
        ax.bar(xs, ys, width, label=labels[cfg], color=f"C{i % 10}",
               yerr=[lo, hi] if errors else None, capsize=2, error_kw={"lw": 0.8})
    ax.set_xticks(range(len(workloads)), workloads)
    ax.set_xlabel("workload")
    ax.grid(axis="y", alpha=0.3, which="both")
    maybe_log(ax, drawn)
    return drawn


def metric_table(rows, column):
    """{(config, workload): value} for one numeric column (first row wins)."""
    table = {}
    for r in rows:
        v = num(r.get(column))
        if v is not None:
            table.setdefault((config_key(r), r["workload"]), v)
    return table


def scene_title(scene, rows, what):
    """Figure title: what, scene and primitive count."""
    prims = next((r.get("prims") for r in rows if r.get("prims")), "?")
    return f"{what} — {scene} ({prims} prims)"


def plot_mrays(scene, rows, labels, workloads, configs, path, written):
    """Grouped Mrays/s bars with min/max error bars."""
    table, errors = {}, {}
    for r in rows:
        key = (config_key(r), r["workload"])
        v = num(r["mrays_per_s"])
        if v is None and num(r["rays"]) and num(r["trace_ms"]):
            v = num(r["rays"]) / num(r["trace_ms"]) / 1000.0
        if v is not None and key not in table:
            table[key], errors[key] = v, mrays_errors(r, v)
    fig, ax = plt.subplots(figsize=(max(7, 1.2 * len(workloads) * max(1, len(configs)) ** 0.5), 4.8))
    grouped_bars(ax, table, workloads, configs, labels, errors)
    ax.set_ylabel("throughput [Mrays/s]")
    ax.set_title(scene_title(scene, rows, "Ray throughput (median, min–max)"))
    ax.legend(fontsize=8, ncol=2)
    footer(fig, rows)
    save(fig, path, written)


def plot_tests(scene, rows, labels, workloads, configs, path, written):
    """tests_per_ray bars, plus steps_per_ray when any accel reports steps."""
    tests, steps = metric_table(rows, "tests_per_ray"), metric_table(rows, "steps_per_ray")
    with_tests = [c for c in configs if any(k[0] == c for k in tests)]
    if not with_tests:
        return
    show_steps = any(v > 0 for v in steps.values())
    fig, axes = plt.subplots(1, 2 if show_steps else 1, squeeze=False,
                             figsize=(13 if show_steps else 7, 4.8))
    ax = axes[0][0]
    grouped_bars(ax, tests, workloads, with_tests, labels)
    ax.set_ylabel("primitive tests per ray")
    ax.set_title(scene_title(scene, rows, "Intersection tests"))
    ax.legend(fontsize=8)
    if show_steps:
        ax = axes[0][1]
        grouped_bars(ax, steps, workloads, with_tests, labels)
        ax.set_ylabel("traversal steps per ray")
        ax.set_title(scene_title(scene, rows, "Traversal steps"))
        ax.legend(fontsize=8)
    footer(fig, rows)
    save(fig, path, written)


def plot_build_mem(scene, rows, labels, configs, path, written):
    """Two panels: build_ms and bytes_per_prim, one bar per config."""
    first = {}
    for r in rows:
        first.setdefault(config_key(r), r)
    fig, axes = plt.subplots(1, 2, figsize=(max(9, 1.1 * len(configs) + 4), 4.8))
    for ax, col, ylabel, what in ((axes[0], "build_ms", "build time [ms]", "Build time"),
                                  (axes[1], "bytes_per_prim", "memory [bytes/prim]", "Memory")):
        vals = [num(first[c].get(col)) for c in configs]
        xs = range(len(configs))
        bars = ax.bar(xs, [v or 0 for v in vals], color=[f"C{i % 10}" for i in xs])
        for b, c, v in zip(bars, configs, vals):
            b.set_label(labels[c])
            if v is not None:
                ax.annotate(f"{v:.3g}", (b.get_x() + b.get_width() / 2, v),
                            ha="center", va="bottom", fontsize=7)
        ax.set_xticks(list(xs), [labels[c] for c in configs], rotation=30, ha="right")
        ax.set_xlabel("accelerator")
        ax.set_ylabel(ylabel)
        ax.grid(axis="y", alpha=0.3, which="both")
        maybe_log(ax, vals)
        ax.set_title(scene_title(scene, rows, what))
    axes[1].legend(fontsize=8)
    footer(fig, rows)
    save(fig, path, written)


def geomean(values):
    """Geometric mean of positive values, None when there are none."""
    pos = [v for v in values if v and v > 0]
    return math.exp(sum(map(math.log, pos)) / len(pos)) if pos else None


def plot_overview(rows, labels, scenes, path, written):
    """Heat map of geometric-mean ratio_vs_embree, scene x accelerator."""
    configs = [c for c in ordered(config_key(r) for r in rows) if c[0] != "embree"]
    grid = [[geomean([num(r.get("ratio_vs_embree")) for r in rows
                      if r["scene"] == s and config_key(r) == c]) for c in configs]
            for s in scenes]
    vals = [v for line in grid for v in line if v]
    if not vals:
        return
    span = max(max(vals), 1 / min(vals), 1.01)
    fig, ax = plt.subplots(figsize=(max(6, 1.3 * len(configs) + 3), max(3, 0.6 * len(scenes) + 2.2)))
    im = ax.imshow([[v if v else float("nan") for v in line] for line in grid],
                   cmap="RdYlGn_r", norm=LogNorm(1 / span, span), aspect="auto")
    for i, line in enumerate(grid):
        for j, v in enumerate(line):
            text = f"{v:.2f}" if v else "n/a"
            dark = v and abs(math.log(v)) > 0.6 * math.log(span)
            ax.text(j, i, text, ha="center", va="center", fontsize=8,
                    color="white" if dark else "black")
    ax.set_xticks(range(len(configs)), [labels[c] for c in configs], rotation=30, ha="right")
    prims = {r["scene"]: r.get("prims", "?") for r in rows}
    ax.set_yticks(range(len(scenes)), [f"{s} ({prims[s]} prims)" for s in scenes])
    ax.set_xlabel("accelerator")
    ax.set_ylabel("scene")
    ax.set_title("trace time / Embree trace time (geo. mean over workloads; >1 = slower)")
    fig.colorbar(im, ax=ax, label="ratio vs Embree [×]")
    footer(fig, rows)
    save(fig, path, written)


def parse_args(argv):
    """Command-line interface."""
    p = argparse.ArgumentParser(
        prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=f"Required columns: {', '.join(REQUIRED)}. Prints the files written "
               "unless --quiet.")
    p.add_argument("csv", metavar="CSV", help="benchmark CSV written by the harness")
    p.add_argument("--out", metavar="DIR", help="output folder (default: the CSV's folder)")
    p.add_argument("--quiet", action="store_true", help="do not list the files written")
    return p.parse_args(argv)


def main(argv=None):
    """Load the CSV and write all plots."""
    args = parse_args(argv)
    rows = load_rows(args.csv)
    out = args.out or os.path.dirname(os.path.abspath(args.csv))
    os.makedirs(out, exist_ok=True)
    if not rows:
        print(f"{PROG}: warning: {args.csv}: no data rows, nothing plotted", file=sys.stderr)
        return 0
    labels = config_labels(rows)
    workloads = ordered((r["workload"] for r in rows), WORKLOAD_ORDER)
    scenes = ordered(r["scene"] for r in rows)
    written, stems = [], set()
    for scene in scenes:
        srows = [r for r in rows if r["scene"] == scene]
        stem = safe_name(scene)
        while stem in stems:
            stem += "_"
        stems.add(stem)
        wls = [w for w in workloads if any(r["workload"] == w for r in srows)]
        cfgs = ordered(config_key(r) for r in srows)
        base = os.path.join(out, stem)
        plot_mrays(scene, srows, labels, wls, cfgs, base + "__mrays.png", written)
        plot_tests(scene, srows, labels, wls, cfgs, base + "__tests.png", written)
        plot_build_mem(scene, srows, labels, cfgs, base + "__build_mem.png", written)
    plot_overview(rows, labels, scenes, os.path.join(out, "overview__ratio.png"), written)
    if not args.quiet:
        print("\n".join(written))
    return 0


if __name__ == "__main__":
    sys.exit(main())
