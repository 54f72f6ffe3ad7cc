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

int main(void)
{
    check_bad_kernel();
    check_scene("bunny", 48);
    static const char *const spd[] = {"spd:balls:2", "spd:balls:2:t", "spd:gears:2", "spd:tree:4", "spd:shells:2"};
    for (size_t i = 0; i < sizeof spd / sizeof spd[0]; i++) check_scene(spd[i], 32);
    return check_report();
}
