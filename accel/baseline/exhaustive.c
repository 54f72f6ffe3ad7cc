/* exhaustive.c: no acceleration at all; every ray tests every primitive.
 * Reference: docs/accels/exhaustive.md.
 *
 * Paper: the baseline every survey measures against (Arvo and Kirk, "A
 * Survey of Ray Tracing Acceleration Techniques", 1989, section 1: the
 * cost of naive ray tracing is linear in the number of objects).
 *
 * Parameters: none.
 * Memory layout: nothing beyond the scene's primitive store but the base
 * object itself (sizeof(accel) bytes, what memory() reports).
 * Counters: prim_tests = primitives per ray (closest hit), fewer for
 * occlusion rays, which stop at the first hit. No box tests, no steps.
 * intersect_fast/occluded_fast: the same loop with prims/'s counting-free
 * tests. Version 2 with no stats, reset, bounds (the scene's) or variants:
 * it has no structure and no parameters.
 * It is the correctness anchor of the testbed: its only logic is the
 * prims/ interface itself. */
#include <stdlib.h>
#include "../accel.h"
#include "../common/prim_hit.h"

static const accel_param exhaustive_params[] = {PARAM_ROW_END};

static accel *exhaustive_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    (void)params, (void)err, (void)errlen;
    accel *a = calloc(1, sizeof *a);
    if (!a) return NULL;
    a->scene = scene;
    return a;
}

/* One source for the counting and the counting-free queries: `counting`
 * is a constant at every call site, so the fast ones are this loop with
 * prims/'s counting-free tests and nothing else changed. */
static inline __attribute__((always_inline)) bool scan(const accel *a, const ray_t *ray, hit_t *hit, counters_t *c,
                                                       const bool shadow, const bool counting)
{
    const prims_t *p = &a->scene->prims;
    for (uint32_t id = 0; id < p->count; id++) {
        if (shadow) {
            if (prim_test_any(p, id, ray, c, counting)) return true;
        } else {
            prim_test_closest(p, id, ray, hit, c, counting);
        }
    }
    return shadow ? false : hit->prim != HIT_NONE;
}

static bool exhaustive_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    (void)ctx;
    return scan(a, ray, hit, c, false, true);
}

static bool exhaustive_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    (void)ctx;
    return scan(a, ray, NULL, c, true, true);
}

static bool exhaustive_intersect_fast(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit)
{
    (void)ctx;
    return scan(a, ray, hit, NULL, false, false);
}

static bool exhaustive_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *ray)
{
    (void)ctx;
    return scan(a, ray, NULL, NULL, true, false);
}

static size_t exhaustive_memory(const accel *a) { return sizeof *a; }
static void exhaustive_destroy(accel *a) { free(a); }

const struct accel_ops accel_exhaustive = {
    .version = 2,
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
    .intersect_fast = exhaustive_intersect_fast,
    .occluded_fast = exhaustive_occluded_fast,
    .cost = {1, 2, ACCEL_COST_TRACE_LINEAR},
};
