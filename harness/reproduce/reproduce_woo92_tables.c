/* reproduce_woo92_tables.c: the report of `reproduce woo92`: Woo's Tables
 * 1-4 and the ablation in the paper's shapes with OUR numbers, Woo's
 * figures (data/woo92_figures.csv) beside them, and a "finding:" line
 * wherever ours differ from his (markdown.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "markdown.h"
#include "reproduce_woo92.h"

/* ------------------------------------------------------------ numbers */

static double tests(const meas *m) { return rp_tests(m); }
static double boxes(const meas *m) { return rp_boxes(m); }
/* Percent of a saved by b (positive: b is faster / smaller). */
static double saved(double a, double b) { return a > 0 ? 100.0 * (a - b) / a : 0.0; }
static double noise2(const meas *a, const meas *b) { return rp_noise2(a, b); }
/* Percent of a's time saved by b, through their Embree-paired ratios (rp_relative), so a machine that
 * slows between the two measurements does not tilt it. */
static double saved_paired(const meas *a, const meas *b) { return 100.0 * (1.0 - rp_relative(b, a)); }

static double spread_of(const double *v, int n)
{
    double lo = v[0], hi = v[0];
    for (int i = 1; i < n; i++) lo = fmin(lo, v[i]), hi = fmax(hi, v[i]);
    return hi > 0 ? 100.0 * (hi - lo) / hi : 0.0;
}

static int argmin(const double *v, int n)
{
    int b = 0;
    for (int i = 1; i < n; i++)
        if (v[i] < v[b]) b = i;
    return b;
}

static double min_of(const double *v, int n) { return v[argmin(v, n)]; }

static double max_of(const double *v, int n)
{
    double m = v[0];
    for (int i = 1; i < n; i++) m = fmax(m, v[i]);
    return m;
}

static const char *mmss(double s, char *buf, size_t len)
{
    snprintf(buf, len, "%d:%02d", (int)s / 60, (int)s % 60);
    return buf;
}

/* v[0..n) as "a / b / c", each with fmt (one double), or as m:ss. */
static const char *join(const double *v, int n, const char *fmt, char *buf, size_t len)
{
    size_t k = 0;
    buf[0] = 0;
    for (int i = 0; i < n && k < len; i++) {
        char one[32];
        if (fmt) snprintf(one, sizeof one, fmt, v[i]);
        else mmss(v[i], one, sizeof one);
        k += (size_t)snprintf(buf + k, len - k, "%s%s", i ? " / " : "", one);
    }
    return buf;
}

/* The percent saved from a[i] to b[i], i < n. */
static void saved_each(const double *a, const double *b, int n, double *out)
{
    for (int i = 0; i < n; i++) out[i] = saved(a[i], b[i]);
}

/* "saves 12.3%" or "costs 4.5% more time" for a percent saved. */
static const char *effect(double pct_saved, char *buf, size_t len)
{
    if (pct_saved >= 0) snprintf(buf, len, "saves %.1f%%", pct_saved);
    else snprintf(buf, len, "costs %.1f%% more time", -pct_saved);
    return buf;
}

/* The product of the sides of "AxBxC". */
static long cells_of(const char *res)
{
    long n = 1;
    for (const char *p = res; *p;) {
        char *end;
        n *= strtol(p, &end, 10);
        if (*end != 'x') break;
        p = end + 1;
    }
    return n;
}

/* ------------------------------------------------------------ tables */

/* What Tables 2-4 and the ablation trace: "640x480 primary + mirror
 * reflection to depth 3". */
static const char *image_rays(const woo_run *r, char *buf, size_t len)
{
    snprintf(buf, len, "%dx%d primary + mirror reflection to depth %d", r->cf.img_w, r->cf.img_h, r->woo.depth);
    return buf;
}

static void print_header(woo_run *r, FILE *f)
{
    const rp_config *c = &r->cf;
    const woo_figures *w = &r->woo;
    char paths[64];
    rp_timed_paths(&r->k, paths, sizeof paths);
    md_heading(f, 1, "Woo 1992 reproduced: accelbench reproduce woo92");
    md_para(f, "A. Woo, \"Ray Tracing Polygons using Spatial Subdivision\", Graphics Interface 1992: Tables 1-4 "
                   "(sections 8-9) and an ablation of sections 4-7, re-run on our scenes. Every number is OURS; Woo's are "
                   "quoted from data/woo92_figures.csv beside each table and in the finding lines.");
    md_bullet(f, 0, "machine: %s, %s; accelbench %s; %s", r->k.mi.host, r->k.mi.cpu, r->k.mi.git_rev, r->k.mi.date);
    md_bullet(f, 0, "threads: every timed trace runs on **1 thread** (grid-raybox reorders its shared candidate lists, "
                        "ACCEL_MUTATES, so it must; every other variant and Embree run on 1 thread too, for fairness). "
                        "Untimed work (ray sets, Embree's reference answers): %d thread%s.",
                  r->k.o.threads, r->k.o.threads == 1 ? "" : "s");
    md_bullet(f, 0, "repeats: %d timed sample%s after 1 warm-up trace, median reported%s; each sample is paired with "
                        "one of Embree's on the same rays, in alternating order (the CSV's ratio_vs_embree and its "
                        "spread). The warm-up's answers are verified against Embree and give the counters (tests/ray = "
                        "primitive tests per ray, box tests/ray = grid clip + voxel-box + ray-box crossing + bounds tests "
                        "per ray). Timed path: %s.",
                  r->k.o.repeat, r->k.o.repeat == 1 ? "" : "s", r->k.o.repeat == 1 ? " (1 repeat: no noise estimate)" : "",
                  paths[0] ? paths : "none");
    md_bullet(f, 0, "ratios: every comparison of two of our measurements (%% saved, raw / ray box, spreads, the "
                        "fastest grid) goes through their Embree-paired ratios, (A / Embree) / (B / Embree), so a machine "
                        "that slows down between two measurements does not tilt it; the ms columns are raw medians.");
    md_bullet(f, 0, "noise: \"within noise\" in the findings means within the larger min-max spread of the two "
                        "measurements' repeats, and at least 1%%. Run-to-run variation (another process, a shared VM) can "
                        "be larger: read differences of a few percent as ties.");
    md_bullet(f, 0, "mode: %s",
                  r->k.o.quick ? "**--quick**: small images and 1 repeat; for testing the command, not for reading" : "default");
    md_bullet(f, 0, "time: ms of wall clock to trace the image's ray sets, no shading (Woo: CPU minutes of a whole "
                        "render on a %s). Tables 2-4 and the ablation trace the %dx%d primary rays plus the `reflection` "
                        "workload (mirror bounces of every hit, depth %d): an image's time is the sum of the two. Memory: "
                        "bytes of the grid (Woo's Table 4: the whole program).",
                  w->img_machine, c->img_w, c->img_h, w->depth);
    md_bullet(f, 0, "variants (all `grid-raybox`): **old** = raybox=on with every Woo switch off (Snyder-Barr alone), "
                        "res=auto (Woo s8.2); **new** = grid-raybox defaults (woo90, mtf=almost, dynbox, voxbox, beta=0.75, "
                        "tclip; eyeorigin and rayid are off by default); **tri** = old + tclip=on + eyeorigin=on (Woo s7). "
                        "Table 1's raw traversal is `grid` (3DDDA with mailboxes).");
    md_bullet(f, 0, "scenes:");
    for (int i = 0; i < SC_N; i++) {
        const scene_def *d = &woo92_scenes[i];
        char his[128];
        if (i == SC_FLAKE) snprintf(his, sizeof his, "his Table 1: %d spheres", w->t1_spheres);
        else snprintf(his, sizeof his, "his Table 2: %.0f triangles, grid %s", w->t2_tris[i - 1], w->t2_grid[i - 1]);
        if (r->k.standin_reason[i][0])
            md_bullet(f, 1, "%s = Woo's %s (%s): **STAND-IN** for %s, which is not on this machine (%s). %s", r->k.label[i],
                          d->image, his, d->load, r->k.standin_reason[i], d->standin_why);
        else md_bullet(f, 1, "%s = Woo's %s (%s): %s", r->k.label[i], d->image, his, d->why);
    }
    md_end(f);
}

static void table1(woo_run *r, FILE *f)
{
    const rp_config *c = &r->cf;
    const woo_figures *w = &r->woo;
    md_section(f, "Table 1: Ray Box vs. Voxel Traversal",
                   "%s, primary rays only, %dx%d, one sample per pixel. Ray Box = grid-raybox with only raybox=on "
                   "(plain Snyder-Barr); Raw Traversal = grid.",
                   r->k.shown[SC_FLAKE], c->t1_w, c->t1_h);
    md_table(f, "#Sphere:|Grid Res|Image Res|Ray Box ms:|Ray Box tests/ray:|Ray Box box tests/ray:|Raw Traversal ms:|"
                    "Raw tests/ray:|Raw / Ray Box:|real mismatches:");
    double rb[4], raw[4], ratio[4], woo_ratio[4], cut = 0, box = 0;
    for (int i = 0; i < 4; i++) {
        const meas *a = r->t1_raybox[i], *b = r->t1_raw[i];
        rb[i] = rp_vs_embree(a), raw[i] = rp_vs_embree(b), ratio[i] = rp_relative(b, a);
        woo_ratio[i] = w->t1_raw[i] / w->t1_raybox[i];
        cut += saved(tests(b), tests(a)) / 4, box += boxes(a) / 4;
        md_row(f, "%u|%s|%dx%d|%.1f|%.2f|%.2f|%.1f|%.2f|%.2f|%llu / %llu", a->rows[0].prims, a->res_str, c->t1_w,
                   c->t1_h, a->ms, tests(a), boxes(a), b->ms, tests(b), ratio[i], (unsigned long long)a->mm[MM_REAL],
                   (unsigned long long)b->mm[MM_REAL]);
    }
    md_end(f);
    char j1[96], j2[96], j3[96];
    md_para(f, "Woo (%s, CPU minutes): ray box %s, raw %s at %d^3..%d^3 (raw / ray box %s).", w->t1_machine,
                join(w->t1_raybox, 4, "%.0f", j1, sizeof j1), join(w->t1_raw, 4, "%.0f", j2, sizeof j2), w->t1_res[0],
                w->t1_res[3], join(woo_ratio, 4, "%.2f", j3, sizeof j3));
    int wins = 0;
    double rmin = ratio[0], rmax = ratio[0];
    char faster_rb[128] = "", faster_raw[128] = "";
    for (int i = 0; i < 4; i++) {
        rmin = fmin(rmin, ratio[i]), rmax = fmax(rmax, ratio[i]);
        char *dst = rb[i] < raw[i] ? faster_rb : faster_raw;
        size_t n = strlen(dst);
        snprintf(dst + n, 128 - n, "%s%d^3", n ? ", " : "", w->t1_res[i]);
        if (rb[i] < raw[i]) wins++;
    }
    double woo_lo = min_of(woo_ratio, 4), woo_hi = max_of(woo_ratio, 4);
    if (wins == 4)
        md_finding(f, "ray boxes beat raw traversal at every resolution, raw / ray box = %.2f..%.2f (Woo: %.2f..%.2f): %s.",
                       rmin, rmax, woo_lo, woo_hi,
                       rmax < woo_lo ? "a SMALLER margin than Woo's" : rmin > woo_hi ? "a LARGER margin than Woo's"
                                                                              : "overlapping Woo's range");
    else if (wins == 0)
        md_finding(f, "raw traversal BEATS ray boxes at every resolution (raw / ray box = %.2f..%.2f), unlike Woo, "
                          "where ray boxes were %.2f..%.2fx faster.",
                       rmin, rmax, woo_lo, woo_hi);
    else
        md_finding(f, "mixed, unlike Woo (ray boxes faster everywhere, %.2f..%.2fx): ray boxes faster at %s, raw "
                          "traversal faster at %s (raw / ray box = %.2f..%.2f).",
                       woo_lo, woo_hi, faster_rb, faster_raw, rmin, rmax);
    double s_rb = spread_of(rb, 4), s_raw = spread_of(raw, 4);
    double w_rb = spread_of(w->t1_raybox, 4), w_raw = spread_of(w->t1_raw, 4);
    md_finding(f, "from %d^3 to %d^3 the time varies by %.0f%% with ray boxes and %.0f%% raw (Woo: %.0f%% and %.0f%%): "
                      "ray boxes are %s sensitive to the grid resolution than raw traversal, %s. Fastest: ray box at %d^3, "
                      "raw at %d^3 (Woo: ray box at %d^3, raw at %d^3).",
                   w->t1_res[0], w->t1_res[3], s_rb, s_raw, w_rb, w_raw, s_rb < s_raw ? "less" : "MORE",
                   s_rb < s_raw ? "as Woo found" : "unlike Woo", w->t1_res[argmin(rb, 4)], w->t1_res[argmin(raw, 4)],
                   w->t1_res[argmin(w->t1_raybox, 4)], w->t1_res[argmin(w->t1_raw, 4)]);
    md_finding(f, "the ray box removes %.0f%% of the primitive tests per ray (mean over the four grids) at a cost of "
                      "%.1f box tests per ray.",
                   cut, box);
}

static void table2(woo_run *r, FILE *f)
{
    const woo_figures *w = &r->woo;
    char rays[96];
    md_section(f, "Table 2: General Optimization Benchmarks",
                   "%s, one sample per pixel. Old = Snyder-Barr alone at the s8.2 auto resolution; New = all of Woo's "
                   "switches (grid-raybox defaults). %%Intersect = primitive tests saved by New.",
                   image_rays(r, rays, sizeof rays));
    md_table(f, "Image|Scene|#Prims:|Grid Res|%Intersect saved:|Old Time ms:|New Time ms:|% time saved:|rays:|"
                    "real mismatches old / new:");
    for (int i = 0; i < 3; i++) {
        const meas *o = r->t2_old[i], *n = r->t2_new[i];
        md_row(f, "%s|%s|%u|%s|%.1f%%|%.1f|%.1f|%.1f%%|%llu|%llu / %llu", woo92_scenes[i + 1].image, r->k.shown[i + 1],
                   o->rows[0].prims, o->res_str, saved((double)o->c.prim_tests, (double)n->c.prim_tests), o->ms, n->ms,
                   saved_paired(o, n), (unsigned long long)o->rays, (unsigned long long)o->mm[MM_REAL],
                   (unsigned long long)n->mm[MM_REAL]);
    }
    md_end(f);
    double woo_saved[3];
    saved_each(w->t2_old, w->t2_new, 3, woo_saved);
    char line[1024] = "", b[2][16];
    for (int i = 0; i < 3; i++) {
        size_t n = strlen(line);
        snprintf(line + n, sizeof line - n, "%s%s %.0f tri %s %.1f%% %s -> %s", i ? "; " : "", woo92_scenes[i + 1].image,
                 w->t2_tris[i], w->t2_grid[i], w->t2_isect[i], mmss(w->t2_old[i], b[0], sizeof b[0]),
                 mmss(w->t2_new[i], b[1], sizeof b[1]));
    }
    char j1[96];
    md_para(f, "Woo (%s): %s (%s%% time saved; his summary: \"about %g-%g%%\").", w->img_machine, line,
                join(woo_saved, 3, "%.1f", j1, sizeof j1), w->improve_lo, w->improve_hi);
    double lo = 1e9, hi = -1e9;
    for (int i = 0; i < 3; i++) {
        const meas *o = r->t2_old[i], *n = r->t2_new[i];
        double s = round(10.0 * saved_paired(o, n)) / 10.0, nz = noise2(o, n), is = saved((double)o->c.prim_tests, (double)n->c.prim_tests);
        lo = fmin(lo, s), hi = fmax(hi, s);
        char where[64];
        if (s < 0) snprintf(where, sizeof where, "new is SLOWER than old, unlike Woo");
        else snprintf(where, sizeof where, "%s Woo's %g-%g%%", s < w->improve_lo ? "BELOW" : s <= w->improve_hi ? "within" : "ABOVE",
                      w->improve_lo, w->improve_hi);
        md_finding(f, "%s (%s): new saves %.1f%% of old's time (Woo's %s: %.1f%%): %s%s; it saves %.1f%% of the "
                          "intersection tests (Woo: %.1f%%).",
                       woo92_scenes[i + 1].image, r->k.shown[i + 1], s, woo92_scenes[i + 1].image, woo_saved[i], where,
                       fabs(s) <= nz ? "; the difference is within this run's timing noise" : "", is, w->t2_isect[i]);
    }
    md_finding(f, "over the three images new saves %.1f..%.1f%% of the time (Woo: %.1f..%.1f%%, \"about %g-%g%%\").", lo,
                   hi, min_of(woo_saved, 3), max_of(woo_saved, 3), w->improve_lo,
                   w->improve_hi);
    /* Woo's s9 flop count puts the [Woo90] box check inside his triangle
     * test, so his Old likely had it already; ours skips the primitive test
     * in the grid (a box test, not an intersection), inflating %Intersect. */
    char ours[512] = "";
    for (int i = 0; i < 3; i++) {
        const meas *m = r->abl[i][1], *n = r->t2_new[i];
        char e[48];
        size_t k = strlen(ours);
        snprintf(ours + k, sizeof ours - k, "%s %s: %s, %.1f%% of the intersection tests saved", i ? ";" : "",
                 woo92_scenes[i + 1].image, effect(saved_paired(m, n), e, sizeof e),
                 saved((double)m->c.prim_tests, (double)n->c.prim_tests));
    }
    char j2[96], j3[96];
    md_finding(f, "measured from old+woo90 instead (the ablation's second row: Woo's s9 flop count has the [Woo90] "
                      "check inside his triangle test, so his Old probably had it, and his intersection count includes the "
                      "polygons it rejects; ours skips them before the test), new vs old+woo90:%s (Woo: %s%% and %s%%).",
                   ours, join(woo_saved, 3, "%.1f", j2, sizeof j2), join(w->t2_isect, 3, "%.1f", j3, sizeof j3));
}

static void table3(woo_run *r, FILE *f)
{
    const woo_figures *w = &r->woo;
    char rays[96];
    md_section(f, "Table 3: Lamp Image with Levels of Anti-Aliasing",
                   "%s (Woo's lamp), %s, %d / %d / %d stratified samples per pixel (Woo: adaptive sampling, rows %s / %s / "
                   "%s; ours traces every sample). Tri = old + tclip + eyeorigin (Woo s7 alone); New = all switches.",
                   r->k.shown[SC_LAMP], image_rays(r, rays, sizeof rays), w->spp[0], w->spp[1], w->spp[2], w->t3_rows[0],
                   w->t3_rows[1], w->t3_rows[2]);
    md_table(f, "Sampling|Old Time ms:|Tri Time ms:|%Improve:|New Time ms:|%Improve:|rays:|real mismatches old / tri / new:");
    double ti[3], ni[3];
    bool tri_noise = true;
    for (int i = 0; i < 3; i++) {
        const meas *o = r->t3_old[i], *t = r->t3_tri[i], *n = r->t3_new[i];
        int side = (int)ceil(sqrt((double)w->spp[i]));
        ti[i] = saved_paired(o, t), ni[i] = saved_paired(o, n);
        if (fabs(ti[i]) > noise2(o, t)) tri_noise = false;
        md_row(f, "%dx%d|%.1f|%.1f|%.1f%%|%.1f|%.1f%%|%llu|%llu / %llu / %llu", side, side, o->ms, t->ms, ti[i], n->ms,
                   ni[i], (unsigned long long)o->rays, (unsigned long long)o->mm[MM_REAL],
                   (unsigned long long)t->mm[MM_REAL], (unsigned long long)n->mm[MM_REAL]);
    }
    md_end(f);
    char j[5][96];
    md_para(f, "Woo (lamp, %s / %s / %s): old %s, tri %s, new %s; %%Improve as printed: tri %s%%, new %s%%.",
                w->t3_rows[0], w->t3_rows[1], w->t3_rows[2], join(w->t3_old, 3, NULL, j[0], sizeof j[0]),
                join(w->t3_tri, 3, NULL, j[1], sizeof j[1]), join(w->t3_new, 3, NULL, j[2], sizeof j[2]),
                join(w->t3_tri_improve, 3, "%.1f", j[3], sizeof j[3]), join(w->t3_new_improve, 3, "%.1f", j[4], sizeof j[4]));
    bool tri_all_neg = ti[0] < 0 && ti[1] < 0 && ti[2] < 0, tri_all_pos = ti[0] > 0 && ti[1] > 0 && ti[2] > 0;
    md_finding(f, "tri (s7 alone) changes old's time by %.1f%% / %.1f%% / %.1f%% saved (Woo: %s%%): %s%s.", ti[0], ti[1],
                   ti[2], j[3],
                   tri_all_neg   ? "tri is SLOWER than old at every sampling rate, unlike Woo"
                   : tri_all_pos ? "a small gain at every rate, as Woo found"
                                 : "mixed signs, unlike Woo's small steady gain",
                   tri_noise ? " (every difference is within this run's timing noise)" : "");
    bool rises = ni[1] > ni[0] && ni[2] > ni[1], falls = ni[1] < ni[0] && ni[2] < ni[1];
    md_finding(f, "new saves %.1f%% / %.1f%% / %.1f%% at %d / %d / %d spp (Woo: %s%%): the gain %s with sampling, %s "
                      "Woo's claim that the coherence optimisations (s5-6) pay more with more samples per pixel.",
                   ni[0], ni[1], ni[2], w->spp[0], w->spp[1], w->spp[2], j[4],
                   rises ? "rises" : falls ? "FALLS" : "does not rise steadily", rises ? "supporting" : "NOT supporting");
}

static void table4(woo_run *r, FILE *f)
{
    const woo_figures *w = &r->woo;
    char rays[96];
    md_section(f, "Table 4: Sphere Image with different Subdivision",
                   "%s (Woo's spheres), new (all switches), %s. Space = bytes of the grid (cells, candidate lists, voxel "
                   "boxes; Woo: the whole program).",
                   r->k.shown[SC_SPHERES], image_rays(r, rays, sizeof rays));
    md_table(f, "Grid Res|Time ms:|Space Usage bytes:|tests/ray:|box tests/ray:|real mismatches:");
    double t[4], mem[4];
    for (int i = 0; i < 4; i++) {
        const meas *m = r->t4[i];
        t[i] = rp_vs_embree(m), mem[i] = (double)m->mem;
        md_row(f, "%s%s|%.1f|%llu|%.2f|%.2f|%llu", m->res_str, i == 0 ? " (auto)" : "", m->ms, (unsigned long long)m->mem,
                   tests(m), boxes(m), (unsigned long long)m->mm[MM_REAL]);
    }
    md_end(f);
    char line[512] = "", b[16];
    for (int i = 0; i < 4; i++) {
        size_t n = strlen(line);
        snprintf(line + n, sizeof line - n, "%s%s%s %s %.0f bytes", i ? "; " : "", w->t4_rows[i], i == 0 ? " (auto)" : "",
                 mmss(w->t4_time[i], b, sizeof b), w->t4_space[i]);
    }
    md_para(f, "Woo: %s.", line);
    int best = argmin(t, 4), woo_best = argmin(w->t4_time, 4);
    const char *names[4];
    char lab[3][16];
    names[0] = "auto";
    for (int i = 0; i < 3; i++) snprintf(lab[i], sizeof lab[i], "%d^3", w->t4_res[i]), names[i + 1] = lab[i];
    const int *ar = r->t4[0]->res;
    md_finding(f, "the fastest grid is %s (%s)%s; the s8.2 auto grid (%s, %d cells) is %.1f%% slower than the fastest. "
                      "Woo: the fastest was %s (%s, %ld cells) and %s only %.1f%% slower than auto.",
                   names[best], r->t4[best]->res_str, best == woo_best ? ", as in Woo" : ", unlike Woo", r->t4[0]->res_str,
                   ar[0] * ar[1] * ar[2], t[best] > 0 ? 100.0 * (t[0] - t[best]) / t[best] : 0.0, names[woo_best],
                   w->t4_rows[woo_best], cells_of(w->t4_rows[woo_best]), names[3],
                   100.0 * (w->t4_time[3] - w->t4_time[0]) / w->t4_time[0]);
    if (ar[0] == 1 || ar[1] == 1 || ar[2] == 1)
        md_finding(f, "the auto grid has ONE cell along an axis: s8.2 sizes the grid by the bounding box, which the "
                          "large floor makes flat, so all the spheres share one layer of cells.");
    md_finding(f, "time varies by %.0f%% across the four grids (Woo: %.0f%%), grid memory grows %.1fx from auto to %d^3 "
                      "(Woo, whole program: %.2fx).",
                   spread_of(t, 4), spread_of(w->t4_time, 4), mem[0] > 0 ? mem[3] / mem[0] : 0.0, w->t4_res[2],
                   w->t4_space[3] / w->t4_space[0]);
}

/* One image's ablation table; its per-step time saved into delta[]. */
static void ablation_image(woo_run *r, FILE *f, int si, double *delta)
{
    const woo_figures *w = &r->woo;
    md_heading(f, 3, "%s (%s, grid %s)", woo92_scenes[si + 1].image, r->k.shown[si + 1], r->abl[si][0]->res_str);
    md_table(f, "Step|Time ms:|tests/ray:|box tests/ray:|% vs old:|% vs prev:|real mismatches:");
    for (int k = 0; k < ABL_N; k++) {
        const meas *m = r->abl[si][k], *o = r->abl[si][0], *p = r->abl[si][k ? k - 1 : 0];
        delta[k] = k ? saved_paired(p, m) : 0.0;
        char dp[32] = "";
        if (k) snprintf(dp, sizeof dp, "%.1f%%", delta[k]);
        md_row(f, "%s%s|%.1f|%.2f|%.2f|%.1f%%|%s|%llu", woo92_abl_steps[k].name, r->abl_is_new[k] ? " (= new)" : "",
                   m->ms, tests(m), boxes(m), saved_paired(o, m), dp, (unsigned long long)m->mm[MM_REAL]);
    }
    md_end(f);
    int best = 1, worst = 1;
    for (int k = 1; k < ABL_N; k++) {
        if (delta[k] > delta[best]) best = k;
        if (delta[k] < delta[worst]) worst = k;
    }
    char slower[256] = "";
    for (int k = 1; k < ABL_N; k++) {
        const meas *m = r->abl[si][k], *p = r->abl[si][k - 1];
        if (-delta[k] > noise2(m, p)) {
            size_t n = strlen(slower);
            snprintf(slower + n, sizeof slower - n, "%s%s (+%.1f%% time)", n ? ", " : "", woo92_abl_steps[k].name, -delta[k]);
        }
    }
    int inew = 0;
    for (int k = 0; k < ABL_N; k++)
        if (r->abl_is_new[k]) inew = k;
    char e1[48], e2[48], e3[48], e4[48], e5[48];
    md_finding(f, "%s: old -> new %s (Woo: saves %.1f%%); the largest single gain is %s (%s), the largest loss %s (%s); "
                      "switches that make it slower than the row above beyond noise: %s. rayid=twopass (Woo removed it as "
                      "no help): %s; eyeorigin: %s.",
                   woo92_scenes[si + 1].image, effect(saved_paired(r->abl[si][0], r->abl[si][inew]), e1, sizeof e1),
                   saved(w->t2_old[si], w->t2_new[si]), woo92_abl_steps[best].name, effect(delta[best], e2, sizeof e2),
                   delta[worst] < 0 ? woo92_abl_steps[worst].name : "none",
                   delta[worst] < 0 ? effect(delta[worst], e3, sizeof e3) : "no step costs time", slower[0] ? slower : "none",
                   effect(delta[ABL_N - 1], e4, sizeof e4), effect(delta[ABL_N - 2], e5, sizeof e5));
}

static void ablation(woo_run *r, FILE *f)
{
    char rays[96];
    md_section(f, "Ablation: Woo's switches added one at a time",
                   "Start from old (Snyder-Barr alone, res=auto) and add one switch at a time in Woo's order; each row keeps "
                   "the switches above it. %s, one sample. %% vs old: time saved relative to old; %% vs prev: time saved "
                   "by this row's switch.",
                   image_rays(r, rays, sizeof rays));
    double delta[3][ABL_N];
    for (int si = 0; si < 3; si++) ablation_image(r, f, si, delta[si]);
    char helps[512] = "", hurts[512] = "";
    for (int k = 1; k < ABL_N; k++) {
        bool all_pos = true, all_neg = true;
        for (int si = 0; si < 3; si++) {
            const meas *m = r->abl[si][k], *p = r->abl[si][k - 1];
            double nz = noise2(m, p);
            if (!(delta[si][k] > nz)) all_pos = false;
            if (!(-delta[si][k] > nz)) all_neg = false;
        }
        char *dst = all_pos ? helps : all_neg ? hurts : NULL;
        if (!dst) continue;
        size_t n = strlen(dst);
        snprintf(dst + n, 512 - n, "%s%s", n ? ", " : "", woo92_abl_steps[k].name);
    }
    md_finding(f, "switches that save time beyond noise on all three images: %s; that cost time on all three: %s.",
                   helps[0] ? helps : "none", hurts[0] ? hurts : "none");
}

static void verification(woo_run *r, FILE *f)
{
    meas *flat[3 * ABL_N];
    for (int si = 0; si < 3; si++)
        for (int k = 0; k < ABL_N; k++) flat[si * ABL_N + k] = r->abl[si][k];
    meas *t1[8], *t2[6], *t3[9];
    for (int i = 0; i < 4; i++) t1[2 * i] = r->t1_raybox[i], t1[2 * i + 1] = r->t1_raw[i];
    for (int i = 0; i < 3; i++) t2[2 * i] = r->t2_old[i], t2[2 * i + 1] = r->t2_new[i];
    for (int i = 0; i < 3; i++) t3[3 * i] = r->t3_old[i], t3[3 * i + 1] = r->t3_tri[i], t3[3 * i + 2] = r->t3_new[i];
    const rp_group groups[] = {{"Table 1", t1, 8}, {"Table 2", t2, 6}, {"Table 3", t3, 9}, {"Table 4", r->t4, 4},
                               {"Ablation", flat, 3 * ABL_N}};
    rp_verification(&r->k, f, groups, (int)(sizeof groups / sizeof groups[0]));
}

void woo92_report(void *ctx, FILE *f)
{
    woo_run *r = ctx;
    print_header(r, f);
    table1(r, f);
    table2(r, f);
    table3(r, f);
    table4(r, f);
    ablation(r, f);
    verification(r, f);
}
