#!/bin/bash
# test_shard.sh: sharded runs as a user meets them: run --shard
# K/N's refusals (exit 2, one line); a matrix of 2 scenes x 3 accelerators x
# 2 workloads run as 3 shards and merged equals a one-machine run of it in
# every column but the timing and machine columns (scripts/compare_matrix.py),
# rows in the same order; a shard resumed in its folder measures nothing
# again and adds no row; a folder of another shard is refused; merge with a
# shard missing lists the missing cells, with a shard folder given twice
# lists the duplicates, with shards of other options says which option
# differs (each exit 2); merge --help. Prints "N passed, N failed"; exits 1
# on a failure.
set -u
AB=${ACCELBENCH:?set ACCELBENCH to the accelbench binary}
SRCDIR=${SRCDIR:?set SRCDIR to the source folder}
T=$(mktemp -d /tmp/accelbench-shard.XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"
PY=/usr/bin/python3

M0=(--scenes spd:balls:1,spd:gears:1 --accels exhaustive,embree,grid --workloads primary,shadow --res 16x16 --repeat 1
    --threads 1 --no-plots)
M=("${M0[@]}" --quiet)

# --- refusals
for bad in 0/3 3/2 1/4097 x 1/2/3 ""; do
    refused "--shard $bad: expected K/N with 1 <= K <= N <= 4096" -- "$AB" run "${M[@]}" --shard "$bad" --out "$T/bad"
done
refused "--shard is an option of run" -- "$AB" verify --scenes spd:balls:1 --shard 1/2
expect 0 "usage: accelbench merge DIR" -- "$AB" merge --help
expect 0 "--shard K/N" -- "$AB" run --help
refused "no shard folder given" -- "$AB" merge --out "$T/x"
refused "no --out DIR given" -- "$AB" merge "$T"
refused "$T/nope/shard.txt: cannot open" -- "$AB" merge "$T/nope" --out "$T/x"

# --- the one-machine run and three shards
"$AB" run "${M[@]}" --out "$T/one" 2> "$T/one.err" && ok || { bad "one-machine run"; cat "$T/one.err" >&2; }
for k in 1 2 3; do
    "$AB" run "${M[@]}" --shard $k/3 --out "$T/s$k" 2> "$T/s$k.err" && ok || { bad "shard $k/3"; cat "$T/s$k.err" >&2; }
    grep -q "^shard: $k/3: " "$T/s$k/run.txt" && ok || bad "run.txt of shard $k says no shard"
    grep -q "^shard: $k/3$" "$T/s$k/shard.txt" && grep -q "^cells: 12$" "$T/s$k/shard.txt" && ok || bad "shard.txt of shard $k"
done
n1=$(($(wc -l < "$T/s1/matrix.csv") + $(wc -l < "$T/s2/matrix.csv") + $(wc -l < "$T/s3/matrix.csv") - 3))
[ "$n1" = 12 ] && ok || bad "the three shards hold $n1 rows, want 12"
for k in 1 2 3; do
    [ "$(wc -l < "$T/s$k/matrix.csv")" -gt 1 ] && ok || bad "shard $k/3 has no cell"
done
"$AB" merge "$T/s1" "$T/s2" "$T/s3" --out "$T/merged" --no-plots 2> "$T/merge.err" && ok || { bad "merge"; cat "$T/merge.err" >&2; }
grep -q "merged 12 cells of 3 shards" "$T/merge.err" && ok || bad "merge did not say what it merged"
"$PY" "$SRCDIR/scripts/compare_matrix.py" "$T/one/matrix.csv" "$T/merged/matrix.csv" > "$T/cmp.out" && ok \
    || { bad "merged != one-machine run"; cat "$T/cmp.out" >&2; }
grep -q "skipped build_ms, trace_ms.*run_id, machine, cpu, date" "$T/cmp.out" && ok || bad "compare skipped other columns: $(head -1 "$T/cmp.out")"
# the comparison can fail: a changed counter is found
sed '2s/,0,0,0,0,0,0,/,0,0,0,0,0,7,/' "$T/merged/matrix.csv" > "$T/changed.csv"
if cmp -s "$T/changed.csv" "$T/merged/matrix.csv"; then bad "the sed did not change a row"
else ! "$PY" "$SRCDIR/scripts/compare_matrix.py" "$T/one/matrix.csv" "$T/changed.csv" > /dev/null && ok || bad "compare missed a change"; fi
# merged again: the same bytes (deterministic)
"$AB" merge "$T/s3" "$T/s1" "$T/s2" --out "$T/merged2" --no-plots --quiet && cmp -s "$T/merged/matrix.csv" "$T/merged2/matrix.csv" \
    && ok || bad "merging in another folder order gave another file"

# --- resume within a shard folder: nothing measured again, no row added
before=$(wc -l < "$T/s2/matrix.csv")
"$AB" run "${M0[@]}" --shard 2/3 --out "$T/s2" > "$T/resume.out" 2>&1 && ok || bad "resume of shard 2/3"
grep -q "nothing to measure" "$T/resume.out" && [ "$(wc -l < "$T/s2/matrix.csv")" = "$before" ] && ok \
    || { bad "resumed shard measured again"; tail -3 "$T/resume.out" >&2; }
# a row lost (the task killed before writing it): the resumed shard measures that cell only
head -n -1 "$T/s2/matrix.csv" > "$T/cut" && cat "$T/cut" > "$T/s2/matrix.csv"
"$AB" run "${M0[@]}" --shard 2/3 --out "$T/s2" > "$T/resume2.out" 2>&1 && ok || bad "resume of a cut shard"
[ "$(grep -c '^\[' "$T/resume2.out")" = 1 ] && [ "$(wc -l < "$T/s2/matrix.csv")" = "$before" ] && ok \
    || { bad "the cut shard did not measure exactly its missing cell"; cat "$T/resume2.out" >&2; }
refused "s2/shard.txt: this folder holds shard 2/3 of this matrix; choose another --out" -- "$AB" run "${M[@]}" --shard 1/3 --out "$T/s2"
refused "s2/shard.txt: this folder holds shard 2/3 of another matrix" -- "$AB" run "${M[@]}" --seed 7 --shard 2/3 --out "$T/s2"

# --- a missing shard: exit 2, its cells listed
out=$("$AB" merge "$T/s1" "$T/s3" --out "$T/m1" --no-plots 2>&1); rc=$?
n2=$(($(wc -l < "$T/s2/matrix.csv") - 1))
[ $rc = 2 ] && ok || bad "merge without shard 2: exit $rc"
grep -q "^accelbench merge: $n2 of the matrix's 12 cells missing, 0 duplicated" <<<"$out" && ok || bad "missing count: $(head -1 <<<"$out")"
[ "$(grep -c '^  missing: scene=.*(shard 2/3, no folder given)$' <<<"$out")" = "$n2" ] && ok || bad "missing cells not listed: $out"
[ ! -e "$T/m1/matrix.csv" ] && ok || bad "a failed merge wrote a CSV"

# --- a shard folder given twice: exit 2, duplicates listed
n3=$(($(wc -l < "$T/s3/matrix.csv") - 1))
out=$("$AB" merge "$T/s1" "$T/s2" "$T/s3" "$T/s3" --out "$T/m2" --no-plots 2>&1); rc=$?
[ $rc = 2 ] && ok || bad "merge with shard 3 twice: exit $rc"
grep -q "^accelbench merge: 0 of the matrix's 12 cells missing, $n3 duplicated" <<<"$out" && ok || bad "duplicate count: $(head -1 <<<"$out")"
[ "$(grep -c "^  duplicated: scene=.* (in $T/s3 and $T/s3)$" <<<"$out")" = "$n3" ] && grep -q "shard 3/3 given 2 times" <<<"$out" \
    && ok || bad "duplicates not listed: $out"
# a copy of a row in another shard's folder
tail -1 "$T/s3/matrix.csv" >> "$T/s1/matrix.csv"
out=$("$AB" merge "$T/s1" "$T/s2" "$T/s3" --out "$T/m2" --no-plots 2>&1); rc=$?
[ $rc = 2 ] && grep -q "1 duplicated" <<<"$out" && grep -q "(in $T/s1 and $T/s3)" <<<"$out" && ok || bad "a copied row: exit $rc: $out"
head -n -1 "$T/s1/matrix.csv" > "$T/cut" && cat "$T/cut" > "$T/s1/matrix.csv"

# --- mismatched options: exit 2, the option named
"$AB" run "${M[@]}" --repeat 2 --shard 2/3 --out "$T/r2" 2> /dev/null
refused "the shards are not of one matrix: options differ between $T/s1 and $T/r2: repeat=1 vs repeat=2" -- \
    "$AB" merge "$T/s1" "$T/r2" "$T/s3" --out "$T/m3" --no-plots
"$AB" run "${M[@]}" --shard 2/4 --out "$T/q2" 2> /dev/null
refused "the shards are not of one matrix: $T/s1 is shard 1/3, $T/q2 is shard 2/4" -- "$AB" merge "$T/s1" "$T/q2" --out "$T/m3"
# another build: the rows' git_rev differ
sed -i "s/,$(sed -n 2p "$T/s3/matrix.csv" | "$PY" -c 'import csv,sys; print(next(csv.reader(sys.stdin))[-4])'),/,0000000-other,/" "$T/s3/matrix.csv"
out=$("$AB" merge "$T/s1" "$T/s2" "$T/s3" --out "$T/m4" --no-plots 2>&1); rc=$?
[ $rc = 2 ] && grep -q "rows of 2 git revisions" <<<"$out" && grep -q "^  0000000-other: $T/s3$" <<<"$out" && ok \
    || bad "mixed revisions: exit $rc: $out"
"$AB" merge "$T/s1" "$T/s2" "$T/s3" --out "$T/m4" --no-plots --allow-mixed-revisions > /dev/null 2>&1 && ok \
    || bad "--allow-mixed-revisions refused"
refused "is one of the shard folders" -- "$AB" merge "$T/s1" "$T/s2" --out "$T/s2"

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
