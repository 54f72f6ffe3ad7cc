/* collapse.c: the kit's binary BVH collapsed to 4- or 8-wide nodes
 * (wide.h), with the greedy rule of the wide-BVH papers (Dammertz et al.
 * 2008, Ernst and Greiner 2008, Wald et al. 2008): a wide node starts from
 * the two children of a binary interior node and repeatedly opens the
 * interior child of largest surface area (a ray that meets the node meets
 * it most often, so pulling its children up saves the most visits) until
 * it has `width` children or only leaves remain. Each remaining interior
 * child becomes a wide node of its own, collapsed the same way. The leaves
 * are the binary tree's, so every primitive is in exactly one leaf. */
#include <stdlib.h>
#include <string.h>
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

uint32_t wide_count_nodes(const bvh_t *b, uint32_t width)
{
    if (!b->nnodes) return 0;
    /* Pending binary nodes that become wide nodes: at most the interior
     * nodes (plus the root). */
    uint32_t *pending = malloc(((size_t)b->nnodes + 1) * sizeof *pending), np = 0, count = 0;
    if (!pending) return UINT32_MAX; /* the caller's cap check then refuses */
    pending[np++] = 0;
    while (np) {
        uint32_t bi = pending[--np], list[8];
        count++;
        uint32_t n = open_children(b, bi, width, list);
        for (uint32_t k = 0; k < n; k++)
            if (!b->nodes[list[k]].count) pending[np++] = list[k];
    }
    free(pending);
    return count;
}

static void set_slot(wide_bvh *w, uint32_t ni, uint32_t k, box3 box, uint32_t child, uint32_t count)
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

/* Node ni's slot orders per octant (wide.h): the n used slots by the
 * centres of their boxes projected on the octant's diagonal, ascending,
 * ties by slot (an insertion sort: stable), then the unused slots. */
static void set_orders(wide_bvh *w, uint32_t ni, uint32_t n)
{
    const uint32_t W = w->width;
    char *node = (char *)w->nodes + (size_t)ni * WIDE_NODE_BYTES(W), *orders = node + WIDE_ORDER_OFFSET(W);
    for (uint32_t oct = 0; oct < WIDE_OCTANTS; oct++) {
        float key[8];
        uint32_t ord[8];
        for (uint32_t k = 0; k < W; k++) {
            if (k < n) key[k] = wide_octant_key(wide_slot_box(WIDE_ROWS(node), W, k), oct);
            uint32_t j = k;
            while (k < n && j > 0 && key[ord[j - 1]] > key[k]) ord[j] = ord[j - 1], j--;
            ord[j] = k;
        }
        uint32_t packed = 0;
        for (uint32_t i = 0; i < W; i++) packed |= ord[i] << (3 * i);
        if (W == 2) ((uint8_t *)orders)[oct] = (uint8_t)packed;
        else if (W == 4) ((uint16_t *)orders)[oct] = (uint16_t)packed;
        else ((uint32_t *)orders)[oct] = packed;
    }
}

int wide_collapse(wide_bvh *w, bvh_t *b, uint32_t width)
{
    memset(w, 0, sizeof *w);
    w->width = width;
    if (!b->nnodes) return 0;
    uint32_t total = wide_count_nodes(b, width);
    size_t bytes = (size_t)total * wide_node_bytes(width);
    w->nodes = aligned_alloc(64, bytes);
    /* (binary node, wide node, depth) triples pending */
    uint32_t *pending = malloc(3 * ((size_t)b->nnodes + 1) * sizeof *pending), np = 0;
    if (total == UINT32_MAX || !w->nodes || !pending) {
        free(pending);
        free(w->nodes);
        memset(w, 0, sizeof *w);
        return -1;
    }
    memset(w->nodes, 0, bytes);
    w->nnodes = 1;
    pending[np++] = 0, pending[np++] = 0, pending[np++] = 0;
    while (np) {
        uint32_t depth = pending[--np], ni = pending[--np], bi = pending[--np], list[8];
        uint32_t n = open_children(b, bi, width, list);
        for (uint32_t k = 0; k < width; k++) {
            if (k >= n) {
                set_slot(w, ni, k, box_empty(), WIDE_EMPTY, 0);
                continue;
            }
            const bvh_node *c = &b->nodes[list[k]];
            if (c->count) {
                set_slot(w, ni, k, c->box, WIDE_LEAF | c->index, c->count);
                w->nleaves++;
                if (depth + 1 > w->max_depth) w->max_depth = depth + 1;
                continue;
            }
            uint32_t child = w->nnodes++;
            set_slot(w, ni, k, c->box, child, 0);
            pending[np++] = list[k], pending[np++] = child, pending[np++] = depth + 1;
        }
        WIDE_NCHILDREN((char *)w->nodes + (size_t)ni * WIDE_NODE_BYTES(width), width) = (uint8_t)n;
        set_orders(w, ni, n);
        w->nchildren += n;
    }
    free(pending);
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

size_t wide_memory(const wide_bvh *w)
{
    return (size_t)w->nnodes * wide_node_bytes(w->width) + (size_t)w->nrefs * sizeof(uint32_t) +
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
    accel_stat all[] = {
        {"nodes", (double)w->nnodes},
        {"leaves", (double)w->nleaves},
        {"max_depth", (double)w->max_depth},
        {"avg_leaf_prims", w->nleaves ? (double)w->nrefs / w->nleaves : 0.0},
        {"refs_per_prim", nprims ? (double)w->nrefs / nprims : 0.0},
        {"avg_children", w->nnodes ? (double)w->nchildren / w->nnodes : 0.0},
    };
    int n = (int)(sizeof all / sizeof all[0]);
    if (n > max) n = max;
    memcpy(out, all, (size_t)(n > 0 ? n : 0) * sizeof *out);
    return n;
}
