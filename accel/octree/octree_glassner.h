/* octree_glassner.h: test accessors of the `octree` accelerator
 * (octree_glassner.c, Glassner 1984). Never used while tracing. */
#ifndef ACCELBENCH_OCTREE_GLASSNER_H
#define ACCELBENCH_OCTREE_GLASSNER_H

#include <stdint.h>
#include "../accel.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The deepest maxdepth the octree accepts. */
#define OCTREE_MAXDEPTH_LIMIT 20

enum { OCTREE_ABSENT = 0, OCTREE_INTERIOR = 1, OCTREE_LEAF = 2 };

/* One node looked up by its name (hi * 2^64 + lo; names are decimal:
 * root 1, child 10 * parent + digit 1..8). */
typedef struct {
    int kind;            /* OCTREE_ABSENT (an empty voxel, or no such node), _INTERIOR, _LEAF */
    uint32_t count;      /* a leaf's candidates */
    const uint32_t *ids; /* [count] its primitive ids, ascending */
    uint32_t home;       /* name mod table size */
    uint32_t probes;     /* slots the lookup examined */
} octree_node_info;
octree_node_info octree_debug_node(const accel *a, uint64_t name_lo, uint32_t name_hi);

/* The tree and its table. */
typedef struct {
    uint32_t interior, leaves, empty; /* interior nodes, stored leaves, empty voxels (absent names) */
    int depth;                        /* deepest node (root 0) */
    float minlen;                     /* shortest voxel edge */
    box3 root;                        /* the box the root subdivides */
    uint32_t table_size, table_count; /* slots (a prime), stored names */
    double probes_avg;                /* mean slots examined to find a stored name */
    uint32_t probes_max;
    double probes_miss_avg;           /* mean slots examined for the name of an empty voxel */
} octree_info;
void octree_debug_info(const accel *a, octree_info *out);

/* Glassner's point location (by names from the root) of the point q, ties
 * on a mid plane going to the side dir points to (+ for 0): the name of
 * the voxel found and its depth. */
void octree_debug_locate(const accel *a, vec3 q, vec3 dir, uint64_t *name_lo, uint32_t *name_hi, int *depth);

/* How many times this context's walks fell back from Glassner's moved
 * point to a location by ray parameter, and to testing every primitive
 * (both counted since context_new). */
void octree_debug_fallbacks(const accel_ctx *ctx, uint64_t *relocated, uint64_t *exhaustive);

/* For testing the walks' safety nets only: replace Glassner's step beyond
 * a face (minlen/2) by half, and the walk's step cap (voxels entered
 * before every primitive is tested instead) by step_cap. */
void octree_debug_sabotage(accel *a, float half, uint64_t step_cap);

#ifdef __cplusplus
}
#endif

#endif
