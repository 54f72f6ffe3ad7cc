/* matrix.h: the scene x accelerator x workload loop behind `run`. Data
 * flows one way: scene -> ray set -> reference answers -> each
 * accelerator's cell (measure.h: build, warm-up with answers and counters,
 * verify, timing paired with Embree's) -> CSV row. */
#ifndef ACCELBENCH_MATRIX_H
#define ACCELBENCH_MATRIX_H

#include "run_options.h"

/* `accelbench run`: returns the process exit status. */
int matrix_run(options *o);

#endif
