/* advise_cmd.h: `accelbench advise SCENE`: which structure to use on a
 * scene, predicted before tracing from each candidate's cost model (its
 * statistics after a build) and the machine's calibration, each at its
 * best predicted setting; with --check, measured and the regret reported
 * (scripts/advise.py; docs/cli.md). */
#ifndef ACCELBENCH_ADVISE_CMD_H
#define ACCELBENCH_ADVISE_CMD_H

int advise_main(int argc, char **argv);

#endif
