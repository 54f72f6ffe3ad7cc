/* prim_hit.h: one primitive test of a traversal, counting or not.
 *
 * Every walk is written once and compiled twice, with `counting` a
 * constant: the warm-up's copy calls prims/'s counting tests (prim_tests,
 * prim_hits), the timed copy the counting-free *_fast forms (accel.h
 * intersect_fast/occluded_fast). Always inlined, so the constant folds and
 * neither copy pays for the other's branch. */
#ifndef ACCELBENCH_PRIM_HIT_H
#define ACCELBENCH_PRIM_HIT_H

#include <stdbool.h>
#include <stdint.h>
#include "../../prims/prims.h"

static inline __attribute__((always_inline)) bool prim_test_closest(const prims_t *p, uint32_t id, const ray_t *ray,
                                                                    hit_t *hit, counters_t *c, const bool counting)
{
    return counting ? prim_intersect(p, id, ray, hit, c) : prim_intersect_fast(p, id, ray, hit);
}

static inline __attribute__((always_inline)) bool prim_test_any(const prims_t *p, uint32_t id, const ray_t *ray,
                                                                counters_t *c, const bool counting)
{
    return counting ? prim_occluded(p, id, ray, c) : prim_occluded_fast(p, id, ray);
}

#endif
