/* sphere.c: the ray/sphere kernels.
 *
 * Formulation from Eric Haines, Johannes Guenther, Tomas Akenine-Moller,
 * "Precision Improvements for Ray/Sphere Intersection", Ray Tracing Gems,
 * chapter 7 (2019), the section on floating-point precision: written from
 * the chapter's description, not copied.
 *
 * With f = org - centre, the ray org + t*dir meets the sphere where
 *   a t^2 + 2 b t + c = 0,   a = d.d,  b = f.d,  c = f.f - r^2.
 * The textbook discriminant b^2 - a c subtracts two large, nearly equal
 * numbers when the sphere is small relative to its distance (|f| >> r): in
 * float, for r = 1e-3 at distance 170, b^2 and a c are about 3e4 with
 * rounding errors near 2e-3, while the true difference is at most
 * a r^2 = 1e-6, so the discriminant is pure noise. The
 * chapter rewrites it with l = f - (b/a) d, the vector from the centre to
 * the closest point of the ray's line:
 *   b^2 - a c = a (r^2 - l.l),
 * which only subtracts quantities of the size of r^2. The roots then come
 * from the cancellation-free pair q = -(b + sign(b) sqrt(disc)),
 * t0 = c / q, t1 = q / a (the classic Numerical Recipes trick).
 *
 * dir need not be unit length: t is in units of dir, so a = d.d is kept
 * everywhere. A tangent ray (disc == 0) hits; disc < 0 misses.
 * The nearest root in [tnear, tmax) wins, so a ray starting inside the
 * sphere hits the far side. */
#include "prims_internal.h"

/* The two roots in increasing order, or false for a miss (disc < 0, NaN,
 * zero direction). Float version. */
static bool sphere_roots(sphere_t s, const ray_t *ray, float *t0, float *t1)
{
    vec3 d = ray->dir;
    vec3 f = v3_sub(ray->org, s.center);
    float a = v3_dot(d, d);
    if (!(a > 0.0f)) return false;
    float b = v3_dot(f, d);
    float c = v3_dot(f, f) - s.radius * s.radius;
    vec3 l = v3_madd(f, d, -b / a);
    float disc = a * (s.radius * s.radius - v3_dot(l, l));
    if (!(disc >= 0.0f)) return false;

    float root = sqrtf(disc);
    float q = b >= 0.0f ? -(b + root) : -(b - root);
    if (q == 0.0f) {
        /* b == 0 and disc == 0: origin on the sphere, ray tangent there;
         * the double root is t = 0 (c / q would be 0 / 0). */
        *t0 = *t1 = 0.0f;
        return true;
    }
    float r0 = c / q, r1 = q / a;
    *t0 = fminf(r0, r1);
    *t1 = fmaxf(r0, r1);
    return true;
}

/* The same in double, for the arbiter. */
static bool sphere_roots_double(sphere_t s, const ray_t *ray, double *t0, double *t1)
{
    dvec3 d = dv3(ray->dir);
    dvec3 f = dv3_sub(dv3(ray->org), dv3(s.center));
    double r = s.radius;
    double a = dv3_dot(d, d);
    if (!(a > 0.0)) return false;
    double b = dv3_dot(f, d);
    double c = dv3_dot(f, f) - r * r;
    double k = -b / a;
    dvec3 l = {f.x + d.x * k, f.y + d.y * k, f.z + d.z * k};
    double disc = a * (r * r - dv3_dot(l, l));
    if (!(disc >= 0.0)) return false;

    double root = sqrt(disc);
    double q = b >= 0.0 ? -(b + root) : -(b - root);
    if (q == 0.0) {
        *t0 = *t1 = 0.0;
        return true;
    }
    double r0 = c / q, r1 = q / a;
    *t0 = fmin(r0, r1);
    *t1 = fmax(r0, r1);
    return true;
}

bool sphere_intersect(sphere_t s, const ray_t *ray, float tmax, float *t)
{
    float t0, t1;
    if (!sphere_roots(s, ray, &t0, &t1)) return false;
    if (t0 >= ray->tnear && t0 < tmax) {
        *t = t0;
        return true;
    }
    if (t1 >= ray->tnear && t1 < tmax) {
        *t = t1;
        return true;
    }
    return false;
}

bool sphere_intersect_double(sphere_t s, const ray_t *ray, double *t)
{
    double t0, t1, tnear = ray->tnear, tfar = ray->tfar;
    if (!sphere_roots_double(s, ray, &t0, &t1)) return false;
    if (t0 >= tnear && t0 < tfar) {
        *t = t0;
        return true;
    }
    if (t1 >= tnear && t1 < tfar) {
        *t = t1;
        return true;
    }
    return false;
}

/* Radius minus the distance from the centre to the ray's infinite line:
 * positive inside the silhouette, near 0 for a graze, negative outside. */
double sphere_boundary_distance(sphere_t s, const ray_t *ray)
{
    dvec3 d = dv3(ray->dir);
    dvec3 f = dv3_sub(dv3(ray->org), dv3(s.center));
    double a = dv3_dot(d, d);
    double k = a > 0.0 ? -dv3_dot(f, d) / a : 0.0;
    dvec3 l = {f.x + d.x * k, f.y + d.y * k, f.z + d.z * k};
    return (double)s.radius - sqrt(dv3_dot(l, l));
}
