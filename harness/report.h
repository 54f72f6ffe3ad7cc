/* report.h: the Markdown of a `reproduce` report: headings, paragraphs,
 * bullets, tables and "finding:" lines, so that every paper's report has
 * one shape and its findings one form (a line that starts "finding: ",
 * each its own paragraph, which tests and readers can grep for).
 * Formats are printf's; everything goes to f. */
#ifndef ACCELBENCH_REPORT_H
#define ACCELBENCH_REPORT_H

#include <stdio.h>

#if defined(__GNUC__)
#define REPORT_PRINTF(n) __attribute__((format(printf, n, n + 1)))
#else
#define REPORT_PRINTF(n)
#endif

/* "#... text" at level 1..6, then a blank line. */
void report_heading(FILE *f, int level, const char *fmt, ...) REPORT_PRINTF(3);
/* A section: "## title", then its introduction as a paragraph. */
void report_section(FILE *f, const char *title, const char *fmt, ...) REPORT_PRINTF(3);
/* A paragraph: the text, then a blank line. */
void report_para(FILE *f, const char *fmt, ...) REPORT_PRINTF(2);
/* A list item, indented by depth (0: top level); end the list with report_end. */
void report_bullet(FILE *f, int depth, const char *fmt, ...) REPORT_PRINTF(3);
/* A table's header and rule. columns: the titles separated by '|'; a title
 * ending in ':' is right-aligned (numbers), the ':' not shown. Rows follow
 * (report_row), then report_end. */
void report_table(FILE *f, const char *columns);
/* One row: the formatted text's '|' separate the cells (so a cell cannot
 * hold one). */
void report_row(FILE *f, const char *fmt, ...) REPORT_PRINTF(2);
/* The blank line that ends a table or a list. */
void report_end(FILE *f);
/* "finding: text" as a paragraph of its own. */
void report_finding(FILE *f, const char *fmt, ...) REPORT_PRINTF(2);

#endif
