/* kd_sah.c: the SAH kd-tree build in O(N log N) (I. Wald, V. Havran, "On
 * building fast kd-Trees for Ray Tracing, and on doing that in
 * O(N log N)", IEEE Symposium on Interactive Ray Tracing 2006), with the
 * cost constants and termination of pbrt-v4's KdTreeAggregate (its source,
 * cpu/aggregates.cpp; the algorithm is the one of Pharr, Jakob, Humphreys,
 * "Physically Based Rendering", 3rd ed., 2016, s4.4).
 *
 * Events (Wald-Havran): each primitive gives, per axis, a start event at
 * the low end of its box and an end event at the high end, or one planar
 * event when the box is flat on that axis. Sorted once at the root by
 * (position, type) with end < planar < start, the three lists are only
 * ever filtered and merged afterwards, never sorted again, which is what
 * makes the whole build O(N log N).
 *
 * The sweep (per axis, over the node's sorted events). The classification
 * is the tree's closed one with its slack (kd_tree.h): below when the
 * primitive's low end is at most s + pad, above when its high end is at
 * least s - pad. A plane AT an event would put every primitive touching it
 * on both sides, so the candidates are 2 pad below each distinct low end
 * (primitives starting there go above only, as Wald-Havran send them, which
 * also gives the empty-space cut-offs) and 2 pad above each distinct high end
 * (those ending there go below only); a planar primitive has both, which
 * is Wald-Havran's choice of a side for it. The counts at a candidate are
 * taken by cursors over the same sorted events with exactly the
 * classification's float comparisons, so the cost sees the children the
 * split makes. A candidate closer than float_res_min_cell() (float_res.h: 4 pads,
 * 64 float steps of the root's coordinates) to either end of the cell is
 * skipped: far from the origin such a child holds every nearby primitive
 * again, and float coordinates there cannot tell its planes apart. Where a mesh vertex is both some triangles' high end and
 * others' low end, one of the two groups straddles whichever candidate is
 * taken (Wald-Havran put both groups on their own sides): that is the price
 * of watertightness through vertices lying in a plane. Cost (pbrt-v4):
 *   C = trav + isect (1 - eb) (P_below N_below + P_above N_above),
 *   P = surface area of the child / surface area of the cell,
 *   eb = emptybonus when a child is empty, else 0; a leaf costs isect N.
 * Termination (pbrt-v4): a leaf when N <= maxprims or at maxdepth; a split
 * costlier than the leaf is a "bad refine"; a leaf when no candidate
 * exists, on the third bad refine along the path, or when the best cost is
 * over 4 times the leaf's with fewer than 16 primitives.
 *
 * Perfect splits (cfg->perfect, Wald-Havran): a straddling primitive is
 * clipped to each child grown by pad (prim_clip_bounds) and its events
 * there are made from the clipped box, sorted (only the straddlers' few)
 * and merged into the filtered lists; a primitive whose part in a child is
 * empty is dropped from it. Without them, as pbrt, a straddler keeps its
 * whole bounds in both children.
 *
 * Scratch (charged against the memory cap): the event lists (8 bytes an
 * event, at most 6 per primitive reference) of the path and of the
 * waiting above siblings, one side byte per primitive. */
#include <stdlib.h>
#include <string.h>
#include "../common/float_res.h"
#include "kd_build.h"

enum { EV_END = 0, EV_PLANAR = 1, EV_START = 2 };
enum { SIDE_L = 1, SIDE_R = 2, SIDE_BOTH = 3 };

typedef struct {
    float pos;
    uint32_t pt; /* primitive << 2 | type */
} event;
static_assert(sizeof(event) == 8, "an event is 8 bytes");

static inline uint32_t ev_prim(event e) { return e.pt >> 2; }
static inline uint32_t ev_type(event e) { return e.pt & 3u; }

/* A node's events: the three axes' sorted lists, one allocation. */
typedef struct {
    event *ev;
    size_t m[3]; /* events per axis; axis a starts at ev + off(a) */
    uint32_t n;  /* primitives */
} evlist;

static inline size_t ev_total(const evlist *l) { return l->m[0] + l->m[1] + l->m[2]; }
static inline event *ev_axis(const evlist *l, int a) { return l->ev + (a > 0 ? l->m[0] : 0) + (a > 1 ? l->m[1] : 0); }

static int cmp_event(const void *x, const void *y)
{
    const event *a = x, *b = y;
    if (a->pos != b->pos) return a->pos < b->pos ? -1 : 1;
    return (int)ev_type(*a) - (int)ev_type(*b);
}

typedef struct {
    kd_builder *b;
    uint8_t *side; /* [count] classification of the node being split */
} sah_ctx;

/* Events of one box on axis a: 1 (planar) or 2; written at out if not NULL. */
static int box_events(box3 bb, uint32_t id, int a, event *out)
{
    float lo = kd_get(bb.lo, a), hi = kd_get(bb.hi, a);
    if (lo == hi) {
        if (out) out[0] = (event){lo, id << 2 | EV_PLANAR};
        return 1;
    }
    if (out) out[0] = (event){lo, id << 2 | EV_START}, out[1] = (event){hi, id << 2 | EV_END};
    return 2;
}

static bool evlist_alloc(kd_builder *b, evlist *l)
{
    l->ev = kd_scratch_alloc(b, ev_total(l), sizeof(event));
    return l->ev != NULL;
}

static void evlist_free(kd_builder *b, evlist *l)
{
    kd_scratch_free(b, l->ev, ev_total(l), sizeof(event));
    l->ev = NULL;
}

/* pbrt-v4's split cost of the plane s on axis a of cell. */
static double split_cost(const kd_config *c, box3 cell, int a, float s, uint32_t nb, uint32_t na)
{
    int a1 = (a + 1) % 3, a2 = (a + 2) % 3;
    double d1 = (double)kd_get(cell.hi, a1) - kd_get(cell.lo, a1), d2 = (double)kd_get(cell.hi, a2) - kd_get(cell.lo, a2);
    double da = (double)kd_get(cell.hi, a) - kd_get(cell.lo, a);
    double total = 2.0 * (d1 * d2 + da * (d1 + d2));
    double below = 2.0 * (d1 * d2 + ((double)s - kd_get(cell.lo, a)) * (d1 + d2));
    double above = 2.0 * (d1 * d2 + ((double)kd_get(cell.hi, a) - s) * (d1 + d2));
    double eb = (nb == 0 || na == 0) ? c->empty_bonus : 0.0;
    return c->trav_cost + c->isect_cost * (1.0 - eb) * (below / total * nb + above / total * na);
}

typedef struct {
    double cost;
    int axis; /* -1: none */
    float pos;
} split_t;

/* Start and planar events carry a primitive's low end, end and planar
 * events its high end. */
static inline bool has_lo(event e) { return ev_type(e) != EV_END; }
static inline bool has_hi(event e) { return ev_type(e) != EV_START; }

/* The next event at or after i that carries a low end (lo) or a high end. */
static inline size_t next_end(const event *e, size_t m, size_t i, bool lo)
{
    while (i < m && (lo ? !has_lo(e[i]) : !has_hi(e[i]))) i++;
    return i;
}

/* The sweep over axis a. Candidates: 2 pad below each distinct low end
 * (the primitives starting there go above only) and 2 pad above each
 * distinct high end (those ending there go below only), in increasing
 * order from the two sorted streams; at each, two more cursors count
 * N_below = #{lo <= s + pad} and N_above = #{hi >= s - pad}, exactly the
 * classification's float comparisons. O(events). */
static void sweep(const kd_config *c, float pad, float minw, const evlist *l, box3 cell, int a, split_t *best)
{
    const event *e = ev_axis(l, a);
    size_t m = l->m[a];
    float lo = kd_get(cell.lo, a), hi = kd_get(cell.hi, a), pad2 = 2.0f * pad;
    size_t ia = next_end(e, m, 0, true), ib = next_end(e, m, 0, false), il = 0, ih = 0;
    uint32_t nl = 0, nh = 0; /* low ends <= s + pad; high ends < s - pad */
    while (ia < m || ib < m) {
        float ca = ia < m ? e[ia].pos - pad2 : INFINITY, cb = ib < m ? e[ib].pos + pad2 : INFINITY, s;
        if (ca <= cb) {
            float p0 = e[ia].pos;
            s = ca;
            do ia = next_end(e, m, ia + 1, true);
            while (ia < m && e[ia].pos == p0);
        } else {
            float p0 = e[ib].pos;
            s = cb;
            do ib = next_end(e, m, ib + 1, false);
            while (ib < m && e[ib].pos == p0);
        }
        if (!(s - lo >= minw && hi - s >= minw)) continue; /* a child float coordinates cannot resolve */
        float sp = s + pad, sm = s - pad;
        for (; il < m && (!has_lo(e[il]) || e[il].pos <= sp); il++) nl += has_lo(e[il]);
        for (; ih < m && (!has_hi(e[ih]) || e[ih].pos < sm); ih++) nh += has_hi(e[ih]);
        double cost = split_cost(c, cell, a, s, nl, l->n - nh);
        if (cost < best->cost) *best = (split_t){cost, a, s};
    }
}

/* side[] of every primitive of the node for the plane sp: below when its
 * low end is within pad above the plane or lower, above when its high end
 * is within pad below it or higher (both for a straddler). */
static void classify(sah_ctx *x, float pad, const evlist *l, const split_t *sp)
{
    const event *e = ev_axis(l, sp->axis);
    float up = sp->pos + pad, dn = sp->pos - pad;
    for (size_t i = 0; i < l->m[sp->axis]; i++)
        if (has_lo(e[i])) x->side[ev_prim(e[i])] = e[i].pos <= up ? SIDE_L : 0;
    for (size_t i = 0; i < l->m[sp->axis]; i++)
        if (has_hi(e[i]) && e[i].pos >= dn) x->side[ev_prim(e[i])] |= SIDE_R;
}

/* Merge the sorted a[0..na) and b[0..nb) into out. */
static void merge(const event *a, size_t na, const event *b, size_t nb, event *out)
{
    size_t i = 0, j = 0, k = 0;
    while (i < na && j < nb) out[k++] = cmp_event(&b[j], &a[i]) < 0 ? b[j++] : a[i++];
    while (i < na) out[k++] = a[i++];
    while (j < nb) out[k++] = b[j++];
}

/* The children's event lists. Without perfect splits: filters of the
 * parent's (order kept). With them: the one-sided primitives' events
 * filtered, the straddlers' events made from their clipped boxes, sorted
 * and merged in. false when the builder failed. */
static bool split_events(sah_ctx *x, const evlist *l, box3 cl, box3 cr, evlist *L, evlist *R)
{
    kd_builder *b = x->b;
    const prims_t *p = b->p;
    bool perfect = b->cfg->perfect;
    memset(L, 0, sizeof *L);
    memset(R, 0, sizeof *R);
    /* The straddlers (perfect splits only) and their clipped boxes. */
    const event *e0 = ev_axis(l, 0);
    uint32_t nboth = 0, *both = NULL;
    box3 *clip = NULL;
    if (perfect) {
        for (size_t i = 0; i < l->m[0]; i++)
            nboth += ev_type(e0[i]) != EV_END && x->side[ev_prim(e0[i])] == SIDE_BOTH;
        both = kd_scratch_alloc(b, nboth, sizeof *both);
        clip = kd_scratch_alloc(b, 2 * (size_t)nboth, sizeof *clip);
        if (!both || !clip) goto fail;
        nboth = 0;
        for (size_t i = 0; i < l->m[0]; i++)
            if (ev_type(e0[i]) != EV_END && x->side[ev_prim(e0[i])] == SIDE_BOTH) both[nboth++] = ev_prim(e0[i]);
        for (uint32_t k = 0; k < nboth; k++) {
            clip[2 * k] = prim_clip_bounds(p, both[k], cl);
            clip[2 * k + 1] = prim_clip_bounds(p, both[k], cr);
        }
    }
    /* Primitive counts (from axis 0's start and planar events). */
    for (size_t i = 0; i < l->m[0]; i++) {
        if (ev_type(e0[i]) == EV_END) continue;
        uint8_t sd = x->side[ev_prim(e0[i])];
        if (perfect && sd == SIDE_BOTH) continue;
        L->n += (sd & SIDE_L) != 0;
        R->n += (sd & SIDE_R) != 0;
    }
    for (uint32_t k = 0; k < nboth; k++) {
        L->n += !box_is_empty(clip[2 * k]);
        R->n += !box_is_empty(clip[2 * k + 1]);
    }
    /* Event counts per axis. */
    size_t gl[3] = {0, 0, 0}, gr[3] = {0, 0, 0}; /* generated (perfect) */
    for (int a = 0; a < 3; a++) {
        const event *e = ev_axis(l, a);
        for (size_t i = 0; i < l->m[a]; i++) {
            uint8_t sd = x->side[ev_prim(e[i])];
            if (perfect && sd == SIDE_BOTH) continue;
            L->m[a] += (sd & SIDE_L) != 0;
            R->m[a] += (sd & SIDE_R) != 0;
        }
        for (uint32_t k = 0; k < nboth; k++) {
            if (!box_is_empty(clip[2 * k])) gl[a] += box_events(clip[2 * k], both[k], a, NULL);
            if (!box_is_empty(clip[2 * k + 1])) gr[a] += box_events(clip[2 * k + 1], both[k], a, NULL);
        }
        L->m[a] += gl[a];
        R->m[a] += gr[a];
    }
    if (!evlist_alloc(b, L) || !evlist_alloc(b, R)) goto fail;
    size_t gmax = 0;
    for (int a = 0; a < 3; a++) gmax = gl[a] > gmax ? gl[a] : gmax, gmax = gr[a] > gmax ? gr[a] : gmax;
    event *gen = NULL, *kept = NULL;
    size_t keptmax = 0;
    if (perfect) {
        for (int a = 0; a < 3; a++) keptmax = l->m[a] > keptmax ? l->m[a] : keptmax;
        gen = kd_scratch_alloc(b, gmax, sizeof *gen);
        kept = kd_scratch_alloc(b, keptmax, sizeof *kept);
        if (!gen || !kept) {
            kd_scratch_free(b, gen, gmax, sizeof *gen);
            kd_scratch_free(b, kept, keptmax, sizeof *kept);
            goto fail;
        }
    }
    for (int a = 0; a < 3; a++) {
        const event *e = ev_axis(l, a);
        for (int s = 0; s < 2; s++) {
            evlist *c = s ? R : L;
            uint8_t want = s ? SIDE_R : SIDE_L;
            event *out = ev_axis(c, a);
            if (!perfect) {
                size_t k = 0;
                for (size_t i = 0; i < l->m[a]; i++)
                    if (x->side[ev_prim(e[i])] & want) out[k++] = e[i];
                continue;
            }
            size_t nk = 0, ng = 0;
            for (size_t i = 0; i < l->m[a]; i++)
                if (x->side[ev_prim(e[i])] == want) kept[nk++] = e[i];
            for (uint32_t k = 0; k < nboth; k++)
                if (!box_is_empty(clip[2 * k + s])) ng += box_events(clip[2 * k + s], both[k], a, gen + ng);
            qsort(gen, ng, sizeof *gen, cmp_event);
            merge(kept, nk, gen, ng, out);
        }
    }
    kd_scratch_free(b, gen, gmax, sizeof *gen);
    kd_scratch_free(b, kept, keptmax, sizeof *kept);
    kd_scratch_free(b, both, nboth, sizeof *both);
    kd_scratch_free(b, clip, 2 * (size_t)nboth, sizeof *clip);
    return true;
fail:
    if (L->ev) evlist_free(b, L);
    if (R->ev) evlist_free(b, R);
    kd_scratch_free(b, both, nboth, sizeof *both);
    kd_scratch_free(b, clip, 2 * (size_t)nboth, sizeof *clip);
    return false;
}

/* The leaf of a node: its primitives (axis 0's start and planar events). */
static void make_leaf(sah_ctx *x, const evlist *l, int depth)
{
    kd_builder *b = x->b;
    uint32_t *ids = kd_scratch_alloc(b, l->n, sizeof *ids);
    if (!ids) return;
    uint32_t k = 0;
    const event *e = ev_axis(l, 0);
    for (size_t i = 0; i < l->m[0] && k < l->n; i++)
        if (ev_type(e[i]) != EV_END) ids[k++] = ev_prim(e[i]);
    kd_emit_leaf(b, ids, k, depth);
    kd_scratch_free(b, ids, l->n, sizeof *ids);
}

/* Build the subtree of cell from its events l (consumed: freed here). */
static void build(sah_ctx *x, box3 cell, evlist *l, int depth, int bad)
{
    kd_builder *b = x->b;
    const kd_config *c = b->cfg;
    if (b->failed) {
        evlist_free(b, l);
        return;
    }
    float pad = b->t->pad;
    split_t best = {INFINITY, -1, 0.0f};
    if ((int64_t)l->n > c->maxprims && depth < c->maxdepth)
        for (int a = 0; a < 3; a++) sweep(c, pad, float_res_min_cell(b->t->box, pad), l, cell, a, &best);
    double leaf_cost = c->isect_cost * l->n;
    if (best.axis >= 0 && best.cost > leaf_cost) bad++;
    if (best.axis < 0 || (best.cost > 4.0 * leaf_cost && l->n < 16) || bad >= 3) {
        make_leaf(x, l, depth);
        evlist_free(b, l);
        return;
    }
    classify(x, pad, l, &best);
    box3 cl = cell, cr = cell;
    kd_set(&cl.hi, best.axis, best.pos);
    kd_set(&cr.lo, best.axis, best.pos);
    evlist L, R;
    bool ok = split_events(x, l, kd_box_pad(cl, pad), kd_box_pad(cr, pad), &L, &R);
    evlist_free(b, l);
    if (!ok) return;
    uint32_t node = kd_emit_interior(b, best.axis, best.pos);
    build(x, cl, &L, depth + 1, bad);
    kd_link_above(b, node);
    build(x, cr, &R, depth + 1, bad);
}

void kd_build_sah(kd_builder *b)
{
    const prims_t *p = b->p;
    sah_ctx x = {b, kd_scratch_alloc(b, p->count, 1)};
    if (!x.side) return;
    evlist root = {.n = 0};
    for (uint32_t id = 0; id < p->count; id++) {
        box3 bb = prim_bounds(p, id);
        if (box_is_empty(bb)) continue;
        root.n++;
        for (int a = 0; a < 3; a++) root.m[a] += box_events(bb, id, a, NULL);
    }
    if (evlist_alloc(b, &root)) {
        size_t k[3] = {0, 0, 0};
        for (uint32_t id = 0; id < p->count; id++) {
            box3 bb = prim_bounds(p, id);
            if (box_is_empty(bb)) continue;
            for (int a = 0; a < 3; a++) k[a] += box_events(bb, id, a, ev_axis(&root, a) + k[a]);
        }
        for (int a = 0; a < 3; a++) qsort(ev_axis(&root, a), root.m[a], sizeof(event), cmp_event);
        build(&x, b->t->box, &root, 0, 0);
    }
    kd_scratch_free(b, x.side, p->count, 1);
}
