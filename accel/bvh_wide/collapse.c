/* collapse.c: the kit's binary BVH collapsed to 4- or 8-wide nodes
 * (wide.h), with the greedy rule of the wide-BVH papers (Dammertz et al.
 * 2008, Ernst and Greiner 2008, Wald et al. 2008): a wide node starts from
 * the two children of a binary interior node and repeatedly opens the
 * interior child of largest surface area (a ray that meets the node meets
 * it most often, so pulling its children up saves the most visits) until
 * it has `width` children or only leaves remain. Each remaining interior
 * child becomes a wide node of its own, collapsed the same way. The leaves
 * are the binary tree's, so every primitive is in exactly one leaf; with a
 * merge rule (wide_merge: Embree's leaf rule, wide.h) an interior child
 * about to become a wide node may become one leaf of its subtree's run of
 * refs instead, and a node's slots may be ordered by subtree size. Both
 * need per binary node its subtree's run (subtree_spans: 12 bytes a node,
 * and 8 more while they are computed). */
#include <stdlib.h>
#include <string.h>
#include "../bvh/build.h"
#include "../common/big_alloc.h"
#include "wide.h"

const char *const wide_isa_names[WIDE_ISA_COUNT + 1] = {"scalar", "sse42", "avx2", "avx512", NULL};

size_t wide_node_bytes(uint32_t width) { return WIDE_NODE_BYTES(width); }

/* The binary nodes that become the children of the wide node made from
 * binary node bi, in slot order: bi's two children opened greedily (bi
 * itself, alone, when it is a leaf: the root of a one-leaf tree). Returns
 * how many (at most width). */
static uint32_t open_children(const bvh_t *b, uint32_t bi, uint32_t width, uint32_t *list)
{
    const bvh_node *nodes = b->nodes;
    if (nodes[bi].count) {
        list[0] = bi;
        return 1;
    }
    uint32_t n = 2;
    list[0] = nodes[bi].index, list[1] = nodes[bi].index + 1;
    while (n < width) {
        int best = -1;
        float best_area = -1.0f;
        for (uint32_t k = 0; k < n; k++) {
            if (nodes[list[k]].count) continue;
            float a = box_area(nodes[list[k]].box);
            if (a > best_area) best_area = a, best = (int)k;
        }
        if (best < 0) break; /* only leaves left */
        /* Its left child takes its slot, its right child the next; the
         * slots after it move up one. */
        uint32_t left = nodes[list[best]].index;
        memmove(&list[best + 2], &list[best + 1], (n - (uint32_t)best - 1) * sizeof *list);
        list[best] = left, list[best + 1] = left + 1;
        n++;
    }
    return n;
}

/* Big leaves (wide_merge): per binary node, the run of refs its subtree's
 * leaves hold when they are one contiguous run (count 0 when not), so that
 * an interior node can become one leaf of them. */
typedef struct wide_span {
    uint32_t first, count; /* the run, count 0 when the subtree's refs are not one run */
    uint32_t prims;        /* refs below, in one run or not */
} span_t;

/* The spans of every node reachable from the root: a pre-order list, then
 * its reverse (children before parents), with no recursion. NULL out of
 * memory. */
static span_t *subtree_spans(const bvh_t *b)
{
    const bvh_node *nodes = b->nodes;
    /* span and order are written through (huge pages, big_alloc.h); the stack only to the tree's depth. */
    span_t *span = big_calloc(b->nnodes, sizeof *span);
    uint32_t *order = big_alloc((size_t)b->nnodes * sizeof *order), *stack = malloc(((size_t)b->nnodes + 1) * sizeof *stack);
    if (!span || !order || !stack) {
        free(span), free(order), free(stack);
        return NULL;
    }
    uint32_t n = 0, sp = 0;
    stack[sp++] = 0;
    while (sp) {
        uint32_t i = stack[--sp];
        order[n++] = i;
        if (!nodes[i].count) stack[sp++] = nodes[i].index, stack[sp++] = nodes[i].index + 1;
    }
    while (n--) {
        const bvh_node *nd = &nodes[order[n]];
        if (nd->count) {
            span[order[n]] = (span_t){nd->index, nd->count, nd->count};
            continue;
        }
        span_t l = span[nd->index], r = span[nd->index + 1];
        span[order[n]].prims = l.prims + r.prims;
        if (l.count && r.count && l.first + l.count == r.first)
            span[order[n]].first = l.first, span[order[n]].count = l.count + r.count;
    }
    free(order);
    free(stack);
    return span;
}

/* Whether interior binary node bi becomes one leaf of its subtree's refs:
 * at most m->max_leaf of them in one run, and the SAH's leaf cost no more
 * than its split's, ct A(bi) + ci (N(L) A(L) + N(R) A(R)) against ci N A(bi)
 * (counts in whole blocks). */
static bool merges(const bvh_t *b, const span_t *span, const wide_merge *m, uint32_t bi)
{
    if (!span || !m->max_leaf || b->nodes[bi].count || !span[bi].count || span[bi].count > m->max_leaf) return false;
    const bvh_node *nd = &b->nodes[bi], *l = &b->nodes[nd->index], *r = l + 1;
    const uint32_t blk = m->leaf_block ? m->leaf_block : 1;
    double leaf = bvh_leaf_blocks(span[bi].count, blk) * box_area(nd->box);
    double split = m->cost_traversal * box_area(nd->box) + bvh_leaf_blocks(span[nd->index].count, blk) * box_area(l->box) +
                   bvh_leaf_blocks(span[nd->index + 1].count, blk) * box_area(r->box);
    return leaf <= split;
}

/* A slot's child as the wide tree holds it: its node (interior), or its
 * leaf's run of refs. */
typedef struct {
    bool leaf;
    uint32_t first, count;
} slot_t;

static slot_t slot_of(const bvh_t *b, const span_t *span, const wide_merge *m, uint32_t bi)
{
    const bvh_node *nd = &b->nodes[bi];
    if (nd->count) return (slot_t){true, nd->index, nd->count};
    if (merges(b, span, m, bi)) return (slot_t){true, span[bi].first, span[bi].count};
    return (slot_t){false, 0, 0};
}

static int collapse(wide_bvh *w, const bvh_t *b, uint32_t width, const wide_merge *m, const span_t *span,
                    uint32_t *total);

/* The spans the merge rule m needs (NULL when it needs none); *ok false
 * out of memory. */
static span_t *spans_for(const bvh_t *b, const wide_merge *m, bool *ok)
{
    span_t *span = m && (m->max_leaf || m->by_size) ? subtree_spans(b) : NULL;
    *ok = span || !(m && (m->max_leaf || m->by_size));
    return span;
}

int wide_plan_collapse(wide_plan *plan, const bvh_t *b, uint32_t width, const wide_merge *m)
{
    memset(plan, 0, sizeof *plan);
    if (!b->nnodes) return 0;
    bool ok;
    plan->span = spans_for(b, m, &ok);
    if (ok && !collapse(NULL, b, width, m, plan->span, &plan->nodes)) return 0;
    wide_plan_free(plan);
    return -1;
}

void wide_plan_free(wide_plan *plan)
{
    free(plan->span);
    memset(plan, 0, sizeof *plan);
}

void wide_set_slot(wide_bvh *w, uint32_t ni, uint32_t k, box3 box, uint32_t child, uint32_t count)
{
    const uint32_t W = w->width;
    char *node = (char *)w->nodes + (size_t)ni * WIDE_NODE_BYTES(W);
    float *rows[6];
    for (uint32_t r = 0; r < 6; r++) rows[r] = WIDE_ROWS(node) + r * W;
    uint32_t *children = WIDE_CHILD(node, W);
    uint8_t *counts = WIDE_COUNT(node, W);
    rows[0][k] = box.lo.x, rows[1][k] = box.hi.x;
    rows[2][k] = box.lo.y, rows[3][k] = box.hi.y;
    rows[4][k] = box.lo.z, rows[5][k] = box.hi.z;
    children[k] = child;
    counts[k] = (uint8_t)count;
}

/* The orders per octant (wide.h) of n slots with these boxes: by the
 * centres of the boxes projected on the octant's diagonal, ascending, ties
 * by slot (an insertion sort: stable), then the unused slots. */
void wide_orders_of(const box3 *box, uint32_t n, uint32_t W, uint32_t order[WIDE_OCTANTS])
{
    for (uint32_t oct = 0; oct < WIDE_OCTANTS; oct++) {
        float key[8];
        uint32_t ord[8];
        for (uint32_t k = 0; k < W; k++) {
            if (k < n) key[k] = wide_octant_key(box[k], oct);
            uint32_t j = k;
            while (k < n && j > 0 && key[ord[j - 1]] > key[k]) ord[j] = ord[j - 1], j--;
            ord[j] = k;
        }
        order[oct] = 0;
        for (uint32_t i = 0; i < W; i++) order[oct] |= ord[i] << (3 * i);
    }
}

/* Node ni's slot orders per octant from its n used slots' boxes. */
void wide_set_orders(wide_bvh *w, uint32_t ni, uint32_t n)
{
    const uint32_t W = w->width;
    char *node = (char *)w->nodes + (size_t)ni * WIDE_NODE_BYTES(W), *orders = node + WIDE_ORDER_OFFSET(W);
    box3 box[8];
    uint32_t order[WIDE_OCTANTS];
    for (uint32_t k = 0; k < n; k++) box[k] = wide_slot_box(WIDE_ROWS(node), W, k);
    wide_orders_of(box, n, W, order);
    for (uint32_t oct = 0; oct < WIDE_OCTANTS; oct++) {
        if (W == 2) ((uint8_t *)orders)[oct] = (uint8_t)order[oct];
        else if (W == 4) ((uint16_t *)orders)[oct] = (uint16_t)order[oct];
        else ((uint32_t *)orders)[oct] = order[oct];
    }
}

/* The collapse, or with w NULL only its node count (*total). The root's
 * binary node is a wide node's source unless it is a leaf or merges: then
 * the root holds it as one leaf child. */
static int collapse(wide_bvh *w, const bvh_t *b, uint32_t width, const wide_merge *m, const span_t *span,
                    uint32_t *total)
{
    *total = 0;
    if (!b->nnodes) return 0;
    /* (binary node, wide node, depth) triples pending: at most one per
     * interior binary node, plus the root. */
    uint32_t *pending = malloc(3 * ((size_t)b->nnodes + 1) * sizeof *pending), np = 0, nnodes = 1;
    if (!pending) return -1;
    pending[np++] = 0, pending[np++] = 0, pending[np++] = 0;
    while (np) {
        uint32_t depth = pending[--np], ni = pending[--np], bi = pending[--np], list[8];
        /* A root that is a leaf or merges is its wide root's one child. */
        uint32_t n = ni == 0 && slot_of(b, span, m, 0).leaf ? (list[0] = 0, 1) : open_children(b, bi, width, list);
        /* Largest subtree first (stable), as Embree orders a node's
         * children "for faster shadow ray traversal": an any-hit walk takes
         * them in slot order, and a closest-hit walk where entry distances
         * tie. */
        for (uint32_t k = 1; span && m->by_size && k < n; k++)
            for (uint32_t j = k; j > 0 && span[list[j - 1]].prims < span[list[j]].prims; j--) {
                uint32_t tmp = list[j];
                list[j] = list[j - 1], list[j - 1] = tmp;
            }
        for (uint32_t k = 0; w && k < width; k++) {
            if (k >= n) wide_set_slot(w, ni, k, box_empty(), WIDE_EMPTY, 0);
        }
        for (uint32_t k = 0; k < n; k++) {
            const box3 box = b->nodes[list[k]].box;
            slot_t s = slot_of(b, span, m, list[k]);
            if (s.leaf) {
                if (!w) continue;
                wide_set_slot(w, ni, k, box, WIDE_LEAF | s.first, s.count);
                w->nleaves++;
                if (depth + 1 > w->max_depth) w->max_depth = depth + 1;
                continue;
            }
            uint32_t child = nnodes++;
            if (w) wide_set_slot(w, ni, k, box, child, 0);
            pending[np++] = list[k], pending[np++] = child, pending[np++] = depth + 1;
        }
        if (!w) continue;
        WIDE_NCHILDREN((char *)w->nodes + (size_t)ni * WIDE_NODE_BYTES(width), width) = (uint8_t)n;
        wide_set_orders(w, ni, n);
        w->nchildren += n;
    }
    free(pending);
    *total = nnodes;
    return 0;
}

int wide_collapse(wide_bvh *w, bvh_t *b, uint32_t width, const wide_merge *m, const wide_plan *plan)
{
    memset(w, 0, sizeof *w);
    w->width = width;
    if (!b->nnodes) return 0;
    uint32_t total = plan->nodes;
    /* 64-byte aligned, on huge pages when large (accel/common/big_alloc.h) */
    w->nodes = big_calloc(total, wide_node_bytes(width));
    if (w->nodes) w->nnodes = total;
    if (!w->nodes || collapse(w, b, width, m, plan->span, &total)) {
        free(w->nodes);
        memset(w, 0, sizeof *w);
        return -1;
    }
    w->refs = b->refs;
    w->nrefs = b->nrefs;
    b->refs = NULL;
    b->nrefs = 0;
    return 0;
}

void wide_free(wide_bvh *w)
{
    free(w->nodes);
    free(w->packets);
    free(w->refs);
    memset(w, 0, sizeof *w);
}

box3 wide_bounds(const wide_bvh *w)
{
    box3 b = box_empty();
    if (!w->nnodes) return b;
    const uint32_t n = WIDE_NCHILDREN_Q(w->nodes, w->width, w->quantized);
    for (uint32_t k = 0; k < n; k++) b = box_union(b, wide_node_slot_box(w, 0, k));
    return b;
}

size_t wide_memory(const wide_bvh *w)
{
    return (size_t)w->nnodes * WIDE_NODE_SIZE(w->width, w->quantized) + (size_t)w->nrefs * sizeof(uint32_t) +
           (size_t)w->npackets * sizeof(prim_tri_packet);
}

uint32_t wide_stack_cap(const wide_bvh *w)
{
    /* A visit pushes at most W entries and the walk pops one before the
     * next visit, so at most W - 1 stay per level above the deepest. */
    return (w->width - 1) * (w->max_depth + 1) + 1;
}

int wide_stats(const wide_bvh *w, uint32_t nprims, accel_stat *out, int max)
{
    const wide_prediction pr = wide_predict(w);
    accel_stat all[] = {
        {"nodes", (double)w->nnodes},
        {"leaves", (double)w->nleaves},
        {"max_depth", (double)w->max_depth},
        {"avg_leaf_prims", w->nleaves ? (double)w->nrefs / w->nleaves : 0.0},
        {"refs_per_prim", nprims ? (double)w->nrefs / nprims : 0.0},
        {"avg_children", w->nnodes ? (double)w->nchildren / w->nnodes : 0.0},
        /* the last three: the cost model's, left out when it ran out of memory */
        {"predicted_box_tests_per_ray", pr.box_tests},
        {"predicted_tests_per_ray", pr.prim_tests},
        {"predicted_steps_per_ray", pr.steps},
    };
    int n = (int)(sizeof all / sizeof all[0]) - (pr.box_tests < 0.0 ? 3 : 0);
    if (n > max) n = max;
    memcpy(out, all, (size_t)(n > 0 ? n : 0) * sizeof *out);
    return n;
}
