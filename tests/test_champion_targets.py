#!/usr/bin/python3
"""test_champion_targets.py: scripts/champion_targets.py on a constructed
matrix.csv and constructed tinyanchor logs (no measurement).

The CSV has two scenes, two workloads and 1 and 2 threads, with the rows
bench_champion.sh writes when bvh has a robust parameter: bvh (robust=on),
bvh robust=off, Embree's default and Embree robust=on, each cell with its
rayset_hash. The anchor logs give tinybvh's RESULT lines for those cells
(one cell in two logs: their median counts), one for a scene the CSV lacks
(left out and said) and HQ lines. It checks: the per-cell table (bvh /
Embree, bvh robust=off / Embree, tinybvh / Embree and the two quotients)
and its geometric means against a recomputation written here; each target's
number and verdict; that a RESULT line whose rayset_hash differs from the
cell's is refused (exit status 2, nothing written); a malformed RESULT line
is refused; and that without the robust rows and without --anchor those
targets say not measured. Prints "N passed, N failed"; exits 1 on a failure."""
import contextlib
import csv
import io
import math
import os
import re
import sys
import tempfile
import zlib

SRC = os.environ.get("SRCDIR", os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
sys.path.insert(0, os.path.join(SRC, "scripts"))
import champion_targets  # noqa: E402
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pycheck import check, report as report_checks  # noqa: E402

BVH = "width=8,bins=16,robust=on,isa=avx512"
BVH_OFF = "width=8,bins=16,robust=off,isa=avx512"
EMB = "quality=medium,robust=off"
EMB_ROBUST = "quality=medium,robust=on"
# (scene, workload) -> (bvh ratio, bvh robust=off ratio, embree robust=on ratio, tinybvh T8 ratios in the logs)
CELLS = {
    ("a", "primary"): (1.10, 0.95, 1.20, [1.00]),
    ("a", "shadow"): (1.00, 0.90, 1.10, [1.25]),
    ("spd:b:t", "primary"): (0.90, 0.80, 1.00, [0.80, 1.00]),
    ("spd:b:t", "shadow"): (1.20, 1.05, 1.25, [1.20]),
}
COLS = ["scene", "prims", "accel", "params", "workload", "rays", "threads", "rayset_hash", "build_ms", "trace_ms",
        "mrays_per_s", "ratio_vs_embree", "bytes_per_prim", "mismatch_real", "machine", "cpu", "git_rev", "cell_key"]


def rayset_hash(s, w):
    """A made-up rayset_hash per cell, 16 hex digits as the CSV and tinyanchor print it."""
    return f"{zlib.crc32(s.encode()):08x}{zlib.crc32(w.encode()):08x}"


def csv_rows(robust=True):
    out = []
    for (s, w), (bvh, off, er, _) in CELLS.items():
        for t in ("1", "2"):
            mr = 10.0 if t == "1" else 19.0  # a 2-thread speed-up of 1.9
            rows = [("bvh", BVH, bvh, 10.0, 70.0), ("embree", EMB, 1.0, 12.0, 80.0)]
            if robust:
                rows += [("bvh", BVH_OFF, off, 10.0, 70.0), ("embree", EMB_ROBUST, er, 13.0, 80.0)]
            for accel, params, ratio, build, bpp in rows:
                out.append({"scene": s, "prims": "1000", "accel": accel, "params": params, "workload": w, "rays": "4096",
                            "threads": t, "rayset_hash": rayset_hash(s, w), "build_ms": build, "trace_ms": 1.0,
                            "mrays_per_s": mr / ratio, "ratio_vs_embree": ratio, "bytes_per_prim": bpp,
                            "mismatch_real": 0, "machine": "testvm", "cpu": "test cpu", "git_rev": "abc",
                            "cell_key": f"{s} {accel} {params} {w} {t}"})
    return out


def write_csv(path, rows):
    with open(path, "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=COLS)
        wr.writeheader()
        wr.writerows(rows)


def result_line(label, s, w, h, tracer, ratio):
    return "\t".join(["RESULT", label, s, w, h, "4096", tracer, f"{ratio:.4f}", f"{ratio * 0.9:.4f}",
                      f"{ratio * 1.1:.4f}", "1.0000", f"{ratio:.4f}", "0", "0"])


def write_logs(folder, bad_hash=None):
    """Two tinyanchor logs; bad_hash=(scene, workload) gives that cell another hash."""
    logs = []
    for k in range(2):
        lines = ["tinyanchor: tinybvh 1.6.7, Embree 3.13.5", "BUILD\tx\t1000\tE_ms=1\tT8_ms=1\tHQ_ms=2\tE_Bpt=1\t"
                 "E_total_Bpt=2\tT8_Bpt=3\tHQ_Bpt=4"]
        for (s, w), (_, _, _, tiny) in CELLS.items():
            if k >= len(tiny):
                continue
            h = rayset_hash(s, w) if (s, w) != bad_hash else "00000000deadbeef"
            lines.append(f"\nrays {s}__{w}.rays: workload {w}, scene {s}, rayset_hash {h}")
            lines.append("WORK\tx\t%s\t%s\tT8\t10.0\t40.0\t3.0\t9.0" % (s, w))
            lines.append(result_line("x", s, w, h, "T8", tiny[k]))
            lines.append(result_line("x", s, w, h, "HQ", tiny[k] * 0.9))
        if k == 0:
            lines.append(result_line("x", "elsewhere", "primary", "0123456789abcdef", "T8", 0.5))
        path = os.path.join(folder, f"anchor{k}.txt")
        with open(path, "w") as f:
            f.write("\n".join(lines) + "\n")
        logs.append(path)
    return logs


def run(args):
    """champion_targets.main(args): (exit status, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            rc = champion_targets.main(args)
        except SystemExit as e:
            rc = e.code
    return rc, out.getvalue(), err.getvalue()


def table_row(text, first, second):
    m = re.search(rf"^\| {re.escape(first)} \| *{re.escape(second)} *\|(.*)\|$", text, re.M)
    return [c.strip() for c in m.group(1).split("|")] if m else None


def target_row(text, start):
    m = re.search(rf"^\| {re.escape(start)}[^|]* \| ([^|]*) \| ([^|]*) \|$", text, re.M)
    return (m.group(1), m.group(2)) if m else None


def geo(vals):
    return math.exp(sum(math.log(v) for v in vals) / len(vals))


def main():
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "matrix.csv")
        write_csv(path, csv_rows())
        logs = write_logs(d)
        rc, text, err = run([path, "--anchor"] + logs)
        check(rc == 0, f"exit status 0 with --anchor (got {rc}: {err})")
        check("## Against tinybvh (tinyanchor) on the same rays" in text, "the anchor table is written")
        header = re.search(r"^\| scene \| workload \|(.*)\|$", text, re.M)
        check(header and [c.strip() for c in header.group(1).split("|")] ==
              ["bvh / Embree", "bvh robust=off / Embree", "tinybvh / Embree", "bvh / tinybvh", "bvh robust=off / tinybvh",
               "tinybvh HQ / Embree"], f"the anchor table's columns ({header and header.group(1)})")
        over, off_over = [], []
        for (s, w), (bvh, off, _, tiny) in CELLS.items():
            t = sorted(tiny)[len(tiny) // 2] if len(tiny) % 2 else sum(tiny) / len(tiny)
            want = [f"{bvh:.3f}", f"{off:.3f}", f"{t:.3f}", f"{bvh / t:.3f}", f"{off / t:.3f}", f"{t * 0.9:.3f}"]
            got = table_row(text, s, w)
            check(got == want, f"{s} {w}: the anchor table's row {got}, expected {want}")
            over.append(bvh / t)
            off_over.append(off / t)
        tinys = [sum(v) / len(v) for *_, v in CELLS.values()]
        want = [f"{geo([c[0] for c in CELLS.values()]):.3f}", f"{geo([c[1] for c in CELLS.values()]):.3f}",
                f"{geo(tinys):.3f}", f"{geo(over):.3f}", f"{geo(off_over):.3f}", f"{geo([t * 0.9 for t in tinys]):.3f}"]
        got = table_row(text, "geometric mean", "")
        check(got == want, f"the geometric means {got}, expected {want}")
        check("elsewhere primary" in text and "left out" in text, "an anchor line for a scene not in the CSV is said")

        # the targets
        g_off = geo(off_over)
        check(target_row(text, "bvh robust=off / tinybvh") ==
              (f"{g_off:.3f} over 4 cells", "met" if g_off <= 0.90 else "missed"),
              f"bvh robust=off / tinybvh target: {target_row(text, 'bvh robust=off / tinybvh')} ({g_off:.3f})")
        g_on = geo(over)
        check(target_row(text, "bvh robust=on / tinybvh") == (f"{g_on:.3f} over 4 cells", "met"),
              f"bvh robust=on / tinybvh target: {target_row(text, 'bvh robust=on / tinybvh')} ({g_on:.3f})")
        check(target_row(text, "bvh robust=off / Embree") == ("worst 1.050, 6 of 8 cells", "missed"),
              f"bvh robust=off / Embree in every cell: {target_row(text, 'bvh robust=off / Embree')}")
        g_r = geo([c[0] / c[2] for c in CELLS.values()])
        check(target_row(text, "bvh robust=on / Embree robust=on") ==
              (f"{g_r:.3f} at 1 thread, {g_r:.3f} at 2 threads", "met"),
              f"bvh robust=on / Embree robust=on: {target_row(text, 'bvh robust=on / Embree robust=on')} ({g_r:.3f})")
        check(target_row(text, "build time <= Embree's at 1 thread") == ("worst 0.83, 2 of 2 scenes", "met"),
              f"build target: {target_row(text, 'build time <= Embree')}")
        check(target_row(text, "memory <= 84") == ("worst 70.0", "met"), f"memory: {target_row(text, 'memory <= 84')}")
        sp = target_row(text, "2-thread trace speed-up")
        check(sp == ("lowest 1.90, 4 of 4 cells", "met"), f"speed-up target: {sp}")

        # a RESULT line on other rays (its rayset_hash differs from the cell's) is refused, nothing written
        bad = os.path.join(d, "bad")
        os.mkdir(bad)
        logs = write_logs(bad, bad_hash=("a", "shadow"))
        out = os.path.join(d, "summary.md")
        rc, text, err = run([path, "--out", out, "--anchor"] + logs)
        check(rc == 2, f"a rayset_hash mismatch exits 2 (got {rc})")
        check("00000000deadbeef" in err and "not the same rays" in err and "a shadow" in err,
              f"the refusal names the cell and the hash: {err.strip()}")
        check(not os.path.exists(out), "nothing is written on a refusal")

        # a malformed RESULT line is refused with its line
        mal = os.path.join(d, "malformed.txt")
        with open(mal, "w") as f:
            f.write("RESULT\tx\ta\tprimary\tnothex\n")
        rc, _, err = run([path, "--anchor", mal])
        check(rc == 2 and "malformed.txt:1" in err, f"a malformed RESULT line exits 2 with its line ({rc}: {err.strip()})")

        # without the robust rows and without --anchor: those targets are not measured, the others still are
        write_csv(path, csv_rows(robust=False))
        rc, text, err = run([path])
        check(rc == 0, f"exit status 0 without the robust rows ({rc}: {err})")
        for t in ("bvh robust=off / tinybvh", "bvh robust=off / Embree", "bvh robust=on / Embree robust=on",
                  "bvh robust=on / tinybvh"):
            row = target_row(text, t)
            check(row is not None and row[0].startswith("not measured") and row[1] == "n/a", f"{t} without its rows: {row}")
        check("## Against tinybvh" not in text, "no anchor table without --anchor")
        check(target_row(text, "memory <= 84") == ("worst 70.0", "met"), "memory still judged without the robust rows")
    report_checks()


if __name__ == "__main__":
    main()
