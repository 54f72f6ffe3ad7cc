/* wide_traverse_avx.h: the body the AVX2 and AVX-512 kernels share
 * (wide_traverse_avx2.c and _avx512.c): the box test's interval for 4
 * children in a 128-bit register and 8 in a 256-bit one, the box kernels
 * and the walks' entry points and table. Each file defines WIDE_TARGET,
 * its comparison of the intervals into a hit mask (WIDE_AVX_MASK4 and
 * WIDE_AVX_MASK8, the only difference), its entry points' prefix
 * (WIDE_AVX_NAME) and its table's name (WIDE_AVX_TABLE), and includes this
 * once.
 * The arithmetic is wide_walk.h's box test: fma=off subtracts the origin
 * and multiplies by the (far-scaled) reciprocal, fma=on (F) takes one
 * fused multiply-add a plane with the ray's directed constants
 * (wide_fused_init); the planes are read as floats from a node's rows,
 * or decoded from a quantised wide8q_node's bytes (compress=on). Each
 * entry point comes in robust=on and robust=off (wide_walk.h). */
#include <immintrin.h>
#define TRI_PACKET_MT_SSE /* robust=off's packet test: SSE lanes, VEX-encoded, */
#define TRI_PACKET_MT_FMA /* fused under fma=on */
#include "wide_walk.h"

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
                              __m256 *z_out, const bool F)
{
    __m256 a = _mm256_set1_ps(t0), z = _mm256_set1_ps(t1);
    for (uint32_t ax = 0; ax < 3; ax++) {
        const __m256 pn = wide_row8(rows, q, r->near[ax], ax), pf = wide_row8(rows, q, r->far[ax], ax);
        __m256 n, f;
        if (F) {
            n = _mm256_fmsub_ps(pn, _mm256_set1_ps(r->nmul[ax]), _mm256_set1_ps(r->nsub[ax]));
            f = _mm256_fmsub_ps(pf, _mm256_set1_ps(r->fmul[ax]), _mm256_set1_ps(r->fsub[ax]));
        } else {
            const __m256 o = _mm256_set1_ps(r->org[ax]);
            n = _mm256_mul_ps(_mm256_sub_ps(pn, o), _mm256_set1_ps(r->inv[ax]));
            f = _mm256_mul_ps(_mm256_sub_ps(pf, o), _mm256_set1_ps(r->inv_far[ax]));
        }
        a = _mm256_max_ps(n, a); /* a NaN n keeps a */
        z = _mm256_min_ps(f, z);
    }
    *z_out = z;
    return a;
}

/* The same for the 4 children of a BVH4 node. */
WIDE_FN __m128 wide_interval4(const wide_ray *r, const float *rows, float t0, float t1, __m128 *z_out, const bool F)
{
    __m128 a = _mm_set1_ps(t0), z = _mm_set1_ps(t1);
    for (uint32_t ax = 0; ax < 3; ax++) {
        const __m128 pn = _mm_load_ps(rows + r->near[ax] * 4), pf = _mm_load_ps(rows + r->far[ax] * 4);
        __m128 n, f;
        if (F) {
            n = _mm_fmsub_ps(pn, _mm_set1_ps(r->nmul[ax]), _mm_set1_ps(r->nsub[ax]));
            f = _mm_fmsub_ps(pf, _mm_set1_ps(r->fmul[ax]), _mm_set1_ps(r->fsub[ax]));
        } else {
            const __m128 o = _mm_set1_ps(r->org[ax]);
            n = _mm_mul_ps(_mm_sub_ps(pn, o), _mm_set1_ps(r->inv[ax]));
            f = _mm_mul_ps(_mm_sub_ps(pf, o), _mm_set1_ps(r->inv_far[ax]));
        }
        a = _mm_max_ps(n, a);
        z = _mm_min_ps(f, z);
    }
    *z_out = z;
    return a;
}

WIDE_FN unsigned box4_any(const wide_ray *r, const void *node, float t0, float t1, float *tn, const bool F)
{
    __m128 z, a = wide_interval4(r, &((const wide4_node *)node)->box[0][0], t0, t1, &z, F);
    const unsigned hit = WIDE_AVX_MASK4(a, z);
    _mm_store_ps(tn, a);
    return hit;
}

WIDE_FN unsigned box8_any(const wide_ray *r, const void *node, float t0, float t1, float *tn, const bool F)
{
    __m256 z, a = wide_interval8(r, &((const wide8_node *)node)->box[0][0], NULL, t0, t1, &z, F);
    const unsigned hit = WIDE_AVX_MASK8(a, z);
    _mm256_store_ps(tn, a);
    return hit;
}

/* compress=on: the unused slots, which decode to a box at the node's
 * corner, masked off. */
WIDE_FN unsigned box8q_any(const wide_ray *r, const void *node, float t0, float t1, float *tn, const bool F)
{
    const wide8q_node *q = node;
    __m256 z, a = wide_interval8(r, NULL, q, t0, t1, &z, F);
    const unsigned hit = WIDE_AVX_MASK8(a, z);
    _mm256_store_ps(tn, a);
    return hit & ((1u << q->nchildren) - 1);
}

/* Each kernel with fma=off's arithmetic (NAME) and fma=on's (NAMEf). */
#define BOTH(NAME)                                                                                                     \
    WIDE_FN unsigned NAME(const wide_ray *r, const void *node, float t0, float t1, float *tn)                         \
    {                                                                                                                  \
        return NAME##_any(r, node, t0, t1, tn, false);                                                                 \
    }                                                                                                                  \
    WIDE_FN unsigned NAME##f(const wide_ray *r, const void *node, float t0, float t1, float *tn)                      \
    {                                                                                                                  \
        return NAME##_any(r, node, t0, t1, tn, true);                                                                  \
    }
BOTH(box4)
BOTH(box8)
BOTH(box8q)

WIDE_ENTRY_POINTS(WIDE_AVX_NAME(4), 4, false, false, box4)
WIDE_ENTRY_POINTS(WIDE_AVX_NAME(8), 8, false, false, box8)
WIDE_ENTRY_POINTS(WIDE_AVX_NAME(8q), 8, true, false, box8q)
WIDE_ENTRY_POINTS(WIDE_AVX_NAME(4f), 4, false, true, box4f)
WIDE_ENTRY_POINTS(WIDE_AVX_NAME(8f), 8, false, true, box8f)
WIDE_ENTRY_POINTS(WIDE_AVX_NAME(8qf), 8, true, true, box8qf)

/* No width 2: BVH2 nodes run the SSE4.2 kernel (wide_isa_running). */
const wide_kernels WIDE_AVX_TABLE[WIDE_LAYOUTS][2][2] = {
    {{{0}}},
    {WIDE_KERNELS_RO(WIDE_AVX_NAME(4)), WIDE_KERNELS_RO(WIDE_AVX_NAME(4f))},
    {WIDE_KERNELS_RO(WIDE_AVX_NAME(8)), WIDE_KERNELS_RO(WIDE_AVX_NAME(8f))},
    {WIDE_KERNELS_RO(WIDE_AVX_NAME(8q)), WIDE_KERNELS_RO(WIDE_AVX_NAME(8qf))},
};
