/* build_sbvh.c: the spatial split BVH builder (bvh.h, bvh_build_sbvh).
 *
 * Paper: M. Stich, H. Friedrich, A. Dietrich, "Spatial Splits in Bounding
 * Volume Hierarchies", High Performance Graphics 2009 (section 3: the
 * split search; 3.2 the overlap threshold alpha). A BVH node's children
 * may overlap, and a long thin triangle makes every box it joins large. A
 * spatial split cuts the node's box by a plane, as a kd-tree does (Havran's
 * and Wald's perfect splits), and puts each primitive that crosses the
 * plane into both children, each with the bounds of its part on that side:
 * references, not primitives, are partitioned.
 *
 * At every node of more than one reference:
 *   1. the object split of the binned SAH (build_sah.c, the same binning
 *      and cost as split=object) over the references' boxes and centroids;
 *   2. when the overlap of its two sides' boxes is more than alpha times
 *      the root's surface area (lambda > alpha A(root), s3.2; alpha = 1
 *      never looks, alpha = 0 always does), the spatial split: `bins`
 *      equal slabs of the node's box along each axis; a reference's part
 *      in every slab it spans joins that slab's bin: estimated, when the
 *      caller gives split(), by chopping it at each plane from the left
 *      (prims/ prim_split_bounds: the triangle split in float as Embree's
 *      builder bins splits), else clipped to the slab by clip() (for
 *      prims/ the exact clipping of prim_clip_bounds: Sutherland-Hodgman
 *      for triangles and polygons, rounded outward; 70 % of a Sponza
 *      build's time in perf, hence the estimate); it enters the first
 *      slab and exits the last (entry and exit counts, Stich's figure 3); sweeping both ways gives
 *      every plane's cost ct A + ci (A(L) N(L) + A(R) N(R)) with N(L) the
 *      entries left of the plane and N(R) the exits right of it;
 *   3. the cheaper of the two; a node of at most max_leaf references
 *      becomes a leaf when neither is cheaper than its leaf cost; a larger
 *      one with no split is halved by count.
 * A spatial split's straddlers are clipped exactly (clip()) to each side
 * of the plane, whatever estimated the bins, so the boxes the tree keeps
 * bound their parts; one whose part on a side is empty (it only touches
 * the plane) goes to the other side only. Not done: reference unsplitting (s3.1's
 * "unsplitting" test of putting a straddler wholly on one side), which
 * would save some references; chopped binning finer than the bins.
 *
 * Bounds, so that the build ends and the memory is known up front:
 *   - references at most n + dup n (bvh_sbvh_config.dup, default 1: twice
 *     the primitives, Embree's spatial split builder's budget is of the same
 *     kind); a spatial split that would pass it is not taken;
 *   - a spatial split must leave both children fewer references than the
 *     node, so every step down reduces the count and the depth is below n.
 * Threads (cfg->threads), as build.c's driver: with 0 the whole tree is
 * built on the calling thread in one pass; with 1 or more the top is built
 * on the calling thread down to nodes of at most grain references (n /
 * BVH_SUBTREES, at least BVH_MIN_GRAIN: n alone decides it), which are
 * deferred, and then built in parallel, each by a builder of its own over
 * a copy of its references with a reference budget of its own: its
 * references plus its share, by references, of what the top left of the
 * whole budget, so the tree never passes n + dup n. Each subtree is built
 * into a tree of its own, trimmed, and the trees are stitched into the
 * output in the order the top deferred them. A top node of more than
 * max(grain, BVH_PARALLEL_BINS) references bins its object and spatial
 * splits in BVH_BIN_CHUNKS chunks of its references on the threads,
 * merged in chunk order (the chunks are the same on every thread count).
 * So the tree, node numbers included, is the same for every count >= 1;
 * threads 0 may differ from it (one budget for the whole tree).
 *
 * Output: a bvh_t whose refs[] holds primitive ids, a primitive in as many
 * leaves as it has references (refs_per_prim > 1; bvh_check's "exactly
 * once" does not hold; tests/test_bvh.c checks that every primitive is in
 * some leaf and every node's box holds its children's). Leaf
 * boxes bound the clipped parts, so a leaf's box may be smaller than a
 * primitive's box in it: traversals test the primitive itself, never its
 * box, so this is sound. Memory while building: 32 bytes a reference
 * (box, centroid, primitive id) and the final tree's nodes and refs,
 * allocated for the budget and trimmed by bvh_finish; with threads, also
 * the subtrees' copies of their references and their trees (each within
 * its budget, the budgets summing to at most the whole one), held until
 * stitched. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "../../prims/box4.h"
#include "build.h"

#define SBVH_MAX_BINS 256

typedef struct {
    box3 *box;      /* [cap] each reference's box (its primitive's part) */
    vec3 *cen;      /* [cap] its centre */
    uint32_t *prim; /* [cap] its primitive */
    uint32_t count, cap;
} refs_t;

typedef struct {
    uint32_t node;  /* its node in the output */
    uint32_t *ids;  /* its references (owned) */
    uint32_t n;
} sbvh_task;

typedef struct {
    box4 box; /* prims/box4.h: the same bins as box3 with box_union, faster */
    uint32_t entry, exit;
} sbin_t;

void bvh_sbvh_config_defaults(bvh_sbvh_config *s)
{
    memset(s, 0, sizeof *s);
    s->alpha = 1e-5;
    s->dup = 1.0;
}

static inline double blocks_of(uint32_t n, uint32_t block)
{
    block = block ? block : 1;
    return (double)((n + block - 1) / block * block);
}

/* The slab of bin k of `bins` along axis over [lo, hi]: the same plane
 * positions for binning and partitioning. */
static inline float plane_at(float lo, float hi, uint32_t k, uint32_t bins)
{
    return k == 0 ? lo : k >= bins ? hi : lo + (hi - lo) * ((float)k / (float)bins);
}

static inline uint32_t bin_of(float x, float lo, float hi, uint32_t bins)
{
    float f = (x - lo) / (hi - lo) * (float)bins;
    if (!(f > 0.0f)) return 0;
    return f < (float)bins ? (uint32_t)f : bins - 1;
}

static box3 with_axis(box3 b, int axis, float lo, float hi)
{
    float *l = &b.lo.x, *h = &b.hi.x;
    if (lo > l[axis]) l[axis] = lo;
    if (hi < h[axis]) h[axis] = hi;
    return b;
}

typedef struct {
    double cost;
    int axis;
    uint32_t plane; /* the cut is at plane_at(..., plane, bins): bins < plane are left */
    uint32_t nl, nr;
} spatial_choice;

/* The spatial bins of ids[0 .. n) on each axis over box (bins[axis][k];
 * an axis where the box is flat is left empty). Entry and exit counts sum
 * and boxes unite exactly, so bins made over parts of ids and merged
 * (spatial_merge) are these bins bit for bit. */
static void spatial_bin(const refs_t *r, const uint32_t *ids, uint32_t n, box3 box, uint32_t nb,
                        const bvh_sbvh_config *s, sbin_t bins[3][SBVH_MAX_BINS])
{
    for (int axis = 0; axis < 3; axis++) {
        float lo = v3_get(box.lo, axis), hi = v3_get(box.hi, axis);
        for (uint32_t k = 0; k < nb; k++) bins[axis][k] = (sbin_t){box4_empty(), 0, 0};
        if (!(hi > lo)) continue;
        sbin_t *bin = bins[axis];
        for (uint32_t i = 0; i < n; i++) {
            uint32_t id = ids[i];
            box3 rb = r->box[id];
            uint32_t b0 = bin_of(v3_get(rb.lo, axis), lo, hi, nb), b1 = bin_of(v3_get(rb.hi, axis), lo, hi, nb);
            bin[b0].entry++;
            bin[b1].exit++;
            if (b0 == b1) {
                bin[b0].box = box4_union(bin[b0].box, box4_load(&rb));
                continue;
            }
            if (s->split) { /* chopped from the left, one plane at a time (Embree's binning of splits) */
                box3 rest = rb;
                for (uint32_t k = b0; k < b1; k++) {
                    box3 part;
                    s->split(s->ctx, r->prim[id], rest, axis, plane_at(lo, hi, k + 1, nb), &part, &rest);
                    bin[k].box = box4_union(bin[k].box, box4_load(&part));
                }
                bin[b1].box = box4_union(bin[b1].box, box4_load(&rest));
                continue;
            }
            for (uint32_t k = b0; k <= b1; k++) {
                box3 slab = with_axis(rb, axis, plane_at(lo, hi, k, nb), plane_at(lo, hi, k + 1, nb));
                box3 part = s->clip(s->ctx, r->prim[id], slab);
                bin[k].box = box4_union(bin[k].box, box4_load(&part));
            }
        }
    }
}

/* bvh_bin_chunked's two steps over spatial_bin's bins. */
typedef struct {
    const refs_t *r;
    uint32_t nb;
    box3 box;
    const bvh_sbvh_config *s;
} spatial_chunks;

static void spatial_chunk(const void *arg, const uint32_t *ids, uint32_t n, void *out)
{
    const spatial_chunks *ch = arg;
    spatial_bin(ch->r, ids, n, ch->box, ch->nb, ch->s, out);
}

static void spatial_merge(const void *arg, void *into_, const void *from_)
{
    const spatial_chunks *ch = arg;
    sbin_t (*into)[SBVH_MAX_BINS] = into_;
    const sbin_t (*from)[SBVH_MAX_BINS] = from_;
    for (int axis = 0; axis < 3; axis++)
        for (uint32_t k = 0; k < ch->nb; k++) {
            into[axis][k].box = box4_union(into[axis][k].box, from[axis][k].box);
            into[axis][k].entry += from[axis][k].entry;
            into[axis][k].exit += from[axis][k].exit;
        }
}

/* The cheapest spatial split of ids[0 .. n) (a node with box `box`): its
 * bins (in chunks on the threads when n > c->parallel_from), then both
 * sweeps of every axis. */
static spatial_choice spatial_best(const refs_t *r, const uint32_t *ids, uint32_t n, box3 box, const bvh_config *c,
                                   const bvh_sbvh_config *s)
{
    spatial_choice best = {INFINITY, -1, 0, 0, 0};
    const uint32_t nb = c->bins < SBVH_MAX_BINS ? c->bins : SBVH_MAX_BINS;
    const double area = box_area(box);
    sbin_t (*chunk)[3][SBVH_MAX_BINS] = NULL;
    sbin_t local[3][SBVH_MAX_BINS], (*bins)[SBVH_MAX_BINS] = local;
    spatial_chunks ch = {r, nb, box, s};
    if (c->parallel_from && n > c->parallel_from &&
        (chunk = bvh_bin_chunked(ids, n, c->threads, sizeof *chunk, spatial_chunk, spatial_merge, &ch))) {
        bins = chunk[0];
    } else {
        spatial_bin(r, ids, n, box, nb, s, local);
    }
    for (int axis = 0; axis < 3; axis++) {
        float lo = v3_get(box.lo, axis), hi = v3_get(box.hi, axis);
        if (!(hi > lo)) continue;
        const sbin_t *bin = bins[axis];
        double right[SBVH_MAX_BINS];
        uint32_t right_n[SBVH_MAX_BINS];
        box4 acc = box4_empty();
        uint32_t cnt = 0;
        for (uint32_t k = nb - 1; k > 0; k--) {
            acc = box4_union(acc, bin[k].box);
            cnt += bin[k].exit;
            right[k - 1] = cnt ? (double)box4_area(acc) * blocks_of(cnt, c->leaf_block) : -1.0;
            right_n[k - 1] = cnt;
        }
        acc = box4_empty();
        cnt = 0;
        for (uint32_t k = 0; k + 1 < nb; k++) {
            acc = box4_union(acc, bin[k].box);
            cnt += bin[k].entry;
            if (!cnt || right[k] < 0.0 || cnt >= n || right_n[k] >= n) continue; /* both sides fewer than n */
            double cost = c->cost_traversal * area +
                          c->cost_intersect * ((double)box4_area(acc) * blocks_of(cnt, c->leaf_block) + right[k]);
            if (cost < best.cost) best = (spatial_choice){cost, axis, k + 1, cnt, right_n[k]};
        }
    }
    free(chunk);
    return best;
}

/* Room for one more reference (the budget was checked by the caller). */
static uint32_t add_ref(refs_t *r, uint32_t prim, box3 b)
{
    uint32_t id = r->count++;
    r->box[id] = b;
    r->cen[id] = box_center(b);
    r->prim[id] = prim;
    return id;
}

/* Split ids by the spatial choice into left[] and right[] (each sized n),
 * clipping the straddlers; sets *nl and *nr. */
static void spatial_partition(refs_t *r, const uint32_t *ids, uint32_t n, box3 box, const bvh_config *c,
                              const bvh_sbvh_config *s, const spatial_choice *sc, uint32_t *left, uint32_t *nl,
                              uint32_t *right, uint32_t *nr)
{
    const uint32_t nb = c->bins < SBVH_MAX_BINS ? c->bins : SBVH_MAX_BINS;
    const int axis = sc->axis;
    float lo = v3_get(box.lo, axis), hi = v3_get(box.hi, axis), cut = plane_at(lo, hi, sc->plane, nb);
    *nl = *nr = 0;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t id = ids[i];
        box3 rb = r->box[id];
        uint32_t b0 = bin_of(v3_get(rb.lo, axis), lo, hi, nb), b1 = bin_of(v3_get(rb.hi, axis), lo, hi, nb);
        if (b1 < sc->plane) {
            left[(*nl)++] = id;
        } else if (b0 >= sc->plane) {
            right[(*nr)++] = id;
        } else {
            box3 lb = s->clip(s->ctx, r->prim[id], with_axis(rb, axis, -INFINITY, cut));
            box3 hb = s->clip(s->ctx, r->prim[id], with_axis(rb, axis, cut, INFINITY));
            if (box_is_empty(lb)) {
                right[(*nr)++] = id;
            } else if (box_is_empty(hb)) {
                left[(*nl)++] = id;
            } else {
                r->box[id] = lb, r->cen[id] = box_center(lb);
                left[(*nl)++] = id;
                right[(*nr)++] = add_ref(r, r->prim[id], hb);
            }
        }
    }
}

/* One builder: its references (r: ids index r's arrays), its output tree
 * (nodes[2 cap - 1] and refs[cap] from bvh_alloc(out, cap)), the next
 * free node pair and output ref. The top of a threaded build is one, each
 * subtree below it another. */
typedef struct {
    refs_t r;
    bvh_t *out;
    uint32_t next, nrefs;
    const bvh_config *c;
    const bvh_sbvh_config *s;
    double overlap_min; /* alpha A(root): the whole tree's root, also in a subtree */
} sbvh_builder;

static void free_refs(refs_t *r)
{
    free(r->box), free(r->cen), free(r->prim);
    memset(r, 0, sizeof *r);
}

static int alloc_refs(refs_t *r, uint32_t cap)
{
    *r = (refs_t){malloc((size_t)cap * sizeof *r->box), malloc((size_t)cap * sizeof *r->cen),
                  malloc((size_t)cap * sizeof *r->prim), 0, cap};
    if (r->box && r->cen && r->prim) return 0;
    free_refs(r);
    return -1;
}

/* The tasks of stack[0 .. ntasks) (room for r.cap) built depth first;
 * with grain > 0 a task of at most grain references is not built but
 * moved to deferred[*ndeferred] (room for r.cap; its ids still owned),
 * its node left for the caller to fill. 0, or -1 out of memory (every
 * task's ids freed, the deferred ones too). */
static int sbvh_loop(sbvh_builder *bd, sbvh_task *stack, uint32_t ntasks, uint32_t grain, sbvh_task *deferred,
                     uint32_t *ndeferred)
{
    refs_t *r = &bd->r;
    const bvh_config *c = bd->c;
    const bvh_sbvh_config *s = bd->s;
    bvh_t *b = bd->out;
    while (ntasks) {
        sbvh_task t = stack[--ntasks];
        if (grain && t.n <= grain) {
            deferred[(*ndeferred)++] = t;
            continue;
        }
        bvh_node *node = &b->nodes[t.node];
        node->box = bvh_ids_bounds(t.ids, t.n, r->box);
        bvh_sah_choice obj = {.cost = INFINITY, .axis = -1};
        spatial_choice sp = {INFINITY, -1, 0, 0, 0};
        if (t.n > 1) {
            obj = bvh_sah_best(t.ids, t.n, node->box, r->box, r->cen, c);
            box3 both = box_meet(obj.left, obj.right);
            bool overlapping = obj.axis < 0 || (!box_is_empty(both) && box_area(both) > bd->overlap_min);
            if (overlapping && s->alpha < 1.0) sp = spatial_best(r, t.ids, t.n, node->box, c, s);
            if (sp.axis >= 0 && (uint64_t)r->count + sp.nl + sp.nr - t.n > r->cap) sp.axis = -1; /* over the budget */
        }
        double best = fmin(obj.axis >= 0 ? obj.cost : INFINITY, sp.axis >= 0 ? sp.cost : INFINITY);
        bool leaf = t.n == 1 || (t.n <= c->max_leaf && bvh_sah_leaf_cost(t.n, node->box, c) <= best);
        if (leaf) {
            node->index = bd->nrefs;
            node->count = t.n;
            for (uint32_t i = 0; i < t.n; i++) b->refs[bd->nrefs++] = r->prim[t.ids[i]];
            free(t.ids);
            continue;
        }
        uint32_t *left = malloc((size_t)t.n * sizeof *left), *right = malloc((size_t)t.n * sizeof *right), nl, nr;
        if (!left || !right) {
            free(left), free(right), free(t.ids);
            goto oom;
        }
        if (sp.axis >= 0 && sp.cost < (obj.axis >= 0 ? obj.cost : INFINITY)) {
            spatial_partition(r, t.ids, t.n, node->box, c, s, &sp, left, &nl, right, &nr);
        } else {
            nl = obj.axis >= 0 ? bvh_sah_partition(t.ids, t.n, r->cen, &obj) : 0;
            if (nl == 0 || nl >= t.n) nl = t.n / 2; /* no cut: halves by count */
            nr = t.n - nl;
            memcpy(left, t.ids, (size_t)nl * sizeof *left);
            memcpy(right, t.ids + nl, (size_t)nr * sizeof *right);
        }
        free(t.ids);
        /* Both sides are non-empty and smaller than the node: a spatial cut
         * sends left only references entering left of it (fewer than n, the
         * choice's nl) and right only those leaving right of it (nr < n),
         * and every reference goes somewhere. */
        uint32_t l = bd->next;
        bd->next += 2;
        node->index = l;
        node->count = 0;
        stack[ntasks++] = (sbvh_task){l + 1, right, nr};
        stack[ntasks++] = (sbvh_task){l, left, nl};
    }
    return 0;
oom:
    while (ntasks) free(stack[--ntasks].ids);
    if (deferred)
        while (*ndeferred) free(deferred[--*ndeferred].ids);
    return -1;
}

/* The second phase of a threaded build: deferred subtree i built by a
 * builder of its own, over a copy of its references with a budget of its
 * own (cap[i]), into tree[i] (trimmed); failed[i] set when out of memory.
 * Reads the top builder's references only. */
typedef struct {
    const sbvh_builder *top;
    const bvh_config *c; /* the subtrees' (parallel_from 0: each is on one thread) */
    sbvh_task *deferred;
    const uint32_t *cap;
    bvh_t *tree;
    bool *failed;
} sbvh_phase2;

static void sbvh_subtree(void *arg, uint32_t i)
{
    sbvh_phase2 *ph = arg;
    sbvh_task *d = &ph->deferred[i];
    const refs_t *from = &ph->top->r;
    const uint32_t cap = ph->cap[i];
    sbvh_builder bd = {.out = &ph->tree[i], .next = 1, .c = ph->c, .s = ph->top->s,
                       .overlap_min = ph->top->overlap_min};
    sbvh_task *stack = malloc((size_t)cap * sizeof *stack);
    uint32_t *ids = malloc((size_t)d->n * sizeof *ids);
    if (!stack || !ids || alloc_refs(&bd.r, cap) || bvh_alloc(bd.out, cap)) goto oom;
    for (uint32_t k = 0; k < d->n; k++) {
        uint32_t id = d->ids[k];
        bd.r.box[k] = from->box[id], bd.r.cen[k] = from->cen[id], bd.r.prim[k] = from->prim[id];
        ids[k] = k;
    }
    bd.r.count = d->n;
    stack[0] = (sbvh_task){0, ids, d->n};
    ids = NULL;
    if (sbvh_loop(&bd, stack, 1, 0, NULL, NULL)) goto oom;
    bd.out->nnodes = bd.next;
    bd.out->nrefs = bd.nrefs;
    /* Trimmed: every subtree's tree is held until all are stitched. */
    bvh_node *nodes = realloc(bd.out->nodes, (size_t)bd.next * sizeof *nodes);
    if (nodes) bd.out->nodes = nodes;
    uint32_t *refs = realloc(bd.out->refs, (size_t)bd.nrefs * sizeof *refs);
    if (refs) bd.out->refs = refs;
    free_refs(&bd.r), free(stack);
    return;
oom:
    ph->failed[i] = true;
    free(ids), free_refs(&bd.r), free(stack);
    bvh_free(bd.out);
}

/* Subtree tree's nodes into b, its root at node `at` and the rest from
 * *next on, its leaves' refs from *nrefs on. */
static void stitch(bvh_t *b, uint32_t at, const bvh_t *tree, uint32_t *next, uint32_t *nrefs)
{
    const uint32_t base = *next - 1; /* the subtree's node j >= 1 lands at base + j */
    for (uint32_t j = 0; j < tree->nnodes; j++) {
        bvh_node nd = tree->nodes[j];
        nd.index += nd.count ? *nrefs : base;
        b->nodes[j ? base + j : at] = nd;
    }
    memcpy(b->refs + *nrefs, tree->refs, (size_t)tree->nrefs * sizeof *b->refs);
    *next += tree->nnodes - 1;
    *nrefs += tree->nrefs;
}

int bvh_build_sbvh(bvh_t *b, const box3 *boxes, uint32_t n, const bvh_config *cfg, const bvh_sbvh_config *s)
{
    memset(b, 0, sizeof *b);
    if (!n) return bvh_alloc(b, 0);
    bvh_config c = bvh_config_or_defaults(cfg);
    double extra = s->dup > 0 ? fmin(s->dup, 16.0) * (double)n : 0.0;
    uint64_t cap64 = (uint64_t)n + (uint64_t)extra;
    if (cap64 > UINT32_MAX / 2) cap64 = UINT32_MAX / 2;
    const uint32_t cap = (uint32_t)cap64;
    /* threads > 0: subtrees of at most grain references (n alone decides
     * it, as in build.c) are built in parallel; the top's nodes bin in
     * parallel, the subtrees' (c) each on its thread. */
    const uint32_t grain = bvh_grain(n, &c);
    const bvh_config top_cfg = bvh_top_config(&c, grain);
    sbvh_builder top = {.out = b, .next = 1, .c = &top_cfg, .s = s};
    sbvh_task *stack = malloc((size_t)cap * sizeof *stack), *deferred = NULL;
    uint32_t *root_ids = malloc((size_t)n * sizeof *root_ids), *sub_cap = NULL, ndeferred = 0;
    bvh_t *sub = NULL;
    bool *failed = NULL;
    if (grain) deferred = malloc((size_t)cap * sizeof *deferred);
    if (alloc_refs(&top.r, cap) || !stack || !root_ids || (grain && !deferred) || bvh_alloc(b, cap)) goto oom;
    for (uint32_t i = 0; i < n; i++) root_ids[i] = add_ref(&top.r, i, boxes[i]);
    box3 root_box = box_empty();
    for (uint32_t i = 0; i < n; i++) root_box = box_union(root_box, boxes[i]);
    top.overlap_min = s->alpha * box_area(root_box);
    stack[0] = (sbvh_task){0, root_ids, n};
    root_ids = NULL;
    if (sbvh_loop(&top, stack, 1, grain, deferred, &ndeferred)) goto oom;
    if (ndeferred) {
        /* Each subtree's budget: its references and its share, by
         * references, of what the top left of the whole budget, so the
         * tree never holds more than cap references (the top's leaves and
         * the subtrees' references are all top.r.count of them). */
        uint64_t deferred_refs = 0;
        for (uint32_t i = 0; i < ndeferred; i++) deferred_refs += deferred[i].n;
        const uint64_t spare = cap - top.r.count;
        sub_cap = malloc((size_t)ndeferred * sizeof *sub_cap);
        sub = calloc(ndeferred, sizeof *sub);
        failed = calloc(ndeferred, sizeof *failed);
        if (!sub_cap || !sub || !failed) goto oom;
        for (uint32_t i = 0; i < ndeferred; i++)
            sub_cap[i] = deferred[i].n + (uint32_t)(spare * deferred[i].n / deferred_refs);
        sbvh_phase2 ph = {&top, &c, deferred, sub_cap, sub, failed};
        bvh_parallel_for(ndeferred, c.threads, sbvh_subtree, &ph);
        for (uint32_t i = 0; i < ndeferred; i++) free(deferred[i].ids); /* copied by the subtrees */
        bool any_failed = false;
        for (uint32_t i = 0; i < ndeferred; i++) any_failed |= failed[i];
        if (any_failed) {
            for (uint32_t i = 0; i < ndeferred; i++) bvh_free(&sub[i]);
            ndeferred = 0;
            goto oom;
        }
        /* In the order the top deferred them: the same tree for every
         * thread count. */
        for (uint32_t i = 0; i < ndeferred; i++) {
            stitch(b, deferred[i].node, &sub[i], &top.next, &top.nrefs);
            bvh_free(&sub[i]);
        }
        ndeferred = 0;
    }
    b->nnodes = top.next;
    b->nrefs = top.nrefs;
    uint32_t *trimmed = realloc(b->refs, (size_t)top.nrefs * sizeof *trimmed);
    if (trimmed) b->refs = trimmed; /* a failed shrink keeps the larger array */
    free_refs(&top.r), free(stack), free(deferred), free(sub_cap), free(sub), free(failed);
    return bvh_finish(b);
oom:
    while (ndeferred) free(deferred[--ndeferred].ids);
    free(root_ids);
    free_refs(&top.r), free(stack), free(deferred), free(sub_cap), free(sub), free(failed);
    bvh_free(b);
    return -1;
}
