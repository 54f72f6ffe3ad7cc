/* wide_traverse_avx2.c: the wide BVH's walk (wide_walk.h) with AVX2 box
 * kernels: a BVH8 node's 8 children in one 256-bit register, a BVH4 node's
 * 4 in a 128-bit one (VEX-encoded). Compiled for AVX2 and FMA by
 * per-function target attributes only (the build does not contract, and
 * the one FMA intrinsic, compress=on's plane decoding, has an exact
 * product, so distances stay the scalar kernel's), run only where
 * __builtin_cpu_supports says so (wide_isa.c). */
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define WIDE_TARGET __attribute__((target("avx2,fma")))
#include "wide_walk.h"
#include "wide_box8_avx.h"

WIDE_FN unsigned box4(const wide_ray *r, const void *node, float t0, float t1, float *tn)
{
    const float *rows = &((const wide4_node *)node)->box[0][0];
    __m128 a = _mm_set1_ps(t0), z = _mm_set1_ps(t1);
    for (uint32_t ax = 0; ax < 3; ax++) {
        const __m128 o = _mm_set1_ps(r->org[ax]), inv = _mm_set1_ps(r->inv[ax]),
                     inv_far = _mm_set1_ps(r->inv_far[ax]);
        __m128 n = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows + r->near[ax] * 4), o), inv);
        __m128 f = _mm_mul_ps(_mm_sub_ps(_mm_load_ps(rows + r->far[ax] * 4), o), inv_far);
        a = _mm_max_ps(n, a); /* a NaN n keeps a */
        z = _mm_min_ps(f, z);
    }
    __m128 hit = _mm_cmp_ps(a, z, _CMP_LE_OQ);
    _mm_store_ps(tn, a);
    return (unsigned)_mm_movemask_ps(hit);
}

WIDE_FN unsigned box8(const wide_ray *r, const void *node, float t0, float t1, float *tn)
{
    __m256 z, a = wide_interval8(r, &((const wide8_node *)node)->box[0][0], NULL, t0, t1, &z);
    const unsigned hit = (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(a, z, _CMP_LE_OQ));
    _mm256_store_ps(tn, a);
    return hit;
}

/* compress=on: the unused slots, which decode to a box at the node's
 * corner, masked off. */
WIDE_FN unsigned box8q(const wide_ray *r, const void *node, float t0, float t1, float *tn)
{
    const wide8q_node *q = node;
    __m256 z, a = wide_interval8(r, NULL, q, t0, t1, &z);
    const unsigned hit = (unsigned)_mm256_movemask_ps(_mm256_cmp_ps(a, z, _CMP_LE_OQ));
    _mm256_store_ps(tn, a);
    return hit & ((1u << q->nchildren) - 1);
}

WIDE_ENTRY_POINTS(avx2_4, 4, box4)
WIDE_ENTRY_POINTS(avx2_8, 8, box8)
WIDE_ENTRY_POINTS_Q(avx2_8q, 8, true, box8q)

const wide_kernels wide_kernels_avx2[2] = {WIDE_KERNELS(avx2_4), WIDE_KERNELS(avx2_8)};
const wide_kernels wide_kernels_avx2_q = WIDE_KERNELS(avx2_8q);
#endif
