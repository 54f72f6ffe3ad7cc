#!/bin/bash
# test_cli_upfront.sh: what run, verify, resume and merge check before the first cell, and what they refuse
# rather than guess: cell keys that do not depend on the memory limit, --accels sweeps counted before they are
# expanded, every scene, number, path and --save-rays target checked up front, a scene named twice measured once,
# a CSV holding a cell twice or a row contradicting its key refused, and messages in the user's terms (a folder
# given as a ray file, a CSV with a byte-order mark). Prints "N passed, N failed"; exits 1 on a failure.
set -u
AB=${ACCELBENCH:?set ACCELBENCH to the accelbench binary}
T=$(mktemp -d /tmp/accelbench-upfront.XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"

TINY=(--workloads primary --res 8x8 --repeat 1 --threads 1 --no-plots --quiet)
rows() { python3 -c 'import csv, sys; print(sum(1 for _ in csv.DictReader(open(sys.argv[1]))))' "$1"; }
# The given columns of every row of a CSV, one row a line.
cols() { python3 -c 'import csv, sys; [print(*(r[c] for c in sys.argv[2:]), sep=" | ") for r in csv.DictReader(open(sys.argv[1]))]' "$@"; }

# --- the memory limit is not part of a cell: the same run with and without ulimit -v (whose cap, half of it,
# is below the accelerators' own cap of 4096 MiB) has the same keys, params and labels, and resumes.
# capped CMD...: CMD under that limit. Under AddressSanitizer (scripts/test.sh's second run) no address-space
# limit can run (its shadow memory reserves terabytes), so there the same cap is given as --memcap 1411, the
# other way the cap is set; build/ runs these cases under ulimit -v itself.
if ldd "$AB" 2>/dev/null | grep -q libasan; then
    echo "note: AddressSanitizer build: the ulimit -v cases run with --memcap 1411 instead" >&2
    capped() { "$@" --memcap 1411; }
else
    capped() { (ulimit -v 3000000 && exec "$@"); }
fi
"$AB" run --scenes spd:balls:1 --accels grid,bsp "${TINY[@]}" --out "$T/free" && ok || bad "run without a limit"
capped "$AB" run --scenes spd:balls:1 --accels grid,bsp "${TINY[@]}" --out "$T/capped" && ok || bad "run under the limit"
a=$(cols "$T/free/matrix.csv" params cell_key) b=$(cols "$T/capped/matrix.csv" params cell_key)
[ -n "$a" ] && [ "$a" = "$b" ] && ok || bad "params and cell keys differ under the limit: <$a> vs <$b>"
grep -q "res=cubic:20" <<<"$b" && ! grep -q "memcap" <<<"$b" && ok || bad "params under the limit hold the cap: $b"
out=$(capped "$AB" run --scenes spd:balls:1 --accels grid,bsp --workloads primary --res 8x8 --repeat 1 --threads 1 \
    --no-plots --out "$T/free" 2>&1)
grep -q "nothing to measure: all 2 cells" <<<"$out" && [ "$(rows "$T/free/matrix.csv")" = 2 ] \
    && ok || bad "resume under the limit did not find every cell done: $out"
# the label verify prints is the plain name, while the cap still bounds the build
out=$(capped "$AB" verify --scenes spd:balls:1 --accels grid --workloads primary --res 8x8 2>&1)
grep -qE "^spd:balls:1 +primary +grid +" <<<"$out" && ! grep -q "memcap" <<<"$out" \
    && ok || bad "verify's label under the limit: $out"
out=$(capped "$AB" verify --scenes spd:balls:1 --accels "grid[res=1000x1000x1000]" --workloads primary --res 8x8 2>&1)
[ $? = 2 ] && grep -qE "over memcap=1[0-9]{3} MiB" <<<"$out" && ok || bad "the limit did not bound the build: $out"

# --- --accels sweeps: counted before they are expanded, the limit (63) named
s=$(python3 -c "print('grid[' + ','.join(['density=1|2|3'] * 40) + ']')")
refused "expand to more than the 63 instances left \\(at most 63 accelerators" -- "$AB" verify --scenes spd:balls:1 --accels "$s" --workloads primary
s=$(python3 -c "print('grid[' + ','.join(['mailbox=on|off'] * 64) + ']')")   # 2^64 instances
refused "expand to more than the 63 instances left \\(at most 63 accelerators" -- "$AB" verify --scenes spd:balls:1 --accels "$s" --workloads primary
s="grid[beta=1|2|3|4|5|6|7|8,density=1|2|3|4|5|6|7|8]"   # 64
refused "expand to more than the 63 instances left \\(at most 63 accelerators" -- "$AB" verify --scenes spd:balls:1 --accels "$s" --workloads primary
s="grid[beta=1|2|3|4|5|6|7,density=1|2|3|4|5|6|7|8|9]"      # 63: just at the limit
out=$("$AB" verify --scenes spd:balls:1 --accels "$s" --workloads primary --res 4x4 2>&1)
[ "$(grep -cE '^spd:balls:1 +primary +grid\[' <<<"$out")" = 63 ] && ok || bad "63 instances: $(tail -3 <<<"$out")"
refused "expand to more than the 62 instances left" -- "$AB" verify --scenes spd:balls:1 --accels "exhaustive,$s" --workloads primary
# a plain name after a sweep that fills the list: no room for its one instance
refused "'exhaustive': the list already holds its limit of 63 accelerators" -- "$AB" verify --scenes spd:balls:1 \
    --accels "$s,exhaustive" --workloads primary
s=$(python3 -c "print(','.join(['exhaustive'] * 64))")
refused "the list already holds its limit of 63 accelerators" -- "$AB" verify --scenes spd:balls:1 --accels "$s" --workloads primary
# a valid sweep runs every combination
"$AB" run --scenes spd:balls:1 --accels "bsp[split=sah|midpoint,maxprims=1|4],grid[mailbox=on|off]" "${TINY[@]}" \
    --out "$T/sweep" && ok || bad "sweep run"
[ "$(rows "$T/sweep/matrix.csv")" = 6 ] && [ "$(cols "$T/sweep/matrix.csv" accel params | sort -u | wc -l)" = 6 ] \
    && ok || bad "sweep: $(rows "$T/sweep/matrix.csv") rows, want 6 distinct"

# --- checked before the first cell: nothing measured, no results file made
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' > "$T/a.obj"
refused "$T/missing.obj: No such file" -- "$AB" run --scenes "$T/a.obj,$T/missing.obj" --accels grid "${TINY[@]}" --out "$T/up"
refused "unknown scene 'nosuch'" -- "$AB" run --scenes "$T/a.obj,nosuch" --accels grid "${TINY[@]}" --out "$T/up"
refused "$T is a folder, not a scene file" -- "$AB" run --scenes "$T/a.obj,file:$T" --accels grid "${TINY[@]}" --out "$T/up"
[ ! -e "$T/up" ] && ok || bad "a refused run made its folder: $(ls "$T/up")"
refused "--res 4294967360x64: expected WxH" -- "$AB" run --scenes spd:balls:1 --res 4294967360x64 --out "$T/up"
refused "--res 64x4294967360: expected WxH" -- "$AB" verify --scenes spd:balls:1 --res 64x4294967360
refused "--res 16x-16: expected WxH" -- "$AB" verify --scenes spd:balls:1 --res 16x-16
long=$T/$(printf 'd%.0s' {1..1100})
refused "--out '.*': a path of 11[0-9]{2} bytes, more than 1023" -- "$AB" run --scenes spd:balls:1 --out "$long"
refused "--save-rays '.*': a path of 11[0-9]{2} bytes" -- "$AB" verify --scenes spd:balls:1 --save-rays "$long"
refused "merge: --out '.*': a path of 11[0-9]{2} bytes, more than 1023" -- "$AB" merge "$T/free" --out "$long" --no-plots
! ls "$T" | grep -q '^ddd' && ok || bad "a folder of a cut --out name was made"
long=$T/$(printf 's%.0s' {1..300}).obj
refused "a name of 3[0-9]{2} bytes, more than 255" -- "$AB" verify --scenes "$long"
touch "$T/afile"
refused "--save-rays $T/afile: not a folder" -- "$AB" run --scenes "spd:balls:1,$T/a.obj" --accels grid "${TINY[@]}" \
    --save-rays "$T/afile" --out "$T/up"
refused "--save-rays $T: a folder, but one ray set" -- "$AB" run --scenes spd:balls:1 --accels grid "${TINY[@]}" \
    --save-rays "$T" --out "$T/up"
[ ! -e "$T/up" ] && ok || bad "a refused run made its folder: $(ls "$T/up")"

# --- a scene named twice is measured once (also through a set)
"$AB" run --scenes "spd:balls:1,$T/a.obj,spd:balls:1" --accels grid "${TINY[@]}" --out "$T/twice" && ok || bad "twice"
[ "$(rows "$T/twice/matrix.csv")" = 2 ] && ok || bad "a scene named twice: $(rows "$T/twice/matrix.csv") rows, want 2"
out=$("$AB" verify --scenes "spd:balls:1,spd:balls:1" --accels grid --workloads primary --res 4x4 2>&1)
[ "$(grep -c '^spd:balls:1 ' <<<"$out")" = 1 ] && ok || bad "verify measured a scene named twice twice: $out"

# --- --rays with --workloads, and --rays given a folder
"$AB" verify --scenes spd:balls:1 --accels exhaustive --workloads primary --res 4x4 --save-rays "$T/p.rays" >/dev/null 2>&1
refused "--rays replays the ray set of its file and --workloads makes new ones" \
    -- "$AB" verify --scenes spd:balls:1 --rays "$T/p.rays" --workloads primary
refused "$T: a folder, not a ray file" -- "$AB" verify --scenes spd:balls:1 --rays "$T"

# --- resume refuses a CSV that holds a cell twice, and one with a byte-order mark
R=(--scenes spd:balls:1 --accels grid,exhaustive "${TINY[@]}")
"$AB" run "${R[@]}" --out "$T/r" && cp "$T/r/matrix.csv" "$T/r.csv" && ok || bad "run for resume"
tail -1 "$T/r.csv" >> "$T/r/matrix.csv"
refused "$T/r/matrix.csv: line 4: cell scene=spd:balls:1 accel=exhaustive .* is in an earlier row too" -- "$AB" run "${R[@]}" --out "$T/r"
printf '\xef\xbb\xbf' | cat - "$T/r.csv" > "$T/r/matrix.csv"
refused "$T/r/matrix.csv: starts with a UTF-8 byte-order mark" -- "$AB" run "${R[@]}" --out "$T/r"
cmp -s <(tail -c +4 "$T/r/matrix.csv") "$T/r.csv" && ok || bad "resume changed a refused file"

# --- merge refuses a row whose columns contradict its cell key, and a CSV with a byte-order mark
"$AB" run "${R[@]}" --shard 1/2 --out "$T/s1" && "$AB" run "${R[@]}" --shard 2/2 --out "$T/s2" && ok || bad "shards"
cp "$T/s1/matrix.csv" "$T/s1.csv"
python3 - "$T/s1/matrix.csv" <<'PY'
import csv, sys
rows = list(csv.reader(open(sys.argv[1], newline='')))
rows[1][rows[0].index('params')] = 'res=cubic:5'
csv.writer(open(sys.argv[1], 'w', newline=''), lineterminator='\n').writerows(rows)
PY
refused "$T/s1/matrix.csv: line 2: column params is 'res=cubic:5' but its cell key says" \
    -- "$AB" merge "$T/s1" "$T/s2" --out "$T/m" --no-plots
printf '\xef\xbb\xbf' | cat - "$T/s1.csv" > "$T/s1/matrix.csv"
refused "$T/s1/matrix.csv: starts with a UTF-8 byte-order mark" -- "$AB" merge "$T/s1" "$T/s2" --out "$T/m" --no-plots
cp "$T/s1.csv" "$T/s1/matrix.csv"
expect 0 "merged 2 cells of 2 shards" -- "$AB" merge "$T/s1" "$T/s2" --out "$T/m" --no-plots

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
