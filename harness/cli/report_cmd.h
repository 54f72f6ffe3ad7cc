/* report_cmd.h: `accelbench report`. */
#ifndef ACCELBENCH_REPORT_CMD_H
#define ACCELBENCH_REPORT_CMD_H

/* accelbench report RUN_DIR [--out FILE.html] [--pictures auto|on|off] [--quiet] */
int report_main(int argc, char **argv);

#endif
