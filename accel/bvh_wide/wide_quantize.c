/* wide_quantize.c: compress=on, the 8-wide tree's nodes with their
 * children's boxes quantised to 8 bits a plane (wide8q_node, wide.h), in
 * the style of H. Ylitie, T. Karras, S. Laine, "Efficient Incoherent Ray
 * Traversal on GPUs Through Compressed Wide BVHs", HPG 2017, section 3.1:
 * a node keeps its box's lower corner and a power-of-two scale per axis,
 * each child plane a byte of steps above the corner, lower planes rounded
 * down and upper ones up. Made from the finished tree, node by node, so the
 * builders, the collapse and the leaf packing stay as they are.
 *
 * Conservative by construction: every plane is chosen by decoding it
 * exactly as the kernels do (wide_q_plane) and checking the result against
 * the child's float plane, so a decoded box always contains the child's
 * box and the walk's robust box test keeps its guarantee. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../common/big_alloc.h"
#include "wide.h"

/* The smallest biased scale exponent whose 255 steps from origin reach hi
 * as the kernels decode them; 0 when none up to WIDE_Q_MAX_EXP does. */
static uint8_t scale_exp_for(float origin, float hi)
{
    const double steps = ((double)hi - (double)origin) / 255.0;
    int e = steps > 0.0 ? ilogb(steps) + 127 - 1 : 1; /* one below the estimate; the loop settles it */
    for (e = e < 1 ? 1 : e; e <= WIDE_Q_MAX_EXP; e++)
        if (wide_q_plane(origin, 255, (uint8_t)e) >= hi) return (uint8_t)e;
    return 0;
}

/* The largest q whose decoded plane is at most lo (q = 0 decodes to origin,
 * which is). */
static uint8_t quantize_lower(float origin, uint8_t e, float lo)
{
    double est = floor(((double)lo - (double)origin) / (double)wide_q_scale(e));
    int q = est < 0.0 ? 0 : est > 255.0 ? 255 : (int)est;
    while (q > 0 && wide_q_plane(origin, (uint8_t)q, e) > lo) q--;
    while (q < 255 && wide_q_plane(origin, (uint8_t)(q + 1), e) <= lo) q++;
    return (uint8_t)q;
}

/* The smallest q whose decoded plane is at least hi (q = 255 is, by the
 * choice of the scale). */
static uint8_t quantize_upper(float origin, uint8_t e, float hi)
{
    double est = ceil(((double)hi - (double)origin) / (double)wide_q_scale(e));
    int q = est < 0.0 ? 0 : est > 255.0 ? 255 : (int)est;
    while (q < 255 && wide_q_plane(origin, (uint8_t)q, e) < hi) q++;
    while (q > 0 && wide_q_plane(origin, (uint8_t)(q - 1), e) >= hi) q--;
    return (uint8_t)q;
}

static box3 decode_slot(const wide8q_node *nd, uint32_t k)
{
    float v[6];
    for (uint32_t r = 0; r < 6; r++) v[r] = wide_q_plane(nd->origin[r / 2], nd->q[r][k], nd->scale_exp[r / 2]);
    return (box3){{v[0], v[2], v[4]}, {v[1], v[3], v[5]}};
}

box3 wide_node_slot_box(const wide_bvh *w, uint32_t ni, uint32_t k)
{
    const char *node = WIDE_NODE_AT(w->nodes, ni, w->width, w->quantized);
    if (w->quantized) return decode_slot((const wide8q_node *)node, k);
    return wide_slot_box(WIDE_ROWS(node), w->width, k);
}

/* Node src (a wide8_node) as a quantised one; false when some axis of its
 * box is wider than the largest scale spans (that axis in *axis, its
 * extent in *span_lo, *span_hi). */
static bool quantize_node(const char *src, wide8q_node *dst, uint32_t *axis, float *span_lo, float *span_hi)
{
    const uint32_t n = WIDE_NCHILDREN(src, 8);
    box3 child[8], node = box_empty();
    for (uint32_t k = 0; k < n; k++) node = box_union(node, child[k] = wide_slot_box(WIDE_ROWS(src), 8, k));
    const float lo[3] = {node.lo.x, node.lo.y, node.lo.z}, hi[3] = {node.hi.x, node.hi.y, node.hi.z};
    memset(dst, 0, sizeof *dst);
    for (uint32_t ax = 0; ax < 3; ax++) {
        dst->origin[ax] = lo[ax];
        if (!(dst->scale_exp[ax] = scale_exp_for(lo[ax], hi[ax]))) {
            *axis = ax, *span_lo = lo[ax], *span_hi = hi[ax];
            return false;
        }
    }
    for (uint32_t k = 0; k < n; k++) {
        const float clo[3] = {child[k].lo.x, child[k].lo.y, child[k].lo.z};
        const float chi[3] = {child[k].hi.x, child[k].hi.y, child[k].hi.z};
        for (uint32_t ax = 0; ax < 3; ax++) {
            dst->q[2 * ax][k] = quantize_lower(dst->origin[ax], dst->scale_exp[ax], clo[ax]);
            dst->q[2 * ax + 1][k] = quantize_upper(dst->origin[ax], dst->scale_exp[ax], chi[ax]);
        }
    }
    dst->nchildren = (uint8_t)n;
    memcpy(dst->child, WIDE_CHILD(src, 8), sizeof dst->child);
    memcpy(dst->count, WIDE_COUNT(src, 8), sizeof dst->count);
    /* The octant orders of the boxes the walk sees: the decoded ones. */
    for (uint32_t k = 0; k < n; k++) child[k] = decode_slot(dst, k);
    wide_orders_of(child, n, 8, dst->order);
    return true;
}

int wide_quantize(wide_bvh *w, char *err, size_t errlen)
{
    if (w->width != 8 || w->quantized) {
        snprintf(err, errlen, "compress=on: quantised nodes are 8 wide (width=8)");
        return -1;
    }
    if (!w->nnodes) {
        w->quantized = true;
        return 0;
    }
    wide8q_node *q = big_alloc((size_t)w->nnodes * sizeof *q); /* 64-byte aligned, huge pages when large */
    if (!q) {
        snprintf(err, errlen, "compress=on: out of memory for %u quantised nodes", w->nnodes);
        return -1;
    }
    for (uint32_t i = 0; i < w->nnodes; i++) {
        uint32_t axis = 0;
        float lo = 0, hi = 0;
        if (!quantize_node(WIDE_NODE_AT(w->nodes, i, 8, false), &q[i], &axis, &lo, &hi)) {
            snprintf(err, errlen,
                     "compress=on: node %u spans %g to %g on %c, wider than 255 steps of the largest scale (2^%d) reach",
                     i, lo, hi, "xyz"[axis], WIDE_Q_MAX_EXP - 127);
            free(q);
            return -1;
        }
    }
    free(w->nodes);
    w->nodes = q;
    w->quantized = true;
    return 0;
}
