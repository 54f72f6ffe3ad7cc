/* reproduce_kit.h: what every `accelbench reproduce EXPERIMENT` shares, so
 * that a paper's reproduction is its set-up and its tables only
 * (reproduce_woo92.c, reproduce_havran.c):
 *   - the command line (--out, --threads, --repeat, --quick, --no-plots,
 *     --quiet, --memcap) and the output folder with its CSV,
 *   - the scenes (a catalogue scene, or a generated stand-in where the
 *     catalogue's file is not on this machine, said so everywhere),
 *   - measurements: an accelerator configuration on the current scene's
 *     ray sets, each a `run` cell (measure.h: build, a verified warm-up,
 *     `repeat` timed samples paired with Embree's, medians), made once and
 *     reused when a table asks for the same configuration again, its rows
 *     written to the CSV under every (table, variant) that uses it,
 *   - the end: the report's Markdown on stdout and in a file, the plot
 *     script, the verification table, and the exit status (0; 1 a real
 *     mismatch or a failed write; 2 bad input).
 * Figures of the paper are read with figures.h from data/PAPER_figures.csv. */
#ifndef ACCELBENCH_REPRODUCE_KIT_H
#define ACCELBENCH_REPRODUCE_KIT_H

#include <stdbool.h>
#include <stdio.h>
#include "../run/machine.h"
#include "../measure/measure.h"
#include "../run/cell_row.h"

typedef struct {
    const char *out;
    const char *scenes; /* --scenes LIST, or NULL: every scene of the experiment */
    const char *accels; /* --accels LIST (spd), or NULL: the experiment's own */
    int threads, repeat;
    bool quick, plots, quiet, repeat_given;
} rp_opts;

typedef struct {
    const char *load;    /* scene_load name */
    const char *image;   /* the paper's scene or image it stands for */
    const char *why;
    const char *standin; /* generated scene measured when `load` is not on this machine, or NULL */
    const char *standin_why;
} scene_def;

#define RP_SETS_MAX 4
#define RP_SCENES_MAX 12
#define RP_MEAS_MAX 200

/* One measurement: an accelerator configuration on a scene's ray sets. */
typedef struct {
    int scene, spp, width, height;
    const struct accel_ops *ops;
    char params[512];
    int nsets;
    csv_row rows[RP_SETS_MAX];
    char workload[RP_SETS_MAX][32];
    int res[3];          /* a grid's built resolution (res_x/y/z stats), else 0 */
    char res_str[40];    /* "AxBxC", or "" for a structure that is not a grid */
    double ms, ms_min, ms_max, build_ms; /* summed over the sets */
    double embree_ms;    /* Embree's paired medians, summed over the sets */
    uint64_t rays, mem;
    counters_t c;
    uint64_t agree, mm[MM_CLASSES];
} meas;

typedef struct {
    const char *experiment;   /* "woo92" */
    const scene_def *scenes;  /* the experiment's scenes, nscenes of them */
    int nscenes;
    int timed_threads;        /* threads of every timed trace (1, or o.threads) */
    rp_opts o;
    machine_info mi;
    FILE *csv;
    char out_dir[1024], csv_path[1200];
    meas store[RP_MEAS_MAX];
    int nmeas;
    bool any_real;
    const char *label[RP_SCENES_MAX];         /* each scene's CSV name: its load name, or its stand-in's */
    char shown[RP_SCENES_MAX][160];           /* its name in the tables, a stand-in marked as one */
    char standin_reason[RP_SCENES_MAX][1024]; /* why the stand-in was measured, "" when it was not */
    /* the scene being measured */
    int cur;
    scene_t *s;
    accel *ref;
    verifier_t *ver;          /* the scene's exact judge, shared by its measurements */
    int nsets, spp, width, height;
    cell_rays cells[RP_SETS_MAX];
    double wall0;
} rp_kit;

/* The shared options' lines of `reproduce --help`. */
void rp_usage_options(FILE *out);
/* Parse argv (argv[0] is the experiment's name) into k->o: 0, 1 after
 * printing the help (usage prints it), 2 after a one-line error. */
int rp_parse(rp_kit *k, int argc, char **argv, void (*usage)(FILE *));
/* The start every experiment's entry shares: its name and scenes, the
 * shared options parsed (rp_parse), the threads of its timed traces
 * (timed_threads, or --threads when 0), and the options it does not take
 * refused: no_accels, no_scenes say why (NULL: taken). true to go on;
 * false with the exit status in *rc (0 after --help). */
bool rp_begin(rp_kit *k, const char *experiment, const scene_def *scenes, int nscenes, int timed_threads, int argc,
              char **argv, const char *no_accels, const char *no_scenes, int *rc);
/* Which of k->scenes --scenes names (by the paper's name or the load
 * name) into use[0..nscenes), all when it was not given; 0, or 2 after a
 * one-line error naming the unknown scene and the known ones. */
int rp_select_scenes(const rp_kit *k, bool *use);
/* Set the labels, the machine, the output folder (default
 * results/EXPERIMENT-<date-time>) and its EXPERIMENT.csv with the header
 * `table,variant,grid_res,` + the run CSV's columns; 0 or 2. */
int rp_start(rp_kit *k);
/* Load scene idx of k->scenes (or its stand-in), build Embree's
 * reference and the exact judge; 0 or -1 after an error on stderr. */
int rp_open_scene(rp_kit *k, int idx);
void rp_close_scene(rp_kit *k);
/* The current scene's ray sets, the named workloads (at most RP_SETS_MAX)
 * with the reference's answers; corners: rays through pixel corners,
 * (w+1)x(h+1) (the SPD's rule). */
void rp_prepare_sets(rp_kit *k, int w, int h, int spp, bool corners, int depth, const char *const *workloads, int n);
/* Measure accelerator `name` with `settings` ("k=v,k=v" over its
 * defaults) on the current ray sets, or reuse an identical earlier
 * measurement; its rows go to the CSV under (table, variant). NULL after
 * an error on stderr. */
meas *rp_measure(rp_kit *k, const char *table, const char *variant, const char *name, const char *settings);
/* Close the CSV; write the report (by report(ctx, f)) to stdout and to
 * EXPERIMENT_tables.md; run scripts/PLOT_SCRIPT unless --no-plots. The
 * exit status: rc when it is not 0, else 0, or 1 on a failed write or any
 * real mismatch. */
int rp_finish(rp_kit *k, int rc, void (*report)(void *ctx, FILE *f), void *ctx, const char *plot_script);

/* ---- numbers for the tables */
static inline double rp_per_ray(const meas *m, uint64_t v) { return m->rays ? (double)v / (double)m->rays : 0.0; }
static inline double rp_tests(const meas *m) { return rp_per_ray(m, m->c.prim_tests); }
static inline double rp_boxes(const meas *m) { return rp_per_ray(m, m->c.box_tests); }
static inline double rp_steps(const meas *m) { return rp_per_ray(m, m->c.steps); }
/* Its time over the Embree samples interleaved with it (the sums of both
 * sides' medians over the sets). */
static inline double rp_vs_embree(const meas *m) { return m->embree_ms > 0 ? m->ms / m->embree_ms : 0.0; }
/* a's time relative to b's on the same rays, through their paired Embree
 * samples: (a / Embree) / (b / Embree), so a machine that slows down
 * between the two measurements (shared, noisy) does not tilt the ratio. */
static inline double rp_relative(const meas *a, const meas *b)
{
    double eb = rp_vs_embree(b);
    return eb > 0 ? rp_vs_embree(a) / eb : 0.0;
}
/* The min-max spread of a measurement's repeats, % of its median. */
static inline double rp_spread(const meas *m) { return m->ms > 0 ? 100.0 * (m->ms_max - m->ms_min) / m->ms : 0.0; }
/* The noise band of a comparison: the larger spread, at least 1%. */
static inline double rp_noise2(const meas *a, const meas *b)
{
    double s = rp_spread(a) > rp_spread(b) ? rp_spread(a) : rp_spread(b);
    return s > 1.0 ? s : 1.0;
}

/* The distinct timed_path values of the measurements, ", "-joined. */
void rp_timed_paths(const rp_kit *k, char *buf, size_t len);
/* The report's "Verification against Embree" section: one row per named
 * group of measurements, then a last row of every measurement once and the
 * verdict line ("verified: 0 real mismatches ..." or "FAILED: ..."). */
typedef struct { const char *name; meas *const *list; int n; } rp_group;
void rp_verification(const rp_kit *k, FILE *f, const rp_group *groups, int ngroups);

#endif
