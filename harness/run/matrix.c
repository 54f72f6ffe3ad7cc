/* matrix.c: the run loop (see matrix.h). It files each cell's row in the
 * results store as the cell finishes (resume.h), skips the cells the store
 * has with the same cell key (cellkey.h) unless --redo, and lets
 * SIGINT/SIGTERM abandon a cell but never a row (signals.h). */
#include "matrix.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>
#include "cell_row.h"
#include "cellkey.h"
#include "cells.h"
#include "shard_plan.h"
#include "csv.h"
#include "machine.h"
#include "../measure/measure.h"
#include "output.h"
#include "../workloads/resources.h"
#include "resume.h"
#include "shard.h"
#include "run_outputs.h"
#include "signals.h"
#include "../workloads/trace.h"
#include "../measure/verify.h"
#include "version.h"

static double monotonic_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* The progress line of a measured cell, and its statistics on a line of
 * their own. The time left is this process's mean time a measured cell
 * times the cells after this one (cells a resume skips among them make it
 * an overestimate). */
static double progress_start; /* when matrix_run began measuring */

static void print_progress(int done, int total, const cell_result *cr, const char *label)
{
    static int measured;
    measured++;
    double elapsed = monotonic_s() - progress_start, left = elapsed / measured * (total - done);
    const csv_row *r = &cr->row;
    fprintf(stderr, "[%d/%d] %s %s %s: %u rays, build %.1f ms, trace %.2f ms (%.3f Mrays/s, %.2fx embree, pairs "
                    "%.2f-%.2f, %s), agree %llu, real mismatches %llu; %.0f s in, about %.0f s left\n",
            done, total, term_text(r->scene), label, r->workload, r->rays, r->build_ms, r->trace_ms, r->mrays_per_s,
            r->ratio_vs_embree, r->ratio_min, r->ratio_max, r->timed_path, (unsigned long long)r->agree,
            (unsigned long long)r->mismatch_real, elapsed, left);
    if (r->nstats) {
        char buf[1024];
        stats_format(r, buf, sizeof buf);
        fprintf(stderr, "        stats: %s\n", buf);
    }
}

/* The command that resumes this run: the one typed, with --out DIR when
 * it had none (the default folder is named for the time). */
static void resume_command(const options *o, const char *out_dir, char *buf, size_t len)
{
    buf[0] = 0;
    for (int i = 0; i < o->argc_full; i++) shell_word(buf, len, o->argv_full[i]);
    if (!o->argc_full) shell_word(buf, len, "accelbench run ...");
    if (!o->out) {
        shell_word(buf, len, "--out");
        shell_word(buf, len, out_dir);
    }
}

/* The cells of a run: every (scene, workload, accelerator) the
 * accelerator answers, each to run or already done. */
enum { CELL_NONE, CELL_RUN, CELL_DONE };

typedef struct {
    unsigned char *state;  /* [scene][workload][accel] */
    int nw, total, done;   /* workloads per scene; cells; cells the CSV has */
    int other_build;       /* done cells whose row another build (git_rev) measured */
    const unsigned char *mine; /* run --shard: [scene][workload][accel] 1 for this shard's cells; NULL: all */
} run_cells;

static unsigned char *cell_state(run_cells *c, const options *o, int si, int wi, int ai)
{
    return &c->state[((size_t)si * (size_t)c->nw + (size_t)wi) * (size_t)o->naccels + (size_t)ai];
}

/* Which cells are there and which the store already has. Returns 0 or 2 (printed). */
static int plan_cells(const options *o, const results_store *store, const rayset_t *replay, const char *git_rev,
                      const unsigned char *mine, run_cells *c)
{
    memset(c, 0, sizeof *c);
    c->mine = mine;
    c->nw = replay ? 1 : o->nworkloads;
    c->state = calloc((size_t)o->nscenes * (size_t)c->nw * (size_t)o->naccels, 1);
    if (!c->state) {
        fprintf(stderr, "accelbench: out of memory planning the cells\n");
        return 2;
    }
    char key[CELL_KEY_MAX];
    for (int si = 0; si < o->nscenes; si++)
        for (int wi = 0; wi < c->nw; wi++)
            for (int ai = 0; ai < o->naccels; ai++) {
                const accel_config *ac = &o->accels[ai];
                query_kind q = replay ? replay->query : o->workloads[wi]->query;
                if (!accel_runs_workload(ac->ops, q)) continue;
                if (c->mine && !c->mine[((size_t)si * (size_t)c->nw + (size_t)wi) * (size_t)o->naccels + (size_t)ai]) continue;
                if (run_cell_key(o, si, wi, ac, replay, key, sizeof key)) return 2;
                c->total++;
                const char *rev = NULL;
                bool done = results_find(store, key, &rev) != NULL;
                c->done += done;
                c->other_build += done && rev && strcmp(rev, git_rev) != 0;
                *cell_state(c, o, si, wi, ai) = done && !o->redo ? CELL_DONE : CELL_RUN;
            }
    return 0;
}

/* Whether any cell of scene si (workload wi, or all when wi < 0) is to run. */
static bool cells_to_run(run_cells *c, const options *o, int si, int wi)
{
    for (int w = wi < 0 ? 0 : wi; w < (wi < 0 ? c->nw : wi + 1); w++)
        for (int ai = 0; ai < o->naccels; ai++)
            if (*cell_state(c, o, si, w, ai) == CELL_RUN) return true;
    return false;
}

static int cells_in(run_cells *c, const options *o, int si, int wi)
{
    int n = 0;
    for (int w = wi < 0 ? 0 : wi; w < (wi < 0 ? c->nw : wi + 1); w++)
        for (int ai = 0; ai < o->naccels; ai++) n += *cell_state(c, o, si, w, ai) != CELL_NONE;
    return n;
}

/* What the folder held, said before any work. */
static void print_found(const options *o, const char *csv_path, const results_found *f, const run_cells *c)
{
    if (f->torn_line)
        fprintf(stderr, "accelbench: %s: line %d: a torn row (%s), left by a run killed while writing it: dropped; "
                        "its cell runs again\n", csv_path, f->torn_line, f->torn_why);
    if (f->rows == 0) return; /* said even with --quiet: it decides what this run measures */
    char runs[32] = "";
    if (f->runs > 0) snprintf(runs, sizeof runs, " from %d run%s", f->runs, f->runs == 1 ? "" : "s");
    if (c->done == 0) {
        fprintf(stderr, "accelbench: %s: %d rows%s; none of this run's %d cells is among them\n", csv_path, f->rows,
                runs, c->total);
        return;
    }
    fprintf(stderr, "accelbench: %s: %d rows%s; %d of this run's %d cells are done with the same options: %s\n",
            csv_path, f->rows, runs, c->done, c->total,
            o->redo ? "measuring them again (--redo), their rows replaced" : "skipping them (--redo measures them again)");
    if (c->other_build)
        fprintf(stderr, "accelbench: note: %d of them were measured by another build than this one (%s)%s\n",
                c->other_build, ACCELBENCH_GIT_REV, o->redo ? "" : "; --redo measures them with this one");
}

/* run.txt: the command, the machine and the run id, appended for each
 * invocation. Returns 0, or 1/2 after printing why. */
static int write_run_info(const options *o, const char *info_path, const machine_info *mi, const run_cells *c,
                          const char *shard_line)
{
    char text[8192], err[1200], cmd[4096];
    cmd[0] = 0;
    for (int i = 1; i < o->argc_full; i++) shell_word(cmd, sizeof cmd, o->argv_full[i]);
    snprintf(text, sizeof text,
             "command: %s\nrun_id: %s\nmachine: %s\ncpu: %s\ngit_rev: %s\ndate: %s\nthreads: %d\nrepeat: %d (timed "
             "samples, each paired with one of Embree's at the same thread count, after 1 warm-up; medians reported)\n"
             "cells: %d, of which %d were in matrix.csv already%s\n%s\n",
             o->argc_full ? cmd : o->argv_line, run_id_current(), mi->host, mi->cpu, mi->git_rev, mi->date, o->threads,
             o->repeat, c->total, c->done, c->done ? (o->redo ? " (measured again: --redo)" : " (skipped)") : "",
             shard_line ? shard_line : "");
    if (!signals_begin_write()) signals_end_write();
    int rc = write_file_checked(info_path, "a", text, err, sizeof err);
    signals_end_write();
    if (rc == 0) return 0;
    fprintf(stderr, "accelbench: %s\n", err);
    return rc == -2 ? 2 : 1;
}

/* Measure one cell and file its row. Returns 0, 1 (a write failed), 2, or
 * CELL_BUILD_FAILED (its build failed, said on stderr; no row). */
#define CELL_BUILD_FAILED 3
static int run_one_cell(const options *o, results_store *store, const cell_rays *in, int si, int wi,
                        const accel_config *ac, const row_settings *settings, const rayset_t *replay_key, int index,
                        int total)
{
    cell_result cr;
    char key[CELL_KEY_MAX], err[1200];
    int m = measure_cell_row(in, ac, settings, &cr);
    if (m) return m == -1 ? CELL_BUILD_FAILED : 2;
    if (run_cell_key(o, si, wi, ac, replay_key, key, sizeof key)) return 2;
    snprintf(cr.row.cell_key, sizeof cr.row.cell_key, "%s", key);
    char *text;
    size_t len;
    if (csv_format_row(&cr.row, &text, &len)) {
        fprintf(stderr, "accelbench: out of memory formatting a row\n");
        return 2;
    }
    /* The row goes in whole or not at all: a signal now waits for it. */
    if (!signals_begin_write()) signals_end_write();
    int rc = results_put(store, key, text, len, err, sizeof err);
    signals_end_write();
    free(text);
    if (rc) {
        fprintf(stderr, "accelbench: %s\n", err);
        return 1;
    }
    signals_cell_done();
    if (!o->quiet) print_progress(index, total, &cr, ac->label);
    return 0;
}

int matrix_run(options *o)
{
    char out_dir[1024], csv_path[1100], info_path[1100], err[1200];
    /* Everything the command names is read or checked before the folder is touched. */
    rayset_t *replay = NULL;
    if (o->rays_file) {
        replay = rayset_load(o->rays_file, err, sizeof err);
        if (!replay) {
            fprintf(stderr, "accelbench: %s\n", err);
            return 2;
        }
    }
    int nw = o->rays_file ? 1 : o->nworkloads;
    if (check_pairs(o, "run", replay, false) || save_rays_check(o, o->nscenes * nw)) {
        rayset_free(replay);
        return 2;
    }
    /* Keys of a replay name its rays by hash; that copy outlives the set given to the first cell. */
    rayset_t replay_key;
    if (replay) replay_key = *replay;
    const rayset_t *rk = replay ? &replay_key : NULL;

    machine_info mi;
    machine_describe(&mi);
    if (output_folder(o->out, "", out_dir, sizeof out_dir)) {
        rayset_free(replay);
        return 2;
    }
    snprintf(csv_path, sizeof csv_path, "%s/matrix.csv", out_dir);
    snprintf(info_path, sizeof info_path, "%s/run.txt", out_dir);

    /* From here a signal abandons the cell in progress and says how to go on. */
    char cmd[6144], msg[7000];
    resume_command(o, out_dir, cmd, sizeof cmd);
    snprintf(msg, sizeof msg, "Every finished cell is in %s; to resume (the cells there are skipped):\n  %s\n%s",
             csv_path, cmd, o->redo ? "(with --redo, that measures every cell again, those this run redid too)\n" : "");
    signals_install(msg);

    results_found found;
    int status;
    if (!signals_begin_write()) signals_end_write();
    results_store *store = results_open(out_dir, csv_path, &found, err, sizeof err, &status);
    signals_end_write();
    if (!store) {
        fprintf(stderr, "accelbench: %s\n", err);
        signals_restore();
        rayset_free(replay);
        return status;
    }
    run_cells cells = {0};
    unsigned char *mine = NULL;
    char shard_line[512] = "";
    status = o->shard_n ? plan_shard(o, rk, out_dir, &mi, &mine, shard_line, sizeof shard_line) : 0;
    if (status == 0) status = plan_cells(o, store, rk, mi.git_rev, mine, &cells);
    if (status == 0) {
        print_found(o, csv_path, &found, &cells);
        status = write_run_info(o, info_path, &mi, &cells, o->shard_n ? shard_line : NULL);
    }
    if (status == 0) check_pairs(o, "run", rk, true);

    row_settings settings = {.cell = {.threads = o->threads, .repeat = o->repeat, .warm_passes = o->warm_passes},
                             .width = o->wl.width, .height = o->wl.height, .spp = o->wl.spp, .mi = &mi};
    if (replay) settings.width = settings.height = settings.spp = 0; /* a replayed file's image is its own, or none */
    int index = 0, measured = 0, failed_builds = 0;
    progress_start = monotonic_s();
    double wall0 = clock_ms();
    for (int si = 0; si < o->nscenes && status == 0; si++) {
        /* A scene whose cells are all done is not even loaded (unless its rays are to be saved). */
        if (!o->save_rays && !cells_to_run(&cells, o, si, -1)) {
            index += cells_in(&cells, o, si, -1);
            continue;
        }
        accel *ref;
        verifier_t *ver;
        scene_t *s = open_scene(o, si, &ref, &ver);
        if (!s) {
            status = 2;
            break;
        }
        for (int wi = 0; wi < nw && status == 0; wi++) {
            if (!o->save_rays && !cells_to_run(&cells, o, si, wi)) {
                index += cells_in(&cells, o, si, wi);
                continue;
            }
            cell_rays in;
            if (cell_prepare(o, s, ref, ver, o->workloads[wi], &replay, &in)) {
                status = 2;
                break;
            }
            if (o->save_rays) {
                if (!signals_begin_write()) signals_end_write();
                if (save_rays(o, in.rs, o->nscenes * nw)) status = 1;
                signals_end_write();
            }
            if (in.rs->count == 0 && !o->quiet && status == 0)
                fprintf(stderr, "  %s %s: the ray set has no rays: nothing is built or timed; its rows say rays 0, "
                                "the measured columns empty\n", term_text(s->name), in.rs->workload);
            for (int ai = 0; ai < o->naccels && status == 0; ai++) {
                unsigned char st = *cell_state(&cells, o, si, wi, ai);
                if (st == CELL_NONE) continue;
                index++;
                if (st == CELL_DONE) continue;
                status = run_one_cell(o, store, &in, si, wi, &o->accels[ai], &settings, rk, index, cells.total);
                measured += status == 0;
                if (status == CELL_BUILD_FAILED) {
                    failed_builds++;
                    status = o->keep_going ? 0 : 2;
                }
            }
            cell_rays_release(&in);
        }
        close_scene(s, ref, ver);
    }
    /* Signals may end the process at once again: nothing is written after this. */
    if (results_close(store, err, sizeof err) && status == 0) {
        fprintf(stderr, "accelbench: %s\n", err);
        status = 1;
    }
    signals_restore();
    rayset_free(replay);
    free(cells.state);
    free(mine);
    if (!o->quiet && status == 0) {
        int skipped = index - measured - failed_builds;
        if (measured == 0 && failed_builds == 0 && cells.total > 0)
            fprintf(stderr, "nothing to measure: all %d cells of this run are in %s\n", cells.total, csv_path);
        else
            fprintf(stderr, "wrote %s (%d cells measured%s, %.1f s)\n", csv_path, measured,
                    skipped ? ", the others done before" : "", (clock_ms() - wall0) / 1e3);
    }
    if (status == 1) fprintf(stderr, "accelbench: %s holds every cell finished before the failure\n", csv_path);
    if (failed_builds && status == 0) {
        /* --keep-going: the others are measured and plotted; the run still says it was not whole. */
        fprintf(stderr, "accelbench: %d cell(s) not measured: their builds failed (above); the run goes on to the "
                        "end with --keep-going, and exits 2\n", failed_builds);
    }
    if (o->report && status == 0) {
        if (run_dir_outputs(out_dir, o->quiet)) status = 1;
    } else if (o->plots && status == 0) run_plot_script("plot.py", csv_path, o->quiet);
    return status == 0 && failed_builds ? 2 : status;
}
