/* bsp_kaplan_jansen.c: `bsp`, the axis-orthogonal BSP tree (kd-tree) with
 * three traversals. Reference: docs/accels/bsp.md.
 *
 * Papers (the survey: J. Arvo, D. Kirk, "A Survey of Ray Tracing
 * Acceleration Techniques", 1989, s5.1, figures 11 and 12, and s5.3):
 *   M. R. Kaplan, "Space-Tracing: A Constant Time Ray-Tracer", SIGGRAPH '85
 *     course notes: midpoint planes, axes in turn, sequential traversal.
 *   F. W. Jansen, "Data Structures for Ray Tracing", Eurographics workshop
 *     1986: recursive traversal (near segment first, far one dropped when
 *     the near one holds a hit).
 *   V. Havran, "Heuristic Ray Shooting Algorithms", PhD thesis, Prague
 *     2000: TA^B_rec, sides decided by entry and exit point coordinates.
 *   I. Wald, V. Havran, RT'06: the SAH event sweep and perfect splits, with
 *     pbrt-v4's KdTreeAggregate costs and termination (kd_sah.c).
 *
 * The tree, its 8-byte nodes and both builders are accel/bsp/kd_tree.h;
 * this file is the three traversals. The tree's memory: the bsp_t, nodes
 * (8 bytes each, depth-first) and leaf id lists (4 bytes a reference;
 * one-primitive leaves keep the id in the node). Per thread: the mailbox
 * (4 bytes a primitive). Stacks on the C stack: recursive 12 bytes a
 * level, havran 24, sequential none.
 *
 * Invariants:
 *   - a primitive within pad (about 16 float ulps) of a child cell is in
 *     it, so a primitive in or touching a plane is found from either side,
 *     and a float decision at a plane, a few ulps off, stays inside it;
 *   - the ray is clipped to the root cell grown by pad (slab_clip_robust);
 *   - a ray parallel to a plane (+-0 component) goes to its origin's side,
 *     lying in it to the side below (Havran's Z2), in all three traversals;
 *     a component whose reciprocal overflows is not parallel: the plane's
 *     distance is then computed by division;
 *   - candidates are tested over [tnear, tHit); a traversal stops only in
 *     the cell whose exit is at or past the hit; any hit stops at the first
 *     occluder;
 *   - sequential: the next point is the exit pushed an infinitesimal step
 *     (a plane at exactly the point's t is already behind it), never a
 *     fixed offset, which rounding would lose far from the origin.
 *
 * Counters: box_tests = 1 root clip per ray; steps = nodes visited (every
 * node of every descent for sequential); empty_leaves; mailbox_hits.
 * intersect_fast/occluded_fast are the same traversals without them.
 * Not implemented: Kaplan's and Jansen's own termination rules (pbrt-v4's
 * depth rule stands in), ropes, packets, parallel builds. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../accel.h"
#include "bsp_kaplan_jansen.h"
#include "kd_tree.h"
#include "../common/mailbox.h"
#include "../common/slab.h"
#include "../../prims/checked_alloc.h"

enum { TRAV_RECURSIVE = 0, TRAV_SEQUENTIAL = 1, TRAV_HAVRAN = 2 };

static const accel_param bsp_params[] = {
    PARAM_ROW_CHOICE("split", "midpoint", "midpoint|sah", "plane choice: midpoint (Kaplan, axes in turn), sah (Wald-Havran sweep, pbrt-v4 costs)"),
    PARAM_ROW_CHOICE("traverse", "recursive", "recursive|sequential|havran",
                     "recursive (Jansen 1986), sequential (Kaplan 1985), havran (TA^B_rec, Havran 2000)"),
    PARAM_ROW_INT_OR("maxdepth", "auto", "auto", 0, KD_MAX_DEPTH, "deepest node: auto = round(8 + 1.3 floor(log2 N)) (pbrt-v4)"),
    PARAM_ROW_INT_OR("maxprims", "auto", "auto", 0, 1000000, "leaf at most this many candidates: auto = 1 (sah), 2 (midpoint)"),
    PARAM_ROW_REAL("isectcost", "80", 1e-9, 1e9, "SAH cost of a primitive test (pbrt-v4)"),
    PARAM_ROW_REAL("travcost", "1", 0, 1e9, "SAH cost of a traversal step (pbrt-v4)"),
    PARAM_ROW_REAL("emptybonus", "0.5", 0, 1, "SAH discount for a split with an empty child (pbrt-v4)"),
    PARAM_ROW_BOOL("perfect", "off", "SAH perfect splits: primitives clipped to the cell (Wald-Havran 2006; split=sah only)"),
    PARAM_ROW_BOOL("mailbox", "on", "Arnaldi mailboxes, per-thread last ray id per primitive"),
    PARAM_ROW_END,
};

/* perfect splits belong to the SAH sweep. */
static int bsp_check(const accel_params *params, char *err, size_t errlen)
{
    if (params_bool(params, "perfect") && params_choice(params, "split") != KD_SPLIT_SAH) {
        snprintf(err, errlen, "perfect=on: perfect splits belong to split=sah (midpoint tests surfaces exactly already)");
        return -1;
    }
    return 0;
}

typedef struct {
    accel base;
    const prims_t *p;
    kd_tree tree;
    box3 clip; /* the root cell grown by the slack: the rays' clip box */
    int traverse;
    bool mailbox;
} bsp_t;

struct accel_ctx {
    mailbox_t mb;
};

/* ---------------------------------------------------------------- build */

static void bsp_destroy(accel *a)
{
    bsp_t *t = (bsp_t *)a;
    if (!t) return;
    kd_free(&t->tree);
    free(t);
}

static accel *bsp_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    const prims_t *p = &scene->prims;
    int split = params_choice(params, "split"), trav = params_choice(params, "traverse");
    double isect = params_real(params, "isectcost"), travc = params_real(params, "travcost"),
           eb = params_real(params, "emptybonus");
    bool perfect = params_bool(params, "perfect"), mailbox = params_bool(params, "mailbox");
    long maxdepth = params_int_or(params, "maxdepth", kd_default_depth(p->count));
    if (maxdepth > KD_MAX_DEPTH) maxdepth = KD_MAX_DEPTH; /* auto past 2^43 primitives */
    long maxprims = params_int_or(params, "maxprims", split == KD_SPLIT_SAH ? 1 : 2);

    bsp_t *t = calloc(1, sizeof *t);
    if (!t) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    t->base.scene = scene;
    t->p = p;
    t->traverse = trav;
    t->mailbox = mailbox;
    kd_config cfg = {.split = split, .maxdepth = (int)maxdepth, .maxprims = (int)maxprims, .isect_cost = isect,
                     .trav_cost = travc, .empty_bonus = eb, .perfect = perfect, .memcap_mib = params_memcap(params, 4096)};
    if (kd_build(&t->tree, p, &cfg, err, errlen)) {
        free(t);
        return NULL;
    }
    float pad = t->tree.pad;
    t->clip.lo = v3_sub(t->tree.box.lo, v3(pad, pad, pad));
    t->clip.hi = v3_add(t->tree.box.hi, v3(pad, pad, pad));
    return &t->base;
}

/* -------------------------------------------------------------- context */

static accel_ctx *bsp_context_new(accel *a)
{
    bsp_t *t = (bsp_t *)a;
    /* context_new cannot fail through the interface: out of memory is exit 2 (prims/checked_alloc.h) */
    accel_ctx *ctx = checked_calloc(1, sizeof *ctx, "a bsp tracing context");
    if (t->mailbox && mailbox_init(&ctx->mb, t->p->count))
        checked_alloc_failed((uint64_t)t->p->count * sizeof(uint32_t), "a bsp thread's mailboxes");
    return ctx;
}

static void bsp_context_free(accel_ctx *ctx)
{
    if (!ctx) return;
    mailbox_free(&ctx->mb);
    free(ctx);
}

/* ---------------------------------------------------------------- trace */

/* What every traversal keeps per ray. Counted locally (prims/ writes *c,
 * so the compiler could not keep them in registers) and added at the end. */
typedef struct {
    const bsp_t *t;
    const ray_t *ray;
    slab_ray sr;
    float d[3];
    mailbox_t mbox; /* a local copy: its address never escapes */
    mailbox_t *mb;  /* &mbox, or NULL without mailboxes */
    uint32_t rid;
    uint64_t nsteps, nempty, nmbox;
} walk_t;

/* The candidates of leaf nd: closest hit into *hit, or (shadow) whether
 * one occludes. */
static inline __attribute__((always_inline)) bool leaf_test(walk_t *w, const kd_node *nd, hit_t *hit, counters_t *c,
                                                            const bool shadow, const bool counting)
{
    const prims_t *p = w->t->p;
    uint32_t n;
    const uint32_t *ids = kd_leaf_ids(&w->t->tree, nd, &n);
    if (counting) w->nsteps++;
    if (!n) {
        if (counting) w->nempty++;
        return false;
    }
    if (!w->mb) {
        if (shadow)
            return counting ? prim_occluded_leaf(p, ids, n, w->ray, c) : prim_occluded_leaf_fast(p, ids, n, w->ray);
        if (counting) prim_intersect_leaf(p, ids, n, w->ray, hit, c);
        else prim_intersect_leaf_fast(p, ids, n, w->ray, hit);
        return false;
    }
    for (uint32_t k = 0; k < n; k++) {
        uint32_t id = ids[k];
        if (mailbox_seen(w->mb, id, w->rid)) {
            if (counting) w->nmbox++;
            continue;
        }
        mailbox_mark(w->mb, id, w->rid);
        if (shadow) {
            if (counting ? prim_occluded(p, id, w->ray, c) : prim_occluded_fast(p, id, w->ray)) return true;
        } else if (counting) {
            prim_intersect(p, id, w->ray, hit, c);
        } else {
            prim_intersect_fast(p, id, w->ray, hit);
        }
    }
    return false;
}

/* The distance to the plane x[a] = s of a ray whose direction component
 * d[a] is not 0: by the reciprocal, or by division where the reciprocal of
 * a tiny component overflowed (the ray still crosses the plane, maybe far). */
static inline float plane_t(const walk_t *w, int a, float s)
{
    float inv = w->sr.inv[a], o = w->sr.org[a];
    return isinf(inv) ? (s - o) / w->d[a] : (s - o) * inv;
}

/* Kaplan's sequential traversal (survey fig. 11), point location by
 * distance along the ray (docs/accels/bsp.md, "Node layout and memory"). */
static inline __attribute__((always_inline)) bool walk_sequential(walk_t *w, float t0, float t1, hit_t *hit,
                                                                  counters_t *c, const bool shadow,
                                                                  const bool counting)
{
    const kd_node *nodes = w->t->tree.nodes;
    float t = t0;
    for (;;) {
        /* Locate the cell holding the point at t (pushed forward), and its exit. */
        uint32_t ni = 0;
        float tex = t1;
        while (!kd_is_leaf(&nodes[ni])) {
            const kd_node *nd = &nodes[ni];
            if (counting) w->nsteps++;
            int a = kd_axis(nd);
            bool below;
            if (w->d[a] == 0.0f) {
                below = w->sr.org[a] <= nd->split; /* parallel: its origin's side; in the plane, below */
            } else {
                float tp = plane_t(w, a, nd->split);
                below = w->d[a] > 0 ? t < tp : !(t < tp);
                if (t < tp && tp < tex) tex = tp; /* the plane lies ahead: a face of this cell */
            }
            ni = below ? ni + 1 : kd_above(nd);
        }
        if (leaf_test(w, &nodes[ni], hit, c, shadow, counting)) return true;
        if (!shadow && hit->t <= tex) return false; /* the hit lies in this cell (s5.3) */
        if (tex >= t1) return false;
        t = tex;
    }
}

/* Jansen's recursive traversal (survey fig. 12), the recursion as a stack
 * of far segments. */
static inline __attribute__((always_inline)) bool walk_recursive(walk_t *w, float t0, float t1, hit_t *hit,
                                                                 counters_t *c, const bool shadow,
                                                                 const bool counting)
{
    const kd_node *nodes = w->t->tree.nodes;
    struct {
        uint32_t node;
        float tmin, tmax;
    } st[KD_MAX_DEPTH];
    int sp = 0;
    uint32_t ni = 0;
    float tmin = t0, tmax = t1;
    for (;;) {
        const kd_node *nd = &nodes[ni];
        if (!kd_is_leaf(nd)) {
            if (counting) w->nsteps++;
            int a = kd_axis(nd);
            float o = w->sr.org[a], s = nd->split;
            uint32_t below = ni + 1, above = kd_above(nd);
            if (w->d[a] == 0.0f) { /* parallel: never crosses the plane */
                ni = o <= s ? below : above;
                continue;
            }
            float tp = plane_t(w, a, s);
            /* Near: the side the ray is on just after t = 0. */
            bool below_first = o < s || (o == s && w->d[a] < 0);
            uint32_t near = below_first ? below : above, far = below_first ? above : below;
            if (tp > tmax || tp <= 0) { /* the plane lies beyond the segment or behind the origin */
                ni = near;
            } else if (tp < tmin) {
                ni = far;
            } else { /* both: near [tmin, tp] now, far [tp, tmax] later */
                st[sp].node = far, st[sp].tmin = tp, st[sp].tmax = tmax;
                sp++;
                ni = near;
                tmax = tp;
            }
            continue;
        }
        if (leaf_test(w, nd, hit, c, shadow, counting)) return true;
        if (!shadow && hit->t <= tmax) return false; /* a hit in the near cell: the far ones are discarded */
        if (!sp) return false;
        sp--;
        ni = st[sp].node, tmin = st[sp].tmin, tmax = st[sp].tmax;
    }
}

/* A coordinate of the ray's point at t; exactly the origin's on an axis
 * the ray does not move along (so a ray in a plane stays in it, and
 * t = inf gives no 0 * inf). */
static inline float ray_at(float o, float d, float t) { return d == 0.0f ? o : o + t * d; }

/* Havran's TA^B_rec (thesis, appendix on traversal algorithms): a stack
 * of entry/exit points; the cases are decided by the entry and exit
 * points' coordinates on the split axis (N: entry below or on the plane,
 * P: above; Z: on it). */
static inline __attribute__((always_inline)) bool walk_havran(walk_t *w, float t0, float t1, hit_t *hit, counters_t *c,
                                                              const bool shadow, const bool counting)
{
    const kd_node *nodes = w->t->tree.nodes;
    struct {
        float t;
        float pb[3];
        uint32_t node;
        int prev;
    } st[KD_MAX_DEPTH + 4]; /* the live chain is at most depth + 1 long, its top index depth + 2 */
    const float *o = w->sr.org, *d = w->d;
    int en = 0, ex = 1;
    st[en].t = t0;
    for (int k = 0; k < 3; k++) st[en].pb[k] = ray_at(o[k], d[k], t0);
    st[ex].t = t1;
    for (int k = 0; k < 3; k++) st[ex].pb[k] = ray_at(o[k], d[k], t1);
    st[ex].node = UINT32_MAX;
    st[ex].prev = 0;
    uint32_t ni = 0;
    while (ni != UINT32_MAX) {
        while (!kd_is_leaf(&nodes[ni])) {
            const kd_node *nd = &nodes[ni];
            if (counting) w->nsteps++;
            int a = kd_axis(nd);
            float s = nd->split;
            uint32_t below = ni + 1, above = kd_above(nd), far;
            if (st[en].pb[a] <= s) {
                if (st[ex].pb[a] <= s) { /* N1, N2, N3, P5, Z2, Z3: below only */
                    ni = below;
                    continue;
                }
                if (st[en].pb[a] == s) { /* Z1: starts on the plane, leaves upward */
                    ni = above;
                    continue;
                }
                far = above, ni = below; /* N4 */
            } else {
                if (s < st[ex].pb[a]) { /* P1, P2, P3, N5: above only */
                    ni = above;
                    continue;
                }
                far = below, ni = above; /* P4 */
            }
            /* N4, P4: the segment crosses the plane; push its far part. */
            float tp = plane_t(w, a, s);
            int prev = ex;
            ex++;
            if (ex == en) ex++;
            st[ex].prev = prev;
            st[ex].t = tp;
            st[ex].node = far;
            int a1 = (a + 1) % 3, a2 = (a + 2) % 3;
            st[ex].pb[a] = s;
            st[ex].pb[a1] = ray_at(o[a1], d[a1], tp);
            st[ex].pb[a2] = ray_at(o[a2], d[a2], tp);
        }
        if (leaf_test(w, &nodes[ni], hit, c, shadow, counting)) return true;
        if (!shadow && hit->t <= st[ex].t) return false; /* the hit lies in this cell */
        en = ex;
        ni = st[ex].node;
        ex = st[en].prev;
    }
    return false;
}

/* One source for all four methods: shadow and counting are constants at
 * the call sites, so the fast methods are these bodies with every counter
 * write compiled out (the same arithmetic, the same answers bit for bit). */
static inline __attribute__((always_inline)) bool trace(bsp_t *t, accel_ctx *ctx, const ray_t *ray, hit_t *hit,
                                                        counters_t *c, const bool shadow, const bool counting)
{
    if (!t->tree.nrefs) return false;
    walk_t w;
    w.t = t;
    w.ray = ray;
    /* A ray no primitive can hit (NaN, infinite, zero direction) misses
     * here, before a NaN could reach a plane test. */
    if (!slab_ray_init(&w.sr, ray->org, ray->dir)) return false;
    float t0 = ray->tnear, t1 = ray->tfar;
    if (!slab_clip_robust(&w.sr, &t->clip, &t0, &t1)) {
        if (counting) c->box_tests++;
        return false;
    }
    w.d[0] = ray->dir.x, w.d[1] = ray->dir.y, w.d[2] = ray->dir.z;
    w.nsteps = w.nempty = w.nmbox = 0;
    w.mb = NULL;
    w.rid = 0;
    if (ctx && ctx->mb.stamp) {
        w.rid = mailbox_next_ray(&ctx->mb);
        w.mbox = ctx->mb;
        w.mb = &w.mbox;
    }
    bool occ;
    switch (t->traverse) {
    case TRAV_SEQUENTIAL: occ = walk_sequential(&w, t0, t1, hit, c, shadow, counting); break;
    case TRAV_HAVRAN: occ = walk_havran(&w, t0, t1, hit, c, shadow, counting); break;
    default: occ = walk_recursive(&w, t0, t1, hit, c, shadow, counting); break;
    }
    if (counting)
        counters_add(c, &(counters_t){.box_tests = 1, .steps = w.nsteps, .empty_leaves = w.nempty, .mailbox_hits = w.nmbox});
    return shadow ? occ : hit->prim != HIT_NONE;
}

static bool bsp_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    return trace((bsp_t *)a, ctx, ray, hit, c, false, true);
}

static bool bsp_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    return trace((bsp_t *)a, ctx, ray, NULL, c, true, true);
}

static bool bsp_intersect_fast(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit)
{
    return trace((bsp_t *)a, ctx, ray, hit, NULL, false, false);
}

static bool bsp_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *ray)
{
    return trace((bsp_t *)a, ctx, ray, NULL, NULL, true, false);
}

/* ------------------------------------------------------------ the rest */

static size_t bsp_memory(const accel *a)
{
    const bsp_t *t = (const bsp_t *)a;
    return sizeof *t + kd_memory(&t->tree);
}

static int bsp_stats(const accel *a, accel_stat *out, int max)
{
    const bsp_t *t = (const bsp_t *)a;
    const kd_tree *k = &t->tree;
    uint32_t full = k->nleaves - k->nempty;
    /* The random-line model: the root clip, the nodes the walk visits
     * (every node of every descent for sequential), the candidates tested. */
    line_prediction pr;
    double nodes_met;
    const bool predicted = kd_predict(k, t->p->count, t->mailbox, &pr, &nodes_met) == 0;
    accel_stat all[] = {
        {"nodes", (double)k->ninterior},
        {"leaves", (double)k->nleaves},
        {"empty_leaves", (double)k->nempty},
        {"max_depth", (double)k->max_depth},
        {"avg_leaf_prims", full ? (double)k->nrefs / full : 0.0},
        {"refs_per_prim", t->p->count ? (double)k->nrefs / t->p->count : 0.0},
        {"predicted_steps_per_ray", t->traverse == TRAV_SEQUENTIAL ? pr.descents : nodes_met},
        {"predicted_tests_per_ray", pr.tests},
        {"predicted_box_tests_per_ray", 1.0},
    };
    int n = (int)(sizeof all / sizeof all[0]) - (predicted ? 0 : 3); /* the model's rows, when it had memory */
    if (n > max) n = max;
    for (int i = 0; i < n; i++) out[i] = all[i];
    return n;
}

static box3 bsp_bounds(const accel *a) { return ((const bsp_t *)a)->tree.box; }

const kd_tree *bsp_debug_tree(const accel *a) { return &((const bsp_t *)a)->tree; }

/* Every traversal with each builder, perfect splits, no mailboxes, one
 * leaf, a shallow tree with big leaves, and other SAH costs. */
static const char *const bsp_variants[] = {
    "traverse=sequential",
    "traverse=havran",
    "split=sah",
    "split=sah,traverse=sequential",
    "split=sah,traverse=havran",
    "split=sah,perfect=on",
    "split=sah,perfect=on,traverse=havran",
    "split=sah,perfect=on,traverse=sequential",
    "mailbox=off",
    "split=sah,mailbox=off,traverse=havran",
    "maxdepth=0",
    "maxdepth=4,maxprims=6,traverse=sequential",
    "split=sah,emptybonus=0,isectcost=4,maxprims=3",
    NULL,
};

const struct accel_ops accel_bsp = {
    .version = 2,
    .name = "bsp",
    .summary = "axis-orthogonal BSP: Kaplan midpoint or SAH (Wald-Havran) planes; Jansen recursive, Kaplan "
               "sequential or Havran TA^B_rec traversal; mailboxes",
    .paper = "Kaplan 1985; Jansen 1986; Arvo & Kirk 1989 survey s5.1, fig. 12; Havran 2000 TA^B_rec; "
             "Wald & Havran 2006; pbrt-v4 kd-tree costs",
    .params = bsp_params,
    .flags = 0,
    .build = bsp_build,
    .context_new = bsp_context_new,
    .context_free = bsp_context_free,
    .intersect = bsp_intersect,
    .occluded = bsp_occluded,
    .memory = bsp_memory,
    .destroy = bsp_destroy,
    .stats = bsp_stats,
    .reset = NULL,
    .bounds = bsp_bounds,
    .intersect_fast = bsp_intersect_fast,
    .occluded_fast = bsp_occluded_fast,
    .variants = bsp_variants,
    .check = bsp_check,
    .cost = {2, 4, 0},
    .tune = "maxdepth=auto|12|16|20|24|28", /* pbrt-v4's rule and fixed depths around it */
};
