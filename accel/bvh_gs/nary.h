/* nary.h: an n-ary bounding volume hierarchy whose leaves are single
 * primitives: the general hierarchy of the survey (J. Arvo, D. Kirk, "A
 * Survey of Ray Tracing Acceleration Techniques", 1989, s4 and figure 3:
 * "a tree ... with an arbitrary branching factor at each internal node ...
 * Each leaf node of the tree is a single primitive object while each
 * interior node consists of a bounding volume and a list of pointers to
 * other nodes"), as Goldsmith and Salmon's builder makes it (build_gs.c,
 * accel/bvh_gs/bvh_goldsmith_salmon.c). bvh.h's binary tree with multi-primitive
 * leaves cannot hold it: a node here has any number of children, mixing
 * boxes and primitives.
 *
 * Memory layout:
 *   nodes[nnodes]  nary_node, 32 bytes: box (24), index (4), count (4).
 *                  count > 0: an interior node whose children are
 *                  nodes[index .. index + count), contiguous, in the order
 *                  the builder stored them (the order `traverse=stored`
 *                  visits). count == 0: a leaf; index is its primitive id
 *                  and box that primitive's bounds (used by the builder,
 *                  never tested while tracing: eq. (3) charges a
 *                  primitive's own test, not a box around it). nodes[0] is
 *                  the root (a leaf when there is one primitive); an empty
 *                  tree has nnodes == 0. Nodes are in breadth-first order.
 *   Total = 32 nnodes (nary_memory()), nnodes = primitives + interior
 *   nodes; every interior node has at least two children, so at most
 *   2 primitives - 1 nodes.
 *   Per context (nary_scratch): a stack of 8-byte entries (tstack_entry),
 *   stack_need of them: the most the depth-first traversal can hold on this
 *   tree (the children of every node on a root-to-leaf path, less the ones
 *   already taken), so it cannot overflow.
 *
 * The estimated cost (survey s4.2, equation (3)): with S() the surface
 * area and EC = 1 for every box and every primitive,
 *   IC(A) = sum over children B of A { EC(B) + S(B)/S(A) IC(B) },
 * IC(primitive) = 0. Unrolled from the root R, a ray that hits R costs
 * EC(R) + IC(R) = 1 + sum over interior A of S(A)/S(R) (children of A),
 * which nary_predict() splits into box tests (the root, and the interior
 * children of every interior A) and primitive tests (the leaf children).
 * The conditional probability S(A)/S(R) (eq. (2)) holds for random lines
 * that hit R; a ray set whose rays do not all hit the root, or are not
 * spread evenly over directions (eye rays from one point, shadow rays to
 * one light), is where the measured counts part from it.
 *
 * Traversals (nary_traverse.c): depth-first with an explicit stack, the
 * ray's distance interval [tnear, closest hit so far] shrinking with every
 * hit (survey s4, figure 4: a box entered beyond the closest hit is not
 * opened).
 *   stored   survey figure 3: a node's children in stored order, each box
 *            tested when its turn comes (so against the interval as it is
 *            then), each primitive tested when its turn comes.
 *   nearest  a node's primitive children first (in stored order: they are
 *            tested in either order, and a hit among them shrinks the
 *            interval before the boxes are tested), then its box children
 *            tested at once and opened nearest entry first; a stacked box
 *            whose entry lies beyond the closest hit by the time it is
 *            popped is dropped.
 * Each comes as intersect and occluded, counting and counting-free
 * (_fast), one body compiled four ways (as traverse.c).
 *
 * Counters: box_tests = boxes tested (the root once per ray, then every
 * box child of every interior node opened; the same count the prediction
 * makes, up to the pruning); steps = nodes visited (interior nodes opened
 * and leaves whose primitive is tested; a stacked node dropped by its
 * entry distance is not a step); prim_tests and prim_hits by prims/. No
 * empty leaves, no mailboxes (each primitive is in exactly one leaf).
 * Box tests are slab_clip_robust() (accel/common/slab.h). */
#ifndef ACCELBENCH_BVH_NARY_H
#define ACCELBENCH_BVH_NARY_H

#include <assert.h>
#include <stdbool.h>
#include <stdint.h>
#include "../accel.h"
#include "../common/stack.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    box3 box;       /* 24 bytes: bounds of everything below */
    uint32_t index; /* interior: first child; leaf: the primitive id */
    uint32_t count; /* interior: children (>= 2); leaf: 0 */
} nary_node;
static_assert(sizeof(nary_node) == 32, "nary_node is 32 bytes: two to a cache line");

typedef struct {
    nary_node *nodes;     /* [nnodes], nodes[0] the root, breadth-first */
    uint32_t nnodes;
    uint32_t nleaves;     /* leaves = primitives */
    uint32_t max_depth;   /* deepest leaf, root = 0 */
    uint32_t max_children;/* the widest interior node */
    uint32_t stack_need;  /* stack entries a traversal needs at most (see the header) */
} nary_t;

void nary_free(nary_t *t);
/* Bytes held: 32 nnodes. */
size_t nary_memory(const nary_t *t);
/* The box of everything (empty for an empty tree). */
box3 nary_bounds(const nary_t *t);

/* Equation (3) per ray that hits the root (header): box tests and
 * primitive tests; and by the same probabilities the steps (each interior
 * node opened, each leaf's primitive tested). An empty tree predicts 0; a
 * root of zero area (every primitive in one point) gives every node
 * probability 1. */
typedef struct {
    double box_tests, prim_tests, steps;
} nary_prediction;
nary_prediction nary_predict(const nary_t *t);

/* The accelerator statistics (accel.h): nodes (interior), leaves,
 * max_depth, avg_leaf_prims (1), refs_per_prim (1), avg_children,
 * predicted_box_tests_per_ray, predicted_tests_per_ray,
 * predicted_steps_per_ray. Returns how many it
 * wrote (at most max). */
int nary_stats(const nary_t *t, uint32_t nprims, accel_stat *out, int max);

/* After the nodes are filled (nodes, nnodes): leaves, depth, widest node
 * and stack_need, from a walk of the tree. 0, or -1 out of memory. */
int nary_measure(nary_t *t);
/* For tests: every primitive 0..n-1 in exactly one leaf, every node
 * reachable once, every box containing its children's and its primitive's
 * boxes[], no node over max_children children (0: no bound), and the
 * measured fields right. 0, or -1 with the first failure in err. */
int nary_check(const nary_t *t, const box3 *boxes, uint32_t n, uint32_t max_children, char *err, size_t errlen);

/* Per-context traversal scratch: the stack (stack_need entries). */
typedef struct {
    tstack_entry *stack;
    uint32_t cap;
} nary_scratch;
/* 0, or -1 out of memory. */
int nary_scratch_init(nary_scratch *s, const nary_t *t);
void nary_scratch_free(nary_scratch *s);

/* Traversals. The accel.h contract: closest hit in [tnear, hit->t) with
 * hit starting as hit_none(ray), returns whether it hit; any hit in
 * [tnear, tfar). s may be NULL: the stack is then NARY_STACK_LOCAL entries
 * on the C stack, and a tree that needs more is finished by testing every
 * primitive whose leaf box the ray meets (exact, counted, slower). */
#define NARY_STACK_LOCAL 128
bool nary_intersect_stored(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray, hit_t *hit, counters_t *c);
bool nary_occluded_stored(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray, counters_t *c);
bool nary_intersect_nearest(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray, hit_t *hit, counters_t *c);
bool nary_occluded_nearest(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray, counters_t *c);
/* The same with no counter writes, answers bit-identical. */
bool nary_intersect_stored_fast(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray, hit_t *hit);
bool nary_occluded_stored_fast(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray);
bool nary_intersect_nearest_fast(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray, hit_t *hit);
bool nary_occluded_nearest_fast(const nary_t *t, const prims_t *p, nary_scratch *s, const ray_t *ray);

/* ------------------------------------------------------------ builder */

/* Goldsmith and Salmon's insertion builder over boxes (build_gs.c says
 * how). order[0 .. n) is the insertion order (a permutation of 0..n-1;
 * NULL: id order); max_children bounds every node's children (0: no bound,
 * as the paper; else at least 2). 0, or -1 out of memory with *t empty. */
typedef struct {
    uint32_t max_children;
    bool ties_first_only; /* ablation and tests: on a tie, descend the first minimal child only */
    /* rep[i]: the coincident class of box i (accel/common/coincident.h), or
     * NULL. A box of a class already in the tree joins it (build_gs.c)
     * instead of searching: every node contains a copy's box, so the
     * search's ties would send it down the whole tree. */
    const uint32_t *rep;
} nary_gs_config;
int nary_build_gs(nary_t *t, const box3 *boxes, const uint32_t *order, uint32_t n, const nary_gs_config *cfg);
/* Bytes the builder holds at most while building over n boxes, the
 * finished tree included (for memory caps). */
uint64_t nary_build_gs_bytes(uint32_t n);

#ifdef __cplusplus
}
#endif

#endif
