#!/usr/bin/python3
"""Plot an accelbench results CSV as PNG figures (written next to the CSV).

Per scene (name made file-safe: ':' '/' etc. -> '_'):
  <scene>__ratio.png      the headline: paired ratio to Embree (ratio_vs_embree)
                          per workload x accelerator, ratio_min-ratio_max bars
  <scene>__mrays.png      Mrays/s per workload x accelerator, min-max error bars;
                          the legend gives each accelerator's threads (one for
                          those that mutate while tracing)
  <scene>__tests.png      tests_per_ray (+ steps_per_ray panel if any nonzero);
                          accelerators with empty counters (embree) omitted
  <scene>__build_mem.png  build_ms and bytes_per_prim per accelerator
Once per file:
  overview__ratio.png     ratio_vs_embree, geometric mean over workloads,
                          scene x accelerator heat map (>1 = slower than Embree)
  overview__ratio__<workload>.png   the same heat map of one workload's cells
  sweep__<accel>__<key>.png         (__2, __3 for further groups) instances of
                          one accelerator differing in one parameter: the
                          parameter on x, the paired ratio (min-max) on y, a
                          line per scene, a panel per workload
  params.csv              the parameters in columns: one row per configuration
                          and parameter (label, accel, threads, params, key,
                          value, default: yes/no, empty when unknown)
  summary.md              scripts/summary.py's Markdown (the findings first),
                          unless a summary.md of another writer is there

Labels: the default instance of an accelerator is its name alone ("grid"),
another "grid[res=cubic:20]" with the parameters that differ from the
defaults, read from `accelbench list accels` (--accelbench BIN, else
$ACCELBENCH, which run sets, else the source tree's build/accelbench). When
no binary runs, an accelerator with several params strings in the file shows
the pairs not shared by all of them (the one with none extra: its name
alone). "@<n>t" is added when one configuration ran with several thread
counts. Rows with fewer fields than
the header (interrupted run) are skipped with a warning. A cell measured
more than once (rows of one cell_key; in files without that column, of one
scene, accel, params, workload, threads and rayset_hash) is plotted from its
LAST row, the newest measurement, with a warning saying how many were
dropped. Exit status 2 for a missing file or a CSV without the required
columns.
"""
import argparse
import csv
import math
import os
import re
import stat
import statistics
import sys

import warnings

import matplotlib
matplotlib.use("Agg")
# A name's control characters have no glyph; matplotlib's warning would print them raw to the terminal.
warnings.filterwarnings("ignore", message="Glyph .* missing from")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.colors import LogNorm  # noqa: E402

REQUIRED = ("scene", "accel", "workload", "rays", "trace_ms", "mrays_per_s")
WORKLOAD_ORDER = ("primary", "shadow", "reflection", "diffuse", "random")
LOG_SPAN = 20.0      # use a log axis when max/min exceeds this
MAX_PARAMS = 40      # longest params string shown in a label
DPI = 110
PROG = "plot.py"


def fail(msg):
    """Print a one-line error and exit with status 2."""
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    sys.exit(2)


def check_replaceable(path):
    """Exit 2 with one line when path exists and is not a regular file (a
    directory, FIFO, device or socket): a file written there and renamed
    over it would replace it. Symlinks are followed."""
    try:
        st = os.stat(path)
    except OSError:
        return
    if stat.S_ISREG(st.st_mode):
        return
    kind = ("a directory" if stat.S_ISDIR(st.st_mode) else "a FIFO" if stat.S_ISFIFO(st.st_mode)
            else "a character device" if stat.S_ISCHR(st.st_mode) else "a block device" if stat.S_ISBLK(st.st_mode)
            else "a socket" if stat.S_ISSOCK(st.st_mode) else "a special file")
    fail(f"{path}: is {kind}, not a regular file: not written (give the path of a file)")


def num(value):
    """Parse a CSV field as float; empty or malformed fields give None."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def load_rows(path, required=REQUIRED, check=None):
    """Read the CSV into a list of dicts, skipping short/long rows, and rows
    for which check(row) gives a reason (each named with its line)."""
    if not os.path.isfile(path):
        fail(f"{path}: no such file")
    try:
        f = open(path, newline="", encoding="utf-8", errors="replace")
    except OSError as e:
        fail(f"{path}: {e.strerror}")
    with f:
        reader = csv.reader(f)
        header = [h.strip() for h in next(reader, [])]
        missing = [c for c in required if c not in header]
        if missing:
            fail(f"{path}: missing required column(s): {', '.join(missing)}")
        rows = []
        for rec in reader:
            if not rec:
                continue
            if len(rec) != len(header):
                print(f"{PROG}: warning: {path}:{reader.line_num}: "
                      f"{len(rec)} fields, expected {len(header)}; row skipped",
                      file=sys.stderr)
                continue
            # A text field that begins with ' was guarded against spreadsheets' formulas (csv.c): unguard it.
            row = dict(zip(header, (v[1:] if v.startswith("'") else v for v in rec)))
            why = check(row) if check else None
            if why:
                print(f"{PROG}: warning: {path}:{reader.line_num}: {why}; row skipped", file=sys.stderr)
                continue
            rows.append(row)
    return rows


# What identifies a cell in a CSV written before rows had a cell_key.
LEGACY_CELL = ("scene", "accel", "params", "workload", "threads", "rayset_hash")


def cell_of(row):
    """The cell a row measures: its cell_key, else the legacy identity columns."""
    key = row.get("cell_key")
    return ("key", key) if key else ("legacy",) + tuple(row.get(c, "") for c in LEGACY_CELL)


def dedup_rows(rows, path):
    """One row per cell, the last of each (a re-measured cell's newest row),
    in the order of those last rows."""
    last = {}
    for i, r in enumerate(rows):
        last[cell_of(r)] = i
    kept = sorted(last.values())
    if len(kept) < len(rows):
        print(f"{PROG}: warning: {path}: {len(rows) - len(kept)} rows measure a cell a later row measures "
              "again; the later rows are plotted", file=sys.stderr)
    return [rows[i] for i in kept]


def split_params(params):
    """'a=1,b=x,y,c=2' -> ['a=1', 'b=x,y', 'c=2'] (a comma not before 'key=' stays in the value)."""
    parts = []
    for piece in params.split(","):
        if parts and "=" not in piece:
            parts[-1] += "," + piece
        else:
            parts.append(piece)
    return [p for p in parts if p]


def short_params(params, siblings, limit=MAX_PARAMS):
    """Params minus the key=value pairs shared by all siblings, cut to limit characters (None: not cut); ""
    when every pair is shared (the instance the others add to: labelled by its name alone)."""
    common = set.intersection(*(set(split_params(p)) for p in siblings))
    text = ",".join(p for p in split_params(params) if p not in common)
    return text if limit is None or len(text) <= limit else text[:limit - 1] + "…"


def parse_accel_listing(text):
    """From the text of `accelbench list accels`: {accel: {key: default}} and {accel: (key, [values])}, the
    search `accelbench tune` makes of each accelerator that declares one (its "tune: KEY=V|V" line)."""
    defaults, tunes, name = {}, {}, None
    for line in text.splitlines():
        m = re.match(r"^  ([a-z][\w-]*) ", line)
        if m:
            name = m.group(1)
            defaults[name] = {}
            continue
        m = re.match(r"^ {19}(\w+)=(\S*)  (?:\[here: (\S+)\] )?", line)
        if m and name:  # a default this machine settles (isa=auto [here: avx512]) is recorded settled
            defaults[name][m.group(1)] = m.group(3) or m.group(2)
            continue
        m = re.match(r"^ {17}tune: (\w+)=(\S+)$", line)
        if m and name:
            tunes[name] = (m.group(1), m.group(2).split("|"))
    return defaults, tunes


def parse_accel_defaults(text):
    """{accel: {key: default}} from the text of `accelbench list accels`."""
    return parse_accel_listing(text)[0]


def find_accelbench(given=None):
    """The accelbench binary whose `list accels` gives the parameters' defaults: the one given (None when it
    does not run), else $ACCELBENCH (run sets it), else SOURCE/build/accelbench when it was built there."""
    if given is not None:  # a binary named that does not run: no defaults
        return given if os.path.isfile(given) and os.access(given, os.X_OK) else None
    src = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    for binary in (os.environ.get("ACCELBENCH"), os.path.join(src, "build", "harness", "accelbench"),
                   os.path.join(src, "build", "accelbench")):
        if binary and os.path.isfile(binary) and os.access(binary, os.X_OK):
            return binary
    return None


def accel_defaults_from_env(given=None):
    """The parameters' defaults from find_accelbench(given), else {} (labels then fall back, config_labels)."""
    binary = find_accelbench(given)
    if not binary:
        return {}
    import subprocess
    try:
        text = subprocess.run([binary, "list", "accels"], capture_output=True, text=True, timeout=30).stdout
    except (OSError, subprocess.SubprocessError):
        return {}
    return parse_accel_defaults(text)


def default_label(accel, params, defaults, limit):
    """'grid[res=40x40x40]': the name and the parameters that differ from the defaults (None: defaults unknown)."""
    d = defaults.get(accel)
    if d is None:
        return None
    diff = ",".join(kv for kv in split_params(params) if d.get(kv.partition("=")[0]) != kv.partition("=")[2])
    if limit is not None and len(diff) > limit:
        diff = diff[:limit - 1] + "…"
    return f"{accel}[{diff}]" if diff else accel


def config_labels(rows, limit=MAX_PARAMS, defaults=None):
    """Map each (accel, params, threads) config to a unique display label (params cut to limit characters):
    with defaults ({accel: {key: default}}, parse_accel_defaults), the name and the parameters that differ from
    them; without, the name and, when an accel has several params strings, those not shared by all of them."""
    params_of, threads_of = {}, {}
    for r in rows:
        accel, params, threads = config_key(r)
        params_of.setdefault(accel, {})[params] = None
        threads_of.setdefault((accel, params), {})[threads] = None
    labels = {}
    for key in ordered(config_key(r) for r in rows):
        accel, params, threads = key
        label = default_label(accel, params, defaults or {}, limit)
        if label is None:
            label = accel
            if len(params_of[accel]) > 1:
                diff = short_params(params, params_of[accel], limit)
                label += f"[{diff}]" if diff else ""
        if len(threads_of[(accel, params)]) > 1:
            label += f"@{threads}t"
        while label in labels.values():
            label += "'"
        labels[key] = label
    return labels


def color_of(labels, cfg):
    """Stable colour for a config: its position in the file-wide label order."""
    return f"C{list(labels).index(cfg) % 10}"


def outside_legend(ax):
    """Legend to the right of the axes, so it never hides bars."""
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)


def config_key(row):
    """The identity of one accelerator configuration. Rows timed warm (run
    --warm-passes) are their own configuration, labelled like a parameter."""
    params = row.get("params", "")
    if row.get("timed_from") == "warm":
        params = f"{params},passes=warm" if params else "passes=warm"
    return (row["accel"], params, row.get("threads", ""))


def ordered(values, preferred=()):
    """Unique values, preferred ones first, the rest in first-seen order."""
    seen = list(dict.fromkeys(values))
    return [v for v in preferred if v in seen] + [v for v in seen if v not in preferred]


def safe_name(name):
    """Turn a scene name into a file-name-safe stem."""
    return re.sub(r"[^A-Za-z0-9.+-]+", "_", name).strip("._") or "scene"


def column_values(rows, col):
    """The distinct non-empty values of a column, in order, joined by commas; "?" when there are none."""
    return ", ".join(v for v in dict.fromkeys(r.get(col, "") for r in rows) if v) or "?"


def footer(fig, rows):
    """Small footer with machine/cpu, threads and git revision."""
    def uniq(col):
        return column_values(rows, col)
    fig.text(0.01, 0.005, f"machine: {uniq('machine')} | cpu: {uniq('cpu')} | "
             f"threads: {uniq('threads')} | git: {uniq('git_rev')}",
             fontsize=7, color="0.35", ha="left", va="bottom")


def save(fig, path, written):
    """Lay out, write and close a figure; record the path."""
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    fig.savefig(path, dpi=DPI, metadata={"Software": None})
    plt.close(fig)
    written.append(path)


def maybe_log(ax, values, axis="y"):
    """Switch an axis to log scale when positive values span > LOG_SPAN."""
    pos = [v for v in values if v is not None and v > 0]
    if pos and max(pos) / min(pos) > LOG_SPAN:
        (ax.set_yscale if axis == "y" else ax.set_xscale)("log")


def grouped_bars(ax, table, workloads, configs, labels, errors=None, legend=None):
    """Draw one bar group per workload, one bar per config; return values drawn. legend: {config: text}
    instead of the label."""
    width = 0.8 / max(1, len(configs))
    drawn = []
    for i, cfg in enumerate(configs):
        xs, ys, lo, hi = [], [], [], []
        for j, wl in enumerate(workloads):
            v = table.get((cfg, wl))
            if v is None:
                continue
            xs.append(j - 0.4 + width * (i + 0.5))
            ys.append(v)
            e = errors.get((cfg, wl), (0.0, 0.0)) if errors else (0.0, 0.0)
            lo.append(e[0])
            hi.append(e[1])
        drawn += ys
        ax.bar(xs, ys, width, label=(legend or labels)[cfg], color=color_of(labels, cfg),
               yerr=[lo, hi] if errors else None, capsize=2, error_kw={"lw": 0.8})
    ax.set_xticks(range(len(workloads)), workloads)
    ax.set_xlabel("workload")
    ax.grid(axis="y", alpha=0.3, which="both")
    maybe_log(ax, drawn)
    return drawn


def metric_table(rows, column):
    """{(config, workload): value} for one numeric column (first row wins)."""
    table = {}
    for r in rows:
        v = num(r.get(column))
        if v is not None:
            table.setdefault((config_key(r), r["workload"]), v)
    return table


def scene_title(scene, rows, what):
    """Figure title: what, scene and primitive count."""
    prims = next((r.get("prims") for r in rows if r.get("prims")), "?")
    return f"{what} — {scene} ({prims} prims)"


def plot_mrays(scene, rows, labels, workloads, configs, path, written):
    """Grouped Mrays/s bars with min/max error bars."""
    table, errors = {}, {}
    for r in rows:
        key = (config_key(r), r["workload"])
        rays, t, tmin, tmax = (num(r.get(c)) for c in ("rays", "trace_ms", "trace_ms_min", "trace_ms_max"))
        v = num(r["mrays_per_s"]) or (rays / t / 1000.0 if rays and t else None)
        if v is None or key in table:
            continue
        table[key] = v
        errors[key] = ((max(0.0, v - rays / tmax / 1000.0), max(0.0, rays / tmin / 1000.0 - v))
                       if rays and tmin and tmax else (0.0, 0.0))
    fig, ax = plt.subplots(figsize=(max(10, 1.6 * len(workloads) + 3), 4.8))
    grouped_bars(ax, table, workloads, configs, labels, errors, legend=threads_legend(rows, labels, configs))
    ax.set_ylabel("throughput [Mrays/s on the legend's threads]")
    ax.set_title(scene_title(scene, rows, "Ray throughput (median, min–max; threads per accelerator)"))
    outside_legend(ax)
    footer(fig, rows)
    save(fig, path, written)


def threads_legend(rows, labels, configs):
    """{config: 'label, N threads'}: a rate is only read with the threads it ran on (an accelerator that
    mutates while tracing runs on one)."""
    out = {}
    for c in configs:
        t = next((r.get("threads", "") for r in rows if config_key(r) == c), "")
        out[c] = f"{labels[c]}, {t} thread{'' if t == '1' else 's'}" if t else labels[c]
    return out


def plot_ratio(scene, rows, labels, workloads, configs, path, written):
    """The headline per scene: the paired ratio to Embree per workload x accelerator, min-max error bars."""
    table, errors = {}, {}
    for r in rows:
        if r["accel"] == "embree":
            continue
        key = (config_key(r), r["workload"])
        v, lo, hi = (num(r.get(c)) for c in ("ratio_vs_embree", "ratio_min", "ratio_max"))
        if v is None or v <= 0 or key in table:
            continue
        table[key] = v
        errors[key] = (max(0.0, v - lo) if lo else 0.0, max(0.0, hi - v) if hi else 0.0)
    cfgs = [c for c in configs if any(k[0] == c for k in table)]
    if not cfgs:
        return
    fig, ax = plt.subplots(figsize=(max(10, 1.6 * len(workloads) + 3), 4.8))
    grouped_bars(ax, table, workloads, cfgs, labels, errors)
    ax.axhline(1.0, color="0.3", lw=0.8, ls="--")
    ax.set_ylabel("trace time / Embree's, same rays [×]")
    ax.set_title(scene_title(scene, rows, "Paired ratio to Embree (median, min–max; <1 faster)"))
    outside_legend(ax)
    footer(fig, rows)
    save(fig, path, written)


def plot_tests(scene, rows, labels, workloads, configs, path, written):
    """tests_per_ray bars, plus steps_per_ray when any accel reports steps."""
    tests, steps = metric_table(rows, "tests_per_ray"), metric_table(rows, "steps_per_ray")
    with_tests = [c for c in configs if any(k[0] == c for k in tests)]
    if not with_tests:
        return
    show_steps = any(v > 0 for v in steps.values())
    fig, axes = plt.subplots(1, 2 if show_steps else 1, squeeze=False,
                             figsize=(14 if show_steps else 10, 4.8))
    ax = axes[0][0]
    grouped_bars(ax, tests, workloads, with_tests, labels)
    ax.set_ylabel("primitive tests per ray")
    ax.set_title(scene_title(scene, rows, "Intersection tests"))
    if show_steps:
        ax = axes[0][1]
        grouped_bars(ax, steps, workloads, with_tests, labels)
        ax.set_ylabel("traversal steps per ray")
        ax.set_title(scene_title(scene, rows, "Traversal steps"))
    outside_legend(axes[0][-1])
    footer(fig, rows)
    save(fig, path, written)


def plot_build_mem(scene, rows, labels, configs, path, written):
    """Two panels: build_ms and bytes_per_prim, one horizontal bar per config."""
    first = {}
    for r in rows:
        first.setdefault(config_key(r), r)
    fig, axes = plt.subplots(1, 2, sharey=True, figsize=(12, max(3.5, 0.45 * len(configs) + 2)))
    ys = list(range(len(configs)))
    for ax, col, xlabel, what in ((axes[0], "build_ms", "build time [ms]", "Build time"),
                                  (axes[1], "bytes_per_prim", "memory [bytes/prim]", "Memory")):
        vals = [num(first[c].get(col)) for c in configs]
        for y, c, v in zip(ys, configs, vals):
            ax.barh(y, v or 0, color=color_of(labels, c), label=labels[c])
            ax.annotate(" n/a" if v is None else f" {v:.3g}", (v or 0, y),
                        ha="left", va="center", fontsize=7)
        ax.set_xlabel(xlabel)
        ax.grid(axis="x", alpha=0.3, which="both")
        maybe_log(ax, vals, "x")
        ax.margins(x=0.15)
        ax.set_title(scene_title(scene, rows, what))
    axes[0].set_yticks(ys, [labels[c] for c in configs])
    axes[0].invert_yaxis()
    axes[0].set_ylabel("accelerator")
    outside_legend(axes[1])
    footer(fig, rows)
    save(fig, path, written)


def geomean(values):
    """Geometric mean of positive values, None when there are none."""
    pos = [v for v in values if v and v > 0]
    return math.exp(sum(map(math.log, pos)) / len(pos)) if pos else None


# The overview's rows: a figure is at most 65536 pixels high (matplotlib's limit), and a heat map of more rows
# than this is not read on one page anyway; the scenes past it are in the per-scene figures and the report's table.
OVERVIEW_MAX_SCENES = 300


def plot_overview(rows, labels, scenes, path, written, workload=None):
    """Heat map of geometric-mean ratio_vs_embree, scene x accelerator (the first OVERVIEW_MAX_SCENES scenes):
    over the workloads, or of one workload's rows."""
    if workload is not None:
        rows = [r for r in rows if r["workload"] == workload]
        scenes = [s for s in scenes if any(r["scene"] == s for r in rows)]
    configs = [c for c in ordered(config_key(r) for r in rows) if c[0] != "embree"]
    total = len(scenes)
    scenes = scenes[:OVERVIEW_MAX_SCENES]
    grid = [[geomean([num(r.get("ratio_vs_embree")) for r in rows
                      if r["scene"] == s and config_key(r) == c]) for c in configs]
            for s in scenes]
    vals = [v for line in grid for v in line if v]
    if not vals:
        return
    span = max(max(vals), 1 / min(vals), 1.01)
    fig, ax = plt.subplots(figsize=(max(6, 1.3 * len(configs) + 3), max(3.5, 0.6 * len(scenes) + 3)))
    im = ax.imshow([[v if v else float("nan") for v in line] for line in grid],
                   cmap="RdYlGn_r", norm=LogNorm(1 / span, span), aspect="auto")
    for i, line in enumerate(grid):
        for j, v in enumerate(line):
            text = f"{v:.2f}" if v else "n/a"
            dark = v and abs(math.log(v)) > 0.6 * math.log(span)
            ax.text(j, i, text, ha="center", va="center", fontsize=8,
                    color="white" if dark else "black")
    ax.set_xticks(range(len(configs)), [labels[c] for c in configs], rotation=30, ha="right")
    prims = {r["scene"]: r.get("prims", "?") for r in rows}
    ax.set_yticks(range(len(scenes)), [f"{s} ({prims[s]} prims)" for s in scenes])
    ax.set_xlabel("accelerator")
    ax.set_ylabel("scene")
    shown = f"; the first {len(scenes)} of {total} scenes" if total > len(scenes) else ""
    what = f"workload {workload}" if workload is not None else "geometric mean over workloads"
    ax.set_title("Trace time relative to Embree, same rays\n"
                 f"({what}; >1 = slower than Embree{shown})")
    fig.colorbar(im, ax=ax, label="ratio vs Embree [×]")
    footer(fig, rows)
    save(fig, path, written)


def overview_name(workload=None):
    """overview__ratio.png (over the workloads), overview__ratio__WORKLOAD.png (one)."""
    return "overview__ratio.png" if workload is None else f"overview__ratio__{safe_name(workload)}.png"


def sweep_name(accel, key, index):
    """sweep__ACCEL__KEY.png, with __2, __3 for further groups of the same accelerator and parameter."""
    return f"sweep__{safe_name(accel)}__{safe_name(key)}" + (f"__{index + 1}" if index else "") + ".png"


def sweep_list(rows):
    """[(file name, accel, key, [(value, config)])] of the run's sweeps (findings.sweeps)."""
    import findings
    out, seen = [], {}
    for accel, key, members in findings.sweeps(rows, config_key, split_params):
        i = seen.get((accel, key), 0)
        seen[(accel, key)] = i + 1
        out.append((sweep_name(accel, key, i), accel, key, members))
    return out


def plot_sweep(rows, labels, accel, key, members, path, written):
    """One sweep: the parameter on x, the paired ratio (min-max bars) on y, one line per scene, one panel per
    workload. A numeric parameter gets a numeric axis (log when it spans > LOG_SPAN), any other its values in
    the file's order."""
    vals = [v for v, _ in members]
    nums = [num(v) for v in vals]
    numeric = all(x is not None for x in nums)
    if numeric:
        order = sorted(range(len(vals)), key=lambda i: nums[i])
    else:
        order = list(range(len(vals)))
    xs = {members[i][1]: (nums[i] if numeric else pos) for pos, i in enumerate(order)}
    cfgs = [members[i][1] for i in order]
    srows = [r for r in rows if config_key(r) in xs]
    workloads = ordered((r["workload"] for r in srows), WORKLOAD_ORDER)
    scenes = ordered(r["scene"] for r in srows)
    if not workloads:
        return
    ncol = min(3, len(workloads))
    nrow = math.ceil(len(workloads) / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.6 * ncol + 2.4, 3.6 * nrow), squeeze=False)
    drawn = []
    for ax, w in zip(axes.flat, workloads):
        for si, s in enumerate(scenes):
            pts = []
            for c in cfgs:
                r = next((r for r in srows if config_key(r) == c and r["scene"] == s and r["workload"] == w), None)
                v = num(r.get("ratio_vs_embree")) if r else None
                if v is None or v <= 0:
                    continue
                lo, hi = num(r.get("ratio_min")), num(r.get("ratio_max"))
                pts.append((xs[c], v, v - lo if lo else 0.0, hi - v if hi else 0.0))
            if not pts:
                continue
            drawn += [p[1] for p in pts]
            ax.errorbar([p[0] for p in pts], [p[1] for p in pts], yerr=[[max(0, p[2]) for p in pts],
                        [max(0, p[3]) for p in pts]], fmt="o-", ms=3, lw=1, capsize=2, color=f"C{si % 10}", label=s)
        ax.axhline(1.0, color="0.3", lw=0.8, ls="--")
        ax.set_title(w, fontsize=10)
        ax.set_xlabel(key)
        ax.set_ylabel("ratio to Embree [×] (min–max)")
        if numeric:
            maybe_log(ax, list(xs.values()), "x")
        else:
            ax.set_xticks(range(len(cfgs)), [vals[i] for i in order], rotation=20)
        maybe_log(ax, drawn)
        ax.grid(alpha=0.3, which="both")
    for ax in list(axes.flat)[len(workloads):]:
        ax.axis("off")
    handles = {}
    for ax in axes.flat:
        for h, n in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(n, h)
    fig.legend(list(handles.values()), list(handles), loc="center right", fontsize=8, title="scene")
    fixed = [kv for kv in split_params(members[0][1][1]) if kv.partition("=")[0] != key]
    fixed_text = ",".join(fixed)
    if len(fixed_text) > 90:
        fixed_text = fixed_text[:89] + "…"
    fig.suptitle(f"{accel}: {key} swept ({fixed_text or 'no other parameters'})", fontsize=10)
    fig.tight_layout(rect=(0, 0.03, 1 - 2.2 / (4.6 * ncol + 2.4), 0.95))
    fig.savefig(path, dpi=DPI, metadata={"Software": None})
    plt.close(fig)
    written.append(path)


def plot_scene(scene, rows, labels, workloads, base, written):
    """Write the per-scene figures to <base>__*.png."""
    wls = [w for w in workloads if any(r["workload"] == w for r in rows)]
    cfgs = ordered(config_key(r) for r in rows)
    plot_ratio(scene, rows, labels, wls, cfgs, base + "__ratio.png", written)
    plot_mrays(scene, rows, labels, wls, cfgs, base + "__mrays.png", written)
    plot_tests(scene, rows, labels, wls, cfgs, base + "__tests.png", written)
    plot_build_mem(scene, rows, labels, cfgs, base + "__build_mem.png", written)


def parse_args(argv, prog=None, doc=__doc__, required=REQUIRED, csv_help="benchmark CSV written by the harness"):
    """Command-line interface (shared with plot_woo92.py)."""
    p = argparse.ArgumentParser(
        prog=prog or PROG, description=doc, formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=f"Required columns: {', '.join(required)}. Prints the files written "
               "unless --quiet.")
    p.add_argument("csv", metavar="CSV", help=csv_help)
    p.add_argument("--out", metavar="DIR", help="output folder (default: the CSV's folder)")
    p.add_argument("--quiet", action="store_true", help="do not list the files written")
    if prog is None:
        p.add_argument("--accelbench", metavar="BIN", help="the binary whose `list accels` gives the defaults "
                       "(default $ACCELBENCH, else the source tree's build/accelbench)")
    return p.parse_args(argv)


def rows_and_folder(args, required=REQUIRED):
    """The CSV's rows and the output folder (created); rows is empty, with a
    warning, when there is nothing to plot. Shared with plot_woo92.py."""
    rows = load_rows(args.csv, required)
    out = args.out or os.path.dirname(os.path.abspath(args.csv))
    os.makedirs(out, exist_ok=True)
    if not rows:
        print(f"{PROG}: warning: {args.csv}: no data rows, nothing plotted", file=sys.stderr)
    return rows, out


def run_folder_rows(run, out=None, required=REQUIRED, accelbench=None):
    """For the scripts that read one run (predict.py, calibrate.py): the CSV's path (run is a folder holding
    matrix.csv, or the CSV), its rows without Embree's (one per cell), the output folder (out, else the CSV's;
    it must exist) and the configurations' labels."""
    csv_path = os.path.join(run, "matrix.csv") if os.path.isdir(run) else run
    rows = [r for r in dedup_rows(load_rows(csv_path, required), csv_path) if r["accel"] != "embree"]
    folder = out or os.path.dirname(os.path.abspath(csv_path))
    if not os.path.isdir(folder):
        fail(f"--out {folder}: no such folder")
    return csv_path, rows, folder, config_labels(rows, defaults=accel_defaults_from_env(accelbench))


def ns_per_ray(row):
    """A row's trace time per ray in ns, or None without a time or rays."""
    t, n = num(row.get("trace_ms")), num(row.get("rays"))
    return t * 1e6 / n if t is not None and n else None


def paired_ns_per_ray(rows):
    """Each row's trace time per ray in ns, read through its pairing with Embree: its ratio to Embree times
    Embree's time per ray on that cell (scene, workload, rays, threads), the median over the rows that measured
    it. On a shared machine the load moves a row's time and its paired Embree time together: the ratio is
    stable and the cell's median Embree time is the least disturbed measure of the cell. A row without a ratio
    keeps its own time. A list in the rows' order; None where a row has no time."""
    def cell(r):
        return r.get("scene"), r.get("workload"), r.get("rays"), r.get("threads")
    embree = {}
    for r in rows:
        e, n = num(r.get("embree_ms")), num(r.get("rays"))
        if e and n:
            embree.setdefault(cell(r), []).append(e * 1e6 / n)
    out = []
    for r in rows:
        ratio, ref = num(r.get("ratio_vs_embree")), embree.get(cell(r))
        out.append(ratio * statistics.median(ref) if ratio and ref else ns_per_ray(r))
    return out


def run_child(argv, quiet):
    """Run argv (an argument vector, never a shell): its exit status. Its output passes through; quiet, it is
    held back, and on a failure the last lines of its errors are printed."""
    import subprocess
    if not quiet:
        return subprocess.run(argv).returncode
    p = subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, errors="replace")
    if p.returncode != 0:
        sys.stderr.write("".join(p.stderr.splitlines(True)[-5:]))
    return p.returncode


PRIM_KINDS = ("triangles", "spheres", "cones", "polygons")
_SCENE_INFO = re.compile(r"^primitives \d+: (\d+) triangles \(\d+ degenerate\), (\d+) spheres, (\d+) cones, "
                         r"(\d+) polygons", re.M)


def scene_kinds(accelbench, scenes):
    """{scene: {kind: count}} from `accelbench scene info SCENE` (an argument vector, one scene a call), for the
    scenes it describes; one it cannot load is left out."""
    import subprocess
    out = {}
    for s in scenes:
        p = subprocess.run([accelbench, "scene", "info", s], capture_output=True, text=True, errors="replace")
        m = _SCENE_INFO.search(p.stdout) if p.returncode == 0 else None
        if m:
            out[s] = dict(zip(PRIM_KINDS, (int(x) for x in m.groups())))
    return out


def mix_cost(prices, kinds):
    """One primitive test of a scene's mix ({kind: count}) at prices {kind: ns}; None when the scene holds no
    primitive or a kind without a price."""
    n = sum(kinds.values()) if kinds else 0
    if not n or any(c and k not in prices for k, c in kinds.items()):
        return None
    return sum(prices[k] * c / n for k, c in kinds.items() if c)


def fmt_g(v, digits=3):
    """v with `digits` significant digits, other values as their text, None as ""."""
    if v is None:
        return ""
    return f"{v:.{digits}g}" if isinstance(v, float) else str(v)


def write_csv(path, header, records, cell=fmt_g):
    """A CSV of header and records (lists of values, each written as cell(value)), whole or not at all."""
    import io
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(header)
    for rec in records:
        w.writerow([cell(v) for v in rec])
    write_text(path, buf.getvalue())


def write_text(path, text):
    """Write a text file whole or not at all (through a temporary file renamed over it)."""
    check_replaceable(path)
    with open(path + ".tmp", "w", encoding="utf-8", newline="") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def main(argv=None):
    """Load the CSV and write all plots."""
    args = parse_args(argv)
    rows, out = rows_and_folder(args)
    if not rows:
        return 0
    rows = dedup_rows(rows, args.csv)
    defaults = accel_defaults_from_env(args.accelbench)
    labels = config_labels(rows, defaults=defaults)
    workloads = ordered((r["workload"] for r in rows), WORKLOAD_ORDER)
    scenes = ordered(r["scene"] for r in rows)
    written, stems = [], set()
    for scene in scenes:
        srows = [r for r in rows if r["scene"] == scene]
        stem = safe_name(scene)
        while stem in stems:
            stem += "_"
        stems.add(stem)
        plot_scene(scene, srows, labels, workloads, os.path.join(out, stem), written)
    plot_overview(rows, labels, scenes, os.path.join(out, overview_name()), written)
    for w in workloads:
        plot_overview(rows, labels, scenes, os.path.join(out, overview_name(w)), written, workload=w)
    for name, accel, key, members in sweep_list(rows):
        plot_sweep(rows, labels, accel, key, members, os.path.join(out, name), written)
    import findings
    path = os.path.join(out, "params.csv")
    check_replaceable(path)
    findings.write_params_csv(path, findings.params_table(rows, labels, config_key, split_params, defaults))
    written.append(path)
    import summary
    path = summary.write_beside(args.csv, out, args.accelbench)
    if path:
        written.append(path)
    if not args.quiet:
        print("\n".join(written))
    return 0


if __name__ == "__main__":
    sys.exit(main())
