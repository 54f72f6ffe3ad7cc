#!/usr/bin/python3
"""From counters to time: what a box test, a primitive test and a traversal step cost on this machine.

For each accelerator configuration of a run folder's matrix.csv, the trace
time per ray of each cell (scene x workload; read through its pairing: its
ratio to Embree times the cell's median Embree time, so that a load that
slowed one row and its paired Embree samples does not move it) is fitted by
least squares,
with every cost kept at or above 0, as
    ns per ray = fixed + box_ns * box tests + test_ns * primitive tests + step_ns * steps
(the counters per ray the walks measured; a counter the structure does not
count, or one the same in every cell, is left out of its fit and its cost
blank: a constant counter cannot be told from the fixed cost). A primitive
test is the same code whichever structure calls it (prims/), so where the
run has exhaustive's cells every structure but bvh (whose leaves test in
SIMD code of their own) is given exhaustive's fitted cost of a test and
only its other costs are fitted: fitted freely, tests and steps that rise
together trade their costs, and the costs do not carry to other scenes.
Written:
  calibration.csv        one row per configuration: the machine (cpu, isa,
                         threads), the costs in ns, the cells, R^2, the
                         median and largest |relative error| of the fit, and
                         the median |relative error| held out by scene (each
                         scene's cells predicted from costs fitted without
                         that scene): how well counters times costs explain
                         time on a scene the fit has not seen;
  calibration_cells.csv  per cell: measured and fitted ns per ray, the
                         relative error, and the held-out prediction;
  calibration.md         the same as tables;
  calibration_kinds.csv  what one primitive test of each kind (triangle,
                         sphere, cone, polygon) costs, from exhaustive's
                         cells: each cell's tests split by the scene's
                         shares of the kinds (`accelbench scene info`), the
                         costs fitted by least squares; a structure given
                         the shared cost of a test pays its scene's mix at
                         these prices;
  calibration_workloads.csv  per configuration and workload: for each
                         counter, the median over the cells of measured /
                         predicted (its own cost-model prediction, or the
                         predicted steps, tests or box tests, in that order,
                         where the model predicts no such counter), and the
                         median of Embree's time over the configuration's:
                         what `accelbench advise` turns a prediction into
                         counters, and counters into a ratio to Embree, with.
A configuration with fewer cells than costs + 1 is listed without a fit.
The CSV's counters do not split tests by kind: the cost of a test by kind
comes from exhaustive's cells and the scenes' shares of the kinds. Exit status 2
on bad input (one line naming it)."""
import argparse
import os
import statistics
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot as common  # noqa: E402

PROG = "calibrate.py"
TERMS = (("box_ns", "box_tests_per_ray"), ("test_ns", "tests_per_ray"), ("step_ns", "steps_per_ray"))
REQUIRED = ("scene", "accel", "params", "workload", "threads", "rays", "trace_ms") + tuple(c for _, c in TERMS)
num = common.num


def nonneg_lstsq(X, y):
    """Least squares with every coefficient >= 0 (Lawson and Hanson's active set, by elimination: fit,
    drop the most negative coefficient's column, refit, until none is negative). Returns the coefficients."""
    n = X.shape[1]
    active = list(range(n))
    while active:
        coef, *_ = np.linalg.lstsq(X[:, active], y, rcond=None)
        if (coef >= 0).all():
            out = np.zeros(n)
            out[active] = coef
            return out
        del active[int(np.argmin(coef))]
    return np.zeros(n)


def fit(cells, terms, given=None, intercept=True):
    """cells: [(scene, workload, {column: value}, ns)]; given: {cost name: a value, or a function of the scene}
    held fixed; intercept False holds the fixed cost at 0. Returns (coefficients [fixed] + terms, a given cost's
    its median over the cells; the fitted ns list; a function from a cell to its fitted ns)."""
    given = given or {}

    def held(n, c):
        return given[n](c[0]) if callable(given[n]) else given[n]

    free = [(n, col) for n, col in terms if n not in given]
    X = np.array([[1.0] * intercept + [c[2][col] for _, col in free] for c in cells])
    y = np.array([c[3] - sum(held(n, c) * c[2][col] for n, col in terms if n in given) for c in cells])
    part = iter(nonneg_lstsq(X, y))
    fixed = next(part) if intercept else 0.0
    costs = {n: next(part) for n, _ in free}

    def predict(c):
        return fixed + sum((held(n, c) if n in given else costs[n]) * c[2][col] for n, col in terms)

    coef = [fixed] + [statistics.median(held(n, c) for c in cells) if n in given else costs[n] for n, _ in terms]
    return coef, [predict(c) for c in cells], predict


def r_squared(y, yhat):
    mean = statistics.fmean(y)
    tot = sum((v - mean) ** 2 for v in y)
    res = sum((a - b) ** 2 for a, b in zip(y, yhat))
    return 1.0 - res / tot if tot > 0 else None


def cells_of(rows):
    """Per configuration, its cells with a time and every counter it counts."""
    out = {}
    paired = common.paired_ns_per_ray(rows)
    for i, r in enumerate(rows):
        ns = paired[i]
        vals = {col: num(r.get(col)) for _, col in TERMS}
        if ns is None or ns <= 0 or all(v is None for v in vals.values()):
            continue
        out.setdefault(common.config_key(r), []).append((r["scene"], r["workload"], vals, ns))
    return out


# The structures whose primitive tests are not the shared ones (prims/): bvh tests its leaves in SIMD code of
# its own. Every other structure's primitive test costs what exhaustive's does.
OWN_TESTS = ("bvh",)
SHARED_TEST = "exhaustive"


def shared_cells(all_cells, without=None):
    """exhaustive's cells (without scene `without`) with their tests counted, or []."""
    for cfg, cells in all_cells.items():
        if cfg[0] == SHARED_TEST:
            cells = [c for c in cells if c[0] != without and c[2]["tests_per_ray"] is not None]
            return cells if len(cells) >= 3 else []
    return []


def kind_costs(all_cells, kinds, without=None):
    """What one primitive test of each kind costs, from exhaustive's cells: ns per ray = the sum over kinds of
    cost x tests x the kind's share of the scene's primitives (least squares, costs >= 0; no fixed cost, which
    beside a test of every primitive is nothing and would take a kind's share). ({kind: ns}, R^2, cells), or None
    when a scene's kinds are unknown or the cells are too few for the kinds present."""
    cells = shared_cells(all_cells, without)
    if not cells or any(c[0] not in kinds for c in cells):
        return None
    present = [k for k in common.PRIM_KINDS if any(kinds[c[0]][k] for c in cells)]
    if len(cells) < len(present) + 1:
        return None
    share = {sc: {k: kinds[sc][k] / max(1, sum(kinds[sc].values())) for k in present} for sc in {c[0] for c in cells}}
    split = [(c[0], c[1], {k: c[2]["tests_per_ray"] * share[c[0]][k] for k in present}, c[3]) for c in cells]
    coef, fitted, _ = fit(split, [(k, k) for k in present], intercept=False)
    return dict(zip(present, coef[1:])), r_squared([c[3] for c in cells], fitted), len(cells)


def test_cost(all_cells, kinds=None, without=None):
    """What one shared primitive test costs, and the prices by kind it came from (kind_costs, or None): a function
    of the scene, the scene's mix at those prices (where every kind it holds has one), else exhaustive's cost of
    the calibration's mix; (None, None) without exhaustive's cells."""
    cells = shared_cells(all_cells, without)
    if not cells:
        return None, None
    coef, _, _ = fit(cells, [("test_ns", "tests_per_ray")])
    mix = coef[1] or None
    by_kind = kind_costs(all_cells, kinds or {}, without)
    if not by_kind:
        return mix, None

    def of_scene(scene):
        priced = common.mix_cost(by_kind[0], (kinds or {}).get(scene))
        return mix if priced is None else priced
    return of_scene, by_kind


def calibrate(rows, kinds=None):
    """(per-configuration results, per-cell rows, the prices of a test by kind as kind_costs gives them or None);
    kinds: {scene: {kind: count}} where known."""
    results, per_cell = [], []
    all_cells = cells_of(rows)
    shared, by_kind = test_cost(all_cells, kinds)
    held_cost = {}  # the shared test's cost without each scene, for the held-out fits of every configuration
    for cfg, cells in all_cells.items():
        # the counters this structure counts, present in every cell; one the same in every cell (lightbuf's
        # one cell read per query) cannot be told from the fixed cost and folds into it
        terms = [(name, col) for name, col in TERMS
                 if all(c[2][col] is not None for c in cells) and len({c[2][col] for c in cells}) > 1]
        res = {"config": cfg, "cells": len(cells), "terms": [n for n, _ in terms]}
        results.append(res)
        # a structure testing through the shared primitive code is given exhaustive's cost of a test: fitted
        # freely, tests and steps that rise together trade their costs (a grid's tests came out at a quarter
        # of exhaustive's), and the costs would not carry to other scenes
        uses_shared = cfg[0] not in OWN_TESTS + (SHARED_TEST,) and any(n == "test_ns" for n, _ in terms)
        given = {"test_ns": shared} if uses_shared and shared else {}
        res["test_from"] = (("exhaustive by kind" if callable(shared) else SHARED_TEST) if given
                            else "fit" if any(n == "test_ns" for n, _ in terms) else "")
        if len(cells) < len(terms) - len(given) + 2:
            continue
        coef, fitted, _ = fit(cells, terms, given)
        y = [c[3] for c in cells]
        errs = [abs(f - m) / m for f, m in zip(fitted, y)]
        res.update(fixed_ns=coef[0], r2=r_squared(y, fitted), median_err=statistics.median(errs), max_err=max(errs))
        for (name, _), v in zip(terms, coef[1:]):
            res[name] = v
        # held out by scene: each scene's cells from the costs of the others (exhaustive's too)
        held = [None] * len(cells)
        scenes = list(dict.fromkeys(c[0] for c in cells))
        if len(scenes) >= 3:
            for s in scenes:
                train = [c for c in cells if c[0] != s]
                if len(train) < len(terms) - len(given) + 2:
                    continue
                if given and s not in held_cost:
                    held_cost[s] = test_cost(all_cells, kinds, s)[0] or shared
                g = {"test_ns": held_cost[s]} if given else {}
                _, _, predict = fit(train, terms, g)
                for i, c in enumerate(cells):
                    if c[0] == s:
                        held[i] = predict(c)
            herr = [abs(h - m) / m for h, m in zip(held, y) if h is not None]
            res["held_out_err"] = statistics.median(herr) if herr else None
        for c, f, h in zip(cells, fitted, held):
            per_cell.append({"config": cfg, "scene": c[0], "workload": c[1], "measured_ns": c[3], "fitted_ns": f,
                             "rel_error": (f - c[3]) / c[3],
                             "held_out_ns": h, "held_out_rel_error": None if h is None else (h - c[3]) / c[3]})
    return results, per_cell, by_kind


# each counter, the predicted column of the same counter, then the others in the order a stand-in is taken
PREDICTED = {"box_tests_per_ray": "predicted_box_tests_per_ray", "tests_per_ray": "predicted_tests_per_ray",
             "steps_per_ray": "predicted_steps_per_ray"}
STAND_INS = ("predicted_steps_per_ray", "predicted_tests_per_ray", "predicted_box_tests_per_ray")


def workload_scales(rows):
    """Per (configuration, workload): {cells, embree_per_ns, and per counter column its scale and the predicted
    column it scales}. A counter scales its own prediction where every cell has it, else the first stand-in every
    cell has; a counter the configuration does not count, or a cell without a prediction, gives none."""
    groups = {}
    for r in rows:
        groups.setdefault((common.config_key(r), r["workload"]), []).append(r)
    out = {}
    for key, cells in groups.items():
        rec = {"cells": len(cells)}
        inv = [1.0 / x for x in (num(r.get("ratio_vs_embree")) for r in cells) if x]
        rec["embree_per_ns"] = statistics.median(inv) if inv else None
        for col in PREDICTED:
            for pcol in (PREDICTED[col],) + STAND_INS:
                pairs = [(num(r.get(col)), num(r.get(pcol))) for r in cells]
                if all(m is not None and p for m, p in pairs):
                    rec[col] = (statistics.median(m / p for m, p in pairs), pcol)
                    break
        out[key] = rec
    return out


fmt = common.fmt_g


def write_csv(path, header, records):
    common.write_csv(path, header, records, lambda v: fmt(v, 9))


def main(argv=None):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", metavar="RUN_DIR", help="a run folder (its matrix.csv) or a matrix.csv")
    ap.add_argument("--out", metavar="DIR", help="where to write calibration.{csv,md} (default: the run folder)")
    ap.add_argument("--isa", default="", help="the SIMD instruction set the machine's kernels use (the key's second part)")
    ap.add_argument("--accelbench", metavar="BIN", help="the binary whose `list accels` gives the labels' defaults")
    ap.add_argument("--quiet", action="store_true", help="do not list the files written")
    args = ap.parse_args(argv)
    common.PROG = PROG
    csv_path, rows, out, labels = common.run_folder_rows(args.run, args.out, REQUIRED, args.accelbench)
    kinds = common.scene_kinds(args.accelbench, list(dict.fromkeys(r["scene"] for r in rows))) \
        if args.accelbench else {}
    results, per_cell, by_kind = calibrate(rows, kinds)
    cpu, threads = common.column_values(rows, "cpu"), common.column_values(rows, "threads")
    names = [n for n, _ in TERMS]
    header = ["cpu", "isa", "threads", "configuration", "accel", "params", "cells", "fixed_ns"] + names + [
        "r2", "median_abs_rel_error", "max_abs_rel_error", "held_out_median_abs_rel_error", "test_ns_from"]
    recs = []
    for r in results:
        cfg = r["config"]
        recs.append([cpu, args.isa, cfg[2], labels[cfg], cfg[0], cfg[1], r["cells"], r.get("fixed_ns")] +
                    [r.get(n) if n in r["terms"] else None for n in names] +
                    [r.get("r2"), r.get("median_err"), r.get("max_err"), r.get("held_out_err"), r.get("test_from")])
    written = []
    path = os.path.join(out, "calibration.csv")
    write_csv(path, header, recs)
    written.append(path)
    path = os.path.join(out, "calibration_cells.csv")
    write_csv(path, ["configuration", "scene", "workload", "measured_ns", "fitted_ns", "rel_error", "held_out_ns",
                     "held_out_rel_error"],
              [[labels[c["config"]], c["scene"], c["workload"], c["measured_ns"], c["fitted_ns"], c["rel_error"],
                c["held_out_ns"], c["held_out_rel_error"]] for c in per_cell])
    written.append(path)
    md = [f"# Calibration: what each counter costs on {cpu} ({args.isa or 'isa not stated'}, {threads} thread(s))\n",
          f"From `{csv_path}`. ns per ray = fixed + box_ns x box tests + test_ns x primitive tests + step_ns x "
          "steps, least squares with every cost >= 0, per configuration over its cells; held out: each scene's "
          "cells predicted from the costs fitted on the other scenes.\n",
          "| configuration | cells | fixed ns | box test ns | test ns | step ns | R^2 | median \\|rel. error\\| | "
          "largest | held out | test cost from |", "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for r, rec in zip(results, recs):
        md.append("| " + " | ".join([rec[3], str(rec[6])] + [fmt(v) for v in rec[7:11]] +
                                    [fmt(v, 2) if v is not None else "" for v in rec[11:15]] + [rec[15] or ""]) + " |")
    if by_kind:
        md.append("\nA primitive test by kind (exhaustive's cells, each test of a scene's mix split by its shares of "
                  f"the kinds; R^2 {fmt(by_kind[1], 2)}): " +
                  ", ".join(f"{k} {fmt(v)} ns" for k, v in by_kind[0].items()) + ".")
    path = os.path.join(out, "calibration.md")
    common.write_text(path, "\n".join(md) + "\n")
    written.append(path)
    path = os.path.join(out, "calibration_kinds.csv")
    write_csv(path, ["cpu", "isa", "kind", "test_ns", "cells", "r2"],
              [[cpu, args.isa, k, v, by_kind[2], by_kind[1]] for k, v in by_kind[0].items()] if by_kind else [])
    written.append(path)
    scales = workload_scales(rows)
    path = os.path.join(out, "calibration_workloads.csv")
    cols = list(PREDICTED)
    write_csv(path, ["configuration", "accel", "params", "workload", "cells", "embree_per_ns"] +
              [x for c in cols for x in (c.replace("_per_ray", "_scale"), c.replace("_per_ray", "_from"))],
              [[labels[cfg], cfg[0], cfg[1], w, rec["cells"], rec["embree_per_ns"]] +
               [x for c in cols for x in (rec[c] if c in rec else (None, None))]
               for (cfg, w), rec in scales.items()])
    written.append(path)
    if not args.quiet:
        for p in written:
            print(f"wrote {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
