/* float_res.h: the finest subdivision float coordinates can resolve.
 *
 * Float coordinates of magnitude up to M lie at most M * 2^-23 apart (one
 * float step). The spatial builders (grid, octree, kd-trees) grow every
 * cell by an insertion slack pad of 2e-6 M + 1e-6 diagonal (about 16 float
 * steps), so that a primitive within rounding of a plane is on both sides.
 * An object a unit across placed 1e5 units from the origin has M = 1e5 and
 * pad = 0.2: a cell of its own size's subdivision is then narrower than the
 * slack, every primitive lands in every nearby cell, and splitting further
 * only copies lists (the grid's list entries and the kd-tree's depth grow
 * without bound). So no builder makes a cell narrower than
 * float_res_min_cell(): FLOAT_RES_PADS slacks and FLOAT_RES_STEPS float
 * steps of the coordinates, whichever is wider. For a scene around the
 * origin it is far below the cells any builder makes (4 pads are at most
 * 1.2e-5 of its diagonal), so only subdivision that float coordinates at
 * the scene's position could not tell apart is cut. */
#ifndef ACCELBENCH_FLOAT_RES_H
#define ACCELBENCH_FLOAT_RES_H

#include <float.h>
#include <math.h>
#include "../../prims/prims.h"

#define FLOAT_RES_PADS 4.0f
#define FLOAT_RES_STEPS 64.0f

/* The largest coordinate magnitude of b. */
static inline float float_res_magnitude(box3 b)
{
    return fmaxf(fmaxf(fabsf(b.lo.x), fmaxf(fabsf(b.lo.y), fabsf(b.lo.z))),
                 fmaxf(fabsf(b.hi.x), fmaxf(fabsf(b.hi.y), fabsf(b.hi.z))));
}

/* The narrowest cell a builder may make inside box b whose insertion slack
 * is pad: FLOAT_RES_PADS pads, at least FLOAT_RES_STEPS float steps of b's
 * largest coordinate. */
static inline float float_res_min_cell(box3 b, float pad)
{
    return fmaxf(FLOAT_RES_PADS * pad, FLOAT_RES_STEPS * FLT_EPSILON * float_res_magnitude(b));
}

#endif
