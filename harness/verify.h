/* verify.h: comparing an accelerator's answers with the reference's.
 *
 * Rule (DESIGN.md): a ray agrees when both miss, or both hit with
 * |t - t_ref| <= 1e-4 * max(1, |t_ref|) (any primitive: shared edges and
 * coincident faces give different ids at the same distance). Any-hit rays
 * agree when both say the same. Every other ray is a mismatch, classified:
 *
 *   edge      the hit point of either answer (or, for any-hit rays, the
 *             nearest double-precision hit) lies within the graze distance
 *             of an edge or vertex of its triangle, or of a sphere's
 *             silhouette, or the ray skims that surface (|cos| between ray
 *             and normal < 1e-3, where float t error grows like 1/cos):
 *             float noise, not a bug
 *   tol       same primitive, t off by more than the bound; or an any-hit
 *             ray whose only hit sits at the very end of [tnear, tfar)
 *   refwrong  the double-precision arbiter (every primitive re-tested in
 *             double) sides with the accelerator, away from any edge:
 *             the reference is wrong, not the accelerator
 *   real      everything else: a bug. A real mismatch fails `verify`.
 *
 * The graze distance is 1e-5 of the scene's bounding-box diagonal: about
 * a hundred float ulps at the scene's scale. The arbiter costs one pass
 * over all primitives per disputed ray, and runs for the first
 * VERIFY_ARBITER_MAX disputes; later ones are classified without it. */
#ifndef ACCELBENCH_VERIFY_H
#define ACCELBENCH_VERIFY_H

#include "rayset.h"
#include "trace.h"

#define VERIFY_ARBITER_MAX 2000
#define VERIFY_LIST_MAX 20

typedef enum { MM_EDGE = 0, MM_TOL, MM_REFWRONG, MM_REAL, MM_CLASSES } mismatch_class;
extern const char *const mismatch_class_name[MM_CLASSES];

typedef struct {
    uint32_t ray;
    mismatch_class cls;
    hit_t got, ref;          /* closest-hit rays */
    uint8_t got_occ, ref_occ;/* any-hit rays */
    double exact_t;          /* arbiter's t, or -1 when it found no hit, NAN when not run */
    uint32_t exact_prim;
} mismatch_t;

typedef struct {
    uint64_t agree;
    uint64_t mismatches[MM_CLASSES];
    uint32_t nlisted;
    mismatch_t listed[VERIFY_LIST_MAX]; /* the first mismatches, in ray order; real ones first */
} verify_result;

void verify_answers(const scene_t *s, const rayset_t *rs, const answers_t *got, const answers_t *ref, verify_result *out);

/* The double-precision closest hit over all primitives: t, or -1. */
double verify_exact_closest(const scene_t *s, const ray_t *r, uint32_t *prim);

#endif
