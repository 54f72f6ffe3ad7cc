/* build_gs.h: Goldsmith and Salmon's insertion builder one step at a time
 * (build_gs.c). Accelerators call nary_build_gs() (nary.h); this header is
 * for the tests, which build a tree by hand, insert into it and read the
 * cost, and for build_gs.c itself.
 *
 * The working tree is linked (children as a list), so that an insertion
 * anywhere costs no moves; gs_finish() lays it out as nary.h's contiguous
 * breadth-first array. Memory: gs_node 48 bytes, at most 2n - 1 of them
 * over n primitives; the search's pending list 16 bytes an entry, at most
 * one entry per node. */
#ifndef ACCELBENCH_BVH_BUILD_GS_H
#define ACCELBENCH_BVH_BUILD_GS_H

#include "nary.h"

#define GS_NONE UINT32_MAX

typedef struct {
    box3 box;          /* 24: bounds of everything below */
    uint32_t prim;     /* leaf: its primitive; interior: GS_NONE */
    uint32_t parent;   /* GS_NONE at the root */
    uint32_t first;    /* interior: first child (GS_NONE while it has none) */
    uint32_t last;     /* interior: last child, where a new child is appended */
    uint32_t next;     /* the next sibling, GS_NONE for the last */
    uint32_t nchildren;
} gs_node;
static_assert(sizeof(gs_node) == 48, "gs_node is 48 bytes");

typedef struct {
    uint32_t node;
    double inherited; /* what the ancestors' growth adds: sum of their children x their area increase */
} gs_pending;

typedef struct {
    gs_node *nodes;
    uint32_t nnodes, cap;
    uint32_t root;           /* GS_NONE while empty */
    const box3 *boxes;       /* boxes[prim] */
    nary_gs_config cfg;
    gs_pending *pending;     /* the search's nodes still to look at */
    uint32_t npending, pending_cap;
    uint64_t tie_descents;   /* children of a tie queued for the search beyond the first, over every insertion */
} gs_builder;

/* Room for the tree over n boxes (2n - 1 nodes; more are allocated when a
 * hand-made tree needs them). 0, or -1 out of memory. */
int gs_builder_init(gs_builder *b, const box3 *boxes, uint32_t n, const nary_gs_config *cfg);
void gs_builder_free(gs_builder *b);

/* Hand construction (tests): a leaf of primitive prim, or an empty
 * interior node, appended as the last child of parent (GS_NONE: it becomes
 * the root, which must not exist yet). A leaf's box grows its ancestors'.
 * Returns the node, or GS_NONE out of memory. */
uint32_t gs_add_leaf(gs_builder *b, uint32_t parent, uint32_t prim);
uint32_t gs_add_interior(gs_builder *b, uint32_t parent);

/* Insert primitive prim (build_gs.c says where it goes). *increase: what
 * gs_cost() grew by, as the search computed it. 0, or -1 out of memory
 * (the tree is then unchanged). */
int gs_insert(gs_builder *b, uint32_t prim, double *increase);
/* Goldsmith and Salmon's cost, unnormalised: the sum over interior nodes
 * of surface area x children (eq. (3) times S(root), every test costing 1). */
double gs_cost(const gs_builder *b);
/* The surface area the builder uses: in double, from the float box. */
double gs_area(box3 b);
/* Lay the tree out breadth-first into *t (nary.h). 0, or -1 out of memory
 * (*t empty). The builder is unchanged. */
int gs_finish(const gs_builder *b, nary_t *t);

#endif
