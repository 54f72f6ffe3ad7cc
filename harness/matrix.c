/* matrix.c: the run and verify loops (see matrix.h). */
#include "matrix.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "csv.h"
#include "machine.h"
#include "measure.h"
#include "output.h"
#include "trace.h"
#include "verify.h"

static int save_rays(const options *o, const rayset_t *rs, int nsets)
{
    char path[1024], err[512];
    if (nsets == 1) {
        snprintf(path, sizeof path, "%s", o->save_rays);
    } else {
        if (mkdir_p(o->save_rays)) {
            fprintf(stderr, "accelbench: --save-rays %s: cannot create folder: %s\n", o->save_rays, strerror(errno));
            return -1;
        }
        char safe[256];
        snprintf(safe, sizeof safe, "%s", rs->scene);
        for (char *p = safe; *p; p++)
            if (*p == '/' || *p == ':') *p = '_';
        snprintf(path, sizeof path, "%s/%s__%s.rays", o->save_rays, safe, rs->workload);
    }
    if (rayset_save(rs, path, err, sizeof err)) {
        fprintf(stderr, "accelbench: %s\n", err);
        return -1;
    }
    if (!o->quiet) fprintf(stderr, "  saved %u rays (hash %016llx) to %s\n", rs->count, (unsigned long long)rs->hash, path);
    return 0;
}

/* Make (or load) the ray set of one workload and the reference's answers. */
static int cell_prepare(const options *o, const scene_t *s, accel *ref, verifier_t *ver, const workload_def *w,
                        cell_rays *in)
{
    char err[512];
    rayset_t *rs;
    if (o->rays_file) {
        rs = rayset_load(o->rays_file, err, sizeof err);
        if (!rs) {
            fprintf(stderr, "accelbench: %s\n", err);
            return -1;
        }
        if (strcmp(rs->scene, s->name) != 0)
            fprintf(stderr, "accelbench: warning: %s was made for scene '%s', replaying on '%s'\n", o->rays_file,
                    rs->scene, s->name);
    } else {
        rs = w->make(s, ref, &o->wl);
    }
    cell_rays_init(in, s, ref, ver, rs, o->threads);
    return 0;
}

static bool accel_runs_workload(const struct accel_ops *ops, query_kind q)
{
    return !(ops->flags & ACCEL_SHADOW_ONLY) || q == QUERY_ANY;
}

/* Load scene number si, build its reference and its verifier; errors go
 * to stderr and give NULL. */
static scene_t *open_scene(const options *o, int si, accel **ref, verifier_t **ver)
{
    char err[512];
    double t0 = clock_ms();
    scene_t *s = scene_load(o->scenes[si], err, sizeof err);
    if (!s) {
        fprintf(stderr, "accelbench: %s\n", err);
        return NULL;
    }
    if (!o->quiet)
        fprintf(stderr, "scene %s: %u primitives (%u triangles, %u spheres, %u cones, %u polygons), loaded in %.0f ms\n",
                s->name, s->prims.count, s->prims.ntris, s->prims.nspheres, s->prims.ncones, s->prims.npolygons,
                clock_ms() - t0);
    *ref = build_reference(s, o->threads, err, sizeof err);
    if (!*ref) {
        fprintf(stderr, "accelbench: %s: reference build failed: %s\n", s->name, err);
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

/* The progress line of a measured cell, and its statistics on a line of
 * their own. */
static void print_progress(int done, int total, const cell_result *cr)
{
    const csv_row *r = &cr->row;
    fprintf(stderr, "[%d/%d] %s %s %s: %u rays, build %.1f ms, trace %.2f ms (%.3f Mrays/s, %.2fx embree, pairs "
                    "%.2f-%.2f, %s), agree %llu, real mismatches %llu\n",
            done, total, r->scene, r->accel, r->workload, r->rays, r->build_ms, r->trace_ms, r->mrays_per_s,
            r->ratio_vs_embree, r->ratio_min, r->ratio_max, r->timed_path, (unsigned long long)r->agree,
            (unsigned long long)r->mismatch_real);
    if (r->nstats) {
        char buf[1024];
        stats_format(r, buf, sizeof buf);
        fprintf(stderr, "        stats: %s\n", buf);
    }
}

int matrix_run(options *o)
{
    machine_info mi;
    machine_describe(&mi);
    char out_dir[1024], csv_path[1100], err[512];
    if (output_folder(o->out, "", out_dir, sizeof out_dir)) return 2;
    snprintf(csv_path, sizeof csv_path, "%s/matrix.csv", out_dir);
    FILE *csv = csv_open(csv_path, err, sizeof err);
    if (!csv) {
        fprintf(stderr, "accelbench: %s\n", err);
        return 2;
    }
    char info_path[1100];
    snprintf(info_path, sizeof info_path, "%s/run.txt", out_dir);
    FILE *info = fopen(info_path, "a");
    if (info) {
        fprintf(info, "command: %s\nmachine: %s\ncpu: %s\ngit_rev: %s\ndate: %s\nthreads: %d\nrepeat: %d (timed samples, each paired with one of Embree's at the same thread count, after 1 warm-up; medians reported)\n\n",
                o->argv_line, mi.host, mi.cpu, mi.git_rev, mi.date, o->threads, o->repeat);
        fclose(info);
    }
    int total = o->nscenes * o->nworkloads * o->naccels, done = 0, status = 0;
    cell_settings settings = {.threads = o->threads, .repeat = o->repeat, .width = o->wl.width, .height = o->wl.height,
                              .spp = o->wl.spp, .mi = &mi};
    double wall0 = clock_ms();
    for (int si = 0; si < o->nscenes; si++) {
        accel *ref;
        verifier_t *ver;
        scene_t *s = open_scene(o, si, &ref, &ver);
        if (!s) {
            status = 2;
            break;
        }
        int nw = o->rays_file ? 1 : o->nworkloads;
        for (int wi = 0; wi < nw && status == 0; wi++) {
            cell_rays in;
            if (cell_prepare(o, s, ref, ver, o->workloads[wi], &in)) {
                status = 2;
                break;
            }
            if (o->save_rays && save_rays(o, in.rs, o->nscenes * nw)) status = 2;
            for (int ai = 0; ai < o->naccels && status == 0; ai++) {
                const accel_config *ac = &o->accels[ai];
                done++;
                if (!accel_runs_workload(ac->ops, in.rs->query)) continue;
                cell_result cr;
                if (measure_cell(&in, ac, &settings, &cr)) {
                    status = 2;
                    break;
                }
                csv_write_row(csv, &cr.row);
                if (!o->quiet) print_progress(done, total, &cr);
            }
            cell_rays_release(&in);
        }
        close_scene(s, ref, ver);
        if (status) break;
    }
    fclose(csv);
    if (!o->quiet) fprintf(stderr, "wrote %s (%d cells, %.1f s)\n", csv_path, done, (clock_ms() - wall0) / 1e3);
    if (o->plots && status == 0) run_plot_script("plot.py", csv_path, o->quiet);
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
           s->name, rs->workload, (unsigned long long)rs->hash, r->org.x, r->org.y, r->org.z, r->dir.x, r->dir.y,
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
    printf("\n      replay: %s\n", cmd);
}

/* The verify table's columns; the text ones are as wide as their longest entry. */
static const char *const verify_counts[] = {"rays", "illposed", "agree", "edge", "origin", "tol", "refwrong", "real", "unjudged"};
#define VERIFY_NCOUNTS (int)(sizeof verify_counts / sizeof verify_counts[0])

typedef struct { int scene, workload, accel; } verify_widths;

static verify_widths table_widths(const options *o)
{
    verify_widths w = {5, 8, 5};
    for (int i = 0; i < o->nscenes; i++) w.scene = (int)fmax(w.scene, strlen(o->scenes[i]));
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
    verify_widths w = table_widths(o);
    printf("%-*s %-*s %-*s", w.scene, "scene", w.workload, "workload", w.accel, "accel");
    for (int k = 0; k < VERIFY_NCOUNTS; k++) printf(" %9s", verify_counts[k]);
    printf("\n");
    for (int si = 0; si < o->nscenes && !status; si++) {
        accel *ref;
        verifier_t *ver;
        scene_t *s = open_scene(o, si, &ref, &ver);
        if (!s) return 2;
        int nw = o->rays_file ? 1 : o->nworkloads;
        for (int wi = 0; wi < nw && !status; wi++) {
            cell_rays in;
            if (cell_prepare(o, s, ref, ver, o->workloads[wi], &in)) {
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
                if (cell_warm_up(&in, ac, cell_threads(ac->ops, o->threads), &wc)) {
                    status = 2;
                    break;
                }
                const verify_result *vr = &wc.vr;
                uint64_t counts[VERIFY_NCOUNTS] = {in.rs->count, in.illposed, vr->agree, vr->mismatches[MM_EDGE],
                                                   vr->mismatches[MM_ORIGIN], vr->mismatches[MM_TOL],
                                                   vr->mismatches[MM_REFWRONG], vr->mismatches[MM_REAL],
                                                   vr->mismatches[MM_UNJUDGED]};
                printf("%-*s %-*s %-*s", w.scene, o->scenes[si], w.workload, in.rs->workload, w.accel, ac->label);
                for (int k = 0; k < VERIFY_NCOUNTS; k++) printf(" %9llu", (unsigned long long)counts[k]);
                printf("\n");
                if (vr->mismatches[MM_REAL]) any_real = true;
                unjudged += vr->mismatches[MM_UNJUDGED];
                if (o->ray_index >= 0) replay_ray(s, ver, in.rs, (uint32_t)o->ray_index, wc.got, in.ref_answers, ac->ops->name);
                else
                    for (uint32_t k = 0; k < vr->nlisted; k++) print_mismatch(o, in.rs, &vr->listed[k], ac, o->scenes[si]);
                warm_cell_release(&wc);
            }
            cell_rays_release(&in);
        }
        close_scene(s, ref, ver);
    }
    fflush(stdout);
    if (unjudged)
        fprintf(stderr, "accelbench: %llu disputed rays were left unjudged: the judge's budget (--judge-seconds %g) ran out\n",
                (unsigned long long)unjudged, o->judge_seconds);
    if (status) return status;
    return any_real ? 1 : 0;
}
