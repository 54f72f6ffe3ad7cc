/* wide_predict.c: the wide BVH's cost model: its counters per ray
 * predicted from the built tree, without tracing (wide.h wide_predict).
 *
 * The surface-area argument (J. D. MacDonald and K. S. Booth, "Heuristics
 * for ray tracing using space subdivision", The Visual Computer 6(3),
 * 1990; the survey's eq. (3) for Goldsmith and Salmon's hierarchies): of
 * the random lines that meet a convex body R, those that also meet a
 * convex body B inside it are the fraction A(B) / A(R) (Cauchy-Crofton:
 * the measure of the lines meeting a convex body is proportional to its
 * surface area). The walk visits the root and tests its used slots, and
 * every child whose slot box a line meets is visited (interior: its slots
 * tested) or tested (a leaf: its primitives), so per line that meets the
 * root's box R (the union of the root's slots):
 *   steps      = 1 + sum over slots below the root of P(slot)
 *   box_tests  = n(root) + sum over interior slots of P(slot) n(child)
 *   prim_tests = sum over leaf slots of P(slot) count(leaf)
 * with P(slot) = A(slot's box) / A(R) and n() a node's used slots: what
 * the counters count (docs/accels/wide-bvh.md). The model walks the whole
 * line: no hit ends it and no stacked entry is dropped, so it is an upper
 * bound for closest-hit and any-hit rays, exact in expectation only for
 * lines uniform over those meeting R and hitting nothing. Rays from one
 * point (primary, shadow) or from inside the scene are not such lines;
 * how far each workload departs is measured (the docs page). */
#include <stdlib.h>
#include "wide.h"

wide_prediction wide_predict(const wide_bvh *w)
{
    wide_prediction pr = {0.0, 0.0, 0.0};
    if (!w->nnodes) return pr;
    const uint32_t W = w->width;
    const bool Q = w->quantized;
    /* A root of zero area (every primitive in one point or on one line
     * segment of a plane): every line that meets it meets every box. */
    const double area = box_area(wide_bounds(w));
    /* Depth-first over the nodes, each pushed once, by its parent, with
     * the probability that a line meeting the root meets its box. */
    uint32_t *stack = malloc((size_t)w->nnodes * sizeof *stack), sp = 0;
    double *prob = malloc((size_t)w->nnodes * sizeof *prob);
    if (!stack || !prob) {
        free(stack);
        free(prob);
        return (wide_prediction){-1.0, -1.0, -1.0};
    }
    pr.steps = 1.0;
    prob[0] = 1.0;
    stack[sp++] = 0;
    while (sp) {
        const uint32_t ni = stack[--sp];
        const char *node = WIDE_NODE_AT(w->nodes, ni, W, Q);
        const uint32_t n = WIDE_NCHILDREN_Q(node, W, Q);
        const uint32_t *child = WIDE_CHILD_Q(node, W, Q);
        const uint8_t *count = WIDE_COUNT_Q(node, W, Q);
        pr.box_tests += prob[ni] * n;
        for (uint32_t k = 0; k < n; k++) {
            const double p = area > 0.0 ? box_area(wide_node_slot_box(w, ni, k)) / area : 1.0;
            pr.steps += p;
            if (child[k] & WIDE_LEAF) {
                pr.prim_tests += p * count[k];
            } else {
                prob[child[k]] = p;
                stack[sp++] = child[k];
            }
        }
    }
    free(prob);
    free(stack);
    return pr;
}
