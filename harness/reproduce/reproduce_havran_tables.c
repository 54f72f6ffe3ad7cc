/* reproduce_havran_tables.c: the report of `reproduce havran`: Havran and
 * Sixta's grid table and Havran's octree tables (RTN 12(1), 12(2)) in their
 * shapes, with OUR numbers as ratios between techniques on the same scene
 * next to the same ratios of theirs (data/havran_figures.csv), a cross
 * comparison of every technique against the D = 20 grid, our BSPs, and a
 * "finding:" line wherever our ordering differs from theirs (markdown.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "markdown.h"
#include "reproduce_havran.h"

/* ------------------------------------------------------------ numbers */

static double ratio(double a, double b) { return b > 0 ? a / b : NAN; }

/* Is a slower than b beyond the noise of the two (a's time over b's minus
 * one, in percent, above the larger spread)? */
static bool slower(const meas *a, const meas *b) { return 100.0 * (rp_relative(a, b) - 1.0) > rp_noise2(a, b); }

static int argmin_meas(meas *const *m, int n)
{
    int b = 0;
    for (int i = 1; i < n; i++)
        if (rp_vs_embree(m[i]) < rp_vs_embree(m[b])) b = i;
    return b;
}

static int argmin(const double *v, int n)
{
    int b = 0;
    for (int i = 1; i < n; i++)
        if (v[i] < v[b]) b = i;
    return b;
}

/* Every measured scene (--scenes may leave some out). */
#define FOR_SCENE(r, i) \
    for (int i = 0; i < HV_SCENES; i++) \
        if ((r)->use[i])

static int measured_scenes(const havran_run *r)
{
    int n = 0;
    FOR_SCENE(r, i) n++;
    return n;
}

/* Append ", text" (or "text" to an empty list) to a fixed buffer. */
static void append(char *buf, size_t len, const char *text)
{
    size_t n = strlen(buf);
    if (n < len) snprintf(buf + n, len - n, "%s%s", n ? ", " : "", text);
}

/* ------------------------------------------------------------ header */

static void print_header(havran_run *r, FILE *f)
{
    const havran_figures *h = &r->hf;
    const rp_kit *k = &r->k;
    char paths[64];
    rp_timed_paths(k, paths, sizeof paths);
    md_heading(f, 1, "Havran 1999 reproduced: accelbench reproduce havran");
    md_para(f, "%s; %s. Their SPD experiments re-run on our structures: the uniform grid at two voxel densities, "
                   "Glassner's octree with centre (O84-C) and cost-based (O84-A) subdivision at maximum depths %d-%d, "
                   "and our BSPs. Every number is OURS; theirs are quoted from data/havran_figures.csv. Their seconds "
                   "(%s, a whole renderer) and our milliseconds (ray casting alone) are not comparable: the tables "
                   "compare RATIOS between techniques on the same scene, and orderings.",
                h->grid_source, h->oct_source, h->depth_min, h->depth_min + HV_DEPTHS - 1, h->grid_machine);
    md_bullet(f, 0, "machine: %s, %s; accelbench %s; %s", k->mi.host, k->mi.cpu, k->mi.git_rev, k->mi.date);
    md_bullet(f, 0, "threads: every timed trace (ours and Embree's paired ones) on %d thread%s; nothing here mutates "
                        "while tracing.",
                  k->timed_threads, k->timed_threads == 1 ? "" : "s");
    md_bullet(f, 0, "repeats: %d timed sample%s after 1 warm-up trace, median reported%s; the warm-up's answers are "
                        "verified against Embree and give the counters (tests/ray = primitive tests per ray, steps/ray = "
                        "voxels or nodes visited per ray). Timed path: %s.",
                  k->o.repeat, k->o.repeat == 1 ? "" : "s", k->o.repeat == 1 ? " (1 repeat: no noise estimate)" : "",
                  paths[0] ? paths : "none");
    md_bullet(f, 0, "ratios: every ratio between two of our measurements is the ratio of their Embree-paired ratios, "
                        "(A / Embree) / (B / Embree), each measurement's time over the Embree samples interleaved with it "
                        "on the same rays: these machines are shared, and a slowdown between two measurements would tilt a "
                        "ratio of raw times. The ms columns are raw medians, for scale only.");
    md_bullet(f, 0, "noise: \"beyond noise\" means by more than the larger min-max spread of the two measurements' "
                        "repeats, and at least 1%%. Read differences of a few percent as ties.");
    md_bullet(f, 0, "mode: %s",
                  k->o.quick ? "**--quick**: a small image and 1 repeat; for testing the command, not for reading" : "default");
    md_bullet(f, 0, "rays: %dx%d primary rays through pixel corners (their %dx%d), the `shadow` workload (every primary "
                        "hit to every light) and the `reflection` workload (mirror bounces of every hit, generations 1..%d); "
                        "an image's time is the sum of the three sets' medians. Their T_TR traces the SPD ray tree to depth "
                        "%d by the materials (reflection and refraction only where a surface has them): our reflection set "
                        "bounces every hit and refracts nothing, so secondary rays weigh more in ours.",
                  r->img_w, r->img_h, h->img_w, h->img_h, h->depth, h->depth);
    md_bullet(f, 0, "variants: **D1**, **D20** = `grid` res=cubic:%d, res=cubic:%d (cubic voxels, about D x N of them; "
                        "their grids listed candidates by bounding box, ours by exact overlap); **O84-C@d** = `octree` "
                        "maxdepth=d, maxprims=%d (a node of %d or more objects is subdivided, as theirs), term=const; "
                        "**O84-A@d** = the same with term=cost (MacDonald-Booth's cost stop with centre planes: their O84-A "
                        "searched 10 planes between the object and spatial medians, Octree-R, which our octree does not "
                        "do); **BSP-seq**, **BSP-rec** = `bsp` split=midpoint (Kaplan) traversed sequentially (Kaplan) and "
                        "recursively (Jansen); **BSP-SAH** = `bsp` split=sah.",
                  h->dens_low, h->dens_high, h->subdivide_at - 1, h->subdivide_at);
    md_bullet(f, 0, "scenes: the SPD databases at their default sizes, as theirs (their ninth scene, \"fluid\", is their "
                        "own and not public):");
    FOR_SCENE(r, i)
        md_bullet(f, 1, "%s: %s, %u primitives", k->shown[i], havran_scenes[i].why, r->d20[i]->rows[0].prims);
    md_end(f);
}

/* ------------------------------------------------------------ grids */

static void grids(havran_run *r, FILE *f)
{
    const havran_figures *h = &r->hf;
    md_section(f, "Grids: D = 1 against D = 20 (RTN 12(1))",
                   "Time ratio D1/D20 above 1: the dense grid is faster. Build ratio D20/D1: what the extra voxels cost to "
                   "build. Theirs: T_TR and T_B of their table.");
    md_table(f, "Scene|D1 res|D20 res|D1 ms:|D20 ms:|D1/D20:|theirs D1/D20:|tests/ray D1:|D20:|steps/ray D1:|D20:|"
                    "build D20/D1:|theirs:");
    FOR_SCENE(r, i) {
        const meas *a = r->d1[i], *b = r->d20[i];
        md_row(f, "%s|%s|%s|%.1f|%.1f|%.2f|%.2f|%.1f|%.1f|%.1f|%.1f|%.2f|%.2f", r->k.shown[i], a->res_str, b->res_str,
                   a->ms, b->ms, rp_relative(a, b), ratio(h->d1_trace[i], h->d20_trace[i]), rp_tests(a), rp_tests(b),
                   rp_steps(a), rp_steps(b), ratio(b->build_ms, a->build_ms), ratio(h->d20_build[i], h->d1_build[i]));
    }
    md_end(f);
    char not_beaten[512] = "", ties[512] = "";
    int wins = 0, theirs = 0;
    FOR_SCENE(r, i) {
        if (h->d20_trace[i] < h->d1_trace[i]) theirs++;
        if (slower(r->d1[i], r->d20[i])) wins++;
        else if (slower(r->d20[i], r->d1[i])) append(not_beaten, sizeof not_beaten, havran_scenes[i].image);
        else append(ties, sizeof ties, havran_scenes[i].image);
    }
    md_para(f, "D = 20 beats D = 1 beyond noise on %d of %d scenes (theirs: %d of them).", wins, measured_scenes(r),
                theirs);
    if (not_beaten[0])
        md_finding(f, "unlike theirs (\"D = 20 always outperforms D = 1\"), D = 1 is faster beyond noise on: %s.",
                       not_beaten);
    if (ties[0]) md_finding(f, "where they found D = 20 faster, ours are within noise of each other on: %s.", ties);
}

/* ------------------------------------------------------------ octrees */

static void octrees(havran_run *r, FILE *f)
{
    const havran_figures *h = &r->hf;
    md_section(f, "Octrees: O84-C against O84-A by maximum depth (RTN 12(2))",
                   "A/C below 1: cost-based subdivision is faster at that depth. Theirs: the ratio of their OCTREE84-A and "
                   "OCTREE84-C times.");
    md_table(f, "Scene|depth:|C ms:|A ms:|A/C:|theirs A/C:|tests/ray C:|A:|steps/ray C:|A:|leaves C:|A:");
    char c_wins[1024] = "";
    int a_wins = 0, cells = 0;
    FOR_SCENE(r, i)
        for (int d = 0; d < HV_DEPTHS; d++) {
            const meas *c = r->oc[i][d], *a = r->oa[i][d];
            double leaves_c = 0, leaves_a = 0;
            for (int s = 0; s < c->rows[0].nstats; s++)
                if (!strcmp(c->rows[0].stats[s].name, "leaves")) leaves_c = c->rows[0].stats[s].value;
            for (int s = 0; s < a->rows[0].nstats; s++)
                if (!strcmp(a->rows[0].stats[s].name, "leaves")) leaves_a = a->rows[0].stats[s].value;
            md_row(f, "%s|%d|%.1f|%.1f|%.2f|%.2f|%.1f|%.1f|%.1f|%.1f|%.0f|%.0f", d ? "" : r->k.shown[i], h->depth_min + d,
                       c->ms, a->ms, rp_relative(a, c), ratio(h->o84a[i][d], h->o84c[i][d]), rp_tests(c), rp_tests(a),
                       rp_steps(c), rp_steps(a), leaves_c, leaves_a);
            cells++;
            if (slower(c, a)) a_wins++;
            else if (h->o84a[i][d] < h->o84c[i][d]) {
                char one[64];
                snprintf(one, sizeof one, "%s@%d%s", havran_scenes[i].image, h->depth_min + d, slower(a, c) ? "" : " (tie)");
                append(c_wins, sizeof c_wins, one);
            }
        }
    md_end(f);
    md_para(f, "O84-A beats O84-C beyond noise in %d of %d (scene, depth) cells.", a_wins, cells);
    /* A control: where the cost rule never fired, the two built the same tree and did the same work ray for
     * ray, so their time ratio is the run's noise floor, not a difference between techniques. */
    int same = 0;
    double lo = INFINITY, hi = 0;
    FOR_SCENE(r, i) {
        for (int d = 0; d < HV_DEPTHS; d++) {
            const meas *c = r->oc[i][d], *a = r->oa[i][d];
            if (memcmp(&c->c, &a->c, sizeof c->c) != 0) continue;
            double q = rp_relative(a, c);
            same++, lo = fmin(lo, q), hi = fmax(hi, q);
        }
    }
    if (same)
        md_para(f, "control: in %d cells O84-A built the same tree as O84-C (identical counters, ray for ray); their "
                       "time ratio there runs from %.2f to %.2f, where 1.00 is the truth: read every ratio of this run "
                       "with that margin.",
                    same, lo, hi);
    if (c_wins[0])
        md_finding(f, "they found cost-based subdivision faster than centre subdivision at every depth on every scene; "
                          "ours is not faster beyond noise at: %s.",
                       c_wins);

    md_heading(f, 3, "Best depth of each");
    md_table(f, "Scene|best C depth:|theirs:|best A depth:|theirs:|best A / best C:|theirs:");
    char depth_c[512] = "", depth_a[512] = "", order[512] = "";
    FOR_SCENE(r, i) {
        int bc = argmin_meas(r->oc[i], HV_DEPTHS), ba = argmin_meas(r->oa[i], HV_DEPTHS);
        int tc = argmin(h->o84c[i], HV_DEPTHS), ta = argmin(h->o84a[i], HV_DEPTHS);
        double ours = rp_relative(r->oa[i][ba], r->oc[i][bc]), their = ratio(h->o84a[i][ta], h->o84c[i][tc]);
        md_row(f, "%s|%d|%d|%d|%d|%.2f|%.2f", r->k.shown[i], h->depth_min + bc, h->depth_min + tc, h->depth_min + ba,
                   h->depth_min + ta, ours, their);
        char one[64];
        if (bc != tc) {
            snprintf(one, sizeof one, "%s %d (theirs %d)", havran_scenes[i].image, h->depth_min + bc, h->depth_min + tc);
            append(depth_c, sizeof depth_c, one);
        }
        if (ba != ta) {
            snprintf(one, sizeof one, "%s %d (theirs %d)", havran_scenes[i].image, h->depth_min + ba, h->depth_min + ta);
            append(depth_a, sizeof depth_a, one);
        }
        bool ours_a = slower(r->oc[i][bc], r->oa[i][ba]), ours_c = slower(r->oa[i][ba], r->oc[i][bc]);
        if ((their < 1 && !ours_a) || (their > 1 && !ours_c)) {
            snprintf(one, sizeof one, "%s (%s)", havran_scenes[i].image, ours_a ? "A" : ours_c ? "C" : "a tie");
            append(order, sizeof order, one);
        }
    }
    md_end(f);
    if (depth_c[0]) md_finding(f, "the best maximum depth of O84-C differs from theirs on: %s.", depth_c);
    if (depth_a[0]) md_finding(f, "the best maximum depth of O84-A differs from theirs on: %s.", depth_a);
    if (order[0]) md_finding(f, "at each one's best depth, the faster of O84-A and O84-C differs from theirs on: %s.", order);
}

/* ------------------------------------------------------------ across */

enum { T_D1, T_D20, T_OC, T_OA, T_SEQ, T_REC, T_SAH, T_N, T_THEIRS = 4 };
static const char *const tech_names[T_N] = {"D1", "D20", "O84-C", "O84-A", "BSP-seq", "BSP-rec", "BSP-SAH"};

/* Scene i's measurement of each technique (the octrees at their best depth). */
static void techniques(havran_run *r, int i, meas *t[T_N])
{
    t[T_D1] = r->d1[i], t[T_D20] = r->d20[i];
    t[T_OC] = r->oc[i][argmin_meas(r->oc[i], HV_DEPTHS)];
    t[T_OA] = r->oa[i][argmin_meas(r->oa[i], HV_DEPTHS)];
    t[T_SEQ] = r->bsp_seq[i], t[T_REC] = r->bsp_rec[i], t[T_SAH] = r->bsp_sah[i];
}

static void across(havran_run *r, FILE *f)
{
    const havran_figures *h = &r->hf;
    md_section(f, "Every technique against the D = 20 grid",
                   "Time of each technique over D20's on the same scene (the octrees at their best depth); below 1 is "
                   "faster than D20. Their grid and octree articles measured the same scenes, rays and machine, so their "
                   "ratios are formed the same way. x Embree: the fastest of ours, its time over Embree's paired medians.");
    md_table(f, "Scene|D20 ms:|D1:|theirs:|O84-C:|theirs:|O84-A:|theirs:|BSP-seq:|BSP-rec:|BSP-SAH:|fastest of 4|theirs|"
                    "fastest of all|x Embree:");
    char order[768] = "";
    FOR_SCENE(r, i) {
        meas *t[T_N];
        techniques(r, i, t);
        double theirs[T_THEIRS] = {h->d1_trace[i], h->d20_trace[i], h->o84c[i][argmin(h->o84c[i], HV_DEPTHS)],
                                   h->o84a[i][argmin(h->o84a[i], HV_DEPTHS)]};
        int ours4 = argmin_meas(t, T_THEIRS), their4 = argmin(theirs, T_THEIRS), all = argmin_meas(t, T_N);
        const meas *d20 = t[T_D20];
        md_row(f, "%s|%.1f|%.2f|%.2f|%.2f|%.2f|%.2f|%.2f|%.2f|%.2f|%.2f|%s|%s|%s|%.1f", r->k.shown[i], d20->ms,
                   rp_relative(t[T_D1], d20), ratio(theirs[T_D1], theirs[T_D20]), rp_relative(t[T_OC], d20),
                   ratio(theirs[T_OC], theirs[T_D20]), rp_relative(t[T_OA], d20), ratio(theirs[T_OA], theirs[T_D20]),
                   rp_relative(t[T_SEQ], d20), rp_relative(t[T_REC], d20), rp_relative(t[T_SAH], d20), tech_names[ours4],
                   tech_names[their4], tech_names[all], rp_vs_embree(t[all]));
        /* A different winner counts only when ours beats theirs' winner beyond noise. */
        if (ours4 != their4 && slower(t[their4], t[ours4])) {
            char one[96];
            snprintf(one, sizeof one, "%s %s (theirs %s)", havran_scenes[i].image, tech_names[ours4], tech_names[their4]);
            append(order, sizeof order, one);
        }
    }
    md_end(f);
    if (order[0])
        md_finding(f, "among the four techniques both measured, the fastest differs from theirs (beyond noise) on: %s.",
                       order);
    else md_para(f, "Among the four techniques both measured, the fastest is theirs, or within noise of it, on every scene.");
}

/* ------------------------------------------------------------ BSPs */

static void bsps(havran_run *r, FILE *f)
{
    md_section(f, "BSP: Kaplan's sequential and Jansen's recursive traversal, midpoint and SAH planes",
                   "No published figures: Havran's thesis (2000) measures kd-trees on these scenes, but its tables are not "
                   "in the sources this project reads, so these rows are ours alone. seq/rec above 1: the recursive "
                   "traversal is faster on the same tree.");
    md_table(f, "Scene|seq ms:|rec ms:|seq/rec:|SAH ms:|SAH/rec:|tests/ray seq:|rec:|SAH:|steps/ray seq:|rec:|SAH:");
    int rec_faster = 0, sah_faster = 0;
    FOR_SCENE(r, i) {
        const meas *s = r->bsp_seq[i], *c = r->bsp_rec[i], *a = r->bsp_sah[i];
        md_row(f, "%s|%.1f|%.1f|%.2f|%.1f|%.2f|%.1f|%.1f|%.1f|%.1f|%.1f|%.1f", r->k.shown[i], s->ms, c->ms,
                   rp_relative(s, c), a->ms, rp_relative(a, c), rp_tests(s), rp_tests(c), rp_tests(a), rp_steps(s),
                   rp_steps(c), rp_steps(a));
        rec_faster += slower(s, c);
        sah_faster += slower(c, a);
    }
    md_end(f);
    md_para(f, "The recursive traversal beats the sequential one beyond noise on %d of %d scenes; SAH planes beat "
                   "midpoint planes (both recursive) on %d of %d.",
                rec_faster, measured_scenes(r), sah_faster, measured_scenes(r));
}

static void verification(havran_run *r, FILE *f)
{
    meas *g[2 * HV_SCENES], *o[2 * HV_SCENES * HV_DEPTHS], *b[3 * HV_SCENES];
    int ng = 0, no = 0, nb = 0;
    FOR_SCENE(r, i) {
        g[ng++] = r->d1[i], g[ng++] = r->d20[i];
        for (int d = 0; d < HV_DEPTHS; d++) o[no++] = r->oc[i][d], o[no++] = r->oa[i][d];
        b[nb++] = r->bsp_seq[i], b[nb++] = r->bsp_rec[i], b[nb++] = r->bsp_sah[i];
    }
    const rp_group groups[] = {{"Grids", g, ng}, {"Octrees", o, no}, {"BSP", b, nb}};
    rp_verification(&r->k, f, groups, 3);
}

void havran_report(void *ctx, FILE *f)
{
    havran_run *r = ctx;
    print_header(r, f);
    grids(r, f);
    octrees(r, f);
    across(r, f);
    bsps(r, f);
    verification(r, f);
}
