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

/* A, B, C: the triangle's corners a, b, c sheared. Accepts tnear <= t <
 * tmax; writes t and barycentrics (u for b, v for c) on a hit. */
static inline __attribute__((always_inline)) bool triangle_sheared_hit(const shear_t *s, sheared_t A, sheared_t B,
                                                                       sheared_t C, const ray_t *ray, float tmax,
                                                                       float *t, float *u, float *v)
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
     * values. Dividing here (rather than comparing T against tnear*det and
     * tmax*det, as the paper does to defer the division) makes the range
     * test apply to exactly the t we return. A NaN fails it. */
    float T = U * (s->sz * A.z) + V * (s->sz * B.z) + W * (s->sz * C.z);
    float tt = T / det;
    if (!(tt >= ray->tnear && tt < tmax)) return false;

    *t = tt;
    *u = V / det;
    *v = W / det;
    return true;
}

#endif
