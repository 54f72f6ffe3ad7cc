/* measure.c: timing, building and folders shared by run and reproduce
 * (see measure.h). Moved unchanged from matrix.c. */
#include "measure.h"

#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#include <string.h>
#include <time.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/stat.h>

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

timing time_traces(accel *a, const rayset_t *rs, int threads, int repeat, double warm_ms, answers_t *scratch)
{
    timing t;
    t.passes = warm_ms >= SAMPLE_MIN_MS ? 1 : warm_ms <= SAMPLE_MIN_MS / PASSES_MAX ? PASSES_MAX
                                                                                    : (int)ceil(SAMPLE_MIN_MS / warm_ms);
    double *ms = calloc((size_t)repeat, sizeof *ms);
    if (!ms) abort();
    for (int k = 0; k < repeat; k++) ms[k] = trace_rayset_passes(a, rs, threads, t.passes, scratch) / t.passes;
    qsort(ms, (size_t)repeat, sizeof *ms, cmp_double);
    t.median = repeat % 2 ? ms[repeat / 2] : 0.5 * (ms[repeat / 2 - 1] + ms[repeat / 2]);
    t.min = ms[0];
    t.max = ms[repeat - 1];
    free(ms);
    return t;
}

int mkdir_p(const char *path)
{
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", path);
    for (char *p = buf + 1; *p; p++)
        if (*p == '/') {
            *p = 0;
            if (mkdir(buf, 0777) && errno != EEXIST) return -1;
            *p = '/';
        }
    return mkdir(buf, 0777) && errno != EEXIST ? -1 : 0;
}

static const struct accel_ops *reference_ops(void) { return accel_find("embree"); }

accel *build_reference(const scene_t *s, int threads, char *err, size_t errlen)
{
    const struct accel_ops *ops = reference_ops();
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

int output_folder(const char *given, const char *prefix, char *out, size_t outlen)
{
    if (given) snprintf(out, outlen, "%s", given);
    else {
        char stamp[32];
        time_t now = time(NULL);
        struct tm tm;
        gmtime_r(&now, &tm);
        strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
        snprintf(out, outlen, "results/%s%s", prefix, stamp);
    }
    if (mkdir_p(out)) {
        fprintf(stderr, "accelbench: %s: cannot create output folder: %s\n", out, strerror(errno));
        return 2;
    }
    return 0;
}

void run_plot_script(const char *script, const char *csv_path, bool quiet)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 '%s/scripts/%s' '%s' %s", ACCELBENCH_SOURCE_DIR, script, csv_path,
             quiet ? "--quiet" : "");
    int rc = system(cmd);
    if (rc != 0) fprintf(stderr, "accelbench: warning: plotting failed (exit %d); the CSV is complete: %s\n", rc, csv_path);
}
