/* boxlist.c: the worked example of docs/contributing.md. A bounding box
 * per primitive, tested before the primitive; no hierarchy.
 *
 * Paper: Arvo and Kirk, "A Survey of Ray Tracing Acceleration Techniques",
 * 1989, section 4: a bounding volume substitutes a simple test for a
 * costly one but does not decrease their number, so the cost stays linear
 * in the primitives (a constant factor at best). Hierarchies (the bvh-gs,
 * slabs-kk and bvh accelerators) are what make it logarithmic.
 *
 * Parameters: boxes (bool, on): off skips the boxes and tests every
 * primitive, as exhaustive does.
 * Memory layout: one 24-byte box3 per primitive in the scene's order, a
 * copy of prims' bounds, so the walk reads one array front to back.
 * Counters: box_tests = primitives per ray (boxes=on); prim_tests = the
 * boxes the ray meets inside [tnear, the closest hit so far].
 * Statistics: box_hit_chance, its own (the table's stat_names): the mean
 * over the primitives of their box's surface area over the scene box's,
 * the chance that a random line through the scene box meets one given
 * primitive's box (the survey's section 4.2 ratio of areas), so roughly
 * the share of primitive tests boxes=on keeps for random rays.
 * Shard planning: its table states no cost, so it is planned at
 * ACCEL_COST_DEFAULT (accel.h).
 *
 * It is registered the way every accelerator is: tests/meson.build builds
 * a registry from accel/meson.build's list plus this file's one line, and
 * the conformance suite and a measured cell run over it. */
#include <stdio.h>
#include <stdlib.h>
#include "../../accel/accel.h"
#include "../../accel/common/memcap.h"
#include "../../accel/common/prim_hit.h"
#include "../../accel/common/slab.h"

/* Its own cap on what it allocates, in MiB (the harness's --memcap bounds it). */
#define BOXLIST_OWN_MIB 4096

typedef struct {
    accel base;
    box3 *boxes; /* [prims.count], prims' bounds */
    bool use_boxes;
    double hit_chance;
} boxlist;

static const accel_param boxlist_params[] = {
    PARAM_ROW_BOOL("boxes", "on", "test each primitive's bounding box before the primitive (off: every primitive)"),
    PARAM_ROW_END,
};

static const char *const boxlist_variants[] = {"boxes=off", NULL};
static const char *const boxlist_stat_names[] = {"box_hit_chance", NULL};

static accel *boxlist_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    const prims_t *p = &scene->prims;
    uint64_t bytes = memcap_mul(p->count, sizeof(box3));
    if (memcap_exceeded(bytes, params_memcap(params, BOXLIST_OWN_MIB), err, errlen, "boxlist's %u boxes", p->count))
        return NULL;
    boxlist *b = calloc(1, sizeof *b);
    if (!b) return NULL;
    b->boxes = malloc(p->count ? p->count * sizeof(box3) : 1);
    if (!b->boxes) {
        free(b);
        snprintf(err, errlen, "boxlist: out of memory for %u boxes", p->count);
        return NULL;
    }
    b->use_boxes = params_bool(params, "boxes");
    double scene_area = box_area(p->box), sum = 0;
    for (uint32_t id = 0; id < p->count; id++) {
        b->boxes[id] = prim_bounds(p, id);
        sum += box_area(b->boxes[id]);
    }
    b->hit_chance = p->count && scene_area > 0 ? sum / p->count / scene_area : 0;
    return &b->base;
}

/* One loop for the four queries (`shadow` and `counting` are constants at
 * every call site). A box is tested over [tnear, the closest hit so far]
 * with the far end widened against rounding (slab_clip_robust), so no
 * primitive the exact ray meets is skipped. */
static inline __attribute__((always_inline)) bool scan(const boxlist *b, const ray_t *ray, hit_t *hit, counters_t *c,
                                                       const bool shadow, const bool counting)
{
    const prims_t *p = &b->base.scene->prims;
    slab_ray sr = {{0, 0, 0}, {0, 0, 0}};
    if (b->use_boxes && !slab_ray_init(&sr, ray->org, ray->dir)) return false; /* no primitive can hit it either */
    for (uint32_t id = 0; id < p->count; id++) {
        if (b->use_boxes) {
            float t0 = ray->tnear, t1 = shadow ? ray->tfar : hit->t;
            if (counting) c->box_tests++;
            if (!slab_clip_robust(&sr, &b->boxes[id], &t0, &t1)) continue;
        }
        if (shadow) {
            if (prim_test_any(p, id, ray, c, counting)) return true;
        } else {
            prim_test_closest(p, id, ray, hit, c, counting);
        }
    }
    return shadow ? false : hit->prim != HIT_NONE;
}

static bool boxlist_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    (void)ctx;
    return scan((const boxlist *)a, ray, hit, c, false, true);
}

static bool boxlist_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    (void)ctx;
    return scan((const boxlist *)a, ray, NULL, c, true, true);
}

static bool boxlist_intersect_fast(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit)
{
    (void)ctx;
    return scan((const boxlist *)a, ray, hit, NULL, false, false);
}

static bool boxlist_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *ray)
{
    (void)ctx;
    return scan((const boxlist *)a, ray, NULL, NULL, true, false);
}

static int boxlist_stats(const accel *a, accel_stat *out, int max)
{
    if (max < 1) return 0;
    out[0] = (accel_stat){"box_hit_chance", ((const boxlist *)a)->hit_chance};
    return 1;
}

static size_t boxlist_memory(const accel *a)
{
    return sizeof(boxlist) + a->scene->prims.count * sizeof(box3);
}

static void boxlist_destroy(accel *a)
{
    boxlist *b = (boxlist *)a;
    free(b->boxes);
    free(b);
}

const struct accel_ops accel_boxlist = {
    .version = 2,
    .name = "boxlist",
    .summary = "a bounding box per primitive, tested first, no hierarchy (the contributing guide's example)",
    .paper = "Arvo & Kirk 1989, survey section 4 (bounding volumes)",
    .params = boxlist_params,
    .build = boxlist_build,
    .intersect = boxlist_intersect,
    .occluded = boxlist_occluded,
    .memory = boxlist_memory,
    .destroy = boxlist_destroy,
    .stats = boxlist_stats,
    .intersect_fast = boxlist_intersect_fast,
    .occluded_fast = boxlist_occluded_fast,
    .variants = boxlist_variants,
    .stat_names = boxlist_stat_names,
};
