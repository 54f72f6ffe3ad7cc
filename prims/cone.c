/* cone.c: the ray/cone kernels (NFF "c": an open truncated cone or
 * cylinder, no caps, two-sided).
 *
 * Geometry. Base centre B with radius rb, apex centre A with radius ra,
 * L = |A - B|, unit axis w = (A - B) / L, slope k = (ra - rb) / L. A point
 * P at height h = (P - B).w above the base and at distance rho from the
 * axis is on the surface when 0 <= h <= L and rho = rb + k h. Both radii
 * are >= 0, so rb + k h >= 0 between the end planes: the other nappe of the
 * double cone (rho = -(rb + k h)) lies beyond them and the height test
 * alone removes it.
 *
 * Intersection: the exact quadric, solved in the cone's own frame. With
 * (e1, e2, w) an orthonormal frame (Duff, Burgess, Christensen, Hery,
 * Kensler, Liani, Villemin, "Building an Orthonormal Basis, Revisited",
 * JCGT 6(1), 2017), q = org - B and d = dir split into 2D parts across the
 * axis (qp, dp) and heights (h0 = q.w, dw = d.w). With R0 = rb + k h0 (the
 * cone's radius at the origin's height) and s = k dw, the ray meets the
 * infinite cone where
 *   a t^2 + 2 b t + c = 0,  a = dp.dp - s^2,  b = qp.dp - R0 s,  c = qp.qp - R0^2.
 * The discriminant b^2 - a c is computed in the cancellation-free form
 *   b^2 - a c = |R0 dp - s qp|^2 - (dp x qp)^2
 * (expand both sides; Lagrange's identity turns (qp.dp)^2 - |qp|^2 |dp|^2
 * into -(dp x qp)^2). For a cylinder (s = 0) it is |dp|^2 (r^2 - l^2), l
 * the distance of the ray's line from the axis across it: the same rewrite
 * Haines, Guenther and Akenine-Moller use for spheres (Ray Tracing Gems,
 * ch. 7; see sphere.c), and for the same reason: a thin cylinder far from
 * the ray origin makes the textbook b^2 - a c pure rounding noise, while
 * here only quantities of the size of r^2 are subtracted. The roots come
 * from the stable pair q = -(b + sign(b) sqrt(disc)), t0 = c / q,
 * t1 = q / a, which also covers a = 0 (a ray parallel to a generator line:
 * one finite root c / q, the other at infinity). a < 0 (a ray steeper than
 * the cone) is fine: the roots are then on the two nappes, and the height
 * test keeps the right one. dir need not be unit length: t is in units of
 * dir throughout.
 *
 * A ray whose line lies in the surface (a = b = c = 0: a generator line, or
 * b = 0, a = 0 as on a cylinder's axis) has no isolated root and misses.
 *
 * Accuracy (tests/test_prims_shapes.c, against the double version): the
 * float t is within a few 1e-6 relative where the problem is well
 * conditioned; the error grows like 1 / cos for rays at a shallow angle to
 * the surface, like 1 / sqrt(margin) near a tangent, and near the tip of a
 * pointed cone, where the quadric is singular and the rounding of
 * org - base (about FLT_EPSILON |org - base|) is large against the radius
 * there. A thin cylinder far from the ray origin is fine (the rewritten
 * discriminant).
 *
 * Box overlap: see cone_overlaps_box below (exact up to a tiny margin,
 * with a separating-plane certificate for every "no"). */
#include "prims_internal.h"

#include <float.h>

/* ---------------------------------------------------------------------- */
/* frames                                                                  */

/* Duff et al. 2017: an orthonormal pair across the unit vector n without
 * a branch on which component is small; copysign keeps it continuous
 * except at n.z = 0 exactly, where either sign is fine. */
static void onb_float(vec3 n, vec3 *e1, vec3 *e2)
{
    float sign = copysignf(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    *e1 = v3(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x);
    *e2 = v3(b, sign + n.y * n.y * a, -n.y);
}

static dvec3 dvec(double x, double y, double z)
{
    dvec3 r = {x, y, z};
    return r;
}
static dvec3 dadd(dvec3 a, dvec3 b) { return dvec(a.x + b.x, a.y + b.y, a.z + b.z); }
static dvec3 dscale(dvec3 a, double s) { return dvec(a.x * s, a.y * s, a.z * s); }
static dvec3 dmadd(dvec3 a, dvec3 b, double s) { return dvec(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s); }
static double dlen(dvec3 a) { return sqrt(dv3_dot(a, a)); }

static void onb_double(dvec3 n, dvec3 *e1, dvec3 *e2)
{
    double sign = copysign(1.0, n.z);
    double a = -1.0 / (sign + n.z);
    double b = n.x * n.y * a;
    *e1 = dvec(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    *e2 = dvec(b, sign + n.y * n.y * a, -n.y);
}

/* The cone in double: centres, unit axis, length and slope. */
typedef struct {
    dvec3 b, a, w;
    double rb, ra, len, k;
} dcone_t;

static dcone_t dcone(cone_t c)
{
    dcone_t K;
    K.b = dv3(c.base);
    K.a = dv3(c.apex);
    dvec3 ax = dv3_sub(K.a, K.b);
    K.len = dlen(ax);
    K.w = dscale(ax, 1.0 / K.len);
    K.rb = c.base_radius;
    K.ra = c.apex_radius;
    K.k = (K.ra - K.rb) / K.len;
    return K;
}

/* ---------------------------------------------------------------------- */
/* intersection                                                            */

/* The quadric's coefficients for one ray, in the cone's frame, plus the
 * heights needed to clip the roots. Float version. */
bool cone_intersect(cone_t c, const ray_t *ray, float tmax, float *t, float *u)
{
    vec3 axis = v3_sub(c.apex, c.base);
    float len = v3_len(axis);
    if (!(len > 0.0f)) return false;
    vec3 w = v3_scale(axis, 1.0f / len), e1, e2;
    onb_float(w, &e1, &e2);
    float k = (c.apex_radius - c.base_radius) / len;

    vec3 q = v3_sub(ray->org, c.base), d = ray->dir;
    float qx = v3_dot(q, e1), qy = v3_dot(q, e2), h0 = v3_dot(q, w);
    float dx = v3_dot(d, e1), dy = v3_dot(d, e2), dw = v3_dot(d, w);
    float r0 = c.base_radius + k * h0, s = k * dw;

    float a = (dx * dx + dy * dy) - s * s;
    float b = (qx * dx + qy * dy) - r0 * s;
    float cc = (qx * qx + qy * qy) - r0 * r0;
    float xx = r0 * dx - s * qx, xy = r0 * dy - s * qy, cr = dx * qy - dy * qx;
    float disc = (xx * xx + xy * xy) - cr * cr;
    if (!(disc >= 0.0f)) return false; /* no real root, or NaN */

    float root = sqrtf(disc);
    float qq = b >= 0.0f ? -(b + root) : -(b - root);
    float t0, t1;
    if (qq == 0.0f) {
        /* b == 0 and disc == 0. With a != 0 the double root is t = 0 (the
         * origin on the surface, the line tangent there); with a == 0 too
         * the line lies in the surface (or never meets it): no hit. */
        if (a == 0.0f) return false;
        t0 = t1 = 0.0f;
    } else {
        float ra_ = cc / qq, rb_ = qq / a; /* a == 0: rb_ = +-inf, out of any range */
        t0 = fminf(ra_, rb_);
        t1 = fmaxf(ra_, rb_);
    }
    float roots[2] = {t0, t1};
    for (int i = 0; i < 2; i++) {
        float tt = roots[i];
        if (!(tt >= ray->tnear && tt < tmax)) continue;
        float h = h0 + tt * dw;
        if (!(h >= 0.0f && h <= len)) continue; /* beyond an open end */
        *t = tt;
        *u = h / len;
        return true;
    }
    return false;
}

/* The same in double, for the arbiter. */
bool cone_intersect_double(cone_t c, const ray_t *ray, double *t)
{
    dcone_t K = dcone(c);
    if (!(K.len > 0.0)) return false;
    dvec3 e1, e2;
    onb_double(K.w, &e1, &e2);

    dvec3 q = dv3_sub(dv3(ray->org), K.b), d = dv3(ray->dir);
    double qx = dv3_dot(q, e1), qy = dv3_dot(q, e2), h0 = dv3_dot(q, K.w);
    double dx = dv3_dot(d, e1), dy = dv3_dot(d, e2), dw = dv3_dot(d, K.w);
    double r0 = K.rb + K.k * h0, s = K.k * dw;

    double a = (dx * dx + dy * dy) - s * s;
    double b = (qx * dx + qy * dy) - r0 * s;
    double cc = (qx * qx + qy * qy) - r0 * r0;
    double xx = r0 * dx - s * qx, xy = r0 * dy - s * qy, cr = dx * qy - dy * qx;
    double disc = (xx * xx + xy * xy) - cr * cr;
    if (!(disc >= 0.0)) return false;

    double root = sqrt(disc);
    double qq = b >= 0.0 ? -(b + root) : -(b - root);
    double t0, t1;
    if (qq == 0.0) {
        if (a == 0.0) return false;
        t0 = t1 = 0.0;
    } else {
        double ra_ = cc / qq, rb_ = qq / a;
        t0 = fmin(ra_, rb_);
        t1 = fmax(ra_, rb_);
    }
    double roots[2] = {t0, t1}, tnear = ray->tnear, tfar = ray->tfar;
    for (int i = 0; i < 2; i++) {
        double tt = roots[i];
        if (!(tt >= tnear && tt < tfar)) continue;
        double h = h0 + tt * dw;
        if (!(h >= 0.0 && h <= K.len)) continue;
        *t = tt;
        return true;
    }
    return false;
}

vec3 cone_normal(cone_t c, vec3 hp)
{
    vec3 axis = v3_sub(c.apex, c.base);
    float len = v3_len(axis);
    vec3 w = v3_scale(axis, 1.0f / len);
    float k = (c.apex_radius - c.base_radius) / len;
    vec3 q = v3_sub(hp, c.base);
    vec3 radial = v3_madd(q, w, -v3_dot(q, w));
    float rho = v3_len(radial);
    /* The gradient of rho - (rb + k h) is (radial unit) - k w: outward, and
     * tilted towards the narrow end. At a pointed tip (rho = 0) there is
     * no tangent plane; the axis out of the tip is the natural choice. */
    if (!(rho > 0.0f)) return k <= 0.0f ? w : v3_scale(w, -1.0f);
    return v3_norm(v3_madd(v3_scale(radial, 1.0f / rho), w, -k));
}

/* Distance to the nearer rim circle, or how far the ray line is from
 * tangency, whichever is smaller (see prims.h). The tangency margin is
 * (|R0 dp - s qp| - |dp x qp|) / |dp|: zero exactly when the discriminant
 * is, positive when the line crosses the infinite cone, unchanged when the
 * origin slides along the ray, and for a cylinder exactly r - l. A line
 * parallel to the axis (dp = 0) never grazes the side: infinite margin. */
double cone_boundary_distance(cone_t c, const ray_t *ray, double t)
{
    dcone_t K = dcone(c);
    dvec3 e1, e2;
    onb_double(K.w, &e1, &e2);
    dvec3 o = dv3(ray->org), d = dv3(ray->dir);
    dvec3 hp = dmadd(o, d, t);

    dvec3 p = dv3_sub(hp, K.b);
    double h = dv3_dot(p, K.w);
    double rho = hypot(dv3_dot(p, e1), dv3_dot(p, e2));
    double rim = fmin(hypot(rho - K.rb, h), hypot(rho - K.ra, h - K.len));

    dvec3 q = dv3_sub(o, K.b);
    double qx = dv3_dot(q, e1), qy = dv3_dot(q, e2), h0 = dv3_dot(q, K.w);
    double dx = dv3_dot(d, e1), dy = dv3_dot(d, e2), dw = dv3_dot(d, K.w);
    double r0 = K.rb + K.k * h0, s = K.k * dw;
    double dplen = hypot(dx, dy);
    double margin = INFINITY;
    if (dplen > 0.0) margin = (hypot(r0 * dx - s * qx, r0 * dy - s * qy) - fabs(dx * qy - dy * qx)) / dplen;
    return fmin(rim, margin);
}

/* ---------------------------------------------------------------------- */
/* bounds                                                                  */

/* A disc of radius r, centre C, unit normal n spans C_k +- r sqrt(1 - n_k^2)
 * along axis k; sqrt(n_i^2 + n_j^2) is the same thing without the
 * cancellation of 1 - n_k^2 when n is close to axis k. The truncated cone
 * is the convex hull of its two end discs, so their bounds are its bounds,
 * and they are tight (each disc touches each of its box faces). */
box3 cone_bounds(cone_t c)
{
    dcone_t K = dcone(c);
    double n[3] = {K.w.x, K.w.y, K.w.z};
    double cb[3] = {K.b.x, K.b.y, K.b.z}, ca[3] = {K.a.x, K.a.y, K.a.z};
    float lo[3], hi[3];
    for (int i = 0; i < 3; i++) {
        double ni = n[(i + 1) % 3], nj = n[(i + 2) % 3];
        double across = sqrt(ni * ni + nj * nj);
        double eb = K.rb * across, ea = K.ra * across;
        lo[i] = float_down(fmin(cb[i] - eb, ca[i] - ea));
        hi[i] = float_up(fmax(cb[i] + eb, ca[i] + ea));
    }
    box3 bx = {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
    return bx;
}

/* ---------------------------------------------------------------------- */
/* box overlap                                                             */

/* Let g(P) = rho(P) - (rb + k h(P)): negative inside the infinite cone,
 * zero on it. rho is a norm of an affine function of P and rb + k h is
 * affine, so g is CONVEX. Let X be the box and X' = X cut to the slab
 * 0 <= h <= L (convex, so connected). The surface meets X iff some point of
 * X' has g = 0, and because X' is connected and g continuous that holds iff
 *   (1) X' is not empty,
 *   (2) max over X' of g >= 0, and
 *   (3) min over X' of g <= 0, i.e. X meets the solid cone K (g <= 0 in the
 *       slab: the convex hull of the two end discs).
 * (2) is exact and cheap: a convex function's maximum over a polytope is
 * at a vertex, and X' has as vertices the box corners inside the slab and
 * the points where box edges cross the two end planes. It rejects boxes
 * inside the hollow of the tube. (3) is two convex sets: GJK (Gilbert,
 * Johnson, Keerthi, IEEE J. Robotics and Automation 4(2), 1988) on the
 * Minkowski difference K - X, with the support mappings of the box (a
 * corner) and of K (the better of the two discs' extreme points). It
 * answers "disjoint" only with a certificate: a direction v with
 *   min over K of v.x - max over X of v.x > tol |v|,
 * checked directly from the support points, so a bug or slow convergence
 * in the simplex steps can only cost tightness, never a false "no". After
 * 64 iterations without a certificate it says "overlap".
 *
 * How conservative: all of (1)-(3) are tested with a margin tol = 64
 * DBL_EPSILON times the largest coordinate magnitude involved (times
 * 1 + |k| where heights feed radii), about 1.4e-14 of it, far below one
 * float ulp. So the answer is exact except that a box missing the surface
 * by less than that margin, or missing the solid cone by so little that
 * GJK has not certified it in 64 iterations (in tests, never at gaps of
 * 1e-6 of the cone's size), may be reported as overlapping. A touching box
 * is never reported as separated. */

static dvec3 box_corner(dvec3 lo, dvec3 hi, int i)
{
    return dvec(i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z);
}

/* g at P, with h taken as computed. */
static double cone_g(const dcone_t *K, dvec3 P, double *h)
{
    dvec3 p = dv3_sub(P, K->b);
    *h = dv3_dot(p, K->w);
    dvec3 radial = dmadd(p, K->w, -*h);
    return dlen(radial) - (K->rb + K->k * *h);
}

/* Support mapping of the solid truncated cone K: the point of K with the
 * largest d.x, found on one of the end rims (or at a disc centre when d is
 * along the axis). */
static dvec3 cone_support(const dcone_t *K, dvec3 d)
{
    dvec3 across = dmadd(d, K->w, -dv3_dot(d, K->w));
    double l = dlen(across);
    dvec3 e = l > 0.0 ? dscale(across, 1.0 / l) : dvec(0, 0, 0);
    dvec3 pb = dmadd(K->b, e, K->rb), pa = dmadd(K->a, e, K->ra);
    return dv3_dot(d, pa) > dv3_dot(d, pb) ? pa : pb;
}

static dvec3 box_support(dvec3 lo, dvec3 hi, dvec3 d)
{
    return dvec(d.x >= 0.0 ? hi.x : lo.x, d.y >= 0.0 ? hi.y : lo.y, d.z >= 0.0 ? hi.z : lo.z);
}

/* GJK's sub-step: the point of the simplex hull closest to the origin, and
 * the smallest face of the simplex that holds it (the simplex is reduced
 * to it). Written plainly: a segment by clamped projection; a triangle by
 * projecting onto its plane and, if that falls outside, the best of its
 * edges; a tetrahedron by an inside test on its four faces and, if
 * outside, the best of its faces. Degenerate simplices fall back to their
 * edges, and only ever cost convergence (see the certificate above). */
static dvec3 closest_segment(dvec3 *S, int *n)
{
    dvec3 a = S[0], ab = dv3_sub(S[1], S[0]);
    double l2 = dv3_dot(ab, ab);
    double t = l2 > 0.0 ? -dv3_dot(a, ab) / l2 : 0.0;
    if (!(t > 0.0)) {
        *n = 1;
        return a;
    }
    if (t >= 1.0) {
        S[0] = S[1];
        *n = 1;
        return S[0];
    }
    return dmadd(a, ab, t);
}

static dvec3 closest_triangle(dvec3 *S, int *n)
{
    dvec3 a = S[0], b = S[1], c = S[2];
    dvec3 nrm = dv3_cross(dv3_sub(b, a), dv3_sub(c, a));
    double nn = dv3_dot(nrm, nrm);
    if (nn > 0.0) {
        /* The origin's projection onto the plane, inside all three edges? */
        dvec3 p = dscale(nrm, dv3_dot(nrm, a) / nn);
        dvec3 pa = dv3_sub(a, p), pb = dv3_sub(b, p), pc = dv3_sub(c, p);
        if (dv3_dot(dv3_cross(pa, pb), nrm) >= 0.0 && dv3_dot(dv3_cross(pb, pc), nrm) >= 0.0 &&
            dv3_dot(dv3_cross(pc, pa), nrm) >= 0.0)
            return p;
    }
    /* On the boundary: the best edge. */
    dvec3 best = a, seg[2];
    double bestd = INFINITY;
    dvec3 keep[2] = {a, a};
    int nkeep = 1;
    static const int E[3][2] = {{0, 1}, {1, 2}, {2, 0}};
    for (int e = 0; e < 3; e++) {
        seg[0] = S[E[e][0]];
        seg[1] = S[E[e][1]];
        int m = 2;
        dvec3 v = closest_segment(seg, &m);
        double dd = dv3_dot(v, v);
        if (dd < bestd) {
            bestd = dd;
            best = v;
            keep[0] = seg[0];
            keep[1] = seg[1];
            nkeep = m;
        }
    }
    S[0] = keep[0];
    S[1] = keep[1];
    *n = nkeep;
    return best;
}

static dvec3 closest_tetrahedron(dvec3 *S, int *n)
{
    static const int F[4][4] = {{0, 1, 2, 3}, {0, 3, 1, 2}, {0, 2, 3, 1}, {1, 3, 2, 0}}; /* face, opposite */
    bool inside = true;
    for (int f = 0; f < 4 && inside; f++) {
        dvec3 a = S[F[f][0]];
        dvec3 nrm = dv3_cross(dv3_sub(S[F[f][1]], a), dv3_sub(S[F[f][2]], a));
        double so = -dv3_dot(nrm, a), sl = dv3_dot(nrm, dv3_sub(S[F[f][3]], a));
        /* A flat tetrahedron (sl == 0) is never "inside": use its faces. */
        if (sl == 0.0 || so * sl < 0.0) inside = false;
    }
    if (inside) return dvec(0, 0, 0); /* *n stays 4: the origin is enclosed */
    dvec3 best = S[0], keep[3] = {S[0], S[0], S[0]};
    double bestd = INFINITY;
    int nkeep = 1;
    for (int f = 0; f < 4; f++) {
        dvec3 tri[3] = {S[F[f][0]], S[F[f][1]], S[F[f][2]]};
        int m = 3;
        dvec3 v = closest_triangle(tri, &m);
        double dd = dv3_dot(v, v);
        if (dd < bestd) {
            bestd = dd;
            best = v;
            for (int i = 0; i < m; i++) keep[i] = tri[i];
            nkeep = m;
        }
    }
    for (int i = 0; i < nkeep; i++) S[i] = keep[i];
    *n = nkeep;
    return best;
}

/* True only when K and the box are certainly more than tol apart. */
static bool gjk_separated(const dcone_t *K, dvec3 lo, dvec3 hi, double tol)
{
    dvec3 S[4];
    int n = 0;
    /* Start from a point of K - X: the axis midpoint (in K since the radius
     * there is >= 0) minus the box centre. */
    dvec3 v = dv3_sub(dscale(dadd(K->b, K->a), 0.5), dscale(dadd(lo, hi), 0.5));
    for (int it = 0; it < 64; it++) {
        double vv = dv3_dot(v, v);
        if (!(vv > tol * tol)) return false; /* touching within tol, or NaN */
        dvec3 w = dv3_sub(cone_support(K, dscale(v, -1.0)), box_support(lo, hi, v));
        double vw = dv3_dot(v, w), vl = sqrt(vv);
        /* w minimises v.m over m in K - X, so every point of K - X is at
         * least vw / |v| from the origin along v: the certificate. */
        if (vw > tol * vl) return true;
        /* No progress possible: the distance is within rounding of |v|,
         * and |v| is then at most about tol. */
        if (vv - vw <= 1e-12 * vv) return false;
        S[n++] = w;
        if (n == 2) v = closest_segment(S, &n);
        else if (n == 3) v = closest_triangle(S, &n);
        else if (n == 4) {
            v = closest_tetrahedron(S, &n);
            if (n == 4) return false; /* the origin is inside K - X */
        }
        /* n == 1: v = w */
        else v = w;
    }
    return false;
}

bool cone_overlaps_box(cone_t c, box3 box)
{
    if (box_is_empty(box)) return false;
    if (!box_overlap(cone_bounds(c), box)) return false;

    dcone_t K = dcone(c);
    dvec3 lo = dv3(box.lo), hi = dv3(box.hi);
    double mag = fmax(fmax(fmax(fabs(lo.x), fabs(hi.x)), fmax(fabs(lo.y), fabs(hi.y))), fmax(fabs(lo.z), fabs(hi.z)));
    mag = fmax(mag, fmax(fmax(fabs(K.b.x), fabs(K.a.x)), fmax(fmax(fabs(K.b.y), fabs(K.a.y)), fmax(fabs(K.b.z), fabs(K.a.z)))));
    mag += fmax(K.rb, K.ra);
    double tol = 64.0 * DBL_EPSILON * mag;
    double tolg = tol * (1.0 + fabs(K.k));

    /* (1) and (2): the vertices of X' and the largest g among them. */
    dvec3 P[8];
    double h[8];
    for (int i = 0; i < 8; i++) {
        P[i] = box_corner(lo, hi, i);
        h[i] = dv3_dot(dv3_sub(P[i], K.b), K.w);
    }
    bool any = false;
    double gmax = -INFINITY, hh;
    for (int i = 0; i < 8; i++)
        if (h[i] >= -tol && h[i] <= K.len + tol) {
            any = true;
            gmax = fmax(gmax, cone_g(&K, P[i], &hh));
        }
    /* The 12 edges join corners that differ in one bit. */
    for (int i = 0; i < 8; i++)
        for (int bit = 1; bit < 8; bit <<= 1) {
            int j = i | bit;
            if (j == i) continue;
            double planes[2] = {0.0, K.len};
            for (int pl = 0; pl < 2; pl++) {
                double H = planes[pl];
                if ((h[i] < H) == (h[j] < H)) continue;
                double lam = (H - h[i]) / (h[j] - h[i]);
                dvec3 X = dmadd(P[i], dv3_sub(P[j], P[i]), lam);
                any = true;
                gmax = fmax(gmax, cone_g(&K, X, &hh));
            }
        }
    if (!any) return false;          /* the box misses the slab between the end planes */
    if (gmax < -tolg) return false;  /* all of X' strictly inside the tube: no wall */

    /* (3): the box meets the solid cone unless GJK certifies otherwise. */
    return !gjk_separated(&K, lo, hi, tol);
}
