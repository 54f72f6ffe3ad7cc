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
#include "trace.h"
#include "verify.h"


/* The scene-and-workload part of a cell: the ray set and the reference's answers. */
typedef struct {
    rayset_t *rs;
    answers_t *ref;
    accel *ref_accel;
    double ref_warm_ms; /* the reference trace that made ref: the warm-up of its timing */
    uint32_t illposed;  /* rays whose reference hit lies within the origin bound (verify.h) */
} cell_input;

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

/* Make (or load) the ray set and the reference answers for one workload. */
static int cell_prepare(const options *o, const scene_t *s, accel *ref, const workload_def *w, cell_input *in)
{
    char err[512];
    in->ref_accel = ref;
    if (o->rays_file) {
        in->rs = rayset_load(o->rays_file, err, sizeof err);
        if (!in->rs) {
            fprintf(stderr, "accelbench: %s\n", err);
            return -1;
        }
        if (strcmp(in->rs->scene, s->name) != 0)
            fprintf(stderr, "accelbench: warning: %s was made for scene '%s', replaying on '%s'\n", o->rays_file,
                    in->rs->scene, s->name);
    } else {
        in->rs = w->make(s, ref, &o->wl);
    }
    in->ref = answers_new(in->rs, false);
    in->ref_warm_ms = trace_rayset(ref, in->rs, o->threads, in->ref);
    in->illposed = verify_count_illposed(s, in->rs, ref, o->threads);
    return 0;
}

static void cell_release(cell_input *in)
{
    answers_free(in->ref);
    rayset_free(in->rs);
    memset(in, 0, sizeof *in);
}

static bool accel_runs_workload(const struct accel_ops *ops, query_kind q)
{
    return !(ops->flags & ACCEL_SHADOW_ONLY) || q == QUERY_ANY;
}

/* Accelerators that reorder themselves while tracing run on one thread. */
static int threads_for(const accel_config *ac, const options *o)
{
    return (ac->ops->flags & ACCEL_MUTATES) ? 1 : o->threads;
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
        fprintf(info, "command: %s\nmachine: %s\ncpu: %s\ngit_rev: %s\ndate: %s\nthreads: %d\nrepeat: %d (after 1 warm-up; median reported)\n\n",
                o->argv_line, mi.host, mi.cpu, mi.git_rev, mi.date, o->threads, o->repeat);
        fclose(info);
    }
    int total = o->nscenes * o->nworkloads * o->naccels, done = 0, status = 0;
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
            cell_input in;
            if (cell_prepare(o, s, ref, o->workloads[wi], &in)) {
                status = 2;
                break;
            }
            if (o->save_rays && save_rays(o, in.rs, o->nscenes * nw)) status = 2;
            /* Embree's time on the same rays, same run: the denominator of ratio_vs_embree. */
            answers_t *scratch = answers_new(in.rs, false);
            timing ref_time = time_traces(ref, in.rs, o->threads, o->repeat, in.ref_warm_ms, scratch);
            for (int ai = 0; ai < o->naccels && status == 0; ai++) {
                const accel_config *ac = &o->accels[ai];
                done++;
                if (!accel_runs_workload(ac->ops, in.rs->query)) continue;
                double build_ms;
                accel *a = build_accel(ac, s, &build_ms);
                if (!a) {
                    status = 2;
                    break;
                }
                int threads = threads_for(ac, o);
                answers_t *got = answers_new(in.rs, false);
                double warm_ms = trace_rayset(a, in.rs, threads, got); /* warm-up: answers and counters */
                verify_result vr;
                verifier_check(ver, in.rs, got, in.ref, &vr);
                timing tt = time_traces(a, in.rs, threads, o->repeat, warm_ms, scratch);
                csv_row row = {
                    .scene = s->name, .prims = s->prims.count, .accel = ac->ops->name, .params = ac->params_str,
                    .workload = in.rs->workload, .rays = in.rs->count, .threads = threads, .seed = in.rs->seed,
                    .rayset_hash = in.rs->hash, .build_ms = build_ms, .trace_ms = tt.median, .trace_ms_min = tt.min,
                    .trace_ms_max = tt.max, .mrays_per_s = tt.median > 0 ? in.rs->count / (tt.median * 1e3) : 0,
                    .ratio_vs_embree = ref_time.median > 0 ? tt.median / ref_time.median : 0,
                    .mem_bytes = a->ops->memory(a), .has_counters = !(ac->ops->flags & ACCEL_OPAQUE),
                    .counters = got->total, .agree = vr.agree, .mismatch_real = vr.mismatches[MM_REAL],
                    .mismatch_edge = vr.mismatches[MM_EDGE], .mismatch_tol = vr.mismatches[MM_TOL],
                    .mismatch_refwrong = vr.mismatches[MM_REFWRONG], .mismatch_origin = vr.mismatches[MM_ORIGIN],
                    .mismatch_unjudged = vr.mismatches[MM_UNJUDGED], .illposed_rays = in.illposed,
                    .judge_ms = vr.judge_ms, .serial = threads != o->threads,
                    .width = o->wl.width, .height = o->wl.height, .spp = o->wl.spp, .repeat = o->repeat, .passes = tt.passes,
                    .git_rev = mi.git_rev, .machine = mi.host, .cpu = mi.cpu, .date = mi.date,
                };
                csv_write_row(csv, &row);
                if (!o->quiet)
                    fprintf(stderr, "[%d/%d] %s %s %s: %u rays, build %.1f ms, trace %.2f ms (%.3f Mrays/s, %.2fx embree), agree %llu, real mismatches %llu\n",
                            done, total, s->name, ac->ops->name, in.rs->workload, in.rs->count, build_ms, tt.median,
                            row.mrays_per_s, row.ratio_vs_embree, (unsigned long long)vr.agree,
                            (unsigned long long)vr.mismatches[MM_REAL]);
                answers_free(got);
                a->ops->destroy(a);
            }
            answers_free(scratch);
            cell_release(&in);
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
            cell_input in;
            if (cell_prepare(o, s, ref, o->workloads[wi], &in)) {
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
                double build_ms;
                accel *a = build_accel(ac, s, &build_ms);
                if (!a) {
                    status = 2;
                    break;
                }
                answers_t *got = answers_new(in.rs, false);
                trace_rayset(a, in.rs, threads_for(ac, o), got);
                verify_result vr;
                verifier_check(ver, in.rs, got, in.ref, &vr);
                uint64_t counts[VERIFY_NCOUNTS] = {in.rs->count, in.illposed, vr.agree, vr.mismatches[MM_EDGE],
                                                   vr.mismatches[MM_ORIGIN], vr.mismatches[MM_TOL],
                                                   vr.mismatches[MM_REFWRONG], vr.mismatches[MM_REAL],
                                                   vr.mismatches[MM_UNJUDGED]};
                printf("%-*s %-*s %-*s", w.scene, o->scenes[si], w.workload, in.rs->workload, w.accel, ac->label);
                for (int k = 0; k < VERIFY_NCOUNTS; k++) printf(" %9llu", (unsigned long long)counts[k]);
                printf("\n");
                if (vr.mismatches[MM_REAL]) any_real = true;
                unjudged += vr.mismatches[MM_UNJUDGED];
                if (o->ray_index >= 0) replay_ray(s, ver, in.rs, (uint32_t)o->ray_index, got, in.ref, ac->ops->name);
                else
                    for (uint32_t k = 0; k < vr.nlisted; k++) print_mismatch(o, in.rs, &vr.listed[k], ac, o->scenes[si]);
                answers_free(got);
                a->ops->destroy(a);
            }
            cell_release(&in);
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
