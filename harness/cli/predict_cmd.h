/* predict_cmd.h: `accelbench predict`. */
#ifndef ACCELBENCH_PREDICT_CMD_H
#define ACCELBENCH_PREDICT_CMD_H

/* accelbench predict RUN_DIR [--out DIR] [--no-plot] [--quiet] */
int predict_main(int argc, char **argv);

#endif
