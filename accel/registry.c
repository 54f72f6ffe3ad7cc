/* registry.c: finding the registered accelerators by name, the shared
 * statistic names, and accel_build(), the one way to build one. The table
 * itself (accel_registry[]) is registry_table.c's, made from accel/
 * meson.build's `accelerators` list; a program that registers one more
 * (tests/meson.build's worked example) links a table of its own instead.
 * Adding an accelerator: write its file exporting `const struct accel_ops
 * accel_NAME` and add its line to that list. */
#include <stdio.h>
#include <string.h>
#include "accel.h"

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
     * eq. (3); bvh: the surface-area argument); the CSV writes these three
     * beside the measured counters, as predicted_*_per_ray, not as stat_
     * columns (harness/csv.c). */
    "predicted_box_tests_per_ray",
    "predicted_tests_per_ray",
    "predicted_steps_per_ray",
    NULL,
};

const struct accel_ops *accel_find(const char *name)
{
    for (int i = 0; accel_registry[i]; i++)
        if (strcmp(accel_registry[i]->name, name) == 0) return accel_registry[i];
    return NULL;
}

static bool listed(const char *const *names, const char *name)
{
    for (int i = 0; names && names[i]; i++)
        if (strcmp(names[i], name) == 0) return true;
    return false;
}

bool accel_stat_known(const struct accel_ops *ops, const char *name)
{
    return listed(accel_stat_names, name) || listed(ops->stat_names, name);
}

/* Whether the own statistic at s of accel_registry[r] has a column
 * already: a shared name, or an own one of an earlier table or earlier in
 * the same list (so each column appears once). */
static bool column_before(int r, const char *const *s)
{
    if (listed(accel_stat_names, *s)) return true;
    for (int q = 0; q < r; q++)
        if (listed(accel_registry[q]->stat_names, *s)) return true;
    for (const char *const *e = accel_registry[r]->stat_names; e < s; e++)
        if (strcmp(*e, *s) == 0) return true;
    return false;
}

const char *accel_stat_column(int i)
{
    int n = 0;
    while (accel_stat_names[n]) n++;
    if (i < n) return accel_stat_names[i];
    for (int r = 0; accel_registry[r]; r++)
        for (const char *const *s = accel_registry[r]->stat_names; s && *s; s++)
            if (!column_before(r, s) && n++ == i) return *s;
    return NULL;
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
        if (accel_stat_known(a->ops, out[i].name)) out[kept++] = out[i];
        else fprintf(stderr, "accelbench: warning: %s reports the statistic '%s', which neither accel_stat_names[] nor its "
                     "table's stat_names declares\n", a->ops->name, out[i].name);
    return kept;
}
