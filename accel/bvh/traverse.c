/* traverse.c: the BVH traversals of bvh.h: the walks of walk.h over the
 * kit's 32-byte box nodes, each compiled four ways.
 *
 * The box test is slab_clip_robust() (accel/common/slab.h), so a box the
 * exact ray meets is never rejected by rounding. Each exported function is
 * one walk with `shadow` (any hit) and `counting` constants: the
 * counting-free ones have no counter writes left, and their arithmetic is
 * the counting ones' exactly (the same answers, bit for bit). */
#include "../common/slab.h"
#include "walk.h"

static inline __attribute__((always_inline)) bool box_clip(const void *tree, const void *ray, uint32_t i, float *t0,
                                                           float *t1)
{
    return slab_clip_robust((const slab_ray *)ray, &((const bvh_t *)tree)->nodes[i].box, t0, t1);
}

static inline __attribute__((always_inline)) void box_node(const void *tree, uint32_t i, uint32_t *index,
                                                           uint32_t *count)
{
    const bvh_node *n = &((const bvh_t *)tree)->nodes[i];
    *index = n->index, *count = n->count;
}

/* One walk over b: false at once for an empty tree or a ray no box can
 * meet (slab_ray_init refuses it). */
static inline __attribute__((always_inline)) bool walk(const bvh_t *b, const prims_t *p, bvh_scratch *s,
                                                       const ray_t *ray, hit_t *hit, counters_t *c, const bool heap,
                                                       const bool shadow, const bool counting)
{
    slab_ray r;
    if (!b->nnodes || !slab_ray_init(&r, ray->org, ray->dir)) return false;
    const bvh_walk w = {b, &r, b->nnodes, b->max_depth, b->refs, p};
    return heap ? bvh_walk_heap(&w, box_clip, box_node, s, ray, hit, c, NULL, shadow, counting)
                : bvh_walk_dfs(&w, box_clip, box_node, s, ray, hit, c, NULL, shadow, counting);
}

/* The four exported forms of one traversal: closest and any hit, counting
 * and counting-free. */
#define EXPORT_TRAVERSAL(NAME, HEAP)                                                                              \
    bool bvh_intersect_##NAME(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray, hit_t *hit,     \
                              counters_t *c)                                                                      \
    {                                                                                                             \
        return walk(b, p, s, ray, hit, c, HEAP, false, true);                                                     \
    }                                                                                                             \
    bool bvh_occluded_##NAME(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray, counters_t *c)   \
    {                                                                                                             \
        return walk(b, p, s, ray, NULL, c, HEAP, true, true);                                                     \
    }                                                                                                             \
    bool bvh_intersect_##NAME##_fast(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray,          \
                                     hit_t *hit)                                                                  \
    {                                                                                                             \
        return walk(b, p, s, ray, hit, NULL, HEAP, false, false);                                                 \
    }                                                                                                             \
    bool bvh_occluded_##NAME##_fast(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray)           \
    {                                                                                                             \
        return walk(b, p, s, ray, NULL, NULL, HEAP, true, false);                                                 \
    }

EXPORT_TRAVERSAL(dfs, false)
EXPORT_TRAVERSAL(heap, true)
