/* box4.h: a box3 held in two 4-lane registers, for the builders' passes
 * over their primitives (bounds, centroid bounds, binning: perf put 85 % of
 * the SAH build's time on Sponza in those passes and the bins' sweeps) and
 * the chopped triangle bounds of spatial splits (prim_split_bounds: 56 %
 * of a split=sbvh build on the bunny).
 *
 * With SSE2 (the x86-64 baseline: no target attribute, no dispatch) a box
 * grows by one min and one max of four lanes instead of six scalar
 * f_min/f_max calls with their NaN tests. A box3's six packed floats are
 * read as two overlapping 4-lane loads, lo in lanes 0-2 of the first and hi
 * in lanes 1-3 of the second, so nothing past the box is read; the other
 * lane of each register is never used. A point (a centroid, 12 bytes) is
 * read as 8 + 4 bytes for the same reason.
 *
 * Bit for bit box_union's: _mm_min_ps(x, acc) is x < acc ? x : acc, which
 * is f_min(acc, x) whenever acc is not NaN, and an accumulator starts at
 * +-inf and only ever takes a value of x that won a comparison, never a
 * NaN one (_mm_max_ps and f_max likewise). So the trees built through
 * box4 are the ones box_union gives (tests/test_bvh.c checks bvh_sah_best's
 * choice against a plain pass per axis, tests/test_prims.c box4 against
 * box_union and prim_split_bounds against its box_union form). Without
 * SSE2, box4 is box3 and these are box_union and box_area. */
#ifndef ACCELBENCH_PRIMS_BOX4_H
#define ACCELBENCH_PRIMS_BOX4_H

#include <stddef.h>
#include "vec3.h"

#if defined(__SSE2__)
#include <emmintrin.h>

_Static_assert(sizeof(box3) == 6 * sizeof(float) && offsetof(box3, hi) == 3 * sizeof(float),
               "box3 is six packed floats, lo then hi");
_Static_assert(sizeof(vec3) == 3 * sizeof(float), "vec3 is three packed floats");

typedef struct {
    __m128 lo, hi; /* lo in lanes 0-2, hi in lanes 1-3 */
} box4;

static inline box4 box4_empty(void) { return (box4){_mm_set1_ps(INFINITY), _mm_set1_ps(-INFINITY)}; }
static inline box4 box4_load(const box3 *b)
{
    const float *f = &b->lo.x;
    return (box4){_mm_loadu_ps(f), _mm_loadu_ps(f + 2)};
}
/* The point p as a box: lanes x, y, z, 0 and 0, x, y, z. x and y come in
 * through __m128i, a may-alias type: a load through a double pointer
 * (_mm_load_sd) is free, under strict aliasing, to move above a store to
 * p's floats, and GCC did (test_prims caught it in prim_split_bounds). */
static inline box4 box4_point(const vec3 *p)
{
    __m128 xy = _mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)(const void *)&p->x));
    __m128 xyz0 = _mm_movelh_ps(xy, _mm_load_ss(&p->z));
    return (box4){xyz0, _mm_shuffle_ps(xyz0, xyz0, _MM_SHUFFLE(2, 1, 0, 3))};
}
static inline box4 box4_union(box4 acc, box4 x) { return (box4){_mm_min_ps(x.lo, acc.lo), _mm_max_ps(x.hi, acc.hi)}; }
static inline box3 box4_store(box4 b)
{
    float l[4], h[4];
    _mm_storeu_ps(l, b.lo);
    _mm_storeu_ps(h, b.hi);
    return (box3){{l[0], l[1], l[2]}, {h[1], h[2], h[3]}};
}
/* box_area(box4_store(b)) in registers: the extent e = hi - lo, then
 * 2 ((ex ey + ey ez) + ez ex) in box_area's order; 0 for an empty box. */
static inline float box4_area(box4 b)
{
    __m128 e = _mm_sub_ps(_mm_shuffle_ps(b.hi, b.hi, _MM_SHUFFLE(0, 3, 2, 1)), b.lo);
    if (_mm_movemask_ps(_mm_cmplt_ps(e, _mm_setzero_ps())) & 7) return 0.0f;
    __m128 p = _mm_mul_ps(e, _mm_shuffle_ps(e, e, _MM_SHUFFLE(3, 0, 2, 1))); /* ex ey, ey ez, ez ex */
    __m128 s = _mm_add_ss(_mm_add_ss(p, _mm_shuffle_ps(p, p, _MM_SHUFFLE(1, 1, 1, 1))), _mm_movehl_ps(p, p));
    return 2.0f * _mm_cvtss_f32(s);
}
#else
typedef box3 box4;
static inline box4 box4_empty(void) { return box_empty(); }
static inline box4 box4_load(const box3 *b) { return *b; }
static inline box4 box4_point(const vec3 *p) { return (box3){*p, *p}; }
static inline box4 box4_union(box4 acc, box4 x) { return box_union(acc, x); }
static inline box3 box4_store(box4 b) { return b; }
static inline float box4_area(box4 b) { return box_area(b); }
#endif

#endif
