/* accel.h: the accelerator interface.
 *
 * An accelerator is a table of methods (struct accel_ops), in the manner of
 * SQLite's sqlite3_io_methods: the harness finds it by name in the static
 * registry (registry.c), builds it over a scene with named parameters, gives
 * each tracing thread its own context, and asks closest-hit and any-hit
 * questions. Methods are only ever appended; `version` says which exist.
 *
 * An implementation "subclasses" struct accel by putting it first in its own
 * struct and casting. It reaches primitives only through prims/prims.h.
 *
 * Counters: implementations bump box_tests (every ray/box, node, voxel or
 * ray-box crossing test), steps (every node popped or voxel entered),
 * empty_leaves (leaves or voxels entered that hold no primitive) and
 * mailbox_hits (a primitive skipped because this ray already tested it);
 * prims/ bumps prim_tests and prim_hits.
 */
#ifndef ACCELBENCH_ACCEL_H
#define ACCELBENCH_ACCEL_H

#include <stdbool.h>
#include <stddef.h>
#include "../prims/prims.h"
#include "../scenes/scene.h"
#include "params.h"

#ifdef __cplusplus
extern "C" {
#endif

enum accel_flag {
    /* Reorders its own data while tracing (Woo's move-to-front, lazy ray
     * classification). Not thread-safe: the harness traces it on one
     * thread, and says so in the CSV. */
    ACCEL_MUTATES = 1u << 0,
    /* Answers occluded() only (Haines-Greenberg light buffer: one structure
     * per light, chosen by ray->light, which the shadow workload sets on
     * every ray); intersect is NULL. The harness runs it on shadow
     * workloads only. */
    ACCEL_SHADOW_ONLY = 1u << 1,
    /* Counters are not observable (Embree): the CSV leaves them empty. */
    ACCEL_OPAQUE = 1u << 2,
};

typedef struct accel accel;
typedef struct accel_ctx accel_ctx; /* per-thread scratch, opaque to the harness */

struct accel_ops {
    int version; /* 1 */
    const char *name;    /* command-line name, e.g. "grid" */
    const char *summary; /* one line */
    const char *paper;   /* citation with section */
    const accel_param *params; /* parameter table, ends with a {NULL} entry */
    unsigned flags;      /* enum accel_flag */

    /* Build over a scene with resolved parameters (every table entry has a
     * value). Returns NULL with a one-line reason in err on failure (a bad
     * parameter value, a memory cap exceeded). The scene outlives the accel. */
    accel *(*build)(const scene_t *scene, const accel_params *params, char *err, size_t errlen);

    /* Per-thread context: mailboxes, stacks, heaps, ray ids. May be NULL,
     * in which case every thread gets a NULL context. */
    accel_ctx *(*context_new)(accel *a);
    void (*context_free)(accel_ctx *ctx);

    /* Closest hit in [ray->tnear, ray->tfar). hit starts as hit_none(ray);
     * on return hit->prim is the primitive id or HIT_NONE. Returns whether
     * it hit. */
    bool (*intersect)(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c);
    /* Any hit in [ray->tnear, ray->tfar). */
    bool (*occluded)(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c);

    /* Bytes held by the structure, not counting the scene's primitives. */
    size_t (*memory)(const accel *a);
    void (*destroy)(accel *a);
};

/* The base of every accelerator object. */
struct accel {
    const struct accel_ops *ops;
    const scene_t *scene;
};

/* Registry (registry.c). */
extern const struct accel_ops *const accel_registry[];
const struct accel_ops *accel_find(const char *name);

#ifdef __cplusplus
}
#endif

#endif
