#!/usr/bin/python3
"""Each structure at its best for the scene: `accelbench tune`'s search, choice and measurement.

For every accelerator of --accels that declares what to search (`accelbench
list accels`, its "tune:" line: one parameter and the values to try, the
default among them), per scene and workload:
  1. training: every value is traced on training rays, a quarter as many
     as the measured ones and other rays (half the image resolution per
     axis, so other pixel centres, and seed + 1 for the bounce and random
     rays), with the run's timed repeats, paired with Embree's
     (OUT/training/, an ordinary run folder: an interrupted search
     resumes);
  2. choice: the value with the lowest paired ratio to Embree on the
     training rays (ties to the default);
  3. measurement: the default and the chosen setting traced on the
     measured rays with the run's repeats, paired with Embree's, into
     OUT/matrix.csv (one `accelbench run` per scene and workload, appending).
Accelerators without a search, and instances given with parameters
(NAME[k=v]), are measured as given. Written to OUT: matrix.csv (every
measured cell), tuning.csv (per scene, workload and structure: the default
and the chosen setting, both ratios to Embree, the gain default / tuned,
the training cells and the search's own time, its builds and traces) and
tuning.md (those, per structure the geometric-mean gain: what its default
leaves on the table, and per value its geometric-mean ratio over the
training cells: the one value a default would best take over the matrix),
tuning_values.csv (that last table) and the run folder's plots. Every child is
started with an argument vector, never a shell. A cell whose build fails
(a value over the memory cap on a large scene, say) is skipped and said on
stderr (`run --keep-going`): that value is not chosen there. Exit status:
the first failing run's (2 on bad input), else 0."""
import argparse
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot as common  # noqa: E402

PROG = "tune.py"
num = common.num


def parse_tune_specs(text):
    """{accel: (key, [values])} from the text of `accelbench list accels` (its "tune: KEY=V|V" lines)."""
    return common.parse_accel_listing(text)[1]


def split_list(text):
    """'grid,bsp[a=1,b=2|3]' -> ['grid', 'bsp[a=1,b=2|3]']: commas inside brackets stay."""
    out, depth, cur = [], 0, ""
    for ch in text:
        if ch == "," and depth == 0:
            out.append(cur)
            cur = ""
            continue
        depth += ch == "["
        depth -= ch == "]"
        cur += ch
    out.append(cur)
    return [x for x in out if x]


def half_res(res):
    w, h = (int(x) for x in res.lower().split("x"))
    return f"{max(8, w // 2)}x{max(8, h // 2)}"


def run(accelbench, args, quiet):
    """accelbench with args (a list): its exit status (plot.run_child)."""
    return common.run_child([accelbench] + args, quiet)


def rows_of(path):
    if not os.path.isfile(path):
        return []
    return common.dedup_rows(common.load_rows(path, ("scene", "accel", "params", "workload", "ratio_vs_embree",
                                                     "trace_ms", "build_ms")), path)


def param_of(params, key):
    for piece in common.split_params(params):
        k, _, v = piece.partition("=")
        if k == key:
            return v
    return None


def choose(training, specs, defaults):
    """{(scene, workload, accel): (chosen value, default value, cells, search ms)} from the training rows."""
    best = {}
    for r in training:
        a = r["accel"]
        if a not in specs:
            continue
        key = specs[a][0]
        v = param_of(r["params"], key)
        ratio = num(r["ratio_vs_embree"])
        if v is None or ratio is None:
            continue
        cell = (r["scene"], r["workload"], a)
        b = best.setdefault(cell, {"value": None, "ratio": math.inf, "cells": 0, "ms": 0.0})
        b["cells"] += 1
        b["ms"] += (num(r["build_ms"]) or 0.0) + (num(r["trace_ms"]) or 0.0)
        is_default = v == defaults.get(a, {}).get(key)
        if ratio < b["ratio"] or (ratio == b["ratio"] and is_default):
            b["value"], b["ratio"] = v, ratio
    return {c: (b["value"], defaults.get(c[2], {}).get(specs[c[2]][0]), b["cells"], b["ms"]) for c, b in best.items()
            if b["value"] is not None}


def per_structure(recs):
    """Per structure of tuning.csv's rows (dicts; gain a number or None): its parameter, default, cells, the
    geometric-mean and largest gain, and the chosen values with how often each was chosen."""
    out = []
    for a in dict.fromkeys(r["accel"] for r in recs):
        mine = [r for r in recs if r["accel"] == a]
        gains = [r["gain"] for r in mine if r["gain"]]
        values = {}
        for r in mine:
            values[r["tuned"]] = values.get(r["tuned"], 0) + 1
        out.append({"accel": a, "key": mine[0]["key"], "default": mine[0]["default"], "cells": len(mine),
                    "gm_gain": common.geomean(gains), "max_gain": max(gains) if gains else None,
                    "values": ", ".join(f"{v} ({n})" for v, n in sorted(values.items(), key=lambda kv: -kv[1]))})
    return out


def per_value(training, specs):
    """Per searched structure and value: the training cells and the geometric mean of their ratios to Embree,
    over the cells where every value was measured (so that each value sees the same cells): [{accel, key, value,
    cells, gm}], in the search's order."""
    by = {}
    for r in training:
        a = r["accel"]
        v = param_of(r["params"], specs[a][0]) if a in specs else None
        ratio = num(r["ratio_vs_embree"])
        if v is not None and ratio:
            by.setdefault(a, {}).setdefault((r["scene"], r["workload"]), {})[v] = ratio
    out = []
    for a, cells in by.items():
        key, values = specs[a]
        full = [c for c in cells.values() if all(v in c for v in values)]
        for v in values:
            out.append({"accel": a, "key": key, "value": v, "cells": len(full),
                        "gm": common.geomean([c[v] for c in full]) if full else None})
    return out


fmt = common.fmt_g


def main(argv=None):
    ap = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--accelbench", required=True, help="the accelbench binary to run")
    ap.add_argument("--scenes", required=True)
    ap.add_argument("--accels", default="")
    ap.add_argument("--workloads", required=True)
    ap.add_argument("--res", required=True)
    ap.add_argument("--repeat", required=True)
    ap.add_argument("--threads", default="")
    ap.add_argument("--seed", default="1")
    ap.add_argument("--out", required=True)
    ap.add_argument("--quiet", action="store_true")
    args = ap.parse_args(argv)
    common.PROG = PROG
    listing = subprocess.run([args.accelbench, "list", "accels"], capture_output=True, text=True).stdout
    defaults, specs = common.parse_accel_listing(listing)
    accels = split_list(args.accels) if args.accels else list(specs)
    tuned = [a for a in accels if a in specs]
    threads = ["--threads", args.threads] if args.threads else []
    # a value that cannot be built on a scene (over the memory cap, say) loses its cells, not the search
    common_args = ["--no-plots", "--keep-going"] + threads
    # 1. training
    training_dir = os.path.join(args.out, "training")
    if tuned:
        sweep = ",".join(f"{a}[{specs[a][0]}={'|'.join(specs[a][1])}]" for a in tuned)
        rc = run(args.accelbench, ["run", "--scenes", args.scenes, "--accels", sweep, "--workloads", args.workloads,
                                   "--res", half_res(args.res), "--seed", str(int(args.seed) + 1), "--repeat", args.repeat,
                                   "--out", training_dir] + common_args, args.quiet)
    training = rows_of(os.path.join(training_dir, "matrix.csv"))
    if tuned and rc != 0:
        if rc != 2 or not training:
            print(f"{PROG}: the training run failed (exit {rc}); run the same command again to resume it",
                  file=sys.stderr)
            return rc
        print(f"{PROG}: some training cells were not measured (their builds failed, above): those values are not "
              "chosen there", file=sys.stderr)
    chosen = choose(training, specs, defaults)  # 2. choice
    # 3. measurement: what is measured as given, in one run over every scene and workload; then per scene and
    # workload of the training run, each searched structure at its default and at its chosen value
    plans = []
    untuned = [a for a in accels if a not in specs]
    if untuned:
        plans.append((args.scenes, args.workloads, untuned))
    for scene, workload in dict.fromkeys((r["scene"], r["workload"]) for r in training):
        inst = []
        for a in tuned:
            c = chosen.get((scene, workload, a))
            if c:
                inst.append(a)
                if c[0] != c[1]:
                    inst.append(f"{a}[{specs[a][0]}={c[0]}]")
        if inst:
            plans.append((scene, workload, inst))
    for scene, workload, inst in plans:
        rc = run(args.accelbench, ["run", "--scenes", scene, "--accels", ",".join(inst), "--workloads", workload,
                                   "--res", args.res, "--seed", args.seed, "--repeat", args.repeat, "--out", args.out]
                 + common_args, args.quiet)
        if rc == 2 and os.path.isfile(os.path.join(args.out, "matrix.csv")):
            print(f"{PROG}: {scene} / {workload}: some cells were not measured (their builds failed, above)",
                  file=sys.stderr)
        elif rc != 0:
            print(f"{PROG}: the measuring run of {scene} / {workload} failed (exit {rc}); run the same command "
                  "again to resume", file=sys.stderr)
            return rc
    # 4. the table
    measured = rows_of(os.path.join(args.out, "matrix.csv"))
    recs = []
    for (scene, workload, a), (value, default, cells, ms) in sorted(chosen.items()):
        key = specs[a][0]
        mine = [r for r in measured if r["scene"] == scene and r["workload"] == workload and r["accel"] == a]
        dflt = [r for r in mine if param_of(r["params"], key) == default]
        best = [r for r in mine if param_of(r["params"], key) == value]
        rd = num(dflt[-1]["ratio_vs_embree"]) if dflt else None
        rt = num(best[-1]["ratio_vs_embree"]) if best else None
        recs.append({"scene": scene, "workload": workload, "accel": a, "key": key, "default": default, "tuned": value,
                     "default_ratio": rd, "tuned_ratio": rt, "gain": rd / rt if rd and rt else None,
                     "training_cells": cells, "search_ms": ms})
    cols = ["scene", "workload", "accel", "key", "default", "tuned", "default_ratio", "tuned_ratio", "gain",
            "training_cells", "search_ms"]
    common.write_csv(os.path.join(args.out, "tuning.csv"), cols, [[r[c] for c in cols] for r in recs],
                     lambda v: fmt(v, 6))
    md = ["# Tuning: each structure at its best for the scene\n",
          f"Training on a quarter as many other rays (half the resolution, seed + 1); measured at "
          f"{args.res} with {args.repeat} paired repeats. Gain: the default's ratio to Embree over the tuned "
          "setting's, on the measured rays.\n",
          "## Per structure\n", "| structure | parameter | cells | geometric-mean gain | largest | tuned value |",
          "|---|---|---:|---:|---:|---|"]
    for p in per_structure(recs):
        md.append(f"| {p['accel']} | {p['key']} (default {p['default']}) | {p['cells']} | {fmt(p['gm_gain'])} | "
                  f"{fmt(p['max_gain'])} | {p['values']} |")
    values = per_value(training, specs)
    md += ["", "## One value for every scene\n",
           "Geometric mean of the training rays' ratios to Embree over the cells where every value was traced: the "
           "value a default would best take over this matrix (marked *).\n",
           "| structure | parameter | value | cells | geometric-mean ratio |", "|---|---|---|---:|---:|"]
    for a in dict.fromkeys(x["accel"] for x in values):
        mine = [x for x in values if x["accel"] == a]
        best = min((x for x in mine if x["gm"]), key=lambda x: x["gm"], default=None)
        for x in mine:
            dflt = " (default)" if x["value"] == defaults.get(a, {}).get(x["key"]) else ""
            md.append(f"| {a} | {x['key']} | {x['value']}{dflt}{' *' if x is best else ''} | {x['cells']} | "
                      f"{fmt(x['gm'])} |")
    common.write_csv(os.path.join(args.out, "tuning_values.csv"), ["accel", "key", "value", "cells", "gm_ratio"],
                     [[x["accel"], x["key"], x["value"], x["cells"], x["gm"]] for x in values], lambda v: fmt(v, 6))
    md += ["", "## Per cell\n", "| scene | workload | structure | default | tuned | default ratio | tuned ratio | gain "
           "| search ms |", "|---|---|---|---|---|---:|---:|---:|---:|"]
    for r in recs:
        md.append(f"| {r['scene']} | {r['workload']} | {r['accel']} | {r['key']}={r['default']} | "
                  f"{r['key']}={r['tuned']} | {fmt(r['default_ratio'])} | {fmt(r['tuned_ratio'])} | "
                  f"{fmt(r['gain'])} | {fmt(r['search_ms'], 4)} |")
    common.write_text(os.path.join(args.out, "tuning.md"), "\n".join(md) + "\n")
    if measured:
        subprocess.run([sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "plot.py"),
                        os.path.join(args.out, "matrix.csv"), "--quiet"])
    if not args.quiet:
        print(f"wrote {os.path.join(args.out, 'tuning.csv')}\nwrote {os.path.join(args.out, 'tuning.md')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
