/* run_outputs.c: a run folder's plots and HTML report (see run_outputs.h). */
#include "run_outputs.h"
#include "output.h"

#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int report_write(const char *dir, const char *out_html, const char *pictures, bool quiet)
{
    char csv[PATH_MAX], out[PATH_MAX], script[PATH_MAX], self[PATH_MAX];
    if (strlen(dir) + sizeof "/report.html" > sizeof out || (out_html && strlen(out_html) >= sizeof out)) {
        fprintf(stderr, "accelbench report: %.60s...: a path longer than %zu bytes\n", out_html ? out_html : dir,
                sizeof out - sizeof "/report.html");
        return 2;
    }
    if (run_folder_csv("report", dir, csv, sizeof csv)) return 2;
    if (out_html) snprintf(out, sizeof out, "%s", out_html);
    else snprintf(out, sizeof out, "%s/report.html", dir);
    char why[PATH_MAX + 128];
    if (output_replaceable(out, why, sizeof why)) {
        fprintf(stderr, "accelbench report: %s%s\n", out_html ? "--out " : "", why);
        return 2;
    }
    /* The page's folder must exist: the report writes one file, it makes no folders. */
    char parent[PATH_MAX];
    snprintf(parent, sizeof parent, "%s", out);
    char *slash = strrchr(parent, '/');
    if (slash && slash != parent) {
        *slash = 0;
        if (!path_is_dir(parent)) {
            fprintf(stderr, "accelbench report: --out %s: no such folder %s\n", out, parent);
            return 2;
        }
    }
    snprintf(script, sizeof script, "%s/scripts/report.py", ACCELBENCH_SOURCE_DIR);
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    self[n > 0 ? n : 0] = 0;
    char *argv[] = {(char *)python_interpreter(), script, (char *)dir, "--out", out, "--accelbench", self, "--pictures",
                    (char *)pictures, quiet ? "--quiet" : NULL, NULL};
    int rc = spawn_wait(argv);
    if (rc == 0) return 0;
    fprintf(stderr, "accelbench: warning: the report failed (exit %d); the CSV is complete: %s\n", rc, csv);
    return rc == 2 ? 2 : 1;
}

int run_dir_outputs(const char *dir, bool quiet)
{
    char csv[PATH_MAX];
    snprintf(csv, sizeof csv, "%s/matrix.csv", dir);
    run_plot_script("plot.py", csv, quiet);
    return report_write(dir, NULL, "auto", quiet) ? 1 : 0;
}
