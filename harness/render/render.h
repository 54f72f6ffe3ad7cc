/* render.h: pictures through any accelerator. */
#ifndef ACCELBENCH_RENDER_H
#define ACCELBENCH_RENDER_H

#include "image.h"
#include "../workloads/workload.h"
#include "../workloads/rayset.h"
#include "../workloads/resources.h"

/* The Whitted image of a primary ray set (one colour per pixel, the mean
 * of its samples), every ray through accelerator a; the work done is
 * summed into *work when it is not NULL. */
image_t *render_whitted(const scene_t *s, accel *a, const rayset_t *prim, counters_t *work);
/* The same with the shadow rays through accelerator shadow (a shadow-only
 * one such as lightbuf, or any other), every other ray through a; the work
 * of both is summed into *work. */
image_t *render_whitted_shadows(const scene_t *s, accel *a, accel *shadow, const rayset_t *prim, counters_t *work);

/* render's image of width x height at spp samples (corners: SPD's corner
 * rays): the primary rays, and the image with its sums (Whitted) or the
 * per-ray counters and the per-pixel costs (heat maps). */
resources_estimate render_estimate(int width, int height, int spp, bool corners, bool heatmap);
int render_check_memory(const char *scene, int width, int height, int spp, bool corners, bool heatmap, char *err,
                        size_t errlen);

#endif
