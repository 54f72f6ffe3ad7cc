/* trace.c: the threaded trace loop (see trace.h). */
#include "trace.h"
#include "resources.h"
#include "../../prims/checked_alloc.h"

#include <pthread.h>
#include <stdio.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Rays per work item: large enough that the atomic is off the hot path,
 * small enough to balance 2-64 threads on 10^4-rays sets. */
#define CHUNK 256

double clock_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

answers_t *answers_new(const rayset_t *rs, bool per_ray_counters)
{
    /* Covered by the ray set's estimate when a workload made it; checked
     * here too for every other caller (resources.h). No error path: exit 2. */
    char err[512];
    if (memory_cap_exceeded(answers_bytes(rs->count, rs->query, per_ray_counters), err, sizeof err,
                            "the answers of %u rays of %s", rs->count, rs->workload)) {
        fflush(stdout);
        fprintf(stderr, "accelbench: %s\n", err);
        exit(2);
    }
    answers_t *a = checked_calloc(1, sizeof *a, "a trace's answers");
    size_t n = rs->count ? rs->count : 1;
    a->query = rs->query;
    a->count = rs->count;
    if (rs->query == QUERY_CLOSEST) a->hits = checked_calloc(n, sizeof *a->hits, "a trace's hits");
    else a->occluded = checked_calloc(n, 1, "a trace's occlusion answers");
    if (per_ray_counters) a->per_ray = checked_calloc(n, sizeof *a->per_ray, "a trace's per-ray counters");
    return a;
}

void answers_free(answers_t *a)
{
    if (!a) return;
    free(a->hits);
    free(a->occluded);
    free(a->per_ray);
    free(a);
}

bool trace_has_fast(const accel *a, query_kind q)
{
    const struct accel_ops *ops = a->ops;
    return ops->version >= 2 && (q == QUERY_CLOSEST ? ops->intersect_fast != NULL : ops->occluded_fast != NULL);
}

typedef struct {
    accel *a;
    const rayset_t *rs;
    answers_t *out;
    bool fast;           /* the counting-free methods (TRACE_FAST, when the accelerator has them) */
    bool guarded;        /* the set holds rays that are not ray_traceable(): answer those "miss" here */
    uint64_t total;      /* rays to trace: count * passes */
    atomic_uint_fast64_t next;
} job_t;

typedef struct {
    job_t *job;
    accel_ctx *ctx;
    counters_t counters;
} worker_t;

/* Trace rays [begin, end): the query test, the path test and the method
 * lookup are hoisted out of the loops, which are the hot path of every
 * measurement; the fast loops differ from the counting ones only in the
 * method and its missing counters argument. */
static void trace_range(const job_t *j, accel_ctx *ctx, uint32_t begin, uint32_t end, counters_t *c)
{
    accel *a = j->a;
    const struct accel_ops *ops = a->ops;
    const ray_t *rays = j->rs->rays;
    if (j->rs->query == QUERY_CLOSEST) {
        hit_t *hits = j->out->hits;
        if (j->fast) {
            bool (*intersect)(accel *, accel_ctx *, const ray_t *, hit_t *) = ops->intersect_fast;
            for (uint32_t i = begin; i < end; i++) {
                hits[i] = hit_none(&rays[i]);
                intersect(a, ctx, &rays[i], &hits[i]);
            }
        } else {
            bool (*intersect)(accel *, accel_ctx *, const ray_t *, hit_t *, counters_t *) = ops->intersect;
            for (uint32_t i = begin; i < end; i++) {
                hits[i] = hit_none(&rays[i]);
                intersect(a, ctx, &rays[i], &hits[i], c);
            }
        }
    } else {
        uint8_t *occ = j->out->occluded;
        if (j->fast) {
            bool (*occluded)(accel *, accel_ctx *, const ray_t *) = ops->occluded_fast;
            for (uint32_t i = begin; i < end; i++) occ[i] = occluded(a, ctx, &rays[i]);
        } else {
            bool (*occluded)(accel *, accel_ctx *, const ray_t *, counters_t *) = ops->occluded;
            for (uint32_t i = begin; i < end; i++) occ[i] = occluded(a, ctx, &rays[i], c);
        }
    }
}

/* Rays that are not traceable never reach the accelerator (prims/ray.h):
 * they are answered "miss", the runs of good rays between them traced. */
static void trace_guarded(const job_t *j, accel_ctx *ctx, uint32_t begin, uint32_t end, counters_t *c)
{
    const ray_t *rays = j->rs->rays;
    while (begin < end) {
        uint32_t good = begin;
        while (good < end && ray_traceable(&rays[good])) good++;
        if (good > begin) trace_range(j, ctx, begin, good, c);
        if (good == end) break;
        if (j->rs->query == QUERY_CLOSEST) j->out->hits[good] = hit_none(&rays[good]);
        else j->out->occluded[good] = 0;
        begin = good + 1;
    }
}

/* Trace rays [begin, end) of the set, with per-ray counters when asked. */
static void trace_slice(const job_t *j, worker_t *w, uint32_t begin, uint32_t end)
{
    if (j->guarded) {
        /* Rare (hand-made sets, tests): one ray at a time is fine here. */
        for (uint32_t i = begin; i < end; i++) {
            counters_t c = {0};
            trace_guarded(j, w->ctx, i, i + 1, &c);
            if (j->out->per_ray) j->out->per_ray[i] = c;
            counters_add(&w->counters, &c);
        }
        return;
    }
    if (!j->out->per_ray || j->fast) {
        trace_range(j, w->ctx, begin, end, &w->counters);
        return;
    }
    /* Heat maps: one ray at a time, so each ray's counters are its own. */
    for (uint32_t i = begin; i < end; i++) {
        counters_t c = {0};
        trace_range(j, w->ctx, i, i + 1, &c);
        j->out->per_ray[i] = c;
        counters_add(&w->counters, &c);
    }
}

static void *worker_main(void *arg)
{
    worker_t *w = arg;
    job_t *j = w->job;
    uint32_t n = j->rs->count;
    memset(&w->counters, 0, sizeof w->counters);
    for (;;) {
        /* A work item is CHUNK consecutive rays of the passes laid end to
         * end; it is cut where one pass ends and the next begins. */
        uint64_t pos = atomic_fetch_add(&j->next, CHUNK);
        if (pos >= j->total) break;
        uint64_t stop = pos + CHUNK < j->total ? pos + CHUNK : j->total;
        while (pos < stop) {
            uint32_t begin = (uint32_t)(pos % n);
            uint64_t len = stop - pos < (uint64_t)(n - begin) ? stop - pos : (uint64_t)(n - begin);
            trace_slice(j, w, begin, begin + (uint32_t)len);
            pos += len;
        }
    }
    return NULL;
}

double trace_rayset(accel *a, const rayset_t *rs, int threads, answers_t *out)
{
    return trace_rayset_passes(a, rs, threads, 1, TRACE_COUNTING, out);
}

double trace_rayset_passes(accel *a, const rayset_t *rs, int threads, int passes, trace_path path, answers_t *out)
{
    if (threads < 1) threads = 1;
    if (passes < 1) passes = 1;
    job_t job = {.a = a, .rs = rs, .out = out, .fast = path == TRACE_FAST && trace_has_fast(a, rs->query),
                 .total = (uint64_t)rs->count * (uint64_t)passes};
    /* Checked once per call, before the clock starts: the sets the
     * workloads make are all traceable, so the timed loops carry no test. */
    for (uint32_t i = 0; i < rs->count && !job.guarded; i++) job.guarded = !ray_traceable(&rs->rays[i]);
    atomic_init(&job.next, 0);
    worker_t *w = checked_calloc((size_t)threads, sizeof *w, "the tracing threads' state");
    pthread_t *tid = checked_calloc((size_t)threads, sizeof *tid, "the tracing threads' ids");
    for (int t = 0; t < threads; t++) {
        w[t].job = &job;
        w[t].ctx = a->ops->context_new ? a->ops->context_new(a) : NULL;
    }
    double t0 = clock_ms();
    /* Thread 0 is the calling thread: one thread means no thread creation. */
    /* The thread count was checked against the memory cap when it was
     * given (resources.h); a machine that still cannot start one is an
     * exit 2 that says so, not an abort. The threads already started are
     * stopped (no work left to take) and joined first, so that nothing
     * traces while the process exits. */
    for (int t = 1; t < threads; t++) {
        int rc = pthread_create(&tid[t], NULL, worker_main, &w[t]);
        if (rc != 0) {
            atomic_store(&job.next, job.total);
            for (int k = 1; k < t; k++) pthread_join(tid[k], NULL);
            fflush(stdout);
            fprintf(stderr, "accelbench: cannot start tracing thread %d of %d: %s (%.1f MiB of stack each); lower --threads\n",
                    t + 1, threads, strerror(rc), (double)resources_thread_stack_bytes() / 1048576.0);
            exit(2);
        }
    }
    worker_main(&w[0]);
    for (int t = 1; t < threads; t++) pthread_join(tid[t], NULL);
    double ms = clock_ms() - t0;
    memset(&out->total, 0, sizeof out->total);
    for (int t = 0; t < threads; t++) {
        counters_add(&out->total, &w[t].counters);
        if (a->ops->context_free) a->ops->context_free(w[t].ctx);
    }
    free(w);
    free(tid);
    return ms;
}

uint64_t answers_bytes(uint64_t n, query_kind q, bool per_ray_counters)
{
    uint64_t each = (q == QUERY_CLOSEST ? sizeof(hit_t) : sizeof(uint8_t)) + (per_ray_counters ? sizeof(counters_t) : 0);
    return memory_mul(n ? n : 1, each);
}

/* A cell tracing a set of n rays of query q (measure/measure.c, run/cells.c): the
 * reference's answers stay for the whole cell; the ill-posed count traces
 * the set for nearest hits beside them (then frees them), and the
 * accelerator's warm-up answers and the timing's scratch answers come
 * after, beside the reference's. */
uint64_t cell_answers_bytes(uint64_t n, query_kind q)
{
    uint64_t ref = answers_bytes(n, q, false), closest = answers_bytes(n, QUERY_CLOSEST, false);
    return memory_add(ref, resources_max(closest, memory_mul(ref, 2)));
}

/* The structs a cell allocates beside its arrays (the set's and the
 * answers' headers, the allocator's own bookkeeping): a few hundred bytes,
 * rounded up. */
#define CELL_OVERHEAD_BYTES 4096

uint64_t cell_bytes(uint64_t n, query_kind q, bool pixels)
{
    return memory_add(memory_add(rayset_bytes(n, pixels), cell_answers_bytes(n, q)), CELL_OVERHEAD_BYTES);
}
