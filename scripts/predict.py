#!/usr/bin/python3
"""How well each structure's cost model predicts its measured work, from a run folder's matrix.csv.

Every accelerator with a cost model writes, from its built structure and
without tracing, predicted_tests_per_ray, predicted_box_tests_per_ray and
predicted_steps_per_ray (docs/csv.md; the models are on each docs/accels
page, "Cost model"). The models are stated for random lines (uniform over
the lines that meet the structure's root volume, walked whole); this
script says how far the measured counters of each workload are from them.

Per configuration (labelled as plot.py labels them), per counter and per
workload (and over all the run's workloads), over the cells with both a
prediction and a measured value above 0:
  cells           how many;
  rank corr.      Spearman's rank correlation of predicted and measured
                  across those cells (ties at their mean rank; blank under
                  3 cells or when either side is constant): does the model
                  order the scenes as the walks do;
  median |rel. error|  the median of |predicted - measured| / measured;
  measured/pred.  the median ratio: below 1 where the model's whole line
                  overcounts rays that stop at a hit or start inside.
Then, as Aila, Karras and Laine (HPG 2013) asked of the SAH cost, the rank
correlation of trace time per ray with the predicted work (the sum of the
predicted counters, uncalibrated) and with the measured work (the sum of
the measured counters) across each configuration's cells of one workload:
how much of the time's order the model explains, beside how much the
counters themselves do.

Writes prediction.csv (one row per configuration, counter and workload),
prediction_time.csv (one per configuration and workload: the time
correlations), prediction.md (both as tables) and prediction.png
(predicted against measured, log-log, one panel per counter) into --out
(default the run folder). Exit status 2 on bad input (one line naming it)."""
import argparse
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot as common  # noqa: E402

PROG = "predict.py"
COUNTERS = (("tests", "tests_per_ray", "predicted_tests_per_ray"),
            ("box_tests", "box_tests_per_ray", "predicted_box_tests_per_ray"),
            ("steps", "steps_per_ray", "predicted_steps_per_ray"))
REQUIRED = ("scene", "accel", "params", "workload", "threads", "rays", "trace_ms") + tuple(
    c for _, m, p in COUNTERS for c in (m, p))
ALL = "all"
CSV_COLUMNS = ("configuration", "accel", "params", "counter", "workload", "cells", "rank_corr", "median_abs_rel_error",
               "median_measured_over_predicted")
TIME_COLUMNS = ("configuration", "accel", "params", "workload", "cells", "rank_corr_time_predicted",
                "rank_corr_time_measured")
num = common.num


def ranks(values):
    """Ranks 1..n, ties at their mean rank."""
    order = sorted(range(len(values)), key=lambda i: values[i])
    r = [0.0] * len(values)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and values[order[j + 1]] == values[order[i]]:
            j += 1
        for k in range(i, j + 1):
            r[order[k]] = (i + j) / 2.0 + 1.0
        i = j + 1
    return r


def spearman(x, y):
    """Spearman's rank correlation (Pearson's of the ranks); None under 3 pairs or for a constant side."""
    if len(x) < 3:
        return None
    rx, ry = ranks(x), ranks(y)
    mx, my = statistics.fmean(rx), statistics.fmean(ry)
    sxy = sum((a - mx) * (b - my) for a, b in zip(rx, ry))
    sxx = sum((a - mx) ** 2 for a in rx)
    syy = sum((b - my) ** 2 for b in ry)
    if sxx == 0 or syy == 0:
        return None
    return sxy / math.sqrt(sxx * syy)


def pairs(rows, measured, predicted):
    """(predicted, measured) of the rows that have both above 0."""
    out = []
    for r in rows:
        p, m = num(r.get(predicted)), num(r.get(measured))
        if p is not None and m is not None and p > 0 and m > 0:
            out.append((p, m))
    return out


def accuracy(pp):
    """cells, rank correlation, median |relative error|, median measured/predicted of (predicted, measured) pairs."""
    if not pp:
        return 0, None, None, None
    ps, ms = [p for p, _ in pp], [m for _, m in pp]
    return (len(pp), spearman(ps, ms), statistics.median(abs(p - m) / m for p, m in pp),
            statistics.median(m / p for p, m in pp))


def work(row, kind):
    """The sum of a row's predicted (kind "predicted_") or measured ("") counters, or None if one is missing."""
    total = 0.0
    for _, m, p in COUNTERS:
        col = p if kind else m
        v = num(row.get(col))
        if v is None:
            # a structure with no model of a counter: leave it out of both sums alike
            if num(row.get(p)) is None:
                continue
            return None
        total += v
    return total


def analyse(rows, labels, workloads):
    """The accuracy rows and the time rows (lists of dicts, CSV_COLUMNS and TIME_COLUMNS)."""
    acc, timing = [], []
    configs = common.ordered(common.config_key(r) for r in rows)
    for cfg in configs:
        mine = [r for r in rows if common.config_key(r) == cfg]
        if not any(num(r.get(p)) is not None for r in mine for _, _, p in COUNTERS):
            continue
        for name, m, p in COUNTERS:
            for w in list(workloads) + [ALL]:
                sel = mine if w == ALL else [r for r in mine if r["workload"] == w]
                n, rho, err, ratio = accuracy(pairs(sel, m, p))
                if n:
                    acc.append(dict(zip(CSV_COLUMNS, (labels[cfg], cfg[0], cfg[1], name, w, n, rho, err, ratio))))
        for w in workloads:
            sel = [r for r in mine if r["workload"] == w]
            trip = [(work(r, "predicted_"), work(r, ""), common.ns_per_ray(r)) for r in sel]
            trip = [t for t in trip if None not in t]
            if trip:
                rp = spearman([a for a, _, _ in trip], [c for _, _, c in trip])
                rm = spearman([b for _, b, _ in trip], [c for _, _, c in trip])
                timing.append(dict(zip(TIME_COLUMNS, (labels[cfg], cfg[0], cfg[1], w, len(trip), rp, rm))))
    return acc, timing


def fmt(v, digits=2):
    if v is None:
        return ""
    return f"{v:.{digits}f}" if isinstance(v, float) else str(v)


def markdown(csv_path, acc, timing, rows):
    def uniq(col):
        return common.column_values(rows, col)
    out = ["# Cost models: predicted against measured work per ray\n",
           f"From `{csv_path}` (machine {uniq('machine')}, cpu {uniq('cpu')}, git {uniq('git_rev')}). "
           "The models are stated for random lines walked whole (docs/accels, \"Cost model\"); rank corr. is "
           "Spearman's across the cells, |rel. error| the median of |predicted - measured| / measured, "
           "measured/pred. the median ratio.\n"]
    for name, _, _ in COUNTERS:
        sel = [r for r in acc if r["counter"] == name]
        if not sel:
            continue
        out.append(f"## {name.replace('_', ' ')} per ray\n")
        out.append("| configuration | workload | cells | rank corr. | median \\|rel. error\\| | measured/pred. |")
        out.append("|---|---|---:|---:|---:|---:|")
        for r in sel:
            out.append(f"| {r['configuration']} | {r['workload']} | {r['cells']} | {fmt(r['rank_corr'])} | "
                       f"{fmt(r['median_abs_rel_error'])} | {fmt(r['median_measured_over_predicted'])} |")
        out.append("")
    if timing:
        out.append("## Trace time against work (Aila, Karras and Laine's question)\n")
        out.append("Rank correlation across a configuration's cells of one workload of the trace time per ray with "
                   "the predicted work (the sum of its predicted counters) and with the measured work (the same "
                   "sum measured).\n")
        out.append("| configuration | workload | cells | time ~ predicted | time ~ measured |")
        out.append("|---|---|---:|---:|---:|")
        for r in timing:
            out.append(f"| {r['configuration']} | {r['workload']} | {r['cells']} | "
                       f"{fmt(r['rank_corr_time_predicted'])} | {fmt(r['rank_corr_time_measured'])} |")
        out.append("")
    if not acc:
        out.append("No row of this run carries a prediction.\n")
    return "\n".join(out) + "\n"


def plot(path, rows, labels, workloads):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    common.check_replaceable(path)
    markers = "osD^vP*X"
    fig, axes = plt.subplots(1, 3, figsize=(15, 5))
    shown = {}
    for ax, (name, m, p) in zip(axes, COUNTERS):
        lo, hi = math.inf, 0.0
        for cfg in labels:
            for wi, w in enumerate(workloads):
                pp = pairs([r for r in rows if common.config_key(r) == cfg and r["workload"] == w], m, p)
                if not pp:
                    continue
                xs, ys = [a for a, _ in pp], [b for _, b in pp]
                lo, hi = min(lo, *xs, *ys), max(hi, *xs, *ys)
                h = ax.scatter(xs, ys, s=22, marker=markers[wi % len(markers)], color=common.color_of(labels, cfg),
                               alpha=0.8, label=f"{labels[cfg]} / {w}")
                shown.setdefault(f"{labels[cfg]} / {w}", h)
        ax.set_title(f"{name.replace('_', ' ')} per ray")
        ax.set_xlabel("predicted (random lines)")
        ax.set_ylabel("measured")
        if hi > 0:
            ax.set_xscale("log")
            ax.set_yscale("log")
            ax.plot([lo, hi], [lo, hi], color="0.5", lw=1, ls="--")
        else:
            ax.text(0.5, 0.5, "no prediction", ha="center", va="center", transform=ax.transAxes)
    if shown:
        fig.legend(list(shown.values()), list(shown), fontsize=7, loc="lower center", ncol=min(6, len(shown)))
    common.footer(fig, rows)
    fig.tight_layout(rect=(0, 0.04 + 0.025 * math.ceil(len(shown) / 6), 1, 1))
    fig.savefig(path, dpi=common.DPI, metadata={"Software": None})
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", metavar="RUN_DIR", help="a run folder (its matrix.csv) or a matrix.csv")
    ap.add_argument("--out", metavar="DIR", help="where to write prediction.csv, prediction_time.csv, .md and .png (default: the run folder)")
    ap.add_argument("--accelbench", metavar="BIN", help="the binary whose `list accels` gives the labels' defaults")
    ap.add_argument("--no-plot", action="store_true", help="write the CSV and Markdown only")
    ap.add_argument("--quiet", action="store_true", help="do not list the files written")
    args = ap.parse_args(argv)
    common.PROG = PROG
    csv_path, rows, out, labels = common.run_folder_rows(args.run, args.out, REQUIRED, args.accelbench)
    workloads = common.ordered((r["workload"] for r in rows), common.WORKLOAD_ORDER)
    acc, timing = analyse(rows, labels, workloads)
    written = []
    for name, columns, records in (("prediction.csv", CSV_COLUMNS, acc), ("prediction_time.csv", TIME_COLUMNS, timing)):
        path = os.path.join(out, name)
        common.write_csv(path, columns, [[r[c] for c in columns] for r in records], lambda v: fmt(v, 4))
        written.append(path)
    path = os.path.join(out, "prediction.md")
    common.write_text(path, markdown(csv_path, acc, timing, rows))
    written.append(path)
    if not args.no_plot:
        path = os.path.join(out, "prediction.png")
        plot(path, rows, labels, workloads)
        written.append(path)
    if not args.quiet:
        for p in written:
            print(f"wrote {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
