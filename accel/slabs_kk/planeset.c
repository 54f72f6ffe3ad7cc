/* planeset.c: the plane-set normals and the per-ray constants of the
 * plane-set volume test (planeset.h says what they guarantee and why). */
#include <float.h>
#include "planeset.h"

const float planeset_normals[PLANESET_MAX][3] = {
    {1, 0, 0}, {0, 1, 0}, {0, 0, 1},                       /* the axes: an AABB */
    {1, 1, 1}, {-1, 1, 1}, {1, -1, 1}, {1, 1, -1},         /* the cube diagonals */
};

/* The rounding error of s = a + b, exactly (TwoSum, Knuth TAOCP vol. 2
 * s4.2.2): 0 when the sum was exact. */
static inline double sum_error(double a, double b, double s)
{
    double bb = s - a;
    return (a - (s - bb)) + (b - bb);
}

/* N . v in double over the four diagonals (components -1 or 1, so each
 * term is exact), and a bound on the error of each sum: 0 when neither
 * addition rounded, else 2 DBL_EPSILON times the sum of magnitudes (twice
 * the gamma_2 bound of two additions). Straight-line over the four, so
 * that the compiler can vectorise it. */
static inline void dot_diagonals(vec3 v, double dot[4], double err[4])
{
    for (int k = 0; k < 4; k++) {
        const float *n = planeset_normals[3 + k];
        double x = n[0] * (double)v.x, y = n[1] * (double)v.y, z = n[2] * (double)v.z;
        double xy = x + y, s = xy + z;
        bool exact = (sum_error(x, y, xy) == 0.0) & (sum_error(xy, z, s) == 0.0);
        dot[k] = s;
        err[k] = exact ? 0.0 : 2.0 * DBL_EPSILON * (fabs(x) + fabs(y) + fabs(z));
    }
}

/* x rounded to a float no greater (round_down) or no less (round_up)
 * than it, without a branch: nudged by 2^-23 relative (more than the
 * 2^-24 that rounding to nearest can move it back) and by 2^-149 (the
 * subnormal step), then rounded to nearest. At most two floats off the
 * directed rounding; the slab only needs it on the safe side. */
static inline float round_down(double x) { return (float)(x - fabs(x) * 0x1p-23 - 0x1p-149); }
static inline float round_up(double x) { return (float)(x + fabs(x) * 0x1p-23 + 0x1p-149); }

/* Relative margins of the reciprocals: 2^-20 covers the test's float
 * subtraction and multiplication (2^-24 each), the float rounding of the
 * reciprocal (2^-24) and the double steps before it (2^-53 each). */
#define INV_SHRINK (1.0 - 0x1p-20)
#define INV_GROW (1.0 + 0x1p-20)

/* The constants of slab k from N . O (within err_o) and N . D (within
 * err_d). */
static inline __attribute__((always_inline)) void set_slab(planeset_ray *r, uint32_t k, double so, double err_o,
                                                           double sd, double err_d)
{
    /* N . O itself when it is exactly a float (always on an axis), else
     * rounded outward; both computed, one selected (no branch). */
    const float o_exact = (float)so, o_up_rounded = round_up(so + err_o), o_down_rounded = round_down(so - err_o);
    const bool exact = (err_o == 0.0) & ((double)o_exact == so);
    const float o_up = exact ? o_exact : o_up_rounded, o_down = exact ? o_exact : o_down_rounded;
    double m = fabs(sd);
    if (sd == 0.0 && err_d == 0.0) {
        /* Exactly parallel: inside or outside by N . O alone. */
        r->near[k] = 0;
        r->s_near[k] = o_up, r->s_far[k] = o_down;
        r->inv_near[k] = r->inv_far[k] = INFINITY;
        return;
    }
    if (m <= err_d) {
        /* The sign of N . D is not known: this slab limits nothing. */
        r->near[k] = 0;
        r->s_near[k] = INFINITY, r->s_far[k] = -INFINITY;
        r->inv_near[k] = r->inv_far[k] = INFINITY;
        return;
    }
    /* Selections by the sign are indexed and copysign'd, not branched:
     * ray directions have random signs, and mispredicted branches cost
     * more here than all the arithmetic. */
    const uint32_t neg = sd < 0.0;
    const float o[2] = {o_up, o_down};
    r->near[k] = (uint8_t)neg;
    r->s_near[k] = o[neg];
    r->s_far[k] = o[1 - neg];
    /* 1 / |N . D| lies in [1 / (m + err_d), 1 / (m - err_d)]. */
    const double small = INV_SHRINK / (m + err_d), large = INV_GROW / (m - err_d);
    r->inv_near[k] = copysignf(small < FLT_MAX ? (float)small : FLT_MAX, (float)sd);
    r->inv_far[k] = copysignf(large < FLT_MAX ? (float)large : INFINITY, (float)sd);
}

bool planeset_ray_init(planeset_ray *r, uint32_t count, vec3 org, vec3 dir)
{
    if ((count != 3 && count != PLANESET_MAX) || !v3_finite(org) || !v3_finite(dir) ||
        (dir.x == 0.0f && dir.y == 0.0f && dir.z == 0.0f))
        return false;
    r->count = count;
    /* The axes: N . O and N . D are the components themselves, exact. */
    const float o[3] = {org.x, org.y, org.z}, d[3] = {dir.x, dir.y, dir.z};
    for (uint32_t k = 0; k < 3; k++) set_slab(r, k, o[k], 0.0, d[k], 0.0);
    if (count == PLANESET_MAX) {
        double so[4], err_o[4], sd[4], err_d[4];
        dot_diagonals(org, so, err_o);
        dot_diagonals(dir, sd, err_d);
        for (uint32_t k = 0; k < 4; k++) set_slab(r, 3 + k, so[k], err_o[k], sd[k], err_d[k]);
    }
    return true;
}
