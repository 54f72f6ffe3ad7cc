/* test_verify: the verifier catches a broken accelerator, and classifies
 * what it should. A test accelerator that silently skips every 5th
 * primitive must show real mismatches on every workload that hits. */
#include <string.h>
#include "harness/verify.h"
#include "testlib.h"

static bool skip_intersect(accel *a, accel_ctx *ctx, const ray_t *r, hit_t *h, counters_t *c)
{
    (void)ctx;
    for (uint32_t id = 0; id < a->scene->prims.count; id++)
        if (id % 5 != 3) prim_intersect(&a->scene->prims, id, r, h, c);
    return h->prim != HIT_NONE;
}

static bool skip_occluded(accel *a, accel_ctx *ctx, const ray_t *r, counters_t *c)
{
    hit_t h = hit_none(r);
    return skip_intersect(a, ctx, r, &h, c);
}

static size_t no_memory(const accel *a) { (void)a; return 0; }
static void no_destroy(accel *a) { (void)a; }

static const accel_param no_params[] = {{NULL, NULL, NULL}};
static const struct accel_ops broken_ops = {
    .version = 1, .name = "broken", .summary = "drops every 5th primitive", .paper = "none", .params = no_params,
    .intersect = skip_intersect, .occluded = skip_occluded, .memory = no_memory, .destroy = no_destroy,
};

int main(void)
{
    scene_t *s = test_scene("spd:balls:2");
    accel *ref = test_build("embree", s, 1);
    accel broken = {.ops = &broken_ops, .scene = s};
    workload_opts o = test_wl(48, 48, 1);
    for (int w = 0; workload_table[w].name; w++) {
        rayset_t *rs = workload_table[w].make(s, ref, &o);
        answers_t *want = test_trace(ref, rs, 1), *got = test_trace(&broken, rs, 1);
        verify_result vr;
        verify_answers(s, rs, got, want, &vr);
        printf("%-10s agree %llu real %llu edge %llu\n", workload_table[w].name, (unsigned long long)vr.agree,
               (unsigned long long)vr.mismatches[MM_REAL], (unsigned long long)vr.mismatches[MM_EDGE]);
        CHECK_MSG(vr.mismatches[MM_REAL] > 0, "%s: the broken accelerator went unnoticed", workload_table[w].name);
        CHECK(vr.nlisted > 0 && vr.listed[0].ray < rs->count);
        /* Agreement with itself is total. */
        verify_answers(s, rs, want, want, &vr);
        CHECK(vr.agree == rs->count);
        answers_free(want);
        answers_free(got);
        rayset_free(rs);
    }

    /* Classification by construction: one ray, answers edited by hand. */
    ray_t r = {v3(0, 0, 5), 0.0f, v3(0, 0, -1), INFINITY, RAY_NO_LIGHT, 0};
    rayset_t *rs = rayset_new("primary", s->name, 1, QUERY_CLOSEST);
    rayset_push(rs, &r, 0);
    rayset_seal(rs);
    answers_t *want = test_trace(ref, rs, 1), *got = test_trace(ref, rs, 1);
    CHECK(want->hits[0].prim != HIT_NONE); /* straight down onto the root sphere, centre (0,0,0) r 0.5 */
    CHECK_NEAR(want->hits[0].t, 4.5, 1e-4);
    verify_result vr;
    got->hits[0].t += 1e-2f; /* same primitive, t off: tolerance */
    verify_answers(s, rs, got, want, &vr);
    CHECK(vr.mismatches[MM_TOL] == 1);
    got->hits[0].t = want->hits[0].t + 1e-6f; /* within 1e-4 relative: agree */
    verify_answers(s, rs, got, want, &vr);
    CHECK(vr.agree == 1);
    got->hits[0].prim = HIT_NONE; /* a miss through the middle of a sphere: real */
    verify_answers(s, rs, got, want, &vr);
    CHECK(vr.mismatches[MM_REAL] == 1);
    answers_free(want);
    answers_free(got);
    rayset_free(rs);

    /* A ray skimming the floor (z = -0.5) at a slope of 1e-4 hits it near
     * x = -10, far from any edge: a missed answer there is classed edge
     * (ill-conditioned graze), while the same miss on a steep ray is real. */
    for (int steep = 0; steep < 2; steep++) {
        ray_t g = {v3(-11.0f, 0.0f, -0.5f + 1e-4f), 0.0f, v3_norm(v3(1.0f, 0.0f, steep ? -1.0f : -1e-4f)), INFINITY,
                   RAY_NO_LIGHT, 0};
        rayset_t *gs = rayset_new("random", s->name, 1, QUERY_CLOSEST);
        rayset_push(gs, &g, 0);
        rayset_seal(gs);
        answers_t *w = test_trace(ref, gs, 1), *m = test_trace(ref, gs, 1);
        CHECK(w->hits[0].prim == 0); /* the floor polygon is primitive 0 */
        m->hits[0].prim = HIT_NONE;
        verify_answers(s, gs, m, w, &vr);
        CHECK_MSG(vr.mismatches[steep ? MM_REAL : MM_EDGE] == 1, "steep=%d: classes edge %llu real %llu", steep,
                  (unsigned long long)vr.mismatches[MM_EDGE], (unsigned long long)vr.mismatches[MM_REAL]);
        answers_free(w);
        answers_free(m);
        rayset_free(gs);
    }

    ref->ops->destroy(ref);
    scene_free(s);
    return check_report();
}
