/* test_agreement: exhaustive vs Embree, every workload, on the CI scenes
 * and on every SPD database at a small size (true spheres, cones and
 * concave polygons, and a tessellated one).
 * Zero real mismatches, and nearly every ray agrees outright (edge grazes
 * are float noise, but there must be few of them). */
#include "harness/verify.h"
#include "testlib.h"

static void check_scene(const char *name, int res)
{
    scene_t *s = test_scene(name);
    accel *ref = test_build("embree", s, 2);
    accel *ex = test_build("exhaustive", s, 2);
    workload_opts o = test_wl(res, res, 2);
    for (int w = 0; workload_table[w].name; w++) {
        rayset_t *rs = workload_table[w].make(s, ref, &o);
        answers_t *want = test_trace(ref, rs, 2), *got = test_trace(ex, rs, 2);
        verify_result vr;
        verify_answers(s, rs, got, want, &vr);
        uint64_t hits = 0;
        for (uint32_t i = 0; i < rs->count; i++)
            hits += rs->query == QUERY_ANY ? want->occluded[i] : want->hits[i].prim != HIT_NONE;
        printf("%-16s %-10s rays %6u hits %6llu agree %6llu edge %llu tol %llu refwrong %llu real %llu\n", name,
               workload_table[w].name, rs->count, (unsigned long long)hits, (unsigned long long)vr.agree,
               (unsigned long long)vr.mismatches[MM_EDGE], (unsigned long long)vr.mismatches[MM_TOL],
               (unsigned long long)vr.mismatches[MM_REFWRONG], (unsigned long long)vr.mismatches[MM_REAL]);
        CHECK_MSG(rs->count > 0, "%s %s: empty ray set", name, workload_table[w].name);
        CHECK_MSG(hits > 0, "%s %s: the reference hit nothing; the test would prove nothing", name, workload_table[w].name);
        CHECK_MSG(vr.mismatches[MM_REAL] == 0, "%s %s: %llu real mismatches", name, workload_table[w].name,
                  (unsigned long long)vr.mismatches[MM_REAL]);
        CHECK_MSG(vr.agree * 1000 >= (uint64_t)rs->count * 999, "%s %s: only %llu of %u agree", name,
                  workload_table[w].name, (unsigned long long)vr.agree, rs->count);
        answers_free(want);
        answers_free(got);
        rayset_free(rs);
    }
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
