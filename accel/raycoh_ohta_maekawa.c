/* raycoh_ohta_maekawa.c: `raycoh`, Ohta and Maekawa's ray coherence
 * algorithm. Reference: docs/accels/directional.md.
 *
 * Paper: M. Ohta, M. Maekawa, "Ray Coherence Theorem and Constant Time Ray
 * Tracing Algorithm", Computer Graphics 1987 (Proc. CG International '87),
 * Springer, 303-314; as the Arvo-Kirk survey (1989) describes it in s6.3,
 * figures 20-21, with s6.1's direction cube (accel/common/dircube.h).
 *
 * The theorem (figure 20): every segment from sphere S1 (O1, r1) to sphere
 * S2 (O2, r2), D = |O2 - O1| > r1 + r2, makes an angle theta with O2 - O1
 * with sin(theta) <= (r1 + r2) / D (its direction lies in the sphere of
 * radius r1 + r2 about O2 - O1; tangent segments reach the bound), and is
 * at least d = D - r1 - r2 long. The survey's printed inequality (4) has
 * lost the square of the ratio; the derived bound is used.
 *
 * Entities and objects: clusters of at most objsize primitives, the kit's
 * median BVH leaves over the distinct primitives (each cluster takes every
 * copy of its members), none narrower than float coordinates resolve
 * (make_clusters); each with a bounding sphere. With lights=on the lights
 * are entities too, answered by a `lightbuf` with its defaults.
 *
 * Build (figure 21): each cluster A has a cube of 6 res^2 cells; every
 * cluster B (A included) is listed with d in each cell whose cone (axis
 * through the cell centre, half-angle to its farthest corner) meets the
 * A-to-B cone, found through a quadtree of cell cones. B's are visited in
 * order of d, so every list is appended sorted.
 *
 * Query: a ray names the primitive it leaves (ray_t.origin, harness/
 * spawn.c). If its org lies inside that primitive's cluster sphere, the
 * cell of dir is read and the listed clusters tested in order of d until d
 * exceeds the closest hit's distance t |dir| (any hit: an occluder or d
 * past tfar |dir|). Every other ray goes to the `fallback` accelerator.
 *
 * Invariants: the cone bound needs only the origin inside the sphere, so a
 * wrong but nearby origin primitive still answers exactly; a query accepts
 * an origin within r + margin of the centre while the cones use r + 2
 * margin (margin = 1e-6 scene diagonal + 4e-6 max coordinate), cells are
 * grown by 1e-3 in u-v and cone tests by 1e-6 rad, d is rounded down: no
 * rounding admits a ray the cones were not built for.
 *
 * Memory (memory() counts it, plus the fallback's and the light buffer's):
 * rcoh_obj 24 bytes a cluster; ids and prim_obj 4 bytes a primitive; rcoh_cell
 * 8 bytes, 6 res^2 a cluster, cell (f, i, j) of cluster k at
 * (6k + f) res^2 + j res + i; rcoh_ref 8 bytes (cluster, d); the quadtree,
 * 56 bytes a node, 2 x 6 res^2 - 6 nodes.
 *
 * Counters: steps = list entries read; empty_leaves = empty cells read;
 * box_tests = bounding-sphere tests (spheres=on); fallback and light-buffer
 * rays count as those accelerators count.
 *
 * Not implemented: convex polyhedral object bounds, a cube for the eye
 * (eye rays use the fallback), non-uniform cell subdivision. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accel.h"
#include "bvh/bvh.h"
#include "common/coincident.h"
#include "common/dircube.h"
#include "common/float_res.h"
#include "common/memcap.h"
#include "common/prim_hit.h"
#include "raycoh_ohta_maekawa.h"

#define RC_UV_MARGIN 1e-3      /* cells grown by this in u and v */
#define RC_ANGLE_SLACK 1e-6    /* radians added to every cone-cone test */
#define RC_DEPTH_SLACK 1e-6    /* d shrunk by this relative amount */
#define RC_STOP_SLACK 1e-5     /* t |dir| grown by this before comparing with d */
#define RC_NO_OBJ UINT32_MAX

typedef struct { vec3 c; float r; uint32_t first, count; } rcoh_obj; /* 24 bytes */
typedef struct { uint32_t first, count; } rcoh_cell;                 /* 8 bytes */
typedef struct { uint32_t obj; float d; } rcoh_ref;                  /* 8 bytes */
static_assert(sizeof(rcoh_obj) == 24 && sizeof(rcoh_cell) == 8 && sizeof(rcoh_ref) == 8, "the sizes the header states");

/* A quadtree node over a block of one face's cells: the bounding cone of
 * the block's (grown) direction pyramids. Leaves are single cells. */
typedef struct {
    double axis[3];
    double alpha;              /* half-angle, radians */
    uint16_t i0, i1, j0, j1;   /* cells [i0, i1) x [j0, j1) */
    int32_t child[2];          /* -1: a leaf (one cell) */
    int32_t face;
} rcoh_node;

typedef struct {
    accel base;
    const prims_t *p;
    uint32_t res, objsize, nobj, ncell_per_obj;
    rcoh_obj *objs;
    uint32_t *ids, *prim_obj;
    rcoh_cell *cells;
    rcoh_ref *refs;
    uint64_t nrefs, refs_cap, prim_refs;
    rcoh_node *nodes;
    int32_t roots[6];
    uint32_t nnodes, nonempty;
    float margin;
    bool spheres; /* test a listed cluster's sphere before its primitives */
    accel *fb;
    accel *lb;    /* lights=on: the lights' direction cubes (a light buffer), else NULL */
} rcoh_t;

typedef struct { accel_ctx *fb; void (*fb_free)(accel_ctx *); } rcoh_ctx; /* the fallback's context */

/* fallback: a registered accelerator answering closest hits that does not
 * mutate and is not raycoh. */
static int check_fallback(const char *name)
{
    const struct accel_ops *ops = accel_find(name);
    return ops && strcmp(name, "raycoh") && ops->intersect && !(ops->flags & (ACCEL_MUTATES | ACCEL_SHADOW_ONLY)) ? 0 : -1;
}

static const accel_param rcoh_params[] = {
    PARAM_ROW_INT("res", "8", 1, 64, "cells per direction-cube face side (6 res^2 cells per cluster)"),
    PARAM_ROW_INT("objsize", "64", 1, 65536,
                  "primitives per cluster at most (clusters: the kit's median BVH leaves; far from the origin none "
                  "narrower than float coordinates resolve, so possibly more)"),
    PARAM_ROW_STRING("fallback", "bvh", "a registered accelerator that answers closest hits and does not mutate (not raycoh)",
                     check_fallback, "accelerator for rays without a usable origin primitive (eye, random rays)"),
    PARAM_ROW_BOOL("lights", "off", "on: a shadow ray toward a scene light is answered by that light's direction cube, "
                                    "a light buffer (lightbuf with its defaults); off: by the cube of the primitive it leaves"),
    PARAM_ROW_BOOL("spheres", "on", "test a listed cluster's bounding sphere before its primitives (an object's own bound)"),
    PARAM_ROW_END,
};

/* ------------------------------------------------------------ geometry */

/* The direction of (u, v) on face f (not normalised). */
static void face_dir(int f, double u, double v, double d[3])
{
    int a = f / 2, o1 = a == 0 ? 1 : 0, o2 = a == 2 ? 1 : 2;
    d[a] = f & 1 ? -1.0 : 1.0;
    d[o1] = u;
    d[o2] = v;
}

static double dnorm(double d[3])
{
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++) d[k] /= l;
    return l;
}

static double angle_between(const double a[3], const double b[3])
{
    double c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    return acos(c > 1.0 ? 1.0 : c < -1.0 ? -1.0 : c);
}

/* The bounding cone of cells [i0, i1) x [j0, j1) of face f, grown. */
static void block_cone(rcoh_node *n, int f, uint32_t res)
{
    double u0 = -1.0 + 2.0 * n->i0 / res - RC_UV_MARGIN, u1 = -1.0 + 2.0 * n->i1 / res + RC_UV_MARGIN;
    double v0 = -1.0 + 2.0 * n->j0 / res - RC_UV_MARGIN, v1 = -1.0 + 2.0 * n->j1 / res + RC_UV_MARGIN;
    face_dir(f, 0.5 * (u0 + u1), 0.5 * (v0 + v1), n->axis);
    dnorm(n->axis);
    double alpha = 0.0, c[3];
    const double us[2] = {u0, u1}, vs[2] = {v0, v1};
    for (int k = 0; k < 4; k++) {
        face_dir(f, us[k & 1], vs[k >> 1], c);
        dnorm(c);
        alpha = fmax(alpha, angle_between(n->axis, c));
    }
    n->alpha = alpha + RC_ANGLE_SLACK;
    n->face = f;
}

/* Build the quadtree below a block, halving its longer side; returns its index. */
static int32_t build_node(rcoh_t *t, int f, uint16_t i0, uint16_t i1, uint16_t j0, uint16_t j1)
{
    int32_t k = (int32_t)t->nnodes++;
    rcoh_node *n = &t->nodes[k];
    *n = (rcoh_node){.i0 = i0, .i1 = i1, .j0 = j0, .j1 = j1, .child = {-1, -1}};
    block_cone(n, f, t->res);
    if (i1 - i0 == 1 && j1 - j0 == 1) return k;
    int32_t a, b;
    if (i1 - i0 >= j1 - j0) {
        uint16_t m = (uint16_t)((i0 + i1) / 2);
        a = build_node(t, f, i0, m, j0, j1), b = build_node(t, f, m, i1, j0, j1);
    } else {
        uint16_t m = (uint16_t)((j0 + j1) / 2);
        a = build_node(t, f, i0, i1, j0, m), b = build_node(t, f, i0, i1, m, j1);
    }
    t->nodes[k].child[0] = a, t->nodes[k].child[1] = b;
    return k;
}

/* A cone of directions: unit axis, half-angle (>= pi: every direction). */
typedef struct { double axis[3], theta; } rcoh_cone;

/* The cells (local index (f res + j) res + i) of every leaf below node k whose cone meets c. */
static uint32_t cone_cells(const rcoh_t *t, int32_t k, const rcoh_cone *c, uint32_t *out, uint32_t n)
{
    const rcoh_node *nd = &t->nodes[k];
    if (c->theta < M_PI && angle_between(nd->axis, c->axis) > nd->alpha + c->theta + RC_ANGLE_SLACK) return n;
    if (nd->child[0] < 0) {
        out[n++] = ((uint32_t)nd->face * t->res + nd->j0) * t->res + nd->i0;
        return n;
    }
    n = cone_cells(t, nd->child[0], c, out, n);
    return cone_cells(t, nd->child[1], c, out, n);
}

/* The cell of A's cube (local index) that holds direction dir. */
static inline uint32_t cell_of(const rcoh_t *t, vec3 dir)
{
    int f = dircube_face(dir);
    float u, v;
    dircube_uv(dir, f, &u, &v);
    float s = 0.5f * (float)t->res;
    int i = (int)((u + 1.0f) * s), j = (int)((v + 1.0f) * s), r = (int)t->res - 1;
    i = i < 0 ? 0 : i > r ? r : i;
    j = j < 0 ? 0 : j > r ? r : j;
    return ((uint32_t)f * t->res + (uint32_t)j) * t->res + (uint32_t)i;
}

/* ------------------------------------------------------------ build */

/* Cluster k's bounding sphere: its box's centre, the farthest member box corner, rounded up. */
static void cluster_sphere(const prims_t *p, const uint32_t *ids, rcoh_obj *o)
{
    box3 b = prim_bounds(p, ids[0]);
    for (uint32_t i = 1; i < o->count; i++) b = box_union(b, prim_bounds(p, ids[i]));
    double c[3] = {0.5 * ((double)b.lo.x + b.hi.x), 0.5 * ((double)b.lo.y + b.hi.y), 0.5 * ((double)b.lo.z + b.hi.z)};
    double r2 = 0.0;
    for (uint32_t i = 0; i < o->count; i++) {
        box3 q = prim_bounds(p, ids[i]);
        double dx = fmax(fabs(q.lo.x - c[0]), fabs(q.hi.x - c[0]));
        double dy = fmax(fabs(q.lo.y - c[1]), fabs(q.hi.y - c[1]));
        double dz = fmax(fabs(q.lo.z - c[2]), fabs(q.hi.z - c[2]));
        r2 = fmax(r2, dx * dx + dy * dy + dz * dz);
    }
    o->c = v3((float)c[0], (float)c[1], (float)c[2]);
    /* The float centre moved by up to half an ulp a coordinate: cover that too. */
    double moved = fabs(o->c.x - c[0]) + fabs(o->c.y - c[1]) + fabs(o->c.z - c[2]);
    o->r = nextafterf((float)((sqrt(r2) + moved) * (1.0 + 1e-7)), INFINITY);
}

/* Whether box b fits in a cube of side w (every side narrower than w). */
static bool fits_cube(box3 b, float w)
{
    vec3 e = box_extent(b);
    return e.x < w && e.y < w && e.z < w;
}

/* The distinct primitives' copies: class c's members are
 * members[mstart[c] .. mstart[c + 1]). */
typedef struct {
    const uint32_t *mstart, *members;
} rcoh_classes;

/* The clusters below BVH node k (over the distinct primitives): a leaf, or
 * a node one of whose children fits in a cube of side min_cell, is one
 * cluster (every copy of every primitive below it, leaf after leaf); any
 * other node is split into its children's. */
static void emit_clusters(rcoh_t *t, const bvh_t *b, const rcoh_classes *cl, uint32_t k, float min_cell, uint32_t *first)
{
    const bvh_node *nd = &b->nodes[k];
    bool whole = nd->count || fits_cube(b->nodes[nd->index].box, min_cell) ||
                 fits_cube(b->nodes[nd->index + 1].box, min_cell);
    if (whole) {
        rcoh_obj *o = &t->objs[t->nobj];
        o->first = *first, o->count = 0;
        uint32_t stack[64], top = 0; /* the median tree is balanced: depth about log2(n / objsize) */
        stack[top++] = k;
        while (top) {
            const bvh_node *q = &b->nodes[stack[--top]];
            if (!q->count) {
                stack[top++] = q->index + 1, stack[top++] = q->index;
                continue;
            }
            for (uint32_t j = 0; j < q->count; j++) {
                uint32_t c = b->refs[q->index + j];
                for (uint32_t m = cl->mstart[c]; m < cl->mstart[c + 1]; m++) {
                    t->ids[*first + o->count++] = cl->members[m];
                    t->prim_obj[cl->members[m]] = t->nobj;
                }
            }
        }
        cluster_sphere(t->p, &t->ids[o->first], o);
        *first += o->count, t->nobj++;
        return;
    }
    emit_clusters(t, b, cl, nd->index, min_cell, first);
    emit_clusters(t, b, cl, nd->index + 1, min_cell, first);
}

/* Clusters: the median BVH's leaves of at most objsize primitives, except
 * that no cluster is made narrower than float coordinates at the scene's
 * position resolve (common/float_res.h): far from the origin the margin
 * that grows every sphere outgrows small clusters, every sphere then
 * covers its neighbours and every cell lists them all, so a node with a
 * child narrower than float_res_min_cell(scene box, margin) on every side
 * stays one cluster (more than objsize primitives). For a scene around the
 * origin that width (4 margins) is about 1e-5 of the scene's size, below
 * the clusters of anything but a tiny detail in a huge scene.
 *
 * The clusters are made over the distinct primitives (common/coincident.h):
 * every copy of one goes into its cluster, which may so hold more than
 * objsize. Clusters of copies would all lie at one place, each seeing all
 * the others in every direction: lists quadratic in the copies. */
static int make_clusters(rcoh_t *t)
{
    const prims_t *p = t->p;
    uint32_t n = p->count;
    prim_classes pc;
    if (prim_classes_init(&pc, p)) return -1;
    uint32_t m = pc.classes;
    /* Class j's members are members[mstart[j] .. mstart[j + 1]); cls[id] = j. */
    box3 *boxes = malloc((size_t)m * sizeof *boxes + 1);
    uint32_t *cls = malloc((size_t)n * sizeof *cls + 1), *mstart = calloc((size_t)m + 2, sizeof *mstart);
    uint32_t *members = malloc((size_t)n * sizeof *members + 1);
    if (!boxes || !cls || !mstart || !members) {
        free(boxes), free(cls), free(mstart), free(members);
        prim_classes_free(&pc);
        return -1;
    }
    for (uint32_t i = 0, j = 0; i < n; i++) {
        if (pc.rep && pc.rep[i] != i) {
            cls[i] = cls[pc.rep[i]]; /* the representative is the smallest id: already numbered */
        } else {
            boxes[j] = prim_bounds(p, i);
            cls[i] = j++;
        }
        mstart[cls[i] + 2]++;
    }
    prim_classes_free(&pc);
    for (uint32_t j = 0; j < m; j++) mstart[j + 2] += mstart[j + 1];
    for (uint32_t i = 0; i < n; i++) members[mstart[cls[i] + 1]++] = i;
    free(cls);
    bvh_config cfg;
    bvh_config_defaults(&cfg);
    cfg.max_leaf = t->objsize;
    bvh_t b;
    memset(&b, 0, sizeof b);
    int rc = bvh_build_median(&b, boxes, NULL, m, &cfg);
    free(boxes);
    if (rc != 0) {
        free(mstart), free(members);
        return -1;
    }
    t->objs = malloc((size_t)b.nleaves * sizeof *t->objs + 1);
    t->ids = malloc((size_t)n * sizeof *t->ids + 1);
    t->prim_obj = malloc((size_t)n * sizeof *t->prim_obj + 1);
    if (!t->objs || !t->ids || !t->prim_obj) {
        bvh_free(&b);
        free(mstart), free(members);
        return -1;
    }
    uint32_t first = 0;
    t->nobj = 0;
    rcoh_classes cl = {mstart, members};
    if (m) emit_clusters(t, &b, &cl, 0, float_res_min_cell(p->box, t->margin), &first); /* m = 0: no tree */
    bvh_free(&b);
    free(mstart), free(members);
    return 0;
}

/* The cone and distance bound of rays from cluster a to cluster b, radii grown by g. */
static rcoh_cone pair_cone(const rcoh_obj *a, const rcoh_obj *b, double g, float *d)
{
    rcoh_cone c;
    c.axis[0] = (double)b->c.x - a->c.x, c.axis[1] = (double)b->c.y - a->c.y, c.axis[2] = (double)b->c.z - a->c.z;
    double D = sqrt(c.axis[0] * c.axis[0] + c.axis[1] * c.axis[1] + c.axis[2] * c.axis[2]);
    double R = (double)a->r + b->r + 2.0 * g;
    if (a == b || !(D > R * (1.0 + 1e-9))) {
        c.theta = 2.0 * M_PI, *d = 0.0f;
        c.axis[0] = 1.0, c.axis[1] = c.axis[2] = 0.0;
        return c;
    }
    for (int k = 0; k < 3; k++) c.axis[k] /= D;
    c.theta = asin(R / D);
    double dd = (D - R) * (1.0 - RC_DEPTH_SLACK);
    float df = (float)dd;
    *d = (double)df > dd ? nextafterf(df, 0.0f) : df;
    return c;
}

typedef struct { uint32_t obj; float d; } rcoh_pair;

static int pair_cmp(const void *x, const void *y)
{
    const rcoh_pair *a = x, *b = y;
    if (a->d != b->d) return a->d < b->d ? -1 : 1;
    return a->obj < b->obj ? -1 : a->obj > b->obj;
}

/* Room for m more refs, within the cap. */
static int refs_reserve(rcoh_t *t, uint64_t m, uint64_t base_bytes, uint64_t cap, char *err, size_t errlen)
{
    if (t->nrefs + m <= t->refs_cap) return 0;
    uint64_t want = t->refs_cap ? t->refs_cap : 1024;
    while (want < t->nrefs + m) want *= 2;
    if (want > UINT32_MAX) want = t->nrefs + m;
    if (t->nrefs + m > UINT32_MAX) {
        snprintf(err, errlen, "raycoh: over 2^32 - 1 list entries: lower res or raise objsize");
        return -2;
    }
    uint64_t bytes = memcap_add(base_bytes, memcap_mul(t->nrefs + m, sizeof(rcoh_ref)));
    if (memcap_exceeded(bytes, cap, err, errlen, "raycoh's clusters, cells and %llu list entries",
                        (unsigned long long)(t->nrefs + m)))
        return -2;
    if (memcap_mul(want, sizeof(rcoh_ref)) + base_bytes > cap * 1048576ull) want = t->nrefs + m;
    rcoh_ref *r = realloc(t->refs, (size_t)want * sizeof *r);
    if (!r) return -1;
    t->refs = r, t->refs_cap = want;
    return 0;
}

/* Cluster a's cube: every cluster, in order of d, into the cells its cone
 * meets. cellbuf: [0, nc) one cone's cells, then the cell of every staged
 * ref (nc (1 + nobj) entries in all); the refs are staged in the refs
 * array's tail, then counting-sorted by cell, stably, so each cell's run
 * stays sorted by d. */
static int fill_cube(rcoh_t *t, uint32_t a, rcoh_pair *pairs, uint32_t *cellbuf, uint32_t *count, uint64_t base_bytes,
                     uint64_t cap, char *err, size_t errlen)
{
    const rcoh_obj *A = &t->objs[a];
    uint32_t nc = t->ncell_per_obj;
    for (uint32_t b = 0; b < t->nobj; b++) {
        pairs[b].obj = b;
        pair_cone(A, &t->objs[b], t->margin, &pairs[b].d);
    }
    qsort(pairs, t->nobj, sizeof *pairs, pair_cmp);
    memset(count, 0, nc * sizeof *count);
    uint64_t m = 0;
    for (uint32_t k = 0; k < t->nobj; k++) {
        float d;
        rcoh_cone c = pair_cone(A, &t->objs[pairs[k].obj], t->margin, &d);
        uint32_t n = 0;
        for (int f = 0; f < 6; f++) n = cone_cells(t, t->roots[f], &c, cellbuf, n);
        int rc = refs_reserve(t, m + n, base_bytes, cap, err, errlen);
        if (rc) return rc;
        for (uint32_t i = 0; i < n; i++) {
            t->refs[t->nrefs + m + i] = (rcoh_ref){pairs[k].obj, d};
            cellbuf[nc + m + i] = cellbuf[i];
            count[cellbuf[i]]++;
        }
        m += n;
    }
    rcoh_cell *cells = &t->cells[(size_t)a * nc];
    uint32_t first = (uint32_t)t->nrefs;
    for (uint32_t c = 0; c < nc; c++) {
        cells[c].first = first, cells[c].count = 0;
        first += count[c];
        t->nonempty += count[c] != 0;
    }
    rcoh_ref *staged = malloc((size_t)m * sizeof *staged + 1);
    if (!staged) return -1;
    memcpy(staged, &t->refs[t->nrefs], (size_t)m * sizeof *staged);
    for (uint64_t i = 0; i < m; i++) {
        rcoh_cell *cl = &cells[cellbuf[nc + i]];
        t->refs[cl->first + cl->count++] = staged[i];
        t->prim_refs += t->objs[staged[i].obj].count;
    }
    free(staged);
    t->nrefs += m;
    return 0;
}

static void rcoh_destroy(accel *a)
{
    rcoh_t *t = (rcoh_t *)a;
    if (!t) return;
    if (t->fb) t->fb->ops->destroy(t->fb);
    if (t->lb) t->lb->ops->destroy(t->lb);
    free(t->objs), free(t->ids), free(t->prim_obj), free(t->cells), free(t->refs), free(t->nodes);
    free(t);
}

static accel *build_fallback(const scene_t *scene, const accel_params *params, const char *name, char *err, size_t errlen)
{
    const struct accel_ops *ops = accel_find(name);
    if (!ops || strcmp(name, "raycoh") == 0 || !ops->intersect || (ops->flags & (ACCEL_MUTATES | ACCEL_SHADOW_ONLY))) {
        snprintf(err, errlen, "raycoh: fallback '%s' is not a registered accelerator answering closest hits that does "
                 "not mutate (and is not raycoh)", name);
        return NULL;
    }
    accel_params fp;
    params_defaults(&fp, ops->params);
    fp.threads = params->threads, fp.seed = params->seed, fp.memcap_mib = params->memcap_mib; /* the harness's */
    char sub[400];
    accel *fb = accel_build(ops, scene, &fp, sub, sizeof sub);
    if (!fb) {
        snprintf(err, errlen, "raycoh: fallback %s: %s", name, sub);
        return NULL;
    }
    if (accel_serial(fb)) {
        fb->ops->destroy(fb);
        snprintf(err, errlen, "raycoh: fallback '%s' must be traced on one thread; choose another", name);
        return NULL;
    }
    return fb;
}

/* lights=on: the light entities' cubes, one light buffer over every scene
 * light (lightbuf, its defaults, the harness's threads). */
static accel *build_lights(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    const struct accel_ops *ops = accel_find("lightbuf");
    accel_params lp;
    params_defaults(&lp, ops->params);
    lp.threads = params->threads, lp.seed = params->seed, lp.memcap_mib = params->memcap_mib;
    char sub[400];
    accel *lb = accel_build(ops, scene, &lp, sub, sizeof sub);
    if (!lb) snprintf(err, errlen, "raycoh: lights=on: lightbuf: %s", sub);
    return lb;
}

static accel *rcoh_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    long res = params_int(params, "res"), objsize = params_int(params, "objsize");
    uint64_t cap = params_memcap(params, 4096);
    bool spheres = params_bool(params, "spheres"), lights = params_bool(params, "lights");
    rcoh_t *t = calloc(1, sizeof *t);
    if (!t) goto oom;
    t->p = &scene->prims;
    t->res = (uint32_t)res, t->objsize = (uint32_t)objsize, t->spheres = spheres;
    t->ncell_per_obj = 6 * t->res * t->res;
    t->fb = build_fallback(scene, params, params_string(params, "fallback"), err, errlen);
    if (!t->fb) goto fail;
    if (lights && !(t->lb = build_lights(scene, params, err, errlen))) goto fail;
    uint32_t n = t->p->count;
    uint64_t maxobj = n ? (n + t->objsize - 1) / t->objsize * 2 : 0; /* median leaves hold at least objsize/2 */
    uint64_t nodes_bytes = memcap_mul(4 * (uint64_t)t->ncell_per_obj, sizeof(rcoh_node));
    uint64_t base = memcap_add(memcap_add(memcap_mul(maxobj, sizeof(rcoh_obj)), memcap_mul(n, 8)),
                               memcap_add(memcap_mul(memcap_mul(maxobj, t->ncell_per_obj), sizeof(rcoh_cell)), nodes_bytes));
    if (memcap_exceeded(memcap_add(base, memcap_mul(maxobj, t->ncell_per_obj * sizeof(rcoh_ref))), cap, err,
                        errlen, "raycoh's %llu clusters with %u cells each and their self entries",
                        (unsigned long long)maxobj, t->ncell_per_obj))
        goto fail;
    box3 sb = t->p->box;
    t->margin = n ? 1e-6f * box_diagonal(sb) + 4e-6f * float_res_magnitude(sb) + 1e-30f : 0.0f;
    t->nodes = malloc((size_t)4 * t->ncell_per_obj * sizeof *t->nodes);
    if (!t->nodes) goto oom;
    for (int f = 0; f < 6; f++) t->roots[f] = build_node(t, f, 0, (uint16_t)t->res, 0, (uint16_t)t->res);
    if (n && make_clusters(t)) goto oom;
    /* Every cluster is listed in at least one cell of every cube: nobj^2 entries at least, known before any. */
    uint64_t least = memcap_add(memcap_mul(memcap_mul(t->nobj, t->nobj), sizeof(rcoh_ref)),
                                memcap_mul(memcap_mul(t->nobj, t->ncell_per_obj), sizeof(rcoh_cell) + 4));
    if (memcap_exceeded(least, cap, err, errlen, "raycoh's %u clusters, all pairs listed at least once,",
                        t->nobj))
        goto fail;
    t->cells = calloc((size_t)t->nobj * t->ncell_per_obj + 1, sizeof *t->cells);
    /* Per cube: the pairs, and every cluster's cells (a cube may list a cluster in all its cells). */
    rcoh_pair *pairs = malloc((size_t)t->nobj * sizeof *pairs + 1);
    uint32_t *count = malloc((size_t)t->ncell_per_obj * sizeof *count);
    uint64_t cb = (uint64_t)t->ncell_per_obj * (1 + (uint64_t)t->nobj);
    uint32_t *cellbuf = malloc((size_t)cb * sizeof *cellbuf);
    int rc = t->cells && pairs && count && cellbuf ? 0 : -1;
    uint64_t base_bytes = memcap_add(memcap_add(memcap_mul(t->nobj, sizeof(rcoh_obj)), memcap_mul(n, 8)),
                                     memcap_add(memcap_mul(memcap_mul(t->nobj, t->ncell_per_obj), sizeof(rcoh_cell)),
                                                nodes_bytes));
    for (uint32_t a = 0; a < t->nobj && rc == 0; a++)
        rc = fill_cube(t, a, pairs, cellbuf, count, base_bytes, cap, err, errlen);
    free(pairs), free(count), free(cellbuf);
    if (rc == -2) goto fail;
    if (rc) goto oom;
    return &t->base;
oom:
    snprintf(err, errlen, "raycoh: out of memory building over %u primitives", scene->prims.count);
fail:
    rcoh_destroy(t ? &t->base : NULL);
    return NULL;
}

/* ------------------------------------------------------------ queries */

/* The cluster whose cube answers ray, or RC_NO_OBJ: the origin primitive in
 * range and the ray's org within its cluster's sphere grown by margin (the
 * cones assume 2 margin: the rounding of this test cannot matter). */
static inline uint32_t origin_cluster(const rcoh_t *t, const ray_t *ray)
{
    uint32_t o = ray->origin;
    if (o >= t->p->count) return RC_NO_OBJ;
    uint32_t k = t->prim_obj[o];
    const rcoh_obj *A = &t->objs[k];
    double dx = (double)ray->org.x - A->c.x, dy = (double)ray->org.y - A->c.y, dz = (double)ray->org.z - A->c.z;
    double r = (double)A->r + t->margin;
    return dx * dx + dy * dy + dz * dz <= r * r ? k : RC_NO_OBJ;
}

/* |dir| grown by the stop slack, in double: a float |dir|^2 underflows to 0
 * for directions of tiny components (which would stop every walk at once)
 * and overflows for huge ones. */
static inline double ray_dir_len(const ray_t *ray)
{
    double x = ray->dir.x, y = ray->dir.y, z = ray->dir.z;
    return sqrt(x * x + y * y + z * z) * (1.0 + RC_STOP_SLACK);
}

/* Whether the ray may meet cluster o's primitives in [tnear, tmax]: its
 * line passes within the sphere (radius grown by 2 margin, as the cones
 * are, and by 1e-6 relative) and the chord through it overlaps the range
 * (by 1e-6 of the distances involved). In double, from the perpendicular
 * offset (no cancellation of b^2 against |o|^2 |d|^2). */
static inline bool sphere_may_hit(const rcoh_t *t, const rcoh_obj *o, const ray_t *ray, float tmax)
{
    double ox = (double)ray->org.x - o->c.x, oy = (double)ray->org.y - o->c.y, oz = (double)ray->org.z - o->c.z;
    double dx = ray->dir.x, dy = ray->dir.y, dz = ray->dir.z, dd = dx * dx + dy * dy + dz * dz;
    double tca = -(ox * dx + oy * dy + oz * dz) / dd;
    double px = ox + tca * dx, py = oy + tca * dy, pz = oz + tca * dz;
    double R = ((double)o->r + 2.0 * t->margin) * (1.0 + 1e-6), h2 = R * R - (px * px + py * py + pz * pz);
    if (h2 < 0.0) return false;
    double h = sqrt(h2 / dd), slack = 1e-6 * (fabs(tca) + h) + 1e-30;
    return tca + h + slack >= ray->tnear && tca - h - slack <= tmax;
}

static inline __attribute__((always_inline)) bool walk_closest(const rcoh_t *t, uint32_t k, const ray_t *ray, hit_t *hit,
                                                               counters_t *c, const bool counting)
{
    const rcoh_cell *cl = &t->cells[(size_t)k * t->ncell_per_obj + cell_of(t, ray->dir)];
    double dl = ray_dir_len(ray);
    if (counting && !cl->count) c->empty_leaves++;
    const rcoh_ref *r = &t->refs[cl->first], *end = r + cl->count;
    for (; r < end; r++) {
        if (r->d > hit->t * dl) break; /* every later object lies beyond the closest hit (double: no overflow) */
        if (counting) c->steps++, c->box_tests += t->spheres;
        const rcoh_obj *o = &t->objs[r->obj];
        if (t->spheres && !sphere_may_hit(t, o, ray, hit->t)) continue;
        for (uint32_t i = 0; i < o->count; i++) prim_test_closest(t->p, t->ids[o->first + i], ray, hit, c, counting);
    }
    return hit->prim != HIT_NONE;
}

static inline __attribute__((always_inline)) bool walk_any(const rcoh_t *t, uint32_t k, const ray_t *ray, counters_t *c,
                                                           const bool counting)
{
    const rcoh_cell *cl = &t->cells[(size_t)k * t->ncell_per_obj + cell_of(t, ray->dir)];
    double reach = ray->tfar * ray_dir_len(ray);
    if (counting && !cl->count) c->empty_leaves++;
    const rcoh_ref *r = &t->refs[cl->first], *end = r + cl->count;
    for (; r < end; r++) {
        if (r->d > reach) break;
        if (counting) c->steps++, c->box_tests += t->spheres;
        const rcoh_obj *o = &t->objs[r->obj];
        if (t->spheres && !sphere_may_hit(t, o, ray, ray->tfar)) continue;
        for (uint32_t i = 0; i < o->count; i++)
            if (prim_test_any(t->p, t->ids[o->first + i], ray, c, counting)) return true;
    }
    return false;
}

static accel_ctx *rcoh_context_new(accel *a)
{
    rcoh_t *t = (rcoh_t *)a;
    rcoh_ctx *x = calloc(1, sizeof *x);
    if (x && t->fb->ops->context_new) x->fb = t->fb->ops->context_new(t->fb), x->fb_free = t->fb->ops->context_free;
    return (accel_ctx *)x;
}

static void rcoh_context_free(accel_ctx *ctx)
{
    rcoh_ctx *x = (rcoh_ctx *)ctx;
    if (x && x->fb_free) x->fb_free(x->fb);
    free(x);
}

static bool rcoh_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    rcoh_t *t = (rcoh_t *)a;
    uint32_t k = origin_cluster(t, ray);
    if (k == RC_NO_OBJ) return t->fb->ops->intersect(t->fb, ((rcoh_ctx *)ctx)->fb, ray, hit, c);
    return walk_closest(t, k, ray, hit, c, true);
}

static bool rcoh_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    rcoh_t *t = (rcoh_t *)a;
    if (t->lb && ray->light != RAY_NO_LIGHT) return t->lb->ops->occluded(t->lb, NULL, ray, c);
    uint32_t k = origin_cluster(t, ray);
    if (k == RC_NO_OBJ) return t->fb->ops->occluded(t->fb, ((rcoh_ctx *)ctx)->fb, ray, c);
    return walk_any(t, k, ray, c, true);
}

static bool rcoh_intersect_fast(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit)
{
    rcoh_t *t = (rcoh_t *)a;
    uint32_t k = origin_cluster(t, ray);
    if (k == RC_NO_OBJ) {
        accel *f = t->fb;
        if (f->ops->version >= 2 && f->ops->intersect_fast) return f->ops->intersect_fast(f, ((rcoh_ctx *)ctx)->fb, ray, hit);
        counters_t dummy = {0};
        return f->ops->intersect(f, ((rcoh_ctx *)ctx)->fb, ray, hit, &dummy);
    }
    return walk_closest(t, k, ray, hit, NULL, false);
}

static bool rcoh_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *ray)
{
    rcoh_t *t = (rcoh_t *)a;
    if (t->lb && ray->light != RAY_NO_LIGHT) return t->lb->ops->occluded_fast(t->lb, NULL, ray);
    uint32_t k = origin_cluster(t, ray);
    if (k == RC_NO_OBJ) {
        accel *f = t->fb;
        if (f->ops->version >= 2 && f->ops->occluded_fast) return f->ops->occluded_fast(f, ((rcoh_ctx *)ctx)->fb, ray);
        counters_t dummy = {0};
        return f->ops->occluded(f, ((rcoh_ctx *)ctx)->fb, ray, &dummy);
    }
    return walk_any(t, k, ray, NULL, false);
}

static size_t rcoh_memory(const accel *a)
{
    const rcoh_t *t = (const rcoh_t *)a;
    return sizeof *t + (size_t)t->nobj * sizeof(rcoh_obj) + (size_t)t->p->count * 8 +
           (size_t)t->nobj * t->ncell_per_obj * sizeof(rcoh_cell) + (size_t)t->nrefs * sizeof(rcoh_ref) +
           (size_t)t->nnodes * sizeof(rcoh_node) + t->fb->ops->memory(t->fb) +
           (t->lb ? t->lb->ops->memory(t->lb) : 0);
}

static int rcoh_stats(const accel *a, accel_stat *out, int max)
{
    const rcoh_t *t = (const rcoh_t *)a;
    uint64_t cells = (uint64_t)t->nobj * t->ncell_per_obj;
    accel_stat s[] = {
        {"nodes", (double)cells},
        {"leaves", (double)t->nonempty},
        {"empty_leaves", (double)(cells - t->nonempty)},
        {"avg_leaf_prims", t->nonempty ? (double)t->prim_refs / (double)t->nonempty : 0.0},
        {"refs_per_prim", t->p->count ? (double)t->prim_refs / t->p->count : 0.0},
        {"res_x", (double)t->res},
        {"res_y", (double)t->res},
    };
    int n = (int)(sizeof s / sizeof s[0]);
    if (n > max) n = max;
    memcpy(out, s, (size_t)n * sizeof *s);
    return n;
}

static const char *const rcoh_variants[] = {
    "res=1,objsize=1",
    "res=3,objsize=5,spheres=off",
    "res=16,objsize=8,fallback=grid",
    "objsize=65536,fallback=exhaustive",
    "lights=on",
    NULL,
};

const struct accel_ops accel_raycoh = {
    .version = 2,
    .name = "raycoh",
    .summary = "Ohta-Maekawa ray coherence: a direction cube per primitive cluster, candidate clusters by the "
               "coherence theorem's cone, depth-sorted; rays without an origin to a fallback",
    .paper = "Ohta & Maekawa, CG International 1987; Arvo & Kirk 1989 survey s6.1, s6.3, s6.5, figs. 19-21",
    .params = rcoh_params,
    .flags = 0,
    .build = rcoh_build,
    .context_new = rcoh_context_new,
    .context_free = rcoh_context_free,
    .intersect = rcoh_intersect,
    .occluded = rcoh_occluded,
    .memory = rcoh_memory,
    .destroy = rcoh_destroy,
    .stats = rcoh_stats,
    .intersect_fast = rcoh_intersect_fast,
    .occluded_fast = rcoh_occluded_fast,
    .variants = rcoh_variants,
    .cost = {2, 4, 0},
    .tune = "res=4|8|16|32", /* cells per cube face side */
};

/* ------------------------------------------------------------ test hooks */

bool raycoh_debug_listed(vec3 c1, float r1, vec3 c2, float r2, uint32_t res, vec3 dir)
{
    /* The quadtree of the last res asked for, kept (tests ask many times). */
    static rcoh_t t;
    static uint32_t *cells;
    if (t.res != res) {
        free(t.nodes), free(cells);
        memset(&t, 0, sizeof t);
        t.res = res, t.ncell_per_obj = 6 * res * res;
        t.nodes = malloc((size_t)4 * t.ncell_per_obj * sizeof *t.nodes);
        cells = malloc((size_t)t.ncell_per_obj * sizeof *cells);
        if (!t.nodes || !cells) abort();
        for (int f = 0; f < 6; f++) t.roots[f] = build_node(&t, f, 0, (uint16_t)res, 0, (uint16_t)res);
    }
    rcoh_obj a = {c1, r1, 0, 1}, b = {c2, r2, 0, 1};
    float d;
    rcoh_cone c = pair_cone(&a, &b, 0.0, &d);
    uint32_t n = 0, want = cell_of(&t, dir);
    for (int f = 0; f < 6; f++) n = cone_cells(&t, t.roots[f], &c, cells, n);
    bool found = false;
    for (uint32_t i = 0; i < n; i++) found |= cells[i] == want;
    return found;
}

float raycoh_debug_depth(vec3 c1, float r1, vec3 c2, float r2)
{
    rcoh_obj a = {c1, r1, 0, 1}, b = {c2, r2, 0, 1};
    float d;
    pair_cone(&a, &b, 0.0, &d);
    return d;
}

uint32_t raycoh_debug_clusters(const accel *a) { return ((const rcoh_t *)a)->nobj; }

bool raycoh_debug_uses_cube(const accel *a, const ray_t *ray) { return origin_cluster((const rcoh_t *)a, ray) != RC_NO_OBJ; }
