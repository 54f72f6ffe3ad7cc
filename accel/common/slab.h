/* slab.h: the ray/box slab test of the accelerators (Kay and Kajiya,
 * "Ray Tracing Complex Scenes", SIGGRAPH 1986: a box is the intersection
 * of three slabs, and the ray is inside the box over the intersection of
 * its three slab intervals).
 *
 * Per axis the near plane is picked by the SIGN of the reciprocal, not by
 * comparing the two plane distances (Williams, Barrus, Morley, Shirley, "An
 * Efficient and Robust Ray-Box Intersection Algorithm", JGT 10(1), 2005).
 * That is what makes +-0 direction components right: 1/+0 = +inf and
 * 1/-0 = -inf, both of the correct sign, so a ray parallel to a slab gets
 * -inf/+inf (inside it) or an empty interval (outside it) with no branch.
 *
 * Definitions (the box is CLOSED, as prims/'s box overlap is):
 * - A ray parallel to a slab (direction component +0 or -0) is inside it
 *   exactly when lo <= org <= hi; then the slab does not limit t.
 * - On the slab's plane (org == lo or org == hi, direction component +-0)
 *   the plane's distance is 0 * inf = NaN. NaN never wins the max/min
 *   below (a comparison with NaN is false), so the slab imposes nothing:
 *   a ray lying in a face of the box is inside it. Example (tested): box
 *   [0,1]^3, org (0.5, 1, 0.5), dir (1, -0.0, 0): hits over [-0.5, 0.5].
 * - A direction component so small that its reciprocal overflows to inf
 *   behaves as a parallel one (exact up to t of about 1e38).
 * - Outside a parallel slab both of its plane distances are +inf (or both
 *   -inf), so the interval is empty even when the ray's tfar is +inf: an
 *   interval that starts at +inf or ends at -inf is a miss.
 * - The interval is [t0, t1] with both ends included: a ray that only
 *   touches an edge or a corner hits (t0 == t1).
 * - tnear > tfar, or a NaN in either: a miss.
 * slab_ray_init() refuses rays no primitive can hit (a NaN or infinite
 * component in org or dir, or dir = 0: prims/ rejects all of those), so a
 * traversal can return "miss" before any box test and this test never sees
 * them.
 *
 * Rounding: each t is (plane - org) * inv, two roundings plus the rounding
 * of inv, so a t can be off by about 1.5 float ulps. slab_clip() is the
 * plain float test (the grids pad their boxes by a position slack instead);
 * slab_clip_robust() scales every far t by SLAB_FAR_SCALE >= 1 + 2 gamma_3
 * (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013), which makes the
 * float test never reject a box the exact ray meets.
 *
 * Memory: a slab_ray is 24 bytes (origin and reciprocal direction), made
 * once per ray. */
#ifndef ACCELBENCH_SLAB_H
#define ACCELBENCH_SLAB_H

#include <float.h>
#include <stdbool.h>
#include "../../prims/ray.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    float org[3]; /* ray origin */
    float inv[3]; /* 1 / dir per axis: +-inf for a +-0 component */
} slab_ray;

/* 1 + 4 FLT_EPSILON = 1 + 2^-21 > 1 + 2 gamma_3 = 1 + 3.6e-7 (Ize 2013). */
#define SLAB_FAR_SCALE (1.0f + 4.0f * FLT_EPSILON)

/* Set up r for the ray (org, dir). false: the ray cannot hit anything (a
 * NaN or infinite component, or a zero direction); r is then unusable. */
static inline bool slab_ray_init(slab_ray *r, vec3 org, vec3 dir)
{
    if (!v3_finite(org) || !v3_finite(dir) || (dir.x == 0.0f && dir.y == 0.0f && dir.z == 0.0f)) return false;
    r->org[0] = org.x, r->org[1] = org.y, r->org[2] = org.z;
    r->inv[0] = 1.0f / dir.x, r->inv[1] = 1.0f / dir.y, r->inv[2] = 1.0f / dir.z;
    return true;
}

/* One axis: narrow [*t0, *t1] to the slab [lo, hi]. far_scale is 1 or
 * SLAB_FAR_SCALE, a constant at every call site. */
static inline void slab_axis(float org, float inv, float lo, float hi, float far_scale, float *t0, float *t1)
{
    bool neg = inv < 0.0f;
    float tn = ((neg ? hi : lo) - org) * inv;
    float tf = ((neg ? lo : hi) - org) * inv * far_scale;
    if (tn > *t0) *t0 = tn; /* a NaN (on the plane of a parallel slab) never wins */
    if (tf < *t1) *t1 = tf;
}

static inline __attribute__((always_inline)) bool slab_clip_scaled(const slab_ray *r, const box3 *b, float *t0,
                                                                   float *t1, const float far_scale)
{
    float a = *t0, z = *t1;
    slab_axis(r->org[0], r->inv[0], b->lo.x, b->hi.x, far_scale, &a, &z);
    slab_axis(r->org[1], r->inv[1], b->lo.y, b->hi.y, far_scale, &a, &z);
    slab_axis(r->org[2], r->inv[2], b->lo.z, b->hi.z, far_scale, &a, &z);
    *t0 = a, *t1 = z;
    return a <= z && a < INFINITY && z > -INFINITY;
}

/* Narrow [*t0, *t1] to the part of the ray inside the closed box b; true
 * when that part is not empty. On false, *t0 and *t1 hold the empty
 * interval (callers do not use them). An empty box (lo > hi) misses. */
static inline bool slab_clip(const slab_ray *r, const box3 *b, float *t0, float *t1)
{
    return slab_clip_scaled(r, b, t0, t1, 1.0f);
}

/* The same, conservative against rounding (far ends scaled, see above). */
static inline bool slab_clip_robust(const slab_ray *r, const box3 *b, float *t0, float *t1)
{
    return slab_clip_scaled(r, b, t0, t1, SLAB_FAR_SCALE);
}

#ifdef __cplusplus
}
#endif

#endif
