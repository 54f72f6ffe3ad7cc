/* machine.h: what the CSV says about where and when a run happened. */
#ifndef ACCELBENCH_MACHINE_H
#define ACCELBENCH_MACHINE_H

#include <stddef.h>

typedef struct {
    char host[128];   /* hostname */
    char cpu[160];    /* /proc/cpuinfo model name, with the logical CPU count */
    char date[32];    /* ISO 8601 UTC, taken once at the start of the run */
    char git_rev[64]; /* the build's git describe */
} machine_info;

void machine_describe(machine_info *m);

#endif
