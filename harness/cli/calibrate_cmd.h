/* calibrate_cmd.h: `accelbench calibrate`. */
#ifndef ACCELBENCH_CALIBRATE_CMD_H
#define ACCELBENCH_CALIBRATE_CMD_H

/* accelbench calibrate [--out DIR] [--from RUN_DIR] [--quick] [--threads N] [--quiet] */
int calibrate_main(int argc, char **argv);

#endif
