/* matrix.c: the run and verify loops (see matrix.h). run files each
 * cell's row in the results store as the cell finishes (resume.h), skips
 * the cells the store has with the same cell key (cellkey.h) unless
 * --redo, and lets SIGINT/SIGTERM abandon a cell but never a row
 * (signals.h). */
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
#include "cellkey.h"
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

/* Write a ray set to path through a temporary file beside it, renamed
 * into place, so that a run killed mid-write leaves no torn file under
 * the name (a path that is not a regular file is refused: nothing may
 * replace a device or a pipe). */
static int save_rays_file(const rayset_t *rs, const char *path, char *err, size_t errlen)
{
    if (output_replaceable(path, err, errlen)) return -1;
    char real[PATH_MAX], tmp[PATH_MAX + 64];
    if (!realpath(path, real)) snprintf(real, sizeof real, "%s", path);
    const char *slash = strrchr(real, '/');
    snprintf(tmp, sizeof tmp, "%.*s.%s.tmp.%ld", slash ? (int)(slash - real + 1) : 0, real, slash ? slash + 1 : real,
             (long)getpid());
    char why[1024];
    if (rayset_save(rs, tmp, why, sizeof why)) {
        unlink(tmp);
        size_t tl = strlen(tmp);
        /* rayset_save named the temporary file; the user knows the path. */
        snprintf(err, errlen, "%s%s", path, strncmp(why, tmp, tl) == 0 ? why + tl : why);
        return -1;
    }
    if (rename(tmp, real) != 0) {
        snprintf(err, errlen, "%s: write failed: %s", path, strerror(errno));
        unlink(tmp);
        return -1;
    }
    return 0;
}

/* Where --save-rays writes the set rs, one of nsets: the file itself, or a file in its folder. */
static void save_rays_path(const options *o, const rayset_t *rs, int nsets, char *path, size_t len)
{
    if (nsets == 1) {
        snprintf(path, len, "%s", o->save_rays);
        return;
    }
    char safe[256];
    snprintf(safe, sizeof safe, "%s", rs->scene);
    for (char *p = safe; *p; p++)
        if (*p == '/' || *p == ':') *p = '_';
    snprintf(path, len, "%s/%s__%s.rays", o->save_rays, safe, rs->workload);
}

/* --save-rays, checked before any work: the folder of several sets is
 * made, the folder of one set's file must exist. Returns 0 or 2 (printed). */
static int save_rays_check(const options *o, int nsets)
{
    if (!o->save_rays) return 0;
    if (nsets > 1) {
        if (mkdir_p(o->save_rays) != 0) {
            fprintf(stderr, "accelbench: --save-rays %s: cannot create folder: %s\n", o->save_rays, strerror(errno));
            return 2;
        }
        struct stat st;
        if (stat(o->save_rays, &st) != 0 || !S_ISDIR(st.st_mode)) {
            fprintf(stderr, "accelbench: --save-rays %s: not a folder (%d ray sets are saved to a folder)\n",
                    o->save_rays, nsets);
            return 2;
        }
        if (access(o->save_rays, W_OK | X_OK) == 0) return 0;
        fprintf(stderr, "accelbench: --save-rays %s: cannot write in the folder: %s\n", o->save_rays, strerror(errno));
        return 2;
    }
    struct stat st;
    if (stat(o->save_rays, &st) == 0 && S_ISDIR(st.st_mode)) {
        fprintf(stderr, "accelbench: --save-rays %s: a folder, but one ray set is saved to a file: name the file\n",
                o->save_rays);
        return 2;
    }
    char dir[PATH_MAX], err[PATH_MAX + 128];
    if (output_replaceable(o->save_rays, err, sizeof err)) { /* a device or a pipe is never replaced */
        fprintf(stderr, "accelbench: --save-rays %s\n", err);
        return 2;
    }
    snprintf(dir, sizeof dir, "%s", o->save_rays);
    char *slash = strrchr(dir, '/');
    if (!slash) snprintf(dir, sizeof dir, ".");
    else if (slash == dir) slash[1] = 0;
    else *slash = 0;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        fprintf(stderr, "accelbench: --save-rays %s: folder %s does not exist\n", o->save_rays, dir);
        return 2;
    }
    /* The set goes to a temporary file in that folder, renamed onto the name (save_rays_file). */
    if (access(dir, W_OK | X_OK) == 0) return 0;
    fprintf(stderr, "accelbench: --save-rays %s: cannot write in folder %s: %s\n", o->save_rays, dir, strerror(errno));
    return 2;
}

/* Save one ray set (--save-rays). Returns 0, or -1 after printing why. */
static int save_rays(const options *o, const rayset_t *rs, int nsets)
{
    char path[PATH_MAX], err[PATH_MAX + 1100];
    save_rays_path(o, rs, nsets, path, sizeof path);
    if (nsets > 1 && mkdir_p(o->save_rays)) {
        fprintf(stderr, "accelbench: --save-rays %s: cannot create folder: %s\n", o->save_rays, strerror(errno));
        return -1;
    }
    if (save_rays_file(rs, path, err, sizeof err)) {
        fprintf(stderr, "accelbench: %s\n", err);
        return -1;
    }
    if (!o->quiet) fprintf(stderr, "  saved %u rays (hash %016llx) to %s\n", rs->count, (unsigned long long)rs->hash, path);
    return 0;
}

/* Make (or load, or take the preloaded) ray set of one workload and the
 * reference's answers. A loaded set's light indices are checked against
 * the scene it is replayed on. */
static int cell_prepare(const options *o, const scene_t *s, accel *ref, verifier_t *ver, const workload_def *w,
                        rayset_t **preloaded, cell_rays *in)
{
    char err[1024];
    rayset_t *rs;
    if (preloaded && *preloaded) {
        rs = *preloaded;
        *preloaded = NULL;
    } else if (o->rays_file) {
        rs = rayset_load(o->rays_file, err, sizeof err);
        if (!rs) {
            fprintf(stderr, "accelbench: %s\n", err);
            return -1;
        }
    } else {
        rs = w->make(s, ref, &o->wl);
    }
    if (o->rays_file) {
        if (rayset_check_lights(rs, o->rays_file, s->name, s->nlights, err, sizeof err) ||
            rayset_check_origins(rs, o->rays_file, s->name, s->prims.count, err, sizeof err)) {
            fprintf(stderr, "accelbench: %s\n", err);
            rayset_free(rs);
            return -1;
        }
        if (strcmp(rs->scene, s->name) != 0)
            fprintf(stderr, "accelbench: warning: %s was made for scene '%s', replaying on '%s'\n", term_text(o->rays_file),
                    term_text(rs->scene), term_text(s->name));
    }
    cell_rays_init(in, s, ref, ver, rs, o->threads);
    return 0;
}

static bool accel_runs_workload(const struct accel_ops *ops, query_kind q)
{
    return !(ops->flags & ACCEL_SHADOW_ONLY) || q == QUERY_ANY;
}

/* The (accelerator, workload) pairs no cell is made of, said before any
 * work: one line per accelerator that skips some workload, naming them and
 * why (say_skips, once the command's other checks have passed). When the
 * pairs leave no cell at all, only one line saying why, and 2: a command
 * that measures nothing should not look like a success. replay is the --rays
 * file's set (its query decides), or NULL. Returns 0 or 2. */
static int check_pairs(const options *o, const char *cmd, const rayset_t *replay, bool say_skips)
{
    int nw = replay ? 1 : o->nworkloads, made = 0;
    for (int ai = 0; ai < o->naccels; ai++)
        for (int wi = 0; wi < nw; wi++)
            made += accel_runs_workload(o->accels[ai].ops, replay ? replay->query : o->workloads[wi]->query);
    char names[1024];
    for (int ai = 0; ai < o->naccels; ai++) {
        const accel_config *ac = &o->accels[ai];
        size_t n = 0;
        names[0] = '\0';
        for (int wi = 0; wi < nw; wi++) {
            if (accel_runs_workload(ac->ops, replay ? replay->query : o->workloads[wi]->query)) continue;
            const char *wname = replay ? o->rays_file : o->workloads[wi]->name;
            if (n < sizeof names) n += (size_t)snprintf(names + n, sizeof names - n, "%s%s", n ? ", " : "", term_text(wname));
        }
        if (!n) continue;
        if (made == 0) { /* no cell at all: the one line names the first reason (every pair has the same kind) */
            fprintf(stderr, "accelbench %s: no cell to %s: %s answers only shadow (any-hit) rays and %s %s closest-hit "
                            "rays (add --workloads shadow, or an accelerator that answers closest hits)\n", cmd,
                    !strcmp(cmd, "run") ? "measure" : "check", ac->label, names, replay || nw == 1 ? "asks for" : "ask for");
            return 2;
        }
        if (say_skips && !o->quiet)
            fprintf(stderr, "accelbench %s: skipped %s x %s: %s answers only shadow (any-hit) rays, %s closest-hit\n", cmd,
                    ac->label, names, ac->label, replay || nw == 1 ? "that one is" : "those are");
    }
    return 0;
}

/* Load scene number si, build its reference and its verifier; errors go
 * to stderr and give NULL. */
static scene_t *open_scene(const options *o, int si, accel **ref, verifier_t **ver)
{
    char err[512];
    double t0 = clock_ms();
    scene_t *s = scene_load(o->scenes[si], err, sizeof err);
    if (!s) {
        fprintf(stderr, "accelbench: %s\n", term_text(err));
        return NULL;
    }
    if (!o->quiet)
        fprintf(stderr, "scene %s: %u primitives (%u triangles, %u spheres, %u cones, %u polygons), loaded in %.0f ms\n",
                term_text(s->name), s->prims.count, s->prims.ntris, s->prims.nspheres, s->prims.ncones, s->prims.npolygons,
                clock_ms() - t0);
    *ref = build_reference(s, o->threads, err, sizeof err);
    if (!*ref) {
        fprintf(stderr, "accelbench: %s: reference build failed: %s\n", term_text(s->name), err);
        scene_free(s);
        return NULL;
    }
    *ver = verifier_new(s, o->judge_seconds);
    return s;
}

static void close_scene(scene_t *s, accel *ref, verifier_t *ver)
{
    verifier_free(ver);
    ref->ops->destroy(ref);
    scene_free(s);
}

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

/* ------------------------------------------------------------------ run */

/* Append one shell word to buf, single-quoted when the shell would split
 * or expand it (a quote inside becomes '\''), or as $'...' with \xHH
 * escapes when it holds a control character. */
static void shell_word(char *buf, size_t len, const char *word)
{
    size_t n = strlen(buf);
    bool plain = *word != 0;
    for (const char *c = word; *c; c++)
        if (!strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789:,._/=+-@%", *c)) plain = false;
    if (n && n + 1 < len) buf[n++] = ' ', buf[n] = 0;
    if (plain) {
        snprintf(buf + n, len - n, "%s", word);
        return;
    }
    bool control = false;
    for (const unsigned char *c = (const unsigned char *)word; *c; c++) control |= *c < 0x20 || *c == 0x7f;
    if (control) {
        /* bash's $'...': the terminal sees no control character, and the line still pastes. */
        if (n + 2 < len) n += (size_t)snprintf(buf + n, len - n, "$'");
        for (const unsigned char *c = (const unsigned char *)word; *c && n + 6 < len; c++) {
            if (*c < 0x20 || *c == 0x7f) n += (size_t)snprintf(buf + n, len - n, "\\x%02x", *c);
            else if (*c == '\'' || *c == '\\') n += (size_t)snprintf(buf + n, len - n, "\\%c", *c);
            else buf[n++] = (char)*c, buf[n] = 0;
        }
        if (n + 1 < len) buf[n++] = '\'', buf[n] = 0;
        return;
    }
    if (n + 1 < len) buf[n++] = '\'', buf[n] = 0;
    for (const char *c = word; *c && n + 5 < len; c++) {
        if (*c == '\'') n += (size_t)snprintf(buf + n, len - n, "'\\''");
        else buf[n++] = *c, buf[n] = 0;
    }
    if (n + 1 < len) buf[n++] = '\'', buf[n] = 0;
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

/* The key of cell (scene si, workload wi, accelerator ac): the options
 * form, or the ray-set form for a replayed file (cellkey.h). */
static int run_cell_key(const options *o, int si, int wi, const accel_config *ac, const rayset_t *replay, char *buf,
                        size_t len)
{
    cell_key_parts k = {.scene = o->scenes[si], .accel = ac->ops->name, .params = ac->params_str,
                        .workload = replay ? replay->workload : o->workloads[wi]->name, .wl = replay ? NULL : &o->wl,
                        .rays_hash = replay ? replay->hash : 0, .threads = o->threads, .repeat = o->repeat,
                        .warm = o->warm_passes};
    if (cell_key_format(&k, buf, len) == 0) return 0;
    fprintf(stderr, "accelbench: %s %s %s: the cell key is longer than %d bytes\n", term_text(o->scenes[si]), ac->ops->name,
            k.workload, CELL_KEY_MAX - 1);
    return -1;
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

/* run --shard K/N: every cell of the whole matrix in the run loop's order
 * (shard.h), its estimated cost (each scene loaded once for its primitives
 * and lights, then freed), the split of all of them into N shards, and
 * this shard's cells in *mine. The manifest goes to DIR/shard.txt; a folder
 * whose shard.txt is of another shard or matrix is refused. Returns 0, or
 * 1/2 after printing why. */
static int plan_shard(const options *o, const rayset_t *replay, const char *out_dir, const machine_info *mi,
                      unsigned char **mine, char *shard_line, size_t shard_line_len)
{
    int nw = replay ? 1 : o->nworkloads;
    size_t nslots = (size_t)o->nscenes * (size_t)nw * (size_t)o->naccels;
    shard_manifest m = {.k = o->shard_k, .n = o->shard_n};
    snprintf(m.git_rev, sizeof m.git_rev, "%s", mi->git_rev);
    char opts[16384], cmd[4096], err[4400], key[CELL_KEY_MAX];
    shard_options_line(o, opts, sizeof opts);
    cmd[0] = 0;
    for (int i = 1; i < o->argc_full; i++) shell_word(cmd, sizeof cmd, o->argv_full[i]);
    m.options = opts;
    m.command = o->argc_full ? cmd : o->argv_line;
    m.cells = calloc(nslots + 1, sizeof *m.cells);
    double *cost = calloc(nslots + 1, sizeof *cost);
    int *shard_of = calloc(nslots + 1, sizeof *shard_of);
    size_t *slot = calloc(nslots + 1, sizeof *slot);
    double *load = calloc((size_t)o->shard_n, sizeof *load);
    *mine = calloc(nslots + 1, 1);
    int status = 0;
    if (!m.cells || !cost || !shard_of || !slot || !load || !*mine) {
        fprintf(stderr, "accelbench: out of memory planning the shards\n");
        status = 2;
    }
    for (int si = 0; si < o->nscenes && status == 0; si++) {
        scene_t *s = scene_load(o->scenes[si], err, sizeof err);
        if (!s) {
            fprintf(stderr, "accelbench: %s\n", err);
            status = 2;
            break;
        }
        uint64_t prims = s->prims.count;
        uint32_t nlights = s->nlights;
        scene_free(s);
        for (int wi = 0; wi < nw && status == 0; wi++) {
            query_kind q = replay ? replay->query : o->workloads[wi]->query;
            uint64_t rays = replay ? replay->count : resources_workload(o->workloads[wi]->name, &o->wl, nlights).rays;
            for (int ai = 0; ai < o->naccels && status == 0; ai++) {
                const accel_config *ac = &o->accels[ai];
                if (!accel_runs_workload(ac->ops, q)) continue;
                if (run_cell_key(o, si, wi, ac, replay, key, sizeof key)) {
                    status = 2;
                    break;
                }
                int i = m.ncells++;
                cost[i] = shard_cell_cost(ac->ops->name, prims, rays, o->repeat);
                slot[i] = ((size_t)si * (size_t)nw + (size_t)wi) * (size_t)o->naccels + (size_t)ai;
                m.cells[i] = (shard_cell){.index = i, .cost = cost[i], .key = strdup(key)};
                if (!m.cells[i].key) status = 2;
            }
        }
    }
    if (status == 0 && shard_assign(cost, m.ncells, m.n, shard_of, load)) status = 2;
    int ncells_mine = 0;
    double total = 0;
    for (int i = 0; i < m.ncells && status == 0; i++) {
        m.cells[i].shard = shard_of[i] + 1;
        total += cost[i];
        if (shard_of[i] + 1 == m.k) (*mine)[slot[i]] = 1, ncells_mine++;
    }
    if (status == 0) {
        /* A folder of another shard, or of another matrix, is refused before anything is written to it. */
        char path[1200];
        snprintf(path, sizeof path, "%s/%s", out_dir, SHARD_MANIFEST);
        shard_manifest old;
        int rc = shard_manifest_read(out_dir, &old, err, sizeof err);
        if (rc < 0) {
            fprintf(stderr, "accelbench: %s\n", err);
            status = 2;
        } else if (rc == 0) {
            if (!shard_manifest_same_matrix(&old, &m)) {
                fprintf(stderr, "accelbench: %s: this folder holds shard %d/%d of %s matrix; choose another --out\n", path,
                        old.k, old.n, strcmp(old.options, m.options) || old.ncells != m.ncells ? "another" : "this");
                status = 2;
            }
            shard_manifest_free(&old);
        }
        char *text = status == 0 ? shard_manifest_format(&m) : NULL;
        if (status == 0 && !text) status = 2;
        if (text) {
            if (!signals_begin_write()) signals_end_write();
            int w = write_file_checked(path, "w", text, err, sizeof err);
            signals_end_write();
            free(text);
            if (w) {
                fprintf(stderr, "accelbench: %s\n", err);
                status = w == -2 ? 2 : 1;
            }
        }
    }
    if (status == 0) {
        double largest = 0;
        for (int k = 0; k < m.n; k++) largest = fmax(largest, load[k]);
        snprintf(shard_line, shard_line_len,
                 "shard: %d/%d: %d of the matrix's %d cells, estimated cost %.3g of %.3g (the largest shard %.3g; %s)\n",
                 m.k, m.n, ncells_mine, m.ncells, load[m.k - 1], total, largest, SHARD_MANIFEST);
        if (!o->quiet)
            fprintf(stderr, "shard %d/%d: %d of the matrix's %d cells (estimated cost %.3g of %.3g)\n", m.k, m.n,
                    ncells_mine, m.ncells, load[m.k - 1], total);
    }
    for (int i = 0; i < m.ncells; i++) free(m.cells[i].key);
    free(m.cells);
    free(cost);
    free(shard_of);
    free(slot);
    free(load);
    if (status) {
        free(*mine);
        *mine = NULL;
    }
    return status;
}

/* Measure one cell and file its row. Returns 0, 1 (a write failed) or 2. */
static int run_one_cell(const options *o, results_store *store, const cell_rays *in, int si, int wi,
                        const accel_config *ac, const cell_settings *settings, const rayset_t *replay_key, int index,
                        int total)
{
    cell_result cr;
    char key[CELL_KEY_MAX], err[1200];
    if (measure_cell(in, ac, settings, &cr)) return 2;
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

    cell_settings settings = {.threads = o->threads, .repeat = o->repeat, .width = o->wl.width, .height = o->wl.height,
                              .spp = o->wl.spp, .warm_passes = o->warm_passes, .mi = &mi};
    if (replay) settings.width = settings.height = settings.spp = 0; /* a replayed file's image is its own, or none */
    int index = 0, measured = 0;
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
        int skipped = index - measured;
        if (measured == 0 && cells.total > 0)
            fprintf(stderr, "nothing to measure: all %d cells of this run are in %s\n", cells.total, csv_path);
        else
            fprintf(stderr, "wrote %s (%d cells measured%s, %.1f s)\n", csv_path, measured,
                    skipped ? ", the others done before" : "", (clock_ms() - wall0) / 1e3);
    }
    if (status == 1) fprintf(stderr, "accelbench: %s holds every cell finished before the failure\n", csv_path);
    if (o->report && status == 0) {
        if (run_dir_outputs(out_dir, o->quiet)) status = 1;
    } else if (o->plots && status == 0) run_plot_script("plot.py", csv_path, o->quiet);
    return status;
}

/* ------------------------------------------------------------------ verify */

/* One answer, with the exact judge's t for the primitive it names. */
static void print_answer(judge_t *j, const char *who, const rayset_t *rs, const answers_t *a, uint32_t i)
{
    const ray_t *r = &rs->rays[i];
    if (rs->query == QUERY_ANY) {
        printf("    %-12s %s\n", who, a->occluded[i] ? "occluded" : "clear");
        return;
    }
    const hit_t *h = &a->hits[i];
    if (h->prim == HIT_NONE) {
        printf("    %-12s miss\n", who);
        return;
    }
    char dec[64], exact[512];
    bool hit = judge_describe(j, r, h->prim, dec, sizeof dec, exact, sizeof exact);
    printf("    %-12s prim %u t=%.9g u=%.6f v=%.6f; judge on prim %u: %s%s%s\n", who, h->prim, h->t, h->u, h->v, h->prim,
           hit ? dec : "miss", hit ? " = " : "", hit ? exact : "");
}

static void replay_ray(const scene_t *s, verifier_t *ver, const rayset_t *rs, uint32_t i, const answers_t *got,
                       const answers_t *ref, const char *accel_name)
{
    const ray_t *r = &rs->rays[i];
    judge_t *j = verifier_judge(ver);
    printf("  ray %u of %s/%s (hash %016llx): org (%.9g %.9g %.9g) dir (%.9g %.9g %.9g) t [%.9g, %.9g) light %d\n", i,
           term_text(s->name), rs->workload, (unsigned long long)rs->hash, r->org.x, r->org.y, r->org.z, r->dir.x, r->dir.y,
           r->dir.z, r->tnear, r->tfar, r->light == RAY_NO_LIGHT ? -1 : (int)r->light);
    print_answer(j, accel_name, rs, got, i);
    print_answer(j, "embree", rs, ref, i);
    judge_hit e = judge_closest(j, r);
    if (e.prim == HIT_NONE) {
        printf("    %-12s miss (exact, every primitive)\n", "judge");
        return;
    }
    char dec[64], exact[512];
    judge_describe(j, r, e.prim, dec, sizeof dec, exact, sizeof exact);
    printf("    %-12s prim %u t=%s = %s; %.3g from the primitive's boundary, noise scale %.3g%s\n", "judge", e.prim, dec,
           exact, prim_boundary_distance(&s->prims, e.prim, r, e.t), verify_noise_scale(s, r, e.prim),
           verify_hit_at_origin(s, r, e.prim, e.t) ? " (at the origin: ill-posed)" : "");
}

static void print_mismatch(const options *o, const rayset_t *rs, const mismatch_t *m, const accel_config *ac,
                           const char *scene_arg)
{
    const char *name = ac->ops->name;
    printf("    ray %-8u %-8s ", m->ray, mismatch_class_name[m->cls]);
    if (rs->query == QUERY_ANY) printf("%s: %s, embree: %s", name, m->got_occ ? "occluded" : "clear", m->ref_occ ? "occluded" : "clear");
    else {
        if (m->got.prim == HIT_NONE) printf("%s: miss", name);
        else printf("%s: prim %u t=%.7g", name, m->got.prim, m->got.t);
        if (m->ref.prim == HIT_NONE) printf(", embree: miss");
        else printf(", embree: prim %u t=%.7g", m->ref.prim, m->ref.t);
    }
    if (m->judged) {
        if (m->exact.prim == HIT_NONE) printf(", judge: miss");
        else printf(", judge: prim %u t=%.7g", m->exact.prim, m->exact.t);
    }
    char cmd[2048];
    options_replay_command(o, scene_arg, rs->workload, ac, m->ray, cmd, sizeof cmd);
    printf("\n      replay: %s\n", term_text(cmd));
}

/* The verify table's columns; the text ones are as wide as their longest entry. */
static const char *const verify_counts[] = {"rays", "illposed", "agree", "edge", "origin", "tol", "refwrong", "real", "unjudged"};
#define VERIFY_NCOUNTS (int)(sizeof verify_counts / sizeof verify_counts[0])

typedef struct { int scene, workload, accel; } verify_widths;

static verify_widths table_widths(const options *o)
{
    verify_widths w = {5, 8, 5};
    for (int i = 0; i < o->nscenes; i++) w.scene = (int)fmax(w.scene, strlen(term_text(o->scenes[i])));
    for (int i = 0; i < o->nworkloads; i++) w.workload = (int)fmax(w.workload, strlen(o->workloads[i]->name));
    if (o->rays_file) w.workload = (int)fmax(w.workload, 31);
    for (int i = 0; i < o->naccels; i++) w.accel = (int)fmax(w.accel, strlen(o->accels[i].label));
    return w;
}

int matrix_verify(options *o)
{
    int status = 0;
    bool any_real = false;
    uint64_t unjudged = 0;
    /* The ray file is read, and --ray and --save-rays checked against it, before the table starts. */
    char err[1200];
    rayset_t *replay = NULL;
    int nsets = o->nscenes * (o->rays_file ? 1 : o->nworkloads);
    if (o->rays_file) {
        replay = rayset_load(o->rays_file, err, sizeof err);
        if (!replay) {
            fprintf(stderr, "accelbench: %s\n", err);
            return 2;
        }
        if (o->ray_index >= (long)replay->count) {
            fprintf(stderr, "accelbench: --ray %ld: %s has %u rays\n", o->ray_index, o->rays_file, replay->count);
            rayset_free(replay);
            return 2;
        }
    }
    if (check_pairs(o, "verify", replay, false) || save_rays_check(o, nsets)) {
        rayset_free(replay);
        return 2;
    }
    verify_widths w = table_widths(o);
    uint64_t ncells = 0, nrays = 0, by_class[MM_CLASSES] = {0};
    check_pairs(o, "verify", replay, true);
    printf("%-*s %-*s %-*s", w.scene, "scene", w.workload, "workload", w.accel, "accel");
    for (int k = 0; k < VERIFY_NCOUNTS; k++) printf(" %9s", verify_counts[k]);
    printf("\n");
    for (int si = 0; si < o->nscenes && !status; si++) {
        accel *ref;
        verifier_t *ver;
        scene_t *s = open_scene(o, si, &ref, &ver);
        if (!s) {
            rayset_free(replay);
            return 2;
        }
        int nw = o->rays_file ? 1 : o->nworkloads;
        for (int wi = 0; wi < nw && !status; wi++) {
            cell_rays in;
            if (cell_prepare(o, s, ref, ver, o->workloads[wi], &replay, &in)) {
                status = 2;
                break;
            }
            if (o->save_rays && save_rays(o, in.rs, o->nscenes * nw)) status = 2;
            if (o->ray_index >= (long)in.rs->count) {
                fprintf(stderr, "accelbench: --ray %ld: the %s ray set of %s has %u rays\n", o->ray_index, in.rs->workload,
                        s->name, in.rs->count);
                status = 2;
            }
            for (int ai = 0; ai < o->naccels && !status; ai++) {
                const accel_config *ac = &o->accels[ai];
                if (!accel_runs_workload(ac->ops, in.rs->query)) continue;
                warm_cell wc;
                if (cell_warm_up(&in, ac, o->threads, &wc)) {
                    status = 2;
                    break;
                }
                const verify_result *vr = &wc.vr;
                uint64_t counts[VERIFY_NCOUNTS] = {in.rs->count, in.illposed, vr->agree, vr->mismatches[MM_EDGE],
                                                   vr->mismatches[MM_ORIGIN], vr->mismatches[MM_TOL],
                                                   vr->mismatches[MM_REFWRONG], vr->mismatches[MM_REAL],
                                                   vr->mismatches[MM_UNJUDGED]};
                printf("%-*s %-*s %-*s", w.scene, term_text(o->scenes[si]), w.workload, in.rs->workload, w.accel, ac->label);
                for (int k = 0; k < VERIFY_NCOUNTS; k++) printf(" %9llu", (unsigned long long)counts[k]);
                printf("\n");
                if (vr->mismatches[MM_REAL]) any_real = true;
                unjudged += vr->mismatches[MM_UNJUDGED];
                ncells++;
                nrays += in.rs->count;
                for (int k = 0; k < MM_CLASSES; k++) by_class[k] += vr->mismatches[k];
                if (o->ray_index >= 0) replay_ray(s, ver, in.rs, (uint32_t)o->ray_index, wc.got, in.ref_answers, ac->ops->name);
                else
                    for (uint32_t k = 0; k < vr->nlisted; k++) print_mismatch(o, in.rs, &vr->listed[k], ac, o->scenes[si]);
                warm_cell_release(&wc);
            }
            cell_rays_release(&in);
        }
        close_scene(s, ref, ver);
    }
    rayset_free(replay); /* NULL once a cell took it */
    /* The whole in one line: only real mismatches fail verify; the other classes are the reference's or the
     * judge's (docs/method.md: verification). */
    if (!status) {
        printf("total: %llu cells, %llu rays: %llu real mismatches; the classes that do not fail verify: edge %llu, "
               "origin %llu, tol %llu, refwrong %llu, unjudged %llu; exit %d: %s\n", (unsigned long long)ncells, (unsigned long long)nrays,
               (unsigned long long)by_class[MM_REAL], (unsigned long long)by_class[MM_EDGE],
               (unsigned long long)by_class[MM_ORIGIN], (unsigned long long)by_class[MM_TOL],
               (unsigned long long)by_class[MM_REFWRONG], (unsigned long long)by_class[MM_UNJUDGED], any_real ? 1 : 0,
               any_real ? "real mismatches found (listed above, each with the command that replays it)"
                        : "no real mismatch");
    }
    fflush(stdout);
    if (unjudged)
        fprintf(stderr, "accelbench: %llu disputed rays were left unjudged: the judge's budget (--judge-seconds %g) ran out\n",
                (unsigned long long)unjudged, o->judge_seconds);
    if (status) return status;
    return any_real ? 1 : 0;
}
