/* run_outputs.h: what a run folder gets once its matrix.csv is written: the
 * plots (scripts/plot.py) and the HTML report (scripts/report.py), which
 * `accelbench report RUN_DIR` (cli/report_cmd.h) writes alone. `run` (and
 * any command that fills a run folder: merge, shards) ends by calling
 * run_dir_outputs, so every producer of a folder writes the same outputs
 * the same way. */
#ifndef ACCELBENCH_RUN_OUTPUTS_H
#define ACCELBENCH_RUN_OUTPUTS_H

#include <stdbool.h>

/* Plots, then the report (DIR/report.html, pictures "auto") of the run folder
 * DIR. A failure of either is a warning: the CSV stands. Returns 0, or 1
 * when the report could not be written. */
int run_dir_outputs(const char *dir, bool quiet);

/* Write the report of run folder DIR to out_html (NULL: DIR/report.html)
 * through scripts/report.py; pictures is "auto", "on" or "off" (render's heat
 * maps and images per scene). Returns 0, 1 (the script failed) or 2 (bad
 * input, printed in one line). */
int report_write(const char *dir, const char *out_html, const char *pictures, bool quiet);

#endif
