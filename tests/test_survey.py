#!/usr/bin/python3
"""test_survey.py: `accelbench reproduce survey` (scripts/survey.py).

  - geo_interval: the geometric mean and the 95 % interval of the mean of
    the logarithms against a recomputation by hand (t = 4.303 for three
    values), one value without an interval;
  - growth_exponent recovers b of time = c_w N^b exactly from constructed
    cells with one constant per workload, and gives none for one size;
  - analyse() on constructed rows: the default and tuned geometric means,
    the rays to pay for a build against exhaustive's cost per test by hand
    ("never" when not faster), bytes per primitive, diffuse over primary,
    the tuning gain, the prediction's rank correlation; findings name the
    fastest structure over the same cells and the shadow-only one apart;
  - the command on one tiny scene with four structures: exit 0, survey.csv
    with a row per structure, survey.md with the table and findings;
  - bad input (--threads, --memcap, an unknown option) exits 2 with one line.
Prints "N passed, N failed"; exits 1 on a failure."""
import math
import os
import subprocess
import sys
import tempfile

SRC = os.environ.get("SRCDIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(SRC, "scripts"))
import survey  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pycheck import check, close, report as report_checks  # noqa: E402

ACCELBENCH = os.environ.get("ACCELBENCH", os.path.join(SRC, "build", "harness", "accelbench"))


# geo_interval by hand
vals = [1.0, 2.0, 4.0]
logs = [math.log(v) for v in vals]
m = sum(logs) / 3
sd = math.sqrt(sum((x - m) ** 2 for x in logs) / 2)
g, lo, hi = survey.geo_interval(vals)
check(close(g, 2.0) and close(lo, math.exp(m - 4.303 * sd / math.sqrt(3))) and
      close(hi, math.exp(m + 4.303 * sd / math.sqrt(3))), f"geo_interval: {g} {lo} {hi}")
check(close(survey.geo_interval([3.0])[0], 3.0) and survey.geo_interval([3.0])[1:] == (None, None) and survey.geo_interval([]) is None, "one value, none")

# growth exponent: t = c_w N^0.4
cells = [(w, n, c * n ** 0.4) for w, c in (("primary", 3.0), ("diffuse", 11.0)) for n in (100, 1000, 50000)]
check(close(survey.growth_exponent(cells), 0.4, 1e-9), f"growth: {survey.growth_exponent(cells)}")
check(survey.growth_exponent([("primary", 10, 5.0), ("diffuse", 10, 7.0)]) is None, "one size: none")


# analyse on constructed rows
def row(scene, prims, accel, params, workload, ratio, ns, build_ms=1.0, mem=1000, tests=None):
    return {"scene": scene, "prims": str(prims), "accel": accel, "params": params, "workload": workload,
            "rays": "1000", "trace_ms": repr(ns * 1000 / 1e6), "ratio_vs_embree": repr(ratio),
            "build_ms": repr(build_ms), "mem_bytes": str(mem), "tests_per_ray": "" if tests is None else repr(tests)}


rows = []
for scene, n in (("a", 1000), ("b", 8000)):
    rows += [row(scene, n, "grid", "res=cubic:20,mailbox=on", "primary", 2.0, 100.0, build_ms=2.0, mem=40 * n),
             row(scene, n, "grid", "res=cubic:20,mailbox=on", "diffuse", 8.0, 300.0, build_ms=2.0, mem=40 * n),
             row(scene, n, "grid", "res=cubic:5,mailbox=on", "primary", 1.0, 50.0),
             row(scene, n, "grid", "res=cubic:5,mailbox=on", "diffuse", 4.0, 150.0),
             row(scene, n, "lightbuf", "res=auto", "shadow", 3.0, 100.0, build_ms=5.0, mem=n)]
tuning = [{"scene": s, "workload": w, "accel": "grid", "key": "res", "tuned": "cubic:5", "gain": "2"}
          for s in ("a", "b") for w in ("primary", "diffuse")]
prediction = [{"accel": "grid", "params": "res=cubic:20,mailbox=on", "counter": "tests", "workload": "all",
               "rank_corr": "0.5"}]
defaults = {"grid": {"res": "cubic:20", "mailbox": "on"}, "lightbuf": {"res": "auto"}}
erows = [row("a", 1000, "exhaustive", "", "primary", 50.0, 2000.0, tests=1000)]
test_ns = survey.test_cost(erows)
check(close(test_ns, 2.0), f"exhaustive's cost per test: 2000 ns / 1000 tests: {test_ns}")
recs = {r["accel"]: r for r in survey.analyse(rows, tuning, prediction, defaults, test_ns)}
g = recs["grid"]
check(g["cells"] == 4 and close(g["speed"], 4.0) and close(g["speed_tuned"], 2.0) and close(g["tuning_gain"], 2.0),
      f"grid: default gm of 2, 8, 2, 8 = 4; tuned 2; gain 2: {g}")
# break-even: build 2 ms over (N x 2 ns - t): a/primary 2e6/(2000-100), a/diffuse 2e6/1700, b: 2e6/15900, 2e6/15700
even = sorted([2e6 / 1900, 2e6 / 1700, 2e6 / 15900, 2e6 / 15700])
check(close(g["break_even_rays"], (even[1] + even[2]) / 2), f"rays to pay off: {g['break_even_rays']}")
check(close(g["bytes_per_prim"], 40.0) and close(g["diffuse_over_primary"], 3.0) and g["pred_tests_corr"] == 0.5,
      f"bytes, coherence, prediction: {g}")
check(close(g["growth"], 0.0), f"grid's time does not change with N here: {g['growth']}")
slow = survey.analyse([row("a", 10, "grid", "res=cubic:20,mailbox=on", "primary", 2.0, 100.0)], [], [], defaults,
                      test_ns)
check(slow[0]["break_even_rays"] == math.inf, f"not faster than testing 10 primitives at 2 ns: never: {slow}")
lines = survey.findings(list(recs.values()))
check(any("fastest structure is grid" in x for x in lines) and any(x.startswith("lightbuf, on the shadow rays")
                                                                   for x in lines), f"findings: {lines}")
md = survey.markdown(list(recs.values()), lines, "a,b", "16x16", "1")
check("| uniform grids (s5.2) | grid | primary and diffuse rays | 4 |" in md and
      "| directional (s6) | lightbuf | shadow rays | 2 |" in md, "the table's rows: what rays each was measured on")
fam = [{"accel": "grid", "applies_to": "all rays", "speed": 3.0, "speed_tuned": 2.0},
       {"accel": "grid-raybox", "applies_to": "all rays", "speed": 2.5, "speed_tuned": 2.4},
       {"accel": "raycoh", "applies_to": "all rays", "speed": 9.0, "speed_tuned": None},
       {"accel": "lightbuf", "applies_to": "shadow rays", "speed": 1.0, "speed_tuned": 0.5}]
check([r["accel"] for r in survey.family_rows(fam)] == ["grid", "raycoh"],
      "per family: the best tuned structure over all rays (the light buffer answers shadow rays only)")

with tempfile.TemporaryDirectory() as tmp:
    out = os.path.join(tmp, "s")
    r = subprocess.run([ACCELBENCH, "reproduce", "survey", "--quick", "--scenes", "spd:balls:1", "--accels",
                        "grid,lightbuf,exhaustive,bvh-gs,embree", "--out", out, "--quiet", "--no-plots"],
                       capture_output=True, text=True)
    check(r.returncode == 0, f"reproduce survey: {r.returncode} {r.stderr[-400:]}")
    if r.returncode == 0:
        got = survey.common.load_rows(os.path.join(out, "survey.csv"), ("accel", "speed"))
        check([x["accel"] for x in got] == ["grid", "bvh-gs", "lightbuf", "exhaustive", "embree"],
              f"a row per structure, by family: {[x['accel'] for x in got]}")
        check(all(survey.num(x["speed"]) for x in got), "every structure has a speed")
        md = open(os.path.join(out, "survey.md")).read()
        check("## Findings" in md and "| family | structure |" in md, "survey.md: table and findings")
        check("finding:" in r.stdout, f"findings printed: {r.stdout[:200]}")
        check("real mismatches against Embree" in md, "survey.md states the verification")
    for args in (["--threads", "2"], ["--memcap", "100"], ["--bogus"]):
        r = subprocess.run([ACCELBENCH, "reproduce", "survey"] + args + ["--out", os.path.join(tmp, "bad")],
                           capture_output=True, text=True)
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 2 and len(lines) == 1, f"{args}: exit {r.returncode}, {lines}")

sys.exit(report_checks())
