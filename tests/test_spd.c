/* test_spd.c: the Standard Procedural Databases generators (scenes/spd*.c)
 * against shared/SPD-SCENES.md: primitive counts from the page's formulas,
 * exactly, at sizes 1-4 and the defaults, true and tessellated; a few
 * coordinates per generator derived by hand from the page's rules (the
 * derivations are in the comments); views, lights and materials; the name
 * grammar and its errors; and the named scene sets. */
#include "../scenes/scene.h"
#include "../scenes/spd.h"
#include "check.h"
#include "require_meshes.h"

#include <stdlib.h>
#include <string.h>

static char err[1024];

#define EPS 1e-5

static bool near3(vec3 a, double x, double y, double z, double eps)
{
    return fabs(a.x - x) <= eps && fabs(a.y - y) <= eps && fabs(a.z - z) <= eps;
}

#define CHECK_V3(a, X, Y, Z)                                                                                     \
    CHECK_MSG(near3((a), (X), (Y), (Z), EPS), "(%.7g %.7g %.7g) vs (%.7g %.7g %.7g)", (double)(a).x, (double)(a).y, \
              (double)(a).z, (double)(X), (double)(Y), (double)(Z))

static scene_t *load(const char *name)
{
    err[0] = '\0';
    scene_t *s = scene_load(name, err, sizeof err);
    CHECK_MSG(s != NULL, "%s: %s", name, err);
    return s;
}

static void expect_error(const char *name, const char *want)
{
    err[0] = '\0';
    scene_t *s = scene_load(name, err, sizeof err);
    CHECK_MSG(s == NULL, "%s loaded but should fail", name);
    CHECK_MSG(strstr(err, want) != NULL, "%s: error '%s' lacks '%s'", name, err, want);
    CHECK_MSG(strchr(err, '\n') == NULL, "error is not one line: '%s'", err);
    scene_free(s);
}

/* Vertex k of primitive id, for a triangle or a polygon. */
static vec3 vert(const prims_t *p, uint32_t id, uint32_t k)
{
    if (p->kind[id] == PRIM_TRIANGLE) return p->verts[p->tris[p->index[id]].v[k]];
    const polygon_t *g = &p->polygons[p->index[id]];
    return p->verts[p->poly_verts[g->first + k]];
}

static uint32_t nverts_of(const prims_t *p, uint32_t id)
{
    if (p->kind[id] == PRIM_TRIANGLE) return 3;
    if (p->kind[id] == PRIM_POLYGON) return p->polygons[p->index[id]].count;
    return 0;
}

/* ---- counts ---- */

typedef struct { uint64_t spheres, cones, tris, polys; } counts;

/* The page's formulas, true primitives (-c). tris: 3-vertex polygons and
 * patches; polys: polygons of 4 or more vertices. */
static counts formula(const char *gen, int n)
{
    counts c = {0, 0, 0, 0};
    uint64_t N = (uint64_t)n;
    if (!strcmp(gen, "balls")) {
        uint64_t p = 1;
        for (int k = 0; k <= n; k++, p *= 9) c.spheres += p; /* sum 9^k */
        c.polys = 1;                                         /* the floor quad */
    } else if (!strcmp(gen, "gears")) {
        c.polys = 146 * N * N * N + 1;
    } else if (!strcmp(gen, "mount")) {
        c.tris = 2ull << (2 * n); /* 2*4^SF */
        c.spheres = 4;
    } else if (!strcmp(gen, "rings")) {
        c.spheres = c.cones = 5 * N * (N + 1) * (2 * N + 1);
        c.polys = 1;
    } else if (!strcmp(gen, "teapot")) {
        c.tris = 64 * N * N - 8 * N;
        c.polys = N * N;
    } else if (!strcmp(gen, "tetra")) {
        c.tris = 1ull << (2 * n);
    } else if (!strcmp(gen, "tree")) {
        c.spheres = c.cones = (2ull << n) - 1;
        c.polys = 1;
    } else if (!strcmp(gen, "lattice")) {
        c.spheres = (N + 1) * (N + 1) * (N + 1);
        c.cones = 3 * N * (N + 1) * (N + 1);
    } else if (!strcmp(gen, "shells")) {
        c.spheres = (180ull << n) + 1;
    } else if (!strcmp(gen, "jacks")) {
        uint64_t j = 0, p = 1;
        for (int k = 0; k < n; k++, p *= 8) j += p;
        c.spheres = 6 * j;
        c.cones = 3 * j;
    } else if (!strcmp(gen, "sombrero")) {
        uint64_t w = 32ull << (n - 1);
        c.tris = 2 * (w - 1) * (w - 1);
    }
    return c;
}

static void check_counts(const char *gen, int size)
{
    char name[64];
    snprintf(name, sizeof name, "spd:%s:%d", gen, size);
    scene_t *s = load(name);
    if (!s) return;
    counts f = formula(gen, size);
    const prims_t *p = &s->prims;
    CHECK_MSG(p->nspheres == f.spheres && p->ncones == f.cones && p->ntris == f.tris && p->npolygons == f.polys,
              "%s: %u spheres %u cones %u triangles %u polygons, want %llu %llu %llu %llu", name, p->nspheres, p->ncones,
              p->ntris, p->npolygons, (unsigned long long)f.spheres, (unsigned long long)f.cones,
              (unsigned long long)f.tris, (unsigned long long)f.polys);
    CHECK(p->count == f.spheres + f.cones + f.tris + f.polys);
    /* The generator's own census agrees with what it made. */
    const spd_generator *g = spd_generator_find(gen);
    spd_census cs;
    g->census(size, &cs);
    CHECK_MSG(spd_census_prims(&cs, 0) == p->count, "%s: census %llu vs %u", name,
              (unsigned long long)spd_census_prims(&cs, 0), p->count);
    uint64_t pv = 0;
    for (uint32_t id = 0; id < p->count; id++) pv += nverts_of(p, id);
    CHECK_MSG(cs.polygon_verts == pv, "%s: census polygon vertices %llu vs %llu", name,
              (unsigned long long)cs.polygon_verts, (unsigned long long)pv);
    CHECK(strcmp(s->name, name) == 0 && s->source[0]);
    /* Every primitive has one of the scene's materials. */
    bool mats_ok = s->prim_material != NULL;
    for (uint32_t id = 0; mats_ok && id < p->count; id++) mats_ok = s->prim_material[id] < s->nmaterials;
    CHECK_MSG(mats_ok, "%s: material ids", name);
    scene_free(s);
}

static void test_counts(void)
{
    for (int i = 0; i < spd_ngenerators; i++)
        for (int size = 1; size <= 4; size++) check_counts(spd_generators[i].name, size);

    /* The defaults, named without a size, against the Readme's table. */
    static const struct { const char *name; uint32_t count; } defaults[] = {
        {"spd:balls", 7382},   {"spd:gears", 9345},  {"spd:mount", 8196},   {"spd:rings", 8401},
        {"spd:teapot", 9264},  {"spd:tetra", 4096},  {"spd:tree", 8191},    {"spd:lattice", 8281},
        {"spd:shells", 5761},  {"spd:jacks", 9},     {"spd:sombrero", 1922},
    };
    for (size_t i = 0; i < sizeof defaults / sizeof defaults[0]; i++) {
        scene_t *s = load(defaults[i].name);
        if (s) CHECK_MSG(s->prims.count == defaults[i].count, "%s: %u, want %u", defaults[i].name, s->prims.count,
                         defaults[i].count);
        scene_free(s);
    }
    /* The defaults by size, through the formulas (gears 4 etc. are above). */
    check_counts("mount", 6);
    check_counts("rings", 7);
    check_counts("teapot", 12);
    check_counts("tetra", 6);
    check_counts("tree", 11);
    check_counts("lattice", 12);
    check_counts("shells", 5);
    /* Jacks at 2..5 from the page: 81, 657, 5,265, 42,129; sombrero 1..4:
     * 1,922, 7,938, 32,258, 130,050. */
    static const uint32_t jacks[] = {0, 9, 81, 657, 5265, 42129}, sombrero[] = {0, 1922, 7938, 32258, 130050};
    for (int n = 1; n <= 5; n++) {
        char name[32];
        snprintf(name, sizeof name, "spd:jacks:%d", n);
        scene_t *s = load(name);
        if (s) CHECK_MSG(s->prims.count == jacks[n], "%s: %u", name, s->prims.count);
        scene_free(s);
        if (n > 4) continue;
        snprintf(name, sizeof name, "spd:sombrero:%d", n);
        s = load(name);
        if (s) CHECK_MSG(s->prims.count == sombrero[n], "%s: %u", name, s->prims.count);
        scene_free(s);
    }
    /* Teapot at n 1..8 from the page: 57, 244, 561, 1,008, 1,585, 2,292, 3,129, 4,096. */
    static const uint32_t teapot[] = {0, 57, 244, 561, 1008, 1585, 2292, 3129, 4096};
    for (int n = 1; n <= 8; n++) {
        char name[32];
        snprintf(name, sizeof name, "spd:teapot:%d", n);
        scene_t *s = load(name);
        if (s) CHECK_MSG(s->prims.count == teapot[n], "%s: %u", name, s->prims.count);
        scene_free(s);
    }
}

/* Tessellated: only triangles, counts from the page's "Counts at res 3"
 * (polygons of n vertices become n - 2 ear-clipping triangles). */
static void test_tessellated(void)
{
    static const struct { const char *name; uint32_t tris; } t[] = {
        {"spd:balls:2:t3", 9828 + 2},      /* 91 spheres x 108 + the floor quad's 2 */
        {"spd:balls:3:t", 88560 + 2},      /* :t is RES 3 */
        {"spd:balls:4:t", 797148 + 2},
        {"spd:mount:6:t3", 8192 + 432},    /* 4 spheres x 108 */
        {"spd:rings:7:t", 554400 + 2},     /* 4200 x (108 + 24) + wall */
        {"spd:tree:11:t", 540540 + 2},     /* 4095 x (108 + 24) + field */
        {"spd:lattice:12:t", 383292},      /* 2197 x 108 + 6084 x 24 */
        {"spd:shells:5:t", 622188},        /* 5761 x 108 */
        {"spd:jacks:4:t", 196560},         /* RES forced to 2: 585 x (6 x 48 + 3 x 16) */
        {"spd:jacks:4:t5", 196560},
        {"spd:gears:1:t", 2 * 142 + 144 * 2 + 2}, /* two 144-gons, 144 quads, ground */
        {"spd:teapot:12:t", 9120 + 144 * 2},
        {"spd:tetra:t", 4096},             /* default size 6 */
        {"spd:sombrero:1:t7", 1922},
        {"spd:balls:1:t1", 10 * 12 + 2},   /* a cube per sphere */
        {"spd:tree:2:t4", 7 * (192 + 32) + 2},
    };
    for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
        scene_t *s = load(t[i].name);
        if (!s) continue;
        const prims_t *p = &s->prims;
        CHECK_MSG(p->ntris == t[i].tris && p->count == t[i].tris, "%s: %u triangles of %u prims, want %u", t[i].name,
                  p->ntris, p->count, t[i].tris);
        CHECK(p->nspheres == 0 && p->ncones == 0 && p->npolygons == 0);
        scene_free(s);
    }
    /* Cube spheres and cone bands lie on their surfaces: the root of the
     * tree at RES 2 is a cone from (0,0,0) r 0.15 to (0,0,1) r 0.1005 (16
     * triangles after the field's 2); each vertex sits at its end's radius. */
    scene_t *s = load("spd:tree:1:t2");
    if (s) {
        const prims_t *p = &s->prims;
        int ok = 0;
        for (uint32_t id = 2; id < 2 + 16; id++)
            for (int k = 0; k < 3; k++) {
                vec3 v = vert(p, id, k);
                double r = sqrt((double)v.x * v.x + (double)v.y * v.y);
                ok += (fabs(v.z) < 1e-6 && fabs(r - 0.15) < 1e-6) || (fabs(v.z - 1) < 1e-6 && fabs(r - 0.1005) < 1e-6);
            }
        CHECK_MSG(ok == 16 * 3, "%d of 48 cone vertices on the rims", ok);
        /* Wound outward: the normal of each band triangle points away from the axis. */
        int out = 0;
        for (uint32_t id = 2; id < 2 + 16; id++) {
            vec3 a = vert(p, id, 0), b = vert(p, id, 1), c = vert(p, id, 2);
            vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
            vec3 m = v3_scale(v3_add(v3_add(a, b), c), 1.0f / 3.0f);
            out += n.x * m.x + n.y * m.y > 0;
        }
        CHECK(out == 16);
        CHECK(p->ndegenerate == 0);
    }
    scene_free(s);
}

/* ---- hand-derived coordinates ---- */

static void test_balls(void)
{
    scene_t *s = load("spd:balls:1");
    if (!s) return;
    const prims_t *p = &s->prims;
    /* The floor is one quad, first: (12,12), (-12,12), (-12,-12), (12,-12) at z = -0.5. */
    CHECK(p->kind[0] == PRIM_POLYGON && nverts_of(p, 0) == 4);
    CHECK_V3(vert(p, 0, 0), 12, 12, -0.5);
    CHECK_V3(vert(p, 0, 1), -12, 12, -0.5);
    CHECK_V3(vert(p, 0, 2), -12, -12, -0.5);
    CHECK_V3(vert(p, 0, 3), 12, -12, -0.5);
    /* Root: (0,0,0), r 0.5. First child: (1,1,0)/sqrt2 is perpendicular to
     * the tilt axis a = (1,-1,0)/sqrt2 and a x (1,1,0)/sqrt2 = (0,0,1), so
     * turning it by asin(2/sqrt6) (cos = 1/sqrt3) gives
     * u0 = (1,1,0)/sqrt2 /sqrt3 + (0,0,1) 2/sqrt6 = (1,1,2)/sqrt6; the root
     * points at +Z (M = I), so the child is at u0 (0.5 + 1/6), radius 1/6. */
    CHECK(p->kind[1] == PRIM_SPHERE && p->kind[2] == PRIM_SPHERE);
    sphere_t r = p->spheres[p->index[1]], c0 = p->spheres[p->index[2]];
    CHECK_V3(r.center, 0, 0, 0);
    CHECK_NEAR(r.radius, 0.5, 1e-7);
    double k = 2.0 / 3.0 / sqrt(6.0);
    CHECK_V3(c0.center, k, k, 2 * k);
    CHECK_NEAR(c0.radius, 1.0 / 6.0, 1e-7);
    /* Child 3 is the first of the copy turned 120 degrees about +Z:
     * Rz(120) u0 = ((cos120 - sin120), (sin120 + cos120), 2)/sqrt6. */
    sphere_t c3 = p->spheres[p->index[5]];
    double c120 = -0.5, s120 = sqrt(3.0) / 2;
    CHECK_V3(c3.center, k * (c120 - s120), k * (s120 + c120), 2 * k);
    /* Materials: floor f 1 0.75 0.33 0.8 0; spheres f 1 0.9 0.7 0.5 0.5. */
    const material_t *fm = &s->materials[s->prim_material[0]], *sm = &s->materials[s->prim_material[1]];
    CHECK(near3(fm->color, 1, 0.75, 0.33, 1e-6) && fm->kd == 0.8f && fm->ks == 0.0f);
    CHECK(near3(sm->color, 1, 0.9, 0.7, 1e-6) && sm->kd == 0.5f && sm->ks == 0.5f);
    CHECK(s->prim_material[10] == s->prim_material[1] && s->nmaterials == 2);
    scene_free(s);
}

static void test_tetra(void)
{
    /* Size 1: one tetrahedron of half-size 1 at 0: P0 (-1,-1,1), P1 (-1,1,-1),
     * P2 (1,-1,-1), P3 (1,1,1); faces (0,1,2), (3,2,1), (2,3,0), (1,0,3). */
    scene_t *s = load("spd:tetra:1");
    if (s) {
        const prims_t *p = &s->prims;
        CHECK(p->count == 4 && p->kind[0] == PRIM_TRIANGLE);
        CHECK_V3(vert(p, 0, 0), -1, -1, 1);
        CHECK_V3(vert(p, 0, 1), -1, 1, -1);
        CHECK_V3(vert(p, 0, 2), 1, -1, -1);
        CHECK_V3(vert(p, 1, 0), 1, 1, 1);
        CHECK_V3(vert(p, 1, 1), 1, -1, -1);
        CHECK_V3(vert(p, 1, 2), -1, 1, -1);
        CHECK_V3(vert(p, 2, 0), 1, -1, -1);
        CHECK_V3(vert(p, 2, 2), -1, -1, 1);
        CHECK_V3(vert(p, 3, 0), -1, 1, -1);
        CHECK_V3(vert(p, 3, 2), 1, 1, 1);
    }
    scene_free(s);
    /* Size 2: the first child is at (-,-,+)/2 with half-size 1/2, so its
     * face 0 is (-1,-1,1), (-1,0,0), (0,-1,0); the last child (+,+,+)/2
     * (ids 12..15) has P0 = (0,0,1), P1 = (0,1,0), P2 = (1,0,0), P3 = (1,1,1). */
    s = load("spd:tetra:2");
    if (s) {
        const prims_t *p = &s->prims;
        CHECK_V3(vert(p, 0, 0), -1, -1, 1);
        CHECK_V3(vert(p, 0, 1), -1, 0, 0);
        CHECK_V3(vert(p, 0, 2), 0, -1, 0);
        CHECK_V3(vert(p, 12, 0), 0, 0, 1);
        CHECK_V3(vert(p, 12, 1), 0, 1, 0);
        CHECK_V3(vert(p, 12, 2), 1, 0, 0);
        CHECK_V3(vert(p, 13, 0), 1, 1, 1);
        const material_t *m = &s->materials[s->prim_material[0]];
        CHECK(near3(m->color, 1, 0.2, 0.2, 1e-6) && m->kd == 1.0f && m->ks == 0.0f);
    }
    scene_free(s);
}

static void test_gears(void)
{
    /* Size 1: R = 1/(1 - 0) = 1, one gear at (-1 + R, -1 + R, 1 - 0) =
     * (0,0,1), thickness min(0.1, 1/2) = 0.1, ro 0.995, ri 0.9, a0 = 0,
     * ta = 10 degrees. Tooth 0: (ro, -1.9), (ro, 1.9), (ri, 3), (ri, 7)
     * degrees at z = 1. */
    scene_t *s = load("spd:gears:1");
    if (!s) return;
    const prims_t *p = &s->prims;
    const double d = M_PI / 180.0, ro = 0.995, ri = 0.9;
    /* Ground first: (2,2,0), (-2,2,0), (-2,-2,0), (2,-2,0). */
    CHECK(p->kind[0] == PRIM_POLYGON && nverts_of(p, 0) == 4);
    CHECK_V3(vert(p, 0, 0), 2, 2, 0);
    CHECK_V3(vert(p, 0, 2), -2, -2, 0);
    /* Top face: 144 vertices. */
    CHECK(p->kind[1] == PRIM_POLYGON && nverts_of(p, 1) == 144);
    CHECK_V3(vert(p, 1, 0), ro * cos(-1.9 * d), ro * sin(-1.9 * d), 1);
    CHECK_V3(vert(p, 1, 1), ro * cos(1.9 * d), ro * sin(1.9 * d), 1);
    CHECK_V3(vert(p, 1, 2), ri * cos(3 * d), ri * sin(3 * d), 1);
    CHECK_V3(vert(p, 1, 3), ri * cos(7 * d), ri * sin(7 * d), 1);
    /* Tooth 1 starts at 10 - 1.9 degrees. */
    CHECK_V3(vert(p, 1, 4), ro * cos(8.1 * d), ro * sin(8.1 * d), 1);
    /* Side 0 (id 2): [p0, p0 - (0,0,0.1), p1 - (0,0,0.1), p1]. */
    CHECK(nverts_of(p, 2) == 4);
    CHECK_V3(vert(p, 2, 0), ro * cos(-1.9 * d), ro * sin(-1.9 * d), 1);
    CHECK_V3(vert(p, 2, 1), ro * cos(-1.9 * d), ro * sin(-1.9 * d), 0.9);
    CHECK_V3(vert(p, 2, 2), ro * cos(1.9 * d), ro * sin(1.9 * d), 0.9);
    CHECK_V3(vert(p, 2, 3), ro * cos(1.9 * d), ro * sin(1.9 * d), 1);
    /* The last side (id 145) closes p143 -> p0. */
    CHECK_V3(vert(p, 145, 3), ro * cos(-1.9 * d), ro * sin(-1.9 * d), 1);
    /* Bottom (id 146) at z 0.9, ta negated: tooth 0 at (ro, +1.9),
     * (ro, -1.9), (ri, -3), (ri, -7); tooth 1 at ga = -10 degrees. */
    CHECK(nverts_of(p, 146) == 144);
    CHECK_V3(vert(p, 146, 0), ro * cos(1.9 * d), ro * sin(1.9 * d), 0.9);
    CHECK_V3(vert(p, 146, 3), ri * cos(-7 * d), ri * sin(-7 * d), 0.9);
    CHECK_V3(vert(p, 146, 4), ro * cos(-8.1 * d), ro * sin(-8.1 * d), 0.9);
    /* Top and bottom normals face +Z and -Z. */
    CHECK(p->polygons[p->index[1]].normal.z > 0.99f && p->polygons[p->index[146]].normal.z < -0.99f);
    /* Gear (0,0,0): (4*0 + 2*0 + 0) mod 5 = 0, so glass: kd 0.2, ks 0. Its
     * colour (0.01 + frac(5/7), 0.01 + frac(3/7), 0.01 + frac(2/7)) over its max. */
    const material_t *m = &s->materials[s->prim_material[1]];
    double r = 0.01 + 5.0 / 7, g = 0.01 + 3.0 / 7, b = 0.01 + 2.0 / 7;
    CHECK(m->kd == 0.2f && m->ks == 0.0f && near3(m->color, 1, g / r, b / r, 1e-6));
    const material_t *gm = &s->materials[s->prim_material[0]];
    CHECK(near3(gm->color, 1, 0.85, 0.7, 1e-6) && gm->kd == 0.3f && gm->ks == 0.6f);
    scene_free(s);

    /* Size 2: R = 1/(2 - 0.05), gear (ix=1, iy=0, iz=0) (id 1 + 146 + 1) at
     * x = -1 + R + 1.9R, y = -1 + R, z = 1, offset a0 = pi/36 (odd sum), so
     * its first top vertex is at angle 5 - 1.9 = 3.1 degrees. */
    s = load("spd:gears:2");
    if (s) {
        const prims_t *p2 = &s->prims;
        double R = 1.0 / 1.95, cx = -1 + R + 1.9 * R, cy = -1 + R;
        CHECK_V3(vert(p2, 147, 0), cx + 0.995 * R * cos(3.1 * d), cy + 0.995 * R * sin(3.1 * d), 1);
    }
    scene_free(s);
}

/* The page's gaussian deviate, for the mountain check. */
static double page_gauss(long seed)
{
    long ix1, ix2 = seed;
    double v1, v2, r;
    for (;;) {
        ix1 = (28411 + 8121 * ix2) % 134456;
        ix2 = (28411 + 8121 * ix1) % 134456;
        v1 = 2.0 * ix1 / 134456 - 1;
        v2 = 2.0 * ix2 / 134456 - 1;
        r = v1 * v1 + v2 * v2;
        if (r < 1) return v1 * sqrt(-2 * log(r) / r);
    }
}

static void test_mount(void)
{
    scene_t *s = load("spd:mount:1");
    if (!s) return;
    const prims_t *p = &s->prims;
    /* Spheres first, radius 0.17 about c = (-0.8, 0.8, 1): the top at
     * c + (0,0,h), h = 0.17 sqrt(1.5). q0 = (0,0,h) is perpendicular to
     * a = (1,1,0)/sqrt2 and a x q0 = (h,-h,0)/sqrt2; with cos = -1/3 and
     * sin = sqrt(8)/3, q1 = (0,0,-h/3) + (h,-h,0) 2/3 = (2h/3, -2h/3, -h/3):
     * sphere 1 at c + q1, sphere 2 at c + Rz(120) q1. */
    double h = 0.17 * sqrt(1.5);
    for (int i = 0; i < 4; i++) CHECK(p->kind[i] == PRIM_SPHERE && fabsf(p->spheres[p->index[i]].radius - 0.17f) < 1e-7f);
    CHECK_V3(p->spheres[p->index[0]].center, -0.8, 0.8, 1 + h);
    CHECK_V3(p->spheres[p->index[1]].center, -0.8 + 2 * h / 3, 0.8 - 2 * h / 3, 1 - h / 3);
    double c = -0.5, sn = sqrt(3.0) / 2, qx = 2 * h / 3, qy = -2 * h / 3;
    CHECK_V3(p->spheres[p->index[2]].center, -0.8 + c * qx - sn * qy, 0.8 + sn * qx + c * qy, 1 - h / 3);
    /* All four touch: centres 0.34 apart. */
    vec3 d01 = v3_sub(p->spheres[p->index[0]].center, p->spheres[p->index[1]].center);
    CHECK_NEAR(v3_len(d01), 0.34, 1e-6);
    /* Mountain, size 1: n = 2, one split (w 2, hw 1), rise = (1*2/2)*roughness.
     * lower = rise * G(1, 0), G = gauss(21 + hash), hash(1,0) =
     * ((1 << 22) + (0 << 14) + (1 << 6)) & 0xFFFF = 64. The first cell
     * (0,0) has corners ll 0, lr lower, ur middle, ul left; its first
     * triangle is (ll, lr, ur) = ((-1,-1,0), (0,-1,lower), (0,0,middle)).
     * middle = 1.4142136 rise G(1,1), hash(1,1) = 64 + (1 << 14) = 16448. */
    double ratio = 2.0 / pow(2.0, 1.0 / 1.2), rough = sqrt(ratio * ratio - 1);
    CHECK_NEAR(rough, 0.5098, 1e-4);
    CHECK(p->kind[4] == PRIM_TRIANGLE);
    CHECK_V3(vert(p, 4, 0), -1, -1, 0);
    CHECK_V3(vert(p, 4, 1), 0, -1, rough * page_gauss(21 + 64));
    CHECK_V3(vert(p, 4, 2), 0, 0, 1.4142136 * rough * page_gauss(21 + 16448));
    /* Second triangle (ur, ul, ll); ul = left = rise G(0, 1), hash = 1 << 14. */
    CHECK_V3(vert(p, 5, 1), -1, 0, rough * page_gauss(21 + 16384));
    CHECK_V3(vert(p, 5, 2), -1, -1, 0);
    const material_t *g = &s->materials[s->prim_material[0]], *m = &s->materials[s->prim_material[4]];
    CHECK(near3(g->color, 1, 1, 1, 0) && g->kd == 0.1f && g->ks == 0.1f);
    CHECK(near3(m->color, 0.5, 0.45, 0.35, 1e-6) && m->kd == 1.0f && m->ks == 0.0f);
    scene_free(s);
}

static void test_rings(void)
{
    scene_t *s = load("spd:rings:1");
    if (!s) return;
    const prims_t *p = &s->prims;
    const double rho = 0.07412, sp = 1 / sin(M_PI / 8), sc = 1 / (1 + rho);
    /* Wall first at y = 2s, h = 1.01 (2s + s) tan(pi/8) = 3.03 (since
     * s tan(pi/8) = 1/cos(pi/8)... kept numeric): corners (h-1, y, h+.5), ... */
    double hw = 1.01 * (2 * sp + sp) * tan(M_PI / 8);
    CHECK(p->kind[0] == PRIM_POLYGON);
    CHECK_V3(vert(p, 0, 0), hw - 1, 2 * sp, hw + 0.5);
    CHECK_V3(vert(p, 0, 2), -hw - 1, 2 * sp, -hw + 0.5);
    /* The first cylinder (id 1): element 0 at V[0] + off, off = (0, s, 0),
     * V[0] = (sc, 0, 0), to V[4] = sc (cos 288, sin 288, 0); radius rho both. */
    CHECK(p->kind[1] == PRIM_CONE && p->kind[2] == PRIM_SPHERE);
    cone_t c0 = p->cones[p->index[1]];
    CHECK_V3(c0.base, sc, sp, 0);
    CHECK_V3(c0.apex, sc * cos(8 * M_PI / 5), sp + sc * sin(8 * M_PI / 5), 0);
    CHECK_NEAR(c0.base_radius, rho, 1e-7);
    CHECK_NEAR(c0.apex_radius, rho, 1e-7);
    /* Then the sphere at V[0] + off; element 1's cylinder runs V[1] -> V[0]. */
    CHECK_V3(p->spheres[p->index[2]].center, sc, sp, 0);
    cone_t c1 = p->cones[p->index[3]];
    CHECK_V3(c1.base, sc * cos(2 * M_PI / 5), sp + sc * sin(2 * M_PI / 5), 0);
    CHECK_V3(c1.apex, sc, sp, 0);
    /* Every vertex of the object is on the sphere of radius sc about the offset. */
    bool on = true;
    for (uint32_t id = 1; id < p->count; id++)
        if (p->kind[id] == PRIM_SPHERE) on &= fabs(v3_len(v3_sub(p->spheres[p->index[id]].center, v3(0, (float)sp, 0))) - sc) < 1e-5;
    CHECK(on);
    /* Ring colours: red for elements 0..4, green from element 5 (id 1 + 10). */
    CHECK(near3(s->materials[s->prim_material[1]].color, 1, 0, 0, 0));
    CHECK(near3(s->materials[s->prim_material[11]].color, 0, 1, 0, 0));
    CHECK(s->materials[s->prim_material[11]].kd == 0.5f && s->materials[s->prim_material[11]].ks == 0.2f);
    scene_free(s);
}

static void test_tree(void)
{
    scene_t *s = load("spd:tree:1");
    if (!s) return;
    const prims_t *p = &s->prims;
    /* Field first: (50,50,0), (-50,50,0), (-50,-50,0), (50,-50,0). */
    CHECK_V3(vert(p, 0, 0), 50, 50, 0);
    CHECK_V3(vert(p, 0, 3), 50, -50, 0);
    /* Root: cone (0,0,0) r 0.15 to (0,0,1) r 0.15*0.67, sphere at the apex. */
    cone_t c = p->cones[p->index[1]];
    CHECK_V3(c.base, 0, 0, 0);
    CHECK_V3(c.apex, 0, 0, 1);
    CHECK_NEAR(c.base_radius, 0.15, 1e-7);
    CHECK_NEAR(c.apex_radius, 0.1005, 1e-7);
    CHECK_V3(p->spheres[p->index[2]].center, 0, 0, 1);
    CHECK_NEAR(p->spheres[p->index[2]].radius, 0.1005, 1e-7);
    /* Child 0 (id 3): L0(p) = 0.65 Rz(90) Rx(40) p + (0,0,1). Base L0(0) =
     * (0,0,1); Rx(40)(0,0,1) = (0, -sin40, cos40), Rz(90)(x,y,z) = (-y,x,z),
     * so the apex is (0.65 sin40, 0, 1 + 0.65 cos40); radii 0.1005 and
     * 0.1005 * 0.67. */
    const double d = M_PI / 180;
    cone_t c1 = p->cones[p->index[3]];
    CHECK_V3(c1.base, 0, 0, 1);
    CHECK_V3(c1.apex, 0.65 * sin(40 * d), 0, 1 + 0.65 * cos(40 * d));
    CHECK_NEAR(c1.base_radius, 0.1005, 1e-7);
    CHECK_NEAR(c1.apex_radius, 0.1005 * 0.67, 1e-7);
    /* Child 1 (id 5): Rx(25)(0,0,1) = (0, -sin25, cos25), Rz(230) turns
     * (0, -sin25) to (sin25 sin230, -sin25 cos230): apex
     * 0.70 (sin25 sin230, -sin25 cos230, cos25) + (0,0,1). */
    cone_t c2 = p->cones[p->index[5]];
    CHECK_V3(c2.apex, 0.7 * sin(25 * d) * sin(230 * d), -0.7 * sin(25 * d) * cos(230 * d), 1 + 0.7 * cos(25 * d));
    const material_t *m = &s->materials[s->prim_material[1]];
    CHECK(near3(m->color, 0.55, 0.4, 0.2, 1e-6));
    scene_free(s);
}

static void test_teapot(void)
{
    const int n = 12;
    scene_t *s = load("spd:teapot");
    if (!s) return;
    const prims_t *p = &s->prims;
    /* First square: the first (s+t) odd one, (s,t) = (0,1): x in [-4, -4 + 8/n],
     * y in [-4 + 8/n, -4 + 16/n], corners (lo,lo), (hi,lo), (hi,hi), (lo,hi). */
    CHECK(p->kind[0] == PRIM_POLYGON);
    CHECK_V3(vert(p, 0, 0), -4, -4 + 8.0 / n, 0);
    CHECK_V3(vert(p, 0, 1), -4 + 8.0 / n, -4 + 8.0 / n, 0);
    CHECK_V3(vert(p, 0, 2), -4 + 8.0 / n, -4 + 16.0 / n, 0);
    /* The 72 odd (white) squares, then the 72 even (grey): (0,0) is id 72. */
    CHECK_V3(vert(p, 72, 0), -4, -4, 0);
    CHECK(near3(s->materials[s->prim_material[0]].color, 1, 1, 1, 0));
    CHECK(near3(s->materials[s->prim_material[72]].color, 0.5, 0.5, 0.5, 0));
    /* The first patch's first triangle (id 144): (s0,t0) is control point
     * G[0][0] = vertex 1 of the data, (1.4, 0, 2.4). */
    CHECK(p->kind[144] == PRIM_TRIANGLE);
    CHECK_V3(vert(p, 144, 0), 1.4, 0, 2.4);
    const material_t *m = &s->materials[s->prim_material[144]];
    CHECK(near3(m->color, 1, 0.5, 0.1, 1e-6) && m->kd == 0.75f && m->ks == 0.25f);
    /* No kept triangle has 2 vertices on the axis. */
    int bad = 0;
    for (uint32_t id = 144; id < p->count; id++) {
        int on = 0;
        for (int k = 0; k < 3; k++) {
            vec3 v = vert(p, id, k);
            on += fabsf(v.x) < 1e-4f && fabsf(v.y) < 1e-4f;
        }
        bad += on >= 2;
    }
    CHECK(bad == 0);
    scene_free(s);
}

static void test_lattice(void)
{
    scene_t *s = load("spd:lattice");
    if (!s) return;
    const prims_t *p = &s->prims;
    const double n = 12, r1 = 0.25 / n, r2 = (1.0 / 16) / n, delta = 0.99 * r1 * (1 - 0.5);
    /* Point (0,0,0): the sphere, radius 0.25/12, then the x cylinder from
     * (delta,0,0) to (1/12 - delta, 0, 0), radius 1/(16*12), then y, z. */
    CHECK(p->kind[0] == PRIM_SPHERE);
    CHECK_V3(p->spheres[p->index[0]].center, 0, 0, 0);
    CHECK_NEAR(p->spheres[p->index[0]].radius, r1, 1e-8);
    cone_t cx = p->cones[p->index[1]], cz = p->cones[p->index[3]];
    CHECK_V3(cx.base, delta, 0, 0);
    CHECK_V3(cx.apex, 1 / n - delta, 0, 0);
    CHECK_NEAR(cx.base_radius, r2, 1e-8);
    CHECK_V3(cz.apex, 0, 0, 1 / n - delta);
    /* Point (0,0,1) (z inner) next: its sphere is id 4. */
    CHECK_V3(p->spheres[p->index[4]].center, 0, 0, 1 / n);
    /* Materials: sphere grey kd 0.5 ks 0.5; x cylinder red kd 0.99. */
    CHECK(near3(s->materials[s->prim_material[0]].color, 0.9, 0.9, 0.9, 1e-6));
    CHECK(near3(s->materials[s->prim_material[1]].color, 0.9, 0.1, 0.1, 1e-6) && s->materials[s->prim_material[1]].kd == 0.99f);
    CHECK(near3(s->materials[s->prim_material[3]].color, 0.1, 0.1, 0.9, 1e-6));
    scene_free(s);
}

static void test_shells_jacks_sombrero(void)
{
    /* Shells 5: steps 5760; the first i = -3840 gives theta = -12 pi,
     * r = e^(-1.8 pi), sphere (r sin, r cos, -2r) = (0, r, -2r); the last,
     * i = 1920, theta = 6 pi, r = e^(0.9 pi), also (0, r, -2r). */
    scene_t *s = load("spd:shells");
    if (s) {
        const prims_t *p = &s->prims;
        double r0 = exp(-1.8 * M_PI), r1 = exp(0.9 * M_PI);
        CHECK_V3(p->spheres[p->index[0]].center, 0, r0, -2 * r0);
        CHECK_NEAR(p->spheres[p->index[0]].radius, r0, 1e-9);
        sphere_t last = p->spheres[p->index[p->count - 1]];
        CHECK(near3(last.center, 0, r1, -2 * r1, 1e-4 * r1)); /* r1 ~ 16.9: float rounding */
    }
    scene_free(s);

    /* Jacks 1: the first cylinder is Rx(-30) Ry(-20) of (-0.75,0,0) ->
     * (0.75,0,0). Ry(-20)(x,0,0) = (x cos20, 0, x sin20) for x = -0.75;
     * Rx(-30)(x,y,z) = (x, y cos30 + z sin30, -y sin30 + z cos30), so
     * base = (-0.75 cos20, -0.375 sin20, -0.75 sin20 cos30), apex = -base,
     * radius 0.1 * 0.75. The spheres follow at +x, +y, +z, -x, -y, -z. */
    s = load("spd:jacks");
    if (s) {
        const prims_t *p = &s->prims;
        const double d = M_PI / 180;
        cone_t c = p->cones[p->index[0]];
        double bx = -0.75 * cos(20 * d), by = -0.375 * sin(20 * d), bz = -0.75 * sin(20 * d) * cos(30 * d);
        CHECK_V3(c.base, bx, by, bz);
        CHECK_V3(c.apex, -bx, -by, -bz);
        CHECK_NEAR(c.base_radius, 0.075, 1e-7);
        CHECK(p->kind[3] == PRIM_SPHERE);
        CHECK_V3(p->spheres[p->index[3]].center, -bx, -by, -bz); /* +x */
        CHECK_V3(p->spheres[p->index[6]].center, bx, by, bz);    /* -x */
        CHECK_NEAR(p->spheres[p->index[3]].radius, 0.15, 1e-7);
        CHECK(near3(s->background, 0.2, 0.05, 0.2, 1e-6));
    }
    scene_free(s);
    /* Jacks 2: the first child (i,j,k) = (-.5,-.5,-.5), frame R o T o S(0.5):
     * its first cylinder is R((-.5,-.5,-.5) + 0.5 (-0.75,0,0)), radius 0.0375. */
    s = load("spd:jacks:2");
    if (s) {
        const prims_t *p = &s->prims;
        cone_t c = p->cones[p->index[9]];
        spd_mat rx = spd_mat_rotation(spd_v(1, 0, 0), -30 * M_PI / 180), ry = spd_mat_rotation(spd_v(0, 1, 0), -20 * M_PI / 180);
        spd_vec q = spd_v(-0.5 - 0.375, -0.5, -0.5);
        spd_vec t = spd_mat_apply(&ry, q);
        q = spd_mat_apply(&rx, t);
        CHECK_V3(c.base, q.x, q.y, q.z);
        CHECK_NEAR(c.base_radius, 0.0375, 1e-7);
    }
    scene_free(s);

    /* Sombrero 1: w = 32; vertex (0,0) = (-4, -3 + h(-4,-4), -4) with
     * h = cos(2 pi rho) e^-rho, rho = 4 sqrt2; the first triangle is
     * (0,0), (1,1), (0,1), and (1,1) is at x = z = -4 + 8/31 but sampled
     * at x = y = -4 + 8/32. */
    s = load("spd:sombrero");
    if (s) {
        const prims_t *p = &s->prims;
        double rho = 4 * sqrt(2.0), h = cos(2 * M_PI * rho) * exp(-rho);
        CHECK_V3(vert(p, 0, 0), -4, -3 + h, -4);
        double x = -4 + 8.0 / 32, rho1 = sqrt(2 * x * x), h1 = cos(2 * M_PI * rho1) * exp(-rho1);
        CHECK_V3(vert(p, 0, 1), -4 + 8.0 / 31, -3 + h1, -4 + 8.0 / 31);
        double rho2 = sqrt(16 + x * x), h2 = cos(2 * M_PI * rho2) * exp(-rho2);
        CHECK_V3(vert(p, 0, 2), -4 + 8.0 / 31, -3 + h2, -4);
    }
    scene_free(s);
}

/* ---- views and lights ---- */

static void test_views(void)
{
    static const struct {
        const char *name;
        double from[3], at[3], up[3], angle, hither;
        int res;
        uint32_t nlights;
        double light0[3], bg[3];
    } v[] = {
        {"spd:balls:1", {2.1, 1.3, 1.7}, {0, 0, 0}, {0, 0, 1}, 45, 0.01, 512, 3, {4, 3, 2}, {0.078, 0.361, 0.753}},
        {"spd:gears:1", {-1.1, -2.1, 2.6}, {0, 0, 0}, {0, 0, 1}, 45, 1, 512, 5, {2, 4, 4}, {0.078, 0.361, 0.753}},
        {"spd:mount:1", {-1.6, 1.6, 1.7}, {0, 0, 0}, {0, 0, 1}, 45, 0.01, 512, 1, {-100, -100, 100}, {0.078, 0.361, 0.753}},
        {"spd:rings:1", {-1, -2.6131259, 0.5}, {-1, -1.6131259, 0.5}, {0, 0, 1}, 45, 1, 512, 3, {3, -2.6131259, 3},
         {0.078, 0.361, 0.753}},
        {"spd:teapot:1", {4.86, 7.2, 5.4}, {0, 0, 0}, {0, 0, 1}, 45, 1, 512, 2, {-3.1, 9.8, 12.1}, {0.078, 0.361, 0.753}},
        {"spd:tetra:1", {1.022846, -3.177154, -2.174512}, {-0.004103, -0.004103, 0.216539}, {-0.816497, -0.816497, 0.816497},
         45, 1, 512, 1, {2, -18, -5}, {0.078, 0.361, 0.753}},
        {"spd:tree:1", {4.5, 0.4, 2.0}, {0, 0, 1.5}, {0, 0, 1}, 45, 1, 512, 7, {-5, 5, 50}, {0.078, 0.361, 0.753}},
        /* lattice 12: ((12>>1) + 0.5)/12 = 6.5/12; 1 - 1/24 */
        {"spd:lattice:12", {6.5 / 12, 1, 1 - 1.0 / 24}, {6.5 / 12, -1, -1 - 1.0 / 24}, {0.2, 1, 0}, 60, 0, 512, 6, {2, .5, .5},
         {0.078, 0.361, 0.753}},
        {"spd:shells:1", {-6, -60, 35}, {0, 8, -15}, {0, 0, 1}, 45, 0.5, 512, 1, {-100, -100, 100}, {0.078, 0.361, 0.753}},
        {"spd:jacks:1", {0, 0, -8}, {0, 0, 0}, {0, 1, 0}, 25, 0.001, 256, 1, {-10, 3, -20}, {0.2, 0.05, 0.2}},
        {"spd:sombrero:1", {0, 5, -8}, {0, 0, 0}, {0, 0, 1}, 40, 0.01, 512, 1, {10, 10, -10}, {0.078, 0.361, 0.753}},
    };
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        scene_t *s = load(v[i].name);
        if (!s) continue;
        const camera_t *c = &s->camera;
        CHECK_MSG(near3(c->from, v[i].from[0], v[i].from[1], v[i].from[2], 1e-5) &&
                      near3(c->at, v[i].at[0], v[i].at[1], v[i].at[2], 1e-5) &&
                      near3(c->up, v[i].up[0], v[i].up[1], v[i].up[2], 1e-6),
                  "%s: view", v[i].name);
        CHECK_MSG(c->fov_deg == (float)v[i].angle && fabs(c->hither - v[i].hither) < 1e-9 && c->width == v[i].res &&
                      c->height == v[i].res,
                  "%s: angle %g hither %g res %dx%d", v[i].name, c->fov_deg, c->hither, c->width, c->height);
        CHECK_MSG(s->nlights == v[i].nlights, "%s: %u lights", v[i].name, s->nlights);
        if (s->nlights) CHECK_V3(s->lights[0], v[i].light0[0], v[i].light0[1], v[i].light0[2]);
        CHECK(near3(s->background, v[i].bg[0], v[i].bg[1], v[i].bg[2], 1e-6));
        scene_free(s);
    }
    /* The last lights of the multi-light scenes. */
    scene_t *s = load("spd:gears:1");
    if (s && s->nlights == 5) CHECK_V3(s->lights[4], -1.111, -2.121, 2.626);
    scene_free(s);
    s = load("spd:tree:1");
    if (s && s->nlights == 7) CHECK_V3(s->lights[6], -10, -60, 30);
    scene_free(s);
    s = load("spd:lattice:1");
    if (s && s->nlights == 6) CHECK_V3(s->lights[5], .5, .5, -1);
    if (s) CHECK_V3(s->camera.from, 0.5, 1, 0.5); /* ((1>>1) + 0.5)/1, 1, 1 - 1/2 */
    scene_free(s);
}

/* ---- names, errors, sets ---- */

static void test_names(void)
{
    expect_error("spd:gears:99", "spd:gears:99: size must be 1..12");
    expect_error("spd:balls:8", "spd:balls:8: size must be 1..7");
    expect_error("spd:mount:0", "size must be 1..10");
    expect_error("spd:teapot:65", "size must be 1..64");
    expect_error("spd:tree:x", "spd:tree:x: size must be 1..18");
    expect_error("spd:x", "unknown SPD database 'x' (known: balls, gears, mount, rings, teapot, tetra, tree, lattice, "
                          "shells, jacks, sombrero)");
    expect_error("spd:", "unknown SPD database ''");
    expect_error("spd:tetra:2:t0", "resolution must be 1..64");
    expect_error("spd:tetra:t65", "resolution must be 1..64");
    expect_error("spd:tetra:2:q", "spd:tetra:2:q");
    expect_error("spd:tetra:2:t:3", "spd:tetra:2:t:3");
    expect_error("set:medium", "set of scenes");
    expect_error("set:nope", "unknown scene set 'set:nope'");
    /* Too many primitives for the store. */
    expect_error("spd:balls:7:t64", "exceed");

    /* spd:NAME:t is the default size tessellated at RES 3. */
    scene_t *s = load("spd:gears:t");
    if (s) CHECK(s->prims.ntris == 64 * (2 * 142 + 288) + 2 && s->prims.npolygons == 0);
    scene_free(s);
    s = load("spd:mount:2:t1"); /* 32 triangles + 4 cubes of 12 */
    if (s) CHECK(s->prims.ntris == 32 + 48);
    scene_free(s);
    /* The old entry point still works. */
    s = scene_spd_balls("b", 1, 0, err, sizeof err);
    CHECK(s && s->prims.count == 11);
    scene_free(s);

    /* The catalogue lists every generator, the new meshes and the sets. */
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    scene_catalogue_print(m);
    fclose(m);
    for (int i = 0; i < spd_ngenerators; i++) {
        char want[32];
        snprintf(want, sizeof want, "spd:%s ", spd_generators[i].name);
        CHECK_MSG(strstr(buf, want) != NULL, "catalogue lacks %s", want);
    }
    CHECK(strstr(buf, "motorbike") && strstr(buf, "buildings") && strstr(buf, "openfoam-examples"));
    CHECK(strstr(buf, "sibenik") && strstr(buf, "dragon100k") && strstr(buf, "buddha100k"));
    CHECK(strstr(buf, "set:medium") && strstr(buf, "set:scaling:gears"));
    free(buf);
}

/* The meshes of the scene path load (xz-compressed OBJ, ../shared/scenes,
 * the user folder or $ACCELBENCH_SCENES), with scenes/README.md's counts. */
static void test_path_meshes(void)
{
    static const char *const names[] = {"sibenik", "sponza", "dragon100k", "buddha100k", NULL};
    static const uint32_t ntris[] = {75284, 262205, 100000, 100000};
    require_meshes(names);
    for (int i = 0; names[i]; i++) {
        scene_t *s = load(names[i]);
        if (s) CHECK_MSG(s->prims.ntris == ntris[i], "%s: %u triangles", names[i], s->prims.ntris);
        scene_free(s);
    }
}

static void test_sets(void)
{
    char out[4096];
    CHECK(scene_set_expand("set:spd", out, sizeof out) == 1);
    CHECK(strcmp(out, "spd:balls:4,spd:gears:4,spd:mount:6,spd:rings:7,spd:teapot:12,spd:tetra:6,spd:tree:11") == 0);
    /* Every member of set:spd loads. */
    char *save = NULL;
    for (char *tok = strtok_r(out, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        scene_t *s = load(tok);
        scene_free(s);
    }
    CHECK(scene_set_expand("set:medium", out, sizeof out) == 1);
    CHECK(strncmp(out, "bunny,elephant,armadillo,dragon,glbunny,motorbike,buildings,head,", 64) == 0);
    CHECK(strstr(out, ",sibenik,dragon100k,buddha100k") != NULL);
    CHECK(scene_set_expand("set:scaling:gears", out, sizeof out) == 1);
    CHECK(strncmp(out, "spd:gears:2,spd:gears:3,", 24) == 0 && strstr(out, ",spd:gears:12") != NULL);
    CHECK(scene_set_expand("set:scaling", out, sizeof out) == 1);
    CHECK(strncmp(out, "spd:balls:1,", 12) == 0 && strstr(out, "spd:tetra:9") && strstr(out, "spd:mount:4") &&
          strstr(out, "spd:jacks:6") && strstr(out, "spd:gears:12,") && strstr(out, ",spd:balls:5:t"));
    int n = 1;
    for (const char *c = out; *c; c++) n += *c == ',';
    CHECK_MSG(n == 6 + 6 + 6 + 11 + 5 + 4 + 7 + 8, "set:scaling has %d names", n);
    CHECK(scene_set_expand("bunny", out, sizeof out) == 0);
    CHECK(scene_set_expand("set:nope", out, sizeof out) == 0);
    CHECK(scene_set_expand("set:spd", out, 10) == -1 && out[0] == '\0');
}

/* "test_spd meshes" runs only the checks that need the scene path's meshes
 * (a suite of its own, skipped where they are absent). */
int main(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "meshes") == 0) {
        test_path_meshes();
        return check_report();
    }
    test_counts();
    test_tessellated();
    test_balls();
    test_tetra();
    test_gears();
    test_mount();
    test_rings();
    test_tree();
    test_teapot();
    test_lattice();
    test_shells_jacks_sombrero();
    test_views();
    test_names();
    test_sets();
    return check_report();
}
