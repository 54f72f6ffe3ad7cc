/* lightbuf_haines_greenberg.h: the test accessors of `lightbuf`
 * (lightbuf_haines_greenberg.c); never used while tracing. */
#ifndef ACCELBENCH_LIGHTBUF_HAINES_GREENBERG_H
#define ACCELBENCH_LIGHTBUF_HAINES_GREENBERG_H

#include "../accel.h"

/* Cell `cell` (index (face res + j) res + i, see the .c file's header) of
 * light `light`'s buffer: its list's primitive ids and depths in list
 * order into ids[] and depths[] (at most cap of them), its full-occlusion
 * depth (+inf for none) and whether it keeps a single-polygon slab.
 * Returns the list's length (which may pass cap); 0 for a bad index.
 * cell UINT32_MAX: the light's near list (occ +inf, single false). */
uint32_t lightbuf_debug_cell(const accel *a, uint32_t light, uint32_t cell, uint32_t *ids, float *depths, uint32_t cap,
                             float *occ, bool *single);

/* Light `light`'s resolution, near-list length, culled primitives and
 * near radius rho. 0, or -1 for a bad index. */
int lightbuf_debug_light(const accel *a, uint32_t light, uint32_t *res, uint32_t *nnear, uint32_t *nculled,
                         double *rho);

#endif
