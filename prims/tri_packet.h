/* tri_packet.h: the triangle packet tests (prims.h's
 * prim_intersect_tris and prim_occluded_tris) as always-inlined bodies
 * over a ray whose shear is already set up, so that a traversal can
 * inline them into its walk with the shear computed once per ray
 * (accel/bvh_wide/wide_walk.h) instead of once per leaf behind a call. A
 * function that includes this under a target attribute (AVX2, AVX-512)
 * gets the same IEEE operations in the same order, VEX-encoded: the
 * same answers bit for bit.
 *
 * The test of each lane is the one-triangle watertight test's own body
 * (tri_sheared.h: Woop, Benthin, Wald, JCGT 2(1), 2013), fed the lane's
 * corners sheared by the same shear_vertex, so a packet answers exactly
 * what prim_intersect_leaf answers over the same ids in the same order:
 * lanes are taken in order against the closest hit so far. */
#ifndef ACCELBENCH_TRI_PACKET_H
#define ACCELBENCH_TRI_PACKET_H

#include "prims.h"
#include "shear.h" /* also turns FP contraction off, as in triangle.c */
#include "tri_sheared.h"

#ifndef TRI_PACKET_TARGET
#define TRI_PACKET_TARGET
#endif
#define TRI_PACKET_FN static inline __attribute__((always_inline)) TRI_PACKET_TARGET

TRI_PACKET_FN vec3 tripk_corner(const prim_tri_packet *pk, int corner, uint32_t l)
{
    return v3(pk->v[corner][0][l], pk->v[corner][1][l], pk->v[corner][2][l]);
}

/* Lane l against [tnear, tmax): the one-triangle test's arithmetic. */
TRI_PACKET_FN bool tripk_lane_hit(const shear_t *s, const prim_tri_packet *pk, uint32_t l, const ray_t *ray,
                                  float tmax, float *t, float *u, float *v)
{
    vec3 a = tripk_corner(pk, 0, l), b = tripk_corner(pk, 1, l), c = tripk_corner(pk, 2, l);
    return triangle_sheared_hit(s, a, b, c, shear_vertex(s, a, ray->org), shear_vertex(s, b, ray->org),
                                shear_vertex(s, c, ray->org), ray, tmax, t, u, v);
}

/* The hit distance of lane l, inside by the sign test, whose sheared float
 * t is tf: tri_sheared.h's triangle_plane_t, as the one-triangle test. */
TRI_PACKET_FN float tripk_lane_t(const prim_tri_packet *pk, uint32_t l, const ray_t *ray, float tf)
{
    return triangle_plane_t(tripk_corner(pk, 0, l), tripk_corner(pk, 1, l), tripk_corner(pk, 2, l), ray->org,
                            ray->dir, tf);
}

/* Tested lanes: every lane with an id, in order. */
TRI_PACKET_FN uint32_t tripk_lanes(const prim_tri_packet *pk)
{
    uint32_t n = 0;
    while (n < PRIM_TRI_LANES && pk->id[n] != PRIM_TRI_NO_ID) n++;
    return n;
}

#if defined(__SSE2__)
#include <emmintrin.h>
/* All lanes of a packet at once with SSE2 (the x86-64 baseline, so no
 * target attribute and no dispatch): the same operations as
 * tri_sheared.h in the same order, each an IEEE single-precision operation
 * (no contraction), and the same scalar triangle_plane_t for the distance
 * of the lanes inside, so every lane gets the one-triangle test's values
 * bit for bit. Lanes where a float edge function is exactly 0 need the double
 * fallback: those go through the scalar tripk_lane_hit. Returns the mask of the
 * live lanes that hit in [tnear, tmax), with t, u, v per lane. */
TRI_PACKET_FN unsigned tripk_hits(const shear_t *s, const prim_tri_packet *pk, unsigned live, const ray_t *ray,
                                  float tmax, float *t, float *u, float *v)
{
    const float o[3] = {ray->org.x, ray->org.y, ray->org.z};
    const __m128 ox = _mm_set1_ps(o[s->kx]), oy = _mm_set1_ps(o[s->ky]), oz = _mm_set1_ps(o[s->kz]);
    const __m128 sx = _mm_set1_ps(s->sx), sy = _mm_set1_ps(s->sy), sz = _mm_set1_ps(s->sz), zero = _mm_setzero_ps();
    __m128 X[3], Y[3], Z[3];
    for (int c = 0; c < 3; c++) { /* shear_vertex */
        __m128 rx = _mm_sub_ps(_mm_loadu_ps(pk->v[c][s->kx]), ox);
        __m128 ry = _mm_sub_ps(_mm_loadu_ps(pk->v[c][s->ky]), oy);
        __m128 rz = _mm_sub_ps(_mm_loadu_ps(pk->v[c][s->kz]), oz);
        X[c] = _mm_sub_ps(rx, _mm_mul_ps(sx, rz));
        Y[c] = _mm_sub_ps(ry, _mm_mul_ps(sy, rz));
        Z[c] = rz;
    }
    /* edge_function(C, B), (A, C), (B, A) */
    __m128 U = _mm_sub_ps(_mm_mul_ps(X[2], Y[1]), _mm_mul_ps(Y[2], X[1]));
    __m128 V = _mm_sub_ps(_mm_mul_ps(X[0], Y[2]), _mm_mul_ps(Y[0], X[2]));
    __m128 W = _mm_sub_ps(_mm_mul_ps(X[1], Y[0]), _mm_mul_ps(Y[1], X[0]));
    unsigned exact = (unsigned)_mm_movemask_ps(
        _mm_or_ps(_mm_cmpeq_ps(U, zero), _mm_or_ps(_mm_cmpeq_ps(V, zero), _mm_cmpeq_ps(W, zero))));
    __m128 neg = _mm_or_ps(_mm_cmplt_ps(U, zero), _mm_or_ps(_mm_cmplt_ps(V, zero), _mm_cmplt_ps(W, zero)));
    __m128 pos = _mm_or_ps(_mm_cmpgt_ps(U, zero), _mm_or_ps(_mm_cmpgt_ps(V, zero), _mm_cmpgt_ps(W, zero)));
    __m128 outside = _mm_and_ps(neg, pos); /* signs differ: the ray passes beside the triangle */
    /* No live lane inside (or on an edge that needs the exact test): no
     * hit, and the divisions below, most of the test's latency, are
     * skipped; the lanes that go on get the same values as before. */
    if (!((~(unsigned)_mm_movemask_ps(outside) | exact) & live)) return 0;
    __m128 det = _mm_add_ps(_mm_add_ps(U, V), W);
    __m128 T = _mm_add_ps(_mm_add_ps(_mm_mul_ps(U, _mm_mul_ps(sz, Z[0])), _mm_mul_ps(V, _mm_mul_ps(sz, Z[1]))),
                          _mm_mul_ps(W, _mm_mul_ps(sz, Z[2])));
    _mm_storeu_ps(t, _mm_div_ps(T, det));
    _mm_storeu_ps(u, _mm_div_ps(V, det));
    _mm_storeu_ps(v, _mm_div_ps(W, det));
    /* The lanes inside (signs agree, det != 0) get their distance from
     * triangle_plane_t, one at a time, as the one-triangle test does; the
     * range test applies to that t. */
    unsigned mask = 0;
    unsigned inside = (unsigned)_mm_movemask_ps(_mm_andnot_ps(outside, _mm_cmpneq_ps(det, zero))) & live & ~exact;
    for (; inside; inside &= inside - 1) {
        uint32_t l = (uint32_t)__builtin_ctz(inside);
        t[l] = tripk_lane_t(pk, l, ray, t[l]);
        if (t[l] >= ray->tnear && t[l] < tmax) mask |= 1u << l;
    }
    for (unsigned rest = exact & live; rest; rest &= rest - 1) {
        uint32_t l = (uint32_t)__builtin_ctz(rest);
        if (tripk_lane_hit(s, pk, l, ray, tmax, &t[l], &u[l], &v[l])) mask |= 1u << l;
    }
    return mask;
}
#else
/* No SSE2: the lanes one after the other, the same answers. */
TRI_PACKET_FN unsigned tripk_hits(const shear_t *s, const prim_tri_packet *pk, unsigned live, const ray_t *ray,
                                  float tmax, float *t, float *u, float *v)
{
    unsigned mask = 0;
    for (uint32_t l = 0; l < PRIM_TRI_LANES; l++)
        if ((live >> l & 1) && tripk_lane_hit(s, pk, l, ray, tmax, &t[l], &u[l], &v[l])) mask |= 1u << l;
    return mask;
}
#endif

/* A ray ray_shear refused: no triangle can be hit; each is still a test,
 * as prim_intersect counts it. */
TRI_PACKET_FN bool tripk_unsheared(uint32_t count, counters_t *c, const bool counting)
{
    if (counting) c->prim_tests += count;
    return false;
}

/* Triangles in the packets pk[0 .. npk), from their ids (for callers that
 * know only npk). */
TRI_PACKET_FN uint32_t tripk_count(const prim_tri_packet *pk, uint32_t npk)
{
    uint32_t count = 0;
    for (uint32_t k = 0; k < npk; k++) count += tripk_lanes(&pk[k]);
    return count;
}

/* Live lanes of packet k of count triangles packed in order: every packet
 * but the last is full (prim_tri_pack). From the count rather than the
 * ids, so that the test's first loads are the corners, not the ids in the
 * packet's last cache line (perf: 8 % of Sponza's closest-hit walk waited
 * on that line before any corner was loaded). */
TRI_PACKET_FN uint32_t tripk_live(uint32_t count, uint32_t k)
{
    uint32_t rest = count - k * PRIM_TRI_LANES;
    return rest < PRIM_TRI_LANES ? rest : PRIM_TRI_LANES;
}

/* The count triangles packed in pk[0 .. prim_tri_packets(count)) against
 * ray, whose shear s is set up (sheared:
 * ray_shear's answer; false: no triangle can be hit, each is still a test,
 * as prim_intersect counts it). */
TRI_PACKET_FN bool tripk_intersect(const shear_t *sp, bool sheared, const prim_tri_packet *pk, uint32_t count,
                                  const ray_t *ray, hit_t *hit, counters_t *c, const bool counting)
{
    bool found = false;
    if (!sheared) return tripk_unsheared(count, c, counting);
    const uint32_t npk = prim_tri_packets(count);
    const shear_t s = *sp;
    for (uint32_t k = 0; k < npk; k++) {
        uint32_t n = tripk_live(count, k);
        if (counting) c->prim_tests += n;
        float t[PRIM_TRI_LANES], u[PRIM_TRI_LANES], v[PRIM_TRI_LANES];
        unsigned mask = tripk_hits(&s, &pk[k], (1u << n) - 1, ray, hit->t, t, u, v);
        /* In lane order, each against the closest hit so far, as the lanes
         * one after the other would be (all were tested against the
         * packet's starting hit->t, which only shrinks). */
        for (; mask; mask &= mask - 1) {
            uint32_t l = (uint32_t)__builtin_ctz(mask);
            if (!(t[l] < hit->t)) continue;
            if (counting) c->prim_hits++;
            hit->t = t[l], hit->u = u[l], hit->v = v[l], hit->prim = pk[k].id[l];
            found = true;
        }
    }
    return found;
}

TRI_PACKET_FN bool tripk_occluded(const shear_t *sp, bool sheared, const prim_tri_packet *pk, uint32_t count,
                                 const ray_t *ray, counters_t *c, const bool counting)
{
    if (!sheared) return tripk_unsheared(count, c, counting);
    const uint32_t npk = prim_tri_packets(count);
    const shear_t s = *sp;
    for (uint32_t k = 0; k < npk; k++) {
        uint32_t n = tripk_live(count, k);
        float t[PRIM_TRI_LANES], u[PRIM_TRI_LANES], v[PRIM_TRI_LANES];
        unsigned mask = tripk_hits(&s, &pk[k], (1u << n) - 1, ray, ray->tfar, t, u, v);
        if (mask) {
            /* The first occluder in lane order ends it: the lanes up to it are the tests counted. */
            if (counting) c->prim_tests += (uint32_t)__builtin_ctz(mask) + 1, c->prim_hits++;
            return true;
        }
        if (counting) c->prim_tests += n;
    }
    return false;
}

#endif
