#!/usr/bin/python3
"""Summarise an accelbench matrix.csv as Markdown tables (stdout, or --out FILE).

First the findings (scripts/findings.py, the same code and numbers as the
HTML report's): per workload, every configuration ranked by the geometric
mean of its paired ratio to Embree with a 95 % interval and its number of
cells; per scene and workload the fastest configuration and the fastest of
the survey's structures, ties marked; one line per accelerator family.

Then, for every accelerator configuration (labelled as plot.py labels them:
the name alone for the default instance, name[the parameters that differ
from the defaults] for another; the defaults come from `accelbench list
accels` of --accelbench, $ACCELBENCH or the source tree's build) over every
scene of the file:
  - one table per workload: per scene, each configuration's ratio to Embree
    (the paired median, ratio_vs_embree: >1 is slower than Embree) and, in
    a last column, the configuration with the lowest ratio (the winner);
  - one table of the per-configuration medians over scenes and workloads:
    geometric-mean ratio to Embree, Mrays/s, tests, box tests and steps per
    ray, build ms and bytes per primitive, and the number of (scene,
    workload) cells it wins;
  - the count of real mismatches (which must be 0);
  - when the file has cells timed both from a reset (timed_from=reset: every
    timed pass starts from the post-build state, so a lazily built
    structure grows itself in each) and warm (run --warm-passes: the passes
    trace what the first one grew), on the same rays: per cell, the two
    paired ratios to Embree, cold over warm (what lazy construction costs a
    first pass over later ones) and the lazy build time of a cold pass;
  - with --predicted, for rows that carry a cost model's prediction
    (bvh-gs: eq. (3) of the survey, predicted_tests_per_ray and
    predicted_box_tests_per_ray), the predicted and measured tests and box
    tests per ray side by side, per workload, with measured/predicted and
    how many cells fall within 25 % of the prediction.
Embree's own rows (ratio 1 by definition) are left out. Every number comes
from the CSV; a cell measured twice counts once (its last row, as plot.py).
Exit status 2 for a missing file or missing columns.
"""
import argparse
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot as common  # noqa: E402
import findings  # noqa: E402

PROG = "summary.py"
REQUIRED = ("scene", "accel", "params", "workload", "threads", "ratio_vs_embree", "mrays_per_s", "tests_per_ray",
            "box_tests_per_ray", "steps_per_ray", "build_ms", "bytes_per_prim", "mismatch_real")
num = common.num


def geomean(values):
    values = [v for v in values if v and v > 0]
    return math.exp(sum(math.log(v) for v in values) / len(values)) if values else None


def fmt(v, digits=2):
    return "" if v is None else f"{v:.{digits}f}"


def lazy_pass_table(rows, scenes, workloads):
    """Cold (timed from a reset) against warm (--warm-passes) rows of the same rays, or [] when there are none."""
    if rows and "timed_from" not in rows[0]:
        return []
    def same_rays(r):
        return (r["accel"], r["params"], r["threads"], r["scene"], r["workload"], r.get("rayset_hash", ""))
    cold = {same_rays(r): r for r in rows if r["timed_from"] == "reset"}
    pairs = [(cold[same_rays(r)], r) for r in rows if r["timed_from"] == "warm" and same_rays(r) in cold]
    if not pairs:
        return []
    pairs.sort(key=lambda p: (p[0]["accel"], p[0]["params"], scenes.index(p[0]["scene"]),
                              workloads.index(p[0]["workload"])))
    out = ["## Lazy construction: the first pass against later passes\n",
           "cold: every timed pass from the post-build state (the structure grows itself in each); warm: "
           "run --warm-passes, the timed passes trace what the first pass grew. Both ratios are paired with "
           "Embree in their own samples, so cold/warm is what lazy construction costs a first pass over the "
           "later ones; lazy build ms is what a cold pass spent growing the structure (stat_lazy_build_ms: the median over samples "
           "of their last pass, where cold ms is the median of whole samples per pass, so the share can pass 100 % "
           "when growing is nearly all of a pass).\n"]
    out.append("| accel | params | scene | workload | rays | ratio cold | ratio warm | cold / warm | cold ms | warm ms | "
               "lazy build ms | lazy share of cold |")
    out.append("|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    quotients = []
    for c, w in pairs:
        rc, rw = num(c["ratio_vs_embree"]), num(w["ratio_vs_embree"])
        q = rc / rw if rc and rw else None
        if q:
            quotients.append(q)
        tc, tw, lb = num(c["trace_ms"]), num(w["trace_ms"]), num(c.get("stat_lazy_build_ms", ""))
        share = lb / tc if lb is not None and tc else None
        out.append(f"| {c['accel']} | {c['params']} | {c['scene']} | {c['workload']} | {c['rays']} | {fmt(rc)} | "
                   f"{fmt(rw)} | {fmt(q, 1)} | {fmt(tc, 1)} | {fmt(tw, 1)} | {fmt(lb, 1)} | "
                   f"{'' if share is None else f'{100 * share:.0f} %'} |")
    if quotients:
        out.append(f"\nOver {len(quotients)} cells, cold / warm: geometric mean {fmt(geomean(quotients), 1)}, "
                   f"from {fmt(min(quotients), 1)} to {fmt(max(quotients), 1)}.")
    out.append("")
    return out


def predicted_tables(rows, labels, scenes, workloads):
    """Predicted against measured tests per ray, per workload (rows with a prediction only)."""
    if rows and "predicted_tests_per_ray" not in rows[0]:
        common.fail("the CSV has no predicted_tests_per_ray column (written by accelbench since bvh-gs)")
    rows = [r for r in rows if num(r.get("predicted_tests_per_ray", "")) is not None]
    out = [PREDICTED_HEADING + " (measured / predicted)\n",
           "The prediction is eq. (3) of the survey with surface-area conditional probabilities, made for rays "
           "that start outside the root volume and cross it (Goldsmith and Salmon's primary rays): a ratio "
           "near 1 is where it holds.\n"]
    if not rows:
        return out + ["No row carries a prediction.\n"]
    for w in workloads:
        ws = [r for r in rows if r["workload"] == w]
        if not ws:
            continue
        out.append(f"### {w}\n")
        out.append("| scene | configuration | tests/ray predicted | measured | ratio | box tests/ray predicted | measured | ratio |")
        out.append("|---|---|---:|---:|---:|---:|---:|---:|")
        within = 0
        for r in sorted(ws, key=lambda r: (scenes.index(r["scene"]), labels[common.config_key(r)])):
            pt, mt = num(r["predicted_tests_per_ray"]), num(r["tests_per_ray"])
            pb, mb = num(r["predicted_box_tests_per_ray"]), num(r["box_tests_per_ray"])
            rt = mt / pt if pt and mt is not None else None
            rb = mb / pb if pb and mb is not None else None
            within += rt is not None and 0.75 <= rt <= 1.25
            out.append(f"| {r['scene']} | {labels[common.config_key(r)]} | {fmt(pt, 1)} | {fmt(mt, 1)} | {fmt(rt)} | "
                       f"{fmt(pb, 1)} | {fmt(mb, 1)} | {fmt(rb)} |")
        out.append(f"\nTests per ray within 25 % of the prediction in {within} of {len(ws)} cells.\n")
    return out


def written_by_us(path):
    """Whether path is absent or a summary.py summary (its first line "# Summary of"), so it may be rewritten."""
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return f.readline().startswith("# Summary of")
    except FileNotFoundError:
        return True
    except OSError:
        return False


PREDICTED_HEADING = "## Cost model: predicted against measured"


def had_predicted(path):
    """Whether the summary at path was written with --predicted (rewritten, it keeps them)."""
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return any(line.startswith(PREDICTED_HEADING) for line in f)
    except OSError:
        return False


def write_beside(csv_path, folder=None, accelbench=None):
    """summary.md in folder (default: beside the CSV; plot.py and report.py call this at the end of a run),
    unless a summary.md there was written by something else (a reproduce or champion run's). Returns its
    path, or None."""
    path = os.path.join(folder or os.path.dirname(os.path.abspath(csv_path)), "summary.md")
    if not written_by_us(path) or not os.access(os.path.dirname(path), os.W_OK):
        return None
    prog = common.PROG
    argv = [csv_path, "--out", path] + (["--accelbench", accelbench] if accelbench else []) + (
        ["--predicted"] if had_predicted(path) else [])
    try:
        main(argv)
    except SystemExit:  # nothing to summarise (no accelerator but embree): no file
        return None
    finally:
        common.PROG = prog
    return path


def main(argv=None):
    p = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv", metavar="CSV", help="matrix.csv written by accelbench run")
    p.add_argument("--out", metavar="FILE", help="write the Markdown here (default: stdout)")
    p.add_argument("--predicted", action="store_true", help="add the cost model's predictions against the measured counters")
    p.add_argument("--accelbench", metavar="BIN", help="the binary whose `list accels` gives the parameters' defaults "
                   "(default $ACCELBENCH, else the source tree's build/accelbench)")
    args = p.parse_args(argv)
    common.PROG = PROG
    rows = common.dedup_rows(common.load_rows(args.csv, REQUIRED), args.csv)
    rows = [r for r in rows if r["accel"] != "embree"]
    if not rows:
        common.fail(f"{args.csv}: no rows of an accelerator other than embree")
    labels = common.config_labels(rows, limit=None, defaults=common.accel_defaults_from_env(args.accelbench))
    configs = list(labels)
    scenes = common.ordered(r["scene"] for r in rows)
    workloads = common.ordered((r["workload"] for r in rows), common.WORKLOAD_ORDER)
    cell = {(common.config_key(r), r["scene"], r["workload"]): r for r in rows}
    out = []
    out.append(f"# Summary of {args.csv}\n")
    out.append("Ratio = the accelerator's time over Embree's on the same rays, the median of samples interleaved "
               "with Embree's (ratio_vs_embree; >1: slower than Embree).\n")
    out.append(findings.markdown(findings.findings(rows, labels, common.config_key)))
    out.append("## Every cell\n")
    wins = {c: 0 for c in configs}
    for w in workloads:
        out.append(f"## {w}: ratio to Embree\n")
        out.append("| scene | " + " | ".join(labels[c] for c in configs) + " | winner |")
        out.append("|---|" + "---:|" * len(configs) + "---|")
        for s in scenes:
            vals = [num(cell[(c, s, w)]["ratio_vs_embree"]) if (c, s, w) in cell else None for c in configs]
            present = [(v, c) for v, c in zip(vals, configs) if v]
            best = min(present)[1] if present else None
            if best:
                wins[best] += 1
            out.append(f"| {s} | " + " | ".join(fmt(v) for v in vals) + f" | {labels[best] if best else ''} |")
        out.append("")
    out.append("## Per configuration, over every scene and workload\n")
    out.append("Geometric mean of the ratio; medians of the rest over the configuration's cells.\n")
    out.append("Mrays/s is on the configuration's threads (an accelerator that mutates while tracing runs on one): "
               "compare by the ratio.\n")
    out.append("| configuration | cells | wins | ratio (geomean) | Mrays/s | threads | tests/ray | box tests/ray | "
               "steps/ray | build ms | bytes/prim | real mismatches |")
    out.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for c in configs:
        rs = [r for (k, _, _), r in cell.items() if k == c]

        def med(col):
            vals = [num(r[col]) for r in rs if num(r[col]) is not None]
            return statistics.median(vals) if vals else None
        real = sum(int(num(r["mismatch_real"]) or 0) for r in rs)
        out.append(f"| {labels[c]} | {len(rs)} | {wins[c]} | {fmt(geomean(num(r['ratio_vs_embree']) for r in rs))} | "
                   f"{fmt(med('mrays_per_s'), 3)} | {c[2]} | {fmt(med('tests_per_ray'), 1)} | {fmt(med('box_tests_per_ray'), 1)} | "
                   f"{fmt(med('steps_per_ray'), 1)} | {fmt(med('build_ms'), 1)} | {fmt(med('bytes_per_prim'), 1)} | {real} |")
    out.append("")
    out.extend(lazy_pass_table(rows, scenes, workloads))
    if args.predicted:
        out.extend(predicted_tables(rows, labels, scenes, workloads))
    text = "\n".join(out) + "\n"
    if args.out:
        tmp = args.out + ".tmp"
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, args.out)
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
