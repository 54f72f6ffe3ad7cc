/* intersect.c: the ray/primitive tests every accelerator calls, counting
 * and counting-free, from ONE body.
 *
 * test_one() below is the only dispatch to the kernels. It takes `counting`
 * as a compile-time constant and is always inlined, so each exported
 * function is that body compiled once with the counter writes and once
 * without: prim_intersect and prim_intersect_fast do exactly the same
 * arithmetic and cannot drift apart. The counting-free ones are for timed
 * traces, where a counter write per test would tax the accelerator (and
 * Embree has none). The leaf forms loop inside prims/, one call per leaf
 * instead of one per primitive, and still count one test per primitive
 * tested. */
#include "prims.h"
#include "prims_internal.h"

/* One primitive: the contract of prim_intersect (prims.h). */
static inline __attribute__((always_inline)) bool test_one(const prims_t *p, uint32_t id, const ray_t *ray,
                                                           hit_t *hit, counters_t *c, const bool counting)
{
    uint32_t k = p->index[id];
    float t, u = 0.0f, v = 0.0f;
    bool ok = false;
    if (counting) c->prim_tests++;
    switch ((prim_kind)p->kind[id]) {
    case PRIM_TRIANGLE: {
        if (p->tri_degenerate[k]) return false;
        vec3 a, b, cc;
        tri_verts(p, k, &a, &b, &cc);
        ok = triangle_intersect(a, b, cc, ray, hit->t, &t, &u, &v);
        break;
    }
    case PRIM_SPHERE:
        ok = sphere_intersect(p->spheres[k], ray, hit->t, &t);
        break;
    case PRIM_CONE:
        ok = cone_intersect(p->cones[k], ray, hit->t, &t, &u);
        break;
    case PRIM_POLYGON: {
        const polygon_t *g = &p->polygons[k];
        if (g->degenerate) return false;
        ok = polygon_intersect(p->verts, p->poly_verts + g->first, g->count, g->normal, g->offset, ray, hit->t, &t);
        break;
    }
    default:
        break;
    }
    if (!ok) return false;
    if (counting) c->prim_hits++;
    hit->t = t;
    hit->u = u;
    hit->v = v;
    hit->prim = id;
    return true;
}

static inline __attribute__((always_inline)) bool occluded_one(const prims_t *p, uint32_t id, const ray_t *ray,
                                                               counters_t *c, const bool counting)
{
    hit_t h = hit_none(ray);
    return test_one(p, id, ray, &h, c, counting);
}

/* Every primitive of the leaf, nearest hit kept in *hit. */
static inline __attribute__((always_inline)) bool leaf_intersect(const prims_t *p, const uint32_t *ids, uint32_t n,
                                                                 const ray_t *ray, hit_t *hit, counters_t *c,
                                                                 const bool counting)
{
    bool found = false;
    for (uint32_t i = 0; i < n; i++) found |= test_one(p, ids[i], ray, hit, c, counting);
    return found;
}

/* Up to the first primitive that occludes. */
static inline __attribute__((always_inline)) bool leaf_occluded(const prims_t *p, const uint32_t *ids, uint32_t n,
                                                                const ray_t *ray, counters_t *c, const bool counting)
{
    for (uint32_t i = 0; i < n; i++)
        if (occluded_one(p, ids[i], ray, c, counting)) return true;
    return false;
}

bool prim_intersect(const prims_t *p, uint32_t id, const ray_t *ray, hit_t *hit, counters_t *c)
{
    return test_one(p, id, ray, hit, c, true);
}

bool prim_intersect_fast(const prims_t *p, uint32_t id, const ray_t *ray, hit_t *hit)
{
    return test_one(p, id, ray, hit, NULL, false);
}

bool prim_occluded(const prims_t *p, uint32_t id, const ray_t *ray, counters_t *c)
{
    return occluded_one(p, id, ray, c, true);
}

bool prim_occluded_fast(const prims_t *p, uint32_t id, const ray_t *ray)
{
    return occluded_one(p, id, ray, NULL, false);
}

bool prim_intersect_leaf(const prims_t *p, const uint32_t *ids, uint32_t n, const ray_t *ray, hit_t *hit, counters_t *c)
{
    return leaf_intersect(p, ids, n, ray, hit, c, true);
}

bool prim_intersect_leaf_fast(const prims_t *p, const uint32_t *ids, uint32_t n, const ray_t *ray, hit_t *hit)
{
    return leaf_intersect(p, ids, n, ray, hit, NULL, false);
}

bool prim_occluded_leaf(const prims_t *p, const uint32_t *ids, uint32_t n, const ray_t *ray, counters_t *c)
{
    return leaf_occluded(p, ids, n, ray, c, true);
}

bool prim_occluded_leaf_fast(const prims_t *p, const uint32_t *ids, uint32_t n, const ray_t *ray)
{
    return leaf_occluded(p, ids, n, ray, NULL, false);
}
