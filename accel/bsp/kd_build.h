/* kd_build.h: what the two kd-tree builders (kd_midpoint.c, kd_sah.c)
 * share, from kd_tree.c: emitting nodes in depth-first order and charging
 * every byte (tree and build scratch) against the memory cap. Internal to
 * accel/common's kd files. */
#ifndef ACCELBENCH_KD_BUILD_H
#define ACCELBENCH_KD_BUILD_H

#include "../common/coincident.h"
#include "kd_tree.h"

typedef struct {
    kd_tree *t;
    const prims_t *p;
    const kd_config *cfg;
    uint64_t scratch; /* bytes of build scratch alive now */
    prim_classes classes; /* coincident primitives (midpoint: counted once against maxprims) */
    bool failed;      /* err holds the reason; every later call is a no-op */
    char *err;
    size_t errlen;
} kd_builder;

/* Charge (bytes > 0) or release (bytes < 0) build scratch: false (and the
 * builder failed, with the memcap reason) when tree plus scratch would
 * exceed the cap. */
bool kd_charge(kd_builder *b, int64_t bytes);
/* malloc of n * size bytes charged as scratch; NULL (builder failed) on a
 * cap or an allocation failure. kd_scratch_free releases the charge. */
void *kd_scratch_alloc(kd_builder *b, size_t n, size_t size);
void kd_scratch_free(kd_builder *b, void *ptr, size_t n, size_t size);

/* Append an interior node (its below child must be the next node
 * appended); returns its index, UINT32_MAX when the builder failed. */
uint32_t kd_emit_interior(kd_builder *b, int axis, float split);
/* Once the below subtree is complete: the above child is the next node. */
void kd_link_above(kd_builder *b, uint32_t node);
/* Append a leaf with ids[0..n) (copied, sorted by id), at depth. */
void kd_emit_leaf(kd_builder *b, uint32_t *ids, uint32_t n, int depth);
/* Fail with a reason (printf format), unless already failed. */
void kd_fail(kd_builder *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* The builders: the whole tree below the root cell t->box. */
void kd_build_midpoint(kd_builder *b);
void kd_build_sah(kd_builder *b);

/* b grown by e on every side. */
static inline box3 kd_box_pad(box3 b, float e)
{
    b.lo = v3_sub(b.lo, v3(e, e, e));
    b.hi = v3_add(b.hi, v3(e, e, e));
    return b;
}

static inline float kd_get(vec3 v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }
static inline void kd_set(vec3 *v, int a, float x)
{
    if (a == 0) v->x = x;
    else if (a == 1) v->y = x;
    else v->z = x;
}

#endif
