/* output.h: where `run` and `reproduce` write (a results folder) and the
 * plot scripts they call on what they wrote. */
#ifndef ACCELBENCH_OUTPUT_H
#define ACCELBENCH_OUTPUT_H

#include <stdbool.h>
#include <stddef.h>

/* mkdir -p; 0 or -1 with errno set. */
int mkdir_p(const char *path);

/* s as it may be printed to a terminal: control characters escaped (\n,
 * \r, \t, others as \xHH, C1 controls as \xc2\xHH), so that a name
 * cannot move the cursor, change colours or forge a line. The result is in
 * one of four buffers of this thread, reused in turn: print it before the
 * fifth call. Long names are cut with "...". */
const char *term_text(const char *s);

/* Whether path may be written (a new file, or one replacing it): 0 when
 * it does not exist or is a regular file (symlinks followed); -1 with a
 * one-line reason in err when it is a directory, FIFO, device or socket.
 * Every writer of an output file asks first, so that no special file is
 * replaced by a rename, written through, or waited on. */
int output_replaceable(const char *path, char *err, size_t errlen);

/* The output folder of a run: `given` when not NULL, else
 * results/<prefix><date-time UTC>; created with its parents. Returns 0,
 * or 2 after printing a one-line error. */
int output_folder(const char *given, const char *prefix, char *out, size_t outlen);

/* Whether path names a folder (symlinks followed). */
bool path_is_dir(const char *path);

/* The matrix.csv of run folder dir, written to csv: 0, or 2 after printing
 * one line "accelbench CMD: ..." (no such folder, a path too long, no
 * readable matrix.csv). report, predict and calibrate --from ask it. */
int run_folder_csv(const char *cmd, const char *dir, char *csv, size_t csvlen);

/* Run argv[0] (a path, or a bare name looked up on PATH) with the arguments
 * argv (NULL-terminated) and wait for it: no shell, so paths may hold any
 * character. Returns its exit status, or -1 when it could not be started or
 * did not exit. */
int spawn_wait(char *const argv[]);

/* The python that runs the plot and report scripts: $ACCELBENCH_PYTHON when
 * set, else /usr/bin/python3 when it exists (Debian's, which
 * python3-matplotlib and python3-numpy install into), else python3 on PATH.
 * Not python3 on PATH first: a virtualenv or a conda python ahead of it
 * usually lacks matplotlib. */
const char *python_interpreter(void);

/* Run scripts/SCRIPT on a CSV with python_interpreter(); a failure is a
 * warning, the CSV stands. */
void run_plot_script(const char *script, const char *csv_path, bool quiet);

/* Append one shell word to buf (after a space when buf is not empty),
 * single-quoted when the shell would split or expand it (a quote inside
 * becomes '\''), or as $'...' with \xHH escapes when it holds a control
 * character: a command line a user can paste. */
void shell_word(char *buf, size_t len, const char *word);

#endif
