/* reproduce_havran.c: `accelbench reproduce havran`: the SPD experiments of
 *   V. Havran and F. Sixta, "Comparison of Hierarchical Grids", Ray Tracing
 *     News 12(1), 1999 (uniform grids at voxel densities D = 1 and D = 20),
 *   V. Havran, "A Summary of Octree Ray Traversal Algorithms", Ray Tracing
 *     News 12(2), 1999 (OCTREE84-C: Glassner with centre subdivision, and
 *     OCTREE84-A: the same with a cost-based subdivision, at maximum depths
 *     4-7),
 * re-run on the same eight SPD databases at their default sizes with our
 * grid (res=cubic:D), octree (term=const|cost) and, where Havran's thesis
 * (2000) goes beyond what those articles print, our BSPs (Kaplan's midpoint
 * tree traversed sequentially and recursively, and an SAH kd-tree). This
 * file sets up and measures; reproduce_havran_tables.c prints the report.
 * Their numbers and the experiment's shape (image size, recursion depth,
 * densities, depths, the subdivision threshold) come from
 * data/havran_figures.csv, which scripts/plot_havran.py reads too.
 *
 * Their seconds are of a Pentium II with a full renderer (GOLEM); ours are
 * milliseconds of ray casting alone on another machine: only RATIOS
 * between techniques on the same scene, and orderings, are compared.
 *
 * Rays (their T_TR: 513x513 primary rays and the SPD ray tree to depth 4):
 * the primary rays through the (512+1)x(512+1) pixel corners, the `shadow`
 * workload (every primary hit to every light) and the `reflection`
 * workload (mirror bounces of every hit, generations 1..4). Their ray tree
 * follows the materials (reflection and refraction only where the surface
 * has them); ours bounces every hit, so our reflection set is larger and
 * has no refracted rays. An image's time is the sum of the three sets'
 * medians.
 *
 * Variants per scene:
 *   D1, D20         grid res=cubic:1 and res=cubic:20 (cubic voxels, about
 *                   D x N of them: their "heterogeneous" grid)
 *   O84-C@d         octree maxdepth=d, maxprims=1 (subdivide a node of 2 or
 *                   more objects, as theirs), term=const, for d = 4..7
 *   O84-A@d         the same with term=cost: MacDonald-Booth's cost stop
 *                   with centre planes, NOT the Octree-R plane search their
 *                   O84-A used (accel/octree_glassner.c says why)
 *   BSP-seq, BSP-rec  bsp split=midpoint, traverse=sequential / recursive
 *   BSP-SAH         bsp split=sah (traverse=recursive)
 * None of these mutates while tracing, so the timed traces run on
 * --threads (default 1), Embree's paired samples too.
 *
 * Output folder (default results/havran-<date-time>): havran.csv (the run
 * CSV's columns preceded by table, variant, grid_res; one row per
 * (table, variant, scene, workload)), havran_tables.md and havran_*.png.
 * Exit status: 0, 1 when any measurement had a real mismatch, 2 bad input. */
#include "reproduce.h"
#include "reproduce_havran.h"

#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#include <stdlib.h>
#include <string.h>

#define FIGURES_PATH ACCELBENCH_SOURCE_DIR "/data/havran_figures.csv"

const scene_def havran_scenes[HV_SCENES] = {
    {"spd:balls", "balls", "sphereflake, 7382 objects", NULL, NULL},
    {"spd:gears", "gears", "SIZE^3 gears, 9345 objects, some glass", NULL, NULL},
    {"spd:lattice", "lattice", "spheres and cylinders on a lattice, 8281 objects", NULL, NULL},
    {"spd:mount", "mount", "fractal mountain and four glass spheres, 8196 objects", NULL, NULL},
    {"spd:rings", "rings", "pyramid of rings, 8401 objects", NULL, NULL},
    {"spd:teapot", "teapot", "the teapot on a checkerboard, 9264 objects", NULL, NULL},
    {"spd:tetra", "tetra", "Sierpinski tetrahedron, 4096 triangles", NULL, NULL},
    {"spd:tree", "tree", "Aono-Kunii tree, 8191 objects, a sparse scene", NULL, NULL},
};

static havran_run R; /* large: static */

void havran_usage(FILE *out)
{
    fprintf(out,
            "    havran  V. Havran and F. Sixta, \"Comparison of Hierarchical Grids\", RTN 12(1) 1999, and V. Havran,\n"
            "            \"A Summary of Octree Ray Traversal Algorithms\", RTN 12(2) 1999, on the eight SPD\n"
            "            databases at default sizes, 513x513 corner rays + shadow + mirror reflection to depth 4:\n"
            "            the uniform grid at D = 1 and D = 20 voxels per object, octrees O84-C and O84-A at maximum\n"
            "            depths 4-7, and our BSPs (midpoint sequential and recursive, SAH), as ratios between\n"
            "            techniques on each scene next to theirs. Their figures: data/havran_figures.csv.\n"
            "            Timed traces run on --threads. About 20 minutes on one core.\n");
}

/* ------------------------------------------------------------ their figures */

static int load_figures(havran_figures *h)
{
    char err[512];
    memset(h, 0, sizeof *h);
    figures *f = h->f = figures_load(FIGURES_PATH, err, sizeof err);
    if (!f) {
        fprintf(stderr, "accelbench: reproduce havran: %s\n", err);
        return 2;
    }
    h->grid_source = figures_text(f, "grids", "all", "source");
    h->grid_machine = figures_text(f, "grids", "all", "machine");
    h->oct_source = figures_text(f, "octrees", "all", "source");
    h->oct_machine = figures_text(f, "octrees", "all", "machine");
    const char *img = figures_text(f, "grids", "all", "image_res");
    h->depth = (int)figures_number(f, "grids", "all", "recursion_depth");
    h->dens_low = (int)figures_number(f, "grids", "all", "density_low");
    h->dens_high = (int)figures_number(f, "grids", "all", "density_high");
    h->depth_min = (int)figures_number(f, "octrees", "all", "depth_min");
    int depth_max = (int)figures_number(f, "octrees", "all", "depth_max");
    h->subdivide_at = (int)figures_number(f, "octrees", "all", "subdivide_at");
    for (int i = 0; i < HV_SCENES; i++) {
        const char *row = havran_scenes[i].image;
        h->d1_build[i] = figures_number(f, "grids", row, "d1_build");
        h->d1_trace[i] = figures_number(f, "grids", row, "d1_trace");
        h->d20_build[i] = figures_number(f, "grids", row, "d20_build");
        h->d20_trace[i] = figures_number(f, "grids", row, "d20_trace");
        for (int d = 0; d < HV_DEPTHS; d++) {
            char q[32];
            snprintf(q, sizeof q, "o84c_d%d", h->depth_min + d);
            h->o84c[i][d] = figures_number(f, "octrees", row, q);
            snprintf(q, sizeof q, "o84a_d%d", h->depth_min + d);
            h->o84a[i][d] = figures_number(f, "octrees", row, q);
        }
    }
    const char *bad = figures_missing(f);
    if (!bad && (!img || sscanf(img, "%dx%d", &h->img_w, &h->img_h) != 2 || h->img_w < 2 || h->img_h < 2))
        bad = "grids,all,image_res as WxH";
    if (!bad && (depth_max - h->depth_min + 1 != HV_DEPTHS)) bad = "octrees,all,depth_min..depth_max: 4 depths";
    if (!bad && (h->depth < 1 || h->dens_low < 1 || h->dens_high < 1 || h->subdivide_at < 1))
        bad = "recursion_depth, density_low, density_high, subdivide_at >= 1";
    if (bad) {
        fprintf(stderr, "accelbench: reproduce havran: %s: no usable figure %s\n", FIGURES_PATH, bad);
        return 2;
    }
    return 0;
}

/* ------------------------------------------------------------ the run */

static int run_experiments(havran_run *r)
{
    static const char *const workloads[3] = {"primary", "shadow", "reflection"};
    const havran_figures *h = &r->hf;
    rp_kit *k = &r->k;
    char set[128], variant[32];
    for (int si = 0; si < HV_SCENES; si++) {
        if (!r->use[si]) continue;
        if (rp_open_scene(k, si)) return 2;
        /* their WxH rays through pixel corners: a (W-1)x(H-1) image with corners */
        rp_prepare_sets(k, r->img_w - 1, r->img_h - 1, 1, true, h->depth, workloads, 3);
        snprintf(set, sizeof set, "res=cubic:%d", h->dens_low);
        if (!(r->d1[si] = rp_measure(k, "grids", "D1", "grid", set))) return 2;
        snprintf(set, sizeof set, "res=cubic:%d", h->dens_high);
        if (!(r->d20[si] = rp_measure(k, "grids", "D20", "grid", set))) return 2;
        for (int d = 0; d < HV_DEPTHS; d++) {
            int depth = h->depth_min + d;
            snprintf(variant, sizeof variant, "O84-C@%d", depth);
            snprintf(set, sizeof set, "maxdepth=%d,maxprims=%d,term=const", depth, h->subdivide_at - 1);
            if (!(r->oc[si][d] = rp_measure(k, "octrees", variant, "octree", set))) return 2;
            snprintf(variant, sizeof variant, "O84-A@%d", depth);
            snprintf(set, sizeof set, "maxdepth=%d,maxprims=%d,term=cost", depth, h->subdivide_at - 1);
            if (!(r->oa[si][d] = rp_measure(k, "octrees", variant, "octree", set))) return 2;
        }
        if (!(r->bsp_seq[si] = rp_measure(k, "bsp", "BSP-seq", "bsp", "split=midpoint,traverse=sequential"))) return 2;
        if (!(r->bsp_rec[si] = rp_measure(k, "bsp", "BSP-rec", "bsp", "split=midpoint,traverse=recursive"))) return 2;
        if (!(r->bsp_sah[si] = rp_measure(k, "bsp", "BSP-SAH", "bsp", "split=sah,traverse=recursive"))) return 2;
    }
    rp_close_scene(k);
    return 0;
}

int reproduce_havran(int argc, char **argv)
{
    havran_run *r = &R;
    memset(r, 0, sizeof *r);
    rp_kit *k = &r->k;
    int rc;
    /* Nothing here mutates while tracing: timed on --threads. */
    if (!rp_begin(k, "havran", havran_scenes, HV_SCENES, 0, argc, argv,
                  "Havran's tables name their own structures (--accels is for spd)", NULL, &rc))
        return rc;
    if ((rc = rp_select_scenes(k, r->use))) return rc;
    if ((rc = load_figures(&r->hf))) return rc;
    /* Their 513x513 rays, or 33x33 for --quick. */
    r->img_w = k->o.quick ? 33 : r->hf.img_w;
    r->img_h = k->o.quick ? 33 : r->hf.img_h;
    if ((rc = rp_start(k))) {
        figures_free(r->hf.f);
        return rc;
    }
    if (!k->o.quiet)
        fprintf(stderr, "reproduce havran: %s mode, %dx%d corner rays + shadow + reflection to depth %d, timed on %d thread%s, "
                        "%d repeat%s, writing %s\n",
                k->o.quick ? "quick" : "default", r->img_w, r->img_h, r->hf.depth, k->timed_threads,
                k->timed_threads == 1 ? "" : "s", k->o.repeat, k->o.repeat == 1 ? "" : "s", k->out_dir);
    rc = run_experiments(r);
    rc = rp_finish(k, rc, havran_report, r, "plot_havran.py");
    figures_free(r->hf.f);
    return rc;
}
