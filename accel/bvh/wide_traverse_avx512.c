/* wide_traverse_avx512.c: the wide BVH's walk (wide_walk.h) with AVX-512
 * box kernels: the AVX2 arithmetic on 128- and 256-bit registers
 * (AVX-512VL), the comparison into a mask register instead of
 * vector masks and a movemask. Compiled for AVX-512F and VL by
 * per-function target attributes only, run only where
 * __builtin_cpu_supports says so (wide_isa.c). */
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define WIDE_TARGET __attribute__((target("avx512f,avx512vl,avx2,fma")))
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
    __mmask8 hit = _mm_cmp_ps_mask(a, z, _CMP_LE_OQ);
    _mm_store_ps(tn, a);
    return hit;
}

WIDE_FN unsigned box8(const wide_ray *r, const void *node, float t0, float t1, float *tn)
{
    __m256 z, a = wide_interval8(r, &((const wide8_node *)node)->box[0][0], NULL, t0, t1, &z);
    const unsigned hit = _mm256_cmp_ps_mask(a, z, _CMP_LE_OQ);
    _mm256_store_ps(tn, a);
    return hit;
}

/* compress=on: the unused slots, which decode to a box at the node's
 * corner, masked off. */
WIDE_FN unsigned box8q(const wide_ray *r, const void *node, float t0, float t1, float *tn)
{
    const wide8q_node *q = node;
    __m256 z, a = wide_interval8(r, NULL, q, t0, t1, &z);
    const unsigned hit = _mm256_cmp_ps_mask(a, z, _CMP_LE_OQ);
    _mm256_store_ps(tn, a);
    return hit & ((1u << q->nchildren) - 1);
}

WIDE_ENTRY_POINTS(avx512_4, 4, box4)
WIDE_ENTRY_POINTS(avx512_8, 8, box8)
WIDE_ENTRY_POINTS_Q(avx512_8q, 8, true, box8q)

const wide_kernels wide_kernels_avx512[2] = {WIDE_KERNELS(avx512_4), WIDE_KERNELS(avx512_8)};
const wide_kernels wide_kernels_avx512_q = WIDE_KERNELS(avx512_8q);
#endif
