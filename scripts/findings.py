#!/usr/bin/python3
"""What a run found, computed once from matrix.csv for report.py and summary.py.

findings(rows, labels) gives:
  - ranking: per workload, every accelerator configuration (Embree left out)
    ordered by the geometric mean over its cells (scenes) of its paired ratio
    to Embree (ratio_vs_embree: the median over the samples of the
    accelerator's time over Embree's on the same rays), with a 95 % t-interval
    of that mean: on the logs x_i = ln r_i of its n cells,
        m = mean(x), s = sd(x) (n - 1 in the denominator),
        interval = exp(m -+ t(0.975, n - 1) s / sqrt(n)),
    none for n = 1;
  - winners: per (scene, workload) cell, the configuration with the lowest
    ratio, and the lowest among the survey's structures (every one except
    SURVEY_EXCLUDED); a winner is tied when its [ratio_min, ratio_max] (the
    smallest and largest of its paired samples' ratios) overlaps the
    runner-up's;
  - families: per accelerator name (all its instances), the cells it wins and
    the cell where its best instance is furthest behind the cell's winner.
markdown(f) and html(f) show the same numbers with the same rounding (NUMBER).
"""
import math

import numpy as np

SURVEY_EXCLUDED = ("embree", "cgal-aabb", "bvh")

# Two-sided 95 % quantiles of Student's t, df 1..30, then 40, 60, 120 (beyond: 1.960).
T975 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306, 9: 2.262, 10: 2.228,
        11: 2.201, 12: 2.179, 13: 2.160, 14: 2.145, 15: 2.131, 16: 2.120, 17: 2.110, 18: 2.101, 19: 2.093,
        20: 2.086, 21: 2.080, 22: 2.074, 23: 2.069, 24: 2.064, 25: 2.060, 26: 2.056, 27: 2.052, 28: 2.048,
        29: 2.045, 30: 2.042, 40: 2.021, 60: 2.000, 120: 1.980}


def t975(df):
    """The 0.975 quantile of Student's t with df degrees of freedom (scipy when installed, else the table)."""
    try:
        from scipy.stats import t
        return float(t.ppf(0.975, df))
    except ImportError:
        pass
    if df in T975:
        return T975[df]
    for d in (40, 60, 120):
        if df < d:
            return T975[d]  # the next tabulated df up: a slightly narrower interval than exact, within 1 %
    return 1.960


def number(v):
    """How findings print a ratio: 3 significant digits."""
    return "" if v is None else f"{v:.3g}"


def _num(text):
    try:
        x = float(text)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) and x > 0 else None


def log_interval(ratios):
    """(geometric mean, lo, hi, n) of positive ratios; lo and hi None for n < 2."""
    x = np.log(np.asarray(ratios, dtype=float))
    n = len(x)
    m = float(np.mean(x))
    if n < 2:
        return math.exp(m), None, None, n
    half = t975(n - 1) * float(np.std(x, ddof=1)) / math.sqrt(n)
    return math.exp(m), math.exp(m - half), math.exp(m + half), n


def _ordered(values, preferred=()):
    seen = list(dict.fromkeys(values))
    return [v for v in preferred if v in seen] + [v for v in seen if v not in preferred]


WORKLOAD_ORDER = ("primary", "shadow", "reflection", "diffuse", "random")


def _pick(cands):
    """Winner and runner-up of [(ratio, lo, hi, label, accel)] with the tie flag."""
    if not cands:
        return None
    cands = sorted(cands, key=lambda c: (c[0], c[3]))
    win = cands[0]
    run = cands[1] if len(cands) > 1 else None
    tie = False
    if run is not None:
        wlo, whi = (win[1] if win[1] is not None else win[0]), (win[2] if win[2] is not None else win[0])
        rlo, rhi = (run[1] if run[1] is not None else run[0]), (run[2] if run[2] is not None else run[0])
        tie = wlo <= rhi and rlo <= whi
    return {"label": win[3], "ratio": win[0], "lo": win[1], "hi": win[2],
            "runner_up": run[3] if run else None, "runner_ratio": run[0] if run else None, "tie": tie}


def findings(rows, labels, config_key):
    """The findings of deduplicated rows; labels maps config_key(row) to the configuration's label."""
    cells = {}
    for r in rows:
        if r["accel"] == "embree":
            continue
        v = _num(r.get("ratio_vs_embree"))
        if v is None:
            continue
        cells[(labels[config_key(r)], r["scene"], r["workload"])] = (v, _num(r.get("ratio_min")),
                                                                     _num(r.get("ratio_max")), r["accel"])
    workloads = _ordered((k[2] for k in cells), WORKLOAD_ORDER)
    scenes = _ordered(k[1] for k in cells)
    order = list(dict.fromkeys(k[0] for k in cells))
    ranking = {}
    for w in workloads:
        entries = []
        for lab in order:
            vs = [v[0] for (l, s, ww), v in cells.items() if l == lab and ww == w]
            if vs:
                gm, lo, hi, n = log_interval(vs)
                entries.append({"label": lab, "gm": gm, "lo": lo, "hi": hi, "n": n})
        entries.sort(key=lambda e: (e["gm"], e["label"]))
        ranking[w] = entries
    winners = {}
    for s in scenes:
        for w in workloads:
            cands = [(v[0], v[1], v[2], l, v[3]) for (l, ss, ww), v in cells.items() if ss == s and ww == w]
            if not cands:
                continue
            survey = [c for c in cands if c[4] not in SURVEY_EXCLUDED]
            winners[(s, w)] = {"all": _pick(cands), "survey": _pick(survey)}
    families = []
    accels = list(dict.fromkeys(v[3] for v in cells.values()))
    for a in accels:
        won, worst = [], None
        for (s, w), win in winners.items():
            mine = [(v[0], l) for (l, ss, ww), v in cells.items() if ss == s and ww == w and v[3] == a]
            if not mine:
                continue
            best = min(mine)
            if cells[(win["all"]["label"], s, w)][3] == a:
                won.append((s, w, win["all"]["label"]))
            else:
                behind = best[0] / win["all"]["ratio"]
                if worst is None or behind > worst["behind"]:
                    worst = {"scene": s, "workload": w, "label": best[1], "ratio": best[0], "behind": behind,
                             "winner": win["all"]["label"], "winner_ratio": win["all"]["ratio"]}
        ncells = len({(s, w) for (l, s, w), v in cells.items() if v[3] == a})
        families.append({"accel": a, "cells": ncells, "won": won, "worst": worst})
    return {"workloads": workloads, "scenes": scenes, "ranking": ranking, "winners": winners, "families": families}


def interval_text(e):
    return "n = 1: none" if e["lo"] is None else f"[{number(e['lo'])}, {number(e['hi'])}]"


def winner_text(p):
    if p is None:
        return "–"
    t = f"{p['label']} {number(p['ratio'])}"
    if p["tie"]:
        t += f" (tie with {p['runner_up']} {number(p['runner_ratio'])})"
    return t


def family_sentence(f):
    won = f["won"]
    if won:
        per_w = {}
        for s, w, lab in won:
            per_w[w] = per_w.get(w, 0) + 1
        by = {}
        for s, w, lab in won:
            by[lab] = by.get(lab, 0) + 1
        text = (f"wins {len(won)} of its {f['cells']} cells ("
                + ", ".join(f"{w} {k}" for w, k in per_w.items()) + "; by "
                + ", ".join(f"{lab} {k}" for lab, k in by.items()) + ")")
    else:
        text = f"wins none of its {f['cells']} cells"
    x = f["worst"]
    if x:
        text += (f"; loses worst on {x['scene']}/{x['workload']}: {x['label']} {number(x['ratio'])}, "
                 f"{number(x['behind'])}x the winner {x['winner']} {number(x['winner_ratio'])}")
    return f"{f['accel']}: {text}."


INTRO = ("Ratio: the accelerator's trace time over Embree's on the same rays, the median of paired samples "
         "(ratio_vs_embree; below 1 is faster than Embree). Ranking: geometric mean over the workload's cells "
         "(scenes) with a 95 % t-interval of the mean of the log ratios, n the number of cells. Winners: the "
         "lowest ratio per cell; \"survey\" leaves out " + ", ".join(SURVEY_EXCLUDED) + "; a tie is a winner whose "
         "min-max ratio range overlaps the runner-up's.")


NO_RATIO = "No cell has a ratio to Embree: ratio_vs_embree is empty in every row."


def markdown(f):
    out = ["## Findings", "", INTRO, ""]
    if not f["workloads"]:
        return "\n".join(out + [NO_RATIO, ""])
    for w in f["workloads"]:
        out += [f"### Ranking: {w}", "", "| rank | configuration | ratio (geomean) | 95 % interval | n cells |",
                "|---:|---|---:|---|---:|"]
        for i, e in enumerate(f["ranking"][w], 1):
            out.append(f"| {i} | {e['label']} | {number(e['gm'])} | {interval_text(e)} | {e['n']} |")
        out.append("")
    out += ["### Winners per scene and workload", "", "| scene | workload | fastest | fastest of the survey |",
            "|---|---|---|---|"]
    for (s, w), p in f["winners"].items():
        out.append(f"| {s} | {w} | {winner_text(p['all'])} | {winner_text(p['survey'])} |")
    out += ["", "### Per family", ""]
    out += [f"- {family_sentence(x)}" for x in f["families"]]
    out.append("")
    return "\n".join(out)


def html(f, esc):
    """The findings section of the report; esc escapes text for HTML."""
    out = ['<section id="findings"><h2>Findings</h2>', f'<p class="note">{esc(INTRO)}</p>']
    if not f["workloads"]:
        return "\n".join(out + [f"<p>{esc(NO_RATIO)}</p></section>"])
    out.append('<div class="ranks">')
    for w in f["workloads"]:
        out.append(f"<div><h3>Ranking: {esc(w)}</h3>")
        out.append(f'<div class="scroll" tabindex="0" role="region" aria-label="ranking of {esc(w)}">'
                   f'<table class="rank" data-workload="{esc(w)}"><thead><tr><th>rank</th><th class="t">configuration'
                   '</th><th>ratio (geomean)</th><th>95 % interval</th><th>n cells</th></tr></thead><tbody>')
        for i, e in enumerate(f["ranking"][w], 1):
            out.append(f'<tr data-label="{esc(e["label"])}" data-gm="{e["gm"]!r}" data-n="{e["n"]}"><td>{i}</td>'
                       f'<td class="t">{esc(e["label"])}</td><td class="gm">{number(e["gm"])}</td>'
                       f'<td>{esc(interval_text(e))}</td><td class="n">{e["n"]}</td></tr>')
        out.append("</tbody></table></div></div>")
    out.append("</div>")
    out.append("<h3>Winners per scene and workload</h3>")
    out.append('<p class="note">Each cell: the fastest configuration and its ratio; below it, the fastest of the '
               "survey's structures. <b>tie</b>: the winner's min-max range overlaps the runner-up's.</p>")
    out.append('<div class="scroll" tabindex="0" role="region" aria-label="winners map"><table id="winners"><thead>'
               '<tr><th class="t">scene</th>' + "".join(f'<th class="t">{esc(w)}</th>' for w in f["workloads"])
               + "</tr></thead><tbody>")
    for s in f["scenes"]:
        tds = []
        for w in f["workloads"]:
            p = f["winners"].get((s, w))
            if not p:
                tds.append('<td class="t"></td>')
                continue
            tie = ' data-tie="1"' if p["all"]["tie"] else ""
            tds.append(f'<td class="t"{tie}>{esc(winner_text(p["all"]))}<br><span class="note">survey: '
                       f'{esc(winner_text(p["survey"]))}</span></td>')
        out.append(f'<tr><td class="t">{esc(s)}</td>' + "".join(tds) + "</tr>")
    out.append("</tbody></table></div>")
    out.append("<h3>Per family</h3>")
    out.append('<ul class="sent">' + "".join(f"<li>{esc(family_sentence(x))}</li>" for x in f["families"]) + "</ul>")
    out.append("</section>")
    return "\n".join(out)


# ------------------------------------------------------------------ parameters in columns

def params_table(rows, labels, config_key, split_params, defaults):
    """The rows of params.csv: one per (configuration, parameter): label, accel, threads, params, key, value, and
    whether it is the default (yes, no, or empty when the defaults are unknown)."""
    out = []
    for key in dict.fromkeys(config_key(r) for r in rows):
        accel, params, threads = key
        d = defaults.get(accel)
        for kv in split_params(params):
            k, _, v = kv.partition("=")
            isdef = "" if d is None else ("yes" if d.get(k) == v else "no")
            out.append({"label": labels[key], "accel": accel, "threads": threads, "params": params,
                        "key": k, "value": v, "default": isdef})
    return out


PARAMS_COLUMNS = ("label", "accel", "threads", "params", "key", "value", "default")


def write_params_csv(path, table):
    import csv
    import os
    tmp = path + ".tmp"
    with open(tmp, "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, PARAMS_COLUMNS)
        w.writeheader()
        w.writerows(table)
    os.replace(tmp, path)


# ------------------------------------------------------------------ sweeps

def sweeps(rows, config_key, split_params):
    """Instances of one accelerator (and thread count) that differ in one parameter only:
    [(accel, key, [(value, config)] in the file's order)], one entry per group of the other parameters."""
    by_accel = {}
    for c in dict.fromkeys(config_key(r) for r in rows):
        if c[0] != "embree":
            by_accel.setdefault((c[0], c[2]), []).append(c)
    out = []
    for (accel, _), cfgs in by_accel.items():
        if len(cfgs) < 2:
            continue
        parsed = {c: dict(kv.partition("=")[::2] for kv in split_params(c[1])) for c in cfgs}
        keys = list(dict.fromkeys(k for p in parsed.values() for k in p))
        for k in keys:
            groups = {}
            for c, p in parsed.items():
                if k not in p:
                    continue
                rest = tuple(sorted((kk, vv) for kk, vv in p.items() if kk != k))
                groups.setdefault(rest, []).append((p[k], c))
            for members in groups.values():
                if len({v for v, _ in members}) >= 2:
                    out.append((accel, k, members))
    return out
