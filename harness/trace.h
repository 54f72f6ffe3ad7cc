/* trace.h: tracing a ray set through an accelerator on N threads.
 *
 * Rays are handed out in chunks from an atomic counter; every answer is
 * written at its ray's index, so answers do not depend on the thread
 * count or on scheduling. Each thread has its own accelerator context and
 * its own counters, summed when the threads are joined. */
#ifndef ACCELBENCH_TRACE_H
#define ACCELBENCH_TRACE_H

#include "../accel/accel.h"
#include "rayset.h"

typedef struct {
    query_kind query;
    uint32_t count;
    hit_t *hits;          /* QUERY_CLOSEST: [count] */
    uint8_t *occluded;    /* QUERY_ANY: [count], 0 or 1 */
    counters_t total;     /* summed over threads */
    counters_t *per_ray;  /* [count] when asked for (heat maps), else NULL */
} answers_t;

answers_t *answers_new(const rayset_t *rs, bool per_ray_counters);
void answers_free(answers_t *a);

/* Trace every ray of rs through a; returns the wall-clock time of the
 * tracing in milliseconds (threads started and joined inside the timed
 * span, contexts made outside it). threads < 1 means 1. */
double trace_rayset(accel *a, const rayset_t *rs, int threads, answers_t *out);
/* The same, tracing the whole set `passes` times back to back with one
 * thread start-up (for timing small sets); counters are summed over all
 * passes. Per-ray counters, when asked for, hold the last pass's. */
double trace_rayset_passes(accel *a, const rayset_t *rs, int threads, int passes, answers_t *out);

/* Monotonic clock in milliseconds. */
double clock_ms(void);

#endif
