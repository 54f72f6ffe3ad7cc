/* wide_traverse_avx2.c: the wide BVH's walk (wide_walk.h) with AVX2 box
 * kernels: a BVH8 node's 8 children in one 256-bit register, a BVH4 node's
 * 4 in a 128-bit one (VEX-encoded). Compiled for AVX2 and FMA by
 * per-function target attributes only (no FMA intrinsic is used, and the
 * build does not contract, so distances stay the scalar kernel's), run
 * only where __builtin_cpu_supports says so (wide_isa.c). */
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#define WIDE_TARGET __attribute__((target("avx2,fma")))
#include "wide_walk.h"

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
    const float *rows = &((const wide8_node *)node)->box[0][0];
    __m256 a = _mm256_set1_ps(t0), z = _mm256_set1_ps(t1);
    for (uint32_t ax = 0; ax < 3; ax++) {
        const __m256 o = _mm256_set1_ps(r->org[ax]), inv = _mm256_set1_ps(r->inv[ax]),
                     inv_far = _mm256_set1_ps(r->inv_far[ax]);
        __m256 n = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(rows + r->near[ax] * 8), o), inv);
        __m256 f = _mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(rows + r->far[ax] * 8), o), inv_far);
        a = _mm256_max_ps(n, a);
        z = _mm256_min_ps(f, z);
    }
    __m256 hit = _mm256_cmp_ps(a, z, _CMP_LE_OQ);
    _mm256_store_ps(tn, a);
    return (unsigned)_mm256_movemask_ps(hit);
}

WIDE_ENTRY_POINTS(avx2_4, 4, box4)
WIDE_ENTRY_POINTS(avx2_8, 8, box8)

const wide_kernels wide_kernels_avx2[2] = {WIDE_KERNELS(avx2_4), WIDE_KERNELS(avx2_8)};
#endif
