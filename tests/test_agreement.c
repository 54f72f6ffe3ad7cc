/* test_agreement: exhaustive vs Embree, every workload, on the CI scenes
 * and on every SPD database at a small size (true spheres, cones and
 * concave polygons, and a tessellated one).
 * Zero real mismatches, and nearly every ray agrees outright (edge grazes
 * are float noise, but there must be few of them). */
#include "testlib.h"

static void check_scene(const char *name, int res)
{
    scene_t *s = test_scene(name);
    accel *ref = test_build("embree", s, 2);
    accel *ex = test_build("exhaustive", s, 2);
    test_workloads_agree(s, ref, ex, res, "exhaustive");
    ex->ops->destroy(ex);
    ref->ops->destroy(ref);
    scene_free(s);
}

int main(void)
{
    check_scene("spd:balls:2", 64);
    check_scene("spd:balls:2:t", 64);
    check_scene("bunny", 48);
    static const char *const spd[] = {"spd:gears:2", "spd:mount:3", "spd:rings:2", "spd:teapot:4", "spd:tetra:3",
                                      "spd:tree:4", "spd:lattice:3", "spd:shells:2", "spd:jacks:2", "spd:sombrero:1",
                                      "spd:gears:1:t", "spd:tree:3:t"};
    for (size_t i = 0; i < sizeof spd / sizeof spd[0]; i++) check_scene(spd[i], 32);
    return check_report();
}
