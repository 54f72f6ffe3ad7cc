/* resume.h: run's results file (DIR/matrix.csv) on disk, lossless and
 * resumable.
 *
 * Opening reads what is there: the header must be this version's; a torn
 * last record (no line break at the end of the file, or another field
 * count than the header's: a run killed mid-row) is dropped from the file
 * with a message, and so is a header cut short; a malformed record before
 * the last is refused (nothing this program writes leaves one), and so
 * are a second row of one cell key (named by its line and key) and a file
 * that starts with a UTF-8 byte-order mark. Every record's cell key
 * (cellkey.h) is then known, so a run can ask which of its cells are done.
 *
 * Writing a row appends it with one write(2) (and fdatasync), or, when a
 * row of the same cell key is there (run --redo), rewrites the whole file
 * to a temporary file in the same folder and renames it over the old one,
 * the new row in the old one's place: the file holds every cell once at
 * every moment, whenever the process dies. A failed write is undone (the
 * file cut back to its last whole row) and reported as "PATH: write
 * failed: REASON"; the caller exits 1.
 *
 * The folder is locked (flock) while the store is open, so two runs never
 * write one file; a temporary file left by a run killed mid-rewrite is
 * removed. A path that is not a regular file (a device such as /dev/full,
 * a pipe) is only ever appended to: it has no rows to read or rewrite. */
#ifndef ACCELBENCH_RESUME_H
#define ACCELBENCH_RESUME_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef struct results_store results_store;

/* What opening found. */
typedef struct {
    int rows;           /* whole rows kept */
    int runs;           /* distinct run ids among them */
    int torn_line;      /* line number of a dropped torn record, or 0 */
    char torn_why[96];  /* "no line break at the end of the file", "12 fields, expected 58" */
    bool header_written; /* the file was new (or empty, or only a cut header) */
} results_found;

/* Open (creating it) the results file at path in folder dir. Returns the
 * store, or NULL with a one-line reason in err and *status: 2 for a file
 * this program cannot take (other columns, a malformed record, another run
 * holding the folder, cannot open, not a regular file), 1 when a write (the header, the
 * repair of a torn tail) failed. */
results_store *results_open(const char *dir, const char *path, results_found *found, char *err, size_t errlen,
                            int *status);

/* The run id of the row of cell `key`, or
 * NULL when no row has that key. git_rev, when not NULL, gets that row's
 * git_rev column. */
const char *results_find(const results_store *s, const char *key, const char **git_rev);

/* Write one row (text: one CSV record ending in "\n") of cell `key`:
 * appended, or replacing the rows of that key. Returns 0, or -1 with
 * "PATH: write failed: REASON" in err (the file then holds what it held). */
int results_put(results_store *s, const char *key, const char *text, size_t len, char *err, size_t errlen);

/* Close the store and release the folder. Returns 0, or -1 with the reason
 * in err when closing the file reported a failed write. */
int results_close(results_store *s, char *err, size_t errlen);

/* Write all of text to the file at path (mode "a" appends, "w" replaces)
 * and close it, every call checked. Returns 0, -1 with "PATH: write
 * failed: REASON" in err, or -2 with "PATH: cannot open: REASON" (or the
 * reason output_replaceable refuses a path that is not a regular file).
 * For run.txt. */
int write_file_checked(const char *path, const char *mode, const char *text, char *err, size_t errlen);

#endif
