/* tri_packet_mt.h: the triangle packets (prims.h's prim_tri_packet) tested
 * by Moller and Trumbore's algorithm (T. Moller, B. Trumbore, "Fast,
 * Minimum Storage Ray/Triangle Intersection", Journal of Graphics Tools
 * 2(1), 1997), as always-inlined bodies for a traversal's walk: the
 * non-robust test of the wide BVH's robust=off (accel/bvh_wide/
 * wide_walk.h), the test Embree uses by default and tinybvh uses.
 *
 * Per lane, with e1 = b - a, e2 = c - a, s = o - a:
 *   p = d x e2, det = e1 . p, inv = 1 / det (a division, not a reciprocal
 *   approximation), u = (s . p) inv, q = s x e1, v = (d . q) inv,
 *   t = (e2 . q) inv;
 * a hit when det != 0, u >= 0, v >= 0, u + v <= 1 and tnear <= t < tmax
 * (two-sided: inv carries det's sign). u weights b and v weights c, as the
 * watertight test's barycentrics do. The edges are computed from the
 * packet's corners, so the packets are the watertight test's (160 bytes).
 *
 * What it gives up against prims/tri_packet.h's watertight test (Woop,
 * Benthin, Wald, JCGT 2013):
 *   - not watertight: u, v and u + v are rounded differently for the two
 *     triangles sharing an edge, so a ray through the edge (or a vertex)
 *     can miss both and slip through the surface;
 *   - t is the float expression above, not refined in double
 *     (tri_sheared.h's triangle_plane_t): on a large triangle seen from
 *     close by it can be off by many float steps at the hit's scale;
 *   - no exact fallback on a zero edge function: the decision at an edge
 *     is whatever rounding gives.
 * What it saves: the ray's shear set-up (three divisions a ray) and, per
 * packet, two of the watertight test's three divisions and the double
 * refinement of every lane inside.
 *
 * Arithmetic: F (a compile-time constant, the wide BVH's resolved fma
 * setting) fuses every a b + c of the cross and dot products into one
 * fused multiply-add (fmaf in the lane-by-lane reference, the FMA
 * instructions in the SIMD body), otherwise separate multiplies and adds;
 * the same operations in the same order either way, and no contraction
 * (shear.h's pragma, -ffp-contract=off), so every instruction set gives
 * the reference's t, u, v bit for bit.
 *
 * Which body: the includer defines TRI_PACKET_MT_SSE (128-bit SSE, the
 * x86-64 baseline) and, where its target has FMA, TRI_PACKET_MT_FMA;
 * without them (the scalar reference) the lanes are computed one after
 * the other in plain C. F without TRI_PACKET_MT_FMA takes the plain-C
 * lanes with fmaf. */
#ifndef ACCELBENCH_TRI_PACKET_MT_H
#define ACCELBENCH_TRI_PACKET_MT_H

#include <math.h>
#include "prims.h"
#include "shear.h" /* FP contraction off */

#ifndef TRI_PACKET_TARGET
#define TRI_PACKET_TARGET
#endif
#define TRI_PACKET_MT_FN static inline __attribute__((always_inline)) TRI_PACKET_TARGET

/* a b - c d and a.b, fused (F) or not: the order of operations every body follows. */
TRI_PACKET_MT_FN float tripk_mt_msub(float a, float b, float c, float d, const bool F)
{
    return F ? fmaf(a, b, -(c * d)) : a * b - c * d;
}
TRI_PACKET_MT_FN float tripk_mt_dot(float ax, float ay, float az, float bx, float by, float bz, const bool F)
{
    return F ? fmaf(ax, bx, fmaf(ay, by, az * bz)) : ax * bx + ay * by + az * bz;
}

/* The reference: lane l in plain C. Writes t, u, v; true when it hits in
 * [tnear, tmax). */
TRI_PACKET_MT_FN bool tripk_mt_lane(const prim_tri_packet *pk, uint32_t l, const ray_t *ray, float tmax, float *t,
                                    float *u, float *v, const bool F)
{
    const float ax = pk->v[0][0][l], ay = pk->v[0][1][l], az = pk->v[0][2][l];
    const float e1x = pk->v[1][0][l] - ax, e1y = pk->v[1][1][l] - ay, e1z = pk->v[1][2][l] - az;
    const float e2x = pk->v[2][0][l] - ax, e2y = pk->v[2][1][l] - ay, e2z = pk->v[2][2][l] - az;
    const float dx = ray->dir.x, dy = ray->dir.y, dz = ray->dir.z;
    const float sx = ray->org.x - ax, sy = ray->org.y - ay, sz = ray->org.z - az;
    const float px = tripk_mt_msub(dy, e2z, dz, e2y, F), py = tripk_mt_msub(dz, e2x, dx, e2z, F),
                pz = tripk_mt_msub(dx, e2y, dy, e2x, F);
    const float qx = tripk_mt_msub(sy, e1z, sz, e1y, F), qy = tripk_mt_msub(sz, e1x, sx, e1z, F),
                qz = tripk_mt_msub(sx, e1y, sy, e1x, F);
    const float det = tripk_mt_dot(e1x, e1y, e1z, px, py, pz, F), inv = 1.0f / det;
    const float uu = tripk_mt_dot(sx, sy, sz, px, py, pz, F) * inv;
    const float vv = tripk_mt_dot(dx, dy, dz, qx, qy, qz, F) * inv;
    const float tt = tripk_mt_dot(e2x, e2y, e2z, qx, qy, qz, F) * inv;
    *t = tt, *u = uu, *v = vv;
    return det != 0.0f && uu >= 0.0f && vv >= 0.0f && uu + vv <= 1.0f && tt >= ray->tnear && tt < tmax;
}

#if defined(TRI_PACKET_MT_SSE)
#include <immintrin.h>
#if defined(TRI_PACKET_MT_FMA)
#define TRIPK_MT_FMA(a, b, c) _mm_fmadd_ps(a, b, c)
#define TRIPK_MT_HAS_FMA 1
#else
#define TRIPK_MT_FMA(a, b, c) _mm_add_ps(_mm_mul_ps(a, b), c) /* never taken: F needs TRI_PACKET_MT_FMA */
#define TRIPK_MT_HAS_FMA 0
#endif
TRI_PACKET_MT_FN __m128 tripk_mt_msub4(__m128 a, __m128 b, __m128 c, __m128 d, const bool F)
{
    const __m128 cd = _mm_mul_ps(c, d);
    return F ? TRIPK_MT_FMA(a, b, _mm_xor_ps(cd, _mm_set1_ps(-0.0f))) : _mm_sub_ps(_mm_mul_ps(a, b), cd);
}
TRI_PACKET_MT_FN __m128 tripk_mt_dot4(__m128 ax, __m128 ay, __m128 az, __m128 bx, __m128 by, __m128 bz, const bool F)
{
    if (F) return TRIPK_MT_FMA(ax, bx, TRIPK_MT_FMA(ay, by, _mm_mul_ps(az, bz)));
    return _mm_add_ps(_mm_add_ps(_mm_mul_ps(ax, bx), _mm_mul_ps(ay, by)), _mm_mul_ps(az, bz));
}
#endif

/* The lanes in live against [tnear, tmax): the mask of those hit, with t,
 * u, v written for every lane (valid where the mask says). */
TRI_PACKET_MT_FN unsigned tripk_mt_hits(const prim_tri_packet *pk, unsigned live, const ray_t *ray, float tmax,
                                        float *t, float *u, float *v, const bool F)
{
#if defined(TRI_PACKET_MT_SSE)
    if (!F || TRIPK_MT_HAS_FMA) {
        const __m128 ax = _mm_loadu_ps(pk->v[0][0]), ay = _mm_loadu_ps(pk->v[0][1]), az = _mm_loadu_ps(pk->v[0][2]);
        const __m128 e1x = _mm_sub_ps(_mm_loadu_ps(pk->v[1][0]), ax), e1y = _mm_sub_ps(_mm_loadu_ps(pk->v[1][1]), ay),
                     e1z = _mm_sub_ps(_mm_loadu_ps(pk->v[1][2]), az);
        const __m128 e2x = _mm_sub_ps(_mm_loadu_ps(pk->v[2][0]), ax), e2y = _mm_sub_ps(_mm_loadu_ps(pk->v[2][1]), ay),
                     e2z = _mm_sub_ps(_mm_loadu_ps(pk->v[2][2]), az);
        const __m128 dx = _mm_set1_ps(ray->dir.x), dy = _mm_set1_ps(ray->dir.y), dz = _mm_set1_ps(ray->dir.z);
        const __m128 sx = _mm_sub_ps(_mm_set1_ps(ray->org.x), ax), sy = _mm_sub_ps(_mm_set1_ps(ray->org.y), ay),
                     sz = _mm_sub_ps(_mm_set1_ps(ray->org.z), az);
        const __m128 px = tripk_mt_msub4(dy, e2z, dz, e2y, F), py = tripk_mt_msub4(dz, e2x, dx, e2z, F),
                     pz = tripk_mt_msub4(dx, e2y, dy, e2x, F);
        const __m128 qx = tripk_mt_msub4(sy, e1z, sz, e1y, F), qy = tripk_mt_msub4(sz, e1x, sx, e1z, F),
                     qz = tripk_mt_msub4(sx, e1y, sy, e1x, F);
        /* Every lane divided, with no early out: skipping the division
         * for a packet with no lane inside was slower (docs/accels/
         * wide-bvh.md, Measured). */
        const __m128 det = tripk_mt_dot4(e1x, e1y, e1z, px, py, pz, F), inv = _mm_div_ps(_mm_set1_ps(1.0f), det);
        const __m128 U = _mm_mul_ps(tripk_mt_dot4(sx, sy, sz, px, py, pz, F), inv);
        const __m128 V = _mm_mul_ps(tripk_mt_dot4(dx, dy, dz, qx, qy, qz, F), inv);
        const __m128 T = _mm_mul_ps(tripk_mt_dot4(e2x, e2y, e2z, qx, qy, qz, F), inv);
        const __m128 zero = _mm_setzero_ps();
        __m128 ok = _mm_and_ps(_mm_cmpneq_ps(det, zero), _mm_and_ps(_mm_cmpge_ps(U, zero), _mm_cmpge_ps(V, zero)));
        ok = _mm_and_ps(ok, _mm_cmple_ps(_mm_add_ps(U, V), _mm_set1_ps(1.0f)));
        ok = _mm_and_ps(ok, _mm_and_ps(_mm_cmpge_ps(T, _mm_set1_ps(ray->tnear)), _mm_cmplt_ps(T, _mm_set1_ps(tmax))));
        _mm_storeu_ps(t, T);
        _mm_storeu_ps(u, U);
        _mm_storeu_ps(v, V);
        return (unsigned)_mm_movemask_ps(ok) & live;
    }
#endif
    unsigned mask = 0;
    for (uint32_t l = 0; l < PRIM_TRI_LANES; l++)
        if ((live >> l & 1) && tripk_mt_lane(pk, l, ray, tmax, &t[l], &u[l], &v[l], F)) mask |= 1u << l;
    return mask;
}

/* The count triangles packed in pk[0 .. prim_tri_packets(count)) against
 * ray: closest hit, lanes taken in order against the closest hit so far,
 * counted as tri_packet.h's tripk_intersect counts (one test a live lane,
 * one hit a closer hit). */
TRI_PACKET_MT_FN bool tripk_mt_intersect(const prim_tri_packet *pk, uint32_t count, const ray_t *ray, hit_t *hit,
                                         counters_t *c, const bool counting, const bool F)
{
    bool found = false;
    const uint32_t npk = prim_tri_packets(count);
    for (uint32_t k = 0; k < npk; k++) {
        const uint32_t rest = count - k * PRIM_TRI_LANES, n = rest < PRIM_TRI_LANES ? rest : PRIM_TRI_LANES;
        if (counting) c->prim_tests += n;
        float t[PRIM_TRI_LANES], u[PRIM_TRI_LANES], v[PRIM_TRI_LANES];
        unsigned mask = tripk_mt_hits(&pk[k], (1u << n) - 1, ray, hit->t, t, u, v, F);
        for (; mask; mask &= mask - 1) {
            const uint32_t l = (uint32_t)__builtin_ctz(mask);
            if (!(t[l] < hit->t)) continue;
            if (counting) c->prim_hits++;
            hit->t = t[l], hit->u = u[l], hit->v = v[l], hit->prim = pk[k].id[l];
            found = true;
        }
    }
    return found;
}

/* Any hit: the first occluder in lane order ends it, counted as
 * tripk_occluded counts (the lanes up to it). */
TRI_PACKET_MT_FN bool tripk_mt_occluded(const prim_tri_packet *pk, uint32_t count, const ray_t *ray, counters_t *c,
                                        const bool counting, const bool F)
{
    const uint32_t npk = prim_tri_packets(count);
    for (uint32_t k = 0; k < npk; k++) {
        const uint32_t rest = count - k * PRIM_TRI_LANES, n = rest < PRIM_TRI_LANES ? rest : PRIM_TRI_LANES;
        float t[PRIM_TRI_LANES], u[PRIM_TRI_LANES], v[PRIM_TRI_LANES];
        const unsigned mask = tripk_mt_hits(&pk[k], (1u << n) - 1, ray, ray->tfar, t, u, v, F);
        if (mask) {
            if (counting) c->prim_tests += (uint32_t)__builtin_ctz(mask) + 1, c->prim_hits++;
            return true;
        }
        if (counting) c->prim_tests += n;
    }
    return false;
}

#endif
