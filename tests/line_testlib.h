/* line_testlib.h: the walk the cost-model tests measure (test_line_model,
 * test_wide_predict): n lines uniform over those that meet an accelerator's
 * bounds (prims_testlib.h random_line), each traced for its closest hit
 * with the counters on. Include after prims_testlib.h and testlib.h. */
#ifndef ACCELBENCH_LINE_TESTLIB_H
#define ACCELBENCH_LINE_TESTLIB_H

/* Adds the walks' counters to *c; returns how many lines hit something. */
static inline uint32_t trace_random_lines(accel *a, uint32_t n, counters_t *c)
{
    const box3 root = a->ops->bounds(a);
    accel_ctx *ctx = a->ops->context_new(a);
    uint32_t hits = 0;
    for (uint32_t i = 0; i < n; i++) {
        ray_t ray = random_line(root);
        hit_t h = hit_none(&ray);
        hits += a->ops->intersect(a, ctx, &ray, &h, c);
    }
    a->ops->context_free(ctx);
    return hits;
}

#endif
