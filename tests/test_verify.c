/* test_verify: the verifier catches a broken accelerator, and classifies
 * what it should. A test accelerator that silently skips every 5th
 * primitive must show real mismatches on every workload that hits. */
#include <string.h>
#include "harness/measure/verify.h"
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

static const accel_param no_params[] = {PARAM_ROW_END};
static const struct accel_ops broken_ops = {
    .version = 1, .name = "broken", .summary = "drops every 5th primitive", .paper = "none", .params = no_params,
    .intersect = skip_intersect, .occluded = skip_occluded, .memory = no_memory, .destroy = no_destroy,
};

/* ------------------------------------------------ each class on purpose */

/* One ray and hand-edited answers on a scene of two triangles: T0 in z = 0
 * around the coordinate origin, T1 in z = 0 around (1e6, 1e6), where one
 * float step of the coordinates is 0.0625. */
static scene_t *two_triangles(void)
{
    scene_t *s = scene_new("two triangles");
    prims_t *p = &s->prims;
    uint32_t a = prims_add_vertex(p, v3(-10, -10, 0)), b = prims_add_vertex(p, v3(10, -10, 0)), c = prims_add_vertex(p, v3(0, 10, 0));
    prims_add_triangle(p, a, b, c);
    a = prims_add_vertex(p, v3(1e6f - 100, 1e6f - 100, 0)), b = prims_add_vertex(p, v3(1e6f + 100, 1e6f - 100, 0));
    c = prims_add_vertex(p, v3(1e6f, 1e6f + 100, 0));
    prims_add_triangle(p, a, b, c);
    char err[256];
    if (scene_finish(s, false, err, sizeof err)) {
        fprintf(stderr, "%s\n", err);
        exit(2);
    }
    return s;
}

/* Classify one ray with the given answers; returns the class, or -1 when it agrees. */
static int classify(verifier_t *v, ray_t r, query_kind q, hit_t got, hit_t ref, bool got_occ, bool ref_occ)
{
    rayset_t *rs = rayset_new(q == QUERY_ANY ? "shadow" : "primary", "two triangles", 1, q);
    rayset_push(rs, &r, 0);
    rayset_seal(rs);
    answers_t *g = answers_new(rs, false), *w = answers_new(rs, false);
    if (q == QUERY_ANY) g->occluded[0] = got_occ, w->occluded[0] = ref_occ;
    else g->hits[0] = got, w->hits[0] = ref;
    verify_result vr;
    verifier_check(v, rs, g, w, &vr);
    int cls = -1;
    for (int c = 0; c < MM_CLASSES; c++)
        if (vr.mismatches[c]) cls = c;
    answers_free(g);
    answers_free(w);
    rayset_free(rs);
    return cls;
}

#define CHECK_CLASS(got, want) CHECK_MSG((got) == (want), "class %s, expected %s", (got) < 0 ? "agree" : mismatch_class_name[got], mismatch_class_name[want])

static void classes_on_purpose(void)
{
    scene_t *s = two_triangles();
    verifier_t *v = verifier_new(s, 0.0);
    const hit_t miss = {INFINITY, 0, 0, HIT_NONE};
    ray_t down = {v3(1, 1, 5), 0.0f, v3(0, 0, -1), INFINITY, RAY_NO_LIGHT, 0};
    hit_t t0 = {5.0f, 0, 0, 0};
    /* edge: the ray meets T0 exactly on its edge y = -10, and one side missed. */
    ray_t on_edge = {v3(0, -10, 5), 0.0f, v3(0, 0, -1), INFINITY, RAY_NO_LIGHT, 0};
    CHECK_CLASS(classify(v, on_edge, QUERY_CLOSEST, miss, t0, 0, 0), MM_EDGE);
    /* origin: the ray starts on T0 and leaves it; the reference "hit" T0 at t = 0. */
    ray_t leaving = {v3(1, 1, 0), 0.0f, v3(0, 0, 1), INFINITY, RAY_NO_LIGHT, 0};
    hit_t at_zero = {0.0f, 0, 0, 0};
    CHECK_CLASS(classify(v, leaving, QUERY_CLOSEST, miss, at_zero, 0, 0), MM_ORIGIN);
    /* tol: T1 at coordinates 1e6, t off by 0.5: beyond 1e-4 relative (0.001),
     * within 64 float steps of the coordinates (64 * 0.0625 = 4). */
    ray_t far = {v3(1e6f, 1e6f, 10), 0.0f, v3(0, 0, -1), INFINITY, RAY_NO_LIGHT, 0};
    hit_t t1 = {10.0f, 0, 0, 1}, t1_off = {10.5f, 0, 0, 1};
    CHECK_CLASS(classify(v, far, QUERY_CLOSEST, t1_off, t1, 0, 0), MM_TOL);
    /* The same 0.5 near the coordinate origin is no rounding: real. */
    hit_t t0_off = {5.5f, 0, 0, 0};
    CHECK_CLASS(classify(v, down, QUERY_CLOSEST, t0_off, t0, 0, 0), MM_REAL);
    /* refwrong: the reference says miss through the middle of T0. */
    CHECK_CLASS(classify(v, down, QUERY_CLOSEST, t0, miss, 0, 0), MM_REFWRONG);
    /* real: a broken accelerator misses the middle of T0. */
    CHECK_CLASS(classify(v, down, QUERY_CLOSEST, miss, t0, 0, 0), MM_REAL);
    /* Any-hit rays: the same two through the judge. */
    ray_t shadow = {v3(1, 1, 5), 0.0f, v3(0, 0, -1), 10.0f, 0, 0};
    CHECK_CLASS(classify(v, shadow, QUERY_ANY, miss, miss, 0, 1), MM_REAL);
    CHECK_CLASS(classify(v, shadow, QUERY_ANY, miss, miss, 1, 0), MM_REFWRONG);
    /* The hit at the very end of a shadow ray's range is a tolerance question. */
    ray_t to_end = {v3(1, 1, 5), 0.0f, v3(0, 0, -1), nextafterf(5.0f, INFINITY), 0, 0};
    CHECK_CLASS(classify(v, to_end, QUERY_ANY, miss, miss, 0, 1), MM_TOL);
    verifier_free(v);
    /* unjudged: a judge with no time left. */
    v = verifier_new(s, 1e-12);
    CHECK_CLASS(classify(v, down, QUERY_CLOSEST, miss, t0, 0, 0), MM_UNJUDGED);
    verifier_free(v);
    scene_free(s);
}

/* origin, measured at the ray's start: buildings' shadow ray 2761 at
 * 256x256 starts 1.2e-4 from the plane of a triangle 40 high and 0.0036
 * wide (a thin wall seen nearly edge-on), which crosses the ray at
 * t = -0.00057: no hit (the judge's miss). The triangle test reports that
 * (its distance comes from the plane, tri_sheared.h's triangle_plane_t);
 * a float test summing the sheared z's put the hit at t = 0.0040, where
 * t |d . n| passed the origin bound. Such a hit is origin: the origin's
 * distance from the plane is within the bound. An "occluded" on this ray
 * that no float test finds (none of prims/ does) has no primitive to be
 * noise on: real. Moved 0.01 on along the ray, away from the wall, a hit
 * on it is real too. */
static void origin_on_thin_wall(void)
{
    scene_t *s = scene_new("thin wall");
    prims_t *p = &s->prims;
    uint32_t a = prims_add_vertex(p, v3(0x1.d90ffap+5f, 0x1.8cdcfap+6f, 0.0f));
    uint32_t b = prims_add_vertex(p, v3(0x1.d908cep+5f, 0x1.8ce69ap+6f, 0.0f));
    uint32_t c = prims_add_vertex(p, v3(0x1.d908cep+5f, 0x1.8ce69ap+6f, 0x1.4p+5f));
    prims_add_triangle(p, a, b, c);
    char err[256];
    if (scene_finish(s, false, err, sizeof err)) {
        fprintf(stderr, "%s\n", err);
        exit(2);
    }
    const vec3 o = v3(0x1.d90a46p+5f, 0x1.8ce4f6p+6f, 0x1.c89454p+4f), d = v3(0x1.959586p-2f, -0x1.f7d776p-2f, 0x1.8ceeb2p-1f);
    ray_t r = {o, 0.0f, d, 608.137451f, 0, 0};
    hit_t h = hit_none(&r);
    counters_t cnt = {0};
    CHECK_MSG(!prim_intersect(p, 0, &r, &h, &cnt), "the float test's hit: t %g, behind the origin", h.t);
    CHECK(prim_plane_distance(p, 0, o) < 2e-4);
    verifier_t *v = verifier_new(s, 0.0);
    const hit_t miss = {INFINITY, 0, 0, HIT_NONE}, summed = {0.0040148f, 0.5f, 0.0f, 0};
    CHECK_CLASS(classify(v, r, QUERY_CLOSEST, summed, miss, 0, 0), MM_ORIGIN);
    CHECK_CLASS(classify(v, r, QUERY_ANY, miss, miss, 1, 0), MM_REAL);
    ray_t away = r;
    away.org = v3(o.x + 0.01f * d.x, o.y + 0.01f * d.y, o.z + 0.01f * d.z);
    CHECK(prim_plane_distance(p, 0, away.org) > 1e-3);
    CHECK_CLASS(classify(v, away, QUERY_ANY, miss, miss, 1, 0), MM_REAL);
    verifier_free(v);
    scene_free(s);
}

int main(void)
{
    scene_t *s = test_scene("spd:balls:2");
    accel *ref = test_build("embree", s, 1);
    /* The mountain has glass spheres: every workload, whitted:refracted too, has rays. */
    scene_t *glass = test_scene("spd:mount:3");
    accel *glass_ref = test_build("embree", glass, 1);
    accel broken = {.ops = &broken_ops, .scene = glass};
    workload_opts o = test_wl(48, 48, 1);
    for (int w = 0; workload_table[w].name; w++) {
        rayset_t *rs = workload_table[w].make(glass, glass_ref, &o);
        answers_t *want = test_trace(glass_ref, rs, 1), *got = test_trace(&broken, rs, 1);
        verify_result vr;
        verify_answers(glass, rs, got, want, &vr);
        printf("%-10s agree %llu real %llu edge %llu\n", workload_table[w].name, (unsigned long long)vr.agree,
               (unsigned long long)vr.mismatches[MM_REAL], (unsigned long long)vr.mismatches[MM_EDGE]);
        CHECK_MSG(vr.mismatches[MM_REAL] > 0, "%s: the broken accelerator went unnoticed", workload_table[w].name);
        CHECK(vr.nlisted > 0 && vr.listed[0].ray < rs->count);
        /* Agreement with itself is total. */
        verify_answers(glass, rs, want, want, &vr);
        CHECK(vr.agree == rs->count);
        answers_free(want);
        answers_free(got);
        rayset_free(rs);
    }

    verify_result vr;
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
    glass_ref->ops->destroy(glass_ref);
    scene_free(glass);
    scene_free(s);
    classes_on_purpose();
    origin_on_thin_wall();
    return check_report();
}
