/* grid_woo.h: helpers of the uniform grids `grid` and `grid-raybox`
 * (grid_woo.c) exposed for the tests. */
#ifndef ACCELBENCH_GRID_WOO_H
#define ACCELBENCH_GRID_WOO_H

#include <stdint.h>
#include "accel.h"

/* Largest auto resolution per axis (explicit res= may go higher, up to the
 * memory cap). */
#define GRID_AUTO_MAX 1024

/* Woo 1992, section 8.2: m = n^(1/3) * density; X = s_x / maxS * m (and Y,
 * Z alike), each rounded to the nearest integer and clamped to
 * [1, GRID_AUTO_MAX]. An empty box or one of zero extent gives 1x1x1; a
 * zero-extent axis gets 1 cell. */
void grid_auto_resolution(box3 box, uint64_t n, double density, int res[3]);

/* res=cubic:D (Havran and Sixta, Ray Tracing News 12(1), 1999): cubic
 * voxels, about D x n of them. The side is h = (prod s_a / (D n))^(1/k)
 * over the k axes of nonzero extent; each such axis gets round(s_a / h)
 * cells, clamped to [1, GRID_AUTO_MAX]; a zero-extent axis 1. D = 1 is the
 * "one voxel per object" n^(1/3) rule, D = 20 what Havran and Sixta found
 * always beats it. An empty box gives 1x1x1. */
void grid_cubic_resolution(box3 box, uint64_t n, double d, int res[3]);

/* Test accessors (never used while tracing). The resolution of a built grid. */
void grid_debug_dims(const accel *a, int res[3]);
/* The candidate list of cell (i, j, k) in its current (shared) order. */
const uint32_t *grid_debug_cell(const accel *a, int i, int j, int k, uint32_t *count);
/* FNV-1a hash of the whole (shared) candidate-id array: changes when
 * move-to-front reorders any list. */
uint64_t grid_debug_list_hash(const accel *a);

#endif
