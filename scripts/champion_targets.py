#!/usr/bin/python3
"""Judge the champion accelerator `bvh` against its targets from a
matrix.csv written by scripts/bench_champion.sh (Markdown on stdout, or
--out FILE; the ratio plot with --plot FILE.png).

Targets, each cell marked met or missed:
  - trace time over Embree's on the same rays (ratio_vs_embree, the paired
    median): primary <= 0.91 (1.1x Embree's speed), every other workload
    <= 1.0, for `bvh` with its defaults at every thread count;
  - with split=sbvh against Embree's quality=high (spatial splits on both
    sides): the same bounds on bvh[split=sbvh]'s ratio divided by
    embree[quality=high]'s (both paired with the same default Embree on
    the same rays, so the quotient compares the two on those rays);
  - build time <= Embree's at the same thread count (build_ms over the
    embree row's, median over the scene's workloads);
  - memory <= 84 bytes per triangle (bytes_per_prim; Embree's own figure
    stands beside it);
  - 2-thread speed-up >= 1.85 (mrays_per_s at 2 threads over 1 thread);
  - like with like, when the CSV has the rows (bench_champion.sh runs them
    when bvh has a robust parameter): bvh robust=off <= 1.0 of Embree's
    default in every cell; bvh robust=on (its default) <= 0.95 of Embree
    robust=on's time in geometric mean (bvh's ratio over embree[robust=on]'s,
    as for split=sbvh);
  - against tinybvh's BVH8_CPU on the same rays (--anchor LOG...: the
    RESULT lines of tinyanchor, an outside tool, docs/benchmarks.md): bvh
    robust=off <= 0.90 of tinybvh's time in geometric mean, bvh robust=on
    <= 1.0. Each RESULT line gives tinybvh's time over Embree's (the median
    of interleaved rounds) for one scene, workload and rayset_hash; it is
    matched with the CSV's 1-thread cell of that scene and workload, and a
    rayset_hash that differs from the cell's is refused (exit status 2):
    those were other rays. bvh / tinybvh is the CSV's ratio_vs_embree over
    tinyanchor's (each against Embree's default on the same rays); several
    logs of one cell count by their median.
A "Targets" section lists each target met or missed with its number.
The ISA is read from the bvh rows' params (isa=...) and the machine and cpu
columns. Every number comes from the CSV; a cell measured twice counts
once (its last row). Exit status 2 for a missing file or columns, 1 when
the CSV has no bvh row.
"""
import argparse
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot as common  # noqa: E402

PROG = "champion_targets.py"
REQUIRED = ("scene", "accel", "params", "workload", "threads", "ratio_vs_embree", "mrays_per_s", "build_ms",
            "bytes_per_prim", "mismatch_real", "machine", "cpu")
num = common.num
PRIMARY_BOUND, OTHER_BOUND, BYTES_BOUND, SPEEDUP_BOUND = 0.91, 1.0, 84.0, 1.85
ROBUST_GEO_BOUND, FAST_CELL_BOUND = 0.95, 1.0     # bvh robust=on over Embree robust=on; robust=off over Embree
TINY_FAST_BOUND, TINY_ROBUST_BOUND = 0.90, 1.0    # geometric means of bvh robust=off / robust=on over tinybvh
# tinyanchor's RESULT line: RESULT label scene workload rayset_hash rays tracer ratio min max E_ms tracer_ms hitmiss dt
ANCHOR_FIELDS = 14


def param(row, key):
    """The value of key in a row's params ('' when absent)."""
    for p in common.split_params(row["params"]):
        k, _, v = p.partition("=")
        if k == key:
            return v
    return ""


def role(row):
    """Which side of which comparison a row is: bvh / bvh-sbvh / bvh-off (robust=off) / embree / embree-high /
    embree-robust (None: neither)."""
    if row["accel"] == "bvh":
        if param(row, "split") == "sbvh":
            return "bvh-sbvh"
        return "bvh-off" if param(row, "robust") == "off" else "bvh"
    if row["accel"] == "embree":
        if param(row, "quality") == "high":
            return "embree-high"
        return "embree-robust" if param(row, "robust") == "on" else "embree"
    return None


# A comparison: the bvh role and the Embree role it is judged against (None: the default Embree every
# row is paired with, so ratio_vs_embree itself).
COMPARISONS = {"bvh": ("bvh", None), "bvh-off": ("bvh-off", None), "bvh-sbvh": ("bvh-sbvh", "embree-high"),
               "bvh-robust": ("bvh", "embree-robust")}


def bound(workload):
    return PRIMARY_BOUND if workload == "primary" else OTHER_BOUND


def mark(value, limit, below=True):
    if value is None:
        return "n/a"
    return "met" if (value <= limit if below else value >= limit) else "missed"


def fmt(v, digits=2):
    return "" if v is None else f"{v:.{digits}f}"


class Matrix:
    """The CSV's rows by (role, scene, workload, threads)."""

    def __init__(self, rows):
        self.cell = {}
        for r in rows:
            k = role(r)
            if k:
                self.cell[(k, r["scene"], r["workload"], r["threads"])] = r
        self.scenes = common.ordered(r["scene"] for r in rows)
        self.workloads = common.ordered((r["workload"] for r in rows), common.WORKLOAD_ORDER)
        self.threads = sorted({r["threads"] for r in rows}, key=lambda t: num(t) or 0)

    def get(self, k, s, w, t, col):
        r = self.cell.get((k, s, w, t))
        return num(r[col]) if r else None

    def ratio(self, k, s, w, t):
        """Trace time over the comparison's Embree (COMPARISONS): bvh and bvh robust=off against default Embree,
        sbvh against quality=high, bvh against robust=on (k bvh-robust)."""
        mine_role, theirs_role = COMPARISONS[k]
        mine = self.get(mine_role, s, w, t, "ratio_vs_embree")
        if theirs_role is None:
            return mine
        theirs = self.get(theirs_role, s, w, t, "ratio_vs_embree")
        return mine / theirs if mine is not None and theirs else None

    def ratios(self, k, t=None):
        """Every cell's ratio of comparison k (at thread count t, or all)."""
        return [v for s in self.scenes for w in self.workloads for tt in self.threads
                if (t is None or tt == t) and (v := self.ratio(k, s, w, tt)) is not None]

    def has(self, k):
        return any(key[0] == k for key in self.cell)

    def per_scene(self, k, s, t, col):
        """Median of col over the scene's workloads (build time and memory are per build, one per cell)."""
        vals = [v for w in self.workloads if (v := self.get(k, s, w, t, col)) is not None]
        return statistics.median(vals) if vals else None


def trace_table(m, k, title, against):
    out = [f"## {title}\n", f"Trace time over {against} on the same rays; target primary <= {PRIMARY_BOUND}, "
           f"others <= {OTHER_BOUND}.\n",
           "| scene | threads | " + " | ".join(m.workloads) + " |", "|---|---:|" + "---|" * len(m.workloads)]
    met = total = 0
    for s in m.scenes:
        for t in m.threads:
            cells = []
            for w in m.workloads:
                v = m.ratio(k, s, w, t)
                verdict = mark(v, bound(w))
                met += verdict == "met"
                total += verdict != "n/a"
                cells.append(f"{fmt(v)} {verdict}" if v is not None else "")
            out.append(f"| {s} | {t} | " + " | ".join(cells) + " |")
    out.append(f"\nMet in {met} of {total} cells.\n")
    return out


def builds(m, k, e):
    """Per scene and thread count: (scene, threads, build ms, Embree's, their ratio, bytes/prim, Embree's)."""
    out = []
    for s in m.scenes:
        for t in m.threads:
            b, eb = m.per_scene(k, s, t, "build_ms"), m.per_scene(e, s, t, "build_ms")
            mem, emem = m.per_scene(k, s, t, "bytes_per_prim"), m.per_scene(e, s, t, "bytes_per_prim")
            if b is not None:
                out.append((s, t, b, eb, b / eb if eb else None, mem, emem))
    return out


def build_table(m, k, e, title):
    out = [f"## {title}\n", f"Build time over Embree's at the same thread count (target <= 1.0); bytes per triangle "
           f"(target <= {BYTES_BOUND:.0f}) beside Embree's.\n",
           "| scene | threads | build ms | Embree build ms | ratio | | bytes/prim | Embree bytes/prim | |",
           "|---|---:|---:|---:|---:|---|---:|---:|---|"]
    for s, t, b, eb, r, mem, emem in builds(m, k, e):
        out.append(f"| {s} | {t} | {fmt(b, 1)} | {fmt(eb, 1)} | {fmt(r)} | {mark(r, 1.0)} | {fmt(mem, 1)} | "
                   f"{fmt(emem, 1)} | {mark(mem, BYTES_BOUND)} |")
    out.append("")
    return out


def speedups(m):
    """Per scene and workload: (scene, workload, bvh's 2-thread speed-up, Embree's); [] without 1 and 2 threads."""
    out = []
    if "1" not in m.threads or "2" not in m.threads:
        return out
    for s in m.scenes:
        for w in m.workloads:
            one, two = m.get("bvh", s, w, "1", "mrays_per_s"), m.get("bvh", s, w, "2", "mrays_per_s")
            eone, etwo = m.get("embree", s, w, "1", "mrays_per_s"), m.get("embree", s, w, "2", "mrays_per_s")
            if one and two is not None:
                out.append((s, w, two / one, etwo / eone if eone and etwo is not None else None))
    return out


def speedup_table(m):
    if "1" not in m.threads or "2" not in m.threads:
        return ["## 2-thread speed-up\n", "Not measured: the CSV lacks rows at 1 or 2 threads.\n"]
    out = ["## 2-thread speed-up\n", f"Mrays/s at 2 threads over 1 thread (target >= {SPEEDUP_BOUND}); Embree's beside it.\n",
           "| scene | workload | bvh | | Embree |", "|---|---|---:|---|---:|"]
    for s, w, sp, esp in speedups(m):
        out.append(f"| {s} | {w} | {fmt(sp)} | {mark(sp, SPEEDUP_BOUND, below=False)} | {fmt(esp)} |")
    out.append("")
    return out


def read_anchor(paths):
    """tinyanchor's RESULT lines: {(scene, workload, tracer): [(ratio, rayset_hash, where), ...]}. A malformed
    RESULT line, or a file that cannot be read or has none, exits 2."""
    found = {}
    for path in paths:
        try:
            with open(path, encoding="utf-8", errors="replace") as f:
                lines = f.read().splitlines()
        except OSError as e:
            common.fail(f"--anchor {path}: {e.strerror}")
        n = 0
        for i, line in enumerate(lines, 1):
            if not line.startswith("RESULT\t"):
                continue
            f = line.split("\t")
            ratio = num(f[7]) if len(f) == ANCHOR_FIELDS else None
            if ratio is None or len(f[4]) != 16 or any(c not in "0123456789abcdef" for c in f[4].lower()):
                common.fail(f"--anchor {path}:{i}: not a tinyanchor RESULT line ({ANCHOR_FIELDS} tab-separated fields: "
                            "RESULT label scene workload rayset_hash rays tracer ratio min max E_ms ms hitmiss dt)")
            found.setdefault((f[2], f[3], f[6]), []).append((ratio, f[4].lower(), f"{path}:{i}"))
            n += 1
        if not n:
            common.fail(f"--anchor {path}: no RESULT line (is it tinyanchor's output?)")
    return found


class Anchor:
    """tinybvh's time over Embree's per (scene, workload, tracer), matched with the CSV's 1-thread cells."""

    def __init__(self, m, found):
        self.t = "1" if "1" in m.threads else (m.threads[0] if m.threads else "1")
        self.value, self.count, self.unmatched = {}, {}, []
        for (s, w, tracer), entries in found.items():
            row = m.cell.get(("bvh", s, w, self.t))
            if row is None:
                self.unmatched.append(f"{s} {w} ({tracer}, {entries[0][2]})")
                continue
            mine = row.get("rayset_hash", "").lower()
            for ratio, h, where in entries:
                if h != mine:
                    common.fail(f"--anchor {where}: {s} {w}: rayset_hash {h}, the CSV's cell has {mine or 'none'}: "
                                "not the same rays (refused)")
            self.value[(s, w, tracer)] = statistics.median(r for r, _, _ in entries)
            self.count[(s, w, tracer)] = len(entries)

    def get(self, s, w, tracer="T8"):
        return self.value.get((s, w, tracer))

    def cells(self, m):
        return [(s, w) for s in m.scenes for w in m.workloads if self.get(s, w) is not None]

    def over_tiny(self, m, k, tracer="T8"):
        """Per matched cell: comparison k's ratio over tinybvh's (both against Embree's default)."""
        out = {}
        for s, w in self.cells(m):
            mine, tiny = m.ratio(k, s, w, self.t), self.get(s, w, tracer)
            if mine is not None and tiny:
                out[(s, w)] = mine / tiny
        return out


def anchor_table(m, a):
    """The per-cell table of bvh, tinybvh and Embree on the same rays, with geometric means."""
    cols = [("bvh / Embree", lambda s, w: m.ratio("bvh", s, w, a.t))]
    if m.has("bvh-off"):
        cols.append(("bvh robust=off / Embree", lambda s, w: m.ratio("bvh-off", s, w, a.t)))
    cols.append(("tinybvh / Embree", lambda s, w: a.get(s, w)))
    cols.append(("bvh / tinybvh", lambda s, w: a.over_tiny(m, "bvh").get((s, w))))
    if m.has("bvh-off"):
        cols.append(("bvh robust=off / tinybvh", lambda s, w: a.over_tiny(m, "bvh-off").get((s, w))))
    if any(k[2] == "HQ" for k in a.value):
        cols.append(("tinybvh HQ / Embree", lambda s, w: a.get(s, w, "HQ")))
    out = ["## Against tinybvh (tinyanchor) on the same rays\n",
           f"tinybvh's BVH8_CPU (Build) from tinyanchor's RESULT lines beside the CSV's {a.t}-thread cells, each "
           "matched by scene, workload and rayset_hash; every figure is a trace time over Embree's default on the "
           "same rays (bvh / tinybvh is their quotient; below 1: bvh is faster).\n",
           "| scene | workload | " + " | ".join(c for c, _ in cols) + " |", "|---|---|" + "---:|" * len(cols)]
    cells = a.cells(m)
    for s, w in cells:
        out.append(f"| {s} | {w} | " + " | ".join(fmt(f(s, w), 3) for _, f in cols) + " |")
    if cells:
        out.append("| geometric mean | | " + " | ".join(fmt(common.geomean([f(s, w) for s, w in cells]), 3)
                                                for _, f in cols) + " |")
    else:
        out.append("\nNo RESULT line matched a cell of the CSV.")
    if a.unmatched:
        out.append(f"\nNot in the CSV (no bvh row at {a.t} thread), left out: " + "; ".join(a.unmatched) + ".")
    out.append("")
    return out


def targets(m, a):
    """Each target, met or missed, with its number: [(target, number, verdict)]."""
    def geo_verdict(vals, limit):
        g = common.geomean(vals)
        return (f"{fmt(g, 3)} over {len(vals)} cells" if g is not None else "not measured"), mark(g, limit)

    out = []
    why_off = "not measured: no bvh robust=off row" + ("" if a else ", no --anchor")
    if a is not None and m.has("bvh-off"):
        out.append((f"bvh robust=off / tinybvh, geometric mean <= {TINY_FAST_BOUND}",
                    *geo_verdict(list(a.over_tiny(m, "bvh-off").values()), TINY_FAST_BOUND)))
    else:
        out.append((f"bvh robust=off / tinybvh, geometric mean <= {TINY_FAST_BOUND}", why_off, "n/a"))
    vals = m.ratios("bvh-off")
    worst = max(vals) if vals else None
    out.append((f"bvh robust=off / Embree (default) <= {FAST_CELL_BOUND} in every cell",
                f"worst {fmt(worst, 3)}, {sum(v <= FAST_CELL_BOUND for v in vals)} of {len(vals)} cells"
                if vals else "not measured: no bvh robust=off row", mark(worst, FAST_CELL_BOUND)))
    per_t = [(t, m.ratios("bvh-robust", t)) for t in m.threads]
    per_t = [(t, v) for t, v in per_t if v]
    geos = [(t, common.geomean(v)) for t, v in per_t]
    out.append((f"bvh robust=on / Embree robust=on, geometric mean <= {ROBUST_GEO_BOUND}",
                ", ".join(f"{fmt(g, 3)} at {t} thread{'s' if t != '1' else ''}" for t, g in geos)
                if geos else "not measured: no embree robust=on row",
                mark(max(g for _, g in geos) if geos else None, ROBUST_GEO_BOUND)))
    if a is not None:
        out.append((f"bvh robust=on / tinybvh, geometric mean <= {TINY_ROBUST_BOUND}",
                    *geo_verdict(list(a.over_tiny(m, "bvh").values()), TINY_ROBUST_BOUND)))
    else:
        out.append((f"bvh robust=on / tinybvh, geometric mean <= {TINY_ROBUST_BOUND}", "not measured: no --anchor", "n/a"))
    b = builds(m, "bvh", "embree")
    for t in ("1", "2"):
        rs = [r for _, tt, _, _, r, _, _ in b if tt == t and r is not None]
        worst = max(rs) if rs else None
        out.append((f"build time <= Embree's at {t} thread{'s' if t != '1' else ''}",
                    f"worst {fmt(worst)}, {sum(r <= 1.0 for r in rs)} of {len(rs)} scenes" if rs else "not measured",
                    mark(worst, 1.0)))
    mems = [mem for _, _, _, _, _, mem, _ in b if mem is not None]
    out.append((f"memory <= {BYTES_BOUND:.0f} bytes a triangle", f"worst {fmt(max(mems), 1)}" if mems else "not measured",
                mark(max(mems) if mems else None, BYTES_BOUND)))
    sps = [sp for _, _, sp, _ in speedups(m)]
    out.append((f"2-thread trace speed-up >= {SPEEDUP_BOUND}",
                f"lowest {fmt(min(sps))}, {sum(v >= SPEEDUP_BOUND for v in sps)} of {len(sps)} cells" if sps
                else "not measured", mark(min(sps) if sps else None, SPEEDUP_BOUND, below=False)))
    return out


def targets_table(m, a):
    out = ["## Targets\n", "| target | measured | |", "|---|---|---|"]
    out += [f"| {t} | {v} | {verdict} |" for t, v, verdict in targets(m, a)]
    out.append("")
    return out


def plot(m, rows, path):
    """One panel per workload: each scene's ratio per comparison and thread count, the target as a line."""
    plt = common.plt
    series = [(k, t) for k in ("bvh", "bvh-sbvh") for t in m.threads
              if any(m.ratio(k, s, w, t) is not None for s in m.scenes for w in m.workloads)]
    fig, axes = plt.subplots(1, len(m.workloads), figsize=(3.2 * len(m.workloads) + 1.5, 3.8), squeeze=False)
    width = 0.8 / max(1, len(series))
    for ax, w in zip(axes[0], m.workloads):
        for i, (k, t) in enumerate(series):
            xs, ys = [], []
            for j, s in enumerate(m.scenes):
                v = m.ratio(k, s, w, t)
                if v is not None:
                    xs.append(j - 0.4 + width * (i + 0.5))
                    ys.append(v)
            label = ("bvh / Embree" if k == "bvh" else "bvh[sbvh] / Embree[high]") + f", {t} thread" + ("s" if t != "1" else "")
            ax.bar(xs, ys, width, label=label, color=f"C{i % 10}")
        ax.axhline(bound(w), color="k", ls="--", lw=0.8)
        ax.set_xticks(range(len(m.scenes)), m.scenes, rotation=30, ha="right", fontsize=7)
        ax.set_title(f"{w} (target <= {bound(w)})", fontsize=9)
        ax.grid(axis="y", alpha=0.3)
    axes[0][0].set_ylabel("trace time ratio (< 1: faster than Embree)")
    axes[0][-1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    isa = ", ".join(dict.fromkeys(param(r, "isa") for r in rows if r["accel"] == "bvh")) or "?"
    fig.suptitle(f"bvh against Embree, isa={isa}", fontsize=10)
    common.footer(fig, rows)
    common.save(fig, path, [])


def main(argv=None):
    p = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("csv", metavar="CSV", help="matrix.csv written by scripts/bench_champion.sh")
    p.add_argument("--out", metavar="FILE", help="write the Markdown here (default: stdout)")
    p.add_argument("--plot", metavar="PNG", help="also draw the ratios per scene and workload here")
    p.add_argument("--anchor", metavar="FILE", nargs="+",
                   help="tinyanchor's output logs (RESULT lines) on this run's saved rays: tinybvh beside bvh and Embree")
    args = p.parse_args(argv)
    common.PROG = PROG
    rows = common.dedup_rows(common.load_rows(args.csv, REQUIRED), args.csv)
    bvh_rows = [r for r in rows if r["accel"] == "bvh"]
    if not bvh_rows:
        print(f"{PROG}: {args.csv}: no bvh row", file=sys.stderr)
        return 1
    m = Matrix(rows)
    a = Anchor(m, read_anchor(args.anchor)) if args.anchor else None

    def uniq(col, rs=rows):
        return common.column_values(rs, col)
    isa = ", ".join(dict.fromkeys(param(r, "isa") for r in bvh_rows)) or "?"
    out = [f"# The champion's targets from {args.csv}\n",
           f"ISA of bvh's box kernels: **{isa}** (params column); machine {uniq('machine')}, cpu {uniq('cpu')}; "
           f"threads {', '.join(m.threads)}; git {uniq('git_rev')}.\n",
           f"bvh parameters: `{uniq('params', [r for r in bvh_rows if role(r) == 'bvh'])}`.\n",
           f"Real mismatches (must be 0): {sum(int(num(r['mismatch_real']) or 0) for r in rows)}.\n"]
    out += targets_table(m, a)
    if a is not None:
        out += anchor_table(m, a)
    out += trace_table(m, "bvh", "bvh (defaults) against Embree (defaults)", "Embree's (quality=medium)")
    if m.has("bvh-off"):
        out += trace_table(m, "bvh-off", "bvh robust=off against Embree (defaults)", "Embree's (quality=medium)")
    if m.has("bvh") and m.has("embree-robust"):
        out += trace_table(m, "bvh-robust", "bvh (robust=on) against Embree robust=on", "Embree robust=on's")
    out += build_table(m, "bvh", "embree", "Build time and memory, bvh (defaults)")
    if any(k[0] == "bvh-sbvh" for k in m.cell):
        out += trace_table(m, "bvh-sbvh", "bvh split=sbvh against Embree quality=high", "Embree quality=high's")
        out += build_table(m, "bvh-sbvh", "embree-high", "Build time and memory, bvh split=sbvh against Embree quality=high")
    else:
        out.append("## split=sbvh\n\nNot measured: the CSV has no bvh row with split=sbvh.\n")
    out += speedup_table(m)
    text = "\n".join(out) + "\n"
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    else:
        sys.stdout.write(text)
    if args.plot:
        plot(m, rows, args.plot)
    return 0


if __name__ == "__main__":
    sys.exit(main())
