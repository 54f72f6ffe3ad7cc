/* measure.h: measuring one cell (an accelerator on one ray set), the one
 * way `run` (run/matrix.c) and every `reproduce` do it:
 *
 *   1. build, timed;
 *   2. reset, then one warm-up trace through the counting methods: its
 *      answers are verified against the reference's and its counters go in
 *      the CSV;
 *   3. paired timing against the reference on the same rays at the same
 *      thread count (timing.h), through the counting-free methods when the
 *      accelerator has them: trace_ms and ratio_vs_embree with its spread;
 *   4. the accelerator's statistics, its memory and what the timed passes
 *      called: one measurement record (cell_measurement), which run/cell_row.h
 *      makes a CSV row of.
 *
 * A ray set of no rays (a shadow workload where no primary ray hits a lit
 * surface, say) is not measured: nothing is built or timed, and the
 * record says so (no_rays), instead of the times and ratios of tracing
 * nothing.
 *
 * Data flows one way: scene -> ray set -> the reference's answers
 * (cell_rays) -> each accelerator's cell (cell_result). */
#ifndef ACCELBENCH_MEASURE_H
#define ACCELBENCH_MEASURE_H

#include "accel_choice.h"
#include "../workloads/rayset.h"
#include "timing.h"
#include "../workloads/trace.h"
#include "verify.h"

/* A cell's rays: one ray set of one scene and the reference's answers. */
typedef struct {
    const scene_t *scene;
    rayset_t *rs;            /* owned */
    accel *ref;              /* the reference (Embree): made ref_answers, and is the paired series */
    answers_t *ref_answers;  /* owned */
    uint32_t illposed;       /* rays whose reference hit lies within the origin bound (verify.h) */
    verifier_t *ver;         /* the scene's judge, shared by its cells */
} cell_rays;

/* Take rs (and its ownership) and trace the reference's answers on
 * `threads` threads. */
void cell_rays_init(cell_rays *c, const scene_t *s, accel *ref, verifier_t *ver, rayset_t *rs, int threads);
void cell_rays_release(cell_rays *c);

/* How every cell of a run is measured. */
typedef struct {
    int threads;            /* asked for; a serial accelerator runs on 1 (cell_threads) */
    int repeat;             /* timed pairs */
    bool warm_passes;       /* run --warm-passes: no reset before the timed passes (timing.h) */
} cell_settings;

/* An accelerator built and warmed up on a cell's rays (steps 1-2). */
typedef struct {
    accel *a;            /* the caller destroys it (warm_cell_release) */
    int threads;         /* it is traced on */
    double build_ms, warm_ms;
    answers_t *got;      /* the warm-up's answers and counters */
    verify_result vr;    /* got against the reference */
} warm_cell;

/* What one cell measured (steps 1-4). */
typedef struct {
    bool no_rays;             /* a set of no rays: nothing below was measured */
    int threads;              /* the accelerator was traced on (cell_threads) */
    double build_ms;
    paired_timing pt;         /* the timed samples, paired with the reference's */
    int passes;               /* traces per timed sample */
    size_t mem_bytes;
    counters_t counters;      /* the warm-up's */
    verify_result vr;         /* the warm-up's answers against the reference's */
    const char *timed_path;   /* "fast", "counting" or "opaque": the methods the timed samples called */
    const char *timed_from;   /* "" (no reset method), "reset" or "warm": what each timed pass starts from */
    accel_stat stats[ACCEL_STATS_MAX]; /* lazy_build_ms: its median over the samples */
    int nstats;
} cell_measurement;

/* The one rule for the threads an accelerator is traced on when `threads`
 * are asked for: one for an instance that reorders itself while tracing or
 * whose answers depend on the order of its rays (accel_serial). a is the
 * built instance, or NULL where nothing was built (a set of no rays): then
 * only the table's flags are known (ACCEL_MUTATES). Every trace of a
 * measured accelerator (warm-up, timing, verify, heat maps) goes through it. */
int cell_threads(const struct accel_ops *ops, const accel *a, int threads);

/* Steps 1-2: build ac over the cell's scene and trace its warm-up on
 * cell_threads(threads) threads (w->threads). Returns 0, or -1 when the
 * build failed (reported on stderr; nothing to release). */
int cell_warm_up(const cell_rays *c, const accel_config *ac, int threads, warm_cell *w);
void warm_cell_release(warm_cell *w);

/* Steps 1-4 (none for a set of no rays). Returns 0, or -1 when the build
 * failed (reported on stderr). */
int measure_cell(const cell_rays *c, const accel_config *ac, const cell_settings *st, cell_measurement *out);

/* Build ac over s, timed; a failure is reported on stderr and gives NULL. */
accel *build_accel(const accel_config *ac, const scene_t *s, double *ms);

/* The reference accelerator (Embree, default parameters) over s. */
accel *build_reference(const scene_t *s, int threads, char *err, size_t errlen);

#endif
