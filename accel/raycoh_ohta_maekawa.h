/* raycoh_ohta_maekawa.h: test hooks of the ray coherence accelerator
 * (accel/raycoh_ohta_maekawa.c), for tests/test_raycoh.c. */
#ifndef ACCELBENCH_RAYCOH_OHTA_MAEKAWA_H
#define ACCELBENCH_RAYCOH_OHTA_MAEKAWA_H

#include <stdbool.h>
#include <stdint.h>
#include "accel.h"

/* Whether a cube of res x res cells a face, for rays from sphere (c1, r1)
 * to sphere (c2, r2), lists the second in the cell holding dir (no margin
 * on the radii: the build adds its own). */
bool raycoh_debug_listed(vec3 c1, float r1, vec3 c2, float r2, uint32_t res, vec3 dir);
/* The distance bound d the build stores for that pair (no margin). */
float raycoh_debug_depth(vec3 c1, float r1, vec3 c2, float r2);
/* How many clusters a built raycoh has. */
uint32_t raycoh_debug_clusters(const accel *a);
/* Whether ray would be answered by a cube (else by the fallback). */
bool raycoh_debug_uses_cube(const accel *a, const ray_t *ray);

#endif
