/* reproduce.h: `accelbench reproduce EXPERIMENT`: a paper's experiments
 * re-run on our scenes, printed in the paper's table shapes with our
 * numbers (reproduce_woo92.c: Woo, Graphics Interface 1992, Tables 1-4
 * plus a one-switch-at-a-time ablation).
 *
 *   accelbench reproduce woo92 [--out DIR] [--threads N] [--repeat N] [--quick]
 *
 * Exit status: 0 done, 1 a real mismatch against Embree, 2 bad input. */
#ifndef ACCELBENCH_REPRODUCE_H
#define ACCELBENCH_REPRODUCE_H

#include <stdio.h>

/* argv[0] is "reproduce". */
int reproduce_main(int argc, char **argv);
void reproduce_usage(FILE *out);

#endif
