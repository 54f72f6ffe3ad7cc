/* markdown.c: Markdown for reproduce reports (see markdown.h). */
#include "markdown.h"

#include <stdarg.h>
#include <string.h>

void md_heading(FILE *f, int level, const char *fmt, ...)
{
    va_list ap;
    level = level < 1 ? 1 : level > 6 ? 6 : level;
    fprintf(f, "%.*s ", level, "######");
    va_start(ap, fmt);
    vfprintf(f, fmt, ap);
    va_end(ap);
    fputs("\n\n", f);
}

void md_section(FILE *f, const char *title, const char *fmt, ...)
{
    va_list ap;
    fprintf(f, "## %s\n\n", title);
    va_start(ap, fmt);
    vfprintf(f, fmt, ap);
    va_end(ap);
    fputs("\n\n", f);
}

void md_para(FILE *f, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vfprintf(f, fmt, ap);
    va_end(ap);
    fputs("\n\n", f);
}

void md_bullet(FILE *f, int depth, const char *fmt, ...)
{
    va_list ap;
    fprintf(f, "%*s- ", 2 * (depth < 0 ? 0 : depth), "");
    va_start(ap, fmt);
    vfprintf(f, fmt, ap);
    va_end(ap);
    fputc('\n', f);
}

void md_table(FILE *f, const char *columns)
{
    /* Two passes over the titles: the header line, then the rule. */
    for (int rule = 0; rule < 2; rule++) {
        fputc('|', f);
        const char *c = columns;
        for (;;) {
            size_t len = strcspn(c, "|");
            int right = len > 0 && c[len - 1] == ':';
            if (rule) fputs(right ? "---:|" : "---|", f);
            else fprintf(f, " %.*s |", (int)len - right, c);
            if (!c[len]) break;
            c += len + 1;
        }
        fputc('\n', f);
    }
}

void md_row(FILE *f, const char *fmt, ...)
{
    char buf[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    fputs("| ", f);
    for (const char *p = buf; *p; p++)
        if (*p == '|') fputs(" | ", f);
        else fputc(*p, f);
    fputs(" |\n", f);
}

void md_end(FILE *f) { fputc('\n', f); }

void md_finding(FILE *f, const char *fmt, ...)
{
    va_list ap;
    fputs("finding: ", f);
    va_start(ap, fmt);
    vfprintf(f, fmt, ap);
    va_end(ap);
    fputs("\n\n", f);
}
