/* extent.c: a primitive's extent along a direction, min and max of
 * dot(x, dir) over its points, for plane-set bounding volumes (Kay and
 * Kajiya, "Ray Tracing Complex Scenes", SIGGRAPH 1986: a volume is
 * bounded by pairs of parallel planes with normals from a fixed set, and
 * each primitive's pair comes from its extent along each normal).
 *
 * Where the extremes lie (a linear function over a convex hull peaks at an
 * extreme point of it):
 *   triangles, polygons  the vertices;
 *   spheres              c.dir -+ r |dir|;
 *   cones                the two rim circles (every point of the lateral
 *                        surface lies on a segment between them); a circle
 *                        of centre C, radius r and unit axis w spans
 *                        C.dir -+ r |dir x w|, the cross product rather
 *                        than sqrt(|dir|^2 - (dir.w)^2), which cancels
 *                        catastrophically when dir is nearly along w.
 * Everything is computed in double: a product of two floats is exact
 * there, and the few roundings that remain are bounded by 16 DBL_EPSILON
 * times the sum of the magnitudes involved (far more than they can be).
 * The interval is widened by that bound and each end rounded outward to
 * float, so the true extent lies inside [lo, hi], at most about one float
 * ulp wider at each end. The widening is skipped when every step was
 * exact (each sum checked by Knuth's TwoSum, the sphere's r |dir| by an
 * fma residual; cones are always widened): along a coordinate axis a
 * triangle's, polygon's or sphere's extent is then exactly its bounds. */
#include <float.h>
#include "prims.h"
#include "prims_internal.h"

/* A running extent in double with the magnitude of its terms and whether
 * any rounding happened. */
typedef struct {
    double lo, hi, mag;
    bool inexact;
} span_t;

/* a + b, noting whether it rounded (TwoSum, Knuth TAOCP vol. 2 s4.2.2:
 * err is the exact rounding error of s = a + b). */
static double add(double a, double b, bool *inexact)
{
    double s = a + b, bb = s - a, err = (a - (s - bb)) + (b - bb);
    if (err != 0.0) *inexact = true;
    return s;
}

static void span_add(span_t *s, double v, double mag)
{
    s->lo = fmin(s->lo, v);
    s->hi = fmax(s->hi, v);
    s->mag = fmax(s->mag, mag);
}

/* dot(x, d) of float vectors (each product exact in double) and its
 * magnitude sum |x_i d_i|. */
static double ddot(dvec3 x, dvec3 d, double *mag, bool *inexact)
{
    *mag = fabs(x.x * d.x) + fabs(x.y * d.y) + fabs(x.z * d.z);
    return add(add(x.x * d.x, x.y * d.y, inexact), x.z * d.z, inexact);
}

static void span_point(span_t *s, vec3 x, dvec3 d)
{
    double m, v = ddot(dv3(x), d, &m, &s->inexact);
    span_add(s, v, m);
}

/* A disc's rim: centre c, radius r, unit axis w. */
static void span_circle(span_t *s, vec3 c, double r, dvec3 w, dvec3 d)
{
    double m, v = ddot(dv3(c), d, &m, &s->inexact);
    dvec3 x = dv3_cross(d, w);
    double across = r * sqrt(dv3_dot(x, x));
    span_add(s, v - across, m + across);
    span_add(s, v + across, m + across);
}

bool prim_extent(const prims_t *p, uint32_t id, vec3 dir, float *lo, float *hi)
{
    if (id >= p->count || !v3_finite(dir)) return false;
    dvec3 d = dv3(dir);
    span_t s = {INFINITY, -INFINITY, 0.0, false};
    uint32_t k = p->index[id];
    switch ((prim_kind)p->kind[id]) {
    case PRIM_TRIANGLE:
        for (int j = 0; j < 3; j++) span_point(&s, p->verts[p->tris[k].v[j]], d);
        break;
    case PRIM_POLYGON: {
        const polygon_t *g = &p->polygons[k];
        for (uint32_t j = 0; j < g->count; j++) span_point(&s, p->verts[p->poly_verts[g->first + j]], d);
        break;
    }
    case PRIM_SPHERE: {
        sphere_t sp = p->spheres[k];
        double dd = add(add(d.x * d.x, d.y * d.y, &s.inexact), d.z * d.z, &s.inexact);
        double len = sqrt(dd), r = (double)sp.radius * len;
        if (fma(len, len, -dd) != 0.0 || fma((double)sp.radius, len, -r) != 0.0) s.inexact = true;
        double m, v = ddot(dv3(sp.center), d, &m, &s.inexact);
        span_add(&s, add(v, -r, &s.inexact), m + r);
        span_add(&s, add(v, r, &s.inexact), m + r);
        break;
    }
    case PRIM_CONE: {
        cone_t c = p->cones[k];
        dvec3 ax = dv3_sub(dv3(c.apex), dv3(c.base));
        double len = sqrt(dv3_dot(ax, ax));
        dvec3 w = {ax.x / len, ax.y / len, ax.z / len};
        span_circle(&s, c.base, c.base_radius, w, d);
        span_circle(&s, c.apex, c.apex_radius, w, d);
        s.inexact = true; /* the axis, the cross product and the roots round */
        break;
    }
    default:
        return false;
    }
    double e = s.inexact ? 16.0 * DBL_EPSILON * s.mag : 0.0;
    *lo = float_down(s.lo - e);
    *hi = float_up(s.hi + e);
    return true;
}
