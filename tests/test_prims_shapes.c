/* test_prims_shapes.c: unit tests of the cone and polygon primitives and
 * of polygon_triangulate (test_prims.c covers triangles and spheres).
 *
 * Cones: exact hits on cylinders and cones (hand-computed t), open ends,
 * the axis and generator lines, rays from inside, the t range, non-unit
 * directions, normals, tight bounds, box overlap (touching, near misses,
 * random boxes around surface points, certified-disjoint boxes), float vs
 * double, boundary distance, prims_finish validation.
 * Polygons: a 144-gon gear face (teeth hit, notches miss), an L-shape,
 * adjacent quads and closed polyhedra (watertightness, measured against the
 * textbook dominant-axis projection), degenerate polygons, triangulation
 * (areas, centroids, windings, collinear and non-simple input), box
 * overlap, counters, float vs double, boundary distance, validation.
 *
 * Build: gcc -O2 -std=gnu11 -Wall -Wextra -ffp-contract=off -D_GNU_SOURCE -o /tmp/test_prims_shapes \
 *   tests/test_prims_shapes.c prims/prims.c prims/triangle.c prims/sphere.c prims/cone.c \
 *   prims/polygon.c prims/overlap.c -lm
 * Random inputs come from a fixed seed, so every run tests the same rays. */
#include "../prims/prims.h"
#include "../prims/prims_internal.h"
#include "check.h"

#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------------- */
/* helpers                                                                 */

#define PRIMS_TEST_SEED 0x0c0de5ba5e5eedull
#include "prims_testlib.h"

static cone_t cone(vec3 b, float rb, vec3 a, float ra)
{
    cone_t c = {b, rb, a, ra};
    return c;
}

static bool cone_hit(cone_t c, const ray_t *r, float *t)
{
    float u;
    return cone_intersect(c, r, r->tfar, t, &u);
}

static dvec3 dvec(double x, double y, double z)
{
    dvec3 r = {x, y, z};
    return r;
}
static dvec3 dmadd(dvec3 a, dvec3 b, double s) { return dvec(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s); }
static double dlen(dvec3 a) { return sqrt(dv3_dot(a, a)); }
static vec3 tof(dvec3 a) { return v3((float)a.x, (float)a.y, (float)a.z); }

static bool in_box(vec3 q, box3 b)
{
    return q.x >= b.lo.x && q.x <= b.hi.x && q.y >= b.lo.y && q.y <= b.hi.y && q.z >= b.lo.z && q.z <= b.hi.z;
}

/* Distance from a point to a box (0 inside), in double. */
static double point_box_distance(dvec3 p, box3 b)
{
    double dx = fmax(fmax(b.lo.x - p.x, 0.0), p.x - b.hi.x);
    double dy = fmax(fmax(b.lo.y - p.y, 0.0), p.y - b.hi.y);
    double dz = fmax(fmax(b.lo.z - p.z, 0.0), p.z - b.hi.z);
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* A cone's frame in double, for building test points on its surface. */
typedef struct {
    dvec3 b, ax, w, e1, e2;
    double len, rb, ra;
} cframe_t;

static cframe_t cframe(cone_t c)
{
    cframe_t f;
    f.b = dv3(c.base);
    dvec3 ax = dv3_sub(dv3(c.apex), f.b);
    f.ax = ax;
    f.len = dlen(ax);
    f.w = dvec(ax.x / f.len, ax.y / f.len, ax.z / f.len);
    dvec3 helper = fabs(f.w.x) < 0.6 ? dvec(1, 0, 0) : dvec(0, 1, 0);
    dvec3 e1 = dv3_cross(f.w, helper);
    double l = dlen(e1);
    f.e1 = dvec(e1.x / l, e1.y / l, e1.z / l);
    f.e2 = dv3_cross(f.w, f.e1);
    f.rb = c.base_radius;
    f.ra = c.apex_radius;
    return f;
}

/* The surface point at height fraction s in [0,1] and angle th, and its
 * outward unit normal. */
static dvec3 cone_point(const cframe_t *f, double s, double th, dvec3 *normal)
{
    double r = f->rb + (f->ra - f->rb) * s;
    dvec3 e = dmadd(dvec(f->e1.x * cos(th), f->e1.y * cos(th), f->e1.z * cos(th)), f->e2, sin(th));
    if (normal) {
        double k = (f->ra - f->rb) / f->len;
        dvec3 n = dmadd(e, f->w, -k);
        double l = dlen(n);
        *normal = dvec(n.x / l, n.y / l, n.z / l);
    }
    return dmadd(dmadd(f->b, f->ax, s), e, r); /* b + s (a - b): exactly a at s = 1 */
}

/* A random valid cone: a cylinder, a pointed cone either way, or a
 * truncated one either way. */
static cone_t random_cone(int kind)
{
    vec3 b = rnd_v3(-3, 3), a;
    do a = rnd_v3(-3, 3);
    while (v3_len(v3_sub(a, b)) < 0.5f);
    float rb = rnd(0.1f, 1.5f), ra = rnd(0.1f, 1.5f);
    switch (kind % 5) {
    case 0: ra = rb; break;
    case 1: ra = 0.0f; break;
    case 2: rb = 0.0f; break;
    default: break;
    }
    return cone(b, rb, a, ra);
}

/* ---------------------------------------------------------------------- */
/* cones: intersection                                                     */

/* Cylinder along z from (0,0,0) to (0,0,4), radius 1. */
static const cone_t CYL = {{0, 0, 0}, 1.0f, {0, 0, 4}, 1.0f};

static void test_cone_cylinder_hits(void)
{
    float t = -1, u = -1;
    /* From the side through the axis: enters at x = -1 (t = 4), leaves at
     * x = 1 (t = 6); all exact in float. */
    ray_t r = make_ray(v3(-5, 0, 2), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(cone_intersect(CYL, &r, r.tfar, &t, &u) && t == 4.0f && u == 0.5f);
    double td;
    CHECK(cone_intersect_double(CYL, &r, &td) && td == 4.0);
    /* Off the axis by 0.6: x = -sqrt(1 - 0.36) = -0.8, t = 4.2. */
    r = make_ray(v3(-5, 0.6f, 1), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(cone_hit(CYL, &r, &t));
    CHECK_NEAR(t, 4.2, 1e-6);
    /* Oblique: (-5,0,1) + t (1,0,0.25) reaches x = -1 at t = 4, z = 2. */
    r = make_ray(v3(-5, 0, 1), v3(1, 0, 0.25f), 0.0f, INFINITY);
    CHECK(cone_intersect(CYL, &r, r.tfar, &t, &u) && t == 4.0f && u == 0.5f);
    /* Non-unit directions: t in units of dir. */
    r = make_ray(v3(-5, 0, 2), v3(2, 0, 0), 0.0f, INFINITY);
    CHECK(cone_hit(CYL, &r, &t) && t == 2.0f);
    r = make_ray(v3(-5, 0, 2), v3(0.25f, 0, 0), 0.0f, INFINITY);
    CHECK(cone_hit(CYL, &r, &t) && t == 16.0f);
    r = make_ray(v3(-3, -4, 2), v3(0.3f, 0.4f, 0), 0.0f, INFINITY); /* |dir| = 0.5, distance 4 to the wall */
    CHECK(cone_hit(CYL, &r, &t));
    CHECK_NEAR(t, 8.0, 1e-5);
    /* From inside: the far wall. */
    r = make_ray(v3(0, 0, 2), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(cone_hit(CYL, &r, &t) && t == 1.0f);
    r = make_ray(v3(0.5f, 0, 3), v3(-1, 0, 0), 0.0f, INFINITY);
    CHECK(cone_hit(CYL, &r, &t) && t == 1.5f);
    /* In through the open top, onto the inside wall: (0,0,6) + t (0.25,0,-1)
     * reaches x = 1 at t = 4, z = 2. */
    r = make_ray(v3(0, 0, 6), v3(0.25f, 0, -1), 0.0f, INFINITY);
    CHECK(cone_intersect(CYL, &r, r.tfar, &t, &u) && t == 4.0f && u == 0.5f);

    /* Misses. Past the open end: the line crosses the cylinder at z = 4.5. */
    r = make_ray(v3(-5, 0, 4.5f), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(!cone_hit(CYL, &r, &t));
    CHECK(!cone_intersect_double(CYL, &r, &td));
    r = make_ray(v3(-5, 0, -0.001f), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(!cone_hit(CYL, &r, &t));
    /* Through the tube and out of the far end without touching: (0,0,-1) +
     * t (0.1,0,1) reaches the wall x = 1 only at z = 9. */
    r = make_ray(v3(0, 0, -1), v3(0.1f, 0, 1), 0.0f, INFINITY);
    CHECK(!cone_hit(CYL, &r, &t));
    /* Exactly on the axis: never touches the side. Also from inside. */
    r = make_ray(v3(0, 0, -5), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(!cone_hit(CYL, &r, &t));
    CHECK(!cone_intersect_double(CYL, &r, &td));
    r = make_ray(v3(0, 0, 2), v3(0, 0, -3), 0.0f, INFINITY);
    CHECK(!cone_hit(CYL, &r, &t));
    /* Along a generator line (lying in the surface): no isolated hit. */
    r = make_ray(v3(1, 0, -5), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(!cone_hit(CYL, &r, &t));
    CHECK(!cone_intersect_double(CYL, &r, &td));
    /* Parallel to the axis outside; beside it; pointing away. */
    r = make_ray(v3(1.5f, 0, -5), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(!cone_hit(CYL, &r, &t));
    r = make_ray(v3(-5, 1.01f, 2), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(!cone_hit(CYL, &r, &t));
    r = make_ray(v3(-5, 0, 2), v3(-1, 0, 0), 0.0f, INFINITY);
    CHECK(!cone_hit(CYL, &r, &t));
    r = make_ray(v3(-5, 0, 2), v3(0, 0, 0), 0.0f, INFINITY);
    CHECK(!cone_hit(CYL, &r, &t));
    /* Tangent: the line x = -5..5 at y = 1 touches at (0,1,2), t = 5. */
    r = make_ray(v3(-5, 1, 2), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(cone_hit(CYL, &r, &t) && t == 5.0f);

    /* A tilted cylinder, hit perpendicular to its axis through the axis:
     * axis (1,1,1)/sqrt3 from the origin, length 2 sqrt 3, radius 1; the
     * ray starts 5 from the axis point (1,1,1). */
    cone_t tc = cone(v3(0, 0, 0), 1.0f, v3(2, 2, 2), 1.0f);
    vec3 uperp = v3_norm(v3(1, -1, 0));
    r = make_ray(v3_madd(v3(1, 1, 1), uperp, 5.0f), v3_scale(uperp, -1.0f), 0.0f, INFINITY);
    CHECK(cone_intersect(tc, &r, r.tfar, &t, &u));
    CHECK_NEAR(t, 4.0, 2e-6);
    CHECK_NEAR(u, 0.5, 1e-6);
    CHECK(cone_intersect_double(tc, &r, &td));
    CHECK_NEAR(td, 4.0, 2e-6);
}

static void test_cone_cone_hits(void)
{
    float t = -1, u = -1;
    double td;
    /* Base (0,0,0) radius 2, apex (0,0,2) radius 1: r(z) = 2 - z/2. */
    cone_t c = cone(v3(0, 0, 0), 2.0f, v3(0, 0, 2), 1.0f);
    ray_t r = make_ray(v3(-5, 0, 1), v3(1, 0, 0), 0.0f, INFINITY); /* r(1) = 1.5 */
    CHECK(cone_intersect(c, &r, r.tfar, &t, &u) && t == 3.5f && u == 0.5f);
    CHECK(cone_intersect_double(c, &r, &td) && td == 3.5);
    /* Slanted: (4,0,0) + t (-2,0,1): x = 4 - 2t equals r(t) = 2 - t/2 at
     * t = 4/3 (z = 4/3, inside 0..2). */
    r = make_ray(v3(4, 0, 0), v3(-2, 0, 1), 0.0f, INFINITY);
    CHECK(cone_hit(c, &r, &t));
    CHECK_NEAR(t, 4.0 / 3.0, 1e-6);
    /* From inside at z = 1 the far wall: 1.5. */
    r = make_ray(v3(0, 0, 1), v3(0, 1, 0), 0.0f, INFINITY);
    CHECK(cone_hit(c, &r, &t) && t == 1.5f);
    /* Down the axis of this truncated cone: the tip (z = 4) is beyond the
     * apex plane, so no hit. */
    r = make_ray(v3(0, 0, 10), v3(0, 0, -1), 0.0f, INFINITY);
    CHECK(!cone_hit(c, &r, &t));
    CHECK(!cone_intersect_double(c, &r, &td));
    /* Through both openings: (0,0,10) + t (0.1,0,-1) is at radius
     * 1 - 0.1 z, which equals r(z) = 2 - z/2 only at z = 2.5 (above the
     * apex plane) and -(2 - z/2) at z = 5 (the other nappe). It enters the
     * top opening at radius 0.8 < 1 and leaves the base one at 1 < 2. */
    r = make_ray(v3(0, 0, 10), v3(0.1f, 0, -1), 0.0f, INFINITY);
    CHECK(!cone_hit(c, &r, &t));

    /* Pointed cone: base (0,0,0) radius 1, apex (0,0,1) radius 0. Down the
     * axis, the ray touches the tip (z = 1, t = 2 from z = -1). */
    cone_t pc = cone(v3(0, 0, 0), 1.0f, v3(0, 0, 1), 0.0f);
    r = make_ray(v3(0, 0, -1), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(cone_intersect(pc, &r, r.tfar, &t, &u) && t == 2.0f && u == 1.0f);
    /* From the side at z = 0.5 (radius 0.5). */
    r = make_ray(v3(3, 0, 0.5f), v3(-1, 0, 0), 0.0f, INFINITY);
    CHECK(cone_hit(pc, &r, &t) && t == 2.5f);
    /* Parallel to the axis at x = 0.25 from below: only the wall at z = 0.75
     * (the other nappe, above the tip, is cut away). */
    r = make_ray(v3(0.25f, 0, -3), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK(cone_hit(pc, &r, &t) && t == 3.75f);
    r.tnear = 3.8f;
    CHECK(!cone_hit(pc, &r, &t));

    /* Widening the other way (ra > rb) and pointing down: base (1,1,1)
     * radius 0.5, apex (1,1,-1) radius 1.5. At z = 0 (h = 1) the radius is
     * 1, so a ray from x = -4 along x at y = 1, z = 0 meets x = 0 at t = 4. */
    cone_t wc = cone(v3(1, 1, 1), 0.5f, v3(1, 1, -1), 1.5f);
    r = make_ray(v3(-4, 1, 0), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(cone_intersect(wc, &r, r.tfar, &t, &u) && t == 4.0f && u == 0.5f);
    CHECK(cone_intersect_double(wc, &r, &td) && td == 4.0);
    /* Base radius 0: the tip is at the base. */
    cone_t bc = cone(v3(0, 0, 0), 0.0f, v3(0, 0, 2), 2.0f); /* r(z) = z */
    r = make_ray(v3(-5, 0, 1.5f), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(cone_hit(bc, &r, &t) && t == 3.5f);
}

/* A cylinder and cones of radius 1e-3 about 141 from the ray origins: the
 * textbook discriminant b^2 - a c is rounding noise there (checked: it gets
 * half of these rays wrong), the rewritten one is not. Rays aimed at 0.9 r
 * across the line of sight hit, at 1.1 r miss. */
static void test_cone_tiny_far(void)
{
    int textbook_wrong = 0;
    for (int variant = 0; variant < 3; variant++) {
        float rr = 1e-3f;
        cone_t c = cone(v3(100, 100, 99), rr, v3(100, 100, 101), variant == 0 ? rr : variant == 1 ? 0.0f : 2 * rr);
        int miss_in = 0, hit_out = 0, dbl_bad = 0;
        for (int i = 0; i < 4000; i++) {
            double z = rndd(99.5, 100.5), hfrac = (z - 99) / 2;
            double rad_here = rr * (variant == 0 ? 1.0 : variant == 1 ? 1 - hfrac : 1 + hfrac);
            double off = ((i & 1) ? 1.1 : rndd(0, 0.9)) * rad_here * ((i & 2) ? 1 : -1);
            /* Across the line of sight from (0,0,z), which looks along (1,1,0). */
            vec3 target = v3((float)(100 + off / sqrt(2.0)), (float)(100 - off / sqrt(2.0)), (float)z);
            ray_t r = make_ray(v3(0, 0, (float)z), v3(target.x, target.y, 0), 0.0f, INFINITY);
            float t;
            double td;
            bool hit = cone_hit(c, &r, &t);
            if (i & 1) hit_out += hit;
            else {
                miss_in += !hit;
                dbl_bad += !(cone_intersect_double(c, &r, &td) && hit && fabs(t - td) <= 1e-6 * td);
            }
            if (variant == 0) { /* the textbook discriminant, same frame */
                float qx = -100, qy = -100, dx = target.x, dy = target.y;
                float a = dx * dx + dy * dy, b = qx * dx + qy * dy, cc = qx * qx + qy * qy - rr * rr;
                volatile float disc = b * b - a * cc;
                textbook_wrong += (disc >= 0.0f) != !(i & 1);
            }
        }
        CHECK_MSG(miss_in == 0 && hit_out == 0 && dbl_bad == 0, "variant %d: %d misses inside, %d hits outside, %d double disagreements",
                  variant, miss_in, hit_out, dbl_bad);
    }
    CHECK_MSG(textbook_wrong > 1000, "textbook discriminant wrong %d times", textbook_wrong); /* the premise */
}

static void test_cone_trange(void)
{
    float t;
    double td;
    ray_t r = make_ray(v3(-5, 0, 2), v3(1, 0, 0), 4.0f, INFINITY); /* roots 4 and 6 */
    CHECK(cone_hit(CYL, &r, &t) && t == 4.0f); /* t == tnear is in */
    r.tnear = nextafterf(4.0f, INFINITY);
    CHECK(cone_hit(CYL, &r, &t) && t == 6.0f); /* the first root is out: far wall */
    CHECK(cone_intersect_double(CYL, &r, &td) && td == 6.0);
    r.tnear = 6.0f;
    CHECK(cone_hit(CYL, &r, &t) && t == 6.0f);
    r.tnear = nextafterf(6.0f, INFINITY);
    CHECK(!cone_hit(CYL, &r, &t));
    r = make_ray(v3(-5, 0, 2), v3(1, 0, 0), 0.0f, 4.0f);
    CHECK(!cone_hit(CYL, &r, &t)); /* t == tmax is out, 6 even more so */
    CHECK(!cone_intersect_double(CYL, &r, &td));
    r.tfar = nextafterf(4.0f, INFINITY);
    CHECK(cone_hit(CYL, &r, &t) && t == 4.0f);
    /* tmax is the argument. */
    r.tfar = INFINITY;
    float u;
    CHECK(!cone_intersect(CYL, &r, 4.0f, &t, &u));
    CHECK(cone_intersect(CYL, &r, 4.5f, &t, &u) && t == 4.0f);
    /* Behind the origin, and a negative tnear. */
    r = make_ray(v3(5, 0, 2), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK(!cone_hit(CYL, &r, &t));
    r.tnear = -100.0f;
    CHECK(cone_hit(CYL, &r, &t) && t == -6.0f);
}

static void test_cone_api_normals_counters(void)
{
    prims_t p;
    char err[256];
    prims_init(&p);
    CHECK(prims_add_cone(&p, v3(0, 0, 0), 1.0f, v3(0, 0, 4), 1.0f) == 0);
    CHECK(prims_add_cone(&p, v3(0, 0, 0), 2.0f, v3(0, 0, 2), 1.0f) == 1);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    CHECK(p.ncones == 2 && p.kind[0] == PRIM_CONE && p.index[1] == 1);
    counters_t c = {0};

    ray_t r = make_ray(v3(-5, 0, 2), v3(1, 0, 0), 0.0f, 100.0f);
    hit_t h = hit_none(&r);
    CHECK(prim_intersect(&p, 0, &r, &h, &c) && h.t == 4.0f && h.prim == 0 && h.u == 0.5f && h.v == 0.0f);
    vec3 n = prim_normal(&p, &h, &r);
    CHECK(n.x == -1.0f && n.y == 0.0f && n.z == 0.0f); /* outward, not flipped */
    /* Same test again: 4 is not < 4; a miss leaves the record alone. */
    hit_t before = h;
    CHECK(!prim_intersect(&p, 0, &r, &h, &c));
    CHECK(memcmp(&before, &h, sizeof h) == 0);
    CHECK(c.prim_tests == 2 && c.prim_hits == 1);
    /* The far wall from inside: normal still outward (+x). */
    ray_t in = make_ray(v3(0, 0, 2), v3(1, 0, 0), 0.0f, 100.0f);
    h = hit_none(&in);
    CHECK(prim_intersect(&p, 0, &in, &h, &c) && h.t == 1.0f);
    n = prim_normal(&p, &h, &in);
    CHECK_NEAR(n.x, 1.0, 1e-7);
    CHECK_NEAR(n.y, 0.0, 1e-7);
    CHECK_NEAR(n.z, 0.0, 1e-7);
    /* Cone normal: (-1, 0, 1/2) normalised at (-1.5, 0, 1). */
    r = make_ray(v3(-5, 0, 1), v3(1, 0, 0), 0.0f, 100.0f);
    h = hit_none(&r);
    CHECK(prim_intersect(&p, 1, &r, &h, &c) && h.t == 3.5f);
    n = prim_normal(&p, &h, &r);
    CHECK_NEAR(n.x, -2.0 / sqrt(5.0), 1e-6);
    CHECK_NEAR(n.y, 0.0, 1e-7);
    CHECK_NEAR(n.z, 1.0 / sqrt(5.0), 1e-6);
    /* Occlusion counts the same way. */
    CHECK(prim_occluded(&p, 0, &r, &c));
    ray_t miss = make_ray(v3(-5, 0, 4.5f), v3(1, 0, 0), 0.0f, 100.0f);
    CHECK(!prim_occluded(&p, 0, &miss, &c));
    hit_t junk = {42.0f, 0.125f, 0.5f, 7};
    h = junk;
    CHECK(!prim_intersect(&p, 1, &miss, &h, &c));
    CHECK(memcmp(&junk, &h, sizeof h) == 0);
    CHECK(c.prim_tests == 7 && c.prim_hits == 4);
    CHECK(c.box_tests == 0 && c.steps == 0);
    double td;
    CHECK(prim_intersect_double(&p, 0, &in, &td) && td == 1.0);
    CHECK(prims_memory(&p) >= 2 * sizeof(cone_t));

    /* The pointed tip's normal is the axis out of the tip. */
    cone_t pc = cone(v3(0, 0, 0), 1.0f, v3(0, 0, 1), 0.0f);
    n = cone_normal(pc, v3(0, 0, 1));
    CHECK(n.x == 0.0f && n.y == 0.0f && n.z == 1.0f);
    n = cone_normal(cone(v3(0, 0, 1), 0.0f, v3(0, 0, 0), 1.0f), v3(0, 0, 1));
    CHECK(n.z == 1.0f);
    prims_free(&p);
}

static void test_cone_bounds(void)
{
    /* Axis-aligned: exact. */
    box3 b = cone_bounds(CYL);
    CHECK(b.lo.x == -1.0f && b.lo.y == -1.0f && b.lo.z == 0.0f && b.hi.x == 1.0f && b.hi.y == 1.0f && b.hi.z == 4.0f);
    /* Tilted cylinder from (0,0,0) to (3,4,0), radius 1: axis (0.6,0.8,0),
     * half-extents sqrt(1-0.36) = 0.8, sqrt(1-0.64) = 0.6, 1. */
    cone_t c = cone(v3(0, 0, 0), 1.0f, v3(3, 4, 0), 1.0f);
    b = cone_bounds(c);
    CHECK_NEAR(b.lo.x, -0.8, 2e-7);
    CHECK_NEAR(b.hi.x, 3.8, 5e-7);
    CHECK_NEAR(b.lo.y, -0.6, 2e-7);
    CHECK_NEAR(b.hi.y, 4.6, 5e-7);
    CHECK(b.lo.z == -1.0f && b.hi.z == 1.0f);
    /* Rounded outwards. */
    CHECK(b.lo.x <= -0.8 && b.hi.x >= 3.8 && b.lo.y <= -0.6 && b.hi.y >= 4.6);
    /* A cone on the same axis, radii 2 and 1: x in [-1.6, 3.8], y in [-1.2, 4.6]. */
    c = cone(v3(0, 0, 0), 2.0f, v3(3, 4, 0), 1.0f);
    b = cone_bounds(c);
    CHECK_NEAR(b.lo.x, -1.6, 3e-7);
    CHECK_NEAR(b.hi.x, 3.8, 5e-7);
    CHECK_NEAR(b.lo.y, -1.2, 3e-7);
    CHECK_NEAR(b.hi.y, 4.6, 5e-7);
    CHECK(b.lo.z == -2.0f && b.hi.z == 2.0f);
    /* Through prims_finish. */
    prims_t p;
    char err[256];
    prims_init(&p);
    prims_add_cone(&p, v3(0, 0, 0), 2.0f, v3(3, 4, 0), 1.0f);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    CHECK(memcmp(&p.bounds[0], &b, sizeof b) == 0 && memcmp(&p.box, &b, sizeof b) == 0);
    prims_free(&p);

    /* Random cones: the bounds hold every surface point and each face is
     * reached (tight) to within the sampling. */
    int outside = 0, loose = 0;
    for (int i = 0; i < 200; i++) {
        cone_t rc = random_cone(i);
        cframe_t f = cframe(rc);
        box3 bb = cone_bounds(rc);
        box3 seen = box_empty();
        for (int s = 0; s <= 8; s += 8)
            for (int k = 0; k < 4096; k++) {
                dvec3 q = cone_point(&f, s / 8.0, 2 * M_PI * k / 4096.0, NULL);
                outside += q.x < bb.lo.x || q.x > bb.hi.x || q.y < bb.lo.y || q.y > bb.hi.y || q.z < bb.lo.z || q.z > bb.hi.z;
                seen = box_grow(seen, tof(q));
            }
        double size = box_diagonal(bb);
        loose += fabs(seen.lo.x - bb.lo.x) > 1e-5 * size || fabs(seen.hi.x - bb.hi.x) > 1e-5 * size ||
                 fabs(seen.lo.y - bb.lo.y) > 1e-5 * size || fabs(seen.hi.y - bb.hi.y) > 1e-5 * size ||
                 fabs(seen.lo.z - bb.lo.z) > 1e-5 * size || fabs(seen.hi.z - bb.hi.z) > 1e-5 * size;
    }
    CHECK_MSG(outside == 0, "%d surface points outside their cone's bounds", outside);
    CHECK_MSG(loose == 0, "%d cones with bounds looser than the rims", loose);
}

static void test_cone_finish_errors(void)
{
    struct {
        vec3 b;
        float rb;
        vec3 a;
        float ra;
        const char *what;
    } bad[] = {
        {{1, 2, 3}, 1.0f, {1, 2, 3}, 0.5f, "base != apex"},
        {{0, 0, 0}, 0.0f, {0, 0, 1}, 0.0f, "radius > 0"},
        {{0, NAN, 0}, 1.0f, {0, 0, 1}, 1.0f, "finite"},
        {{0, 0, 0}, 1.0f, {0, 0, INFINITY}, 1.0f, "finite"},
        {{0, 0, 0}, NAN, {0, 0, 1}, 1.0f, "finite"},
        {{0, 0, 0}, 1.0f, {0, 0, 1}, -0.5f, "radii >= 0"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        prims_t p;
        char err[256] = "";
        prims_init(&p);
        prims_add_sphere(&p, v3(0, 0, 0), 1.0f);
        prims_add_cone(&p, v3(0, 0, 0), 1.0f, v3(0, 0, 1), 0.0f);
        prims_add_cone(&p, bad[i].b, bad[i].rb, bad[i].a, bad[i].ra);
        CHECK(prims_finish(&p, err, sizeof err) == -1);
        CHECK_MSG(strstr(err, "cone 1 (primitive 2)") && strstr(err, bad[i].what), "case %zu: %s", i, err);
        prims_free(&p);
    }
    /* Valid edge cases: one radius 0 either end, ra > rb. */
    prims_t p;
    char err[256];
    prims_init(&p);
    prims_add_cone(&p, v3(0, 0, 0), 0.0f, v3(0, 0, 1), 1.0f);
    prims_add_cone(&p, v3(0, 0, 0), 1.0f, v3(0, 0, 1), 0.0f);
    prims_add_cone(&p, v3(0, 0, 0), 1.0f, v3(0, 0, 1), 3.0f);
    CHECK_MSG(prims_finish(&p, err, sizeof err) == 0, "%s", err);
    prims_free(&p);
}

/* ---------------------------------------------------------------------- */
/* cones: box overlap                                                      */

static void test_cone_box_overlap(void)
{
    /* CYL: z in [0,4], radius 1. */
    CHECK(cone_overlaps_box(CYL, box(v3(1, -0.5f, 1), v3(2, 0.5f, 2))));                      /* touches the side line x = 1 */
    CHECK(!cone_overlaps_box(CYL, box(v3(nextafterf(1, 2), -0.5f, 1), v3(2, 0.5f, 2))));    /* one ulp away */
    CHECK(cone_overlaps_box(CYL, box(v3(0.5f, -0.5f, 1), v3(2, 0.5f, 2))));                 /* through the wall */
    CHECK(cone_overlaps_box(CYL, box(v3(-2, -2, -2), v3(2, 2, 6))));                         /* containing it */
    CHECK(!cone_overlaps_box(CYL, box(v3(-0.5f, -0.5f, 1), v3(0.5f, 0.5f, 3))));            /* inside the hollow */
    CHECK(!cone_overlaps_box(CYL, box(v3(-0.5f, -0.5f, 3.9f), v3(0.5f, 0.5f, 4.5f))));      /* in the open top */
    CHECK(!cone_overlaps_box(CYL, box(v3(-0.5f, -0.5f, 4.5f), v3(0.5f, 0.5f, 5))));         /* above it */
    CHECK(!cone_overlaps_box(CYL, box(v3(0.9f, 0.9f, 3.5f), v3(1.2f, 1.2f, 4))));           /* bounds corner near the rim, outside */
    CHECK(cone_overlaps_box(CYL, box(v3(0.9f, -0.1f, 3.9f), v3(1.1f, 0.1f, 4.1f))));        /* straddling the rim */
    CHECK(cone_overlaps_box(CYL, box(v3(0.5f, -0.1f, 4), v3(1.5f, 0.1f, 4.5f))));           /* touching the rim from above */
    CHECK(!cone_overlaps_box(CYL, box(v3(0.5f, -0.1f, nextafterf(4, 5)), v3(1.5f, 0.1f, 4.5f))));
    CHECK(cone_overlaps_box(CYL, box(v3(-2, -2, 2), v3(2, 2, 2))));                          /* a flat slice */
    CHECK(!cone_overlaps_box(CYL, box(v3(-0.7f, -0.7f, 2), v3(0.7f, 0.7f, 2))));            /* a flat slice inside */
    /* The box corner (0.75, 0.75) of [0.75,2]^2 is at radius 1.06: outside;
     * at 0.7 (radius 0.99) it cuts the wall. */
    CHECK(!cone_overlaps_box(CYL, box(v3(0.75f, 0.75f, 1), v3(2, 2, 3))));
    CHECK(cone_overlaps_box(CYL, box(v3(0.7f, 0.7f, 1), v3(2, 2, 3))));
    /* A box corner exactly on the wall: (3, 4) on a cylinder of radius 5;
     * one ulp further out in x and y it misses by about 5e-7. */
    cone_t c5 = cone(v3(0, 0, 0), 5.0f, v3(0, 0, 1), 5.0f);
    CHECK(cone_overlaps_box(c5, box(v3(3, 4, 0.5f), v3(6, 6, 0.5f))));
    CHECK(!cone_overlaps_box(c5, box(v3(nextafterf(3, 4), nextafterf(4, 5), 0.5f), v3(6, 6, 0.5f))));
    CHECK(!cone_overlaps_box(CYL, box_empty()));

    /* A cone: base radius 2 at z = 0, apex radius 1 at z = 2. The wall
     * point at z = 1 is radius 1.5; a box just outside its slant. */
    cone_t c = cone(v3(0, 0, 0), 2.0f, v3(0, 0, 2), 1.0f);
    CHECK(cone_overlaps_box(c, box(v3(1.5f, -0.1f, 1), v3(2, 0.1f, 1.2f)))); /* touches at (1.5,0,1) */
    CHECK(!cone_overlaps_box(c, box(v3(1.51f, -0.1f, 1), v3(2, 0.1f, 1.2f))));
    /* Above the slant near the apex rim, inside the cone's bounds. */
    CHECK(!cone_overlaps_box(c, box(v3(1.3f, -0.1f, 1.8f), v3(1.9f, 0.1f, 2))));
    /* Pointed cone, a box just above the tip and one touching it. */
    cone_t pc = cone(v3(0, 0, 0), 1.0f, v3(0, 0, 1), 0.0f);
    CHECK(cone_overlaps_box(pc, box(v3(-0.1f, -0.1f, 1), v3(0.1f, 0.1f, 1.5f))));
    CHECK(!cone_overlaps_box(pc, box(v3(-0.1f, -0.1f, 1.001f), v3(0.1f, 0.1f, 1.5f))));

    /* Through the API: bounds overlap, primitive does not. */
    prims_t p;
    char err[256];
    prims_init(&p);
    prims_add_cone(&p, v3(0, 0, 0), 1.0f, v3(0, 0, 4), 1.0f);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    box3 hollow = box(v3(-0.5f, -0.5f, 1), v3(0.5f, 0.5f, 3));
    CHECK(box_overlap(prim_bounds(&p, 0), hollow) && !prim_overlaps_box(&p, 0, hollow));
    CHECK(prim_overlaps_box(&p, 0, box(v3(0.5f, -0.5f, 1), v3(2, 0.5f, 2))));
    prims_free(&p);
}

/* Random cones and boxes. Boxes holding a point of the surface (with room
 * around it for the float rounding of the point) must overlap; boxes
 * certainly clear of the surface must not. "Certainly clear": every
 * surface point is within dmax of one of the grid samples, so a box
 * farther than dmax from all samples is disjoint. Near misses are also
 * built directly: small boxes around points at a distance eps off the
 * surface along its normal (outside, and inside the tube). */
static void test_cone_box_random(void)
{
    int false_neg = 0, n_true = 0, clear = 0, clear_yes = 0, near = 0, near_yes = 0, tiny_neg = 0;
    for (int ci = 0; ci < 40; ci++) {
        cone_t c = random_cone(ci);
        cframe_t f = cframe(c);
        double size = box_diagonal(cone_bounds(c));

        /* Boxes around surface points. */
        for (int i = 0; i < 500; i++) {
            dvec3 q = cone_point(&f, rndd(0, 1), rndd(0, 2 * M_PI), NULL);
            double e = (i % 4 == 0) ? 1e-5 * size : rndd(1e-4, 1.5);
            vec3 lo = tof(dvec(q.x - e * rndd(0.01, 1), q.y - e * rndd(0.01, 1), q.z - e * rndd(0.01, 1)));
            vec3 hi = tof(dvec(q.x + e * rndd(0.01, 1), q.y + e * rndd(0.01, 1), q.z + e * rndd(0.01, 1)));
            bool ov = cone_overlaps_box(c, box(lo, hi));
            false_neg += !ov;
            tiny_neg += !ov && i % 4 == 0;
            n_true += ov;
        }
        /* Rim points exactly: boxes with a corner on the rim circle's
         * sample, small. */
        for (int i = 0; i < 100; i++) {
            dvec3 q = cone_point(&f, i & 1, rndd(0, 2 * M_PI), NULL);
            double e = 1e-4 * size;
            box3 bx = box(tof(dvec(q.x - e, q.y - e, q.z - e)), tof(dvec(q.x + e, q.y + e, q.z + e)));
            false_neg += !cone_overlaps_box(c, bx);
        }

        /* Certainly clear boxes. */
        enum { NH = 48, NT = 192 };
        static dvec3 grid[(NH + 1) * NT];
        for (int a = 0; a <= NH; a++)
            for (int b = 0; b < NT; b++) grid[a * NT + b] = cone_point(&f, (double)a / NH, 2 * M_PI * b / NT, NULL);
        double slant = hypot(f.len, f.ra - f.rb), rmax = fmax(f.rb, f.ra);
        double dmax = 0.5 * hypot(slant / NH, rmax * 2 * M_PI / NT) * 1.01;
        box3 cb = cone_bounds(c);
        for (int i = 0; i < 150; i++) {
            vec3 ctr = v3(rnd(cb.lo.x - 0.3f, cb.hi.x + 0.3f), rnd(cb.lo.y - 0.3f, cb.hi.y + 0.3f), rnd(cb.lo.z - 0.3f, cb.hi.z + 0.3f));
            vec3 ext = rnd_v3(0.0f, 0.4f);
            box3 bx = box(v3_sub(ctr, ext), v3_add(ctr, ext));
            double dmin = INFINITY;
            for (int g = 0; g < (NH + 1) * NT; g++) dmin = fmin(dmin, point_box_distance(grid[g], bx));
            if (dmin > dmax) {
                clear++;
                clear_yes += cone_overlaps_box(c, bx);
            }
        }
        /* Near misses at 1e-5 and 1e-6 of the size, away from the rims. */
        for (int i = 0; i < 100; i++) {
            dvec3 nrm;
            dvec3 q = cone_point(&f, rndd(0.05, 0.95), rndd(0, 2 * M_PI), &nrm);
            double eps = (i & 2 ? 1e-6 : 1e-5) * size, side = (i & 1) ? 1.0 : -1.0;
            /* Inside the tube only where the wall is not too curved. */
            double r_here = dlen(dv3_sub(q, dmadd(f.b, f.w, dv3_dot(dv3_sub(q, f.b), f.w))));
            if (side < 0 && r_here < 100 * eps) continue;
            dvec3 m = dmadd(q, nrm, side * eps);
            double e = 0.2 * eps;
            box3 bx = box(tof(dvec(m.x - e, m.y - e, m.z - e)), tof(dvec(m.x + e, m.y + e, m.z + e)));
            near++;
            near_yes += cone_overlaps_box(c, bx);
        }
    }
    CHECK_MSG(false_neg == 0, "%d boxes holding a surface point reported disjoint (%d of them tiny)", false_neg, tiny_neg);
    CHECK_MSG(clear_yes == 0, "%d of %d certainly disjoint boxes reported overlapping", clear_yes, clear);
    CHECK_MSG(near_yes == 0, "%d of %d boxes 1e-5 or 1e-6 off the surface reported overlapping", near_yes, near);
    CHECK(clear > 1000 && near > 2000 && n_true > 15000);
    printf("cone/box: %d touching boxes all overlap; %d certainly clear and %d near-miss (1e-5, 1e-6) boxes, %d and %d reported overlapping\n",
           n_true, clear, near, clear_yes, near_yes);
}

/* ---------------------------------------------------------------------- */
/* cones: float vs double, boundary distance                               */

static double rel_err(double a, double b, double scale) { return fabs(a - b) / fmax(fmax(fabs(b), scale), 1e-30); }

static void test_cone_float_double(void)
{
    prims_t p;
    char err[256];
    prims_init(&p);
    for (int k = 0; k < 50; k++) {
        cone_t c = random_cone(k);
        prims_add_cone(&p, c.base, c.base_radius, c.apex, c.apex_radius);
    }
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    int both = 0, disagree = 0, unexplained = 0, far = 0, graze = 0;
    double worst = 0, worst_ratio = 0;
    counters_t cnt = {0};
    for (uint32_t id = 0; id < p.count; id++) {
        cone_t c = p.cones[p.index[id]];
        cframe_t f = cframe(c);
        double size = box_diagonal(p.bounds[id]);
        for (int i = 0; i < 2000; i++) {
            /* Aim at a point near the surface (a little beyond the rims
             * too); origins outside, or inside the tube. */
            dvec3 q = cone_point(&f, rndd(-0.1, 1.1), rndd(0, 2 * M_PI), NULL);
            vec3 org = (i & 1) ? tof(dmadd(f.b, f.w, rndd(0.1, 0.9) * f.len)) : rnd_v3(-6, 6);
            ray_t r = ray_through(org, tof(q));
            hit_t h = hit_none(&r);
            double td;
            bool hf = prim_intersect(&p, id, &r, &h, &cnt), hd = prim_intersect_double(&p, id, &r, &td);
            /* Both hit, but one took the near root and the other (which
             * found the near one just past a rim) the far one: a rim
             * disagreement, not an accuracy problem. */
            if (hf && hd && rel_err(h.t, td, 0.0) > 1e-3 &&
                fabs(prim_boundary_distance(&p, id, &r, fmin((double)h.t, td))) <= 1e-5 * size) {
                disagree++;
                continue;
            }
            if (hf && hd) {
                /* Conditioning: the rim / tangency distance, and the angle
                 * between the ray and the surface (t error ~ 1 / cos). */
                double g = prim_boundary_distance(&p, id, &r, td) / size;
                vec3 n = prim_normal(&p, &h, &r);
                double cosang = fabs(v3_dot(n, r.dir)) / v3_len(r.dir);
                double e = rel_err(h.t, td, v3_len(v3_sub(r.org, c.base)) / v3_len(r.dir));
                both++;
                /* The tolerance grows with the conditioning (first-order,
                 * measured over many seeds, with a margin of about 5): like
                 * 1 / cos for a shallow ray, like 1 / sqrt(g) near a
                 * tangent or rim, and like 1 / distance near the tip of a
                 * pointed cone, where the quadric is singular (the rounding
                 * of org - base, about eps |org - base|, is then large
                 * against the radius there). */
                double lim = fmax(1e-5, 5e-6 / fmax(cosang, 1e-3)) * fmax(1.0, sqrt(1e-3 / fmax(g, 1e-12)));
                if (c.base_radius == 0.0f || c.apex_radius == 0.0f) {
                    vec3 tip = c.base_radius == 0.0f ? c.base : c.apex;
                    double gtip = dlen(dv3_sub(dmadd(dv3(r.org), dv3(r.dir), td), dv3(tip))) / size;
                    lim *= fmax(1.0, 0.5 / fmax(gtip, 1e-12));
                }
                if (g >= 1e-3 && cosang >= 0.05) worst = fmax(worst, e);
                else graze++;
                worst_ratio = fmax(worst_ratio, e / lim);
                far += e > lim;
            } else if (hf != hd) {
                disagree++;
                double t = hf ? h.t : td;
                unexplained += fabs(prim_boundary_distance(&p, id, &r, t)) > 1e-5 * size;
            }
        }
    }
    CHECK_MSG(far == 0, "%d of %d cone hits differ beyond tolerance (worst %.3g, %.3g of the limit)", far, both, worst, worst_ratio);
    CHECK_MSG(unexplained == 0, "%d of %d float/double hit-miss disagreements are away from rims and tangents", unexplained, disagree);
    CHECK(both > 50000 && graze < both / 5);
    printf("cones: %d hits compared, worst relative t error %.3g where cos >= 0.05 (%d shallow or grazing), worst %.3g of the limit, %d rim/tangent disagreements\n",
           both, worst, graze, worst_ratio, disagree);
    prims_free(&p);
}

static void test_cone_boundary_distance(void)
{
    ray_t r = make_ray(v3(-5, 0, 2), v3(1, 0, 0), 0.0f, INFINITY);
    /* Through the axis at mid-height: rims 2 away, tangency margin r = 1. */
    CHECK_NEAR(cone_boundary_distance(CYL, &r, 4.0), 1.0, 1e-12);
    r = make_ray(v3(-5, 0.6f, 2), v3(1, 0, 0), 0.0f, INFINITY);
    CHECK_NEAR(cone_boundary_distance(CYL, &r, 4.2), 1.0 - 0.6, 1e-7);
    r = make_ray(v3(-5, 0, 3.75f), v3(1, 0, 0), 0.0f, INFINITY); /* near the top rim */
    CHECK_NEAR(cone_boundary_distance(CYL, &r, 4.0), 0.25, 1e-12);
    r = make_ray(v3(-5, 1, 2), v3(1, 0, 0), 0.0f, INFINITY); /* tangent */
    CHECK_NEAR(cone_boundary_distance(CYL, &r, 5.0), 0.0, 1e-12);
    r = make_ray(v3(-5, 2, 2), v3(1, 0, 0), 0.0f, INFINITY); /* misses by 1 */
    CHECK_NEAR(cone_boundary_distance(CYL, &r, 5.0), -1.0, 1e-12);
    /* Oblique through the axis: the margin is still r (measured across the
     * axis), whatever the slope; the rim 2 away. */
    r = make_ray(v3(-5, 0, 1), v3(1, 0, 0.25f), 0.0f, INFINITY);
    CHECK_NEAR(cone_boundary_distance(CYL, &r, 4.0), 1.0, 1e-12);
    /* Parallel to the axis: no tangency; just the rims. */
    cone_t pc = cone(v3(0, 0, 0), 1.0f, v3(0, 0, 1), 0.0f);
    r = make_ray(v3(0.25f, 0, -3), v3(0, 0, 1), 0.0f, INFINITY);
    CHECK_NEAR(cone_boundary_distance(pc, &r, 3.75), sqrt(0.25 * 0.25 + 0.25 * 0.25), 1e-12);
    /* Through the API, the margin does not depend on where the origin sits. */
    prims_t p;
    char err[256];
    prims_init(&p);
    prims_add_cone(&p, v3(0, 0, 0), 2.0f, v3(0, 0, 2), 1.0f);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    ray_t r1 = make_ray(v3(-5, 0.5f, 1), v3(1, 0, 0.125f), 0.0f, INFINITY);
    ray_t r2 = make_ray(v3(-3, 0.5f, 1.25f), v3(1, 0, 0.125f), 0.0f, INFINITY);
    double t1 = 0, t2 = 0;
    CHECK(prim_intersect_double(&p, 0, &r1, &t1) && prim_intersect_double(&p, 0, &r2, &t2));
    CHECK_NEAR(prim_boundary_distance(&p, 0, &r1, t1), prim_boundary_distance(&p, 0, &r2, t2), 1e-12);
    prims_free(&p);
}

/* ---------------------------------------------------------------------- */
/* polygons: helpers                                                       */

/* Even-odd point in polygon in 2D (test-side reference; boundary
 * undefined). */
static bool pip2(const double (*q)[2], int n, double x, double y)
{
    bool in = false;
    for (int i = 0, j = n - 1; i < n; j = i++) {
        if ((q[i][1] > y) != (q[j][1] > y)) {
            double xi = q[j][0] + (y - q[j][1]) * (q[i][0] - q[j][0]) / (q[i][1] - q[j][1]);
            if (xi > x) in = !in;
        }
    }
    return in;
}

static double shoelace(const double (*q)[2], int n)
{
    double a = 0;
    for (int i = 0, j = n - 1; i < n; j = i++) a += q[j][0] * q[i][1] - q[i][0] * q[j][1];
    return 0.5 * a;
}

/* A rigid rotation (about a fixed tilted axis) plus a translation: maps
 * the 2D test polygons into a general plane. */
typedef struct {
    double m[3][3];
    dvec3 t;
} xform_t;

static xform_t tilt(double ax, double ay, double az, double ang, dvec3 t)
{
    double l = sqrt(ax * ax + ay * ay + az * az);
    ax /= l, ay /= l, az /= l;
    double c = cos(ang), s = sin(ang), C = 1 - c;
    xform_t x = {{{c + ax * ax * C, ax * ay * C - az * s, ax * az * C + ay * s},
                  {ay * ax * C + az * s, c + ay * ay * C, ay * az * C - ax * s},
                  {az * ax * C - ay * s, az * ay * C + ax * s, c + az * az * C}},
                 t};
    return x;
}

static dvec3 xf(const xform_t *x, double px, double py, double pz)
{
    return dvec(x->m[0][0] * px + x->m[0][1] * py + x->m[0][2] * pz + x->t.x,
                x->m[1][0] * px + x->m[1][1] * py + x->m[1][2] * pz + x->t.y,
                x->m[2][0] * px + x->m[2][1] * py + x->m[2][2] * pz + x->t.z);
}

/* A store holding one polygon per 2D outline (mapped by x, or at z = z0
 * when x is NULL). Returns the first vertex index. */
static uint32_t add_outline(prims_t *p, const double (*q)[2], int n, const xform_t *x, float z0, bool reverse)
{
    uint32_t base = p->nverts;
    uint32_t idx[512];
    for (int i = 0; i < n; i++) {
        int k = reverse ? n - 1 - i : i;
        vec3 v = x ? tof(xf(x, q[k][0], q[k][1], 0)) : v3((float)q[k][0], (float)q[k][1], z0);
        idx[i] = prims_add_vertex(p, v);
    }
    prims_add_polygon(p, idx, (uint32_t)n);
    return base;
}

/* The SPD gear face: 36 teeth of 4 points, radii ro (tips) and ri (roots). */
enum { GEAR_N = 144 };
static const double GEAR_RO = 1.0, GEAR_RI = 0.9;
static void gear_outline(double (*q)[2])
{
    double ta = 2 * M_PI / 36;
    for (int k = 0; k < 36; k++) {
        double ga = 2 * M_PI * k / 36;
        double pr[4] = {GEAR_RO, GEAR_RO, GEAR_RI, GEAR_RI}, pa[4] = {ga - 0.19 * ta, ga + 0.19 * ta, ga + 0.3 * ta, ga + 0.7 * ta};
        for (int j = 0; j < 4; j++) {
            q[4 * k + j][0] = pr[j] * cos(pa[j]);
            q[4 * k + j][1] = pr[j] * sin(pa[j]);
        }
    }
}

static const double LSHAPE[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};

/* ---------------------------------------------------------------------- */
/* polygons: intersection                                                  */

static void test_polygon_gear(void)
{
    double q[GEAR_N][2];
    gear_outline(q);
    double ta = 2 * M_PI / 36;
    for (int variant = 0; variant < 3; variant++) {
        /* 0: in the plane z = 2; 1: reversed winding (the bottom face); 2: tilted. */
        prims_t p;
        char err[256];
        prims_init(&p);
        xform_t x = tilt(0.3, -0.5, 0.8, 0.9, dvec(0.25, -1.5, 2.0));
        add_outline(&p, (const double(*)[2])q, GEAR_N, variant == 2 ? &x : NULL, 2.0f, variant == 1);
        CHECK(prims_finish(&p, err, sizeof err) == 0);
        CHECK(p.npolygons == 1 && p.polygons[0].count == GEAR_N && !p.polygons[0].degenerate && p.npoly_tris == GEAR_N - 2);
        vec3 n = p.polygons[0].normal;
        if (variant == 0) CHECK(n.x == 0.0f && n.y == 0.0f && n.z == 1.0f && p.polygons[0].offset == 2.0f && p.polygons[0].axis == 2);
        if (variant == 1) CHECK(n.z == -1.0f);
        /* The rays: along the normal from 8 above the point. */
        dvec3 nz = variant == 2 ? dv3_sub(xf(&x, 0, 0, 1), xf(&x, 0, 0, 0)) : dvec(0, 0, 1);
        counters_t c = {0};
        int tooth_miss = 0, notch_hit = 0, inner_miss = 0, outer_hit = 0, bad_t = 0;
        for (int k = 0; k < 36; k++) {
            double ga = 2 * M_PI * k / 36;
            struct { double r, a; int want; } pts[4] = {
                {0.95, ga, 1}, {0.95, ga + 0.5 * ta, 0}, {0.85, ga + rndd(0, ta), 1}, {1.02, ga + rndd(0, ta), 0}};
            for (int j = 0; j < 4; j++) {
                double px = pts[j].r * cos(pts[j].a), py = pts[j].r * sin(pts[j].a);
                dvec3 target = variant == 2 ? xf(&x, px, py, 0) : dvec(px, py, 2.0);
                ray_t r = make_ray(tof(dmadd(target, nz, 8.0)), tof(dvec(-nz.x, -nz.y, -nz.z)), 0.0f, INFINITY);
                hit_t h = hit_none(&r);
                bool hit = prim_intersect(&p, 0, &r, &h, &c);
                if (hit) bad_t += fabs(h.t - 8.0) > 1e-5;
                double td;
                bool dh = prim_intersect_double(&p, 0, &r, &td);
                if (dh != hit) bad_t++;
                if (j == 0) tooth_miss += !hit;
                if (j == 1) notch_hit += hit;
                if (j == 2) inner_miss += !hit;
                if (j == 3) outer_hit += hit;
            }
        }
        CHECK_MSG(tooth_miss == 0 && notch_hit == 0 && inner_miss == 0 && outer_hit == 0,
                  "variant %d: %d teeth missed, %d notches hit, %d inner misses, %d outer hits", variant, tooth_miss, notch_hit, inner_miss, outer_hit);
        CHECK_MSG(bad_t == 0, "variant %d: %d wrong t or float/double disagreements", variant, bad_t);
        /* The centre. */
        dvec3 centre = variant == 2 ? xf(&x, 0, 0, 0) : dvec(0, 0, 2);
        ray_t r = make_ray(tof(dmadd(centre, nz, 8.0)), tof(dvec(-nz.x, -nz.y, -nz.z)), 0.0f, INFINITY);
        hit_t h = hit_none(&r);
        CHECK(prim_intersect(&p, 0, &r, &h, &c));
        CHECK_NEAR(h.t, 8.0, 1e-5);
        CHECK(h.u == 0.0f && h.v == 0.0f && h.prim == 0);
        CHECK(c.prim_tests == 36 * 4 + 1 && c.prim_hits == 36 * 2 + 1);
        /* An oblique ray through a tooth, and one through a notch. */
        if (variant == 0) {
            r = ray_through(v3(3, -1, 7), v3((float)(0.95 * cos(5 * ta)), (float)(0.95 * sin(5 * ta)), 2));
            h = hit_none(&r);
            CHECK(prim_intersect(&p, 0, &r, &h, &c) && fabs(h.t - 1.0) < 1e-6);
            r = ray_through(v3(3, -1, 7), v3((float)(0.95 * cos(5.5 * ta)), (float)(0.95 * sin(5.5 * ta)), 2));
            CHECK(!prim_occluded(&p, 0, &r, &c));
        }
        prims_free(&p);
    }
}

static void test_polygon_lshape(void)
{
    prims_t p;
    char err[256];
    prims_init(&p);
    add_outline(&p, LSHAPE, 6, NULL, 1.0f, false);
    add_outline(&p, LSHAPE, 6, NULL, 3.0f, true); /* clockwise copy above */
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    CHECK(p.polygons[0].normal.z == 1.0f && p.polygons[1].normal.z == -1.0f);
    counters_t c = {0};
    static const float in[][2] = {{0.5f, 0.5f}, {1.5f, 0.5f}, {0.5f, 1.5f}, {1.9f, 0.9f}, {0.1f, 1.9f}};
    static const float out[][2] = {{1.5f, 1.5f}, {1.1f, 1.1f}, {1.9f, 1.9f}, {2.5f, 0.5f}, {-0.1f, 1}};
    for (int id = 0; id < 2; id++) {
        float z = id ? 3.0f : 1.0f;
        for (int i = 0; i < 5; i++) {
            ray_t r = make_ray(v3(in[i][0], in[i][1], 5), v3(0, 0, -1), 0.0f, INFINITY);
            hit_t h = hit_none(&r);
            CHECK(prim_intersect(&p, (uint32_t)id, &r, &h, &c) && h.t == 5.0f - z);
            r = make_ray(v3(out[i][0], out[i][1], -5), v3(0, 0, 2), 0.0f, INFINITY);
            CHECK(!prim_occluded(&p, (uint32_t)id, &r, &c));
        }
    }
    CHECK(c.prim_tests == 20 && c.prim_hits == 10);
    prims_free(&p);
}

/* The textbook float method, for comparison: each polygon's own plane, the
 * hit point, the projection that drops the dominant axis, crossings. */
static bool textbook_float_hit(const prims_t *p, uint32_t id, const ray_t *r)
{
    const polygon_t *g = &p->polygons[p->index[id]];
    float dn = v3_dot(g->normal, r->dir);
    if (dn == 0.0f) return false;
    float t = (g->offset - v3_dot(g->normal, r->org)) / dn;
    if (!(t >= r->tnear && t < r->tfar)) return false;
    vec3 hp = v3_madd(r->org, r->dir, t);
    int ix = (g->axis + 1) % 3, iy = (g->axis + 2) % 3;
    bool in = false;
    const uint32_t *idx = p->poly_verts + g->first;
    for (uint32_t i = 0, j = g->count - 1; i < g->count; j = i++) {
        vec3 a = p->verts[idx[j]], b = p->verts[idx[i]];
        float ax = v3_get(a, ix) - v3_get(hp, ix), ay = v3_get(a, iy) - v3_get(hp, iy);
        float bx = v3_get(b, ix) - v3_get(hp, ix), by = v3_get(b, iy) - v3_get(hp, iy);
        if ((ay > 0) != (by > 0)) {
            float e = ax * by - ay * bx;
            if (e != 0 && (e > 0) == (by > 0)) in = !in;
        }
    }
    return in;
}

/* Two quads sharing an edge (x = 1 of the rectangle [0,2] x [0,1]), first
 * in the plane z = 0 (exact grid of rays), then in random tilted planes
 * with random rays through points of the shared edge. */
static void test_polygon_shared_edge(void)
{
    static const double Q[6][2] = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {1, 1}, {0, 1}};
    static const uint32_t A[4] = {0, 1, 4, 5}, B[4] = {1, 2, 3, 4};
    int gaps = 0, both = 0, n = 0;
    prims_t p;
    char err[256];
    prims_init(&p);
    for (int i = 0; i < 6; i++) prims_add_vertex(&p, v3((float)Q[i][0], (float)Q[i][1], 0));
    prims_add_polygon(&p, A, 4);
    prims_add_polygon(&p, B, 4);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    counters_t c = {0};
    for (int i = 0; i <= 64; i++)
        for (int j = 0; j < 16; j++) {
            vec3 d = v3((j % 4 - 1.5f) / 4.0f, (j / 4 - 1.5f) / 2.0f, 1.0f);
            if (j == 5) d = v3(0, 0, -1);
            vec3 target = v3(1, i / 64.0f, 0);
            ray_t r = make_ray(v3_sub(target, d), d, 0.0f, INFINITY);
            int h = prim_occluded(&p, 0, &r, &c) + prim_occluded(&p, 1, &r, &c);
            /* The ends of the shared edge are corners of the rectangle:
             * those rays may legitimately miss both (outside boundary). */
            if (i > 0 && i < 64) {
                gaps += h == 0;
                both += h == 2;
                n++;
            }
        }
    CHECK_MSG(gaps == 0, "%d of %d exact rays through the shared edge hit neither quad", gaps, n);
    printf("shared edge, plane z = 0: %d exact rays, %d hit neither, %d hit both\n", n, gaps, both);
    prims_free(&p);

    /* Tilted: random planes, random rays. */
    int tgaps = 0, tboth = 0, tn = 0, text_gaps = 0, text_both = 0, text_bad = 0;
    for (int k = 0; k < 200; k++) {
        xform_t x = tilt(rndd(-1, 1), rndd(-1, 1), rndd(-1, 1), rndd(0, 3), dvec(rndd(-3, 3), rndd(-3, 3), rndd(-3, 3)));
        prims_init(&p);
        for (int i = 0; i < 6; i++) prims_add_vertex(&p, tof(xf(&x, Q[i][0], Q[i][1], 0)));
        prims_add_polygon(&p, A, 4);
        prims_add_polygon(&p, B, 4);
        CHECK(prims_finish(&p, err, sizeof err) == 0);
        vec3 e0 = p.verts[1], e1 = p.verts[4];
        /* The comparison method is right away from the edge. */
        for (int i = 0; i < 20; i++) {
            vec3 target = tof(xf(&x, rndd(0.05, 1.95), rndd(0.05, 0.95), 0));
            ray_t r = ray_through(v3_add(target, rnd_v3(-3, 3)), target);
            for (uint32_t id = 0; id < 2; id++) text_bad += textbook_float_hit(&p, id, &r) != prim_occluded(&p, id, &r, &c);
        }
        for (int i = 0; i < 200; i++) {
            float s = rnd(0.02f, 0.98f);
            vec3 target = v3_add(v3_scale(e0, 1 - s), v3_scale(e1, s));
            vec3 d = v3_norm(rnd_v3(-1, 1));
            if (fabsf(v3_dot(d, p.polygons[0].normal)) < 0.1f) continue;
            ray_t r = ray_through(v3_sub(target, v3_scale(d, rnd(0.5f, 5))), target);
            int h = prim_occluded(&p, 0, &r, &c) + prim_occluded(&p, 1, &r, &c);
            int th = textbook_float_hit(&p, 0, &r) + textbook_float_hit(&p, 1, &r);
            tgaps += h == 0;
            tboth += h == 2;
            text_gaps += th == 0;
            text_both += th == 2;
            tn++;
        }
        prims_free(&p);
    }
    CHECK_MSG(tgaps == 0, "%d of %d random rays through a tilted shared edge hit neither quad", tgaps, tn);
    CHECK_MSG(text_bad < 5, "the textbook comparison disagrees %d times away from the edge", text_bad);
    CHECK(tn > 30000);
    printf("shared edge, tilted planes: %d rays, %d hit neither, %d hit both (textbook dominant-axis method in float: %d neither, %d both)\n",
           tn, tgaps, tboth, text_gaps, text_both);
}

/* Closed polyhedra of polygons: a hexagonal prism (2 hexagons, 6 quads)
 * and a fan of pentagons around a shared vertex. Rays through the
 * interior must hit at least twice, rays through the shared vertex at
 * least once, whatever the rounding. */
static void test_polygon_watertight(void)
{
    prims_t p;
    char err[256];
    prims_init(&p);
    xform_t x = tilt(0.2, 0.7, -0.4, 1.1, dvec(0.1, 0.2, -0.3));
    for (int z = 0; z < 2; z++)
        for (int k = 0; k < 6; k++) {
            double a = k * M_PI / 3 + 0.1;
            prims_add_vertex(&p, tof(xf(&x, cos(a), sin(a), z ? 0.8 : -0.8)));
        }
    uint32_t bot[6], top[6];
    for (int k = 0; k < 6; k++) {
        bot[k] = (uint32_t)(5 - k); /* outward windings */
        top[k] = (uint32_t)(6 + k);
    }
    prims_add_polygon(&p, bot, 6);
    prims_add_polygon(&p, top, 6);
    for (int k = 0; k < 6; k++) {
        uint32_t q[4] = {(uint32_t)k, (uint32_t)(k + 1) % 6, (uint32_t)(k + 1) % 6 + 6, (uint32_t)k + 6};
        prims_add_polygon(&p, q, 4);
    }
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    /* Outward normals: the centre is behind every face. */
    dvec3 ctr = xf(&x, 0, 0, 0);
    int inward = 0;
    for (uint32_t i = 0; i < p.npolygons; i++)
        inward += dv3_dot(dv3(p.polygons[i].normal), dv3_sub(ctr, dv3(p.verts[p.poly_verts[p.polygons[i].first]]))) > 0;
    CHECK(inward == 0);

    int inside = 0, gaps = 0;
    for (int i = 0; i < 20000; i++) {
        /* Targets on edges and at vertices of the prism, and random ones. */
        vec3 target;
        int kind = i % 3;
        uint32_t e = (uint32_t)(rng_next() % 12);
        if (kind == 0) target = p.verts[e];
        else if (kind == 1) {
            float s = rnd(0, 1);
            uint32_t a = e, b = e < 6 ? (e + 1) % 6 : (e < 12 ? (e - 6 + 1) % 6 + 6 : e);
            if (rng_next() & 1) b = e < 6 ? e + 6 : e - 6; /* a vertical edge */
            target = v3_add(v3_scale(p.verts[a], 1 - s), v3_scale(p.verts[b], s));
        } else target = tof(xf(&x, rndd(-1.1, 1.1), rndd(-1.1, 1.1), rndd(-0.9, 0.9)));
        vec3 org = v3_add(tof(ctr), v3_scale(v3_norm(rnd_v3(-1, 1)), 6.0f));
        ray_t r = ray_through(org, target);
        /* Clip the line against the 8 half-spaces (unit normals) in double,
         * from the exact prism in its own frame. The line counts as
         * through the interior when the middle of its chord is at least
         * 1e-4 inside every face: then it passes 1e-4 inside the silhouette
         * too. (A long chord alone is not enough: a ray aimed at a vertex
         * can clip the corner while grazing a face at 1e-5 radians, and
         * then it is a silhouette graze.) */
        dvec3 o = dv3(r.org), d = dv3(r.dir), n8[8];
        double off8[8], lo = -INFINITY, hi = INFINITY;
        for (int f = 0; f < 8; f++) {
            if (f < 2) {
                n8[f] = dv3_sub(xf(&x, 0, 0, f ? 1 : -1), xf(&x, 0, 0, 0));
                off8[f] = 0.8;
            } else {
                double a = (f - 2) * M_PI / 3 + 0.1 + M_PI / 6;
                n8[f] = dv3_sub(xf(&x, cos(a), sin(a), 0), xf(&x, 0, 0, 0));
                off8[f] = cos(M_PI / 6);
            }
            double s0 = dv3_dot(n8[f], dv3_sub(o, ctr)) - off8[f], sd = dv3_dot(n8[f], d);
            if (sd > 0) hi = fmin(hi, -s0 / sd);
            else if (sd < 0) lo = fmax(lo, -s0 / sd);
            else if (s0 > 0) hi = -INFINITY;
        }
        double depth = -INFINITY;
        if (hi > lo) {
            dvec3 mid = dmadd(o, d, 0.5 * (lo + hi));
            depth = INFINITY;
            for (int f = 0; f < 8; f++) depth = fmin(depth, off8[f] - dv3_dot(n8[f], dv3_sub(mid, ctr)));
        }
        if (depth > 1e-4) {
            inside++;
            counters_t c = {0};
            int h = 0;
            for (uint32_t id = 0; id < p.count; id++) h += prim_occluded(&p, id, &r, &c);
            gaps += h < 2;
        }
    }
    CHECK_MSG(gaps == 0, "%d of %d rays through the prism interior hit fewer than 2 faces", gaps, inside);
    CHECK(inside > 5000);
    prims_free(&p);

    /* 6 planar quads around a shared vertex, on a shallow cone: quad k is
     * (centre, a_k, b_k, a_k+1) with b_k = 0.9 (a_k + a_k+1) relative to the
     * centre, in the plane of the other three. */
    prims_init(&p);
    vec3 centre = v3(0.3f, -0.2f, 0.1f);
    prims_add_vertex(&p, centre);
    for (int k = 0; k < 12; k++) {
        double a0 = (k / 2) * M_PI / 3 + 0.05, a1 = a0 + M_PI / 3;
        dvec3 ak = dvec(0.6 * cos(a0), 0.6 * sin(a0), -0.18), an = dvec(0.6 * cos(a1), 0.6 * sin(a1), -0.18);
        dvec3 v = (k & 1) ? dvec(0.9 * (ak.x + an.x), 0.9 * (ak.y + an.y), 0.9 * (ak.z + an.z)) : ak;
        prims_add_vertex(&p, v3_add(centre, tof(v)));
    }
    for (int k = 0; k < 6; k++) {
        uint32_t q[4] = {0, (uint32_t)(2 * k + 1), (uint32_t)(2 * k + 2), (uint32_t)((2 * k + 2) % 12 + 1)};
        prims_add_polygon(&p, q, 4);
    }
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    int fgaps = 0, fn = 0;
    for (int i = 0; i < 5000; i++) {
        vec3 d = v3(rnd(-0.5f, 0.5f), rnd(-0.5f, 0.5f), -1.0f);
        d = v3_scale(d, rnd(0.1f, 10.0f));
        ray_t r = make_ray(v3_sub(centre, v3_scale(d, 4.0f)), d, 0.0f, INFINITY);
        counters_t c = {0};
        int h = 0;
        for (uint32_t id = 0; id < p.count; id++) h += prim_occluded(&p, id, &r, &c);
        fgaps += h == 0;
        fn++;
    }
    CHECK_MSG(fgaps == 0, "%d of %d rays through a vertex shared by 6 quads hit none", fgaps, fn);
    prims_free(&p);
}

static void test_polygon_degenerate(void)
{
    prims_t p;
    char err[256];
    prims_init(&p);
    static const vec3 v[8] = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {2, 2, 0}};
    for (int i = 0; i < 8; i++) prims_add_vertex(&p, v[i]);
    static const uint32_t collinear[4] = {0, 1, 2, 3}, backforth[4] = {0, 2, 1, 3}, repeated[4] = {4, 4, 5, 5}, point[3] = {1, 1, 1};
    static const uint32_t lead_collinear[5] = {0, 4, 6, 7, 5}; /* (0,0),(1,0),(2,0) collinear first: real area */
    prims_add_polygon(&p, collinear, 4);
    prims_add_polygon(&p, backforth, 4);
    prims_add_polygon(&p, repeated, 4);
    prims_add_polygon(&p, point, 3);
    prims_add_polygon(&p, lead_collinear, 5);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    CHECK(p.npoly_degenerate == 4 && p.ndegenerate == 0);
    for (int i = 0; i < 4; i++) CHECK(p.polygons[i].degenerate == 1);
    CHECK(!p.polygons[4].degenerate && p.polygons[4].normal.z == 1.0f);
    CHECK(p.npoly_tris == 2 + 2 + 2 + 1 + 3);

    counters_t c = {0};
    int hits = 0, dhits = 0, real = 0;
    for (int i = 0; i < 2000; i++) {
        uint32_t id = (uint32_t)(i % 5);
        const polygon_t *g = &p.polygons[id];
        /* Aim at a point on the polygon: a random point of a random edge
         * (for the real one: a random interior point). */
        vec3 target;
        if (id == 4) target = v3(rnd(0.1f, 1.9f), rnd(0.1f, 0.9f), 0); /* inside the pentagon */
        else {
            uint32_t e = (uint32_t)(rng_next() % g->count);
            vec3 a = p.verts[p.poly_verts[g->first + e]], b = p.verts[p.poly_verts[g->first + (e + 1) % g->count]];
            float s = rnd(0, 1);
            target = v3_add(v3_scale(a, 1 - s), v3_scale(b, s));
        }
        ray_t r = ray_through(v3_add(target, rnd_v3(-3, 3)), target);
        hit_t h = hit_none(&r);
        bool hit = prim_intersect(&p, id, &r, &h, &c);
        double td;
        bool dh = prim_intersect_double(&p, id, &r, &td);
        if (id == 4) {
            real += hit;
            continue;
        }
        hits += hit;
        dhits += dh;
    }
    CHECK_MSG(hits == 0 && dhits == 0, "degenerate polygons hit %d times (%d in double)", hits, dhits);
    CHECK(real > 300);
    CHECK(c.prim_tests == 2000 && c.prim_hits == (uint64_t)real);
    /* Box overlap still works for a degenerate polygon (as its segments). */
    CHECK(prim_overlaps_box(&p, 0, box(v3(1.5f, 1.5f, 1.5f), v3(1.6f, 1.6f, 1.6f))));
    CHECK(!prim_overlaps_box(&p, 0, box(v3(1.5f, 1.6f, 1.5f), v3(1.55f, 1.7f, 1.55f))));
    prims_free(&p);

    CHECK(polygon_normal(v, 4).x == 0.0f && polygon_normal(v, 4).y == 0.0f && polygon_normal(v, 4).z == 0.0f);
}

static void test_polygon_finish_errors(void)
{
    prims_t p;
    char err[256] = "";
    prims_init(&p);
    for (int i = 0; i < 4; i++) prims_add_vertex(&p, v3((float)(i & 1), (float)(i >> 1), 0));
    static const uint32_t ok[4] = {0, 1, 3, 2}, bad[4] = {0, 1, 7, 2};
    prims_add_polygon(&p, ok, 4);
    prims_add_polygon(&p, bad, 4);
    CHECK(prims_finish(&p, err, sizeof err) == -1);
    CHECK_MSG(strstr(err, "polygon 1 (primitive 1)") && strstr(err, "vertex 7"), "message: %s", err);
    prims_free(&p);

    prims_init(&p);
    for (int i = 0; i < 4; i++) prims_add_vertex(&p, v3((float)(i & 1), (float)(i >> 1), 0));
    prims_add_sphere(&p, v3(0, 0, 0), 1.0f);
    prims_add_polygon(&p, ok, 2);
    err[0] = 0;
    CHECK(prims_finish(&p, err, sizeof err) == -1);
    CHECK_MSG(strstr(err, "polygon 0 (primitive 1)") && strstr(err, "at least 3"), "message: %s", err);
    prims_free(&p);

    /* A NaN vertex is caught as before. */
    prims_init(&p);
    prims_add_vertex(&p, v3(0, 0, 0));
    prims_add_vertex(&p, v3(1, 0, 0));
    prims_add_vertex(&p, v3(NAN, 1, 0));
    static const uint32_t t3[3] = {0, 1, 2};
    prims_add_polygon(&p, t3, 3);
    CHECK(prims_finish(&p, err, sizeof err) == -1 && strstr(err, "vertex 2"));
    prims_free(&p);

    /* A mixed store: ids in scene order, every kind, memory counted, and
     * finish can run twice. */
    prims_init(&p);
    for (int i = 0; i < 4; i++) prims_add_vertex(&p, v3((float)(i & 1), (float)(i >> 1), 5));
    CHECK(prims_add_polygon(&p, ok, 4) == 0);
    CHECK(prims_add_sphere(&p, v3(0, 0, -5), 1.0f) == 1);
    CHECK(prims_add_cone(&p, v3(0, 0, 0), 1.0f, v3(0, 0, 1), 1.0f) == 2);
    CHECK(prims_add_triangle(&p, 0, 1, 2) == 3);
    CHECK(prims_add_polygon(&p, ok + 1, 3) == 4);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    CHECK(p.kind[0] == PRIM_POLYGON && p.kind[2] == PRIM_CONE && p.kind[4] == PRIM_POLYGON && p.index[4] == 1);
    CHECK(p.npoly_tris == 3 && p.polygons[1].tri_first == 2 && p.npoly_verts == 7);
    CHECK(p.bounds[0].lo.z == 5.0f && p.bounds[0].hi.x == 1.0f && p.box.lo.z == -6.0f && p.box.hi.z == 5.0f);
    CHECK(prims_memory(&p) >= 2 * sizeof(polygon_t) + 7 * sizeof(uint32_t) + 3 * sizeof(tri_t) + sizeof(cone_t));
    prims_free(&p);
    CHECK(p.count == 0 && p.polygons == NULL && p.cones == NULL);
}

/* ---------------------------------------------------------------------- */
/* triangulation                                                           */

/* Checks one triangulation of the 2D outline q (as 3D points in the plane
 * given by x, or z = 0): n - 2 triangles, valid distinct indices, total
 * area = |shoelace| area, each triangle with the polygon's orientation,
 * and each non-degenerate triangle's centroid inside the polygon. */
static int check_triangulation(const double (*q)[2], int n, const xform_t *x, bool pass_normal, const char *what)
{
    vec3 pts[512];
    uint32_t tris[512][3];
    for (int i = 0; i < n; i++) pts[i] = x ? tof(xf(x, q[i][0], q[i][1], 0)) : v3((float)q[i][0], (float)q[i][1], 0);
    vec3 normal = pass_normal ? polygon_normal(pts, (uint32_t)n) : v3(0, 0, 0);
    uint32_t nt = polygon_triangulate(pts, (uint32_t)n, normal, tris);
    int bad = 0;
    if (nt != (uint32_t)(n - 2)) {
        fprintf(stderr, "%s: %u triangles for %d vertices\n", what, nt, n);
        return 1;
    }
    double area = fabs(shoelace(q, n)), sum = 0, orient = shoelace(q, n) > 0 ? 1 : -1;
    int outside = 0, flipped = 0;
    for (uint32_t t = 0; t < nt; t++) {
        uint32_t a = tris[t][0], b = tris[t][1], c = tris[t][2];
        if (a >= (uint32_t)n || b >= (uint32_t)n || c >= (uint32_t)n || a == b || b == c || a == c) {
            bad++;
            continue;
        }
        double tq[3][2] = {{q[a][0], q[a][1]}, {q[b][0], q[b][1]}, {q[c][0], q[c][1]}};
        double ta = shoelace((const double(*)[2])tq, 3);
        flipped += ta * orient < -1e-12 * area;
        sum += fabs(ta);
        if (fabs(ta) > 1e-9 * area) {
            double cx = (tq[0][0] + tq[1][0] + tq[2][0]) / 3, cy = (tq[0][1] + tq[1][1] + tq[2][1]) / 3;
            outside += !pip2(q, n, cx, cy);
        }
    }
    if (bad || outside || flipped || fabs(sum - area) > 1e-6 * area) {
        fprintf(stderr, "%s: %d bad indices, %d centroids outside, %d flipped, area %.9g vs %.9g\n", what, bad, outside, flipped, sum, area);
        return 1;
    }
    return 0;
}

static void test_triangulate(void)
{
    double gear[GEAR_N][2], rev[GEAR_N][2];
    gear_outline(gear);
    xform_t x = tilt(0.5, 0.2, -0.7, 2.2, dvec(1, 2, 3));
    static const double square[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    double hex[6][2], lrev[6][2];
    for (int k = 0; k < 6; k++) {
        hex[k][0] = cos(k * M_PI / 3);
        hex[k][1] = sin(k * M_PI / 3);
        lrev[k][0] = LSHAPE[5 - k][0];
        lrev[k][1] = LSHAPE[5 - k][1];
    }
    for (int i = 0; i < GEAR_N; i++) {
        rev[i][0] = gear[GEAR_N - 1 - i][0];
        rev[i][1] = gear[GEAR_N - 1 - i][1];
    }
    /* Collinear vertices along the edges of a square, and a comb. */
    static const double coll[8][2] = {{0, 0}, {1, 0}, {2, 0}, {2, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}};
    static const double comb[12][2] = {{0, 0}, {5, 0}, {5, 3}, {4, 3}, {4, 1}, {3, 1}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
    static const double spiral_like[10][2] = {{0, 0}, {4, 0}, {4, 4}, {1, 4}, {1, 2}, {2, 2}, {2, 3}, {3, 3}, {3, 1}, {0, 1}};
    int fails = 0;
    for (int tilted = 0; tilted < 2; tilted++)
        for (int pass = 0; pass < 2; pass++) {
            const xform_t *xp = tilted ? &x : NULL;
            fails += check_triangulation(square, 4, xp, pass, "square");
            fails += check_triangulation((const double(*)[2])hex, 6, xp, pass, "hexagon");
            fails += check_triangulation(LSHAPE, 6, xp, pass, "L ccw");
            fails += check_triangulation((const double(*)[2])lrev, 6, xp, pass, "L cw");
            fails += check_triangulation((const double(*)[2])gear, GEAR_N, xp, pass, "gear ccw");
            fails += check_triangulation((const double(*)[2])rev, GEAR_N, xp, pass, "gear cw");
            fails += check_triangulation(coll, 8, xp, pass, "collinear edges");
            fails += check_triangulation(comb, 12, xp, pass, "comb");
            fails += check_triangulation(spiral_like, 10, xp, pass, "hook");
        }
    CHECK_MSG(fails == 0, "%d fixed triangulations failed", fails);

    /* Random star-shaped polygons (simple, often very concave), both
     * windings, in random planes. */
    int rfails = 0;
    for (int k = 0; k < 400; k++) {
        int n = 3 + (int)(rng_next() % 120);
        double q[512][2];
        double a0 = rndd(0, 1);
        for (int i = 0; i < n; i++) {
            double a = 2 * M_PI * (i + a0 * rndd(0.05, 0.95)) / n, r = rndd(0.05, 1.0);
            int j = (k & 1) ? n - 1 - i : i;
            q[j][0] = r * cos(a);
            q[j][1] = r * sin(a);
        }
        xform_t rx = tilt(rndd(-1, 1), rndd(-1, 1), rndd(-1, 1), rndd(0, 3), dvec(0, 0, 0));
        rfails += check_triangulation((const double(*)[2])q, n, (k & 2) ? &rx : NULL, (k & 4) != 0, "random star");
    }
    CHECK_MSG(rfails == 0, "%d of 400 random star polygons triangulated wrongly", rfails);

    /* A normal of the opposite sign works too; the winding is the polygon's. */
    vec3 pts[6];
    uint32_t tris[6][3];
    for (int i = 0; i < 6; i++) pts[i] = v3((float)LSHAPE[i][0], (float)LSHAPE[i][1], 0);
    CHECK(polygon_triangulate(pts, 6, v3(0, 0, -3), tris) == 4);
    double asum = 0;
    for (int t = 0; t < 4; t++) {
        vec3 n = v3_cross(v3_sub(pts[tris[t][1]], pts[tris[t][0]]), v3_sub(pts[tris[t][2]], pts[tris[t][0]]));
        CHECK(n.z >= 0.0f);
        asum += 0.5 * n.z;
    }
    CHECK(asum == 3.0);
    /* Not simple: a bowtie and a self-crossing star still give n - 2. */
    static const vec3 bow[4] = {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}};
    CHECK(polygon_triangulate(bow, 4, v3(0, 0, 1), tris) == 2);
    vec3 star[5];
    for (int i = 0; i < 5; i++) star[i] = v3(cosf(i * 4 * (float)M_PI / 5), sinf(i * 4 * (float)M_PI / 5), 0);
    CHECK(polygon_triangulate(star, 5, v3(0, 0, 0), tris) == 3);
    for (int t = 0; t < 3; t++) CHECK(tris[t][0] < 5 && tris[t][1] < 5 && tris[t][2] < 5);
    /* Fewer than 3 vertices; exactly 3. */
    CHECK(polygon_triangulate(star, 2, v3(0, 0, 1), tris) == 0);
    CHECK(polygon_triangulate(star, 3, v3(0, 0, 1), tris) == 1 && tris[0][0] == 0 && tris[0][1] == 1 && tris[0][2] == 2);
    /* polygon_normal follows the winding. */
    vec3 n = polygon_normal(pts, 6);
    CHECK(n.x == 0.0f && n.y == 0.0f && n.z == 1.0f);
}

/* ---------------------------------------------------------------------- */
/* polygons: box overlap, float vs double, boundary distance               */

static void test_polygon_box_overlap(void)
{
    double q[GEAR_N][2];
    gear_outline(q);
    double ta = 2 * M_PI / 36;
    prims_t p;
    char err[256];
    prims_init(&p);
    add_outline(&p, (const double(*)[2])q, GEAR_N, NULL, 0.0f, false);
    add_outline(&p, LSHAPE, 6, NULL, 0.0f, false);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    int wrong = 0;
    for (int k = 0; k < 36; k++) {
        double ga = 2 * M_PI * k / 36;
        /* A small box in the notch (it cuts the plane, but only the gap). */
        float nx = (float)(0.96 * cos(ga + 0.5 * ta)), ny = (float)(0.96 * sin(ga + 0.5 * ta));
        box3 notch = box(v3(nx - 0.01f, ny - 0.01f, -0.1f), v3(nx + 0.01f, ny + 0.01f, 0.1f));
        float tx = (float)(0.96 * cos(ga)), ty = (float)(0.96 * sin(ga));
        box3 tooth = box(v3(tx - 0.01f, ty - 0.01f, -0.1f), v3(tx + 0.01f, ty + 0.01f, 0.1f));
        box3 above = box(v3(tx - 0.01f, ty - 0.01f, 0.001f), v3(tx + 0.01f, ty + 0.01f, 0.1f));
        box3 touching = box(v3(tx - 0.01f, ty - 0.01f, 0.0f), v3(tx + 0.01f, ty + 0.01f, 0.1f));
        wrong += prim_overlaps_box(&p, 0, notch) || !prim_overlaps_box(&p, 0, tooth) || prim_overlaps_box(&p, 0, above) ||
                 !prim_overlaps_box(&p, 0, touching);
    }
    CHECK_MSG(wrong == 0, "%d teeth with a wrong box overlap", wrong);
    CHECK(prim_overlaps_box(&p, 0, box(v3(-2, -2, -1), v3(2, 2, 1))));
    CHECK(prim_overlaps_box(&p, 0, box(v3(-0.1f, -0.1f, -1), v3(0.1f, 0.1f, 1)))); /* the middle */
    /* L-shape: a box in the notch [1,2]^2 (within the bounds) misses, one
     * on the reflex corner touches, one across the arm overlaps. */
    CHECK(!prim_overlaps_box(&p, 1, box(v3(1.2f, 1.2f, -1), v3(1.9f, 1.9f, 1))));
    CHECK(prim_overlaps_box(&p, 1, box(v3(1, 1, -1), v3(1.9f, 1.9f, 1))));
    CHECK(!prim_overlaps_box(&p, 1, box(v3(nextafterf(1, 2), nextafterf(1, 2), -1), v3(1.9f, 1.9f, 1))));
    CHECK(prim_overlaps_box(&p, 1, box(v3(1.5f, 0.5f, -1), v3(2.5f, 0.6f, 1))));
    CHECK(!prim_overlaps_box(&p, 1, box(v3(3, 3, -1), v3(4, 4, 1))));
    CHECK(!prim_overlaps_box(&p, 1, box_empty()));
    prims_free(&p);

    /* Random star polygons in random planes: boxes around sample points
     * inside must overlap; boxes reported disjoint hold no sample. */
    int false_neg = 0, false_pos = 0, nov = 0, nsep = 0;
    for (int k = 0; k < 100; k++) {
        int n = 3 + (int)(rng_next() % 60);
        double qq[64][2];
        for (int i = 0; i < n; i++) {
            double a = 2 * M_PI * (i + rndd(0.05, 0.95)) / n, r = rndd(0.1, 1.0);
            qq[i][0] = r * cos(a);
            qq[i][1] = r * sin(a);
        }
        xform_t x = tilt(rndd(-1, 1), rndd(-1, 1), rndd(-1, 1), rndd(0, 3), dvec(rndd(-2, 2), rndd(-2, 2), rndd(-2, 2)));
        prims_init(&p);
        add_outline(&p, (const double(*)[2])qq, n, &x, 0, false);
        CHECK(prims_finish(&p, err, sizeof err) == 0);
        /* Samples inside the polygon. */
        dvec3 samples[400];
        int ns = 0;
        while (ns < 400) {
            double sx = rndd(-1, 1), sy = rndd(-1, 1);
            if (pip2((const double(*)[2])qq, n, sx, sy)) samples[ns++] = xf(&x, sx, sy, 0);
        }
        for (int i = 0; i < 300; i++) {
            vec3 lo = v3_add(tof(samples[i]), rnd_v3(-0.3f, -1e-4f)), hi = v3_add(tof(samples[i]), rnd_v3(1e-4f, 0.3f));
            false_neg += !prim_overlaps_box(&p, 0, box(lo, hi));
            /* A random box nearby. */
            vec3 c = v3_add(tof(samples[i]), rnd_v3(-0.5f, 0.5f)), e = rnd_v3(0.01f, 0.2f);
            box3 b = box(v3_sub(c, e), v3_add(c, e));
            bool ov = prim_overlaps_box(&p, 0, b);
            nov += ov;
            nsep += !ov;
            if (!ov)
                for (int s = 0; s < ns; s++) false_pos += in_box(tof(samples[s]), b);
        }
        prims_free(&p);
    }
    CHECK_MSG(false_neg == 0, "%d boxes around points inside a polygon reported disjoint", false_neg);
    CHECK_MSG(false_pos == 0, "%d polygon samples inside boxes reported disjoint", false_pos);
    CHECK(nov > 1000 && nsep > 1000);
}

static void test_polygon_float_double(void)
{
    int both = 0, disagree = 0, unexplained = 0, far = 0, grazing = 0;
    double worst = 0, worst_graze = 0;
    counters_t cnt = {0};
    for (int k = 0; k < 60; k++) {
        int n = 3 + (int)(rng_next() % 40);
        double qq[64][2];
        for (int i = 0; i < n; i++) {
            double a = 2 * M_PI * (i + rndd(0.05, 0.95)) / n, r = rndd(0.1, 1.0);
            qq[i][0] = r * cos(a);
            qq[i][1] = r * sin(a);
        }
        xform_t x = tilt(rndd(-1, 1), rndd(-1, 1), rndd(-1, 1), rndd(0, 3), dvec(rndd(-2, 2), rndd(-2, 2), rndd(-2, 2)));
        prims_t p;
        char err[256];
        prims_init(&p);
        add_outline(&p, (const double(*)[2])qq, n, &x, 0, false);
        CHECK(prims_finish(&p, err, sizeof err) == 0);
        dvec3 nrm = dv3(p.polygons[0].normal), centroid = xf(&x, 0, 0, 0);
        for (int i = 0; i < 1000; i++) {
            vec3 target = tof(xf(&x, rndd(-0.8, 0.8), rndd(-0.8, 0.8), 0));
            ray_t r = ray_through(rnd_v3(-5, 5), target);
            hit_t h = hit_none(&r);
            double td;
            bool hf = prim_intersect(&p, 0, &r, &h, &cnt), hd = prim_intersect_double(&p, 0, &r, &td);
            if (hf && hd) {
                dvec3 d = dv3(r.dir);
                double cosang = fabs(dv3_dot(nrm, d)) / dlen(d);
                double e = rel_err(h.t, td, dlen(dv3_sub(dv3(r.org), centroid)) / dlen(d));
                both++;
                /* t is a ray/plane distance: its error grows like 1 / cos
                 * (the float plane is the double one rounded, and the
                 * rounding is amplified as the ray turns parallel). */
                if (cosang >= 0.05) worst = fmax(worst, e);
                else grazing++;
                worst_graze = fmax(worst_graze, e * cosang);
                far += e > fmax(1e-5, 5e-6 / cosang);
            } else if (hf != hd) {
                disagree++;
                double t = hf ? h.t : td;
                /* Near an edge, or so nearly parallel to the plane that the
                 * edge distance seen along the ray (about bd * cos) is
                 * tiny: then the rounding of the vertices (and their
                 * slight non-planarity after rotation) decides. */
                double bd = prim_boundary_distance(&p, 0, &r, t), cosang = fabs(dv3_dot(nrm, dv3(r.dir))) / dlen(dv3(r.dir));
                unexplained += bd > 1e-5 && bd * cosang > 1e-6;
            }
        }
        prims_free(&p);
    }
    CHECK_MSG(far == 0, "%d of %d polygon hits differ beyond tolerance (worst %.3g, worst %.3g / cos)", far, both, worst, worst_graze);
    CHECK_MSG(unexplained == 0, "%d of %d polygon float/double disagreements are away from edges", unexplained, disagree);
    CHECK(both > 15000);
    printf("polygons: %d hits compared, worst relative t error %.3g where cos >= 0.05 (%d below), worst %.3g / cos overall, %d edge disagreements\n",
           both, worst, grazing, worst_graze, disagree);
}

static void test_polygon_boundary_distance(void)
{
    prims_t p;
    char err[256];
    prims_init(&p);
    add_outline(&p, LSHAPE, 6, NULL, 0.0f, false);
    CHECK(prims_finish(&p, err, sizeof err) == 0);
    ray_t r = make_ray(v3(0.5f, 0.5f, 1), v3(0, 0, -1), 0.0f, INFINITY);
    hit_t h = hit_none(&r);
    counters_t c = {0};
    CHECK(prim_intersect(&p, 0, &r, &h, &c) && h.t == 1.0f);
    CHECK_NEAR(prim_boundary_distance(&p, 0, &r, h.t), 0.5, 1e-12);
    r = make_ray(v3(0.75f, 0.75f, 1), v3(0, 0, -1), 0.0f, INFINITY); /* nearest: the reflex corner (1,1) */
    CHECK_NEAR(prim_boundary_distance(&p, 0, &r, 1.0), sqrt(0.125), 1e-12);
    r = make_ray(v3(1.5f, 1.5f, 1), v3(0, 0, -1), 0.0f, INFINITY); /* in the notch, 0.5 from its two edges */
    CHECK_NEAR(prim_boundary_distance(&p, 0, &r, 1.0), 0.5, 1e-12);
    r = make_ray(v3(0.5f, 0.0f, 1), v3(0, 0, -2), 0.0f, INFINITY); /* on an edge */
    CHECK_NEAR(prim_boundary_distance(&p, 0, &r, 0.5), 0.0, 1e-12);
    prims_free(&p);
}

int main(void)
{
    test_cone_cylinder_hits();
    test_cone_cone_hits();
    test_cone_tiny_far();
    test_cone_trange();
    test_cone_api_normals_counters();
    test_cone_bounds();
    test_cone_finish_errors();
    test_cone_box_overlap();
    test_cone_box_random();
    test_cone_float_double();
    test_cone_boundary_distance();
    test_polygon_gear();
    test_polygon_lshape();
    test_polygon_shared_edge();
    test_polygon_watertight();
    test_polygon_degenerate();
    test_polygon_finish_errors();
    test_triangulate();
    test_polygon_box_overlap();
    test_polygon_float_double();
    test_polygon_boundary_distance();
    return check_report();
}
