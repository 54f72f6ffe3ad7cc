/* reproduce_havran.h: what the two halves of `reproduce havran` share:
 * the measurements (reproduce_havran.c makes them) and Havran's published
 * figures (data/havran_figures.csv), which the tables
 * (reproduce_havran_tables.c) print side by side. Private to those two. */
#ifndef ACCELBENCH_REPRODUCE_HAVRAN_H
#define ACCELBENCH_REPRODUCE_HAVRAN_H

#include "figures.h"
#include "reproduce_kit.h"

#define HV_SCENES 8 /* the SPD databases both articles traced (their ninth, "fluid", is their own) */
#define HV_DEPTHS 4 /* the octrees' maximum depths, 4..7 */

extern const scene_def havran_scenes[HV_SCENES];

/* Their figures: T_B and T_TR in seconds of a Pentium II. */
typedef struct {
    figures *f;
    const char *grid_source, *grid_machine, *oct_source, *oct_machine;
    int img_w, img_h, depth;      /* 513x513 rays, recursion depth 4 */
    int dens_low, dens_high;      /* voxels per object, D = 1 and D = 20 */
    int depth_min, subdivide_at;  /* octree depths depth_min..+HV_DEPTHS-1; subdivide at >= this many objects */
    double d1_build[HV_SCENES], d1_trace[HV_SCENES], d20_build[HV_SCENES], d20_trace[HV_SCENES];
    double o84c[HV_SCENES][HV_DEPTHS], o84a[HV_SCENES][HV_DEPTHS];
} havran_figures;

typedef struct {
    rp_kit k; /* options, scenes, measurements, CSV (reproduce_kit.h) */
    havran_figures hf;
    bool use[HV_SCENES]; /* the scenes measured (--scenes); the tables skip the others */
    int img_w, img_h; /* the primary image: (img_w + 1) x (img_h + 1) rays through pixel corners */
    /* the tables */
    meas *d1[HV_SCENES], *d20[HV_SCENES];
    meas *oc[HV_SCENES][HV_DEPTHS], *oa[HV_SCENES][HV_DEPTHS];
    meas *bsp_seq[HV_SCENES], *bsp_rec[HV_SCENES], *bsp_sah[HV_SCENES];
} havran_run;

/* The report: every table, finding and the verification summary. */
void havran_report(void *havran_run, FILE *f);

#endif
