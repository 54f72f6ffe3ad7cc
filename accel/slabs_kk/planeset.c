/* planeset.c: the plane-set normals and the per-ray constants of the
 * plane-set volume test (planeset.h says what they guarantee and why). */
#include <float.h>
#include <string.h>
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

/* ------------------------------------------------------ surface area */

enum { FACE_MAX = 4 + 2 * PLANESET_MAX }; /* a square clipped by 2K - 1 planes gains at most one vertex each */

typedef struct {
    double n[3], d; /* the half-space n . x <= d */
} halfspace;

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* Keep the part of polygon p (n vertices) in h, within tol; returns the
 * new vertex count. */
static int clip_polygon(double p[][3], int n, const halfspace *h, double tol)
{
    double out[FACE_MAX + 2][3];
    int m = 0;
    for (int i = 0; i < n; i++) {
        const double *a = p[i], *b = p[(i + 1) % n];
        double da = dot3(h->n, a) - h->d, db = dot3(h->n, b) - h->d;
        bool ina = da <= tol, inb = db <= tol;
        if (ina && m < FACE_MAX + 2) memcpy(out[m++], a, sizeof out[0]);
        if (ina != inb && m < FACE_MAX + 2) {
            double t = da / (da - db);
            for (int k = 0; k < 3; k++) out[m][k] = a[k] + t * (b[k] - a[k]);
            m++;
        }
    }
    memcpy(p, out, (size_t)m * sizeof out[0]);
    return m;
}

double planeset_area(const planeset_slab *v, uint32_t K)
{
    if (K == 3) { /* a box */
        if (!(v[0][0] <= v[0][1] && v[1][0] <= v[1][1] && v[2][0] <= v[2][1])) return 0.0;
        double x = (double)v[0][1] - v[0][0], y = (double)v[1][1] - v[1][0], z = (double)v[2][1] - v[2][0];
        return 2.0 * (x * y + y * z + z * x);
    }
    halfspace h[2 * PLANESET_MAX];
    double scale = 0.0;
    for (uint32_t k = 0; k < K; k++) {
        if (!(v[k][0] <= v[k][1])) return 0.0; /* empty (or NaN) */
        for (int s = 0; s < 2; s++) {
            double sign = s ? -1.0 : 1.0;
            for (int c = 0; c < 3; c++) h[2 * k + s].n[c] = sign * planeset_normals[k][c];
            h[2 * k + s].d = sign * (s ? v[k][0] : v[k][1]);
            scale = fmax(scale, fabs(v[k][0]) + fabs(v[k][1]));
        }
    }
    /* Every point of the polytope is within sqrt(3) scale of the origin
     * (the axis slabs bound it) and each plane's point nearest the origin
     * within scale of it, so a square of half-side 4 (scale + ext) about
     * that point covers the plane's face. */
    double ext = 0.0;
    for (int c = 0; c < 3; c++) ext += (double)v[c][1] - v[c][0];
    const double half = 4.0 * (scale + ext) + 1.0, tol = 1e-12 * (scale + ext);
    double area = 0.0;
    for (uint32_t f = 0; f < 2 * K; f++) {
        const double *n = h[f].n;
        double nn = dot3(n, n), o[3], u[3], w[3];
        for (int c = 0; c < 3; c++) o[c] = n[c] * h[f].d / nn;
        /* u: a unit vector across n; w = n x u / |n|. */
        double a[3] = {fabs(n[0]) < 0.5 ? 1.0 : 0.0, fabs(n[0]) < 0.5 ? 0.0 : 1.0, 0.0};
        u[0] = n[1] * a[2] - n[2] * a[1], u[1] = n[2] * a[0] - n[0] * a[2], u[2] = n[0] * a[1] - n[1] * a[0];
        double lu = sqrt(dot3(u, u)), ln = sqrt(nn);
        for (int c = 0; c < 3; c++) u[c] /= lu;
        w[0] = (n[1] * u[2] - n[2] * u[1]) / ln, w[1] = (n[2] * u[0] - n[0] * u[2]) / ln,
        w[2] = (n[0] * u[1] - n[1] * u[0]) / ln;
        double p[FACE_MAX + 2][3];
        static const double corner[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
        for (int i = 0; i < 4; i++)
            for (int c = 0; c < 3; c++) p[i][c] = o[c] + half * (corner[i][0] * u[c] + corner[i][1] * w[c]);
        int m = 4;
        for (uint32_t g = 0; g < 2 * K && m >= 3; g++)
            if (g != f) m = clip_polygon(p, m, &h[g], tol);
        /* The polygon's area: half the length of the sum of its edges'
         * cross products about vertex 0. */
        double s[3] = {0, 0, 0};
        for (int i = 1; i + 1 < m; i++) {
            double e1[3], e2[3];
            for (int c = 0; c < 3; c++) e1[c] = p[i][c] - p[0][c], e2[c] = p[i + 1][c] - p[0][c];
            s[0] += e1[1] * e2[2] - e1[2] * e2[1];
            s[1] += e1[2] * e2[0] - e1[0] * e2[2];
            s[2] += e1[0] * e2[1] - e1[1] * e2[0];
        }
        area += 0.5 * sqrt(dot3(s, s));
    }
    return area;
}
