/* test_cgal_aabb: CGAL's AABB tree (both kernels) against Embree on every
 * workload, over meshes, true spheres, polygons and cones (the mixed tree);
 * zero real mismatches and >= 99.9% agreement; a bad kernel value is
 * refused with a reason; memory() is positive. */
#include <string.h>
#include "testlib.h"

static accel *build_kernel(const scene_t *s, const char *kernel, char *err, size_t errlen)
{
    const struct accel_ops *ops = accel_find("cgal-aabb");
    CHECK_MSG(ops != NULL, "cgal-aabb is not registered");
    if (!ops) exit(2);
    char settings[64];
    snprintf(settings, sizeof settings, "kernel=%s", kernel);
    return test_build_with(ops, s, settings, 2, err, errlen);
}

static void check_scene(const char *name, int res)
{
    scene_t *s = test_scene(name);
    accel *ref = test_build("embree", s, 2);
    static const char *const kernels[] = {"simple", "epick"};
    for (int k = 0; k < 2; k++) {
        char err[512], label[32];
        accel *a = build_kernel(s, kernels[k], err, sizeof err);
        CHECK_MSG(a != NULL, "%s kernel=%s: build failed: %s", name, kernels[k], err);
        if (!a) continue;
        CHECK_MSG(a->ops->memory(a) > 0, "%s kernel=%s: memory() is 0", name, kernels[k]);
        snprintf(label, sizeof label, "cgal-aabb[kernel=%s]", kernels[k]);
        test_workloads_agree(s, ref, a, res, label);
        a->ops->destroy(a);
    }
    ref->ops->destroy(ref);
    scene_free(s);
}

static void check_bad_kernel(void)
{
    scene_t *s = test_scene("spd:balls:1");
    char err[512] = "";
    accel *a = build_kernel(s, "epeck", err, sizeof err);
    CHECK_MSG(a == NULL, "kernel=epeck was accepted");
    CHECK_MSG(strstr(err, "kernel=epeck") != NULL && strchr(err, '\n') == NULL, "kernel=epeck: reason \"%s\"", err);
    printf("kernel=epeck refused: %s\n", err);
    if (a) a->ops->destroy(a);
    scene_free(s);
}

/* A shadow segment shorter than double precision resolves (a direction of
 * 1e-30 from z = 1: org + tfar dir == org) is one point, which CGAL's
 * segment predicates refuse with a precondition failure that ended the
 * program (the ray-file fuzzer found it). It must answer as exhaustive does:
 * clear for the short one, occluded for the same direction reaching the
 * ground plane 1e30 further on. */
static void check_point_segment(void)
{
    scene_t *s = test_scene("spd:balls:1");
    vec3 c = box_center(s->bounds), org = v3(c.x, c.y, s->bounds.hi.z + 1.0f);
    rayset_t *rs = rayset_new("point-segment", s->name, 1, QUERY_ANY);
    const ray_t rays[2] = {{org, 0.0f, v3(0, 0, -1e-30f), 1.0f, RAY_NO_LIGHT, 0},
                           {org, 0.0f, v3(0, 0, -1e-30f), INFINITY, RAY_NO_LIGHT, 0}};
    for (int i = 0; i < 2; i++) rayset_push(rs, &rays[i], 0);
    rayset_seal(rs);
    accel *ex = test_build("exhaustive", s, 1);
    answers_t *want = test_trace(ex, rs, 1);
    CHECK_MSG(!want->occluded[0] && want->occluded[1], "exhaustive: short segment %d, long %d (want clear, occluded)",
              want->occluded[0], want->occluded[1]);
    static const char *const kernels[] = {"simple", "epick"};
    for (int k = 0; k < 2; k++) {
        char err[512];
        accel *a = build_kernel(s, kernels[k], err, sizeof err);
        CHECK_MSG(a != NULL, "kernel=%s: build failed: %s", kernels[k], err);
        if (!a) continue;
        answers_t *got = test_trace(a, rs, 1);
        for (int i = 0; i < 2; i++)
            CHECK_MSG(got->occluded[i] == want->occluded[i], "kernel=%s: segment %d: occluded %d, exhaustive %d",
                      kernels[k], i, got->occluded[i], want->occluded[i]);
        answers_free(got);
        a->ops->destroy(a);
    }
    answers_free(want);
    ex->ops->destroy(ex);
    rayset_free(rs);
    scene_free(s);
}

int main(void)
{
    check_bad_kernel();
    check_point_segment();
    check_scene("bunny", 48);
    static const char *const spd[] = {"spd:balls:2", "spd:balls:2:t", "spd:gears:2", "spd:tree:4", "spd:shells:2"};
    for (size_t i = 0; i < sizeof spd / sizeof spd[0]; i++) check_scene(spd[i], 32);
    return check_report();
}
