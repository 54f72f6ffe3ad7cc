/* ray.h: rays, hits and the work counters.
 *
 * A ray is the segment org + t*dir for t in [tnear, tfar]. dir need not be
 * unit length (random segments use the segment vector), and t is measured in
 * units of dir. A closest-hit query returns the smallest t in the range; an
 * any-hit (occlusion) query returns whether any t in the range hits. */
#ifndef ACCELBENCH_RAY_H
#define ACCELBENCH_RAY_H

#include <assert.h> /* static_assert, also in C++ */
#include <stdint.h>
#include <stdbool.h>
#include "vec3.h"

#ifdef __cplusplus
extern "C" {
#endif

#define RAY_NO_LIGHT UINT32_MAX
#define RAY_NO_ORIGIN UINT32_MAX
#define HIT_NONE UINT32_MAX

typedef struct {
    vec3 org;
    float tnear;
    vec3 dir;
    float tfar;
    uint32_t light; /* shadow rays: index of the scene light the ray goes to; else RAY_NO_LIGHT */
    /* Secondary rays (shadow, reflection, refraction, diffuse, whitted's):
     * the primitive whose hit spawned the ray, which the origin lies on (up
     * to the robust offset); eye rays, random rays and anything without a
     * known origin: RAY_NO_ORIGIN. A hint only: the ray coherence
     * accelerator (raycoh) uses it after checking the origin is near that
     * primitive; every other accelerator ignores it. */
    uint32_t origin;
} ray_t;
static_assert(sizeof(ray_t) == 40, "ray_t is 40 bytes; the ray file format depends on it");

/* The largest coordinate magnitude a traceable ray may have: 2^60, under
 * Embree's limit (FLT_LARGE, 1.8e19, past which its ray.valid() assertion
 * aborts) and far from float overflow in o + t d for any t that matters. */
#define RAY_COORD_MAX 0x1p60f

/* Whether a ray may reach an accelerator: finite origin and direction with
 * components of magnitude at most RAY_COORD_MAX, a nonzero direction, and
 * 0 <= tnear <= tfar with tnear finite (tfar may be +inf). The harness
 * answers any other ray "miss" itself (harness/workloads/trace.c), so no accelerator
 * needs its own check. */
static inline bool ray_traceable(const ray_t *r)
{
    const float c[6] = {r->org.x, r->org.y, r->org.z, r->dir.x, r->dir.y, r->dir.z};
    for (int i = 0; i < 6; i++)
        if (!(fabsf(c[i]) <= RAY_COORD_MAX)) return false; /* also NaN */
    if (r->dir.x == 0.0f && r->dir.y == 0.0f && r->dir.z == 0.0f) return false;
    return r->tnear >= 0.0f && r->tnear <= RAY_COORD_MAX && r->tnear <= r->tfar; /* NaN fails every comparison */
}

/* A hit: distance, primitive id (scene order) and the primitive's own
 * parameters (barycentrics for triangles, unused for spheres). prim ==
 * HIT_NONE means no hit; t then holds the ray's tfar. */
typedef struct {
    float t, u, v;
    uint32_t prim;
} hit_t;

static inline hit_t hit_none(const ray_t *r)
{
    hit_t h = {r->tfar, 0.0f, 0.0f, HIT_NONE};
    return h;
}

/* Work counters. Each thread owns one; they are summed at the end, so
 * nothing shared is written while tracing. prim_tests and prim_hits are
 * bumped only inside prims/, so they mean the same for every accelerator;
 * the others are bumped by the accelerators (see accel.h for definitions). */
typedef struct {
    uint64_t prim_tests;    /* ray/primitive intersection tests performed */
    uint64_t prim_hits;     /* tests that found a hit inside the current [tnear, t] */
    uint64_t box_tests;     /* ray/box tests: BVH nodes, voxels, slabs, ray boxes */
    uint64_t steps;         /* traversal steps: nodes visited, voxels stepped */
    uint64_t empty_leaves;  /* leaves or voxels visited that held no primitive */
    uint64_t mailbox_hits;  /* primitive tests skipped because the mailbox said "done" */
} counters_t;

#define COUNTERS_N 6
static inline uint64_t *counters_array(counters_t *c) { return &c->prim_tests; }
static inline void counters_add(counters_t *a, const counters_t *b)
{
    a->prim_tests += b->prim_tests;
    a->prim_hits += b->prim_hits;
    a->box_tests += b->box_tests;
    a->steps += b->steps;
    a->empty_leaves += b->empty_leaves;
    a->mailbox_hits += b->mailbox_hits;
}

#ifdef __cplusplus
}
#endif

#endif
