/* build.c: the parts every BVH builder shares: allocation, trimming and
 * measuring, centroids, and the top-down driver that the median and SAH
 * builders run with their own split choice.
 *
 * With bvh_config.threads > 0 the driver builds in two phases: the top of
 * the tree on the calling thread down to subtrees of at most n /
 * BVH_SUBTREES primitives, then those subtrees in parallel (pthreads),
 * each into a node range reserved for it (the ranges' unused ends squeezed
 * out afterwards, so the tree is as dense as a one-pass build's): the
 * task-parallel split of the recursion that parallel BVH builders use
 * below their top levels (I. Wald,
 * "Fast Construction of SAH BVHs on the Intel Many Integrated Core (MIC)
 * Architecture", IEEE TVCG 18(1), 2012: subtrees as independent tasks
 * once there are enough of them, and its top levels bin in parallel: here
 * a top node of more than max(grain, BVH_PARALLEL_BINS) primitives bins
 * them in fixed chunks on the threads, build_sah.c). Where a
 * subtree is cut depends on n and the splits alone and each subtree's
 * nodes land in its own range, so the tree, node numbers included, is the
 * same for every thread count. */
#include "build.h"
#include "../../prims/box4.h"
#include "../common/big_alloc.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

void bvh_config_defaults(bvh_config *cfg)
{
    cfg->max_leaf = 4;
    cfg->min_leaf = 0;
    cfg->bins = 16;
    cfg->small_bins = false;
    cfg->bin_node_box = false;
    cfg->cost_traversal = 1.0f;
    cfg->cost_intersect = 1.0f;
    cfg->leaf_block = 1;
    cfg->threads = 0;
    cfg->insert_seed = 0;
    cfg->parallel_from = 0;
    cfg->insert_rep = NULL;
}

bvh_config bvh_config_or_defaults(const bvh_config *cfg)
{
    bvh_config c;
    bvh_config_defaults(&c);
    if (cfg) c = *cfg;
    if (c.max_leaf < 1) c.max_leaf = 1;
    if (c.leaf_block < 1) c.leaf_block = 1;
    if (c.bins < 2) c.bins = 2;
    if (c.bins > 256) c.bins = 256;
    c.parallel_from = 0; /* the drivers' own (bvh_top_config), never a caller's */
    return c;
}

uint32_t bvh_grain(uint32_t n, const bvh_config *c)
{
    if (!c->threads) return 0;
    return n / BVH_SUBTREES > BVH_MIN_GRAIN ? n / BVH_SUBTREES : BVH_MIN_GRAIN;
}

bvh_config bvh_top_config(const bvh_config *c, uint32_t grain)
{
    bvh_config top = *c;
    top.parallel_from = !grain ? 0 : grain > BVH_PARALLEL_BINS ? grain : BVH_PARALLEL_BINS;
    return top;
}

int bvh_alloc(bvh_t *b, uint32_t n)
{
    memset(b, 0, sizeof *b);
    if (!n) return 0;
    /* On huge pages (accel/common/big_alloc.h): a build writes them at once. */
    b->nodes = big_alloc((2 * (size_t)n - 1) * sizeof *b->nodes);
    b->refs = big_alloc((size_t)n * sizeof *b->refs);
    if (!b->nodes || !b->refs) {
        bvh_free(b);
        return -1;
    }
    return 0;
}

int bvh_finish(bvh_t *b)
{
    if (!b->nnodes) return 0;
    bvh_node *nodes = realloc(b->nodes, (size_t)b->nnodes * sizeof *nodes);
    if (nodes) b->nodes = nodes; /* a failed shrink keeps the larger array */
    /* Depth-first over the tree with (node, depth) pairs: at most nnodes
     * are ever pending. */
    uint32_t *stack = malloc(2 * (size_t)b->nnodes * sizeof *stack), n = 0;
    if (!stack) {
        bvh_free(b);
        return -1;
    }
    b->nleaves = b->max_depth = 0;
    stack[n++] = 0, stack[n++] = 0;
    while (n) {
        uint32_t depth = stack[--n], ni = stack[--n];
        const bvh_node *node = &b->nodes[ni];
        if (node->count) {
            b->nleaves++;
            if (depth > b->max_depth) b->max_depth = depth;
            continue;
        }
        for (uint32_t k = 0; k < 2; k++) stack[n++] = node->index + k, stack[n++] = depth + 1;
    }
    free(stack);
    return 0;
}

const vec3 *bvh_centroids(const box3 *boxes, const vec3 *centroids, uint32_t n, vec3 **owned)
{
    *owned = NULL;
    if (centroids) return centroids;
    *owned = big_alloc(((size_t)n + 1) * sizeof **owned);
    if (!*owned) return NULL;
    for (uint32_t i = 0; i < n; i++) (*owned)[i] = box_center(boxes[i]);
    return *owned;
}

box3 bvh_centroid_bounds(const uint32_t *ids, uint32_t n, const vec3 *centroids)
{
    box4 cb = box4_empty();
    for (uint32_t i = 0; i < n; i++) cb = box4_union(cb, box4_point(&centroids[ids[i]]));
    return box4_store(cb);
}

box3 bvh_ids_bounds(const uint32_t *ids, uint32_t n, const box3 *boxes)
{
    box4 b = box4_empty();
    for (uint32_t i = 0; i < n; i++) b = box4_union(b, box4_load(&boxes[ids[i]]));
    return box4_store(b);
}

void bvh_select(uint32_t *ids, uint32_t n, uint32_t k, const vec3 *centroids, int axis)
{
    int64_t lo = 0, hi = (int64_t)n - 1;
    while (lo < hi) {
        float pivot = v3_get(centroids[ids[lo + (hi - lo) / 2]], axis);
        int64_t i = lo, j = hi;
        /* Hoare's partition: both scans stop on keys equal to the pivot,
         * so runs of equal centroids split in the middle. */
        while (i <= j) {
            while (v3_get(centroids[ids[i]], axis) < pivot) i++;
            while (v3_get(centroids[ids[j]], axis) > pivot) j--;
            if (i <= j) {
                uint32_t t = ids[i];
                ids[i++] = ids[j];
                ids[j--] = t;
            }
        }
        /* Now ids[lo .. j] <= pivot <= ids[i .. hi], and between them
         * (if anything) equal to the pivot. */
        if ((int64_t)k <= j) hi = j;
        else if ((int64_t)k >= i) lo = i;
        else break;
    }
}

typedef struct {
    uint32_t node, begin, end;
    uint32_t boxed; /* the node's box is set already (its parent's split knew it) */
} task_t;

/* A subtree left for the second phase: its task, the first node of the
 * range reserved for its descendants, and (after the second phase) the
 * end of the part of that range it used. */
typedef struct {
    task_t task;
    uint32_t base, used_end;
} deferred_t;
_Static_assert(sizeof(task_t) + sizeof(deferred_t) == BVH_TOPDOWN_TASK_BYTES, "bvh.h's BVH_TOPDOWN_TASK_BYTES");

/* The top-down loop over a stack of tasks (tasks[0 .. ntasks), room for
 * one per primitive of its range), new node pairs taken from *next. With
 * grain > 0, a task of at most grain primitives is not built but recorded
 * in deferred[] with a range of 2 cnt - 2 nodes reserved for its
 * descendants (a binary tree over cnt primitives has at most 2 cnt - 1
 * nodes, its root already made), so the 2n - 1 nodes bvh_alloc made are
 * always enough. */
static void topdown_loop(bvh_t *b, task_t *tasks, uint32_t ntasks, uint32_t *next, const box3 *boxes,
                         const vec3 *cent, const bvh_config *c, bvh_split_fn split, uint32_t grain,
                         deferred_t *deferred, uint32_t *ndeferred)
{
    while (ntasks) {
        task_t t = tasks[--ntasks];
        uint32_t *ids = b->refs + t.begin, cnt = t.end - t.begin;
        if (cnt <= grain) {
            deferred[(*ndeferred)++] = (deferred_t){t, *next, *next};
            *next += 2 * cnt - 2;
            continue;
        }
        bvh_node *node = &b->nodes[t.node];
        if (!t.boxed) node->box = bvh_ids_bounds(ids, cnt, boxes);
        bvh_split_sides sides = {false, {box_empty(), box_empty()}};
        uint32_t m = cnt > 1 ? split(ids, cnt, node->box, boxes, cent, c, &sides) : 0;
        if (m == 0 && cnt > c->max_leaf) m = cnt / 2; /* a split function that declined: split by count */
        if (m == 0 || m >= cnt) {
            node->index = t.begin;
            node->count = cnt;
            continue;
        }
        uint32_t l = *next;
        *next += 2;
        node->index = l;
        node->count = 0;
        if (sides.known) b->nodes[l].box = sides.box[0], b->nodes[l + 1].box = sides.box[1];
        tasks[ntasks++] = (task_t){l + 1, t.begin + m, t.end, sides.known};
        tasks[ntasks++] = (task_t){l, t.begin, t.begin + m, sides.known};
    }
}

/* bvh_parallel_for (build.h): workers take the jobs in order from one
 * atomic counter, so nothing is shared but the next index. */
typedef struct {
    void (*job)(void *ctx, uint32_t i);
    void *ctx;
    uint32_t count;
    atomic_uint taken;
} parallel_for_t;

static void *parallel_worker(void *arg)
{
    parallel_for_t *pf = arg;
    for (;;) {
        uint32_t i = atomic_fetch_add(&pf->taken, 1);
        if (i >= pf->count) return NULL;
        pf->job(pf->ctx, i);
    }
}

void bvh_parallel_for(uint32_t count, uint32_t threads, void (*job)(void *ctx, uint32_t i), void *ctx)
{
    parallel_for_t pf = {job, ctx, count, 0};
    uint32_t nworkers = threads < count ? threads : count, started = 0;
    pthread_t tid[BVH_MAX_THREADS];
    if (nworkers > BVH_MAX_THREADS) nworkers = BVH_MAX_THREADS;
    /* The calling thread is one worker; a thread that cannot be started
     * leaves its share to the others. */
    while (started + 1 < nworkers && pthread_create(&tid[started], NULL, parallel_worker, &pf) == 0) started++;
    parallel_worker(&pf);
    for (uint32_t i = 0; i < started; i++) pthread_join(tid[i], NULL);
}

/* The second phase: each deferred subtree built on its own slice of refs,
 * of the task array (a subtree's task stack never holds more than its
 * primitives) and of the nodes (its reserved range). */
typedef struct {
    bvh_t *b;
    task_t *tasks;
    const box3 *boxes;
    const vec3 *cent;
    const bvh_config *c;
    bvh_split_fn split;
    deferred_t *deferred;
} phase2_t;

static void phase2_subtree(void *arg, uint32_t i)
{
    phase2_t *ph = arg;
    deferred_t *d = &ph->deferred[i];
    uint32_t next = d->base;
    task_t *tasks = ph->tasks + d->task.begin;
    tasks[0] = d->task;
    topdown_loop(ph->b, tasks, 1, &next, ph->boxes, ph->cent, ph->c, ph->split, 0, NULL, NULL);
    d->used_end = next;
}

/* After the second phase the node array holds, in order, runs of the top's
 * nodes and of each subtree's, with the unused end of each subtree's
 * reservation between them (a subtree of cnt primitives reserves 2 cnt - 2
 * nodes and uses about cnt / 2 with leaves of four). Compacting moves the
 * runs down over those gaps, so the tree is dense again (2 leaves - 1
 * nodes, none unreachable) without writing, or touching the pages of, the
 * gaps. A node pair never straddles two runs; a subtree's nodes point into
 * their own run, the top's into any (binary search over the runs' starts).
 * *end: the node count before, and after. 0, or -1 out of memory. */
typedef struct {
    uint32_t begin, end, shift; /* old [begin, end) moves to [begin - shift, end - shift) */
} node_run;

static uint32_t run_shift(const node_run *runs, uint32_t nruns, uint32_t index)
{
    uint32_t lo = 0, hi = nruns; /* the last run with begin <= index */
    while (hi - lo > 1) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (runs[mid].begin <= index) lo = mid;
        else hi = mid;
    }
    return runs[lo].shift;
}

static int compact_subtrees(bvh_t *b, const deferred_t *deferred, uint32_t ndeferred, uint32_t *end)
{
    node_run *runs = malloc((2 * (size_t)ndeferred + 1) * sizeof *runs);
    if (!runs) return -1;
    /* The runs in order: top nodes before each subtree, the subtree's used
     * part, and the top nodes after the last one. The deferred subtrees
     * were recorded in the order their ranges were reserved. */
    uint32_t nruns = 0, at = 0, gaps = 0;
    for (uint32_t i = 0; i < ndeferred; i++) {
        const deferred_t *d = &deferred[i];
        runs[nruns++] = (node_run){at, d->base, gaps};
        runs[nruns++] = (node_run){d->base, d->used_end, gaps};
        at = d->base + 2 * (d->task.end - d->task.begin) - 2;
        gaps += at - d->used_end;
    }
    runs[nruns++] = (node_run){at, *end, gaps};
    for (uint32_t r = 0; r < nruns; r++) {
        const node_run *run = &runs[r];
        bvh_node *to = b->nodes + run->begin - run->shift;
        if (run->shift && run->end > run->begin) memmove(to, b->nodes + run->begin, (size_t)(run->end - run->begin) * sizeof *to);
        const bool subtree = r % 2 == 1;
        for (uint32_t k = 0; k < run->end - run->begin; k++)
            if (!to[k].count) to[k].index -= subtree ? run->shift : run_shift(runs, nruns, to[k].index);
    }
    free(runs);
    *end -= gaps;
    return 0;
}

int bvh_build_topdown(bvh_t *b, const box3 *boxes, const vec3 *centroids, uint32_t n, const bvh_config *cfg,
                      bvh_split_fn split)
{
    if (bvh_alloc(b, n)) return -1;
    if (!n) return 0;
    bvh_config c = bvh_config_or_defaults(cfg);
    vec3 *owned;
    const vec3 *cent = bvh_centroids(boxes, centroids, n, &owned);
    /* Pending tasks never exceed the leaves still to make: n. */
    task_t *tasks = big_alloc((size_t)n * sizeof *tasks);
    /* threads > 0: subtrees of at most `grain` primitives are deferred to
     * a second phase over threads (grain depends on n alone, so the tree
     * is the same whatever the thread count). */
    const uint32_t grain = bvh_grain(n, &c);
    deferred_t *deferred = c.threads ? malloc((size_t)n * sizeof *deferred) : NULL;
    if (!cent || !tasks || (c.threads && !deferred)) {
        free(owned);
        free(tasks);
        free(deferred);
        bvh_free(b);
        return -1;
    }
    for (uint32_t i = 0; i < n; i++) b->refs[i] = i;
    b->nrefs = n;
    uint32_t next = 1, ndeferred = 0;
    tasks[0] = (task_t){0, 0, n, 0};
    /* The top's nodes bin in parallel, the subtrees' (c) each on its thread. */
    const bvh_config top = bvh_top_config(&c, grain);
    topdown_loop(b, tasks, 1, &next, boxes, cent, &top, split, grain, deferred, &ndeferred);
    if (ndeferred) {
        phase2_t ph = {b, tasks, boxes, cent, &c, split, deferred};
        bvh_parallel_for(ndeferred, c.threads, phase2_subtree, &ph);
        if (compact_subtrees(b, deferred, ndeferred, &next)) {
            free(deferred);
            free(tasks);
            free(owned);
            bvh_free(b);
            return -1;
        }
    }
    b->nnodes = next;
    free(deferred);
    free(tasks);
    free(owned);
    return bvh_finish(b);
}

/* bvh_bin_chunked (build.h). */
typedef struct {
    const uint32_t *ids;
    uint32_t n;
    size_t size;
    void (*bin)(const void *ctx, const uint32_t *ids, uint32_t n, void *out);
    const void *ctx;
    char *blocks;
} bin_chunks;

static void bin_chunk(void *arg, uint32_t i)
{
    const bin_chunks *ch = arg;
    uint32_t begin = (uint32_t)((uint64_t)ch->n * i / BVH_BIN_CHUNKS);
    uint32_t end = (uint32_t)((uint64_t)ch->n * (i + 1) / BVH_BIN_CHUNKS);
    ch->bin(ch->ctx, ch->ids + begin, end - begin, ch->blocks + (size_t)i * ch->size);
}

void *bvh_bin_chunked(const uint32_t *ids, uint32_t n, uint32_t threads, size_t size,
                      void (*bin)(const void *ctx, const uint32_t *ids, uint32_t n, void *out),
                      void (*merge)(const void *ctx, void *into, const void *from), const void *ctx)
{
    char *blocks = malloc(BVH_BIN_CHUNKS * size);
    if (!blocks) return NULL;
    bin_chunks job = {ids, n, size, bin, ctx, blocks};
    bvh_parallel_for(BVH_BIN_CHUNKS, threads, bin_chunk, &job);
    for (uint32_t i = 1; i < BVH_BIN_CHUNKS; i++) merge(ctx, blocks, blocks + (size_t)i * size);
    return blocks;
}
