/* slabs_kay_kajiya.c: `slabs-kk`, Kay and Kajiya's hierarchy of plane-set
 * volumes with heap-ordered traversal. Reference: docs/accels/kay-kajiya.md.
 *
 * Paper: T. L. Kay, J. T. Kajiya, "Ray Tracing Complex Scenes", SIGGRAPH
 * '86, as the Arvo-Kirk survey (1989) describes it in s4 (the distance
 * interval, figure 4), s4.3-4.4 (plane sets, slabs, nested volumes) and
 * figure 9 (Hull_Sort_Intersect):
 *   - a volume is the intersection of slabs over a FIXED set of normals
 *     (3: the axes; 7: axes and cube diagonals), so the ray's part of each
 *     slab test is computed once per ray (accel/slabs_kk/planeset.h);
 *   - an object's slab is the range of N . x over it (prims/ prim_extent);
 *     a parent's slab spans its children's (s4.4);
 *   - the heap walk keeps the volumes the ray meets keyed by entry
 *     distance, expands the nearest, and stops when it lies beyond the
 *     closest hit (figure 9).
 * The tree's shape comes from the BVH kit over the primitives' boxes
 * (median | gs | sah); only its volumes are Kay and Kajiya's.
 *
 * Nodes: binary, slab[k] = {lo, hi} per normal, then index and count: 32
 * bytes with 3 normals, 64 with 7 (one cache line, 64-byte aligned array).
 * count == 0: interior, children nodes[index], nodes[index + 1]; else a
 * leaf of refs[index .. index + count). Depth-first, siblings adjacent.
 * memory(): the object, 2 leaves - 1 nodes, 4 bytes a primitive of refs.
 * Per thread (bvh_scratch): the stack (8 bytes a level) and the heap
 * (8 bytes an entry, grown by doubling).
 *
 * Invariants: every slab test is conservative (never rejects a volume the
 * ray meets); children come after their parent; each primitive is in
 * exactly one leaf. If the heap cannot grow, the walk finishes by testing
 * every leaf whose volume the ray meets, so the answer stays exact.
 *
 * Counters: box_tests = volumes tested (root once, both children of each
 * node expanded); steps = nodes expanded (a candidate dropped by the stop
 * rule is not one); no empty leaves, no mailboxes. The walks are
 * accel/bvh/walk.h's, compiled per normal count; intersect_fast /
 * occluded_fast are the same walks without counters.
 *
 * Not implemented: Kay and Kajiya's own cut axis and arbitrary branching
 * factor (the kit's trees are binary), per-object choice of normals. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../accel.h"
#include "slabs_kay_kajiya.h"
#include "../bvh/walk.h"
#include "../common/coincident.h"
#include "../common/memcap.h"
#include "planeset.h"
#include "../../prims/checked_alloc.h"

enum { TREE_MEDIAN = 0, TREE_GS = 1, TREE_SAH = 2 };
enum { TRAV_HEAP = 0, TRAV_DFS = 1 };

#define KK_MAX_LEAF 16
#define BODY static inline __attribute__((always_inline))

static const accel_param kk_params[] = {
    PARAM_ROW_CHOICE("normals", "7", "3|7", "plane-set normals: 3 (the axes: AABBs), 7 (axes and cube diagonals, Kay-Kajiya)"),
    PARAM_ROW_CHOICE("tree", "median", "median|gs|sah", "hierarchy: median (median cuts, Kay-Kajiya), gs (Goldsmith-Salmon insertion), sah"),
    PARAM_ROW_CHOICE("traverse", "heap", "heap|dfs", "heap (by entry distance, Kay-Kajiya figure 9), dfs (depth-first, nearer child first)"),
    PARAM_ROW_INT("maxleaf", "1", 1, KK_MAX_LEAF, "primitives per leaf, median and sah (1: every object its own volume)"),
    PARAM_ROW_END,
};

/* The two node layouts, one per normal count (sizes in the file header). */
typedef struct {
    planeset_slab slab[3]; /* 24 bytes: lo, hi along the axes */
    uint32_t index;        /* interior: left child (right = index + 1); leaf: first entry of refs */
    uint32_t count;        /* 0: interior; else primitives in the leaf */
} kk_node3;
_Static_assert(sizeof(kk_node3) == 32, "kk_node3 is 32 bytes: two to a cache line");

typedef struct {
    planeset_slab slab[7]; /* 56 bytes: lo, hi along the axes and the diagonals */
    uint32_t index, count; /* as kk_node3 */
} kk_node7;
_Static_assert(sizeof(kk_node7) == 64, "kk_node7 is 64 bytes: one cache line");

typedef struct {
    accel base;
    const prims_t *p;
    uint32_t normals; /* 3 or 7 */
    int traverse;
    union {
        kk_node3 *n3;
        kk_node7 *n7;
        void *any;
    } nodes;
    /* The kit's tree with its box nodes freed (nodes == NULL): its refs,
     * nnodes, nleaves and max_depth describe this tree, which has the same
     * node count and leaves, for bvh_stats and bvh_scratch_init. */
    bvh_t topo;
} kk_t;

struct accel_ctx {
    bvh_scratch s;
};

/* Node i's fields in either layout; K is t->normals, a constant in the
 * walks (so each walk reads one layout with no test). */
#define NODE(t, i, K, field) ((K) == 3 ? (t)->nodes.n3[i].field : (t)->nodes.n7[i].field)
BODY planeset_slab *node_slab(const kk_t *t, uint32_t i, const uint32_t K) { return NODE(t, i, K, slab); }
BODY uint32_t node_index(const kk_t *t, uint32_t i, const uint32_t K) { return NODE(t, i, K, index); }
BODY uint32_t node_count(const kk_t *t, uint32_t i, const uint32_t K) { return NODE(t, i, K, count); }
static void node_set(kk_t *t, uint32_t i, uint32_t index, uint32_t count)
{
    if (t->normals == 3) t->nodes.n3[i].index = index, t->nodes.n3[i].count = count;
    else t->nodes.n7[i].index = index, t->nodes.n7[i].count = count;
}

/* ---------------------------------------------------------------- build */

static void kk_destroy(accel *a)
{
    kk_t *t = (kk_t *)a;
    if (!t) return;
    free(t->nodes.any);
    bvh_free(&t->topo);
    free(t);
}

static size_t node_bytes(uint32_t normals) { return normals == 3 ? sizeof(kk_node3) : sizeof(kk_node7); }

/* Grow volume v by volume w over K normals (s4.4: min of the los, max of
 * the his). */
static void slab_union(planeset_slab *v, const planeset_slab *w, uint32_t K)
{
    for (uint32_t k = 0; k < K; k++) {
        if (w[k][0] < v[k][0]) v[k][0] = w[k][0];
        if (w[k][1] > v[k][1]) v[k][1] = w[k][1];
    }
}

static void slab_clear(planeset_slab *v, uint32_t K)
{
    for (uint32_t k = 0; k < K; k++) v[k][0] = INFINITY, v[k][1] = -INFINITY;
}

/* Copy the kit's tree into this layout, depth-first with the two children
 * of a node allocated together when it is reached (so children come after
 * their parent, which the insertion builder's array does not promise),
 * then compute every volume bottom-up: a leaf's from its primitives'
 * extents, an interior node's from its two children. */
static int convert(kk_t *t, const planeset_slab *ext)
{
    const bvh_t *b = &t->topo;
    const uint32_t K = t->normals;
    size_t bytes = (size_t)b->nnodes * node_bytes(K);
    t->nodes.any = aligned_alloc(64, (bytes + 63) / 64 * 64);
    uint32_t *stack = malloc(2 * (size_t)b->nnodes * sizeof *stack); /* (old, new) pairs, at most nnodes pending */
    if (!t->nodes.any || !stack) {
        free(stack);
        return -1;
    }
    uint32_t sp = 0, next = 1;
    stack[sp++] = 0, stack[sp++] = 0;
    while (sp) {
        uint32_t w = stack[--sp], o = stack[--sp];
        const bvh_node *bn = &b->nodes[o];
        if (bn->count) {
            node_set(t, w, bn->index, bn->count);
            continue;
        }
        uint32_t c = next;
        next += 2;
        node_set(t, w, c, 0);
        stack[sp++] = bn->index + 1, stack[sp++] = c + 1;
        stack[sp++] = bn->index, stack[sp++] = c;
    }
    free(stack);
    for (uint32_t w = b->nnodes; w-- > 0;) {
        planeset_slab *v = node_slab(t, w, K);
        uint32_t index = node_index(t, w, K), count = node_count(t, w, K);
        slab_clear(v, K);
        if (count) {
            for (uint32_t i = 0; i < count; i++) slab_union(v, ext + (size_t)b->refs[index + i] * K, K);
        } else {
            slab_union(v, node_slab(t, index, K), K);
            slab_union(v, node_slab(t, index + 1, K), K);
        }
    }
    return 0;
}

/* What a build allocates at its peak, for memcap: the nodes and refs kept,
 * and the scratch (boxes, extents, the kit's tree and its builders' task
 * and centroid arrays, the renumbering stack). */
static uint64_t build_bytes(uint64_t n, uint32_t normals)
{
    uint64_t nodes = n ? 2 * n - 1 : 0;
    uint64_t b = memcap_mul(nodes, node_bytes(normals) + sizeof(bvh_node) + 2 * sizeof(uint32_t));
    uint64_t per_prim = sizeof(uint32_t) + sizeof(box3) + (uint64_t)normals * sizeof(planeset_slab) + 2 * sizeof(vec3) +
                        BVH_TOPDOWN_TASK_BYTES;
    return memcap_add(b, memcap_mul(n, per_prim));
}

static accel *kk_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    int nset = params_choice(params, "normals"), tree = params_choice(params, "tree"), trav = params_choice(params, "traverse");
    long maxleaf = params_int(params, "maxleaf");
    uint64_t memcap = params_memcap(params, 4096);
    const prims_t *p = &scene->prims;
    const uint32_t K = nset == 0 ? 3 : 7, n = p->count;
    if (memcap_exceeded(build_bytes(n, K), memcap, err, errlen,
                        "the slabs-kk nodes and build scratch over %u primitives", n))
        return NULL;

    kk_t *t = calloc(1, sizeof *t);
    box3 *boxes = malloc(((size_t)n + 1) * sizeof *boxes);
    planeset_slab *ext = malloc(((size_t)n * K + 1) * sizeof *ext);
    if (!t || !boxes || !ext) goto oom;
    t->base.scene = scene;
    t->p = p;
    t->normals = K;
    t->traverse = trav;

    /* Every primitive's box (for the builders) and extents (for the volumes). */
    for (uint32_t id = 0; id < n; id++) {
        boxes[id] = prim_bounds(p, id);
        for (uint32_t k = 0; k < K; k++) {
            const float *nk = planeset_normals[k];
            planeset_slab *e = &ext[(size_t)id * K + k];
            if (!prim_extent(p, id, v3(nk[0], nk[1], nk[2]), &(*e)[0], &(*e)[1])) {
                snprintf(err, errlen, "slabs-kk: no extent for primitive %u", id);
                goto fail;
            }
        }
    }
    bvh_config cfg;
    bvh_config_defaults(&cfg);
    cfg.max_leaf = (uint32_t)maxleaf;
    /* tree=gs: copies of a primitive go next to it (accel/bvh/build_insert.c, common/coincident.h). */
    prim_classes pc = {NULL, n};
    if (tree == TREE_GS && prim_classes_init(&pc, p)) goto oom;
    cfg.insert_rep = pc.rep;
    int rc = tree == TREE_MEDIAN ? bvh_build_median(&t->topo, boxes, NULL, n, &cfg)
             : tree == TREE_GS   ? bvh_build_insert(&t->topo, boxes, NULL, n, &cfg)
                                 : bvh_build_sah(&t->topo, boxes, NULL, n, &cfg);
    prim_classes_free(&pc);
    if (rc || (t->topo.nnodes && convert(t, ext))) goto oom;
    free(t->topo.nodes);
    t->topo.nodes = NULL;
    free(boxes);
    free(ext);
    return &t->base;
oom:
    snprintf(err, errlen, "slabs-kk: out of memory building over %u primitives", n);
fail:
    free(boxes);
    free(ext);
    kk_destroy(t ? &t->base : NULL);
    return NULL;
}

/* -------------------------------------------------------------- context */

static accel_ctx *kk_context_new(accel *a)
{
    kk_t *t = (kk_t *)a;
    /* context_new cannot fail through the interface: out of memory is exit 2 (prims/checked_alloc.h) */
    accel_ctx *ctx = checked_calloc(1, sizeof *ctx, "a slabs-kk tracing context");
    if (bvh_scratch_init(&ctx->s, &t->topo))
        checked_alloc_failed(((uint64_t)t->topo.max_depth + 1) * 24, "a slabs-kk thread's stack and heap");
    return ctx;
}

static void kk_context_free(accel_ctx *ctx)
{
    if (!ctx) return;
    bvh_scratch_free(&ctx->s);
    free(ctx);
}

/* ---------------------------------------------------------------- trace */

/* The layout's two callbacks of the kit's walks (accel/bvh/walk.h), one
 * pair per normal count, so that the slab loop has a constant length. */
BODY bool clip3(const void *tree, const void *ray, uint32_t i, float *t0, float *t1)
{
    return planeset_clip((const planeset_ray *)ray, ((const kk_t *)tree)->nodes.n3[i].slab, 3, t0, t1);
}
BODY bool clip7(const void *tree, const void *ray, uint32_t i, float *t0, float *t1)
{
    return planeset_clip((const planeset_ray *)ray, ((const kk_t *)tree)->nodes.n7[i].slab, 7, t0, t1);
}
BODY void node3(const void *tree, uint32_t i, uint32_t *index, uint32_t *count)
{
    const kk_node3 *n = &((const kk_t *)tree)->nodes.n3[i];
    *index = n->index, *count = n->count;
}
BODY void node7(const void *tree, uint32_t i, uint32_t *index, uint32_t *count)
{
    const kk_node7 *n = &((const kk_t *)tree)->nodes.n7[i];
    *index = n->index, *count = n->count;
}

/* One query: the per-ray constants once (false at once for a ray nothing
 * can hit), then the walk; the traversal and the normal count are chosen at
 * run time, `shadow` and `counting` are constants, so each of the eight
 * walks is compiled on its own. */
BODY bool trace(const kk_t *t, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c, bvh_walk_log *log,
                const bool shadow, const bool counting)
{
    planeset_ray r;
    if (!t->topo.nnodes || !planeset_ray_init(&r, t->normals, ray->org, ray->dir)) return false;
    const bvh_walk w = {t, &r, t->topo.nnodes, t->topo.max_depth, t->topo.refs, t->p};
    bvh_scratch *s = &ctx->s;
    if (t->normals == 3)
        return t->traverse == TRAV_HEAP ? bvh_walk_heap(&w, clip3, node3, s, ray, hit, c, log, shadow, counting)
                                        : bvh_walk_dfs(&w, clip3, node3, s, ray, hit, c, log, shadow, counting);
    return t->traverse == TRAV_HEAP ? bvh_walk_heap(&w, clip7, node7, s, ray, hit, c, log, shadow, counting)
                                    : bvh_walk_dfs(&w, clip7, node7, s, ray, hit, c, log, shadow, counting);
}

static bool kk_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    return trace((const kk_t *)a, ctx, ray, hit, c, NULL, false, true);
}

static bool kk_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    return trace((const kk_t *)a, ctx, ray, NULL, c, NULL, true, true);
}

static bool kk_intersect_fast(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit)
{
    return trace((const kk_t *)a, ctx, ray, hit, NULL, NULL, false, false);
}

static bool kk_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *ray)
{
    return trace((const kk_t *)a, ctx, ray, NULL, NULL, NULL, true, false);
}

/* ------------------------------------------------------------ the rest */

static size_t kk_memory(const accel *a)
{
    const kk_t *t = (const kk_t *)a;
    return sizeof *t + (size_t)t->topo.nnodes * node_bytes(t->normals) + (size_t)t->topo.nrefs * sizeof(uint32_t);
}

/* The surface-area model (the survey's eq. (3), MacDonald and Booth) over
 * the plane-set volumes, for lines uniform over those that meet the root
 * volume, walked whole (nothing hit): every node whose volume a line meets
 * is expanded (a step), an interior one tests its two children's volumes,
 * a leaf its primitives; plus the root's own test. P(node) = area(node) /
 * area(root) with each volume's own polytope area (planeset_area). */
static void kk_predict(const kk_t *t, double *steps, double *box_tests, double *tests)
{
    const uint32_t K = t->normals;
    *steps = *tests = 0.0;
    *box_tests = 1.0;
    if (!t->topo.nnodes) return;
    const double root = planeset_area(node_slab(t, 0, K), K);
    for (uint32_t i = 0; i < t->topo.nnodes; i++) {
        const double p = root > 0.0 ? planeset_area(node_slab(t, i, K), K) / root : 1.0;
        const uint32_t count = node_count(t, i, K);
        *steps += p;
        if (count) *tests += p * count;
        else *box_tests += 2.0 * p;
    }
}

static int kk_stats(const accel *a, accel_stat *out, int max)
{
    const kk_t *t = (const kk_t *)a;
    int n = bvh_stats(&t->topo, t->p->count, out, max);
    double steps, box_tests, tests;
    kk_predict(t, &steps, &box_tests, &tests);
    const accel_stat predicted[] = {
        {"predicted_steps_per_ray", steps},
        {"predicted_box_tests_per_ray", box_tests},
        {"predicted_tests_per_ray", tests},
    };
    for (int k = 0; k < 3 && n < max; k++) out[n++] = predicted[k];
    return n;
}

/* The root's axis slabs: its box (the first three normals are the axes). */
static box3 kk_bounds(const accel *a)
{
    const kk_t *t = (const kk_t *)a;
    if (!t->topo.nnodes) return box_empty();
    const planeset_slab *v = node_slab(t, 0, t->normals);
    box3 b = {{v[0][0], v[1][0], v[2][0]}, {v[0][1], v[1][1], v[2][1]}};
    return b;
}

uint32_t slabs_kk_debug_node(const accel *a, uint32_t i, planeset_slab out[PLANESET_MAX], uint32_t *index,
                             uint32_t *count, const uint32_t **refs)
{
    const kk_t *t = (const kk_t *)a;
    if (i >= t->topo.nnodes) return 0;
    memcpy(out, node_slab(t, i, t->normals), t->normals * sizeof(planeset_slab));
    *index = node_index(t, i, t->normals);
    *count = node_count(t, i, t->normals);
    *refs = t->topo.refs;
    return t->normals;
}

uint32_t slabs_kk_debug_visits(const accel *a, const ray_t *ray, bool shadow, uint32_t *nodes, float *keys,
                               uint32_t cap, hit_t *hit)
{
    const kk_t *t = (const kk_t *)a;
    bvh_walk_log log = {nodes, keys, 0, cap};
    accel_ctx *ctx = kk_context_new((accel *)a);
    counters_t c = {0};
    *hit = hit_none(ray);
    if (shadow) trace(t, ctx, ray, NULL, &c, &log, true, true);
    else trace(t, ctx, ray, hit, &c, &log, false, true);
    kk_context_free(ctx);
    return log.n;
}

/* Each parameter away from its default, and a few together. */
static const char *const kk_variants[] = {
    "normals=3",
    "tree=gs",
    "tree=sah",
    "traverse=dfs",
    "normals=3,traverse=dfs",
    "tree=gs,traverse=dfs",
    "tree=sah,maxleaf=4,normals=3",
    "maxleaf=3,traverse=dfs",
    NULL,
};

const struct accel_ops accel_slabs_kk = {
    .version = 2,
    .name = "slabs-kk",
    .summary = "Kay-Kajiya plane-set (slab) volumes over 3 or 7 fixed normals, heap-ordered traversal by entry "
               "distance; median, Goldsmith-Salmon or SAH tree",
    .paper = "Kay & Kajiya, SIGGRAPH 1986; Arvo & Kirk 1989 survey s4.3-4.4, fig. 9",
    .params = kk_params,
    .flags = 0,
    .build = kk_build,
    .context_new = kk_context_new,
    .context_free = kk_context_free,
    .intersect = kk_intersect,
    .occluded = kk_occluded,
    .memory = kk_memory,
    .destroy = kk_destroy,
    .stats = kk_stats,
    .reset = NULL,
    .bounds = kk_bounds,
    .intersect_fast = kk_intersect_fast,
    .occluded_fast = kk_occluded_fast,
    .variants = kk_variants,
    .cost = {2, 2, 0},
    .tune = "maxleaf=1|2|4|8", /* Kay and Kajiya's one object per volume, and larger leaves */
};
