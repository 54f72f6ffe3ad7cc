/* spd.h: the emitter shared by the Standard Procedural Databases
 * generators (Eric Haines' SPD 3.14, rules in shared/SPD-SCENES.md), and
 * the table of generators.
 *
 * A generator is only its geometry rules: it calls spd_background(),
 * spd_view(), spd_light(), spd_material() and the primitive calls below in
 * the SPD's order, and the emitter turns them into scene_t primitives in
 * one of two modes, fixed for the whole scene:
 *
 *   true (the SPD's -c)       a sphere is a sphere, a cone a cone, a
 *                             3-vertex polygon one triangle, a polygon of
 *                             4 or more vertices one polygon primitive.
 *   tessellated (-t RES)      only triangles: a sphere is the equi-angular
 *                             cube sphere of 12*RES^2 triangles, a cone
 *                             4*RES segments of 2 triangles (8*RES), and
 *                             every polygon its ear-clipping triangles.
 *
 * Like the SPD's polygon writer, spd_polygon() first merges consecutive
 * vertices (the last and the first included) closer than 1e-6 and drops a
 * polygon left with fewer than 3. Geometry is computed in double and
 * stored as float. */
#ifndef ACCELBENCH_SPD_H
#define ACCELBENCH_SPD_H

#include "scene.h"

#include <math.h>

/* --- double-precision vectors and 3x3 matrices for the generators --- */

typedef struct { double x, y, z; } spd_vec;
/* Row-major m[row][col], applied to column vectors: M*v. */
typedef struct { double m[3][3]; } spd_mat;

static inline spd_vec spd_v(double x, double y, double z) { spd_vec r = {x, y, z}; return r; }
static inline spd_vec spd_add(spd_vec a, spd_vec b) { return spd_v(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline spd_vec spd_sub(spd_vec a, spd_vec b) { return spd_v(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline spd_vec spd_scale(spd_vec a, double s) { return spd_v(a.x * s, a.y * s, a.z * s); }
static inline double spd_dot(spd_vec a, spd_vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline spd_vec spd_cross(spd_vec a, spd_vec b)
{
    return spd_v(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double spd_len(spd_vec a) { return sqrt(spd_dot(a, a)); }
static inline spd_vec spd_norm(spd_vec a) { return spd_scale(a, 1.0 / spd_len(a)); }

static inline spd_vec spd_mat_apply(const spd_mat *M, spd_vec v)
{
    return spd_v(M->m[0][0] * v.x + M->m[0][1] * v.y + M->m[0][2] * v.z,
                 M->m[1][0] * v.x + M->m[1][1] * v.y + M->m[1][2] * v.z,
                 M->m[2][0] * v.x + M->m[2][1] * v.y + M->m[2][2] * v.z);
}
/* A*B: apply B first, then A. */
spd_mat spd_mat_mul(const spd_mat *A, const spd_mat *B);
/* s times the identity. */
spd_mat spd_mat_scaling(double s);
/* Right-hand-rule (counter-clockwise) rotation by angle (radians) about the
 * unit axis a. */
spd_mat spd_mat_rotation(spd_vec a, double angle);

/* The NFF "Shine" (Phong exponent) of a highlight half-angle in degrees, as
 * the SPD computes it: ln(0.5)/ln(cos(ang)); 100000 for ang <= 0 and 1 for
 * ang >= 90. */
double spd_shine(double angle_deg);

/* --- the emitter --- */

typedef struct spd_ctx spd_ctx; /* opaque: the scene, the mode, scratch space */

/* The SPD's "b": background colour. */
void spd_background(spd_ctx *c, double r, double g, double b);
/* The SPD's "v": angle is NFF's full field of view in degrees. */
void spd_view(spd_ctx *c, spd_vec from, spd_vec at, spd_vec up, double angle_deg, double hither, int xres, int yres);
/* The SPD's "l": a point light. */
void spd_light(spd_ctx *c, spd_vec p);
/* The SPD's "f R G B Kd Ks Shine T ior", for the primitives that follow.
 * material_t keeps the colour, kd, ks (the mirror weight), T and ior (the
 * whitted workload refracts through T > 0); shine is accepted for the
 * record but not stored (nothing here computes highlights). Identical
 * materials are shared. */
void spd_material(spd_ctx *c, double r, double g, double b, double kd, double ks, double shine, double t, double ior);

/* The SPD's "s": a sphere (tessellated: 12*RES^2 triangles). */
void spd_sphere(spd_ctx *c, spd_vec centre, double r);
/* The SPD's "c": an open cone or cylinder from base (radius rb) to apex
 * (radius ra) (tessellated: 8*RES triangles). */
void spd_cone(spd_ctx *c, spd_vec base, double rb, spd_vec apex, double ra);
/* The SPD's "p": a planar polygon, possibly concave, wound counter-clockwise
 * seen from its front. After merging near vertices: nothing if fewer than
 * 3 remain, one triangle for 3, else a polygon (tessellated: its n - 2
 * ear-clipping triangles). */
void spd_polygon(spd_ctx *c, const spd_vec *pts, int n);
/* The SPD's "pp 3": a triangle patch with per-vertex normals (kept in
 * scene_t.normals, unit length), one triangle in both modes, without the
 * polygon writer's vertex merging (the SPD's patch writer has none). */
void spd_patch(spd_ctx *c, const spd_vec pts[3], const spd_vec normals[3]);

/* --- the generators --- */

/* What a generator emits at a size, in true-primitive counts; used to
 * refuse scenes beyond the 2^32 primitive ids before generating, and
 * checked against the real output by the tests. */
typedef struct {
    uint64_t spheres, cones;
    uint64_t polygons;      /* "p" (any n) and "pp" primitives */
    uint64_t polygon_tris;  /* their triangles when tessellated: sum of (n - 2) */
    uint64_t polygon_verts; /* their vertices: sum of n */
    uint64_t patches;       /* of the polygons, "pp" triangle patches (vertex normals) */
} spd_census;

typedef struct {
    const char *name;    /* "balls" */
    const char *file;    /* the SPD source: "src/balls.c" */
    int default_size, max_size;
    const char *summary; /* one line for the catalogue */
    void (*generate)(spd_ctx *c, int size);
    void (*census)(int size, spd_census *n);
    /* Non-zero: the tessellation resolution the original program forces
     * whatever -t says (jacks calls lib_set_polygonalization(2, 2) after
     * reading its options), so :t and :tRES both use it. */
    int forced_res;
} spd_generator;

extern const spd_generator spd_generators[];
extern const int spd_ngenerators;
/* NULL if there is none of that name. */
const spd_generator *spd_generator_find(const char *name);

/* Primitive count of a census in a mode (tess_res 0: true primitives). */
uint64_t spd_census_prims(const spd_census *n, int tess_res);
/* What scene_spd(g, size, tess_res) would make, counted without making it
 * (the generator's forced resolution applied). */
uint64_t spd_prims(const spd_generator *g, int size, int tess_res);

/* The generators, one file each (scenes/spd_NAME.c). */
#define SPD_GENERATOR(name)                        \
    void spd_gen_##name(spd_ctx *c, int size);     \
    void spd_census_##name(int size, spd_census *n);
SPD_GENERATOR(balls)
SPD_GENERATOR(gears)
SPD_GENERATOR(mount)
SPD_GENERATOR(rings)
SPD_GENERATOR(teapot)
SPD_GENERATOR(tetra)
SPD_GENERATOR(tree)
SPD_GENERATOR(lattice)
SPD_GENERATOR(shells)
SPD_GENERATOR(jacks)
SPD_GENERATOR(sombrero)
#undef SPD_GENERATOR

/* The SPD views' shared defaults: "UNC sky blue" background, 45 degrees,
 * 512x512, +Z up. */
#define SPD_SKY_BLUE 0.078, 0.361, 0.753

#endif
