/* shard.c: run --shard's split of a matrix and its manifest (see shard.h). */
#include "shard.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int shard_parse(const char *s, int *k, int *n, char *err, size_t errlen)
{
    long a, b;
    char *end;
    errno = 0;
    a = strtol(s, &end, 10);
    bool good = !errno && end != s && *end == '/' && end[1] >= '0' && end[1] <= '9';
    if (good) {
        const char *t = end + 1;
        b = strtol(t, &end, 10);
        good = !errno && end != t && *end == 0 && s[0] >= '0' && s[0] <= '9';
    }
    if (!good || a < 1 || b < 1 || a > b || b > SHARD_MAX) {
        snprintf(err, errlen, "--shard %s: expected K/N with 1 <= K <= N <= %d", s, SHARD_MAX);
        return -1;
    }
    *k = (int)a;
    *n = (int)b;
    return 0;
}

double shard_cell_cost(const struct accel_ops *ops, uint64_t prims, uint64_t rays, int repeat)
{
    double P = (double)prims, R = (double)rays, L = log2(P + 2.0), passes = repeat + 1.0;
    double wt = ops->cost.trace > 0 ? ops->cost.trace : ACCEL_COST_DEFAULT;
    double wb = ops->cost.build > 0 ? ops->cost.build : ACCEL_COST_DEFAULT;
    double build = wb * P * L;
    double trace = ops->cost.shape & ACCEL_COST_TRACE_LINEAR ? wt * R * P : wt * R * L;
    if (ops->cost.shape & ACCEL_COST_BUILD_EACH_PASS) build *= passes;
    return build + passes * trace + (1.0 + repeat) * R * L;
}

typedef struct { double cost; int index; } cost_ref;

static int by_cost_desc(const void *a, const void *b)
{
    const cost_ref *x = a, *y = b;
    if (x->cost != y->cost) return x->cost > y->cost ? -1 : 1;
    return (x->index > y->index) - (x->index < y->index);
}

int shard_assign(const double *cost, int ncells, int nshards, int *shard_of, double *load)
{
    cost_ref *order = malloc((size_t)(ncells > 0 ? ncells : 1) * sizeof *order);
    double *sum = calloc((size_t)nshards, sizeof *sum);
    if (!order || !sum) {
        free(order);
        free(sum);
        return -1;
    }
    for (int i = 0; i < ncells; i++) order[i] = (cost_ref){cost[i], i};
    qsort(order, (size_t)ncells, sizeof *order, by_cost_desc);
    /* Largest first, each to the least-loaded shard (the lowest of equals). A
     * linear scan: N <= 4096 and matrices of thousands of cells. */
    for (int i = 0; i < ncells; i++) {
        int best = 0;
        for (int s = 1; s < nshards; s++)
            if (sum[s] < sum[best]) best = s;
        sum[best] += order[i].cost;
        shard_of[order[i].index] = best;
    }
    if (load) memcpy(load, sum, (size_t)nshards * sizeof *sum);
    free(order);
    free(sum);
    return 0;
}

/* Append " NAME=VALUE" (VALUE's spaces as %20: the line splits at spaces). */
static void put(char *buf, size_t len, const char *name, const char *value)
{
    size_t n = strlen(buf);
    n += (size_t)snprintf(buf + n, n < len ? len - n : 0, "%s%s=", n ? " " : "", name);
    for (const char *c = value; *c && n + 4 < len; c++) {
        if (*c == ' ' || *c == '%' || (unsigned char)*c < ' ') n += (size_t)snprintf(buf + n, len - n, "%%%02X", (unsigned char)*c);
        else buf[n++] = *c, buf[n] = 0;
    }
}

void shard_options_line(const options *o, char *buf, size_t len)
{
    char v[4096];
    buf[0] = 0;
    v[0] = 0;
    for (int i = 0; i < o->nscenes; i++) snprintf(v + strlen(v), sizeof v - strlen(v), "%s%s", i ? "," : "", o->scenes[i]);
    put(buf, len, "scenes", v);
    v[0] = 0;
    for (int i = 0; i < o->naccels; i++)
        snprintf(v + strlen(v), sizeof v - strlen(v), "%s%s[%s]", i ? "," : "", o->accels[i].ops->name, o->accels[i].params_str);
    put(buf, len, "accels", v);
    v[0] = 0;
    if (!o->rays_file)
        for (int i = 0; i < o->nworkloads; i++) snprintf(v + strlen(v), sizeof v - strlen(v), "%s%s", i ? "," : "", o->workloads[i]->name);
    put(buf, len, "workloads", o->rays_file ? "(rays file)" : v);
    snprintf(v, sizeof v, "%dx%d", o->wl.width, o->wl.height);
    put(buf, len, "res", v);
    snprintf(v, sizeof v, "%d", o->wl.spp);
    put(buf, len, "spp", v);
    put(buf, len, "corners", o->wl.corners ? "1" : "0");
    snprintf(v, sizeof v, "%d", o->wl.depth);
    put(buf, len, "depth", v);
    snprintf(v, sizeof v, "%llu", (unsigned long long)o->wl.seed);
    put(buf, len, "seed", v);
    snprintf(v, sizeof v, "%d", o->threads);
    put(buf, len, "threads", v);
    snprintf(v, sizeof v, "%d", o->repeat);
    put(buf, len, "repeat", v);
    put(buf, len, "warm-passes", o->warm_passes ? "1" : "0");
    put(buf, len, "rays", o->rays_file ? o->rays_file : "-");
    snprintf(v, sizeof v, "%g", o->judge_seconds);
    put(buf, len, "judge-seconds", v);
    snprintf(v, sizeof v, "%llu", (unsigned long long)o->memcap_mib);
    put(buf, len, "memcap", v);
}

/* ------------------------------------------------------------ the manifest */

char *shard_manifest_format(const shard_manifest *m)
{
    size_t len = 512 + strlen(m->options) + strlen(m->command ? m->command : "");
    for (int i = 0; i < m->ncells; i++) len += strlen(m->cells[i].key) + 64;
    char *text = malloc(len);
    if (!text) return NULL;
    size_t n = (size_t)snprintf(text, len, "%s\nshard: %d/%d\ngit_rev: %s\noptions: %s\ncommand: %s\ncells: %d\n",
                                SHARD_MANIFEST_MAGIC, m->k, m->n, m->git_rev, m->options, m->command ? m->command : "",
                                m->ncells);
    for (int i = 0; i < m->ncells && n < len; i++)
        n += (size_t)snprintf(text + n, len - n, "cell: %d %d %.6g %s\n", m->cells[i].index, m->cells[i].shard,
                              m->cells[i].cost, m->cells[i].key);
    return text;
}

void shard_manifest_free(shard_manifest *m)
{
    for (int i = 0; i < m->ncells; i++) free(m->cells[i].key);
    free(m->cells);
    free(m->options);
    free(m->command);
    memset(m, 0, sizeof *m);
}

/* The value after "name: " on line, or NULL. */
static const char *field(const char *line, const char *name)
{
    size_t n = strlen(name);
    return strncmp(line, name, n) == 0 && line[n] == ':' && line[n + 1] == ' ' ? line + n + 2 : NULL;
}

int shard_manifest_read(const char *dir, shard_manifest *m, char *err, size_t errlen)
{
    memset(m, 0, sizeof *m);
    char path[4200];
    snprintf(path, sizeof path, "%s/%s", dir, SHARD_MANIFEST);
    FILE *f = fopen(path, "r");
    if (!f) {
        snprintf(err, errlen, "%s: cannot open: %s%s", path, strerror(errno),
                 errno == ENOENT ? " (not a folder written by run --shard)" : "");
        return errno == ENOENT ? 1 : -1;
    }
    char *line = NULL;
    size_t cap = 0;
    ssize_t got;
    int lineno = 0, want_cells = -1, rc = 0;
    bool have_shard = false;
    while ((got = getline(&line, &cap, f)) >= 0 && rc == 0) {
        lineno++;
        if (got > 0 && line[got - 1] == '\n') line[--got] = 0;
        const char *v;
        if (lineno == 1) {
            if (strcmp(line, SHARD_MANIFEST_MAGIC)) {
                snprintf(err, errlen, "%s: line 1: not a shard manifest (want '%s')", path, SHARD_MANIFEST_MAGIC);
                rc = -1;
            }
        } else if ((v = field(line, "shard"))) {
            char why[256];
            if (shard_parse(v, &m->k, &m->n, why, sizeof why)) {
                snprintf(err, errlen, "%s: line %d: %s", path, lineno, why);
                rc = -1;
            }
            have_shard = true;
        } else if ((v = field(line, "git_rev"))) {
            snprintf(m->git_rev, sizeof m->git_rev, "%s", v);
        } else if ((v = field(line, "options"))) {
            free(m->options);
            m->options = strdup(v);
        } else if ((v = field(line, "command"))) {
            free(m->command);
            m->command = strdup(v);
        } else if ((v = field(line, "cells"))) {
            want_cells = atoi(v);
            if (want_cells < 0 || want_cells > 100000000) {
                snprintf(err, errlen, "%s: line %d: bad cell count '%s'", path, lineno, v);
                rc = -1;
            } else if (!(m->cells = calloc((size_t)want_cells + 1, sizeof *m->cells))) {
                snprintf(err, errlen, "%s: out of memory", path);
                rc = -1;
            }
        } else if ((v = field(line, "cell"))) {
            shard_cell c;
            int used = 0;
            if (!m->cells || m->ncells >= want_cells || sscanf(v, "%d %d %lf %n", &c.index, &c.shard, &c.cost, &used) < 3 ||
                !used || !v[used] || c.index != m->ncells || c.shard < 1 || c.shard > m->n) {
                snprintf(err, errlen, "%s: line %d: a malformed or unexpected cell line", path, lineno);
                rc = -1;
                break;
            }
            c.key = strdup(v + used);
            m->cells[m->ncells++] = c;
        } else {
            snprintf(err, errlen, "%s: line %d: unknown line '%.60s'", path, lineno, line);
            rc = -1;
        }
    }
    free(line);
    fclose(f);
    if (rc == 0 && (!have_shard || !m->options || want_cells != m->ncells)) {
        snprintf(err, errlen, "%s: incomplete (%s)", path,
                 !have_shard ? "no shard line" : !m->options ? "no options line" : "fewer cell lines than 'cells:' says");
        rc = -1;
    }
    if (rc) shard_manifest_free(m);
    return rc;
}

bool shard_manifest_same_matrix(const shard_manifest *a, const shard_manifest *b)
{
    if (a->k != b->k || a->n != b->n || a->ncells != b->ncells || strcmp(a->options, b->options)) return false;
    for (int i = 0; i < a->ncells; i++)
        if (a->cells[i].shard != b->cells[i].shard || strcmp(a->cells[i].key, b->cells[i].key)) return false;
    return true;
}
