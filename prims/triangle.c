/* triangle.c: the ray/triangle kernels.
 *
 * triangle_intersect is the watertight ray/triangle test of
 *   Sven Woop, Carsten Benthin, Ingo Wald, "Watertight Ray/Triangle
 *   Intersection", Journal of Computer Graphics Techniques 2(1), 2013
 *   (the headers spell the first author "Woo"; it is Woop),
 * written from the paper's description of the algorithm (section 3: ray
 * setup, shear, 2D edge tests with the double-precision fallback, hit
 * distance), single precision and two-sided.
 *
 * Why watertight: a closed mesh has no holes, so a ray that crosses its
 * surface through a shared edge or vertex must hit at least one of the
 * triangles around it. Tests whose rounding depends on the triangle as a whole
 * (e.g. Moller-Trumbore, built on the triangle's own edge vectors) round
 * differently for the two triangles sharing an edge, so such a ray can slip between them; for
 * this benchmark that would make accelerators disagree with each other for
 * reasons that have nothing to do with traversal. Woop et al. instead
 * transform all vertices into ONE ray-dependent frame (a permutation and a
 * shear that map the ray onto the +z axis from the origin), where the
 * ray-edge test becomes a 2D edge function of the two edge endpoints alone.
 * The neighbour computes the same products with the endpoints swapped, so it
 * gets exactly the negated value: no gap, whatever the rounding.
 *
 * triangle_intersect_double is an independent arbiter (Moller-Trumbore in
 * double) and triangle_boundary_distance measures how close a point is to
 * the triangle's edges; both are for verification only. */
#include "prims_internal.h"
#include "shear.h" /* the ray-space shear and edge functions; also turns FP contraction off */
#include "tri_sheared.h" /* the test proper, in the sheared frame: shared with the packets (tri_packet.c) */

/* ---------------------------------------------------------------------- */
/* Watertight test, single precision (Woop et al. 2013, section 3)         */

/* ray_shear, shear_vertex, edge_function and its exact double fallback
 * live in shear.h, shared with the polygon kernel so both see the same
 * sheared vertices. The double fallback is computed for all three edges
 * when one float edge function is 0, so the neighbour across the edge sees
 * the same exact value. */

bool triangle_intersect(vec3 a, vec3 b, vec3 c, const ray_t *ray, float tmax, float *t, float *u, float *v)
{
    shear_t s;
    if (!ray_shear(ray->dir, &s)) return false;
    return triangle_sheared_hit(&s, a, b, c, shear_vertex(&s, a, ray->org), shear_vertex(&s, b, ray->org),
                                shear_vertex(&s, c, ray->org), ray, tmax, t, u, v);
}

/* ---------------------------------------------------------------------- */
/* Verification helpers, double precision                                  */

/* Moller-Trumbore in double: an algorithm independent of the float test,
 * so a shared mistake cannot make the two agree. Edges and vertices count
 * as inside (closed triangle), like the float test. */
bool triangle_intersect_double(vec3 a, vec3 b, vec3 c, const ray_t *ray, double *t)
{
    dvec3 da = dv3(a), o = dv3(ray->org), d = dv3(ray->dir);
    dvec3 e1 = dv3_sub(dv3(b), da), e2 = dv3_sub(dv3(c), da);
    dvec3 p = dv3_cross(d, e2);
    double det = dv3_dot(e1, p);
    if (det == 0.0 || !isfinite(det)) return false;

    dvec3 s = dv3_sub(o, da);
    double u = dv3_dot(s, p) / det;
    if (u < 0.0 || u > 1.0) return false;
    dvec3 q = dv3_cross(s, e1);
    double v = dv3_dot(d, q) / det;
    if (v < 0.0 || u + v > 1.0) return false;

    double tt = dv3_dot(e2, q) / det;
    if (!(tt >= (double)ray->tnear && tt < (double)ray->tfar)) return false;
    *t = tt;
    return true;
}

/* Distance from p to the closed segment a-b (a point if a == b). */
double triangle_boundary_distance(vec3 a, vec3 b, vec3 c, dvec3 p)
{
    dvec3 da = dv3(a), db = dv3(b), dc = dv3(c);
    double dab = dv3_point_segment_distance(p, da, db);
    double dbc = dv3_point_segment_distance(p, db, dc);
    double dca = dv3_point_segment_distance(p, dc, da);
    return fmin(dab, fmin(dbc, dca));
}
