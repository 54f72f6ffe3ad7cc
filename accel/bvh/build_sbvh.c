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
 * Deterministic: the references are processed in one order on the calling
 * thread (cfg->threads is not used: the tree is the same for every thread
 * count because there is only one).
 *
 * Output: a bvh_t whose refs[] holds primitive ids, a primitive in as many
 * leaves as it has references (refs_per_prim > 1; bvh_check's "exactly
 * once" does not hold; tests/test_bvh.c checks that every primitive is in
 * some leaf and every node's box holds its children's). Leaf
 * boxes bound the clipped parts, so a leaf's box may be smaller than a
 * primitive's box in it: traversals test the primitive itself, never its
 * box, so this is sound. Memory while building: 32 bytes a reference
 * (box, centroid, primitive id) and the final tree's nodes and refs,
 * allocated for the budget and trimmed by bvh_finish. */
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

static spatial_choice spatial_best(const refs_t *r, const uint32_t *ids, uint32_t n, box3 box, const bvh_config *c,
                                   const bvh_sbvh_config *s)
{
    spatial_choice best = {INFINITY, -1, 0, 0, 0};
    const uint32_t nb = c->bins < SBVH_MAX_BINS ? c->bins : SBVH_MAX_BINS;
    const double area = box_area(box);
    sbin_t bins[SBVH_MAX_BINS];
    for (int axis = 0; axis < 3; axis++) {
        float lo = v3_get(box.lo, axis), hi = v3_get(box.hi, axis);
        if (!(hi > lo)) continue;
        for (uint32_t k = 0; k < nb; k++) bins[k] = (sbin_t){box4_empty(), 0, 0};
        for (uint32_t i = 0; i < n; i++) {
            uint32_t id = ids[i];
            box3 rb = r->box[id];
            uint32_t b0 = bin_of(v3_get(rb.lo, axis), lo, hi, nb), b1 = bin_of(v3_get(rb.hi, axis), lo, hi, nb);
            bins[b0].entry++;
            bins[b1].exit++;
            if (b0 == b1) {
                bins[b0].box = box4_union(bins[b0].box, box4_load(&rb));
                continue;
            }
            if (s->split) { /* chopped from the left, one plane at a time (Embree's binning of splits) */
                box3 rest = rb;
                for (uint32_t k = b0; k < b1; k++) {
                    box3 part;
                    s->split(s->ctx, r->prim[id], rest, axis, plane_at(lo, hi, k + 1, nb), &part, &rest);
                    bins[k].box = box4_union(bins[k].box, box4_load(&part));
                }
                bins[b1].box = box4_union(bins[b1].box, box4_load(&rest));
                continue;
            }
            for (uint32_t k = b0; k <= b1; k++) {
                box3 slab = with_axis(rb, axis, plane_at(lo, hi, k, nb), plane_at(lo, hi, k + 1, nb));
                box3 part = s->clip(s->ctx, r->prim[id], slab);
                bins[k].box = box4_union(bins[k].box, box4_load(&part));
            }
        }
        double right[SBVH_MAX_BINS];
        uint32_t right_n[SBVH_MAX_BINS];
        box4 acc = box4_empty();
        uint32_t cnt = 0;
        for (uint32_t k = nb - 1; k > 0; k--) {
            acc = box4_union(acc, bins[k].box);
            cnt += bins[k].exit;
            right[k - 1] = cnt ? (double)box4_area(acc) * blocks_of(cnt, c->leaf_block) : -1.0;
            right_n[k - 1] = cnt;
        }
        acc = box4_empty();
        cnt = 0;
        for (uint32_t k = 0; k + 1 < nb; k++) {
            acc = box4_union(acc, bins[k].box);
            cnt += bins[k].entry;
            if (!cnt || right[k] < 0.0 || cnt >= n || right_n[k] >= n) continue; /* both sides fewer than n */
            double cost = c->cost_traversal * area +
                          c->cost_intersect * ((double)box4_area(acc) * blocks_of(cnt, c->leaf_block) + right[k]);
            if (cost < best.cost) best = (spatial_choice){cost, axis, k + 1, cnt, right_n[k]};
        }
    }
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

int bvh_build_sbvh(bvh_t *b, const box3 *boxes, uint32_t n, const bvh_config *cfg, const bvh_sbvh_config *s)
{
    memset(b, 0, sizeof *b);
    if (!n) return bvh_alloc(b, 0);
    bvh_config c = bvh_config_or_defaults(cfg);
    double extra = s->dup > 0 ? fmin(s->dup, 16.0) * (double)n : 0.0;
    uint64_t cap64 = (uint64_t)n + (uint64_t)extra;
    if (cap64 > UINT32_MAX / 2) cap64 = UINT32_MAX / 2;
    const uint32_t cap = (uint32_t)cap64;
    refs_t r = {malloc((size_t)cap * sizeof *r.box), malloc((size_t)cap * sizeof *r.cen),
                malloc((size_t)cap * sizeof *r.prim), 0, cap};
    sbvh_task *stack = malloc((size_t)cap * sizeof *stack);
    uint32_t *root_ids = malloc((size_t)n * sizeof *root_ids);
    uint32_t ntasks = 0;
    if (!r.box || !r.cen || !r.prim || !stack || !root_ids || bvh_alloc(b, cap)) goto oom;
    for (uint32_t i = 0; i < n; i++) root_ids[i] = add_ref(&r, i, boxes[i]);
    box3 root_box = box_empty();
    for (uint32_t i = 0; i < n; i++) root_box = box_union(root_box, boxes[i]);
    const double overlap_min = s->alpha * box_area(root_box);
    uint32_t next = 1, nrefs = 0;
    stack[ntasks++] = (sbvh_task){0, root_ids, n};
    root_ids = NULL;
    while (ntasks) {
        sbvh_task t = stack[--ntasks];
        bvh_node *node = &b->nodes[t.node];
        node->box = bvh_ids_bounds(t.ids, t.n, r.box);
        bvh_sah_choice obj = {.cost = INFINITY, .axis = -1};
        spatial_choice sp = {INFINITY, -1, 0, 0, 0};
        if (t.n > 1) {
            obj = bvh_sah_best(t.ids, t.n, node->box, r.box, r.cen, &c);
            box3 both = box_meet(obj.left, obj.right);
            bool overlapping = obj.axis < 0 || (!box_is_empty(both) && box_area(both) > overlap_min);
            if (overlapping && s->alpha < 1.0) sp = spatial_best(&r, t.ids, t.n, node->box, &c, s);
            if (sp.axis >= 0 && (uint64_t)r.count + sp.nl + sp.nr - t.n > cap) sp.axis = -1; /* over the budget */
        }
        double best = fmin(obj.axis >= 0 ? obj.cost : INFINITY, sp.axis >= 0 ? sp.cost : INFINITY);
        bool leaf = t.n == 1 || (t.n <= c.max_leaf && bvh_sah_leaf_cost(t.n, node->box, &c) <= best);
        if (leaf) {
            node->index = nrefs;
            node->count = t.n;
            for (uint32_t i = 0; i < t.n; i++) b->refs[nrefs++] = r.prim[t.ids[i]];
            free(t.ids);
            continue;
        }
        uint32_t *left = malloc((size_t)t.n * sizeof *left), *right = malloc((size_t)t.n * sizeof *right), nl, nr;
        if (!left || !right) {
            free(left), free(right), free(t.ids);
            goto oom;
        }
        if (sp.axis >= 0 && sp.cost < (obj.axis >= 0 ? obj.cost : INFINITY)) {
            spatial_partition(&r, t.ids, t.n, node->box, &c, s, &sp, left, &nl, right, &nr);
        } else {
            nl = obj.axis >= 0 ? bvh_sah_partition(t.ids, t.n, r.cen, &obj) : 0;
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
        uint32_t l = next;
        next += 2;
        node->index = l;
        node->count = 0;
        stack[ntasks++] = (sbvh_task){l + 1, right, nr};
        stack[ntasks++] = (sbvh_task){l, left, nl};
    }
    b->nnodes = next;
    b->nrefs = nrefs;
    uint32_t *trimmed = realloc(b->refs, (size_t)nrefs * sizeof *trimmed);
    if (trimmed) b->refs = trimmed; /* a failed shrink keeps the larger array */
    free(r.box), free(r.cen), free(r.prim), free(stack);
    return bvh_finish(b);
oom:
    while (ntasks) free(stack[--ntasks].ids);
    free(root_ids);
    free(r.box), free(r.cen), free(r.prim), free(stack);
    bvh_free(b);
    return -1;
}
