/* machine.c: host, CPU, date and revision for the CSV. */
#include "machine.h"

#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include "version.h"

void machine_describe(machine_info *m)
{
    memset(m, 0, sizeof *m);
    if (gethostname(m->host, sizeof m->host - 1) != 0) snprintf(m->host, sizeof m->host, "unknown");
    char model[128] = "unknown cpu";
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (f) {
        char line[512];
        while (fgets(line, sizeof line, f))
            if (strncmp(line, "model name", 10) == 0) {
                char *colon = strchr(line, ':');
                if (colon) {
                    colon++;
                    while (*colon == ' ') colon++;
                    colon[strcspn(colon, "\n")] = 0;
                    snprintf(model, sizeof model, "%s", colon);
                }
                break;
            }
        fclose(f);
    }
    snprintf(m->cpu, sizeof m->cpu, "%s x%ld", model, sysconf(_SC_NPROCESSORS_ONLN));
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    strftime(m->date, sizeof m->date, "%Y-%m-%dT%H:%M:%SZ", &tm);
    snprintf(m->git_rev, sizeof m->git_rev, "%s", ACCELBENCH_GIT_REV);
}
