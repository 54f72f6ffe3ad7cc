/* reproduce.h: `accelbench reproduce EXPERIMENT`: a paper's experiments
 * re-run on our scenes, printed in the paper's table shapes with our
 * numbers, the paper's figures beside them and a "finding:" line wherever
 * the two disagree. One file per experiment, on the shared machinery of
 * reproduce_kit.h:
 *   woo92   reproduce_woo92.c: Woo, Graphics Interface 1992, Tables 1-4
 *           plus a one-switch-at-a-time ablation
 *   havran  reproduce_havran.c: Havran and Sixta's grids (RTN 12(1)) and
 *           Havran's octrees (RTN 12(2)) on the SPD databases, plus BSPs
 *   spd     reproduce_spd.c: the SPD Readme's testing procedure (the
 *           whitted workload) and its ray counts and test counts
 *   survey  reproduce_survey.c: the survey's structures at their defaults
 *           and tuned, its Figure 1's considerations as numbers
 *           (scripts/survey.py)
 *
 *   accelbench reproduce EXPERIMENT [--out DIR] [--threads N] [--repeat N] [--quick] ...
 *
 * Exit status: 0 done, 1 a real mismatch against Embree, 2 bad input. */
#ifndef ACCELBENCH_REPRODUCE_H
#define ACCELBENCH_REPRODUCE_H

#include <stdio.h>

/* argv[0] is "reproduce". */
int reproduce_main(int argc, char **argv);
void reproduce_usage(FILE *out);
/* One line per experiment, "INDENTreproduce NAME SUMMARY" with the name
 * padded to width: the list accelbench --help shows. */
void reproduce_list(FILE *out, const char *indent, int width);

/* The experiments: argv[0] is the experiment's name; each prints its own
 * lines of the usage. */
int reproduce_woo92(int argc, char **argv);
void woo92_usage(FILE *out);
int reproduce_havran(int argc, char **argv);
void havran_usage(FILE *out);
int reproduce_spd(int argc, char **argv);
void spd_usage(FILE *out);
int reproduce_survey(int argc, char **argv);
void survey_usage(FILE *out);

#endif
