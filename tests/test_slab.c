/* test_slab: the kit's ray/box slab test (accel/common/slab.h): the
 * documented +-0 and infinite-reciprocal cases one by one, rays lying in a
 * face, edges and corners, tnear > tfar and NaN ranges, the rays
 * slab_ray_init refuses, and random rays (with zero components) against a
 * double-precision reference written the other way (explicit parallel
 * branches), for which the robust form must never miss a hit. */
#include <float.h>
#include <math.h>
#include "accel/common/slab.h"
#include "check.h"
#define PRIMS_TEST_SEED 0x51ab51ab
#include "prims_testlib.h"

static const box3 unit = {{0, 0, 0}, {1, 1, 1}};

/* Clip [t0, t1] by the unit box (or b): hit? and the interval. */
static bool clip(box3 b, vec3 o, vec3 d, float t0, float t1, float *a, float *z)
{
    slab_ray r;
    if (!slab_ray_init(&r, o, d)) return false;
    *a = t0, *z = t1;
    return slab_clip(&r, &b, a, z);
}

static void test_zero_components(void)
{
    float a, z;
    /* The documented example: a ray in the face y = 1 with dir.y = -0. */
    CHECK(clip(unit, v3(0.5f, 1.0f, 0.5f), v3(1.0f, -0.0f, 0.0f), -INFINITY, INFINITY, &a, &z));
    CHECK(a == -0.5f && z == 0.5f);
    /* The same face with +0, and the face y = 0 with both signs. */
    CHECK(clip(unit, v3(0.5f, 1.0f, 0.5f), v3(1.0f, 0.0f, 0.0f), 0.0f, INFINITY, &a, &z) && a == 0.0f && z == 0.5f);
    CHECK(clip(unit, v3(0.5f, 0.0f, 0.5f), v3(1.0f, -0.0f, 0.0f), 0.0f, INFINITY, &a, &z) && z == 0.5f);
    CHECK(clip(unit, v3(0.5f, 0.0f, 0.5f), v3(1.0f, 0.0f, 0.0f), 0.0f, INFINITY, &a, &z) && z == 0.5f);
    /* Along an edge of the box (two zero components, both on faces). */
    CHECK(clip(unit, v3(-1.0f, 1.0f, 0.0f), v3(1.0f, -0.0f, 0.0f), 0.0f, INFINITY, &a, &z) && a == 1.0f && z == 2.0f);
    CHECK(clip(unit, v3(-1.0f, 0.0f, 1.0f), v3(1.0f, 0.0f, -0.0f), 0.0f, INFINITY, &a, &z) && a == 1.0f && z == 2.0f);
    /* Parallel and outside, on either side and with either zero: a miss
     * even though tfar is +inf (both plane distances are +inf or -inf). */
    const float outside[2] = {-0.25f, 1.25f}, zeros[2] = {0.0f, -0.0f};
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < 2; k++) {
            CHECK(!clip(unit, v3(0.5f, outside[i], 0.5f), v3(1.0f, zeros[k], 0.0f), 0.0f, INFINITY, &a, &z));
            CHECK(!clip(unit, v3(0.5f, outside[i], 0.5f), v3(1.0f, zeros[k], 0.0f), -INFINITY, INFINITY, &a, &z));
        }
    /* Parallel and inside: that axis sets nothing. */
    CHECK(clip(unit, v3(0.5f, 0.5f, -2.0f), v3(0.0f, -0.0f, 1.0f), 0.0f, INFINITY, &a, &z) && a == 2.0f && z == 3.0f);
    /* A degenerate (flat) box lying in the ray's plane of motion. */
    box3 flat = {{0, 0.5f, 0}, {1, 0.5f, 1}};
    CHECK(clip(flat, v3(-1.0f, 0.5f, 0.5f), v3(1.0f, -0.0f, 0.0f), 0.0f, INFINITY, &a, &z) && a == 1.0f && z == 2.0f);
    /* A component so small its reciprocal overflows acts as a zero one. */
    float tiny = 1e-45f;
    CHECK(isinf(1.0f / tiny));
    CHECK(clip(unit, v3(0.5f, 1.0f, 0.5f), v3(1.0f, -tiny, 0.0f), 0.0f, INFINITY, &a, &z) && z == 0.5f);
    CHECK(!clip(unit, v3(0.5f, 1.5f, 0.5f), v3(1.0f, tiny, 0.0f), 0.0f, INFINITY, &a, &z));
}

static void test_edges_ranges_and_refusals(void)
{
    float a, z;
    /* Touching an edge or a corner hits with an empty-length interval. */
    CHECK(clip(unit, v3(-1.0f, 0.0f, 0.5f), v3(1.0f, 1.0f, 0.0f), 0.0f, INFINITY, &a, &z) && a == 1.0f && z == 1.0f);
    CHECK(clip(unit, v3(2.0f, 2.0f, 2.0f), v3(-1.0f, -1.0f, -1.0f), 0.0f, INFINITY, &a, &z) && a == 1.0f && z == 2.0f);
    CHECK(clip(unit, v3(-1.0f, -1.0f, 1.0f), v3(1.0f, 1.0f, 0.0f), 0.0f, INFINITY, &a, &z) && a == 1.0f && z == 2.0f); /* in the face z = 1 */
    /* The range limits the answer: ends before, starts after, inside. */
    CHECK(!clip(unit, v3(-2.0f, 0.5f, 0.5f), v3(1.0f, 0.0f, 0.0f), 0.0f, 1.5f, &a, &z));
    CHECK(!clip(unit, v3(-2.0f, 0.5f, 0.5f), v3(1.0f, 0.0f, 0.0f), 3.5f, INFINITY, &a, &z));
    CHECK(clip(unit, v3(-2.0f, 0.5f, 0.5f), v3(1.0f, 0.0f, 0.0f), 2.25f, 2.5f, &a, &z) && a == 2.25f && z == 2.5f);
    CHECK(clip(unit, v3(-2.0f, 0.5f, 0.5f), v3(1.0f, 0.0f, 0.0f), 3.0f, 3.0f, &a, &z)); /* the exit point alone */
    /* tnear > tfar, NaN range ends, a box behind the ray, an empty box. */
    CHECK(!clip(unit, v3(0.5f, 0.5f, 0.5f), v3(1.0f, 0.0f, 0.0f), 0.4f, 0.3f, &a, &z));
    CHECK(!clip(unit, v3(0.5f, 0.5f, 0.5f), v3(1.0f, 0.0f, 0.0f), NAN, INFINITY, &a, &z));
    CHECK(!clip(unit, v3(0.5f, 0.5f, 0.5f), v3(1.0f, 0.0f, 0.0f), 0.0f, NAN, &a, &z));
    CHECK(!clip(unit, v3(2.0f, 0.5f, 0.5f), v3(1.0f, 0.0f, 0.0f), 0.0f, INFINITY, &a, &z));
    CHECK(!clip(box_empty(), v3(0.5f, 0.5f, 0.5f), v3(1.0f, 0.0f, 0.0f), 0.0f, INFINITY, &a, &z));
    /* Rays that cannot hit anything are refused before any test. */
    slab_ray r;
    CHECK(!slab_ray_init(&r, v3(NAN, 0, 0), v3(1, 0, 0)));
    CHECK(!slab_ray_init(&r, v3(0, INFINITY, 0), v3(1, 0, 0)));
    CHECK(!slab_ray_init(&r, v3(0, 0, 0), v3(1, NAN, 0)));
    CHECK(!slab_ray_init(&r, v3(0, 0, 0), v3(0, -INFINITY, 0)));
    CHECK(!slab_ray_init(&r, v3(0, 0, 0), v3(0.0f, -0.0f, 0.0f)));
    CHECK(slab_ray_init(&r, v3(0, 0, 0), v3(0.0f, -0.0f, 1e-30f)));
}

/* The reference: double precision, parallel axes by an explicit branch. */
static bool ref_clip(box3 b, vec3 o, vec3 d, double *t0, double *t1)
{
    const double lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    const double oo[3] = {o.x, o.y, o.z}, dd[3] = {d.x, d.y, d.z};
    for (int k = 0; k < 3; k++) {
        if (dd[k] == 0.0) {
            if (oo[k] < lo[k] || oo[k] > hi[k]) return false;
            continue;
        }
        double ta = (lo[k] - oo[k]) / dd[k], tb = (hi[k] - oo[k]) / dd[k];
        if (ta > tb) {
            double s = ta;
            ta = tb, tb = s;
        }
        *t0 = fmax(*t0, ta);
        *t1 = fmin(*t1, tb);
    }
    return *t0 <= *t1;
}

/* Coordinates on a coarse lattice, so rays often lie in faces and hit
 * edges exactly; components are zero a quarter of the time. */
static float lattice(void) { return (float)((int)(rng_next() % 9) - 4) * 0.5f; }
static float comp(void)
{
    uint64_t k = rng_next() % 8;
    return k == 0 ? 0.0f : k == 1 ? -0.0f : k == 2 ? lattice() : rnd(-1.0f, 1.0f);
}

static void test_random_against_reference(void)
{
    int plain_diff = 0, robust_missed = 0, hits = 0, n = 200000;
    for (int i = 0; i < n; i++) {
        vec3 lo = v3(lattice(), lattice(), lattice());
        box3 b = {lo, v3_add(lo, v3(rnd(0.0f, 2.0f) * (rng_next() % 4 != 0), rnd(0.0f, 2.0f), rnd(0.0f, 2.0f)))};
        vec3 o = rng_next() % 2 ? v3(lattice(), lattice(), lattice()) : rnd_v3(-3.0f, 3.0f);
        vec3 d = v3(comp(), comp(), comp());
        if (rng_next() % 2) { /* aimed at a point of the box, some components zeroed */
            vec3 t = v3(rnd(b.lo.x, b.hi.x), rnd(b.lo.y, b.hi.y), rnd(b.lo.z, b.hi.z));
            d = v3_sub(t, o);
            if (rng_next() % 4 == 0) d.x = rng_next() % 2 ? 0.0f : -0.0f;
            if (rng_next() % 4 == 0) d.y = rng_next() % 2 ? 0.0f : -0.0f;
        }
        slab_ray r;
        if (!slab_ray_init(&r, o, d)) continue;
        double rt0 = 0.0, rt1 = INFINITY;
        bool want = ref_clip(b, o, d, &rt0, &rt1);
        float a = 0.0f, z = INFINITY, ra = 0.0f, rz = INFINITY;
        bool got = slab_clip(&r, &b, &a, &z), robust = slab_clip_robust(&r, &b, &ra, &rz);
        hits += want;
        /* The plain float test may differ only where the double interval
         * is a few float ulps long (rounding of the plane distances). */
        if (got != want && !(rt1 - rt0 <= 1e-6 * fmax(1.0, fabs(rt0)))) plain_diff++;
        if (want && !robust) robust_missed++;
    }
    printf("random rays: %d hits of %d; plain differs off the rounding band %d, robust misses %d\n", hits, n, plain_diff,
           robust_missed);
    CHECK(hits > n / 4);
    CHECK(plain_diff == 0);
    CHECK(robust_missed == 0);
}

int main(void)
{
    test_zero_components();
    test_edges_ranges_and_refusals();
    test_random_against_reference();
    return check_report();
}
