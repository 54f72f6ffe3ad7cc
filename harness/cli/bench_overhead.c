/* bench_overhead: what the harness costs on top of Embree.
 *
 * Traces the same primary rays through Embree twice, on one thread:
 *   harness  trace_rayset() -> accel_ops.intersect -> rtcIntersect1
 *   bare     a plain loop of rtcIntersect1 over the same RTCScene,
 *            storing t, u, v and prim per ray, as the harness does
 * and prints the median of N runs of each (after a warm-up) and the
 * overhead in percent. Not a test: a benchmark that writes numbers.
 *
 * usage: accelbench-overhead [SCENE [RES [REPEAT]]]   (default bunny 512 11) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../../accel/peers/embree.h"
#include "../run/machine.h"
#include "../workloads/trace.h"
#include "../../prims/checked_alloc.h"
#include "../workloads/workload.h"

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double bare_loop(RTCScene scene, const rayset_t *rs, hit_t *out)
{
    double t0 = clock_ms();
    struct RTCIntersectContext ic;
    rtcInitIntersectContext(&ic);
    for (uint32_t i = 0; i < rs->count; i++) {
        const ray_t *r = &rs->rays[i];
        struct RTCRayHit rh;
        rh.ray.org_x = r->org.x, rh.ray.org_y = r->org.y, rh.ray.org_z = r->org.z, rh.ray.tnear = r->tnear;
        rh.ray.dir_x = r->dir.x, rh.ray.dir_y = r->dir.y, rh.ray.dir_z = r->dir.z, rh.ray.time = 0.0f;
        rh.ray.tfar = r->tfar, rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ic, &rh);
        out[i].t = rh.ray.tfar;
        out[i].u = rh.hit.u;
        out[i].v = rh.hit.v;
        out[i].prim = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? HIT_NONE : rh.hit.primID;
    }
    return clock_ms() - t0;
}

int main(int argc, char **argv)
{
    const char *scene_name = argc > 1 ? argv[1] : "bunny";
    int res = argc > 2 ? atoi(argv[2]) : 512, repeat = argc > 3 ? atoi(argv[3]) : 11;
    if (res < 1 || repeat < 1) {
        fprintf(stderr, "usage: accelbench-overhead [SCENE [RES [REPEAT]]]\n");
        return 2;
    }
    char err[512];
    scene_t *s = scene_load(scene_name, err, sizeof err);
    if (!s) {
        fprintf(stderr, "accelbench-overhead: %s\n", err);
        return 2;
    }
    const struct accel_ops *ops = accel_find(ACCEL_REFERENCE);
    accel_params p;
    params_defaults(&p, ops->params);
    p.threads = 1;
    accel *a = accel_build(ops, s, &p, err, sizeof err);
    if (!a) {
        fprintf(stderr, "accelbench-overhead: %s\n", err);
        return 2;
    }
    workload_opts o = {.width = res, .height = res, .spp = 1, .depth = 3, .seed = 1, .threads = 1};
    rayset_t *rs = workload_primary(s, &o);
    answers_t *ans = answers_new(rs, false);
    /* Both paths write into the same answer buffer, so the comparison is
     * not skewed by where two different 4 MB arrays happen to land. The
     * answers checked below come from one more bare loop into a buffer of
     * their own. */
    hit_t *bare = checked_calloc(rs->count, sizeof *bare, "the bare loop's answers");
    double *th = checked_calloc((size_t)repeat, sizeof(double), "the harness's times");
    double *tb = checked_calloc((size_t)repeat, sizeof(double), "the bare loop's times");
    trace_rayset(a, rs, 1, ans); /* warm-up both paths */
    bare_loop(embree_scene_of(a), rs, ans->hits);
    for (int k = 0; k < repeat; k++) { /* interleaved, alternating who goes first, so drift and order hit both alike */
        if (k % 2) {
            th[k] = trace_rayset(a, rs, 1, ans);
            tb[k] = bare_loop(embree_scene_of(a), rs, ans->hits);
        } else {
            tb[k] = bare_loop(embree_scene_of(a), rs, ans->hits);
            th[k] = trace_rayset(a, rs, 1, ans);
        }
    }
    bare_loop(embree_scene_of(a), rs, bare);
    trace_rayset(a, rs, 1, ans);
    qsort(th, (size_t)repeat, sizeof *th, cmp);
    qsort(tb, (size_t)repeat, sizeof *tb, cmp);
    uint32_t same = 0;
    for (uint32_t i = 0; i < rs->count; i++) same += ans->hits[i].t == bare[i].t || (ans->hits[i].prim == HIT_NONE && bare[i].prim == HIT_NONE);
    machine_info mi;
    machine_describe(&mi);
    double mh = th[repeat / 2], mb = tb[repeat / 2];
    printf("scene %s, %u primary rays, 1 thread, median of %d after a warm-up, %s, %s\n", s->name, rs->count, repeat,
           mi.cpu, mi.git_rev);
    printf("  bare rtcIntersect1 loop   %8.2f ms  %7.3f Mrays/s\n", mb, rs->count / (mb * 1e3));
    printf("  through accelbench        %8.2f ms  %7.3f Mrays/s\n", mh, rs->count / (mh * 1e3));
    printf("  overhead                  %+7.2f %%   (same answers: %u of %u)\n", 100.0 * (mh - mb) / mb, same, rs->count);
    free(th), free(tb), free(bare);
    answers_free(ans);
    rayset_free(rs);
    a->ops->destroy(a);
    scene_free(s);
    return same == rs->count ? 0 : 1;
}
