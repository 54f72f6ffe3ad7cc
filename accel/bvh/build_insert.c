/* build_insert.c: incremental insertion in the manner of Goldsmith and
 * Salmon, "Automatic Creation of Object Hierarchies for Ray Tracing", IEEE
 * CG&A 7(5), 1987 (bvh.h).
 *
 * Goldsmith and Salmon estimate a hierarchy's cost as the sum, over its
 * interior nodes, of the node's surface area (the chance that a ray meets
 * it) times its number of children (the boxes tested once it is met). They
 * insert the objects one at a time, each going down from the root along the
 * path of least cost increase, and stopping where making it a new child is
 * cheapest. In this binary tree "a new child of X" becomes "a new parent P
 * of X and the object" (P has 2 children), so with A() the area and B the
 * new box, at node X reached with inherited increase I (the growth of the
 * boxes above X):
 *   here:          I + 2 A(X u B)                  (P's cost)
 *   below, in C:   I + 2 (A(X u B) - A(X)) + least(C)
 * where X grows in the second case and least(C) is the least that putting
 * B under child C can add: 2 A(C u B) for a leaf (a new parent above it),
 * 2 (A(C u B) - A(C)) + 2 A(B) for an interior node (C grows, and a new
 * parent no smaller than B appears below it). The insertion descends into
 * the child of smaller bound while that bound is below "here", growing each
 * box on the way; a leaf is never entered. Choosing the child by its
 * growth, not by the size of C u B, is what sends a box that lies inside a
 * large child into it; choosing by size sends it to the smaller sibling,
 * which then grows over the other one and the tree fills with overlapping
 * siblings (on the bunny, ten times the SAH cost). The paper's objects are
 * its leaves; here each leaf holds one primitive.
 *
 * The tree depends on the insertion order (the paper studies the effect
 * of the order): id order by default, or a shuffle by cfg->insert_seed. Each insertion costs the
 * depth of the path, O(n log n) for reasonable orders, O(n^2) at worst.
 *
 * Coincident boxes (cfg->insert_rep, accel/common/coincident.h): a copy of
 * a primitive already in the tree goes under a new parent next to the
 * class's latest leaf, in O(1); descending for it would walk the chain its
 * earlier copies made (each one's "here" ties with going below), which is
 * quadratic on a mesh of repeated faces. */
#include <stdlib.h>
#include "../common/shuffle.h"
#include "build.h"

static inline double area_with(box3 a, box3 b) { return box_area(box_union(a, b)); }

/* The least that putting box bb somewhere under node k can add: a new
 * parent above a leaf costs 2 A(k u bb); an interior node grows (its 2
 * children are tested over the extra area) and a new parent of area at
 * least A(bb) appears somewhere below it. */
static double least_below(const bvh_node *k, box3 bb)
{
    double grown = area_with(k->box, bb);
    return k->count ? 2.0 * grown : 2.0 * (grown - box_area(k->box)) + 2.0 * box_area(bb);
}

/* Put leaf (refs slot r, box bb) next to node x: x moves to a fresh pair
 * with the leaf, and x's slot becomes their parent. */
static void insert_at(bvh_t *b, uint32_t x, uint32_t r, box3 bb)
{
    uint32_t a = b->nnodes;
    b->nnodes += 2;
    b->nodes[a] = b->nodes[x];
    b->nodes[a + 1] = (bvh_node){bb, r, 1};
    b->nodes[x] = (bvh_node){box_union(b->nodes[a].box, bb), a, 0};
}

int bvh_build_insert(bvh_t *b, const box3 *boxes, const vec3 *centroids, uint32_t n, const bvh_config *cfg)
{
    (void)centroids; /* the cost sees boxes only */
    if (bvh_alloc(b, n)) return -1;
    if (!n) return 0;
    bvh_config c = bvh_config_or_defaults(cfg);
    for (uint32_t i = 0; i < n; i++) b->refs[i] = i;
    if (c.insert_seed) shuffle_ids(b->refs, n, c.insert_seed);
    b->nrefs = n;
    b->nodes[0] = (bvh_node){boxes[b->refs[0]], 0, 1};
    b->nnodes = 1;
    /* With coincident classes: the leaf of each class's latest member. */
    const uint32_t *rep = c.insert_rep;
    uint32_t *at = rep ? malloc((size_t)n * sizeof *at) : NULL;
    if (rep && !at) return -1;
    for (uint32_t i = 0; at && i < n; i++) at[i] = UINT32_MAX;
    if (at) at[rep[b->refs[0]]] = 0;
    for (uint32_t r = 1; r < n; r++) {
        box3 bb = boxes[b->refs[r]];
        uint32_t x = 0;
        if (at) {
            /* A copy goes next to the class's leaf, still a leaf of that class
             * (another insertion may have put a parent in its slot). */
            uint32_t k = rep[b->refs[r]], l = at[k];
            at[k] = b->nnodes + 1; /* the leaf insert_at makes */
            if (l != UINT32_MAX && b->nodes[l].count && rep[b->refs[b->nodes[l].index]] == k) {
                insert_at(b, l, r, bb);
                continue;
            }
        }
        double inherited = 0.0;
        for (;;) {
            bvh_node *node = &b->nodes[x];
            if (node->count) break; /* a leaf: the new parent goes above it */
            double grown = area_with(node->box, bb);
            double here = inherited + 2.0 * grown;
            double below = inherited + 2.0 * (grown - box_area(node->box));
            const bvh_node *kid = &b->nodes[node->index];
            double cl = below + least_below(&kid[0], bb), cr = below + least_below(&kid[1], bb);
            if (here <= (cl < cr ? cl : cr)) break;
            node->box = box_union(node->box, bb);
            x = node->index + (cr < cl);
            inherited = below;
        }
        insert_at(b, x, r, bb);
    }
    free(at);
    return bvh_finish(b);
}
