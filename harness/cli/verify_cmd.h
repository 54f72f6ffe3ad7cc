/* verify_cmd.h: `accelbench verify`. */
#ifndef ACCELBENCH_VERIFY_CMD_H
#define ACCELBENCH_VERIFY_CMD_H

#include "../run/run_options.h"

/* Returns 0, 1 (a real mismatch) or 2 (bad input). */
int verify_main(options *o);

#endif
