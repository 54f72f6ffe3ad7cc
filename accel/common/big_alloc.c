/* big_alloc.c: large blocks on transparent huge pages (big_alloc.h). */
#include "big_alloc.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

static size_t round_up(size_t n, size_t to) { return n > SIZE_MAX - (to - 1) ? 0 : (n + to - 1) / to * to; }

void *big_alloc(size_t bytes)
{
    if (!bytes) bytes = 1;
    const size_t align = bytes >= BIG_ALLOC_HUGE_FROM ? BIG_ALLOC_HUGE_FROM : 64;
    const size_t size = round_up(bytes, align);
    if (!size) return NULL;
    void *p = aligned_alloc(align, size);
#ifdef MADV_HUGEPAGE
    /* Advice only: refused (no transparent huge pages), the block is still good. */
    if (p && align == BIG_ALLOC_HUGE_FROM) (void)madvise(p, size, MADV_HUGEPAGE);
#endif
    return p;
}

void *big_calloc(size_t n, size_t size)
{
    if (size && n > SIZE_MAX / size) return NULL;
    void *p = big_alloc(n * size);
    if (p) memset(p, 0, n * size);
    return p;
}
