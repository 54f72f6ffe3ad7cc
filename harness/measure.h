/* measure.h: the timing and building steps shared by `run` (matrix.c) and
 * `reproduce` (reproduce_woo92.c), so both measure a cell the same way:
 * build (timed), one warm-up trace (answers, counters, verified by the
 * caller), then `repeat` timed samples of which the median is reported. */
#ifndef ACCELBENCH_MEASURE_H
#define ACCELBENCH_MEASURE_H

#include "options.h"
#include "rayset.h"
#include "trace.h"

typedef struct { double median, min, max; int passes; } timing;

/* A timed sample should last at least this long, so that clock resolution
 * and thread start-up do not dominate small ray sets: a sample traces the
 * set `passes` times, calibrated from the warm-up, and is reported per pass. */
#define SAMPLE_MIN_MS 20.0
#define PASSES_MAX 1000

/* Time `repeat` samples (after the caller's warm-up, which took warm_ms)
 * and summarise them per pass. */
timing time_traces(accel *a, const rayset_t *rs, int threads, int repeat, double warm_ms, answers_t *scratch);

/* Build ac over s, timed; a failure is reported on stderr and gives NULL. */
accel *build_accel(const accel_config *ac, const scene_t *s, double *ms);

/* The reference accelerator (Embree, default parameters) over s. */
accel *build_reference(const scene_t *s, int threads, char *err, size_t errlen);

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
