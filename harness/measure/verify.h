/* verify.h: comparing an accelerator's answers with the reference's.
 *
 * Rule (DESIGN.md): a ray agrees when both miss, or both hit with
 * |t - t_ref| <= 1e-4 * max(1, |t_ref|) (any primitive: shared edges and
 * coincident faces give different ids at the same distance). Any-hit rays
 * agree when both say the same. Every other ray is a mismatch, put in the
 * first class that applies, in this order:
 *
 *   edge      the ray passes within float noise of the boundary of a
 *             disputed primitive (the one either side hit, or the judge's):
 *             its hit point is within EDGE_ULPS * u * M of an edge or vertex
 *             of its triangle or polygon, of a sphere's silhouette or a
 *             cone's rim or silhouette, or the ray skims the surface (|cos|
 *             between ray and normal < GRAZE_COS, where t's error grows
 *             like 1/cos);
 *   origin    the ray starts within ORIGIN_ULPS * u * M of a disputed
 *             primitive (for a triangle, the origin's distance from its
 *             plane, computed in double; for other primitives, how far the
 *             hit on it lies from the origin along the normal, t |d . n|):
 *             an ill-posed ray whose answer rounding decides; counted apart
 *             and never real. (The origin's distance is measured, not
 *             read from a hit's t: another test's float t that close to
 *             the origin, on a thin wall seen edge-on, may be off by many
 *             times that distance);
 *   tol       the same primitive, t off by no more than
 *             TOL_ULPS * u * (|o| + t |d|) / (|d| max(|cos|, GRAZE_COS)): a
 *             few float steps of the coordinates at the hit, magnified by
 *             the incidence; for any-hit rays, a judged hit that lies that
 *             close to either end of [tnear, tfar);
 *   refwrong  the exact judge (judge.h: CGAL's exact kernels) sides with the
 *             accelerator: the reference is wrong;
 *   real      the judge sides with the reference (or with neither) and no
 *             noise class applies: a bug. A real mismatch fails `verify`;
 *   unjudged  the judge's time budget for the cell was spent before this
 *             ray's turn: counted, never hidden, and reported.
 *
 * Here u = 2^-24 (float's unit roundoff) and M = |o|_inf + the largest
 * coordinate magnitude of the primitive's bounds: the size of the numbers a
 * float test subtracts and multiplies (vertices minus origin, the origin
 * itself), so the noise bounds scale with the coordinates, not with the
 * scene's size or a fixed epsilon. The judge sees the disputed primitives
 * when both sides hit, and every primitive when one side missed or for
 * any-hit rays.
 *
 * A ray is ill-posed when the reference's nearest hit on it lies within the
 * origin bound: every ray set reports how many (verify_count_illposed). */
#ifndef ACCELBENCH_VERIFY_H
#define ACCELBENCH_VERIFY_H

#include "judge.h"
#include "../workloads/rayset.h"
#include "../workloads/trace.h"

#define EDGE_ULPS 64.0
#define ORIGIN_ULPS 64.0
#define TOL_ULPS 64.0
#define GRAZE_COS 1e-3
#define VERIFY_LIST_MAX 20
/* The judge's default time budget per cell (verify --judge-seconds). */
#define VERIFY_JUDGE_SECONDS 20.0

typedef enum { MM_EDGE = 0, MM_ORIGIN, MM_TOL, MM_REFWRONG, MM_REAL, MM_UNJUDGED, MM_CLASSES } mismatch_class;
extern const char *const mismatch_class_name[MM_CLASSES];

typedef struct {
    uint32_t ray;
    mismatch_class cls;
    hit_t got, ref;          /* closest-hit rays */
    uint8_t got_occ, ref_occ;/* any-hit rays */
    bool judged;             /* the judge ran on this ray */
    judge_hit exact;         /* its answer (prim HIT_NONE: nothing hit) */
} mismatch_t;

typedef struct {
    uint64_t agree;
    uint64_t mismatches[MM_CLASSES];
    double judge_ms;         /* time the judge spent in this cell */
    uint64_t judged;         /* rays it judged */
    uint32_t nlisted;
    mismatch_t listed[VERIFY_LIST_MAX]; /* the first mismatches, in ray order; real ones first */
} verify_result;

/* One scene's verifier: it owns the judge, so the judge's search structure
 * is built once per scene and serves every cell. judge_seconds bounds the
 * judge's time per verifier_check call (<= 0: unlimited). */
typedef struct verifier verifier_t;
verifier_t *verifier_new(const scene_t *s, double judge_seconds);
void verifier_free(verifier_t *v);
void verifier_check(verifier_t *v, const rayset_t *rs, const answers_t *got, const answers_t *ref, verify_result *out);
judge_t *verifier_judge(verifier_t *v);

/* verifier_check with a verifier of its own and the default budget. */
void verify_answers(const scene_t *s, const rayset_t *rs, const answers_t *got, const answers_t *ref, verify_result *out);

/* The noise bounds above, for a ray and a primitive (world units). */
double verify_noise_scale(const scene_t *s, const ray_t *r, uint32_t prim);
/* Whether a hit on prim at t is an ill-posed one: within the origin bound. */
bool verify_hit_at_origin(const scene_t *s, const ray_t *r, uint32_t prim, double t);
/* Rays of the set whose nearest hit through the reference accelerator ref
 * lies within the origin bound (any-hit sets are traced for closest hits
 * for this). */
uint32_t verify_count_illposed(const scene_t *s, const rayset_t *rs, accel *ref, int threads);

#endif
