#!/usr/bin/python3
"""compare_matrix.py A.csv B.csv: whether two accelbench matrix CSVs measure
the same cells with the same answers: the same cell keys in the same order,
and equal values in every column but the timing and machine columns, which
are told from the header by name:

  timing:  a name ending in _ms or holding _ms_ (build_ms, trace_ms,
           trace_ms_min/max, embree_ms, judge_ms, stat_lazy_build_ms),
           starting with mrays (throughput) or ratio (ratios to Embree and
           their spreads), passes (traces a timed sample repeats to outlast the
           clock's resolution: chosen by the time it takes)
  machine: run_id, machine, cpu, date

Used by tests/test_shard.sh and tests/test_slurm.sh: a merged N-shard run
against a one-machine run. Prints the columns it compared and skipped, and
every difference (at most 20); exits 0 when equal, 1 when not, 2 on a bad
file."""
import csv
import sys

MACHINE = {"run_id", "machine", "cpu", "date"}


def skipped(name):
    return (name.endswith("_ms") or "_ms_" in name or name.startswith("mrays") or name.startswith("ratio")
            or name == "passes" or name in MACHINE)


def read(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        print(f"compare_matrix: {path}: {e.strerror}", file=sys.stderr)
        sys.exit(2)
    if not rows:
        print(f"compare_matrix: {path}: empty", file=sys.stderr)
        sys.exit(2)
    return rows[0], rows[1:]


def main():
    if len(sys.argv) != 3:
        print("usage: compare_matrix.py A.csv B.csv", file=sys.stderr)
        sys.exit(2)
    (ha, ra), (hb, rb) = read(sys.argv[1]), read(sys.argv[2])
    if ha != hb:
        print(f"compare_matrix: the headers differ: {sorted(set(ha) ^ set(hb))}")
        sys.exit(1)
    k = ha.index("cell_key")
    ka, kb = [r[k] for r in ra], [r[k] for r in rb]
    if ka != kb:
        if sorted(ka) != sorted(kb):
            print(f"compare_matrix: other cells: only in A {sorted(set(ka) - set(kb))[:5]}, "
                  f"only in B {sorted(set(kb) - set(ka))[:5]} ({len(ka)} and {len(kb)} rows)")
        else:
            print(f"compare_matrix: the same {len(ka)} cells in another order")
        sys.exit(1)
    compared = [i for i, n in enumerate(ha) if not skipped(n)]
    print(f"compare_matrix: {len(ka)} rows; compared {len(compared)} columns; skipped "
          f"{', '.join(n for n in ha if skipped(n))}")
    diffs = [(r, ha[i], a[i], b[i]) for r, (a, b) in enumerate(zip(ra, rb)) for i in compared if a[i] != b[i]]
    for r, name, x, y in diffs[:20]:
        print(f"  row {r + 2} ({ka[r][:80]}): {name}: {x!r} vs {y!r}")
    if diffs:
        print(f"compare_matrix: {len(diffs)} differences in columns {sorted({d[1] for d in diffs})}")
        sys.exit(1)
    print("compare_matrix: equal in every compared column")


if __name__ == "__main__":
    main()
