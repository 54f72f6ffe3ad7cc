/* testlib.h: small helpers shared by the integration tests. */
#ifndef ACCELBENCH_TESTLIB_H
#define ACCELBENCH_TESTLIB_H

#include <stdio.h>
#include <stdlib.h>
#include "accel/accel.h"
#include "harness/trace.h"
#include "harness/workload.h"
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
    accel *a = ops->build(s, &p, err, sizeof err);
    if (!a) {
        fprintf(stderr, "build %s failed: %s\n", name, err);
        exit(2);
    }
    a->ops = ops;
    a->scene = s;
    return a;
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

#endif
