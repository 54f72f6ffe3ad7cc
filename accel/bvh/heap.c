/* heap.c: allocation of the heap (heap.h). */
#include "heap.h"

#include <stdlib.h>

int minheap_init(minheap *h, uint32_t cap)
{
    h->n = 0;
    h->cap = cap;
    h->e = cap ? malloc((size_t)cap * sizeof *h->e) : NULL;
    return cap && !h->e ? -1 : 0;
}

void minheap_free(minheap *h)
{
    free(h->e);
    h->e = NULL;
    h->n = h->cap = 0;
}

int minheap_grow(minheap *h)
{
    uint64_t cap = h->cap ? 2 * (uint64_t)h->cap : 64;
    if (cap > UINT32_MAX) return -1;
    minheap_entry *e = realloc(h->e, (size_t)cap * sizeof *e);
    if (!e) return -1;
    h->e = e;
    h->cap = (uint32_t)cap;
    return 0;
}
