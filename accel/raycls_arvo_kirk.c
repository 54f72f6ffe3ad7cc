/* raycls_arvo_kirk.c: `raycls`, Arvo and Kirk's ray classification.
 * Reference: docs/accels/directional.md.
 *
 * Paper: J. Arvo, D. Kirk, "Fast Ray Tracing by Ray Classification",
 * SIGGRAPH '87, as their survey (1989) describes it in s6.1 (the direction
 * cube, figure 19), s6.4 (figures 22, 23) and s6.5 (figure 24).
 *   - A ray is a 5-D point (x, y, z, u, v): its origin in the scene box B
 *     and its direction on the face of its dominant axis
 *     (accel/common/dircube.h). Six hyper-octrees, one per face.
 *   - A hypercube H is a set of rays; its candidate list C(H) holds every
 *     primitive meeting its beam (origin box swept along the u-v pyramid).
 *   - Built while tracing (figure 23): the ray's leaf is found (cache or
 *     root), its inherited list culled against its beam; while longer than
 *     maxcands and shallower than maxdepth it splits along all five axes
 *     into 32 children that inherit the list, and the ray's child is culled
 *     in turn. Siblings are culled when a ray first reaches them.
 *   - Root lists are sorted once by each primitive's minimum extent along
 *     the face's direction (ties by id); culling only deletes, so every
 *     list stays sorted, and a ray stops once [tnear, t_hit] projected on
 *     the direction lies before the next candidate (rcls_reach adds a slack).
 *   - truncate=D (s6.4 partial lists) drops the suffix wholly past a plane;
 *     a ray passing it unhit is pushed to the plane and classified anew,
 *     its running hit kept and a per-thread mailbox skipping re-tests.
 *
 * Invariants: culling runs in double on origin boxes grown by pad, u-v
 * cells grown by 1e-6 and spheres grown likewise, so no primitive that a
 * ray of H can hit is dropped by rounding; an inherited list is a superset
 * of the culled one, so a leaf left unculled (memcap reached while
 * tracing) still answers exactly; beam=exact never keeps what beam=cone
 * drops. An origin axis too narrow for float coordinates at B is not
 * split. A ray so far away that its classification point could round past
 * the slack is tested against its face's root list instead.
 *
 * Node: rcls_node, 64 bytes (one cache line): lo[5], hi[5], first of 32
 * consecutive children (0: leaf), list and count into pool, tplane,
 * parent, depth, own, face. memory(): the object, key[6n] (4 bytes),
 * sphere[n] (16 bytes), nodes (six roots first) and pool (six root lists,
 * 6n entries, then culled lists appended); each split adds 2 KiB. reset()
 * drops all past the roots. Per thread: the last leaf per face; with
 * truncate a mailbox.
 *
 * ACCEL_MUTATES (the lazy build writes the shared tree); lazy=off builds
 * everything up front and is then immutable, under the same table.
 * Counters: box_tests = clip to B + cache probes; steps = hypercubes
 * entered on the way down; empty_leaves; mailbox_hits after pushes. Steps
 * and box tests depend on the thread's earlier rays through the cache;
 * primitive tests and answers do not.
 *
 * Not implemented: the eye-ray special case, object hierarchies for
 * culling, bounds tighter than a box. Building is single-threaded. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "accel.h"
#include "raycls_arvo_kirk.h"
#include "common/dircube.h"
#include "common/float_res.h"
#include "common/mailbox.h"
#include "common/memcap.h"
#include "common/prim_hit.h"
#include "../prims/checked_alloc.h"

#define RC_ROOTS 6
#define RC_FANOUT 32
#define RC_DEPTH_MAX 20
#define RC_PUSH_MAX 4096 /* pushes before a ray falls back to its root list */
#define RC_DIR_SLACK 1e-6 /* u-v cells grown by this for culling */
#define BODY static inline __attribute__((always_inline))

enum { BEAM_CONE = 0, BEAM_EXACT = 1 };

static const accel_param rcls_params[] = {
    PARAM_ROW_INT_OR("maxdepth", "auto", "auto", 0, RC_DEPTH_MAX, "deepest hypercube: auto = 8 (lazy), 2 (lazy=off)"),
    PARAM_ROW_INT("maxcands", "16", 1, 1000000000L, "split a leaf whose candidate list is longer than this"),
    PARAM_ROW_REAL("truncate", "0", 0, 1e6, "partial lists (s6.4): drop candidates wholly D x (B's extent) past the origin box, 0 = off"),
    PARAM_ROW_BOOL("lazy", "on", "on: build while tracing (figure 23), off: build eagerly, immutable"),
    PARAM_ROW_CHOICE("beam", "cone", "cone|exact", "culling: cone (cone-sphere), exact (bounding box against the polyhedral beam)"),
    PARAM_ROW_END,
};

/* raycls's own memory cap, MiB (params_memcap): lazy growth past it stops splitting. */
#define RC_MEMCAP_MIB 1024

typedef struct {
    float lo[5], hi[5]; /* 40: origin box x, y, z, then the u-v cell */
    uint32_t child;     /* first of 32 children; 0: a leaf (the roots are 0..5) */
    uint32_t list;      /* first entry of its list in pool */
    uint32_t count;     /* entries in its list */
    float tplane;       /* every primitive dropped from the list has key > tplane; +inf: none dropped */
    uint32_t parent;    /* a root: itself */
    uint8_t depth, own, face, pad;
} rcls_node;
_Static_assert(sizeof(rcls_node) == 64, "rcls_node is 64 bytes: one cache line");

typedef struct {
    accel base;
    const prims_t *p;
    uint32_t n;
    int lazy, beam;
    uint32_t maxdepth, maxcands;
    double truncate;
    uint64_t cap_bytes;
    long memcap;
    box3 box; /* B */
    float pad;
    float min_cell; /* narrowest origin-box side a split makes (float_res_min_cell of B and pad) */
    float *key;    /* [6 n] minimum extent along each face's direction */
    float *sphere; /* [4 n] centre x, y, z, radius */
    rcls_node *nodes;
    uint32_t nnodes, nodes_cap;
    uint32_t *pool;
    uint64_t npool, pool_cap;
    bool capped, warned;
    uint64_t refusals;
    double lazy_ms;
} rcls_t;

struct accel_ctx {
    uint32_t cache[RC_ROOTS]; /* the leaf last used per face; UINT32_MAX: none */
    mailbox_t mb;             /* truncate > 0: primitives already tested by this ray */
};

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static float maxabs3(vec3 a) { return fmaxf(fabsf(a.x), fmaxf(fabsf(a.y), fabsf(a.z))); }
static float get3(vec3 a, int k) { return k == 0 ? a.x : k == 1 ? a.y : a.z; }

/* Face f's axis, sign and the two lexicographic other axes (figure 19). */
static void face_axes(int f, int *a, double *s, int *ua, int *va)
{
    *a = f / 2;
    *s = (f & 1) ? -1.0 : 1.0;
    *ua = *a == 0 ? 1 : 0;
    *va = *a == 2 ? 1 : 2;
}

/* --------------------------------------------------------- beam tests */

/* A hypercube's beam, grown by the slack, in the two forms the tests use. */
typedef struct {
    int a, ua, va;
    double s;
    double olo[3], ohi[3];         /* origin box, grown by pad */
    double u0, u1, v0, v1;         /* cell, grown by RC_DIR_SLACK */
    double apex[3], w[3], cs, sn;  /* bounding cone: apex, unit axis, cos and sin of the half-angle */
} rcls_beam;

static void beam_init(rcls_beam *b, int face, const float lo[5], const float hi[5], float pad)
{
    face_axes(face, &b->a, &b->s, &b->ua, &b->va);
    for (int k = 0; k < 3; k++) b->olo[k] = (double)lo[k] - pad, b->ohi[k] = (double)hi[k] + pad;
    b->u0 = lo[3] - RC_DIR_SLACK, b->u1 = hi[3] + RC_DIR_SLACK;
    b->v0 = lo[4] - RC_DIR_SLACK, b->v1 = hi[4] + RC_DIR_SLACK;
    /* The cone's axis: the cell centre's direction. */
    double uc = 0.5 * (b->u0 + b->u1), vc = 0.5 * (b->v0 + b->v1);
    double w[3] = {0, 0, 0};
    w[b->a] = b->s, w[b->ua] = uc, w[b->va] = vc;
    double wl = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    for (int k = 0; k < 3; k++) b->w[k] = w[k] / wl;
    /* Half-angle: the widest corner (the angle to a convex spherical cell
     * is largest at a vertex), widened a little against rounding. */
    double cmin = 1.0;
    for (int c = 0; c < 4; c++) {
        double d[3] = {0, 0, 0};
        d[b->a] = b->s, d[b->ua] = (c & 1) ? b->u1 : b->u0, d[b->va] = (c & 2) ? b->v1 : b->v0;
        double dl = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        double cc = (d[0] * b->w[0] + d[1] * b->w[1] + d[2] * b->w[2]) / dl;
        if (cc < cmin) cmin = cc;
    }
    b->cs = fmin(cmin, 1.0) - 1e-9;
    b->sn = sqrt(fmax(0.0, 1.0 - b->cs * b->cs)) + 1e-9;
    /* The origin box's ball, swept along the cone, stays in the cone whose
     * apex is r / sin(theta) behind the ball's centre. */
    double r2 = 0;
    for (int k = 0; k < 3; k++) r2 += 0.25 * (b->ohi[k] - b->olo[k]) * (b->ohi[k] - b->olo[k]);
    double back = sqrt(r2) * (1.0 + 1e-9) / b->sn;
    for (int k = 0; k < 3; k++) b->apex[k] = 0.5 * (b->olo[k] + b->ohi[k]) - b->w[k] * back;
}

/* Sphere (centre c, radius rad) against the bounding cone. */
static bool cone_keeps(const rcls_beam *b, const double c[3], double rad)
{
    double q[3] = {c[0] - b->apex[0], c[1] - b->apex[1], c[2] - b->apex[2]};
    double qq = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
    double h = q[0] * b->w[0] + q[1] * b->w[1] + q[2] * b->w[2];
    double p = sqrt(fmax(0.0, qq - h * h));
    /* Behind the apex (outside the cone's normal fan): the apex is nearest. */
    if (h * b->cs + p * b->sn < 0) return qq <= rad * rad;
    return p * b->cs - h * b->sn <= rad;
}

/* One linear bound c T <= rhs on T, narrowing [*tlo, *thi]. */
static void t_bound(double c, double rhs, double *tlo, double *thi)
{
    if (c > 0) *thi = fmin(*thi, rhs / c);
    else if (c < 0) *tlo = fmax(*tlo, rhs / c);
    else if (rhs < 0) *tlo = INFINITY; /* 0 <= rhs fails: empty */
}

/* Box q against the beam itself (beam=exact; docs/accels/directional.md). */
static bool exact_keeps(const rcls_beam *b, box3 q)
{
    double qlo[3], qhi[3];
    for (int k = 0; k < 3; k++) qlo[k] = get3(q.lo, k) - b->ohi[k], qhi[k] = get3(q.hi, k) - b->olo[k];
    double tlo = b->s > 0 ? qlo[b->a] : -qhi[b->a], thi = b->s > 0 ? qhi[b->a] : -qlo[b->a];
    tlo = fmax(tlo, 0.0);
    t_bound(b->u0, qhi[b->ua], &tlo, &thi);  /* u0 T <= x_U max */
    t_bound(-b->u1, -qlo[b->ua], &tlo, &thi); /* u1 T >= x_U min */
    t_bound(b->v0, qhi[b->va], &tlo, &thi);
    t_bound(-b->v1, -qlo[b->va], &tlo, &thi);
    return tlo <= thi + 1e-12 * (fabs(tlo) + fabs(thi));
}

static bool beam_keeps(const rcls_t *r, const rcls_beam *b, uint32_t id)
{
    if (r->beam == BEAM_EXACT) return exact_keeps(b, prim_bounds(r->p, id));
    const float *sp = r->sphere + 4 * (size_t)id;
    double c[3] = {sp[0], sp[1], sp[2]};
    return cone_keeps(b, c, sp[3] * (1.0 + 1e-6) + r->pad);
}

void raycls_debug_beam_tests(int face, const float lo[5], const float hi[5], float pad, box3 box, bool *cone,
                             bool *exact)
{
    rcls_beam b;
    beam_init(&b, face, lo, hi, pad);
    double dx = (double)box.hi.x - box.lo.x, dy = (double)box.hi.y - box.lo.y, dz = (double)box.hi.z - box.lo.z;
    double cc[3] = {0.5 * ((double)box.lo.x + box.hi.x), 0.5 * ((double)box.lo.y + box.hi.y),
                    0.5 * ((double)box.lo.z + box.hi.z)};
    *cone = cone_keeps(&b, cc, 0.5 * sqrt(dx * dx + dy * dy + dz * dz) * (1.0 + 1e-6) + pad);
    *exact = exact_keeps(&b, box);
}

/* ------------------------------------------------------------- storage */

static size_t fixed_bytes(uint32_t n) { return sizeof(rcls_t) + (size_t)n * (RC_ROOTS * sizeof(float) + 4 * sizeof(float)); }

static uint64_t in_use(const rcls_t *r)
{
    return fixed_bytes(r->n) + (uint64_t)r->nnodes * sizeof(rcls_node) + r->npool * sizeof(uint32_t);
}

static uint64_t room_left(uint64_t cap, uint64_t used) { return cap > used ? cap - used : 0; }

/* Room for more_nodes nodes and more_entries list entries, within memcap
 * (what is in use AND what is allocated) and 32-bit indices. false:
 * refused, nothing changed. */
static bool rcls_reserve(rcls_t *r, uint32_t more_nodes, uint64_t more_entries)
{
    uint64_t need_nodes = (uint64_t)r->nnodes + more_nodes, need_pool = r->npool + more_entries;
    if (need_nodes >= UINT32_MAX || need_pool >= UINT32_MAX) return false;
    uint64_t fixed = fixed_bytes(r->n);
    if (fixed + need_nodes * sizeof(rcls_node) + need_pool * 4 > r->cap_bytes) return false;
    if (need_nodes > r->nodes_cap) {
        uint64_t room = room_left(r->cap_bytes, fixed + r->pool_cap * 4) / sizeof(rcls_node);
        uint64_t cap = r->nodes_cap * 2 < room ? r->nodes_cap * 2 : room;
        if (cap < need_nodes) cap = need_nodes;
        if (cap >= UINT32_MAX) cap = UINT32_MAX - 1;
        rcls_node *nn = realloc(r->nodes, cap * sizeof *nn);
        if (!nn) return false;
        r->nodes = nn, r->nodes_cap = (uint32_t)cap;
    }
    if (need_pool > r->pool_cap) {
        uint64_t room = room_left(r->cap_bytes, fixed + (uint64_t)r->nodes_cap * sizeof(rcls_node)) / 4;
        uint64_t cap = r->pool_cap * 2 < room ? r->pool_cap * 2 : room;
        if (cap < need_pool) cap = need_pool;
        if (cap >= UINT32_MAX) cap = UINT32_MAX - 1;
        uint32_t *np = realloc(r->pool, cap * sizeof *np);
        if (!np) return false;
        r->pool = np, r->pool_cap = cap;
    }
    return true;
}

/* The truncation plane of hypercube nd (along its face's direction): D x
 * B's extent past the far face of its origin box; +inf when off. */
static float trunc_plane(const rcls_t *r, const rcls_node *nd)
{
    if (!(r->truncate > 0)) return INFINITY;
    int a = nd->face / 2;
    float far = (nd->face & 1) ? -nd->lo[a] : nd->hi[a];
    return far + (float)(r->truncate * (get3(r->box.hi, a) - get3(r->box.lo, a)));
}

/* C(H) = C(H) n Beam(H) (figure 23), truncated at H's plane: node h's
 * inherited list culled into a new list of its own. false: memcap refused
 * (h keeps the inherited list, a superset in the same order). */
static bool rcls_cull(rcls_t *r, uint32_t h)
{
    if (!rcls_reserve(r, 0, r->nodes[h].count)) return false;
    rcls_node *nd = &r->nodes[h];
    rcls_beam b;
    beam_init(&b, nd->face, nd->lo, nd->hi, r->pad);
    const uint32_t *src = r->pool + nd->list;
    uint32_t *dst = r->pool + r->npool;
    const float *key = r->key + (size_t)nd->face * r->n;
    float tp = trunc_plane(r, nd);
    uint32_t k = 0;
    bool cut = false;
    for (uint32_t i = 0; i < nd->count; i++) {
        uint32_t id = src[i];
        if (key[id] > tp) { /* sorted by key: the rest lie beyond too */
            cut = true;
            break;
        }
        if (beam_keeps(r, &b, id)) dst[k++] = id;
    }
    nd->tplane = cut || nd->tplane < INFINITY ? tp : INFINITY;
    nd->list = (uint32_t)r->npool;
    nd->count = k;
    nd->own = 1;
    r->npool += k;
    return true;
}

/* Split leaf h into 32 children at the midpoints of its five axes; they
 * inherit its list. An origin axis whose halves would be narrower than
 * min_cell is not split (float_res.h: far from the origin the slack pad
 * outgrows such halves, and every child would keep its parent's list): its
 * midpoint is put at lo, so the children with that axis's bit set hold all
 * of it and the others, [lo, lo), are never reached (rcls_reachable). The
 * u-v axes are always split. false: memcap refused. */
static bool rcls_split(rcls_t *r, uint32_t h)
{
    if (!rcls_reserve(r, RC_FANOUT, 0)) return false;
    rcls_node *nd = &r->nodes[h];
    uint32_t first = r->nnodes;
    float mid[5];
    for (int k = 0; k < 5; k++)
        mid[k] = k < 3 && 0.5f * (nd->hi[k] - nd->lo[k]) < r->min_cell ? nd->lo[k]
                                                                         : nd->lo[k] + 0.5f * (nd->hi[k] - nd->lo[k]);
    for (uint32_t c = 0; c < RC_FANOUT; c++) {
        rcls_node *ch = &r->nodes[first + c];
        for (int k = 0; k < 5; k++) {
            bool up = (c >> k) & 1;
            ch->lo[k] = up ? mid[k] : nd->lo[k];
            ch->hi[k] = up ? nd->hi[k] : mid[k];
        }
        ch->child = 0;
        ch->list = nd->list, ch->count = nd->count, ch->tplane = nd->tplane;
        ch->parent = h;
        ch->depth = (uint8_t)(nd->depth + 1), ch->own = 0, ch->face = nd->face, ch->pad = 0;
    }
    nd->child = first;
    r->nnodes += RC_FANOUT;
    return true;
}

static bool wants_split(const rcls_t *r, const rcls_node *nd)
{
    return nd->count > r->maxcands && nd->depth < r->maxdepth;
}

/* Whether the descent (rcls_child) can reach node h: not when, on an axis
 * whose bit h lacks, its parent's midpoint is the parent's lo (an axis left
 * unsplit, or one too narrow for its midpoint to round above lo). */
static bool rcls_reachable(const rcls_t *r, uint32_t h)
{
    const rcls_node *nd = &r->nodes[h], *up = &r->nodes[nd->parent];
    if (nd->parent == h) return true; /* a root */
    uint32_t bits = h - up->child;
    const float *mid = r->nodes[up->child + RC_FANOUT - 1].lo;
    for (int k = 0; k < 5; k++)
        if (!((bits >> k) & 1) && mid[k] <= up->lo[k]) return false;
    return true;
}

/* -------------------------------------------------------------- locate */

/* The child of interior h holding the 5-D point pt: lower halves are
 * half-open [lo, mid), upper halves [mid, hi]. Child 31 starts at every
 * midpoint. */
static uint32_t rcls_child(const rcls_t *r, uint32_t h, const float pt[5])
{
    uint32_t first = r->nodes[h].child;
    const float *mid = r->nodes[first + RC_FANOUT - 1].lo;
    uint32_t bits = (uint32_t)(pt[0] >= mid[0]) | (uint32_t)(pt[1] >= mid[1]) << 1 | (uint32_t)(pt[2] >= mid[2]) << 2 |
                    (uint32_t)(pt[3] >= mid[3]) << 3 | (uint32_t)(pt[4] >= mid[4]) << 4;
    return first + bits;
}

/* Whether leaf h holds pt by the descent's rule (an upper bound is
 * included only where it is the root's). */
static bool rcls_holds(const rcls_t *r, uint32_t h, const float pt[5])
{
    const rcls_node *nd = &r->nodes[h], *root = &r->nodes[nd->face];
    for (int k = 0; k < 5; k++)
        if (!(nd->lo[k] <= pt[k] && (pt[k] < nd->hi[k] || nd->hi[k] == root->hi[k]))) return false;
    return true;
}

static void refuse(rcls_t *r)
{
    r->capped = true;
    r->refusals++;
    if (!r->warned) {
        r->warned = true;
        fprintf(stderr, "accelbench: raycls: memcap=%ld MiB reached: hypercubes stop splitting%s (answers stay exact)\n",
                r->memcap, r->lazy ? " until reset" : "");
    }
}

/* Figure 23's lazy subdivision from leaf h down to the leaf holding pt;
 * the levels it makes are counted in *steps. */
static uint32_t rcls_refine(rcls_t *r, uint32_t h, const float pt[5], uint64_t *steps)
{
    if (r->nodes[h].own && !wants_split(r, &r->nodes[h])) return h;
    if (r->capped) {
        r->refusals++;
        return h;
    }
    double t0 = now_ms();
    for (;;) {
        if (!r->nodes[h].own && !rcls_cull(r, h)) {
            refuse(r);
            break;
        }
        if (!wants_split(r, &r->nodes[h])) break;
        if (!rcls_split(r, h)) {
            refuse(r);
            break;
        }
        h = rcls_child(r, h, pt);
        (*steps)++;
    }
    r->lazy_ms += now_ms() - t0;
    return h;
}

/* The leaf of face f's hyper-octree holding pt: the cached one when it
 * still is a leaf holding pt, else found from the root; refined when lazy. */
BODY uint32_t rcls_locate(rcls_t *r, accel_ctx *ctx, int f, const float pt[5], counters_t *c, const bool counting)
{
    uint32_t h = ctx->cache[f];
    uint64_t steps = 0;
    bool cached = h < r->nnodes;
    if (counting && cached) c->box_tests++;
    if (!(cached && r->nodes[h].child == 0 && r->nodes[h].face == f && rcls_holds(r, h, pt))) {
        h = (uint32_t)f;
        steps++;
        while (r->nodes[h].child) {
            h = rcls_child(r, h, pt);
            steps++;
        }
    }
    if (r->lazy) h = rcls_refine(r, h, pt, &steps);
    if (counting) c->steps += steps;
    ctx->cache[f] = h;
    return h;
}

/* ---------------------------------------------------------------- trace */

/* A ray as the walk sees it: face, its axis and sign, double copies, the
 * part inside B and the 5-D point. */
typedef struct {
    int face, a;
    double s, o[3], d[3];
    double tstart, texit;
    float pt[5];
} rcls_ray;

enum { RC_MISS, RC_FAR, RC_INSIDE };

/* pt from the point at t (clamped into B; the clamp only absorbs rounding). */
static void rcls_point(const rcls_t *r, rcls_ray *q, double t)
{
    const float lo[3] = {r->box.lo.x, r->box.lo.y, r->box.lo.z}, hi[3] = {r->box.hi.x, r->box.hi.y, r->box.hi.z};
    for (int k = 0; k < 3; k++) q->pt[k] = (float)fmin(fmax(q->o[k] + t * q->d[k], lo[k]), hi[k]);
}

/* Clip the ray to B and classify it: RC_MISS (it misses B, so everything),
 * RC_FAR (too far out to classify soundly: use the root list) or RC_INSIDE
 * (q->pt set). */
static int rcls_classify(const rcls_t *r, const ray_t *ray, rcls_ray *q)
{
    q->face = dircube_face(ray->dir);
    dircube_uv(ray->dir, q->face, &q->pt[3], &q->pt[4]);
    q->a = q->face / 2;
    q->s = (q->face & 1) ? -1.0 : 1.0;
    q->o[0] = ray->org.x, q->o[1] = ray->org.y, q->o[2] = ray->org.z;
    q->d[0] = ray->dir.x, q->d[1] = ray->dir.y, q->d[2] = ray->dir.z;
    double t0 = ray->tnear, t1 = ray->tfar;
    bool miss = false;
    for (int k = 0; k < 3; k++) {
        double lo = get3(r->box.lo, k), hi = get3(r->box.hi, k);
        if (q->d[k] == 0) {
            miss |= q->o[k] < lo || q->o[k] > hi;
            continue;
        }
        double ta = (lo - q->o[k]) / q->d[k], tb = (hi - q->o[k]) / q->d[k];
        if (ta > tb) {
            double x = ta;
            ta = tb, tb = x;
        }
        t0 = fmax(t0, ta), t1 = fmin(t1, tb);
    }
    /* Double rounding of the point, against the slack. */
    double om = fmax(fabs(q->o[0]), fmax(fabs(q->o[1]), fabs(q->o[2])));
    double dm = fmax(fabs(q->d[0]), fmax(fabs(q->d[1]), fabs(q->d[2])));
    double tm = fmax(fabs(t0), isfinite(t1) ? fabs(t1) : 0.0);
    if (!(1e-15 * (om + tm * dm) <= 0.25 * r->pad)) return RC_FAR;
    if (miss || t0 > t1) return RC_MISS;
    q->tstart = t0, q->texit = t1;
    rcls_point(r, q, t0);
    return RC_INSIDE;
}

/* The largest value along the face's direction of the ray's points over
 * [tnear, t]: at t, as the face's component of dir has the face's sign;
 * plus a slack, as a primitive's hit t is computed in float: a primitive
 * whose exact hit lies just past t may return a float t just before it
 * (exhaustive search would take it), so the stop waits until the next
 * minimum extent is clearly beyond (pad: some 16 ulps at the scene's scale,
 * and 1e-6 of the distances involved). */
static double rcls_reach(const rcls_t *r, const rcls_ray *q, float t)
{
    double o = q->s * q->o[q->a], dt = (double)t * fabs(q->d[q->a]);
    return o + dt + r->pad + 1e-6 * (fabs(o) + dt);
}

/* Push the ray to where it crosses plane (along the face's direction):
 * false when that is past B (nothing is left to find). */
static bool rcls_push(const rcls_t *r, rcls_ray *q, float plane)
{
    double t = (q->s * plane - q->o[q->a]) / q->d[q->a];
    t -= 1e-12 * fabs(t); /* before the crossing is always sound, past it not */
    if (!(t < q->texit)) return false;
    if (t > q->tstart) q->tstart = t;
    rcls_point(r, q, q->tstart);
    return true;
}

/* Figure 23 for one ray: classify, then process the candidates in order
 * until the stopping rule, pushing past truncation planes. */
BODY bool rcls_walk(rcls_t *r, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c, const bool shadow,
                  const bool counting)
{
    rcls_ray q;
    int cls = rcls_classify(r, ray, &q);
    if (counting) c->box_tests++;
    if (cls == RC_MISS) return false;
    uint32_t rid = r->truncate > 0 ? mailbox_next_ray(&ctx->mb) : 0;
    uint32_t h = cls == RC_FAR ? (uint32_t)q.face : rcls_locate(r, ctx, q.face, q.pt, c, counting);
    const float *key = r->key + (size_t)q.face * r->n;
    bool found = false;
    for (int pushes = 0;; pushes++) {
        const rcls_node *nd = &r->nodes[h];
        const uint32_t *ids = r->pool + nd->list;
        if (counting && nd->count == 0) c->empty_leaves++;
        double reach = rcls_reach(r, &q, shadow ? ray->tfar : hit->t);
        bool stopped = false;
        for (uint32_t i = 0; i < nd->count; i++) {
            uint32_t id = ids[i];
            if (reach < key[id]) { /* past the distance interval */
                stopped = true;
                break;
            }
            if (rid) {
                if (mailbox_seen(&ctx->mb, id, rid)) {
                    if (counting) c->mailbox_hits++;
                    continue;
                }
                mailbox_mark(&ctx->mb, id, rid);
            }
            if (shadow) {
                if (prim_test_any(r->p, id, ray, c, counting)) return true;
            } else if (prim_test_closest(r->p, id, ray, hit, c, counting)) {
                found = true;
                reach = rcls_reach(r, &q, hit->t);
            }
        }
        /* Done unless the list was truncated at a plane the ray reaches. */
        if (stopped || !(reach >= nd->tplane)) break;
        if (pushes >= RC_PUSH_MAX) {
            h = (uint32_t)q.face; /* the complete root list; the mailbox skips what was tested */
            continue;
        }
        if (!rcls_push(r, &q, nd->tplane)) break;
        h = rcls_locate(r, ctx, q.face, q.pt, c, counting);
    }
    return found;
}

static bool rcls_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    return rcls_walk((rcls_t *)a, ctx, ray, hit, c, false, true);
}

static bool rcls_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    hit_t h = hit_none(ray);
    return rcls_walk((rcls_t *)a, ctx, ray, &h, c, true, true);
}

static bool rcls_intersect_fast(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit)
{
    return rcls_walk((rcls_t *)a, ctx, ray, hit, NULL, false, false);
}

static bool rcls_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *ray)
{
    hit_t h = hit_none(ray);
    return rcls_walk((rcls_t *)a, ctx, ray, &h, NULL, true, false);
}

/* -------------------------------------------------------------- context */

static accel_ctx *rcls_context_new(accel *a)
{
    rcls_t *r = (rcls_t *)a;
    /* context_new cannot fail through the interface: out of memory is exit 2 (prims/checked_alloc.h) */
    accel_ctx *ctx = checked_calloc(1, sizeof *ctx, "a raycls tracing context");
    for (int f = 0; f < RC_ROOTS; f++) ctx->cache[f] = UINT32_MAX;
    if (r->truncate > 0 && mailbox_init(&ctx->mb, r->n))
        checked_alloc_failed((uint64_t)r->n * sizeof(uint32_t), "a raycls thread's mailboxes");
    return ctx;
}

static void rcls_context_free(accel_ctx *ctx)
{
    if (!ctx) return;
    mailbox_free(&ctx->mb);
    free(ctx);
}

/* ---------------------------------------------------------------- build */

static void rcls_destroy(accel *a)
{
    rcls_t *r = (rcls_t *)a;
    if (!r) return;
    free(r->key);
    free(r->sphere);
    free(r->nodes);
    free(r->pool);
    free(r);
}

typedef struct {
    float key;
    uint32_t id;
} keyed;

static int cmp_keyed(const void *x, const void *y)
{
    const keyed *a = x, *b = y;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}

/* B: the primitives' bounds padded by the slack (so the entry point of a
 * ray lies before every primitive), flat axes widened as the grid does. */
static void scene_box(rcls_t *r)
{
    const prims_t *p = r->p;
    box3 b = p->count && !box_is_empty(p->box) ? p->box : (box3){{-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}};
    vec3 e = box_extent(b);
    float maxe = fmaxf(e.x, fmaxf(e.y, e.z));
    float base = maxe > 0 ? maxe : fmaxf(1.0f, fmaxf(maxabs3(b.lo), maxabs3(b.hi)));
    float *lo[3] = {&b.lo.x, &b.lo.y, &b.lo.z}, *hi[3] = {&b.hi.x, &b.hi.y, &b.hi.z};
    for (int a = 0; a < 3; a++)
        if (*hi[a] - *lo[a] <= 1e-7f * base) *lo[a] -= 1e-3f * base, *hi[a] += 1e-3f * base;
    r->pad = 2e-6f * fmaxf(maxabs3(b.lo), maxabs3(b.hi)) + 1e-6f * box_diagonal(b);
    for (int a = 0; a < 3; a++) *lo[a] -= r->pad, *hi[a] += r->pad;
    r->box = b;
    r->min_cell = float_res_min_cell(b, r->pad);
}

/* Keys, spheres and the six sorted root lists. */
static void build_roots(rcls_t *r, keyed *scratch)
{
    const prims_t *p = r->p;
    for (uint32_t id = 0; id < r->n; id++) {
        box3 b = prim_bounds(p, id);
        double dx = (double)b.hi.x - b.lo.x, dy = (double)b.hi.y - b.lo.y, dz = (double)b.hi.z - b.lo.z;
        float *s = r->sphere + 4 * (size_t)id;
        s[0] = 0.5f * b.lo.x + 0.5f * b.hi.x, s[1] = 0.5f * b.lo.y + 0.5f * b.hi.y, s[2] = 0.5f * b.lo.z + 0.5f * b.hi.z;
        /* The centre's own rounding is inside the 1e-6 relative and pad
         * slack of the test; the radius rounds up. */
        s[3] = nextafterf((float)(0.5 * sqrt(dx * dx + dy * dy + dz * dz)), INFINITY);
    }
    for (int f = 0; f < RC_ROOTS; f++) {
        int a = f / 2;
        vec3 dir = v3(a == 0, a == 1, a == 2);
        if (f & 1) dir = v3_scale(dir, -1.0f);
        float *key = r->key + (size_t)f * r->n;
        for (uint32_t id = 0; id < r->n; id++) {
            float lo, hi;
            if (!prim_extent(p, id, dir, &lo, &hi)) {
                box3 b = prim_bounds(p, id);
                lo = (f & 1) ? -get3(b.hi, a) : get3(b.lo, a);
            }
            key[id] = lo;
            scratch[id] = (keyed){lo, id};
        }
        qsort(scratch, r->n, sizeof *scratch, cmp_keyed);
        uint32_t *list = r->pool + (size_t)f * r->n;
        for (uint32_t i = 0; i < r->n; i++) list[i] = scratch[i].id;
        rcls_node *nd = &r->nodes[f];
        memset(nd, 0, sizeof *nd);
        for (int k = 0; k < 3; k++) nd->lo[k] = get3(r->box.lo, k), nd->hi[k] = get3(r->box.hi, k);
        nd->lo[3] = nd->lo[4] = -1.0f, nd->hi[3] = nd->hi[4] = 1.0f;
        nd->list = (uint32_t)f * r->n, nd->count = r->n, nd->tplane = INFINITY;
        nd->parent = (uint32_t)f, nd->own = 1, nd->face = (uint8_t)f;
    }
    r->nnodes = RC_ROOTS;
    r->npool = (uint64_t)RC_ROOTS * r->n;
}

/* lazy=off: every hypercube by the same rule, breadth first (the node
 * array is the queue), so that memcap, if it stops the build, stops it at
 * an even depth everywhere. Hypercubes no ray can reach (rcls_reachable) keep
 * their parent's list and are not split. */
static void build_eager(rcls_t *r)
{
    for (uint32_t h = 0; h < r->nnodes && !r->capped; h++) {
        if (!rcls_reachable(r, h)) continue;
        if (!r->nodes[h].own && !rcls_cull(r, h)) {
            refuse(r);
            break;
        }
        if (wants_split(r, &r->nodes[h]) && !rcls_split(r, h)) refuse(r);
    }
}

static accel *rcls_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    bool lazy = params_bool(params, "lazy");
    int beam = params_choice(params, "beam");
    long maxdepth = params_int_or(params, "maxdepth", lazy ? 8 : 2), maxcands = params_int(params, "maxcands");
    double truncate = params_real(params, "truncate");
    uint64_t memcap = params_memcap(params, RC_MEMCAP_MIB);

    const prims_t *p = &scene->prims;
    uint64_t n = p->count;
    uint64_t base = fixed_bytes(p->count) + RC_ROOTS * sizeof(rcls_node) + RC_ROOTS * n * 4;
    if (memcap_exceeded(memcap_add(base, n * sizeof(keyed)), memcap, err, errlen,
                        "raycls over %llu primitives: six sorted root lists, keys and spheres",
                        (unsigned long long)n))
        return NULL;
    if (RC_ROOTS * n >= UINT32_MAX) {
        snprintf(err, errlen, "raycls over %llu primitives: more than 2^32 root-list entries", (unsigned long long)n);
        return NULL;
    }

    rcls_t *r = calloc(1, sizeof *r);
    keyed *scratch = NULL;
    if (!r) goto oom;
    r->base.scene = scene;
    r->p = p;
    r->n = p->count;
    r->lazy = lazy, r->beam = beam;
    r->maxdepth = (uint32_t)maxdepth, r->maxcands = (uint32_t)maxcands;
    r->truncate = truncate;
    r->memcap = (long)memcap;
    r->cap_bytes = memcap << 20;
    scene_box(r);
    r->key = malloc(((size_t)RC_ROOTS * r->n + 1) * sizeof *r->key);
    r->sphere = malloc((4 * (size_t)r->n + 1) * sizeof *r->sphere);
    r->nodes = malloc(RC_ROOTS * sizeof *r->nodes);
    r->pool = malloc(((size_t)RC_ROOTS * r->n + 1) * sizeof *r->pool);
    scratch = malloc(((size_t)r->n + 1) * sizeof *scratch);
    if (!r->key || !r->sphere || !r->nodes || !r->pool || !scratch) goto oom;
    r->nodes_cap = RC_ROOTS;
    r->pool_cap = (uint64_t)RC_ROOTS * r->n + 1;
    build_roots(r, scratch);
    free(scratch);
    if (!lazy) build_eager(r);
    return &r->base;

oom:
    free(scratch);
    snprintf(err, errlen, "out of memory building raycls over %llu primitives", (unsigned long long)n);
    rcls_destroy(r ? &r->base : NULL);
    return NULL;
}

/* ------------------------------------------------------- version 2 */

static size_t rcls_memory(const accel *a) { return (size_t)in_use((const rcls_t *)a); }

static int rcls_stats(const accel *a, accel_stat *out, int max)
{
    const rcls_t *r = (const rcls_t *)a;
    uint64_t interior = 0, leaves = 0, empty = 0, entries = 0;
    uint32_t depth = 0;
    for (uint32_t h = 0; h < r->nnodes; h++) {
        const rcls_node *nd = &r->nodes[h];
        if (nd->child) {
            interior++;
            continue;
        }
        if (!nd->own) continue; /* never reached: still its parent's list */
        leaves++;
        empty += nd->count == 0;
        entries += nd->count;
        if (nd->depth > depth) depth = nd->depth;
    }
    accel_stat all[] = {
        {"nodes", (double)interior},
        {"leaves", (double)leaves},
        {"empty_leaves", (double)empty},
        {"max_depth", (double)depth},
        {"avg_leaf_prims", leaves > empty ? (double)entries / (double)(leaves - empty) : 0.0},
        {"refs_per_prim", r->n ? (double)r->npool / r->n : 0.0},
        {"lazy_build_ms", r->lazy_ms},
    };
    int n = (int)(sizeof all / sizeof all[0]);
    if (n > max) n = max;
    for (int k = 0; k < n; k++) out[k] = all[k];
    return n;
}

/* Lazy: back to the six roots and their lists, which culling never writes
 * (new lists are appended past them), so nothing needs restoring but the
 * counts. Capacity is kept for the next pass. Eager: nothing changes. */
static void rcls_reset(accel *a)
{
    rcls_t *r = (rcls_t *)a;
    if (!r->lazy) return;
    r->nnodes = RC_ROOTS;
    r->npool = (uint64_t)RC_ROOTS * r->n;
    for (int f = 0; f < RC_ROOTS; f++) r->nodes[f].child = 0;
    r->capped = false;
    r->refusals = 0;
    r->lazy_ms = 0;
}

static box3 rcls_bounds(const accel *a) { return ((const rcls_t *)a)->box; }

void raycls_debug_counts(const accel *a, uint32_t *nodes, uint64_t *entries, uint64_t *refusals)
{
    const rcls_t *r = (const rcls_t *)a;
    *nodes = r->nnodes;
    *entries = r->npool;
    *refusals = r->refusals;
}

/* Besides the defaults: built eagerly, polyhedral culling, tiny lists that
 * force deep splits, truncated lists (pushes), and a deep eager tree. */
static const char *const rcls_variants[] = {"lazy=off", "beam=exact", "maxcands=1", "truncate=0.05",
                                          "truncate=0.02,maxcands=2,beam=exact", "lazy=off,maxdepth=3,maxcands=4",
                                          NULL};

/* ACCEL_MUTATES: lazy construction writes the shared tree while tracing;
 * reset() returns it to the roots. */
const struct accel_ops accel_raycls = {
    .version = 2,
    .name = "raycls",
    .summary = "Arvo-Kirk ray classification: six lazily built 5-D hyper-octrees of rays, beam-culled sorted lists",
    .paper = "Arvo & Kirk, Fast Ray Tracing by Ray Classification, SIGGRAPH 1987; survey s6.1, s6.4, figs. 19, 22-24",
    .params = rcls_params,
    .flags = ACCEL_MUTATES,
    .build = rcls_build,
    .context_new = rcls_context_new,
    .context_free = rcls_context_free,
    .intersect = rcls_intersect,
    .occluded = rcls_occluded,
    .memory = rcls_memory,
    .destroy = rcls_destroy,
    .stats = rcls_stats,
    .reset = rcls_reset,
    .bounds = rcls_bounds,
    .intersect_fast = rcls_intersect_fast,
    .occluded_fast = rcls_occluded_fast,
    .variants = rcls_variants,
    .cost = {4, 8, ACCEL_COST_BUILD_EACH_PASS},
    .tune = "maxcands=4|8|16|32|64", /* the longest candidate list a hypercube keeps */
};
