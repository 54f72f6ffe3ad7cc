/* raycls_arvo_kirk.h: the test accessors of `raycls`
 * (raycls_arvo_kirk.c); never used while tracing. */
#ifndef ACCELBENCH_RAYCLS_ARVO_KIRK_H
#define ACCELBENCH_RAYCLS_ARVO_KIRK_H

#include "accel.h"

/* The two beam tests on one hypercube of face (0..5, dircube.h): origin
 * box lo[0..3) to hi[0..3), direction cell u in [lo[3], hi[3]], v in
 * [lo[4], hi[4]], both grown by pad (world units) and the file's direction
 * slack, against a primitive whose bounds are box (its bounding sphere the
 * box's circumsphere). *cone: the cone-sphere test keeps it; *exact: the
 * polyhedral (box against beam) test keeps it. */
void raycls_debug_beam_tests(int face, const float lo[5], const float hi[5], float pad, box3 box, bool *cone,
                             bool *exact);

/* Hypercubes made (roots included), candidate-list entries held, and the
 * splits or list cullings refused by memcap since the last reset. */
void raycls_debug_counts(const accel *a, uint32_t *nodes, uint64_t *entries, uint64_t *refusals);

#endif
