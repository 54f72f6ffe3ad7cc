/* cells.c: what run and verify share on the way to a cell (see cells.h).
 * Data flows one way: scene -> ray set -> the reference's answers -> each
 * accelerator's cell. */
#include "cells.h"

#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "cellkey.h"
#include "output.h"
#include "../workloads/resources.h"
#include "signals.h"

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
int save_rays_check(const options *o, int nsets)
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
int save_rays(const options *o, const rayset_t *rs, int nsets)
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
int cell_prepare(const options *o, const scene_t *s, accel *ref, verifier_t *ver, const workload_def *w,
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

bool accel_runs_workload(const struct accel_ops *ops, query_kind q)
{
    return !(ops->flags & ACCEL_SHADOW_ONLY) || q == QUERY_ANY;
}

/* The (accelerator, workload) pairs no cell is made of, said before any
 * work: one line per accelerator that skips some workload, naming them and
 * why (say_skips, once the command's other checks have passed). When the
 * pairs leave no cell at all, only one line saying why, and 2: a command
 * that measures nothing should not look like a success. replay is the --rays
 * file's set (its query decides), or NULL. Returns 0 or 2. */
int check_pairs(const options *o, const char *cmd, const rayset_t *replay, bool say_skips)
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
scene_t *open_scene(const options *o, int si, accel **ref, verifier_t **ver)
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

void close_scene(scene_t *s, accel *ref, verifier_t *ver)
{
    verifier_free(ver);
    ref->ops->destroy(ref);
    scene_free(s);
}

/* The key of cell (scene si, workload wi, accelerator ac): the options
 * form, or the ray-set form for a replayed file (cellkey.h). */
int run_cell_key(const options *o, int si, int wi, const accel_config *ac, const rayset_t *replay, char *buf,
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
