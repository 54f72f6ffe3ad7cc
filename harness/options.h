/* options.h: the command line of accelbench's subcommands. */
#ifndef ACCELBENCH_OPTIONS_H
#define ACCELBENCH_OPTIONS_H

#include <stdbool.h>
#include <stdint.h>
#include "../accel/accel.h"
#include "workload.h"

#define OPT_LIST_MAX 64
/* The longest --out, --save-rays and --rays path, in bytes (longer ones are refused, never cut). */
#define OPT_PATH_MAX 1023

/* --up and --light, as run, verify, render and scene info take them. */
#define SCENE_UP_LIGHT_USAGE \
    "  --up X|Y|Z|auto         the up axis of the camera: a scene with no camera of its own (a mesh file, a catalogue\n" \
    "                          mesh without a named view) gets its automatic camera and lights built around it; a\n" \
    "                          camera of the scene's (NFF, spd:, gen:, a named view) keeps its eye and look-at and\n" \
    "                          turns its up vector to it. auto: the scene's thinnest bounding-box extent, ties to Y,\n" \
    "                          then Z. Default: auto for a mesh file (file:PATH or a path) without a view; a catalogue\n" \
    "                          mesh keeps Y (Z when Y alone is thinnest). Same as the view part up=AXIS\n" \
    "  --light X,Y,Z           a point light at X,Y,Z; repeatable up to 4 times; the lights given replace the scene's\n" \
    "                          (its own, or the automatic two above and behind the camera). Same as the part light=X,Y,Z\n" \
    "                          --view, --up and --light make one view, applied to every scene: the CSV's scene column\n" \
    "                          says it (mesh.obj@up=Z;light=0,0,9)\n"

typedef struct {
    const struct accel_ops *ops;
    accel_params params;
    char params_str[512]; /* every parameter, "k=v,k=v" in table order (the CSV's params) */
    char label[600];      /* name, with [params] when they differ from the defaults */
} accel_config;

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
    uint64_t memcap_mib;  /* --memcap MIB, 0 for the default (scenes/memory_cap.h, harness/resources.h) */
    char **owned;         /* copies of option strings the lists point into, freed by options_free */
    int nowned;
} options;

/* Parse the options of subcommand `cmd` (run, verify, render). Returns 0,
 * 1 after printing --help, or 2 after printing a one-line error. */
int options_parse(options *o, const char *cmd, int argc, char **argv);
void options_free(options *o);
void options_usage(FILE *out, const char *cmd);
/* The verify command line that replays ray `ray` of one cell exactly: the
 * scene, the ray file or every option that shaped the ray set (workload,
 * res, spp, seed, depth, corners), the accelerator and each of its
 * parameters that differs from the default. */
void options_replay_command(const options *o, const char *scene, const char *workload, const accel_config *ac,
                            uint32_t ray, char *buf, size_t len);

#endif
