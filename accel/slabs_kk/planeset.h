/* planeset.h: the ray test of Kay and Kajiya's plane-set bounding volumes
 * (Kay and Kajiya, "Ray Tracing Complex Scenes", SIGGRAPH 1986; survey
 * s4.4, figure 8): a volume is the intersection of slabs, one per normal of
 * a fixed set, slab k being { x : lo_k <= N_k . x <= hi_k }.
 *
 * The normals: the three axes, then the four cube diagonals, as Kay and
 * Kajiya used; a set is the first 3 or all 7 (PLANESET_NORMALS). They are
 * NOT normalised: every component is -1, 0 or 1, so N . x of float x is a
 * sum of (at most three) floats, exact in the extents (prims/ prim_extent
 * takes any length) and nearly so per ray. A slab's [lo, hi] along an
 * unnormalised normal is the same volume as along the unit one, scaled.
 *
 * Per-ray constants (survey s4.4: "common expressions ... factored out and
 * done once per ray"): for each normal the origin's N . O and the
 * reciprocal of N . D, so that each slab then costs two subtractions, two
 * multiplications and the comparisons that narrow the interval:
 *     t_near = (near plane - s_near) * inv_near
 *     t_far  = (far plane  - s_far)  * inv_far
 * The near plane is lo when N . D > 0, else hi: chosen per ray, by the sign
 * (Williams et al., JGT 2005, as accel/common/slab.h does per axis).
 *
 * Conservative (never rejects a volume the exact ray meets, up to the
 * limits below): where slab.h scales every far t by 1 + 2^-21 (Ize 2013),
 * here the scales are folded into the per-ray constants, so the test has
 * no extra multiplication. planeset_ray_init() works in double:
 * - N . O and N . D are sums of up to three floats, done in double with
 *   every rounding detected (Knuth's TwoSum) and bounded (2 DBL_EPSILON
 *   times the sum of magnitudes when one happened);
 * - s_near and s_far are N . O rounded to float in the direction that
 *   moves each plane distance toward the ray's side: t_near only smaller,
 *   t_far only larger (exact when N . O is a float: always for the axes);
 * - inv_near and inv_far are 1 / N . D over the bound of N . D, shrunk and
 *   grown by 2^-20 relative (covering the float subtraction and
 *   multiplication of the test, 2^-24 each, and the double steps), each
 *   rounded to nearest float, and inv_near clamped to FLT_MAX.
 * So a computed t_near >= 0 is at most the exact one and a computed
 * t_far >= 0 at least the exact one; the signs are those of the exact
 * values or on the accepting side, and negative values never decide
 * (the interval starts at the ray's tnear >= 0).
 *
 * Parallel slabs. N . D exactly 0 (a +0 or -0 direction component on an
 * axis, or a direction like (1, -1, 0) on a diagonal; the sign of the zero
 * does not matter): inv = +inf, lo is the near plane. Then t_near is
 * (lo - s_near) * inf: -inf when lo < s_near (no limit), +inf when lo >
 * s_near (the ray misses: outside the slab, whatever its range), NaN when
 * lo == s_near, which never wins the comparisons (the ray lies in the
 * plane: inside); likewise t_far against hi. So the ray is inside the
 * slab exactly when lo <= N . O <= hi, decided by N . O alone, exactly
 * when N . O is a float (always on an axis) and conservatively by an ulp
 * otherwise. A direction component so small that 1 / N . D overflows is
 * not parallel: inv_far is +inf (t_far +inf or NaN: no limit), inv_near
 * FLT_MAX (a t_near past FLT_MAX is +inf: such a volume is entered beyond
 * any float distance and misses).
 * A sum N . D whose rounding leaves its sign unknown (|N . D| within the
 * bound, only when its three terms differ in size by more than 2^29) makes
 * the slab impose nothing for this ray: s_near = +inf, s_far = -inf.
 *
 * Limits: results in the subnormal range (|t| < 2^-126) carry an absolute
 * error of 2^-149, outside the relative bounds. Rays that cannot hit
 * anything (a NaN or infinite component, a zero direction) are refused by
 * planeset_ray_init.
 *
 * Memory: a planeset_ray is 4 + 7 * 17 bytes (about 124), made once per ray;
 * a volume is 2 floats per normal (24 or 56 bytes). */
#ifndef ACCELBENCH_PLANESET_H
#define ACCELBENCH_PLANESET_H

#include <assert.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include "../../prims/ray.h"

#ifdef __cplusplus
extern "C" {
#endif

#define PLANESET_MAX 7

/* The normals, axes first: planeset_normals[0 .. count). */
extern const float planeset_normals[PLANESET_MAX][3];

/* A volume's slab k: slab[k][0] = lo, slab[k][1] = hi. */
typedef float planeset_slab[2];

/* The surface area of volume v over the first K normals (3 or 7): the
 * convex polytope { lo_k <= N_k . x <= hi_k }, each of its 2K planes'
 * faces clipped by the other half-spaces (Sutherland-Hodgman), in double.
 * A flat volume (lo == hi on a normal) counts both sides, as the measure of
 * the lines meeting a flat body asks; an empty one (lo > hi) is 0. The
 * cost model's P(a line meets v) = area(v) / area(root) (Cauchy-Crofton). */
double planeset_area(const planeset_slab *v, uint32_t K);

typedef struct {
    uint32_t count;                  /* normals used: 3 or 7 */
    uint8_t near[PLANESET_MAX];      /* 0: lo is the near plane (N . D > 0 or parallel), 1: hi */
    float s_near[PLANESET_MAX];      /* N . O rounded so that t_near only shrinks */
    float s_far[PLANESET_MAX];       /* N . O rounded so that t_far only grows */
    float inv_near[PLANESET_MAX];    /* ~1 / N . D, magnitude rounded down (FLT_MAX at most) */
    float inv_far[PLANESET_MAX];     /* ~1 / N . D, magnitude rounded up (may be inf) */
} planeset_ray;
static_assert(sizeof(planeset_ray) == 124, "planeset_ray is 124 bytes");

/* Set up r for the ray (org, dir) over the first count (3 or 7) normals.
 * false: the ray cannot hit anything (a NaN or infinite component, a zero
 * direction) or count is neither 3 nor 7; r is then unusable. */
bool planeset_ray_init(planeset_ray *r, uint32_t count, vec3 org, vec3 dir);

/* Narrow [*t0, *t1] to the part of the ray inside the volume slab[0 .. K)
 * (the closed volume: touching counts); true when that part is not empty,
 * and then *t0 is the entry distance (Kay and Kajiya's "estimated
 * distance"). K is r->count, a constant at every call site so the loop
 * unrolls. *t0 must be >= 0 (a ray's tnear): the conservative rounding
 * covers distances ahead of the origin, not behind it. On false *t0 and
 * *t1 are not meaningful. */
static inline __attribute__((always_inline)) bool planeset_clip(const planeset_ray *r, const planeset_slab *slab,
                                                                const uint32_t K, float *t0, float *t1)
{
    float a = *t0, z = *t1;
    for (uint32_t k = 0; k < K; k++) {
        const uint32_t n = r->near[k];
        float tn = (slab[k][n] - r->s_near[k]) * r->inv_near[k];
        float tf = (slab[k][1 - n] - r->s_far[k]) * r->inv_far[k];
        if (tn > a) a = tn; /* a NaN (a ray in the plane of a parallel slab) never wins */
        if (tf < z) z = tf;
    }
    *t0 = a, *t1 = z;
    return a <= z && a < INFINITY && z > -INFINITY;
}

#ifdef __cplusplus
}
#endif

#endif
