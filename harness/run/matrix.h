/* matrix.h: the scene x accelerator x workload loop behind `run` and
 * `verify`. Data flows one way: scene -> ray set -> reference answers ->
 * each accelerator's cell (measure.h: build, warm-up with answers and
 * counters, verify, timing paired with Embree's) -> CSV row / verify
 * table (verify stops after the warm-up). */
#ifndef ACCELBENCH_MATRIX_H
#define ACCELBENCH_MATRIX_H

#include "../cli/options.h"

/* `accelbench run`: returns the process exit status. */
int matrix_run(options *o);
/* `accelbench verify`: returns 0, 1 (a real mismatch) or 2 (bad input). */
int matrix_verify(options *o);

#endif
