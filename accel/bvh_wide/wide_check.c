/* wide_check.c: the structural check of a wide BVH (wide.h), for tests:
 * what the walk assumes of the tree, checked node by node. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "wide.h"

typedef struct {
    const wide_bvh *w;
    uint32_t node;
    const uint32_t *child;
    const uint8_t *count;
    uint32_t nchildren;
} node_view;

static node_view view(const wide_bvh *w, uint32_t i)
{
    const uint32_t W = w->width;
    const bool Q = w->quantized;
    char *n = WIDE_NODE_AT(w->nodes, i, W, Q);
    return (node_view){w, i, WIDE_CHILD_Q(n, W, Q), WIDE_COUNT_Q(n, W, Q), WIDE_NCHILDREN_Q(n, W, Q)};
}

/* A quantised slot's box is its decoded one: it may be larger than what
 * it bounds, never smaller, which is all the checks below ask. */
static box3 slot_box(const node_view *v, uint32_t k) { return wide_node_slot_box(v->w, v->node, k); }

static bool box_contains(box3 outer, box3 inner)
{
    return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z &&
           outer.hi.x >= inner.hi.x && outer.hi.y >= inner.hi.y && outer.hi.z >= inner.hi.z;
}

/* Primitive j of the leaf whose child word is ch. */
static uint32_t leaf_prim(const wide_bvh *w, uint32_t ch, uint32_t j)
{
    const uint32_t first = ch & WIDE_INDEX;
    if (ch & WIDE_PACKED) return w->packets[first + j / PRIM_TRI_LANES].id[j % PRIM_TRI_LANES];
    return w->refs[first + j];
}

/* A quantised tree's subtree bounds from its primitives, bottom up
 * (children come after their parents, so a reverse pass sees them first):
 * a child's decoded slots may reach past its parent's decoded slot (each
 * node rounds outward on a grid of its own), so a slot is checked against
 * what it must hold, the primitives below it. NULL when out of memory or
 * with a bad leaf (the main pass reports it). */
static box3 *subtree_bounds(const wide_bvh *w, const box3 *boxes, uint32_t n)
{
    box3 *b = malloc(((size_t)w->nnodes + 1) * sizeof *b);
    for (uint32_t i = w->nnodes; b && i-- > 0;) {
        node_view v = view(w, i);
        b[i] = box_empty();
        for (uint32_t k = 0; k < v.nchildren && k < w->width; k++) {
            if (!(v.child[k] & WIDE_LEAF)) {
                if (v.child[k] <= i || v.child[k] >= w->nnodes) continue;
                b[i] = box_union(b[i], b[v.child[k]]);
                continue;
            }
            const uint32_t first = v.child[k] & WIDE_INDEX, cnt = v.count[k];
            if (v.child[k] & WIDE_PACKED ? (uint64_t)first + prim_tri_packets(cnt) > w->npackets
                                         : (uint64_t)first + cnt > w->nrefs)
                continue;
            for (uint32_t j = 0; j < cnt; j++) {
                uint32_t id = leaf_prim(w, v.child[k], j);
                if (id < n) b[i] = box_union(b[i], boxes[id]);
            }
        }
    }
    return b;
}

#define FAIL(...) do { snprintf(err, errlen, __VA_ARGS__); goto fail; } while (0)

int wide_check(const wide_bvh *w, const box3 *boxes, uint32_t n, char *err, size_t errlen)
{
    const uint32_t W = w->width;
    uint8_t *seen_prim = calloc((size_t)n + 1, 1), *seen_node = calloc((size_t)w->nnodes + 1, 1);
    uint32_t *depth = calloc((size_t)w->nnodes + 1, sizeof *depth);
    uint32_t leaves = 0, refs = 0, max_depth = 0;
    uint64_t nchildren = 0, packets = 0;
    box3 *exact = w->quantized && !w->spatial ? subtree_bounds(w, boxes, n) : NULL;
    if (!seen_prim || !seen_node || !depth || (w->quantized && !w->spatial && !exact)) FAIL("out of memory");
    if (W != 2 && W != 4 && W != 8) FAIL("width %u", W);
    if (w->quantized && W != 8) FAIL("quantised nodes of width %u", W);
    if (n && !w->nnodes) FAIL("no nodes over %u primitives", n);
    if (w->nnodes) seen_node[0] = 1;
    /* Children always come after their parent (collapse allocates them
     * when it reaches them), so one pass in index order sees every
     * parent's depth before its children. */
    for (uint32_t i = 0; i < w->nnodes; i++) {
        if (!seen_node[i]) FAIL("node %u is not reachable", i);
        node_view v = view(w, i);
        if (v.nchildren < 1 || v.nchildren > W) FAIL("node %u has %u children", i, v.nchildren);
        if (v.nchildren < 2 && i != 0) FAIL("node %u has one child", i);
        nchildren += v.nchildren;
        /* The octant orders: permutations of the slots, the used ones first,
         * by their centres on the octant's diagonal, ties by slot. */
        for (uint32_t oct = 0; oct < WIDE_OCTANTS; oct++) {
            const uint32_t perm = WIDE_ORDER_Q(WIDE_NODE_AT(w->nodes, i, W, w->quantized), W, w->quantized, oct);
            unsigned used = 0;
            float prev = 0;
            uint32_t prev_slot = 0;
            for (uint32_t pos = 0; pos < W; pos++) {
                uint32_t k = (perm >> 3 * pos) & 7;
                if (k >= W || (used >> k & 1) || (pos < v.nchildren) != (k < v.nchildren))
                    FAIL("node %u octant %u: position %u holds slot %u (order %#x)", i, oct, pos, k, perm);
                used |= 1u << k;
                if (pos >= v.nchildren) continue;
                float key = wide_octant_key(slot_box(&v, k), oct);
                if (pos && (key < prev || (key == prev && k < prev_slot)))
                    FAIL("node %u octant %u: slot %u before slot %u out of order", i, oct, prev_slot, k);
                prev = key, prev_slot = k;
            }
        }
        for (uint32_t k = 0; k < W; k++) {
            box3 b = slot_box(&v, k);
            if (k >= v.nchildren) {
                /* (a quantised node's unused slots decode to a box at its
                 * origin; its kernels mask them off) */
                const bool empty_box = b.lo.x == INFINITY && b.hi.x == -INFINITY;
                if (v.child[k] != WIDE_EMPTY || v.count[k] || (!w->quantized && !empty_box))
                    FAIL("node %u slot %u: unused but not empty", i, k);
                continue;
            }
            if (v.child[k] & WIDE_LEAF) {
                uint32_t first = v.child[k] & WIDE_INDEX, cnt = v.count[k];
                bool packed = v.child[k] & WIDE_PACKED;
                if (!cnt || (!packed && (uint64_t)first + cnt > w->nrefs) ||
                    (packed && (uint64_t)first + prim_tri_packets(cnt) > w->npackets))
                    FAIL("node %u slot %u: leaf [%u, +%u) out of %s", i, k, first, cnt, packed ? "packets" : "refs");
                for (uint32_t j = 0; j < cnt; j++) {
                    /* A packet leaf's lanes in order: the ids it was packed from, unused lanes only at the end. */
                    uint32_t id = leaf_prim(w, v.child[k], j);
                    if (packed && j + 1 == cnt && (j + 1) % PRIM_TRI_LANES &&
                        w->packets[first + j / PRIM_TRI_LANES].id[(j + 1) % PRIM_TRI_LANES] != PRIM_TRI_NO_ID)
                        FAIL("node %u slot %u: packet leaf of %u has more lanes", i, k, cnt);
                    if (id >= n || (seen_prim[id] && !w->spatial)) FAIL("primitive %u in two leaves or out of range", id);
                    seen_prim[id] = 1;
                    if (w->spatial ? !box_overlap(b, boxes[id]) : !box_contains(b, boxes[id]))
                        FAIL("node %u slot %u does not %s primitive %u", i, k, w->spatial ? "meet" : "contain", id);
                }
                leaves++, refs += cnt;
                packets += packed ? prim_tri_packets(cnt) : 0;
                if (depth[i] + 1 > max_depth) max_depth = depth[i] + 1;
                continue;
            }
            uint32_t c = v.child[k];
            if (v.count[k] || c <= i || c >= w->nnodes || seen_node[c]) FAIL("node %u slot %u: bad child %u", i, k, c);
            seen_node[c] = 1;
            depth[c] = depth[i] + 1;
            /* The child node's box; quantised: the primitives below
             * (split=sbvh's clipped parts are not kept, so there the slot
             * need only meet its node) */
            box3 u = box_empty();
            if (exact) {
                u = exact[c];
            } else {
                node_view cv = view(w, c);
                for (uint32_t j = 0; j < cv.nchildren; j++) u = box_union(u, slot_box(&cv, j));
            }
            if (w->quantized && w->spatial ? !box_overlap(b, u) : !box_contains(b, u))
                FAIL("node %u slot %u does not contain its node %u", i, k, c);
        }
    }
    for (uint32_t id = 0; id < n; id++)
        if (!seen_prim[id]) FAIL("primitive %u in no leaf", id);
    if (packets != w->npackets) FAIL("packets: %llu used of %u", (unsigned long long)packets, w->npackets);
    if (leaves != w->nleaves || refs != w->nrefs || max_depth != w->max_depth || nchildren != w->nchildren)
        FAIL("counts: leaves %u/%u refs %u/%u depth %u/%u", leaves, w->nleaves, refs, w->nrefs, max_depth, w->max_depth);
    free(seen_prim), free(seen_node), free(depth), free(exact);
    return 0;
fail:
    free(seen_prim), free(seen_node), free(depth), free(exact);
    return -1;
}
