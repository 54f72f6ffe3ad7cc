/* wide_traverse_scalar.c: the reference traversal of the wide BVH
 * (isa=scalar): wide_walk.h's walk with one child box at a time, in plain
 * C with no target attribute. The SIMD kernels (wide_traverse_sse42.c,
 * _avx2.c, _avx512.c) must give its hits and counters bit for bit
 * (tests/test_champion.c checks it ray for ray). */
#include "wide_walk.h"

static inline __attribute__((always_inline)) unsigned box4(const wide_ray *r, const void *node, float t0, float t1,
                                                           float *tn)
{
    return wide_box_scalar(r, &((const wide4_node *)node)->box[0][0], 4, t0, t1, tn);
}

static inline __attribute__((always_inline)) unsigned box8(const wide_ray *r, const void *node, float t0, float t1,
                                                           float *tn)
{
    return wide_box_scalar(r, &((const wide8_node *)node)->box[0][0], 8, t0, t1, tn);
}

static inline __attribute__((always_inline)) unsigned box2(const wide_ray *r, const void *node, float t0, float t1,
                                                           float *tn)
{
    return wide_box_scalar(r, &((const wide2_node *)node)->box[0][0], 2, t0, t1, tn);
}

static inline __attribute__((always_inline)) unsigned box8q(const wide_ray *r, const void *node, float t0, float t1,
                                                            float *tn)
{
    return wide_box_scalar_q(r, node, t0, t1, tn);
}

WIDE_ENTRY_POINTS(scalar2, 2, box2)
WIDE_ENTRY_POINTS(scalar4, 4, box4)
WIDE_ENTRY_POINTS(scalar8, 8, box8)
WIDE_ENTRY_POINTS_Q(scalar8q, 8, true, box8q)

const wide_kernels wide_kernels_scalar[3] = {WIDE_KERNELS(scalar4), WIDE_KERNELS(scalar8), WIDE_KERNELS(scalar2)};
const wide_kernels wide_kernels_scalar_q = WIDE_KERNELS(scalar8q);
