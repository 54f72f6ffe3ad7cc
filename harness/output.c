/* output.c: results folders and plot scripts (see output.h). */
#include "output.h"

#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

int mkdir_p(const char *path)
{
    char buf[1024];
    if (strlen(path) >= sizeof buf) { /* never a folder of a cut name */
        errno = ENAMETOOLONG;
        return -1;
    }
    snprintf(buf, sizeof buf, "%s", path);
    for (char *p = buf + 1; *p; p++)
        if (*p == '/') {
            *p = 0;
            if (mkdir(buf, 0777) && errno != EEXIST) return -1;
            *p = '/';
        }
    return mkdir(buf, 0777) && errno != EEXIST ? -1 : 0;
}

int output_folder(const char *given, const char *prefix, char *out, size_t outlen)
{
    if (given && strlen(given) >= outlen) {
        fprintf(stderr, "accelbench: --out '%.60s...': a path of %zu bytes, more than %zu\n", given, strlen(given),
                outlen - 1);
        return 2;
    }
    if (given) snprintf(out, outlen, "%s", given);
    else {
        char stamp[32];
        time_t now = time(NULL);
        struct tm tm;
        gmtime_r(&now, &tm);
        strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
        snprintf(out, outlen, "results/%s%s", prefix, stamp);
    }
    if (mkdir_p(out)) {
        fprintf(stderr, "accelbench: %s: cannot create output folder: %s\n", out, strerror(errno));
        return 2;
    }
    return 0;
}

void run_plot_script(const char *script, const char *csv_path, bool quiet)
{
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "/usr/bin/python3 '%s/scripts/%s' '%s' %s", ACCELBENCH_SOURCE_DIR, script, csv_path,
             quiet ? "--quiet" : "");
    /* The script reads the parameters' defaults from this binary (its labels: name[what differs]). */
    char self[1024];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    if (n > 0) {
        self[n] = 0;
        setenv("ACCELBENCH", self, 0);
    }
    int rc = system(cmd);
    if (rc != 0) fprintf(stderr, "accelbench: warning: plotting failed (exit %d); the CSV is complete: %s\n", rc, csv_path);
}
