/* tri_packet.c: triangle packets (prims.h): triangles packed in SoA
 * groups of PRIM_TRI_LANES and tested together with one ray set-up.
 *
 * The tests' bodies are in tri_packet.h, which traversals may inline
 * (accel/bvh_wide/wide_walk.h); here they are compiled once for prims.h's
 * entry points, each setting the ray's shear up per call. What the
 * packet saves is the per-triangle work around the test: the ray's shear
 * (three divisions), the kind dispatch, the loads through the primitive's
 * index and the triangle's vertex indices, and (SSE2) three of every four
 * tests' instructions: the four lanes are computed at once. Like intersect.c,
 * one body is compiled counting and counting-free (`counting` a constant). */
#include "prims.h"
#include "prims_internal.h"
#include "tri_packet.h"

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

bool prim_intersect_tris(const prim_tri_packet *pk, uint32_t npk, const ray_t *ray, hit_t *hit, counters_t *c)
{
    shear_t s;
    bool sheared = ray_shear(ray->dir, &s);
    return tripk_intersect(&s, sheared, pk, tripk_count(pk, npk), ray, hit, c, true);
}

bool prim_intersect_tris_fast(const prim_tri_packet *pk, uint32_t npk, const ray_t *ray, hit_t *hit)
{
    shear_t s;
    bool sheared = ray_shear(ray->dir, &s);
    return tripk_intersect(&s, sheared, pk, tripk_count(pk, npk), ray, hit, NULL, false);
}

bool prim_occluded_tris(const prim_tri_packet *pk, uint32_t npk, const ray_t *ray, counters_t *c)
{
    shear_t s;
    bool sheared = ray_shear(ray->dir, &s);
    return tripk_occluded(&s, sheared, pk, tripk_count(pk, npk), ray, c, true);
}

bool prim_occluded_tris_fast(const prim_tri_packet *pk, uint32_t npk, const ray_t *ray)
{
    shear_t s;
    bool sheared = ray_shear(ray->dir, &s);
    return tripk_occluded(&s, sheared, pk, tripk_count(pk, npk), ray, NULL, false);
}
