#!/usr/bin/python3
"""test_report_findings.py: scripts/findings.py and what uses it, on a constructed matrix.csv.

The CSV has three scenes, two workloads, Embree and five other
configurations (grid twice, res swept; bsp; bvh and cgal-aabb, which the
survey's winners leave out), with ratios and min-max ranges chosen so that:
  - spd:a/primary: bsp wins, and its range overlaps grid's: a tie;
  - spd:b/primary: bsp wins by a margin: no tie;
  - spd:c/primary: bvh wins overall (not a tie), bsp wins the survey's;
  - spd:a/shadow: two configurations with equal ratios and touching ranges: a tie.
It checks: the ranking's geometric means, 95 % intervals and n against a
recomputation written here (plain math, Student's t from a table), in the
findings, in summary.py's Markdown and in the HTML; the winners and ties;
the family lines; the labelling rule (with known defaults the default
instance is the bare name, another name[the differing parameters]; without,
the instance the others add to is the bare name); params.csv; the sweep;
and that plot.py writes the per-workload heat maps, the sweep figure,
params.csv and summary.md. Prints "N passed, N failed"; exits 1 on a failure."""
import csv
import html
import math
import os
import re
import sys
import tempfile

SRC = os.environ.get("SRCDIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(SRC, "scripts"))
import plot  # noqa: E402
import findings  # noqa: E402
import summary  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pycheck import check, report as report_checks  # noqa: E402



GRID = "res=auto,mailbox=on"
GRID8 = "res=8x8x8,mailbox=on"
CONFIGS = [("grid", GRID), ("grid", GRID8), ("bsp", "split=sah"), ("bvh", "width=8"), ("cgal-aabb", "kernel=simple")]
# (scene, workload) -> {config index: (ratio, min, max)}
RATIOS = {
    ("spd:a", "primary"): {0: (0.95, 0.92, 1.10), 1: (1.40, 1.30, 1.50), 2: (0.90, 0.85, 1.00), 3: (1.10, 1.0, 1.2),
                           4: (3.0, 2.9, 3.1)},
    ("spd:b", "primary"): {0: (0.90, 0.85, 0.95), 1: (1.20, 1.10, 1.30), 2: (0.50, 0.45, 0.55), 3: (0.70, 0.6, 0.8),
                           4: (2.0, 1.9, 2.1)},
    ("spd:c", "primary"): {0: (2.00, 1.90, 2.10), 1: (1.70, 1.60, 1.80), 2: (1.20, 1.10, 1.30), 3: (0.30, 0.29, 0.31),
                           4: (4.0, 3.9, 4.1)},
    ("spd:a", "shadow"): {0: (0.80, 0.75, 0.85), 1: (0.80, 0.85, 0.90), 2: (1.50, 1.40, 1.60), 3: (2.0, 1.9, 2.1),
                          4: (5.0, 4.9, 5.1)},
    ("spd:b", "shadow"): {0: (0.60, 0.55, 0.65), 1: (0.90, 0.85, 0.95), 2: (1.10, 1.0, 1.2), 3: (2.5, 2.4, 2.6),
                          4: (6.0, 5.9, 6.1)},
}
COLS = ["scene", "prims", "accel", "params", "workload", "rays", "threads", "trace_ms", "trace_ms_min", "trace_ms_max",
        "mrays_per_s", "ratio_vs_embree", "ratio_min", "ratio_max", "tests_per_ray", "box_tests_per_ray",
        "steps_per_ray", "build_ms", "bytes_per_prim", "mismatch_real", "cell_key"]


def csv_rows():
    out = []
    for (s, w), cells in RATIOS.items():
        for i, (accel, params) in [(-1, ("embree", "quality=medium"))] + list(enumerate(CONFIGS)):
            r, lo, hi = (1.0, 1.0, 1.0) if i < 0 else cells[i]
            t = 2.0 * r
            out.append({"scene": s, "prims": "100", "accel": accel, "params": params, "workload": w, "rays": "1024",
                        "threads": "2", "trace_ms": repr(t), "trace_ms_min": repr(t * 0.9), "trace_ms_max": repr(t * 1.1),
                        "mrays_per_s": repr(1024 / t / 1000), "ratio_vs_embree": repr(r), "ratio_min": repr(lo),
                        "ratio_max": repr(hi), "tests_per_ray": "" if accel == "embree" else "3",
                        "box_tests_per_ray": "", "steps_per_ray": "", "build_ms": "1", "bytes_per_prim": "10",
                        "mismatch_real": "0", "cell_key": f"scene={s} accel={accel} params={params} workload={w}"})
    return out


tmp = tempfile.mkdtemp(prefix="accelbench-findings.")
path = os.path.join(tmp, "matrix.csv")
with open(path, "w", newline="") as f:
    w = csv.DictWriter(f, COLS)
    w.writeheader()
    w.writerows(csv_rows())

DEFAULTS = {"grid": {"res": "auto", "mailbox": "on"}, "bsp": {"split": "sah"}, "bvh": {"width": "8"},
            "cgal-aabb": {"kernel": "simple"}, "embree": {"quality": "medium"}}
rows = plot.dedup_rows(plot.load_rows(path), path)

# --- the labelling rule
labels = plot.config_labels(rows, defaults=DEFAULTS)
got = [labels[("grid", GRID, "2")], labels[("grid", GRID8, "2")], labels[("bsp", "split=sah", "2")]]
check(got == ["grid", "grid[res=8x8x8]", "bsp"], f"labels with defaults: {got}")
nodef = plot.config_labels(rows, defaults={})
got = [nodef[("grid", GRID, "2")], nodef[("grid", GRID8, "2")], nodef[("bsp", "split=sah", "2")]]
check(got == ["grid[res=auto]", "grid[res=8x8x8]", "bsp"], f"labels without defaults: {got}")
odd = plot.config_labels([{"accel": "grid", "params": "res=auto,raybox=off", "threads": "1"},
                          {"accel": "grid", "params": "res=cubic:20,raybox=off", "threads": "1"}],
                         defaults={"grid": {"res": "auto", "raybox": "off"}})
check(list(odd.values()) == ["grid", "grid[res=cubic:20]"], f"default instance's label: {list(odd.values())}")

LABEL = {0: "grid", 1: "grid[res=8x8x8]", 2: "bsp", 3: "bvh", 4: "cgal-aabb"}
T = {1: 12.706, 2: 4.303, 3: 3.182}


def expected(workload):
    """{label: (geomean, lo, hi, n)} recomputed here: mean and sample sd of the logs, t from the table."""
    out = {}
    for i, lab in LABEL.items():
        xs = [math.log(c[i][0]) for (s, w), c in RATIOS.items() if w == workload]
        n = len(xs)
        m = sum(xs) / n
        sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (n - 1))
        half = T[n - 1] * sd / math.sqrt(n)
        out[lab] = (math.exp(m), math.exp(m - half), math.exp(m + half), n)
    return out


f = findings.findings(rows, labels, plot.config_key)
check(f["workloads"] == ["primary", "shadow"], f"workloads {f['workloads']}")
for w in ("primary", "shadow"):
    exp = expected(w)
    got = f["ranking"][w]
    check([e["label"] for e in got] == sorted(exp, key=lambda l: (exp[l][0], l)), f"{w}: ranking order "
          f"{[e['label'] for e in got]}")
    for e in got:
        g, lo, hi, n = exp[e["label"]]
        check(abs(e["gm"] / g - 1) < 1e-12 and e["n"] == n, f"{w} {e['label']}: gm {e['gm']} n {e['n']}, want {g} {n}")
        # scipy's exact quantile may stand in for the table's three decimals
        check(abs(e["lo"] / lo - 1) < 2e-3 and abs(e["hi"] / hi - 1) < 2e-3,
              f"{w} {e['label']}: interval [{e['lo']}, {e['hi']}], want [{lo}, {hi}]")

# --- winners and ties
win = f["winners"]
check(win[("spd:a", "primary")]["all"]["label"] == "bsp" and win[("spd:a", "primary")]["all"]["tie"]
      and win[("spd:a", "primary")]["all"]["runner_up"] == "grid", f"spd:a/primary: {win[('spd:a', 'primary')]}")
check(win[("spd:b", "primary")]["all"]["label"] == "bsp" and not win[("spd:b", "primary")]["all"]["tie"],
      f"spd:b/primary: {win[('spd:b', 'primary')]}")
c = win[("spd:c", "primary")]
check(c["all"]["label"] == "bvh" and not c["all"]["tie"] and c["survey"]["label"] == "bsp" and not c["survey"]["tie"],
      f"spd:c/primary: {c}")
check(win[("spd:a", "shadow")]["all"]["tie"], f"spd:a/shadow (touching ranges): {win[('spd:a', 'shadow')]}")
check(not win[("spd:b", "shadow")]["all"]["tie"] and win[("spd:b", "shadow")]["all"]["label"] == "grid",
      f"spd:b/shadow: {win[('spd:b', 'shadow')]}")
check(all(p["survey"]["label"] not in ("bvh", "cgal-aabb") for p in win.values()), "a survey winner is excluded")

# --- families
fam = {x["accel"]: x for x in f["families"]}
check(len(fam["bsp"]["won"]) == 2 and fam["bsp"]["worst"]["scene"] == "spd:c"
      and fam["bsp"]["worst"]["workload"] == "primary" and abs(fam["bsp"]["worst"]["behind"] - 4.0) < 1e-9,
      f"bsp family: {fam['bsp']}")
check(fam["cgal-aabb"]["won"] == [] and "wins none of its 5 cells" in findings.family_sentence(fam["cgal-aabb"]),
      f"cgal-aabb family: {findings.family_sentence(fam['cgal-aabb'])}")
check(fam["cgal-aabb"]["worst"]["scene"] == "spd:c" and fam["cgal-aabb"]["worst"]["workload"] == "primary",
      f"cgal-aabb loses worst: {fam['cgal-aabb']['worst']}")


# --- summary.py's Markdown carries the same numbers (recomputed here), and the ties
def md_rankings(text):
    out, w = {}, None
    for line in text.splitlines():
        m = re.match(r"^### Ranking: (\S+)", line)
        if m:
            w = m.group(1)
            continue
        m = re.match(r"^\| (\d+) \| ([^|]+) \| ([^|]+) \| ([^|]+) \| (\d+) \|$", line)
        if m and w:
            out.setdefault(w, {})[m.group(2).strip()] = (m.group(3).strip(), int(m.group(5)))
        if line.startswith("### Winners"):
            w = None
    return out


md_path = os.path.join(tmp, "summary.md")
os.environ["ACCELBENCH"] = ""
summary.main([path, "--out", md_path, "--accelbench", "/nonexistent"])
text = open(md_path).read()
mr = md_rankings(text)
check(sorted(mr) == ["primary", "shadow"], f"summary.md rankings: {sorted(mr)}")
for w in mr:
    exp = expected(w)
    for lab, (gm, n) in mr[w].items():
        base = {"grid[res=auto]": "grid"}.get(lab, lab)  # no defaults: the pairs not shared
        check(base in exp and gm == f"{exp[base][0]:.3g}" and n == exp[base][3],
              f"summary.md {w} {lab}: {gm} n {n}, want {exp.get(base)}")
check(text.index("## Findings") < text.index("## primary: ratio to Embree"), "summary.md: findings not first")
check("| spd:a | primary | bsp 0.9 (tie with grid[res=auto] 0.95) |" in text, "summary.md: the tie of spd:a/primary")
check("| spd:b | primary | bsp 0.5 | bsp 0.5 |" in text, "summary.md: spd:b/primary is no tie")
check("| spd:c | primary | bvh 0.3 | bsp 1.2 |" in text, "summary.md: spd:c/primary's survey winner")

# --- the HTML: data attributes and shown text agree with the recomputation; ties marked
page = findings.html(f, html.escape)
for w in ("primary", "shadow"):
    exp = expected(w)
    table = page.split(f'data-workload="{w}"', 1)[1].split("</table>", 1)[0]
    trs = re.findall(r'<tr data-label="([^"]*)" data-gm="([^"]*)" data-n="(\d+)">.*?<td class="gm">([^<]*)</td>', table)
    check(len(trs) == len(exp), f"html {w}: {len(trs)} ranking rows")
    for lab, gm, n, shown in trs:
        lab = html.unescape(lab)
        check(abs(float(gm) / exp[lab][0] - 1) < 1e-12 and int(n) == exp[lab][3] and shown == f"{exp[lab][0]:.3g}",
              f"html {w} {lab}: {gm} {n} {shown}")
ties = page.count('data-tie="1"')
check(ties == 2, f"html ties: {ties}, want 2")

# --- params.csv and sweeps
table = findings.params_table(rows, labels, plot.config_key, plot.split_params, DEFAULTS)
res = [(t["label"], t["value"], t["default"]) for t in table if t["accel"] == "grid" and t["key"] == "res"]
check(res == [("grid", "auto", "yes"), ("grid[res=8x8x8]", "8x8x8", "no")], f"params.csv res rows: {res}")
sw = findings.sweeps(rows, plot.config_key, plot.split_params)
check([(a, k, [v for v, _ in m]) for a, k, m in sw] == [("grid", "res", ["auto", "8x8x8"])], f"sweeps: {sw}")

# --- plot.py writes the per-workload heat maps, the sweep, params.csv and summary.md
out = os.path.join(tmp, "plots")
os.makedirs(out)
plot.main([path, "--out", out, "--quiet", "--accelbench", "/nonexistent"])
for name in ("overview__ratio.png", "overview__ratio__primary.png", "overview__ratio__shadow.png",
             "sweep__grid__res.png", "spd_a__ratio.png", "params.csv", "summary.md"):
    check(os.path.isfile(os.path.join(out, name)) and os.path.getsize(os.path.join(out, name)) > 0, f"plot.py: no {name}")
got = list(csv.DictReader(open(os.path.join(out, "params.csv"))))
check(len(got) == 2 * 2 + 1 + 1 + 1 + 1 and set(got[0]) == set(findings.PARAMS_COLUMNS), f"params.csv: {got[:2]}")
check(md_rankings(open(os.path.join(out, "summary.md")).read()) == mr, "plot.py's summary.md differs from summary.py's")

# --- a summary.md of another writer (a champion run's) is left alone; summary.py's own is rewritten
other = os.path.join(tmp, "other")
os.makedirs(other)
with open(os.path.join(other, "matrix.csv"), "w") as f:
    f.write(open(path).read())
with open(os.path.join(other, "summary.md"), "w") as f:
    f.write("# Targets of another script\n")
check(summary.write_beside(os.path.join(other, "matrix.csv")) is None
      and open(os.path.join(other, "summary.md")).read() == "# Targets of another script\n", "a foreign summary.md was replaced")
with open(os.path.join(other, "summary.md"), "w") as f:
    f.write("# Summary of an older run\n")
check(summary.write_beside(os.path.join(other, "matrix.csv")) is not None
      and "## Findings" in open(os.path.join(other, "summary.md")).read(), "summary.py's own summary.md not rewritten")

report_checks()
