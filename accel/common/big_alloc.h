/* big_alloc.h: the large arrays of a build and of the structure it makes,
 * on transparent huge pages where the system offers them.
 *
 * A build writes tens of megabytes it has just allocated; with 4 KiB pages
 * the first touch of each page is a fault, and on a virtual machine the
 * faults took a third of the wide BVH's build (perf, spd:balls:4:t). Embree
 * asks the kernel for 2 MiB pages for its large blocks (its os_malloc,
 * common/sys/alloc.cpp: madvise(MADV_HUGEPAGE)), so to compare build times
 * like with like, and trace times over the same kind of pages (fewer TLB
 * misses), the BVH kit allocates its large arrays the same way. Where the
 * system gives no huge pages (transparent_hugepage=never) the advice is
 * ignored and the memory is ordinary.
 *
 * Memory from big_alloc and big_calloc is freed with free() and may be
 * given to realloc() (glibc: an aligned block is an ordinary one). */
#ifndef ACCELBENCH_BIG_ALLOC_H
#define ACCELBENCH_BIG_ALLOC_H

#include <stddef.h>

/* From this size on, a block is aligned to and advised as huge pages. */
#define BIG_ALLOC_HUGE_FROM ((size_t)2 << 20)

/* bytes (at least 1), aligned to 64 bytes (a cache line) or, from
 * BIG_ALLOC_HUGE_FROM on, to 2 MiB and advised MADV_HUGEPAGE. NULL out of
 * memory. */
void *big_alloc(size_t bytes);
/* n x size bytes, zero; NULL out of memory or when n x size overflows. */
void *big_calloc(size_t n, size_t size);

#endif
