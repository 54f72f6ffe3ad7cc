/* prims_internal.h: the per-kind kernels behind prims.h's dispatch.
 * One file per kind: triangle.c, sphere.c; box overlap in overlap.c.
 * None of these count; prims.c counts around them. */
#ifndef ACCELBENCH_PRIMS_INTERNAL_H
#define ACCELBENCH_PRIMS_INTERNAL_H

#include "prims.h"

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

#endif
