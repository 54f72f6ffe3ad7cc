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
 *   new   grid-raybox defaults at res=auto: Woo's final implementation.
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
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include "../workloads/resources.h"

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
#define OLD_SETTINGS WOO_RES ",raybox=on,mtf=off,dynbox=off,voxbox=off,beta=0,tclip=off,woo90=off,eyeorigin=off,rayid=off"
/* Woo's resolution rule (s8.2), which every variant of his tables uses
 * unless a table names a resolution; `new` is grid-raybox's defaults at it. */
#define WOO_RES "res=auto"
#define NEW_SETTINGS WOO_RES
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

static woo_run R; /* large: static */

void woo92_usage(FILE *out)
{
    fprintf(out,
            "    woo92   A. Woo, \"Ray Tracing Polygons using Spatial Subdivision\", GI 1992:\n"
            "            Table 1 ray box vs raw traversal (spd:balls:4 at Woo's four grid resolutions, primary rays),\n"
            "            Table 2 old (Snyder-Barr) vs new (all of Woo's switches) on three images\n"
            "            (spheres, room, lamp; primary + mirror reflection),\n"
            "            Table 3 the lamp at Woo's three sampling rates (old, tri = s7 only, new),\n"
            "            Table 4 the spheres at the auto grid and Woo's three cubic grids (time, memory),\n"
            "            Ablation: Woo's switches added one at a time on the three images.\n"
            "            Woo's figures and the sizes taken from them: data/woo92_figures.csv.\n"
            "            The room is sibenik@nave, or the stand-in gen:room where Sibenik is not installed.\n"
            "            Every TIMED trace runs on 1 thread whatever --threads is: grid-raybox mutates its\n"
            "            lists and must, so every variant does, for fairness. A few minutes on one core.\n");
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

/* ------------------------------------------------------------ the run */

/* The image's ray sets: primary, and mirror reflection when asked. */
static void prepare_sets(woo_run *r, int w, int h, int spp, bool reflection)
{
    static const char *const workloads[2] = {"primary", "reflection"};
    rp_prepare_sets(&r->k, w, h, spp, false, r->woo.depth, workloads, reflection ? 2 : 1);
}


/* Which ablation row is `new` (grid-raybox defaults at Woo's rule): the
 * cumulative settings of each row against them. */
static int find_new_rows(woo_run *r)
{
    const struct accel_ops *ops = accel_find("grid-raybox");
    accel_params d, p;
    char ds[512], ps[512], err[256], cum[600] = OLD_SETTINGS;
    params_defaults(&d, ops->params);
    params_defaults(&p, ops->params);
    if (params_set_list(&d, NEW_SETTINGS, err, sizeof err)) return 2;
    params_format(&d, ds, sizeof ds);
    if (params_set_list(&p, cum, err, sizeof err)) return 2;
    for (int k = 0; k < ABL_N; k++) {
        if (woo92_abl_steps[k].set[0] && params_set_list(&p, woo92_abl_steps[k].set, err, sizeof err)) return 2;
        params_format(&p, ps, sizeof ps);
        r->abl_is_new[k] = strcmp(ps, ds) == 0;
    }
    return 0;
}

static int run_experiments(woo_run *r)
{
    const rp_config *c = &r->cf;
    const woo_figures *w = &r->woo;
    char set[600];
    /* Table 1: the sphereflake, primary rays, four grids, ray box vs raw. */
    if (rp_open_scene(&r->k, SC_FLAKE)) return 2;
    prepare_sets(r, c->t1_w, c->t1_h, 1, false);
    for (int i = 0; i < 4; i++) {
        char variant[32];
        int n = w->t1_res[i];
        snprintf(variant, sizeof variant, "raybox@%d", n);
        snprintf(set, sizeof set, OLD_SETTINGS ",res=%dx%dx%d", n, n, n);
        if (!(r->t1_raybox[i] = rp_measure(&r->k, "table1", variant, "grid-raybox", set))) return 2;
        snprintf(variant, sizeof variant, "raw@%d", n);
        snprintf(set, sizeof set, "res=%dx%dx%d", n, n, n);
        if (!(r->t1_raw[i] = rp_measure(&r->k, "table1", variant, "grid", set))) return 2;
    }
    if (find_new_rows(r)) return 2;
    /* Tables 2-4 and the ablation: the three images. */
    for (int si = 0; si < 3; si++) {
        int scene = SC_SPHERES + si;
        if (rp_open_scene(&r->k, scene)) return 2;
        prepare_sets(r, c->img_w, c->img_h, 1, true);
        char cum[600] = OLD_SETTINGS;
        for (int k = 0; k < ABL_N; k++) {
            if (woo92_abl_steps[k].set[0]) {
                size_t n = strlen(cum);
                snprintf(cum + n, sizeof cum - n, ",%s", woo92_abl_steps[k].set);
            }
            if (!(r->abl[si][k] = rp_measure(&r->k, "ablation", woo92_abl_steps[k].name, "grid-raybox", cum))) return 2;
        }
        if (!(r->t2_old[si] = rp_measure(&r->k, "table2", "old", "grid-raybox", OLD_SETTINGS))) return 2;
        if (!(r->t2_new[si] = rp_measure(&r->k, "table2", "new", "grid-raybox", NEW_SETTINGS))) return 2;
        if (scene == SC_SPHERES) {
            if (!(r->t4[0] = rp_measure(&r->k, "table4", "new@auto", "grid-raybox", NEW_SETTINGS))) return 2;
            for (int i = 0; i < 3; i++) {
                int n = w->t4_res[i];
                char variant[32];
                snprintf(variant, sizeof variant, "new@%d", n);
                snprintf(set, sizeof set, "res=%dx%dx%d", n, n, n);
                if (!(r->t4[i + 1] = rp_measure(&r->k, "table4", variant, "grid-raybox", set))) return 2;
            }
        }
        if (scene == SC_LAMP) {
            for (int i = 0; i < 3; i++) {
                if (w->spp[i] != r->k.spp) prepare_sets(r, c->img_w, c->img_h, w->spp[i], true);
                char v[3][32];
                snprintf(v[0], sizeof v[0], "old@spp%d", w->spp[i]);
                snprintf(v[1], sizeof v[1], "tri@spp%d", w->spp[i]);
                snprintf(v[2], sizeof v[2], "new@spp%d", w->spp[i]);
                if (!(r->t3_old[i] = rp_measure(&r->k, "table3", v[0], "grid-raybox", OLD_SETTINGS))) return 2;
                if (!(r->t3_tri[i] = rp_measure(&r->k, "table3", v[1], "grid-raybox", TRI_SETTINGS))) return 2;
                if (!(r->t3_new[i] = rp_measure(&r->k, "table3", v[2], "grid-raybox", NEW_SETTINGS))) return 2;
            }
        }
    }
    rp_close_scene(&r->k);
    return 0;
}

int reproduce_woo92(int argc, char **argv)
{
    woo_run *r = &R;
    memset(r, 0, sizeof *r);
    rp_kit *k = &r->k;
    int rc;
    /* grid-raybox mutates its lists: every timed trace on 1 thread. */
    if (!rp_begin(k, "woo92", woo92_scenes, SC_N, 1, argc, argv,
                  "Woo's tables name their own grids (--accels is for spd)", "Woo's tables need all four of his scenes", &rc))
        return rc;
    if ((rc = load_figures(&r->woo))) return rc;
    /* Woo's image sizes, or small ones for --quick. */
    r->cf = k->o.quick ? (rp_config){64, 64, 80, 60} : (rp_config){r->woo.t1_w, r->woo.t1_h, r->woo.img_w, r->woo.img_h};
    if ((rc = rp_start(k))) {
        figures_free(r->woo.f);
        return rc;
    }
    if (!k->o.quiet)
        fprintf(stderr, "reproduce woo92: %s mode, timed traces on 1 thread, %d repeat%s, writing %s\n",
                k->o.quick ? "quick" : "default", k->o.repeat, k->o.repeat == 1 ? "" : "s", k->out_dir);
    rc = run_experiments(r);
    rc = rp_finish(k, rc, woo92_report, r, "plot_woo92.py");
    figures_free(r->woo.f);
    return rc;
}
