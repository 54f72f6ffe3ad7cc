/* bvh_wide.h: what tests may see of `bvh` (accel/bvh_wide/bvh_wide.c)
 * beyond the accel.h interface. */
#ifndef ACCELBENCH_BVH_CHAMPION_H
#define ACCELBENCH_BVH_CHAMPION_H

#include "../accel.h"
#include "wide.h"

/* The wide tree of a built `bvh`, and (isa not NULL) the instruction set
 * its kernels were chosen for. */
const wide_bvh *bvh_wide_tree(const accel *a, wide_isa *isa);

#endif
