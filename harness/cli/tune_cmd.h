/* tune_cmd.h: `accelbench tune`. */
#ifndef ACCELBENCH_TUNE_CMD_H
#define ACCELBENCH_TUNE_CMD_H

/* accelbench tune --scenes L --workloads L [--accels L] [--res WxH] [--repeat N] [--threads N] [--seed S]
 * [--out DIR] [--quiet] */
int tune_main(int argc, char **argv);

#endif
