/* trace.h: tracing a ray set through an accelerator on N threads.
 *
 * Rays are handed out in chunks from an atomic counter; every answer is
 * written at its ray's index, so answers do not depend on the thread
 * count or on scheduling. Each thread has its own accelerator context and
 * its own counters, summed when the threads are joined. */
#ifndef ACCELBENCH_TRACE_H
#define ACCELBENCH_TRACE_H

#include "../../accel/accel.h"
#include "rayset.h"

typedef struct {
    query_kind query;
    uint32_t count;
    hit_t *hits;          /* QUERY_CLOSEST: [count] */
    uint8_t *occluded;    /* QUERY_ANY: [count], 0 or 1 */
    counters_t total;     /* summed over threads */
    counters_t *per_ray;  /* [count] when asked for (heat maps), else NULL */
} answers_t;

/* Which methods a trace calls. */
typedef enum {
    /* intersect/occluded: answers and work counters (warm-ups, verify,
     * heat maps). */
    TRACE_COUNTING,
    /* intersect_fast/occluded_fast (interface version 2), the counting
     * compiled out: answers only, for timed samples. An accelerator
     * without them for the set's query is traced through the counting
     * methods instead (trace_has_fast says which will run). */
    TRACE_FAST,
} trace_path;

/* Whether a has the counting-free method for query q. */
bool trace_has_fast(const accel *a, query_kind q);

answers_t *answers_new(const rayset_t *rs, bool per_ray_counters);
void answers_free(answers_t *a);

/* Trace every ray of rs through a; returns the wall-clock time of the
 * tracing in milliseconds (threads started and joined inside the timed
 * span, contexts made outside it). threads < 1 means 1. */
/* A ray that is not ray_traceable() (prims/ray.h: NaN, infinite or huge
 * components, a zero direction, an empty or NaN range) is answered "miss"
 * (not occluded) here and never reaches the accelerator; a set that holds
 * one is traced one ray at a time, checked before the clock starts. */
double trace_rayset(accel *a, const rayset_t *rs, int threads, answers_t *out);
/* The same through the methods `path` names, tracing the whole set
 * `passes` times back to back with one thread start-up (for timing small
 * sets); counters are summed over all passes (zero on the fast path).
 * Per-ray counters, when asked for, hold the last pass's (counting path
 * only). */
double trace_rayset_passes(accel *a, const rayset_t *rs, int threads, int passes, trace_path path, answers_t *out);

/* Monotonic clock in milliseconds. */
double clock_ms(void);

/* Heap bytes of the answers of n rays (answers_new). */
uint64_t answers_bytes(uint64_t n, query_kind q, bool per_ray_counters);
/* The answers alive while a cell traces n rays of query q: the
 * reference's, and the accelerator's beside the timing's scratch. */
uint64_t cell_answers_bytes(uint64_t n, query_kind q);
/* A cell tracing a set of n rays of query q: the set, its answers and the
 * structs beside them. */
uint64_t cell_bytes(uint64_t n, query_kind q, bool pixels);

#endif
