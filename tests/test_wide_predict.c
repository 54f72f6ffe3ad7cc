/* test_wide_predict: bvh's cost model (accel/bvh_wide/wide_predict.c), the
 * counters per ray it predicts from the tree, against
 * - a tree whose answer is computed by hand: two triangles in boxes of
 *   area 6 under a root box of area 18, each its own leaf (leafsize=1,
 *   bigleaf=0): steps 1 + 6/18 + 6/18, box tests 2 (the root's slots),
 *   primitive tests 6/18 + 6/18;
 * - the measured counters of the walk over lines the model is stated for:
 *   uniform over the lines that meet the root's box (prims_testlib.h
 *   random_line, as test_bvh_gs draws them for eq. (3)),
 *   through a scene of tiny triangles that the lines almost never hit, so
 *   nothing cuts a walk short. The mean of 1,600,000 lines must be within 2 %
 *   of the prediction for steps, box tests and primitive tests, at widths
 *   4 and 8 and with quantised nodes. */
#include <math.h>
#define PRIMS_TEST_SEED 0x5eed2026u
#include "prims_testlib.h"
#include "testlib.h"
#include "line_testlib.h"
#include "accel/bvh_wide/wide.h"
#include "accel/bvh_wide/bvh_wide.h"


static scene_t *finished(scene_t *s)
{
    test_finish_scene(s);
    return s;
}

static void add_tri(scene_t *s, vec3 a, vec3 b, vec3 c)
{
    prims_add_triangle(&s->prims, prims_add_vertex(&s->prims, a), prims_add_vertex(&s->prims, b),
                       prims_add_vertex(&s->prims, c));
}

static void test_by_hand(void)
{
    scene_t *s = scene_new("two boxes of area 6");
    add_tri(s, v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 1)); /* box [0,1]^3 */
    add_tri(s, v3(3, 0, 0), v3(4, 0, 0), v3(3, 1, 1)); /* box [3,4]x[0,1]^2 */
    finished(s);
    accel *a = test_build_or_die("bvh", s, "leafsize=1,bigleaf=0,width=4");
    const wide_bvh *w = bvh_wide_tree(a, NULL);
    CHECK_MSG(w->nnodes == 1 && w->nleaves == 2, "the tree: %u nodes, %u leaves (want 1 root, 2 leaves)", w->nnodes,
              w->nleaves);
    wide_prediction pr = wide_predict(w);
    printf("by hand: steps %.6f box tests %.6f prim tests %.6f\n", pr.steps, pr.box_tests, pr.prim_tests);
    CHECK(fabs(pr.steps - (1.0 + 12.0 / 18.0)) < 1e-9);
    CHECK(fabs(pr.box_tests - 2.0) < 1e-9);
    CHECK(fabs(pr.prim_tests - 12.0 / 18.0) < 1e-9);
    CHECK(test_stat(a, "predicted_box_tests_per_ray") == pr.box_tests && test_stat(a, "predicted_tests_per_ray") == pr.prim_tests &&
          test_stat(a, "predicted_steps_per_ray") == pr.steps);
    a->ops->destroy(a);
    scene_free(s);
}

static void test_against_lines(const scene_t *s, const char *cfg, uint32_t nlines)
{
    accel *a = test_build_or_die("bvh", s, cfg);
    const wide_bvh *w = bvh_wide_tree(a, NULL);
    const wide_prediction pr = wide_predict(w);
    counters_t c = {0};
    const uint32_t hits = trace_random_lines(a, nlines, &c);
    const double steps = (double)c.steps / nlines, box = (double)c.box_tests / nlines,
                 prim = (double)c.prim_tests / nlines;
    printf("%-8s %u lines (%u hit a triangle): steps %.3f predicted %.3f, box tests %.3f predicted %.3f, prim "
           "tests %.3f predicted %.3f\n",
           cfg, nlines, hits, steps, pr.steps, box, pr.box_tests, prim, pr.prim_tests);
    CHECK_MSG(fabs(steps / pr.steps - 1.0) < 0.02, "%s: steps %.3f, predicted %.3f", cfg, steps, pr.steps);
    CHECK_MSG(fabs(box / pr.box_tests - 1.0) < 0.02, "%s: box tests %.3f, predicted %.3f", cfg, box, pr.box_tests);
    CHECK_MSG(fabs(prim / pr.prim_tests - 1.0) < 0.02, "%s: prim tests %.3f, predicted %.3f", cfg, prim,
              pr.prim_tests);
    a->ops->destroy(a);
}

int main(void)
{
    test_by_hand();
    /* 3000 triangles of edge 0.01 scattered in a 10-unit cube. */
    scene_t *s = scene_new("tiny triangles");
    for (int i = 0; i < 3000; i++) {
        vec3 p = v3(rnd(0, 10), rnd(0, 10), rnd(0, 10));
        add_tri(s, p, v3_add(p, v3(0.01f, 0, 0)), v3_add(p, v3(0, 0.01f, 0.005f)));
    }
    finished(s);
    test_against_lines(s, "width=8", 1600000);
    test_against_lines(s, "width=4", 1600000);
    test_against_lines(s, "compress=on", 1600000);
    scene_free(s);
    return check_report();
}
