/* build_sah.c: the binned SAH builder (bvh.h).
 *
 * The surface area heuristic (MacDonald and Booth 1990; Goldsmith and
 * Salmon 1987 before them): a ray that meets a node's box meets a child's
 * box with probability A(child) / A(node) (uniform random lines, convex
 * boxes), so splitting n primitives into L and R costs
 *   C = ct + ci (A(L) N(L) + A(R) N(R)) / A(node)
 * against ci n for a leaf. Binning (Wald 2007): the centroids of a node are
 * dropped into `bins` equal slots along each axis of their bounds; the
 * candidate cuts are the bins - 1 slot boundaries, all evaluated in one
 * sweep from each side; the cheapest over the three axes wins.
 *
 * With bin_node_box the slots divide the node's box instead of the
 * centroids' bounds (tinybvh's binned builders do so): coarser where the
 * boxes reach far past the centroids, yet on Sponza, whose big wall and
 * floor triangles do, the wide tree then takes 20-32 % fewer traversal
 * steps on every workload (docs/accels/wide-bvh.md), and as many on the
 * scanned meshes. The partition uses the same range, so binning and
 * partition still agree.
 *
 * With small_bins, a node of n primitives gets min(bins, 4 + n / 20)
 * slots, the rule of Embree's binner (its BinMapping; Wald et al. 2014):
 * the set-up and sweeps of 16 or more bins per axis would dominate the
 * many small nodes near the leaves, where a few bins separate a handful of
 * centroids as well.
 *
 * A node of at most max_leaf primitives becomes a leaf when no cut is
 * cheaper; a larger one is always cut (the cheapest cut, or, when all
 * centroids fall into one slot on every axis, in two halves by count).
 * Costs are compared multiplied through by A(node), so a node of zero area
 * (all its primitives on one line or point) needs no division.
 *
 * With leaf_block > 1 (leaves tested in SIMD packets of that many
 * primitives), every count N above is rounded up to a multiple of
 * leaf_block, the price of the packets that hold them: Embree's binned SAH
 * does the same with its block size (I. Wald, S. Woop, C. Benthin,
 * G. Johnson, M. Ernst, "Embree: A Kernel Framework for Efficient CPU Ray
 * Tracing", ACM TOG 33(4), 2014, section 4.3: leaves of Triangle4 blocks),
 * so a node of 4 triangles stays one full packet instead of two halves. */
#include <stdlib.h>
#include "../../prims/box4.h"
#include "build.h"

#define SAH_MAX_BINS 256

typedef struct {
    box4 box;
    uint32_t count;
} bin_t;

/* The slot of centroid coordinate x: the one formula binning and
 * partitioning both use, so they cannot disagree. f is compared before the
 * conversion, which is undefined for values past uint32_t: a denormal
 * centroid extent makes scale +inf (then f is +inf, or NaN at x == lo,
 * which goes to slot 0). */
static inline uint32_t slot_of(float x, float lo, float scale, uint32_t bins)
{
    float f = (x - lo) * scale;
    if (!(f > 0.0f)) return 0;
    return f < (float)bins ? (uint32_t)f : bins - 1;
}


uint32_t bvh_sah_bins(uint32_t n, const bvh_config *cfg)
{
    uint32_t small = 4 + n / 20;
    return cfg->small_bins && small < cfg->bins ? small : cfg->bins;
}

/* The bins of ids[0 .. n) on the live axes (the others left empty). Counts
 * sum and boxes unite exactly, so bins made over parts of ids and merged
 * are these bins bit for bit. */
typedef struct {
    float lo[3], scale[3];
    bool live[3];
    uint32_t nb;
} sah_binning;

static void sah_bin(const sah_binning *bm, const uint32_t *ids, uint32_t n, const box3 *boxes,
                    const vec3 *centroids, bin_t bins[3][SAH_MAX_BINS])
{
    for (int axis = 0; axis < 3; axis++)
        for (uint32_t k = 0; k < bm->nb; k++) bins[axis][k] = (bin_t){box4_empty(), 0};
    /* The three axes binned in one pass over the primitives (Wald 2007
     * bins all three at once): each box and centroid is fetched through
     * ids once instead of once per axis. Boxes as box4 (prims/box4.h): the
     * same bins, faster. */
    for (uint32_t i = 0; i < n; i++) {
        const vec3 c = centroids[ids[i]];
        const box4 bx = box4_load(&boxes[ids[i]]);
        for (int axis = 0; axis < 3; axis++) {
            if (!bm->live[axis]) continue;
            bin_t *bn = &bins[axis][slot_of(v3_get(c, axis), bm->lo[axis], bm->scale[axis], bm->nb)];
            bn->box = box4_union(bn->box, bx);
            bn->count++;
        }
    }
}

/* bvh_bin_chunked's two steps over sah_bin's bins. */
typedef struct {
    const sah_binning *bm;
    const box3 *boxes;
    const vec3 *centroids;
} sah_chunks;

static void sah_chunk(const void *arg, const uint32_t *ids, uint32_t n, void *out)
{
    const sah_chunks *ch = arg;
    sah_bin(ch->bm, ids, n, ch->boxes, ch->centroids, out);
}

static void sah_merge(const void *arg, void *into_, const void *from_)
{
    const sah_chunks *ch = arg;
    bin_t (*into)[SAH_MAX_BINS] = into_;
    const bin_t (*from)[SAH_MAX_BINS] = from_;
    for (int axis = 0; axis < 3; axis++)
        for (uint32_t k = 0; k < ch->bm->nb; k++) {
            into[axis][k].box = box4_union(into[axis][k].box, from[axis][k].box);
            into[axis][k].count += from[axis][k].count;
        }
}

bvh_sah_choice bvh_sah_best(const uint32_t *ids, uint32_t n, box3 box, const box3 *boxes, const vec3 *centroids,
                            const bvh_config *cfg)
{
    uint32_t nb = bvh_sah_bins(n, cfg);
    /* The range the bins span: the centroids' bounds, or the node's box
     * (bin_node_box), which holds them. */
    box3 cb = cfg->bin_node_box ? box : bvh_centroid_bounds(ids, n, centroids);
    double area = box_area(box);
    bvh_sah_choice ch = {.cost = INFINITY, .axis = -1, .slot = 0, .bins = nb, .cb = cb, .left = box_empty(), .right = box_empty()};
    sah_binning bm = {.nb = nb};
    bool *live = bm.live;
    for (int axis = 0; axis < 3; axis++) {
        bm.lo[axis] = v3_get(cb.lo, axis);
        float ext = v3_get(cb.hi, axis) - bm.lo[axis];
        live[axis] = ext > 0.0f;
        bm.scale[axis] = live[axis] ? (float)nb / ext : 0.0f;
    }
    bin_t local[3][SAH_MAX_BINS], (*bins)[SAH_MAX_BINS] = local, (*chunk)[3][SAH_MAX_BINS] = NULL;
    /* Chunked whenever the driver asks, on any number of threads, so the
     * order of the unions (which may decide the sign of a zero in the
     * sides' boxes) is the same for every count. */
    sah_chunks job = {&bm, boxes, centroids};
    if (cfg->parallel_from && n > cfg->parallel_from &&
        (chunk = bvh_bin_chunked(ids, n, cfg->threads, sizeof *chunk, sah_chunk, sah_merge, &job))) {
        bins = chunk[0];
    } else {
        sah_bin(&bm, ids, n, boxes, centroids, local);
    }
    for (int axis = 0; axis < 3; axis++) {
        if (!live[axis]) continue;
        const bin_t *bin = bins[axis];
        /* right[k]: area-times-count of bins k+1 .. nb-1, swept from the right; right_box[k] their box. */
        double right[SAH_MAX_BINS];
        box4 right_box[SAH_MAX_BINS];
        box4 acc = box4_empty();
        uint32_t cnt = 0;
        for (uint32_t k = nb - 1; k > 0; k--) {
            acc = box4_union(acc, bin[k].box);
            cnt += bin[k].count;
            right[k - 1] = cnt ? (double)box4_area(acc) * bvh_leaf_blocks(cnt, cfg->leaf_block) : -1.0; /* -1: empty side */
            right_box[k - 1] = acc;
        }
        acc = box4_empty();
        cnt = 0;
        for (uint32_t k = 0; k + 1 < nb; k++) {
            acc = box4_union(acc, bin[k].box);
            cnt += bin[k].count;
            if (!cnt || right[k] < 0.0) continue;
            double cost = cfg->cost_traversal * area + cfg->cost_intersect * ((double)box4_area(acc) * bvh_leaf_blocks(cnt, cfg->leaf_block) + right[k]);
            if (cost < ch.cost) ch.cost = cost, ch.axis = axis, ch.slot = k, ch.left = box4_store(acc), ch.right = box4_store(right_box[k]);
        }
    }
    free(chunk);
    return ch;
}

uint32_t bvh_sah_partition(uint32_t *ids, uint32_t n, const vec3 *centroids, const bvh_sah_choice *ch)
{
    const uint32_t bins = ch->bins;
    /* Slots <= ch->slot first, by the binning's own slot formula. */
    float lo = v3_get(ch->cb.lo, ch->axis), scale = (float)bins / (v3_get(ch->cb.hi, ch->axis) - lo);
    uint32_t i = 0, j = n;
    while (i < j) {
        if (slot_of(v3_get(centroids[ids[i]], ch->axis), lo, scale, bins) <= ch->slot) {
            i++;
        } else {
            uint32_t t = ids[i];
            ids[i] = ids[--j];
            ids[j] = t;
        }
    }
    return i;
}

double bvh_sah_leaf_cost(uint32_t n, box3 box, const bvh_config *cfg)
{
    return (double)cfg->cost_intersect * bvh_leaf_blocks(n, cfg->leaf_block) * box_area(box);
}

static uint32_t sah_split(uint32_t *ids, uint32_t n, box3 box, const box3 *boxes, const vec3 *centroids,
                          const bvh_config *cfg, bvh_split_sides *sides)
{
    if (n <= cfg->min_leaf && n <= cfg->max_leaf) return 0;
    bvh_sah_choice ch = bvh_sah_best(ids, n, box, boxes, centroids, cfg);
    if (ch.axis < 0) return 0; /* every centroid in one slot: the driver splits by count */
    if (n <= cfg->max_leaf && bvh_sah_leaf_cost(n, box, cfg) <= ch.cost) return 0;
    /* The partition puts on the left exactly the primitives the sweep's
     * left bins hold (one slot formula), so the sides' boxes are the
     * children's. */
    *sides = (bvh_split_sides){true, {ch.left, ch.right}};
    return bvh_sah_partition(ids, n, centroids, &ch);
}

int bvh_build_sah(bvh_t *b, const box3 *boxes, const vec3 *centroids, uint32_t n, const bvh_config *cfg)
{
    return bvh_build_topdown(b, boxes, centroids, n, cfg, sah_split);
}
