/* test_measure.c: the measuring kit of run and reproduce: the trace paths
 * (trace.c), paired timing with resets and lazy build times (timing.c),
 * the threads a cell of a serial accelerator traces on (measure.c),
 * the CSV's fixed columns (csv.c), a paper's figures file (figures.c) and
 * report Markdown (markdown.c). A fake accelerator counts what the harness
 * calls, so the tests check the calls, not timings. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "check.h"
#include "harness/run/csv.h"
#include "harness/measure/measure.h"
#include "harness/run/cell_row.h"
#include "harness/reproduce/figures.h"
#include "harness/reproduce/markdown.h"
#include "harness/measure/timing.h"
#include "harness/workloads/trace.h"

/* ------------------------------------------------------------ a fake accelerator */

typedef struct {
    accel base;
    long counting, fast, resets, since_reset;
} fake;

static accel *fake_build(const scene_t *s, const accel_params *p, char *err, size_t errlen)
{
    (void)s, (void)p, (void)err, (void)errlen;
    fake *f = calloc(1, sizeof *f);
    if (!f) abort();
    return &f->base;
}
static bool fake_intersect(accel *a, accel_ctx *ctx, const ray_t *r, hit_t *h, counters_t *c)
{
    (void)ctx, (void)r, (void)h, (void)c;
    ((fake *)a)->counting++;
    return false;
}
static bool fake_occluded(accel *a, accel_ctx *ctx, const ray_t *r, counters_t *c)
{
    (void)ctx, (void)r, (void)c;
    ((fake *)a)->counting++;
    return false;
}
static bool fake_intersect_fast(accel *a, accel_ctx *ctx, const ray_t *r, hit_t *h)
{
    (void)ctx, (void)r, (void)h;
    fake *f = (fake *)a;
    f->fast++, f->since_reset++;
    return false;
}
static bool fake_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *r)
{
    (void)ctx, (void)r;
    ((fake *)a)->fast++;
    return false;
}
static size_t fake_memory(const accel *a)
{
    (void)a;
    return sizeof(fake);
}
static void fake_destroy(accel *a) { free(a); }
static void fake_reset(accel *a)
{
    fake *f = (fake *)a;
    f->resets++, f->since_reset = 0;
}
/* lazy_build_ms: the rays traced since the last reset, a stand-in for the
 * time a lazy structure spends building, which resets to zero. */
static int fake_stats(const accel *a, accel_stat *out, int max)
{
    if (max < 1) return 0;
    out[0] = (accel_stat){"lazy_build_ms", (double)((const fake *)a)->since_reset};
    return 1;
}

static const accel_param no_params[] = {PARAM_ROW_END};

/* Version 2 with every method: mutates, so it must reset. */
static const struct accel_ops fake_v2 = {
    .version = 2, .name = "fake", .summary = "counts calls", .paper = "-", .params = no_params,
    .flags = ACCEL_MUTATES, .build = fake_build, .intersect = fake_intersect, .occluded = fake_occluded,
    .memory = fake_memory, .destroy = fake_destroy, .stats = fake_stats, .reset = fake_reset,
    .intersect_fast = fake_intersect_fast, .occluded_fast = fake_occluded_fast,
};
/* Version 1: no fast methods, no reset. */
static const struct accel_ops fake_v1 = {
    .version = 1, .name = "fake1", .summary = "counts calls", .paper = "-", .params = no_params,
    .build = fake_build, .intersect = fake_intersect, .occluded = fake_occluded,
    .memory = fake_memory, .destroy = fake_destroy,
};

/* An accelerator whose answers depend on the order of its rays
 * (order_dependent) though its table does not say ACCEL_MUTATES: every
 * trace of it must run on one thread. od_threads counts the threads its
 * counting method was called on. */
static pthread_mutex_t od_lock = PTHREAD_MUTEX_INITIALIZER;
static pthread_t od_first;
static int od_threads;

static bool od_intersect(accel *a, accel_ctx *ctx, const ray_t *r, hit_t *h, counters_t *c)
{
    (void)a, (void)ctx, (void)r, (void)h, (void)c;
    pthread_mutex_lock(&od_lock);
    if (od_threads == 0) od_first = pthread_self(), od_threads = 1;
    else if (!pthread_equal(od_first, pthread_self())) od_threads = 2;
    pthread_mutex_unlock(&od_lock);
    return false;
}
static bool od_yes(const accel *a) { (void)a; return true; }
static bool od_no(const accel *a) { (void)a; return false; }

static const struct accel_ops fake_od = {
    .version = 2, .name = "fake-od", .summary = "order-dependent", .paper = "-", .params = no_params,
    .build = fake_build, .intersect = od_intersect, .occluded = fake_occluded, .memory = fake_memory,
    .destroy = fake_destroy, .order_dependent = od_yes,
};
static const struct accel_ops fake_free_order = {
    .version = 2, .name = "fake-free", .summary = "order-free", .paper = "-", .params = no_params,
    .build = fake_build, .intersect = od_intersect, .occluded = fake_occluded, .memory = fake_memory,
    .destroy = fake_destroy, .order_dependent = od_no,
};

static fake *fake_new(const struct accel_ops *ops, const scene_t *s)
{
    accel_params p;
    params_defaults(&p, ops->params);
    char err[256];
    accel *a = accel_build(ops, s, &p, err, sizeof err);
    if (!a) {
        fprintf(stderr, "fake build: %s\n", err);
        exit(2);
    }
    return (fake *)a;
}

static rayset_t *some_rays(query_kind q, uint32_t n)
{
    rayset_t *rs = rayset_new("test", "test", 1, q);
    for (uint32_t i = 0; i < n; i++) {
        ray_t r = {.org = v3(0, 0, (float)i), .dir = v3(0, 0, 1), .tnear = 0, .tfar = 1e30f, .light = RAY_NO_LIGHT};
        rayset_push(rs, &r, i);
    }
    rayset_seal(rs);
    return rs;
}

/* ------------------------------------------------------------ tests */

static void test_trace_paths(const scene_t *s)
{
    const uint32_t n = 100;
    for (int q = 0; q < 2; q++) {
        rayset_t *rs = some_rays(q ? QUERY_ANY : QUERY_CLOSEST, n);
        answers_t *ans = answers_new(rs, false);
        fake *f2 = fake_new(&fake_v2, s), *f1 = fake_new(&fake_v1, s);
        CHECK(trace_has_fast(&f2->base, rs->query) && !trace_has_fast(&f1->base, rs->query));
        trace_rayset_passes(&f2->base, rs, 1, 3, TRACE_FAST, ans);
        CHECK_MSG(f2->fast == 3 * n && f2->counting == 0, "fast path: %ld fast, %ld counting calls", f2->fast, f2->counting);
        trace_rayset_passes(&f2->base, rs, 1, 1, TRACE_COUNTING, ans);
        CHECK(f2->counting == n);
        /* No fast methods: the fast path traces the counting ones. */
        trace_rayset_passes(&f1->base, rs, 2, 2, TRACE_FAST, ans);
        CHECK_MSG(f1->counting == 2 * n && f1->fast == 0, "fallback: %ld counting calls", f1->counting);
        f1->base.ops->destroy(&f1->base);
        f2->base.ops->destroy(&f2->base);
        answers_free(ans);
        rayset_free(rs);
    }
}

static void test_pairs(const scene_t *s)
{
    const uint32_t n = 50;
    rayset_t *rs = some_rays(QUERY_CLOSEST, n);
    answers_t *scratch = answers_new(rs, false);
    fake *a = fake_new(&fake_v2, s), *e = fake_new(&fake_v1, s);
    timed_series sa = {.a = &a->base, .threads = 1, .path = TRACE_FAST, .passes = 2};
    timed_series se = {.a = &e->base, .threads = 1, .path = TRACE_FAST, .passes = 3};
    paired_timing t = timing_pairs(&sa, &se, rs, 5, scratch);
    /* Every pass of an accelerator with reset() starts from a reset. */
    CHECK_MSG(a->resets == 5 * 2, "%ld resets, want 10", a->resets);
    CHECK(a->fast == 5 * 2 * n && a->counting == 0);
    CHECK(e->counting == 5 * 3 * n && e->resets == 0);
    /* lazy_build_ms: what one pass did since its reset; none for e. */
    CHECK_NEAR(t.a.lazy_build_ms, n, 0);
    CHECK(isnan(t.e.lazy_build_ms));
    CHECK(t.ratio_min <= t.ratio && t.ratio <= t.ratio_max && t.ratio_min > 0);
    CHECK(t.a.min <= t.a.median && t.a.median <= t.a.max && t.e.min <= t.e.median && t.e.median <= t.e.max);
    /* timing_trace_once starts from a reset too. */
    long before = a->resets;
    timing_trace_once(&sa, rs, scratch);
    CHECK(a->resets == before + 1 && a->since_reset == n);
    CHECK(timing_passes(25) == 1 && timing_passes(5) == 4 && timing_passes(1e-6) == PASSES_MAX);
    /* Calibration: the fastest of CALIBRATION_TRACES traces (the fake's
     * take microseconds), each from a reset; a long first trace ends it. */
    before = a->resets;
    CHECK(timing_calibrate(&sa, rs, scratch, -1) == PASSES_MAX && a->resets == before + CALIBRATION_TRACES);
    CHECK(timing_calibrate(&sa, rs, scratch, 10.0) == PASSES_MAX && a->resets == before + 2 * CALIBRATION_TRACES - 1);
    CHECK(timing_calibrate(&sa, rs, scratch, 3 * SAMPLE_MIN_MS) == 1 && a->resets == before + 2 * CALIBRATION_TRACES - 1);
    /* A warm series (run --warm-passes) is never reset: its passes trace
     * what the earlier ones left, so lazy_build_ms keeps growing from the
     * last reset (here: every ray traced since). */
    timed_series warm = sa;
    warm.warm = true;
    accel_reset(&a->base);
    before = a->resets;
    long fast_before = a->fast;
    paired_timing tw = timing_pairs(&warm, &se, rs, 3, scratch);
    CHECK_MSG(a->resets == before, "a warm series was reset %ld times", a->resets - before);
    CHECK(a->fast == fast_before + 3 * 2 * n && a->since_reset == 3 * 2 * n);
    CHECK(tw.a.lazy_build_ms > n);
    timing_trace_once(&warm, rs, scratch);
    CHECK(a->resets == before && a->since_reset == 3 * 2 * n + n);
    CHECK(timing_calibrate(&warm, rs, scratch, -1) == PASSES_MAX && a->resets == before);
    a->base.ops->destroy(&a->base);
    e->base.ops->destroy(&e->base);
    answers_free(scratch);
    rayset_free(rs);
}

/* One rule for a serial cell: measure_cell traces an order-dependent
 * instance (warm-up and timed passes) on one thread whatever is asked, and
 * its row says threads 1, serial; an order-free one gets the threads asked. */
static void test_serial_cell(const scene_t *s)
{
    fake *ref = fake_new(&fake_v1, s);
    verifier_t *ver = verifier_new(s, 0);
    machine_info mi = {0};
    row_settings st = {.cell = {.threads = 4, .repeat = 1}, .mi = &mi};
    for (int od = 1; od >= 0; od--) {
        cell_rays c;
        cell_rays_init(&c, s, &ref->base, ver, some_rays(QUERY_CLOSEST, 4096), st.cell.threads);
        accel_config ac = {.ops = od ? &fake_od : &fake_free_order};
        params_defaults(&ac.params, ac.ops->params);
        snprintf(ac.label, sizeof ac.label, "%s", ac.ops->name);
        od_threads = 0;
        cell_measurement m;
        CHECK(measure_cell(&c, &ac, &st.cell, &m) == 0);
        csv_row row;
        CHECK(cell_row(&c, &ac, &st, &m, &row) == 0);
        if (od) {
            CHECK_MSG(od_threads == 1, "an order-dependent accelerator traced on %d threads", od_threads);
            CHECK(m.threads == 1 && row.threads == 1 && row.serial);
        } else {
            CHECK(od_threads >= 1);
            CHECK(m.threads == 4 && row.threads == 4 && !row.serial);
        }
        cell_rays_release(&c);
    }
    verifier_free(ver);
    ref->base.ops->destroy(&ref->base);
}

static void test_csv_header(void)
{
    char h[CSV_HEADER_MAX];
    csv_header(h, sizeof h);
    CHECK(strncmp(h, "scene,prims,", 12) == 0);
    CHECK(strstr(h, ",ratio_vs_embree,ratio_min,ratio_max,embree_ms,") != NULL);
    CHECK(strstr(h, ",passes,timed_path,timed_from,stat_") != NULL);
    /* Every statistic has a column: stat_NAME, or, for a prediction of a
     * counter (predicted_*_per_ray), one of its own beside the counters. */
    for (int i = 0; accel_stat_column(i); i++) {
        const char *name = accel_stat_column(i);
        char col[80], own[80];
        snprintf(col, sizeof col, ",stat_%s,", name);
        snprintf(own, sizeof own, ",%s,", name);
        bool predicted = !strncmp(name, "predicted_", 10);
        CHECK_MSG(predicted ? strstr(h, own) && !strstr(h, col) && csv_column_index(name) < csv_column_index("agree")
                            : strstr(h, col) != NULL,
                  "no column for statistic %s", name);
    }
    size_t len = strlen(h);
    CHECK(len > 5 && strcmp(h + len - 5, ",date") == 0);
}

static void test_figures(void)
{
    char path[] = "/tmp/accelbench-figures-XXXXXX";
    int fd = mkstemp(path);
    FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL;
    if (!f) {
        CHECK(!"cannot write a temporary file");
        return;
    }
    fputs("table,row,quantity,value,unit\n"
          "t1,all,machine,Mac IIfx,\n"
          "t1,a,time,7:55,m:ss\n"
          "t1,a,pct,13.6,pct\n"
          "t1,b,time,1:02:03,h:mm:ss\n"
          "t1,a,grid,15x9x5,cells\n"
          "t2,x,n,1,count\n",
          f);
    fclose(f);
    char err[256];
    figures *fg = figures_load(path, err, sizeof err);
    CHECK(fg != NULL);
    if (fg) {
        CHECK_NEAR(figures_number(fg, "t1", "a", "time"), 475, 0);
        CHECK_NEAR(figures_number(fg, "t1", "b", "time"), 3723, 0);
        CHECK_NEAR(figures_number(fg, "t1", "a", "pct"), 13.6, 1e-12);
        CHECK(strcmp(figures_text(fg, "t1", "all", "machine"), "Mac IIfx") == 0);
        CHECK(figures_missing(fg) == NULL);
        const char *rows[4];
        CHECK(figures_rows(fg, "t1", rows, 4) == 2 && !strcmp(rows[0], "a") && !strcmp(rows[1], "b"));
        CHECK(isnan(figures_number(fg, "t1", "a", "grid")));
        CHECK(figures_missing(fg) && !strcmp(figures_missing(fg), "t1,a,grid"));
        CHECK(figures_text(fg, "t1", "c", "time") == NULL && !strcmp(figures_missing(fg), "t1,a,grid"));
        figures_free(fg);
    }
    f = fopen(path, "w");
    fputs("table,row,value\nt1,a,1\n", f);
    fclose(f);
    CHECK(figures_load(path, err, sizeof err) == NULL && strstr(err, path) && strstr(err, ":1:"));
    f = fopen(path, "w");
    fputs("table,row,quantity,value,unit\nt1,a,time\n", f);
    fclose(f);
    CHECK(figures_load(path, err, sizeof err) == NULL && strstr(err, ":2:"));
    remove(path);
    CHECK(figures_load(path, err, sizeof err) == NULL && strstr(err, path));
}

static void test_report(void)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    md_heading(f, 2, "Table %d", 1);
    md_table(f, "Name|Time ms:|%Saved:");
    md_row(f, "%s|%.1f|%d%%", "old", 12.34, 5);
    md_end(f);
    md_bullet(f, 1, "b%d", 2);
    md_finding(f, "it is %s.", "faster");
    md_para(f, "end");
    md_section(f, "Ablation", "from %s", "old");
    fclose(f);
    const char *want = "## Table 1\n\n"
                       "| Name | Time ms | %Saved |\n|---|---:|---:|\n"
                       "| old | 12.3 | 5% |\n\n"
                       "  - b2\n"
                       "finding: it is faster.\n\n"
                       "end\n\n"
                       "## Ablation\n\nfrom old\n\n";
    CHECK_MSG(strcmp(buf, want) == 0, "report:\n%s", buf);
    free(buf);
}

int main(void)
{
    char err[256];
    scene_t *s = scene_load("spd:balls:1", err, sizeof err);
    if (!s) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    test_trace_paths(s);
    test_pairs(s);
    test_serial_cell(s);
    test_csv_header();
    test_figures();
    test_report();
    scene_free(s);
    return check_report();
}
