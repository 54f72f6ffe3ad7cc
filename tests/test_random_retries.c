/* test_random_retries: the random workload redraws a zero-length segment a
 * bounded number of times (harness/workloads/workload.h workload_random): on a scene
 * whose box is a point it fails with the reason instead of looping forever
 * (the hang), while a box one float step wide, where about half the
 * draws are zero-length, still gives every ray. */
#include <string.h>
#include "testlib.h"

static scene_t *triangle(vec3 a, vec3 b, vec3 c)
{
    char err[512];
    scene_t *s = scene_new("tri");
    prims_add_vertex(&s->prims, a);
    prims_add_vertex(&s->prims, b);
    prims_add_vertex(&s->prims, c);
    prims_add_triangle(&s->prims, 0, 1, 2);
    if (scene_finish(s, false, err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        exit(2);
    }
    return s;
}

int main(void)
{
    char err[512] = "";
    workload_opts o = test_wl(16, 16, 1);
    scene_t *point = triangle(v3(1, 1, 1), v3(1, 1, 1), v3(1, 1, 1));
    rayset_t *rs = workload_random(point, &o, err, sizeof err);
    CHECK_MSG(!rs && strstr(err, "random workload: scene 'tri' has no box to draw segments in") &&
                  strstr(err, "(1 1 1) .. (1 1 1)"), "%s", rs ? "made rays" : err);
    rayset_free(rs);
    scene_free(point);

    const float x = 1e6f, next = nextafterf(1e6f, 2e6f); /* the 5% pad is below a float step here */
    scene_t *thin = triangle(v3(x, 0, 0), v3(next, 0, 0), v3(x, 0, 0));
    rs = workload_random(thin, &o, err, sizeof err);
    CHECK_MSG(rs && rs->count == 256, "%s", rs ? "short" : err);
    for (uint32_t i = 0; rs && i < rs->count; i++) CHECK(ray_traceable(&rs->rays[i]) && rs->rays[i].tfar > 0);
    rayset_free(rs);
    scene_free(thin);
    return check_report();
}
