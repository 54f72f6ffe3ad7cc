/* output.h: where `run` and `reproduce` write (a results folder) and the
 * plot scripts they call on what they wrote. */
#ifndef ACCELBENCH_OUTPUT_H
#define ACCELBENCH_OUTPUT_H

#include <stdbool.h>
#include <stddef.h>

/* mkdir -p; 0 or -1 with errno set. */
int mkdir_p(const char *path);

/* The output folder of a run: `given` when not NULL, else
 * results/<prefix><date-time UTC>; created with its parents. Returns 0,
 * or 2 after printing a one-line error. */
int output_folder(const char *given, const char *prefix, char *out, size_t outlen);

/* Run scripts/SCRIPT on a CSV with the system python (matplotlib comes from
 * Debian's python3-matplotlib); a failure is a warning, the CSV stands. */
void run_plot_script(const char *script, const char *csv_path, bool quiet);

#endif
