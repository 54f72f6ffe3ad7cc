/* csv.h: the tidy benchmark CSV, one row per (scene, accel+params,
 * workload, threads). Counter columns are per ray (averages); they are
 * empty for accelerators whose counters are not observable (Embree). The
 * columns are fixed: csv_header() lists them, one stat_NAME for every
 * statistic a registered accelerator declares included (accel_stat_column),
 * so every row of every run has the same columns whatever it measured. Every row carries the run that wrote it
 * (run_id) and the cell it measures (cell_key, cellkey.h), so a results
 * file can be resumed and deduplicated (resume.h).
 *
 * This file formats rows and splits records (RFC 4180); resume.h keeps
 * run's matrix.csv on disk (appending, replacing, repairing a torn tail). */
#ifndef ACCELBENCH_CSV_H
#define ACCELBENCH_CSV_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include "../../accel/accel.h"
#include "cellkey.h"

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
    int width, height, spp;    /* the ray set's image and samples; 0 = none (written empty) */
    int repeat;
    int passes;                /* traces of the ray set per timed sample; times are per pass */
    const char *timed_path;    /* "fast", "counting" or "opaque": the methods the timed samples called */
    const char *timed_from;    /* "reset": an accelerator with reset() timed from its post-build state every pass;
                                  "warm": not reset (run --warm-passes); "": it has no reset() */
    accel_stat stats[ACCEL_STATS_MAX]; /* the accelerator's statistics (names from accel_stat_column) */
    int nstats;
    /* A ray set of no rays: nothing was built, traced or timed, and every
     * column that would be a time, a rate, a ratio, memory, a per-ray
     * counter or a statistic is written empty (counts stay: 0 of 0). */
    bool no_rays;
    char run_id[RUN_ID_MAX];     /* the run that measured it (cellkey.h) */
    char cell_key[CELL_KEY_MAX]; /* what it measured (cellkey.h); stored, not pointed to: rows are copied */
    const char *git_rev, *machine, *cpu, *date;
} csv_row;

/* The header line (no newline) into buf; the longest is under CSV_HEADER_MAX. */
#define CSV_HEADER_MAX 4096
void csv_header(char *buf, size_t len);
/* The statistics with CSV columns of their own (a cost model's predicted
 * counters per ray), NULL-terminated. */
extern const char *const csv_predicted_columns[];
/* The number of columns of csv_header(). */
int csv_columns(void);
/* The 0-based index of column `name` in csv_header(), or -1. */
int csv_column_index(const char *name);

/* The row as one CSV record with its newline, in a malloc'd buffer (the
 * caller frees *text). Returns 0, or -1 when out of memory. */
int csv_format_row(const csv_row *r, char **text, size_t *len);
/* Write the row to f and flush it. Returns 0, or -1 with errno set when a
 * write or the flush failed (the caller reports "PATH: write failed"). */
int csv_write_row(FILE *f, const csv_row *r);
/* One text field as the rows write it: quoted (RFC 4180) when it holds a
 * comma, quote or line break, and a leading = + - @ tab, return or quote
 * guarded with a ' so that a spreadsheet does not run it as a formula. */
void csv_put_text(FILE *f, const char *s);

/* Where one field lies in a record's text: len bytes from off, quotes
 * included when quoted. */
typedef struct {
    size_t off, len;
    bool quoted;
} csv_span;

/* One record of RFC 4180 CSV starting at text[0] of n bytes: fields are
 * quoted when they hold a comma, a quote or a line break, a quote inside
 * is doubled, and a record ends at an unquoted "\n" (or "\r\n"). Returns
 * the record's length in bytes including its line break, with *nfields its
 * field count and *complete whether a line break ended it (false: the text
 * ran out first, a torn record). The first maxfields fields' spans go to
 * spans (may be NULL). */
size_t csv_split_record(const char *text, size_t n, int *nfields, bool *complete, csv_span *spans, int maxfields);
/* A field's value, unquoted and without the ' that guards a text field
 * beginning with =, +, -, @, tab, carriage return or ' (a spreadsheet
 * would run the others as a formula), into buf (cut to len - 1 bytes,
 * NUL-terminated). */
void csv_field(const char *text, csv_span span, char *buf, size_t len);

#endif
