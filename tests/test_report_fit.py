#!/usr/bin/python3
"""test_report_fit.py: scripts/report.py's cost-growth fits on synthetic CSV rows with known exponents.

Writes a matrix.csv of two SPD families at five sizes (and a scene that is no
series), two accelerators and two workloads, where trace time per ray, tests
per ray, build time and memory grow as known powers of the primitive count
(times a deterministic +-3% wiggle), reads it back through plot.py's loader
and checks that report.scaling_fits recovers every exponent within 0.03 with
a 95% interval that contains it and is narrower than 0.2; that exact data
gives the exponent to 1e-9 with an empty interval; that fewer than three
sizes give no fit; and that family names follow spd:NAME:N[:t]. Prints
"N passed, N failed"; exits 1 on a failure."""
import csv
import math
import os
import sys
import tempfile

SRC = os.environ.get("SRCDIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(SRC, "scripts"))
import plot  # noqa: E402
import report  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pycheck import check, report as report_checks  # noqa: E402



# (accel, params, workload) -> exponents of time per ray, tests per ray; build and memory per accel
TRUE = {("grid", "res=auto"): {"primary": (0.31, 0.25), "shadow": (0.42, 0.36), "build": 1.05, "memory": 0.93},
        ("bvh", "isa=scalar"): {"primary": (0.12, 0.08), "shadow": (0.18, 0.11), "build": 1.21, "memory": 1.0}}
SIZES = {"balls": [11, 92, 821, 7382, 66431], "tetra-t": [256, 1024, 4096, 16384, 65536]}
SCENE = {"balls": "spd:balls:{i}", "tetra-t": "spd:tetra:{i}:t"}
COLS = ["scene", "prims", "accel", "params", "workload", "rays", "threads", "trace_ms", "mrays_per_s",
        "tests_per_ray", "build_ms", "mem_bytes", "cell_key"]


def wiggle(i, j):
    return 1.0 + 0.03 * math.sin(1.7 * i + 0.9 * j + 0.4)


def rows(noisy=True):
    out = []
    for fam, sizes in SIZES.items():
        for i, n in enumerate(sizes):
            scene = SCENE[fam].format(i=i + 1)
            for j, ((accel, params), e) in enumerate(TRUE.items()):
                for k, wl in enumerate(("primary", "shadow")):
                    w = (lambda a: wiggle(i, j + 3 * k + a)) if noisy else (lambda a: 1.0)
                    rays = 4096 if wl == "primary" else 3000 + 10 * i
                    ns = 50.0 * n ** e[wl][0] * w(0)
                    out.append({"scene": scene, "prims": str(n), "accel": accel, "params": params, "workload": wl,
                                "rays": str(rays), "threads": "1", "trace_ms": repr(ns * rays / 1e6),
                                "mrays_per_s": "1", "tests_per_ray": repr(3.0 * n ** e[wl][1] * w(1)),
                                "build_ms": repr(0.001 * n ** e["build"] * w(2)),
                                "mem_bytes": repr(40.0 * n ** e["memory"] * w(3)),
                                "cell_key": f"scene={scene} accel={accel} params={params} workload={wl}"})
    # not a series: a mesh, and a family of two sizes
    for scene, n in (("bunny", 69451), ("spd:gears:2", 1169), ("spd:gears:3", 3500)):
        out.append({"scene": scene, "prims": str(n), "accel": "grid", "params": "res=auto", "workload": "primary",
                    "rays": "4096", "threads": "1", "trace_ms": "1", "mrays_per_s": "1", "tests_per_ray": "5",
                    "build_ms": "1", "mem_bytes": "100", "cell_key": f"scene={scene} accel=grid"})
    return out


def write(path, data):
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, COLS)
        w.writeheader()
        w.writerows(data)


def fits_of(data):
    tmp = tempfile.mkdtemp(prefix="accelbench-fit.")
    path = os.path.join(tmp, "matrix.csv")
    write(path, data)
    loaded = plot.load_rows(path)
    labels = plot.config_labels(loaded, defaults={"grid": {"res": "auto"}, "bvh": {"isa": "auto"}})
    return report.scaling_fits(loaded, labels)


fits = fits_of(rows())
check(sorted(fits) == ["balls", "tetra-t"], f"families fitted: {sorted(fits)} (want balls, tetra-t; no gears, no bunny)")
LABEL = {("grid", "res=auto"): "grid", ("bvh", "isa=scalar"): "bvh[isa=scalar]"}
for fam in SIZES:
    f = fits.get(fam, {}).get("fits", {})
    for cfg, e in TRUE.items():
        want = {("time", "primary"): e["primary"][0], ("tests", "primary"): e["primary"][1],
                ("time", "shadow"): e["shadow"][0], ("tests", "shadow"): e["shadow"][1],
                ("build", None): e["build"], ("memory", None): e["memory"]}
        for (metric, wl), k in want.items():
            got = f.get((metric, LABEL[cfg], wl))
            if not got:
                check(False, f"{fam} {LABEL[cfg]} {metric} {wl}: no fit")
                continue
            check(abs(got["k"] - k) < 0.03, f"{fam} {LABEL[cfg]} {metric} {wl}: k {got['k']:.4f}, want {k}")
            check(got["lo"] < k < got["hi"], f"{fam} {LABEL[cfg]} {metric} {wl}: {k} outside [{got['lo']:.4f}, {got['hi']:.4f}]")
            check(got["hi"] - got["lo"] < 0.2, f"{fam} {LABEL[cfg]} {metric} {wl}: interval {got['hi'] - got['lo']:.3f} wide")
            check(got["n"] == 5, f"{fam} {LABEL[cfg]} {metric} {wl}: {got['n']} points")

# exact power laws: the exponent to rounding, an interval of width ~0
exact = fits_of(rows(noisy=False))["balls"]["fits"][("time", "grid", "primary")]
check(abs(exact["k"] - 0.31) < 1e-9 and exact["hi"] - exact["lo"] < 1e-6, f"exact data: {exact}")

# fit_power: fewer than three distinct sizes is no fit; the interval uses t on n - 2 degrees of freedom
check(report.fit_power([10, 100], [1, 2]) is None, "two sizes gave a fit")
check(report.fit_power([10, 10, 10], [1, 2, 3]) is None, "one size three times gave a fit")
three = report.fit_power([10, 100, 1000], [1.0, 2.2, 3.9])
check(three is not None and three["hi"] - three["lo"] > 2 * (report.t975(1) - 1) * 0.01, f"three points: {three}")
check(abs(report.t975(1) - 12.706) < 0.01 and abs(report.t975(10) - 2.228) < 0.005 and 1.95 < report.t975(1000) < 1.97,
      "t quantiles")

# sentences: one per accelerator, with the exponent and its interval
sent = report.sentences(fits["balls"], ["grid", "bvh[isa=scalar]"], ["primary", "shadow"])
check(len(sent) == 2 and sent[0].startswith("grid: primary trace time per ray grows as N^0.3"), f"sentences: {sent}")

# family names
for scene, fam in (("spd:balls:3", "balls"), ("spd:balls:3:t", "balls-t"), ("spd:balls:3:t5", "balls-t5"),
                   ("bunny", None), ("spd:balls", None), ("spd:balls:3@eye=1,2,3", None)):
    check(report.family_of(scene) == fam, f"family_of({scene}) = {report.family_of(scene)}, want {fam}")

report_checks()
