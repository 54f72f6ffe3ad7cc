/* vec3.h: the small 3-vector and box math every part of accelbench uses.
 *
 * Single precision, because that is what the accelerators and Embree trace
 * with; dvec3 (double) serves prims/'s double-precision checks, the
 * surface points that secondary rays leave from (surface.c) and the light
 * buffer's projections and solid analysis (accel/lightbuf/). */
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
/* The smaller (larger) operand by one comparison: the first when they
 * compare equal or the second is a NaN (as fminf and fmaxf ignore a NaN
 * there), a NaN first operand kept. The grid's and octree's box and
 * clipping arithmetic, which never sees a NaN first operand. */
static inline float f_min_keep(float a, float b) { return b < a ? b : a; }
static inline float f_max_keep(float a, float b) { return b > a ? b : a; }
static inline vec3 v3_min(vec3 a, vec3 b) { return v3(f_min(a.x, b.x), f_min(a.y, b.y), f_min(a.z, b.z)); }
static inline vec3 v3_max(vec3 a, vec3 b) { return v3(f_max(a.x, b.x), f_max(a.y, b.y), f_max(a.z, b.z)); }
static inline float v3_get(vec3 a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }
static inline void v3_set(vec3 *a, int axis, float x) { *(axis == 0 ? &a->x : axis == 1 ? &a->y : &a->z) = x; }
/* The largest |coordinate| (f_max_keep). */
static inline float v3_max_abs(vec3 v) { return f_max_keep(fabsf(v.x), f_max_keep(fabsf(v.y), fabsf(v.z))); }
static inline bool v3_finite(vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

static inline dvec3 dv3(vec3 a) { dvec3 r = {a.x, a.y, a.z}; return r; }
static inline dvec3 dv3_sub(dvec3 a, dvec3 b) { dvec3 r = {a.x - b.x, a.y - b.y, a.z - b.z}; return r; }
static inline double dv3_dot(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline dvec3 dv3_cross(dvec3 a, dvec3 b)
{
    dvec3 r = {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    return r;
}

static inline dvec3 dv3_madd(dvec3 a, dvec3 b, double s)
{
    dvec3 r = {a.x + b.x * s, a.y + b.y * s, a.z + b.z * s};
    return r;
}
static inline double dv3_len(dvec3 a) { return sqrt(dv3_dot(a, a)); }
static inline double dv3_get(dvec3 a, int axis) { return axis == 0 ? a.x : axis == 1 ? a.y : a.z; }
static inline void dv3_set(dvec3 *a, int axis, double x) { *(axis == 0 ? &a->x : axis == 1 ? &a->y : &a->z) = x; }
static inline dvec3 dv3_min(dvec3 a, dvec3 b)
{
    dvec3 r = {fmin(a.x, b.x), fmin(a.y, b.y), fmin(a.z, b.z)};
    return r;
}
static inline dvec3 dv3_max(dvec3 a, dvec3 b)
{
    dvec3 r = {fmax(a.x, b.x), fmax(a.y, b.y), fmax(a.z, b.z)};
    return r;
}
/* The distance from p to the segment ab (to a when a = b). */
static inline double dv3_point_segment_distance(dvec3 p, dvec3 a, dvec3 b)
{
    dvec3 ab = dv3_sub(b, a), ap = dv3_sub(p, a);
    double len2 = dv3_dot(ab, ab);
    double s = len2 > 0.0 ? dv3_dot(ap, ab) / len2 : 0.0;
    s = s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
    return dv3_len(dv3_sub(p, dv3_madd(a, ab, s)));
}

/* Distance from point q to triangle abc (Ericson, Real-Time Collision
 * Detection s5.1.5's regions, in double). */
static inline double dv3_point_triangle_distance(dvec3 q, dvec3 a, dvec3 b, dvec3 c)
{
    dvec3 ab = dv3_sub(b, a), ac = dv3_sub(c, a), ap = dv3_sub(q, a);
    double d1 = dv3_dot(ab, ap), d2 = dv3_dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return dv3_len(ap);
    dvec3 bp = dv3_sub(q, b);
    double d3 = dv3_dot(ab, bp), d4 = dv3_dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return dv3_len(bp);
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return dv3_len(dv3_sub(q, dv3_madd(a, ab, d1 / (d1 - d3))));
    dvec3 cp = dv3_sub(q, c);
    double d5 = dv3_dot(ab, cp), d6 = dv3_dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return dv3_len(cp);
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return dv3_len(dv3_sub(q, dv3_madd(a, ac, d2 / (d2 - d6))));
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
        return dv3_len(dv3_sub(q, dv3_madd(b, dv3_sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)))));
    double den = va + vb + vc;
    if (!(den > 0)) return fmin(fmin(dv3_len(ap), dv3_len(bp)), dv3_len(cp)); /* degenerate: never asked, safe anyway */
    dvec3 x = dv3_madd(dv3_madd(a, ab, vb / den), ac, vc / den);
    return dv3_len(dv3_sub(q, x));
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
