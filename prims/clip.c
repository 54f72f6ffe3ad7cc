/* clip.c: the bounds of the part of a primitive that lies inside a box, for
 * kd-tree "perfect splits" (Wald and Havran, "On building fast kd-Trees
 * for Ray Tracing, and on doing that in O(N log N)", IEEE Symposium on
 * Interactive Ray Tracing 2006, their "perfect splits"; Havran's thesis,
 * 2000, clips likewise): a builder that clips each primitive to the cell it
 * is in sees split candidates where the primitive really leaves the cell,
 * not where its bounds do.
 *
 * Triangles and polygons are clipped exactly (Sutherland and Hodgman,
 * "Reentrant Polygon Clipping", CACM 17(1), 1974: the convex polygon is cut
 * by the six planes of the box in turn; a polygon through each of its ear
 * triangles), in double, from the float vertices. A vertex on a plane
 * counts as inside (the box is closed, as in prim_overlaps_box), and a new
 * vertex on a cutting plane gets that plane's coordinate exactly (and the
 * coordinates its edge's two ends share); its other coordinates carry a few
 * double roundings, so an end of the result that comes from one is widened
 * by 8 DBL_EPSILON times the magnitudes involved, and every end is rounded
 * outward to float: the result CONTAINS the exact bounds of
 * primitive-inside-box, is exact where no interpolated coordinate decides
 * it (an axis-aligned cut of an axis-aligned triangle), and at most about
 * one float ulp wider at each end otherwise. Spheres and cones are not clipped: their bounds intersected with the
 * box (containing, not tight). The result always lies within both the box
 * and the primitive's bounds.
 *
 * Empty (box_empty()) exactly when nothing is left: for triangles and
 * polygons when the clipped polygon is empty and prim_overlaps_box() also
 * says they do not touch (the exact test decides where rounding might have
 * cut a touching vertex away), for spheres and cones when
 * prim_overlaps_box() says so. */
#include <float.h>
#include "box4.h"
#include "prims.h"
#include "prims_internal.h"

#define CLIP_MAX 16 /* a triangle cut by 6 planes has at most 3 + 6 vertices */

static inline double dget(dvec3 v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }
static inline void dset(dvec3 *v, int a, double x)
{
    if (a == 0) v->x = x;
    else if (a == 1) v->y = x;
    else v->z = x;
}

/* A vertex of the clipped polygon and which of its coordinates carry a
 * rounding (bit a set: coordinate a was interpolated); the input vertices
 * and every coordinate set to a plane are exact. */
typedef struct {
    dvec3 p;
    unsigned inexact;
} cvert;

/* Keep the part of the polygon in[0..n) on the side dir * (x[a] - c) >= 0
 * of the plane x[a] = c; returns the new vertex count. */
static int clip_plane(const cvert *in, int n, cvert *out, int a, double c, double dir)
{
    int m = 0;
    for (int i = 0; i < n; i++) {
        cvert p = in[i], q = in[(i + 1) % n];
        double dp = dir * (dget(p.p, a) - c), dq = dir * (dget(q.p, a) - c);
        if (dp >= 0) out[m++] = p;
        if ((dp > 0 && dq < 0) || (dp < 0 && dq > 0)) {
            /* The edge crosses the plane strictly: the crossing point, with
             * the plane's own coordinate set exactly; a coordinate the two
             * ends share is exact too. */
            double s = dp / (dp - dq);
            cvert r = {{p.p.x + s * (q.p.x - p.p.x), p.p.y + s * (q.p.y - p.p.y), p.p.z + s * (q.p.z - p.p.z)},
                       p.inexact | q.inexact};
            for (int k = 0; k < 3; k++)
                if (dget(p.p, k) == dget(q.p, k) && !((p.inexact | q.inexact) >> k & 1u)) {
                    dset(&r.p, k, dget(p.p, k));
                    r.inexact &= ~(1u << k);
                } else {
                    r.inexact |= 1u << k;
                }
            dset(&r.p, a, c);
            r.inexact &= ~(1u << a);
            out[m++] = r;
        }
    }
    return m;
}

/* Grow lo/hi (and the inexact marks of each end) by triangle (a, b, c)
 * clipped to box; false when nothing of it is left. */
static bool clip_triangle(vec3 a, vec3 b, vec3 c, box3 box, double lo[3], double hi[3], unsigned *lo_inexact,
                          unsigned *hi_inexact)
{
    cvert buf[2][CLIP_MAX];
    buf[0][0] = (cvert){dv3(a), 0}, buf[0][1] = (cvert){dv3(b), 0}, buf[0][2] = (cvert){dv3(c), 0};
    int n = 3, cur = 0;
    for (int ax = 0; ax < 3 && n > 0; ax++) {
        n = clip_plane(buf[cur], n, buf[cur ^ 1], ax, v3_get(box.lo, ax), 1.0), cur ^= 1;
        if (n > 0) n = clip_plane(buf[cur], n, buf[cur ^ 1], ax, v3_get(box.hi, ax), -1.0), cur ^= 1;
    }
    for (int i = 0; i < n; i++)
        for (int ax = 0; ax < 3; ax++) {
            double v = dget(buf[cur][i].p, ax);
            bool inexact = buf[cur][i].inexact >> ax & 1u;
            if (v < lo[ax] || (v == lo[ax] && inexact)) lo[ax] = v, *lo_inexact = (*lo_inexact & ~(1u << ax)) | (unsigned)inexact << ax;
            if (v > hi[ax] || (v == hi[ax] && inexact)) hi[ax] = v, *hi_inexact = (*hi_inexact & ~(1u << ax)) | (unsigned)inexact << ax;
        }
    return n > 0;
}

box3 prim_clip_bounds(const prims_t *p, uint32_t id, box3 box)
{
    if (id >= p->count || box_is_empty(box)) return box_empty();
    box3 bb = box_meet(p->bounds[id], box);
    if (box_is_empty(bb)) return bb;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    unsigned lo_inexact = 0, hi_inexact = 0;
    bool any = false;
    uint32_t k = p->index[id];
    switch ((prim_kind)p->kind[id]) {
    case PRIM_TRIANGLE: {
        vec3 a, b, c;
        tri_verts(p, k, &a, &b, &c);
        any = clip_triangle(a, b, c, box, lo, hi, &lo_inexact, &hi_inexact);
        break;
    }
    case PRIM_POLYGON: {
        const polygon_t *g = &p->polygons[k];
        for (uint32_t t = 0; t + 2 < g->count; t++) {
            const tri_t *tr = &p->poly_tris[g->tri_first + t];
            any |= clip_triangle(p->verts[tr->v[0]], p->verts[tr->v[1]], p->verts[tr->v[2]], box, lo, hi, &lo_inexact,
                                 &hi_inexact);
        }
        break;
    }
    default: /* spheres, cones: bounds within the box, if they touch it */
        return prim_overlaps_box(p, id, box) ? bb : box_empty();
    }
    if (!any) return prim_overlaps_box(p, id, box) ? bb : box_empty();
    /* Widen by the roundings of the crossing points and round outward. */
    double mag = 0;
    for (int ax = 0; ax < 3; ax++) {
        double m = fmax(fabs(v3_get(box.lo, ax)), fabs(v3_get(box.hi, ax)));
        m = fmax(m, fmax(fabs(v3_get(p->bounds[id].lo, ax)), fabs(v3_get(p->bounds[id].hi, ax))));
        mag = fmax(mag, m);
    }
    double e = 8.0 * DBL_EPSILON * mag, el[3], eh[3];
    for (int ax = 0; ax < 3; ax++) el[ax] = (lo_inexact >> ax & 1u) ? e : 0.0, eh[ax] = (hi_inexact >> ax & 1u) ? e : 0.0;
    box3 r = {{float_down(lo[0] - el[0]), float_down(lo[1] - el[1]), float_down(lo[2] - el[2])},
              {float_up(hi[0] + eh[0]), float_up(hi[1] + eh[1]), float_up(hi[2] + eh[2])}};
    r = box_meet(r, bb);
    return box_is_empty(r) ? bb : r; /* cannot be empty: the clipped points lie in bb up to e */
}

/* A triangle split at the plane x[axis] = pos as Embree's spatial-split
 * builder splits one to bin it: each vertex goes to the side(s) it is on,
 * each edge that crosses the plane adds its crossing point (interpolated
 * in float, its axis coordinate set to pos) to both; each side's box is
 * then met with that half of box. Not exact: the whole triangle is split,
 * not its part in box (so a side may be larger than the exact part), and
 * the crossing points carry float rounding (a side may miss the exact part
 * by about an ulp). Good for cost estimates, which is all it is for. */
void prim_split_bounds(const prims_t *p, uint32_t id, box3 box, int axis, float pos, box3 *left, box3 *right)
{
    box3 lh = box, rh = box;
    float *lhi = &lh.hi.x, *rlo = &rh.lo.x;
    lhi[axis] = pos;
    rlo[axis] = pos;
    if (id >= p->count || (prim_kind)p->kind[id] != PRIM_TRIANGLE) { /* other kinds: their bounds, halved */
        box3 b = id < p->count ? p->bounds[id] : box_empty();
        *left = box_meet(b, lh);
        *right = box_meet(b, rh);
        return;
    }
    vec3 v[3];
    tri_verts(p, p->index[id], &v[0], &v[1], &v[2]);
    box4 l = box4_empty(), r = box4_empty(); /* box_union's boxes, in registers (box4.h) */
    for (int i = 0; i < 3; i++) {
        vec3 a = v[i], b = v[(i + 1) % 3];
        float da = v3_get(a, axis) - pos, db = v3_get(b, axis) - pos;
        box4 pa = box4_point(&v[i]);
        if (da <= 0.0f) l = box4_union(l, pa);
        if (da >= 0.0f) r = box4_union(r, pa);
        if ((da < 0.0f && db > 0.0f) || (da > 0.0f && db < 0.0f)) {
            vec3 c = v3_add(a, v3_scale(v3_sub(b, a), da / (da - db)));
            float *cc = &c.x;
            cc[axis] = pos;
            box4 pc = box4_point(&c);
            l = box4_union(l, pc);
            r = box4_union(r, pc);
        }
    }
    *left = box_meet(box4_store(l), lh);
    *right = box_meet(box4_store(r), rh);
}
