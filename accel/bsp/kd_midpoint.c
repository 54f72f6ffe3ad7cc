/* kd_midpoint.c: Kaplan's BSP build (M. R. Kaplan, "Space-Tracing: A
 * Constant Time Ray-Tracer", SIGGRAPH '85 course notes "State of the Art
 * in Image Synthesis"; as the survey of Arvo and Kirk 1989 describes it in
 * s5.1): axis-orthogonal planes through the cell's spatial midpoint, the
 * axes taken in turn, so the subdivision is nearly the octree's (three
 * levels of BSP are one octree level), with explicit children instead of
 * hashed names.
 *
 * A cell's candidates are the primitives whose SURFACE touches it (the
 * survey s5: "objects which intersect the voxels"), tested exactly with
 * prim_overlaps_box on the child cells grown by the tree's pad (kd_tree.h),
 * so one lying in, touching or passing within rounding of the plane is in
 * both children; primitives whose bounds end more than pad below the
 * plane go below without a test (and likewise above). A cell is a leaf when it has at most
 * maxprims candidates, coincident ones counted once (coincident.h: copies of
 * a triangle fall on both sides of every plane through it, so no midpoint
 * separates them), at maxdepth, or when no axis can be halved into
 * children at least float_res_min_cell() wide (4 pads, 64 float steps of
 * the root's coordinates: float_res.h); an axis too narrow for that is
 * skipped for the next one in turn. Far from the origin the slack would
 * otherwise copy every candidate into both halves down to maxdepth.
 *
 * Scratch: the candidate lists of the cells on the current path and of the
 * above siblings waiting for their turn, charged against the memory cap. */
#include <stdlib.h>
#include "../common/float_res.h"
#include "kd_build.h"

static void build(kd_builder *b, box3 cell, uint32_t *ids, uint32_t n, int depth)
{
    const kd_config *cfg = b->cfg;
    const prims_t *p = b->p;
    if (b->failed) return;
    /* The axis in turn, or the next one whose halves float coordinates still resolve (common/float_res.h);
     * a leaf when none does. */
    float minw = float_res_min_cell(b->t->box, b->t->pad), lo = 0, hi = 0, s = 0;
    int axis = depth % 3, tries = 0;
    for (; tries < 3; tries++, axis = (axis + 1) % 3) {
        lo = kd_get(cell.lo, axis), hi = kd_get(cell.hi, axis);
        s = lo + 0.5f * (hi - lo);
        if (s - lo >= minw && hi - s >= minw) break;
    }
    if (prim_classes_at_most(&b->classes, ids, n, (uint64_t)(cfg->maxprims < 0 ? 0 : cfg->maxprims)) ||
        depth >= cfg->maxdepth || tries == 3) {
        kd_emit_leaf(b, ids, n, depth);
        return;
    }
    box3 below = cell, above = cell;
    kd_set(&below.hi, axis, s);
    kd_set(&above.lo, axis, s);
    float pad = b->t->pad;
    box3 gbelow = kd_box_pad(below, pad), gabove = kd_box_pad(above, pad);

    /* Classify into two lists (the above one kept while the below subtree
     * is built). */
    uint32_t *l = kd_scratch_alloc(b, n, sizeof *l), *r = kd_scratch_alloc(b, n, sizeof *r);
    if (!l || !r) {
        kd_scratch_free(b, l, n, sizeof *l);
        kd_scratch_free(b, r, n, sizeof *r);
        return;
    }
    uint32_t nl = 0, nr = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t id = ids[i];
        box3 bb = prim_bounds(p, id);
        float blo = kd_get(bb.lo, axis), bhi = kd_get(bb.hi, axis);
        /* A candidate touches the grown cell, the union of the grown halves. */
        if (bhi < s - pad) l[nl++] = id;      /* it misses the grown above half */
        else if (blo > s + pad) r[nr++] = id; /* it misses the grown below half */
        else {
            if (prim_overlaps_box(p, id, gbelow)) l[nl++] = id;
            if (prim_overlaps_box(p, id, gabove)) r[nr++] = id;
        }
    }

    uint32_t node = kd_emit_interior(b, axis, s);
    build(b, below, l, nl, depth + 1);
    kd_scratch_free(b, l, n, sizeof *l);
    kd_link_above(b, node);
    build(b, above, r, nr, depth + 1);
    kd_scratch_free(b, r, n, sizeof *r);
}

void kd_build_midpoint(kd_builder *b)
{
    uint32_t n = b->p->count;
    uint32_t *ids = kd_scratch_alloc(b, n, sizeof *ids);
    if (!ids) return;
    for (uint32_t i = 0; i < n; i++) ids[i] = i;
    build(b, b->t->box, ids, n, 0);
    kd_scratch_free(b, ids, n, sizeof *ids);
}
