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

static inline box3 box(vec3 lo, vec3 hi)
{
    box3 b = {lo, hi};
    return b;
}

#endif
