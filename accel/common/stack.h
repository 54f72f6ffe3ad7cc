/* stack.h: the fixed-capacity traversal stack of depth-first traversals.
 *
 * An entry is a node index and the distance at which the ray enters it, so
 * a closest-hit traversal can drop, when it pops, a node that lies beyond
 * the hit found meanwhile. The storage is the caller's (an array on the C
 * stack, or a context's buffer sized for its tree), so pushing never
 * allocates.
 *
 * Overflow: a push onto a full stack does NOT store the entry; it returns
 * false and sets `overflowed`, which stays set until tstack_init(). The
 * subtree of the dropped entry is then unvisited, so the caller must not
 * trust the answer: it finishes the query another way (the BVH traversals
 * fall back to testing every leaf, accel/bvh/bvh.h) or reports the
 * overflow. A traversal that pushes at most one entry per level never
 * overflows a stack of capacity >= its tree's depth.
 *
 * Memory layout: entries of 8 bytes (node 4, t 4); the struct is 24. */
#ifndef ACCELBENCH_STACK_H
#define ACCELBENCH_STACK_H

#include <assert.h>
#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    uint32_t node; /* node index */
    float t;       /* entry distance along the ray */
} tstack_entry;
static_assert(sizeof(tstack_entry) == 8, "tstack_entry is 8 bytes");

typedef struct {
    tstack_entry *e; /* [cap], the caller's */
    uint32_t n, cap;
    bool overflowed; /* a push was dropped since tstack_init */
} tstack;

static inline void tstack_init(tstack *s, tstack_entry *buf, uint32_t cap)
{
    s->e = buf;
    s->n = 0;
    s->cap = cap;
    s->overflowed = false;
}

/* Push (node, t); false (and overflowed set) when the stack is full. */
static inline bool tstack_push(tstack *s, uint32_t node, float t)
{
    if (s->n == s->cap) {
        s->overflowed = true;
        return false;
    }
    s->e[s->n].node = node;
    s->e[s->n].t = t;
    s->n++;
    return true;
}

/* Pop the last entry into *out; false when empty. */
static inline bool tstack_pop(tstack *s, tstack_entry *out)
{
    if (!s->n) return false;
    *out = s->e[--s->n];
    return true;
}

#ifdef __cplusplus
}
#endif

#endif
