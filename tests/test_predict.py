#!/usr/bin/python3
"""test_predict.py: scripts/predict.py (`accelbench predict`) on a constructed matrix.csv and on a real run.

Constructed: two configurations over four scenes and two workloads, with
predicted and measured counters chosen so that
  - ranks() gives tied values their mean rank;
  - Spearman's of 1,3,2,4 against 1,2,3,4 is 0.8 (1 - 6 * 2 / (4 * 15));
  - grid's predicted tests on primary rank 1,3,2,4 and its measured ones
    1.5,3,1.5,4 (a tie): the Pearson correlation of those ranks,
    recomputed here;
  - its median relative error and measured/predicted ratio are
    recomputed here;
  - a constant side (bsp's box tests, one per ray) has no rank correlation;
  - a counter with no prediction (grid's box tests on shadow) has no row;
  - Embree's rows (no counters) are left out;
  - the time correlations follow the sums of the predicted and measured
    counters (computed by hand: 0.8 and 0.8 for grid, -1 for bsp).
Then `accelbench predict` on a small real run (grid, bsp, bvh, lightbuf on
two SPD scenes): exit 0, the four files, a row for every counter each
structure predicts; and bad input (no folder, a folder with no
matrix.csv, --out to a missing folder, an unknown option) exits 2 with one
line; and the run folder's report, with prediction.csv written into it,
shows the cost-model table. Prints "N passed, N failed"; exits 1 on a failure."""
import csv
import math
import os
import statistics
import subprocess
import sys
import tempfile

SRC = os.environ.get("SRCDIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(SRC, "scripts"))
import predict  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pycheck import check, report as report_checks  # noqa: E402

ACCELBENCH = os.environ.get("ACCELBENCH", os.path.join(SRC, "build", "harness", "accelbench"))

# --- ranks and Spearman
check(predict.ranks([10, 20, 20, 30]) == [1.0, 2.5, 2.5, 4.0], f"ties: {predict.ranks([10, 20, 20, 30])}")
check(abs(predict.spearman([1, 3, 2, 4], [1, 2, 3, 4]) - 0.8) < 1e-12, "spearman 0.8")
check(abs(predict.spearman([1, 2, 3, 4], [40, 30, 20, 10]) + 1.0) < 1e-12, "spearman -1")
check(predict.spearman([1, 2], [1, 2]) is None, "under 3 pairs")
check(predict.spearman([1, 2, 3], [5, 5, 5]) is None, "a constant side")

# --- a constructed run
COLS = ["scene", "prims", "accel", "params", "workload", "rays", "threads", "trace_ms", "tests_per_ray",
        "box_tests_per_ray", "steps_per_ray", "predicted_tests_per_ray", "predicted_box_tests_per_ray",
        "predicted_steps_per_ray", "cell_key"]
SCENES = ["s1", "s2", "s3", "s4"]
# grid primary: predicted tests 1,3,2,4 (times 10), measured 20,40,20,60 (rank 1.5,3,1.5,4)
GRID_P = [10, 30, 20, 40]
GRID_M = [20, 40, 20, 60]
rows = []


def row(scene, accel, params, workload, trace_ms, m, p):
    keys = ("tests_per_ray", "box_tests_per_ray", "steps_per_ray")
    r = {"scene": scene, "prims": "100", "accel": accel, "params": params, "workload": workload, "rays": "1000",
         "threads": "1", "trace_ms": repr(trace_ms), "cell_key": f"{scene} {accel} {params} {workload}"}
    for k, mv, pv in zip(keys, m, p):
        r[k] = "" if mv is None else repr(mv)
        r["predicted_" + k] = "" if pv is None else repr(pv)
    return r


for i, s in enumerate(SCENES):
    rows.append(row(s, "embree", "quality=medium", "primary", 1.0, (None,) * 3, (None,) * 3))
    rows.append(row(s, "grid", "res=auto", "primary", 1.0 + i, (GRID_M[i], 1, 5 + i), (GRID_P[i], 1, 6 + i)))
    rows.append(row(s, "grid", "res=auto", "shadow", 1.0 + i, (GRID_M[i], 1, 5 + i), (GRID_P[i], None, 6 + i)))
    rows.append(row(s, "bsp", "split=sah", "primary", 4.0 - i, (5 + i, 1, 9 - i), (4 + i, 1, 8 + i)))
tmp = tempfile.mkdtemp(prefix="accelbench-predict.")
path = os.path.join(tmp, "matrix.csv")
with open(path, "w", newline="") as f:
    w = csv.DictWriter(f, COLS)
    w.writeheader()
    w.writerows(rows)
check(predict.main([tmp, "--quiet"]) == 0, "predict.py on the constructed run")
for name in ("prediction.csv", "prediction_time.csv", "prediction.md", "prediction.png"):
    check(os.path.getsize(os.path.join(tmp, name)) > 0, f"{name} written")
with open(os.path.join(tmp, "prediction.csv"), newline="") as f:
    acc = list(csv.DictReader(f))
with open(os.path.join(tmp, "prediction_time.csv"), newline="") as f:
    timing = list(csv.DictReader(f))


def find(table, **kw):
    got = [r for r in table if all(r[k] == v for k, v in kw.items())]
    return got[0] if len(got) == 1 else None


g = find(acc, accel="grid", counter="tests", workload="primary")
check(g is not None and g["cells"] == "4", f"grid tests primary: {g}")
# The textbook Spearman of the ranks (ties averaged): Pearson of [1,3,2,4] and [1.5,3,1.5,4].
rx, ry = [1, 3, 2, 4], [1.5, 3, 1.5, 4]
mx, my = sum(rx) / 4, sum(ry) / 4
want = sum((a - mx) * (b - my) for a, b in zip(rx, ry)) / math.sqrt(
    sum((a - mx) ** 2 for a in rx) * sum((b - my) ** 2 for b in ry))
check(g is not None and abs(float(g["rank_corr"]) - want) < 1e-4, f"rank corr {g and g['rank_corr']}, want {want}")
err = statistics.median(abs(p - m) / m for p, m in zip(GRID_P, GRID_M))
ratio = statistics.median(m / p for p, m in zip(GRID_P, GRID_M))
check(g is not None and abs(float(g["median_abs_rel_error"]) - err) < 1e-4, f"rel. error {g}, want {err}")
check(g is not None and abs(float(g["median_measured_over_predicted"]) - ratio) < 1e-4, f"ratio {g}, want {ratio}")
allg = find(acc, accel="grid", counter="tests", workload="all")
check(allg is not None and allg["cells"] == "8", f"grid tests over all workloads: {allg}")
b = find(acc, accel="bsp", counter="box_tests", workload="primary")
check(b is not None and b["rank_corr"] == "" and float(b["median_abs_rel_error"]) == 0.0, f"bsp box tests: {b}")
check(find(acc, accel="grid", counter="box_tests", workload="shadow") is None, "no prediction: no row")
check(not any(r["accel"] == "embree" for r in acc + timing), "embree left out")
t = find(timing, accel="grid", workload="primary")
# work sums: predicted 17, 38, 29, 50 and measured 26, 47, 28, 69 (ranks 1, 3, 2, 4 both) against times 1..4
check(t is not None and float(t["rank_corr_time_measured"]) == 0.8 and float(t["rank_corr_time_predicted"]) == 0.8,
      f"grid time correlations: {t}")
t = find(timing, accel="bsp", workload="primary")
check(t is not None and float(t["rank_corr_time_predicted"]) == -1.0, f"bsp time against predicted work: {t}")
md = open(os.path.join(tmp, "prediction.md")).read()
check(f"| primary | 4 | {want:.2f} | {err:.2f} | {ratio:.2f} |" in md, "the Markdown table row")

# --- the command on a real run
run = os.path.join(tmp, "run")
p = subprocess.run([ACCELBENCH, "run", "--scenes", "spd:tetra:3,spd:balls:1", "--accels", "grid,bsp,bvh,lightbuf",
                    "--workloads", "shadow,random", "--res", "16x16", "--repeat", "1", "--out", run, "--no-plots"],
                   capture_output=True, text=True)
check(p.returncode == 0, f"the run: exit {p.returncode} {p.stderr[-300:]}")
out = os.path.join(tmp, "pred")
os.mkdir(out)
p = subprocess.run([ACCELBENCH, "predict", run, "--out", out], capture_output=True, text=True)
check(p.returncode == 0 and p.stdout.count("wrote ") == 4, f"accelbench predict: exit {p.returncode}: {p.stdout}{p.stderr}")
with open(os.path.join(out, "prediction.csv"), newline="") as f:
    acc = list(csv.DictReader(f))
for accel, counters in (("grid", ("tests", "box_tests", "steps")), ("bsp", ("tests", "box_tests", "steps")),
                        ("bvh", ("tests", "box_tests", "steps")), ("lightbuf", ("tests", "steps"))):
    for c in counters:
        r = find(acc, configuration=accel, counter=c, workload="all")
        check(r is not None and int(r["cells"]) >= 2, f"{accel} {c}: {r}")

# the report of a folder that holds prediction.csv shows the models section
p = subprocess.run([ACCELBENCH, "predict", run, "--quiet", "--no-plot"], capture_output=True, text=True)
p = subprocess.run([ACCELBENCH, "report", run, "--pictures", "off", "--quiet"], capture_output=True, text=True)
page = open(os.path.join(run, "report.html"), encoding="utf-8").read() if p.returncode == 0 else ""
check("<h3>Cost models" in page and '<td class="t">bvh</td>' in page, f"the report's cost-model table: exit {p.returncode}")

for argv, what in (([os.path.join(tmp, "nope")], "no folder"), ([out], "no matrix.csv"),
                   ([run, "--out", os.path.join(tmp, "nope")], "--out missing"), ([run, "--bogus"], "unknown option")):
    p = subprocess.run([ACCELBENCH, "predict"] + argv, capture_output=True, text=True)
    check(p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1, f"{what}: exit {p.returncode}: {p.stderr}")

report_checks()
