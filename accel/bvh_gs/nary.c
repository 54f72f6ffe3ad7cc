/* nary.c: the n-ary tree's bookkeeping (nary.h): freeing, memory, bounds,
 * equation (3), statistics, the measuring walk, the consistency check of
 * the tests, and the per-context traversal scratch. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "build_gs.h"
#include "nary.h"

void nary_free(nary_t *t)
{
    free(t->nodes);
    memset(t, 0, sizeof *t);
}

size_t nary_memory(const nary_t *t) { return (size_t)t->nnodes * sizeof(nary_node); }

box3 nary_bounds(const nary_t *t) { return t->nnodes ? t->nodes[0].box : box_empty(); }

nary_prediction nary_predict(const nary_t *t)
{
    nary_prediction p = {0.0, 0.0, 0.0};
    if (!t->nnodes) return p;
    const nary_node *root = &t->nodes[0];
    if (!root->count) { /* one primitive: tested without a box, one step */
        p.prim_tests = p.steps = 1.0;
        return p;
    }
    double sroot = gs_area(root->box);
    p.box_tests = 1.0; /* EC(root): the root box, for every ray */
    for (uint32_t i = 0; i < t->nnodes; i++) {
        const nary_node *a = &t->nodes[i];
        if (!a->count) continue;
        /* S(A)/S(root): the chance a ray that hits the root hits A (eq. (2)). */
        double prob = sroot > 0.0 ? gs_area(a->box) / sroot : 1.0;
        uint32_t boxes = 0;
        for (uint32_t k = 0; k < a->count; k++) boxes += t->nodes[a->index + k].count != 0;
        p.box_tests += prob * boxes;
        p.prim_tests += prob * (a->count - boxes);
        p.steps += prob; /* A opened */
    }
    p.steps += p.prim_tests; /* each leaf whose primitive is tested is a step */
    return p;
}

int nary_stats(const nary_t *t, uint32_t nprims, accel_stat *out, int max)
{
    uint32_t interior = t->nnodes - t->nleaves;
    nary_prediction p = nary_predict(t);
    accel_stat all[] = {
        {"nodes", (double)interior},
        {"leaves", (double)t->nleaves},
        {"max_depth", (double)t->max_depth},
        {"avg_leaf_prims", t->nleaves ? 1.0 : 0.0},
        {"refs_per_prim", nprims ? (double)t->nleaves / nprims : 0.0},
        {"avg_children", interior ? (double)(t->nnodes - 1) / interior : 0.0},
        {"predicted_box_tests_per_ray", p.box_tests},
        {"predicted_tests_per_ray", p.prim_tests},
        {"predicted_steps_per_ray", p.steps},
    };
    int n = (int)(sizeof all / sizeof all[0]);
    if (n > max) n = max;
    memcpy(out, all, (size_t)(n > 0 ? n : 0) * sizeof *out);
    return n;
}

int nary_measure(nary_t *t)
{
    t->nleaves = t->max_depth = t->max_children = 0;
    t->stack_need = t->nnodes ? 1 : 0;
    if (!t->nnodes) return 0;
    /* Depth-first with (node, depth, entries below it on the traversal's
     * stack when it is popped): every node is pushed once, so nnodes
     * triples at most. */
    uint32_t *st = malloc(3 * (size_t)t->nnodes * sizeof *st), n = 0;
    if (!st) return -1;
    st[n++] = 0, st[n++] = 0, st[n++] = 0;
    while (n) {
        uint32_t below = st[--n], depth = st[--n], ni = st[--n];
        const nary_node *node = &t->nodes[ni];
        if (!node->count) {
            t->nleaves++;
            if (depth > t->max_depth) t->max_depth = depth;
            continue;
        }
        if (node->count > t->max_children) t->max_children = node->count;
        /* Popping node leaves `below`; its children go on top, and while
         * the first of them is worked on the other count - 1 wait. */
        if (below + node->count > t->stack_need) t->stack_need = below + node->count;
        for (uint32_t k = 0; k < node->count; k++)
            st[n++] = node->index + k, st[n++] = depth + 1, st[n++] = below + node->count - 1;
    }
    free(st);
    return 0;
}

static bool box_contains(box3 outer, box3 inner)
{
    if (box_is_empty(inner)) return true;
    return outer.lo.x <= inner.lo.x && outer.lo.y <= inner.lo.y && outer.lo.z <= inner.lo.z &&
           outer.hi.x >= inner.hi.x && outer.hi.y >= inner.hi.y && outer.hi.z >= inner.hi.z;
}

int nary_check(const nary_t *t, const box3 *boxes, uint32_t n, uint32_t max_children, char *err, size_t errlen)
{
    if (!n) {
        if (t->nnodes) return snprintf(err, errlen, "empty input, %u nodes", t->nnodes), -1;
        return 0;
    }
    uint8_t *seen_prim = calloc(n, 1), *seen_node = calloc(t->nnodes, 1);
    int rc = 0;
    if (!seen_prim || !seen_node) {
        snprintf(err, errlen, "out of memory");
        rc = -1;
    }
    /* Every node but the root is the child of exactly one node. */
    if (rc == 0 && t->nnodes) seen_node[0] = 1;
    for (uint32_t i = 0; i < t->nnodes && rc == 0; i++) {
        const nary_node *a = &t->nodes[i];
        if (!a->count) {
            if (a->index >= n || seen_prim[a->index]++) snprintf(err, errlen, "primitive %u out of range or in two leaves", a->index), rc = -1;
            else if (!box_contains(a->box, boxes[a->index])) snprintf(err, errlen, "leaf %u does not contain primitive %u", i, a->index), rc = -1;
            continue;
        }
        if (a->count < 2) snprintf(err, errlen, "interior node %u has %u child", i, a->count), rc = -1;
        else if (max_children && a->count > max_children) snprintf(err, errlen, "node %u has %u children, over %u", i, a->count, max_children), rc = -1;
        else if ((uint64_t)a->index + a->count > t->nnodes || a->index <= i)
            snprintf(err, errlen, "node %u children [%u, +%u) out of range", i, a->index, a->count), rc = -1;
        for (uint32_t k = 0; k < a->count && rc == 0; k++) {
            uint32_t c = a->index + k;
            if (seen_node[c]++) snprintf(err, errlen, "node %u reached twice", c), rc = -1;
            else if (!box_contains(a->box, t->nodes[c].box)) snprintf(err, errlen, "node %u does not contain its child %u", i, c), rc = -1;
        }
    }
    for (uint32_t i = 0; i < t->nnodes && rc == 0; i++)
        if (!seen_node[i]) snprintf(err, errlen, "node %u is unreachable", i), rc = -1;
    for (uint32_t i = 0; i < n && rc == 0; i++)
        if (!seen_prim[i]) snprintf(err, errlen, "primitive %u is in no leaf", i), rc = -1;
    if (rc == 0) {
        nary_t m = *t;
        if (nary_measure(&m)) snprintf(err, errlen, "out of memory"), rc = -1;
        else if (m.nleaves != t->nleaves || m.max_depth != t->max_depth || m.max_children != t->max_children ||
                 m.stack_need != t->stack_need)
            snprintf(err, errlen, "measured %u leaves, depth %u, width %u, stack %u; the tree says %u, %u, %u, %u",
                     m.nleaves, m.max_depth, m.max_children, m.stack_need, t->nleaves, t->max_depth, t->max_children,
                     t->stack_need), rc = -1;
    }
    free(seen_prim);
    free(seen_node);
    return rc;
}

int nary_scratch_init(nary_scratch *s, const nary_t *t)
{
    s->cap = t->stack_need ? t->stack_need : 1;
    s->stack = malloc((size_t)s->cap * sizeof *s->stack);
    return s->stack ? 0 : -1;
}

void nary_scratch_free(nary_scratch *s)
{
    free(s->stack);
    s->stack = NULL;
}
