#!/usr/bin/python3
"""The comparison the survey lacked: `accelbench reproduce survey`.

Every structure of the survey (and the testbed's own wide BVH, Embree and
CGAL's tree as peers), at its default and at its tuned setting, on the
same rays, one thread, paired with Embree; then one row per structure,
grouped by family, with the considerations of the survey's Figure 1 as
numbers:
  speed         the geometric mean of the ratio to Embree over the cells
                (scenes x workloads), at the default and tuned, with the
                default's 95 % interval (Student's t on the logarithms);
  growth        the exponent b of trace time per ray ~ N^b over the scenes'
                primitive counts N (least squares on the logarithms, one
                intercept per workload), at the default;
  build         the median build time per thousand primitives, and the rays
                a build must serve to pay for itself against no structure
                at all (build time / (N x the cost of one primitive test -
                time per ray), median over the cells; the test's cost is
                exhaustive's, measured on the run's smaller scenes);
  storage       the median bytes per primitive;
  coherence     the geometric mean over scenes of the time per diffuse ray
                over the time per primary ray (1: coherence does not help);
  parameters    the geometric-mean gain of the tuned setting over the
                default (`accelbench tune`'s): how much the "a priori
                selection of unintuitive parameters" costs;
  prediction    the cost model's rank correlation with the measured
                primitive tests and steps over all cells (`accelbench
                predict`), where it has one.
The steps: `accelbench tune` over the scenes and the five workloads into
OUT/tune/ (training rays, then the default and the choice measured),
`accelbench run` of exhaustive on the scenes of at most EXHAUSTIVE_MAX
primitives into OUT/exhaustive/, scripts/predict.py on OUT/tune/; each
is resumable, every child gets an argument vector. Written: OUT/survey.csv,
OUT/survey.md (the table and the findings, also printed).
Exit status: the first failing child's (2 on bad input), else 1 when a
cell's answers had a real mismatch against Embree's, else 0."""
import argparse
import math
import os
import statistics
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot as common  # noqa: E402
import tune  # noqa: E402

PROG = "survey.py"
num = common.num
fmt = common.fmt_g
ns_per_ray = common.ns_per_ray
run = common.run_child
WORKLOADS = "primary,shadow,reflection,diffuse,random"
EXHAUSTIVE_MAX = 20000
# family, structures, in the survey's order; the last two families are the baseline and the peers
FAMILIES = (("uniform grids (s5.2)", ("grid", "grid-raybox")), ("octree (s5.2)", ("octree",)),
            ("BSP tree (s5.2)", ("bsp",)), ("hierarchies (s4)", ("bvh-gs", "slabs-kk")),
            ("directional (s6)", ("raycls", "lightbuf", "raycoh")), ("no structure", ("exhaustive",)),
            ("peers", ("bvh", "embree", "cgal-aabb")))
SURVEY = tuple(a for _, acc in FAMILIES[:5] for a in acc)
# two-sided 95 % Student t quantiles by degrees of freedom (1..30; beyond, the normal's)
T95 = (12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160, 2.145, 2.131,
       2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056, 2.052, 2.048, 2.045, 2.042)


def family_of(accel):
    return next((f for f, acc in FAMILIES if accel in acc), "other")


def geo_interval(values):
    """(geometric mean, low, high) with the 95 % interval of the mean of the logarithms; None without values."""
    logs = [math.log(v) for v in values if v and v > 0]
    if not logs:
        return None
    m = statistics.fmean(logs)
    if len(logs) < 2:
        return math.exp(m), None, None
    half = (T95[len(logs) - 2] if len(logs) - 1 <= len(T95) else 1.960) * statistics.stdev(logs) / math.sqrt(len(logs))
    return math.exp(m), math.exp(m - half), math.exp(m + half)


def growth_exponent(cells):
    """b of ns ~ N^b from [(workload, N, ns)], one intercept per workload; None with fewer than two sizes."""
    cells = [(w, n, t) for w, n, t in cells if n and n > 0 and t and t > 0]
    if len({n for _, n, _ in cells}) < 2:
        return None
    ws = sorted({w for w, _, _ in cells})
    X = np.array([[math.log(n)] + [1.0 if w == x else 0.0 for x in ws] for w, n, _ in cells])
    y = np.array([math.log(t) for _, _, t in cells])
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    return float(coef[0])


def test_cost(rows):
    """exhaustive's ns per primitive test: the median over its cells of time per ray over tests per ray."""
    per = [ns_per_ray(r) / num(r["tests_per_ray"]) for r in rows
           if r["accel"] == "exhaustive" and ns_per_ray(r) and num(r.get("tests_per_ray"))]
    return statistics.median(per) if per else None


def analyse(rows, tuning, prediction, defaults, test_ns):
    """One record per structure measured (see the module's text)."""
    def is_default(r):
        d = defaults.get(r["accel"], {})
        return all(tune.param_of(r["params"], k) == v for k, v in d.items())

    tuned_value = {(t["scene"], t["workload"], t["accel"]): (t["key"], t["tuned"]) for t in tuning}
    gains = {}
    for t in tuning:
        if num(t.get("gain")):
            gains.setdefault(t["accel"], []).append(num(t["gain"]))
    out = []
    accels = [a for _, acc in FAMILIES for a in acc if any(r["accel"] == a for r in rows)]
    for a in accels:
        dflt = [r for r in rows if r["accel"] == a and is_default(r)]
        tuned = []
        for r in rows:
            if r["accel"] != a:
                continue
            kv = tuned_value.get((r["scene"], r["workload"], a))
            if kv is None and is_default(r):
                tuned.append(r)
            elif kv is not None and tune.param_of(r["params"], kv[0]) == kv[1]:
                tuned.append(r)
        rec = {"family": family_of(a), "accel": a, "cells": len(dflt)}
        measured_w = sorted({r["workload"] for r in dflt}, key=lambda w: WORKLOADS.split(",").index(w)
                            if w in WORKLOADS.split(",") else 99)
        all_w = {r["workload"] for r in rows}
        rec["applies_to"] = "all rays" if set(measured_w) >= all_w else " and ".join(measured_w) + " rays"
        gi = geo_interval([num(r["ratio_vs_embree"]) for r in dflt])
        if gi:
            rec.update(speed=gi[0], speed_lo=gi[1], speed_hi=gi[2])
        gt = geo_interval([num(r["ratio_vs_embree"]) for r in tuned])
        rec["speed_tuned"] = gt[0] if gt else None
        rec["growth"] = growth_exponent([(r["workload"], num(r["prims"]), ns_per_ray(r)) for r in dflt])
        per_k = [num(r["build_ms"]) / num(r["prims"]) * 1000 for r in dflt if num(r.get("build_ms")) is not None
                 and num(r.get("prims"))]
        rec["build_ms_per_kprim"] = statistics.median(per_k) if per_k else None
        if test_ns and a != "exhaustive":
            even = []
            for r in dflt:
                t, n, b = ns_per_ray(r), num(r.get("prims")), num(r.get("build_ms"))
                if t is None or not n or b is None:
                    continue
                saved = n * test_ns - t
                even.append(b * 1e6 / saved if saved > 0 else math.inf)
            rec["break_even_rays"] = statistics.median(even) if even else None
        mem = [num(r["mem_bytes"]) / num(r["prims"]) for r in dflt if num(r.get("mem_bytes")) and num(r.get("prims"))]
        rec["bytes_per_prim"] = statistics.median(mem) if mem else None
        by_scene = {}
        for r in dflt:
            if r["workload"] in ("primary", "diffuse") and ns_per_ray(r):
                by_scene.setdefault(r["scene"], {})[r["workload"]] = ns_per_ray(r)
        coh = [s["diffuse"] / s["primary"] for s in by_scene.values() if "diffuse" in s and "primary" in s]
        rec["diffuse_over_primary"] = common.geomean(coh) if coh else None
        rec["tuning_gain"] = common.geomean(gains[a]) if gains.get(a) else None
        for counter in ("tests", "steps"):
            p = [x for x in prediction if x["accel"] == a and x["counter"] == counter and x["workload"] == "all"
                 and is_default(x)]
            rec[f"pred_{counter}_corr"] = num(p[0]["rank_corr"]) if p else None
        out.append(rec)
    return out


COLS = ["family", "accel", "applies_to", "cells", "speed", "speed_lo", "speed_hi", "speed_tuned", "tuning_gain", "growth",
        "build_ms_per_kprim", "break_even_rays", "bytes_per_prim", "diffuse_over_primary", "pred_tests_corr",
        "pred_steps_corr"]


def findings(recs):
    """Sentences the table supports, each naming its numbers."""
    out = []
    # speed is compared over the same cells: the structures measured on every workload (the light buffer answers
    # shadow rays only and is compared with the others there)
    full = max((r["cells"] for r in recs), default=0)
    survey = [r for r in recs if r["accel"] in SURVEY and r.get("speed") and r["cells"] == full]
    shadow_only = [r for r in recs if r["accel"] in SURVEY and r.get("speed") and r["cells"] < full]
    if survey:
        best = min(survey, key=lambda r: r["speed"])
        out.append(f"At the defaults the survey's fastest structure is {best['accel']} ({best['family']}), "
                   f"{fmt(best['speed'])}x Embree's time in geometric mean.")
        tuned = [r for r in survey if r.get("speed_tuned")]
        if tuned:
            bt = min(tuned, key=lambda r: r["speed_tuned"])
            out.append(f"Tuned per scene and workload, the fastest is {bt['accel']} at {fmt(bt['speed_tuned'])}x.")
        for r in shadow_only:
            out.append(f"{r['accel']}, on the shadow rays it answers ({r['cells']} cells), is at {fmt(r['speed'])}x "
                       f"Embree at its default and {fmt(r.get('speed_tuned'))}x tuned.")
        never = [r["accel"] for r in survey if r.get("break_even_rays") == math.inf]
        if never:
            out.append(f"{', '.join(never)} never pays for its build against testing every primitive on the median "
                       "cell.")
        sens = [r for r in survey + shadow_only if r.get("tuning_gain")]
        if sens:
            s = max(sens, key=lambda r: r["tuning_gain"])
            flat = [r["accel"] for r in sens if r["tuning_gain"] < 1.05]
            out.append(f"The most parameter-sensitive is {s['accel']}: tuning gains {fmt(s['tuning_gain'])}x over its "
                       f"default" + (f"; {', '.join(flat)} gain under 5 %." if flat else "."))
        # the structures at either end of a column: (sentence, column, digits)
        for text, col, digits in (
                ("Time per ray grows slowest with scene size for {lo} (N^{vlo}) and fastest for {hi} (N^{vhi}).",
                 "growth", 2),
                ("Incoherent rays cost {vlo}x the primary rays' time for {lo} and {vhi}x for {hi}.",
                 "diffuse_over_primary", 3),
                ("Storage ranges from {vlo} bytes a primitive ({lo}) to {vhi} ({hi}).", "bytes_per_prim", 3)):
            have = sorted((r for r in survey if r.get(col) is not None), key=lambda r: r[col])
            if have:
                out.append(text.format(lo=have[0]["accel"], hi=have[-1]["accel"], vlo=fmt(have[0][col], digits),
                                       vhi=fmt(have[-1][col], digits)))
    return out


def family_rows(recs):
    """Per family of the survey, its structure of lowest tuned (else default) geometric mean over all rays."""
    out = []
    for fam, accs in FAMILIES:
        mine = [r for r in recs if r["accel"] in accs and r["applies_to"] == "all rays" and r.get("speed")]
        if mine:
            out.append(min(mine, key=lambda r: r.get("speed_tuned") or r["speed"]))
    return out


def markdown(recs, lines, scenes, res, repeat):
    def row(r):
        ci = f"{fmt(r.get('speed_lo'))}-{fmt(r.get('speed_hi'))}" if r.get("speed_lo") else ""
        even = r.get("break_even_rays")
        even_s = "never" if even == math.inf else fmt(even)
        pred = ", ".join(fmt(r.get(f"pred_{c}_corr"), 2) if r.get(f"pred_{c}_corr") is not None else "-"
                         for c in ("tests", "steps"))
        return (f"| {r['family']} | {r['accel']} | {r['applies_to']} | {r['cells']} | {fmt(r.get('speed'))} | {ci} | "
                f"{fmt(r.get('speed_tuned'))} | {fmt(r.get('tuning_gain'))} | {fmt(r.get('growth'), 2)} | "
                f"{fmt(r.get('build_ms_per_kprim'))} | {even_s} | {fmt(r.get('bytes_per_prim'))} | "
                f"{fmt(r.get('diffuse_over_primary'))} | {pred} |")
    head = ["| family | structure | applies to | cells | x Embree (default) | 95 % interval | x Embree (tuned) | "
            "default / tuned | growth N^b | build ms per 1k prims | rays to pay off | bytes per prim | "
            "diffuse / primary | model rank corr. (tests, steps) |",
            "|---|---|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---|"]
    md = ["# The survey's comparison, measured\n",
          f"Scenes `{scenes}` x workloads {WORKLOADS.replace(',', ', ')}; {res} rays a cell, {repeat} paired repeats, "
          "one thread. Ratios are to Embree's time on the same rays (lower is faster). The columns answer the "
          "questions of the survey's Figure 1: applicability (does it apply to all rays?), performance (fast "
          "enough: x Embree; how it scales: growth; does pre-processing pay: rays to pay off; coherence: diffuse "
          "/ primary), resources (storage: bytes per primitive) and simplicity (unintuitive parameters: "
          "default / tuned); and the prediction the survey wished for: the cost model's rank correlation.\n",
          "## Per family: its best structure\n"] + head + [row(r) for r in family_rows(recs)] + \
         ["", "## Every structure\n"] + head + [row(r) for r in recs]
    md += ["", "Rays to pay off: the rays one build must serve before it costs less than testing every primitive "
           "(\"never\": not faster than that on the median cell). Model rank correlation: over all cells, of the "
           "cost model's predicted counters with the measured ones (`accelbench predict`; - where there is none).",
           "", "## Findings\n"] + [f"- {x}" for x in lines]
    return "\n".join(md) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--accelbench", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--scenes", required=True)
    ap.add_argument("--accels", required=True)
    ap.add_argument("--res", required=True)
    ap.add_argument("--repeat", required=True)
    ap.add_argument("--workloads", default=WORKLOADS)
    ap.add_argument("--no-plots", action="store_true")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    common.PROG = PROG
    tdir, edir = os.path.join(args.out, "tune"), os.path.join(args.out, "exhaustive")
    accels = [a for a in args.accels.split(",") if a and a != "exhaustive"]
    rc = run([args.accelbench, "tune", "--scenes", args.scenes, "--workloads", args.workloads, "--accels",
              ",".join(accels), "--res", args.res, "--repeat", args.repeat, "--threads", "1", "--out", tdir]
             + (["--quiet"] if args.quiet else []), False)
    if rc:
        print(f"{PROG}: the tuning run failed (exit {rc}); run the same command again to resume", file=sys.stderr)
        return rc
    rows = common.dedup_rows(common.load_rows(os.path.join(tdir, "matrix.csv"),
                                              ("scene", "prims", "accel", "params", "workload", "rays", "trace_ms",
                                               "ratio_vs_embree", "build_ms", "mem_bytes")),
                             os.path.join(tdir, "matrix.csv"))
    small = list(dict.fromkeys(r["scene"] for r in rows if (num(r["prims"]) or math.inf) <= EXHAUSTIVE_MAX))
    erows = []
    if "exhaustive" in args.accels.split(",") and small:
        rc = run([args.accelbench, "run", "--scenes", ",".join(small), "--accels", "exhaustive", "--workloads",
                  args.workloads, "--res", args.res, "--repeat", args.repeat, "--threads", "1", "--no-plots", "--out",
                  edir], args.quiet)
        if rc:
            print(f"{PROG}: the exhaustive run failed (exit {rc}); run the same command again to resume",
                  file=sys.stderr)
            return rc
        erows = [r for r in common.dedup_rows(common.load_rows(os.path.join(edir, "matrix.csv"),
                                                                ("scene", "accel", "rays", "trace_ms", "tests_per_ray")),
                                              os.path.join(edir, "matrix.csv")) if r["accel"] == "exhaustive"]
    rc = run([sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "predict.py"), tdir,
              "--accelbench", args.accelbench, "--quiet"] + (["--no-plot"] if args.no_plots else []), True)
    prediction = []
    if rc == 0 and os.path.isfile(os.path.join(tdir, "prediction.csv")):
        prediction = common.load_rows(os.path.join(tdir, "prediction.csv"), ("accel", "params", "counter", "workload",
                                                                             "rank_corr"))
    tuning = common.load_rows(os.path.join(tdir, "tuning.csv"), ("scene", "workload", "accel", "key", "tuned", "gain")) \
        if os.path.isfile(os.path.join(tdir, "tuning.csv")) else []
    defaults = common.accel_defaults_from_env(args.accelbench)
    recs = analyse(rows + [dict(r, ratio_vs_embree=r.get("ratio_vs_embree", "")) for r in erows], tuning, prediction,
                   defaults, test_cost(erows))
    lines = findings(recs)
    # every cell's answers were checked against Embree's by the runs; a real mismatch fails the survey
    checked = rows + erows
    real = sum(int(num(r.get("mismatch_real")) or 0) for r in checked)
    lines.append(f"Verification: {len(checked)} cells, {real} real mismatches against Embree.")
    common.write_csv(os.path.join(args.out, "survey.csv"), COLS,
                     [[r.get(c) for c in COLS] for r in recs], lambda v: fmt(v, 6))
    text = markdown(recs, lines, args.scenes, args.res, args.repeat)
    common.write_text(os.path.join(args.out, "survey.md"), text)
    print(text if not args.quiet else "\n".join(f"finding: {x}" for x in lines))
    if not args.quiet:
        print(f"wrote {os.path.join(args.out, 'survey.csv')}\nwrote {os.path.join(args.out, 'survey.md')}")
    if real:
        print(f"{PROG}: {real} real mismatches against Embree (the cells' mismatch_real)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
