/* verify_cmd.c: `accelbench verify` (see verify_cmd.h): every cell's
 * answers against the reference's, as a table, and with --ray I one ray of
 * each cell replayed with the exact judge's verdict. */
#include "verify_cmd.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "options.h"
#include "../run/cells.h"
#include "../run/output.h"
#include "../measure/measure.h"
#include "../measure/verify.h"

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
    print_answer(j, ACCEL_REFERENCE, rs, ref, i);
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

int verify_main(options *o)
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
