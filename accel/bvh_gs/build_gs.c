/* build_gs.c: Goldsmith and Salmon's automatic hierarchy (J. Goldsmith,
 * J. Salmon, "Automatic Creation of Object Hierarchies for Ray Tracing",
 * IEEE CG&A 7(5), 1987), n-ary, one primitive a leaf (nary.h).
 *
 * The spec is the survey (Arvo and Kirk 1989, s4.2-4.3): "the hierarchy is
 * constructed incrementally, inserting the primitive objects into the
 * growing structure one at a time while striving to minimize the resulting
 * increases in the bounding volume surface areas. Each object is inserted
 * by beginning at the root of the tree and selecting the subtree which
 * would incur the smallest increase in surface area if the new object were
 * to become a child of it. This selection process continues until a leaf
 * of the tree is reached. In the case of a tie at any level, all minimal
 * subtrees are searched, and the one which ultimately produces the
 * smallest increase in the estimated cost of the tree is used."
 * The paper itself is not at hand; the three ways to place an object at a
 * node and what each adds to the cost are as Haines retells the paper
 * ("Automatic Creation of Object Hierarchies for Ray Tracing", Ray Tracing
 * News, an explanation of the May '87 paper), as a course page
 * summarises it ("Goldsmith Salmon Bounding hierarchies",
 * geocities.ws/prizmaweb/raytrace/298page2.html: "Method 1 ... cost
 * difference = 2 P(BV); Method 2 ... (P(BV') - P(BV)) k + P(BV'); Method
 * 3: try one of the above methods for child nodes ... (P(BV') - P(BV))
 * k"), and as Ericson, Real-Time Collision Detection (2005) s6.2.3.1
 * describes it (descend into the child of least surface-area increase;
 * "when a ray hits the root volume at least an additional k intersection
 * tests must be performed, where k is the number of children").
 *
 * The cost being minimised is eq. (3) with every test costing 1, times
 * S(root): C = sum over interior nodes A of S(A) k(A), k the number of
 * children (all the root's choices end in the same root box, so comparing
 * unnormalised increases is comparing eq. (3)'s). Inserting an object of
 * box b, a node V is reached with I, the sum over V's ancestors X of
 * k(X) (S(X u b) - S(X)), what their growth adds. At V:
 *   new parent:  V and the object become the two children of a new node
 *                P in V's place (V a leaf or not):  I + 2 S(V u b);
 *   sibling:     (V interior) the object becomes one more child of V:
 *                I + k(V) (S(V u b) - S(V)) + S(V u b);
 *   descend:     (V interior) into the child of least area increase
 *                S(C u b) - S(C), with I' = I + k(V) (S(V u b) - S(V));
 *                on a tie, into every child of that least increase.
 * The search keeps the cheapest placement met on every path it takes and
 * ends at leaves; a path whose I' alone is no cheaper than the best found
 * is cut (everything below it adds to I'), which changes no choice. The
 * first of equal costs wins (depth-first, children in stored order), so
 * the build is deterministic. Areas are in double from the float boxes
 * (gs_area), so an increase of 0 (a box inside a child) is exactly 0 and
 * ties between such children are ties.
 *
 * Branching factor: the survey and the retellings above give the paper's
 * cost no bound on k; the S(A) k(A) term is what keeps nodes narrow (a
 * sibling costs S(V u b) more for every ray entering V). `max_children`
 * (0 = none, the paper) forbids the sibling case at a full node.
 *
 * Costs: an insertion looks at the children of every node on its path(s):
 * O(depth x width) without ties; a tie over children that all contain the
 * box sends it down each, which is what s4.3 asks for.
 *
 * Coincident primitives (cfg->rep, accel/common/coincident.h): the copy of
 * a primitive already in the tree does not search, since every node holds
 * its box and the ties above would visit the whole tree (quadratic on a
 * mesh of repeated faces); it joins the first one's leaf under a new parent,
 * and later copies are that parent's children (a new parent over it when
 * max_children is reached). Without copies the build is unchanged. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "build_gs.h"

double gs_area(box3 b)
{
    if (box_is_empty(b)) return 0.0;
    double ex = (double)b.hi.x - b.lo.x, ey = (double)b.hi.y - b.lo.y, ez = (double)b.hi.z - b.lo.z;
    return 2.0 * (ex * ey + ey * ez + ez * ex);
}

int gs_builder_init(gs_builder *b, const box3 *boxes, uint32_t n, const nary_gs_config *cfg)
{
    memset(b, 0, sizeof *b);
    b->root = GS_NONE;
    b->boxes = boxes;
    if (cfg) b->cfg = *cfg;
    b->cap = n ? 2 * n - 1 : 1;
    b->nodes = malloc((size_t)b->cap * sizeof *b->nodes);
    b->pending_cap = 64;
    b->pending = malloc((size_t)b->pending_cap * sizeof *b->pending);
    if (!b->nodes || !b->pending) {
        gs_builder_free(b);
        return -1;
    }
    return 0;
}

void gs_builder_free(gs_builder *b)
{
    free(b->nodes);
    free(b->pending);
    memset(b, 0, sizeof *b);
    b->root = GS_NONE;
}

/* Room for `more` nodes beyond those in use. 0, or -1 out of memory. */
static int reserve(gs_builder *b, uint32_t more)
{
    if (b->cap - b->nnodes >= more) return 0;
    uint64_t cap = 2 * (uint64_t)b->cap + more;
    if (cap > UINT32_MAX - 1) return -1;
    gs_node *nodes = realloc(b->nodes, (size_t)cap * sizeof *nodes);
    if (!nodes) return -1;
    b->nodes = nodes;
    b->cap = (uint32_t)cap;
    return 0;
}

/* A node in reserved room. */
static uint32_t new_node(gs_builder *b, uint32_t prim, box3 box)
{
    uint32_t i = b->nnodes++;
    b->nodes[i] = (gs_node){box, prim, GS_NONE, GS_NONE, GS_NONE, GS_NONE, 0};
    return i;
}

/* x becomes the last child of p. */
static void append_child(gs_builder *b, uint32_t p, uint32_t x)
{
    gs_node *pn = &b->nodes[p];
    b->nodes[x].parent = p;
    b->nodes[x].next = GS_NONE;
    if (pn->last == GS_NONE) pn->first = x;
    else b->nodes[pn->last].next = x;
    pn->last = x;
    pn->nchildren++;
}

/* Node x and its ancestors grow over box. */
static void grow_up(gs_builder *b, uint32_t x, box3 box)
{
    for (; x != GS_NONE; x = b->nodes[x].parent) b->nodes[x].box = box_union(b->nodes[x].box, box);
}

static uint32_t add_node(gs_builder *b, uint32_t parent, uint32_t prim, box3 box)
{
    if ((parent == GS_NONE && b->root != GS_NONE) || reserve(b, 1)) return GS_NONE;
    uint32_t x = new_node(b, prim, box);
    if (parent == GS_NONE) b->root = x;
    else {
        append_child(b, parent, x);
        grow_up(b, parent, box);
    }
    return x;
}

uint32_t gs_add_leaf(gs_builder *b, uint32_t parent, uint32_t prim) { return add_node(b, parent, prim, b->boxes[prim]); }

uint32_t gs_add_interior(gs_builder *b, uint32_t parent) { return add_node(b, parent, GS_NONE, box_empty()); }

static int push_pending(gs_builder *b, uint32_t node, double inherited)
{
    if (b->npending == b->pending_cap) {
        uint32_t cap = b->pending_cap * 2;
        gs_pending *p = realloc(b->pending, (size_t)cap * sizeof *p);
        if (!p) return -1;
        b->pending = p;
        b->pending_cap = cap;
    }
    b->pending[b->npending++] = (gs_pending){node, inherited};
    return 0;
}

/* How much child k's area grows to take box bb in. */
static inline double growth(const gs_builder *b, uint32_t k, box3 bb)
{
    box3 kb = b->nodes[k].box;
    return gs_area(box_union(kb, bb)) - gs_area(kb);
}

typedef struct {
    double cost;     /* the increase of gs_cost() */
    uint32_t node;   /* where */
    bool sibling;    /* true: one more child of node; false: a new parent over node */
} placement;

/* The search of the header: the cheapest placement of box bb. 0, or -1
 * out of memory. */
static int search(gs_builder *b, box3 bb, placement *best)
{
    *best = (placement){INFINITY, GS_NONE, false};
    b->npending = 0;
    if (push_pending(b, b->root, 0.0)) return -1;
    while (b->npending) {
        gs_pending e = b->pending[--b->npending];
        if (!(e.inherited < best->cost)) continue; /* every placement at or below it adds more */
        const gs_node *v = &b->nodes[e.node];
        double with = gs_area(box_union(v->box, bb));
        /* New parent over v: two children over v u b. */
        double c = e.inherited + 2.0 * with;
        if (c < best->cost) *best = (placement){c, e.node, false};
        if (v->prim != GS_NONE) continue; /* a leaf ends the path */
        double below = e.inherited + (double)v->nchildren * (with - gs_area(v->box));
        /* Sibling: one more child of v, tested by every ray that enters v. */
        if (!b->cfg.max_children || v->nchildren < b->cfg.max_children) {
            c = below + with;
            if (c < best->cost) *best = (placement){c, e.node, true};
        }
        if (!(below < best->cost)) continue; /* nothing below v can add less than `below` */
        /* Descend into the children of least area increase, every one of them on a tie. */
        double least = INFINITY;
        for (uint32_t k = v->first; k != GS_NONE; k = b->nodes[k].next) least = fmin(least, growth(b, k, bb));
        uint32_t from = b->npending, tied = 0;
        for (uint32_t k = v->first; k != GS_NONE; k = b->nodes[k].next) {
            if (growth(b, k, bb) != least) continue;
            if (tied++ && b->cfg.ties_first_only) break;
            if (push_pending(b, k, below)) return -1;
        }
        if (tied > 1 && !b->cfg.ties_first_only) b->tie_descents += tied - 1;
        /* Popped last-in first-out: reverse, so the first child in stored order is searched first. */
        for (uint32_t i = from, j = b->npending; i + 1 < j; i++, j--) {
            gs_pending t = b->pending[i];
            b->pending[i] = b->pending[j - 1];
            b->pending[j - 1] = t;
        }
    }
    return 0;
}

/* Put prim where best says. 0, or -1 out of memory (the tree unchanged). */
static int place(gs_builder *b, uint32_t prim, placement best)
{
    box3 bb = b->boxes[prim];
    /* Either placement makes at most two nodes: room first, so a failure
     * leaves the tree as it was. */
    if (reserve(b, 2)) return -1;
    uint32_t v = best.node;
    if (best.sibling) {
        uint32_t leaf = new_node(b, prim, bb);
        append_child(b, v, leaf);
        grow_up(b, v, bb);
    } else {
        /* P takes v's place among its parent's children (or as the root), then holds v and the leaf. */
        uint32_t parent = b->nodes[v].parent;
        uint32_t p = new_node(b, GS_NONE, box_union(b->nodes[v].box, bb));
        uint32_t leaf = new_node(b, prim, bb);
        gs_node *pn = &b->nodes[p];
        pn->parent = parent;
        if (parent == GS_NONE) {
            b->root = p;
        } else {
            gs_node *par = &b->nodes[parent];
            pn->next = b->nodes[v].next;
            if (par->first == v) par->first = p;
            else {
                uint32_t k = par->first;
                while (b->nodes[k].next != v) k = b->nodes[k].next;
                b->nodes[k].next = p;
            }
            if (par->last == v) par->last = p;
            grow_up(b, parent, bb);
        }
        append_child(b, p, v);
        append_child(b, p, leaf);
    }
    return 0;
}

int gs_insert(gs_builder *b, uint32_t prim, double *increase)
{
    *increase = 0.0;
    if (b->root == GS_NONE) return gs_add_leaf(b, GS_NONE, prim) == GS_NONE ? -1 : 0;
    placement best;
    if (search(b, b->boxes[prim], &best) || place(b, prim, best)) return -1;
    *increase = best.cost;
    return 0;
}

/* A copy of a primitive already in the tree, whose node is *at: the leaf of
 * the first one (the copy and it get a new parent, which *at becomes) or
 * that parent (one more child of it; a new parent over it when it is
 * full). The search would find every node containing the copy's box and
 * tie on all of them; here a copy costs O(1). */
static int place_copy(gs_builder *b, uint32_t prim, uint32_t *at)
{
    const gs_node *g = &b->nodes[*at];
    bool sibling = g->prim == GS_NONE && (!b->cfg.max_children || g->nchildren < b->cfg.max_children);
    if (place(b, prim, (placement){0.0, *at, sibling})) return -1;
    if (!sibling) *at = b->nnodes - 2; /* the new parent (place made it just before the leaf) */
    return 0;
}

double gs_cost(const gs_builder *b)
{
    double sum = 0.0;
    for (uint32_t i = 0; i < b->nnodes; i++)
        if (b->nodes[i].prim == GS_NONE) sum += gs_area(b->nodes[i].box) * b->nodes[i].nchildren;
    return sum;
}

int gs_finish(const gs_builder *b, nary_t *t)
{
    memset(t, 0, sizeof *t);
    if (b->root == GS_NONE) return 0;
    /* Breadth-first: out[i] is the builder's node from[i]; a node's
     * children are appended as one run when it is laid out. */
    uint32_t *from = malloc((size_t)b->nnodes * sizeof *from);
    t->nodes = malloc((size_t)b->nnodes * sizeof *t->nodes);
    if (!from || !t->nodes) {
        free(from);
        nary_free(t);
        return -1;
    }
    uint32_t tail = 0;
    from[tail++] = b->root;
    for (uint32_t head = 0; head < tail; head++) {
        const gs_node *g = &b->nodes[from[head]];
        nary_node *o = &t->nodes[head];
        o->box = g->box;
        if (g->prim != GS_NONE) {
            o->index = g->prim;
            o->count = 0;
            continue;
        }
        o->index = tail;
        o->count = g->nchildren;
        for (uint32_t k = g->first; k != GS_NONE; k = b->nodes[k].next) from[tail++] = k;
    }
    free(from);
    t->nnodes = tail;
    if (nary_measure(t)) {
        nary_free(t);
        return -1;
    }
    return 0;
}

int nary_build_gs(nary_t *t, const box3 *boxes, const uint32_t *order, uint32_t n, const nary_gs_config *cfg)
{
    memset(t, 0, sizeof *t);
    gs_builder b;
    if (gs_builder_init(&b, boxes, n, cfg)) return -1;
    /* With coincident classes: the node holding each class in the tree. */
    uint32_t *at = cfg && cfg->rep ? malloc(((size_t)n + 1) * sizeof *at) : NULL;
    if (cfg && cfg->rep && !at) {
        gs_builder_free(&b);
        return -1;
    }
    for (uint32_t i = 0; at && i < n; i++) at[i] = GS_NONE;
    for (uint32_t i = 0; i < n; i++) {
        double increase;
        uint32_t prim = order ? order[i] : i, r = at ? cfg->rep[prim] : 0;
        int rc = at && at[r] != GS_NONE ? place_copy(&b, prim, &at[r]) : gs_insert(&b, prim, &increase);
        if (rc) {
            free(at);
            gs_builder_free(&b);
            return -1;
        }
        if (at && at[r] == GS_NONE) at[r] = b.nnodes - 1; /* the leaf gs_insert made last */
    }
    free(at);
    int rc = gs_finish(&b, t);
    gs_builder_free(&b);
    return rc;
}

uint64_t nary_build_gs_bytes(uint32_t n)
{
    /* Per node of the 2n - 1: the builder's node, a pending entry, the
     * layout's index and output node, nary_measure's walk (12 bytes). */
    uint64_t per_node = sizeof(gs_node) + sizeof(gs_pending) + sizeof(uint32_t) + sizeof(nary_node) + 12;
    return (2 * (uint64_t)n + 1) * per_node + 4096;
}
