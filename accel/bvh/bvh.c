/* bvh.c: the tree's bookkeeping (bvh.h): freeing, memory, bounds,
 * statistics, SAH cost, the consistency check of the tests, and the
 * per-context traversal scratch. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "bvh.h"

void bvh_free(bvh_t *b)
{
    free(b->nodes);
    free(b->refs);
    memset(b, 0, sizeof *b);
}

size_t bvh_memory(const bvh_t *b) { return (size_t)b->nnodes * sizeof(bvh_node) + (size_t)b->nrefs * sizeof(uint32_t); }

box3 bvh_bounds(const bvh_t *b) { return b->nnodes ? b->nodes[0].box : box_empty(); }

int bvh_stats(const bvh_t *b, uint32_t nprims, accel_stat *out, int max)
{
    accel_stat all[] = {
        {"nodes", (double)(b->nnodes - b->nleaves)},
        {"leaves", (double)b->nleaves},
        {"max_depth", (double)b->max_depth},
        {"avg_leaf_prims", b->nleaves ? (double)b->nrefs / b->nleaves : 0.0},
        {"refs_per_prim", nprims ? (double)b->nrefs / nprims : 0.0},
    };
    int n = (int)(sizeof all / sizeof all[0]);
    if (n > max) n = max;
    memcpy(out, all, (size_t)(n > 0 ? n : 0) * sizeof *out);
    return n;
}

double bvh_sah_cost(const bvh_t *b, double ct, double ci)
{
    double root = b->nnodes ? box_area(b->nodes[0].box) : 0.0, sum = 0.0;
    if (!(root > 0.0)) return 0.0;
    for (uint32_t i = 0; i < b->nnodes; i++) {
        const bvh_node *n = &b->nodes[i];
        sum += (n->count ? ci * n->count : ct) * box_area(n->box);
    }
    return sum / root;
}

static bool box_contains(box3 outer, box3 inner)
{
    return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z &&
           outer.hi.x >= inner.hi.x && outer.hi.y >= inner.hi.y && outer.hi.z >= inner.hi.z;
}

int bvh_check(const bvh_t *b, const box3 *boxes, uint32_t n, char *err, size_t errlen)
{
    if (!n) {
        if (b->nnodes || b->nrefs) return snprintf(err, errlen, "empty input, %u nodes", b->nnodes), -1;
        return 0;
    }
    if (b->nrefs != n) return snprintf(err, errlen, "%u refs for %u primitives", b->nrefs, n), -1;
    uint8_t *seen_prim = calloc(n, 1), *seen_node = calloc(b->nnodes, 1);
    /* Each node is expanded once, so at most 2 nnodes + 1 (node, depth) pairs are pushed, even for a broken tree. */
    uint32_t *stack = malloc(2 * (2 * (size_t)b->nnodes + 1) * sizeof *stack), sp = 0, leaves = 0, depth_max = 0;
    int rc = 0;
    if (!seen_prim || !seen_node || !stack) {
        snprintf(err, errlen, "out of memory");
        rc = -1;
        goto out;
    }
    stack[sp++] = 0, stack[sp++] = 0;
    while (sp && rc == 0) {
        uint32_t depth = stack[--sp], ni = stack[--sp];
        if (ni >= b->nnodes || seen_node[ni]++) {
            snprintf(err, errlen, "node %u out of range or reached twice", ni);
            rc = -1;
            break;
        }
        const bvh_node *node = &b->nodes[ni];
        if (node->count) {
            leaves++;
            depth_max = depth > depth_max ? depth : depth_max;
            if ((uint64_t)node->index + node->count > b->nrefs) {
                snprintf(err, errlen, "leaf %u refs [%u, +%u) past %u", ni, node->index, node->count, b->nrefs);
                rc = -1;
            }
            for (uint32_t k = 0; k < node->count && rc == 0; k++) {
                uint32_t id = b->refs[node->index + k];
                if (id >= n || seen_prim[id]++) snprintf(err, errlen, "primitive %u out of range or in two leaves", id), rc = -1;
                else if (!box_contains(node->box, boxes[id])) snprintf(err, errlen, "leaf %u does not contain primitive %u", ni, id), rc = -1;
            }
            continue;
        }
        if ((uint64_t)node->index + 1 >= b->nnodes) {
            snprintf(err, errlen, "node %u children %u past %u", ni, node->index, b->nnodes);
            rc = -1;
            break;
        }
        for (uint32_t k = 0; k < 2; k++) {
            if (!box_contains(node->box, b->nodes[node->index + k].box)) {
                snprintf(err, errlen, "node %u does not contain its child %u", ni, node->index + k);
                rc = -1;
            }
            stack[sp++] = node->index + k, stack[sp++] = depth + 1;
        }
    }
    if (rc == 0) {
        for (uint32_t i = 0; i < b->nnodes && rc == 0; i++)
            if (!seen_node[i]) snprintf(err, errlen, "node %u is unreachable", i), rc = -1;
        if (rc == 0 && (leaves != b->nleaves || depth_max != b->max_depth))
            snprintf(err, errlen, "%u leaves, depth %u; the tree says %u, %u", leaves, depth_max, b->nleaves, b->max_depth), rc = -1;
    }
out:
    free(seen_prim);
    free(seen_node);
    free(stack);
    return rc;
}

int bvh_scratch_init(bvh_scratch *s, const bvh_t *b)
{
    s->stack_cap = b->max_depth + 1;
    s->stack = malloc((size_t)s->stack_cap * sizeof *s->stack);
    if (!s->stack || minheap_init(&s->heap, 2 * s->stack_cap)) {
        free(s->stack);
        s->stack = NULL;
        return -1;
    }
    return 0;
}

void bvh_scratch_free(bvh_scratch *s)
{
    free(s->stack);
    s->stack = NULL;
    minheap_free(&s->heap);
}
