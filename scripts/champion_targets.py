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
  - 2-thread speed-up >= 1.85 (mrays_per_s at 2 threads over 1 thread).
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


def param(row, key):
    """The value of key in a row's params ('' when absent)."""
    for p in common.split_params(row["params"]):
        k, _, v = p.partition("=")
        if k == key:
            return v
    return ""


def role(row):
    """Which side of which comparison a row is: bvh / bvh-sbvh / embree / embree-high (None: neither)."""
    if row["accel"] == "bvh":
        return "bvh-sbvh" if param(row, "split") == "sbvh" else "bvh"
    if row["accel"] == "embree":
        return "embree-high" if param(row, "quality") == "high" else "embree"
    return None


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
        """Trace time over the comparison's Embree: bvh against default Embree, sbvh against quality=high."""
        if k == "bvh":
            return self.get("bvh", s, w, t, "ratio_vs_embree")
        mine, theirs = self.get("bvh-sbvh", s, w, t, "ratio_vs_embree"), self.get("embree-high", s, w, t, "ratio_vs_embree")
        return mine / theirs if mine is not None and theirs else None

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


def build_table(m, k, e, title):
    out = [f"## {title}\n", f"Build time over Embree's at the same thread count (target <= 1.0); bytes per triangle "
           f"(target <= {BYTES_BOUND:.0f}) beside Embree's.\n",
           "| scene | threads | build ms | Embree build ms | ratio | | bytes/prim | Embree bytes/prim | |",
           "|---|---:|---:|---:|---:|---|---:|---:|---|"]
    for s in m.scenes:
        for t in m.threads:
            b, eb = m.per_scene(k, s, t, "build_ms"), m.per_scene(e, s, t, "build_ms")
            mem, emem = m.per_scene(k, s, t, "bytes_per_prim"), m.per_scene(e, s, t, "bytes_per_prim")
            if b is None:
                continue
            r = b / eb if eb else None
            out.append(f"| {s} | {t} | {fmt(b, 1)} | {fmt(eb, 1)} | {fmt(r)} | {mark(r, 1.0)} | {fmt(mem, 1)} | "
                       f"{fmt(emem, 1)} | {mark(mem, BYTES_BOUND)} |")
    out.append("")
    return out


def speedup_table(m):
    if "1" not in m.threads or "2" not in m.threads:
        return ["## 2-thread speed-up\n", "Not measured: the CSV lacks rows at 1 or 2 threads.\n"]
    out = ["## 2-thread speed-up\n", f"Mrays/s at 2 threads over 1 thread (target >= {SPEEDUP_BOUND}); Embree's beside it.\n",
           "| scene | workload | bvh | | Embree |", "|---|---|---:|---|---:|"]
    for s in m.scenes:
        for w in m.workloads:
            one, two = m.get("bvh", s, w, "1", "mrays_per_s"), m.get("bvh", s, w, "2", "mrays_per_s")
            eone, etwo = m.get("embree", s, w, "1", "mrays_per_s"), m.get("embree", s, w, "2", "mrays_per_s")
            sp = two / one if one and two is not None else None
            esp = etwo / eone if eone and etwo is not None else None
            if sp is not None:
                out.append(f"| {s} | {w} | {fmt(sp)} | {mark(sp, SPEEDUP_BOUND, below=False)} | {fmt(esp)} |")
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
    args = p.parse_args(argv)
    common.PROG = PROG
    rows = common.dedup_rows(common.load_rows(args.csv, REQUIRED), args.csv)
    bvh_rows = [r for r in rows if r["accel"] == "bvh"]
    if not bvh_rows:
        print(f"{PROG}: {args.csv}: no bvh row", file=sys.stderr)
        return 1
    m = Matrix(rows)

    def uniq(col, rs=rows):
        return ", ".join(v for v in dict.fromkeys(r.get(col, "") for r in rs) if v) or "?"
    isa = ", ".join(dict.fromkeys(param(r, "isa") for r in bvh_rows)) or "?"
    out = [f"# The champion's targets from {args.csv}\n",
           f"ISA of bvh's box kernels: **{isa}** (params column); machine {uniq('machine')}, cpu {uniq('cpu')}; "
           f"threads {', '.join(m.threads)}; git {uniq('git_rev')}.\n",
           f"bvh parameters: `{uniq('params', [r for r in bvh_rows if role(r) == 'bvh'])}`.\n",
           f"Real mismatches (must be 0): {sum(int(num(r['mismatch_real']) or 0) for r in rows)}.\n"]
    out += trace_table(m, "bvh", "bvh (defaults) against Embree (defaults)", "Embree's (quality=medium)")
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
