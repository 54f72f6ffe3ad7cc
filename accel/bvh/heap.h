/* heap.h: a binary min-heap of (distance, index), for Kay-Kajiya
 * heap-ordered traversal (Kay and Kajiya, "Ray Tracing Complex Scenes",
 * SIGGRAPH 1986: the candidate volumes are kept in a heap by the
 * distance at which the ray enters them, and the nearest is always
 * expanded next, so the walk can stop as soon as the nearest remaining
 * entry lies beyond the closest hit found).
 *
 * The classic array heap (Williams 1964): entry i has children 2i+1 and
 * 2i+2; push sifts up, pop moves the last entry to the root and sifts
 * down; both O(log n). Keys must not be NaN; equal keys pop in no
 * particular order.
 *
 * Capacity grows by doubling when a push finds the heap full (a context
 * keeps its heap between rays, so that happens on the first few rays
 * only); push returns false only when that allocation fails.
 *
 * Memory layout: entries of 8 bytes (key 4, value 4), cap of them. */
#ifndef ACCELBENCH_HEAP_H
#define ACCELBENCH_HEAP_H

#include <assert.h>
#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    float key;      /* distance */
    uint32_t value; /* node index */
} minheap_entry;
static_assert(sizeof(minheap_entry) == 8, "minheap_entry is 8 bytes");

typedef struct {
    minheap_entry *e; /* [cap] */
    uint32_t n, cap;
} minheap;

/* An empty heap with room for cap entries (cap 0 allocates on the first
 * push). 0, or -1 out of memory. */
int minheap_init(minheap *h, uint32_t cap);
void minheap_free(minheap *h);
/* Double the capacity. 0, or -1 out of memory (the heap is unchanged). */
int minheap_grow(minheap *h);

static inline void minheap_clear(minheap *h) { h->n = 0; }

static inline bool minheap_push(minheap *h, float key, uint32_t value)
{
    if (h->n == h->cap && minheap_grow(h)) return false;
    uint32_t i = h->n++;
    while (i > 0) {
        uint32_t parent = (i - 1) / 2;
        if (!(key < h->e[parent].key)) break;
        h->e[i] = h->e[parent];
        i = parent;
    }
    h->e[i].key = key;
    h->e[i].value = value;
    return true;
}

/* Remove the entry of least key into *out; false when empty. */
static inline bool minheap_pop(minheap *h, minheap_entry *out)
{
    if (!h->n) return false;
    *out = h->e[0];
    minheap_entry last = h->e[--h->n];
    uint32_t i = 0, n = h->n;
    for (;;) {
        uint32_t c = 2 * i + 1;
        if (c >= n) break;
        if (c + 1 < n && h->e[c + 1].key < h->e[c].key) c++;
        if (!(h->e[c].key < last.key)) break;
        h->e[i] = h->e[c];
        i = c;
    }
    if (n) h->e[i] = last;
    return true;
}

#ifdef __cplusplus
}
#endif

#endif
