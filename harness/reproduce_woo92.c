/* reproduce_woo92.c: `accelbench reproduce woo92`: the experiments of
 *   A. Woo, "Ray Tracing Polygons using Spatial Subdivision", Graphics
 *   Interface 1992 (Tables 1-4, sections 8-9)
 * re-run on our scenes with the grids of accel/grid_woo.c, printed in the
 * paper's table shapes with OUR numbers, plus an ablation that adds Woo's
 * switches one at a time (sections 4-7). This file sets up and measures;
 * reproduce_woo92_tables.c prints the report. Woo's own numbers, and the
 * experiment's shape taken from them (his grid resolutions, image sizes,
 * sampling rates, reflection depth), come from data/woo92_figures.csv,
 * which scripts/plot_woo92.py reads too.
 *
 * Every measurement is a `run` cell (measure.h: build, one warm-up trace
 * whose answers are verified against Embree and give the counters, then
 * `repeat` timed samples paired with Embree's, medians reported). Every
 * timed trace runs on ONE thread: grid-raybox reorders its shared lists
 * (ACCEL_MUTATES) and must, so every variant (and Embree, its pair) does
 * too. --threads only speeds up the untimed work (ray sets, reference
 * answers).
 *
 * Variants (all grid-raybox unless said):
 *   old   raybox=on and every Woo switch off: Snyder-Barr alone, res=auto
 *         (Woo s8.2), the "Old Time" of Woo's Tables 2-3.
 *   new   grid-raybox defaults: Woo's final implementation.
 *   tri   old + tclip=on + eyeorigin=on: Woo s7 alone ("Tri Time").
 *   raw   `grid` (3DDDA, mailboxes, no ray box): Table 1's raw traversal.
 *   ablation: old, then +woo90, +mtf=hit, +mtf=almost, +dynbox, +voxbox,
 *         +beta=0.75, +tclip (= new), +eyeorigin, +rayid=twopass,
 *         cumulative, in Woo's order.
 *
 * Images (Tables 2-4, ablation): the primary rays plus the `reflection`
 * workload (mirror bounces) of the same pixels; an image's time is the sum
 * of the two sets' median times, as Woo's times are whole images.
 *
 * Scenes: Woo's Room is Sibenik from inside (the catalogue view
 * sibenik@nave). Sibenik comes from a public repository, not with the
 * project: on a machine without it the Room is measured on the generated
 * stand-in gen:room, and the output, the CSV's scene column and the tables
 * say so.
 *
 * Output folder (default results/woo92-<date-time>):
 *   woo92.csv        the main CSV's columns (csv.h) preceded by `table`,
 *                    `variant` and `grid_res` (the built resolution): one
 *                    row per (table, variant, scene, spp, workload). A
 *                    measurement used by two tables (Table 2's old and new
 *                    are ablation rows, Table 3's 1x1 row is Table 2's lamp)
 *                    is measured once and written under each table with the
 *                    same numbers. The file is rewritten, not appended.
 *   woo92_tables.md  the tables, findings and verification counts printed
 *                    on stdout.
 *   woo92_*.png      scripts/plot_woo92.py, called at the end.
 * Exit status: 0, 1 when any measurement had a real mismatch, 2 bad input. */
#include "reproduce.h"
#include "reproduce_woo92.h"

#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include "csv.h"
#include "output.h"
#include "resources.h"
#include "../prims/checked_alloc.h"
#include "trace.h"
#include "workload.h"

#define FIGURES_PATH ACCELBENCH_SOURCE_DIR "/data/woo92_figures.csv"

/* ------------------------------------------------------------ the set-up */

const scene_def woo92_scenes[SC_N] = {
    {"spd:balls:4", "sphere flakes",
     "Haines' sphereflake with true spheres (7381 spheres and the floor): Woo's Table 1 scene itself (optik, true "
     "spheres, the SPD image).",
     NULL, NULL},
    {"spd:balls:2:t2", "Spheres",
     "his tracer tessellates every surface (the section 4-7 optimisations are for polygons); the 91-sphere sphereflake "
     "tessellated at RES 2 (4368 triangles + 2 floor triangles = 4370) is the sphere set whose triangle count is "
     "closest; true spheres are covered by Table 1.",
     NULL, NULL},
    {"sibenik@nave", "Room",
     "an interior: the Sibenik cathedral (75,284 triangles) from the catalogue's view inside the nave; every eye ray hits "
     "a wall, so all three reflection generations are full.",
     "gen:room",
     "gen:room, the generated hall (scenes/gen_room.c), is an interior too, but of 72 primitives where Woo's room has "
     "thousands: its numbers test the command, they do not reproduce Woo's Room."},
    {"spd:teapot:12", "Lamp",
     "a dense tessellated object (small nuts and bolts) on a large floor, a non-uniform scene; the SPD teapot (9120 "
     "triangles) on its 12x12 checkerboard floor is the same shape: a dense triangle object on a large floor (spd:gears "
     "is a uniform array of gears, the opposite).",
     NULL, NULL},
};

/* Woo's Snyder-Barr alone: the ray box on, every one of his switches off. */
#define OLD_SETTINGS "raybox=on,mtf=off,dynbox=off,voxbox=off,beta=0,tclip=off,woo90=off,eyeorigin=off,rayid=off"
#define TRI_SETTINGS OLD_SETTINGS ",tclip=on,eyeorigin=on"

const abl_step woo92_abl_steps[ABL_N] = {
    {"old", ""},
    {"+woo90", "woo90=on"},
    {"+mtf=hit", "mtf=hit"},
    {"+mtf=almost", "mtf=almost"},
    {"+dynbox", "dynbox=on"},
    {"+voxbox", "voxbox=on"},
    {"+beta=0.75", "beta=0.75"},
    {"+tclip", "tclip=on"},
    {"+eyeorigin", "eyeorigin=on"},
    {"+rayid=twopass", "rayid=twopass"},
};

static rp_run R; /* large: static */

void reproduce_usage(FILE *out)
{
    fprintf(out,
            "usage: accelbench reproduce EXPERIMENT [--out DIR] [--threads N] [--repeat N] [--quick] [--no-plots] [--quiet]\n"
            "                                  [--memcap MIB]\n"
            "  Re-runs a paper's experiments on our scenes and prints the paper's tables with OUR\n"
            "  numbers, each under a \"finding:\" line that compares them with the paper's.\n"
            "  experiments:\n"
            "    woo92   A. Woo, \"Ray Tracing Polygons using Spatial Subdivision\", GI 1992:\n"
            "            Table 1 ray box vs raw traversal (spd:balls:4 at Woo's four grid resolutions, primary rays),\n"
            "            Table 2 old (Snyder-Barr) vs new (all of Woo's switches) on three images\n"
            "            (spheres, room, lamp; primary + mirror reflection),\n"
            "            Table 3 the lamp at Woo's three sampling rates (old, tri = s7 only, new),\n"
            "            Table 4 the spheres at the auto grid and Woo's three cubic grids (time, memory),\n"
            "            Ablation: Woo's switches added one at a time on the three images.\n"
            "            Woo's figures and the sizes taken from them: data/woo92_figures.csv.\n"
            "            The room is sibenik@nave, or the stand-in gen:room where Sibenik is not installed.\n"
            "  --out DIR      output folder (default results/woo92-<date-time>): woo92.csv (the run CSV's\n"
            "                 columns plus table, variant, grid_res), woo92_tables.md, woo92_*.png\n"
            "  --threads N    threads for the untimed work (ray sets, Embree's reference answers);\n"
            "                 default 1. Every TIMED trace runs on 1 thread whatever N is: grid-raybox\n"
            "                 mutates its lists and must, so every variant does, for fairness\n"
            "  --repeat N     timed repeats after one verified warm-up, each paired with Embree's,\n"
            "                 median reported (default 3)\n"
            "  --quick        small images and 1 repeat: the same tables in seconds (for tests only)\n"
            "  --no-plots     do not call scripts/plot_woo92.py at the end\n"
            "  --quiet        no progress on stderr\n"
            "  --memcap MIB   refuse work estimated above MIB MiB before allocating it (default: half the memory\n"
            "                 this process may use; README: Limits and resources)\n"
            "  Every measurement is verified against Embree: exit 1 on any real mismatch, 2 on bad input.\n"
            "  A default run takes a few minutes on one core.\n");
}

/* ------------------------------------------------------------ Woo's figures */

/* N of "NxN..." (the first side); 0 when it does not start with a number. */
static int side_of(const char *label) { return label ? atoi(label) : 0; }

/* Samples per pixel of a Table 3 row, "2x2" or "1x1 2x2 3x3" (adaptive up
 * to the last): the last NxN's N^2. */
static int spp_of(const char *row)
{
    const char *last = strrchr(row, ' ');
    int n = side_of(last ? last + 1 : row);
    return n * n;
}

/* One quantity of a table's rows, into column[row]. */
typedef struct { const char *quantity; double *column; } figure_column;

/* Read the columns (up to a NULL quantity) of rows[0..n) of a table. */
static void read_rows(figures *f, const char *table, const char *const *rows, int n, const figure_column *cols)
{
    for (int i = 0; i < n; i++)
        for (const figure_column *c = cols; c->quantity; c++) c->column[i] = figures_number(f, table, rows[i], c->quantity);
}

/* Read every figure the report and the experiment use; 0, or 2 after a
 * one-line error naming the file and the figure. */
static int load_figures(woo_figures *w)
{
    char err[512];
    memset(w, 0, sizeof *w);
    figures *f = w->f = figures_load(FIGURES_PATH, err, sizeof err);
    if (!f) {
        fprintf(stderr, "accelbench: reproduce woo92: %s\n", err);
        return 2;
    }
    const char *t1_rows[4], *images[3];
    int n1 = figures_rows(f, "table1", t1_rows, 4);
    read_rows(f, "table1", t1_rows, n1,
              (figure_column[]){{"raybox_time", w->t1_raybox}, {"raw_time", w->t1_raw}, {NULL, NULL}});
    for (int i = 0; i < n1; i++) w->t1_res[i] = side_of(t1_rows[i]);
    w->t1_spheres = (int)figures_number(f, "table1", t1_rows[0], "spheres");
    const char *t1_img = figures_text(f, "table1", t1_rows[0], "image_res");
    w->t1_machine = figures_text(f, "table1", "all", "machine");
    w->img_machine = figures_text(f, "s9.1", "all", "machine");
    const char *img = figures_text(f, "s9.1", "all", "image_res");
    w->depth = (int)figures_number(f, "s9.1", "all", "reflection_depth");
    w->improve_lo = figures_number(f, "s9.1", "all", "improve_lo");
    w->improve_hi = figures_number(f, "s9.1", "all", "improve_hi");
    for (int i = 0; i < 3; i++) {
        images[i] = woo92_scenes[SC_SPHERES + i].image;
        w->t2_grid[i] = figures_text(f, "table2", images[i], "grid_res");
    }
    read_rows(f, "table2", images, 3,
              (figure_column[]){{"tris", w->t2_tris}, {"intersect_saved", w->t2_isect}, {"old_time", w->t2_old},
                                {"new_time", w->t2_new}, {NULL, NULL}});
    int n3 = figures_rows(f, "table3", w->t3_rows, 3);
    read_rows(f, "table3", w->t3_rows, n3,
              (figure_column[]){{"old_time", w->t3_old}, {"tri_time", w->t3_tri}, {"new_time", w->t3_new},
                                {"tri_improve", w->t3_tri_improve}, {"new_improve", w->t3_new_improve}, {NULL, NULL}});
    for (int i = 0; i < n3; i++) w->spp[i] = spp_of(w->t3_rows[i]);
    int n4 = figures_rows(f, "table4", w->t4_rows, 4);
    read_rows(f, "table4", w->t4_rows, n4, (figure_column[]){{"time", w->t4_time}, {"space", w->t4_space}, {NULL, NULL}});
    for (int i = 1; i < n4; i++) w->t4_res[i - 1] = side_of(w->t4_rows[i]);
    const char *bad = figures_missing(f);
    if (!bad && (n1 != 4 || n3 != 3 || n4 != 4)) bad = "4 rows of table1, 3 of table3 and 4 of table4";
    if (!bad && (!t1_img || sscanf(t1_img, "%dx%d", &w->t1_w, &w->t1_h) != 2)) bad = "table1 image_res as WxH";
    if (!bad && (!img || sscanf(img, "%dx%d", &w->img_w, &w->img_h) != 2)) bad = "s9.1,all,image_res as WxH";
    if (bad) {
        fprintf(stderr, "accelbench: reproduce woo92: %s: no usable figure %s\n", FIGURES_PATH, bad);
        return 2;
    }
    return 0;
}

/* ------------------------------------------------------------ measuring */

static void free_sets(rp_run *r)
{
    for (int k = 0; k < r->nsets; k++) cell_rays_release(&r->cells[k]);
    r->nsets = 0;
}

static void close_scene(rp_run *r)
{
    free_sets(r);
    if (r->ref) r->ref->ops->destroy(r->ref);
    verifier_free(r->ver);
    if (r->s) scene_free(r->s);
    r->ref = NULL;
    r->ver = NULL;
    r->s = NULL;
}

/* The scene to load for def d: its own, or its stand-in when d's catalogue
 * file is not on this machine (the reason goes in `reason`, else ""). */
static const char *scene_to_load(const scene_def *d, char *reason, size_t len)
{
    reason[0] = 0;
    char where[1024];
    if (!d->standin || scene_catalogue_available(d->load, where, sizeof where)) return d->load;
    snprintf(reason, len, "%s", where);
    return d->standin;
}

static int open_scene(rp_run *r, int idx)
{
    char err[512];
    close_scene(r);
    const scene_def *d = &woo92_scenes[idx];
    const char *name = scene_to_load(d, r->standin_reason[idx], sizeof r->standin_reason[idx]);
    if (r->standin_reason[idx][0])
        fprintf(stderr, "reproduce woo92: STAND-IN: Woo's %s is measured on %s, because %s is not on this machine: %s\n",
                d->image, name, d->load, r->standin_reason[idx]);
    r->label[idx] = name;
    if (r->standin_reason[idx][0]) snprintf(r->shown[idx], sizeof r->shown[idx], "%s (STAND-IN for %s)", name, d->load);
    else snprintf(r->shown[idx], sizeof r->shown[idx], "%s", name);
    double t0 = clock_ms();
    r->s = scene_load(name, err, sizeof err);
    if (!r->s) {
        fprintf(stderr, "accelbench: %s\n", err);
        return -1;
    }
    r->ref = build_reference(r->s, r->o.threads, err, sizeof err);
    if (!r->ref) {
        fprintf(stderr, "accelbench: %s: reference build failed: %s\n", name, err);
        return -1;
    }
    r->ver = verifier_new(r->s, VERIFY_JUDGE_SECONDS);
    r->cur = idx;
    if (!r->o.quiet)
        fprintf(stderr, "scene %s: %u primitives, loaded in %.0f ms\n", name, r->s->prims.count, clock_ms() - t0);
    return 0;
}

/* The image's ray sets (primary, and reflection when asked) with the
 * reference's answers (on --threads). */
static void prepare_sets(rp_run *r, int w, int h, int spp, bool reflection)
{
    static const char *const workloads[SETS_MAX] = {"primary", "reflection"};
    free_sets(r);
    workload_opts wo = {.width = w, .height = h, .spp = spp, .corners = false, .depth = r->woo.depth, .seed = 1,
                        .threads = r->o.threads};
    for (int k = 0; k < (reflection ? 2 : 1); k++) {
        rayset_t *rs = workload_find(workloads[k])->make(r->s, r->ref, &wo);
        cell_rays_init(&r->cells[r->nsets++], r->s, r->ref, r->ver, rs, r->o.threads);
    }
    r->width = w, r->height = h, r->spp = spp;
}

static void write_rows(rp_run *r, const meas *m, const char *table, const char *variant)
{
    for (int k = 0; k < m->nsets; k++) {
        fprintf(r->csv, "%s,%s,%s,", table, variant, m->res_str);
        csv_write_row(r->csv, &m->rows[k]);
    }
}

/* The grid's resolution, from its res_x/res_y/res_z statistics; 0 or -1
 * after an error when it reports none. */
static int grid_res(const csv_row *row, int res[3])
{
    static const char *const axis[3] = {"res_x", "res_y", "res_z"};
    int found = 0;
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < row->nstats; k++)
            if (!strcmp(row->stats[k].name, axis[i])) res[i] = (int)row->stats[k].value, found++;
    if (found == 3) return 0;
    fprintf(stderr, "accelbench: reproduce woo92: %s reports no res_x, res_y and res_z statistics\n", row->accel);
    return -1;
}

/* Add one cell of m (ray set k) and report its real mismatches. */
static void add_cell(rp_run *r, meas *m, int k, const cell_result *cr, const char *table, const char *variant)
{
    const csv_row *row = &cr->row;
    const verify_result *vr = &cr->vr;
    m->ms += row->trace_ms, m->ms_min += row->trace_ms_min, m->ms_max += row->trace_ms_max, m->build_ms += row->build_ms;
    m->rays += row->rays;
    m->mem = row->mem_bytes;
    counters_add(&m->c, &row->counters);
    m->agree += vr->agree;
    for (int c = 0; c < MM_CLASSES; c++) m->mm[c] += vr->mismatches[c];
    if (!vr->mismatches[MM_REAL]) return;
    r->any_real = true;
    fprintf(stderr, "accelbench: REAL MISMATCH: %s %s [%s] on %s/%s: %llu rays\n", table, variant, m->params,
            r->label[r->cur], m->workload[k], (unsigned long long)vr->mismatches[MM_REAL]);
    for (uint32_t i = 0; i < vr->nlisted; i++)
        if (vr->listed[i].cls == MM_REAL) {
            const mismatch_t *x = &vr->listed[i];
            fprintf(stderr, "  ray %u: got prim %d t=%.7g, embree prim %d t=%.7g\n", x->ray,
                    x->got.prim == HIT_NONE ? -1 : (int)x->got.prim, x->got.t,
                    x->ref.prim == HIT_NONE ? -1 : (int)x->ref.prim, x->ref.t);
        }
}

/* Measure accelerator `name` with `settings` ("k=v,k=v" over its defaults)
 * on the current ray sets, or reuse an identical earlier measurement. */
static meas *measure(rp_run *r, const char *table, const char *variant, const char *name, const char *settings)
{
    accel_config ac;
    char err[512];
    memset(&ac, 0, sizeof ac);
    ac.ops = accel_find(name);
    if (!ac.ops) {
        fprintf(stderr, "accelbench: reproduce: accelerator '%s' is not built in\n", name);
        return NULL;
    }
    params_defaults(&ac.params, ac.ops->params);
    ac.params.threads = 1;
    if (resources_bound_memcap_param(ac.ops->name, &ac.params)) return NULL; /* its memcap within --memcap */
    if (params_set_list(&ac.params, settings, err, sizeof err)) {
        fprintf(stderr, "accelbench: reproduce: %s.%s\n", name, err);
        return NULL;
    }
    params_format(&ac.params, ac.params_str, sizeof ac.params_str);
    snprintf(ac.label, sizeof ac.label, "%s", name);

    for (int i = 0; i < r->nmeas; i++) {
        meas *m = &r->store[i];
        if (m->scene == r->cur && m->spp == r->spp && m->width == r->width && m->height == r->height && m->ops == ac.ops &&
            strcmp(m->params, ac.params_str) == 0) {
            write_rows(r, m, table, variant);
            return m;
        }
    }
    if (r->nmeas == MEAS_MAX) {
        fprintf(stderr, "accelbench: reproduce: more than %d measurements\n", MEAS_MAX);
        return NULL;
    }
    meas *m = &r->store[r->nmeas++];
    memset(m, 0, sizeof *m);
    m->scene = r->cur, m->spp = r->spp, m->width = r->width, m->height = r->height, m->ops = ac.ops;
    snprintf(m->params, sizeof m->params, "%s", ac.params_str);
    m->nsets = r->nsets;
    cell_settings st = {.threads = 1, .repeat = r->o.repeat, .width = r->width, .height = r->height, .spp = r->spp,
                        .mi = &r->mi};
    for (int k = 0; k < r->nsets; k++) {
        cell_result cr;
        if (measure_cell(&r->cells[k], &ac, &st, &cr)) return NULL;
        if (k == 0) {
            if (grid_res(&cr.row, m->res)) return NULL;
            snprintf(m->res_str, sizeof m->res_str, "%dx%dx%d", m->res[0], m->res[1], m->res[2]);
        }
        snprintf(m->workload[k], sizeof m->workload[k], "%s", cr.row.workload);
        /* The stored row outlives the scene and the ray sets: point it at
         * strings that live as long as the run. */
        cr.row.scene = r->label[r->cur];
        cr.row.params = m->params;
        cr.row.workload = m->workload[k];
        m->rows[k] = cr.row;
        add_cell(r, m, k, &cr, table, variant);
    }
    write_rows(r, m, table, variant);
    if (!r->o.quiet)
        fprintf(stderr, "  [%3d] %-8s %-16s %-16s %s %dx%d spp %d: %.1f ms (%.0f-%.0f), %.2f tests/ray, real mismatches %llu (%.0f s)\n",
                r->nmeas, table, variant, r->label[r->cur], m->res_str, r->width, r->height, r->spp, m->ms, m->ms_min,
                m->ms_max, (double)m->c.prim_tests / (double)m->rays, (unsigned long long)m->mm[MM_REAL],
                (clock_ms() - r->wall0) / 1e3);
    return m;
}

/* ------------------------------------------------------------ the run */

/* Which ablation row is `new` (grid-raybox defaults): the cumulative
 * settings of each row against the defaults. */
static int find_new_rows(rp_run *r)
{
    const struct accel_ops *ops = accel_find("grid-raybox");
    accel_params d, p;
    char ds[512], ps[512], err[256], cum[600] = OLD_SETTINGS;
    params_defaults(&d, ops->params);
    params_defaults(&p, ops->params);
    /* as measure() sets them, so that the two strings differ only where the rows do */
    if (resources_bound_memcap_param(ops->name, &d) || resources_bound_memcap_param(ops->name, &p)) return 2;
    params_format(&d, ds, sizeof ds);
    if (params_set_list(&p, cum, err, sizeof err)) return 2;
    for (int k = 0; k < ABL_N; k++) {
        if (woo92_abl_steps[k].set[0] && params_set_list(&p, woo92_abl_steps[k].set, err, sizeof err)) return 2;
        params_format(&p, ps, sizeof ps);
        r->abl_is_new[k] = strcmp(ps, ds) == 0;
    }
    return 0;
}

static int run_experiments(rp_run *r)
{
    const rp_config *c = &r->cf;
    const woo_figures *w = &r->woo;
    char set[600];
    /* Table 1: the sphereflake, primary rays, four grids, ray box vs raw. */
    if (open_scene(r, SC_FLAKE)) return 2;
    prepare_sets(r, c->t1_w, c->t1_h, 1, false);
    for (int i = 0; i < 4; i++) {
        char variant[32];
        int n = w->t1_res[i];
        snprintf(variant, sizeof variant, "raybox@%d", n);
        snprintf(set, sizeof set, OLD_SETTINGS ",res=%dx%dx%d", n, n, n);
        if (!(r->t1_raybox[i] = measure(r, "table1", variant, "grid-raybox", set))) return 2;
        snprintf(variant, sizeof variant, "raw@%d", n);
        snprintf(set, sizeof set, "res=%dx%dx%d", n, n, n);
        if (!(r->t1_raw[i] = measure(r, "table1", variant, "grid", set))) return 2;
    }
    if (find_new_rows(r)) return 2;
    /* Tables 2-4 and the ablation: the three images. */
    for (int si = 0; si < 3; si++) {
        int scene = SC_SPHERES + si;
        if (open_scene(r, scene)) return 2;
        prepare_sets(r, c->img_w, c->img_h, 1, true);
        char cum[600] = OLD_SETTINGS;
        for (int k = 0; k < ABL_N; k++) {
            if (woo92_abl_steps[k].set[0]) {
                size_t n = strlen(cum);
                snprintf(cum + n, sizeof cum - n, ",%s", woo92_abl_steps[k].set);
            }
            if (!(r->abl[si][k] = measure(r, "ablation", woo92_abl_steps[k].name, "grid-raybox", cum))) return 2;
        }
        if (!(r->t2_old[si] = measure(r, "table2", "old", "grid-raybox", OLD_SETTINGS))) return 2;
        if (!(r->t2_new[si] = measure(r, "table2", "new", "grid-raybox", ""))) return 2;
        if (scene == SC_SPHERES) {
            if (!(r->t4[0] = measure(r, "table4", "new@auto", "grid-raybox", ""))) return 2;
            for (int i = 0; i < 3; i++) {
                int n = w->t4_res[i];
                char variant[32];
                snprintf(variant, sizeof variant, "new@%d", n);
                snprintf(set, sizeof set, "res=%dx%dx%d", n, n, n);
                if (!(r->t4[i + 1] = measure(r, "table4", variant, "grid-raybox", set))) return 2;
            }
        }
        if (scene == SC_LAMP) {
            for (int i = 0; i < 3; i++) {
                if (w->spp[i] != r->spp) prepare_sets(r, c->img_w, c->img_h, w->spp[i], true);
                char v[3][32];
                snprintf(v[0], sizeof v[0], "old@spp%d", w->spp[i]);
                snprintf(v[1], sizeof v[1], "tri@spp%d", w->spp[i]);
                snprintf(v[2], sizeof v[2], "new@spp%d", w->spp[i]);
                if (!(r->t3_old[i] = measure(r, "table3", v[0], "grid-raybox", OLD_SETTINGS))) return 2;
                if (!(r->t3_tri[i] = measure(r, "table3", v[1], "grid-raybox", TRI_SETTINGS))) return 2;
                if (!(r->t3_new[i] = measure(r, "table3", v[2], "grid-raybox", ""))) return 2;
            }
        }
    }
    close_scene(r);
    return 0;
}

static int parse(rp_opts *o, int argc, char **argv)
{
    static const struct option opts[] = {
        {"out", required_argument, NULL, 'o'},  {"threads", required_argument, NULL, 't'},
        {"repeat", required_argument, NULL, 'n'}, {"quick", no_argument, NULL, 'k'},
        {"no-plots", no_argument, NULL, 'P'},   {"quiet", no_argument, NULL, 'q'},
        {"memcap", required_argument, NULL, 'M'},
        {"help", no_argument, NULL, 'h'},       {NULL, 0, NULL, 0},
    };
    uint64_t memcap_mib = 0; /* --memcap MIB; 0: the default (scenes/memory_cap.h) */
    char why[512];
    memset(o, 0, sizeof *o);
    o->threads = 1;
    o->repeat = 3;
    o->plots = true;
    optind = 1;
    opterr = 0;
    int ch;
    while ((ch = getopt_long(argc, argv, "hq", opts, NULL)) != -1) {
        char *end;
        long v;
        switch (ch) {
        case 'o': o->out = optarg; break;
        case 't':
        case 'n':
            errno = 0;
            v = strtol(optarg, &end, 10);
            if (errno || end == optarg || *end || v < 1 || v > (ch == 't' ? 1024 : 1000)) {
                fprintf(stderr, "accelbench reproduce: --%s %s: expected an integer in 1..%d\n", ch == 't' ? "threads" : "repeat",
                        optarg, ch == 't' ? 1024 : 1000);
                return 2;
            }
            if (ch == 't') o->threads = (int)v;
            else o->repeat = (int)v, o->repeat_given = true;
            break;
        case 'k': o->quick = true; break;
        case 'M':
            if (resources_parse_memcap(optarg, &memcap_mib, why, sizeof why)) {
                fprintf(stderr, "accelbench reproduce: %s\n", why);
                return 2;
            }
            break;
        case 'P': o->plots = false; break;
        case 'q': o->quiet = true; break;
        case 'h': reproduce_usage(stdout); return 1;
        default:
            fprintf(stderr, "accelbench reproduce: unknown or incomplete option '%s' (see accelbench reproduce --help)\n",
                    argv[optind - 1]);
            return 2;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "accelbench reproduce: unexpected argument '%s' (see accelbench reproduce --help)\n", argv[optind]);
        return 2;
    }
    if (o->quick && !o->repeat_given) o->repeat = 1;
    /* The memory cap, and the threads' stacks against it (resources.h). */
    memory_cap_set_mib(memcap_mib);
    if (resources_check_threads(o->threads, "--threads", why, sizeof why)) {
        fprintf(stderr, "accelbench reproduce: %s\n", why);
        return 2;
    }
    return 0;
}

static int reproduce_woo92(int argc, char **argv)
{
    rp_run *r = &R;
    memset(r, 0, sizeof *r);
    int rc = parse(&r->o, argc, argv);
    if (rc) return rc == 1 ? 0 : rc;
    if ((rc = load_figures(&r->woo))) return rc;
    /* Woo's image sizes, or small ones for --quick. */
    r->cf = r->o.quick ? (rp_config){64, 64, 80, 60} : (rp_config){r->woo.t1_w, r->woo.t1_h, r->woo.img_w, r->woo.img_h};
    for (int i = 0; i < SC_N; i++) r->label[i] = woo92_scenes[i].load;
    machine_describe(&r->mi);
    char out_dir[1024], path[1200];
    if (output_folder(r->o.out, "woo92-", out_dir, sizeof out_dir)) return 2;
    char csv_path[1200];
    snprintf(csv_path, sizeof csv_path, "%s/woo92.csv", out_dir);
    r->csv = fopen(csv_path, "w");
    if (!r->csv) {
        fprintf(stderr, "accelbench: %s: cannot write: %s\n", csv_path, strerror(errno));
        return 2;
    }
    char header[CSV_HEADER_MAX];
    csv_header(header, sizeof header);
    if (fprintf(r->csv, "table,variant,grid_res,%s\n", header) < 0 || fflush(r->csv) != 0) {
        fprintf(stderr, "accelbench: %s: write failed: %s\n", csv_path, strerror(errno));
        fclose(r->csv);
        return 1;
    }
    r->wall0 = clock_ms();
    if (!r->o.quiet)
        fprintf(stderr, "reproduce woo92: %s mode, timed traces on 1 thread, %d repeat%s, writing %s\n",
                r->o.quick ? "quick" : "default", r->o.repeat, r->o.repeat == 1 ? "" : "s", out_dir);
    rc = run_experiments(r);
    /* Every row went through stdio: its error flag and the close say whether all of them reached the file. */
    bool csv_ok = !ferror(r->csv) && fflush(r->csv) == 0;
    int csv_errno = errno;
    if (fclose(r->csv) != 0 && csv_ok) csv_ok = false, csv_errno = errno;
    if (!csv_ok && rc == 0) {
        fprintf(stderr, "accelbench: %s: write failed: %s\n", csv_path, strerror(csv_errno));
        rc = 1;
    }
    if (rc) {
        close_scene(r);
        figures_free(r->woo.f);
        return rc;
    }
    double wall_s = (clock_ms() - r->wall0) / 1e3;

    char *md = NULL;
    size_t mdlen = 0;
    FILE *f = open_memstream(&md, &mdlen);
    if (!f) checked_alloc_failed(0, "the tables' Markdown (open_memstream)");
    woo92_report(r, f);
    fprintf(f, "Measured in %.0f s (%d measurements). CSV: %s\n", wall_s, r->nmeas, csv_path);
    fclose(f);
    figures_free(r->woo.f);
    fputs(md, stdout);
    fflush(stdout);
    snprintf(path, sizeof path, "%s/woo92_tables.md", out_dir);
    FILE *mf = fopen(path, "w");
    if (!mf) {
        fprintf(stderr, "accelbench: %s: cannot write: %s\n", path, strerror(errno));
        free(md);
        return 2;
    }
    bool md_ok = fputs(md, mf) != EOF && fflush(mf) == 0;
    int md_errno = errno;
    if (fclose(mf) != 0 && md_ok) md_ok = false, md_errno = errno;
    if (!md_ok) {
        fprintf(stderr, "accelbench: %s: write failed: %s\n", path, strerror(md_errno));
        free(md);
        return 1;
    }
    free(md);
    if (!r->o.quiet) fprintf(stderr, "wrote %s and %s (%.1f s)\n", csv_path, path, wall_s);
    if (r->o.plots) run_plot_script("plot_woo92.py", csv_path, r->o.quiet);
    if (r->any_real) {
        fprintf(stderr, "accelbench: reproduce woo92: REAL mismatches against Embree (see above and the Verification table)\n");
        return 1;
    }
    return 0;
}

int reproduce_main(int argc, char **argv)
{
    if (argc < 2) {
        reproduce_usage(stderr);
        return 2;
    }
    const char *exp = argv[1];
    if (!strcmp(exp, "--help") || !strcmp(exp, "-h") || !strcmp(exp, "help")) {
        reproduce_usage(stdout);
        return 0;
    }
    if (!strcmp(exp, "woo92")) return reproduce_woo92(argc - 1, argv + 1);
    fprintf(stderr, "accelbench reproduce: unknown experiment '%s' (known: woo92; see accelbench reproduce --help)\n", exp);
    return 2;
}
