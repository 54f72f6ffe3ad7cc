/* surface.c: where a ray leaves a surface (see prims.h, "Spawning
 * secondary rays").
 *
 * Method: pbrt-v4's error-bound method (Pharr, Jakob, Humphreys, Physically
 * Based Rendering, 4th ed., s6.8: "Managing Rounding Error"). The hit point
 * is recomputed on the primitive's own surface from its parameterisation
 * (barycentrics for triangles and polygon ear triangles, centre + r n for
 * spheres, the axis frame for cones), together with a conservative bound on
 * the rounding error of every coordinate (s6.8.5: gamma(7) times the sum of
 * |b_i p_i| for barycentric interpolation, gamma(5) times the point's
 * magnitude for a reprojected sphere point); the origin is then moved along
 * the geometric normal by the projection of that error box onto the normal
 * and rounded away from the surface (s6.8.6, OffsetRayOrigin).
 *
 * Why this and not Wachter and Binder's integer-ULP offset (Ray Tracing Gems
 * ch. 6): that method moves the point a fixed number of float steps of its
 * own coordinates and assumes the point is accurate to a few steps. The
 * harness used it on o + t d, whose error grows with |o| and t|d|, not with
 * |p|: on a room with coordinates in the thousands and floors thousands of
 * units long, origins landed behind the surface they left. The pbrt bound is
 * derived from the primitive's own vertices, so it holds at any scale and is
 * testable: tests/test_surface.c checks it in double precision.
 *
 * Where the parameterisation is evaluated in double (every kind here) and
 * rounded to float once, the true error is below half a float step plus a
 * double rounding term; the pbrt bounds used are larger than that, so they
 * stay conservative.
 *
 * One term is ours, not pbrt's. pbrt also makes its triangle test reject
 * any t within that test's own rounding error of 0 (s6.8.7); the tests that
 * trace our rays (prims/, Embree, CGAL) do not, and Embree's cannot be
 * changed. A float test that translates vertices to the ray origin rounds
 * each to about u |v - o|, so it can place the surface it starts on that far
 * off, on either side, and report a hit at t ~ 0 even from an origin that
 * is exactly on the correct side. The bound therefore also carries
 * gamma(32) times the primitive's reach from the point (its farthest vertex,
 * or its radius and length for spheres and cones): a floor 10000 units long
 * gets an offset of about 0.02 even where the point's own
 * coordinates are near 0. tests/test_rooms.c fails without it (888
 * self-shadowed pixels through the float watertight test on gen:room:empty). */
#include "prims.h"
#include "prims_internal.h"

#include <float.h>
#include <math.h>

/* pbrt's gamma(n) = n u / (1 - n u), u = 2^-24 the float unit roundoff. */
static double gamma_f(int n)
{
    const double u = 0x1p-24;
    return n * u / (1.0 - n * u);
}
/* Double-rounding slack for the double evaluations, relative to the largest
 * magnitude involved: far above their true error (~1e-15), far below a
 * float step (6e-8). */
#define DOUBLE_SLACK 0x1p-44

static dvec3 dmake(double x, double y, double z) { dvec3 r = {x, y, z}; return r; }
static dvec3 dadd(dvec3 a, dvec3 b) { return dmake(a.x + b.x, a.y + b.y, a.z + b.z); }
static dvec3 dscale(dvec3 a, double s) { return dmake(a.x * s, a.y * s, a.z * s); }
static dvec3 dabs(dvec3 a) { return dmake(fabs(a.x), fabs(a.y), fabs(a.z)); }
static double dmaxc(dvec3 a) { return fmax(fabs(a.x), fmax(fabs(a.y), fabs(a.z))); }
static vec3 to_float(dvec3 a) { return v3((float)a.x, (float)a.y, (float)a.z); }

static dvec3 ray_point(const ray_t *r, double t)
{
    dvec3 o = dv3(r->org), d = dv3(r->dir);
    return dmake(o.x + t * d.x, o.y + t * d.y, o.z + t * d.z);
}

/* The ray's point on the plane through a with normal nrm: along the ray
 * where that is well conditioned, else the orthogonal projection of the
 * ray's point at t (a grazing ray). */
static dvec3 onto_plane(const ray_t *r, double t, dvec3 a, dvec3 nrm)
{
    dvec3 o = dv3(r->org), d = dv3(r->dir);
    double nn = dv3_dot(nrm, nrm), dn = dv3_dot(d, nrm);
    if (fabs(dn) > 1e-6 * sqrt(nn * dv3_dot(d, d))) {
        double tp = dv3_dot(nrm, dv3_sub(a, o)) / dn;
        if (isfinite(tp)) return ray_point(r, tp);
    }
    dvec3 q = ray_point(r, t);
    return dadd(q, dscale(nrm, -dv3_dot(nrm, dv3_sub(q, a)) / nn));
}

/* Barycentrics of q (on or near the plane of abc) clamped onto the closed
 * triangle, so that a point just past an edge comes back to the edge: an
 * origin must lie on the primitive it leaves, not beyond its corner where
 * a neighbouring wall may stand. Returns the smallest unclamped weight (how
 * far inside q was; negative when outside). */
static double barycentric(dvec3 a, dvec3 b, dvec3 c, dvec3 q, double w[3])
{
    dvec3 e1 = dv3_sub(b, a), e2 = dv3_sub(c, a), f = dv3_sub(q, a);
    double d11 = dv3_dot(e1, e1), d12 = dv3_dot(e1, e2), d22 = dv3_dot(e2, e2);
    double f1 = dv3_dot(f, e1), f2 = dv3_dot(f, e2), den = d11 * d22 - d12 * d12;
    double wb = (d22 * f1 - d12 * f2) / den, wc = (d11 * f2 - d12 * f1) / den;
    w[0] = 1.0 - wb - wc, w[1] = wb, w[2] = wc;
    double inside = fmin(w[0], fmin(w[1], w[2]));
    double sum = 0.0;
    for (int k = 0; k < 3; k++) sum += w[k] = fmax(w[k], 0.0);
    for (int k = 0; k < 3; k++) w[k] /= sum;
    return inside;
}

/* The tests' own rounding: gamma(REACH_GAMMA) times the primitive's reach
 * from p, the same in every coordinate (see the file header). A float test
 * that translates, shears and takes edge functions and their weighted sum
 * accumulates about ten roundings of u R in t times |cos| (the offset along
 * the ray is the normal offset over |cos| too, so the angle cancels); 32 is
 * that with a margin, an estimate checked by tests/test_rooms.c, not a
 * proof. */
#define REACH_GAMMA 32
static dvec3 with_reach(dvec3 err, double reach)
{
    double e = gamma_f(REACH_GAMMA) * reach;
    return dadd(err, dmake(e, e, e));
}

/* p = sum w_i v_i, evaluated in double and rounded, with pbrt's bound
 * gamma(7) sum |w_i v_i| per coordinate, plus the reach term for the
 * farthest vertex. */
static void interpolate(const vec3 v[3], const double w[3], vec3 *p, vec3 *err)
{
    dvec3 sum = {0, 0, 0}, mag = {0, 0, 0};
    for (int k = 0; k < 3; k++) {
        dvec3 term = dscale(dv3(v[k]), w[k]);
        sum = dadd(sum, term);
        mag = dadd(mag, dabs(term));
    }
    double reach = 0.0;
    for (int k = 0; k < 3; k++) reach = fmax(reach, dmaxc(dv3_sub(dv3(v[k]), sum)));
    *p = to_float(sum);
    *err = to_float(with_reach(dscale(mag, gamma_f(7)), reach));
}

static bool triangle_point(const vec3 v[3], const ray_t *r, double t, vec3 *p, vec3 *err, double *inside, double w[3])
{
    dvec3 a = dv3(v[0]), b = dv3(v[1]), c = dv3(v[2]);
    dvec3 nrm = dv3_cross(dv3_sub(b, a), dv3_sub(c, a));
    if (!(dv3_dot(nrm, nrm) > 0.0)) return false;
    *inside = barycentric(a, b, c, onto_plane(r, t, a, nrm), w);
    interpolate(v, w, p, err);
    return true;
}

static void tri_vertices(const vec3 *verts, const tri_t *tri, vec3 v[3])
{
    for (int k = 0; k < 3; k++) v[k] = verts[tri->v[k]];
}

/* Record the shading triangle and weights (see surface_point). */
static void set_shading(surface_point *sp, const tri_t *tri, const double w[3])
{
    for (int k = 0; k < 3; k++) sp->tri[k] = tri->v[k], sp->w[k] = (float)w[k];
}

static surface_point no_shading(vec3 p, vec3 err, vec3 normal)
{
    surface_point sp = {p, err, normal, {SURFACE_NO_TRIANGLE, SURFACE_NO_TRIANGLE, SURFACE_NO_TRIANGLE}, {0, 0, 0}};
    return sp;
}

static surface_point sphere_point(sphere_t s, const ray_t *r, double t)
{
    dvec3 c = dv3(s.center), off = dv3_sub(ray_point(r, t), c);
    double len = sqrt(dv3_dot(off, off));
    /* The centre itself (only for a ray starting there): any direction. */
    dvec3 n = len > 0.0 ? dscale(off, 1.0 / len) : dmake(0, 1, 0);
    dvec3 lever = dscale(n, (double)s.radius);
    surface_point sp = no_shading(to_float(dadd(c, lever)), v3(0, 0, 0), v3(0, 0, 0));
    /* gamma(5) times the magnitudes that make up each coordinate. */
    dvec3 mag = dadd(dabs(c), dabs(lever));
    double slack = DOUBLE_SLACK * (dmaxc(c) + s.radius);
    sp.err = to_float(with_reach(dadd(dscale(mag, gamma_f(5)), dmake(slack, slack, slack)), 2.0 * s.radius));
    sp.normal = v3_norm(to_float(n));
    return sp;
}

/* The axis frame: the height h along the unit axis w from the base,
 * clamped to the cone's length, and the radial direction around it. */
static surface_point cone_point(cone_t cn, const ray_t *r, double t)
{
    dvec3 b = dv3(cn.base), ax = dv3_sub(dv3(cn.apex), b);
    double len = sqrt(dv3_dot(ax, ax));
    dvec3 w = dscale(ax, 1.0 / len), q = dv3_sub(ray_point(r, t), b);
    double h = fmin(fmax(dv3_dot(q, w), 0.0), len);
    dvec3 radial = dadd(q, dscale(w, -dv3_dot(q, w)));
    double rho = sqrt(dv3_dot(radial, radial));
    if (!(rho > 0.0)) { /* on the axis (a pointed tip): any perpendicular */
        dvec3 any = fabs(w.x) < 0.9 ? dmake(1, 0, 0) : dmake(0, 1, 0);
        radial = dv3_cross(w, any);
        rho = sqrt(dv3_dot(radial, radial));
    }
    double radius = cn.base_radius + (cn.apex_radius - cn.base_radius) * h / len;
    dvec3 along = dscale(w, h), out = dscale(radial, radius / rho);
    surface_point sp = no_shading(to_float(dadd(b, dadd(along, out))), v3(0, 0, 0), v3(0, 0, 0));
    dvec3 mag = dadd(dabs(b), dadd(dabs(along), dabs(out)));
    double slack = DOUBLE_SLACK * (dmaxc(b) + len + fmax(cn.base_radius, cn.apex_radius));
    double reach = len + 2.0 * fmax(cn.base_radius, cn.apex_radius);
    sp.err = to_float(with_reach(dadd(dscale(mag, gamma_f(7)), dmake(slack, slack, slack)), reach));
    sp.normal = cone_normal(cn, sp.p);
    return sp;
}

/* A polygon's point lies on the ear triangle that contains the ray's
 * point (the most-inside one). The float polygon test sees the Newell
 * plane, which a slightly non-planar polygon's ear triangles leave by a
 * little: that gap joins the error bound. */
static surface_point polygon_point(const prims_t *p, const polygon_t *g, const ray_t *r, double t)
{
    surface_point sp = no_shading(v3(0, 0, 0), v3(0, 0, 0), g->normal);
    double best = -INFINITY;
    for (uint32_t k = 0; k + 2 < g->count; k++) {
        vec3 v[3], q, e;
        double inside, w[3];
        const tri_t *ear = &p->poly_tris[g->tri_first + k];
        tri_vertices(p->verts, ear, v);
        if (triangle_point(v, r, t, &q, &e, &inside, w) && inside > best) {
            best = inside, sp.p = q, sp.err = e;
            set_shading(&sp, ear, w);
        }
    }
    /* The polygon test works with every vertex, not only the ear's. */
    double reach = 0.0;
    for (uint32_t k = 0; k < g->count; k++)
        reach = fmax(reach, dmaxc(dv3_sub(dv3(p->verts[p->poly_verts[g->first + k]]), dv3(sp.p))));
    double gap = fabs(dv3_dot(dv3(g->normal), dv3(sp.p)) - (double)g->offset), e = gap + gamma_f(REACH_GAMMA) * reach;
    sp.err = v3_add(sp.err, v3((float)e, (float)e, (float)e));
    return sp;
}

surface_point prim_surface_point(const prims_t *p, const ray_t *ray, const hit_t *hit)
{
    uint32_t k = p->index[hit->prim];
    double t = hit->t;
    switch ((prim_kind)p->kind[hit->prim]) {
    case PRIM_TRIANGLE: {
        surface_point sp;
        vec3 v[3];
        double inside, w[3];
        tri_vertices(p->verts, &p->tris[k], v);
        if (!triangle_point(v, ray, t, &sp.p, &sp.err, &inside, w)) break;
        sp.normal = prim_normal(p, hit, ray);
        set_shading(&sp, &p->tris[k], w);
        return sp;
    }
    case PRIM_SPHERE:
        return sphere_point(p->spheres[k], ray, t);
    case PRIM_CONE:
        return cone_point(p->cones[k], ray, t);
    case PRIM_POLYGON:
        if (p->polygons[k].degenerate) break;
        return polygon_point(p, &p->polygons[k], ray, t);
    default:
        break;
    }
    /* Degenerate primitives are never hit; keep the ray's own point. */
    return no_shading(v3_madd(ray->org, ray->dir, hit->t), v3(0, 0, 0), prim_normal(p, hit, ray));
}

vec3 offset_ray_origin(vec3 p, vec3 err, vec3 n)
{
    float d = fabsf(n.x) * err.x + fabsf(n.y) * err.y + fabsf(n.z) * err.z;
    vec3 off = v3_scale(n, d);
    float c[3] = {p.x + off.x, p.y + off.y, p.z + off.z}, side[3] = {n.x, n.y, n.z};
    /* Round away from the surface: the sum above may have rounded back (and
     * a zero bound, at a vertex on the coordinate origin, moved nothing). */
    for (int i = 0; i < 3; i++)
        if (side[i] > 0.0f) c[i] = nextafterf(c[i], INFINITY);
        else if (side[i] < 0.0f) c[i] = nextafterf(c[i], -INFINITY);
    return v3(c[0], c[1], c[2]);
}
