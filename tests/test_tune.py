#!/usr/bin/python3
"""test_tune.py: scripts/tune.py (`accelbench tune`): the search's declaration, its choice, and the command.

  - parse_tune_specs reads the "tune:" lines of `accelbench list accels`
    and finds one for every accelerator that declares a search (grid,
    grid-raybox, octree, bsp, slabs-kk, raycls, lightbuf, bvh, raycoh),
    none for exhaustive, embree, bvh-gs and cgal-aabb;
  - split_list keeps the commas inside an instance's brackets;
  - choose() on constructed training rows picks the known optimum of a
    synthetic cost (a ratio that is lowest at one value), prefers the
    default on a tie, and sums the training cells and their build and
    trace time;
  - the command on spd:balls:1 (grid, lightbuf and exhaustive, shadow
    rays, 16x16):
    exit 0; every value of both searches in training/matrix.csv; a
    tuning.csv row per structure whose chosen value is one of its search's
    and whose tuned ratio is the chosen setting's measured row; the default
    and the chosen setting measured in matrix.csv;
  - per_value's one value for every scene: the synthetic optimum, over the
    cells where every value was traced, and tuning_values.csv from the
    command with every value of grid's search;
  - the folder's report shows a tuning table with both structures;
  - bad input (no --scenes, a malformed --res, --repeat 0, an unknown
    option) exits 2 with one line.
Prints "N passed, N failed"; exits 1 on a failure."""
import csv
import os
import subprocess
import sys
import tempfile

SRC = os.environ.get("SRCDIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(SRC, "scripts"))
import tune  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pycheck import check, report as report_checks  # noqa: E402

ACCELBENCH = os.environ.get("ACCELBENCH", os.path.join(SRC, "build", "harness", "accelbench"))

listing = subprocess.run([ACCELBENCH, "list", "accels"], capture_output=True, text=True).stdout
specs = tune.parse_tune_specs(listing)
defaults = tune.common.parse_accel_defaults(listing)
want = {"grid", "grid-raybox", "octree", "bsp", "slabs-kk", "raycls", "lightbuf", "bvh", "raycoh"}
check(set(specs) == want, f"accelerators with a search: {sorted(specs)}")
check(specs.get("grid", ("", []))[0] == "res" and "cubic:20" in specs["grid"][1], f"grid's search: {specs.get('grid')}")

check(tune.split_list("grid,bsp[maxdepth=12,maxprims=1|2],bvh") == ["grid", "bsp[maxdepth=12,maxprims=1|2]", "bvh"],
      "split_list keeps bracketed commas")

# a synthetic cost: ratio (v - 40)^2 / 100 + 1 over grid's cubic:D, lowest at D = 40
rows = []
for d in (5, 10, 20, 40, 80):
    rows.append({"scene": "s", "workload": "primary", "accel": "grid", "params": f"res=cubic:{d},mailbox=on",
                 "ratio_vs_embree": repr((d - 40) ** 2 / 100 + 1), "build_ms": "2", "trace_ms": "3"})
# a tie between the default (cubic:20) and cubic:5 on shadow: the default stays
for d, r in ((5, 1.5), (20, 1.5), (80, 2.0)):
    rows.append({"scene": "s", "workload": "shadow", "accel": "grid", "params": f"res=cubic:{d},mailbox=on",
                 "ratio_vs_embree": repr(r), "build_ms": "1", "trace_ms": "1"})
rows.append({"scene": "s", "workload": "primary", "accel": "exhaustive", "params": "", "ratio_vs_embree": "9",
             "build_ms": "0", "trace_ms": "9"})
got = tune.choose(rows, {"grid": ("res", ["cubic:5", "cubic:10", "cubic:20", "cubic:40", "cubic:80"])},
                  {"grid": {"res": "cubic:20", "mailbox": "on"}})
check(got.get(("s", "primary", "grid")) == ("cubic:40", "cubic:20", 5, 25.0), f"the optimum: {got}")
check(got.get(("s", "shadow", "grid")) == ("cubic:20", "cubic:20", 3, 6.0), f"a tie keeps the default: {got}")
check(not any(k[2] == "exhaustive" for k in got), "an accelerator without a search is not chosen for")

# one value for every scene: the geometric mean over the cells where every value was traced (shadow lacks
# cubic:10 and cubic:40, so primary alone counts): lowest at cubic:40, ratio 1
vals = tune.per_value(rows, {"grid": ("res", ["cubic:5", "cubic:10", "cubic:20", "cubic:40", "cubic:80"])})
by = {v["value"]: v for v in vals}
check(len(vals) == 5 and all(v["cells"] == 1 for v in vals), f"per_value: the complete cells only: {vals}")
check(abs(by["cubic:40"]["gm"] - 1.0) < 1e-12 and abs(by["cubic:5"]["gm"] - 13.25) < 1e-12 and
      min(vals, key=lambda v: v["gm"])["value"] == "cubic:40", f"per_value: the synthetic optimum: {vals}")

tmp = tempfile.mkdtemp(prefix="accelbench-tune.")
out = os.path.join(tmp, "t")
p = subprocess.run([ACCELBENCH, "tune", "--scenes", "spd:balls:1", "--workloads", "shadow", "--accels", "grid,lightbuf,exhaustive",
                    "--res", "16x16", "--repeat", "1", "--out", out, "--quiet"], capture_output=True, text=True)
check(p.returncode == 0, f"accelbench tune: exit {p.returncode}: {p.stderr[-400:]}")


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


training = read(os.path.join(out, "training", "matrix.csv")) if p.returncode == 0 else []
for a in ("grid", "lightbuf"):
    key, values = specs[a]
    seen = {tune.param_of(r["params"], key) for r in training if r["accel"] == a}
    check(seen == set(values), f"{a}: training traced {sorted(seen)}, want {sorted(values)}")
table = read(os.path.join(out, "tuning.csv")) if p.returncode == 0 else []
measured = read(os.path.join(out, "matrix.csv")) if p.returncode == 0 else []
for a in ("grid", "lightbuf"):
    key, values = specs[a]
    r = [x for x in table if x["accel"] == a]
    check(len(r) == 1 and r[0]["tuned"] in values and r[0]["default"] == defaults[a][key], f"{a}: tuning row {r}")
    if len(r) != 1:
        continue
    mine = [m for m in measured if m["accel"] == a]
    tuned_rows = [m for m in mine if tune.param_of(m["params"], key) == r[0]["tuned"]]
    default_rows = [m for m in mine if tune.param_of(m["params"], key) == r[0]["default"]]
    check(len(tuned_rows) == 1 and len(default_rows) == 1, f"{a}: measured {[(m['params']) for m in mine]}")
    if tuned_rows and r[0]["tuned_ratio"]:
        check(abs(float(r[0]["tuned_ratio"]) - float(tuned_rows[0]["ratio_vs_embree"])) < 1e-4 * float(
            r[0]["tuned_ratio"]), f"{a}: tuned ratio {r[0]['tuned_ratio']} is the measured row's")
    check(int(r[0]["training_cells"]) == len(values) and float(r[0]["search_ms"]) > 0, f"{a}: search {r[0]}")
check(os.path.getsize(os.path.join(out, "tuning.md")) > 0 if p.returncode == 0 else False, "tuning.md written")
values = read(os.path.join(out, "tuning_values.csv")) if p.returncode == 0 else []
check({(v["accel"], v["value"]) for v in values} >= {("grid", x) for x in specs["grid"][1]},
      f"tuning_values.csv: every value of grid's search: {values}")
check(sum(1 for m in measured if m["accel"] == "exhaustive") == 1 and not any(x["accel"] == "exhaustive" for x in table),
      "exhaustive (no search) measured once, as given")

# the report of the folder shows the tuning table
p = subprocess.run([ACCELBENCH, "report", out, "--pictures", "off", "--quiet"], capture_output=True, text=True)
page = open(os.path.join(out, "report.html"), encoding="utf-8").read() if p.returncode == 0 else ""
check('<section id="models">' in page and "<td class=\"t\">grid</td>" in page and "<td class=\"t\">lightbuf</td>" in page,
      f"the report's tuning section: exit {p.returncode} {p.stderr[-200:]}")

for argv, what in ((["--workloads", "shadow"], "no --scenes"), (["--scenes", "spd:balls:1", "--workloads", "shadow",
                                                                   "--res", "16"], "--res 16"),
                   (["--scenes", "spd:balls:1", "--workloads", "shadow", "--repeat", "0"], "--repeat 0"),
                   (["--bogus"], "unknown option")):
    p = subprocess.run([ACCELBENCH, "tune", "--out", os.path.join(tmp, "bad")] + argv, capture_output=True, text=True)
    check(p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1, f"{what}: exit {p.returncode}: {p.stderr}")

report_checks()
