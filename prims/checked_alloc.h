/* checked_alloc.h: the one allocation helper of prims/, scenes/ and
 * harness/: malloc, calloc, realloc and strdup that, when the allocator
 * says no, print one line naming what was being allocated and how many
 * bytes, and exit with status 2 (bad input: the work asked for more memory
 * than there is), never abort().
 *
 * It is the backstop. What a command can size before it allocates (ray
 * sets, images, answers, primitive stores, threads) is estimated first and
 * refused above the memory cap (scenes/memory_cap.h, --memcap) with a line
 * that says how to raise it; this catches what no estimate covers (a mesh
 * file's counts, the machine running short while working).
 *
 * Header-only (static inline) so that the primitive store, the lowest
 * layer, uses the same helper as everything above it without a library of
 * its own. `what` names the item in words ("the primitive store's
 * triangles"); sizes of 0 allocate 1 byte, so NULL always means failure. */
#ifndef ACCELBENCH_CHECKED_ALLOC_H
#define ACCELBENCH_CHECKED_ALLOC_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Print "accelbench: out of memory: cannot allocate N bytes (M MiB) for
 * WHAT; ..." (bytes 0: size unknown) and exit(2). Stdout is flushed first,
 * so what a command printed before stays. */
__attribute__((noreturn, cold)) static inline void checked_alloc_failed(uint64_t bytes, const char *what)
{
    char size[64] = "memory";
    if (bytes == UINT64_MAX) snprintf(size, sizeof size, "more than 2^64 bytes");
    else if (bytes) snprintf(size, sizeof size, "%llu bytes (%.1f MiB)", (unsigned long long)bytes, (double)bytes / 1048576.0);
    fflush(stdout);
    fprintf(stderr, "accelbench: out of memory: cannot allocate %s for %s; ask for less work or free memory "
            "(docs/limits.md)\n", size, what ? what : "an allocation");
    exit(2);
}

/* n * size, or checked_alloc_failed when it does not fit in a size_t. */
static inline size_t checked_array_bytes(size_t n, size_t size, const char *what)
{
    if (size && n > SIZE_MAX / size) checked_alloc_failed(UINT64_MAX, what);
    return n * size;
}

static inline void *checked_malloc(size_t bytes, const char *what)
{
    void *p = malloc(bytes ? bytes : 1);
    if (!p) checked_alloc_failed(bytes, what);
    return p;
}

/* Zeroed n * size bytes (the product checked). */
static inline void *checked_calloc(size_t n, size_t size, const char *what)
{
    size_t bytes = checked_array_bytes(n, size, what);
    void *p = calloc(bytes ? n : 1, bytes ? size : 1);
    if (!p) checked_alloc_failed(bytes, what);
    return p;
}

/* realloc(p, bytes); on failure p is not freed (the process exits). */
static inline void *checked_realloc(void *p, size_t bytes, const char *what)
{
    void *q = realloc(p, bytes ? bytes : 1);
    if (!q) checked_alloc_failed(bytes, what);
    return q;
}

static inline char *checked_strdup(const char *s, const char *what)
{
    size_t n = strlen(s) + 1;
    char *d = (char *)checked_malloc(n, what);
    memcpy(d, s, n);
    return d;
}

#ifdef __cplusplus
}
#endif

#endif
