/* figures.h: a paper's published figures, read from its one data file
 * (data/PAPER_figures.csv), which both the reproduce report (C) and the
 * plot script (Python) read, so no number of a paper is typed twice.
 *
 * The file is CSV with the header `table,row,quantity,value,unit`, one
 * published value a line, e.g. `table2,Room,old_time,12:34,m:ss`: `row` is
 * the paper's row label, `value` as printed (no commas: 1,234,567 is
 * written 1234567; no quoting), `unit` says how to read it. */
#ifndef ACCELBENCH_FIGURES_H
#define ACCELBENCH_FIGURES_H

#include <stddef.h>

typedef struct figures figures;

/* The figures of PATH, or NULL with a one-line reason naming the file (and
 * line) in err. */
figures *figures_load(const char *path, char *err, size_t errlen);
void figures_free(figures *f);

/* A value as printed; NULL when the file has none. */
const char *figures_text(figures *f, const char *table, const char *row, const char *quantity);
/* A value as a number, m:ss and h:mm:ss read as seconds; NAN when the file
 * has none or it is not a number. */
double figures_number(figures *f, const char *table, const char *row, const char *quantity);
/* The first (table, row, quantity) asked for that was absent or not a
 * number, "table,row,quantity", or NULL: lets a reader fetch everything,
 * then check once. */
const char *figures_missing(const figures *f);

/* The row labels of a table in file order (each once), at most max, the
 * row "all" (figures of the whole table) left out; returns how many. */
int figures_rows(const figures *f, const char *table, const char **rows, int max);

#endif
