/* figures.c: reading a paper's figures file (see figures.h). */
#include "figures.h"
#include "../../prims/checked_alloc.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FIELD_MAX 96
#define HEADER "table,row,quantity,value,unit"

typedef struct { char table[FIELD_MAX], row[FIELD_MAX], quantity[FIELD_MAX], value[FIELD_MAX]; } entry;

struct figures {
    entry *e;
    int n, cap;
    char missing[3 * FIELD_MAX + 3];
};

/* Split line at commas into exactly 5 fields of at most FIELD_MAX - 1
 * characters; returns 0 or -1. */
static int split5(char *line, char *field[5])
{
    int n = 0;
    for (char *p = line;; p++) {
        char *c = strchr(p, ',');
        if (n == 5) return -1;
        field[n++] = p;
        if (!c) break;
        *c = 0;
        p = c;
    }
    if (n != 5) return -1;
    for (int i = 0; i < 5; i++)
        if (strlen(field[i]) >= FIELD_MAX) return -1;
    return 0;
}

figures *figures_load(const char *path, char *err, size_t errlen)
{
    FILE *in = fopen(path, "r");
    if (!in) {
        snprintf(err, errlen, "%s: cannot read the paper's figures: %s", path, strerror(errno));
        return NULL;
    }
    figures *f = checked_calloc(1, sizeof *f, "a paper's figures");
    char line[1024];
    int lineno = 0;
    while (fgets(line, sizeof line, in)) {
        lineno++;
        line[strcspn(line, "\r\n")] = 0;
        if (lineno == 1) {
            if (strcmp(line, HEADER) != 0) {
                snprintf(err, errlen, "%s:1: the header is not '%s'", path, HEADER);
                goto fail;
            }
            continue;
        }
        if (!line[0]) continue;
        char *field[5];
        if (split5(line, field)) {
            snprintf(err, errlen, "%s:%d: expected 5 fields (%s) of under %d characters", path, lineno, HEADER, FIELD_MAX);
            goto fail;
        }
        if (f->n == f->cap) {
            f->cap = f->cap ? 2 * f->cap : 64;
            f->e = checked_realloc(f->e, (size_t)f->cap * sizeof *f->e, "a paper's figures");
        }
        entry *e = &f->e[f->n++];
        snprintf(e->table, sizeof e->table, "%s", field[0]);
        snprintf(e->row, sizeof e->row, "%s", field[1]);
        snprintf(e->quantity, sizeof e->quantity, "%s", field[2]);
        snprintf(e->value, sizeof e->value, "%s", field[3]);
    }
    if (lineno == 0) {
        snprintf(err, errlen, "%s: empty", path);
        goto fail;
    }
    fclose(in);
    return f;
fail:
    fclose(in);
    figures_free(f);
    return NULL;
}

void figures_free(figures *f)
{
    if (!f) return;
    free(f->e);
    free(f);
}

static void note_missing(figures *f, const char *table, const char *row, const char *quantity)
{
    if (!f->missing[0]) snprintf(f->missing, sizeof f->missing, "%s,%s,%s", table, row, quantity);
}

const char *figures_text(figures *f, const char *table, const char *row, const char *quantity)
{
    for (int i = 0; i < f->n; i++)
        if (!strcmp(f->e[i].table, table) && !strcmp(f->e[i].row, row) && !strcmp(f->e[i].quantity, quantity))
            return f->e[i].value;
    note_missing(f, table, row, quantity);
    return NULL;
}

/* "12.5" -> 12.5; "m:ss" and "h:mm:ss" -> seconds; NAN otherwise. */
static double parse_number(const char *s)
{
    double v = 0;
    for (;;) {
        char *end;
        errno = 0;
        double part = strtod(s, &end);
        if (end == s || errno) return NAN;
        v = 60 * v + part;
        if (!*end) return v;
        if (*end != ':') return NAN;
        s = end + 1;
    }
}

double figures_number(figures *f, const char *table, const char *row, const char *quantity)
{
    const char *t = figures_text(f, table, row, quantity);
    double v = t ? parse_number(t) : NAN;
    if (t && isnan(v)) note_missing(f, table, row, quantity);
    return v;
}

const char *figures_missing(const figures *f) { return f->missing[0] ? f->missing : NULL; }

int figures_rows(const figures *f, const char *table, const char **rows, int max)
{
    int n = 0;
    for (int i = 0; i < f->n; i++) {
        const entry *e = &f->e[i];
        if (strcmp(e->table, table) || !strcmp(e->row, "all")) continue;
        bool seen = false;
        for (int k = 0; k < n && !seen; k++) seen = !strcmp(rows[k], e->row);
        if (!seen && n < max) rows[n++] = e->row;
    }
    return n;
}
