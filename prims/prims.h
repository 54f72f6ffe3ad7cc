/* prims.h: the primitive store and the ONE ray/primitive interface.
 *
 * Every accelerator reaches geometry only through these calls: bounds,
 * exact box overlap, closest-hit and any-hit tests (one primitive or a
 * leaf of them), extents along a direction. The tests bump the
 * prim_tests / prim_hits counters here, so an "intersection test" means the
 * same thing for every accelerator, and a new primitive kind needs no
 * accelerator change; their _fast forms (for timed traces) count nothing.
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
 * - Cones (NFF "c"): the lateral surface of a truncated cone from the base
 *   centre B, radius rb, to the apex centre A, radius ra. Open ends (no
 *   caps). Either end may be the wider one, ra == rb is a cylinder and one
 *   radius may be 0 (a pointed cone), but not both; B != A. Exact quadric,
 *   nearest root in range whose point lies between the two end planes, so
 *   a ray starting inside the tube hits the far wall. A ray lying in the
 *   surface (on a cylinder's axis, along a generator line) misses. The hit
 *   has u = the fraction of the way from B to A, v = 0. NFF's negative
 *   radii ("inside visible") are the loader's business: pass |r|.
 * - Polygons (NFF "p"): N >= 3 vertices (indices into verts) of a planar,
 *   simple, possibly concave polygon. The plane comes from Newell's method
 *   over all vertices, so collinear leading vertices and slightly
 *   non-planar input are fine; its normal follows the winding by the right
 *   hand rule. Inside-ness is the even-odd crossings test (Haines) done in
 *   the same ray-sheared 2D frame as the watertight triangle test, with a
 *   half-open rule: a ray through an edge shared by two polygons that lie
 *   on opposite sides of it as seen along the ray hits exactly one of them
 *   (both polygons see the same sheared vertices, so rounding cannot open
 *   a gap). Zero-area polygons (all vertices collinear, fewer than 3
 *   distinct ones) are kept, so ids stay stable, but flagged degenerate and
 *   never hit. Hits have u = v = 0.
 * - All kinds are two-sided.
 */
#ifndef ACCELBENCH_PRIMS_H
#define ACCELBENCH_PRIMS_H

#include <stdbool.h>
#include <stddef.h>
#include <assert.h> /* static_assert, also in C++ */
#include <stdint.h>
#include "ray.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum { PRIM_TRIANGLE = 0, PRIM_SPHERE = 1, PRIM_CONE = 2, PRIM_POLYGON = 3, PRIM_KINDS } prim_kind;

typedef struct { uint32_t v[3]; } tri_t;     /* indices into prims_t.verts */
typedef struct { vec3 center; float radius; } sphere_t;
typedef struct { vec3 base; float base_radius; vec3 apex; float apex_radius; } cone_t;

/* A polygon's vertex indices are poly_verts[first .. first + count). The
 * rest is derived by prims_finish(). */
typedef struct {
    uint32_t first, count;
    vec3 normal;        /* unit plane normal (Newell), right-handed to the winding; 0 if degenerate */
    float offset;       /* the plane is dot(normal, x) == offset (through the vertex centroid) */
    uint32_t tri_first; /* its count - 2 ear-clipping triangles are poly_tris[tri_first ..] */
    uint8_t axis;       /* dominant axis of normal, the one a 2D projection drops */
    uint8_t degenerate; /* 1 when the polygon has zero area: never hit */
} polygon_t;
static_assert(sizeof(cone_t) == 32 && sizeof(polygon_t) == 32, "cone_t and polygon_t are 32 bytes");

typedef struct prims {
    uint32_t count;      /* all primitives */
    uint8_t *kind;       /* [count] prim_kind */
    uint32_t *index;     /* [count] index into tris, spheres, cones or polygons */
    box3 *bounds;        /* [count] tight bounds, filled by prims_finish() */

    uint32_t nverts, nverts_cap;
    vec3 *verts;
    uint32_t ntris, ntris_cap;
    tri_t *tris;
    uint8_t *tri_degenerate; /* [ntris] 1 when the triangle has zero area */
    uint32_t ndegenerate;
    uint32_t nspheres, nspheres_cap;
    sphere_t *spheres;
    uint32_t ncones, ncones_cap;
    cone_t *cones;
    uint32_t npolygons, npolygons_cap;
    polygon_t *polygons;
    uint32_t npoly_verts, npoly_verts_cap;
    uint32_t *poly_verts;      /* all polygons' vertex indices, concatenated */
    uint32_t npoly_tris;
    tri_t *poly_tris;          /* [npoly_tris] all polygons' triangulations (prims_finish) */
    uint32_t npoly_degenerate; /* polygons flagged degenerate (not in ndegenerate) */

    uint32_t count_cap;
    box3 box;            /* bounds of all primitives */
} prims_t;

/* Building. Append vertices and primitives in scene order, then call
 * prims_finish() once: it computes bounds and the degenerate flags and
 * checks the data. The add functions return the new id (or vertex index);
 * out of memory, the only failure they have, is one line and exit 2
 * (checked_alloc.h). */
void prims_init(prims_t *p);
uint32_t prims_add_vertex(prims_t *p, vec3 v);
uint32_t prims_add_triangle(prims_t *p, uint32_t a, uint32_t b, uint32_t c);
uint32_t prims_add_sphere(prims_t *p, vec3 center, float radius);
uint32_t prims_add_cone(prims_t *p, vec3 base, float base_radius, vec3 apex, float apex_radius);
/* Copies the n indices (into verts, in winding order). */
uint32_t prims_add_polygon(prims_t *p, const uint32_t *vertex_indices, uint32_t n);
/* Returns 0, or -1 with a reason in err: a NaN/infinite coordinate, a
 * vertex index out of range, a sphere radius that is not finite and > 0,
 * a cone with a NaN/infinite value, a negative radius, both radii 0 or
 * base == apex, a polygon with fewer than 3 vertices. The reason names the
 * primitive or vertex by index. */
int prims_finish(prims_t *p, char *err, size_t errlen);
void prims_free(prims_t *p);
/* Heap bytes held by the store. */
size_t prims_memory(const prims_t *p);

/* Bounds and exact overlap: triangle/box by the separating axis test
 * (Akenine-Moller 2001), sphere/box by Arvo's closest-point distance,
 * polygon/box as "one of its ear-clipping triangles overlaps" (exact for
 * simple polygons), cone/box exact up to a margin of 64 DBL_EPSILON (about
 * 1.4e-14) times the largest coordinate magnitude involved (see cone.c: it
 * may say true for a box that misses the surface by less than that, never
 * false for one touching it).
 * Touching counts as overlapping, so a primitive lying exactly on a voxel
 * plane is in both voxels. Cone bounds are those of its two end discs. */
static inline box3 prim_bounds(const prims_t *p, uint32_t id) { return p->bounds[id]; }
bool prim_overlaps_box(const prims_t *p, uint32_t id, box3 box);

/* Closest hit in [ray->tnear, hit->t). Counts one test, and one hit when it
 * returns true. */
bool prim_intersect(const prims_t *p, uint32_t id, const ray_t *ray, hit_t *hit, counters_t *c);
/* Any hit in [ray->tnear, ray->tfar). Counts like prim_intersect. */
bool prim_occluded(const prims_t *p, uint32_t id, const ray_t *ray, counters_t *c);

/* Leaves: the same tests over ids[0 .. n), one call per leaf. intersect
 * keeps the nearest hit in *hit and returns whether any test hit; occluded
 * stops at the first primitive that occludes. Each counts one test per
 * primitive it tests (so occluded counts those up to the occluder). */
bool prim_intersect_leaf(const prims_t *p, const uint32_t *ids, uint32_t n, const ray_t *ray, hit_t *hit, counters_t *c);
bool prim_occluded_leaf(const prims_t *p, const uint32_t *ids, uint32_t n, const ray_t *ray, counters_t *c);

/* Counting-free forms for timed traces: exactly the arithmetic of the
 * counting ones (intersect.c compiles one body both ways), no counter
 * writes, the same answers bit for bit. */
bool prim_intersect_fast(const prims_t *p, uint32_t id, const ray_t *ray, hit_t *hit);
bool prim_occluded_fast(const prims_t *p, uint32_t id, const ray_t *ray);
bool prim_intersect_leaf_fast(const prims_t *p, const uint32_t *ids, uint32_t n, const ray_t *ray, hit_t *hit);
bool prim_occluded_leaf_fast(const prims_t *p, const uint32_t *ids, uint32_t n, const ray_t *ray);

/* --- triangle packets (tri_packet.c) ---
 *
 * Triangles copied out of the store in groups of PRIM_TRI_LANES, corners in
 * SoA (v[corner][axis][lane]), for accelerators that keep their leaves'
 * triangles next to their nodes: no id -> index -> vertex indirection and
 * one ray set-up (the watertight test's shear) per call instead of one per
 * triangle. The tests are prim_intersect_leaf / prim_occluded_leaf over
 * the packed ids in lane order, with the same arithmetic (tri_sheared.h,
 * shared with the one-triangle test): the same hit bit for bit, one test
 * counted per triangle and one hit per closer hit, occluded stopping at
 * the first occluder. A degenerate triangle is stored with NaN corners,
 * which no ray hits (still counted as tested, as prim_intersect does).
 * Memory: 160 bytes a packet (corners 144, ids 16). */
#define PRIM_TRI_LANES 4
#define PRIM_TRI_NO_ID UINT32_MAX /* an unused lane (only the last packet of a group has them) */
typedef struct {
    float v[3][3][PRIM_TRI_LANES]; /* corner a, b, c; axis x, y, z; lane */
    uint32_t id[PRIM_TRI_LANES];   /* primitive ids, PRIM_TRI_NO_ID in unused lanes */
} prim_tri_packet;
static_assert(sizeof(prim_tri_packet) == 160, "prim_tri_packet: 3*3*4*4 + 4*4 = 160 bytes");

/* Packets for n ids: ceil(n / PRIM_TRI_LANES). */
static inline uint32_t prim_tri_packets(uint32_t n) { return (n + PRIM_TRI_LANES - 1) / PRIM_TRI_LANES; }
/* Whether every one of ids[0 .. n) is a triangle (what can be packed). */
bool prim_all_triangles(const prims_t *p, const uint32_t *ids, uint32_t n);
/* Pack ids[0 .. n), all triangles, into out[0 .. prim_tri_packets(n)),
 * in order. */
void prim_tri_pack(const prims_t *p, const uint32_t *ids, uint32_t n, prim_tri_packet *out);
/* Closest hit and any hit over the npk packets pk[0 .. npk) (the contract
 * of prim_intersect_leaf and prim_occluded_leaf), counting and not. Their
 * bodies are tri_packet.h's, for traversals that inline them. */
bool prim_intersect_tris(const prim_tri_packet *pk, uint32_t npk, const ray_t *ray, hit_t *hit, counters_t *c);
bool prim_occluded_tris(const prim_tri_packet *pk, uint32_t npk, const ray_t *ray, counters_t *c);
bool prim_intersect_tris_fast(const prim_tri_packet *pk, uint32_t npk, const ray_t *ray, hit_t *hit);
bool prim_occluded_tris_fast(const prim_tri_packet *pk, uint32_t npk, const ray_t *ray);

/* The exact extent of primitive id along dir (any length, not 0 needed):
 * [*lo, *hi] contains min and max of dot(x, dir) over its points x,
 * rounded outward to float (at most about an ulp wider at each end; see
 * extent.c). Triangles and polygons over their vertices, spheres
 * c.dir -+ r |dir|, cones over their two rim circles. false (nothing
 * written) for an id out of range or a NaN or infinite dir. For Kay and
 * Kajiya's plane-set volumes. */
bool prim_extent(const prims_t *p, uint32_t id, vec3 dir, float *lo, float *hi);

/* Unit geometric normal at a hit (not flipped toward the ray). */
vec3 prim_normal(const prims_t *p, const hit_t *hit, const ray_t *ray);

/* --- spawning secondary rays (surface.c) --- */

/* A hit point recomputed on the primitive's own surface, with a
 * conservative bound on the rounding error of each coordinate (pbrt-v4's
 * error-bound method, PBR 4th ed. s6.8.5) and the unit geometric normal
 * there (not flipped toward the ray). */
typedef struct {
    vec3 p, err, normal;
    /* Where p lies for shading: the vertex indices of the triangle (a
     * polygon's ear triangle) and p's barycentric weights on it; tri[0] is
     * SURFACE_NO_TRIANGLE for spheres, cones and degenerate primitives. */
    uint32_t tri[3];
    float w[3];
} surface_point;
#define SURFACE_NO_TRIANGLE UINT32_MAX
/* From the ray's parameterisation point o + t d at hit->t: triangles and
 * polygons (through the ear triangle that contains it) by barycentrics
 * clamped onto the primitive, spheres as centre + r n, cones in their axis
 * frame. */
surface_point prim_surface_point(const prims_t *p, const ray_t *ray, const hit_t *hit);
/* pbrt-v4's OffsetRayOrigin (PBR 4th ed. s6.8.6): p moved along the unit
 * normal n (pointing to the side the new ray leaves toward) by the error
 * box's extent along n, every coordinate rounded one more float step away
 * from the surface. The result lies strictly on n's side of the surface in
 * exact arithmetic. */
vec3 offset_ray_origin(vec3 p, vec3 err, vec3 n);

/* --- for verification only (never counted, never used to trace) --- */

/* Double-precision test of one primitive: the nearest t in
 * [ray->tnear, ray->tfar) or returns false. An independent check for the
 * primitive tests' own tests; verify's judge of disputed rays is exact
 * (harness/measure/judge.h). */
bool prim_intersect_double(const prims_t *p, uint32_t id, const ray_t *ray, double *t);
/* How close the point at distance t on the ray is to the boundary of the
 * primitive, in world units: for a triangle or polygon the distance to its
 * nearest edge line segment, for a sphere how far the ray line passes
 * inside the silhouette (radius minus the ray line's distance to the
 * centre). For a cone the smaller of the distance to the nearer rim circle
 * and how far the ray line is from being tangent to the (infinite) cone:
 * for a cylinder exactly the radius minus the distance between the ray line
 * and the axis measured across the axis, negative when the line misses.
 * Small values mark edge, vertex, rim or silhouette grazes. */
double prim_boundary_distance(const prims_t *p, uint32_t id, const ray_t *ray, double t);

/* How far point q lies from triangle id's plane, in double (|n . (q - a)| /
 * |n| over its corners as floats); NAN for a primitive that is not a
 * triangle, or a triangle of zero area. The verifier's "origin" class
 * measures a ray's start with it: a float test's t near the origin can be
 * off by many times the origin's distance (a thin wall seen edge-on). */
double prim_plane_distance(const prims_t *p, uint32_t id, vec3 q);

/* --- polygon helpers, also for scene code --- */

/* The unit normal of the polygon pts[0..n) by Newell's method (the sum of
 * the cross products of consecutive vertices, taken relative to pts[0]),
 * right-handed to the winding; (0,0,0) for a zero-area polygon. */
vec3 polygon_normal(const vec3 *pts, uint32_t n);

/* Ear clipping (Meisters 1975: every simple polygon with n > 3 vertices has
 * an ear). Triangulates the simple, possibly concave, planar polygon
 * pts[0..n) whose normal is given (any length; a zero normal means "compute
 * it with polygon_normal"), writing n - 2 triangles of local indices into
 * tris and returning n - 2 (0 when n < 3). Either winding works; each
 * triangle keeps the polygon's winding. Collinear vertices give zero-area
 * triangles. If no ear can be found because the polygon is not simple
 * (self-intersecting), the rest is fanned from one vertex, so the count is
 * still n - 2 but the triangles may overlap or leave the polygon.
 * O(n^2) typically, O(n^3) worst case. */
uint32_t polygon_triangulate(const vec3 *pts, uint32_t n, vec3 normal, uint32_t (*tris)[3]);

/* --- clipping (clip.c) --- */

/* The bounds of the part of primitive id inside the closed box, for kd-tree
 * "perfect splits" (Wald and Havran 2006): triangles and polygons
 * clipped exactly (Sutherland-Hodgman in double, rounded outward: contains
 * the exact bounds, about an ulp wider at most), spheres and cones their
 * bounds within the box. Always inside both the box and prim_bounds();
 * box_empty() when the primitive does not touch the box (prim_overlaps_box
 * decides touching). */
box3 prim_clip_bounds(const prims_t *p, uint32_t id, box3 box);
/* An estimate of prim_clip_bounds of box's two halves at the plane
 * x[axis] = pos, for a builder's cost estimates only (spatial-split
 * binning), never for boxes it keeps: triangles split as Embree splits
 * them to bin (vertices and edge crossings in float, met with each half),
 * other primitives their bounds met with each half. Either may be empty. */
void prim_split_bounds(const prims_t *p, uint32_t id, box3 box, int axis, float pos, box3 *left, box3 *right);

#ifdef __cplusplus
}
#endif

#endif
