/* tri_packet.c: triangle packets (prims.h): triangles packed in SoA
 * groups of PRIM_TRI_LANES and tested together with one ray set-up.
 *
 * The test of each lane is the one-triangle watertight test's own body
 * (tri_sheared.h: Woop, Benthin, Wald, JCGT 2(1), 2013), fed the lane's
 * corners sheared by the same shear_vertex, so a packet answers exactly
 * what prim_intersect_leaf answers over the same ids in the same order:
 * lanes are taken in order against the closest hit so far. What the
 * packet saves is the per-triangle work around the test: the ray's shear
 * (three divisions), the kind dispatch, the loads through the primitive's
 * index and the triangle's vertex indices, and (SSE2) three of every four
 * tests' instructions: the four lanes are computed at once. Like intersect.c,
 * one body is compiled counting and counting-free (`counting` a constant). */
#include "prims.h"
#include "prims_internal.h"
#include "shear.h" /* also turns FP contraction off, as in triangle.c */
#include "tri_sheared.h"

bool prim_all_triangles(const prims_t *p, const uint32_t *ids, uint32_t n)
{
    for (uint32_t i = 0; i < n; i++)
        if (ids[i] >= p->count || p->kind[ids[i]] != PRIM_TRIANGLE) return false;
    return true;
}

void prim_tri_pack(const prims_t *p, const uint32_t *ids, uint32_t n, prim_tri_packet *out)
{
    for (uint32_t k = 0; k < prim_tri_packets(n); k++) {
        prim_tri_packet *pk = &out[k];
        for (uint32_t l = 0; l < PRIM_TRI_LANES; l++) {
            uint32_t i = k * PRIM_TRI_LANES + l;
            vec3 c[3] = {v3(NAN, NAN, NAN), v3(NAN, NAN, NAN), v3(NAN, NAN, NAN)};
            pk->id[l] = PRIM_TRI_NO_ID;
            if (i < n) {
                uint32_t t = p->index[ids[i]];
                pk->id[l] = ids[i];
                if (!p->tri_degenerate[t]) tri_verts(p, t, &c[0], &c[1], &c[2]);
            }
            for (int corner = 0; corner < 3; corner++) {
                pk->v[corner][0][l] = c[corner].x;
                pk->v[corner][1][l] = c[corner].y;
                pk->v[corner][2][l] = c[corner].z;
            }
        }
    }
}

static inline __attribute__((always_inline)) sheared_t lane_corner(const shear_t *s, const prim_tri_packet *pk,
                                                                   int corner, uint32_t l, vec3 org)
{
    return shear_vertex(s, v3(pk->v[corner][0][l], pk->v[corner][1][l], pk->v[corner][2][l]), org);
}

/* Lane l against [tnear, tmax): the one-triangle test's arithmetic. */
static inline __attribute__((always_inline)) bool lane_hit(const shear_t *s, const prim_tri_packet *pk, uint32_t l,
                                                           const ray_t *ray, float tmax, float *t, float *u, float *v)
{
    return triangle_sheared_hit(s, lane_corner(s, pk, 0, l, ray->org), lane_corner(s, pk, 1, l, ray->org),
                                lane_corner(s, pk, 2, l, ray->org), ray, tmax, t, u, v);
}

/* Tested lanes: every lane with an id, in order. */
static inline __attribute__((always_inline)) uint32_t lanes_of(const prim_tri_packet *pk)
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
 * (no contraction), so every lane gets the one-triangle test's values bit
 * for bit. Lanes where a float edge function is exactly 0 need the double
 * fallback: those go through the scalar lane_hit. Returns the mask of the
 * live lanes that hit in [tnear, tmax), with t, u, v per lane. */
static inline __attribute__((always_inline)) unsigned packet_hits(const shear_t *s, const prim_tri_packet *pk,
                                                                  unsigned live, const ray_t *ray, float tmax,
                                                                  float *t, float *u, float *v)
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
    /* No live lane inside (or on an edge that needs the exact test): no
     * hit, and the divisions below, most of the test's latency, are
     * skipped; the lanes that go on get the same values as before. */
    __m128 inside = _mm_andnot_ps(_mm_and_ps(neg, pos), _mm_castsi128_ps(_mm_set1_epi32(-1)));
    if (!(((unsigned)_mm_movemask_ps(inside) | exact) & live)) return 0;
    __m128 det = _mm_add_ps(_mm_add_ps(U, V), W);
    __m128 T = _mm_add_ps(_mm_add_ps(_mm_mul_ps(U, _mm_mul_ps(sz, Z[0])), _mm_mul_ps(V, _mm_mul_ps(sz, Z[1]))),
                          _mm_mul_ps(W, _mm_mul_ps(sz, Z[2])));
    __m128 tt = _mm_div_ps(T, det);
    __m128 ok = _mm_andnot_ps(_mm_and_ps(neg, pos), _mm_cmpneq_ps(det, zero));
    ok = _mm_and_ps(ok, _mm_and_ps(_mm_cmpge_ps(tt, _mm_set1_ps(ray->tnear)), _mm_cmplt_ps(tt, _mm_set1_ps(tmax))));
    _mm_storeu_ps(t, tt);
    _mm_storeu_ps(u, _mm_div_ps(V, det));
    _mm_storeu_ps(v, _mm_div_ps(W, det));
    unsigned mask = (unsigned)_mm_movemask_ps(ok) & live & ~exact;
    for (unsigned rest = exact & live; rest; rest &= rest - 1) {
        uint32_t l = (uint32_t)__builtin_ctz(rest);
        if (lane_hit(s, pk, l, ray, tmax, &t[l], &u[l], &v[l])) mask |= 1u << l;
    }
    return mask;
}
#else
/* No SSE2: the lanes one after the other, the same answers. */
static inline __attribute__((always_inline)) unsigned packet_hits(const shear_t *s, const prim_tri_packet *pk,
                                                                  unsigned live, const ray_t *ray, float tmax,
                                                                  float *t, float *u, float *v)
{
    unsigned mask = 0;
    for (uint32_t l = 0; l < PRIM_TRI_LANES; l++)
        if ((live >> l & 1) && lane_hit(s, pk, l, ray, tmax, &t[l], &u[l], &v[l])) mask |= 1u << l;
    return mask;
}
#endif

static inline __attribute__((always_inline)) bool tris_intersect(const prim_tri_packet *pk, uint32_t npk,
                                                                 const ray_t *ray, hit_t *hit, counters_t *c,
                                                                 const bool counting)
{
    shear_t s;
    bool found = false;
    if (!ray_shear(ray->dir, &s)) {
        /* No triangle can be hit; each is still a test, as prim_intersect counts it. */
        if (counting)
            for (uint32_t k = 0; k < npk; k++) c->prim_tests += lanes_of(&pk[k]);
        return false;
    }
    for (uint32_t k = 0; k < npk; k++) {
        uint32_t n = lanes_of(&pk[k]);
        if (counting) c->prim_tests += n;
        float t[PRIM_TRI_LANES], u[PRIM_TRI_LANES], v[PRIM_TRI_LANES];
        unsigned mask = packet_hits(&s, &pk[k], (1u << n) - 1, ray, hit->t, t, u, v);
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

static inline __attribute__((always_inline)) bool tris_occluded(const prim_tri_packet *pk, uint32_t npk,
                                                                const ray_t *ray, counters_t *c, const bool counting)
{
    shear_t s;
    if (!ray_shear(ray->dir, &s)) {
        if (counting)
            for (uint32_t k = 0; k < npk; k++) c->prim_tests += lanes_of(&pk[k]);
        return false;
    }
    for (uint32_t k = 0; k < npk; k++) {
        uint32_t n = lanes_of(&pk[k]);
        float t[PRIM_TRI_LANES], u[PRIM_TRI_LANES], v[PRIM_TRI_LANES];
        unsigned mask = packet_hits(&s, &pk[k], (1u << n) - 1, ray, ray->tfar, t, u, v);
        if (mask) {
            /* The first occluder in lane order ends it: the lanes up to it are the tests counted. */
            if (counting) c->prim_tests += (uint32_t)__builtin_ctz(mask) + 1, c->prim_hits++;
            return true;
        }
        if (counting) c->prim_tests += n;
    }
    return false;
}

bool prim_intersect_tris(const prim_tri_packet *pk, uint32_t npk, const ray_t *ray, hit_t *hit, counters_t *c)
{
    return tris_intersect(pk, npk, ray, hit, c, true);
}

bool prim_intersect_tris_fast(const prim_tri_packet *pk, uint32_t npk, const ray_t *ray, hit_t *hit)
{
    return tris_intersect(pk, npk, ray, hit, NULL, false);
}

bool prim_occluded_tris(const prim_tri_packet *pk, uint32_t npk, const ray_t *ray, counters_t *c)
{
    return tris_occluded(pk, npk, ray, c, true);
}

bool prim_occluded_tris_fast(const prim_tri_packet *pk, uint32_t npk, const ray_t *ray)
{
    return tris_occluded(pk, npk, ray, NULL, false);
}
