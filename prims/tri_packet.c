/* tri_packet.c: triangle packets (prims.h): triangles packed in SoA
 * groups of PRIM_TRI_LANES and tested together with one ray set-up.
 *
 * The test of each lane is the one-triangle watertight test's own body
 * (tri_sheared.h: Woop, Benthin, Wald, JCGT 2(1), 2013), fed the lane's
 * corners sheared by the same shear_vertex, so a packet answers exactly
 * what prim_intersect_leaf answers over the same ids in the same order:
 * lanes are tested in order against the closest hit so far. What the
 * packet saves is the per-triangle work around the test: the ray's shear
 * (three divisions), the kind dispatch, and the loads through the
 * primitive's index and the triangle's vertex indices. Like intersect.c,
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
        for (uint32_t l = 0; l < n; l++) {
            float t, u, v;
            if (!lane_hit(&s, &pk[k], l, ray, hit->t, &t, &u, &v)) continue;
            if (counting) c->prim_hits++;
            hit->t = t, hit->u = u, hit->v = v, hit->prim = pk[k].id[l];
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
        for (uint32_t l = 0; l < n; l++) {
            float t, u, v;
            if (counting) c->prim_tests++;
            if (lane_hit(&s, &pk[k], l, ray, ray->tfar, &t, &u, &v)) {
                if (counting) c->prim_hits++;
                return true;
            }
        }
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
