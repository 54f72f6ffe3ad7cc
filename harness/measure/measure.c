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
    return (a->ops->flags & ACCEL_OPAQUE) ? "opaque" : "counting";
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

/* The row's identity, its ray set's image and what no measurement needs. */
static int row_frame(const cell_rays *c, const accel_config *ac, const cell_settings *st, int threads, csv_row *r)
{
    const rayset_t *rs = c->rs;
    *r = (csv_row){
        .scene = c->scene->name, .prims = c->scene->prims.count, .accel = ac->ops->name, .params = ac->params_str,
        .workload = rs->workload, .rays = rs->count, .threads = threads, .seed = rs->seed, .rayset_hash = rs->hash,
        .has_counters = !(ac->ops->flags & ACCEL_OPAQUE), .illposed_rays = c->illposed, .serial = threads != st->threads,
        .repeat = st->repeat, .git_rev = st->mi->git_rev, .machine = st->mi->host, .cpu = st->mi->cpu,
        .date = st->mi->date,
    };
    /* What ran: the ray set's own image and samples (a replayed file's), else the settings' (random has no image). */
    bool image = rs->width > 0 && rs->height > 0;
    r->width = image ? (int)rs->width : st->width;
    r->height = image ? (int)rs->height : st->height;
    r->spp = image ? (int)rs->spp : st->spp;
    snprintf(r->run_id, sizeof r->run_id, "%s", run_id_current());
    cell_key_parts k = {.scene = r->scene, .accel = r->accel, .params = r->params, .workload = r->workload,
                        .wl = NULL, .rays_hash = rs->hash, .threads = st->threads, .repeat = st->repeat,
                        .warm = st->warm_passes};
    if (cell_key_format(&k, r->cell_key, sizeof r->cell_key)) {
        fprintf(stderr, "accelbench: %s %s %s: the cell key is longer than %d bytes\n", r->scene, r->accel, r->workload,
                CELL_KEY_MAX - 1);
        return -1;
    }
    return 0;
}

int measure_cell(const cell_rays *c, const accel_config *ac, const cell_settings *st, cell_result *out)
{
    const rayset_t *rs = c->rs;
    memset(&out->vr, 0, sizeof out->vr);
    csv_row *r = &out->row;
    if (rs->count == 0) {
        if (row_frame(c, ac, st, cell_threads(ac->ops, NULL, st->threads), r)) return -1;
        r->no_rays = true;
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
    paired_timing pt = timing_pairs(&sa, &se, rs, st->repeat, scratch);
    answers_free(scratch);

    const verify_result *vr = &w.vr;
    out->vr = w.vr;
    if (row_frame(c, ac, st, w.threads, r)) {
        warm_cell_release(&w);
        return -1;
    }
    r->build_ms = w.build_ms;
    r->trace_ms = pt.a.median, r->trace_ms_min = pt.a.min, r->trace_ms_max = pt.a.max;
    r->mrays_per_s = pt.a.median > 0 ? rs->count / (pt.a.median * 1e3) : 0;
    r->ratio_vs_embree = pt.ratio, r->ratio_min = pt.ratio_min, r->ratio_max = pt.ratio_max;
    r->embree_ms = pt.e.median;
    r->mem_bytes = w.a->ops->memory(w.a);
    r->counters = w.got->total;
    r->agree = vr->agree;
    r->mismatch_real = vr->mismatches[MM_REAL], r->mismatch_edge = vr->mismatches[MM_EDGE];
    r->mismatch_tol = vr->mismatches[MM_TOL], r->mismatch_refwrong = vr->mismatches[MM_REFWRONG];
    r->mismatch_origin = vr->mismatches[MM_ORIGIN], r->mismatch_unjudged = vr->mismatches[MM_UNJUDGED];
    r->judge_ms = vr->judge_ms;
    r->passes = sa.passes;
    r->timed_path = timed_path_name(w.a, rs->query);
    r->timed_from = !accel_resets(w.a) ? "" : st->warm_passes ? "warm" : "reset";
    r->nstats = read_stats(w.a, &pt, r->stats);
    warm_cell_release(&w);
    return 0;
}

void stats_format(const csv_row *row, char *buf, size_t len)
{
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; i < row->nstats && n < len; i++)
        n += (size_t)snprintf(buf + n, len - n, "%s%s %.6g", i ? ", " : "", row->stats[i].name, row->stats[i].value);
}

accel *build_reference(const scene_t *s, int threads, char *err, size_t errlen)
{
    const struct accel_ops *ops = accel_find("embree");
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
