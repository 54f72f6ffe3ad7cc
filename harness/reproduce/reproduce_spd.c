/* reproduce_spd.c: `accelbench reproduce spd`: the SPD Readme's testing
 * procedure on every SPD database at its default size, in the shape of the
 * Readme's tables (E. Haines, Standard Procedural Databases 3.14,
 * Readme.txt: "Database Analysis" and "Timings"), our numbers beside its
 * figures (data/spd_figures.csv).
 *
 * Rays: the whitted workload (workload.h, workload_whitted.c): 513 x 513
 * eye rays through the pixel corners of a 512 x 512 image, the Whitted
 * tree to depth 5 (the eye ray being 1), reflection where Ks > 0 or T > 0,
 * refraction by Snell's law where T > 0, shadow rays to every light the
 * surface faces; the tree made from Embree's hits. Each accelerator
 * (bvh-gs, or --accels) traces the four ray sets, verified against Embree
 * and timed paired with it (reproduce_kit.h).
 *
 * Tables:
 *   1. the Readme's "Database Analysis" rows: eye rays that hit, reflected,
 *      refracted and shadow rays, ours next to the Readme's, with a
 *      "finding:" line for every count more than 10 % off (the Readme: "The
 *      numbers given can vary noticeably from a given ray tracer, but
 *      should all be within about 10%");
 *   2. per accelerator, its "Timings" row: bounding volume tests and
 *      primitive tests per ray, build and trace time; next to the Readme's
 *      per-ray counts from its HP-835 hierarchy, which was built by
 *      Goldsmith and Salmon's method, so bvh-gs's rows get a finding line
 *      where a count is more than 10 % off;
 *   3. per accelerator, the same split by ray type.
 * --quick traces 33 x 33 eye rays; the Readme's counts are then scaled by
 * the ratio of eye rays, and the comparison is only indicative. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../measure/accel_choice.h"
#include "figures.h"
#include "markdown.h"
#include "reproduce.h"
#include "reproduce_kit.h"
#include "../workloads/workload.h"

#define FIGURES_PATH ACCELBENCH_SOURCE_DIR "/data/spd_figures.csv"
#define SPD_SCENES 11
#define SPD_ACCELS 16
#define SPD_TOLERANCE 0.10 /* the Readme's "within about 10%" */

static const scene_def spd_scenes[SPD_SCENES] = {
    {"spd:balls", "balls", "sphereflake, 7382 objects, 3 lights", NULL, NULL},
    {"spd:gears", "gears", "gears of 144-gons, some glass, 5 lights", NULL, NULL},
    {"spd:mount", "mount", "fractal mountain and four glass spheres, 1 light", NULL, NULL},
    {"spd:rings", "rings", "pyramid of rings, 3 lights", NULL, NULL},
    {"spd:teapot", "teapot", "the teapot (smooth patches) on a checkerboard, 2 lights", NULL, NULL},
    {"spd:tetra", "tetra", "Sierpinski tetrahedron, 1 light", NULL, NULL},
    {"spd:tree", "tree", "Aono-Kunii tree, 7 lights", NULL, NULL},
    {"spd:lattice", "lattice", "spheres and cylinders on a lattice (no Readme figures)", NULL, NULL},
    {"spd:shells", "shells", "Pickover sea shell (no Readme figures)", NULL, NULL},
    {"spd:jacks", "jacks", "recursive jacks (no Readme figures)", NULL, NULL},
    {"spd:sombrero", "sombrero", "sombrero height field (no Readme figures)", NULL, NULL},
};

/* The four counts of the Readme's table, in whitted_part order: eye rays
 * that hit (not all eye rays), reflected, refracted, shadow. */
static const char *const count_quantity[WHITTED_PARTS] = {"eye_hits", "reflected", "refracted", "shadow"};
static const char *const count_title[WHITTED_PARTS] = {"eye hits", "reflected", "refracted", "shadow"};

typedef struct {
    rp_kit k;
    figures *f;
    bool use[SPD_SCENES];
    bool has_figures[SPD_SCENES];
    int img; /* image side: eye rays are (img+1)^2 */
    const char *accel[SPD_ACCELS]; /* each instance's label (accel_choice.h): bvh-gs, bvh-gs[order=sorted] */
    const char *name[SPD_ACCELS];  /* its accelerator */
    char label[SPD_ACCELS][600];
    char settings[SPD_ACCELS][1024]; /* its parameters that differ from the defaults, k=v,k=v */
    int naccels;
    double theirs[SPD_SCENES][WHITTED_PARTS];     /* the Readme's counts, scaled to our eye rays */
    double their_box[SPD_SCENES], their_prim[SPD_SCENES]; /* its tests per ray */
    uint64_t ours[SPD_SCENES][WHITTED_PARTS];     /* eye hits, then the sets' ray counts */
    meas *m[SPD_SCENES][SPD_ACCELS];
} spd_run;

static spd_run R; /* large: static */

void spd_usage(FILE *out)
{
    fprintf(out,
            "    spd     E. Haines, Standard Procedural Databases 3.14, Readme: its testing procedure (513x513\n"
            "            corner eye rays, Whitted trees to depth 5, reflection, refraction, shadow rays) on every\n"
            "            SPD database at its default size, through bvh-gs (Goldsmith-Salmon, as the Readme's own\n"
            "            figures) or --accels: eye hits, reflected, refracted and shadow rays beside the Readme's,\n"
            "            bounding volume and primitive tests per ray beside its HP-835's, build and trace times,\n"
            "            all split by ray type. Figures: data/spd_figures.csv. About 5 minutes on one core.\n");
}

static int parse_accels(spd_run *r)
{
    const char *list = r->k.o.accels ? r->k.o.accels : "bvh-gs";
    /* Instances and sweeps as run's --accels (accel_choice.h): 'bvh-gs,bvh-gs[order=sorted]'. */
    static accel_config inst[SPD_ACCELS];
    char err[1024];
    int n = accel_spec_expand(list, inst, SPD_ACCELS, err, sizeof err);
    if (n < 0) {
        fprintf(stderr, "accelbench reproduce spd: %s\n", err);
        return 2;
    }
    for (int i = 0; i < n; i++) {
        if (inst[i].ops->flags & ACCEL_SHADOW_ONLY) {
            fprintf(stderr, "accelbench reproduce spd: --accels: %s answers shadow rays only; the protocol needs closest hits\n",
                    inst[i].ops->name);
            return 2;
        }
        /* The label names the variant in the tables; the name and the differing parameters build it. */
        accel_config_label(&inst[i], r->label[i], sizeof r->label[i]);
        for (char *c = r->label[i]; *c; c++)
            if (*c == ',') *c = ';'; /* the label is spd.csv's variant column: no comma */
        size_t len = 0;
        r->settings[i][0] = 0;
        for (int k = 0; k < inst[i].params.count; k++)
            if (strcmp(inst[i].params.values[k], inst[i].params.table[k].default_value))
                len += (size_t)snprintf(r->settings[i] + len, sizeof r->settings[i] - len, "%s%s=%s", len ? "," : "",
                                        inst[i].params.table[k].name, inst[i].params.values[k]);
        r->name[i] = inst[i].ops->name;
        r->accel[i] = r->label[i];
    }
    r->naccels = n;
    return 0;
}

/* The Readme's figures of every database it has them for, scaled to eye_rays. */
static int load_figures(spd_run *r, double eye_rays)
{
    char err[512];
    if (!(r->f = figures_load(FIGURES_PATH, err, sizeof err))) {
        fprintf(stderr, "accelbench: reproduce spd: %s\n", err);
        return 2;
    }
    double theirs_eye = figures_number(r->f, "rays", "all", "eye_rays"), scale = eye_rays / theirs_eye;
    const char *rows[SPD_SCENES];
    int nrows = figures_rows(r->f, "rays", rows, SPD_SCENES);
    for (int i = 0; i < SPD_SCENES; i++) {
        const char *row = spd_scenes[i].image;
        bool listed = false;
        for (int j = 0; j < nrows; j++) listed |= !strcmp(rows[j], row);
        if (!listed) continue; /* the Readme has no figures of the later databases */
        r->has_figures[i] = true;
        double total = theirs_eye;
        for (int p = 0; p < WHITTED_PARTS; p++) {
            double v = figures_number(r->f, "rays", row, count_quantity[p]);
            r->theirs[i][p] = v * scale;
            if (p > 0) total += v;
        }
        double prims = figures_number(r->f, "tests", row, "polygon") + figures_number(r->f, "tests", row, "sphere") +
                       figures_number(r->f, "tests", row, "cylcone");
        r->their_prim[i] = prims / total;
        r->their_box[i] = figures_number(r->f, "tests", row, "box") / total;
    }
    const char *missing = figures_missing(r->f);
    if (missing) {
        fprintf(stderr, "accelbench: reproduce spd: %s: no usable figure %s\n", FIGURES_PATH, missing);
        return 2;
    }
    return 0;
}

static int run_experiments(spd_run *r)
{
    rp_kit *k = &r->k;
    for (int si = 0; si < SPD_SCENES; si++) {
        if (!r->use[si]) continue;
        if (rp_open_scene(k, si)) return 2;
        rp_prepare_sets(k, r->img, r->img, 1, true, WORKLOAD_WHITTED_DEPTH, whitted_part_name, WHITTED_PARTS);
        const answers_t *eye = k->cells[WHITTED_EYE].ref_answers;
        for (uint32_t i = 0; i < eye->count; i++) r->ours[si][WHITTED_EYE] += eye->hits[i].prim != HIT_NONE;
        for (int p = 1; p < WHITTED_PARTS; p++) r->ours[si][p] = k->cells[p].rs->count;
        for (int a = 0; a < r->naccels; a++)
            if (!(r->m[si][a] = rp_measure(k, "spd", r->accel[a], r->name[a], r->settings[a]))) return 2;
    }
    rp_close_scene(k);
    return 0;
}

/* ------------------------------------------------------------ the report */

static double off(double ours, double theirs) { return theirs > 0 ? ours / theirs - 1.0 : (ours > 0 ? INFINITY : 0.0); }

static void counts_table(spd_run *r, FILE *f)
{
    md_section(f, "Rays (the Readme's Database Analysis)",
                   "Our counts from the Whitted trees Embree's hits make, beside the Readme's%s. Eye hits: eye rays that "
                   "hit an object; reflected: rays spawned by reflecting and transmitting surfaces; refracted: by "
                   "transmitting surfaces; shadow: rays toward the lights, none where the surface faces away.",
                   r->k.o.quick ? " (scaled to our fewer eye rays: --quick)" : "");
    md_table(f, "database|eye hits:|Readme:|reflected:|Readme:|refracted:|Readme:|shadow:|Readme:");
    for (int i = 0; i < SPD_SCENES; i++) {
        if (!r->use[i]) continue;
        char cells[WHITTED_PARTS][64];
        for (int p = 0; p < WHITTED_PARTS; p++)
            if (r->has_figures[i])
                snprintf(cells[p], sizeof cells[p], "%llu|%.0f", (unsigned long long)r->ours[i][p], r->theirs[i][p]);
            else snprintf(cells[p], sizeof cells[p], "%llu|", (unsigned long long)r->ours[i][p]);
        md_row(f, "%s|%s|%s|%s|%s", r->k.shown[i], cells[0], cells[1], cells[2], cells[3]);
    }
    md_end(f);
    int within = 0, compared = 0;
    for (int i = 0; i < SPD_SCENES; i++) {
        if (!r->use[i] || !r->has_figures[i]) continue;
        for (int p = 0; p < WHITTED_PARTS; p++) {
            double d = off((double)r->ours[i][p], r->theirs[i][p]);
            compared++;
            if (fabs(d) <= SPD_TOLERANCE) {
                within++;
                continue;
            }
            md_finding(f, "%s: %s rays %llu against the Readme's %.0f (%+.0f %%), beyond its \"within about 10%%\".",
                           spd_scenes[i].image, count_title[p], (unsigned long long)r->ours[i][p], r->theirs[i][p],
                           100.0 * d);
        }
    }
    md_para(f, "%d of %d counts within 10 %% of the Readme's.", within, compared);
}

static void accel_table(spd_run *r, FILE *f, int a)
{
    const char *name = r->accel[a];
    bool gs = !strcmp(r->name[a], "bvh-gs");
    md_section(f, name, "Every ray of the protocol through %s (the four sets summed): bounding volume (box) tests "
                   "and primitive tests per ray beside the Readme's HP-835 figures (its Goldsmith-Salmon hierarchy; "
                   "its tests over all its rays), build and trace time (median of %d, paired with Embree).%s",
                   name, r->k.o.repeat, gs ? "" : " The Readme's counts are of another structure: no findings here.");
    md_table(f, "database|rays:|box tests/ray:|Readme:|prim tests/ray:|Readme:|build ms:|trace ms:|x Embree:");
    for (int i = 0; i < SPD_SCENES; i++) {
        const meas *m = r->m[i][a];
        if (!r->use[i] || !m) continue;
        char theirs_box[32] = "", theirs_prim[32] = "";
        if (r->has_figures[i]) {
            snprintf(theirs_box, sizeof theirs_box, "%.2f", r->their_box[i]);
            snprintf(theirs_prim, sizeof theirs_prim, "%.2f", r->their_prim[i]);
        }
        md_row(f, "%s|%llu|%.2f|%s|%.2f|%s|%.1f|%.1f|%.2f", r->k.shown[i], (unsigned long long)m->rays, rp_boxes(m),
                   theirs_box, rp_tests(m), theirs_prim, m->build_ms / m->nsets, m->ms, rp_vs_embree(m));
    }
    md_end(f);
    if (!gs) return;
    for (int i = 0; i < SPD_SCENES; i++) {
        const meas *m = r->m[i][a];
        if (!r->use[i] || !m || !r->has_figures[i]) continue;
        double db = off(rp_boxes(m), r->their_box[i]), dp = off(rp_tests(m), r->their_prim[i]);
        if (fabs(db) > SPD_TOLERANCE)
            md_finding(f, "%s: bvh-gs makes %.2f box tests per ray, the Readme's hierarchy %.2f (%+.0f %%).",
                           spd_scenes[i].image, rp_boxes(m), r->their_box[i], 100.0 * db);
        if (fabs(dp) > SPD_TOLERANCE)
            md_finding(f, "%s: bvh-gs makes %.2f primitive tests per ray, the Readme's hierarchy %.2f (%+.0f %%).",
                           spd_scenes[i].image, rp_tests(m), r->their_prim[i], 100.0 * dp);
    }
}

static void type_table(spd_run *r, FILE *f, int a)
{
    md_heading(f, 3, "%s by ray type", r->accel[a]);
    md_table(f, "database|rays|count:|box tests/ray:|prim tests/ray:|trace ms:|Mrays/s:|x Embree:");
    for (int i = 0; i < SPD_SCENES; i++) {
        const meas *m = r->m[i][a];
        if (!r->use[i] || !m) continue;
        for (int p = 0; p < m->nsets; p++) {
            const csv_row *row = &m->rows[p];
            double n = row->rays ? (double)row->rays : 1.0;
            if (!row->rays) {
                md_row(f, "%s|%s|0||||||", r->k.shown[i], m->workload[p] + 8);
                continue;
            }
            char box[32] = "", prim[32] = "";
            if (row->has_counters) {
                snprintf(box, sizeof box, "%.2f", (double)row->counters.box_tests / n);
                snprintf(prim, sizeof prim, "%.2f", (double)row->counters.prim_tests / n);
            }
            md_row(f, "%s|%s|%u|%s|%s|%.2f|%.3f|%.2f", r->k.shown[i], m->workload[p] + 8 /* after "whitted:" */,
                       row->rays, box, prim, row->trace_ms, row->mrays_per_s, row->ratio_vs_embree);
        }
    }
    md_end(f);
}

static void spd_report(void *ctx, FILE *f)
{
    spd_run *r = ctx;
    rp_kit *k = &r->k;
    md_heading(f, 1, "reproduce spd: the SPD Readme's testing procedure");
    char paths[128];
    rp_timed_paths(k, paths, sizeof paths);
    md_para(f, "Source: %s; %s. Ours: %s, %s, %s; %dx%d corner eye rays (%s), Whitted trees to depth %d; timed on %d "
                "thread%s (%s), %d repeat%s paired with Embree.",
                figures_text(r->f, "rays", "all", "source"), figures_text(r->f, "tests", "all", "source"), k->mi.cpu,
                k->mi.host, k->mi.git_rev, r->img + 1, r->img + 1, k->o.quick ? "--quick" : "the Readme's",
                WORKLOAD_WHITTED_DEPTH, k->timed_threads, k->timed_threads == 1 ? "" : "s", paths, k->o.repeat,
                k->o.repeat == 1 ? "" : "s");
    counts_table(r, f);
    for (int a = 0; a < r->naccels; a++) {
        accel_table(r, f, a);
        type_table(r, f, a);
    }
    meas *all[SPD_SCENES * SPD_ACCELS];
    int n = 0;
    for (int i = 0; i < SPD_SCENES; i++)
        for (int a = 0; a < r->naccels; a++)
            if (r->use[i] && r->m[i][a]) all[n++] = r->m[i][a];
    rp_group groups[1] = {{"the protocol's rays", all, n}};
    rp_verification(k, f, groups, 1);
}

int reproduce_spd(int argc, char **argv)
{
    spd_run *r = &R;
    memset(r, 0, sizeof *r);
    rp_kit *k = &r->k;
    int rc;
    /* An accelerator that mutates is timed on 1 (cell_threads), every other on --threads. */
    if (!rp_begin(k, "spd", spd_scenes, SPD_SCENES, 0, argc, argv, NULL, NULL, &rc)) return rc;
    if ((rc = rp_select_scenes(k, r->use)) || (rc = parse_accels(r))) return rc;
    r->img = k->o.quick ? 32 : 512;
    if ((rc = load_figures(r, (double)(r->img + 1) * (r->img + 1)))) {
        figures_free(r->f);
        return rc;
    }
    if ((rc = rp_start(k))) {
        figures_free(r->f);
        return rc;
    }
    if (!k->o.quiet)
        fprintf(stderr, "reproduce spd: %s mode, %dx%d corner eye rays, trees to depth %d, %d accelerator%s, timed on %d "
                        "thread%s, %d repeat%s, writing %s\n",
                k->o.quick ? "quick" : "default", r->img + 1, r->img + 1, WORKLOAD_WHITTED_DEPTH, r->naccels,
                r->naccels == 1 ? "" : "s", k->timed_threads, k->timed_threads == 1 ? "" : "s", k->o.repeat,
                k->o.repeat == 1 ? "" : "s", k->out_dir);
    rc = run_experiments(r);
    rc = rp_finish(k, rc, spd_report, r, NULL);
    figures_free(r->f);
    return rc;
}
