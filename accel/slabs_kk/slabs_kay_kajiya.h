/* slabs_kay_kajiya.h: the test accessors of `slabs-kk`
 * (slabs_kay_kajiya.c); never used while tracing. */
#ifndef ACCELBENCH_SLABS_KAY_KAJIYA_H
#define ACCELBENCH_SLABS_KAY_KAJIYA_H

#include "../accel.h"
#include "planeset.h"

/* Node i of a built `slabs-kk` (node 0 is the root): its slab volume
 * into out[0 .. normals), its index and count (count 0: interior, children
 * index and index + 1; else a leaf of the primitives refs[index ..
 * index + count), *refs set to the refs array). Returns the number of
 * normals (3 or 7), or 0 when i is not a node. */
uint32_t slabs_kk_debug_node(const accel *a, uint32_t i, planeset_slab out[PLANESET_MAX], uint32_t *index,
                             uint32_t *count, const uint32_t **refs);

/* Trace ray (closest hit, or any hit when shadow) with the built
 * traversal, recording in order the nodes it expands (its steps) and the
 * key each was expanded with (its entry distance) into nodes[] and keys[],
 * at most cap of them. Returns how many it expanded (which may pass cap);
 * *hit gets the closest-hit answer (HIT_NONE for shadow rays, and on a
 * miss). */
uint32_t slabs_kk_debug_visits(const accel *a, const ray_t *ray, bool shadow, uint32_t *nodes, float *keys,
                               uint32_t cap, hit_t *hit);

#endif
