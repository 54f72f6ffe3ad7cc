/* overlap.c: exact primitive/box overlap, for building spatial structures
 * (grids, kd-trees and spatial splits put a primitive in every cell it
 * touches; a false "no" would lose the primitive from that cell).
 *
 * Triangle/box: the separating axis theorem as applied by
 *   Tomas Akenine-Moller, "Fast 3D Triangle-Box Overlap Testing",
 *   Journal of Graphics Tools 6(1), 2001 (the separating-axis derivation
 *   and its 13 candidate axes),
 * written from the paper's description. A triangle and a box (both convex)
 * are disjoint iff their projections are disjoint on one of 13 axes: the 3
 * box face normals, the triangle normal, and the 9 cross products of a
 * triangle edge with a box edge direction.
 *
 * Sphere/box: James Arvo, "A Simple Method for Box-Sphere Intersection
 * Testing", Graphics Gems I (1990): the squared distance from the centre
 * to the nearest point of the box, compared with r^2.
 *
 * Touching counts as overlapping in both, so a primitive lying exactly on a
 * cell boundary is in both cells. */
#include "prims_internal.h"

#include <float.h>

/* ---------------------------------------------------------------------- */
/* Triangle / box                                                          */

/* Floating-point policy. The box axes compare float coordinates directly,
 * which is exact. The other 10 axes project in double: the inputs are
 * floats, so every product of two inputs is exact and each projection (a
 * sum of three products) has an error below about 3 double ulps of
 * |L|.M, where M holds per axis the largest magnitude of any input
 * coordinate. We declare separation only when the gap exceeds
 * 16 * DBL_EPSILON * |L|.M, i.e. the box is enlarged by a few double ulps
 * relative to the magnitude of the data (far below one float ulp), so a
 * triangle that touches the box can never be reported as separated.
 * Rounding in the axis itself is harmless: any axis is a valid candidate,
 * and the projections onto the axis actually computed are what we test.
 * Degenerate triangles (zero normal, parallel edges) only produce zero
 * axes, which never separate; the remaining axes still cover segments and
 * points, so the test stays exact for them too. A NaN anywhere makes every
 * comparison false, which reads as "overlaps": conservative. */

typedef struct {
    dvec3 v[3];   /* triangle vertices */
    dvec3 lo, hi; /* box */
    dvec3 mag;    /* per axis: the largest |coordinate| of any of the above */
} sat_t;

static double dmax(double a, double b) { return a > b ? a : b; }
static double dmin(double a, double b) { return a < b ? a : b; }

static dvec3 dvec(double x, double y, double z)
{
    dvec3 r = {x, y, z};
    return r;
}

/* The extent of the box's projection onto L: for each axis pick the
 * corner coordinate that minimises / maximises L_k * x_k. */
static void box_interval(const sat_t *s, dvec3 L, double *bmin, double *bmax)
{
    double x0 = L.x * s->lo.x, x1 = L.x * s->hi.x;
    double y0 = L.y * s->lo.y, y1 = L.y * s->hi.y;
    double z0 = L.z * s->lo.z, z1 = L.z * s->hi.z;
    *bmin = dmin(x0, x1) + dmin(y0, y1) + dmin(z0, z1);
    *bmax = dmax(x0, x1) + dmax(y0, y1) + dmax(z0, z1);
}

/* True when L separates the triangle from the (slightly enlarged) box. */
static bool separated_on(const sat_t *s, dvec3 L)
{
    double p0 = dv3_dot(L, s->v[0]), p1 = dv3_dot(L, s->v[1]), p2 = dv3_dot(L, s->v[2]);
    double tmin = dmin(p0, dmin(p1, p2)), tmax = dmax(p0, dmax(p1, p2));
    double bmin, bmax;
    box_interval(s, L, &bmin, &bmax);
    dvec3 absL = dvec(fabs(L.x), fabs(L.y), fabs(L.z));
    double margin = 16.0 * DBL_EPSILON * dv3_dot(absL, s->mag);
    return tmin > bmax + margin || tmax < bmin - margin;
}

static double max_abs4(float a, float b, float c, float d)
{
    return dmax(dmax(fabs(a), fabs(b)), dmax(fabs(c), fabs(d)));
}

/* The 3 box face normals, done in float where they are exact. */
static bool separated_by_box_axes(vec3 a, vec3 b, vec3 c, box3 box)
{
    vec3 tlo = v3_min(a, v3_min(b, c)), thi = v3_max(a, v3_max(b, c));
    return tlo.x > box.hi.x || thi.x < box.lo.x ||
           tlo.y > box.hi.y || thi.y < box.lo.y ||
           tlo.z > box.hi.z || thi.z < box.lo.z;
}

bool triangle_overlaps_box(vec3 a, vec3 b, vec3 c, box3 box)
{
    if (separated_by_box_axes(a, b, c, box)) return false;

    sat_t s;
    s.v[0] = dv3(a);
    s.v[1] = dv3(b);
    s.v[2] = dv3(c);
    s.lo = dv3(box.lo);
    s.hi = dv3(box.hi);
    s.mag = dvec(dmax(max_abs4(a.x, b.x, c.x, box.lo.x), fabs(box.hi.x)),
                 dmax(max_abs4(a.y, b.y, c.y, box.lo.y), fabs(box.hi.y)),
                 dmax(max_abs4(a.z, b.z, c.z, box.lo.z), fabs(box.hi.z)));

    dvec3 e[3] = {dv3_sub(s.v[1], s.v[0]), dv3_sub(s.v[2], s.v[1]), dv3_sub(s.v[0], s.v[2])};

    /* The triangle's plane. */
    if (separated_on(&s, dv3_cross(e[0], e[1]))) return false;

    /* Edge x box axis: e x (1,0,0) = (0, e.z, -e.y), and so on. These catch
     * a triangle passing beside a box edge or corner, where neither the
     * face normals nor the plane separate. */
    for (int i = 0; i < 3; i++) {
        dvec3 d = e[i];
        if (separated_on(&s, dvec(0.0, d.z, -d.y))) return false;
        if (separated_on(&s, dvec(-d.z, 0.0, d.x))) return false;
        if (separated_on(&s, dvec(d.y, -d.x, 0.0))) return false;
    }
    return true;
}

/* ---------------------------------------------------------------------- */
/* Sphere / box                                                            */

/* Arvo: sum, over the axes where the centre lies outside the box's slab,
 * of the squared distance to that slab. Done in double: the differences of
 * two floats are (almost always) exact there and the squares and sums add
 * a relative error of a few DBL_EPSILON, all terms being >= 0; the
 * comparison allows 8 DBL_EPSILON relative slack so a sphere exactly
 * touching a face, edge or corner always counts as overlapping. */
bool sphere_overlaps_box(sphere_t s, box3 box)
{
    double c[3] = {s.center.x, s.center.y, s.center.z};
    double lo[3] = {box.lo.x, box.lo.y, box.lo.z};
    double hi[3] = {box.hi.x, box.hi.y, box.hi.z};
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double e = 0.0;
        if (c[k] < lo[k])
            e = c[k] - lo[k];
        else if (c[k] > hi[k])
            e = c[k] - hi[k];
        d2 += e * e;
    }
    double r = s.radius;
    return d2 <= r * r * (1.0 + 8.0 * DBL_EPSILON);
}
