/* wide_traverse_sse42.c: the wide BVH's walk (wide_walk.h) with SSE4.2 box
 * kernels: 4 children per 128-bit register (a BVH8 node in two halves, a
 * BVH2 node's two children in the low lanes of one).
 * Compiled for SSE4.2 by per-function target attributes only, and run only
 * where __builtin_cpu_supports("sse4.2") says so (wide_isa.c). */
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#include <string.h>
#define WIDE_TARGET __attribute__((target("sse4.2")))
#define TRI_PACKET_MT_SSE /* robust=off's packet test on SSE lanes (unfused: no fma here) */
#include "wide_walk.h"

/* Four floats of row `row` from slot `off` (rows `stride` floats apart): a
 * BVH2 row is two floats, loaded as one 64-bit word with the high lanes
 * zero (masked off by the caller); wider rows are 16-byte aligned. */
WIDE_FN __m128 row4(const float *rows, uint32_t row, const uint32_t stride, const uint32_t off)
{
    if (stride == 2) return _mm_castpd_ps(_mm_load_sd((const double *)(rows + row * 2)));
    return _mm_load_ps(rows + row * stride + off);
}

/* Four slots of a quantised node from slot `off`: row `row`'s planes
 * decoded (wide_q_plane: q * scale is exact, so the multiply and add
 * round once, as the scalar kernel's sum does). */
WIDE_FN __m128 row4q(const wide8q_node *nd, uint32_t row, uint32_t ax, const uint32_t off)
{
    int32_t bytes;
    memcpy(&bytes, &nd->q[row][off], 4);
    const __m128 q = _mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(bytes)));
    return _mm_add_ps(_mm_mul_ps(q, _mm_set1_ps(wide_q_scale(nd->scale_exp[ax]))), _mm_set1_ps(nd->origin[ax]));
}

/* Four slots of a node whose rows are `stride` floats apart (or, with q
 * set, of the quantised node q), starting at slot `off`:
 * slab_clip_robust's arithmetic (wide_walk.h), lane by lane. */
WIDE_FN unsigned box4_at(const wide_ray *r, const float *rows, const wide8q_node *q, const uint32_t stride,
                         const uint32_t off, float t0, float t1, float *tn)
{
    __m128 a = _mm_set1_ps(t0), z = _mm_set1_ps(t1);
    for (uint32_t ax = 0; ax < 3; ax++) {
        const __m128 o = _mm_set1_ps(r->org[ax]), inv = _mm_set1_ps(r->inv[ax]),
                     inv_far = _mm_set1_ps(r->inv_far[ax]);
        const __m128 pn = q ? row4q(q, r->near[ax], ax, off) : row4(rows, r->near[ax], stride, off);
        const __m128 pf = q ? row4q(q, r->far[ax], ax, off) : row4(rows, r->far[ax], stride, off);
        __m128 n = _mm_mul_ps(_mm_sub_ps(pn, o), inv);
        __m128 f = _mm_mul_ps(_mm_sub_ps(pf, o), inv_far);
        a = _mm_max_ps(n, a); /* a NaN n keeps a */
        z = _mm_min_ps(f, z);
    }
    __m128 hit = _mm_cmple_ps(a, z);
    _mm_store_ps(tn + off, a); /* at width 2, lanes 2 and 3 of tn[8] are scratch */
    return (unsigned)_mm_movemask_ps(hit) << off;
}

WIDE_FN unsigned box4(const wide_ray *r, const void *node, float t0, float t1, float *tn)
{
    return box4_at(r, &((const wide4_node *)node)->box[0][0], NULL, 4, 0, t0, t1, tn);
}

WIDE_FN unsigned box8(const wide_ray *r, const void *node, float t0, float t1, float *tn)
{
    const float *rows = &((const wide8_node *)node)->box[0][0];
    return box4_at(r, rows, NULL, 8, 0, t0, t1, tn) | box4_at(r, rows, NULL, 8, 4, t0, t1, tn);
}

/* A BVH2 node: both children in the low two lanes. */
WIDE_FN unsigned box2(const wide_ray *r, const void *node, float t0, float t1, float *tn)
{
    return box4_at(r, &((const wide2_node *)node)->box[0][0], NULL, 2, 0, t0, t1, tn) & 3u;
}

/* compress=on: the unused slots, which decode to a box at the node's
 * corner, masked off. */
WIDE_FN unsigned box8q(const wide_ray *r, const void *node, float t0, float t1, float *tn)
{
    const wide8q_node *nd = node;
    const unsigned hit = box4_at(r, NULL, nd, 8, 0, t0, t1, tn) | box4_at(r, NULL, nd, 8, 4, t0, t1, tn);
    return hit & ((1u << nd->nchildren) - 1);
}

WIDE_ENTRY_POINTS(sse2, 2, false, false, box2)
WIDE_ENTRY_POINTS(sse4, 4, false, false, box4)
WIDE_ENTRY_POINTS(sse8, 8, false, false, box8)
WIDE_ENTRY_POINTS(sse8q, 8, true, false, box8q)

/* No fma=on: SSE4.2 has no fused multiply-add. */
const wide_kernels wide_kernels_sse42[WIDE_LAYOUTS][2][2] = {
    {WIDE_KERNELS_RO(sse2)}, {WIDE_KERNELS_RO(sse4)}, {WIDE_KERNELS_RO(sse8)}, {WIDE_KERNELS_RO(sse8q)}};
#endif
