/* registry.c: the static table of accelerators, found by name, and
 * accel_build(), the one way to build one.
 * Adding an accelerator: write accel/NAME.c exporting `const struct
 * accel_ops accel_NAME` and add its line to accel/meson.build's
 * `accelerators` list, which reaches this file as ACCEL_TABLES
 * (X(accel_exhaustive) X(accel_embree) ...). */
#include <stdio.h>
#include <string.h>
#include "accel.h"

#ifndef ACCEL_TABLES
#error "ACCEL_TABLES comes from accel/meson.build's accelerators list"
#endif

#define X(table) extern const struct accel_ops table;
ACCEL_TABLES
#undef X

const struct accel_ops *const accel_registry[] = {
#define X(table) &table,
    ACCEL_TABLES
#undef X
    NULL,
};

const char *const accel_stat_names[] = {
    "nodes",          /* interior nodes, or cells of a grid */
    "leaves",         /* leaves, or non-empty cells */
    "empty_leaves",   /* leaves or cells that hold no primitive */
    "max_depth",      /* deepest leaf (root = 0) */
    "avg_leaf_prims", /* primitive references per non-empty leaf */
    "refs_per_prim",  /* references stored over primitives: duplication */
    "res_x", "res_y", "res_z", /* grid resolution */
    "lazy_build_ms",  /* time spent building while tracing, since the last reset */
    "hash_load",            /* nodes over buckets of a hashed structure (Glassner's octree) */
    "hash_probes_avg",      /* key compares to find a stored node, averaged over the nodes */
    "hash_probes_max",      /* the most compares any stored node takes */
    "hash_probes_miss_avg", /* compares to learn a name is absent (an empty voxel), averaged */
    "avg_children",         /* children per interior node of an n-ary tree (bvh-gs) */
    /* A tree's own prediction of the per-ray counters (bvh-gs: the survey's
     * eq. (3)); the CSV writes these two beside the measured counters, as
     * predicted_*_per_ray, not as stat_ columns (harness/csv.c). */
    "predicted_box_tests_per_ray",
    "predicted_tests_per_ray",
    NULL,
};

const struct accel_ops *accel_find(const char *name)
{
    for (int i = 0; accel_registry[i]; i++)
        if (strcmp(accel_registry[i]->name, name) == 0) return accel_registry[i];
    return NULL;
}

static bool known_stat(const char *name)
{
    for (int i = 0; accel_stat_names[i]; i++)
        if (strcmp(accel_stat_names[i], name) == 0) return true;
    return false;
}

accel *accel_build(const struct accel_ops *ops, const scene_t *scene, const accel_params *params, char *err,
                   size_t errlen)
{
    const char *missing = NULL;
    if (ops->version < 1 || ops->version > ACCEL_OPS_VERSION) {
        snprintf(err, errlen, "%s: interface version %d, this harness knows 1..%d", ops->name, ops->version,
                 ACCEL_OPS_VERSION);
        return NULL;
    }
    if (!ops->build || !ops->occluded || !ops->memory || !ops->destroy) missing = "build, occluded, memory and destroy";
    else if (!ops->intersect && !(ops->flags & ACCEL_SHADOW_ONLY)) missing = "intersect (it is not SHADOW_ONLY)";
    else if (ops->version >= 2 && (ops->flags & ACCEL_MUTATES) && !ops->reset) missing = "reset (it MUTATES)";
    if (missing) {
        snprintf(err, errlen, "%s: the method table lacks %s", ops->name, missing);
        return NULL;
    }
    if (accel_check_params(ops, params, err, errlen)) return NULL;
    accel *a = ops->build(scene, params, err, errlen);
    if (!a) return NULL;
    a->ops = ops;
    a->scene = scene;
    return a;
}

int accel_check_params(const struct accel_ops *ops, const accel_params *params, char *err, size_t errlen)
{
    return ops->version >= 2 && ops->check ? ops->check(params, err, errlen) : 0;
}

void accel_settle_params(const struct accel_ops *ops, accel_params *params)
{
    if (ops->version >= 2 && ops->settle_params) ops->settle_params(params);
}

bool accel_resets(const accel *a) { return a->ops->version >= 2 && a->ops->reset; }

bool accel_serial(const accel *a)
{
    return (a->ops->flags & ACCEL_MUTATES) || (a->ops->version >= 2 && a->ops->order_dependent && a->ops->order_dependent(a));
}

void accel_reset(accel *a)
{
    if (accel_resets(a)) a->ops->reset(a);
}

box3 accel_bounds(const accel *a)
{
    return a->ops->version >= 2 && a->ops->bounds ? a->ops->bounds(a) : a->scene->bounds;
}

int accel_stats(const accel *a, accel_stat *out, int max)
{
    if (a->ops->version < 2 || !a->ops->stats) return 0;
    int n = a->ops->stats(a, out, max), kept = 0;
    if (n > max) n = max;
    /* A name the CSV has no column for is dropped, loudly (the conformance
     * suite fails on it). */
    for (int i = 0; i < n; i++)
        if (known_stat(out[i].name)) out[kept++] = out[i];
        else fprintf(stderr, "accelbench: warning: %s reports the statistic '%s', which accel_stat_names[] does not list\n",
                     a->ops->name, out[i].name);
    return kept;
}
