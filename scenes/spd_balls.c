/* spd_balls.c: the "balls" (sphereflake) scene of Eric Haines' Standard
 * Procedural Databases (SPD 3.14, src/balls.c), written from the rules in
 * shared/SPD-SCENES.md, not from the original code.
 *
 * A sphere of radius r carries 9 spheres of radius r/3 touching it, 3 on
 * an upper cone and 6 around its equator, recursively, to SIZE levels:
 * sum_{k=0..SIZE} 9^k spheres, over a square floor. Order, as in the SPD:
 * the floor first, then the spheres depth-first (a sphere, then each of its
 * children's whole subtrees in list order).
 *
 * The SPD floor is one quad (SPD count 7,382 at size 4 = 7,381 spheres + 1
 * quad). There is no polygon primitive here, so the quad becomes two
 * triangles (0,1,2) and (0,2,3) in the SPD's corner order: 7,381 spheres
 * + 2 triangles, and every sphere id is one more than its SPD number.
 *
 * Tessellated mode (the SPD's -t RES) replaces each sphere with an
 * equi-angular cube sphere of 12*RES^2 triangles; see cube_sphere_build()
 * for the exact layout. Geometry is computed in double and stored as float. */
#include "scene.h"

#include <stdlib.h>
#include <string.h>

typedef struct { double x, y, z; } d3;

static d3 d3make(double x, double y, double z) { d3 r = {x, y, z}; return r; }
static d3 d3add(d3 a, d3 b) { return d3make(a.x + b.x, a.y + b.y, a.z + b.z); }
static d3 d3scale(d3 a, double s) { return d3make(a.x * s, a.y * s, a.z * s); }
static d3 d3norm(d3 a)
{
    double l = sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
    return d3scale(a, 1.0 / l);
}
static vec3 tof(d3 a) { return v3((float)a.x, (float)a.y, (float)a.z); }

/* 3x3 rotation, row-major: m[r][c]. */
typedef struct { double m[3][3]; } mat3;

static d3 mat3_apply(const mat3 *M, d3 v)
{
    return d3make(M->m[0][0] * v.x + M->m[0][1] * v.y + M->m[0][2] * v.z,
                  M->m[1][0] * v.x + M->m[1][1] * v.y + M->m[1][2] * v.z,
                  M->m[2][0] * v.x + M->m[2][1] * v.y + M->m[2][2] * v.z);
}

/* Right-hand-rule rotation by angle about the unit axis a (Rodrigues). */
static mat3 mat3_rotation(d3 a, double angle)
{
    double c = cos(angle), s = sin(angle), t = 1.0 - c;
    mat3 R = {{{t * a.x * a.x + c, t * a.x * a.y - s * a.z, t * a.x * a.z + s * a.y},
               {t * a.x * a.y + s * a.z, t * a.y * a.y + c, t * a.y * a.z - s * a.x},
               {t * a.x * a.z - s * a.y, t * a.y * a.z + s * a.x, t * a.z * a.z + c}}};
    return R;
}

/* The rotation taking +Z to the unit vector d, by the SPD's rule: the
 * identity near +Z, a half turn about +Y near -Z, else the rotation about
 * Z x d by the angle between them. */
static mat3 rotation_z_to(d3 d)
{
    if (d.z >= 0.9999) return mat3_rotation(d3make(0, 0, 1), 0.0);
    if (d.z <= -0.9999) return mat3_rotation(d3make(0, 1, 0), M_PI);
    d3 axis = d3norm(d3make(-d.y, d.x, 0.0)); /* Z x d */
    return mat3_rotation(axis, acos(d.z));
}

/* The 9 child directions of a sphere whose direction is +Z. A trio, one
 * vector tilted 54.7 degrees from the pole and two on the equator at 15 and
 * 75 degrees azimuth, turned three times by 120 degrees about +Z. */
static void child_directions(d3 u[9])
{
    const double s2 = sqrt(0.5);
    d3 trio[3] = {d3make(s2, s2, 0), d3make(s2, 0, -s2), d3make(0, s2, -s2)};
    mat3 tilt = mat3_rotation(d3norm(d3make(1, -1, 0)), asin(2.0 / sqrt(6.0)));
    for (int k = 0; k < 3; k++) {
        mat3 turn = mat3_rotation(d3make(0, 0, 1), k * 2.0 * M_PI / 3.0);
        for (int i = 0; i < 3; i++) u[3 * k + i] = mat3_apply(&turn, mat3_apply(&tilt, trio[i]));
    }
}

/* --- tessellated spheres --- */

/* A unit cube sphere: shared vertex directions and triangles indexing them.
 *
 * A grid point of a cube face is the normalized cube point n + x*s + y*t,
 * where n is the face normal, s and t are its in-plane axes (s x t = n) and
 * x, y take the values tan((pi/4)(2k/res - 1)), k = 0..res: equal angles
 * along each face. For +Z (s = +X, t = +Y) the point (i, j) is the SPD's
 * (u, v) = (i, res - j), since normalize(Xu x Yv) is the direction of
 * (tan a_u, -tan b_v, 1); the other faces are the same grid turned onto
 * them. Points on face edges are shared: each is identified by its integer
 * lattice coordinates on the cube [0, res]^3, so a sphere has 6*res^2 + 2
 * vertices.
 *
 * Triangle order: faces +X, -X, +Y, -Y, +Z, -Z; in a face, quads by rows of
 * t (j outer) then s (i inner); in a quad, (i,j)(i+1,j)(i+1,j+1) then
 * (i,j)(i+1,j+1)(i,j+1). Both wind counter-clockwise seen from outside. */
typedef struct {
    uint32_t nverts, ntris;
    d3 *dir;
    uint32_t (*tri)[3];
} cube_sphere;

typedef struct { int axis, sign; } signed_axis;

static void cube_sphere_build(cube_sphere *cs, int res)
{
    static const signed_axis faces[6][3] = {
        /*  n        s        t   */
        {{0, +1}, {2, -1}, {1, +1}}, /* +X */
        {{0, -1}, {2, +1}, {1, +1}}, /* -X */
        {{1, +1}, {0, +1}, {2, -1}}, /* +Y */
        {{1, -1}, {0, +1}, {2, +1}}, /* -Y */
        {{2, +1}, {0, +1}, {1, +1}}, /* +Z */
        {{2, -1}, {0, -1}, {1, +1}}, /* -Z */
    };
    const int n1 = res + 1;
    double *tanv = malloc((size_t)n1 * sizeof *tanv);
    int32_t *slot = malloc((size_t)n1 * n1 * n1 * sizeof *slot);
    uint32_t *grid = malloc((size_t)n1 * n1 * sizeof *grid);
    cs->dir = malloc((size_t)(6 * res * res + 2) * sizeof *cs->dir);
    cs->tri = malloc((size_t)12 * res * res * sizeof *cs->tri);
    if (!tanv || !slot || !grid || !cs->dir || !cs->tri) {
        fprintf(stderr, "accelbench: out of memory building a cube sphere of resolution %d\n", res);
        abort();
    }
    for (int k = 0; k <= res; k++) tanv[k] = tan(M_PI / 4.0 * (2.0 * k / res - 1.0));
    tanv[0] = -1.0; /* exact cube edges, whatever tan() rounds to */
    tanv[res] = 1.0;
    for (int k = 0; k < n1 * n1 * n1; k++) slot[k] = -1;
    cs->nverts = cs->ntris = 0;

    for (int f = 0; f < 6; f++) {
        const signed_axis *n = &faces[f][0], *s = &faces[f][1], *t = &faces[f][2];
        for (int j = 0; j <= res; j++)
            for (int i = 0; i <= res; i++) {
                int lat[3];
                lat[n->axis] = n->sign > 0 ? res : 0;
                lat[s->axis] = s->sign > 0 ? i : res - i; /* tan is odd: -tan a_i = tan a_(res-i) */
                lat[t->axis] = t->sign > 0 ? j : res - j;
                int key = lat[0] + n1 * (lat[1] + n1 * lat[2]);
                if (slot[key] < 0) {
                    slot[key] = (int32_t)cs->nverts;
                    cs->dir[cs->nverts++] = d3norm(d3make(tanv[lat[0]], tanv[lat[1]], tanv[lat[2]]));
                }
                grid[j * n1 + i] = (uint32_t)slot[key];
            }
        for (int j = 0; j < res; j++)
            for (int i = 0; i < res; i++) {
                uint32_t a = grid[j * n1 + i], b = grid[j * n1 + i + 1];
                uint32_t c = grid[(j + 1) * n1 + i + 1], d = grid[(j + 1) * n1 + i];
                uint32_t *t1 = cs->tri[cs->ntris++], *t2 = cs->tri[cs->ntris++];
                t1[0] = a, t1[1] = b, t1[2] = c;
                t2[0] = a, t2[1] = c, t2[2] = d;
            }
    }
    free(tanv);
    free(slot);
    free(grid);
}

static void cube_sphere_free(cube_sphere *cs)
{
    free(cs->dir);
    free(cs->tri);
}

/* --- the generator --- */

typedef struct {
    prims_t *p;
    d3 u[9];                 /* child directions for a parent pointing at +Z */
    const cube_sphere *tess; /* NULL: true spheres */
} flake;

static void emit_sphere(flake *fl, d3 c, double r)
{
    if (!fl->tess) {
        prims_add_sphere(fl->p, tof(c), (float)r);
        return;
    }
    const cube_sphere *cs = fl->tess;
    uint32_t base = fl->p->nverts;
    for (uint32_t i = 0; i < cs->nverts; i++) prims_add_vertex(fl->p, tof(d3add(c, d3scale(cs->dir[i], r))));
    for (uint32_t i = 0; i < cs->ntris; i++)
        prims_add_triangle(fl->p, base + cs->tri[i][0], base + cs->tri[i][1], base + cs->tri[i][2]);
}

/* Emit a sphere, then, depth levels deep, its children: child i points
 * along M*u_i (M takes +Z to this sphere's direction) and sits at distance
 * r + r/3 from the centre, so it touches its parent. */
static void grow_flake(flake *fl, d3 c, double r, d3 dir, int depth)
{
    emit_sphere(fl, c, r);
    if (depth == 0) return;
    mat3 M = rotation_z_to(dir);
    double rc = r / 3.0;
    for (int i = 0; i < 9; i++) {
        d3 d = mat3_apply(&M, fl->u[i]);
        grow_flake(fl, d3add(c, d3scale(d, r + rc)), rc, d, depth - 1);
    }
}

uint64_t spd_balls_sphere_count(int size)
{
    uint64_t n = 0, p = 1;
    for (int k = 0; k <= size; k++, p *= 9) n += p;
    return n;
}

scene_t *scene_spd_balls(const char *name, int size, int tess_res, char *err, size_t errlen)
{
    if (size < 1 || size > 7) {
        snprintf(err, errlen, "spd:balls:%d: size must be 1..7", size);
        return NULL;
    }
    if (tess_res < 0 || tess_res > 64) {
        snprintf(err, errlen, "spd:balls:%d:t%d: tessellation resolution must be 1..64", size, tess_res);
        return NULL;
    }
    uint64_t nspheres = spd_balls_sphere_count(size);
    uint64_t per = tess_res ? 12ull * tess_res * tess_res : 1;
    uint64_t vper = tess_res ? 6ull * tess_res * tess_res + 2 : 0;
    if (nspheres * per + 2 > UINT32_MAX || nspheres * vper + 4 > UINT32_MAX) {
        snprintf(err, errlen, "spd:balls:%d:t%d: %llu triangles is more than the 2^32 primitive ids", size, tess_res,
                 (unsigned long long)(nspheres * per + 2));
        return NULL;
    }

    scene_t *s = scene_new(name);
    if (tess_res)
        snprintf(s->source, sizeof s->source, "SPD 3.14 balls -s %d -t %d: %llu spheres x %llu triangles + 2 floor triangles",
                 size, tess_res, (unsigned long long)nspheres, (unsigned long long)per);
    else
        snprintf(s->source, sizeof s->source, "SPD 3.14 balls -s %d -c: %llu spheres + 2 floor triangles", size,
                 (unsigned long long)nspheres);

    s->background = v3(0.078f, 0.361f, 0.753f);
    camera_t *cam = &s->camera;
    cam->from = v3(2.1f, 1.3f, 1.7f);
    cam->at = v3(0.0f, 0.0f, 0.0f);
    cam->up = v3(0.0f, 0.0f, 1.0f);
    cam->fov_deg = 45.0f;
    cam->hither = 0.01f;
    cam->width = cam->height = 512;
    scene_add_light(s, v3(4.0f, 3.0f, 2.0f));
    scene_add_light(s, v3(1.0f, -4.0f, 4.0f));
    scene_add_light(s, v3(-3.0f, 1.0f, 5.0f));
    /* NFF "f R G B Kd Ks Shine T ior"; the shine and transmission are not
     * in material_t (the floor's is a plain diffuse, the spheres' a mirror). */
    material_t floor_mat = {v3(1.0f, 0.75f, 0.33f), 0.8f, 0.0f};
    material_t sphere_mat = {v3(1.0f, 0.9f, 0.7f), 0.5f, 0.5f};
    uint16_t floor_id = scene_add_material(s, floor_mat);
    uint16_t sphere_id = scene_add_material(s, sphere_mat);

    /* The floor: SPD corners (12,12), (-12,12), (-12,-12), (12,-12) at
     * z = -0.5, facing +Z; fanned from the first corner. */
    prims_t *p = &s->prims;
    uint32_t f0 = prims_add_vertex(p, v3(12.0f, 12.0f, -0.5f));
    prims_add_vertex(p, v3(-12.0f, 12.0f, -0.5f));
    prims_add_vertex(p, v3(-12.0f, -12.0f, -0.5f));
    prims_add_vertex(p, v3(12.0f, -12.0f, -0.5f));
    prims_add_triangle(p, f0, f0 + 1, f0 + 2);
    prims_add_triangle(p, f0, f0 + 2, f0 + 3);
    scene_set_material_upto(s, floor_id);

    cube_sphere cs;
    flake fl = {.p = p, .tess = NULL};
    child_directions(fl.u);
    if (tess_res) {
        cube_sphere_build(&cs, tess_res);
        fl.tess = &cs;
    }
    grow_flake(&fl, d3make(0, 0, 0), 0.5, d3make(0, 0, 1), size);
    if (tess_res) cube_sphere_free(&cs);
    scene_set_material_upto(s, sphere_id);

    if (scene_finish(s, true, err, errlen) != 0) {
        scene_free(s);
        return NULL;
    }
    return s;
}
