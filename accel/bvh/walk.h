/* walk.h: the BVH walks, written once for every node layout and volume
 * test.
 *
 * A binary hierarchy whose node i is either interior (children index and
 * index + 1) or a leaf of the primitives refs[index .. index + count) is
 * walked the same way whatever its volumes are: the kit's boxes
 * (traverse.c, slab_clip_robust) or Kay and Kajiya's plane-set volumes
 * (accel/slabs_kk/slabs_kay_kajiya.c, planeset_clip). The layout gives two
 * callbacks, the volume test of a node and its index and count; the walks
 * are always inlined and the callbacks are constants at every call site, so
 * each use compiles to a walk specialised to its layout, with no indirect
 * call left (as accel/common/prim_hit.h does for counting).
 *
 *   bvh_walk_dfs   depth-first, the nearer child first, the farther one
 *                  stacked with its entry distance and dropped on pop when a
 *                  closer hit is already known;
 *   bvh_walk_heap  heap-ordered (Kay and Kajiya, SIGGRAPH 1986; survey
 *                  figure 9, Hull_Sort_Intersect): the candidates in a heap
 *                  by entry distance, the nearest expanded next, and a
 *                  closest-hit query over when it lies beyond the hit.
 * Any-hit queries end at the first occluder. Overflow (a stack shallower
 * than the tree, a heap that cannot grow): the walk finishes by testing
 * every leaf whose volume the ray meets, so the answer stays exact.
 *
 * Counters (accel.h; bvh.h says what they mean): box_tests = volumes
 * tested, steps = nodes expanded; prim_tests and prim_hits by prims/. Work
 * is counted in locals and added to *c once at the end, because the leaf
 * calls into prims/ could otherwise make the compiler store every
 * increment. */
#ifndef ACCELBENCH_BVH_WALK_H
#define ACCELBENCH_BVH_WALK_H

#include "bvh.h"

#define BVH_WALK_BODY static inline __attribute__((always_inline))

/* A tree as the walks see it. */
typedef struct {
    const void *tree;       /* the layout's own tree, handed back to the callbacks */
    const void *ray;        /* the per-ray constants of its volume test (slab_ray, planeset_ray) */
    uint32_t nnodes;        /* nodes; node 0 is the root */
    uint32_t max_depth;     /* deepest leaf, root = 0: the depth-first stack's size */
    const uint32_t *refs;   /* primitive ids, by leaf */
    const prims_t *p;
} bvh_walk;

/* The volume test of node i: narrow [*t0, *t1] (t0 >= 0) to the part of
 * the ray inside the volume; true when it is not empty, and then *t0 is the
 * entry distance. Must never reject a volume the exact ray meets. */
typedef bool (*bvh_walk_clip_fn)(const void *tree, const void *ray, uint32_t i, float *t0, float *t1);
/* Node i's index and count (count 0: interior). */
typedef void (*bvh_walk_node_fn)(const void *tree, uint32_t i, uint32_t *index, uint32_t *count);

/* For tests: the nodes a walk expands, in order, with the key (entry
 * distance) each was expanded with; n counts them all, at most cap are
 * stored. NULL while tracing (the walks then compile it away). */
typedef struct {
    uint32_t *nodes;
    float *keys;
    uint32_t n, cap;
} bvh_walk_log;

BVH_WALK_BODY void bvh_walk_visit(bvh_walk_log *log, uint32_t node, float key)
{
    if (!log) return;
    if (log->n < log->cap) log->nodes[log->n] = node, log->keys[log->n] = key;
    log->n++;
}

BVH_WALK_BODY bool bvh_walk_leaf(const bvh_walk *w, uint32_t index, uint32_t count, const ray_t *ray, hit_t *hit,
                                 counters_t *c, const bool shadow, const bool counting)
{
    const uint32_t *ids = w->refs + index;
    if (shadow)
        return counting ? prim_occluded_leaf(w->p, ids, count, ray, c) : prim_occluded_leaf_fast(w->p, ids, count, ray);
    return counting ? prim_intersect_leaf(w->p, ids, count, ray, hit, c)
                    : prim_intersect_leaf_fast(w->p, ids, count, ray, hit);
}

/* The far end of the range a volume must meet: the ray's tfar for any
 * hit, the closest hit so far for closest hit. */
BVH_WALK_BODY float bvh_walk_end(const ray_t *ray, const hit_t *hit, const bool shadow)
{
    return shadow ? ray->tfar : hit->t;
}

/* The overflow fallback: every leaf whose volume the ray meets, in node
 * order. Exact, since it sees every primitive the walk could have. */
BVH_WALK_BODY bool bvh_walk_scan(const bvh_walk *w, const bvh_walk_clip_fn clip, const bvh_walk_node_fn node,
                                 const ray_t *ray, hit_t *hit, counters_t *c, uint64_t *nbox, uint64_t *nsteps,
                                 const bool shadow, const bool counting)
{
    for (uint32_t i = 0; i < w->nnodes; i++) {
        uint32_t index, count;
        node(w->tree, i, &index, &count);
        if (!count) continue;
        float t0 = ray->tnear, t1 = bvh_walk_end(ray, hit, shadow);
        (*nbox)++;
        if (!clip(w->tree, w->ray, i, &t0, &t1)) continue;
        (*nsteps)++;
        if (bvh_walk_leaf(w, index, count, ray, hit, c, shadow, counting) && shadow) return true;
    }
    return false;
}

/* Depth-first, the nearer child first. s NULL: a stack of BVH_STACK_LOCAL
 * entries on the C stack. */
BVH_WALK_BODY bool bvh_walk_dfs(const bvh_walk *w, const bvh_walk_clip_fn clip, const bvh_walk_node_fn node,
                                bvh_scratch *s, const ray_t *ray, hit_t *hit, counters_t *c, bvh_walk_log *log,
                                const bool shadow, const bool counting)
{
    if (!w->nnodes) return false;
    tstack_entry local[BVH_STACK_LOCAL];
    tstack st;
    if (s) tstack_init(&st, s->stack, s->stack_cap);
    else tstack_init(&st, local, BVH_STACK_LOCAL);
    uint64_t nbox = 1, nsteps = 0;
    bool occluded = false;
    float t0 = ray->tnear, t1 = bvh_walk_end(ray, hit, shadow);
    if (clip(w->tree, w->ray, 0, &t0, &t1)) {
        uint32_t ni = 0;
        float key = t0;
        for (;;) {
            uint32_t index, count;
            node(w->tree, ni, &index, &count);
            nsteps++;
            bvh_walk_visit(log, ni, key);
            if (count) {
                if (bvh_walk_leaf(w, index, count, ray, hit, c, shadow, counting) && shadow) {
                    occluded = true;
                    break;
                }
            } else {
                /* Both children against the current range; go to the
                 * nearer, stack the farther with its entry distance. */
                float end = bvh_walk_end(ray, hit, shadow);
                float l0 = ray->tnear, l1 = end, r0 = ray->tnear, r1 = end;
                bool hl = clip(w->tree, w->ray, index, &l0, &l1);
                bool hr = clip(w->tree, w->ray, index + 1, &r0, &r1);
                nbox += 2;
                if (hl && hr) {
                    bool left_first = l0 <= r0;
                    tstack_push(&st, left_first ? index + 1 : index, left_first ? r0 : l0);
                    ni = left_first ? index : index + 1;
                    key = left_first ? l0 : r0;
                    continue;
                }
                if (hl || hr) {
                    ni = hl ? index : index + 1;
                    key = hl ? l0 : r0;
                    continue;
                }
            }
            /* Pop, dropping nodes that start beyond the closest hit. */
            tstack_entry e;
            bool more;
            while ((more = tstack_pop(&st, &e)) && !shadow && e.t > hit->t) {}
            if (!more) break;
            ni = e.node;
            key = e.t;
        }
        if (!occluded && st.overflowed)
            occluded = bvh_walk_scan(w, clip, node, ray, hit, c, &nbox, &nsteps, shadow, counting);
    }
    if (counting) {
        c->box_tests += nbox;
        c->steps += nsteps;
    }
    return shadow ? occluded : hit->prim != HIT_NONE;
}

/* Heap-ordered: always expand the nearest candidate. s NULL: a heap
 * allocated for the ray. */
BVH_WALK_BODY bool bvh_walk_heap(const bvh_walk *w, const bvh_walk_clip_fn clip, const bvh_walk_node_fn node,
                                 bvh_scratch *s, const ray_t *ray, hit_t *hit, counters_t *c, bvh_walk_log *log,
                                 const bool shadow, const bool counting)
{
    if (!w->nnodes) return false;
    bvh_scratch own;
    bool owned = false, overflow = false, occluded = false;
    if (!s) {
        const bvh_t shape = {.max_depth = w->max_depth};
        owned = bvh_scratch_init(&own, &shape) == 0;
        s = owned ? &own : NULL;
        overflow = !owned;
    }
    uint64_t nbox = 1, nsteps = 0;
    float t0 = ray->tnear, t1 = bvh_walk_end(ray, hit, shadow);
    bool enter = clip(w->tree, w->ray, 0, &t0, &t1);
    if (enter && s) {
        minheap *h = &s->heap;
        minheap_clear(h);
        overflow = !minheap_push(h, t0, 0);
        minheap_entry e;
        while (!overflow && minheap_pop(h, &e)) {
            /* "if candidate.key > ray.interval.max then return": everything
             * left starts beyond the closest hit. */
            if (!shadow && e.key > hit->t) break;
            uint32_t index, count;
            node(w->tree, e.value, &index, &count);
            nsteps++;
            bvh_walk_visit(log, e.value, e.key);
            if (count) {
                if (bvh_walk_leaf(w, index, count, ray, hit, c, shadow, counting) && shadow) {
                    occluded = true;
                    break;
                }
                continue;
            }
            float end = bvh_walk_end(ray, hit, shadow);
            for (uint32_t k = 0; k < 2; k++) {
                float a = ray->tnear, z = end;
                nbox++;
                if (clip(w->tree, w->ray, index + k, &a, &z) && !minheap_push(h, a, index + k)) overflow = true;
            }
        }
    }
    if (enter && overflow && !occluded)
        occluded = bvh_walk_scan(w, clip, node, ray, hit, c, &nbox, &nsteps, shadow, counting);
    if (owned) bvh_scratch_free(&own);
    if (counting) {
        c->box_tests += nbox;
        c->steps += nsteps;
    }
    return shadow ? occluded : hit->prim != HIT_NONE;
}

#endif
