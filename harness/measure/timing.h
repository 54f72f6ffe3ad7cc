/* timing.h: paired timing of an accelerator against the reference on the
 * same rays.
 *
 * Why paired: a busy or frequency-scaling machine changes the speed of
 * everything over seconds, so a ratio of two series timed one after the
 * other measures the machine as much as the structures. Here the two
 * series' samples alternate, A E E A A E ... (the order swapped every pair,
 * so neither always runs on the caches or the turbo budget the other left),
 * and each pair gives one ratio a_k / e_k of two samples taken moments
 * apart. Both series run at the same thread count. Samples are per pass:
 * a sample traces the set `passes` times (calibrated from untimed traces
 * so that it lasts at least SAMPLE_MIN_MS) and is divided by it.
 *
 * A series whose accelerator has reset() starts every pass from the
 * post-build state (the reset itself is not timed), so a self-mutating or
 * lazily built structure pays its mutations and its construction in every
 * timed pass instead of hiding them in the warm-up. A warm series (run
 * --warm-passes) is never reset: its passes trace the structure that the
 * warm-up and the passes before them grew, so they measure lookups in a
 * grown structure; cold against warm is what lazy construction costs a
 * first pass over later ones. */
#ifndef ACCELBENCH_TIMING_H
#define ACCELBENCH_TIMING_H

#include "../workloads/rayset.h"
#include "../workloads/trace.h"

/* A timed sample should last at least this long, so that clock resolution
 * and thread start-up do not dominate small ray sets. */
#define SAMPLE_MIN_MS 20.0
#define PASSES_MAX 1000

/* One series: what is traced and how. */
typedef struct {
    accel *a;
    int threads;
    trace_path path;
    int passes;  /* from timing_calibrate() */
    bool warm;   /* no reset() before a pass: the passes trace what the earlier ones built (run --warm-passes) */
} timed_series;

/* A series' samples, ms per pass. */
typedef struct {
    double median, min, max;
    double lazy_build_ms; /* median of the accelerator's lazy_build_ms after each sample (its last pass), or NAN */
} series_summary;

typedef struct {
    series_summary a, e;
    /* Over the pairs' ratios a_k / e_k: the median, and the min and max
     * (with n pairs, [min, max] holds the median ratio with probability
     * 1 - 2^(1-n): 94% at n = 5, 99.8% at n = 10). */
    double ratio, ratio_min, ratio_max;
} paired_timing;

/* Passes per sample for a trace that took once_ms. */
int timing_passes(double once_ms);

/* Passes per sample for series s: from the fastest of up to
 * CALIBRATION_TRACES untimed traces of its path (first_ms, when >= 0, is
 * one already taken, the warm-up of a counting path). The fastest,
 * because a trace can only be slowed by the machine: two series as fast
 * as each other get the same passes, so their samples last as long and
 * carry the same share of thread start-up, and their ratio no bias. */
#define CALIBRATION_TRACES 3
int timing_calibrate(const timed_series *s, const rayset_t *rs, answers_t *scratch, double first_ms);

/* Trace s->a once (untimed use: calibration, warm-up) from its post-build
 * state, through its path; returns the ms it took. */
double timing_trace_once(const timed_series *s, const rayset_t *rs, answers_t *scratch);

/* `repeat` (>= 1) interleaved pairs of samples of a and e on rs. */
paired_timing timing_pairs(const timed_series *a, const timed_series *e, const rayset_t *rs, int repeat,
                           answers_t *scratch);

#endif
