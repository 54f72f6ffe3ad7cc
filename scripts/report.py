#!/usr/bin/python3
"""Write one self-contained HTML page of an accelbench run folder.

    report.py RUN_DIR [--out FILE.html] [--accelbench BIN] [--pictures auto|on|off] [--quiet]

The page (default RUN_DIR/report.html) holds, every number from RUN_DIR/matrix.csv
(and run.txt for the commands), in this order:
  - the findings (scripts/findings.py, the same as summary.md's): per workload
    every configuration ranked by the geometric mean of its paired ratio to
    Embree, with a 95 % t-interval and its number of cells; the winners map
    (per scene and workload the fastest, and the fastest of the survey's
    structures, ties marked); a line per family: where it wins, where it
    loses worst;
  - the run: machine, cpu, revision, threads, dates and every command of run.txt;
  - plot.py's figures: the overview heat map (over workloads) and one per
    workload, the sweeps (one parameter of an accelerator on x, the paired ratio
    on y), per scene the paired ratio, Mrays/s (with threads), tests and build;
  - pictures, cost growth and verification (below);
  - last, a table with one row per CSV row (the last row of each cell, as plot.py):
    scene, accelerator (labelled by its parameters that differ from the
    defaults), workload, Mrays/s, the paired ratio to Embree with its spread,
    tests/box tests/steps per ray, build time, bytes per primitive, mismatches by
    class; ratio cells coloured (green faster than Embree, red slower); sortable
    by every column (the headers are buttons: click, Enter or Space);
  - (plot.py's figures are reused from RUN_DIR when there, else drawn);
  - with pictures (--pictures; auto: runs of at most 10 scenes, scenes of at most
    100000 primitives), per scene a picture (render through embree) and the
    per-pixel primitive tests of the primary rays of every accelerator side by
    side on one colour scale (render --heatmap tests --heatmap-max): two renders
    and two builds per accelerator and scene;
  - cost growth: for every SPD family with three or more sizes (spd:NAME:N,
    spd:NAME:N:t), fits of log(trace time per ray), log(tests per ray), log(build
    time) and log(memory) against log(N), N the primitive count, by numpy.polyfit
    with the slope's 95% confidence interval (t quantile on N - 2 degrees of
    freedom), on log-log plots, with a sentence per accelerator;
  - verification: mismatch totals by class, and every cell with a real mismatch
    with the verify command that lists its rays and their replay commands;
  - findings of reproduce runs in the folder (*_tables.md, summary.md), as text.
Images are embedded as data: URIs; the page loads nothing from anywhere.
Beside the page, RUN_DIR/summary.md is (re)written with the same findings as
Markdown (scripts/summary.py) unless a summary.md of another writer is there.
Exit status 2 for a missing folder, CSV or column.
"""
import argparse
import base64
import glob
import html
import io
import math
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot as common  # noqa: E402
import findings  # noqa: E402
import summary  # noqa: E402
import numpy as np  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402

PROG = "report.py"
common.PROG = PROG
num = common.num
PICTURE_MAX_PRIMS = 100000
PICTURE_MAX_SCENES = 10
PLOT_MAX_SCENES = 12     # more scenes: per-scene figures linked, not embedded
HEAT_SIDE = 128          # heat maps and pictures: this many pixels on the longer side
CLOSEST = ("primary", "reflection", "diffuse", "random", "whitted:eye", "whitted:reflected", "whitted:refracted")
MISMATCH = ("real", "edge", "tol", "refwrong", "origin", "unjudged")

# Student's t quantiles: the findings' intervals and the cost-growth fits use the same ones.
T975 = findings.T975
t975 = findings.t975


def fit_power(ns, ys):
    """Fit y = c N^k: numpy.polyfit of log y on log N. Returns {k, lo, hi, c, n} (the 95% interval of k from
    polyfit's covariance and the t quantile on n - 2 degrees of freedom), or None for fewer than 3 points."""
    pts = [(n, y) for n, y in zip(ns, ys) if n and y and n > 0 and y > 0]
    if len({n for n, _ in pts}) < 3:
        return None
    x = np.log([n for n, _ in pts])
    y = np.log([y for _, y in pts])
    coef, cov = np.polyfit(x, y, 1, cov=True)
    half = t975(len(pts) - 2) * math.sqrt(max(cov[0][0], 0.0))
    return {"k": float(coef[0]), "lo": float(coef[0] - half), "hi": float(coef[0] + half),
            "c": float(math.exp(coef[1])), "n": len(pts)}


FAMILY_RE = re.compile(r"^spd:([a-z]+):(\d+)(?::t(\d*))?$")


def family_of(scene):
    """'spd:balls:3' -> 'balls', 'spd:balls:3:t' -> 'balls-t', 'spd:balls:3:t5' -> 'balls-t5'; None otherwise."""
    m = FAMILY_RE.match(scene)
    if not m:
        return None
    return m.group(1) + ("" if m.group(3) is None else "-t" + m.group(3))


def per_ray_ns(r):
    t, rays = num(r.get("trace_ms")), num(r.get("rays"))
    return t * 1e6 / rays if t and rays else None


# What cost growth fits: (key, what the sentence calls it, unit, value of a row, per workload?)
METRICS = (("time", "trace time per ray", "ns/ray", per_ray_ns, True),
           ("tests", "primitive tests per ray", "tests/ray", lambda r: num(r.get("tests_per_ray")), True),
           ("build", "build time", "ms", lambda r: num(r.get("build_ms")), False),
           ("memory", "memory", "bytes", lambda r: num(r.get("mem_bytes")), False))


def scaling_fits(rows, labels=None):
    """Cost-growth fits of every family with three or more sizes.
    Returns {family: {"points": {(metric, label, workload): [(N, y)]}, "fits": {same key: fit}}};
    workload is None for build and memory (one value per scene: the median over its workloads)."""
    labels = labels or config_labels(rows, {})
    out = {}
    for r in rows:
        fam = family_of(r["scene"])
        n = num(r.get("prims"))
        if not fam or not n:
            continue
        pts = out.setdefault(fam, {"points": {}, "scenes": set()})
        pts["scenes"].add(r["scene"])
        label = labels[common.config_key(r)]
        for key, _, _, value, per_workload in METRICS:
            v = value(r)
            if v is None or v <= 0:
                continue
            pts["points"].setdefault((key, label, r["workload"] if per_workload else None), {}) \
                .setdefault(n, []).append(v)
    result = {}
    for fam, d in out.items():
        if len({num(r.get("prims")) for r in rows if r["scene"] in d["scenes"]}) < 3:
            continue
        points = {k: sorted((n, float(np.median(v))) for n, v in by_n.items()) for k, by_n in d["points"].items()}
        fits = {}
        for k, p in points.items():
            f = fit_power([n for n, _ in p], [y for _, y in p])
            if f:
                fits[k] = f
        result[fam] = {"points": points, "fits": fits}
    return result


# ------------------------------------------------------------------ labels

def accel_defaults(binary):
    """{accel: {key: default}} from `accelbench list accels`; {} when it cannot be run."""
    if not binary:
        return {}
    try:
        text = subprocess.run([binary, "list", "accels"], capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.SubprocessError):
        return {}
    return common.parse_accel_defaults(text)


def config_labels(rows, defaults):
    return common.config_labels(rows, common.MAX_PARAMS, defaults)


# ------------------------------------------------------------------ html helpers

def esc(s):
    return html.escape(str(s), quote=True)


def png_uri(path_or_bytes):
    data = path_or_bytes if isinstance(path_or_bytes, bytes) else open(path_or_bytes, "rb").read()
    return "data:image/png;base64," + base64.b64encode(data).decode("ascii")


def img(src, alt, cls="plot"):
    return f'<img class="{cls}" src="{png_uri(src)}" alt="{esc(alt)}">'


def fig_bytes(fig):
    buf = io.BytesIO()
    fig.tight_layout()
    fig.savefig(buf, format="png", dpi=100, metadata={"Software": None})
    plt.close(fig)
    return buf.getvalue()


def fmt(v, digits=3):
    if v is None:
        return ""
    if v == 0:
        return "0"
    return f"{v:.{digits}g}" if abs(v) < 1e5 else f"{v:.3e}"


# Measured columns a hand-edited or damaged CSV may spoil: ratios and times must be positive, counts not negative.
POSITIVE = ("ratio_vs_embree", "ratio_min", "ratio_max", "embree_ms")
NON_NEGATIVE = ("prims", "rays", "build_ms", "trace_ms", "trace_ms_min", "trace_ms_max", "mrays_per_s", "mem_bytes",
                "bytes_per_prim", "tests_per_ray", "box_tests_per_ray", "steps_per_ray") + tuple(
                    "mismatch_" + m for m in MISMATCH)


def bad_measure(row):
    """Why a row's numbers cannot be shown (None when they can): a field that is no finite number, a ratio or
    Embree time of 0 or below, a negative time or count. Empty fields are fine (a ray set of no rays)."""
    for col in POSITIVE + NON_NEGATIVE:
        text = row.get(col, "")
        if text == "":
            continue
        v = num(text)
        if v is None:
            return f"{col} {text!r} is not a number"
        if v <= 0 and col in POSITIVE:
            return f"{col} {text!r} is not above 0"
        if v < 0:
            return f"{col} {text!r} is negative"
    return None


def ratio_colour(r):
    """Background for a ratio cell: green below 1 (faster than Embree), red above, white at 1 (log scale, 8x full)."""
    if r is None:
        return ""
    t = max(-1.0, min(1.0, math.log(r) / math.log(8.0)))
    if t >= 0:
        c = (255, int(255 - 150 * t), int(255 - 170 * t))
    else:
        c = (int(255 + 170 * t), 255, int(255 + 150 * t))
    return f"background:rgb({c[0]},{c[1]},{c[2]})"


CSS = """
*{box-sizing:border-box}
body{font:15px/1.45 system-ui,-apple-system,"Segoe UI",Roboto,"DejaVu Sans",sans-serif;color:#1b1b1b;background:#fff;
 margin:0 auto;padding:1rem 1.25rem 3rem;max-width:1280px;overflow-wrap:anywhere}
h1{font-size:1.6rem;margin:.2rem 0 .6rem}h2{font-size:1.25rem;margin:2rem 0 .6rem;border-bottom:1px solid #ccc}
h3{font-size:1.05rem;margin:1.2rem 0 .4rem}
dl.meta{display:grid;grid-template-columns:max-content 1fr;gap:.15rem 1rem;margin:0}
dl.meta dt{font-weight:600}dl.meta dd{margin:0}
code,pre{font:13px/1.4 ui-monospace,"DejaVu Sans Mono",monospace}
pre{white-space:pre-wrap;word-break:break-word;background:#f6f6f6;padding:.6rem;border-radius:4px;max-width:100%}
.scroll{overflow-x:auto;max-width:100%;border:1px solid #ddd;border-radius:4px}
.scroll:focus{outline:2px solid #1a5fb4}
table{border-collapse:collapse;font-size:13px;white-space:nowrap}
th,td{padding:.2rem .45rem;border-bottom:1px solid #eee;text-align:right}
td.t,th.t{text-align:left}
thead th{position:sticky;top:0;background:#f0f0f0;z-index:1}
th button{font:inherit;font-weight:600;background:none;border:0;padding:.15rem 0;cursor:pointer;color:inherit;text-align:inherit}
th button:focus{outline:2px solid #1a5fb4}
th[aria-sort=ascending] button::after{content:" \\25B2"}th[aria-sort=descending] button::after{content:" \\25BC"}
.figs{display:flex;flex-wrap:wrap;gap:.8rem}
.ranks{display:flex;flex-wrap:wrap;gap:0 1.2rem;align-items:flex-start}.ranks>div{max-width:100%;min-width:0}
img.plot{max-width:100%;height:auto;border:1px solid #eee}
.heat{display:flex;flex-wrap:wrap;gap:.6rem;align-items:flex-start}
.heat figure{margin:0;text-align:center;font-size:12px}
.heat img{width:160px;max-width:42vw;height:auto;image-rendering:pixelated;border:1px solid #ccc}
.heat img.bar{width:auto;height:160px;image-rendering:auto;border:0}
.note{color:#555;font-size:13px}
.bad{color:#a40000;font-weight:600}
ul.sent li{margin:.15rem 0}
@media (max-width:700px){body{padding:.6rem;font-size:14px}dl.meta{grid-template-columns:1fr}}
"""

SORT_JS = """
(function(){
 var t=document.getElementById('cells');if(!t)return;
 var hs=t.tHead.rows[0].cells;
 function key(td){var v=td.getAttribute('data-v');if(v===null)v=td.textContent;var x=parseFloat(v);
  return (v!==''&&!isNaN(x)&&isFinite(x))?[0,x]:[v===''?2:1,v.toLowerCase()];}
 function sortBy(i){var th=hs[i],dir=th.getAttribute('aria-sort')==='ascending'?-1:1;
  for(var k=0;k<hs.length;k++)hs[k].removeAttribute('aria-sort');
  th.setAttribute('aria-sort',dir>0?'ascending':'descending');
  var b=t.tBodies[0],rs=Array.prototype.slice.call(b.rows);
  rs.sort(function(a,c){var x=key(a.cells[i]),y=key(c.cells[i]);
   if(x[0]!==y[0])return x[0]-y[0];if(x[0]===2)return 0;return (x[1]<y[1]?-1:x[1]>y[1]?1:0)*dir;});
  rs.forEach(function(r){b.appendChild(r);});}
 for(var i=0;i<hs.length;i++)(function(i){var btn=hs[i].querySelector('button');
  if(btn)btn.addEventListener('click',function(){sortBy(i);});})(i);
})();
"""


# ------------------------------------------------------------------ sections

def read_run_txt(path):
    """The invocations of run.txt, each a dict of its 'key: value' lines."""
    runs, cur = [], {}
    if not os.path.isfile(path):
        return runs
    for line in open(path, encoding="utf-8", errors="replace"):
        line = line.rstrip("\n")
        if not line.strip():
            if cur:
                runs.append(cur)
            cur = {}
            continue
        k, sep, v = line.partition(": ")
        if sep:
            cur[k] = v
    if cur:
        runs.append(cur)
    return runs


def uniq(rows, col):
    return ", ".join(v for v in dict.fromkeys(r.get(col, "") for r in rows) if v) or "?"


def section_run(rows, run_dir):
    runs = read_run_txt(os.path.join(run_dir, "run.txt"))
    dates = sorted(r.get("date", "") for r in rows if r.get("date"))
    meta = [("folder", os.path.normpath(run_dir)), ("machine", uniq(rows, "machine")), ("cpu", uniq(rows, "cpu")),
            ("revision", uniq(rows, "git_rev")), ("threads", uniq(rows, "threads")),
            ("repeat", uniq(rows, "repeat")), ("rays made at", uniq(rows, "res") + " px, spp " + uniq(rows, "spp")),
            ("dates", f"{dates[0]} to {dates[-1]}" if dates else "?"),
            ("cells", f"{len(rows)} (scenes {len({r['scene'] for r in rows})}, "
                      f"accelerators {len({common.config_key(r) for r in rows})}, "
                      f"workloads {len({r['workload'] for r in rows})})")]
    out = ['<section id="run"><h2>The run</h2><dl class="meta">']
    out += [f"<dt>{esc(k)}</dt><dd>{esc(v)}</dd>" for k, v in meta]
    out.append("</dl>")
    if runs:
        out.append(f"<h3>Commands ({len(runs)} invocation{'s' if len(runs) != 1 else ''}, from run.txt)</h3><pre>")
        out += [esc(f"accelbench {r.get('command', '?')}    # run {r.get('run_id', '?')}, {r.get('date', '?')}") + "\n"
                for r in runs]
        out.append("</pre>")
    else:
        out.append('<p class="note">No run.txt in the folder: the commands are unknown.</p>')
    out.append("</section>")
    return "\n".join(out)


COLUMNS = (  # header, title, value of a row (text, sort key), left-aligned
    ("scene", "scene", lambda r, l: (r["scene"], None), True),
    ("prims", "primitives", lambda r, l: (r.get("prims", ""), num(r.get("prims"))), False),
    ("accelerator", "accelerator, with the parameters that differ from its defaults",
     lambda r, l: (l, None), True),
    ("workload", "workload", lambda r, l: (r["workload"], None), True),
    ("rays", "rays", lambda r, l: (r.get("rays", ""), num(r.get("rays"))), False),
    ("ratio", "trace time / Embree's, median over the paired samples (>1 slower)",
     lambda r, l: (fmt(num(r.get("ratio_vs_embree"))), num(r.get("ratio_vs_embree"))), False),
    ("ratio min–max", "smallest and largest paired ratio",
     lambda r, l: (f"{fmt(num(r.get('ratio_min')))}–{fmt(num(r.get('ratio_max')))}"
                   if num(r.get("ratio_min")) is not None else "", num(r.get("ratio_min"))), False),
    ("Mrays/s", "million rays per second (median of the timed samples) on the threads of the next column",
     lambda r, l: (fmt(num(r.get("mrays_per_s"))), num(r.get("mrays_per_s"))), False),
    ("threads", "threads the cell traced on (an accelerator that mutates while tracing runs on one)",
     lambda r, l: (r.get("threads", ""), num(r.get("threads"))), False),
    ("tests/ray", "primitive tests per ray",
     lambda r, l: (fmt(num(r.get("tests_per_ray"))), num(r.get("tests_per_ray"))), False),
    ("box tests/ray", "bounding-volume tests per ray",
     lambda r, l: (fmt(num(r.get("box_tests_per_ray"))), num(r.get("box_tests_per_ray"))), False),
    ("steps/ray", "traversal steps per ray",
     lambda r, l: (fmt(num(r.get("steps_per_ray"))), num(r.get("steps_per_ray"))), False),
    ("build ms", "build time, milliseconds", lambda r, l: (fmt(num(r.get("build_ms"))), num(r.get("build_ms"))), False),
    ("bytes/prim", "memory per primitive",
     lambda r, l: (fmt(num(r.get("bytes_per_prim"))), num(r.get("bytes_per_prim"))), False),
) + tuple((m, f"mismatches of class {m}", (lambda c: lambda r, l: (r.get(c, ""), num(r.get(c))))("mismatch_" + m),
           False) for m in MISMATCH)


def section_table(rows, labels):
    out = ['<section id="table"><h2>Every cell</h2>',
           '<p class="note">One row per CSV row (the last measurement of each cell). Ratio: trace time over '
           "Embree's on the same rays, paired samples; green is faster than Embree, red slower. Mrays/s is on "
           "the row's threads. The parameters in columns: params.csv beside the CSV (plot.py writes it). "
           "Sort by any column with its header button (click, Enter or Space; again to reverse).</p>",
           '<div class="scroll" tabindex="0" role="region" aria-label="table of every cell, scrolls sideways">',
           '<table id="cells"><thead><tr>']
    for head, title, _, left in COLUMNS:
        out.append(f'<th scope="col" class="{"t" if left else ""}" title="{esc(title)}">'
                   f'<button type="button">{esc(head)}</button></th>')
    out.append("</tr></thead><tbody>")
    for r in rows:
        label = labels[common.config_key(r)]
        cells = []
        for head, _, value, left in COLUMNS:
            text, key = value(r, label)
            style = ""
            if head == "ratio":
                style = ratio_colour(num(r.get("ratio_vs_embree")))
            if head == "real" and (num(r.get("mismatch_real")) or 0) > 0:
                style = "background:#f6b0b0;font-weight:700"
            attrs = f' data-v="{esc(repr(key))}"' if key is not None else ' data-v=""'
            if head == "accelerator":
                attrs += f' title="{esc(r.get("params", ""))}"'
            cls = ' class="t"' if left else ""
            sty = f' style="{style}"' if style else ""
            cells.append(f"<td{cls}{attrs}{sty}>{esc(text)}</td>")
        out.append("<tr>" + "".join(cells) + "</tr>")
    out.append("</tbody></table></div></section>")
    return "\n".join(out)


SCENE_FIGS = (("ratio", "Paired ratio to Embree per workload and accelerator, min-max bars"),
              ("mrays", "Ray throughput in Mrays/s per workload and accelerator, the legend giving each one's threads"),
              ("tests", "Primitive tests and traversal steps per ray per workload and accelerator"),
              ("build_mem", "Build time and bytes per primitive per accelerator"))


def plot_files(rows, labels, run_dir, tmp):
    """plot.py's PNGs: each from the run folder when it is there, else drawn into tmp.
    Returns {"overview": [(workload or None, path)], "sweeps": [(accel, key, path)], "scenes": [(scene, stem)],
    "scene_folder": folder of the per-scene PNGs}."""
    scenes = common.ordered(r["scene"] for r in rows)
    workloads = common.ordered((r["workload"] for r in rows), common.WORKLOAD_ORDER)
    stems, names = set(), []
    for s in scenes:
        stem = common.safe_name(s)
        while stem in stems:
            stem += "_"
        stems.add(stem)
        names.append((s, stem))
    drawn = os.path.join(tmp, "plots")
    os.makedirs(drawn, exist_ok=True)
    overview = []
    for w in [None] + workloads:
        name = common.overview_name(w)
        path = os.path.join(run_dir, name)
        if not os.path.isfile(path):
            path = os.path.join(drawn, name)
            common.plot_overview(rows, labels, scenes, path, [], workload=w)
        if os.path.isfile(path):
            overview.append((w, path))
    sweeps = []
    for name, accel, key, members in common.sweep_list(rows):
        path = os.path.join(run_dir, name)
        if not os.path.isfile(path):
            path = os.path.join(drawn, name)
            common.plot_sweep(rows, labels, accel, key, members, path, [])
        if os.path.isfile(path):
            sweeps.append((accel, key, path))
    folder = run_dir
    if len(names) <= PLOT_MAX_SCENES and not all(
            os.path.isfile(os.path.join(run_dir, f"{stem}__{suf}.png")) for _, stem in names for suf, _ in SCENE_FIGS):
        folder = drawn
        for scene, stem in names:
            srows = [r for r in rows if r["scene"] == scene]
            common.plot_scene(scene, srows, labels, workloads, os.path.join(drawn, stem), [])
    return {"overview": overview, "sweeps": sweeps, "scenes": names, "scene_folder": folder}


def section_plots(rows, plots, run_dir):
    out = ['<section id="plots"><h2>Plots</h2>']
    for w, path in plots["overview"]:
        if w is None:
            out.append("<h3>Ratio to Embree, every scene and accelerator (geometric mean over workloads)</h3>")
            out.append(img(path, "Heat map of trace time relative to Embree, geometric mean over workloads, one row "
                                 "per scene and one column per accelerator; values above 1 are slower than Embree"))
    per_workload = [(w, path) for w, path in plots["overview"] if w is not None]
    if per_workload:
        out.append('<h3 id="heatmaps">Ratio to Embree per workload</h3><div class="figs">')
        for w, path in per_workload:
            out.append(img(path, f"Heat map of trace time relative to Embree for the {w} workload, one row per scene "
                                 "and one column per accelerator; values above 1 are slower than Embree"))
        out.append("</div>")
    if plots["sweeps"]:
        out.append('<h3 id="sweeps">Sweeps</h3><p class="note">Instances of one accelerator that differ in one '
                   "parameter: the parameter on x, the paired ratio to Embree (median, min–max bars) on y, one line "
                   "per scene, one panel per workload.</p>")
        for accel, key, path in plots["sweeps"]:
            out.append(img(path, f"Sweep of {accel}'s parameter {key}: paired ratio to Embree against {key}, one line "
                                 "per scene, one panel per workload"))
    names, folder = plots["scenes"], plots["scene_folder"]
    if len(names) > PLOT_MAX_SCENES:
        out.append(f'<p class="note">{len(names)} scenes: their per-scene figures are not embedded, to keep the page '
                   "small (accelbench report embeds them for runs of at most "
                   f"{PLOT_MAX_SCENES} scenes); plot.py's PNGs beside the CSV:</p><ul>")
        for scene, stem in names:
            have = [suf for suf, _ in SCENE_FIGS if os.path.isfile(os.path.join(run_dir, f"{stem}__{suf}.png"))]
            links = " · ".join(f'<a href="{esc(stem)}__{suf}.png">{suf}</a>' for suf in have) or "not drawn"
            out.append(f"<li>{esc(scene)}: {links}</li>")
        out.append("</ul></section>")
        return "\n".join(out)
    for scene, stem in names:
        out.append(f"<h3>{esc(scene)}</h3><div class=\"figs\">")
        for suffix, what in SCENE_FIGS:
            p = os.path.join(folder, f"{stem}__{suffix}.png")
            if os.path.isfile(p):
                out.append(img(p, f"{what} on {scene}"))
        out.append("</div>")
    out.append("</section>")
    return "\n".join(out)


def scene_args(option, scene):
    """[option, scene], or [option, base, --view, spec] for SCENE@eye=... (a view's commas cannot go in a list)."""
    if "@" in scene and "=" in scene.split("@", 1)[1]:
        base, view = scene.split("@", 1)
        return [option, base, "--view", view]
    return [option, scene]


def param_args(accel, params, defaults):
    """--param ACCEL.KEY=VALUE for every parameter that differs from the defaults (every one when they are unknown)."""
    d, args = defaults.get(accel, {}), []
    for kv in common.split_params(params):
        k, _, v = kv.partition("=")
        if not d or d.get(k) != v:
            args += ["--param", f"{accel}.{k}={v}"]
    return args


def render_args(binary, scene, accel, params, defaults):
    """accelbench render's arguments for one scene and accelerator configuration."""
    return [binary, "render"] + scene_args("--scene", scene) + ["--accel", accel] + param_args(accel, params, defaults)


def heat_side(rows):
    res = next((r.get("res") for r in rows if r.get("res")), "128x128")
    try:
        w, h = (int(x) for x in res.split("x"))
    except ValueError:
        w, h = 128, 128
    s = HEAT_SIDE / max(w, h)  # the run's aspect, HEAT_SIDE pixels on its longer side
    return max(8, int(w * s)), max(8, int(h * s))


def colourbar(top):
    fig = plt.figure(figsize=(1.1, 2.4))
    ax = fig.add_axes((0.15, 0.05, 0.25, 0.9))
    fig.colorbar(plt.cm.ScalarMappable(norm=plt.Normalize(0, top), cmap="inferno"), cax=ax)
    ax.tick_params(labelsize=8)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100, metadata={"Software": None})
    plt.close(fig)
    return buf.getvalue()


def run_render(args, out, quiet):
    p = subprocess.run(args + ["--out", out], capture_output=True, text=True)
    if p.returncode != 0:
        return None, (p.stderr.strip().splitlines() or ["exit %d" % p.returncode])[-1]
    m = re.search(r"max ([0-9.eE+-]+)", p.stdout)
    return (float(m.group(1)) if m else 0.0), None


def section_pictures(rows, labels, binary, defaults, mode, tmp, quiet):
    scenes = common.ordered(r["scene"] for r in rows)
    out = ['<section id="pictures"><h2>Pictures and primary-ray cost heat maps</h2>']
    if mode == "off" or not binary:
        out.append('<p class="note">Not drawn (report --pictures on draws them: one picture per scene and two '
                   'heat map renders and builds per accelerator and scene).</p></section>')
        return "\n".join(out)
    if mode == "auto" and len(scenes) > PICTURE_MAX_SCENES:
        out.append(f'<p class="note">Not drawn: {len(scenes)} scenes, more than {PICTURE_MAX_SCENES} '
                   '(report --pictures on draws them: two heat map renders and builds per accelerator and scene).</p>'
                   "</section>")
        return "\n".join(out)
    w, h = heat_side(rows)
    out.append(f'<p class="note">Per-pixel primitive tests of the primary rays ({w}x{h} pixels, '
               "`accelbench render --heatmap tests`), every accelerator of a scene on the same colour scale "
               "(--heatmap-max: black none, yellow the scene's highest cost, or 4x the median of the accelerators' maxima "
               "when one is far above the rest: that map saturates); the picture is rendered through "
               "embree. Accelerators that count nothing (embree) or answer shadow rays only are left out.</p>")
    for si, scene in enumerate(scenes):
        srows = [r for r in rows if r["scene"] == scene]
        prims = num(srows[0].get("prims")) or 0
        out.append(f"<h3>{esc(scene)} ({int(prims)} primitives)</h3>")
        if mode == "auto" and prims > PICTURE_MAX_PRIMS:
            out.append(f'<p class="note">Not drawn: more than {PICTURE_MAX_PRIMS} primitives (--pictures on).</p>')
            continue
        configs = common.ordered(common.config_key(r) for r in srows
                                 if r["workload"] in CLOSEST and num(r.get("tests_per_ray")) is not None)
        size = ["--res", f"{w}x{h}"]
        pic = os.path.join(tmp, f"pic{si}.png")
        figs, notes = [], []
        _, err = run_render(render_args(binary, scene, "embree", "", {}) + size, pic, quiet)
        if err is None:
            figs.append(f'<figure>{img(pic, f"Picture of {scene}: Whitted shading with shadows and mirrors", "pic")}'
                        "<figcaption>picture</figcaption></figure>")
        else:
            notes.append(f"picture: {err}")
        maxima = {}
        for ci, cfg in enumerate(configs):
            m, err = run_render(render_args(binary, scene, cfg[0], cfg[1], defaults) + size + ["--heatmap", "tests"],
                                os.path.join(tmp, f"h{si}_{ci}.png"), quiet)
            if err is None:
                maxima[cfg] = m
            else:
                notes.append(f"{labels[cfg]}: {err}")
        # One scale for the scene: the largest maximum, unless one map's is far above the others' (a degenerate
        # structure testing everything): then 4x their median, and that map saturates (its caption says so).
        top = max(list(maxima.values()) + [1.0])
        if len(maxima) >= 3:
            top = max(1.0, min(top, 4.0 * float(np.median(list(maxima.values())))))
        for ci, cfg in enumerate(configs):
            if cfg not in maxima:
                continue
            path = os.path.join(tmp, f"h{si}_{ci}.png")
            _, err = run_render(render_args(binary, scene, cfg[0], cfg[1], defaults) + size +
                                ["--heatmap", "tests", "--heatmap-max", repr(top)], path, quiet)
            if err is not None:
                notes.append(f"{labels[cfg]}: {err}")
                continue
            over = maxima[cfg] > top
            alt = (f"Heat map of primitive tests per primary ray through {labels[cfg]} on {scene}, colour scale 0 to "
                   f"{top:g} tests; its own maximum {maxima[cfg]:g}" + (", above the scale" if over else ""))
            figs.append(f'<figure>{img(path, alt, "hm")}<figcaption>{esc(labels[cfg])}<br>max {maxima[cfg]:g}'
                        + (" (above the scale)" if over else "") + "</figcaption></figure>")
        if maxima:
            alt = f"Colour scale of the heat maps of {scene}: 0 to {top:g} primitive tests per pixel"
            figs.append(f'<figure>{img(colourbar(top), alt, "bar")}<figcaption>tests/pixel</figcaption></figure>')
        out.append('<div class="heat">' + "".join(figs) + "</div>")
        if notes:
            out.append('<p class="note">' + "<br>".join(esc(n) for n in notes) + "</p>")
    out.append("</section>")
    return "\n".join(out)


def scaling_plot(fam, data, labels_order, workloads):
    """Log-log plot of one family: time and tests per workload, build and memory; points and fitted lines."""
    panels = [("time", w) for w in workloads] + [("tests", w) for w in workloads] + [("build", None), ("memory", None)]
    panels = [p for p in panels if any(k[0] == p[0] and k[2] == p[1] for k in data["points"])]
    ncol = min(3, len(panels))
    nrow = math.ceil(len(panels) / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.3 * ncol + 2.2, 3.4 * nrow), squeeze=False)
    meta = {m[0]: m for m in METRICS}
    for ax, (metric, wl) in zip(axes.flat, panels):
        for i, label in enumerate(labels_order):
            key = (metric, label, wl)
            if key not in data["points"]:
                continue
            p = data["points"][key]
            colour = f"C{i % 10}"
            ax.plot([n for n, _ in p], [y for _, y in p], "o", color=colour, ms=4, label=label)
            f = data["fits"].get(key)
            if f:
                xs = np.array([p[0][0], p[-1][0]])
                ax.plot(xs, f["c"] * xs ** f["k"], "-", color=colour, lw=1)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("N (primitives)")
        ax.set_ylabel(meta[metric][2])
        ax.set_title(f"{meta[metric][1]}" + (f" ({wl})" if wl else ""), fontsize=10)
        ax.grid(alpha=0.3, which="both")
    for ax in list(axes.flat)[len(panels):]:
        ax.axis("off")
    legend = {}
    for ax in axes.flat:  # every accelerator once, also those missing from the first panel (lightbuf)
        for h, n in zip(*ax.get_legend_handles_labels()):
            legend.setdefault(n, h)
    fig.legend(list(legend.values()), list(legend), loc="center right", fontsize=8)
    fig.suptitle(f"spd:{fam}: cost against size, log-log, fitted y = c N^k", fontsize=11)
    fig.tight_layout(rect=(0, 0, 1 - 1.9 / (4.3 * ncol + 2.2), 0.95))
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=95, metadata={"Software": None})
    plt.close(fig)
    return buf.getvalue()


def exponent_plot(fam, data, labels_order, workloads):
    """The fitted exponents with their 95% intervals: one row per accelerator, one marker per quantity."""
    keys = [("time", w) for w in workloads] + [("tests", w) for w in workloads] + [("build", None), ("memory", None)]
    keys = [k for k in keys if any((k[0], l, k[1]) in data["fits"] for l in labels_order)]
    labs = [l for l in labels_order if any((k[0], l, k[1]) in data["fits"] for k in keys)]
    fig, ax = plt.subplots(figsize=(9, 0.22 * len(labs) * max(1, len(keys)) ** 0.5 + 1.6))
    step = 0.8 / max(1, len(keys))
    for j, (metric, wl) in enumerate(keys):
        ys, xs, lo, hi = [], [], [], []
        for i, l in enumerate(labs):
            f = data["fits"].get((metric, l, wl))
            if not f:
                continue
            ys.append(i - 0.4 + step * (j + 0.5))
            xs.append(f["k"])
            lo.append(f["k"] - f["lo"])
            hi.append(f["hi"] - f["k"])
        name = {m[0]: m[1] for m in METRICS}[metric] + (f" ({wl})" if wl else "")
        ax.errorbar(xs, ys, xerr=[lo, hi], fmt="o", ms=4, capsize=2, lw=0.9, label=name, color=f"C{j % 10}")
    ax.axvline(0, color="0.5", lw=0.8)
    ax.axvline(1, color="0.5", lw=0.8, ls="--")
    ax.set_yticks(range(len(labs)), labs)
    ax.invert_yaxis()
    ax.set_xlabel("exponent k in c N^k (95% interval)")
    ax.set_xlim(max(-1.5, ax.get_xlim()[0]), min(3.0, ax.get_xlim()[1]))
    ax.set_title(f"spd:{fam}: fitted growth exponents", fontsize=11)
    ax.grid(axis="x", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    return fig_bytes(fig)


def fit_text(f):
    return f"N^{f['k']:.2f} [{f['lo']:.2f}, {f['hi']:.2f}]"


def sentences(data, labels_order, workloads):
    """One sentence per accelerator of a family."""
    out = []
    for l in labels_order:
        parts = []
        for w in workloads:
            f = data["fits"].get(("time", l, w))
            if f:
                parts.append(f"{w} trace time per ray grows as {fit_text(f)}")
            f = data["fits"].get(("tests", l, w))
            if f:
                parts.append(f"{w} tests per ray as {fit_text(f)}")
        for key, name in (("build", "build time"), ("memory", "memory")):
            f = data["fits"].get((key, l, None))
            if f:
                parts.append(f"{name} as {fit_text(f)}")
        if parts:
            out.append(f"{l}: " + "; ".join(parts) + ".")
    return out


def section_scaling(rows, labels):
    fits = scaling_fits(rows, labels)
    out = ['<section id="scaling"><h2>Cost growth</h2>']
    if not fits:
        out.append('<p class="note">No scaling series: no SPD family (spd:NAME:N) with three or more sizes in the run '
                   "(accelbench run --scenes set:scaling:FAMILY makes one).</p></section>")
        return "\n".join(out)
    out.append('<p class="note">Each quantity is fitted as c N^k, N the primitive count, by least squares on '
               "log y against log N (numpy.polyfit); the interval is the slope's 95% confidence interval from "
               "polyfit's covariance and Student's t on (sizes - 2) degrees of freedom. Trace time is per ray "
               "(trace_ms / rays), tests per ray from the warm-up's counters, build time and memory the median over "
               "a scene's workloads. k = 0: constant; k = 1: linear in N.</p>")
    workloads = common.ordered((r["workload"] for r in rows), common.WORKLOAD_ORDER)
    labels_order = list(dict.fromkeys(labels[common.config_key(r)] for r in rows))
    for fam, data in fits.items():
        sizes = sorted({n for p in data["points"].values() for n, _ in p})
        out.append(f"<h3>spd:{esc(fam)} ({len(sizes)} sizes, {int(sizes[0])} to {int(sizes[-1])} primitives)</h3>")
        out.append('<ul class="sent">' + "".join(f"<li>{esc(s)}</li>" for s in sentences(data, labels_order, workloads))
                   + "</ul>")
        out.append('<div class="figs">')
        out.append(img(scaling_plot(fam, data, labels_order, workloads),
                       f"Log-log plots for spd:{fam}: trace time and tests per ray per workload, build time and "
                       "memory against the primitive count, one colour per accelerator, with fitted power lines"))
        out.append(img(exponent_plot(fam, data, labels_order, workloads),
                       f"Fitted growth exponents for spd:{fam} with 95% confidence intervals, one row per "
                       "accelerator, one marker per quantity"))
        out.append("</div>")
        out.append(f'<details><summary>Exponents of spd:{esc(fam)} as a table</summary><div class="scroll" tabindex="0" '
                   f'role="region" aria-label="exponents of spd:{esc(fam)}"><table><thead><tr><th class="t">accelerator'
                   '</th><th class="t">quantity</th><th>k</th><th>95% interval</th><th>sizes</th></tr></thead><tbody>')
        for (metric, l, wl), f in sorted(data["fits"].items(), key=lambda kv: (labels_order.index(kv[0][1]),
                                                                                 kv[0][0], kv[0][2] or "")):
            name = {m[0]: m[1] for m in METRICS}[metric] + (f" ({wl})" if wl else "")
            out.append(f'<tr><td class="t">{esc(l)}</td><td class="t">{esc(name)}</td><td>{f["k"]:.3f}</td>'
                       f'<td>[{f["lo"]:.3f}, {f["hi"]:.3f}]</td><td>{f["n"]}</td></tr>')
        out.append("</tbody></table></div></details>")
    out.append("</section>")
    return "\n".join(out)


def growth_markdown(rows, labels):
    """The cost-growth sentences of every family, as Markdown (report.py --growth-md)."""
    workloads = common.ordered((r["workload"] for r in rows), common.WORKLOAD_ORDER)
    order = list(dict.fromkeys(labels[common.config_key(r)] for r in rows))
    out = ["# Cost growth", "", "Fitted c N^k (N primitives) with the exponent's 95% interval; see report.html.", ""]
    for fam, data in scaling_fits(rows, labels).items():
        sizes = sorted({n for p in data["points"].values() for n, _ in p})
        out += [f"## spd:{fam}", "", f"sizes: {', '.join(str(int(n)) for n in sizes)} primitives", ""]
        out += [f"- {s}" for s in sentences(data, order, workloads)] + [""]
    return "\n".join(out)


def parse_cell_key(key):
    words = {}
    for w in (key or "").split(" "):
        k, sep, v = w.partition("=")
        if sep:
            words[k] = re.sub(r"%([0-9A-Fa-f]{2})", lambda m: chr(int(m.group(1), 16)), v)
    return words


def verify_command(r, defaults):
    """The verify command that re-runs one cell's verification (it lists the mismatching rays, each with its replay)."""
    k = parse_cell_key(r.get("cell_key", ""))
    scene = k.get("scene", r["scene"])
    args = ["accelbench", "verify"] + scene_args("--scenes", scene)
    if "rays" in k:
        args += ["--rays", f"RAYFILE(hash {k['rays']})"]
    else:
        args += ["--workloads", r["workload"], "--res", k.get("res", r.get("res", "")), "--spp", k.get("spp", "1"),
                 "--seed", k.get("seed", r.get("seed", "1"))]
        if k.get("depth", "0") not in ("", "0"):
            args += ["--depth", k["depth"]]
        if k.get("corners") == "1":
            args.append("--corners")
    args += ["--accels", r["accel"]] + param_args(r["accel"], r.get("params", ""), defaults)
    return " ".join(shlex.quote(a) for a in args)


def section_verify(rows, labels, defaults):
    out = ['<section id="verification"><h2>Verification</h2>']
    totals = {m: sum(int(num(r.get("mismatch_" + m)) or 0) for r in rows) for m in MISMATCH}
    agree = sum(int(num(r.get("agree")) or 0) for r in rows)
    out.append(f"<p>{agree} answers agree with Embree; mismatches by class: " +
               ", ".join(f"{m} {totals[m]}" for m in MISMATCH) +
               ". Only <b>real</b> ones are bugs (edge, tol and origin are float noise or ill-posed rays, refwrong "
               "is Embree wrong by the exact judge, unjudged ran out of the judge's time).</p>")
    bad = [r for r in rows if (num(r.get("mismatch_real")) or 0) > 0]
    if not bad:
        out.append('<p>No real mismatch in any cell.</p></section>')
        return "\n".join(out)
    out.append(f'<p class="bad">{len(bad)} cell{"s" if len(bad) != 1 else ""} with real mismatches. Each command '
               "lists the cell's mismatching rays, each with the exact command that replays it (--ray I).</p><ul>")
    for r in bad:
        out.append(f"<li>{esc(r['scene'])} · {esc(labels[common.config_key(r)])} · {esc(r['workload'])}: "
                   f"{esc(r.get('mismatch_real'))} real of {esc(r.get('rays'))} rays"
                   f"<pre>{esc(verify_command(r, defaults))}</pre></li>")
    out.append("</ul></section>")
    return "\n".join(out)


def section_models(run_dir):
    """What `accelbench tune` and `accelbench predict` wrote into the folder, when they did: per structure the
    gain of its tuned setting over its default, and how well its cost model ranks its measured work."""
    import csv as _csv
    import tune
    out = []
    path = os.path.join(run_dir, "tuning.csv")
    if os.path.isfile(path):
        with open(path, newline="", encoding="utf-8", errors="replace") as f:
            recs = [dict(r, gain=common.num(r.get("gain"))) for r in _csv.DictReader(f)]
        out.append("<h3>Tuning: each structure's default against its best setting</h3>"
                   '<p class="note">From tuning.csv (accelbench tune): the gain is the default\'s ratio to Embree over '
                   "the tuned setting's, on the measured rays; the setting was chosen on other, training rays.</p>"
                   '<table><thead><tr><th class="t">structure</th><th class="t">parameter (default)</th><th>cells</th>'
                   '<th>geometric-mean gain</th><th>largest</th><th class="t">chosen (times)</th></tr></thead><tbody>')
        for p in tune.per_structure(recs):
            out.append(f'<tr><td class="t">{esc(p["accel"])}</td><td class="t">{esc(p["key"])} ({esc(p["default"])})'
                       f'</td><td>{p["cells"]}</td><td>{tune.fmt(p["gm_gain"])}</td><td>{tune.fmt(p["max_gain"])}</td>'
                       f'<td class="t">{esc(p["values"])}</td></tr>')
        out.append("</tbody></table>")
    path = os.path.join(run_dir, "prediction.csv")
    if os.path.isfile(path):
        with open(path, newline="", encoding="utf-8", errors="replace") as f:
            rows = [r for r in _csv.DictReader(f) if r.get("workload") == "all"]
        out.append("<h3>Cost models: predicted against measured work, over all workloads</h3>"
                   '<p class="note">From prediction.csv (accelbench predict): Spearman\'s rank correlation across the '
                   "cells and the median of measured over predicted; per workload in prediction.md.</p>"
                   '<table><thead><tr><th class="t">configuration</th><th class="t">counter</th><th>cells</th>'
                   "<th>rank corr.</th><th>measured / predicted</th></tr></thead><tbody>")
        for r in rows:
            out.append(f'<tr><td class="t">{esc(r["configuration"])}</td><td class="t">{esc(r["counter"])}</td>'
                       f'<td>{esc(r["cells"])}</td><td>{esc(r["rank_corr"])}</td>'
                       f'<td>{esc(r["median_measured_over_predicted"])}</td></tr>')
        out.append("</tbody></table>")
    if not out:
        return ""
    return '<section id="models"><h2>Tuning and cost models</h2>' + "\n".join(out) + "</section>"


def section_reproduce(run_dir):
    files = []
    for pat in ("*_tables.md", "summary.md", "report.md", "*/*_tables.md", "*/summary.md", "*/report.md"):
        files += sorted(glob.glob(os.path.join(run_dir, pat)))
    files = [f for f in dict.fromkeys(files) if not (os.path.basename(f) == "summary.md" and summary.written_by_us(f))]
    if not files:
        return ""
    out = ['<section id="reproduce"><h2>Findings of reproduce runs</h2>']
    for path in files:
        text = open(path, encoding="utf-8", errors="replace").read()
        rel = os.path.relpath(path, run_dir)
        finds = [l.strip() for l in text.splitlines() if "finding:" in l]
        out.append(f"<h3>{esc(rel)}</h3>")
        if finds:
            out.append("<ul>" + "".join(f"<li>{esc(f)}</li>" for f in finds) + "</ul>")
        out.append(f"<details><summary>{esc(rel)} in full</summary><pre>{esc(text)}</pre></details>")
    out.append("</section>")
    return "\n".join(out)


def write_page(path, body, title):
    """The page through a temporary file beside path, renamed over it."""
    common.check_replaceable(path)
    fd, tmp = tempfile.mkstemp(prefix=".report.", suffix=".tmp", dir=os.path.dirname(os.path.abspath(path)))
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(f'<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
                    f'<meta name="viewport" content="width=device-width, initial-scale=1">'
                    f"<title>{esc(title)}</title><style>{CSS}</style></head><body>\n{body}\n"
                    f"<script>{SORT_JS}</script></body></html>\n")
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(tmp, 0o666 & ~mask)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def main(argv=None):
    p = argparse.ArgumentParser(prog=PROG, description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run_dir", metavar="RUN_DIR")
    p.add_argument("--out", metavar="FILE.html", help="default RUN_DIR/report.html")
    p.add_argument("--accelbench", metavar="BIN", help="the accelbench binary (for defaults, heat maps and pictures)")
    p.add_argument("--pictures", choices=("auto", "on", "off"), default="auto")
    p.add_argument("--quiet", action="store_true")
    p.add_argument("--growth-md", action="store_true",
                   help="print the cost-growth sentences of every family as Markdown instead of writing the page")
    args = p.parse_args(argv)
    if not os.path.isdir(args.run_dir):
        common.fail(f"{args.run_dir}: no such folder")
    csv_path = os.path.join(args.run_dir, "matrix.csv")
    rows = common.load_rows(csv_path, common.REQUIRED + ("prims", "params", "threads"), check=bad_measure)
    rows = common.dedup_rows(rows, csv_path) if rows else rows
    binary = args.accelbench or os.environ.get("ACCELBENCH")
    if binary and not os.access(binary, os.X_OK):
        binary = None
    # The defaults (labels) also from the source tree's build when no binary is given; pictures only with one given.
    defaults_from = common.find_accelbench(binary)
    defaults = accel_defaults(defaults_from)
    labels = config_labels(rows, defaults)
    if args.growth_md:
        print(growth_markdown(rows, labels))
        return 0
    out_path = args.out or os.path.join(args.run_dir, "report.html")
    common.check_replaceable(out_path)
    title = f"accelbench report: {os.path.basename(os.path.abspath(args.run_dir))}"
    tmp = tempfile.mkdtemp(prefix="accelbench-report.")
    try:
        parts = [f"<h1>{esc(title)}</h1>",
                 '<nav aria-label="sections"><p><a href="#findings">findings</a> · <a href="#run">run</a> · '
                 '<a href="#plots">plots</a> · <a href="#pictures">pictures</a> · <a href="#scaling">cost growth</a>'
                 ' · <a href="#verification">verification</a> · <a href="#table">every cell</a></p></nav>']
        if not rows:
            parts.append("<p>The CSV has no data rows.</p>")
        else:
            parts.append(findings.html(findings.findings(rows, labels, common.config_key), esc))
            parts.append(section_run(rows, args.run_dir))
            plots = plot_files(rows, labels, args.run_dir, tmp)
            parts.append(section_plots(rows, plots, args.run_dir))
            parts.append(section_pictures(rows, labels, binary, defaults, args.pictures, tmp, args.quiet))
            parts.append(section_scaling(rows, labels))
            parts.append(section_verify(rows, labels, defaults))
        parts.append(section_models(args.run_dir))
        parts.append(section_reproduce(args.run_dir))
        if rows:
            parts.append(section_table(rows, labels))
        write_page(out_path, "\n".join(parts), title)
        if rows and os.path.dirname(os.path.abspath(out_path)) == os.path.abspath(args.run_dir):
            summary.write_beside(csv_path, args.run_dir, defaults_from)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    if not args.quiet:
        print(f"wrote {out_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
