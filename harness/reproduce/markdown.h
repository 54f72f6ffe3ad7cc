/* markdown.h: the Markdown of a `reproduce` report: headings, paragraphs,
 * bullets, tables and "finding:" lines, so that every paper's report has
 * one shape and its findings one form (a line that starts "finding: ",
 * each its own paragraph, which tests and readers can grep for).
 * Formats are printf's; everything goes to f. */
#ifndef ACCELBENCH_MARKDOWN_H
#define ACCELBENCH_MARKDOWN_H

#include <stdio.h>

#if defined(__GNUC__)
#define MD_PRINTF(n) __attribute__((format(printf, n, n + 1)))
#else
#define MD_PRINTF(n)
#endif

/* "#... text" at level 1..6, then a blank line. */
void md_heading(FILE *f, int level, const char *fmt, ...) MD_PRINTF(3);
/* A section: "## title", then its introduction as a paragraph. */
void md_section(FILE *f, const char *title, const char *fmt, ...) MD_PRINTF(3);
/* A paragraph: the text, then a blank line. */
void md_para(FILE *f, const char *fmt, ...) MD_PRINTF(2);
/* A list item, indented by depth (0: top level); end the list with md_end. */
void md_bullet(FILE *f, int depth, const char *fmt, ...) MD_PRINTF(3);
/* A table's header and rule. columns: the titles separated by '|'; a title
 * ending in ':' is right-aligned (numbers), the ':' not shown. Rows follow
 * (md_row), then md_end. */
void md_table(FILE *f, const char *columns);
/* One row: the formatted text's '|' separate the cells (so a cell cannot
 * hold one). */
void md_row(FILE *f, const char *fmt, ...) MD_PRINTF(2);
/* The blank line that ends a table or a list. */
void md_end(FILE *f);
/* "finding: text" as a paragraph of its own. */
void md_finding(FILE *f, const char *fmt, ...) MD_PRINTF(2);

#endif
