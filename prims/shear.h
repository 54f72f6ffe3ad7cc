/* shear.h: the ray-space projection shared by the watertight kernels
 * (triangle.c, polygon.c).
 *
 * From Sven Woop, Carsten Benthin, Ingo Wald, "Watertight Ray/Triangle
 * Intersection", JCGT 2(1), 2013, section 3: permute the axes so the ray
 * direction's largest component is z, then shear so the direction becomes
 * (0, 0, 1) and the ray origin the 2D origin. A vertex's sheared x, y then
 * depend only on the vertex and the ray, so every primitive that uses the
 * vertex sees bit-identical values, and the 2D edge function of two vertices
 * changes sign exactly when their order is swapped: two primitives sharing
 * an edge can never both miss a ray through it because of rounding.
 *
 * Only static inline helpers live here; the kernels are in the .c files. */
#ifndef ACCELBENCH_SHEAR_H
#define ACCELBENCH_SHEAR_H

#include "vec3.h"

/* The watertight argument needs edge(p, q) == -edge(q, p) bit for bit.
 * Fusing p.x*q.y - p.y*q.x into an FMA rounds one product but not the
 * other, and which one depends on the operand order, so the symmetry (and
 * the watertightness) is lost on targets with FMA (aarch64, x86-64 with
 * -march=haswell or later), where GCC contracts by default in gnu11 mode:
 * tests/test_prims.c then finds rays slipping through shared edges. GCC
 * ignores "#pragma STDC FP_CONTRACT", hence its own pragma. The build also
 * passes -ffp-contract=off; this keeps the kernels right when someone
 * compiles them by hand. It applies to everything after this point in the
 * including file. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=off")
#elif defined(__clang__)
#pragma STDC FP_CONTRACT OFF
#endif

/* Per-ray constants: the axes permutation (kz = dominant direction axis)
 * and the shear that maps the ray direction onto (0, 0, 1). */
typedef struct {
    int kx, ky, kz;
    float sx, sy, sz;
} shear_t;

/* A vertex relative to the ray origin, in the sheared frame. */
typedef struct {
    float x, y, z;
} sheared_t;

static inline int shear_dominant_axis(vec3 d)
{
    float ax = fabsf(d.x), ay = fabsf(d.y), az = fabsf(d.z);
    if (ax >= ay && ax >= az) return 0;
    return ay >= az ? 1 : 2;
}

/* Ray setup: choose kz so that the division by dir[kz] is as well
 * conditioned as possible; swap kx and ky when dir[kz] < 0 so the
 * permutation keeps the primitive's winding (the sign of det). Returns
 * false for a zero or non-finite direction, which cannot hit anything. */
static inline bool ray_shear(vec3 dir, shear_t *s)
{
    s->kz = shear_dominant_axis(dir);
    s->kx = (s->kz + 1) % 3;
    s->ky = (s->kx + 1) % 3;
    float dz = v3_get(dir, s->kz);
    if (dz < 0.0f) {
        int tmp = s->kx;
        s->kx = s->ky;
        s->ky = tmp;
    }
    /* Every field written even when the ray is refused (a division by 0
     * or of NaN is then harmless), so that a caller may keep s beside the
     * answer (accel/bvh_wide/wide_walk.h) without the compiler seeing fields
     * that might be unset. */
    s->sx = v3_get(dir, s->kx) / dz;
    s->sy = v3_get(dir, s->ky) / dz;
    s->sz = 1.0f / dz;
    return dz != 0.0f && v3_finite(dir);
}

/* Shear: translate to the ray origin and shear. Every primitive that
 * uses a vertex gets exactly the same sheared coordinates for it. */
static inline sheared_t shear_vertex(const shear_t *s, vec3 p, vec3 org)
{
    vec3 r = v3_sub(p, org);
    float rz = v3_get(r, s->kz);
    sheared_t out;
    out.x = v3_get(r, s->kx) - s->sx * rz;
    out.y = v3_get(r, s->ky) - s->sy * rz;
    out.z = rz; /* scaled by sz later, only once the 2D test has passed */
    return out;
}

/* 2D edge function: twice the signed area of (origin, p, q). Its sign says
 * on which side of the projected edge p-q the ray (the origin) lies. */
static inline float edge_function(sheared_t p, sheared_t q)
{
    return p.x * q.y - p.y * q.x;
}

/* The paper's fallback: when a float edge function is exactly 0 the ray
 * may really be on the edge, or the two products may merely have rounded
 * to the same value. The product of two floats is exact in double, so one
 * subtraction there gives the exact sign: 0 only when the ray is truly on
 * the edge (barring float underflow of the result). */
static inline float edge_function_double(sheared_t p, sheared_t q)
{
    return (float)((double)p.x * (double)q.y - (double)p.y * (double)q.x);
}

#endif
