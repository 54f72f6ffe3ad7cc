/* shard_plan.c: this shard's cells of a run --shard K/N (see shard_plan.h). */
#include "shard_plan.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cellkey.h"
#include "cells.h"
#include "output.h"
#include "shard.h"
#include "resume.h"
#include "signals.h"
#include "../workloads/resources.h"

int plan_shard(const options *o, const rayset_t *replay, const char *out_dir, const machine_info *mi,
               unsigned char **mine, char *shard_line, size_t shard_line_len)
{
    int nw = replay ? 1 : o->nworkloads;
    size_t nslots = (size_t)o->nscenes * (size_t)nw * (size_t)o->naccels;
    shard_manifest m = {.k = o->shard_k, .n = o->shard_n};
    snprintf(m.git_rev, sizeof m.git_rev, "%s", mi->git_rev);
    char opts[16384], cmd[4096], err[4400], key[CELL_KEY_MAX];
    shard_options_line(o, opts, sizeof opts);
    cmd[0] = 0;
    for (int i = 1; i < o->argc_full; i++) shell_word(cmd, sizeof cmd, o->argv_full[i]);
    m.options = opts;
    m.command = o->argc_full ? cmd : o->argv_line;
    m.cells = calloc(nslots + 1, sizeof *m.cells);
    double *cost = calloc(nslots + 1, sizeof *cost);
    int *shard_of = calloc(nslots + 1, sizeof *shard_of);
    size_t *slot = calloc(nslots + 1, sizeof *slot);
    double *load = calloc((size_t)o->shard_n, sizeof *load);
    *mine = calloc(nslots + 1, 1);
    int status = 0;
    if (!m.cells || !cost || !shard_of || !slot || !load || !*mine) {
        fprintf(stderr, "accelbench: out of memory planning the shards\n");
        status = 2;
    }
    for (int si = 0; si < o->nscenes && status == 0; si++) {
        scene_t *s = scene_load(o->scenes[si], err, sizeof err);
        if (!s) {
            fprintf(stderr, "accelbench: %s\n", err);
            status = 2;
            break;
        }
        uint64_t prims = s->prims.count;
        uint32_t nlights = s->nlights;
        scene_free(s);
        for (int wi = 0; wi < nw && status == 0; wi++) {
            query_kind q = replay ? replay->query : o->workloads[wi]->query;
            uint64_t rays = replay ? replay->count : workload_estimate(o->workloads[wi]->name, &o->wl, nlights).rays;
            for (int ai = 0; ai < o->naccels && status == 0; ai++) {
                const accel_config *ac = &o->accels[ai];
                if (!accel_runs_workload(ac->ops, q)) continue;
                if (run_cell_key(o, si, wi, ac, replay, key, sizeof key)) {
                    status = 2;
                    break;
                }
                int i = m.ncells++;
                cost[i] = shard_cell_cost(ac->ops, prims, rays, o->repeat);
                slot[i] = ((size_t)si * (size_t)nw + (size_t)wi) * (size_t)o->naccels + (size_t)ai;
                m.cells[i] = (shard_cell){.index = i, .cost = cost[i], .key = strdup(key)};
                if (!m.cells[i].key) status = 2;
            }
        }
    }
    if (status == 0 && shard_assign(cost, m.ncells, m.n, shard_of, load)) status = 2;
    int ncells_mine = 0;
    double total = 0;
    for (int i = 0; i < m.ncells && status == 0; i++) {
        m.cells[i].shard = shard_of[i] + 1;
        total += cost[i];
        if (shard_of[i] + 1 == m.k) (*mine)[slot[i]] = 1, ncells_mine++;
    }
    if (status == 0) {
        /* A folder of another shard, or of another matrix, is refused before anything is written to it. */
        char path[1200];
        snprintf(path, sizeof path, "%s/%s", out_dir, SHARD_MANIFEST);
        shard_manifest old;
        int rc = shard_manifest_read(out_dir, &old, err, sizeof err);
        if (rc < 0) {
            fprintf(stderr, "accelbench: %s\n", err);
            status = 2;
        } else if (rc == 0) {
            if (!shard_manifest_same_matrix(&old, &m)) {
                fprintf(stderr, "accelbench: %s: this folder holds shard %d/%d of %s matrix; choose another --out\n", path,
                        old.k, old.n, strcmp(old.options, m.options) || old.ncells != m.ncells ? "another" : "this");
                status = 2;
            }
            shard_manifest_free(&old);
        }
        char *text = status == 0 ? shard_manifest_format(&m) : NULL;
        if (status == 0 && !text) status = 2;
        if (text) {
            if (!signals_begin_write()) signals_end_write();
            int w = write_file_checked(path, "w", text, err, sizeof err);
            signals_end_write();
            free(text);
            if (w) {
                fprintf(stderr, "accelbench: %s\n", err);
                status = w == -2 ? 2 : 1;
            }
        }
    }
    if (status == 0) {
        double largest = 0;
        for (int k = 0; k < m.n; k++) largest = fmax(largest, load[k]);
        snprintf(shard_line, shard_line_len,
                 "shard: %d/%d: %d of the matrix's %d cells, estimated cost %.3g of %.3g (the largest shard %.3g; %s)\n",
                 m.k, m.n, ncells_mine, m.ncells, load[m.k - 1], total, largest, SHARD_MANIFEST);
        if (!o->quiet)
            fprintf(stderr, "shard %d/%d: %d of the matrix's %d cells (estimated cost %.3g of %.3g)\n", m.k, m.n,
                    ncells_mine, m.ncells, load[m.k - 1], total);
    }
    for (int i = 0; i < m.ncells; i++) free(m.cells[i].key);
    free(m.cells);
    free(cost);
    free(shard_of);
    free(slot);
    free(load);
    if (status) {
        free(*mine);
        *mine = NULL;
    }
    return status;
}
