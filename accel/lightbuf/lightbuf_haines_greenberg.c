/* lightbuf_haines_greenberg.c: `lightbuf`, Haines and Greenberg's light
 * buffer: shadow rays only. Reference: docs/accels/directional.md.
 *
 * Paper: E. A. Haines, D. P. Greenberg, "The Light Buffer: A Shadow-Testing
 * Accelerator", IEEE CG&A 6(9), 1986, as the Arvo-Kirk survey (1989)
 * describes it in s6.1 (the direction cube, figure 19: common/dircube.h)
 * and s6.2: a direction cube of res x res cells a face per point light;
 * each primitive listed in every cell its projection covers, lists sorted
 * by depth from the light; a shadow query reads the cell of its direction
 * and tests in depth order until an occluder or a candidate beyond the
 * point; s6.2's three simplifications as switches (cull, single, fullocc),
 * each implemented only in a form proven sound (the page says how); cull
 * rests on the closed-solid analysis of closed_solids.h.
 *
 * Build: in double, relative to the light, with a u-v margin M
 * (min(1/8, max(cell side / 16, 2^-10))): a primitive is in every cell
 * whose square grown by M meets its projection. Triangles and polygon ears
 * are clipped (Sutherland-Hodgman) to |u|, |v| <= 1 + M and rasterised
 * conservatively row by row; spheres and cones through their bounding
 * box's faces. A primitive within rho (2^-8 of the light's distance to
 * the scene box's far corner) goes to the light's NEAR LIST, read by every
 * query of that light, so cells hold only primitives with real depths.
 * Depths are lower bounds of the distance from the light, rounded down.
 *
 * Query invariants (Ps = O + tnear D, Pe = O + tfar D):
 *   - only a shadow ray of a light whose Pe is within rho / 4096 of it is
 *     answered by the buffer; every other any-hit ray goes to the FALLBACK,
 *     the kit's binned-SAH BVH (exact, counted as the bvh's work);
 *   - the segment lies within max(|Ps - L|, e) of L: a deeper candidate
 *     cannot touch it (the stopping rule);
 *   - |Ps - L| <= rho: the near list alone; else the cell of Ps - L, whose
 *     M-grown square holds every direction of the segment's part beyond
 *     rho unless 8 e / rho > M (then the fallback);
 *   - order: full-occlusion record, single-polygon plane test, the cell's
 *     list by depth, the near list by depth.
 *
 * Memory (memory() counts it), per light: cells[6 res^2] (lb_cell, 16
 * bytes: first, count, occ depth, single slab index; cell
 * (face res + j) res + i, faces +x -x +y -y +z -z), refs (lb_ref, 8 bytes:
 * id, depth; each run sorted by (depth, id)), the near list, slabs (20
 * bytes), lb_light (80). Shared: the fallback BVH. No per-thread context.
 *
 * Counters: steps = cells read (+ fallback nodes); empty_leaves = cells
 * read with no candidate and no record; box_tests = single-polygon plane
 * tests (+ fallback boxes); a full-occlusion answer is a step, no test.
 *
 * Not implemented: the scan-line rasteriser itself (same coverage), lights
 * other than points, the shading point's orientation test, enclosing
 * meshes for curved surfaces, culling of solids neither convex nor
 * embedded, per-cell minimum depths, per-light resolutions, adaptive face
 * subdivision (survey figure 18(c)). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../accel.h"
#include "lightbuf_haines_greenberg.h"
#include "closed_solids.h"
#include "../bvh/bvh.h"
#include "../common/coincident.h"
#include "../common/dircube.h"
#include "../common/memcap.h"
#include "../common/prim_hit.h"
#include "../../prims/checked_alloc.h"

#define BODY static inline __attribute__((always_inline))
#define LB_NONE UINT32_MAX
#define LB_RES_MAX 1024
#define LB_RHO_FRAC (1.0 / 256.0)   /* rho over the light's reach */
#define LB_END_FRAC (1.0 / 4096.0)  /* the largest e / rho a shadow ray may have */
#define LB_PERTURB 8.0              /* u-v movement per unit of e / rho (see the header) */
#define LB_UV_ROUND 4e-6            /* dircube_uv's float rounding of W, with room */
#define LB_DEPTH_SLACK 1e-6         /* relative: depths rounded down, query depths and occ up */

static const accel_param lb_params[] = {
    PARAM_ROW_INT_OR("res", "auto", "auto", 1, LB_RES_MAX,
                     "cells per direction-cube face side (6 res^2 cells per light); auto: from the scene's size"),
    PARAM_ROW_BOOL("cull", "on", "drop polygons facing away from the light on closed solids (convex or embedded, decided soundly)"),
    PARAM_ROW_BOOL("single", "on", "a cell listing one polygon skips its test when the segment stays on one side of it"),
    PARAM_ROW_BOOL("fullocc", "on", "full-occlusion records: points beyond a primitive covering the cell are in shadow"),
    PARAM_ROW_END,
};

typedef struct {
    uint32_t id; /* primitive */
    float depth; /* lower bound of its distance from the light */
} lb_ref;
_Static_assert(sizeof(lb_ref) == 8, "lb_ref is 8 bytes");

typedef struct {
    uint32_t first, count; /* the cell's run refs[first .. first + count) */
    float occ;             /* full-occlusion depth, +inf for none */
    uint32_t single;       /* index into slabs when the list is one polygon (single=on), else LB_NONE */
} lb_cell;
_Static_assert(sizeof(lb_cell) == 16, "lb_cell is 16 bytes: four to a cache line");

typedef struct {
    vec3 n;        /* unit normal */
    float lo, hi;  /* n . x over the polygon lies in [lo, hi] */
} lb_slab;
_Static_assert(sizeof(lb_slab) == 20, "lb_slab is 20 bytes");

typedef struct {
    double pos[3]; /* the light */
    double rho;    /* near-list radius */
    lb_cell *cells;
    lb_ref *refs, *near;
    lb_slab *slabs;
    uint32_t nrefs, nnear, nslabs, nculled;
} lb_light;

typedef struct {
    accel base;
    const prims_t *p;
    uint32_t res, ncells; /* ncells = 6 res^2, per light */
    double margin;        /* M, u-v units */
    bool cull, single, fullocc;
    uint32_t nlights;
    lb_light *lights;
    bvh_t fallback;
} lb_t;

/* ------------------------------------------------- a primitive's pieces */

/* The convex planar pieces a primitive is projected through: its
 * triangle, a polygon's ear triangles, or the twelve triangles of a
 * sphere's or cone's bounding box (its polyhedral hull). Returns how many
 * (at most LB_MAX_PIECES; polygons may have more: *more is then set and
 * the caller pages through them with `from`). */
#define LB_MAX_PIECES 64
static uint32_t prim_pieces(const prims_t *p, uint32_t id, uint32_t from, dvec3 out[][3], bool *more)
{
    *more = false;
    uint32_t k = p->index[id];
    switch ((prim_kind)p->kind[id]) {
    case PRIM_TRIANGLE:
        if (from) return 0;
        for (int v = 0; v < 3; v++) out[0][v] = dv3(p->verts[p->tris[k].v[v]]);
        return 1;
    case PRIM_POLYGON: {
        const polygon_t *g = &p->polygons[k];
        uint32_t nt = g->count - 2, n = 0;
        for (uint32_t t = from; t < nt && n < LB_MAX_PIECES; t++, n++)
            for (int v = 0; v < 3; v++) out[n][v] = dv3(p->verts[p->poly_tris[g->tri_first + t].v[v]]);
        *more = from + n < nt;
        return n;
    }
    default: {
        if (from) return 0;
        box3 b = prim_bounds(p, id);
        dvec3 c[8];
        for (int i = 0; i < 8; i++)
            c[i] = (dvec3){i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 4 ? b.hi.z : b.lo.z};
        static const int quads[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
        for (int q = 0; q < 6; q++) {
            out[2 * q][0] = c[quads[q][0]], out[2 * q][1] = c[quads[q][1]], out[2 * q][2] = c[quads[q][2]];
            out[2 * q + 1][0] = c[quads[q][0]], out[2 * q + 1][1] = c[quads[q][2]], out[2 * q + 1][2] = c[quads[q][3]];
        }
        return 12;
    }
    }
}

static bool prim_degenerate(const prims_t *p, uint32_t id)
{
    uint32_t k = p->index[id];
    if (p->kind[id] == PRIM_TRIANGLE) return p->tri_degenerate[k];
    if (p->kind[id] == PRIM_POLYGON) return p->polygons[k].degenerate;
    return false;
}

/* A lower bound of the distance from L to primitive id (see the header). */
static double prim_min_dist(const prims_t *p, uint32_t id, dvec3 L)
{
    uint32_t k = p->index[id];
    switch ((prim_kind)p->kind[id]) {
    case PRIM_SPHERE:
        return dv3_len(dv3_sub(dv3(p->spheres[k].center), L)) - p->spheres[k].radius;
    case PRIM_CONE: {
        const cone_t *c = &p->cones[k];
        return dv3_point_segment_distance(L, dv3(c->base), dv3(c->apex)) - fmax(c->base_radius, c->apex_radius);
    }
    default: {
        dvec3 t[LB_MAX_PIECES][3];
        bool more = true;
        double d = INFINITY;
        for (uint32_t from = 0; more;) {
            uint32_t n = prim_pieces(p, id, from, t, &more);
            for (uint32_t i = 0; i < n; i++) d = fmin(d, dv3_point_triangle_distance(L, t[i][0], t[i][1], t[i][2]));
            from += n;
        }
        return d;
    }
    }
}

/* -------------------------------------------------- the direction cube */

/* Face f's frame (figure 19): the dominant axis, its sign, and U and V,
 * the other two axes in lexicographic order. */
static void face_axes(int f, int *major, double *sign, int *ua, int *va)
{
    *major = f >> 1;
    *sign = (f & 1) ? -1.0 : 1.0;
    *ua = *major == 0 ? 1 : 0;
    *va = *major == 2 ? 1 : 2;
}

/* The world direction through (u, v) of face f. */
static dvec3 face_dir(int f, double u, double v)
{
    int major, ua, va;
    double sign;
    face_axes(f, &major, &sign, &ua, &va);
    dvec3 d = {0, 0, 0}; /* every axis set below: major, ua and va are the three */
    dv3_set(&d, major, sign), dv3_set(&d, ua, u), dv3_set(&d, va, v);
    return d;
}

/* --------------------------------------------------------- projection */

typedef struct {
    lb_t *t;
    lb_light *L;
    uint32_t *stamp; /* [ncells]: the last primitive (id + 1) marked in each cell */
    uint32_t *count; /* pass 1: refs per cell; pass 2: refs written per cell */
    bool fill;       /* pass 2 */
    uint32_t id;
    float depth;
    uint64_t total;  /* refs marked */
    uint32_t *marked; /* pass 2, fullocc: the cells the current primitive marked */
    uint32_t nmarked, marked_cap;
    bool oom;
} lb_raster;

static void mark_cell(lb_raster *r, uint32_t cell)
{
    if (r->stamp[cell] == r->id + 1) return;
    r->stamp[cell] = r->id + 1;
    r->total++;
    if (r->fill) {
        lb_cell *c = &r->L->cells[cell];
        r->L->refs[c->first + r->count[cell]] = (lb_ref){r->id, r->depth};
        if (r->t->fullocc) {
            if (r->nmarked == r->marked_cap) {
                uint32_t cap = r->marked_cap ? 2 * r->marked_cap : 256;
                uint32_t *m = realloc(r->marked, (size_t)cap * sizeof *m);
                if (!m) {
                    r->oom = true;
                    r->count[cell]++;
                    return;
                }
                r->marked = m, r->marked_cap = cap;
            }
            r->marked[r->nmarked++] = cell;
        }
    }
    r->count[cell]++;
}

/* Clip triangle tri (relative to the light) against face f's pyramid
 * |x|, |y| <= K z grown to K = 1 + M, and project: uv[n][2]. Returns n
 * (0: nothing in the pyramid), or -1 when a clipped point is not in front
 * of the light (z <= 0: only a primitive through the light). */
static int clip_project(const dvec3 tri[3], int f, double K, double uv[16][2])
{
    int major, ua, va;
    double sign;
    face_axes(f, &major, &sign, &ua, &va);
    double a[16][3], b[16][3];
    int n = 3;
    for (int i = 0; i < 3; i++) a[i][0] = dv3_get(tri[i], ua), a[i][1] = dv3_get(tri[i], va), a[i][2] = sign * dv3_get(tri[i], major);
    /* The four planes K z -+ x >= 0, K z -+ y >= 0, one after another. */
    for (int pl = 0; pl < 4 && n > 0; pl++) {
        int axis = pl >> 1;
        double s = (pl & 1) ? 1.0 : -1.0;
        int m = 0;
        for (int i = 0; i < n; i++) {
            const double *p = a[i], *q = a[(i + 1) % n];
            double dp = K * p[2] + s * p[axis], dq = K * q[2] + s * q[axis];
            if (dp >= 0) memcpy(b[m++], p, sizeof b[0]);
            if ((dp >= 0) != (dq >= 0)) {
                double w = dp / (dp - dq);
                for (int c = 0; c < 3; c++) b[m][c] = p[c] + w * (q[c] - p[c]);
                m++;
            }
        }
        n = m;
        memcpy(a, b, (size_t)n * sizeof a[0]);
    }
    for (int i = 0; i < n; i++) {
        if (!(a[i][2] > 0)) return -1;
        uv[i][0] = a[i][0] / a[i][2], uv[i][1] = a[i][1] / a[i][2];
    }
    return n;
}

/* The u-range of the convex polygon uv[n] within the strip lo <= v <= hi:
 * its vertices inside and its edges' crossings of the two lines. false
 * when it does not meet the strip. */
static bool strip_range(const double uv[16][2], int n, double lo, double hi, double *umin, double *umax)
{
    double a = INFINITY, b = -INFINITY;
    for (int i = 0; i < n; i++) {
        const double *p = uv[i], *q = uv[(i + 1) % n];
        if (p[1] >= lo && p[1] <= hi) a = fmin(a, p[0]), b = fmax(b, p[0]);
        const double lines[2] = {lo, hi};
        for (int k = 0; k < 2; k++)
            if ((p[1] - lines[k]) * (q[1] - lines[k]) < 0) {
                double x = p[0] + (lines[k] - p[1]) / (q[1] - p[1]) * (q[0] - p[0]);
                a = fmin(a, x), b = fmax(b, x);
            }
    }
    *umin = a, *umax = b;
    return a <= b;
}

/* Cells i in 0..res-1 whose grown range [-1 + i h - M, -1 + (i + 1) h + M]
 * meets [lo, hi]. */
static void cell_span(double lo, double hi, uint32_t res, double M, int *i0, int *i1)
{
    const double h = 2.0 / res, eps = 1e-9;
    double a = ceil((lo - M + 1.0) / h - 1.0 - eps), b = floor((hi + M + 1.0) / h + eps);
    *i0 = a < 0 ? 0 : a > res - 1 ? (int)res : (int)a;
    *i1 = b > res - 1 ? (int)res - 1 : b < 0 ? -1 : (int)b;
}

/* Conservative rasterisation of the convex u-v polygon on face f. */
static void raster_uv(lb_raster *r, int f, const double uv[16][2], int n)
{
    const uint32_t res = r->t->res;
    const double M = r->t->margin, h = 2.0 / res, eps = 1e-9;
    double vmin = INFINITY, vmax = -INFINITY;
    for (int i = 0; i < n; i++) vmin = fmin(vmin, uv[i][1]), vmax = fmax(vmax, uv[i][1]);
    int j0, j1;
    cell_span(vmin, vmax, res, M, &j0, &j1);
    for (int j = j0; j <= j1; j++) {
        double umin, umax;
        double lo = -1.0 + j * h - M - eps, hi = -1.0 + (j + 1) * h + M + eps;
        if (!strip_range(uv, n, lo, hi, &umin, &umax)) continue;
        int i0, i1;
        cell_span(umin - eps, umax + eps, res, M, &i0, &i1);
        for (int i = i0; i <= i1; i++) mark_cell(r, ((uint32_t)f * res + (uint32_t)j) * res + (uint32_t)i);
    }
}

static void raster_face(lb_raster *r, int f)
{
    uint32_t res = r->t->res;
    for (uint32_t c = 0; c < res * res; c++) mark_cell(r, (uint32_t)f * res * res + c);
}

/* Project primitive r->id from light L onto the six faces. */
static void raster_prim(lb_raster *r, dvec3 L)
{
    const prims_t *p = r->t->p;
    const double K = 1.0 + r->t->margin + 1e-9;
    dvec3 t[LB_MAX_PIECES][3];
    bool more = true;
    for (uint32_t from = 0; more;) {
        uint32_t n = prim_pieces(p, r->id, from, t, &more);
        from += n;
        for (uint32_t i = 0; i < n; i++) {
            dvec3 rel[3];
            for (int v = 0; v < 3; v++) rel[v] = dv3_sub(t[i][v], L);
            for (int f = 0; f < 6; f++) {
                double uv[16][2];
                int m = clip_project(rel, f, K, uv);
                if (m < 0) raster_face(r, f);
                else if (m > 0) raster_uv(r, f, uv, m);
            }
        }
    }
}

/* --------------------------------------------------- full occlusion */

/* Whether every direction d[0..3] lies strictly inside the cone from the
 * light over triangle tri (relative to the light): the signed volumes
 * (Cramer's coefficients) all of the triangle's sign, with a 1e-7
 * relative margin. */
static bool tri_covers(const dvec3 tri[3], const dvec3 d[4])
{
    dvec3 bc = dv3_cross(tri[1], tri[2]), ca = dv3_cross(tri[2], tri[0]), ab = dv3_cross(tri[0], tri[1]);
    double det = dv3_dot(tri[0], bc);
    if (!(fabs(det) > 1e-9 * dv3_len(tri[0]) * dv3_len(tri[1]) * dv3_len(tri[2]))) return false; /* its plane nearly holds the light */
    double s = det > 0 ? 1.0 : -1.0;
    const dvec3 *cr[3] = {&bc, &ca, &ab};
    for (int k = 0; k < 4; k++)
        for (int e = 0; e < 3; e++)
            if (!(s * dv3_dot(*cr[e], d[k]) > 1e-7 * dv3_len(*cr[e]) * dv3_len(d[k]))) return false;
    return true;
}

/* Whether polygon g's cone from the light is convex and holds every
 * direction d[0..3] strictly inside (each on the inner side of every
 * edge's plane through the light, 1e-7 relative margin); *D is then its
 * farthest vertex distance. A concave cone is left to the ear triangles
 * (all four corners in one of them). */
static bool convex_poly_covers(const prims_t *p, const polygon_t *g, dvec3 L, const dvec3 d[4], double *D)
{
    uint32_t n = g->count;
    dvec3 nrm = dv3(g->normal);
    double far = 0, plane = 0;
    dvec3 axis = {0, 0, 0};
    for (uint32_t k = 0; k < n; k++) {
        dvec3 v = dv3_sub(dv3(p->verts[p->poly_verts[g->first + k]]), L);
        far = fmax(far, dv3_len(v));
        plane += dv3_dot(nrm, v) / n;
        axis = dv3_madd(axis, v, 1.0 / n);
    }
    if (!(fabs(plane) > 1e-9 * far)) return false; /* its plane nearly holds the light */
    /* The inner side of edge k's plane is the side of the vertex centroid
     * (inside a convex polygon; the vertex test below refuses the others). */
    for (uint32_t k = 0; k < n; k++) {
        dvec3 a = dv3_sub(dv3(p->verts[p->poly_verts[g->first + k]]), L);
        dvec3 b = dv3_sub(dv3(p->verts[p->poly_verts[g->first + (k + 1) % n]]), L);
        dvec3 e = dv3_cross(a, b);
        double le = dv3_len(e);
        if (!(le > 0)) return false;
        double side = dv3_dot(e, axis) >= 0 ? 1.0 : -1.0;
        for (int c = 0; c < 4; c++)
            if (!(side * dv3_dot(e, d[c]) > 1e-7 * le * dv3_len(d[c]))) return false;
    }
    /* Convex: every vertex on the inner side of every edge's plane (or on
     * it); checked last, as few cells get this far. */
    for (uint32_t k = 0; k < n; k++) {
        dvec3 a = dv3_sub(dv3(p->verts[p->poly_verts[g->first + k]]), L);
        dvec3 b = dv3_sub(dv3(p->verts[p->poly_verts[g->first + (k + 1) % n]]), L);
        dvec3 e = dv3_cross(a, b);
        double le = dv3_len(e), side = dv3_dot(e, axis) >= 0 ? 1.0 : -1.0;
        for (uint32_t m = 0; m < n; m++) {
            dvec3 v = dv3_sub(dv3(p->verts[p->poly_verts[g->first + m]]), L);
            if (side * dv3_dot(e, v) < -1e-9 * le * dv3_len(v)) return false;
        }
    }
    *D = far;
    return true;
}

/* The full-occlusion depth of primitive id over the grown cell whose four
 * corner directions are d (the farthest distance at which every direction
 * of the cell has met it), or +inf when it does not cover the cell. */
static double cover_depth(const prims_t *p, uint32_t id, dvec3 L, const dvec3 d[4])
{
    uint32_t k = p->index[id];
    if (p->kind[id] == PRIM_SPHERE) {
        dvec3 c = dv3_sub(dv3(p->spheres[k].center), L);
        double dist = dv3_len(c), r = p->spheres[k].radius;
        if (!(dist > r)) return INFINITY;
        double cosa = sqrt(dist * dist - r * r) / dist;
        for (int i = 0; i < 4; i++)
            if (!(dv3_dot(c, d[i]) / (dist * dv3_len(d[i])) > cosa * (1 + 1e-7) + 1e-9)) return INFINITY;
        return dist;
    }
    if (p->kind[id] == PRIM_CONE || prim_degenerate(p, id)) return INFINITY;
    if (p->kind[id] == PRIM_POLYGON) {
        double D;
        if (convex_poly_covers(p, &p->polygons[k], L, d, &D)) return D;
    }
    dvec3 t[LB_MAX_PIECES][3];
    bool more = true;
    for (uint32_t from = 0; more;) {
        uint32_t n = prim_pieces(p, id, from, t, &more);
        from += n;
        for (uint32_t i = 0; i < n; i++) {
            dvec3 rel[3];
            for (int v = 0; v < 3; v++) rel[v] = dv3_sub(t[i][v], L);
            if (tri_covers(rel, d)) return fmax(fmax(dv3_len(rel[0]), dv3_len(rel[1])), dv3_len(rel[2]));
        }
    }
    return INFINITY;
}

/* The four corner directions of cell `cell` grown by M. */
static void cell_corners(const lb_t *t, uint32_t cell, dvec3 d[4])
{
    uint32_t res = t->res, f = cell / (res * res), j = cell / res % res, i = cell % res;
    double h = 2.0 / res, M = t->margin;
    double u0 = -1.0 + i * h - M, u1 = -1.0 + (i + 1) * h + M, v0 = -1.0 + j * h - M, v1 = -1.0 + (j + 1) * h + M;
    d[0] = face_dir((int)f, u0, v0), d[1] = face_dir((int)f, u1, v0), d[2] = face_dir((int)f, u0, v1), d[3] = face_dir((int)f, u1, v1);
}

/* ------------------------------------------------------------ culling */

/* The solid angle of triangle abc (relative to the viewpoint) over 4 pi,
 * signed by its winding (Van Oosterom and Strackee's formula). */
static double solid_fraction(dvec3 a, dvec3 b, dvec3 c)
{
    double la = dv3_len(a), lb = dv3_len(b), lc = dv3_len(c);
    double num = dv3_dot(a, dv3_cross(b, c));
    double den = la * lb * lc + dv3_dot(a, b) * lc + dv3_dot(a, c) * lb + dv3_dot(b, c) * la;
    return atan2(num, den) / (2 * M_PI);
}

/* Per light: which qualifying components the light lies outside of, more
 * than rho from every triangle (so every point within rho / 4096 of the
 * light is outside too): the winding number, the sum of the triangles'
 * solid angles over 4 pi, is 0 (within 1/4) there, 1 inside. */
static bool *cull_outside(const closed_solids *ci, dvec3 L, double rho)
{
    bool *out = calloc((size_t)ci->ncomps + 1, sizeof *out);
    if (!out) return NULL;
    for (uint32_t c = 0; c < ci->ncomps; c++) {
        if (!ci->ok[c]) continue;
        double w = 0, dmin = INFINITY;
        for (uint32_t t = ci->cfirst[c]; t < ci->cfirst[c + 1]; t++) {
            dvec3 *tr = ci->ctris[t];
            dvec3 a = dv3_sub(tr[0], L), b = dv3_sub(tr[1], L), d = dv3_sub(tr[2], L);
            w += solid_fraction(a, b, d);
            dmin = fmin(dmin, dv3_point_triangle_distance(L, tr[0], tr[1], tr[2]));
        }
        out[c] = fabs(w) < 0.25 && dmin > rho;
    }
    return out;
}

/* Whether primitive id is culled for light L: on a qualifying component
 * the light is outside of, every non-degenerate triangle of it with the
 * light at least rho / 2 behind its plane (and at least one such). */
static bool prim_culled(const prims_t *p, const closed_solids *ci, const bool *outside, uint32_t id, dvec3 L, double rho)
{
    uint32_t c = ci->comp[id];
    if (c == SOLID_NONE || !outside[c]) return false;
    dvec3 t[LB_MAX_PIECES][3];
    bool more = true, any = false;
    for (uint32_t from = 0; more;) {
        uint32_t n = prim_pieces(p, id, from, t, &more);
        from += n;
        for (uint32_t i = 0; i < n; i++) {
            dvec3 nrm = dv3_cross(dv3_sub(t[i][1], t[i][0]), dv3_sub(t[i][2], t[i][0]));
            double ln = dv3_len(nrm);
            if (!(ln > 0)) continue;
            if (!(dv3_dot(nrm, dv3_sub(L, t[i][0])) < -0.5 * rho * ln)) return false;
            any = true;
        }
    }
    return any;
}

/* -------------------------------------------------------------- build */

static void lb_destroy(accel *a)
{
    lb_t *t = (lb_t *)a;
    if (!t) return;
    for (uint32_t l = 0; t->lights && l < t->nlights; l++) {
        free(t->lights[l].cells);
        free(t->lights[l].refs);
        free(t->lights[l].near);
        free(t->lights[l].slabs);
    }
    free(t->lights);
    bvh_free(&t->fallback);
    free(t);
}

static int ref_cmp(const void *x, const void *y)
{
    const lb_ref *a = x, *b = y;
    if (a->depth != b->depth) return a->depth < b->depth ? -1 : 1;
    return a->id < b->id ? -1 : a->id > b->id;
}

/* Rounded toward -inf / +inf from double to float (for depths). */
static float round_down(double x) { float f = (float)x; return (double)f > x ? nextafterf(f, -INFINITY) : f; }
static float round_up(double x) { float f = (float)x; return (double)f < x ? nextafterf(f, INFINITY) : f; }

/* The slab of polygon (or triangle) id: its unit normal and the range of
 * n . x over its vertices, rounded outward with room. */
static lb_slab prim_slab(const prims_t *p, uint32_t id)
{
    dvec3 t[LB_MAX_PIECES][3];
    bool more = true;
    uint32_t n = prim_pieces(p, id, 0, t, &more);
    dvec3 nrm = {0, 0, 0};
    if (p->kind[id] == PRIM_POLYGON) nrm = dv3(p->polygons[p->index[id]].normal);
    else if (n) nrm = dv3_cross(dv3_sub(t[0][1], t[0][0]), dv3_sub(t[0][2], t[0][0]));
    double ln = dv3_len(nrm);
    lb_slab s = {v3(0, 0, 0), INFINITY, -INFINITY};
    if (!(ln > 0)) return s;
    s.n = v3((float)(nrm.x / ln), (float)(nrm.y / ln), (float)(nrm.z / ln));
    dvec3 nf = dv3(s.n);
    double lo = INFINITY, hi = -INFINITY, mag = 0;
    more = true;
    for (uint32_t from = 0; more;) {
        n = prim_pieces(p, id, from, t, &more);
        from += n;
        for (uint32_t i = 0; i < n; i++)
            for (int v = 0; v < 3; v++) {
                double x = dv3_dot(nf, t[i][v]);
                lo = fmin(lo, x), hi = fmax(hi, x), mag = fmax(mag, dv3_len(t[i][v]));
            }
    }
    double slack = 1e-6 * mag + 1e-30;
    s.lo = round_down(lo - slack), s.hi = round_up(hi + slack);
    return s;
}

/* The fullocc and single simplifications of one light's sorted cells,
 * then the runs compacted. Returns 0, -1 out of memory or -2 over the
 * memory cap with the slabs (err set). */
static int finish_cells(lb_t *t, lb_light *L, const float *occ, uint64_t cap_mib, uint64_t *used, char *err,
                        size_t errlen)
{
    const prims_t *p = t->p;
    uint32_t w = 0, nsingle = 0;
    for (uint32_t c = 0; c < t->ncells; c++) {
        lb_cell *cell = &L->cells[c];
        lb_ref *run = &L->refs[cell->first];
        qsort(run, cell->count, sizeof *run, ref_cmp);
        cell->occ = t->fullocc ? occ[c] : INFINITY;
        uint32_t keep = cell->count;
        while (keep && run[keep - 1].depth > cell->occ) keep--; /* deeper than the record: never reached */
        memmove(&L->refs[w], run, keep * sizeof *run);
        cell->first = w, cell->count = keep, cell->single = LB_NONE;
        w += keep;
        if (t->single && keep == 1 && (p->kind[L->refs[cell->first].id] == PRIM_TRIANGLE ||
                                       p->kind[L->refs[cell->first].id] == PRIM_POLYGON))
            nsingle++;
    }
    L->nrefs = w;
    if (w) {
        lb_ref *shrunk = realloc(L->refs, (size_t)w * sizeof *L->refs);
        if (shrunk) L->refs = shrunk;
    }
    if (!nsingle) return 0;
    *used = memcap_add(*used, memcap_mul(nsingle, sizeof(lb_slab)));
    if (memcap_exceeded(*used, cap_mib, err, errlen, "the lightbuf lists and single-polygon slabs with its cells and fallback"))
        return -2;
    L->slabs = malloc((size_t)nsingle * sizeof *L->slabs);
    if (!L->slabs) return -1;
    for (uint32_t c = 0; c < t->ncells; c++) {
        lb_cell *cell = &L->cells[c];
        if (cell->count != 1) continue;
        uint32_t id = L->refs[cell->first].id;
        if (p->kind[id] != PRIM_TRIANGLE && p->kind[id] != PRIM_POLYGON) continue;
        lb_slab s = prim_slab(p, id);
        if (!(s.lo <= s.hi)) continue;
        cell->single = L->nslabs;
        L->slabs[L->nslabs++] = s;
    }
    return 0;
}

/* One light's buffer: near list, two projection passes (count, fill),
 * sort and simplify. err set on failure (memcap or out of memory). */
static int build_light(lb_t *t, lb_light *L, const closed_solids *ci, uint64_t cap_mib, uint64_t *used, char *err,
                       size_t errlen)
{
    const prims_t *p = t->p;
    const uint32_t n = p->count;
    dvec3 Lp = {L->pos[0], L->pos[1], L->pos[2]};
    /* rho from the light's reach: the far corner of the scene box. */
    double reach = 0;
    for (int i = 0; i < 8; i++) {
        dvec3 c = {i & 1 ? p->box.hi.x : p->box.lo.x, i & 2 ? p->box.hi.y : p->box.lo.y, i & 4 ? p->box.hi.z : p->box.lo.z};
        reach = fmax(reach, dv3_len(dv3_sub(c, Lp)));
    }
    L->rho = LB_RHO_FRAC * reach;
    float *depth = malloc(((size_t)n + 1) * sizeof *depth);
    uint8_t *cls = malloc((size_t)n + 1); /* 0: skipped, 1: near, 2: projected */
    uint32_t *stamp = calloc(t->ncells, sizeof *stamp), *count = calloc(t->ncells, sizeof *count);
    float *occ = malloc((size_t)t->ncells * sizeof *occ);
    bool *outside = t->cull ? cull_outside(ci, Lp, L->rho) : NULL;
    lb_raster r = {.t = t, .L = L, .stamp = stamp, .count = count, .fill = false};
    int rc = -1;
    if (!depth || !cls || !stamp || !count || !occ || (t->cull && !outside)) goto oom;
    /* Classify: degenerate (never hit) and culled primitives are left out. */
    for (uint32_t id = 0; id < n; id++) {
        cls[id] = 0;
        if (prim_degenerate(p, id)) continue;
        if (t->cull && prim_culled(p, ci, outside, id, Lp, L->rho)) {
            L->nculled++;
            continue;
        }
        double d = prim_min_dist(p, id, Lp);
        depth[id] = round_down(fmax(0.0, d) * (1 - LB_DEPTH_SLACK));
        cls[id] = d <= L->rho ? 1 : 2;
        L->nnear += cls[id] == 1;
    }
    /* Pass 1: count every cell's refs. */
    for (uint32_t id = 0; id < n; id++)
        if (cls[id] == 2) r.id = id, raster_prim(&r, Lp);
    if (r.total > UINT32_MAX) { /* runs are addressed by 32-bit offsets */
        snprintf(err, errlen, "lightbuf: %llu cell refs for one light, above 2^32 - 1: lower res",
                 (unsigned long long)r.total);
        rc = -2;
        goto out;
    }
    uint64_t bytes = memcap_add(memcap_mul(r.total, sizeof(lb_ref)), memcap_mul(L->nnear, sizeof(lb_ref)));
    *used = memcap_add(*used, bytes);
    if (memcap_exceeded(*used, cap_mib, err, errlen, "the lightbuf lists (%llu cell refs) with its cells and fallback",
                        (unsigned long long)r.total)) {
        rc = -2;
        goto out;
    }
    L->refs = malloc((size_t)r.total * sizeof *L->refs + 1);
    L->near = malloc((size_t)L->nnear * sizeof *L->near + 1);
    if (!L->refs || !L->near) goto oom;
    uint32_t first = 0;
    for (uint32_t c = 0; c < t->ncells; c++) L->cells[c].first = first, L->cells[c].count = count[c], first += count[c];
    /* Pass 2: fill, and find every cell's full-occlusion depth. */
    memset(stamp, 0, t->ncells * sizeof *stamp);
    memset(count, 0, t->ncells * sizeof *count);
    for (uint32_t c = 0; c < t->ncells; c++) occ[c] = INFINITY;
    r.fill = true, r.total = 0;
    uint32_t nn = 0;
    for (uint32_t id = 0; id < n; id++) {
        if (cls[id] == 1) L->near[nn++] = (lb_ref){id, depth[id]};
        if (cls[id] != 2) continue;
        r.id = id, r.depth = depth[id], r.nmarked = 0;
        raster_prim(&r, Lp);
        if (r.oom) goto oom;
        if (!t->fullocc) continue;
        for (uint32_t k = 0; k < r.nmarked; k++) {
            uint32_t c = r.marked[k];
            dvec3 d[4];
            cell_corners(t, c, d);
            double D = cover_depth(p, id, Lp, d);
            if (D < INFINITY) occ[c] = fminf(occ[c], round_up(D * (1 + LB_DEPTH_SLACK)));
        }
    }
    qsort(L->near, L->nnear, sizeof *L->near, ref_cmp);
    rc = finish_cells(t, L, occ, cap_mib, used, err, errlen);
    if (rc == -1) goto oom;
    goto out;
oom:
    snprintf(err, errlen, "lightbuf: out of memory building the buffer of a light over %u primitives", n);
out:
    free(depth), free(cls), free(stamp), free(count), free(occ), free(outside), free(r.marked);
    return rc;
}

/* What the build holds before its lists: the cells of every light, the
 * fallback BVH with its build scratch, the per-light scratch. */
static uint64_t base_bytes(const prims_t *p, uint64_t nlights, uint64_t ncells, bool cull)
{
    uint64_t n = p->count;
    uint64_t b = memcap_mul(memcap_mul(nlights, ncells), sizeof(lb_cell));
    b = memcap_add(b, memcap_mul(n ? 2 * n : 1, sizeof(bvh_node)));
    b = memcap_add(b, memcap_mul(n, sizeof(uint32_t) + sizeof(box3) + 2 * sizeof(vec3) + 4 + 1));
    b = memcap_add(b, memcap_mul(ncells, 3 * sizeof(uint32_t)));
    if (!cull) return b;
    return memcap_add(b, closed_solids_bytes(p));
}

/* res=auto (docs/accels/directional.md): per light, the primitives' centres are
 * binned on a coarse cube of G x G cells a face, 6 G^2 = N / 4 (about 4 a
 * cell were they spread over every direction); with O of its cells
 * occupied, N / O primitives a cell there, the resolution at which that
 * becomes LB_AUTO_PER_CELL is G sqrt(N / (4 O)). The largest over the
 * lights, within 8..LB_AUTO_MAX. 0 out of memory. */
#define LB_AUTO_PER_CELL 4.0
#define LB_AUTO_MAX 512
static long auto_res(const scene_t *scene)
{
    const prims_t *p = &scene->prims;
    /* Coincident primitives count once (common/coincident.h): copies share
     * every cell, so finer cells would only repeat them. */
    prim_classes pc;
    if (prim_classes_init(&pc, p)) return 0;
    double n = pc.classes;
    uint32_t g = (uint32_t)fmax(1.0, fmin(256.0, ceil(sqrt(n / (6.0 * LB_AUTO_PER_CELL)))));
    uint8_t *seen = malloc(6 * (size_t)g * g);
    if (!seen) {
        prim_classes_free(&pc);
        return 0;
    }
    double best = 8;
    for (uint32_t l = 0; l < scene->nlights; l++) {
        memset(seen, 0, 6 * (size_t)g * g);
        double occupied = 0;
        for (uint32_t id = 0; id < p->count; id++) {
            if (pc.rep && pc.rep[id] != id) continue;
            vec3 w = v3_sub(box_center(prim_bounds(p, id)), scene->lights[l]);
            int f = dircube_face(w);
            float u, v;
            dircube_uv(w, f, &u, &v);
            uint32_t i = (uint32_t)fmin(g - 1, fmax(0.0, floor((u + 1.0) * 0.5 * g)));
            uint32_t j = (uint32_t)fmin(g - 1, fmax(0.0, floor((v + 1.0) * 0.5 * g)));
            uint8_t *cell = &seen[((size_t)f * g + j) * g + i];
            occupied += !*cell;
            *cell = 1;
        }
        best = fmax(best, g * sqrt(n / (LB_AUTO_PER_CELL * occupied)));
    }
    free(seen);
    prim_classes_free(&pc);
    return (long)fmin(ceil(best), LB_AUTO_MAX);
}

static accel *lb_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    long res = params_int_or(params, "res", 0); /* 0: auto */
    bool cull = params_bool(params, "cull"), single = params_bool(params, "single"), fullocc = params_bool(params, "fullocc");
    uint64_t memcap = params_memcap(params, 4096);
    if (!res && !(res = auto_res(scene))) {
        snprintf(err, errlen, "lightbuf: out of memory choosing res=auto");
        return NULL;
    }
    const prims_t *p = &scene->prims;
    const uint32_t ncells = 6 * (uint32_t)res * (uint32_t)res;
    uint64_t used = base_bytes(p, scene->nlights, ncells, cull);
    if (memcap_exceeded(used, memcap, err, errlen,
                        "the lightbuf cells (%u lights x %u) and fallback over %u primitives", scene->nlights, ncells,
                        p->count))
        return NULL;
    lb_t *t = calloc(1, sizeof *t);
    box3 *boxes = malloc(((size_t)p->count + 1) * sizeof *boxes);
    closed_solids ci = {0};
    if (!t || !boxes) goto oom;
    t->base.scene = scene;
    t->p = p;
    t->res = (uint32_t)res, t->ncells = ncells;
    t->margin = fmin(0.125, fmax(2.0 / (double)res / 16.0, 1.0 / 1024.0));
    t->cull = cull, t->single = single, t->fullocc = fullocc;
    /* The fallback for rays the buffer does not answer. */
    for (uint32_t id = 0; id < p->count; id++) boxes[id] = prim_bounds(p, id);
    bvh_config cfg;
    bvh_config_defaults(&cfg);
    if (bvh_build_sah(&t->fallback, boxes, NULL, p->count, &cfg)) goto oom;
    free(boxes);
    boxes = NULL;
    if (cull && closed_solids_find(p, &ci)) goto oom;
    t->nlights = scene->nlights;
    t->lights = calloc((size_t)t->nlights + 1, sizeof *t->lights);
    if (!t->lights) goto oom;
    for (uint32_t l = 0; l < t->nlights; l++) {
        lb_light *L = &t->lights[l];
        L->pos[0] = scene->lights[l].x, L->pos[1] = scene->lights[l].y, L->pos[2] = scene->lights[l].z;
        L->cells = calloc(ncells, sizeof *L->cells);
        if (!L->cells) goto oom;
        int rc = build_light(t, L, &ci, memcap, &used, err, errlen);
        if (rc == -2) goto fail;
        if (rc) goto oom;
    }
    closed_solids_free(&ci);
    return &t->base;
oom:
    snprintf(err, errlen, "lightbuf: out of memory building over %u primitives", p->count);
fail:
    free(boxes);
    closed_solids_free(&ci);
    lb_destroy(t ? &t->base : NULL);
    return NULL;
}

/* ---------------------------------------------------------------- trace */

/* Test the run refs[0 .. n) in depth order while a candidate can reach
 * the segment (depth <= qd). */
BODY bool walk(const prims_t *p, const lb_ref *refs, uint32_t n, double qd, const ray_t *ray, counters_t *c,
               const bool counting)
{
    for (uint32_t k = 0; k < n && (double)refs[k].depth <= qd; k++)
        if (prim_test_any(p, refs[k].id, ray, c, counting)) return true;
    return false;
}

BODY bool fallback(const lb_t *t, const ray_t *ray, counters_t *c, const bool counting)
{
    return counting ? bvh_occluded_dfs(&t->fallback, t->p, NULL, ray, c) : bvh_occluded_dfs_fast(&t->fallback, t->p, NULL, ray);
}

/* Whether the segment [Ps, Pe] stays strictly on one side of the slab. */
BODY bool slab_misses(const lb_slab *s, dvec3 ps, dvec3 pe)
{
    dvec3 n = dv3(s->n);
    double a = dv3_dot(n, ps), b = dv3_dot(n, pe);
    return (a > s->hi && b > s->hi) || (a < s->lo && b < s->lo);
}

/* The query: the file header's query invariants, in their order. */
BODY bool query(const lb_t *t, const ray_t *ray, counters_t *c, const bool counting)
{
    if (ray->light >= t->nlights || !isfinite(ray->tfar)) return fallback(t, ray, c, counting);
    const lb_light *L = &t->lights[ray->light];
    dvec3 lp = {L->pos[0], L->pos[1], L->pos[2]}, o = dv3(ray->org), d = dv3(ray->dir);
    dvec3 ps = dv3_madd(o, d, ray->tnear), pe = dv3_madd(o, d, ray->tfar);
    dvec3 w = dv3_sub(ps, lp);
    double e = dv3_len(dv3_sub(pe, lp)), ds = dv3_len(w);
    if (!(e <= L->rho * LB_END_FRAC)) return fallback(t, ray, c, counting);
    double qd = fmax(ds, e) * (1 + LB_DEPTH_SLACK);
    if (ds > L->rho) {
        if (LB_PERTURB * e / L->rho + LB_UV_ROUND > t->margin) return fallback(t, ray, c, counting);
        vec3 wf = v3((float)w.x, (float)w.y, (float)w.z);
        int f = dircube_face(wf);
        float u, v;
        dircube_uv(wf, f, &u, &v);
        const uint32_t res = t->res;
        int i = (int)floorf((u + 1.0f) * 0.5f * (float)res), j = (int)floorf((v + 1.0f) * 0.5f * (float)res);
        i = i < 0 ? 0 : i >= (int)res ? (int)res - 1 : i;
        j = j < 0 ? 0 : j >= (int)res ? (int)res - 1 : j;
        const lb_cell *cell = &L->cells[((uint32_t)f * res + (uint32_t)j) * res + (uint32_t)i];
        if (counting) c->steps++, c->empty_leaves += cell->count == 0 && cell->occ == INFINITY;
        if (ds > (double)cell->occ) return true; /* beyond a full-occlusion record */
        bool skip = false;
        if (cell->single != LB_NONE) {
            if (counting) c->box_tests++;
            skip = slab_misses(&L->slabs[cell->single], ps, pe);
        }
        if (!skip && walk(t->p, &L->refs[cell->first], cell->count, qd, ray, c, counting)) return true;
    }
    return walk(t->p, L->near, L->nnear, qd, ray, c, counting);
}

static bool lb_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    (void)ctx;
    return query((const lb_t *)a, ray, c, true);
}

static bool lb_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *ray)
{
    (void)ctx;
    return query((const lb_t *)a, ray, NULL, false);
}

/* ------------------------------------------------------- bookkeeping */

static size_t lb_memory(const accel *a)
{
    const lb_t *t = (const lb_t *)a;
    size_t b = sizeof *t + (size_t)t->nlights * sizeof *t->lights + bvh_memory(&t->fallback);
    for (uint32_t l = 0; l < t->nlights; l++) {
        const lb_light *L = &t->lights[l];
        b += (size_t)t->ncells * sizeof(lb_cell) + ((size_t)L->nrefs + L->nnear) * sizeof(lb_ref) +
             (size_t)L->nslabs * sizeof(lb_slab);
    }
    return b;
}

/* The solid angle of the part [u0, u1] x [v0, v1] of a cube face at
 * distance 1 (the rectangle's corners in inclusion-exclusion over
 * F(u, v) = atan(u v / sqrt(1 + u^2 + v^2)), the solid angle of [0, u] x
 * [0, v]). */
static double face_solid_angle(double u0, double u1, double v0, double v1)
{
#define F(u, v) atan((u) * (v) / sqrt(1.0 + (u) * (u) + (v) * (v)))
    return F(u1, v1) - F(u0, v1) - F(u1, v0) + F(u0, v0);
#undef F
}

/* The model of a query's reading (Haines and Greenberg's argument from the
 * direction cube): a shadow query starts on a surface, so its direction
 * from the light lies in a cell that lists something; with directions
 * uniform over the solid angle of those cells (each cell's chance its
 * solid angle over theirs), the list entries a query can read are its
 * cell's list plus the near list, averaged over the lights. It reads them
 * all only when nothing stops it: the stopping rule (a candidate beyond
 * the point), an occluder, a full-occlusion record and the single-polygon
 * test end or skip the reading, and rays the fallback answers are not in
 * it. One cell read per query. */
static double lb_predict_tests(const lb_t *t)
{
    if (!t->nlights) return 0.0;
    const uint32_t res = t->res;
    double *omega = malloc((size_t)res * res * sizeof *omega), sum = 0.0;
    if (!omega) return -1.0;
    for (uint32_t j = 0; j < res; j++)
        for (uint32_t i = 0; i < res; i++) {
            double u0 = -1.0 + 2.0 * i / res, v0 = -1.0 + 2.0 * j / res;
            omega[j * res + i] = face_solid_angle(u0, u0 + 2.0 / res, v0, v0 + 2.0 / res);
        }
    for (uint32_t l = 0; l < t->nlights; l++) {
        const lb_light *L = &t->lights[l];
        double listed = 0.0, entries = 0.0;
        for (uint32_t c = 0; c < t->ncells; c++)
            if (L->cells[c].count) {
                listed += omega[c % (res * res)];
                entries += omega[c % (res * res)] * L->cells[c].count;
            }
        sum += (listed > 0.0 ? entries / listed : 0.0) + L->nnear;
    }
    free(omega);
    return sum / t->nlights;
}

static int lb_stats(const accel *a, accel_stat *out, int max)
{
    const lb_t *t = (const lb_t *)a;
    uint64_t cells = (uint64_t)t->ncells * t->nlights, nonempty = 0, refs = 0, near = 0;
    for (uint32_t l = 0; l < t->nlights; l++) {
        const lb_light *L = &t->lights[l];
        for (uint32_t c = 0; c < t->ncells; c++) nonempty += L->cells[c].count > 0;
        refs += L->nrefs, near += L->nnear;
    }
    accel_stat s[] = {
        {"nodes", (double)cells},
        {"leaves", (double)nonempty},
        {"empty_leaves", (double)(cells - nonempty)},
        {"avg_leaf_prims", nonempty ? (double)refs / (double)nonempty : 0.0},
        {"refs_per_prim", t->p->count ? (double)(refs + near) / t->p->count : 0.0},
        {"res_x", (double)t->res},
        {"res_y", (double)t->res},
        {"predicted_steps_per_ray", t->nlights ? 1.0 : 0.0},
        {"predicted_tests_per_ray", lb_predict_tests(t)},
    };
    int n = (int)(sizeof s / sizeof s[0]);
    if (s[n - 1].value < 0.0) n--; /* the model had no memory: no predicted tests */
    if (n > max) n = max;
    memcpy(out, s, (size_t)n * sizeof *s);
    return n;
}

/* ----------------------------------------------------- test accessors */

uint32_t lightbuf_debug_cell(const accel *a, uint32_t light, uint32_t cell, uint32_t *ids, float *depths, uint32_t cap,
                             float *occ, bool *single)
{
    const lb_t *t = (const lb_t *)a;
    if (light >= t->nlights) return 0;
    const lb_light *L = &t->lights[light];
    if (cell == UINT32_MAX) { /* the near list */
        for (uint32_t k = 0; k < L->nnear && k < cap; k++) ids[k] = L->near[k].id, depths[k] = L->near[k].depth;
        *occ = INFINITY, *single = false;
        return L->nnear;
    }
    if (cell >= t->ncells) return 0;
    const lb_cell *c = &L->cells[cell];
    for (uint32_t k = 0; k < c->count && k < cap; k++) ids[k] = L->refs[c->first + k].id, depths[k] = L->refs[c->first + k].depth;
    *occ = c->occ, *single = c->single != LB_NONE;
    return c->count;
}

int lightbuf_debug_light(const accel *a, uint32_t light, uint32_t *res, uint32_t *nnear, uint32_t *nculled,
                         double *rho)
{
    const lb_t *t = (const lb_t *)a;
    if (light >= t->nlights) return -1;
    *res = t->res, *nnear = t->lights[light].nnear, *nculled = t->lights[light].nculled, *rho = t->lights[light].rho;
    return 0;
}

/* Every switch off, alone and together, and other resolutions. */
static const char *const lb_variants[] = {
    "cull=off",
    "single=off",
    "fullocc=off",
    "cull=off,single=off,fullocc=off",
    "res=1",
    "res=7,fullocc=off",
    "res=128",
    "res=auto",
    NULL,
};

const struct accel_ops accel_lightbuf = {
    .version = 2,
    .name = "lightbuf",
    .summary = "Haines-Greenberg light buffer: a direction cube per point light, depth-sorted candidate lists per "
               "cell, full-occlusion records; shadow rays only",
    .paper = "Haines & Greenberg, IEEE CG&A 6(9) 1986; Arvo & Kirk 1989 survey s6.1-6.2, fig. 19",
    .params = lb_params,
    .flags = ACCEL_SHADOW_ONLY,
    .build = lb_build,
    .intersect = NULL,
    .occluded = lb_occluded,
    .memory = lb_memory,
    .destroy = lb_destroy,
    .stats = lb_stats,
    .occluded_fast = lb_occluded_fast,
    .variants = lb_variants,
    .cost = {2, 2, 0},
    .tune = "res=8|16|32|64|128|auto", /* cells per cube face side, and the scene-sized rule */
};
