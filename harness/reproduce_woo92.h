/* reproduce_woo92.h: what the two halves of `reproduce woo92` share: the
 * measurements (reproduce_woo92.c makes them) and Woo's published figures
 * (data/woo92_figures.csv), which the tables (reproduce_woo92_tables.c)
 * print side by side. Private to those two files. */
#ifndef ACCELBENCH_REPRODUCE_WOO92_H
#define ACCELBENCH_REPRODUCE_WOO92_H

#include <stdbool.h>
#include <stdio.h>
#include "figures.h"
#include "machine.h"
#include "measure.h"

enum { SC_FLAKE, SC_SPHERES, SC_ROOM, SC_LAMP, SC_N };

typedef struct {
    const char *load;    /* scene_load name */
    const char *image;   /* Woo's image it stands for: his Table 1 scene, or a row of his Table 2 */
    const char *why;
    const char *standin; /* generated scene measured when `load` is not on this machine, or NULL */
    const char *standin_why;
} scene_def;

extern const scene_def woo92_scenes[SC_N];

/* The ablation's steps, cumulative, in Woo's order. */
typedef struct { const char *name, *set; } abl_step;
extern const abl_step woo92_abl_steps[];
#define ABL_N 10

/* Woo's figures, from data/woo92_figures.csv: times in seconds except
 * Table 1's (his CPU minutes); Table 2 and 3 arrays in the order of
 * SC_SPHERES..SC_LAMP and of his sampling rows. */
typedef struct {
    figures *f;
    const char *t1_machine, *img_machine;
    int t1_res[4], t1_spheres, t1_w, t1_h;
    double t1_raybox[4], t1_raw[4];
    int img_w, img_h, depth;
    double improve_lo, improve_hi; /* s9.1's "about 9-14%" */
    const char *t2_grid[3];
    double t2_tris[3], t2_isect[3], t2_old[3], t2_new[3];
    const char *t3_rows[3];
    int spp[3];
    double t3_old[3], t3_tri[3], t3_new[3], t3_tri_improve[3], t3_new_improve[3];
    const char *t4_rows[4];
    int t4_res[3]; /* rows 2-4: N of N^3 (row 1 is his auto grid) */
    double t4_time[4], t4_space[4];
} woo_figures;

typedef struct {
    const char *out;
    int threads, repeat;
    bool quick, plots, quiet, repeat_given;
} rp_opts;

typedef struct {
    int t1_w, t1_h;   /* Table 1 image */
    int img_w, img_h; /* Tables 2-4, ablation */
} rp_config;

#define SETS_MAX 2
#define MEAS_MAX 160

/* One measurement: an accelerator configuration on an image's ray sets. */
typedef struct {
    int scene, spp, width, height;
    const struct accel_ops *ops;
    char params[512];
    int nsets;
    csv_row rows[SETS_MAX];
    char workload[SETS_MAX][32];
    int res[3];
    char res_str[40];
    double ms, ms_min, ms_max, build_ms; /* summed over the sets */
    uint64_t rays, mem;
    counters_t c;
    uint64_t agree, mm[MM_CLASSES];
} meas;

typedef struct {
    rp_opts o;
    rp_config cf;
    woo_figures woo;
    machine_info mi;
    FILE *csv;
    meas store[MEAS_MAX];
    int nmeas;
    bool any_real;
    const char *label[SC_N];   /* each scene's CSV name: its load name, or its stand-in's */
    char shown[SC_N][160];     /* its name in the tables, a stand-in marked as one */
    char standin_reason[SC_N][1024]; /* why the stand-in was measured, "" when it was not */
    /* the scene being measured */
    int cur;
    scene_t *s;
    accel *ref;
    verifier_t *ver;           /* the scene's exact judge, shared by its measurements */
    int nsets, spp, width, height;
    cell_rays cells[SETS_MAX];
    /* the tables */
    meas *t1_raybox[4], *t1_raw[4];
    meas *t2_old[3], *t2_new[3];
    meas *t3_old[3], *t3_tri[3], *t3_new[3];
    meas *t4[4];
    meas *abl[3][ABL_N];
    bool abl_is_new[ABL_N];
    double wall0;
} rp_run;

/* The report: every table, finding and the verification summary. */
void woo92_report(rp_run *r, FILE *f);

#endif
