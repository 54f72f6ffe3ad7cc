#!/bin/bash
# test_report_browser.sh: the report of a small run, opened in headless
# Chromium (Debian's chromium, installed by scripts/setup.sh; without it this
# test FAILS). A copy of the page gets a checking script that, once the page
# has loaded, writes into <pre id="result">: the table's rows against the
# CSV's, every image's naturalWidth, whether sorting by a column (its header
# button) changes the row order and reverses on a second press, and whether
# the page is wider than the window; the DOM is dumped at 1280x800 and at
# 420x800 (a narrow window: Chromium makes it 500 wide, its least). A screenshot at 1280x800 must not be one colour.
# The findings: the section is the page's first and comes before the table of every cell, and its rankings (per
# workload each configuration's label, geometric mean as shown and n cells) equal a recomputation from the CSV
# done here, as do summary.md's (written beside the CSV by the run's plot step).
# Prints "N passed, N failed"; exits 1 on a failure.
set -u
AB=${ACCELBENCH:?set ACCELBENCH to the accelbench binary}
T=$(mktemp -d /tmp/accelbench-browser.XXXXXX)
trap 'rm -rf "$T"' EXIT
. "$(dirname "$0")/cli_lib.sh"

CHROMIUM=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$CHROMIUM" ]; then
    echo "FAIL: chromium is not installed (scripts/setup.sh installs Debian's chromium package)" >&2
    echo "0 passed, 1 failed"
    exit 1
fi
chrome() { # chrome WIDTHxHEIGHT ARGS... (the flags keep it off the network and out of the user's profile)
    local size=$1; shift
    timeout 120 "$CHROMIUM" --headless --no-sandbox --disable-gpu --no-first-run --disable-extensions \
        --disable-background-networking --disable-sync --disable-component-update --disable-default-apps \
        --user-data-dir="$T/profile" --hide-scrollbars --window-size="$size" "$@" 2>>"$T/chromium.log"
}

# A small run: two tiny scenes, three accelerators (one of them twice, a sweep), two workloads, 32x32.
"$AB" run --scenes spd:balls:1,spd:balls:2 --accels 'embree,grid,grid[res=4x4x4],bsp' --workloads primary,shadow --res 32x32 \
    --repeat 1 --threads 1 --out "$T/run" --quiet 2>"$T/run.log" && ok || { bad "the run failed"; cat "$T/run.log" >&2; }
expect 0 "wrote" -- "$AB" report "$T/run" --out "$T/report.html"
NROWS=$(/usr/bin/python3 -c 'import csv, sys; print(len(list(csv.DictReader(open(sys.argv[1])))))' "$T/run/matrix.csv")
# The rankings recomputed from the CSV, here and not by scripts/: label by the rule (the default instance is its
# name, the other grid[res=4x4x4]), the geometric mean of ratio_vs_embree over the workload's scenes, shown to three
# significant digits, and n; in order of the mean, one "workload|label|mean|n" per configuration, ';' between.
WANT=$(/usr/bin/python3 - "$T/run/matrix.csv" <<'PY'
import csv, math, sys
cells = {}
for r in csv.DictReader(open(sys.argv[1])):
    if r["accel"] == "embree" or not r["ratio_vs_embree"]:
        continue
    label = r["accel"] + ("[res=4x4x4]" if "res=4x4x4" in r["params"] else "")
    cells.setdefault((r["workload"], label), []).append(float(r["ratio_vs_embree"]))
out = []
for w in ("primary", "shadow"):
    ranked = sorted((math.exp(sum(map(math.log, v)) / len(v)), l, len(v)) for (ww, l), v in cells.items() if ww == w)
    out += [f"{w}|{l}|{g:.3g}|{n}" for g, l, n in ranked]
print(";".join(out))
PY
)
# summary.md's rankings in the same form
MDRANK=$(/usr/bin/python3 - "$T/run/summary.md" <<'PY'
import re, sys
out, w = [], None
for line in open(sys.argv[1]):
    m = re.match(r"^### Ranking: (\S+)", line)
    if m:
        w = m.group(1)
        continue
    if line.startswith("### Winners"):
        w = None
    m = re.match(r"^\| \d+ \| ([^|]+) \| ([^|]+) \| [^|]+ \| (\d+) \|$", line.rstrip("\n"))
    if m and w:
        out.append(f"{w}|{m.group(1).strip()}|{m.group(2).strip()}|{m.group(3)}")
print(";".join(out))
PY
)
[ -n "$WANT" ] && [ "$MDRANK" = "$WANT" ] && ok || bad "summary.md rankings '$MDRANK', recomputed '$WANT'"

# The page with the checks appended before </body>.
/usr/bin/python3 - "$T/report.html" "$T/check.html" <<'PY'
import sys
page = open(sys.argv[1], encoding="utf-8").read()
check = r"""<pre id="result">pending</pre><script>
window.addEventListener('load', function () {
  var out = [], t = document.getElementById('cells');
  var body = t.tBodies[0];
  out.push('rows=' + body.rows.length);
  var imgs = document.images, broken = 0;
  for (var i = 0; i < imgs.length; i++) if (!imgs[i].complete || imgs[i].naturalWidth <= 0) broken++;
  out.push('images=' + imgs.length, 'broken=' + broken);
  function order() { return Array.prototype.map.call(body.rows, function (r) { return r.textContent; }).join('|'); }
  var heads = t.tHead.rows[0].cells, col = -1;
  for (var k = 0; k < heads.length; k++) if (heads[k].textContent.trim() === 'Mrays/s') col = k;
  var before = order();
  heads[col].querySelector('button').click();
  var asc = order(), sortedOk = true, prev = -Infinity;
  for (var r = 0; r < body.rows.length; r++) {
    var v = parseFloat(body.rows[r].cells[col].getAttribute('data-v'));
    if (!isNaN(v)) { if (v < prev) sortedOk = false; prev = v; }
  }
  heads[col].querySelector('button').click();
  var desc = order();
  out.push('changed=' + (asc !== before ? 1 : 0), 'ascending=' + (sortedOk ? 1 : 0),
           'reversed=' + (desc !== asc ? 1 : 0), 'aria=' + heads[col].getAttribute('aria-sort'));
  out.push('pagewidth=' + document.documentElement.scrollWidth, 'window=' + window.innerWidth);
  var fs = document.getElementById('findings');
  out.push('findings_first=' + (fs && document.querySelector('h2') === fs.querySelector('h2') &&
           (fs.compareDocumentPosition(t) & Node.DOCUMENT_POSITION_FOLLOWING) ? 1 : 0));
  var rk = [];
  Array.prototype.forEach.call(document.querySelectorAll('#findings table.rank'), function (tb) {
    var w = tb.getAttribute('data-workload');
    Array.prototype.forEach.call(tb.tBodies[0].rows, function (r) {
      rk.push(w + '|' + r.cells[1].textContent + '|' + r.querySelector('td.gm').textContent + '|' +
              r.querySelector('td.n').textContent);
    });
  });
  out.push('ranking=' + (rk.join(';') || 'none'));
  document.getElementById('result').textContent = 'RES' + 'ULT ' + out.join(' ') + ' END';
});
</script>"""
open(sys.argv[2], "w", encoding="utf-8").write(page.replace("</body>", check + "</body>"))
PY

for size in 1280,800 420,800; do
    chrome "$size" --virtual-time-budget=10000 --dump-dom "file://$T/check.html" > "$T/dom.html"
    res=$(grep -o 'RESULT [^<]* END' "$T/dom.html")
    [ -n "${VERBOSE:-}" ] && echo "$size: $res"
    [ -n "$res" ] && ok || { bad "$size: no result in the dumped DOM"; tail -3 "$T/chromium.log" >&2; continue; }
    val() { sed -n "s/.* $1=\([^ ]*\) .*/\1/p" <<<"$res"; }
    [ "$(val rows)" = "$NROWS" ] && ok || bad "$size: table rows $(val rows), CSV rows $NROWS ($res)"
    [ "$(val images)" -gt 0 ] && [ "$(val broken)" = 0 ] && ok || bad "$size: images not loaded ($res)"
    [ "$(val changed)" = 1 ] && [ "$(val ascending)" = 1 ] && ok || bad "$size: sorting by Mrays/s ($res)"
    [ "$(val reversed)" = 1 ] && [ "$(val aria)" = descending ] && ok || bad "$size: the second press ($res)"
    [ "$(val pagewidth)" -le "$(val window)" ] && ok || bad "$size: the page scrolls sideways ($res)"
    [ "$(val findings_first)" = 1 ] && ok || bad "$size: the findings are not the first section, before the table ($res)"
    [ -n "$WANT" ] && [ "$(val ranking)" = "$WANT" ] && ok || bad "$size: rankings '$(val ranking)', recomputed '$WANT'"
done

# A screenshot of the page itself: not blank (many colours, not one).
(cd "$T" && chrome 1280,800 --screenshot="$T/shot.png" "file://$T/report.html" > /dev/null)
shot=$(/usr/bin/python3 -c '
import sys, numpy as np, matplotlib.image as m
a = m.imread(sys.argv[1])[..., :3]
print(a.shape[1], a.shape[0], len(np.unique((a * 255).astype(np.uint8).reshape(-1, 3), axis=0)), round(float(a.std()), 3))' "$T/shot.png" 2>&1)
read -r w h colours std <<<"$shot"
[ "${w:-0}" = 1280 ] && [ "${colours:-0}" -gt 20 ] && /usr/bin/python3 -c "import sys; sys.exit(not float('${std:-0}') > 0.05)" \
    && ok || bad "screenshot blank or missing: $shot"

echo "$pass passed, $fail failed"
[ "$fail" = 0 ]
