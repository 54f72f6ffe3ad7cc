/* measure.c: one cell, measured the same way by run and reproduce (see
 * measure.h). */
#include "measure.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void cell_rays_init(cell_rays *c, const scene_t *s, accel *ref, verifier_t *ver, rayset_t *rs, int threads)
{
    memset(c, 0, sizeof *c);
    c->scene = s;
    c->rs = rs;
    c->ref = ref;
    c->ver = ver;
    c->ref_answers = answers_new(rs, false);
    trace_rayset(ref, rs, threads, c->ref_answers);
    c->illposed = verify_count_illposed(s, rs, ref, threads);
}

void cell_rays_release(cell_rays *c)
{
    answers_free(c->ref_answers);
    rayset_free(c->rs);
    memset(c, 0, sizeof *c);
}

int cell_threads(const struct accel_ops *ops, const accel *a, int threads)
{
    bool serial = a ? accel_serial(a) : (ops->flags & ACCEL_MUTATES) != 0;
    return serial ? 1 : threads;
}

int cell_warm_up(const cell_rays *c, const accel_config *ac, int threads, warm_cell *w)
{
    memset(w, 0, sizeof *w);
    w->a = build_accel(ac, c->scene, &w->build_ms);
    if (!w->a) return -1;
    w->threads = cell_threads(ac->ops, w->a, threads);
    w->got = answers_new(c->rs, false);
    accel_reset(w->a);
    w->warm_ms = trace_rayset(w->a, c->rs, w->threads, w->got);
    verifier_check(c->ver, c->rs, w->got, c->ref_answers, &w->vr);
    return 0;
}

void warm_cell_release(warm_cell *w)
{
    answers_free(w->got);
    if (w->a) w->a->ops->destroy(w->a);
    memset(w, 0, sizeof *w);
}

/* The CSV's timed_path: the methods the timed samples call. "opaque" is
 * the counting methods of an accelerator whose work is not observable
 * (Embree): they count nothing, so nothing is taxed. */
static const char *timed_path_name(const accel *a, query_kind q)
{
    if (trace_has_fast(a, q)) return "fast";
    return (a->ops->flags & ACCEL_NO_COUNTERS) ? "opaque" : "counting";
}

/* The statistics read after the timed samples, with lazy_build_ms (the
 * last pass's) replaced by its median over the samples. */
static int read_stats(const accel *a, const paired_timing *pt, accel_stat *st)
{
    int n = accel_stats(a, st, ACCEL_STATS_MAX);
    for (int i = 0; i < n; i++)
        if (strcmp(st[i].name, "lazy_build_ms") == 0 && !isnan(pt->a.lazy_build_ms)) st[i].value = pt->a.lazy_build_ms;
    return n;
}

int measure_cell(const cell_rays *c, const accel_config *ac, const cell_settings *st, cell_measurement *out)
{
    const rayset_t *rs = c->rs;
    memset(out, 0, sizeof *out);
    if (rs->count == 0) {
        out->no_rays = true;
        out->threads = cell_threads(ac->ops, NULL, st->threads);
        return 0;
    }
    warm_cell w;
    if (cell_warm_up(c, ac, st->threads, &w)) return -1;
    answers_t *scratch = answers_new(rs, false);
    /* Each series' passes come from untimed traces of its own path (the
     * warm-up is one when the accelerator has no fast path); the reference
     * runs on the accelerator's thread count, whatever it was built with. */
    timed_series sa = {.a = w.a, .threads = w.threads, .path = TRACE_FAST, .warm = st->warm_passes};
    timed_series se = {.a = c->ref, .threads = w.threads, .path = TRACE_FAST};
    /* A warm series' passes follow the warm-up's growth, so the warm-up's own time (a cold pass) does not calibrate it. */
    bool warm_up_calibrates = !trace_has_fast(w.a, rs->query) && !(sa.warm && accel_resets(w.a));
    sa.passes = timing_calibrate(&sa, rs, scratch, warm_up_calibrates ? w.warm_ms : -1);
    se.passes = timing_calibrate(&se, rs, scratch, -1);
    out->pt = timing_pairs(&sa, &se, rs, st->repeat, scratch);
    answers_free(scratch);

    out->threads = w.threads;
    out->vr = w.vr;
    out->build_ms = w.build_ms;
    out->mem_bytes = w.a->ops->memory(w.a);
    out->counters = w.got->total;
    out->passes = sa.passes;
    out->timed_path = timed_path_name(w.a, rs->query);
    out->timed_from = !accel_resets(w.a) ? "" : st->warm_passes ? "warm" : "reset";
    out->nstats = read_stats(w.a, &out->pt, out->stats);
    warm_cell_release(&w);
    return 0;
}

accel *build_reference(const scene_t *s, int threads, char *err, size_t errlen)
{
    const struct accel_ops *ops = accel_find(ACCEL_REFERENCE);
    accel_params p;
    params_defaults(&p, ops->params);
    p.threads = threads;
    return accel_build(ops, s, &p, err, errlen);
}

accel *build_accel(const accel_config *ac, const scene_t *s, double *ms)
{
    char err[512];
    double t0 = clock_ms();
    accel *a = accel_build(ac->ops, s, &ac->params, err, sizeof err);
    *ms = clock_ms() - t0;
    if (!a) fprintf(stderr, "accelbench: %s on %s: build failed: %s\n", ac->ops->name, s->name, err);
    return a;
}
