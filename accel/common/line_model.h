/* line_model.h: the random-line cost model of the spatial subdivisions
 * (grid, octree, kd-tree): their counters per ray predicted from the built
 * cells, without tracing. Used by grid_woo.c, octree_glassner.c and
 * bsp_kaplan_jansen.c; the hierarchies have their own walks of the same
 * argument (bvh_gs/nary.c, bvh_wide/wide_predict.c).
 *
 * The argument (J. G. Cleary and G. Wyvill, "Analysis of an algorithm for
 * fast ray tracing using uniform space subdivision", The Visual Computer
 * 4(2), 1988; J. D. MacDonald and K. S. Booth, The Visual Computer 6(3),
 * 1990): of the random lines that meet a convex body R, those that also
 * meet a convex body C inside it are the fraction A(C) / A(R), A the
 * surface area (Cauchy-Crofton). The lines are uniform over those that
 * meet R (isotropic directions, uniform positions); a walk over such a line
 * enters every cell the line meets and, with nothing hit, tests each cell's
 * list, so per line that meets the root box R:
 *   cells entered  = sum over cells of P(cell)
 *   list entries   = sum over cells of P(cell) count(cell)
 *   tests, mailbox = sum over primitives of P(line meets the union of the
 *                    cells that list it), bounded above by the smaller of
 *                    P(the box of those cells) and the primitive's share of
 *                    list entries; the bound is what is reported: exact
 *                    when the cells that list a primitive make a box (a
 *                    primitive inside one cell, or one across a plane of
 *                    equal neighbours), high for a long primitive across
 *                    many cells;
 *   mailbox hits   = list entries - tests.
 * For a uniform grid of n_a cells per axis over a box of face areas F_a,
 * cells entered = 1 + sum_a (n_a - 1) 2 F_a / A(R): each inner plane is a
 * flat convex body of area 2 F_a (Cleary and Wyvill's count of planes
 * crossed). Over those lines a walk that stops at a hit does at most this
 * work; real rays are not those lines (they start on surfaces or at one
 * eye, stop at hits, gather where the scene is), so how far each workload
 * departs is measured (each docs/accels page, "Cost model"). */
#ifndef ACCELBENCH_LINE_MODEL_H
#define ACCELBENCH_LINE_MODEL_H

#include <stdbool.h>
#include <stdint.h>
#include "../../prims/vec3.h"

typedef struct {
    double root_area;  /* A(R); 0: every line that meets R meets every cell */
    bool mailbox;      /* count each primitive once per line */
    uint32_t nprims;
    box3 *hull;        /* mailbox: per primitive, the box of its cells */
    double *share;     /* mailbox: per primitive, its sum of P(cell) */
    double cells;      /* sum of P(cell) over the cells added */
    double entries;    /* sum of P(cell) count(cell) */
    double deep_cells; /* sum of P(cell) (depth(cell) + 1): root-to-cell descents */
} line_model;

typedef struct {
    double cells, entries, tests, mailbox_hits, descents;
} line_prediction;

/* Zero on success, -1 when the mailbox arrays cannot be allocated. */
int line_model_init(line_model *m, box3 root, uint32_t nprims, bool mailbox);
/* P(a random line meeting R meets b). */
double line_model_prob(const line_model *m, box3 b);
/* A cell (leaf or empty voxel) at depth (root 0; grids 0) and its list. */
void line_model_cell(line_model *m, box3 cell, int depth, const uint32_t *ids, uint32_t count);
line_prediction line_model_result(const line_model *m);
void line_model_free(line_model *m);

#endif
