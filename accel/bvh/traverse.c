/* traverse.c: the BVH traversals of bvh.h, each compiled four ways.
 *
 * One body per traversal (dfs, heap_walk) takes `shadow` (any hit) and
 * `counting` as compile-time constants and is always inlined, so the
 * exported functions are that one source specialised: the counting-free
 * ones have no counter writes left, and their arithmetic is the counting
 * ones' exactly (the same answers, bit for bit). Work is counted in locals
 * and added to *c once at the end, because the leaf calls into prims/
 * could otherwise make the compiler store every increment. */
#include "../common/slab.h"
#include "bvh.h"

#define BODY static inline __attribute__((always_inline))

BODY bool leaf_test(const bvh_t *b, const prims_t *p, const bvh_node *n, const ray_t *ray, hit_t *hit,
                    counters_t *c, const bool shadow, const bool counting)
{
    const uint32_t *ids = b->refs + n->index;
    if (shadow) return counting ? prim_occluded_leaf(p, ids, n->count, ray, c) : prim_occluded_leaf_fast(p, ids, n->count, ray);
    return counting ? prim_intersect_leaf(p, ids, n->count, ray, hit, c)
                    : prim_intersect_leaf_fast(p, ids, n->count, ray, hit);
}

/* The far end of the range a box must meet: the ray's tfar for any hit,
 * the closest hit so far for closest hit. */
BODY float range_end(const ray_t *ray, const hit_t *hit, const bool shadow) { return shadow ? ray->tfar : hit->t; }

/* The overflow fallback: every leaf whose box the ray meets, in node
 * order. Exact, since it sees every primitive the traversal could have. */
BODY bool scan_leaves(const bvh_t *b, const prims_t *p, const slab_ray *r, const ray_t *ray, hit_t *hit,
                      counters_t *c, uint64_t *nbox, uint64_t *nsteps, const bool shadow, const bool counting)
{
    for (uint32_t i = 0; i < b->nnodes; i++) {
        const bvh_node *n = &b->nodes[i];
        if (!n->count) continue;
        float t0 = ray->tnear, t1 = range_end(ray, hit, shadow);
        (*nbox)++;
        if (!slab_clip_robust(r, &n->box, &t0, &t1)) continue;
        (*nsteps)++;
        if (leaf_test(b, p, n, ray, hit, c, shadow, counting) && shadow) return true;
    }
    return false;
}

/* Depth-first, nearer child first. */
BODY bool dfs(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray, hit_t *hit, counters_t *c,
              const bool shadow, const bool counting)
{
    slab_ray r;
    if (!b->nnodes || !slab_ray_init(&r, ray->org, ray->dir)) return false;
    tstack_entry local[BVH_STACK_LOCAL];
    tstack st;
    if (s) tstack_init(&st, s->stack, s->stack_cap);
    else tstack_init(&st, local, BVH_STACK_LOCAL);
    uint64_t nbox = 1, nsteps = 0;
    bool occluded = false;
    float t0 = ray->tnear, t1 = range_end(ray, hit, shadow);
    if (slab_clip_robust(&r, &b->nodes[0].box, &t0, &t1)) {
        uint32_t ni = 0;
        for (;;) {
            const bvh_node *n = &b->nodes[ni];
            nsteps++;
            if (n->count) {
                if (leaf_test(b, p, n, ray, hit, c, shadow, counting) && shadow) {
                    occluded = true;
                    break;
                }
            } else {
                /* Both children against the current range; go to the
                 * nearer, stack the farther with its entry distance. */
                uint32_t l = n->index;
                float end = range_end(ray, hit, shadow);
                float l0 = ray->tnear, l1 = end, r0 = ray->tnear, r1 = end;
                bool hl = slab_clip_robust(&r, &b->nodes[l].box, &l0, &l1);
                bool hr = slab_clip_robust(&r, &b->nodes[l + 1].box, &r0, &r1);
                nbox += 2;
                if (hl && hr) {
                    bool left_first = l0 <= r0;
                    tstack_push(&st, left_first ? l + 1 : l, left_first ? r0 : l0);
                    ni = left_first ? l : l + 1;
                    continue;
                }
                if (hl || hr) {
                    ni = hl ? l : l + 1;
                    continue;
                }
            }
            /* Pop, dropping nodes that start beyond the closest hit. */
            tstack_entry e;
            bool more;
            while ((more = tstack_pop(&st, &e)) && !shadow && e.t > hit->t) {}
            if (!more) break;
            ni = e.node;
        }
        if (!occluded && st.overflowed) occluded = scan_leaves(b, p, &r, ray, hit, c, &nbox, &nsteps, shadow, counting);
    }
    if (counting) {
        c->box_tests += nbox;
        c->steps += nsteps;
    }
    return shadow ? occluded : hit->prim != HIT_NONE;
}

/* Heap-ordered (Kay-Kajiya): always expand the nearest entry. */
BODY bool heap_walk(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray, hit_t *hit, counters_t *c,
                    const bool shadow, const bool counting)
{
    slab_ray r;
    if (!b->nnodes || !slab_ray_init(&r, ray->org, ray->dir)) return false;
    bvh_scratch own;
    bool owned = false, overflow = false, occluded = false;
    if (!s) {
        owned = bvh_scratch_init(&own, b) == 0;
        s = owned ? &own : NULL;
        overflow = !owned;
    }
    uint64_t nbox = 1, nsteps = 0;
    float t0 = ray->tnear, t1 = range_end(ray, hit, shadow);
    bool enter = slab_clip_robust(&r, &b->nodes[0].box, &t0, &t1);
    if (enter && s) {
        minheap *h = &s->heap;
        minheap_clear(h);
        overflow = !minheap_push(h, t0, 0);
        minheap_entry e;
        while (!overflow && minheap_pop(h, &e)) {
            /* Everything left starts beyond the closest hit: done. */
            if (!shadow && e.key > hit->t) break;
            const bvh_node *n = &b->nodes[e.value];
            nsteps++;
            if (n->count) {
                if (leaf_test(b, p, n, ray, hit, c, shadow, counting) && shadow) {
                    occluded = true;
                    break;
                }
                continue;
            }
            float end = range_end(ray, hit, shadow);
            for (uint32_t k = 0; k < 2; k++) {
                float a = ray->tnear, z = end;
                nbox++;
                if (slab_clip_robust(&r, &b->nodes[n->index + k].box, &a, &z) && !minheap_push(h, a, n->index + k))
                    overflow = true;
            }
        }
    }
    if (enter && overflow && !occluded) occluded = scan_leaves(b, p, &r, ray, hit, c, &nbox, &nsteps, shadow, counting);
    if (owned) bvh_scratch_free(&own);
    if (counting) {
        c->box_tests += nbox;
        c->steps += nsteps;
    }
    return shadow ? occluded : hit->prim != HIT_NONE;
}

/* The four exported forms of one traversal body: closest and any hit,
 * counting and counting-free. */
#define EXPORT_TRAVERSAL(NAME, BODYFN)                                                                            \
    bool bvh_intersect_##NAME(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray, hit_t *hit,     \
                              counters_t *c)                                                                      \
    {                                                                                                             \
        return BODYFN(b, p, s, ray, hit, c, false, true);                                                         \
    }                                                                                                             \
    bool bvh_occluded_##NAME(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray, counters_t *c)   \
    {                                                                                                             \
        return BODYFN(b, p, s, ray, NULL, c, true, true);                                                         \
    }                                                                                                             \
    bool bvh_intersect_##NAME##_fast(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray,          \
                                     hit_t *hit)                                                                  \
    {                                                                                                             \
        return BODYFN(b, p, s, ray, hit, NULL, false, false);                                                     \
    }                                                                                                             \
    bool bvh_occluded_##NAME##_fast(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray)           \
    {                                                                                                             \
        return BODYFN(b, p, s, ray, NULL, NULL, true, false);                                                     \
    }

EXPORT_TRAVERSAL(dfs, dfs)
EXPORT_TRAVERSAL(heap, heap_walk)
