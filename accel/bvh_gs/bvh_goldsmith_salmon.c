/* bvh_goldsmith_salmon.c: `bvh-gs`, Goldsmith and Salmon's automatic
 * hierarchy with its cost estimate. Reference: docs/accels/goldsmith-salmon.md.
 *
 * Papers:
 *   J. Goldsmith, J. Salmon, "Automatic Creation of Object Hierarchies for
 *     Ray Tracing", IEEE CG&A 7(5), 1987, as the Arvo-Kirk survey (1989)
 *     describes it: s4.2 (eq. (2) area ratios, eq. (3) the tree's cost),
 *     s4.3 (insertion by least surface-area increase, ties searched;
 *     given, sorted or shuffled insertion orders), s4.1 and figures 3-4
 *     (the traversal). The builder's placements and their costs are in
 *     accel/bvh_gs/build_gs.c with the retellings they come from.
 *
 * This file: the insertion orders (given | sorted along the longest axis |
 * seeded Fisher-Yates shuffles, K of them keeping the tree of least eq. (3)
 * cost; shuffle k is seeded with the k-th splitmix64 number from --seed, so
 * K trees include the one K = 1 builds), the accel_ops table and the
 * statistics. Building is accel/bvh_gs/build_gs.c, the layout, cost model and
 * traversals accel/bvh_gs/nary.h.
 *
 * Node: nary_node, 32 bytes: box, then first child and child count
 * (interior) or primitive id (leaf); breadth-first, each node's children
 * one contiguous run; every primitive a leaf of its own. memory() = the
 * struct + 32 bytes a node. Per thread: the stack, 8 bytes x stack_need.
 *
 * Invariants: maxchildren=0 leaves the branching factor unbounded (the
 * S(A) k(A) term of the cost keeps nodes narrow); a bound only forbids the
 * "one more child" placement at a full node. K > 1 shuffles with another
 * order is refused. The builder's bytes are estimated before building and
 * refused past memcap.
 *
 * Statistics: nodes, leaves, max_depth, avg_leaf_prims (1), refs_per_prim
 * (1), avg_children, and eq. (3)'s prediction per ray that hits the root,
 * predicted_box_tests_per_ray and predicted_tests_per_ray, with
 * predicted_steps_per_ray by the same probabilities (random lines
 * that hit the root box; eye and shadow rays from one point depart from
 * it). Counters (nary.h): box_tests, steps; prims/ counts the rest.
 *
 * Not implemented: bounding spheres, the paper's own test weights (every
 * test costs 1), parallel builds of the K shuffles. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../accel.h"
#include "nary.h"
#include "../common/coincident.h"
#include "../common/memcap.h"
#include "../common/shuffle.h"
#include "../../prims/checked_alloc.h"

enum { ORDER_GIVEN = 0, ORDER_SORTED = 1, ORDER_SHUFFLE = 2 };
enum { TRAV_STORED = 0, TRAV_NEAREST = 1 };

static const accel_param gs_params[] = {
    PARAM_ROW_CHOICE("order", "shuffle", "given|sorted|shuffle",
                     "insertion order: given (the scene's), sorted (centroids along the longest axis), shuffle (seeded by --seed)"),
    PARAM_ROW_INT("shuffles", "1", 1, 1024, "order=shuffle: K trees from K seeded shuffles, the one of least eq. (3) cost kept"),
    PARAM_ROW_INT("maxchildren", "0", 0, 65536, "children per node at most: 0 = no bound (the paper), else at least 2"),
    PARAM_ROW_CHOICE("traverse", "stored", "stored|nearest",
                     "stored (survey fig. 3, stored order), nearest (primitives, then boxes by entry distance)"),
    PARAM_ROW_END,
};

typedef struct {
    accel base;
    const prims_t *p;
    nary_t tree;
    int traverse;
} gs_accel;

struct accel_ctx {
    nary_scratch s;
};

/* ---------------------------------------------------------------- build */

typedef struct {
    float key;
    uint32_t id;
} sort_key;

static int by_key(const void *a, const void *b)
{
    const sort_key *x = a, *y = b;
    if (x->key != y->key) return x->key < y->key ? -1 : 1;
    return (x->id > y->id) - (x->id < y->id); /* equal keys: id order, so the sort is deterministic */
}

/* ids sorted by centroid along the longest axis of the scene box. 0, or
 * -1 out of memory. */
static int sort_along_line(const prims_t *p, uint32_t *ids)
{
    vec3 e = box_extent(p->box);
    int axis = e.x >= e.y && e.x >= e.z ? 0 : e.y >= e.z ? 1 : 2;
    sort_key *k = malloc(((size_t)p->count + 1) * sizeof *k);
    if (!k) return -1;
    for (uint32_t i = 0; i < p->count; i++) k[i] = (sort_key){v3_get(box_center(p->bounds[i]), axis), i};
    qsort(k, p->count, sizeof *k, by_key);
    for (uint32_t i = 0; i < p->count; i++) ids[i] = k[i].id;
    free(k);
    return 0;
}

static double predicted_total(const nary_t *t)
{
    nary_prediction pr = nary_predict(t);
    return pr.box_tests + pr.prim_tests;
}

static void gs_destroy(accel *a)
{
    gs_accel *g = (gs_accel *)a;
    if (!g) return;
    nary_free(&g->tree);
    free(g);
}

/* maxchildren=1 leaves no room for two children; several trees need
 * several shuffles. */
static int gs_check(const accel_params *params, char *err, size_t errlen)
{
    long shuffles = params_int(params, "shuffles");
    if (params_int(params, "maxchildren") == 1) {
        snprintf(err, errlen, "maxchildren=1: a node needs room for two children (0 = no bound, or 2..65536)");
        return -1;
    }
    if (shuffles > 1 && params_choice(params, "order") != ORDER_SHUFFLE) {
        snprintf(err, errlen, "shuffles=%ld: several trees come from several shuffles, so it needs order=shuffle", shuffles);
        return -1;
    }
    return 0;
}

static accel *gs_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    int order = params_choice(params, "order"), trav = params_choice(params, "traverse");
    long shuffles = params_int(params, "shuffles"), maxchildren = params_int(params, "maxchildren");
    uint64_t memcap = params_memcap(params, 4096);
    const prims_t *p = &scene->prims;
    uint32_t n = p->count;
    /* The build, a second tree kept while another is built, and the order. */
    uint64_t bytes = memcap_add(nary_build_gs_bytes(n), memcap_mul(shuffles > 1 ? 2 * (uint64_t)n : 0, sizeof(nary_node)));
    bytes = memcap_add(bytes, memcap_mul(n, sizeof(uint32_t) + sizeof(sort_key)));
    if (memcap_exceeded(bytes, memcap, err, errlen, "bvh-gs over %u primitives:", n)) return NULL;

    /* Coincident primitives join their first copy instead of searching (build_gs.c). */
    prim_classes pc = {NULL, n};
    gs_accel *g = calloc(1, sizeof *g);
    uint32_t *ids = malloc(((size_t)n + 1) * sizeof *ids);
    if (!g || !ids || prim_classes_init(&pc, p)) goto oom;
    g->p = p;
    g->traverse = trav;
    nary_gs_config cfg = {.max_children = (uint32_t)maxchildren, .ties_first_only = false, .rep = pc.rep};
    if (order != ORDER_SHUFFLE) {
        for (uint32_t i = 0; i < n; i++) ids[i] = i;
        if (order == ORDER_SORTED && sort_along_line(p, ids)) goto oom;
        if (nary_build_gs(&g->tree, p->bounds, ids, n, &cfg)) goto oom;
    } else {
        double best = 0.0;
        uint64_t stream = params->seed;
        for (long k = 0; k < shuffles; k++) {
            uint64_t seed = splitmix64_next(&stream);
            for (uint32_t i = 0; i < n; i++) ids[i] = i;
            shuffle_ids(ids, n, seed);
            nary_t t;
            if (nary_build_gs(&t, p->bounds, ids, n, &cfg)) goto oom;
            double cost = predicted_total(&t);
            if (k == 0 || cost < best) { /* the first of equal costs stays */
                nary_free(&g->tree);
                g->tree = t;
                best = cost;
            } else {
                nary_free(&t);
            }
        }
    }
    free(ids);
    prim_classes_free(&pc);
    return &g->base;
oom:
    free(ids);
    prim_classes_free(&pc);
    if (g) gs_destroy(&g->base);
    snprintf(err, errlen, "out of memory building bvh-gs over %u primitives", n);
    return NULL;
}

/* -------------------------------------------------------------- context */

static accel_ctx *gs_context_new(accel *a)
{
    const gs_accel *g = (const gs_accel *)a;
    /* context_new cannot fail through the interface: out of memory is exit 2 (prims/checked_alloc.h) */
    accel_ctx *ctx = checked_calloc(1, sizeof *ctx, "a bvh-gs tracing context");
    if (nary_scratch_init(&ctx->s, &g->tree))
        checked_alloc_failed((uint64_t)g->tree.stack_need * sizeof(tstack_entry), "a bvh-gs thread's traversal stack");
    return ctx;
}

static void gs_context_free(accel_ctx *ctx)
{
    if (!ctx) return;
    nary_scratch_free(&ctx->s);
    free(ctx);
}

/* ---------------------------------------------------------------- trace */

static bool gs_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    const gs_accel *g = (const gs_accel *)a;
    nary_scratch *s = ctx ? &ctx->s : NULL;
    return g->traverse == TRAV_NEAREST ? nary_intersect_nearest(&g->tree, g->p, s, ray, hit, c)
                                       : nary_intersect_stored(&g->tree, g->p, s, ray, hit, c);
}

static bool gs_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    const gs_accel *g = (const gs_accel *)a;
    nary_scratch *s = ctx ? &ctx->s : NULL;
    return g->traverse == TRAV_NEAREST ? nary_occluded_nearest(&g->tree, g->p, s, ray, c)
                                       : nary_occluded_stored(&g->tree, g->p, s, ray, c);
}

static bool gs_intersect_fast(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit)
{
    const gs_accel *g = (const gs_accel *)a;
    nary_scratch *s = ctx ? &ctx->s : NULL;
    return g->traverse == TRAV_NEAREST ? nary_intersect_nearest_fast(&g->tree, g->p, s, ray, hit)
                                       : nary_intersect_stored_fast(&g->tree, g->p, s, ray, hit);
}

static bool gs_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *ray)
{
    const gs_accel *g = (const gs_accel *)a;
    nary_scratch *s = ctx ? &ctx->s : NULL;
    return g->traverse == TRAV_NEAREST ? nary_occluded_nearest_fast(&g->tree, g->p, s, ray)
                                       : nary_occluded_stored_fast(&g->tree, g->p, s, ray);
}

/* ------------------------------------------------------------ the rest */

static size_t gs_memory(const accel *a)
{
    const gs_accel *g = (const gs_accel *)a;
    return sizeof *g + nary_memory(&g->tree);
}

static int gs_stats(const accel *a, accel_stat *out, int max)
{
    const gs_accel *g = (const gs_accel *)a;
    return nary_stats(&g->tree, g->p->count, out, max);
}

static box3 gs_bounds(const accel *a) { return nary_bounds(&((const gs_accel *)a)->tree); }

/* Every order and traversal, several shuffles, bounded widths. */
static const char *const gs_variants[] = {
    "traverse=nearest",
    "order=given",
    "order=sorted,traverse=nearest",
    "shuffles=4",
    "maxchildren=2",
    "maxchildren=3,traverse=nearest,order=given",
    NULL,
};

const struct accel_ops accel_bvh_gs = {
    .version = 2,
    .name = "bvh-gs",
    .summary = "Goldsmith-Salmon automatic n-ary BVH: insertion by least area increase, ties searched, "
               "given/sorted/shuffled orders, eq. (3) cost predicted",
    .paper = "Goldsmith & Salmon, IEEE CG&A 7(5) 1987; Arvo & Kirk 1989 survey s4.1-4.3, eq. (3), figs. 3-4",
    .params = gs_params,
    .flags = 0,
    .build = gs_build,
    .context_new = gs_context_new,
    .context_free = gs_context_free,
    .intersect = gs_intersect,
    .occluded = gs_occluded,
    .memory = gs_memory,
    .destroy = gs_destroy,
    .stats = gs_stats,
    .reset = NULL,
    .bounds = gs_bounds,
    .intersect_fast = gs_intersect_fast,
    .occluded_fast = gs_occluded_fast,
    .variants = gs_variants,
    .check = gs_check,
    .cost = {2, 8, 0},
};
