/* prims.h: the primitive store and the ONE ray/primitive interface.
 *
 * Every accelerator reaches geometry only through these calls: bounds,
 * exact box overlap, closest-hit and any-hit tests. The tests bump the
 * prim_tests / prim_hits counters here, so an "intersection test" means the
 * same thing for every accelerator, and a new primitive kind needs no
 * accelerator change.
 *
 * Primitive ids are dense, 0..count-1, in scene order (the order of the
 * source file or generator). Each id maps to a kind and an index into that
 * kind's array.
 *
 * Conventions:
 * - A test accepts a hit at distance t when ray->tnear <= t < hit->t, where
 *   the caller starts hit->t at ray->tfar (hit_none()). On a hit it writes
 *   t, u, v and prim into *hit and returns true; otherwise *hit is untouched.
 * - Triangles use the watertight test of Woop, Benthin and Wald (JCGT 2013):
 *   a ray through a shared edge or vertex of a closed mesh hits at least one
 *   of the triangles. Degenerate (zero-area) triangles are kept, so ids stay
 *   stable, but never hit.
 * - Spheres return the nearest root in range, so a ray starting inside a
 *   sphere hits its far side (as Embree does).
 * - Triangles and spheres are two-sided.
 */
#ifndef ACCELBENCH_PRIMS_H
#define ACCELBENCH_PRIMS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "ray.h"

typedef enum { PRIM_TRIANGLE = 0, PRIM_SPHERE = 1, PRIM_KINDS } prim_kind;

typedef struct { uint32_t v[3]; } tri_t;     /* indices into prims_t.verts */
typedef struct { vec3 center; float radius; } sphere_t;

typedef struct prims {
    uint32_t count;      /* all primitives */
    uint8_t *kind;       /* [count] prim_kind */
    uint32_t *index;     /* [count] index into tris or spheres */
    box3 *bounds;        /* [count] tight bounds, filled by prims_finish() */

    uint32_t nverts, nverts_cap;
    vec3 *verts;
    uint32_t ntris, ntris_cap;
    tri_t *tris;
    uint8_t *tri_degenerate; /* [ntris] 1 when the triangle has zero area */
    uint32_t ndegenerate;
    uint32_t nspheres, nspheres_cap;
    sphere_t *spheres;

    uint32_t count_cap;
    box3 box;            /* bounds of all primitives */
} prims_t;

/* Building. Append vertices and primitives in scene order, then call
 * prims_finish() once: it computes bounds and the degenerate flags and
 * checks the data. The add functions return the new id (or vertex index);
 * they abort on out-of-memory, which is the only failure they have. */
void prims_init(prims_t *p);
uint32_t prims_add_vertex(prims_t *p, vec3 v);
uint32_t prims_add_triangle(prims_t *p, uint32_t a, uint32_t b, uint32_t c);
uint32_t prims_add_sphere(prims_t *p, vec3 center, float radius);
/* Returns 0, or -1 with a reason in err: a NaN/infinite coordinate, a
 * vertex index out of range, a sphere radius that is not finite and > 0.
 * The reason names the primitive or vertex by index. */
int prims_finish(prims_t *p, char *err, size_t errlen);
void prims_free(prims_t *p);
/* Heap bytes held by the store. */
size_t prims_memory(const prims_t *p);

/* Bounds and exact overlap: triangle/box by the separating axis test
 * (Akenine-Moller 2001), sphere/box by Arvo's closest-point distance.
 * Touching counts as overlapping, so a primitive lying exactly on a voxel
 * plane is in both voxels. */
static inline box3 prim_bounds(const prims_t *p, uint32_t id) { return p->bounds[id]; }
bool prim_overlaps_box(const prims_t *p, uint32_t id, box3 box);

/* Closest hit in [ray->tnear, hit->t). Counts one test, and one hit when it
 * returns true. */
bool prim_intersect(const prims_t *p, uint32_t id, const ray_t *ray, hit_t *hit, counters_t *c);
/* Any hit in [ray->tnear, ray->tfar). Counts like prim_intersect. */
bool prim_occluded(const prims_t *p, uint32_t id, const ray_t *ray, counters_t *c);

/* Unit geometric normal at a hit (not flipped toward the ray). */
vec3 prim_normal(const prims_t *p, const hit_t *hit, const ray_t *ray);

/* --- for verification only (never counted, never used to trace) --- */

/* Double-precision test of one primitive: the nearest t in
 * [ray->tnear, ray->tfar) or returns false. The arbiter for disputed rays. */
bool prim_intersect_double(const prims_t *p, uint32_t id, const ray_t *ray, double *t);
/* How close the point at distance t on the ray is to the boundary of the
 * primitive, in world units: for a triangle the distance to its nearest
 * edge line segment, for a sphere how far the ray line passes inside the
 * silhouette (radius minus the ray line's distance to the centre). Small
 * values mark edge, vertex or silhouette grazes. */
double prim_boundary_distance(const prims_t *p, uint32_t id, const ray_t *ray, double t);

#endif
