/* prims_internal.h: the per-kind kernels behind prims.h's dispatch.
 * One file per kind: triangle.c, sphere.c, cone.c, polygon.c; triangle and
 * sphere box overlap in overlap.c, cone and polygon box overlap in their
 * own files. None of these count; intersect.c counts around them. */
#ifndef ACCELBENCH_PRIMS_INTERNAL_H
#define ACCELBENCH_PRIMS_INTERNAL_H

#include "prims.h"

/* Round a double to the float at or below (down) / at or above (up) it, so
 * float bounds contain the exact ones. */
static inline float float_down(double x)
{
    float f = (float)x;
    return (double)f > x ? nextafterf(f, -INFINITY) : f;
}
static inline float float_up(double x)
{
    float f = (float)x;
    return (double)f < x ? nextafterf(f, INFINITY) : f;
}

/* The corners of triangle k (an index into p->tris). */
static inline void tri_verts(const prims_t *p, uint32_t k, vec3 *a, vec3 *b, vec3 *c)
{
    const tri_t *t = &p->tris[k];
    *a = p->verts[t->v[0]];
    *b = p->verts[t->v[1]];
    *c = p->verts[t->v[2]];
}

/* Watertight ray/triangle test (Woop, Benthin, Wald, JCGT 2(1) 2013), single
 * precision. Accepts tnear <= t < tmax; writes t and barycentrics (u for b,
 * v for c) on a hit. */
bool triangle_intersect(vec3 a, vec3 b, vec3 c, const ray_t *ray, float tmax, float *t, float *u, float *v);
bool triangle_intersect_double(vec3 a, vec3 b, vec3 c, const ray_t *ray, double *t);
bool triangle_overlaps_box(vec3 a, vec3 b, vec3 c, box3 box);
double triangle_boundary_distance(vec3 a, vec3 b, vec3 c, dvec3 p);

/* Ray/sphere: nearest root in [tnear, tmax), numerically careful
 * (Haines et al., "Precision improvements for ray/sphere intersection",
 * Ray Tracing Gems ch. 7). */
bool sphere_intersect(sphere_t s, const ray_t *ray, float tmax, float *t);
bool sphere_intersect_double(sphere_t s, const ray_t *ray, double *t);
bool sphere_overlaps_box(sphere_t s, box3 box);
double sphere_boundary_distance(sphere_t s, const ray_t *ray);

/* Ray/cone (open truncated cone or cylinder, see prims.h): exact quadric
 * solved in the cone's own frame, nearest root in [tnear, tmax) between the
 * end planes; u = the hit's fraction of the way from base to apex. The cone
 * must be valid (prims_finish checks). */
bool cone_intersect(cone_t c, const ray_t *ray, float tmax, float *t, float *u);
bool cone_intersect_double(cone_t c, const ray_t *ray, double *t);
bool cone_overlaps_box(cone_t c, box3 box);
/* Tight bounds: the bounds of the two end discs, rounded outwards. */
box3 cone_bounds(cone_t c);
/* Outward unit normal of the side at the surface point hp (for a pointed
 * cone's tip, the axis direction out of the tip). */
vec3 cone_normal(cone_t c, vec3 hp);
double cone_boundary_distance(cone_t c, const ray_t *ray, double t);

/* Ray/polygon: the plane (normal, offset) of a non-degenerate polygon with
 * vertices verts[idx[0..n)]: plane distance, then even-odd crossings in the
 * ray-sheared frame (watertight, half-open edges; see polygon.c). */
bool polygon_intersect(const vec3 *verts, const uint32_t *idx, uint32_t n, vec3 normal, float offset,
                       const ray_t *ray, float tmax, float *t);
/* The arbiter: Newell plane in double, ray/plane, then crossings in the 2D
 * projection that drops the dominant axis (Haines, Graphics Gems IV). */
bool polygon_intersect_double(const vec3 *verts, const uint32_t *idx, uint32_t n, const ray_t *ray, double *t);
/* Any of the polygon's triangles (global vertex indices) overlaps box. */
bool polygon_overlaps_box(const vec3 *verts, const tri_t *tris, uint32_t ntris, box3 box);
/* Distance from p to the nearest edge segment. */
double polygon_boundary_distance(const vec3 *verts, const uint32_t *idx, uint32_t n, dvec3 p);
/* Plane of verts[idx[0..n)] by Newell's method, in double: unit normal,
 * offset, dominant axis; returns false for a zero-area polygon. */
bool polygon_plane(const vec3 *verts, const uint32_t *idx, uint32_t n, dvec3 *normal, double *offset, int *axis);

#endif
