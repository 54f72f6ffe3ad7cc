/* build.h: what the BVH builders share (build.c); not for accelerators,
 * which include bvh.h. */
#ifndef ACCELBENCH_BVH_BUILD_H
#define ACCELBENCH_BVH_BUILD_H

#include "bvh.h"

/* cfg, or the defaults when NULL. */
bvh_config bvh_config_or_defaults(const bvh_config *cfg);

/* Room for a tree over n primitives (2n - 1 nodes, n refs), *b empty
 * otherwise. 0, or -1 out of memory (nothing held). */
int bvh_alloc(bvh_t *b, uint32_t n);
/* After building: trim the arrays to what is used, count the leaves and
 * measure the depth. 0, or -1 out of memory (*b freed). */
int bvh_finish(bvh_t *b);

/* The centroids the builders use: centroids itself, or (NULL) the boxes'
 * centres in *owned, which the caller frees. NULL out of memory. */
const vec3 *bvh_centroids(const box3 *boxes, const vec3 *centroids, uint32_t n, vec3 **owned);

/* The children's boxes a split function may hand back (known: box[0] is
 * the union of the boxes of ids[0 .. m), box[1] of ids[m .. n), bit for
 * bit what the driver would compute), sparing the driver a pass over each
 * child's primitives. */
typedef struct {
    bool known;
    box3 box[2];
} bvh_split_sides;
/* A top-down builder's choice for the primitives ids[0 .. n) (n >= 2) of a
 * node with box `box`: reorder ids and return m, 0 < m < n, to split them
 * into ids[0 .. m) and ids[m .. n); or 0 to make a leaf (only allowed for
 * n <= cfg->max_leaf). sides->known is false on entry. */
typedef uint32_t (*bvh_split_fn)(uint32_t *ids, uint32_t n, box3 box, const box3 *boxes, const vec3 *centroids,
                                 const bvh_config *cfg, bvh_split_sides *sides);
/* The top-down driver: a node per task, children allocated in adjacent
 * pairs, no recursion (a degenerate split sequence cannot overflow the C
 * stack). */
int bvh_build_topdown(bvh_t *b, const box3 *boxes, const vec3 *centroids, uint32_t n, const bvh_config *cfg,
                      bvh_split_fn split);

/* The drivers' two phases (build.c's header): grain, the size of the
 * subtrees built in parallel (0 when c->threads is 0: one pass), from n
 * alone; and the top phase's config, c with parallel_from set so that its
 * nodes of more than max(grain, BVH_PARALLEL_BINS) primitives bin in
 * chunks on the threads (c itself, as bvh_config_or_defaults leaves it,
 * has parallel_from 0: a subtree bins on its own thread). */
uint32_t bvh_grain(uint32_t n, const bvh_config *c);
bvh_config bvh_top_config(const bvh_config *c, uint32_t grain);

/* job(ctx, i) for every i in [0, count), each once, on up to threads
 * threads (at most BVH_MAX_THREADS; the calling thread is one of them;
 * fewer when a thread cannot be started), returning when all are done.
 * The jobs are taken in order, but finish in any: each must write only its
 * own results. */
void bvh_parallel_for(uint32_t count, uint32_t threads, void (*job)(void *ctx, uint32_t i), void *ctx);

/* A large node's binning on the threads: ids[0 .. n) cut into
 * BVH_BIN_CHUNKS parts (a constant, not the thread count, though any cut
 * gives the same bins), part i binned by bin(ctx, part, its length, the
 * i-th of BVH_BIN_CHUNKS blocks of size bytes), then merge(ctx, block 0,
 * block i) for i = 1, 2, ... in that order, so the result is the same for
 * every thread count. Returns the blocks (block 0 holds the bins; the
 * caller frees them), or NULL out of memory (the caller bins alone). */
#define BVH_BIN_CHUNKS 8
void *bvh_bin_chunked(const uint32_t *ids, uint32_t n, uint32_t threads, size_t size,
                      void (*bin)(const void *ctx, const uint32_t *ids, uint32_t n, void *out),
                      void (*merge)(const void *ctx, void *into, const void *from), const void *ctx);

/* n primitives as a leaf's tests pay for them: whole blocks of block
 * (the SAH's leaf_block; the collapse's merge rule, collapse.c). */
static inline double bvh_leaf_blocks(uint32_t n, uint32_t block) { return (double)((n + block - 1) / block * block); }

/* The binned SAH (build_sah.c) in parts, for builders that weigh its
 * object split against others (build_sbvh.c). bvh_sah_best: the cheapest
 * cut of ids[0 .. n) (a node with box `box`) over the three axes; cost is
 * ct A(box) + ci (A(L) N(L) + A(R) N(R)) with counts in leaf_block
 * blocks, left and right the two sides' boxes; axis -1 (cost +inf) when
 * every centroid falls into one slot; bins the slots per axis it used. bvh_sah_partition: ids reordered,
 * the left side first; returns its count. bvh_sah_leaf_cost: ci N A(box),
 * the same units. */
typedef struct {
    double cost;
    int axis;
    uint32_t slot, bins;  /* the cut: after bin slot of bins (bvh_sah_bins) */
    box3 cb, left, right; /* the range binned (centroid bounds, or the node's box); the sides' boxes */
} bvh_sah_choice;
/* The bins a node of n primitives is binned into: cfg->bins, or with
 * cfg->small_bins min(cfg->bins, 4 + n / 20). */
uint32_t bvh_sah_bins(uint32_t n, const bvh_config *cfg);
bvh_sah_choice bvh_sah_best(const uint32_t *ids, uint32_t n, box3 box, const box3 *boxes, const vec3 *centroids,
                            const bvh_config *cfg);
uint32_t bvh_sah_partition(uint32_t *ids, uint32_t n, const vec3 *centroids, const bvh_sah_choice *ch);
double bvh_sah_leaf_cost(uint32_t n, box3 box, const bvh_config *cfg);
/* Centroid bounds of ids[0 .. n), and the union of their boxes (prims/box4.h). */
box3 bvh_centroid_bounds(const uint32_t *ids, uint32_t n, const vec3 *centroids);
box3 bvh_ids_bounds(const uint32_t *ids, uint32_t n, const box3 *boxes);
/* Reorder ids[0 .. n) so that ids[k] holds the primitive of k-th smallest
 * centroid coordinate on axis, none greater before it and none smaller
 * after (Hoare's FIND, CACM 4(7), 1961); expected O(n). */
void bvh_select(uint32_t *ids, uint32_t n, uint32_t k, const vec3 *centroids, int axis);

#endif
