#!/bin/bash
# test_cli_hostile.sh: names and targets built to break things. Output folders
# whose names hold ', ", $(...), backticks, spaces, a newline and ; get their
# plots from run and merge, and no command in them runs (no shell sees them);
# an output that exists and is not a regular file (a FIFO, a directory, a
# device) is refused with one line and left as it was, by report, merge, run
# (matrix.csv, run.txt) and --save-rays; a plotting failure is a warning;
# scene names that begin with =, -, ' are guarded in the CSV with a ' that
# every reader (resume, merge, plot.py, report.py) drops again, and control
# characters in names never reach the terminal raw; report.py names and skips
# rows with a ratio of 0, a negative or a non-numeric one, and writes the page
# of a run of 1200 scenes. Prints "N passed, N failed"; exits 1 on a failure.
set -u
AB=${ACCELBENCH:?set ACCELBENCH to the accelbench binary}
SRCDIR=${SRCDIR:?set SRCDIR to the source folder}
T=$(mktemp -d /tmp/accelbench-hostile.XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"
PY=/usr/bin/python3
RUN=(run --scenes spd:balls:1 --accels exhaustive --workloads primary --res 8x8 --repeat 1 --threads 1)

# --- folder names that a shell would run: plots written, nothing run
CANARY="$T/canary"
names=("q'uote" "x';touch $CANARY;'" 'd"q' "s\$(touch $CANARY)" "b\`touch $CANARY\`" "sp ace" "n
l" "semi;touch $CANARY;")
"$AB" "${RUN[@]}" --shard 1/1 --no-plots --quiet --out "$T/shard" 2> "$T/shard.err" && ok || { bad "shard run"; cat "$T/shard.err" >&2; }
for n in "${names[@]}"; do
    d="$T/run $n"
    "$AB" "${RUN[@]}" --quiet --out "$d" > "$T/o" 2>&1 && ok || { bad "run --out '$n'"; cat "$T/o" >&2; }
    [ -f "$d/overview__ratio.png" ] && [ -f "$d/spd_balls_1__mrays.png" ] && ok || bad "run --out '$n': no plots"
    grep -q "plotting failed" "$T/o" && bad "run --out '$n': $(cat "$T/o")" || ok
    m="$T/merged $n"
    "$AB" merge "$T/shard" --quiet --out "$m" > "$T/o" 2>&1 && ok || { bad "merge --out '$n'"; cat "$T/o" >&2; }
    [ -f "$m/overview__ratio.png" ] && [ -f "$m/spd_balls_1__mrays.png" ] && [ -f "$m/report.html" ] && ok \
        || bad "merge --out '$n': no plots or report"
done
[ -e "$CANARY" ] && bad "a folder name ran a command" || ok
# a plot that cannot be written is a warning, the run stands
mkdir -p "$T/plotfail/overview__ratio.png"
out=$("$AB" "${RUN[@]}" --quiet --out "$T/plotfail" 2>&1); rc=$?
[ "$rc" = 0 ] && grep -q "accelbench: warning: plotting failed (exit 1); the CSV is complete" <<<"$out" && ok \
    || bad "a failed plot: exit $rc: $out"

# --- outputs that are not regular files: refused with one line, left in place
mkfifo "$T/fifo" && mkdir "$T/dir" || bad "mkfifo"
R="$T/run q'uote"
refused "--out $T/fifo: is a FIFO \(named pipe\), not a regular file" -- timeout 60 "$AB" report "$R" --out "$T/fifo"
refused "--out $T/dir: is a directory, not a regular file" -- timeout 60 "$AB" report "$R" --out "$T/dir"
refused "$T/fifo: is a FIFO" -- timeout 60 "$PY" "$SRCDIR/scripts/report.py" "$R" --out "$T/fifo" --pictures off
refused "--save-rays $T/fifo: is a FIFO" -- timeout 60 "$AB" "${RUN[@]}" --no-plots --out "$T/sr" --save-rays "$T/fifo"
refused "--save-rays $T/dir: a folder, but one ray set" -- timeout 60 "$AB" verify --scenes spd:balls:1 --accels exhaustive \
    --workloads primary --res 8x8 --save-rays "$T/dir"
refused "--save-rays /dev/null: is a character device" -- timeout 60 "$AB" "${RUN[@]}" --no-plots --out "$T/sr" \
    --save-rays /dev/null
for f in matrix.csv run.txt; do
    mkdir -p "$T/special-$f" && mkfifo "$T/special-$f/$f"
    refused "$T/special-$f/$f: is a FIFO" -- timeout 60 "$AB" "${RUN[@]}" --no-plots --out "$T/special-$f"
    [ -p "$T/special-$f/$f" ] && ok || bad "$f: the FIFO was replaced"
done
# resume's rewrite (--redo) onto a matrix.csv that became a FIFO
"$AB" "${RUN[@]}" --no-plots --quiet --out "$T/redo" 2> /dev/null
rm "$T/redo/matrix.csv" && mkfifo "$T/redo/matrix.csv"
refused "$T/redo/matrix.csv: is a FIFO" -- timeout 60 "$AB" "${RUN[@]}" --no-plots --redo --out "$T/redo"
for f in matrix.csv merge.txt; do
    mkdir -p "$T/mspecial-$f/$f"
    refused "$T/mspecial-$f/$f: is a directory" -- timeout 60 "$AB" merge "$T/shard" --no-plots --out "$T/mspecial-$f"
    [ -d "$T/mspecial-$f/$f" ] && [ "$(ls -A "$T/mspecial-$f")" = "$f" ] && ok || bad "merge: $f replaced or another written"
done
[ -p "$T/fifo" ] && [ -d "$T/dir" ] && [ -z "$(ls -A "$T/dir")" ] && [ -c /dev/null ] && ok || bad "a special file was replaced"

# --- scene names a spreadsheet would run, and control characters in names
mkdir -p "$T/names" && cd "$T/names" || exit 1
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > tri.obj
ctl=$(printf 'e\033[31mx\nz.obj')
for n in "=cmd.obj" "-x.obj" "@at.obj" "'q.obj" "$ctl"; do cp tri.obj -- "$n"; done
SC="=cmd.obj,-x.obj,@at.obj,'q.obj,$ctl"
NRUN=(run --scenes "$SC" --accels exhaustive --workloads primary --res 8x8 --repeat 1 --threads 1)
"$AB" "${NRUN[@]}" --out n1 > "$T/n1.out" 2>&1 && ok || { bad "run of hostile names"; cat "$T/n1.out" >&2; }
"$AB" verify --scenes "$SC" --accels exhaustive --workloads primary --res 8x8 >> "$T/n1.out" 2>&1 || bad "verify of hostile names"
"$AB" run --scenes "$(printf 'no\033[2Jsuch.obj')" --accels exhaustive --out n0 >> "$T/n1.out" 2>&1
"$PY" - "$T/n1.out" <<'PY' && ok || bad "a control character reached the terminal: $(cat -A "$T/n1.out" | head -20)"
import sys
data = open(sys.argv[1], "rb").read()
raw = sorted({c for c in data if (c < 0x20 and c != 0x0A) or c == 0x7F})
assert not raw, raw
lines = data.decode().splitlines()
assert not any(l.startswith("z.obj") for l in lines), "a newline in a name forged a line"
assert any("e\\x1b[31mx\\nz.obj" in l for l in lines) and any("no\\x1b[2Jsuch.obj" in l for l in lines), "not escaped"
PY
check_names() { # CSV: raw fields guarded, plot.py's reader gives the names back
    "$PY" - "$SRCDIR/scripts" "$1" "$ctl" <<'PY'
import csv, sys
sys.path.insert(0, sys.argv[1])
import plot
raw = [r[0] for r in list(csv.reader(open(sys.argv[2], newline="")))[1:]]
want = ["=cmd.obj", "-x.obj", "@at.obj", "'q.obj", sys.argv[3]]
assert raw == ["'=cmd.obj", "'-x.obj", "'@at.obj", "''q.obj", sys.argv[3]], raw
assert [r["scene"] for r in plot.load_rows(sys.argv[2])] == want
PY
}
check_names n1/matrix.csv && ok || bad "the CSV's guarded names"
out=$("$AB" "${NRUN[@]}" --out n1 2>&1)
grep -q "nothing to measure: all 5 cells of this run are in n1/matrix.csv" <<<"$out" && ok || bad "resume of hostile names: $out"
"$AB" "${NRUN[@]}" --shard 1/1 --no-plots --quiet --out nshard 2> /dev/null && "$AB" merge nshard --quiet --out nmerged \
    2> "$T/nm.err" && check_names nmerged/matrix.csv && ok || { bad "merge of hostile names"; cat "$T/nm.err" >&2; }
grep -q '<td class="t" data-v="">=cmd.obj</td>' nmerged/report.html && grep -q "<td class=\"t\" data-v=\"\">&#x27;q.obj</td>" \
    nmerged/report.html && ok || bad "the report does not show the names as they are"
cd "$T" || exit 1

# --- report.py: bad rows named and skipped; a run of 1200 scenes gets its page
"$PY" - "$T/shard/matrix.csv" "$T" <<'PY' || bad "making the report inputs"
import csv, os, sys
rows = list(csv.reader(open(sys.argv[1], newline="")))
h, (row,) = rows[0], rows[1:]
si, ki, ri = h.index("scene"), h.index("cell_key"), h.index("ratio_vs_embree")
def write(folder, body):
    os.makedirs(os.path.join(sys.argv[2], folder))
    with open(os.path.join(sys.argv[2], folder, "matrix.csv"), "w", newline="") as f:
        csv.writer(f, lineterminator="\n").writerows([h] + body)
def scene(name, ratio=None):
    r = list(row)
    r[ki] = r[ki].replace("scene=" + r[si], "scene=" + name)
    r[si] = name
    if ratio is not None:
        r[ri] = ratio
    return r
write("bad", [scene("good.obj"), scene("zero.obj", "0"), scene("neg.obj", "-1.5"), scene("text.obj", "fast")])
write("big", [scene(f"s{i}.obj") for i in range(1200)])
PY
out=$(timeout 300 "$PY" "$SRCDIR/scripts/report.py" "$T/bad" --pictures off 2>&1); rc=$?
[ "$rc" = 0 ] && [ -s "$T/bad/report.html" ] && ok || bad "report.py on bad rows: exit $rc: $out"
grep -q "report.py: warning: $T/bad/matrix.csv:3: ratio_vs_embree '0' is not above 0; row skipped" <<<"$out" \
    && grep -q "matrix.csv:4: ratio_vs_embree '-1.5' is not above 0; row skipped" <<<"$out" \
    && grep -q "matrix.csv:5: ratio_vs_embree 'fast' is not a number; row skipped" <<<"$out" && ok || bad "bad rows not named: $out"
grep -q ">good.obj<" "$T/bad/report.html" && ! grep -q ">zero.obj<" "$T/bad/report.html" && ok || bad "bad rows not skipped"
out=$(timeout 600 "$AB" report "$T/big" --pictures off 2>&1); rc=$?
[ "$rc" = 0 ] && [ -s "$T/big/report.html" ] && ok || bad "report of 1200 scenes: exit $rc: $out"
n=$(grep -o '<td class="t" data-v="">s[0-9]*\.obj</td>' "$T/big/report.html" | sort -u | wc -l)
[ "$n" = 1200 ] && ok || bad "report of 1200 scenes: $n scenes in the table"
grep -q 'alt="Heat map of trace time relative to Embree' "$T/big/report.html" && ok \
    || bad "report of 1200 scenes: no overview (a figure past matplotlib's 65536 pixels?)"

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
