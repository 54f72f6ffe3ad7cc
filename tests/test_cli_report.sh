#!/bin/bash
# test_cli_report.sh: the report on the command line: --accels instances and
# sweeps (expansion counts, labels, errors before the first cell, a run with
# two grid instances giving two rows), render --heatmap-max, and the report
# subcommand (arguments, exit statuses, a page with one row per CSV row and
# nothing loaded from outside). Prints "N passed, N failed"; exits 1 on a failure.
set -u
AB=${ACCELBENCH:?set ACCELBENCH to the accelbench binary}
T=$(mktemp -d /tmp/accelbench-report-cli.XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"
S="--scenes spd:balls:1 --workloads primary --res 8x8"

# --- expansion: verify prints one table line per instance; count them and read their labels
lines() { "$AB" verify $S --accels "$1" 2>/dev/null | awk 'NR > 1 && $1 == "spd:balls:1" {print $3}'; }
check_count() { # LIST N
    local n; n=$(lines "$1" | wc -l)
    [ "$n" = "$2" ] && ok || bad "--accels '$1': $n instances, want $2"
}
check_count 'grid' 1
check_count 'grid,grid[res=40x40x40]' 2
check_count 'bsp[split=sah|midpoint]' 2
check_count 'bsp[split=sah|midpoint,maxprims=1|4|8]' 6
check_count 'grid,grid[res=40x40x40],bsp[split=sah|midpoint]' 4
check_count 'grid[res=4x4x4|8x8x8,mailbox=on|off]' 4
got=$(lines 'grid,grid[res=40x40x40],bsp[split=sah|midpoint]' | tr '\n' ' ')
[ "$got" = "grid grid[res=40x40x40] bsp[split=sah] bsp " ] && ok || bad "labels: '$got'"
got=$(lines 'bsp[split=sah|midpoint,maxprims=1|4]' | tr '\n' ' ')
[ "$got" = "bsp[split=sah,maxprims=1] bsp[split=sah,maxprims=4] bsp[maxprims=1] bsp[maxprims=4] " ] && ok || bad "product order: '$got'"
# --param still reaches a plain name, and every instance of it
got=$(lines 'grid' | tr -d '\n'; "$AB" verify $S --accels grid --param grid.res=8x8x8 2>/dev/null | awk 'NR > 1 && $1 == "spd:balls:1" {print $3}')
[ "$got" = "gridgrid[res=8x8x8]" ] && ok || bad "--param on a plain name: '$got'"

# --- errors: exit 2, one line naming the item and what is wrong, before any cell
refused "unclosed '\\['" -- "$AB" run $S --accels 'grid[res=40x40x40' --out "$T/e1"
refused "grid\\[nope=1\\].*unknown parameter 'nope'" -- "$AB" run $S --accels 'grid,grid[nope=1]' --out "$T/e2"
refused "grid\\[res=foo\\].*res=foo" -- "$AB" run $S --accels 'grid[res=foo]' --out "$T/e3"
refused "'split' has an empty value" -- "$AB" run $S --accels 'bsp[split=sah|]' --out "$T/e4"
refused "unknown accelerator 'warp'" -- "$AB" run $S --accels 'grid,warp[a=1]' --out "$T/e5"
refused "grid is given twice" -- "$AB" run $S --accels 'grid,grid' --out "$T/e6"
refused "after '\\]'" -- "$AB" run $S --accels 'grid[res=8x8x8]x' --out "$T/e7"
refused "empty brackets" -- "$AB" run $S --accels 'grid[]' --out "$T/e8"
refused "more than the" -- "$AB" run $S --accels 'grid[res=1x1x1|2x2x2|3x3x3|4x4x4,mailbox=on|off,insert=exact|box,density=1|2|3|4|5]' --out "$T/e9"
[ ! -e "$T/e1/matrix.csv" ] && [ ! -e "$T/e3/matrix.csv" ] && ok || bad "a refused run wrote a CSV"

# --- a run with two grid instances: two rows, distinct params, the label in the progress line
expect 0 "grid\\[res=4x4x4\\]" -- "$AB" run $S --accels 'grid,grid[res=4x4x4]' --repeat 1 --threads 1 --out "$T/two" --no-plots
rows=$(/usr/bin/python3 -c '
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
print(len(rows), len({r["params"] for r in rows}), len({r["cell_key"] for r in rows}), sum("res=4x4x4" in r["params"] for r in rows))' "$T/two/matrix.csv")
[ "$rows" = "2 2 2 1" ] && ok || bad "two grid instances: rows, params, keys, res=4x4x4 rows = $rows"

# --- reproduce spd builds its variants through the same parser
refused "unclosed '\\['" -- "$AB" reproduce spd --quick --accels 'bvh-gs[order=x' --out "$T/spd0"
expect 0 "spd_tables.md" -- "$AB" reproduce spd --quick --scenes tetra --accels 'bvh-gs,bvh-gs[order=sorted|given]' --out "$T/spd"
got=$(cut -d, -f2 "$T/spd/spd.csv" | sed 1d | sort -u | tr '\n' ' ')
[ "$got" = "bvh-gs bvh-gs[order=given] bvh-gs[order=sorted] " ] && ok || bad "reproduce spd variants: '$got'"

# --- render --heatmap-max: the same scale for two images, refused without --heatmap or when not positive
expect 0 "colour scale 0..500" -- "$AB" render --scene spd:balls:2 --accel grid --heatmap tests --heatmap-max 500 --res 16x16 --out "$T/h1.png"
expect 0 "colour scale 0..max" -- "$AB" render --scene spd:balls:2 --accel grid --heatmap tests --res 16x16 --out "$T/h2.png"
refused "--heatmap-max -1" -- "$AB" render --scene spd:balls:2 --accel grid --heatmap tests --heatmap-max -1 --out "$T/h3.png"
refused "give --heatmap" -- "$AB" render --scene spd:balls:2 --accel grid --heatmap-max 5 --out "$T/h3.png"
refused "option of render" -- "$AB" run $S --heatmap-max 5
# a higher scale darkens the same image: the mean brightness falls
dark=$(/usr/bin/python3 -c '
import sys, matplotlib.image as m
a, b = m.imread(sys.argv[1]), m.imread(sys.argv[2])
print(int(a[..., :3].mean() < b[..., :3].mean()))' "$T/h1.png" "$T/h2.png")
[ "$dark" = 1 ] && ok || bad "--heatmap-max 500 is not darker than the image's own scale"

# --- report: arguments and statuses
expect 0 "usage: accelbench report RUN_DIR" -- "$AB" report --help
expect 0 "report " -- "$AB" --help
refused "no run folder given" -- "$AB" report
refused "$T/none: no such folder" -- "$AB" report "$T/none"
mkdir -p "$T/empty"
refused "$T/empty/matrix.csv" -- "$AB" report "$T/empty"
refused "--pictures sometimes" -- "$AB" report "$T/two" --pictures sometimes
refused "no such folder $T/nodir" -- "$AB" report "$T/two" --out "$T/nodir/r.html"
refused "unexpected argument" -- "$AB" report "$T/two" "$T/empty"
refused "option of run" -- "$AB" verify $S --report
expect 0 "wrote $T/two/report.html" -- "$AB" report "$T/two" --pictures off
# the report step writes summary.md beside the CSV: the findings rank both instances, labelled by the rule
# (the default instance by its name alone), each of one cell
grep -q "^## Findings" "$T/two/summary.md" && grep -Eq "^\| [12] \| grid \| [0-9.e+-]+ \| n = 1: none \| 1 \|$" "$T/two/summary.md" \
    && grep -Eq "^\| [12] \| grid\[res=4x4x4\] \| " "$T/two/summary.md" && ok \
    || bad "report: summary.md without its findings ranking grid and grid[res=4x4x4]"
expect 0 "wrote $T/r.html" -- "$AB" report "$T/two" --out "$T/r.html"
# one table row per CSV row, images inline, nothing fetched from elsewhere, alt text on every image
page_check() { # PAGE CSV
    /usr/bin/python3 - "$1" "$2" <<'PY'
import csv, re, sys
page, rows = open(sys.argv[1]).read(), list(csv.DictReader(open(sys.argv[2])))
body = page.split('<table id="cells">', 1)[1].split("</table>", 1)[0]
n = body.count("<tr>") - 1
imgs = re.findall(r"<img [^>]*>", page)
bad = [i for i in imgs if 'src="data:image/png;base64,' not in i or not re.search(r'alt="[^"]{10,}"', i)]
ext = re.findall(r'(?:src|href)="(?:https?:)?//', page)
print(n == len(rows), len(imgs) > 0, not bad, not ext)
PY
}
[ "$(page_check "$T/r.html" "$T/two/matrix.csv")" = "True True True True" ] && ok || bad "report page: $(page_check "$T/r.html" "$T/two/matrix.csv")"
grep -q "grid\[res=4x4x4\]" "$T/r.html" && ok || bad "the report does not label the instance grid[res=4x4x4]"
grep -q 'class="hm"' "$T/r.html" && ok || bad "the report with pictures has no heat map"
# a real mismatch (made up in a copy of the CSV) is listed with the verify command that lists its rays, and that
# command runs; a reproduce run's findings in the folder are quoted
mkdir -p "$T/fake"
/usr/bin/python3 - "$T/two/matrix.csv" "$T/fake/matrix.csv" <<'PY'
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for r in rows:
    if "res=4x4x4" in r["params"]:
        r["mismatch_real"] = "3"
w = csv.DictWriter(open(sys.argv[2], "w", newline=""), list(rows[0]))
w.writeheader()
w.writerows(rows)
PY
printf '# Table 1\n\nfinding: our grid is 2x faster than the paper says\n' > "$T/fake/woo92_tables.md"
expect 0 "wrote" -- "$AB" report "$T/fake" --pictures off
cmd=$(/usr/bin/python3 -c '
import html, re, sys
page = open(sys.argv[1]).read()
sec = page.split("id=\"verification\"")[1]
print(html.unescape(re.findall(r"<pre>(accelbench verify [^<]*)</pre>", sec)[0]) if "1 cell with real" in sec else "")' "$T/fake/report.html")
[ "$cmd" = "accelbench verify --scenes spd:balls:1 --workloads primary --res 8x8 --spp 1 --seed 1 --accels grid --param grid.res=4x4x4" ] \
    && ok || bad "verify command of the real mismatch: '$cmd'"
expect 0 "grid\[res=4x4x4\] +64 " -- "$AB" ${cmd#accelbench }
grep -q "finding: our grid is 2x faster" "$T/fake/report.html" && ok || bad "the folder's finding is not in the report"

# run --report writes the page at the end
expect 0 "report.html" -- "$AB" run $S --accels embree,grid --repeat 1 --threads 1 --out "$T/rr" --report
[ -s "$T/rr/report.html" ] && [ -s "$T/rr/overview__ratio.png" ] && ok || bad "run --report: no report.html or plots"
# the plot step's per-workload heat map, params.csv (one row per configuration and parameter) and summary.md
[ -s "$T/rr/overview__ratio__primary.png" ] && [ -s "$T/rr/spd_balls_1__ratio.png" ] && ok \
    || bad "run --report: no per-workload heat map or per-scene ratio figure"
got=$(/usr/bin/python3 -c '
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
grid = [r for r in rows if r["accel"] == "grid"]
print(len(grid) > 1, all(r["label"] == "grid" for r in grid), all(r["default"] == "yes" for r in grid),
      ",".join(r["key"] + "=" + r["value"] for r in grid) == next(r["params"] for r in grid))' "$T/rr/params.csv" 2>&1)
[ "$got" = "True True True True" ] && ok || bad "params.csv of grid: $got"
# the page opens with the findings (grid ranked, n 1 per workload) and ends with the table of every cell
got=$(/usr/bin/python3 -c '
import re, sys
page = open(sys.argv[1]).read()
f, t = page.find("<section id=\"findings\">"), page.find("<section id=\"table\">")
first = page.find("<section") == f
rank = re.findall(r"<tr data-label=\"grid\" data-gm=\"[^\"]+\" data-n=\"1\">", page)
print(0 <= f < t, first, len(rank))' "$T/rr/report.html")
[ "$got" = "True True 1" ] && ok || bad "run --report: findings first, table last, grid ranked: $got"
grep -q "^| 1 | grid | " "$T/rr/summary.md" && ok || bad "run --report: summary.md does not rank grid"

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
