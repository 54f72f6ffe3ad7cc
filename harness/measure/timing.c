/* timing.c: paired timing (see timing.h). */
#include "timing.h"
#include "../../prims/checked_alloc.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int timing_passes(double once_ms)
{
    if (once_ms >= SAMPLE_MIN_MS) return 1;
    if (once_ms <= SAMPLE_MIN_MS / PASSES_MAX) return PASSES_MAX;
    return (int)ceil(SAMPLE_MIN_MS / once_ms);
}

double timing_trace_once(const timed_series *s, const rayset_t *rs, answers_t *scratch)
{
    if (!s->warm) accel_reset(s->a);
    return trace_rayset_passes(s->a, rs, s->threads, 1, s->path, scratch);
}

int timing_calibrate(const timed_series *s, const rayset_t *rs, answers_t *scratch, double first_ms)
{
    int taken = first_ms >= 0;
    double best = taken ? first_ms : INFINITY;
    /* Once a trace has lasted twice a sample, more looks cannot change the
     * answer (one pass) by much. */
    for (; taken < CALIBRATION_TRACES && (taken == 0 || best < 2 * SAMPLE_MIN_MS); taken++)
        best = fmin(best, timing_trace_once(s, rs, scratch));
    return timing_passes(best);
}

/* The accelerator's lazy_build_ms statistic, NAN when it reports none. */
static double lazy_build_ms(const accel *a)
{
    accel_stat st[ACCEL_STATS_MAX];
    int n = accel_stats(a, st, ACCEL_STATS_MAX);
    for (int i = 0; i < n; i++)
        if (strcmp(st[i].name, "lazy_build_ms") == 0) return st[i].value;
    return NAN;
}

/* One timed sample, ms per pass. Without reset() the passes run back to
 * back under one thread start-up; with it each pass is traced on its own
 * after a reset outside the timed span (a structure that mutates runs on
 * one thread, which starts no thread, so this costs it no start-up). */
static double sample_ms(const timed_series *s, const rayset_t *rs, answers_t *scratch, bool read_lazy, double *lazy)
{
    double ms = 0;
    if (accel_resets(s->a) && !s->warm)
        for (int p = 0; p < s->passes; p++) ms += timing_trace_once(s, rs, scratch);
    else ms = trace_rayset_passes(s->a, rs, s->threads, s->passes, s->path, scratch);
    *lazy = read_lazy ? lazy_build_ms(s->a) : NAN;
    return ms / s->passes;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Sorts v[0..n) and returns its median. */
static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static series_summary summarise(double *ms, double *lazy, int n)
{
    series_summary s = {.median = median(ms, n), .min = ms[0], .max = ms[n - 1]};
    s.lazy_build_ms = isnan(lazy[0]) ? NAN : median(lazy, n);
    return s;
}

paired_timing timing_pairs(const timed_series *a, const timed_series *e, const rayset_t *rs, int repeat,
                           answers_t *scratch)
{
    if (repeat < 1) repeat = 1;
    double *buf = checked_calloc(5 * (size_t)repeat, sizeof *buf, "the timed samples");
    double *ams = buf, *ems = buf + repeat, *ratio = buf + 2 * repeat, *alazy = buf + 3 * repeat,
           *elazy = buf + 4 * repeat;
    /* Whether each reports lazy_build_ms, asked once: the statistics can
     * walk the whole structure (a cost model's prediction), work with no
     * place between timed samples. */
    const bool a_lazy = !isnan(lazy_build_ms(a->a)), e_lazy = !isnan(lazy_build_ms(e->a));
    for (int k = 0; k < repeat; k++) {
        /* A E, then E A: each series goes first in every other pair. */
        if (k % 2 == 0) {
            ams[k] = sample_ms(a, rs, scratch, a_lazy, &alazy[k]);
            ems[k] = sample_ms(e, rs, scratch, e_lazy, &elazy[k]);
        } else {
            ems[k] = sample_ms(e, rs, scratch, e_lazy, &elazy[k]);
            ams[k] = sample_ms(a, rs, scratch, a_lazy, &alazy[k]);
        }
        ratio[k] = ems[k] > 0 ? ams[k] / ems[k] : 0;
    }
    paired_timing t = {.a = summarise(ams, alazy, repeat), .e = summarise(ems, elazy, repeat)};
    t.ratio = median(ratio, repeat);
    t.ratio_min = ratio[0];
    t.ratio_max = ratio[repeat - 1];
    free(buf);
    return t;
}
