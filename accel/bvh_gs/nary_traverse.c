/* nary_traverse.c: the n-ary traversals of nary.h, each compiled four
 * ways, in the manner of traverse.c: one body per traversal takes `shadow`
 * (any hit) and `counting` as compile-time constants and is always
 * inlined, so the counting-free forms are the counting ones with the
 * counter writes folded away (the same answers, bit for bit). Work is
 * counted in locals and added to *c once at the end. */
#include <stdlib.h>
#include "../common/prim_hit.h"
#include "../common/slab.h"
#include "nary.h"

#define BODY static inline __attribute__((always_inline))

/* The far end of the range a box must meet: the ray's tfar for any hit,
 * the closest hit so far for closest hit (survey fig. 4). */
BODY float range_end(const ray_t *ray, const hit_t *hit, const bool shadow) { return shadow ? ray->tfar : hit->t; }

/* A leaf: its primitive's test. true when an any-hit query is answered. */
BODY bool leaf_test(const prims_t *p, const nary_node *n, const ray_t *ray, hit_t *hit, counters_t *c,
                    const bool shadow, const bool counting)
{
    if (shadow) return prim_test_any(p, n->index, ray, c, counting);
    prim_test_closest(p, n->index, ray, hit, c, counting);
    return false;
}

/* The overflow fallback (only with no scratch, on a tree deeper or wider
 * than NARY_STACK_LOCAL entries): every leaf whose box the ray meets. */
BODY bool scan_leaves(const nary_t *t, const prims_t *p, const slab_ray *r, const ray_t *ray, hit_t *hit,
                      counters_t *c, uint64_t *nbox, uint64_t *nsteps, const bool shadow, const bool counting)
{
    for (uint32_t i = 0; i < t->nnodes; i++) {
        const nary_node *n = &t->nodes[i];
        if (n->count) continue;
        float t0 = ray->tnear, t1 = range_end(ray, hit, shadow);
        (*nbox)++;
        if (!slab_clip_robust(r, &n->box, &t0, &t1)) continue;
        (*nsteps)++;
        if (leaf_test(p, n, ray, hit, c, shadow, counting)) return true;
    }
    return false;
}

/* The end of a walk: the fallback if the stack overflowed, the counters
 * added once, the answer. */
BODY bool walk_end(const nary_t *t, const prims_t *p, const slab_ray *r, const tstack *st, const ray_t *ray, hit_t *hit,
                   counters_t *c, bool occluded, uint64_t nbox, uint64_t nsteps, const bool shadow, const bool counting)
{
    if (!occluded && st->overflowed) occluded = scan_leaves(t, p, r, ray, hit, c, &nbox, &nsteps, shadow, counting);
    if (counting) {
        c->box_tests += nbox;
        c->steps += nsteps;
    }
    return shadow ? occluded : hit->prim != HIT_NONE;
}

/* The context's stack, or the local one. */
BODY void stack_for(nary_scratch *s, tstack *st, tstack_entry *local)
{
    if (s) tstack_init(st, s->stack, s->cap);
    else tstack_init(st, local, NARY_STACK_LOCAL);
}

/* Survey figure 3 with figure 4's pruning: children in stored order, each
 * box tested when its turn comes. */
BODY bool walk_stored(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray, hit_t *hit,
                      counters_t *c, const bool shadow, const bool counting)
{
    slab_ray r;
    if (!t->nnodes || !slab_ray_init(&r, ray->org, ray->dir)) return false;
    tstack_entry local[NARY_STACK_LOCAL];
    tstack st;
    stack_for(s, &st, local);
    uint64_t nbox = 0, nsteps = 0;
    bool occluded = false;
    tstack_push(&st, 0, ray->tnear);
    tstack_entry e;
    while (tstack_pop(&st, &e)) {
        const nary_node *n = &t->nodes[e.node];
        if (!n->count) {
            nsteps++;
            if (leaf_test(p, n, ray, hit, c, shadow, counting)) {
                occluded = true;
                break;
            }
            continue;
        }
        float t0 = ray->tnear, t1 = range_end(ray, hit, shadow);
        nbox++;
        if (!slab_clip_robust(&r, &n->box, &t0, &t1)) continue;
        nsteps++;
        /* Reversed, so the first child is popped first. */
        for (uint32_t k = n->count; k-- > 0;) tstack_push(&st, n->index + k, 0.0f);
    }
    return walk_end(t, p, &r, &st, ray, hit, c, occluded, nbox, nsteps, shadow, counting);
}

static int farther_first(const void *a, const void *b)
{
    float x = ((const tstack_entry *)a)->t, y = ((const tstack_entry *)b)->t;
    return (x < y) - (x > y);
}

/* Entries e[0 .. n) by entry distance, farthest first (the nearest is
 * popped first): insertion sort for the few box children a node usually
 * has, qsort for a wide one. */
static inline void sort_far_first(tstack_entry *e, uint32_t n)
{
    if (n > 16) {
        qsort(e, n, sizeof *e, farther_first);
        return;
    }
    for (uint32_t i = 1; i < n; i++) {
        tstack_entry x = e[i];
        uint32_t j = i;
        for (; j > 0 && e[j - 1].t < x.t; j--) e[j] = e[j - 1];
        e[j] = x;
    }
}

/* Primitive children first, then box children nearest entry first. */
BODY bool walk_nearest(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray, hit_t *hit,
                       counters_t *c, const bool shadow, const bool counting)
{
    slab_ray r;
    if (!t->nnodes || !slab_ray_init(&r, ray->org, ray->dir)) return false;
    tstack_entry local[NARY_STACK_LOCAL];
    tstack st;
    stack_for(s, &st, local);
    uint64_t nbox = 0, nsteps = 0;
    bool occluded = false;
    const nary_node *root = &t->nodes[0];
    float t0 = ray->tnear, t1 = range_end(ray, hit, shadow);
    if (!root->count) {
        nsteps++;
        occluded = leaf_test(p, root, ray, hit, c, shadow, counting);
    } else {
        nbox++;
        if (slab_clip_robust(&r, &root->box, &t0, &t1)) tstack_push(&st, 0, t0);
    }
    tstack_entry e;
    while (!occluded && tstack_pop(&st, &e)) {
        if (!shadow && e.t > hit->t) continue; /* opens beyond the closest hit: dropped */
        const nary_node *n = &t->nodes[e.node];
        nsteps++;
        for (uint32_t k = 0; k < n->count && !occluded; k++) {
            const nary_node *kid = &t->nodes[n->index + k];
            if (kid->count) continue;
            nsteps++;
            occluded = leaf_test(p, kid, ray, hit, c, shadow, counting);
        }
        if (occluded) break;
        uint32_t from = st.n;
        float end = range_end(ray, hit, shadow);
        for (uint32_t k = 0; k < n->count; k++) {
            const nary_node *kid = &t->nodes[n->index + k];
            if (!kid->count) continue;
            float a = ray->tnear, z = end;
            nbox++;
            if (slab_clip_robust(&r, &kid->box, &a, &z)) tstack_push(&st, n->index + k, a);
        }
        if (st.n > from) sort_far_first(st.e + from, st.n - from);
    }
    return walk_end(t, p, &r, &st, ray, hit, c, occluded, nbox, nsteps, shadow, counting);
}

/* The four exported forms of one traversal body. */
#define EXPORT_TRAVERSAL(NAME, BODYFN)                                                                            \
    bool nary_intersect_##NAME(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray, hit_t *hit,  \
                               counters_t *c)                                                                     \
    {                                                                                                             \
        return BODYFN(t, p, s, ray, hit, c, false, true);                                                         \
    }                                                                                                             \
    bool nary_occluded_##NAME(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray, counters_t *c) \
    {                                                                                                             \
        return BODYFN(t, p, s, ray, NULL, c, true, true);                                                         \
    }                                                                                                             \
    bool nary_intersect_##NAME##_fast(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray,       \
                                      hit_t *hit)                                                                 \
    {                                                                                                             \
        return BODYFN(t, p, s, ray, hit, NULL, false, false);                                                     \
    }                                                                                                             \
    bool nary_occluded_##NAME##_fast(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray)        \
    {                                                                                                             \
        return BODYFN(t, p, s, ray, NULL, NULL, true, false);                                                     \
    }

EXPORT_TRAVERSAL(stored, walk_stored)
EXPORT_TRAVERSAL(nearest, walk_nearest)
