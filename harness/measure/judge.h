/* judge.h: the exact judge of disputed rays (CGAL's exact number types
 * behind a C interface; see judge.cpp for the design).
 *
 * Semantics are prims.h's, computed exactly: the ray is org + t*dir with
 * the float components converted exactly, t in units of dir, a hit counts
 * when tnear <= t < tfar (tfar may be +inf); all primitives two-sided;
 * triangles closed (edges and vertices hit), degenerate triangles and
 * polygons never hit, a ray in a triangle's plane misses; spheres and
 * cones give their nearest root in range (a tangent ray hits), a cone's
 * root only between its end planes, and a ray lying in a cone's surface
 * misses. Ties at the same exact t go to the lowest primitive id.
 * A miss returns prim HIT_NONE with t = ray->tfar (as hit_none() does).
 * Not thread-safe (verify is single-threaded). Out of memory aborts. */
#ifndef ACCELBENCH_JUDGE_H
#define ACCELBENCH_JUDGE_H
#include <stdbool.h>
#include <stddef.h>
#include "../../scenes/scene.h"
#ifdef __cplusplus
extern "C" {
#endif
typedef struct judge judge_t;
typedef struct { uint32_t prim; double t; } judge_hit; /* prim HIT_NONE when nothing is hit; t is the double nearest to the exact t */
judge_t *judge_new(const scene_t *s);   /* cheap: any search structure is built on first use of judge_closest */
void judge_free(judge_t *j);
/* Exact nearest hit in [ray->tnear, ray->tfar) among the n given primitive ids (HIT_NONE entries and duplicates ignored). */
judge_hit judge_closest_among(judge_t *j, const ray_t *r, const uint32_t *ids, int n);
/* Exact nearest hit in [ray->tnear, ray->tfar) over every primitive of the scene. */
judge_hit judge_closest(judge_t *j, const ray_t *r);
/* The exact t at which ray r meets primitive prim (in range), as text: `decimal` with 17 significant digits,
 * `exact` as a rational p/q for triangles and polygons, and for spheres and cones as the root written with rationals,
 * e.g. "(-b - sqrt(D))/a" with b, D, a printed as p/q. Returns false (and writes "miss") when prim is not hit in range. */
bool judge_describe(judge_t *j, const ray_t *r, uint32_t prim, char *decimal, size_t dlen, char *exact, size_t elen);

/* Details of judge_describe: `decimal` is "%.17g" of the double nearest to
 * the exact t (so it reads back to judge_hit.t). `exact` always writes both
 * parts of a rational ("2/1", "-1/3"); a root that is rational by
 * construction (tangent ray, D = 0, or a cone whose quadratic degenerates
 * to a linear equation) is written as that rational; otherwise
 * "(-(b) - sqrt(D))/(a)" or "(-(b) + sqrt(D))/(a)", the root of
 * a t^2 + 2 b t + c = 0 with D = b^2 - a c. Both are cut to fit dlen/elen. */

/* The candidate filter of judge_closest with a wider margin: writes into
 * ids (at most max of them) every primitive whose box, inflated by 2^-16 M
 * (M the largest coordinate magnitude of the box and the ray origin, so
 * 256 float ulps of the coordinates, against 2^-30 M for judge_closest's
 * own search), the segment [tnear, tfar] touches; every primitive of a
 * small scene. A superset of the primitives the ray hits exactly and of
 * those passing within float noise of it, so a float test run on them
 * finds the noise hits too (a shadow ray re-hitting its own surface).
 * Returns how many candidates there are; when that is more than max, only
 * the first max were written and the caller asks again with more room (as
 * with snprintf). Builds the search structure on first use. */
int judge_candidates(judge_t *j, const ray_t *r, uint32_t *ids, int max);

/* Filter statistics of the last judge_closest (for tests and tuning):
 * primitives whose inflated boxes the ray touched, and of those how many
 * needed the exact (rational) test. */
void judge_last_stats(const judge_t *j, uint32_t *candidates, uint32_t *exact_tests);
#ifdef __cplusplus
}
#endif
#endif
