#!/usr/bin/python3
"""Which structure to use, before tracing: `accelbench advise`'s ranking and its check.

Input: DIR/predictions.csv (`accelbench advise` writes it: per scene, every
candidate built at every value of its search, with its cost model's
predicted counters per ray and its build time and memory) and a calibration
folder (`accelbench calibrate`: calibration.csv, the cost of each counter
per configuration, and calibration_workloads.csv, per configuration and
workload the median of measured over predicted counters and of Embree's
time over the configuration's).

Per scene, workload and candidate, every setting's time per ray is
predicted as
    ns = fixed + sum over counters of cost x scale x prediction
(the counter's calibrated cost; its scale on that workload; the model's
prediction of it, or of the stand-in the calibration names where the model
predicts no such counter), and the setting with the lowest is the
candidate's. A workload the calibration did not measure takes the median
scale of those it did. Costs and scales are the configuration's at its
calibrated parameters (normally its default) and are applied to every value
of its search: the model's prediction is what changes with the value. A primitive test
the fit priced at nothing costs what exhaustive's calibrated test costs
(the same primitive tests), so that a setting trading steps for tests is
not free (bvh, whose leaves test in its own SIMD code, excepted).
Embree's time is predicted from bvh's at its default, times the calibrated
median of Embree's time over bvh's on that workload: both are SAH BVHs. A
structure calibrated with exhaustive's cost of a primitive test pays the
scene's own mix of kinds (`accelbench scene info`) at the calibrated prices
by kind (calibration_kinds.csv), where there are some.

Written to DIR: advice.csv (one row per scene, workload and candidate, in
rank order: setting, predicted ns per ray and ratio to Embree, the term
that dominates and its share, build time, bytes per primitive) and
advice.md; the ranking is printed.

With --check, the candidates are measured at their advised settings,
paired with Embree, one thread (`accelbench run` into DIR/check/, an
argument vector, resumable), and DIR/regret.csv and regret.md give per
cell the regret: the measured ratio of the advised first choice over the
measured best's, for all candidates and for the survey's structures alone
(bvh, the testbed's own wide BVH, left out), with the share of cells
within 10 % and the rank correlation of predicted and measured times, over
all cells and over the scenes the calibration was not fitted on (those of
its calibration_cells.csv are marked).
Exit status 2 on bad input (one line naming it), 1 when a run failed."""
import argparse
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot as common  # noqa: E402
import predict  # noqa: E402

PROG = "advise.py"
num = common.num
fmt = common.fmt_g
mix_cost = common.mix_cost
COUNTERS = (("box_ns", "box_tests_per_ray", "box tests"), ("test_ns", "tests_per_ray", "primitive tests"),
            ("step_ns", "steps_per_ray", "steps"))
EMBREE_PROXY = "bvh"
OWN = {"bvh"}  # the testbed's own structure: left out of the survey-only regret
SHADOW_ONLY = {"lightbuf"}
OWN_TESTS = {"bvh"}  # tests its leaves in its own SIMD code, not through the shared primitive tests
WITHIN = 1.10


def read_csv(path, required):
    if not os.path.isfile(path):
        common.fail(f"{path}: no such file (run `accelbench calibrate` to make one)")
    return common.load_rows(path, required)


def load_calibration(folder):
    """({accel: [calibration.csv rows]}, {(configuration, workload): calibration_workloads row})."""
    costs = {}
    for r in read_csv(os.path.join(folder, "calibration.csv"), ("accel", "params", "configuration", "fixed_ns")):
        costs.setdefault(r["accel"], []).append(r)
    scales = {}
    for r in read_csv(os.path.join(folder, "calibration_workloads.csv"),
                      ("configuration", "workload", "embree_per_ns") + tuple(
                          c.replace("_per_ray", x) for _, c, _ in COUNTERS for x in ("_scale", "_from"))):
        scales[(r["configuration"], r["workload"])] = r
    return costs, scales


def load_kind_costs(folder):
    """{kind: ns} of calibration_kinds.csv, or {} where the calibration has none."""
    path = os.path.join(folder, "calibration_kinds.csv")
    if not os.path.isfile(path):
        return {}
    return {r["kind"]: num(r["test_ns"]) for r in common.load_rows(path, ("kind", "test_ns"))
            if num(r["test_ns"]) is not None}


def calibrated_config(costs, accel, params):
    """The calibration row of accel: the one at params (its default here) if calibrated, else its first."""
    rows = [r for r in costs.get(accel, []) if num(r["fixed_ns"]) is not None]
    same = [r for r in rows if r["params"] == params]
    return (same or rows or [None])[0]


def scale_of(scales, config, workload, counter):
    """(scale, predicted column) of a counter on a workload; a workload not calibrated takes the median of the
    calibrated workloads' scales (the most common predicted column). None when there is none."""
    s, f = counter.replace("_per_ray", "_scale"), counter.replace("_per_ray", "_from")
    row = scales.get((config, workload))
    if row and num(row[s]) is not None and row[f]:
        return num(row[s]), row[f]
    others = [r for (c, _), r in scales.items() if c == config and num(r[s]) is not None and r[f]]
    if not others:
        return None
    col = statistics.mode(r[f] for r in others)
    return statistics.median(num(r[s]) for r in others if r[f] == col), col


def embree_per_ns(scales, config, workload):
    row = scales.get((config, workload))
    if row and num(row["embree_per_ns"]):
        return num(row["embree_per_ns"])
    others = [num(r["embree_per_ns"]) for (c, _), r in scales.items() if c == config and num(r["embree_per_ns"])]
    return statistics.median(others) if others else None


def test_floor(costs):
    """What a primitive test costs at least: exhaustive's calibrated cost of one (the scene mix's), or None."""
    row = calibrated_config(costs, "exhaustive", "")
    return num(row.get("test_ns")) if row else None


def predict_ns(pred, cal, scales, workload, floor=None, scene_test=None):
    """(ns per ray, {term: ns}) of one prediction row on a workload, or None when a term it needs is missing.
    A structure calibrated with exhaustive's cost of a test pays scene_test, this scene's mix at the prices by
    kind, where given. A primitive test the fit priced at nothing (its cost folded into the others over the
    calibration's cells) costs floor where the model predicts tests: otherwise a setting that trades steps for
    tests would look free."""
    fixed = num(cal["fixed_ns"]) or 0.0
    terms = {"fixed cost": fixed}
    for cost_col, counter, name in COUNTERS:
        cost = num(cal.get(cost_col))
        if counter == "tests_per_ray" and scene_test and (cal.get("test_ns_from") or "").startswith("exhaustive"):
            cost = scene_test
        if (not cost and counter == "tests_per_ray" and floor and pred["accel"] not in OWN_TESTS
                and num(pred.get("predicted_tests_per_ray"))):
            cost = floor
        if not cost:
            continue
        sc = scale_of(scales, cal["configuration"], workload, counter)
        if sc is None or num(pred.get(sc[1])) is None:
            return None
        terms[name] = cost * sc[0] * num(pred[sc[1]])
    return sum(terms.values()), terms


def rank(preds, costs, scales, workloads, kind_costs=None, scene_kinds=None):
    """[{scene, workload, accel, setting, value, ns, ratio, term, share, build_ms, bytes_per_prim, params}] in rank
    order per scene and workload, each candidate at its best predicted setting. kind_costs, scene_kinds: the
    calibrated prices of a test by kind and each scene's {kind: count}, where known."""
    out = []
    floor = test_floor(costs)
    for scene in dict.fromkeys(p["scene"] for p in preds):
        mine = [p for p in preds if p["scene"] == scene]
        scene_test = mix_cost(kind_costs or {}, (scene_kinds or {}).get(scene))
        defaults = {p["accel"]: p["params"] for p in mine if p["label"] == p["accel"]}
        for w in workloads:
            proxy = [p for p in mine if p["accel"] == EMBREE_PROXY and p["label"] == EMBREE_PROXY]
            embree_ns = None
            if proxy:
                cal = calibrated_config(costs, EMBREE_PROXY, proxy[0]["params"])
                got = predict_ns(proxy[0], cal, scales, w, floor, scene_test) if cal else None
                per = embree_per_ns(scales, cal["configuration"], w) if cal else None
                embree_ns = got[0] * per if got and per else None
            best = {}
            for p in mine:
                a = p["accel"]
                if p["candidate"] != "1" or (a in SHADOW_ONLY and w != "shadow"):
                    continue
                cal = calibrated_config(costs, a, defaults.get(a, p["params"]))
                got = predict_ns(p, cal, scales, w, floor, scene_test) if cal else None
                if got is None:
                    continue
                ns, terms = got
                if a not in best or ns < best[a]["ns"]:
                    term = max(terms, key=terms.get)
                    prims = num(p["prims"]) or 0
                    best[a] = {"scene": scene, "workload": w, "accel": a, "value": p["value"],
                               "setting": f"{p['key']}={p['value']}" if p["key"] else "default", "ns": ns,
                               "ratio": ns / embree_ns if embree_ns else None, "term": term,
                               "share": terms[term] / ns if ns > 0 else 0.0, "build_ms": num(p["build_ms"]),
                               "bytes_per_prim": num(p["mem_bytes"]) / prims if prims else None,
                               "key": p["key"], "label": p["label"]}
            out += sorted(best.values(), key=lambda b: b["ns"])
    return out


def cells(recs):
    return list(dict.fromkeys((r["scene"], r["workload"]) for r in recs))


def print_ranking(recs, cal_source):
    print(f"predicted with the calibration of {cal_source}; ratios to Embree's predicted time")
    for scene, w in cells(recs):
        mine = [r for r in recs if r["scene"] == scene and r["workload"] == w]
        print(f"{scene} / {w}:")
        for i, r in enumerate(mine, 1):
            ratio = f"{fmt(r['ratio'])}x embree" if r["ratio"] else "ratio unknown"
            print(f"  {i}. {r['accel']:<12} {r['setting']:<22} {ratio:<16} {fmt(r['ns'])} ns/ray, mostly "
                  f"{r['term']} ({fmt(100 * r['share'], 2)} %)")


ADVICE_COLS = ["scene", "workload", "rank", "accel", "setting", "predicted_ns_per_ray", "predicted_ratio_vs_embree",
               "dominant_term", "dominant_share", "build_ms", "bytes_per_prim"]


def write_advice(out, recs, cal_source):
    rows, md = [], ["# Advice: which structure, predicted before tracing\n",
                    f"Calibration: `{cal_source}`. Each candidate at its best predicted setting; ratios to Embree's "
                    "predicted time (bvh's prediction times the calibrated Embree / bvh).\n"]
    for scene, w in cells(recs):
        mine = [r for r in recs if r["scene"] == scene and r["workload"] == w]
        md += [f"## {scene} / {w}\n", "| rank | structure | setting | predicted x Embree | ns per ray | dominant term "
               "| build ms | bytes per primitive |", "|---:|---|---|---:|---:|---|---:|---:|"]
        for i, r in enumerate(mine, 1):
            rows.append([scene, w, i, r["accel"], r["setting"], r["ns"], r["ratio"], r["term"], r["share"],
                         r["build_ms"], r["bytes_per_prim"]])
            md.append(f"| {i} | {r['accel']} | {r['setting']} | {fmt(r['ratio'])} | {fmt(r['ns'])} | {r['term']} "
                      f"({fmt(100 * r['share'], 2)} %) | {fmt(r['build_ms'])} | {fmt(r['bytes_per_prim'])} |")
        md.append("")
    common.write_csv(os.path.join(out, "advice.csv"), ADVICE_COLS, rows, lambda v: fmt(v, 6))
    common.write_text(os.path.join(out, "advice.md"), "\n".join(md))


def check(args, recs):
    """Measure each cell's candidates at their advised settings; returns the exit status of the first failing run."""
    for scene, w in cells(recs):
        mine = [r for r in recs if r["scene"] == scene and r["workload"] == w]
        argv = [args.accelbench, "run", "--scenes", scene, "--accels", ",".join(r["label"] for r in mine),
                "--workloads", w, "--res", args.res, "--repeat", args.repeat, "--seed", args.seed, "--threads", "1",
                "--no-plots", "--out", os.path.join(args.out, "check")]
        rc = common.run_child(argv, args.quiet)
        if rc != 0:
            print(f"{PROG}: the measuring run of {scene} / {w} failed (exit {rc}); run the same "
                  "command again to resume", file=sys.stderr)
            return rc
    return 0


def calibration_scenes(folder):
    """The scenes the calibration was fitted on (its calibration_cells.csv), or an empty set."""
    path = os.path.join(folder, "calibration_cells.csv")
    return {r["scene"] for r in common.load_rows(path, ("scene",))} if os.path.isfile(path) else set()


def regret_table(recs, measured, calibrated=frozenset()):
    """Per cell: the advised and the measured best, over all candidates and over the survey's structures alone;
    whether the scene was one the calibration was fitted on."""
    out = []
    for scene, w in cells(recs):
        mine = [r for r in recs if r["scene"] == scene and r["workload"] == w]
        got = {}
        for r in mine:
            key = r.get("params_full")
            for m in measured:
                if m["scene"] == scene and m["workload"] == w and m["accel"] == r["accel"] and m["params"] == key:
                    got[r["accel"]] = num(m["ratio_vs_embree"])
        rec = {"scene": scene, "workload": w, "calibration_scene": int(scene in calibrated)}
        for tag, pool in (("", mine), ("survey_", [r for r in mine if r["accel"] not in OWN])):
            pool = [r for r in pool if got.get(r["accel"])]
            if not pool:
                continue
            advised = pool[0]
            best = min(pool, key=lambda r: got[r["accel"]])
            rec.update({tag + "advised": advised["accel"], tag + "advised_ratio": got[advised["accel"]],
                        tag + "best": best["accel"], tag + "best_ratio": got[best["accel"]],
                        tag + "regret": got[advised["accel"]] / got[best["accel"]]})
            if tag == "" and len(pool) >= 2:
                rec["rank_corr"] = predict.spearman([r["ns"] for r in pool], [got[r["accel"]] for r in pool])
        out.append(rec)
    return out


REGRET_COLS = ["scene", "workload", "calibration_scene", "advised", "advised_ratio", "best", "best_ratio", "regret", "survey_advised",
               "survey_advised_ratio", "survey_best", "survey_best_ratio", "survey_regret", "rank_corr"]


def summary(table, tag):
    reg = [t[tag + "regret"] for t in table if t.get(tag + "regret")]
    if not reg:
        return None
    return {"cells": len(reg), "within": sum(r <= WITHIN for r in reg) / len(reg), "median": statistics.median(reg),
            "worst": max(reg), "gm": common.geomean(reg)}


def write_regret(out, table):
    common.write_csv(os.path.join(out, "regret.csv"), REGRET_COLS, [[t.get(c) for c in REGRET_COLS] for t in table],
                     lambda v: fmt(v, 6))
    md = ["# Advice checked: regret of the advised choice\n",
          "Regret: the advised first choice's measured ratio to Embree over the measured best's (1 = the best was "
          "advised). Goal: within 10 % of the best in at least 80 % of the cells.\n",
          "| candidates | cells | within 10 % | median regret | geometric mean | worst |", "|---|---:|---:|---:|---:|---:|"]
    lines = []
    held = [t for t in table if not t["calibration_scene"]]
    groups = [("", "all", table), ("survey_", "the survey's structures (bvh left out)", table)]
    if len(held) < len(table):
        groups += [("", "all, scenes not calibrated on", held),
                   ("survey_", "the survey's structures, scenes not calibrated on", held)]
    for tag, name, rows in groups:
        s = summary(rows, tag)
        if s:
            md.append(f"| {name} | {s['cells']} | {fmt(100 * s['within'], 3)} % | {fmt(s['median'])} | "
                      f"{fmt(s['gm'])} | {fmt(s['worst'])} |")
            lines.append(f"{name}: advised within 10 % of the measured best in {fmt(100 * s['within'], 3)} % of "
                         f"{s['cells']} cells (median regret {fmt(s['median'])}, worst {fmt(s['worst'])})")
    corr = [t["rank_corr"] for t in table if t.get("rank_corr") is not None]
    if corr:
        md.append(f"\nRank correlation of predicted and measured times per cell: median {fmt(statistics.median(corr))}"
                  f" over {len(corr)} cells.\n")
    md += ["## Per cell\n", "Scenes the calibration was fitted on are marked *.\n",
           "| scene | workload | advised | x Embree | best | x Embree | regret | survey: advised | best "
           "| regret | rank corr. |", "|---|---|---|---:|---|---:|---:|---|---|---:|---:|"]
    for t in table:
        md.append(f"| {t['scene']}{' *' if t['calibration_scene'] else ''} | {t['workload']} | {t.get('advised', '')} | {fmt(t.get('advised_ratio'))} | "
                  f"{t.get('best', '')} | {fmt(t.get('best_ratio'))} | {fmt(t.get('regret'))} | "
                  f"{t.get('survey_advised', '')} | {t.get('survey_best', '')} | {fmt(t.get('survey_regret'))} | "
                  f"{fmt(t.get('rank_corr'))} |")
    common.write_text(os.path.join(out, "regret.md"), "\n".join(md) + "\n")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", metavar="DIR", help="the folder with predictions.csv; the tables are written there")
    ap.add_argument("--calibration", required=True, metavar="DIR", help="a folder `accelbench calibrate` wrote")
    ap.add_argument("--workloads", required=True)
    ap.add_argument("--accelbench", help="the binary --check runs")
    ap.add_argument("--res", default="64x64")
    ap.add_argument("--repeat", default="3")
    ap.add_argument("--seed", default="1")
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--no-check", dest="check", action="store_false")
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    common.PROG = PROG
    preds = common.load_rows(os.path.join(args.out, "predictions.csv"),
                             ("scene", "prims", "accel", "label", "params", "key", "value", "candidate", "build_ms",
                              "mem_bytes"))
    costs, scales = load_calibration(args.calibration)
    workloads = [w for w in args.workloads.split(",") if w]
    kind_costs = load_kind_costs(args.calibration)
    kinds = common.scene_kinds(args.accelbench, list(dict.fromkeys(p["scene"] for p in preds))) \
        if kind_costs and args.accelbench else {}
    recs = rank(preds, costs, scales, workloads, kind_costs, kinds)
    if not recs:
        common.fail(f"{args.calibration}: calibrates none of the candidates built (run `accelbench calibrate`)")
    params_of = {(p["scene"], p["label"]): p["params"] for p in preds}
    for r in recs:
        r["params_full"] = params_of[(r["scene"], r["label"])]
    write_advice(args.out, recs, args.calibration)
    print_ranking(recs, args.calibration)
    if not args.check:
        if not args.quiet:
            print(f"wrote {os.path.join(args.out, 'advice.csv')}\nwrote {os.path.join(args.out, 'advice.md')}")
        return 0
    rc = check(args, recs)
    if rc:
        return rc
    measured = common.dedup_rows(common.load_rows(os.path.join(args.out, "check", "matrix.csv"),
                                                  ("scene", "accel", "params", "workload", "ratio_vs_embree")),
                                 os.path.join(args.out, "check", "matrix.csv"))
    for line in write_regret(args.out, regret_table(recs, measured, calibration_scenes(args.calibration))):
        print(line)
    if not args.quiet:
        for f in ("advice.csv", "advice.md", "regret.csv", "regret.md"):
            print(f"wrote {os.path.join(args.out, f)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
