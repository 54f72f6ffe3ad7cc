/* testlib.h: small helpers shared by the integration tests. */
#ifndef ACCELBENCH_TESTLIB_H
#define ACCELBENCH_TESTLIB_H

#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <string.h>
#include "accel/accel.h"
#include "harness/workloads/trace.h"
#include "harness/measure/verify.h"
#include "harness/workloads/workload.h"
#include "check.h"

static inline scene_t *test_scene(const char *name)
{
    char err[512];
    scene_t *s = scene_load(name, err, sizeof err);
    if (!s) {
        fprintf(stderr, "cannot load scene %s: %s\n", name, err);
        exit(2);
    }
    return s;
}

/* Build a registered accelerator with its default parameters. */
static inline accel *test_build(const char *name, const scene_t *s, int threads)
{
    const struct accel_ops *ops = accel_find(name);
    if (!ops) {
        fprintf(stderr, "no accelerator %s\n", name);
        exit(2);
    }
    accel_params p;
    params_defaults(&p, ops->params);
    p.threads = threads;
    char err[512];
    accel *a = accel_build(ops, s, &p, err, sizeof err);
    if (!a) {
        fprintf(stderr, "build %s failed: %s\n", name, err);
        exit(2);
    }
    return a;
}

/* Build ops with "k=v,k=v" over its defaults; NULL with the reason. An
 * item memcap=MIB is not a table key: it sets the harness's memory cap
 * (accel_params.memcap_mib), as --memcap would. */
static inline accel *test_build_with(const struct accel_ops *ops, const scene_t *s, const char *settings, int threads,
                                     char *err, size_t errlen)
{
    accel_params p;
    params_defaults(&p, ops->params);
    p.threads = threads;
    char rest[1024] = "";
    const char *q = settings ? settings : "";
    while (*q) {
        size_t len = strcspn(q, ",");
        if (!strncmp(q, "memcap=", 7) && len > 7) p.memcap_mib = strtoull(q + 7, NULL, 10);
        else snprintf(rest + strlen(rest), sizeof rest - strlen(rest), "%s%.*s", *rest ? "," : "", (int)len, q);
        q += len + (q[len] == ',');
    }
    if (params_set_list(&p, rest, err, errlen)) return NULL;
    return accel_build(ops, s, &p, err, errlen);
}

/* Build the registered accelerator `name` with "k=v,k=v" over its defaults
 * on one thread, or print why and exit 2 (a test that cannot build its
 * subject proves nothing). */
static inline accel *test_build_or_die(const char *name, const scene_t *s, const char *settings)
{
    const struct accel_ops *ops = accel_find(name);
    char err[512] = "not registered";
    accel *a = ops ? test_build_with(ops, s, settings, 1, err, sizeof err) : NULL;
    if (!a) {
        fprintf(stderr, "%s [%s] on %s: %s\n", name, settings ? settings : "", s->name, err);
        exit(2);
    }
    return a;
}

/* The statistic `name` of a built accelerator (accel_stats), or NAN when
 * it reports none: a prediction a structure does not state is absent. */
static inline double test_stat(const accel *a, const char *name)
{
    accel_stat st[ACCEL_STATS_MAX];
    int n = accel_stats(a, st, ACCEL_STATS_MAX);
    for (int i = 0; i < n; i++)
        if (!strcmp(st[i].name, name)) return st[i].value;
    return NAN;
}

/* The build of `name` with settings cfg must be refused with a reason that
 * names needle (a parameter, a limit): one CHECK, one printed line. */
static inline void test_expect_refusal(const char *name, const scene_t *s, const char *cfg, const char *needle)
{
    char err[512] = "";
    accel *a = test_build_with(accel_find(name), s, cfg, 1, err, sizeof err);
    CHECK_MSG(a == NULL && strstr(err, needle) != NULL, "%s [%s]: %s (the reason must name \"%s\")", name, cfg,
              a ? "accepted" : err, needle);
    printf("%s refused [%s]: %s\n", name, cfg, err);
    if (a) a->ops->destroy(a);
}

/* scene_finish() on a scene a test made by hand, or print why and exit 2. */
static inline void test_finish_scene(scene_t *s)
{
    char err[256];
    if (scene_finish(s, false, err, sizeof err)) {
        fprintf(stderr, "%s: %s\n", s->name, err);
        exit(2);
    }
}

/* A small deterministic generator (the tests must not depend on libc's):
 * uniform in [0, 1) from the caller's state. */
static inline float test_urand(uint32_t *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (float)(*state >> 8) / 16777216.0f;
}

static inline workload_opts test_wl(int w, int h, int threads)
{
    workload_opts o = {.width = w, .height = h, .spp = 1, .depth = 3, .seed = 7, .threads = threads};
    return o;
}

static inline answers_t *test_trace(accel *a, const rayset_t *rs, int threads)
{
    answers_t *ans = answers_new(rs, false);
    trace_rayset(a, rs, threads, ans);
    return ans;
}

/* Every workload at res x res through accelerator a and the reference ref,
 * one printed line each: the ray set is not empty, the reference hits
 * something (else the check proves nothing), no real mismatch, and at
 * least 99.9 % of the rays agree outright. */
static inline void test_workloads_agree(const scene_t *s, accel *ref, accel *a, int res, const char *label)
{
    workload_opts o = test_wl(res, res, 2);
    int threads = (a->ops->flags & ACCEL_MUTATES) ? 1 : 2;
    for (int w = 0; workload_table[w].name; w++) {
        const char *wl = workload_table[w].name;
        rayset_t *rs = workload_table[w].make(s, ref, &o);
        answers_t *want = test_trace(ref, rs, 2), *got = test_trace(a, rs, threads);
        verify_result vr;
        verify_answers(s, rs, got, want, &vr);
        uint64_t hits = 0;
        for (uint32_t i = 0; i < rs->count; i++)
            hits += rs->query == QUERY_ANY ? want->occluded[i] : want->hits[i].prim != HIT_NONE;
        printf("%-16s %-22s %-10s rays %6u hits %6llu agree %6llu", s->name, label, wl, rs->count,
               (unsigned long long)hits, (unsigned long long)vr.agree);
        for (int c = 0; c < MM_CLASSES; c++) printf(" %s %llu", mismatch_class_name[c], (unsigned long long)vr.mismatches[c]);
        printf("\n");
        bool excused = rs->count == 0 && workload_empty_by_rule(&workload_table[w], s);
        CHECK_MSG(rs->count > 0 || excused, "%s %s: empty ray set", s->name, wl);
        CHECK_MSG(hits > 0 || excused, "%s %s: the reference hit nothing; the test would prove nothing", s->name, wl);
        CHECK_MSG(vr.mismatches[MM_REAL] == 0, "%s %s %s: %llu real mismatches", s->name, label, wl,
                  (unsigned long long)vr.mismatches[MM_REAL]);
        CHECK_MSG(vr.agree * 1000 >= (uint64_t)rs->count * 999, "%s %s %s: only %llu of %u agree", s->name, label, wl,
                  (unsigned long long)vr.agree, rs->count);
        answers_free(want);
        answers_free(got);
        rayset_free(rs);
    }
}

#endif
