/* wide_box8_avx.h: the 8-wide box test's interval in 256-bit registers,
 * shared by the AVX2 and AVX-512 kernels (wide_traverse_avx2.c and
 * _avx512.c include it after wide_walk.h, each under its own WIDE_TARGET;
 * only their comparisons into a mask differ). The arithmetic is
 * wide_walk.h's box test, the planes read as floats from a wide8_node's
 * rows, or decoded from a quantised wide8q_node's bytes (compress=on). */
#ifndef ACCELBENCH_BVH_WIDE_BOX8_AVX_H
#define ACCELBENCH_BVH_WIDE_BOX8_AVX_H

#include <immintrin.h>

/* Row `row` (axis ax's near or far planes) of the 8 children: from rows,
 * or with q set decoded as origin + q * scale, the bytes widened to floats
 * and the multiply-add fused (q * scale is exact, so the fused and the
 * scalar kernel's separate multiply and add round the same, once). */
WIDE_FN __m256 wide_row8(const float *rows, const wide8q_node *q, uint32_t row, uint32_t ax)
{
    if (!q) return _mm256_load_ps(rows + row * 8);
    const __m256 b = _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)q->q[row])));
    return _mm256_fmadd_ps(b, _mm256_set1_ps(wide_q_scale(q->scale_exp[ax])), _mm256_set1_ps(q->origin[ax]));
}

/* The 8 children's entry distances a (returned) and exit distances *z
 * within [t0, t1]; a child is hit where a <= z. */
WIDE_FN __m256 wide_interval8(const wide_ray *r, const float *rows, const wide8q_node *q, float t0, float t1,
                              __m256 *z_out)
{
    __m256 a = _mm256_set1_ps(t0), z = _mm256_set1_ps(t1);
    for (uint32_t ax = 0; ax < 3; ax++) {
        const __m256 o = _mm256_set1_ps(r->org[ax]), inv = _mm256_set1_ps(r->inv[ax]),
                     inv_far = _mm256_set1_ps(r->inv_far[ax]);
        __m256 n = _mm256_mul_ps(_mm256_sub_ps(wide_row8(rows, q, r->near[ax], ax), o), inv);
        __m256 f = _mm256_mul_ps(_mm256_sub_ps(wide_row8(rows, q, r->far[ax], ax), o), inv_far);
        a = _mm256_max_ps(n, a); /* a NaN n keeps a */
        z = _mm256_min_ps(f, z);
    }
    *z_out = z;
    return a;
}

#endif
