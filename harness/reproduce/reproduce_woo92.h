/* reproduce_woo92.h: what the two halves of `reproduce woo92` share: the
 * measurements (reproduce_woo92.c makes them) and Woo's published figures
 * (data/woo92_figures.csv), which the tables (reproduce_woo92_tables.c)
 * print side by side. Private to those two files. */
#ifndef ACCELBENCH_REPRODUCE_WOO92_H
#define ACCELBENCH_REPRODUCE_WOO92_H

#include <stdbool.h>
#include <stdio.h>
#include "figures.h"
#include "reproduce_kit.h"

enum { SC_FLAKE, SC_SPHERES, SC_ROOM, SC_LAMP, SC_N };

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
    int t1_w, t1_h;   /* Table 1 image */
    int img_w, img_h; /* Tables 2-4, ablation */
} rp_config;

typedef struct {
    rp_kit k; /* options, scenes, measurements, CSV (reproduce_kit.h) */
    rp_config cf;
    woo_figures woo;
    /* the tables */
    meas *t1_raybox[4], *t1_raw[4];
    meas *t2_old[3], *t2_new[3];
    meas *t3_old[3], *t3_tri[3], *t3_new[3];
    meas *t4[4];
    meas *abl[3][ABL_N];
    bool abl_is_new[ABL_N];
} woo_run;

/* The report: every table, finding and the verification summary. */
void woo92_report(void *woo_run, FILE *f);

#endif
