#!/usr/bin/python3
"""test_advise.py: `accelbench advise` (scripts/advise.py) and the calibration's per-workload scales it reads.

  - calibrate.workload_scales on constructed rows: the median of measured
    over predicted per counter, the predicted steps standing in where the
    model predicts no such counter, none where a cell lacks a prediction,
    and the median of Embree's time over the configuration's;
  - predict_ns by hand: fixed + cost x scale x prediction per term, a
    primitive test priced at nothing costing exhaustive's (not for bvh),
    an uncalibrated workload taking the median scale of the others;
  - rank() on constructed predictions: each candidate at the value of the
    lowest predicted time (a synthetic cost lowest at a known value), the
    ranking in order of predicted time, the light buffer on shadow rays
    only, the ratio to Embree bvh's prediction times the calibrated
    Embree / bvh;
  - regret_table: the regret of the advised choice, and the survey's
    structures' without bvh;
  - the command: a small calibration (`accelbench run` on four tiny SPD
    scenes, then `accelbench calibrate --from`), then `advise spd:balls:2
    --check` with three candidates: exit 0, every value of grid's search
    predicted, a ranking per workload, each candidate measured at its
    advised setting in check/matrix.csv, a regret >= 1 per cell;
  - bad input (no SCENE, an unknown accelerator or workload, a missing
    calibration, two scenes as two operands) exits 2 with one line.
Prints "N passed, N failed"; exits 1 on a failure."""
import os
import subprocess
import sys
import tempfile

SRC = os.environ.get("SRCDIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(SRC, "scripts"))
import advise  # noqa: E402
import calibrate  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pycheck import check, close, report as report_checks  # noqa: E402

ACCELBENCH = os.environ.get("ACCELBENCH", os.path.join(SRC, "build", "harness", "accelbench"))


# --- calibrate.workload_scales
def row(scene, workload, accel, params, **cols):
    r = {"scene": scene, "workload": workload, "accel": accel, "params": params, "threads": "1"}
    r.update({k: repr(v) if v is not None else "" for k, v in cols.items()})
    return r


rows = [row("a", "primary", "grid", "res=cubic:20", tests_per_ray=2.0, steps_per_ray=10.0, box_tests_per_ray=1.0,
            predicted_tests_per_ray=4.0, predicted_steps_per_ray=5.0, ratio_vs_embree=4.0),
        row("b", "primary", "grid", "res=cubic:20", tests_per_ray=3.0, steps_per_ray=30.0, box_tests_per_ray=1.0,
            predicted_tests_per_ray=3.0, predicted_steps_per_ray=10.0, ratio_vs_embree=2.0),
        row("c", "primary", "grid", "res=cubic:20", tests_per_ray=9.0, steps_per_ray=8.0, box_tests_per_ray=1.0,
            predicted_tests_per_ray=3.0, predicted_steps_per_ray=8.0, ratio_vs_embree=5.0),
        row("a", "primary", "octree", "maxdepth=6", tests_per_ray=2.0, steps_per_ray=4.0,
            predicted_tests_per_ray=None, predicted_steps_per_ray=2.0, ratio_vs_embree=8.0)]
sc = calibrate.workload_scales(rows)
g = next(v for (cfg, w), v in sc.items() if cfg[0] == "grid" and w == "primary")
check(g["cells"] == 3 and close(g["tests_per_ray"][0], 1.0) and g["tests_per_ray"][1] == "predicted_tests_per_ray",
      f"grid's tests: median of 0.5, 1, 3: {g.get('tests_per_ray')}")
check(close(g["steps_per_ray"][0], 2.0), f"grid's steps: median of 2, 3, 1: {g.get('steps_per_ray')}")
check(g["box_tests_per_ray"][1] == "predicted_steps_per_ray" and close(g["box_tests_per_ray"][0], 0.125),
      f"box tests scale the predicted steps (median of 0.2, 0.1, 0.125): {g.get('box_tests_per_ray')}")
check(close(g["embree_per_ns"], 0.25), f"Embree / grid: median of 1/4, 1/2, 1/5: {g.get('embree_per_ns')}")
o = next(v for (cfg, w), v in sc.items() if cfg[0] == "octree")
check(o["tests_per_ray"] == (1.0, "predicted_steps_per_ray") and "box_tests_per_ray" not in o,
      f"octree: tests from steps, no box tests counted: {o}")

# --- predict_ns by hand
cal = {"configuration": "grid", "fixed_ns": "10", "box_ns": "2", "test_ns": "0", "step_ns": "3"}
scales = {("grid", "primary"): {"embree_per_ns": "0.5", "box_tests_scale": "0.5", "box_tests_from": "predicted_steps_per_ray",
                                "tests_scale": "2", "tests_from": "predicted_tests_per_ray",
                                "steps_scale": "1.5", "steps_from": "predicted_steps_per_ray"},
          ("grid", "shadow"): {"embree_per_ns": "0.25", "box_tests_scale": "1.5", "box_tests_from": "predicted_steps_per_ray",
                               "tests_scale": "4", "tests_from": "predicted_tests_per_ray",
                               "steps_scale": "2.5", "steps_from": "predicted_steps_per_ray"}}
pred = {"accel": "grid", "predicted_tests_per_ray": "3", "predicted_steps_per_ray": "4",
        "predicted_box_tests_per_ray": ""}
ns, terms = advise.predict_ns(pred, cal, scales, "primary")
check(close(ns, 10 + 2 * 0.5 * 4 + 3 * 1.5 * 4), f"no floor: 10 + 4 + 18 = 32: {ns} {terms}")
ns, terms = advise.predict_ns(pred, cal, scales, "primary", floor=5.0)
check(close(ns, 32 + 5 * 2 * 3) and close(terms["primitive tests"], 30), f"tests at the floor: 62: {ns} {terms}")
ns, _ = advise.predict_ns(dict(pred, accel="bvh"), cal, scales, "primary", floor=5.0)
check(close(ns, 32), f"bvh's tests keep their own (zero) cost: {ns}")
ns, _ = advise.predict_ns(pred, cal, scales, "random")
check(close(ns, 10 + 2 * 1.0 * 4 + 3 * 2.0 * 4), f"an uncalibrated workload takes the median scales: {ns}")
check(close(advise.mix_cost({"triangles": 10.0, "spheres": 2.0}, {"triangles": 3, "spheres": 1, "cones": 0}), 8.0) and
      advise.mix_cost({"triangles": 10.0}, {"triangles": 3, "cones": 1}) is None, "a scene's mix at the prices by kind")
ns, terms = advise.predict_ns(pred, dict(cal, test_ns="14", test_ns_from="exhaustive by kind"), scales, "primary",
                              scene_test=8.0)
check(close(terms["primitive tests"], 8.0 * 2 * 3), f"a structure priced by exhaustive pays the scene's mix: {terms}")
check(advise.predict_ns({"accel": "grid", "predicted_tests_per_ray": "3"}, cal, scales, "primary") is None,
      "a term without its prediction: no time")

# --- rank(): a synthetic cost lowest at a known value
costs = {"grid": [{"accel": "grid", "params": "res=cubic:20", "configuration": "grid", "fixed_ns": "0", "box_ns": "",
                   "test_ns": "1", "step_ns": "1"}],
         "bvh": [{"accel": "bvh", "params": "leafsize=4", "configuration": "bvh", "fixed_ns": "10", "box_ns": "",
                  "test_ns": "", "step_ns": "1"}],
         "lightbuf": [{"accel": "lightbuf", "params": "res=auto", "configuration": "lightbuf", "fixed_ns": "1",
                       "box_ns": "", "test_ns": "1", "step_ns": ""}]}
one = {"tests_scale": "1", "tests_from": "predicted_tests_per_ray", "steps_scale": "1",
       "steps_from": "predicted_steps_per_ray", "box_tests_scale": "", "box_tests_from": ""}
scales = {(c, w): dict(one, embree_per_ns="0.5") for c in costs for w in ("primary", "shadow")}
preds = []


def p(accel, label, params, key, value, tests, steps, candidate="1"):
    preds.append({"scene": "s", "prims": "100", "accel": accel, "label": label, "params": params, "key": key,
                  "value": value, "candidate": candidate, "build_ms": "1", "mem_bytes": "800",
                  "predicted_tests_per_ray": repr(tests), "predicted_steps_per_ray": repr(steps)})


for d in (5, 10, 20, 40):  # tests + steps = 400 / d + d: lowest at d = 20 (40)
    p("grid", "grid" if d == 20 else f"grid[res=cubic:{d}]", f"res=cubic:{d}", "res", f"cubic:{d}", 400 / d, d)
p("bvh", "bvh", "leafsize=4", "leafsize", "4", 0, 20)            # 10 + 20 = 30
p("lightbuf", "lightbuf", "res=auto", "res", "auto", 3, 0)        # 1 + 3 = 4
got = advise.rank(preds, costs, scales, ["primary", "shadow"])
prim = [r for r in got if r["workload"] == "primary"]
check([r["accel"] for r in prim] == ["bvh", "grid"], f"primary: bvh (30) before grid (40), no lightbuf: {prim}")
gr = next(r for r in prim if r["accel"] == "grid")
check(gr["value"] == "cubic:20" and close(gr["ns"], 40) and close(gr["ratio"], 40 / 15),
      f"grid at its known optimum, 40 ns, ratio 40 / (30 x 0.5): {gr}")
check(close(gr["bytes_per_prim"], 8.0), f"bytes per primitive: {gr['bytes_per_prim']}")
sh = [r["accel"] for r in got if r["workload"] == "shadow"]
check(sh == ["lightbuf", "bvh", "grid"], f"shadow: lightbuf first: {sh}")

# --- regret_table
for r in got:
    r["params_full"] = next(x["params"] for x in preds if x["label"] == r["label"])
measured = [{"scene": "s", "workload": "primary", "accel": "bvh", "params": "leafsize=4", "ratio_vs_embree": "2.0"},
            {"scene": "s", "workload": "primary", "accel": "grid", "params": "res=cubic:20", "ratio_vs_embree": "1.6"},
            {"scene": "s", "workload": "shadow", "accel": "lightbuf", "params": "res=auto", "ratio_vs_embree": "3"},
            {"scene": "s", "workload": "shadow", "accel": "bvh", "params": "leafsize=4", "ratio_vs_embree": "1.5"},
            {"scene": "s", "workload": "shadow", "accel": "grid", "params": "res=cubic:20", "ratio_vs_embree": "6"}]
tab = {t["workload"]: t for t in advise.regret_table(got, measured)}
check(close(tab["primary"]["regret"], 1.25) and tab["primary"]["best"] == "grid",
      f"primary: bvh advised at 2.0, grid best at 1.6: {tab['primary']}")
check(close(tab["primary"]["survey_regret"], 1.0) and tab["primary"]["survey_advised"] == "grid",
      f"survey alone: grid advised and best: {tab['primary']}")
check(close(tab["shadow"]["regret"], 2.0) and close(tab["shadow"]["survey_regret"], 1.0),
      f"shadow: lightbuf 3 against bvh 1.5; lightbuf best of the survey's: {tab['shadow']}")
check(tab["primary"]["calibration_scene"] == 0 and
      advise.regret_table(got, measured, {"s"})[0]["calibration_scene"] == 1, "a calibration scene is marked")
s = advise.summary(list(tab.values()), "")
check(s["cells"] == 2 and s["within"] == 0.0 and close(s["worst"], 2.0), f"summary: {s}")


# --- the command
def run(args, **kw):
    return subprocess.run([ACCELBENCH] + args, capture_output=True, text=True, **kw)


with tempfile.TemporaryDirectory() as tmp:
    calrun, caldir, out = (os.path.join(tmp, x) for x in ("calrun", "cal", "out"))
    r = run(["run", "--scenes", "spd:balls:1,spd:gears:2,spd:tetra:3,spd:mount:3", "--accels",
             "exhaustive,grid,bvh,lightbuf", "--workloads", "primary,shadow", "--res", "16x16", "--repeat", "1",
             "--threads", "1", "--no-plots", "--out", calrun])
    check(r.returncode == 0, f"the calibration run: {r.returncode} {r.stderr[-300:]}")
    r = run(["calibrate", "--from", calrun, "--out", caldir, "--quiet"])
    check(r.returncode == 0 and os.path.isfile(os.path.join(caldir, "calibration_workloads.csv")),
          f"calibrate --from: {r.returncode} {r.stderr[-300:]}")
    r = run(["advise", "spd:balls:2", "--accels", "grid,bvh,lightbuf", "--workloads", "primary,shadow",
             "--calibration", caldir, "--check", "--res", "16x16", "--repeat", "1", "--out", out, "--quiet"])
    check(r.returncode == 0, f"advise --check: {r.returncode} {r.stderr[-400:]}")
    if r.returncode == 0:
        pr = advise.common.load_rows(os.path.join(out, "predictions.csv"), ("accel", "value"))
        grid_values = {x["value"] for x in pr if x["accel"] == "grid"}
        check(grid_values == {"auto", "cubic:5", "cubic:10", "cubic:20", "cubic:40", "cubic:80"},
              f"every value of grid's search predicted: {grid_values}")
        check(all(x["predicted_tests_per_ray"] for x in pr), "every build has a prediction")
        adv = advise.common.load_rows(os.path.join(out, "advice.csv"), ("workload", "rank", "accel"))
        check({x["accel"] for x in adv if x["workload"] == "primary"} == {"grid", "bvh"} and
              {x["accel"] for x in adv if x["workload"] == "shadow"} == {"grid", "bvh", "lightbuf"},
              f"the ranking's candidates per workload: {[(x['workload'], x['accel']) for x in adv]}")
        check("spd:balls:2 / shadow:" in r.stdout and "1. " in r.stdout, f"the ranking printed: {r.stdout[:300]}")
        m = advise.common.load_rows(os.path.join(out, "check", "matrix.csv"), ("accel", "params", "workload"))
        for x in adv:
            label = next(q["label"] for q in pr if q["accel"] == x["accel"] and
                         (x["setting"] == "default" or x["setting"] == f"{q['key']}={q['value']}"))
            params = next(q["params"] for q in pr if q["label"] == label)
            check(any(y["accel"] == x["accel"] and y["params"] == params and y["workload"] == x["workload"] for y in m),
                  f"{x['accel']} {x['setting']} measured on {x['workload']}")
        reg = advise.common.load_rows(os.path.join(out, "regret.csv"), ("workload", "regret"))
        check(len(reg) == 2 and all(float(x["regret"]) >= 1.0 for x in reg), f"a regret >= 1 per cell: {reg}")
        check("within 10 %" in r.stdout, f"the summary printed: {r.stdout[-300:]}")
    for args, what in ((["advise"], "no SCENE"),
                       (["advise", "spd:balls:1", "--accels", "nosuch", "--calibration", caldir], "unknown accel"),
                       (["advise", "spd:balls:1", "--workloads", "sideways", "--calibration", caldir], "unknown workload"),
                       (["advise", "spd:balls:1", "--calibration", os.path.join(tmp, "none")], "no calibration"),
                       (["advise", "spd:balls:1", "spd:balls:2", "--calibration", caldir], "two operands"),
                       (["advise", "spd:balls:1", "--accels", "grid[res=auto]", "--calibration", caldir], "parameters"),
                       (["advise", "nosuchscene", "--calibration", caldir], "unknown scene")):
        r = run(args + ["--out", os.path.join(tmp, "bad")])
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 2 and len(lines) == 1, f"{what}: exit {r.returncode}, {lines}")

sys.exit(report_checks())
