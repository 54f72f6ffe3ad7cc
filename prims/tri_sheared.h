/* tri_sheared.h: the watertight triangle test in the ray's sheared frame
 * (Woop, Benthin, Wald, JCGT 2(1), 2013, section 3), after the ray set-up
 * (ray_shear) and the vertex shear (shear_vertex) of shear.h.
 *
 * One body for triangle_intersect (triangle.c: one triangle, the ray set
 * up per call) and the packet tests (tri_packet.c: the ray set up once per
 * packet call, each lane's vertices sheared the same way), so the two do
 * exactly the same arithmetic and give the same t, u, v bit for bit. */
#ifndef ACCELBENCH_TRI_SHEARED_H
#define ACCELBENCH_TRI_SHEARED_H

#include "shear.h"
#include "ray.h"

/* The hit distance of a ray that the sign test found inside triangle a, b,
 * c, in double: t = n . (a - o) / n . d with n = (b - a) x (c - a).
 *
 * Why not the sheared test's own t = (U Az + V Bz + W Cz) sz / det: its
 * terms are the vertices' distances along the ray, the size of the
 * triangle, and they cancel down to t. On a floor thousands of units wide
 * seen from a few units away, float's rounding of those terms (and of the
 * vertices minus the origin) is thousands of times the float step at the
 * hit. Here every input is a float, so
 * b - a, c - a and a - o are exact in double (operands within 2^29 of each
 * other's magnitude), the products and sums round at 2^-53 of terms of the
 * triangle's size, and the division's result is rounded once to float:
 * t is within about one float step of the exact crossing, at the hit's own
 * scale, unless the triangle is more than ~1e8 times larger than that
 * scale (or a sliver as thin as that). A zero or non-finite answer (the
 * ray parallel to the plane in double, a triangle degenerate in double)
 * keeps the sheared test's float t, tf.
 *
 * The hit-or-miss decision is not changed: it stays the sheared edge
 * functions' signs (watertight); only the reported distance, and the
 * range test tnear <= t < tmax on it, use this. Every triangle path
 * (triangle_sheared_hit below, the packet tests of tri_packet.h,
 * inlined under AVX2 and AVX-512 target attributes by the wide BVH) calls
 * this one function on the same floats, scalar and with contraction off
 * (shear.h), so they return the same t bit for bit. */
static inline __attribute__((always_inline)) float triangle_plane_t(vec3 a, vec3 b, vec3 c, vec3 o, vec3 d, float tf)
{
    double e1x = (double)b.x - a.x, e1y = (double)b.y - a.y, e1z = (double)b.z - a.z;
    double e2x = (double)c.x - a.x, e2y = (double)c.y - a.y, e2z = (double)c.z - a.z;
    double nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
    double num = nx * ((double)a.x - o.x) + ny * ((double)a.y - o.y) + nz * ((double)a.z - o.z);
    double den = nx * d.x + ny * d.y + nz * d.z;
    if (den == 0.0) return tf;
    float t = (float)(num / den);
    return isfinite(t) ? t : tf;
}

/* A, B, C: the triangle's corners a, b, c sheared (a, b, c themselves
 * for the hit distance). Accepts tnear <= t < tmax; writes t and
 * barycentrics (u for b, v for c) on a hit. */
static inline __attribute__((always_inline)) bool triangle_sheared_hit(const shear_t *s, vec3 a, vec3 b, vec3 c,
                                                                       sheared_t A, sheared_t B, sheared_t C,
                                                                       const ray_t *ray, float tmax, float *t,
                                                                       float *u, float *v)
{
    /* Scaled barycentrics: U weights a (the edge b-c opposite it), V
     * weights b, W weights c. */
    float U = edge_function(C, B);
    float V = edge_function(A, C);
    float W = edge_function(B, A);
    if (U == 0.0f || V == 0.0f || W == 0.0f) {
        U = edge_function_double(C, B);
        V = edge_function_double(A, C);
        W = edge_function_double(B, A);
    }

    /* Two-sided: inside means all three have the same sign; zeros (the ray
     * on an edge or vertex) count as inside so shared edges are covered. */
    if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;

    /* det = 0: the ray is parallel to the plane or the triangle has no
     * projected area (degenerate); also catches all three being 0. */
    float det = U + V + W;
    if (det == 0.0f) return false;

    /* Hit distance: the barycentric interpolation of the scaled, sheared z
     * values, the fallback of triangle_plane_t, which gives the distance
     * returned. The range test applies to exactly the t we return (rather
     * than comparing T against tnear*det and tmax*det, as the paper does
     * to defer the division). A NaN fails it. */
    float T = U * (s->sz * A.z) + V * (s->sz * B.z) + W * (s->sz * C.z);
    float tt = triangle_plane_t(a, b, c, ray->org, ray->dir, T / det);
    if (!(tt >= ray->tnear && tt < tmax)) return false;

    *t = tt;
    *u = V / det;
    *v = W / det;
    return true;
}

#endif
