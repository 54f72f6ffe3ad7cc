/* prims_testlib.h: deterministic random inputs and ray/box builders shared
 * by the primitive tests. Define PRIMS_TEST_SEED before including: each
 * test program keeps its own fixed sequence. */
#ifndef ACCELBENCH_PRIMS_TESTLIB_H
#define ACCELBENCH_PRIMS_TESTLIB_H

#include <string.h>
#include "prims/prims.h"

static uint64_t rng_state = PRIMS_TEST_SEED;

/* splitmix64: small, deterministic, good enough for test inputs. */
static inline uint64_t rng_next(void)
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static inline double rndd(double lo, double hi) { return lo + (hi - lo) * ((double)(rng_next() >> 11) * (1.0 / 9007199254740992.0)); }
static inline float rnd(float lo, float hi) { return (float)rndd(lo, hi); }
static inline vec3 rnd_v3(float lo, float hi) { return v3(rnd(lo, hi), rnd(lo, hi), rnd(lo, hi)); }

static inline ray_t make_ray(vec3 org, vec3 dir, float tnear, float tfar)
{
    ray_t r;
    memset(&r, 0, sizeof r);
    r.org = org;
    r.dir = dir;
    r.tnear = tnear;
    r.tfar = tfar;
    r.light = RAY_NO_LIGHT;
    return r;
}

/* A ray from org through target (dir = target - org, so target is t = 1). */
static inline ray_t ray_through(vec3 org, vec3 target) { return make_ray(org, v3_sub(target, org), 0.0f, INFINITY); }

/* A direction uniform on the unit sphere (rejection from the cube). */
static inline vec3 random_dir(void)
{
    for (;;) {
        vec3 d = rnd_v3(-1, 1);
        float l = v3_len(d);
        if (l > 1e-3f && l <= 1.0f) return v3_scale(d, 1.0f / l);
    }
}

/* A random line that meets box bx, uniform in the measure of lines
 * (direction uniform on the sphere, then a point uniform on the plane
 * across it, kept when the line meets the box), as a ray from far away. */
static inline ray_t random_line(box3 bx)
{
    vec3 c = box_center(bx);
    float r = 0.5f * box_diagonal(bx);
    for (;;) {
        vec3 d = random_dir();
        vec3 u = v3_norm(v3_cross(d, fabsf(d.x) < 0.9f ? v3(1, 0, 0) : v3(0, 1, 0))), w = v3_cross(d, u);
        float a = rnd(-r, r), e = rnd(-r, r);
        if (a * a + e * e > r * r) continue;
        vec3 o = v3_sub(v3_add(c, v3_add(v3_scale(u, a), v3_scale(w, e))), v3_scale(d, 4.0f * r));
        float t0 = 0, t1 = INFINITY;
        bool meets = true;
        for (int k = 0; k < 3 && meets; k++) {
            float oo = v3_get(o, k), dd = v3_get(d, k), lo = v3_get(bx.lo, k), hi = v3_get(bx.hi, k);
            if (dd == 0.0f) {
                meets = oo >= lo && oo <= hi;
                continue;
            }
            float ta = (lo - oo) / dd, tb = (hi - oo) / dd;
            if (ta > tb) { float x = ta; ta = tb; tb = x; }
            t0 = ta > t0 ? ta : t0;
            t1 = tb < t1 ? tb : t1;
            meets = t0 <= t1;
        }
        if (meets) return make_ray(o, d, 0.0f, INFINITY);
    }
}

static inline box3 box(vec3 lo, vec3 hi)
{
    box3 b = {lo, hi};
    return b;
}

/* n groups around random centres in [-spread, spread]^3, each a triangle
 * of size about 1 plus, in turn, a sphere, a cone, a parallelogram polygon
 * or nothing: every primitive kind, overlapping. Call prims_finish after. */
static inline void rnd_soup(prims_t *p, int n, float spread)
{
    for (int i = 0; i < n; i++) {
        vec3 c = rnd_v3(-spread, spread);
        uint32_t v[4];
        for (int k = 0; k < 3; k++) v[k] = prims_add_vertex(p, v3_add(c, rnd_v3(-1.0f, 1.0f)));
        prims_add_triangle(p, v[0], v[1], v[2]);
        if (i % 4 == 0) prims_add_sphere(p, c, rnd(0.1f, 1.0f));
        if (i % 4 == 1) prims_add_cone(p, c, rnd(0.1f, 0.8f), v3_add(c, rnd_v3(-2.0f, 2.0f)), rnd(0.0f, 0.8f));
        if (i % 4 == 2) {
            vec3 u = rnd_v3(-1.0f, 1.0f), w = rnd_v3(-1.0f, 1.0f);
            vec3 pts[4] = {c, v3_add(c, u), v3_add(v3_add(c, u), w), v3_add(c, w)};
            for (int k = 0; k < 4; k++) v[k] = prims_add_vertex(p, pts[k]);
            prims_add_polygon(p, v, 4);
        }
    }
}

/* The reference answer of a traversal test: every primitive, closest hit
 * into *hit or (shadow) whether any occludes. */
static inline bool exhaustive(const prims_t *p, const ray_t *ray, hit_t *hit, bool shadow)
{
    for (uint32_t id = 0; id < p->count; id++) {
        if (shadow && prim_occluded_fast(p, id, ray)) return true;
        if (!shadow) prim_intersect_fast(p, id, ray, hit);
    }
    return !shadow && hit->prim != HIT_NONE;
}

#endif
