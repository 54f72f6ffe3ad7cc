/* csv.h: the tidy benchmark CSV, one row per (scene, accel+params,
 * workload, threads). Rows are appended and flushed as each cell finishes,
 * so an interrupted run loses at most the cell it was in. Counter columns
 * are per ray (averages); they are empty for accelerators whose counters
 * are not observable (Embree). The columns are fixed: csv_header() lists
 * them, one stat_NAME for every name of accel_stat_names[] included, so
 * every row of every run has the same columns whatever it measured. */
#ifndef ACCELBENCH_CSV_H
#define ACCELBENCH_CSV_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include "../accel/accel.h"

typedef struct {
    const char *scene;
    uint32_t prims;
    const char *accel, *params, *workload;
    uint32_t rays;
    int threads;
    uint64_t seed, rayset_hash;
    double build_ms, trace_ms, trace_ms_min, trace_ms_max, mrays_per_s;
    double ratio_vs_embree, ratio_min, ratio_max; /* median, min and max of the paired samples' ratios */
    double embree_ms;          /* the median of the Embree series paired with this row's */
    uint64_t mem_bytes;
    bool has_counters;
    counters_t counters;       /* totals; divided by rays when written */
    uint64_t agree, mismatch_real, mismatch_edge, mismatch_tol, mismatch_refwrong;
    uint64_t mismatch_origin, mismatch_unjudged; /* ill-posed rays; rays the judge's budget did not reach */
    uint32_t illposed_rays;    /* rays of the set whose reference hit lies within the origin bound */
    double judge_ms;           /* time the exact judge spent on this cell */
    bool serial;               /* traced on one thread because the accelerator mutates */
    int width, height, spp, repeat;
    int passes;                /* traces of the ray set per timed sample; times are per pass */
    const char *timed_path;    /* "fast", "counting" or "opaque": the methods the timed samples called */
    accel_stat stats[ACCEL_STATS_MAX]; /* the accelerator's statistics (names from accel_stat_names[]) */
    int nstats;
    const char *git_rev, *machine, *cpu, *date;
} csv_row;

/* The header line (no newline) into buf; the longest is under CSV_HEADER_MAX. */
#define CSV_HEADER_MAX 4096
void csv_header(char *buf, size_t len);

/* Open PATH for appending; writes the header when the file is new or
 * empty, refuses a file whose header differs. NULL + err on failure. */
FILE *csv_open(const char *path, char *err, size_t errlen);
void csv_write_row(FILE *f, const csv_row *r);

#endif
