/* cell_row.c: a measured cell as a CSV row (see cell_row.h). */
#include "cell_row.h"

#include <stdio.h>
#include <string.h>
#include "cellkey.h"

/* The row's identity, its ray set's image and what no measurement needs. */
static int row_frame(const cell_rays *c, const accel_config *ac, const row_settings *st, int threads, csv_row *r)
{
    const rayset_t *rs = c->rs;
    *r = (csv_row){
        .scene = c->scene->name, .prims = c->scene->prims.count, .accel = ac->ops->name, .params = ac->params_str,
        .workload = rs->workload, .rays = rs->count, .threads = threads, .seed = rs->seed, .rayset_hash = rs->hash,
        .has_counters = !(ac->ops->flags & ACCEL_NO_COUNTERS), .illposed_rays = c->illposed, .serial = threads != st->cell.threads,
        .repeat = st->cell.repeat, .git_rev = st->mi->git_rev, .machine = st->mi->host, .cpu = st->mi->cpu,
        .date = st->mi->date,
    };
    /* What ran: the ray set's own image and samples (a replayed file's), else the settings' (random has no image). */
    bool image = rs->width > 0 && rs->height > 0;
    r->width = image ? (int)rs->width : st->width;
    r->height = image ? (int)rs->height : st->height;
    r->spp = image ? (int)rs->spp : st->spp;
    snprintf(r->run_id, sizeof r->run_id, "%s", run_id_current());
    cell_key_parts k = {.scene = r->scene, .accel = r->accel, .params = r->params, .workload = r->workload,
                        .wl = NULL, .rays_hash = rs->hash, .threads = st->cell.threads, .repeat = st->cell.repeat,
                        .warm = st->cell.warm_passes};
    if (cell_key_format(&k, r->cell_key, sizeof r->cell_key)) {
        fprintf(stderr, "accelbench: %s %s %s: the cell key is longer than %d bytes\n", r->scene, r->accel, r->workload,
                CELL_KEY_MAX - 1);
        return -1;
    }
    return 0;
}

int cell_row(const cell_rays *c, const accel_config *ac, const row_settings *st, const cell_measurement *m, csv_row *r)
{
    if (row_frame(c, ac, st, m->threads, r)) return -1;
    if (m->no_rays) {
        r->no_rays = true;
        return 0;
    }
    const verify_result *vr = &m->vr;
    const paired_timing *pt = &m->pt;
    r->build_ms = m->build_ms;
    r->trace_ms = pt->a.median, r->trace_ms_min = pt->a.min, r->trace_ms_max = pt->a.max;
    r->mrays_per_s = pt->a.median > 0 ? c->rs->count / (pt->a.median * 1e3) : 0;
    r->ratio_vs_embree = pt->ratio, r->ratio_min = pt->ratio_min, r->ratio_max = pt->ratio_max;
    r->embree_ms = pt->e.median;
    r->mem_bytes = m->mem_bytes;
    r->counters = m->counters;
    r->agree = vr->agree;
    r->mismatch_real = vr->mismatches[MM_REAL], r->mismatch_edge = vr->mismatches[MM_EDGE];
    r->mismatch_tol = vr->mismatches[MM_TOL], r->mismatch_refwrong = vr->mismatches[MM_REFWRONG];
    r->mismatch_origin = vr->mismatches[MM_ORIGIN], r->mismatch_unjudged = vr->mismatches[MM_UNJUDGED];
    r->judge_ms = vr->judge_ms;
    r->passes = m->passes;
    r->timed_path = m->timed_path;
    r->timed_from = m->timed_from;
    r->nstats = m->nstats;
    memcpy(r->stats, m->stats, sizeof r->stats);
    return 0;
}

int measure_cell_row(const cell_rays *c, const accel_config *ac, const row_settings *st, cell_result *out)
{
    cell_measurement m;
    if (measure_cell(c, ac, &st->cell, &m)) return -1;
    out->vr = m.vr;
    return cell_row(c, ac, st, &m, &out->row) ? -2 : 0;
}

void stats_format(const csv_row *row, char *buf, size_t len)
{
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; i < row->nstats && n < len; i++)
        n += (size_t)snprintf(buf + n, len - n, "%s%s %.6g", i ? ", " : "", row->stats[i].name, row->stats[i].value);
}
