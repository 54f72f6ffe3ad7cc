/* wide_traverse_scalar.c: the reference traversal of the wide BVH
 * (isa=scalar): wide_walk.h's walk with one child box at a time, in plain
 * C with no target attribute, with fma=off's arithmetic and with fma=on's
 * (fmaf: exact, as the SIMD kernels' instruction is). The SIMD kernels
 * (wide_traverse_sse42.c, _avx2.c, _avx512.c) must give its hits and
 * counters bit for bit (tests/test_champion.c checks it ray for ray).
 * robust=off's packet test here is prims/tri_packet_mt.h's reference, the
 * lanes one at a time in plain C (fmaf under fma=on). */
#include <string.h>
#include "wide_walk.h"

/* The kernels of one layout with and without fma: NAME(r, node, t0, t1, tn). */
#define SCALAR_BOX(NAME, NODE, W)                                                                                      \
    static inline __attribute__((always_inline)) unsigned NAME(const wide_ray *r, const void *node, float t0,         \
                                                               float t1, float *tn)                                    \
    {                                                                                                                  \
        return wide_box_scalar(r, &((const NODE *)node)->box[0][0], W, t0, t1, tn, false);                            \
    }                                                                                                                  \
    static inline __attribute__((always_inline)) unsigned NAME##f(const wide_ray *r, const void *node, float t0,      \
                                                                  float t1, float *tn)                                 \
    {                                                                                                                  \
        return wide_box_scalar(r, &((const NODE *)node)->box[0][0], W, t0, t1, tn, true);                             \
    }
SCALAR_BOX(box2, wide2_node, 2)
SCALAR_BOX(box4, wide4_node, 4)
SCALAR_BOX(box8, wide8_node, 8)

static inline __attribute__((always_inline)) unsigned box8q(const wide_ray *r, const void *node, float t0, float t1,
                                                            float *tn)
{
    return wide_box_scalar_q(r, node, t0, t1, tn, false);
}
static inline __attribute__((always_inline)) unsigned box8qf(const wide_ray *r, const void *node, float t0, float t1,
                                                             float *tn)
{
    return wide_box_scalar_q(r, node, t0, t1, tn, true);
}

WIDE_ENTRY_POINTS(scalar2, 2, false, false, box2)
WIDE_ENTRY_POINTS(scalar4, 4, false, false, box4)
WIDE_ENTRY_POINTS(scalar8, 8, false, false, box8)
WIDE_ENTRY_POINTS(scalar8q, 8, true, false, box8q)
WIDE_ENTRY_POINTS(scalar2f, 2, false, true, box2f)
WIDE_ENTRY_POINTS(scalar4f, 4, false, true, box4f)
WIDE_ENTRY_POINTS(scalar8f, 8, false, true, box8f)
WIDE_ENTRY_POINTS(scalar8qf, 8, true, true, box8qf)

const wide_kernels wide_kernels_scalar[WIDE_LAYOUTS][2][2] = {
    {WIDE_KERNELS_RO(scalar2), WIDE_KERNELS_RO(scalar2f)},
    {WIDE_KERNELS_RO(scalar4), WIDE_KERNELS_RO(scalar4f)},
    {WIDE_KERNELS_RO(scalar8), WIDE_KERNELS_RO(scalar8f)},
    {WIDE_KERNELS_RO(scalar8q), WIDE_KERNELS_RO(scalar8qf)},
};

unsigned wide_box_probe(const ray_t *ray, box3 box, bool fused)
{
    wide8_node nd;
    memset(&nd, 0, sizeof nd);
    const float lo[3] = {box.lo.x, box.lo.y, box.lo.z}, hi[3] = {box.hi.x, box.hi.y, box.hi.z};
    for (uint32_t k = 0; k < 8; k++)
        for (uint32_t ax = 0; ax < 3; ax++) {
            nd.box[2 * ax][k] = k ? INFINITY : lo[ax]; /* slots 1..7 empty */
            nd.box[2 * ax + 1][k] = k ? -INFINITY : hi[ax];
        }
    wide_ray r;
    float tn[8];
    if (!wide_ray_init(&r, ray, fused, true)) return 0;
    return wide_box_scalar(&r, &nd.box[0][0], 8, r.t0, r.tfar, tn, fused);
}
