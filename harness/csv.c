/* csv.c: writing the benchmark CSV (see csv.h). */
#include "csv.h"

#include <errno.h>
#include <inttypes.h>
#include <string.h>

/* The columns before and after the stat_NAME ones. */
static const char *const columns_head[] = {
    "scene", "prims", "accel", "params", "workload", "rays", "threads", "seed", "rayset_hash",
    "build_ms", "trace_ms", "trace_ms_min", "trace_ms_max", "mrays_per_s", "ratio_vs_embree", "ratio_min",
    "ratio_max", "embree_ms", "mem_bytes", "bytes_per_prim", "tests_per_ray", "prim_hits_per_ray", "box_tests_per_ray",
    "steps_per_ray", "empty_leaves_per_ray", "mailbox_hits_per_ray", "agree", "mismatch_real",
    "mismatch_edge", "mismatch_tol", "mismatch_refwrong", "mismatch_origin", "mismatch_unjudged", "illposed_rays",
    "judge_ms", "serial", "res", "spp", "repeat", "passes", "timed_path", NULL,
};
static const char *const columns_tail[] = {"git_rev", "machine", "cpu", "date", NULL};

/* Appends the column PREFIX NAME to the header in buf (length n so far),
 * after a comma unless it is the first; returns the new length. */
static size_t append_column(char *buf, size_t len, size_t n, const char *prefix, const char *name)
{
    if (n < len) n += (size_t)snprintf(buf + n, len - n, "%s%s%s", n ? "," : "", prefix, name);
    return n;
}

void csv_header(char *buf, size_t len)
{
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; columns_head[i]; i++) n = append_column(buf, len, n, "", columns_head[i]);
    for (int i = 0; accel_stat_names[i]; i++) n = append_column(buf, len, n, "stat_", accel_stat_names[i]);
    for (int i = 0; columns_tail[i]; i++) n = append_column(buf, len, n, "", columns_tail[i]);
}

FILE *csv_open(const char *path, char *err, size_t errlen)
{
    char header[CSV_HEADER_MAX];
    csv_header(header, sizeof header);
    FILE *f = fopen(path, "a+");
    if (!f) {
        snprintf(err, errlen, "%s: cannot open for appending: %s", path, strerror(errno));
        return NULL;
    }
    fseek(f, 0, SEEK_END);
    if (ftell(f) == 0) {
        fprintf(f, "%s\n", header);
        fflush(f);
        return f;
    }
    char first[CSV_HEADER_MAX] = "";
    rewind(f);
    if (!fgets(first, sizeof first, f)) first[0] = 0;
    first[strcspn(first, "\r\n")] = 0;
    if (strcmp(first, header) != 0) {
        snprintf(err, errlen, "%s: exists with other columns; choose a new --out", path);
        fclose(f);
        return NULL;
    }
    fseek(f, 0, SEEK_END);
    return f;
}

/* RFC 4180: quote a field holding a comma, quote or newline. */
static void put_text(FILE *f, const char *s)
{
    if (!s) s = "";
    if (!strpbrk(s, ",\"\n\r")) {
        fputs(s, f);
        return;
    }
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"') fputc('"', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

static void put_per_ray(FILE *f, const csv_row *r, uint64_t total)
{
    if (r->has_counters) fprintf(f, ",%.6g", r->rays ? (double)total / (double)r->rays : 0.0);
    else fputc(',', f);
}

/* One field per name of accel_stat_names[], empty where the accelerator
 * reports no such statistic. */
static void put_stats(FILE *f, const csv_row *r)
{
    for (int i = 0; accel_stat_names[i]; i++) {
        fputc(',', f);
        for (int k = 0; k < r->nstats; k++)
            if (strcmp(r->stats[k].name, accel_stat_names[i]) == 0) {
                fprintf(f, "%.6g", r->stats[k].value);
                break;
            }
    }
}

void csv_write_row(FILE *f, const csv_row *r)
{
    put_text(f, r->scene);
    fprintf(f, ",%" PRIu32 ",", r->prims);
    put_text(f, r->accel);
    fputc(',', f);
    put_text(f, r->params);
    fputc(',', f);
    put_text(f, r->workload);
    fprintf(f, ",%" PRIu32 ",%d,%" PRIu64 ",%016" PRIx64, r->rays, r->threads, r->seed, r->rayset_hash);
    fprintf(f, ",%.4f,%.4f,%.4f,%.4f,%.6g,%.6g,%.6g,%.6g,%.4f", r->build_ms, r->trace_ms, r->trace_ms_min,
            r->trace_ms_max, r->mrays_per_s, r->ratio_vs_embree, r->ratio_min, r->ratio_max, r->embree_ms);
    fprintf(f, ",%" PRIu64 ",%.6g", r->mem_bytes, r->prims ? (double)r->mem_bytes / r->prims : 0.0);
    put_per_ray(f, r, r->counters.prim_tests);
    put_per_ray(f, r, r->counters.prim_hits);
    put_per_ray(f, r, r->counters.box_tests);
    put_per_ray(f, r, r->counters.steps);
    put_per_ray(f, r, r->counters.empty_leaves);
    put_per_ray(f, r, r->counters.mailbox_hits);
    fprintf(f, ",%" PRIu64 ",%" PRIu64 ",%" PRIu64 ",%" PRIu64 ",%" PRIu64, r->agree, r->mismatch_real,
            r->mismatch_edge, r->mismatch_tol, r->mismatch_refwrong);
    fprintf(f, ",%" PRIu64 ",%" PRIu64 ",%" PRIu32 ",%.1f", r->mismatch_origin, r->mismatch_unjudged, r->illposed_rays,
            r->judge_ms);
    fprintf(f, ",%d,%dx%d,%d,%d,%d,", r->serial ? 1 : 0, r->width, r->height, r->spp, r->repeat, r->passes);
    put_text(f, r->timed_path);
    put_stats(f, r);
    const char *const tail[] = {r->git_rev, r->machine, r->cpu, r->date}; /* columns_tail */
    for (int i = 0; i < 4; i++) {
        fputc(',', f);
        put_text(f, tail[i]);
    }
    fputc('\n', f);
    fflush(f);
}
