/* bvh.h: a binary bounding volume hierarchy over primitive boxes: the node
 * layout, the builders and the traversals that the BVH-family accelerators
 * share, so they differ only in builder or traversal, never in a copy.
 *
 * Builders see only boxes and centroids (never prims/), in the manner of
 * madmann91/bvh's bvh3f_build(boxes, centers, n, config): primitive id i is
 * boxes[i]. Three are here:
 *   bvh_build_median  object median on the longest centroid axis (the
 *                     classic top-down split, blind to sizes);
 *   bvh_build_sah     binned surface area heuristic (MacDonald and Booth,
 *                     "Heuristics for Ray Tracing using Space
 *                     Subdivision", The Visual Computer 6(3), 1990, for the
 *                     cost; Wald, "On Fast Construction of SAH-based
 *                     Bounding Volume Hierarchies", IEEE RT 2007, for the
 *                     binning);
 *   bvh_build_insert  incremental insertion in the manner of Goldsmith and
 *                     Salmon, "Automatic Creation of Object Hierarchies for
 *                     Ray Tracing", IEEE CG&A 7(5), 1987: one box at a
 *                     time, down the path of least cost increase.
 * Traversals call prims/ for the leaves (one prim_*_leaf call per leaf):
 *   bvh_*_dfs   depth-first, the nearer child first, the farther one
 *               stacked with its entry distance and dropped on pop when a
 *               closer hit is already known;
 *   bvh_*_heap  heap-ordered (Kay and Kajiya, SIGGRAPH 1986): a heap of nodes by
 *               entry distance; the nearest is expanded next, and a closest
 *               hit query ends when the nearest entry lies beyond the hit.
 * Each comes as intersect and occluded, counting and counting-free (_fast):
 * traverse.c compiles the walks of walk.h over these nodes, the walks that
 * other layouts share through their own volume test (Kay-Kajiya's
 * plane-set nodes, accel/slabs_kk/slabs_kay_kajiya.c).
 *
 * Memory layout:
 *   nodes[nnodes]  bvh_node, 32 bytes: box (24), index (4), count (4).
 *                  count == 0: interior node; its children are
 *                  nodes[index] and nodes[index + 1] (siblings adjacent,
 *                  so one index serves both). count > 0: a leaf holding the
 *                  primitives refs[index .. index + count). nodes[0] is the
 *                  root; an empty tree has nnodes == 0. Leaves always hold
 *                  at least one primitive.
 *   refs[nrefs]    uint32 primitive ids, each leaf's a contiguous run.
 *   Total = 32 nnodes + 4 nrefs (bvh_memory()); nnodes = 2 leaves - 1.
 *   Per context (bvh_scratch): a stack of 8 bytes per level of the tree
 *   and the heap traversal's heap, 8 bytes per entry (grows on demand).
 *
 * Counters (accel.h): box_tests = every node box tested (the root once per
 * ray, then both children of every interior node visited, and every leaf
 * box of an overflow scan); steps = nodes visited (children or primitives
 * tested; a stacked node dropped by its entry distance is not a step);
 * prim_tests and prim_hits by prims/. There are no empty leaves and no
 * mailboxes (each primitive is in exactly one leaf).
 *
 * Box tests are slab_clip_robust() (accel/common/slab.h): a box the exact
 * ray meets is never rejected by rounding. */
#ifndef ACCELBENCH_BVH_H
#define ACCELBENCH_BVH_H

#include <assert.h>
#include <stdbool.h>
#include <stdint.h>
#include "../accel.h"
#include "heap.h"
#include "../common/stack.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    box3 box;       /* 24 bytes: bounds of everything below */
    uint32_t index; /* interior: left child (right = index + 1); leaf: first entry of refs */
    uint32_t count; /* 0: interior; else: primitives in the leaf */
} bvh_node;
static_assert(sizeof(bvh_node) == 32, "bvh_node is 32 bytes: two to a cache line");

typedef struct {
    bvh_node *nodes;    /* [nnodes], nodes[0] the root */
    uint32_t *refs;     /* [nrefs] primitive ids, by leaf */
    uint32_t nnodes, nrefs;
    uint32_t nleaves;   /* leaves among the nodes */
    uint32_t max_depth; /* deepest leaf, root = 0 */
} bvh_t;

/* Build settings; NULL everywhere means bvh_config_defaults(). */
typedef struct {
    uint32_t max_leaf;    /* top-down: a node with more primitives is always split (default 4) */
    uint32_t min_leaf;    /* binned SAH: a node of at most this many primitives is always a leaf, never split
                           * (Embree's minLeafSize; default 0: the SAH decides every node up to max_leaf) */
    uint32_t bins;        /* binned SAH: bins per axis (default 16, 2..256) */
    bool small_bins;      /* binned SAH: a node of n primitives binned into min(bins, 4 + n / 20) slots, Embree's
                           * rule (its BinMapping), which spares small nodes the set-up and sweeps of every bin
                           * (default false: bins for every node) */
    bool bin_node_box;    /* binned SAH: the bins span the node's box instead of its centroids' bounds (tinybvh's
                           * binning; default false: the centroids' bounds, as Wald 2007 and Embree bin) */
    float cost_traversal; /* SAH: cost of visiting a node (default 1) */
    float cost_intersect; /* SAH: cost of one primitive test (default 1) */
    uint32_t leaf_block;  /* SAH: a leaf's primitives are tested leaf_block at a time, so n cost as
                           * ceil(n / leaf_block) * leaf_block (default 1: as counted; 0 means 1) */
    uint64_t insert_seed; /* incremental: 0 inserts in id order, else in an order shuffled by this seed */
    uint32_t threads;     /* top-down: 0 builds on the calling thread in one pass (default); 1 or more builds
                           * the subtrees below the top on that many threads (up to BVH_MAX_THREADS): the same
                           * tree for every count >= 1, whose nodes[] may hold unused zeroed nodes that no node
                           * points to */
    uint32_t parallel_from; /* set by the drivers, not by callers (bvh_config_or_defaults zeroes it): with
                             * threads >= 1, a node of more than this many primitives bins them in fixed chunks
                             * on the threads (the top of a threaded build, above its parallel subtrees); the
                             * bins, and so the tree, are the same for every thread count */
    const uint32_t *insert_rep; /* incremental: rep[i], the coincident class of box i (accel/common/coincident.h),
                                 * or NULL (default): a box of a class already in the tree goes next to it
                                 * (build_insert.c) */
} bvh_config;

#define BVH_MAX_THREADS 64 /* threads a top-down build uses at most */
/* Scratch bytes per primitive of a top-down build's task stack and (threads
 * > 0) its deferred subtrees (build.c asserts it), for memory caps. */
#define BVH_TOPDOWN_TASK_BYTES 40
#define BVH_SUBTREES 64    /* threads > 0: subtrees of at most n / BVH_SUBTREES primitives are built in parallel */
#define BVH_MIN_GRAIN 1024 /* ... and of at most this many when n / BVH_SUBTREES is fewer */
#define BVH_PARALLEL_BINS 32768 /* threads > 0: the top's nodes of more than this many (and the grain) bin in parallel */

void bvh_config_defaults(bvh_config *cfg);

/* Builders. boxes[i] is primitive i's box, centroids[i] its centroid
 * (NULL: the boxes' centres). Return 0, or -1 out of memory with *b empty.
 * The top-down builders split any node of more than max_leaf primitives,
 * down to one primitive per leaf when the centroids allow nothing else
 * (identical centroids are split by count). The incremental builder puts
 * one primitive in each leaf. All are deterministic. */
int bvh_build_median(bvh_t *b, const box3 *boxes, const vec3 *centroids, uint32_t n, const bvh_config *cfg);
int bvh_build_sah(bvh_t *b, const box3 *boxes, const vec3 *centroids, uint32_t n, const bvh_config *cfg);
int bvh_build_insert(bvh_t *b, const box3 *boxes, const vec3 *centroids, uint32_t n, const bvh_config *cfg);
/* The spatial split builder (build_sbvh.c: Stich, Friedrich and Dietrich,
 * HPG 2009), which alone needs the primitives themselves, through clip:
 * the bounds of primitive prim's part inside box (empty when it has none;
 * never outside box or the primitive's box). A primitive may end up in
 * several leaves (refs holds nrefs >= n ids). cfg->threads as for the
 * top-down builds: the same tree for every count >= 1 (build_sbvh.c). */
typedef struct {
    double alpha; /* try a spatial split when the object split's overlap passes alpha A(root) (default 1e-5) */
    double dup;   /* references beyond n at most dup n (default 1; 0: none, so no spatial split) */
    box3 (*clip)(const void *ctx, uint32_t prim, box3 box);
    /* Optional, for binning only: estimates of clip() of box's halves below
     * and above x[axis] = pos (NULL: clip() each slab, exact and slower). */
    void (*split)(const void *ctx, uint32_t prim, box3 box, int axis, float pos, box3 *left, box3 *right);
    const void *ctx;
} bvh_sbvh_config;
void bvh_sbvh_config_defaults(bvh_sbvh_config *s);
int bvh_build_sbvh(bvh_t *b, const box3 *boxes, uint32_t n, const bvh_config *cfg, const bvh_sbvh_config *s);

void bvh_free(bvh_t *b);
/* Bytes held: 32 nnodes + 4 nrefs. */
size_t bvh_memory(const bvh_t *b);
/* The box of everything (empty for an empty tree). */
box3 bvh_bounds(const bvh_t *b);
/* The accelerator statistics (accel.h): nodes (interior), leaves,
 * max_depth, avg_leaf_prims, refs_per_prim over nprims primitives.
 * Returns how many it wrote (at most max). */
int bvh_stats(const bvh_t *b, uint32_t nprims, accel_stat *out, int max);
/* The SAH cost of the tree: sum over interior nodes of ct A(node) and over
 * leaves of ci count A(leaf), over A(root) (0 for an empty tree or a root
 * of zero area). */
double bvh_sah_cost(const bvh_t *b, double ct, double ci);
/* For tests: every primitive 0..n-1 in exactly one leaf, every node
 * reachable once, every box containing its children's (or its primitives'
 * boxes[]), nleaves and max_depth right. 0, or -1 with the first failure
 * in err. */
int bvh_check(const bvh_t *b, const box3 *boxes, uint32_t n, char *err, size_t errlen);

/* Per-context traversal scratch: the depth-first stack (capacity
 * max_depth + 1, so it cannot overflow on the tree it was made for) and
 * the heap of the heap-ordered traversal. */
typedef struct {
    tstack_entry *stack;
    uint32_t stack_cap;
    minheap heap;
} bvh_scratch;
/* 0, or -1 out of memory. */
int bvh_scratch_init(bvh_scratch *s, const bvh_t *b);
void bvh_scratch_free(bvh_scratch *s);

/* Traversals. The accel.h contract: closest hit in [tnear, hit->t) with
 * hit starting as hit_none(ray), returns whether it hit; any hit in
 * [tnear, tfar). s may be NULL: the depth-first ones then use a stack of
 * BVH_STACK_LOCAL entries on the C stack, the heap ones a heap allocated
 * for the ray. Overflow (a stack shallower than the tree, or a heap that
 * cannot grow): the traversal finishes by testing every leaf whose box the
 * ray meets, so the answer stays exact and only costs more (counted). */
#define BVH_STACK_LOCAL 64
bool bvh_intersect_dfs(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray, hit_t *hit, counters_t *c);
bool bvh_occluded_dfs(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray, counters_t *c);
bool bvh_intersect_heap(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray, hit_t *hit, counters_t *c);
bool bvh_occluded_heap(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray, counters_t *c);
/* The same with no counter writes, answers bit-identical. */
bool bvh_intersect_dfs_fast(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray, hit_t *hit);
bool bvh_occluded_dfs_fast(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray);
bool bvh_intersect_heap_fast(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray, hit_t *hit);
bool bvh_occluded_heap_fast(const bvh_t *b, const prims_t *p, bvh_scratch *s, const ray_t *ray);

#ifdef __cplusplus
}
#endif

#endif
