/* kd_tree.h: axis-orthogonal BSP trees (kd-trees) over prims/: the node
 * layout, the tree, and its two builders (the traversals are the
 * accelerator's, accel/bsp/bsp_kaplan_jansen.c).
 *
 * Builders (kd_build, by cfg->split):
 *   KD_SPLIT_MIDPOINT  Kaplan 1985 (survey of Arvo and Kirk 1989, s5.1):
 *                      the cell is cut at its spatial midpoint, the axes
 *                      taken in turn (x, y, z, x, ...; depth mod 3), and a
 *                      primitive goes to every child its SURFACE touches
 *                      (prim_overlaps_box on the child grown by pad). A cell
 *                      becomes a leaf with at most maxprims candidates
 *                      (coincident ones counted once: coincident.h), at
 *                      maxdepth, or when no axis halves into children
 *                      float coordinates there resolve (float_res.h; an
 *                      axis too narrow passes to the next). kd_midpoint.c.
 *   KD_SPLIT_SAH       the surface area heuristic with pbrt-v4's
 *                      KdTreeAggregate costs and termination, built by the
 *                      O(N log N) event sweep of Wald and Havran 2006, with
 *                      their "perfect splits" (primitives clipped to the
 *                      cell, prim_clip_bounds) as an option. kd_sah.c.
 *
 * The slack (both builders): a primitive that touches a child cell grown by
 * pad (2e-6 max|coordinate| + 1e-6 diagonal of the root cell, the uniform
 * grid's insertion slack, some 16 float ulps at the scene's scale) is in
 * that child. So one lying in, touching or passing within rounding of a
 * plane is on both sides, and a traversal whose float plane decisions put a
 * point a few ulps onto the wrong side still finds it there. This is what
 * makes the three traversals watertight on vertices lying exactly in split
 * planes (Kaplan's point location and Havran's TA^B_rec both visit only one
 * side of a plane the ray merely touches).
 *
 * Node layout (8 bytes, pbrt's KdTreeAggregate node): the children of an
 * interior node are explicit, as in Kaplan's BSP (survey s5.1: "the nodes
 * of the BSP tree are constructed with explicit pointers to their two
 * children"), but only one is stored: the nodes are in depth-first order,
 * so the below child (coordinates < split) is the next node and the above
 * child's index is in the node.
 *   interior: split (float, 4) | bits = above << 2 | axis (0, 1, 2)
 *   leaf:     first (uint32, 4) | bits = count << 2 | 3
 *             count == 1: first IS the primitive id (no indirection);
 *             otherwise ids[first .. first + count) (first = 0 if empty).
 * So at most 2^30 - 1 nodes and primitives per leaf (refused beyond).
 *
 * Memory layout of a tree: nodes[nnodes] (8 bytes each), ids[nids]
 * (uint32, the lists of the leaves with 2 or more primitives, each sorted
 * by id), the root cell box. kd_memory() counts the allocated capacity. */
#ifndef ACCELBENCH_KD_TREE_H
#define ACCELBENCH_KD_TREE_H

#include <assert.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "../../prims/prims.h"
#include "../common/line_model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The deepest tree a builder makes (root = depth 0). Traversal stacks are
 * sized by it; deeper trees cut cells below float resolution long before
 * (a cell halves per level: 24 levels per axis exhaust a float's mantissa). */
#define KD_MAX_DEPTH 64

typedef struct {
    union {
        float split;    /* interior: the plane coordinate on axis */
        uint32_t first; /* leaf: the primitive id (count 1) or offset into ids */
    };
    uint32_t bits; /* interior: above child << 2 | axis; leaf: count << 2 | 3 */
} kd_node;
static_assert(sizeof(kd_node) == 8, "kd_node is 8 bytes");

#define KD_LEAF 3u
#define KD_INDEX_MAX ((1u << 30) - 1u) /* largest above index or leaf count */

static inline bool kd_is_leaf(const kd_node *n) { return (n->bits & 3u) == KD_LEAF; }
static inline int kd_axis(const kd_node *n) { return (int)(n->bits & 3u); }
static inline uint32_t kd_above(const kd_node *n) { return n->bits >> 2; }
static inline uint32_t kd_count(const kd_node *n) { return n->bits >> 2; }

typedef struct {
    kd_node *nodes;
    uint32_t nnodes, nodes_cap;
    uint32_t *ids;
    size_t nids, ids_cap;
    box3 box;  /* the root cell: the primitives' bounds, a flat axis widened */
    float pad; /* the slack: a primitive within pad of a plane is on both sides */
    /* statistics of the build */
    uint32_t ninterior, nleaves, nempty, max_depth;
    uint64_t nrefs; /* primitive references over all leaves */
} kd_tree;

enum { KD_SPLIT_MIDPOINT = 0, KD_SPLIT_SAH = 1 };

typedef struct {
    int split;           /* KD_SPLIT_MIDPOINT | KD_SPLIT_SAH */
    int maxdepth;        /* 0..KD_MAX_DEPTH: 0 = one leaf */
    int maxprims;        /* a cell with at most this many candidates is a leaf */
    double isect_cost;   /* SAH: cost of one primitive test (pbrt-v4: 80) */
    double trav_cost;    /* SAH: cost of one traversal step (pbrt-v4: 1) */
    double empty_bonus;  /* SAH: cost discount for an empty child, 0..1 (pbrt-v4: 0.5) */
    bool perfect;        /* SAH: clip primitives to the cell (Wald-Havran perfect splits) */
    uint64_t memcap_mib; /* refuse a tree plus build scratch over this */
} kd_config;

/* pbrt-v4's default depth: round(8 + 1.3 Log2Int(N)), Log2Int the floor of
 * log2 (N < 2: 8). */
int kd_default_depth(uint64_t n);

/* Build over every primitive of p. 0, or -1 with a one-line reason (memcap
 * exceeded, more than 2^30 nodes, out of memory, bad config); t is then
 * empty (kd_free'd). */
int kd_build(kd_tree *t, const prims_t *p, const kd_config *cfg, char *err, size_t errlen);
void kd_free(kd_tree *t);
/* Bytes held: node and id arrays (allocated capacity). */
size_t kd_memory(const kd_tree *t);

/* The random-line model (common/line_model.h) over the leaves' cells:
 * leaves entered (.cells), candidates tested (.tests, counted once per
 * primitive with mailbox), root-to-leaf descents (.descents: the nodes a
 * sequential walk visits); *nodes_met gets the interior and leaf nodes
 * whose cells a line meets (what a recursive walk visits). Returns -1 when
 * the mailbox's scratch cannot be allocated (nothing written then). */
int kd_predict(const kd_tree *t, uint32_t nprims, bool mailbox, line_prediction *out, double *nodes_met);

/* The primitive list of a leaf: n ids at the returned pointer. */
static inline const uint32_t *kd_leaf_ids(const kd_tree *t, const kd_node *n, uint32_t *count)
{
    *count = kd_count(n);
    return *count == 1 ? &n->first : t->ids + n->first;
}

#ifdef __cplusplus
}
#endif

#endif
