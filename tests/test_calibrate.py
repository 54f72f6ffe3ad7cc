#!/usr/bin/python3
"""test_calibrate.py: scripts/calibrate.py (`accelbench calibrate`) recovers known costs from synthetic counters and times.

A constructed matrix.csv of three configurations over five scenes and two
workloads, with counters drawn from a seeded generator and times made from
known costs:
  - "grid": ns = 7 + 2 box + 11 tests + 3 steps, exactly: the fit recovers
    every cost within 1e-6 relative, R^2 = 1, every error and the held-out
    error ~0;
  - "bsp": the same with +-5 % noise from the generator: the costs within
    15 %, R^2 > 0.95;
  - "octree": a time that falls with box tests (ns = 50 + 9 tests - 1 box):
    the unconstrained fit's negative box cost is held at 0 and the others
    refitted (the constrained optimum, checked against a brute-force search
    over the box cost at 0);
  - "lightbuf": no box-test column (empty) and one step in every cell:
    both costs are left out (a constant counter is the fixed cost);
  - "bvh": 3 cells for 4 costs: listed without a fit;
  - with exhaustive in the run, grid is given its cost of a primitive test
    and its other costs recovered exactly, bvh keeps its own;
  - by kind: prices of a triangle, sphere and cone test recovered exactly
    from exhaustive's cells on scenes of known mixes, and a grid given each
    scene's mix at those prices with its other costs recovered;
  - Embree's rows are left out;
  - a time read through its pairing (plot.paired_ns_per_ray): a row whose
    time and paired Embree time a load doubled reads as its ratio times
    the cell's median Embree time, the undisturbed one; a row without a
    ratio keeps its own time.
Then `accelbench calibrate --from` on that folder writes the three files
and keys them by cpu and isa, and bad input (--from a missing folder,
--threads 0, an unknown option, a stray argument) exits 2 with one line.
Last, `calibrate --quick` measures its matrix here and fits at least 8
configurations.
Prints "N passed, N failed"; exits 1 on a failure."""
import csv
import os
import random
import subprocess
import sys
import tempfile

import numpy as np

SRC = os.environ.get("SRCDIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(SRC, "scripts"))
import calibrate  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pycheck import check, report as report_checks  # noqa: E402

ACCELBENCH = os.environ.get("ACCELBENCH", os.path.join(SRC, "build", "harness", "accelbench"))
COLS = ["scene", "prims", "accel", "params", "workload", "rays", "threads", "trace_ms", "tests_per_ray",
        "box_tests_per_ray", "steps_per_ray", "cell_key", "cpu"]
rng = random.Random(20261207)
rows = []


def add(accel, scene, workload, box, tests, steps, ns):
    rays = 1000
    rows.append({"scene": scene, "prims": "100", "accel": accel, "params": "p=1", "workload": workload,
                 "rays": str(rays), "threads": "1", "trace_ms": repr(ns * rays / 1e6),
                 "tests_per_ray": "" if tests is None else repr(tests), "box_tests_per_ray": "" if box is None else repr(box),
                 "steps_per_ray": "" if steps is None else repr(steps), "cell_key": f"{scene} {accel} {workload}",
                 "cpu": "Test CPU x1"})


octree = []
for s in range(5):
    for w in ("primary", "random"):
        scene = f"spd:s{s}"
        box, tests, steps = rng.uniform(5, 60), rng.uniform(1, 30), rng.uniform(3, 40)
        add("grid", scene, w, box, tests, steps, 7 + 2 * box + 11 * tests + 3 * steps)
        b2, t2, s2 = rng.uniform(5, 60), rng.uniform(1, 30), rng.uniform(3, 40)
        add("bsp", scene, w, b2, t2, s2, (7 + 2 * b2 + 11 * t2 + 3 * s2) * rng.uniform(0.95, 1.05))
        b3, t3, s3 = rng.uniform(5, 60), rng.uniform(1, 30), rng.uniform(3, 40)
        add("octree", scene, w, b3, t3, s3, 50 + 9 * t3 - 1 * b3 + 100)
        octree.append((b3, t3, s3, 150 + 9 * t3 - b3))
        t4 = rng.uniform(1, 30)
        add("lightbuf", scene, w, None, t4, 1.0, 20 + 5 * t4)
        add("embree", scene, w, None, None, None, 10)
for s in range(3):
    add("bvh", f"spd:s{s}", "primary", 10, 2, 5, 40)
tmp = tempfile.mkdtemp(prefix="accelbench-calibrate.")
with open(os.path.join(tmp, "matrix.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, COLS)
    w.writeheader()
    w.writerows(rows)

check(calibrate.main([tmp, "--isa", "testisa", "--quiet"]) == 0, "calibrate.py on the constructed run")
with open(os.path.join(tmp, "calibration.csv"), newline="") as f:
    res = {r["accel"]: r for r in csv.DictReader(f)}


def close(got, want, rel):
    return got != "" and abs(float(got) - want) <= rel * abs(want)


g = res.get("grid", {})
check(all(close(g.get(k, ""), v, 1e-6) for k, v in (("fixed_ns", 7), ("box_ns", 2), ("test_ns", 11), ("step_ns", 3))),
      f"grid's exact costs: {g}")
check(close(g.get("r2", ""), 1.0, 1e-9) and float(g.get("median_abs_rel_error", 1)) < 1e-6
      and float(g.get("held_out_median_abs_rel_error", 1)) < 1e-6, f"grid's exact fit: {g}")
check(g.get("cpu") == "Test CPU x1" and g.get("isa") == "testisa" and g.get("cells") == "10", f"grid's key: {g}")
b = res.get("bsp", {})
check(all(close(b.get(k, ""), v, 0.15) for k, v in (("box_ns", 2), ("test_ns", 11), ("step_ns", 3)))
      and float(b.get("r2", 0)) > 0.95, f"bsp with 5 % noise: {b}")
o = res.get("octree", {})
check(o.get("box_ns") not in ("",) and float(o["box_ns"]) == 0.0, f"octree's negative box cost held at 0: {o}")
# the constrained optimum with box at 0: ordinary least squares on the other terms, which must match
X = np.array([[1.0, t, s] for _, t, s, _ in octree])
y = np.array([ns for *_, ns in octree])
want, *_ = np.linalg.lstsq(X, y, rcond=None)
check((want >= 0).all() and close(o.get("fixed_ns", ""), want[0], 1e-6) and close(o.get("test_ns", ""), want[1], 1e-6),
      f"octree refit: {o}, want {want}")
lb = res.get("lightbuf", {})
check(lb.get("box_ns") == "" and lb.get("step_ns") == "" and close(lb.get("test_ns", ""), 5, 1e-6) and close(lb.get("fixed_ns", ""), 20, 1e-6),
      f"lightbuf without box tests: {lb}")
bv = res.get("bvh", {})
check(bv.get("cells") == "3" and bv.get("r2") == "" and bv.get("test_ns") == "", f"bvh, too few cells: {bv}")
check("embree" not in res, "embree left out")
with open(os.path.join(tmp, "calibration_cells.csv"), newline="") as f:
    cells = list(csv.DictReader(f))
check(sum(1 for c in cells if c["configuration"].startswith("grid")) == 10, "grid's ten cells listed")
check(g.get("test_ns_from") == "fit", f"no exhaustive in the run: grid's test cost fitted: {g.get('test_ns_from')}")

# --- the shared primitive test: with exhaustive in the run (19 ns a test), grid is given 19 ns and its other costs
# fitted (recovered exactly); a grid whose tests and steps rise together would trade their costs if fitted freely;
# bvh keeps its own
rows.clear()
rng2 = random.Random(7)
for s in range(6):
    for w in ("primary", "diffuse"):
        scene = f"spd:s{s}"
        n = rng2.uniform(50, 500)
        add("exhaustive", scene, w, None, n, None, 19 * n)
        t = rng2.uniform(1, 30)
        st = 2 * t + rng2.uniform(0, 1)
        add("grid", scene, w, rng2.uniform(1, 9), t, st, 40 + 19 * t + 5 * st)
        b, t2 = rng2.uniform(5, 60), rng2.uniform(1, 9)
        add("bvh", scene, w, b, t2, b / 3, 10 + 3 * b + 2 * t2)
tmp2 = tempfile.mkdtemp(prefix="accelbench-calibrate.")
with open(os.path.join(tmp2, "matrix.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, COLS)
    w.writeheader()
    w.writerows(rows)
check(calibrate.main([tmp2, "--quiet"]) == 0, "calibrate.py on the run with exhaustive")
with open(os.path.join(tmp2, "calibration.csv"), newline="") as f:
    res2 = {r["accel"]: r for r in csv.DictReader(f)}
g2, e2, b2 = res2.get("grid", {}), res2.get("exhaustive", {}), res2.get("bvh", {})
check(close(e2.get("test_ns", ""), 19, 1e-9) and e2.get("test_ns_from") == "fit", f"exhaustive's test: {e2}")
check(g2.get("test_ns_from") == "exhaustive" and close(g2.get("test_ns", ""), 19, 1e-9) and
      close(g2.get("step_ns", ""), 5, 1e-6) and close(g2.get("fixed_ns", ""), 40, 1e-6), f"grid given 19 ns: {g2}")
check(b2.get("test_ns_from") == "fit" and close(b2.get("test_ns", ""), 2, 1e-6), f"bvh's own tests: {b2}")

# --- by kind: exhaustive's scenes of known mixes (triangles 12 ns, spheres 4, cones 30) recovered exactly; a grid
# on those scenes pays each scene's mix at those prices and its step cost is recovered exactly
rows.clear()
kinds = {"t": {"triangles": 100, "spheres": 0, "cones": 0, "polygons": 0},
         "s": {"triangles": 0, "spheres": 100, "cones": 0, "polygons": 0},
         "m": {"triangles": 50, "spheres": 25, "cones": 25, "polygons": 0},
         "c": {"triangles": 0, "spheres": 40, "cones": 60, "polygons": 0}}
price = {"triangles": 12.0, "spheres": 4.0, "cones": 30.0}
mix = {sc: sum(price[k] * n for k, n in kd.items() if n) / sum(kd.values()) for sc, kd in kinds.items()}
for sc in kinds:
    for w in ("primary", "shadow"):
        t = rng2.uniform(20, 100)
        add("exhaustive", sc, w, None, t, None, mix[sc] * t)
        t2 = rng2.uniform(1, 9)
        st = rng2.uniform(3, 30)
        add("grid", sc, w, 1.0, t2, st, 25 + mix[sc] * t2 + 6 * st)
cells = calibrate.cells_of(rows)
kc = calibrate.kind_costs(cells, kinds)
check(kc is not None and all(close(repr(kc[0][k]), v, 1e-6) for k, v in price.items()) and "polygons" not in kc[0],
      f"prices by kind recovered, polygons absent: {kc}")
res3 = {r["config"][0]: r for r in calibrate.calibrate(rows, kinds)[0]}
g3 = res3.get("grid", {})
check(g3.get("test_from") == "exhaustive by kind" and close(repr(g3.get("step_ns")), 6, 1e-6) and
      close(repr(g3.get("fixed_ns")), 25, 1e-6), f"grid at each scene's mix: {g3}")
check(calibrate.kind_costs(cells, {"t": kinds["t"]}) is None, "a scene of unknown kinds: no prices")

# --- times read through their pairing with Embree
import plot  # noqa: E402
cell = {"scene": "s", "workload": "primary", "rays": "1000", "threads": "1"}
paired = [dict(cell, trace_ms="2", embree_ms="1", ratio_vs_embree="2"),   # 2000 ns, Embree 1000
          dict(cell, trace_ms="3", embree_ms="1", ratio_vs_embree="3"),
          dict(cell, trace_ms="8", embree_ms="2", ratio_vs_embree="4"),   # both doubled by a load
          dict(cell, trace_ms="5", embree_ms="", ratio_vs_embree=""),
          dict(cell, scene="t", trace_ms="1", embree_ms="4", ratio_vs_embree="0.25")]
got = plot.paired_ns_per_ray(paired)
check(got == [2000.0, 3000.0, 4000.0, 5000.0, 1000.0], f"paired times: {got}")

# --- the command
out = os.path.join(tmp, "cal")
p = subprocess.run([ACCELBENCH, "calibrate", "--from", tmp, "--out", out], capture_output=True, text=True)
check(p.returncode == 0 and all(os.path.isfile(os.path.join(out, n)) for n in
                                ("calibration.csv", "calibration_cells.csv", "calibration.md"))
      and not os.path.exists(os.path.join(out, "run")), f"calibrate --from: exit {p.returncode}: {p.stderr}")
with open(os.path.join(out, "calibration.csv"), newline="") as f:
    isa = {r["isa"] for r in csv.DictReader(f)}
check(len(isa) == 1 and next(iter(isa)) in ("scalar", "sse42", "avx2", "avx512"), f"the machine's isa: {isa}")
for argv, what in ((["--from", os.path.join(tmp, "nope")], "--from missing"), (["--threads", "0"], "--threads 0"),
                   (["--bogus"], "unknown option"), (["stray"], "a stray argument")):
    p = subprocess.run([ACCELBENCH, "calibrate", "--out", os.path.join(tmp, "bad")] + argv, capture_output=True,
                       text=True)
    check(p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1, f"{what}: exit {p.returncode}: {p.stderr}")

# --- the whole command on this machine (about 10 s)
out = os.path.join(tmp, "quick")
p = subprocess.run([ACCELBENCH, "calibrate", "--quick", "--out", out, "--quiet"], capture_output=True, text=True)
check(p.returncode == 0 and os.path.isfile(os.path.join(out, "run", "matrix.csv")), f"calibrate --quick: {p.stderr}")
with open(os.path.join(out, "calibration.csv"), newline="") as f:
    fitted = [r for r in csv.DictReader(f) if r["r2"]]
check(len(fitted) >= 8, f"calibrate --quick fitted {len(fitted)} configurations")

report_checks()
