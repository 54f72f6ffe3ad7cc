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
 * Who fills what: the implementation fills its static accel_ops and, in
 * build(), everything of its own object; accel_build() (registry.c), the
 * one way to build, checks the table's version, calls build() and then sets
 * the base's ops and scene. Nothing else sets them.
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
    /* Counts nothing: its work is not observable (Embree, CGAL), so the
     * CSV leaves the counters empty. */
    ACCEL_NO_COUNTERS = 1u << 2,
};

typedef struct accel accel;
typedef struct accel_ctx accel_ctx; /* per-thread scratch, opaque to the harness */

/* The newest interface version; tables of an older version end where it
 * did (their later methods are NULL and the harness does without them). */
#define ACCEL_OPS_VERSION 2

/* A named build statistic (version 2 stats()). The names an accelerator may
 * use are the shared accel_stat_names[] (registry.c) and its own table's
 * stat_names; the CSV has one fixed column stat_NAME for each name of
 * either kind (accel_stat_column) and the conformance suite refuses a name
 * reported but not declared. */
typedef struct { const char *name; double value; } accel_stat;
#define ACCEL_STATS_MAX 16
extern const char *const accel_stat_names[]; /* NULL-terminated */

/* What a cell of the accelerator costs, for planning shards (harness/run/
 * shard.c) and nothing else: rough weights relative to Embree's BVH, whose
 * trace is R log2 P and build P log2 P for R rays over P primitives. A
 * table that leaves a weight 0 gets ACCEL_COST_DEFAULT, twice Embree's:
 * planning is then rougher, never wrong (every cell still runs once). */
#define ACCEL_COST_DEFAULT 2.0
enum accel_cost_shape {
    /* A ray tests every primitive: trace is weight x R x P. */
    ACCEL_COST_TRACE_LINEAR = 1u << 0,
    /* The build is redone on every timed pass (a lazy build its reset
     * discards): build counts once per pass. */
    ACCEL_COST_BUILD_EACH_PASS = 1u << 1,
};
typedef struct {
    double trace, build; /* weights, Embree's BVH = 1; 0: ACCEL_COST_DEFAULT */
    unsigned shape;      /* enum accel_cost_shape */
} accel_cost;

struct accel_ops {
    int version; /* 1 or 2: which of the methods below exist */
    const char *name;    /* command-line name, e.g. "grid" */
    const char *summary; /* one line */
    const char *paper;   /* citation with section */
    const accel_param *params; /* parameter table (params.h), ends with PARAM_ROW_END */
    unsigned flags;      /* enum accel_flag */

    /* Build over a scene with resolved parameters (every table entry has a
     * value its row allows, and check() has passed them: read them with the
     * typed getters of params.h). Returns NULL with a one-line reason in err
     * on failure (a memory cap exceeded, a scene it cannot take). The scene
     * outlives the accel. */
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

    /* --- version 2 --- */

    /* Build statistics, owned by the accelerator: writes at most max of
     * them, returns how many; NULL when it has none. Names from
     * accel_stat_names[] (nodes, leaves, max_depth, ...); lazy_build_ms is
     * the time spent building while tracing since the last reset. */
    int (*stats)(const accel *a, accel_stat *out, int max);
    /* Return a self-mutating structure (move-to-front lists, a lazily built
     * classification) to its state right after build(), so that every
     * timed sample starts from the same state. NULL when tracing changes
     * nothing; an ACCEL_MUTATES accelerator must have it. */
    void (*reset)(accel *a);
    /* Bounds of everything the structure holds, so that an accelerator can
     * serve as a primitive of another (Kirk and Arvo's meta hierarchy,
     * survey s12). NULL: the scene's bounds. */
    box3 (*bounds)(const accel *a);
    /* The same queries with the counting compiled out, for the timed
     * samples (the warm-up counts through intersect and occluded). NULL:
     * the harness times the counting methods and says so in the CSV. */
    bool (*intersect_fast)(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit);
    bool (*occluded_fast)(accel *a, accel_ctx *ctx, const ray_t *ray);
    /* Parameter settings worth testing besides the defaults, "k=v,k=v"
     * each, NULL-terminated (or NULL): the conformance suite
     * (tests/test_accels.c) runs every one of them. */
    const char *const *variants;
    /* Whether this built instance's answers or counters depend on the
     * order its rays are traced in, when the table's flags do not say
     * ACCEL_MUTATES: a setting that keeps per-thread history (grid's rayid
     * and mtf), so that which rays each thread happened to trace before
     * changes the counters from run to run. NULL: never. The harness then
     * traces it on one thread, as a mutating one (accel_serial). */
    bool (*order_dependent)(const accel *a);
    /* Settle, before the parameters are written down (the CSV's params,
     * the cell key), values that depend on the machine alone and not on
     * the scene, so the row says what ran: `bvh`'s isa=auto becomes the
     * instruction set build() will pick on this CPU. Values it does not
     * know are left for build() to refuse. Appended after order_dependent
     * (tables are designated initializers, so every other one has NULL:
     * nothing to settle); the harness calls it through
     * accel_settle_params(). */
    void (*settle_params)(accel_params *params);
    /* Rules between parameters that no single row can state (bvh's
     * compress=on needs width=8): 0, or -1 with one line naming the
     * values. Each value has passed its row's check already; the harness
     * calls it when the options are parsed (accel_check_params), and
     * accel_build calls it before build(), so build() may rely on it. NULL:
     * no such rule. */
    int (*check)(const accel_params *params, char *err, size_t errlen);

    /* --- data, any version --- */

    /* What a cell costs, for shard planning; {0}: the stated defaults. */
    accel_cost cost;
    /* Statistics of its own beyond the shared accel_stat_names[] (NULL-
     * terminated, or NULL): each gets a CSV column stat_NAME after the
     * shared ones, in registry order. */
    const char *const *stat_names;
    /* The settings `accelbench tune` searches, in the instance grammar of
     * --accels: "KEY=V|V|V" (one main parameter, the values to try, the
     * default among them), or NULL: nothing to tune. Every value must pass
     * its row (tests/test_params.c checks each). */
    const char *tune;
};

/* The base of every accelerator object. */
struct accel {
    const struct accel_ops *ops;
    const scene_t *scene;
};

/* Registry (registry.c). */
extern const struct accel_ops *const accel_registry[];
const struct accel_ops *accel_find(const char *name);
/* The reference accelerator: the harness's judge of every other one's
 * answers (verify, the warm-up's check, the overhead benchmark's baseline). */
#define ACCEL_REFERENCE "embree"

/* Build ops over scene with resolved parameters: checks the table (version
 * 1..ACCEL_OPS_VERSION, the methods its version and flags require), builds
 * and sets the base's ops and scene. NULL with a one-line reason in err. */
accel *accel_build(const struct accel_ops *ops, const scene_t *scene, const accel_params *params, char *err,
                   size_t errlen);
/* ops's check() on params: 0 when it has none or it passes, else -1 with
 * its reason. */
int accel_check_params(const struct accel_ops *ops, const accel_params *params, char *err, size_t errlen);
/* ops's settle_params() on params, when it has one (nothing otherwise). */
void accel_settle_params(const struct accel_ops *ops, accel_params *params);
/* Whether a has a reset(), and a call of it when it has (tracing changes
 * nothing in the others). */
bool accel_resets(const accel *a);
void accel_reset(accel *a);
/* Whether a must be traced on one thread: ACCEL_MUTATES, or an instance
 * whose order_dependent() says so. */
bool accel_serial(const accel *a);
/* The accelerator's bounds (its bounds() or the scene's). */
box3 accel_bounds(const accel *a);
/* Its statistics (stats() or none), each checked against the names it may
 * use (accel_stat_known; an undeclared one is dropped with a warning). */
int accel_stats(const accel *a, accel_stat *out, int max);
/* Whether ops may report the statistic name: a shared one or its own. */
bool accel_stat_known(const struct accel_ops *ops, const char *name);
/* The i-th statistic with a CSV column: the shared names, then every
 * registered table's own in registry order (each name once); NULL past
 * the last. */
const char *accel_stat_column(int i);

#ifdef __cplusplus
}
#endif

#endif
