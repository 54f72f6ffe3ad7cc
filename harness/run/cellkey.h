/* cellkey.h: the identity of a CSV row: the run that wrote it and the cell
 * it measures.
 *
 * run_id: one per process, made at first use: the start time (UTC) and 24
 *   random bits, "20261122-013139-3fa9c1", so ids sort by time and two runs
 *   started in the same second differ.
 *
 * cell_key: everything that decides what a cell measures, so that two rows
 *   measure the same thing exactly when their keys are equal. A readable
 *   line of space-separated NAME=VALUE words in a fixed order:
 *
 *     scene=S accel=A params=P workload=W res=WxH spp=N corners=0|1 depth=D seed=S threads=T repeat=R
 *
 *   for rays made from options (every option that shapes a workload's rays
 *   is there for every workload, whether or not that workload reads it: a
 *   key may say "different" for rays that happen to be the same, never
 *   "same" for different ones), or
 *
 *     scene=S accel=A params=P workload=W rays=HASH threads=T repeat=R
 *
 *   for rays given as a set (a replayed --rays file, reproduce's cells):
 *   HASH is the set's rayset_hash, which covers every ray. scene is the
 *   name as given (with any @VIEW), params the accelerator's full parameter
 *   string, threads the threads asked for and repeat the timed pairs, the
 *   two options that shape the timing. Not in the key: --judge-seconds (it
 *   bounds the judge, not the rays or the timing), the machine and the
 *   build (a changed build measures the same cell; --redo measures it
 *   again). In a value, '%', a space and control characters are written
 *   %XX, so words split at spaces and the key has one reading. */
#ifndef ACCELBENCH_CELLKEY_H
#define ACCELBENCH_CELLKEY_H

#include <stddef.h>
#include <stdint.h>
#include "../workloads/workload.h"

#define RUN_ID_MAX 40
#define CELL_KEY_MAX 2048

/* This process's run id (made at the first call). */
const char *run_id_current(void);

typedef struct {
    const char *scene, *accel, *params, *workload;
    const workload_opts *wl; /* the options the rays were made from, or NULL: rays given as a set */
    uint64_t rays_hash;      /* when wl is NULL: the set's rayset_hash */
    int threads, repeat;
    bool warm;               /* run --warm-passes: the word "passes=warm" ends the key */
} cell_key_parts;

/* The key into buf (len bytes). Returns 0, or -1 when it does not fit
 * (buf then holds a cut key that must not be used). */
int cell_key_format(const cell_key_parts *k, char *buf, size_t len);

/* The value of word NAME of a key, %XX decoded, into buf. Returns 0, or -1
 * when the key has no such word or it does not fit. */
int cell_key_value(const char *key, const char *name, char *buf, size_t len);

#endif
