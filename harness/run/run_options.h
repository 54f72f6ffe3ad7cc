/* run_options.h: what a run, verify or render command was given, parsed
 * and checked (cli/options.h parses it). */
#ifndef ACCELBENCH_RUN_OPTIONS_H
#define ACCELBENCH_RUN_OPTIONS_H

#include <stdbool.h>
#include <stdint.h>
#include "../measure/accel_choice.h"
#include "../workloads/workload.h"

/* The longest --out, --save-rays and --rays path, in bytes (longer ones are refused, never cut). */
#define OPT_PATH_MAX 1023

typedef struct {
    const char *scenes[OPT_LIST_MAX];
    int nscenes;
    accel_config accels[OPT_LIST_MAX];
    int naccels;
    const workload_def *workloads[OPT_LIST_MAX];
    int nworkloads;
    workload_opts wl;     /* res, spp, corners, depth, seed, threads */
    int threads;
    int repeat;
    const char *out;      /* run: output folder; render: PNG path */
    const char *rays_file;
    const char *save_rays;
    long ray_index;       /* verify --ray I, or -1 */
    bool plots;           /* run: call scripts/plot.py at the end */
    bool report;          /* run --report: plots and report.html at the end (run_outputs.h) */
    double heatmap_max;   /* render --heatmap-max N: the colour scale's top (0: the image's own maximum) */
    bool redo;            /* run --redo: measure cells the CSV already has again, replacing their rows (resume.h) */
    bool keep_going;      /* run --keep-going: a cell whose build fails is reported and skipped, the run goes on */
    bool warm_passes;     /* run --warm-passes: timed passes of a resetting accelerator keep what earlier passes built */
    int shard_k, shard_n; /* run --shard K/N: only shard K of N (shard.h); 0, 0 for the whole matrix */
    int argc_full;        /* main's argc and argv (set by main.c): run prints the command that resumes it */
    char **argv_full;
    const char *heatmap;  /* render: NULL, "tests" or "steps" */
    bool shadow_accel;    /* render --shadow-accel A: accels[1] answers the shadow rays, accels[0] everything else */
    bool quiet;
    bool res_given;       /* --res was on the command line */
    double judge_seconds; /* the exact judge's time budget per cell (0: none) */
    char *argv_line;      /* the command as typed, for run.txt */
    const char *view;     /* --view, --up and --light as one view spec (view_spec), or NULL; every scenes[i] then
                           * ends in "@SPEC" */
    char view_spec[1024];
    char *view_names;     /* the storage of those scene names */
    uint64_t memcap_mib;  /* --memcap MIB, 0 for the default (scenes/memory_cap.h, harness/workloads/resources.h) */
    char **owned;         /* copies of option strings the lists point into, freed by options_free */
    int nowned;
} options;

#endif
