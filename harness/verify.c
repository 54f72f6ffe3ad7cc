/* verify.c: agreement and mismatch classes (see verify.h). */
#include "verify.h"

#include <math.h>
#include <string.h>

const char *const mismatch_class_name[MM_CLASSES] = {"edge", "tol", "refwrong", "real"};

static bool t_close(double t, double tref) { return fabs(t - tref) <= 1e-4 * fmax(1.0, fabs(tref)); }

double verify_exact_closest(const scene_t *s, const ray_t *r, uint32_t *prim)
{
    double best = -1.0;
    *prim = HIT_NONE;
    for (uint32_t id = 0; id < s->prims.count; id++) {
        double t;
        if (prim_intersect_double(&s->prims, id, r, &t) && (best < 0.0 || t < best)) {
            best = t;
            *prim = id;
        }
    }
    return best;
}

/* Cosine below which a ray counts as skimming a surface: float t and the
 * inside test are ill-conditioned there (error grows like 1/cos). */
#define GRAZE_COS 1e-3

static bool grazes(const scene_t *s, const ray_t *r, uint32_t prim, double t, double graze)
{
    if (prim == HIT_NONE) return false;
    if (prim_boundary_distance(&s->prims, prim, r, t) <= graze) return true;
    hit_t h = {(float)t, 0.0f, 0.0f, prim};
    vec3 n = prim_normal(&s->prims, &h, r);
    float len = v3_len(r->dir);
    return len > 0.0f && fabsf(v3_dot(n, r->dir)) < (float)GRAZE_COS * len;
}

static mismatch_class classify_closest(const scene_t *s, const ray_t *r, mismatch_t *m, double graze, bool arbiter)
{
    if (grazes(s, r, m->got.prim, m->got.t, graze) || grazes(s, r, m->ref.prim, m->ref.t, graze)) return MM_EDGE;
    if (m->got.prim != HIT_NONE && m->got.prim == m->ref.prim) return MM_TOL;
    if (!arbiter) return MM_REAL;
    m->exact_t = verify_exact_closest(s, r, &m->exact_prim);
    if (m->exact_t >= 0.0 && grazes(s, r, m->exact_prim, m->exact_t, graze)) return MM_EDGE;
    bool got_right = m->got.prim == HIT_NONE ? m->exact_t < 0.0 : (m->exact_t >= 0.0 && t_close(m->got.t, m->exact_t));
    return got_right ? MM_REFWRONG : MM_REAL;
}

static mismatch_class classify_any(const scene_t *s, const ray_t *r, mismatch_t *m, double graze, bool arbiter)
{
    if (!arbiter) return MM_REAL;
    m->exact_t = verify_exact_closest(s, r, &m->exact_prim);
    if (m->exact_t >= 0.0 && grazes(s, r, m->exact_prim, m->exact_t, graze)) return MM_EDGE;
    /* A hit at the very ends of the range is a tolerance question. */
    if (m->exact_t >= 0.0 && (t_close(m->exact_t, r->tnear) || t_close(m->exact_t, r->tfar))) return MM_TOL;
    bool exact_occ = m->exact_t >= 0.0;
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

void verify_answers(const scene_t *s, const rayset_t *rs, const answers_t *got, const answers_t *ref, verify_result *out)
{
    memset(out, 0, sizeof *out);
    double graze = 1e-5 * box_diagonal(s->bounds);
    uint32_t disputes = 0;
    for (uint32_t i = 0; i < rs->count; i++) {
        mismatch_t m;
        memset(&m, 0, sizeof m);
        m.ray = i;
        m.exact_t = NAN;
        m.exact_prim = HIT_NONE;
        const ray_t *r = &rs->rays[i];
        if (rs->query == QUERY_CLOSEST) {
            m.got = got->hits[i];
            m.ref = ref->hits[i];
            bool gh = m.got.prim != HIT_NONE, rh = m.ref.prim != HIT_NONE;
            if ((!gh && !rh) || (gh && rh && t_close(m.got.t, m.ref.t))) {
                out->agree++;
                continue;
            }
            m.cls = classify_closest(s, r, &m, graze, disputes++ < VERIFY_ARBITER_MAX);
        } else {
            m.got_occ = got->occluded[i];
            m.ref_occ = ref->occluded[i];
            if (m.got_occ == m.ref_occ) {
                out->agree++;
                continue;
            }
            m.cls = classify_any(s, r, &m, graze, disputes++ < VERIFY_ARBITER_MAX);
        }
        out->mismatches[m.cls]++;
        list_mismatch(out, &m);
    }
}
