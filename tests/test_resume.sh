#!/bin/bash
# test_resume.sh: resumable and lossless runs, as a user
# meets them: a run killed with SIGKILL after 0, 1 and 3 rows and mid-row
# (a torn last line, simulated by cutting the file), then started again
# with the same --out, ends with every cell exactly once in a CSV that
# python's csv module reads whole; the found/skipped message; --redo
# replaces rows (no duplicates, other rows kept in place); other options
# are other cells; SIGTERM and SIGINT abandon the cell in progress, exit
# 128+signal and print the exact command that resumes; an output that is
# a device (matrix.csv, run.txt, a saved ray file as symlinks to /dev/full)
# is refused with exit 2, and a write past the file size limit (as on a
# full disk) is exit 1 with the reason and leaves no half row; a second run on
# the same folder is refused; a replayed ray file's own resolution and
# samples are what the row says; a ray set of no rays gives rows with
# rays 0 and empty measurements; --keep-going skips a cell whose build
# fails and measures the rest (exit 2), without it the run stops there;
# plot.py keeps the last row of a cell.
# Prints "N passed, N failed"; exits 1 on a failure.
set -u
set -m # background runs get SIGINT as a terminal's job would (a script's background jobs ignore it otherwise)
AB=${ACCELBENCH:?set ACCELBENCH to the accelbench binary}
SRCDIR=${SRCDIR:?set SRCDIR to the source folder}
T=$(mktemp -d /tmp/accelbench-resume.XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"

# 1 scene x 2 accelerators x 3 workloads = 6 cells of about 0.3 s each.
RUN=(run --scenes spd:balls:1 --accels exhaustive,embree --workloads primary,shadow,random --res 16x16 --repeat 3
     --threads 1 --no-plots)

rows() { [ -f "$1" ] && echo $(($(wc -l < "$1") - 1)) || echo -1; }

# check_csv FILE [KEYS_FILE]: every line a whole row of the header's fields, each cell key once, the file ending in
# a line break; with KEYS_FILE, exactly those cell keys. Prints the row count.
check_csv() {
    /usr/bin/python3 - "$@" <<'PY'
import csv, sys
data = open(sys.argv[1], newline="").read()
assert data.endswith("\n"), "the file does not end with a line break"
rows = list(csv.reader(data.splitlines(keepends=True)))
header, body = rows[0], rows[1:]
bad = [i + 2 for i, r in enumerate(body) if len(r) != len(header)]
assert not bad, f"lines {bad} have other than {len(header)} fields"
k = header.index("cell_key")
keys = [r[k] for r in body]
dup = sorted({x for x in keys if keys.count(x) > 1})
assert not dup, f"cells more than once: {dup}"
assert all(keys) and all(r[header.index("run_id")] for r in body), "a row without run_id or cell_key"
if len(sys.argv) > 2:
    want = set(open(sys.argv[2]).read().splitlines())
    assert set(keys) == want, f"missing {sorted(want - set(keys))}, extra {sorted(set(keys) - want)}"
print(len(body))
PY
}
keys_of() { /usr/bin/python3 -c 'import csv,sys; [print(r["cell_key"]) for r in csv.DictReader(open(sys.argv[1]))]' "$1"; }

# --- the reference: the whole matrix in one go
"$AB" "${RUN[@]}" --out "$T/ref" --quiet 2> "$T/ref.err" && ok || { bad "reference run"; cat "$T/ref.err" >&2; }
n=$(check_csv "$T/ref/matrix.csv") && [ "$n" = 6 ] && ok || bad "reference CSV: $n"
keys_of "$T/ref/matrix.csv" > "$T/keys"
grep -q "^run_id: " "$T/ref/run.txt" && ok || bad "run.txt has no run_id"

# --- SIGKILL after 0, 1 and 3 rows, then the same command again
for k in 0 1 3; do
    d="$T/kill$k"
    "$AB" "${RUN[@]}" --out "$d" --quiet 2> /dev/null &
    pid=$!
    for _ in $(seq 1 1000); do [ "$(rows "$d/matrix.csv")" -ge "$k" ] && break; sleep 0.01; done
    kill -KILL "$pid"
    wait "$pid" 2> /dev/null
    before=$(rows "$d/matrix.csv")
    [ "$before" -ge "$k" ] && [ "$before" -lt 6 ] && ok || bad "kill after $k rows: the file had $before rows"
    "$AB" "${RUN[@]}" --out "$d" > "$d.out" 2>&1 && ok || { bad "resume after kill at $k"; tail -3 "$d.out" >&2; }
    n=$(check_csv "$d/matrix.csv" "$T/keys") && [ "$n" = 6 ] && ok || bad "resume after kill at $k rows: $n"
    if [ "$before" -gt 0 ]; then
        grep -q "matrix.csv: $before rows from 1 run; $before of this run's 6 cells are done with the same options: skipping them" "$d.out" \
            && ok || { bad "resume after $before rows did not say what it found"; head -3 "$d.out" >&2; }
    fi
    measured=$(grep -c '^\[[0-9]*/6\]' "$d.out")
    [ "$measured" = $((6 - before)) ] && ok || bad "resume after $before rows measured $measured cells"
done

# --- mid-row: the last line cut (no line break), and cut with a line break (too few fields)
cp -r "$T/ref" "$T/torn"
size=$(stat -c %s "$T/torn/matrix.csv")
truncate -s $((size - 40)) "$T/torn/matrix.csv"
"$AB" "${RUN[@]}" --out "$T/torn" > "$T/torn.out" 2>&1 && ok || bad "resume of a torn file"
grep -q "matrix.csv: line 7: a torn row (no line break at the end of the file), left by a run killed while writing it: dropped" "$T/torn.out" \
    && ok || { bad "no torn-row message"; head -3 "$T/torn.out" >&2; }
n=$(check_csv "$T/torn/matrix.csv" "$T/keys") && [ "$n" = 6 ] && ok || bad "torn file resumed: $n"
[ "$(grep -c '^\[[0-9]*/6\]' "$T/torn.out")" = 1 ] && ok || bad "the torn row's cell was not the one run again"
cp -r "$T/ref" "$T/short"
/usr/bin/python3 - "$T/short/matrix.csv" <<'PY'
import sys
lines = open(sys.argv[1]).read().splitlines(keepends=True)
lines[-1] = ",".join(lines[-1].split(",")[:5]) + "\n"  # the last row cut after its workload, then a line break
open(sys.argv[1], "w").write("".join(lines))
PY
"$AB" "${RUN[@]}" --out "$T/short" > "$T/short.out" 2>&1 && ok || bad "resume of a short last row"
grep -qE "line 7: a torn row \([0-9]+ fields, expected [0-9]+\)" "$T/short.out" && ok || { bad "no short-row message"; head -3 "$T/short.out" >&2; }
n=$(check_csv "$T/short/matrix.csv" "$T/keys") && [ "$n" = 6 ] && ok || bad "short row resumed: $n"
# the row the old program glued onto a torn one (67 fields) has nowhere to come from now: the file above parsed whole

# --- all done: nothing measured, the file unchanged
cp "$T/ref/matrix.csv" "$T/ref.before"
"$AB" "${RUN[@]}" --out "$T/ref" > "$T/again.out" 2>&1 && ok || bad "rerun of a finished run"
grep -q "nothing to measure: all 6 cells of this run are in" "$T/again.out" && ok || bad "finished run: no 'nothing to measure'"
cmp -s "$T/ref.before" "$T/ref/matrix.csv" && ok || bad "a finished run's rerun changed its CSV"

# --- --redo: the exhaustive cells again, their rows replaced in place, embree's kept
"$AB" "${RUN[@]/exhaustive,embree/exhaustive}" --out "$T/ref" --redo > "$T/redo.out" 2>&1 && ok || bad "--redo run"
grep -q "3 of this run's 3 cells are done with the same options: measuring them again (--redo), their rows replaced" "$T/redo.out" \
    && ok || { bad "--redo message"; head -2 "$T/redo.out" >&2; }
n=$(check_csv "$T/ref/matrix.csv" "$T/keys") && [ "$n" = 6 ] && ok || bad "after --redo: $n"
newid=$(awk '/^run_id:/ {id = $2} END {print id}' "$T/ref/run.txt")
/usr/bin/python3 - "$T/ref.before" "$T/ref/matrix.csv" "$newid" <<'PY' && ok || bad "--redo did not replace exactly the exhaustive rows in place"
import csv, sys
old, new = (list(csv.DictReader(open(p))) for p in sys.argv[1:3])
assert [r["cell_key"] for r in old] == [r["cell_key"] for r in new], "rows moved"
for o, n in zip(old, new):
    if n["accel"] == "exhaustive":
        assert n["run_id"] == sys.argv[3] != o["run_id"], (n["run_id"], sys.argv[3])
    else:
        assert n == o, "an embree row changed"
PY
ls -a "$T/ref" | grep -q 'tmp' && bad "a temporary file is left in the folder" || ok

# --- other options are other cells: appended, nothing skipped
"$AB" "${RUN[@]/--repeat/--seed}" --repeat 2 --out "$T/ref" > "$T/other.out" 2>&1 && ok || bad "run with other options"
grep -q "6 rows from 2 runs; none of this run's 6 cells is among them" "$T/other.out" && ok || { bad "other options: message"; head -2 "$T/other.out" >&2; }
n=$(check_csv "$T/ref/matrix.csv") && [ "$n" = 12 ] && ok || bad "other options: $n rows"

# --- SIGTERM and SIGINT: the cell in progress abandoned, exit 128+N, the exact command that resumes
for sig in TERM INT; do
    d="$T/sig$sig"
    "$AB" "${RUN[@]}" --quiet --out "$d" 2> "$d.err" &
    pid=$!
    for _ in $(seq 1 1000); do [ "$(rows "$d/matrix.csv")" -ge 1 ] && break; sleep 0.01; done
    kill -"$sig" "$pid"
    wait "$pid"
    rc=$?
    want=$([ $sig = TERM ] && echo 143 || echo 130)
    [ "$rc" = "$want" ] && ok || bad "SIG$sig: exit $rc, want $want"
    grep -q "interrupted by SIG$sig: the cell in progress is abandoned" "$d.err" && ok || bad "SIG$sig: no message"
    n=$(check_csv "$d/matrix.csv") && [ "$n" -ge 1 ] && [ "$n" -lt 6 ] && ok || bad "SIG$sig: CSV after the signal: $n"
    cmd=$(grep -A1 "to resume" "$d.err" | tail -1)
    case "$cmd" in "  $AB run --scenes spd:balls:1 "*"--out $d"*) ok ;; *) bad "SIG$sig: resume command '$cmd'" ;; esac
    eval "$cmd" 2> "$d.resume" && ok || bad "SIG$sig: the printed command failed"
    n=$(check_csv "$d/matrix.csv" "$T/keys") && [ "$n" = 6 ] && ok || bad "SIG$sig: resumed CSV: $n"
done
# without --out, the resume command names the folder the run chose
(cd "$T" && exec "$AB" "${RUN[@]}" --quiet 2> "$T/noout.err") &
pid=$!
for _ in $(seq 1 1000); do compgen -G "$T/results/*/matrix.csv" > /dev/null && break; sleep 0.01; done
kill -TERM "$pid"
wait "$pid"
grep -A1 "to resume" "$T/noout.err" | tail -1 | grep -qE -- "--quiet --out results/[0-9]{8}-[0-9]{6}$" && ok || { bad "no --out: resume command"; cat "$T/noout.err" >&2; }

# --- a second run on the same folder is refused while the first holds it
"$AB" "${RUN[@]}" --quiet --out "$T/lock" 2> /dev/null &
pid=$!
for _ in $(seq 1 1000); do [ -f "$T/lock/matrix.csv" ] && break; sleep 0.01; done
out=$("$AB" "${RUN[@]}" --quiet --out "$T/lock" 2>&1); rc=$?
kill -KILL "$pid"; wait "$pid" 2> /dev/null
[ "$rc" = 2 ] && grep -q "another accelbench run is writing to this folder" <<<"$out" && ok || bad "second run on a held folder: exit $rc: $out"

# --- outputs that are devices (a symlink to /dev/full): refused with one line, nothing replaced
mkdir -p "$T/full" "$T/fullinfo" "$T/fullrays"
ln -s /dev/full "$T/full/matrix.csv"
out=$("$AB" "${RUN[@]}" --out "$T/full" 2>&1); rc=$?
[ "$rc" = 2 ] && [ "$out" = "accelbench: $T/full/matrix.csv: is a character device, not a regular file: not written (give the path of a file)" ] \
    && ok || bad "matrix.csv on /dev/full: exit $rc: $out"
ln -s /dev/full "$T/fullinfo/run.txt"
out=$("$AB" "${RUN[@]}" --out "$T/fullinfo" 2>&1); rc=$?
[ "$rc" = 2 ] && grep -q "$T/fullinfo/run.txt: is a character device" <<<"$out" && ok || bad "run.txt on /dev/full: exit $rc: $out"
ln -s /dev/full "$T/fullrays/p.rays"
out=$("$AB" run --scenes spd:balls:1 --accels exhaustive --workloads primary --res 8x8 --repeat 1 --no-plots \
      --save-rays "$T/fullrays/p.rays" --out "$T/fullrays" 2>&1); rc=$?
[ "$rc" = 2 ] && grep -q "$T/fullrays/p.rays: is a character device" <<<"$out" && ok || bad "ray file on /dev/full: exit $rc: $out"
[ -c /dev/full ] && [ -L "$T/fullrays/p.rays" ] && [ -L "$T/full/matrix.csv" ] && [ -L "$T/fullinfo/run.txt" ] && ok \
    || bad "/dev/full or a symlink to it was replaced"
# --- failed writes (past the file size limit, as on a full disk): exit 1 with the reason, never a half row
mkdir -p "$T/bigrays" "$T/biginfo"
out=$(bash -c 'ulimit -f 8; trap "" XFSZ; exec "$@"' sh "$AB" run --scenes spd:balls:1 --accels exhaustive --workloads primary \
      --res 64x64 --repeat 1 --no-plots --save-rays "$T/bigrays/p.rays" --out "$T/bigrays" 2>&1); rc=$?
[ "$rc" = 1 ] && grep -q "$T/bigrays/p.rays: write failed: File too large" <<<"$out" && [ ! -e "$T/bigrays/p.rays" ] && ok \
    || bad "ray file past the size limit: exit $rc: $out"
head -c 8192 /dev/zero | tr '\0' '#' > "$T/biginfo/run.txt"
out=$(bash -c 'ulimit -f 8; trap "" XFSZ; exec "$@"' sh "$AB" "${RUN[@]}" --out "$T/biginfo" 2>&1); rc=$?
[ "$rc" = 1 ] && grep -q "$T/biginfo/run.txt: write failed: File too large" <<<"$out" && ok || bad "run.txt past the size limit: exit $rc: $out"
# the file size limit reached mid-run (a disk filling up): exit 1, whole rows only, and the run resumes
out=$(bash -c 'ulimit -f 3; trap "" XFSZ; exec "$@"' sh "$AB" "${RUN[@]}" --out "$T/fsize" 2>&1); rc=$?
[ "$rc" = 1 ] && grep -q "$T/fsize/matrix.csv: write failed: File too large" <<<"$out" && ok || bad "file size limit: exit $rc: $out"
n=$(check_csv "$T/fsize/matrix.csv") && [ "$n" -ge 1 ] && [ "$n" -lt 6 ] && ok || bad "file size limit: CSV: $n"
"$AB" "${RUN[@]}" --out "$T/fsize" --quiet 2> /dev/null && n=$(check_csv "$T/fsize/matrix.csv" "$T/keys") && [ "$n" = 6 ] && ok \
    || bad "resume after the file size limit: $n"
# --save-rays into a folder that does not exist: refused before any work
out=$("$AB" "${RUN[@]}" --workloads primary --save-rays "$T/nodir/x.rays" --out "$T/nodir2" 2>&1); rc=$?
[ "$rc" = 2 ] && grep -q "folder $T/nodir does not exist" <<<"$out" && [ ! -e "$T/nodir2" ] && ok || bad "save-rays to no folder: exit $rc: $out"

# --- what ran: a replayed file's own resolution and samples, its cells keyed by its rays
"$AB" verify --scenes spd:balls:1 --workloads primary --res 20x12 --spp 2 --accels exhaustive --save-rays "$T/p.rays" > /dev/null 2>&1
"$AB" run --scenes spd:balls:1 --accels exhaustive --rays "$T/p.rays" --repeat 1 --no-plots --out "$T/replay" --quiet && ok || bad "replay run"
/usr/bin/python3 - "$T/replay/matrix.csv" <<'PY' && ok || bad "a replay's row does not record the file's res and spp"
import csv, sys
(r,) = list(csv.DictReader(open(sys.argv[1])))
assert (r["res"], r["spp"], r["rays"]) == ("20x12", "2", "480"), (r["res"], r["spp"], r["rays"])
assert " rays=" + r["rayset_hash"] + " " in r["cell_key"] and " res=" not in r["cell_key"], r["cell_key"]
PY
out=$("$AB" run --scenes spd:balls:1 --accels exhaustive --rays "$T/p.rays" --repeat 1 --no-plots --out "$T/replay" 2>&1)
grep -q "nothing to measure: all 1 cells" <<<"$out" && ok || bad "a replay's cell is not skipped when done: $out"

# --- a ray set of no rays: rows say rays 0, nothing measured (no times or ratios of tracing nothing)
"$AB" run --scenes spd:balls:1 --view 'eye=0,0,10;at=0,0,20;up=0,1,0' --accels exhaustive,embree --workloads primary,shadow \
    --res 8x8 --repeat 1 --no-plots --out "$T/empty" 2> "$T/empty.err" && ok || bad "run with an empty ray set"
grep -q "shadow: the ray set has no rays" "$T/empty.err" && ok || bad "no word on the empty ray set"
/usr/bin/python3 - "$T/empty/matrix.csv" <<'PY' && ok || bad "rows of an empty ray set"
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["workload"] == "shadow"]
assert len(rows) == 2
for r in rows:
    assert r["rays"] == "0" and r["agree"] == "0" and r["mismatch_real"] == "0"
    assert all(r[c] == "" for c in ("build_ms", "trace_ms", "mrays_per_s", "ratio_vs_embree", "embree_ms",
                                     "mem_bytes", "tests_per_ray", "passes", "timed_path")), r
PY

# --- --keep-going: a cell whose build fails (a grid over the memory cap) is skipped and the rest measured, exit 2;
# without it the run stops there
KG=(run --scenes spd:balls:1 --accels "grid[res=600x600x600],exhaustive" --workloads primary,shadow --res 16x16 --repeat 1
    --threads 1 --no-plots --memcap 256)
expect 2 "2 cell\(s\) not measured: their builds failed" -- "$AB" "${KG[@]}" --keep-going --out "$T/kg"
[ "$(rows "$T/kg/matrix.csv")" = 2 ] && ok || bad "--keep-going measured $(rows "$T/kg/matrix.csv") cells, want 2"
expect 2 "build failed" -- "$AB" "${KG[@]}" --out "$T/kgstop"
[ "$(rows "$T/kgstop/matrix.csv")" -le 0 ] && ok || bad "without --keep-going the run went on past the failed build"
refused "keep-going is an option of run" -- "$AB" verify --scenes spd:balls:1 --accels grid --keep-going

# --- plot.py: the last row of a cell wins, in files with and without cell_key
/usr/bin/python3 - "$SRCDIR/scripts" "$T/ref/matrix.csv" <<'PY' && ok || bad "plot.py keeps the last row of a cell"
import csv, io, sys
sys.path.insert(0, sys.argv[1])
import plot
rows = list(csv.DictReader(open(sys.argv[2])))
first, second = dict(rows[0]), dict(rows[0])
first["mrays_per_s"], second["mrays_per_s"] = "1.5", "2.5"
kept = plot.dedup_rows([first] + rows[1:] + [second], "x.csv")
assert len(kept) == len(rows) and [r["mrays_per_s"] for r in kept if r["cell_key"] == first["cell_key"]] == ["2.5"]
legacy = [{k: v for k, v in r.items() if k not in ("cell_key", "run_id")} for r in (first, second)]
assert [r["mrays_per_s"] for r in plot.dedup_rows(legacy, "x.csv")] == ["2.5"]
PY
cp "$T/ref/matrix.csv" "$T/dup.csv"
tail -1 "$T/ref/matrix.csv" >> "$T/dup.csv"
out=$(/usr/bin/python3 "$SRCDIR/scripts/plot.py" "$T/dup.csv" --out "$T/dupplots" --quiet 2>&1) && grep -q "1 rows measure a cell a later row measures again" <<<"$out" \
    && ok || bad "plot.py on duplicates: $out"

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
