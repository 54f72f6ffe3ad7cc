/* vec3.h: the small 3-vector and box math every part of accelbench uses.
 *
 * Single precision, because that is what the accelerators and Embree trace
 * with; dvec3 (double) serves prims/'s double-precision checks and the
 * surface points that secondary rays leave from (surface.c). */
#ifndef ACCELBENCH_VEC3_H
#define ACCELBENCH_VEC3_H

#include <math.h>
#include <stdbool.h>

typedef struct { float x, y, z; } vec3;
typedef struct { double x, y, z; } dvec3;

/* Axis-aligned box; an empty box has lo > hi (see box_empty()). */
typedef struct { vec3 lo, hi; } box3;

static inline vec3 v3(float x, float y, float z) { vec3 r = {x, y, z}; return r; }
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_mul(vec3 a, vec3 b) { return v3(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline vec3 v3_scale(vec3 a, float s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline vec3 v3_madd(vec3 a, vec3 b, float s) { return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s); }
static inline float v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline float v3_len(vec3 a) { return sqrtf(v3_dot(a, a)); }
static inline vec3 v3_norm(vec3 a)
{
    float l = v3_len(a);
    return l > 0.0f ? v3_scale(a, 1.0f / l) : a;
}
/* fminf and fmaxf, inline: GCC calls libm for them on x86-64 (IEEE fmin's
 * NaN rule is not minss's), and the builders' box unions made those calls
 * 6 % of a Sponza run's samples in perf. The same answers as glibc's for
 * every input but signaling NaNs (treated as quiet ones; tests/test_prims.c):
 * the smaller (larger) operand, the non-NaN one when one is NaN, a NaN
 * when both are, the first when they compare equal (for +0 and -0 glibc's
 * sign differs; a box does not care). */
static inline float f_min(float a, float b) { return b < a || a != a ? b : a; }
static inline float f_max(float a, float b) { return b > a || a != a ? b : a; }
static inline vec3 v3_min(vec3 a, vec3 b) { return v3(f_min(a.x, b.x), f_min(a.y, b.y), f_min(a.z, b.z)); }
static inline vec3 v3_max(vec3 a, vec3 b) { return v3(f_max(a.x, b.x), f_max(a.y, b.y), f_max(a.z, b.z)); }
static inline float v3_get(vec3 a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }
static inline bool v3_finite(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

static inline dvec3 dv3(vec3 a) { dvec3 r = {a.x, a.y, a.z}; return r; }
static inline dvec3 dv3_sub(dvec3 a, dvec3 b) { dvec3 r = {a.x - b.x, a.y - b.y, a.z - b.z}; return r; }
static inline double dv3_dot(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline dvec3 dv3_cross(dvec3 a, dvec3 b)
{
    dvec3 r = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    return r;
}

static inline box3 box_empty(void)
{
    box3 b = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
    return b;
}
static inline box3 box_grow(box3 b, vec3 p) { b.lo = v3_min(b.lo, p); b.hi = v3_max(b.hi, p); return b; }
static inline box3 box_union(box3 a, box3 b) { a.lo = v3_min(a.lo, b.lo); a.hi = v3_max(a.hi, b.hi); return a; }
static inline bool box_is_empty(box3 b) { return b.lo.x > b.hi.x || b.lo.y > b.hi.y || b.lo.z > b.hi.z; }
static inline vec3 box_extent(box3 b) { return v3_sub(b.hi, b.lo); }
/* The common part of two boxes (box_empty() when they do not meet). */
static inline box3 box_meet(box3 a, box3 b)
{
    a.lo = v3_max(a.lo, b.lo);
    a.hi = v3_min(a.hi, b.hi);
    return box_is_empty(a) ? box_empty() : a;
}
static inline vec3 box_center(box3 b) { return v3_scale(v3_add(b.lo, b.hi), 0.5f); }
static inline float box_diagonal(box3 b) { return v3_len(box_extent(b)); }
static inline bool box_overlap(box3 a, box3 b)
{
    return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y &&
           a.lo.z <= b.hi.z && b.lo.z <= a.hi.z;
}
static inline float box_area(box3 b)
{
    if (box_is_empty(b)) return 0.0f;
    vec3 e = box_extent(b);
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
}

#endif
