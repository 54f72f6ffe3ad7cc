/* memcap.h: memory caps with a clear refusal.
 *
 * An accelerator whose size a parameter controls (a grid's resolution, a
 * tree's depth) estimates the bytes it would allocate BEFORE allocating
 * them and checks the estimate against its cap (MiB: the smaller of its own
 * and the harness's --memcap, params_memcap in params.h), so a bad
 * setting fails at once with a reason instead of swapping or being killed.
 * The reason is one line, "WHAT need N.N MiB, over memcap=M MiB", where
 * WHAT is the caller's description (printf format), written as the process
 * cap's refusals write theirs (scenes/memory_cap.h memory_refusal_what). */
#ifndef ACCELBENCH_MEMCAP_H
#define ACCELBENCH_MEMCAP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "../../scenes/memory_cap.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The estimates are sums of products of counts and sizes; these saturate
 * at UINT64_MAX instead of wrapping, so an absurd setting stays absurd
 * (the process cap's arithmetic, scenes/memory_cap.h). */
static inline uint64_t memcap_add(uint64_t a, uint64_t b) { return memory_add(a, b); }
static inline uint64_t memcap_mul(uint64_t n, uint64_t size) { return memory_mul(n, size); }

/* true when bytes exceed cap_mib MiB: then err holds the reason (WHAT from
 * the format). false (within the cap): err is untouched. */
bool memcap_exceeded(uint64_t bytes, uint64_t cap_mib, char *err, size_t errlen, const char *what_fmt, ...)
    __attribute__((format(printf, 5, 6)));

#ifdef __cplusplus
}
#endif

#endif
