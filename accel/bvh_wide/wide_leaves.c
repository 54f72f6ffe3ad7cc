/* wide_leaves.c: the wide BVH's all-triangle leaves packed (wide.h
 * wide_pack_leaves): each such leaf's triangles copied by prims/ into
 * ceil(count / 4) SoA packets next to each other, so a leaf visit reads
 * its corners from one place instead of through primitive, triangle and
 * vertex indices, and the watertight test sets the ray up once per leaf. */
#include <stdlib.h>
#include <string.h>
#include "../common/big_alloc.h"
#include "wide.h"

/* Slot k of node i: its child word and its count. */
static uint32_t *slot_child(wide_bvh *w, uint32_t i, uint32_t k, uint32_t *count)
{
    char *n = WIDE_NODE_AT(w->nodes, i, w->width, w->quantized);
    *count = WIDE_COUNT_Q(n, w->width, w->quantized)[k];
    return &WIDE_CHILD_Q(n, w->width, w->quantized)[k];
}

static uint32_t node_children(const wide_bvh *w, uint32_t i)
{
    return WIDE_NCHILDREN_Q(WIDE_NODE_AT(w->nodes, i, w->width, w->quantized), w->width, w->quantized);
}

uint64_t wide_count_packets(const wide_bvh *w, const prims_t *p)
{
    uint64_t n = 0;
    for (uint32_t i = 0; i < w->nnodes; i++)
        for (uint32_t k = 0; k < node_children(w, i); k++) {
            uint32_t count, *c = slot_child((wide_bvh *)w, i, k, &count);
            if ((*c & WIDE_LEAF) && !(*c & WIDE_PACKED) && prim_all_triangles(p, w->refs + (*c & WIDE_INDEX), count))
                n += prim_tri_packets(count);
        }
    return n;
}

int wide_pack_leaves(wide_bvh *w, const prims_t *p)
{
    uint64_t total = wide_count_packets(w, p);
    if (!total) return 0;
    if (total > WIDE_INDEX) return -1; /* first packets must fit the child word */
    prim_tri_packet *pk = big_alloc((size_t)total * sizeof *pk); /* 64-byte aligned, huge pages when large */
    if (!pk) return -1;
    uint32_t next = 0;
    for (uint32_t i = 0; i < w->nnodes; i++)
        for (uint32_t k = 0; k < node_children(w, i); k++) {
            uint32_t count, *c = slot_child(w, i, k, &count);
            const uint32_t *ids = w->refs + (*c & WIDE_INDEX);
            if (!(*c & WIDE_LEAF) || (*c & WIDE_PACKED) || !prim_all_triangles(p, ids, count)) continue;
            prim_tri_pack(p, ids, count, pk + next);
            *c = WIDE_LEAF | WIDE_PACKED | next;
            next += prim_tri_packets(count);
        }
    w->packets = pk;
    w->npackets = next;
    return 0;
}
