/* verify.c: agreement and mismatch classes (see verify.h). */
#include "verify.h"
#include "../../prims/checked_alloc.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const char *const mismatch_class_name[MM_CLASSES] = {"edge", "origin", "tol", "refwrong", "real", "unjudged"};

#define FLOAT_U 0x1p-24

struct verifier {
    const scene_t *s;
    judge_t *judge;
    double judge_seconds;
    uint32_t *cand;          /* judge_candidates' answer, grown as needed */
    int cand_cap;
};

verifier_t *verifier_new(const scene_t *s, double judge_seconds)
{
    verifier_t *v = checked_calloc(1, sizeof *v, "the verifier");
    v->s = s;
    v->judge = judge_new(s);
    v->judge_seconds = judge_seconds;
    return v;
}

void verifier_free(verifier_t *v)
{
    if (!v) return;
    judge_free(v->judge);
    free(v->cand);
    free(v);
}

judge_t *verifier_judge(verifier_t *v) { return v->judge; }

static bool t_close(double t, double tref) { return fabs(t - tref) <= 1e-4 * fmax(1.0, fabs(tref)); }

static double maxabs(vec3 a) { return fmax(fabsf(a.x), fmax(fabsf(a.y), fabsf(a.z))); }

double verify_noise_scale(const scene_t *s, const ray_t *r, uint32_t prim)
{
    box3 b = prim_bounds(&s->prims, prim);
    return FLOAT_U * (maxabs(r->org) + fmax(maxabs(b.lo), maxabs(b.hi)));
}

/* |cos| between the ray and the primitive's normal at the hit. */
static double incidence(const scene_t *s, const ray_t *r, uint32_t prim, double t)
{
    hit_t h = {(float)t, 0.0f, 0.0f, prim};
    vec3 n = prim_normal(&s->prims, &h, r);
    double len = v3_len(r->dir);
    return len > 0.0 ? fabs(v3_dot(n, r->dir)) / len : 0.0;
}

static bool grazes(const scene_t *s, const ray_t *r, uint32_t prim, double t)
{
    if (prim == HIT_NONE) return false;
    if (prim_boundary_distance(&s->prims, prim, r, t) <= EDGE_ULPS * verify_noise_scale(s, r, prim)) return true;
    return incidence(s, r, prim, t) < GRAZE_COS;
}

bool verify_hit_at_origin(const scene_t *s, const ray_t *r, uint32_t prim, double t)
{
    if (prim == HIT_NONE) return false;
    /* A triangle: the origin's distance from its plane, the exact value of
     * t |d . n| (a float test's t this close to the origin may be off by
     * many times it, as on a thin wall seen edge-on); other primitives: t's. */
    double along_normal = prim_plane_distance(&s->prims, prim, r->org);
    if (isnan(along_normal)) along_normal = fabs(t) * v3_len(r->dir) * incidence(s, r, prim, t);
    return along_normal <= ORIGIN_ULPS * verify_noise_scale(s, r, prim);
}

/* Same primitive, t within a few float steps of the hit's coordinates. */
static bool within_tol(const scene_t *s, const ray_t *r, uint32_t prim, double t, double tref)
{
    double dlen = v3_len(r->dir);
    if (!(dlen > 0.0)) return false;
    double coords = maxabs(r->org) + fabs(tref) * maxabs(r->dir);
    double bound = TOL_ULPS * FLOAT_U * coords / (dlen * fmax(incidence(s, r, prim, tref), GRAZE_COS));
    return fabs(t - tref) <= bound;
}

/* Noise that a hit carries on its own: a graze or an ill-posed origin. */
static int noise_of(const scene_t *s, const ray_t *r, uint32_t prim, double t)
{
    if (grazes(s, r, prim, t)) return MM_EDGE;
    if (verify_hit_at_origin(s, r, prim, t)) return MM_ORIGIN;
    return -1;
}

/* A budget the judge spends per cell; once spent, rays stay unjudged. */
typedef struct {
    verifier_t *v;
    double t0, limit_ms;
    uint64_t judged;
} judging;

static bool judge_allowed(const judging *j)
{
    return j->limit_ms <= 0.0 || clock_ms() - j->t0 < j->limit_ms;
}

static mismatch_class classify_closest(judging *jg, const ray_t *r, mismatch_t *m)
{
    const scene_t *s = jg->v->s;
    int noise = noise_of(s, r, m->got.prim, m->got.t);
    if (noise < 0) noise = noise_of(s, r, m->ref.prim, m->ref.t);
    if (noise >= 0) return (mismatch_class)noise;
    bool gh = m->got.prim != HIT_NONE, rh = m->ref.prim != HIT_NONE;
    if (gh && m->got.prim == m->ref.prim && within_tol(s, r, m->got.prim, m->got.t, m->ref.t)) return MM_TOL;
    if (!judge_allowed(jg)) return MM_UNJUDGED;
    jg->judged++;
    m->judged = true;
    if (gh && rh) {
        uint32_t ids[2] = {m->got.prim, m->ref.prim};
        m->exact = judge_closest_among(jg->v->judge, r, ids, 2);
    } else {
        m->exact = judge_closest(jg->v->judge, r);
    }
    if (m->exact.prim != HIT_NONE && (noise = noise_of(s, r, m->exact.prim, m->exact.t)) >= 0) return (mismatch_class)noise;
    bool got_right = !gh ? m->exact.prim == HIT_NONE
                         : m->exact.prim != HIT_NONE && (t_close(m->got.t, m->exact.t) ||
                                                         (m->got.prim == m->exact.prim &&
                                                          within_tol(s, r, m->got.prim, m->got.t, m->exact.t)));
    return got_right ? MM_REFWRONG : MM_REAL;
}

/* The primitive a float test finds first on an any-hit ray, among the
 * judge's candidates: an accelerator that says "occluded" where the judge
 * sees nothing must be given the chance of an edge graze on it. */
static judge_hit float_first_hit(judging *jg, const ray_t *r)
{
    verifier_t *v = jg->v;
    int n = judge_candidates(v->judge, r, v->cand, v->cand_cap);
    if (n > v->cand_cap) {
        v->cand_cap = n;
        v->cand = checked_realloc(v->cand, (size_t)n * sizeof *v->cand, "the judge's candidate primitives");
        n = judge_candidates(v->judge, r, v->cand, v->cand_cap);
    }
    hit_t h = hit_none(r);
    counters_t c = {0};
    for (int i = 0; i < n; i++) prim_intersect(&v->s->prims, v->cand[i], r, &h, &c);
    judge_hit out = {h.prim, h.t};
    return out;
}

static mismatch_class classify_any(judging *jg, const ray_t *r, mismatch_t *m)
{
    const scene_t *s = jg->v->s;
    if (!judge_allowed(jg)) return MM_UNJUDGED;
    jg->judged++;
    m->judged = true;
    m->exact = judge_closest(jg->v->judge, r);
    int noise;
    if (m->exact.prim != HIT_NONE) {
        if ((noise = noise_of(s, r, m->exact.prim, m->exact.t)) >= 0) return (mismatch_class)noise;
        /* A hit at the very end of the range is a tolerance question. */
        double near_end = fabs(m->exact.t - r->tnear) < fabs(m->exact.t - r->tfar) ? r->tnear : r->tfar;
        if (within_tol(s, r, m->exact.prim, m->exact.t, near_end)) return MM_TOL;
    } else if (m->got_occ || m->ref_occ) {
        judge_hit f = float_first_hit(jg, r);
        if (f.prim != HIT_NONE && (noise = noise_of(s, r, f.prim, f.t)) >= 0) return (mismatch_class)noise;
    }
    bool exact_occ = m->exact.prim != HIT_NONE;
    return exact_occ == (bool)m->got_occ ? MM_REFWRONG : MM_REAL;
}

static void list_mismatch(verify_result *out, const mismatch_t *m)
{
    if (out->nlisted < VERIFY_LIST_MAX) {
        out->listed[out->nlisted++] = *m;
        return;
    }
    /* Full: a real mismatch displaces the last listed non-real one. */
    if (m->cls != MM_REAL) return;
    for (int i = VERIFY_LIST_MAX - 1; i >= 0; i--)
        if (out->listed[i].cls != MM_REAL) {
            memmove(&out->listed[i], &out->listed[i + 1], (size_t)(VERIFY_LIST_MAX - 1 - i) * sizeof *m);
            out->listed[VERIFY_LIST_MAX - 1] = *m;
            return;
        }
}

void verifier_check(verifier_t *v, const rayset_t *rs, const answers_t *got, const answers_t *ref, verify_result *out)
{
    memset(out, 0, sizeof *out);
    judging jg = {v, clock_ms(), v->judge_seconds * 1e3, 0};
    for (uint32_t i = 0; i < rs->count; i++) {
        mismatch_t m;
        memset(&m, 0, sizeof m);
        m.ray = i;
        m.exact.prim = HIT_NONE;
        const ray_t *r = &rs->rays[i];
        if (rs->query == QUERY_CLOSEST) {
            m.got = got->hits[i];
            m.ref = ref->hits[i];
            bool gh = m.got.prim != HIT_NONE, rh = m.ref.prim != HIT_NONE;
            if ((!gh && !rh) || (gh && rh && t_close(m.got.t, m.ref.t))) {
                out->agree++;
                continue;
            }
            m.cls = classify_closest(&jg, r, &m);
        } else {
            m.got_occ = got->occluded[i];
            m.ref_occ = ref->occluded[i];
            if (m.got_occ == m.ref_occ) {
                out->agree++;
                continue;
            }
            m.cls = classify_any(&jg, r, &m);
        }
        out->mismatches[m.cls]++;
        list_mismatch(out, &m);
    }
    out->judge_ms = clock_ms() - jg.t0;
    out->judged = jg.judged;
}

void verify_answers(const scene_t *s, const rayset_t *rs, const answers_t *got, const answers_t *ref, verify_result *out)
{
    verifier_t *v = verifier_new(s, VERIFY_JUDGE_SECONDS);
    verifier_check(v, rs, got, ref, out);
    verifier_free(v);
}

uint32_t verify_count_illposed(const scene_t *s, const rayset_t *rs, accel *ref, int threads)
{
    rayset_t closest = *rs;
    closest.query = QUERY_CLOSEST; /* the same rays, asked for their nearest hit */
    answers_t *a = answers_new(&closest, false);
    trace_rayset(ref, &closest, threads, a);
    uint32_t n = 0;
    for (uint32_t i = 0; i < rs->count; i++) n += verify_hit_at_origin(s, &rs->rays[i], a->hits[i].prim, a->hits[i].t);
    answers_free(a);
    return n;
}
