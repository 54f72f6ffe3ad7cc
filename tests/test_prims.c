/* test_prims.c: unit tests of the primitive kernels and the prims.h API.
 *
 * Triangles: exact hits, edges and vertices, watertightness on a quad, a
 * fan and closed meshes, parallel rays, the t range, two-sidedness,
 * degenerate triangles, counters. Spheres: outside, inside, tangent,
 * non-unit directions, the t range, a tiny far sphere. prims_finish
 * validation, triangle/sphere box overlap, float vs double agreement and
 * boundary distances. box4 (the builders' boxes in registers) as
 * box_union and box_area bit for bit, and prim_split_bounds through it as
 * the same computation with box_union.
 *
 * Build: gcc -O2 -std=gnu11 -Wall -Wextra -D_GNU_SOURCE -o /tmp/test_prims \
 *   tests/test_prims.c prims/prims.c prims/triangle.c prims/sphere.c prims/cone.c \
 *   prims/polygon.c prims/overlap.c -lm
 * (Cones, polygons and polygon_triangulate are tested in test_prims_shapes.c.)
 * Random inputs come from a fixed seed, so every run tests the same rays. */
#include "../prims/box4.h"
#include "../prims/prims.h"
#include "../prims/prims_internal.h"
#include "check.h"

#include <float.h>
#include <stdint.h>
#include <string.h>

/* ---------------------------------------------------------------------- */
/* helpers                                                                 */

#define PRIMS_TEST_SEED 0x5eed5eed12345678ull
#include "prims_testlib.h"

static bool tri_hit(vec3 a, vec3 b, vec3 c, const ray_t *r, float *t, float *u, float *v)
{
    return triangle_intersect(a, b, c, r, r->tfar, t, u, v);
}

static bool tri_hits(vec3 a, vec3 b, vec3 c, const ray_t *r)
{
    float t, u, v;
    return tri_hit(a, b, c, r, &t, &u, &v);
}

static bool sph_hit(sphere_t s, const ray_t *r, float *t) { return sphere_intersect(s, r, r->tfar, t); }

static sphere_t sph(vec3 c, float r)
{
    sphere_t s = {c, r};
    return s;
}

/* A finished store holding the given triangles over the given vertices. */
static void build_mesh(prims_t *p, const vec3 *verts, int nv, const uint32_t (*tris)[3], int nt)
{
    char err[256];
    prims_init(p);
    for (int i = 0; i < nv; i++) prims_add_vertex(p, verts[i]);
    for (int i = 0; i < nt; i++) prims_add_triangle(p, tris[i][0], tris[i][1], tris[i][2]);
    int rc = prims_finish(p, err, sizeof err);
    CHECK_MSG(rc == 0, "prims_finish: %s", err);
}

/* How many primitives of p the ray hits anywhere in [tnear, tfar). */
static int count_hits(const prims_t *p, const ray_t *r)
{
    counters_t c = {0};
    int n = 0;
    for (uint32_t id = 0; id < p->count; id++) n += prim_occluded(p, id, r, &c);
    return n;
}

/* ---------------------------------------------------------------------- */
/* triangles                                                               */

/* Right triangle in the plane z = 5 with legs of 4 along x and y. */
static const vec3 TA = {0, 0, 5}, TB = {4, 0, 5}, TC = {0, 4, 5};

static void test_triangle_basic(void)
{
    float t = -1, u = -1, v = -1;
    /* (1,1) = 0.5 a + 0.25 b + 0.25 c: every quantity is exact in float. */
    ray_t r = make_ray(v3(1, 1, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v));
    CHECK(t == 5.0f);
    CHECK(u == 0.25f);
    CHECK(v == 0.25f);

    /* The centroid: u = v = 1/3. */
    r = make_ray(v3(4.0f / 3, 4.0f / 3, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v));
    CHECK_NEAR(t, 5.0, 1e-6);
    CHECK_NEAR(u, 1.0 / 3, 1e-6);
    CHECK_NEAR(v, 1.0 / 3, 1e-6);

    /* Oblique ray to the same point (1,1,5), t in units of dir. */
    r = make_ray(v3(0, -1, 0), v3(0.2f, 0.4f, 1.0f), 0.0f, INFINITY);
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v));
    CHECK_NEAR(t, 5.0, 1e-5);
    CHECK_NEAR(u, 0.25, 1e-5);
    CHECK_NEAR(v, 0.25, 1e-5);

    /* Misses: beyond the hypotenuse, beyond each leg. */
    r = make_ray(v3(3, 3, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(!tri_hits(TA, TB, TC, &r));
    r = make_ray(v3(1, -0.001f, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(!tri_hits(TA, TB, TC, &r));
    r = make_ray(v3(-0.001f, 1, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(!tri_hits(TA, TB, TC, &r));

    /* Back side (two-sided): from above, looking down. */
    r = make_ray(v3(1, 1, 10), v3(0, 0, -1), 0.0f, INFINITY);
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v));
    CHECK(t == 5.0f && u == 0.25f && v == 0.25f);
    /* and with the winding reversed (b and c swapped, so u and v swap). */
    CHECK(tri_hit(TA, TC, TB, &r, &t, &u, &v));
    CHECK(t == 5.0f && u == 0.25f && v == 0.25f);
    r = make_ray(v3(3, 1, 10), v3(0, 0, -1), 0.0f, INFINITY); /* (3,1) = 0.25 TC + 0.75 TB */
    CHECK(tri_hit(TA, TC, TB, &r, &t, &u, &v));
    CHECK(u == 0.25f && v == 0.75f);

    /* Dominant axis x and y, negative directions: the permutation must
     * keep the answer. Triangle in the plane x = 2 and in y = -3. */
    vec3 xa = v3(2, 0, 0), xb = v3(2, 4, 0), xc = v3(2, 0, 4);
    r = make_ray(v3(-1, 1, 1), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(tri_hit(xa, xb, xc, &r, &t, &u, &v) && t == 3.0f && u == 0.25f && v == 0.25f);
    r = make_ray(v3(7, 1, 1), v3(-2, 0, 0), 0.0f, INFINITY);
    CHECK(tri_hit(xa, xb, xc, &r, &t, &u, &v) && t == 2.5f && u == 0.25f && v == 0.25f);
    vec3 ya = v3(0, -3, 0), yb = v3(0, -3, 4), yc = v3(4, -3, 0);
    r = make_ray(v3(1, 5, 1), v3(0, -1, 0), 0.0f, INFINITY);
    CHECK(tri_hit(ya, yb, yc, &r, &t, &u, &v) && t == 8.0f && u == 0.25f && v == 0.25f);
}

static void test_triangle_edges_vertices(void)
{
    float t, u, v;
    /* On the edge a-b, on the hypotenuse b-c, and on each vertex. */
    ray_t r = make_ray(v3(2, 0, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v) && u == 0.5f && v == 0.0f);
    r = make_ray(v3(2, 2, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v) && u == 0.5f && v == 0.5f);
    r = make_ray(v3(0, 0, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v) && u == 0.0f && v == 0.0f && t == 5.0f);
    r = make_ray(v3(4, 0, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v) && u == 1.0f && v == 0.0f);
    r = make_ray(v3(0, 4, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v) && u == 0.0f && v == 1.0f);
    /* Oblique through the vertex b = (4,0,5). */
    r = make_ray(v3(3, -2, 3), v3(0.5f, 1.0f, 1.0f), 0.0f, INFINITY);
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v) && t == 2.0f);

    /* The double-precision fallback. The edge b-c passes 1.2e-9 beside
     * the ray (the z axis): the exact edge function is 3.0e-9, but both
     * float products Cx*By and Cy*Bx round to the same value, so the float
     * edge function is exactly 0 and only the fallback sees the true sign.
     * The ray lies inside the triangle on one side of b-c and outside the
     * one on the other side (found by a search for such products). */
    vec3 fb = v3(1.2580978870391846f, 1.9774080514907837f, 5), fc = v3(-0.7203893065452576f, -1.132267713546753f, 5);
    volatile float p1 = fc.x * fb.y, p2 = fc.y * fb.x; /* volatile: rounded, never fused */
    CHECK(p1 == p2); /* the premise */
    r = make_ray(v3(0, 0, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(tri_hits(v3(-2, 1, 5), fb, fc, &r));
    CHECK(!tri_hits(v3(2, -1, 5), fb, fc, &r));
    double td;
    CHECK(triangle_intersect_double(v3(-2, 1, 5), fb, fc, &r, &td) && td == 5.0);
    CHECK(!triangle_intersect_double(v3(2, -1, 5), fb, fc, &r, &td));
}

/* A unit quad split along its diagonal: rays through points of the shared
 * diagonal, from random oblique directions, must hit at least one half. */
static void test_watertight_quad(void)
{
    static const vec3 q[4] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    static const uint32_t tris[2][3] = {{0, 1, 2}, {0, 2, 3}};
    prims_t p;
    build_mesh(&p, q, 4, tris, 2);

    int gaps = 0, both = 0, n = 0;
    /* Exact: dyadic points and directions, the line meets the diagonal exactly. */
    for (int i = 1; i < 64; i++)
        for (int j = 0; j < 16; j++) {
            float s = i / 64.0f;
            vec3 d = v3((j % 4 - 1.5f) / 4.0f, (j / 4 - 1.5f) / 2.0f, 1.0f);
            ray_t r = make_ray(v3(s - d.x, s - d.y, -1.0f), d, 0.0f, INFINITY);
            int h = count_hits(&p, &r);
            gaps += h == 0;
            both += h == 2;
            n++;
        }
    /* Random: points on the diagonal and directions, rounded to float, so
     * the lines pass within rounding of the diagonal on either side. */
    for (int i = 0; i < 4000; i++) {
        float s = rnd(0.02f, 0.98f);
        vec3 d = v3(rnd(-3, 3), rnd(-3, 3), rnd(0.05f, 1.0f));
        if (i & 1) d.z = -d.z;
        vec3 target = v3(s, s, 0);
        ray_t r = ray_through(v3_sub(target, v3_scale(d, 2.0f)), target);
        gaps += count_hits(&p, &r) == 0;
        n++;
    }
    CHECK_MSG(gaps == 0, "%d of %d rays through the shared diagonal hit neither triangle", gaps, n);
    CHECK(both > 0); /* exact rays on the edge hit both */
    prims_free(&p);
}

/* A fan of 6 triangles around a centre vertex. Rays through the centre
 * vertex must hit at least one triangle: planar fan from any direction not
 * parallel to it, cone-shaped fan from directions inside the cone. */
static void test_watertight_fan(void)
{
    for (int cone = 0; cone < 2; cone++) {
        vec3 verts[7];
        uint32_t tris[6][3];
        vec3 centre = cone ? v3(0, 0, 0) : v3(0.3f, -0.7f, 0.1f);
        verts[0] = centre;
        for (int k = 0; k < 6; k++) {
            float a = (float)k * 1.04719755f + 0.2f; /* 60 degree steps */
            verts[k + 1] = v3_add(centre, v3(cosf(a), sinf(a), cone ? -1.0f : 0.0f));
            tris[k][0] = 0;
            tris[k][1] = (uint32_t)k + 1;
            tris[k][2] = (uint32_t)(k + 1) % 6 + 1;
        }
        prims_t p;
        build_mesh(&p, verts, 7, (const uint32_t(*)[3])tris, 6);
        int gaps = 0, n = 0;
        for (int i = 0; i < 5000; i++) {
            vec3 d;
            if (cone) { /* inside the pyramid (faces at ~41 degrees), downwards */
                d = v3(rnd(-0.55f, 0.55f), rnd(-0.55f, 0.55f), -1.0f);
                d = v3_scale(d, rnd(0.1f, 10.0f));
            } else {
                d = v3_norm(rnd_v3(-1, 1));
                if (fabsf(d.z) < 0.01f) continue;
            }
            /* org = centre - 4 d: the scale by 4 is exact, so the line
             * passes the centre vertex up to the rounding of one sum. */
            ray_t r = make_ray(v3_sub(centre, v3_scale(d, 4.0f)), d, 0.0f, INFINITY);
            gaps += count_hits(&p, &r) == 0;
            n++;
        }
        CHECK_MSG(gaps == 0, "%s fan: %d of %d rays through the shared vertex hit nothing", cone ? "cone" : "planar", gaps, n);
        prims_free(&p);
    }
}

/* Closed cube [-1,1]^3 of 12 triangles. */
static void build_cube(prims_t *p)
{
    /* 0..3 go round the bottom face z = -1, 4..7 round the top. */
    static const vec3 v[8] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                              {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
    static const uint32_t quads[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {3, 2, 6, 7}, {0, 3, 7, 4}, {1, 2, 6, 5}};
    uint32_t tris[12][3];
    for (int f = 0; f < 6; f++) {
        const uint32_t *q = quads[f];
        uint32_t t0[3] = {q[0], q[1], q[2]}, t1[3] = {q[0], q[2], q[3]};
        memcpy(tris[2 * f], t0, sizeof t0);
        memcpy(tris[2 * f + 1], t1, sizeof t1);
    }
    build_mesh(p, v, 8, (const uint32_t(*)[3])tris, 12);
}

/* How the ray's LINE meets the box [-1,1]^3, in double. */
typedef enum { LINE_MISSES, LINE_TOUCHES, LINE_CROSSES } line_box_t;

/* Also returns the parameter interval of the line inside the closed box
 * (entry > exit when it misses). LINE_CROSSES means the line passes
 * through the open interior; LINE_TOUCHES that it only meets the boundary
 * (a face it lies in, an edge or a vertex it grazes). For the dyadic rays
 * below every operation here is exact. */
static line_box_t line_box(const ray_t *r, double *entry, double *exit_)
{
    double o[3] = {r->org.x, r->org.y, r->org.z}, d[3] = {r->dir.x, r->dir.y, r->dir.z};
    double lo = -INFINITY, hi = INFINITY;
    bool in_face_plane = false;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0.0) {
            if (o[k] < -1.0 || o[k] > 1.0) lo = INFINITY; /* outside this slab for ever */
            in_face_plane |= o[k] == -1.0 || o[k] == 1.0;
            continue;
        }
        double t0 = (-1.0 - o[k]) / d[k], t1 = (1.0 - o[k]) / d[k];
        if (t0 > t1) { double tmp = t0; t0 = t1; t1 = tmp; }
        if (t0 > lo) lo = t0;
        if (t1 < hi) hi = t1;
    }
    *entry = lo;
    *exit_ = hi;
    if (lo > hi) return LINE_MISSES;
    return lo < hi && !in_face_plane ? LINE_CROSSES : LINE_TOUCHES;
}

static void test_watertight_cube(void)
{
    prims_t p;
    build_cube(&p);
    CHECK(p.ndegenerate == 0);

    /* 10000 rays on a dyadic grid with dyadic directions: every quantity,
     * in double and in the float kernel, is exact, and many lines pass
     * exactly through cube edges, vertices and face diagonals. */
    static const float dirs[][2] = {{0.25f, 0.125f}, {-0.5f, 0.25f}, {0.125f, -0.375f}, {0.5f, 0.5f},
                                    {0.0f, 0.25f},   {0.0f, 0.0f},   {-0.25f, -0.25f},  {1.0f, 0.5f}};
    int ndirs = (int)(sizeof dirs / sizeof dirs[0]);
    int inside = 0, gaps = 0, outside = 0, phantom = 0;
    for (int i = 0; i < 100; i++)
        for (int j = 0; j < 100; j++) {
            int k = (i * 7 + j * 3) % ndirs, perm = (i + j) % 3, flip = (i * j) & 1;
            float a[3] = {(i - 50) / 32.0f, (j - 50) / 32.0f, flip ? 4.0f : -4.0f};
            float d[3] = {dirs[k][0], dirs[k][1], flip ? -1.0f : 1.0f};
            vec3 org = v3(a[perm], a[(perm + 1) % 3], a[(perm + 2) % 3]);
            vec3 dir = v3(d[perm], d[(perm + 1) % 3], d[(perm + 2) % 3]);
            ray_t r = make_ray(org, dir, 0.0f, INFINITY);
            double en, ex;
            line_box_t kind = line_box(&r, &en, &ex);
            int h = count_hits(&p, &r);
            if (kind == LINE_CROSSES) { /* enters and leaves: two crossings */
                inside++;
                gaps += h < 2;
            } else if (kind == LINE_MISSES) {
                outside++;
                phantom += h != 0;
            }
        }
    CHECK_MSG(gaps == 0, "%d of %d exact rays through the cube interior hit fewer than 2 triangles", gaps, inside);
    CHECK_MSG(phantom == 0, "%d of %d exact rays missing the cube hit it", phantom, outside);
    CHECK(inside > 2000 && outside > 1000);

    /* 10000 random rays aimed at points on the cube's edges, vertices and
     * face diagonals (and some random points), rounded to float. Those
     * whose line passes clearly through the interior must hit twice. */
    inside = gaps = 0;
    for (int i = 0; i < 10000; i++) {
        vec3 target;
        float s = rnd(-1, 1);
        int kind = i % 4, ax = (i / 4) % 3;
        float sx = rnd(0, 1) < 0.5f ? -1.0f : 1.0f, sy = rnd(0, 1) < 0.5f ? -1.0f : 1.0f;
        float c[3];
        if (kind == 0) { /* a point on a cube edge */
            c[ax] = s; c[(ax + 1) % 3] = sx; c[(ax + 2) % 3] = sy;
        } else if (kind == 1) { /* a cube vertex */
            c[ax] = sx; c[(ax + 1) % 3] = sy; c[(ax + 2) % 3] = rnd(0, 1) < 0.5f ? -1.0f : 1.0f;
        } else if (kind == 2) { /* a point on a face diagonal */
            c[ax] = sx; c[(ax + 1) % 3] = s; c[(ax + 2) % 3] = s * sy;
        } else {
            c[0] = rnd(-1.2f, 1.2f); c[1] = rnd(-1.2f, 1.2f); c[2] = rnd(-1.2f, 1.2f);
        }
        target = v3(c[0], c[1], c[2]);
        vec3 org = v3_scale(v3_norm(rnd_v3(-1, 1)), 5.0f);
        ray_t r = ray_through(org, target);
        double en, ex;
        if (line_box(&r, &en, &ex) == LINE_CROSSES && ex - en > 1e-4) {
            inside++;
            gaps += count_hits(&p, &r) < 2;
        }
    }
    CHECK_MSG(gaps == 0, "%d of %d random rays through the cube interior hit fewer than 2 triangles", gaps, inside);
    CHECK(inside > 5000);
    prims_free(&p);
}

/* A skewed tetrahedron, rays aimed at its vertices and edges. */
static void test_watertight_tetrahedron(void)
{
    static const vec3 v[4] = {{0.1f, -0.3f, 0.2f}, {1.3f, 0.2f, -0.4f}, {-0.5f, 1.1f, 0.3f}, {0.2f, 0.3f, 1.4f}};
    static const uint32_t tris[4][3] = {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}};
    prims_t p;
    build_mesh(&p, v, 4, tris, 4);
    vec3 centroid = v3_scale(v3_add(v3_add(v[0], v[1]), v3_add(v[2], v[3])), 0.25f);

    int inside = 0, gaps = 0;
    for (int i = 0; i < 10000; i++) {
        int e0 = (int)(rng_next() % 4), e1 = (e0 + 1 + (int)(rng_next() % 3)) % 4;
        float s = rnd(0, 1);
        vec3 target = (i % 3 == 0) ? v[e0] : v3_add(v3_scale(v[e0], 1.0f - s), v3_scale(v[e1], s));
        vec3 org = v3_add(centroid, v3_scale(v3_norm(rnd_v3(-1, 1)), 6.0f));
        ray_t r = ray_through(org, target);

        /* Clip the line against the 4 inward half-spaces, in double. */
        double lo = -INFINITY, hi = INFINITY;
        for (int f = 0; f < 4; f++) {
            dvec3 a = dv3(v[tris[f][0]]), b = dv3(v[tris[f][1]]), c = dv3(v[tris[f][2]]);
            dvec3 n = dv3_cross(dv3_sub(b, a), dv3_sub(c, a));
            dvec3 opp = dv3(v[6 - tris[f][0] - tris[f][1] - tris[f][2]]);
            double sgn = dv3_dot(n, dv3_sub(opp, a)) > 0 ? 1.0 : -1.0;
            double s0 = sgn * dv3_dot(n, dv3_sub(dv3(r.org), a)), sd = sgn * dv3_dot(n, dv3(r.dir));
            if (sd > 0) lo = fmax(lo, -s0 / sd);
            else if (sd < 0) hi = fmin(hi, -s0 / sd);
            else if (s0 <= 0) hi = -INFINITY;
        }
        if (hi - lo > 1e-4) {
            inside++;
            gaps += count_hits(&p, &r) < 2;
        }
    }
    CHECK_MSG(gaps == 0, "%d of %d rays through the tetrahedron interior hit fewer than 2 faces", gaps, inside);
    CHECK_MSG(inside > 2500, "only %d rays through the interior", inside);
    prims_free(&p);
}

static void test_triangle_parallel(void)
{
    vec3 a = v3(0, 0, 0), b = v3(1, 0, 0), c = v3(0, 1, 0);
    /* In the plane, crossing the triangle. */
    ray_t r = make_ray(v3(-1, 0.25f, 0), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(!tri_hits(a, b, c, &r));
    r = make_ray(v3(-1, -0.5f, 0), v3(1, 1, 0), 0.0f, INFINITY);
    CHECK(!tri_hits(a, b, c, &r));
    /* Above the plane, parallel to it. */
    r = make_ray(v3(-1, 0.25f, 0.5f), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(!tri_hits(a, b, c, &r));
    r = make_ray(v3(0.2f, -1, 1e-3f), v3(0, 3, 0), 0.0f, INFINITY);
    CHECK(!tri_hits(a, b, c, &r));
    /* The double arbiter agrees. */
    double td;
    CHECK(!triangle_intersect_double(a, b, c, &r, &td));
    /* A zero direction hits nothing. */
    r = make_ray(v3(0.2f, 0.2f, -1), v3(0, 0, 0), 0.0f, INFINITY);
    CHECK(!tri_hits(a, b, c, &r));
}

static void test_triangle_trange(void)
{
    float t, u, v;
    ray_t r = make_ray(v3(1, 1, 0), v3(0, 0, 1), 0.0f, 4.9f);
    CHECK(!tri_hit(TA, TB, TC, &r, &t, &u, &v)); /* t = 5 > tmax */
    r.tfar = 5.0f;
    CHECK(!tri_hit(TA, TB, TC, &r, &t, &u, &v)); /* t == tmax is out */
    r.tfar = nextafterf(5.0f, INFINITY);
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v) && t == 5.0f);
    r.tfar = INFINITY;
    r.tnear = 5.0f;
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v) && t == 5.0f); /* t == tnear is in */
    r.tnear = nextafterf(5.0f, INFINITY);
    CHECK(!tri_hit(TA, TB, TC, &r, &t, &u, &v));
    /* Behind the origin: t = -5 < tnear = 0. */
    r = make_ray(v3(1, 1, 10), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(!tri_hit(TA, TB, TC, &r, &t, &u, &v));
    r.tnear = -10.0f; /* a negative tnear lets it in */
    CHECK(tri_hit(TA, TB, TC, &r, &t, &u, &v) && t == -5.0f);
    /* tmax is the argument, not ray->tfar. */
    r = make_ray(v3(1, 1, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(!triangle_intersect(TA, TB, TC, &r, 5.0f, &t, &u, &v));
    CHECK(triangle_intersect(TA, TB, TC, &r, 6.0f, &t, &u, &v));
}

static void test_triangle_degenerate(void)
{
    static const vec3 v[6] = {{0, 0, 0}, {1, 2, 3}, {2, 4, 6}, {1, 0, 0}, {0.5f, 0.5f, 0.5f}, {0, 1, 0}};
    static const uint32_t tris[4][3] = {{0, 1, 2},  /* collinear */
                                        {3, 3, 5},  /* repeated vertex */
                                        {4, 4, 4},  /* a point */
                                        {0, 3, 5}}; /* a real one, for contrast */
    prims_t p;
    build_mesh(&p, v, 6, tris, 4);
    CHECK(p.ndegenerate == 3);
    CHECK(p.tri_degenerate[0] && p.tri_degenerate[1] && p.tri_degenerate[2] && !p.tri_degenerate[3]);

    counters_t c = {0};
    int hits = 0, dhits = 0, khits = 0, real = 0;
    for (int i = 0; i < 3000; i++) {
        uint32_t id = (uint32_t)(i % 4);
        const uint32_t *tr = tris[id];
        /* Aim at a point of the (degenerate) triangle itself. */
        float s = rnd(0, 1), w = rnd(0, 1 - s);
        vec3 target = v3_add(v3_add(v3_scale(v[tr[0]], 1 - s - w), v3_scale(v[tr[1]], s)), v3_scale(v[tr[2]], w));
        ray_t r = ray_through(v3_add(target, rnd_v3(-3, 3)), target);
        hit_t h = hit_none(&r);
        bool hit = prim_intersect(&p, id, &r, &h, &c);
        double td;
        bool dhit = prim_intersect_double(&p, id, &r, &td);
        if (id == 3) {
            real += hit;
            continue;
        }
        hits += hit;
        dhits += dhit;
        /* The kernel alone: a repeated vertex makes det exactly 0. */
        if (id == 1) khits += tri_hits(v[tr[0]], v[tr[1]], v[tr[2]], &r);
    }
    CHECK_MSG(hits == 0, "degenerate triangles hit %d times", hits);
    CHECK_MSG(dhits == 0, "degenerate triangles hit %d times in double", dhits);
    CHECK_MSG(khits == 0, "triangle_intersect hit a repeated-vertex triangle %d times", khits);
    CHECK(real > 600); /* the real triangle is hit (almost always) */
    CHECK(c.prim_tests == 3000); /* degenerate tests still count as tests */
    CHECK(c.prim_hits == (uint64_t)real);
    prims_free(&p);
}

static void test_counters_and_untouched(void)
{
    static const vec3 v[3] = {{0, 0, 5}, {4, 0, 5}, {0, 4, 5}};
    static const uint32_t tris[1][3] = {{0, 1, 2}};
    prims_t p;
    build_mesh(&p, v, 3, tris, 1);
    counters_t c = {0};

    ray_t r = make_ray(v3(1, 1, 0), v3(0, 0, 1), 0.0f, 100.0f);
    hit_t h = hit_none(&r);
    CHECK(h.prim == HIT_NONE && h.t == 100.0f);
    CHECK(prim_intersect(&p, 0, &r, &h, &c));
    CHECK(h.prim == 0 && h.t == 5.0f && h.u == 0.25f && h.v == 0.25f);
    CHECK(c.prim_tests == 1 && c.prim_hits == 1);
    vec3 n = prim_normal(&p, &h, &r);
    CHECK(n.x == 0.0f && n.y == 0.0f && n.z == 1.0f); /* (b-a) x (c-a), not flipped */

    /* A second test of the same triangle: t = 5 is not < hit.t = 5. */
    hit_t before = h;
    CHECK(!prim_intersect(&p, 0, &r, &h, &c));
    CHECK(memcmp(&before, &h, sizeof h) == 0);
    CHECK(c.prim_tests == 2 && c.prim_hits == 1);

    /* A miss leaves an arbitrary hit record alone. */
    hit_t junk = {42.0f, 0.125f, 0.5f, 7};
    h = junk;
    ray_t miss = make_ray(v3(3, 3, 0), v3(0, 0, 1), 0.0f, 100.0f);
    CHECK(!prim_intersect(&p, 0, &miss, &h, &c));
    CHECK(memcmp(&junk, &h, sizeof h) == 0);
    CHECK(c.prim_tests == 3 && c.prim_hits == 1);

    /* prim_occluded counts the same way and ignores nothing but the range. */
    CHECK(prim_occluded(&p, 0, &r, &c));
    CHECK(!prim_occluded(&p, 0, &miss, &c));
    ray_t shortr = make_ray(v3(1, 1, 0), v3(0, 0, 1), 0.0f, 5.0f);
    CHECK(!prim_occluded(&p, 0, &shortr, &c));
    CHECK(c.prim_tests == 6 && c.prim_hits == 2);
    CHECK(c.box_tests == 0 && c.steps == 0 && c.empty_leaves == 0 && c.mailbox_hits == 0);
    prims_free(&p);
}

/* ---------------------------------------------------------------------- */
/* spheres                                                                 */

static void test_sphere_basic(void)
{
    sphere_t s = sph(v3(0, 0, 10), 2.0f);
    float t = -1;
    ray_t r = make_ray(v3(0, 0, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(sph_hit(s, &r, &t) && t == 8.0f);

    /* From inside: the far side. */
    r = make_ray(v3(0, 0, 10), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(sph_hit(s, &r, &t) && t == 2.0f);
    r = make_ray(v3(0.5f, -0.5f, 9), v3(0, 0, -1), 0.0f, INFINITY);
    CHECK(sph_hit(s, &r, &t));
    CHECK_NEAR(t, sqrt(4.0 - 0.5) - 1.0, 1e-6);

    /* Tangent: the line touches at (2,0,10); a hair further out misses. */
    r = make_ray(v3(2, 0, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(sph_hit(s, &r, &t) && t == 10.0f);
    CHECK_NEAR(sphere_boundary_distance(s, &r), 0.0, 1e-12);
    r = make_ray(v3(nextafterf(2.0f, 3.0f), 0, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(!sph_hit(s, &r, &t));
    r = make_ray(v3(1.99f, 0, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(sph_hit(s, &r, &t));
    CHECK_NEAR(t, 10.0 - sqrt(4.0 - 1.99 * 1.99), 2e-5);

    /* Misses: beside it, and pointing away. */
    r = make_ray(v3(5, 0, 0), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(!sph_hit(s, &r, &t));
    r = make_ray(v3(0, 0, 0), v3(0, 0, -1), 0.0f, INFINITY);
    CHECK(!sph_hit(s, &r, &t));

    /* Non-unit directions: t in units of dir. */
    r = make_ray(v3(0, 0, 0), v3(0, 0, 4), 0.0f, INFINITY);
    CHECK(sph_hit(s, &r, &t) && t == 2.0f);
    r = make_ray(v3(0, 0, 0), v3(0, 0, 0.25f), 0.0f, INFINITY);
    CHECK(sph_hit(s, &r, &t) && t == 32.0f);
    r = make_ray(v3(-3, -4, 10), v3(0.3f, 0.4f, 0), 0.0f, INFINITY); /* |dir| = 0.5, distance 3 */
    CHECK(sph_hit(s, &r, &t));
    CHECK_NEAR(t, 6.0, 1e-5);
    r = make_ray(v3(0, 0, 0), v3(0, 0, 0), 0.0f, INFINITY);
    CHECK(!sph_hit(s, &r, &t));
}

static void test_sphere_trange(void)
{
    sphere_t s = sph(v3(0, 0, 10), 2.0f); /* roots 8 and 12 */
    float t;
    ray_t r = make_ray(v3(0, 0, 0), v3(0, 0, 1), 8.0f, INFINITY);
    CHECK(sph_hit(s, &r, &t) && t == 8.0f); /* tnear == t is in */
    r.tnear = nextafterf(8.0f, INFINITY);
    CHECK(sph_hit(s, &r, &t) && t == 12.0f); /* the first root is out: far side */
    r.tnear = 12.0f;
    CHECK(sph_hit(s, &r, &t) && t == 12.0f);
    r.tnear = 12.5f;
    CHECK(!sph_hit(s, &r, &t));
    r = make_ray(v3(0, 0, 0), v3(0, 0, 1), 0.0f, 8.0f);
    CHECK(!sph_hit(s, &r, &t)); /* t == tmax is out, and 12 even more so */
    r.tfar = nextafterf(8.0f, INFINITY);
    CHECK(sph_hit(s, &r, &t) && t == 8.0f);
    r.tfar = 7.9f;
    CHECK(!sph_hit(s, &r, &t));
    /* tmax is the argument: a closer hit already found shortens it. */
    r.tfar = INFINITY;
    CHECK(!sphere_intersect(s, &r, 8.0f, &t));
    double td;
    r.tnear = 8.5f;
    CHECK(sphere_intersect_double(s, &r, &td) && td == 12.0);
}

/* r = 1e-3 at (100,100,100): r^2 = 1e-6 is far below the rounding noise of
 * the textbook discriminant, so this needs the careful formulation. */
static void test_sphere_tiny_far(void)
{
    sphere_t s = sph(v3(100, 100, 100), 1e-3f);
    float t;
    double td;
    ray_t r = make_ray(v3(0, 0, 0), v3(1, 1, 1), 0.0f, INFINITY);
    CHECK(sph_hit(s, &r, &t));
    CHECK_NEAR(t, 100.0 - 1e-3 / sqrt(3.0), 3e-5); /* the near root: 5.8e-4 before 100 */
    r = make_ray(v3(0, 0, 0), v3_norm(v3(1, 1, 1)), 0.0f, INFINITY);
    CHECK(sph_hit(s, &r, &t));
    CHECK_NEAR(t, sqrt(3.0) * 100.0 - 1e-3, 5e-5);

    /* Rays aimed at random points of the disc of radius 0.9 r facing the
     * origin all hit; aimed at 1.1 r, all miss. */
    int miss_in = 0, hit_out = 0, dbl_bad = 0;
    dvec3 w = {1 / sqrt(2.0), -1 / sqrt(2.0), 0}, z = {1 / sqrt(6.0), 1 / sqrt(6.0), -2 / sqrt(6.0)};
    for (int i = 0; i < 2000; i++) {
        double ang = rnd(0, 6.2831853f), rad = (i & 1 ? 1.1 : rnd(0, 0.9f)) * 1e-3;
        double ox = rad * (cos(ang) * w.x + sin(ang) * z.x), oy = rad * (cos(ang) * w.y + sin(ang) * z.y),
               oz = rad * (cos(ang) * w.z + sin(ang) * z.z);
        vec3 target = v3((float)(100.0 + ox), (float)(100.0 + oy), (float)(100.0 + oz));
        r = make_ray(v3(0, 0, 0), target, 0.0f, INFINITY);
        bool hit = sph_hit(s, &r, &t);
        if (i & 1) hit_out += hit;
        else {
            miss_in += !hit;
            dbl_bad += !(sphere_intersect_double(s, &r, &td) && fabs(t - td) <= 1e-5 * td);
        }
    }
    CHECK_MSG(miss_in == 0, "%d rays inside the tiny sphere's silhouette missed", miss_in);
    CHECK_MSG(hit_out == 0, "%d rays outside the tiny sphere's silhouette hit", hit_out);
    CHECK_MSG(dbl_bad == 0, "%d tiny-sphere hits disagree with double", dbl_bad);
}

static void test_sphere_api(void)
{
    prims_t p;
    char err[256];
    prims_init(&p);
    prims_add_sphere(&p, v3(0, 0, 10), 2.0f);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    CHECK(p.bounds[0].lo.x == -2.0f && p.bounds[0].hi.z == 12.0f);
    counters_t c = {0};
    ray_t r = make_ray(v3(0, 0, 0), v3(0, 0, 1), 0.0f, INFINITY);
    hit_t h = hit_none(&r);
    CHECK(prim_intersect(&p, 0, &r, &h, &c) && h.t == 8.0f && h.prim == 0 && h.u == 0.0f && h.v == 0.0f);
    vec3 n = prim_normal(&p, &h, &r);
    CHECK(n.x == 0.0f && n.y == 0.0f && n.z == -1.0f);
    r.tnear = 9.0f;
    h = hit_none(&r);
    CHECK(prim_intersect(&p, 0, &r, &h, &c) && h.t == 12.0f);
    n = prim_normal(&p, &h, &r);
    CHECK(n.z == 1.0f);
    hit_t junk = {1.0f, 2.0f, 3.0f, 4};
    h = junk;
    CHECK(!prim_intersect(&p, 0, &r, &h, &c)); /* hit.t = 1 < 12 */
    CHECK(memcmp(&h, &junk, sizeof h) == 0);
    CHECK(c.prim_tests == 3 && c.prim_hits == 2);
    prims_free(&p);
}

/* ---------------------------------------------------------------------- */
/* prims_finish validation                                                 */

static void test_finish_errors(void)
{
    prims_t p;
    char err[256];

    prims_init(&p);
    prims_add_vertex(&p, v3(0, 0, 0));
    prims_add_vertex(&p, v3(1, 0, 0));
    prims_add_vertex(&p, v3(0, NAN, 0));
    prims_add_triangle(&p, 0, 1, 2);
    err[0] = 0;
    CHECK(prims_finish(&p, err, sizeof err) == -1);
    CHECK_MSG(strstr(err, "vertex 2") != NULL, "message: %s", err);
    prims_free(&p);

    prims_init(&p);
    prims_add_vertex(&p, v3(0, 0, 0));
    prims_add_vertex(&p, v3(1, 0, 0));
    prims_add_vertex(&p, v3(0, 1, 0));
    prims_add_triangle(&p, 0, 1, 2);
    prims_add_triangle(&p, 0, 3, 2);
    err[0] = 0;
    CHECK(prims_finish(&p, err, sizeof err) == -1);
    CHECK_MSG(strstr(err, "triangle 1") != NULL && strstr(err, "vertex 3") != NULL, "message: %s", err);
    prims_free(&p);

    static const float bad[] = {0.0f, -1.0f, NAN, INFINITY};
    for (int i = 0; i < 4; i++) {
        prims_init(&p);
        prims_add_sphere(&p, v3(0, 0, 0), 1.0f);
        prims_add_sphere(&p, v3(5, 0, 0), bad[i]);
        err[0] = 0;
        CHECK(prims_finish(&p, err, sizeof err) == -1);
        CHECK_MSG(strstr(err, "sphere 1") != NULL, "radius %g: message: %s", bad[i], err);
        prims_free(&p);
    }

    /* Mixed and valid: ids in scene order, bounds filled. */
    prims_init(&p);
    prims_add_vertex(&p, v3(0, 0, 0));
    prims_add_vertex(&p, v3(1, 0, 0));
    prims_add_vertex(&p, v3(0, 1, 2));
    CHECK(prims_add_sphere(&p, v3(0, 0, -5), 1.0f) == 0);
    CHECK(prims_add_triangle(&p, 0, 1, 2) == 1);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    CHECK(p.bounds[1].lo.z == 0.0f && p.bounds[1].hi.z == 2.0f && p.box.lo.z == -6.0f);
    prims_free(&p);
}

/* ---------------------------------------------------------------------- */
/* overlap                                                                 */

static void test_triangle_box_overlap(void)
{
    box3 b = box(v3(-1, -1, -1), v3(1, 1, 1));
    /* Inside. */
    CHECK(triangle_overlaps_box(v3(0, 0, 0), v3(0.5f, 0, 0), v3(0, 0.5f, 0.5f), b));
    /* Crossing with no vertex inside: a big triangle through the middle,
     * a thin sliver piercing the box. */
    CHECK(triangle_overlaps_box(v3(-5, -5, 0.3f), v3(5, -5, 0.3f), v3(0, 5, -0.3f), b));
    CHECK(triangle_overlaps_box(v3(-3, 0.1f, 0.1f), v3(3, 0.2f, -0.1f), v3(3, 0.3f, 0.2f), b));
    /* Containing the box's cross-section entirely. */
    CHECK(triangle_overlaps_box(v3(-100, -100, 0), v3(100, -100, 0), v3(0, 100, 0), b));
    /* Lying exactly on the face z = 1; inside it, and covering it. */
    CHECK(triangle_overlaps_box(v3(-0.5f, -0.5f, 1), v3(0.5f, -0.5f, 1), v3(0, 0.5f, 1), b));
    CHECK(triangle_overlaps_box(v3(-9, -9, 1), v3(9, -9, 1), v3(0, 9, 1), b));
    /* In the face plane but beside the face; and one float step above it. */
    CHECK(!triangle_overlaps_box(v3(2, 0, 1), v3(3, 0, 1), v3(2, 1, 1), b));
    float above = nextafterf(1.0f, 2.0f);
    CHECK(!triangle_overlaps_box(v3(-0.5f, -0.5f, above), v3(0.5f, -0.5f, above), v3(0, 0.5f, above), b));
    /* Touching at a single vertex (the corner) from outside. */
    CHECK(triangle_overlaps_box(v3(1, 1, 1), v3(3, 2, 2), v3(2, 3, 4), b));
    CHECK(!triangle_overlaps_box(v3(above, 1, 1), v3(3, 2, 2), v3(2, 3, 4), b));

    /* Beside the box edge x = y = 1: the triangle lies in the plane
     * x + y + z = 2.5 (which cuts the box) and everywhere has x + y >= 2.5,
     * while the box has x + y <= 2. Its bounds overlap the box and its
     * plane cuts it, so only the axis (1,1,0) = edge x z-axis separates. */
    vec3 a = v3(2, 0.5f, 0), bb = v3(0.5f, 2, 0), c = v3(3, 3, -3.5f);
    box3 tb = box_grow(box_grow(box_grow(box_empty(), a), bb), c);
    CHECK(box_overlap(tb, b)); /* the box axes do not separate */
    vec3 n = v3_cross(v3_sub(bb, a), v3_sub(c, a));
    float d = v3_dot(n, a), rad = fabsf(n.x) + fabsf(n.y) + fabsf(n.z);
    CHECK(fabsf(d) < rad); /* nor does the triangle's plane */
    CHECK(!triangle_overlaps_box(a, bb, c, b));
    CHECK(!triangle_overlaps_box(c, a, bb, b));
    /* Moved onto the plane x + y + z = 2, its edge passes through the box
     * edge at (1,1,0): touching. */
    CHECK(triangle_overlaps_box(v3(1.5f, 0.5f, 0), v3(0.5f, 1.5f, 0), v3(3, 3, -4), b));
    /* The same near a box corner: the plane x + y + z = 3.2 leaves the
     * corner (1,1,1) on the other side ... */
    CHECK(!triangle_overlaps_box(v3(1.6f, 1.6f, 0), v3(0.5f, 0.5f, 2.2f), v3(2.5f, 0.2f, 0.5f), b));
    /* ... and at 3 it passes exactly through the corner. */
    CHECK(triangle_overlaps_box(v3(1.5f, 1.5f, 0), v3(0.5f, 0.5f, 2.0f), v3(2.5f, 0.5f, 0), b));

    /* Degenerate triangles: a segment through the box, a point inside, a
     * segment beside an edge (again separated only by an edge axis). */
    CHECK(triangle_overlaps_box(v3(-3, 0, 0), v3(3, 0.5f, 0), v3(3, 0.5f, 0), b));
    CHECK(triangle_overlaps_box(v3(0.5f, 0.5f, 0.5f), v3(0.5f, 0.5f, 0.5f), v3(0.5f, 0.5f, 0.5f), b));
    CHECK(!triangle_overlaps_box(v3(2, 0.5f, 0), v3(0.5f, 2, 0), v3(0.5f, 2, 0), b));
    /* An empty box overlaps nothing. */
    CHECK(!triangle_overlaps_box(v3(0, 0, 0), v3(0.5f, 0, 0), v3(0, 0.5f, 0), box_empty()));
}

/* Random triangles against random boxes: a triangle with any sample point
 * inside the box must overlap; vertices placed exactly on a face (the rest
 * outside) must overlap; an overlap answer of false must have no sample
 * point inside. */
static void test_triangle_box_random(void)
{
    int false_neg = 0, touch_miss = 0, n_overlap = 0, n_sep = 0;
    for (int i = 0; i < 20000; i++) {
        vec3 lo = rnd_v3(-10, 10), ext = rnd_v3(0.01f, 5);
        box3 b = box(lo, v3_add(lo, ext));
        vec3 ctr = box_center(b);
        vec3 a = v3_add(ctr, rnd_v3(-6, 6)), bb = v3_add(ctr, rnd_v3(-6, 6)), c = v3_add(ctr, rnd_v3(-6, 6));
        bool ov = triangle_overlaps_box(a, bb, c, b);
        n_overlap += ov;
        n_sep += !ov;
        bool sample_inside = false;
        for (int k = 0; k < 64 && !sample_inside; k++) {
            float s = rnd(0, 1), w = rnd(0, 1 - s);
            vec3 q = v3_add(v3_add(v3_scale(a, 1 - s - w), v3_scale(bb, s)), v3_scale(c, w));
            sample_inside = q.x >= b.lo.x && q.x <= b.hi.x && q.y >= b.lo.y && q.y <= b.hi.y && q.z >= b.lo.z && q.z <= b.hi.z;
        }
        false_neg += sample_inside && !ov;

        /* One vertex pinned to a random point of a random face. */
        int ax = i % 3;
        float f[3] = {rnd(b.lo.x, b.hi.x), rnd(b.lo.y, b.hi.y), rnd(b.lo.z, b.hi.z)};
        f[ax] = v3_get(i & 4 ? b.hi : b.lo, ax);
        vec3 pin = v3(f[0], f[1], f[2]);
        touch_miss += !triangle_overlaps_box(pin, a, c, b) || !triangle_overlaps_box(bb, c, pin, b);
        /* Two vertices on the face plane, segment inside the face. */
        float g[3] = {rnd(b.lo.x, b.hi.x), rnd(b.lo.y, b.hi.y), rnd(b.lo.z, b.hi.z)};
        g[ax] = f[ax];
        vec3 out = pin;
        float *op = ax == 0 ? &out.x : ax == 1 ? &out.y : &out.z;
        *op += (i & 4) ? 3.0f : -3.0f;
        touch_miss += !triangle_overlaps_box(pin, v3(g[0], g[1], g[2]), out, b);

        /* A vertex on a box corner, the triangle (up to rounding) in a plane
         * that supports the box there: every axis, the normal included,
         * sees the triangle and the box meet in the one corner value. */
        vec3 corner = v3(i & 1 ? b.hi.x : b.lo.x, i & 2 ? b.hi.y : b.lo.y, i & 8 ? b.hi.z : b.lo.z);
        vec3 w = v3((i & 1 ? 1 : -1) * rnd(0.1f, 1), (i & 2 ? 1 : -1) * rnd(0.1f, 1), (i & 8 ? 1 : -1) * rnd(0.1f, 1));
        vec3 t1 = v3_cross(w, rnd_v3(-1, 1)), t2 = v3_cross(w, t1);
        vec3 p1 = v3_madd(corner, t1, rnd(-5, 5)), p2 = v3_madd(corner, t2, rnd(-5, 5));
        touch_miss += !triangle_overlaps_box(corner, p1, p2, b) || !triangle_overlaps_box(p2, corner, p1, b);
    }
    CHECK_MSG(false_neg == 0, "%d triangles with a point inside the box reported separated", false_neg);
    CHECK_MSG(touch_miss == 0, "%d triangles touching a box face reported separated", touch_miss);
    CHECK(n_overlap > 1000 && n_sep > 1000);
}

static void test_sphere_box_overlap(void)
{
    box3 b = box(v3(-1, -1, -1), v3(1, 1, 1));
    CHECK(sphere_overlaps_box(sph(v3(0, 0, 0), 0.5f), b));       /* inside */
    CHECK(sphere_overlaps_box(sph(v3(0, 0, 0), 10.0f), b));      /* containing */
    CHECK(sphere_overlaps_box(sph(v3(0, 0, 2), 1.0f), b));       /* touching the face z = 1 */
    CHECK(!sphere_overlaps_box(sph(v3(0, 0, 2), nextafterf(1.0f, 0.0f)), b));
    CHECK(sphere_overlaps_box(sph(v3(0.9f, -0.9f, -1.5f), 0.6f), b)); /* through a face */
    /* Near the corner (1,1,1): its bounds overlap the box but the corner is
     * at distance sqrt(3) > 1.7. */
    CHECK(!sphere_overlaps_box(sph(v3(2, 2, 2), 1.7f), b));
    CHECK(sphere_overlaps_box(sph(v3(2, 2, 2), 1.75f), b));
    /* Exactly touching an edge (3-4-5) and a corner (1-2-2-3), dyadic. */
    CHECK(sphere_overlaps_box(sph(v3(1.75f, 2.0f, 0.0f), 1.25f), b));
    CHECK(!sphere_overlaps_box(sph(v3(1.75f, 2.0f, 0.0f), nextafterf(1.25f, 0.0f)), b));
    CHECK(sphere_overlaps_box(sph(v3(1.25f, 1.5f, 1.5f), 0.75f), b));
    CHECK(!sphere_overlaps_box(sph(v3(1.25f, 1.5f, 1.5f), nextafterf(0.75f, 0.0f)), b));
    CHECK(!sphere_overlaps_box(sph(v3(0, 0, 0), 1.0f), box_empty()));
}

static void test_overlap_api(void)
{
    prims_t p;
    char err[256];
    prims_init(&p);
    prims_add_vertex(&p, v3(2, 0.5f, 0));
    prims_add_vertex(&p, v3(0.5f, 2, 0));
    prims_add_vertex(&p, v3(3, 3, -3.5f));
    prims_add_triangle(&p, 0, 1, 2);
    prims_add_sphere(&p, v3(2, 2, 2), 1.7f);
    prims_add_sphere(&p, v3(0, 0, 2), 1.0f);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    box3 b = box(v3(-1, -1, -1), v3(1, 1, 1));
    CHECK(box_overlap(prim_bounds(&p, 0), b) && !prim_overlaps_box(&p, 0, b));
    CHECK(box_overlap(prim_bounds(&p, 1), b) && !prim_overlaps_box(&p, 1, b));
    CHECK(prim_overlaps_box(&p, 2, b));
    box3 big = box(v3(-1, -1, -1), v3(3, 3, 3));
    CHECK(prim_overlaps_box(&p, 0, big) && prim_overlaps_box(&p, 1, big));
    prims_free(&p);
}

/* ---------------------------------------------------------------------- */
/* float vs double                                                         */

/* The float and double t must agree within 1e-5 relative wherever the
 * problem itself is well conditioned. Where it is not, float rounding of
 * the intermediate values is amplified, so the tolerance grows with the
 * condition number (first-order growth measured here, with a 10-20x margin):
 * - triangles: t is the ray/plane distance, whose error grows like 1/cos
 *   of the angle between ray and normal (measured: rel error * cos stays
 *   below 6e-8), so 1e-5 for cos >= 0.05 and 5e-7 / cos below;
 * - spheres near tangency: sqrt(disc) amplifies the error of disc by
 *   r / half-chord ~ 1 / sqrt(2 g), g = boundary distance / r (measured
 *   about 4e-8 / sqrt(g)), so 1e-5 for g >= 0.01 and 1e-6 / sqrt(g) below;
 *   and t is measured against max(|t|, |org - centre| / |dir|), the scale
 *   of the inputs, so an origin near the surface (t near 0) is fair. */
static double rel_err(double a, double b, double scale) { return fabs(a - b) / fmax(fmax(fabs(b), scale), 1e-30); }

static void test_float_double_triangles(void)
{
    int both = 0, disagree = 0, unexplained = 0, far = 0, grazing = 0;
    double worst = 0, worst_graze = 0;
    for (int k = 0; k < 50; k++) {
        vec3 a = rnd_v3(-1, 1), b = rnd_v3(-1, 1), c = rnd_v3(-1, 1);
        dvec3 n = dv3_cross(dv3_sub(dv3(b), dv3(a)), dv3_sub(dv3(c), dv3(a)));
        for (int i = 0; i < 2000; i++) {
            /* Aim at the plane near the triangle, edges included: weights
             * from [-0.2, 1.2] that sum to 1. */
            float s = rnd(-0.2f, 1.2f), w = rnd(-0.2f, 1.2f);
            vec3 target = v3_add(v3_add(v3_scale(a, 1 - s - w), v3_scale(b, s)), v3_scale(c, w));
            vec3 org = rnd_v3(-5, 5);
            ray_t r = ray_through(org, target);
            float tf, u, v;
            double td;
            bool hf = tri_hit(a, b, c, &r, &tf, &u, &v), hd = triangle_intersect_double(a, b, c, &r, &td);
            if (hf && hd) {
                dvec3 d = dv3(r.dir);
                double cosang = fabs(dv3_dot(n, d)) / sqrt(dv3_dot(n, n) * dv3_dot(d, d));
                double e = rel_err(tf, td, 0.0);
                both++;
                if (cosang >= 0.05) {
                    worst = fmax(worst, e);
                    far += e > 1e-5;
                } else {
                    grazing++;
                    worst_graze = fmax(worst_graze, e * cosang);
                    far += e > 5e-7 / cosang;
                }
            } else if (hf != hd) {
                /* Allowed only at an edge: the hit point lies within a
                 * float rounding of the boundary. */
                disagree++;
                double t = hf ? tf : td;
                unexplained += triangle_boundary_distance(a, b, c,
                                   (dvec3){org.x + r.dir.x * t, org.y + r.dir.y * t, org.z + r.dir.z * t}) > 1e-5;
            }
        }
    }
    CHECK_MSG(far == 0, "%d of %d triangle hits differ beyond tolerance (worst %.3g, grazing %.3g / cos)", far, both, worst, worst_graze);
    CHECK_MSG(unexplained == 0, "%d of %d float/double hit-miss disagreements are away from edges", unexplained, disagree);
    CHECK(both > 20000 && grazing < both / 10);
    printf("triangles: %d hits compared, worst relative t error %.3g (%d grazing: %.3g / cos), %d edge disagreements\n",
           both, worst, grazing, worst_graze, disagree);
}

static void test_float_double_spheres(void)
{
    prims_t p;
    char err[256];
    prims_init(&p);
    for (int k = 0; k < 50; k++) prims_add_sphere(&p, rnd_v3(-2, 2), rnd(0.05f, 1.5f));
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    int both = 0, disagree = 0, unexplained = 0, far = 0, grazing = 0;
    double worst = 0, worst_graze = 0;
    counters_t cnt = {0};
    for (uint32_t id = 0; id < p.count; id++) {
        sphere_t s = p.spheres[p.index[id]];
        for (int i = 0; i < 2000; i++) {
            /* Half the origins inside the sphere, half anywhere. */
            vec3 org = (i & 1) ? v3_add(s.center, v3_scale(rnd_v3(-0.5f, 0.5f), s.radius)) : rnd_v3(-6, 6);
            ray_t r = ray_through(org, v3_add(s.center, v3_scale(rnd_v3(-1.2f, 1.2f), s.radius)));
            hit_t h = hit_none(&r);
            double td;
            bool hf = prim_intersect(&p, id, &r, &h, &cnt), hd = prim_intersect_double(&p, id, &r, &td);
            if (hf && hd) {
                vec3 f = v3_sub(r.org, s.center);
                double e = rel_err(h.t, td, v3_len(f) / v3_len(r.dir));
                double g = prim_boundary_distance(&p, id, &r, 0.0) / s.radius;
                both++;
                if (g >= 0.01) {
                    worst = fmax(worst, e);
                    far += e > 1e-5;
                } else {
                    grazing++;
                    worst_graze = fmax(worst_graze, e * sqrt(fmax(g, 0.0)));
                    far += e > 1e-6 / sqrt(fmax(g, 1e-300));
                }
            } else if (hf != hd) {
                disagree++;
                unexplained += fabs(prim_boundary_distance(&p, id, &r, 0.0)) > 1e-5 * s.radius;
            }
        }
    }
    CHECK_MSG(far == 0, "%d of %d sphere hits differ beyond tolerance (worst %.3g, grazing %.3g / sqrt(g))", far, both, worst, worst_graze);
    CHECK_MSG(unexplained == 0, "%d of %d sphere hit-miss disagreements are not grazes", unexplained, disagree);
    CHECK(both > 50000 && grazing < both / 10);
    printf("spheres: %d hits compared, worst relative t error %.3g (%d grazing: %.3g / sqrt(g)), %d graze disagreements\n",
           both, worst, grazing, worst_graze, disagree);
    prims_free(&p);
}

/* ---------------------------------------------------------------------- */
/* boundary distance                                                       */

static void test_boundary_distance(void)
{
    float h = (float)(sqrt(3.0) / 2.0);
    vec3 a = v3(0, 0, 0), b = v3(1, 0, 0), c = v3(0.5f, h, 0);
    static const uint32_t tris[1][3] = {{0, 1, 2}};
    vec3 verts[3] = {a, b, c};
    prims_t p;
    build_mesh(&p, verts, 3, tris, 1);

    /* Centroid: the inradius 1/(2 sqrt 3), via the API at the hit distance. */
    ray_t r = make_ray(v3(0.5f, h / 3.0f, -1), v3(0, 0, 1), 0.0f, INFINITY);
    hit_t hit = hit_none(&r);
    counters_t cnt = {0};
    CHECK(prim_intersect(&p, 0, &r, &hit, &cnt));
    CHECK_NEAR(prim_boundary_distance(&p, 0, &r, hit.t), 1.0 / (2.0 * sqrt(3.0)), 1e-7);
    CHECK_NEAR(hit.u, 1.0 / 3, 1e-6);
    CHECK_NEAR(hit.v, 1.0 / 3, 1e-6);

    /* On an edge, at a vertex: 0. Beyond an edge and beyond a vertex. */
    dvec3 mid = {0.5, 0, 0}, onbc = {0.75, h / 2.0, 0}, vtx = {1, 0, 0};
    CHECK_NEAR(triangle_boundary_distance(a, b, c, mid), 0.0, 1e-12);
    CHECK_NEAR(triangle_boundary_distance(a, b, c, onbc), 0.0, 1e-7);
    CHECK_NEAR(triangle_boundary_distance(a, b, c, vtx), 0.0, 1e-12);
    dvec3 below = {0.5, -1, 0}, beyond = {-3, -4, 0}, above = {0.5, 0, 2};
    CHECK_NEAR(triangle_boundary_distance(a, b, c, below), 1.0, 1e-12);
    CHECK_NEAR(triangle_boundary_distance(a, b, c, beyond), 5.0, 1e-12);
    CHECK_NEAR(triangle_boundary_distance(a, b, c, above), 2.0, 1e-12); /* over the edge a-b, height 2 */
    /* An API ray hitting exactly on the edge a-b. */
    r = make_ray(v3(0.25f, 0, -1), v3(0, 0, 2), 0.0f, INFINITY);
    hit = hit_none(&r);
    CHECK(prim_intersect(&p, 0, &r, &hit, &cnt) && hit.t == 0.5f);
    CHECK_NEAR(prim_boundary_distance(&p, 0, &r, hit.t), 0.0, 1e-12);
    prims_free(&p);

    /* Sphere: r through the centre, 0 at a tangent, negative outside. */
    sphere_t s = sph(v3(0, 0, 10), 2.0f);
    r = make_ray(v3(0, 0, 0), v3(0, 0, 3), 0.0f, INFINITY);
    CHECK_NEAR(sphere_boundary_distance(s, &r), 2.0, 1e-12);
    r = make_ray(v3(0, 3, 0), v3(0, 0, 0.5f), 0.0f, INFINITY);
    CHECK_NEAR(sphere_boundary_distance(s, &r), -1.0, 1e-12);
    r = make_ray(v3(-2, 0, 0), v3(2, 0, 10), 0.0f, INFINITY); /* crosses the centre */
    CHECK_NEAR(sphere_boundary_distance(s, &r), 2.0, 1e-12);
}

/* vec3.h's inline f_min / f_max give libm's fminf / fmaxf bit for bit:
 * a quiet NaN on either side (two NaNs give a NaN), zeros (a zero of
 * either sign), infinities, denormals, random pairs. Signaling NaNs (no arithmetic makes one; scene input with one is
 * refused as not finite first) are left out: glibc answers NaN for them,
 * f_min treats them as quiet ones. */
static bool signaling(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return isnan(f) && !(u & 0x400000u);
}

static uint32_t float_bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static void test_min_max_as_libm(void)
{
    const float special[] = {0.0f, -0.0f, 1.0f, -1.0f, INFINITY, -INFINITY, NAN, -NAN, FLT_MIN, -FLT_MIN,
                             FLT_TRUE_MIN, -FLT_TRUE_MIN, FLT_MAX, -FLT_MAX, 1e-30f, 3.5f};
    const int ns = (int)(sizeof special / sizeof special[0]);
    uint32_t differ = 0, pairs = 0;
    uint64_t state = 99;
    for (int i = 0; i < ns + 20000; i++) {
        for (int j = 0; j < ns; j++) {
            float a, b = special[j];
            if (i < ns) a = special[i];
            else {
                state = state * 6364136223846793005ull + 1442695040888963407ull;
                uint32_t u = (uint32_t)(state >> 32);
                memcpy(&a, &u, sizeof a); /* any bit pattern, NaNs included */
                if (j & 1) b = a * 0.5f;
            }
            if (signaling(a) || signaling(b)) continue;
            if (a == 0.0f && b == 0.0f) { /* +0 and -0: equal, libm's sign varies with its build */
                pairs += 2;
                differ += f_min(a, b) != 0.0f || f_max(a, b) != 0.0f || f_min(b, a) != 0.0f || f_max(b, a) != 0.0f;
                continue;
            }
            if (isnan(a) && isnan(b)) { /* a NaN, whose payload libm takes from either side */
                pairs += 2;
                differ += !isnan(f_min(a, b)) || !isnan(f_max(a, b)) || !isnan(f_min(b, a)) || !isnan(f_max(b, a));
                continue;
            }
            pairs += 2;
            differ += float_bits(f_min(a, b)) != float_bits(fminf(a, b)) || float_bits(f_max(a, b)) != float_bits(fmaxf(a, b));
            differ += float_bits(f_min(b, a)) != float_bits(fminf(b, a)) || float_bits(f_max(b, a)) != float_bits(fmaxf(b, a));
        }
    }
    CHECK_MSG(differ == 0, "f_min/f_max differ from fminf/fmaxf on %u of %u ordered pairs", differ, pairs);
    printf("f_min/f_max: %u ordered pairs as fminf/fmaxf\n", pairs);
}

/* box4's union, point, store and area against box_union, box_grow and
 * box_area, bit for bit, on random boxes with special values (signed zeros,
 * infinities, NaN in the box that is added). */
static void test_box4_as_box_union(void)
{
    const float special[] = {0.0f, -0.0f, INFINITY, -INFINITY, NAN, FLT_MAX, -FLT_MAX, FLT_TRUE_MIN, 1.0f};
    uint32_t differ = 0, cases = 0;
    for (int i = 0; i < 20000; i++) {
        box3 acc = box_empty(), b;
        box4 acc4 = box4_empty();
        for (int k = 0; k < 8; k++) {
            float f[6];
            for (int j = 0; j < 6; j++)
                f[j] = (i + j + k) % 7 == 0 ? special[(i * 3 + j + k) % 9] : rnd(-100.0f, 100.0f);
            b = (box3){{f[0], f[1], f[2]}, {f[3], f[4], f[5]}};
            if (k % 3 == 2) {
                acc = box_grow(acc, b.lo);
                acc4 = box4_union(acc4, box4_point(&b.lo));
            } else {
                acc = box_union(acc, b);
                acc4 = box4_union(acc4, box4_load(&b));
            }
            box3 got = box4_store(acc4);
            float a = box_area(acc), a4 = box4_area(acc4);
            cases++;
            differ += memcmp(&got, &acc, sizeof got) != 0 || (float_bits(a) != float_bits(a4) && !(isnan(a) && isnan(a4)));
        }
    }
    CHECK_MSG(differ == 0, "box4 differs from box_union/box_area in %u of %u steps", differ, cases);
}

/* prim_split_bounds's arithmetic with box_union (the chopped triangle's
 * two sides: vertices on each side, crossing points on both). */
static void split_bounds_reference(const vec3 v[3], box3 box, int axis, float pos, box3 *left, box3 *right)
{
    box3 lh = box, rh = box;
    (&lh.hi.x)[axis] = pos;
    (&rh.lo.x)[axis] = pos;
    box3 l = box_empty(), r = box_empty();
    for (int i = 0; i < 3; i++) {
        vec3 a = v[i], b = v[(i + 1) % 3];
        float da = v3_get(a, axis) - pos, db = v3_get(b, axis) - pos;
        if (da <= 0.0f) l = box_union(l, (box3){a, a});
        if (da >= 0.0f) r = box_union(r, (box3){a, a});
        if ((da < 0.0f && db > 0.0f) || (da > 0.0f && db < 0.0f)) {
            vec3 c = v3_add(a, v3_scale(v3_sub(b, a), da / (da - db)));
            (&c.x)[axis] = pos;
            l = box_union(l, (box3){c, c});
            r = box_union(r, (box3){c, c});
        }
    }
    *left = box_meet(l, lh);
    *right = box_meet(r, rh);
}

static void test_split_bounds_box4(void)
{
    prims_t p;
    prims_init(&p);
    for (int i = 0; i < 500; i++) {
        vec3 c = rnd_v3(-5, 5);
        vec3 a = v3_add(c, rnd_v3(-3, 3)), b = v3_add(c, rnd_v3(-3, 3)), d = v3_add(c, rnd_v3(-3, 3));
        if (i % 5 == 0) a.y = b.y = -0.0f, d.y = 0.0f; /* in a plane through signed zeros */
        prims_add_triangle(&p, prims_add_vertex(&p, a), prims_add_vertex(&p, b), prims_add_vertex(&p, d));
    }
    CHECK(prims_finish(&p, NULL, 0) == 0);
    uint32_t differ = 0, cases = 0;
    for (uint32_t id = 0; id < p.count; id++) {
        vec3 v[3];
        tri_verts(&p, p.index[id], &v[0], &v[1], &v[2]);
        for (int axis = 0; axis < 3; axis++) {
            box3 box = p.bounds[id];
            float lo = v3_get(box.lo, axis), hi = v3_get(box.hi, axis);
            const float at[] = {lo, hi, 0.0f, -0.0f, lo + (hi - lo) * rnd(0.0f, 1.0f), v3_get(v[1], axis)};
            for (int k = 0; k < 6; k++) {
                box3 l, r, el, er;
                prim_split_bounds(&p, id, box, axis, at[k], &l, &r);
                split_bounds_reference(v, box, axis, at[k], &el, &er);
                cases++;
                differ += memcmp(&l, &el, sizeof l) != 0 || memcmp(&r, &er, sizeof r) != 0;
            }
        }
    }
    CHECK_MSG(differ == 0, "prim_split_bounds differs from its box_union form in %u of %u splits", differ, cases);
    prims_free(&p);
}

int main(void)
{
    test_min_max_as_libm();
    test_box4_as_box_union();
    test_split_bounds_box4();
    test_triangle_basic();
    test_triangle_edges_vertices();
    test_watertight_quad();
    test_watertight_fan();
    test_watertight_cube();
    test_watertight_tetrahedron();
    test_triangle_parallel();
    test_triangle_trange();
    test_triangle_degenerate();
    test_counters_and_untouched();
    test_sphere_basic();
    test_sphere_trange();
    test_sphere_tiny_far();
    test_sphere_api();
    test_finish_errors();
    test_triangle_box_overlap();
    test_triangle_box_random();
    test_sphere_box_overlap();
    test_overlap_api();
    test_float_double_triangles();
    test_float_double_spheres();
    test_boundary_distance();
    return check_report();
}
