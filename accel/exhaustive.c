/* exhaustive.c: no acceleration at all; every ray tests every primitive.
 *
 * Paper: the baseline every survey measures against (Arvo and Kirk, "A
 * Survey of Ray Tracing Acceleration Techniques", 1989, section 1: the
 * cost of naive ray tracing is linear in the number of objects).
 *
 * Parameters: none.
 * Memory layout: nothing beyond the scene's primitive store (0 bytes).
 * Counters: prim_tests = primitives per ray (closest hit), fewer for
 * occlusion rays, which stop at the first hit. No box tests, no steps.
 * It is the correctness anchor of the testbed: its only logic is the
 * prims/ interface itself. */
#include <stdlib.h>
#include "accel.h"

static const accel_param exhaustive_params[] = {{NULL, NULL, NULL}};

static accel *exhaustive_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    (void)params, (void)err, (void)errlen;
    accel *a = calloc(1, sizeof *a);
    if (!a) return NULL;
    a->scene = scene;
    return a;
}

static bool exhaustive_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    (void)ctx;
    const prims_t *p = &a->scene->prims;
    for (uint32_t id = 0; id < p->count; id++) prim_intersect(p, id, ray, hit, c);
    return hit->prim != HIT_NONE;
}

static bool exhaustive_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    (void)ctx;
    const prims_t *p = &a->scene->prims;
    for (uint32_t id = 0; id < p->count; id++)
        if (prim_occluded(p, id, ray, c)) return true;
    return false;
}

static size_t exhaustive_memory(const accel *a) { (void)a; return 0; }
static void exhaustive_destroy(accel *a) { free(a); }

const struct accel_ops accel_exhaustive = {
    .version = 1,
    .name = "exhaustive",
    .summary = "every ray tests every primitive (the baseline and correctness anchor)",
    .paper = "Arvo & Kirk 1989, survey section 1 (naive ray tracing)",
    .params = exhaustive_params,
    .flags = 0,
    .build = exhaustive_build,
    .intersect = exhaustive_intersect,
    .occluded = exhaustive_occluded,
    .memory = exhaustive_memory,
    .destroy = exhaustive_destroy,
};
