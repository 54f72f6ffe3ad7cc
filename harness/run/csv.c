/* csv.c: the benchmark CSV's columns, its rows as text, and RFC 4180
 * records split back into fields (see csv.h). */
#include "csv.h"

#include <errno.h>
#include <inttypes.h>
#include <stdlib.h>
#include <string.h>

/* The columns before and after the stat_NAME ones. */
static const char *const columns_head[] = {
    "scene", "prims", "accel", "params", "workload", "rays", "threads", "seed", "rayset_hash",
    "build_ms", "trace_ms", "trace_ms_min", "trace_ms_max", "mrays_per_s", "ratio_vs_embree", "ratio_min",
    "ratio_max", "embree_ms", "mem_bytes", "bytes_per_prim", "tests_per_ray", "prim_hits_per_ray", "box_tests_per_ray",
    "steps_per_ray", "empty_leaves_per_ray", "mailbox_hits_per_ray", "predicted_tests_per_ray",
    "predicted_box_tests_per_ray", "predicted_steps_per_ray", "agree", "mismatch_real",
    "mismatch_edge", "mismatch_tol", "mismatch_refwrong", "mismatch_origin", "mismatch_unjudged", "illposed_rays",
    "judge_ms", "serial", "res", "spp", "repeat", "passes", "timed_path", "timed_from", NULL,
};
/* Statistics that have columns of their own (in columns_head, beside the
 * measured counters they predict) instead of stat_ ones. */
const char *const csv_predicted_columns[] = {"predicted_tests_per_ray", "predicted_box_tests_per_ray",
                                             "predicted_steps_per_ray", NULL};

static bool own_column(const char *stat)
{
    for (int i = 0; csv_predicted_columns[i]; i++)
        if (!strcmp(csv_predicted_columns[i], stat)) return true;
    return false;
}

/* run_id and cell_key sit before the provenance columns, after every
 * column a script cuts by position (rayset_hash is the 9th, agree the 29th):
 * a cell key holds commas, so it is quoted. */
static const char *const columns_tail[] = {"run_id", "cell_key", "git_rev", "machine", "cpu", "date", NULL};

/* Appends the column PREFIX NAME to the header in buf (length n so far),
 * after a comma unless it is the first; returns the new length. */
static size_t append_column(char *buf, size_t len, size_t n, const char *prefix, const char *name)
{
    if (n < len) n += (size_t)snprintf(buf + n, len - n, "%s%s%s", n ? "," : "", prefix, name);
    return n;
}

void csv_header(char *buf, size_t len)
{
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; columns_head[i]; i++) n = append_column(buf, len, n, "", columns_head[i]);
    for (int i = 0; accel_stat_column(i); i++)
        if (!own_column(accel_stat_column(i))) n = append_column(buf, len, n, "stat_", accel_stat_column(i));
    for (int i = 0; columns_tail[i]; i++) n = append_column(buf, len, n, "", columns_tail[i]);
}

int csv_columns(void)
{
    int n = 0;
    for (int i = 0; columns_head[i]; i++) n++;
    for (int i = 0; accel_stat_column(i); i++) n += !own_column(accel_stat_column(i));
    for (int i = 0; columns_tail[i]; i++) n++;
    return n;
}

int csv_column_index(const char *name)
{
    int n = 0;
    for (int i = 0; columns_head[i]; i++, n++)
        if (!strcmp(columns_head[i], name)) return n;
    for (int i = 0; accel_stat_column(i); i++) {
        if (own_column(accel_stat_column(i))) continue;
        if (!strncmp(name, "stat_", 5) && !strcmp(accel_stat_column(i), name + 5)) return n;
        n++;
    }
    for (int i = 0; columns_tail[i]; i++, n++)
        if (!strcmp(columns_tail[i], name)) return n;
    return -1;
}

/* A text field a spreadsheet would take for a formula (=, +, -, @, or a
 * tab or carriage return before one) is written after a ', which csv_field
 * and the scripts' readers drop again; so is one that begins with ' itself,
 * so every value reads back as it was. */
static bool needs_guard(const char *s)
{
    return s[0] && strchr("=+-@\t\r'", s[0]);
}

/* RFC 4180: quote a field holding a comma, quote or newline (the guard
 * inside the quotes). */
void csv_put_text(FILE *f, const char *s)
{
    if (!s) s = "";
    bool quote = strpbrk(s, ",\"\n\r") != NULL;
    if (quote) fputc('"', f);
    if (needs_guard(s)) fputc('\'', f);
    if (!quote) {
        fputs(s, f);
        return;
    }
    for (; *s; s++) {
        if (*s == '"') fputc('"', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

/* The measured columns: empty for a row of no rays (csv.h). */
static void put_ms(FILE *f, const csv_row *r, const char *fmt, double v)
{
    fputc(',', f);
    if (!r->no_rays) fprintf(f, fmt, v);
}

static void put_per_ray(FILE *f, const csv_row *r, uint64_t total)
{
    fputc(',', f);
    if (r->has_counters && !r->no_rays && r->rays) fprintf(f, "%.6g", (double)total / (double)r->rays);
}

/* The field of statistic `name`: its value, or empty where the
 * accelerator reports no such statistic. */
static void put_stat(FILE *f, const csv_row *r, const char *name)
{
    fputc(',', f);
    for (int k = 0; k < r->nstats && !r->no_rays; k++)
        if (strcmp(r->stats[k].name, name) == 0) {
            fprintf(f, "%.6g", r->stats[k].value);
            return;
        }
}

/* One field per statistic (accel_stat_column) without a column of its own. */
static void put_stats(FILE *f, const csv_row *r)
{
    for (int i = 0; accel_stat_column(i); i++)
        if (!own_column(accel_stat_column(i))) put_stat(f, r, accel_stat_column(i));
}

/* A count, or empty when zero means "none" (image size, samples, passes). */
static void put_size(FILE *f, int v)
{
    fputc(',', f);
    if (v > 0) fprintf(f, "%d", v);
}

static void put_row(FILE *f, const csv_row *r)
{
    csv_put_text(f, r->scene);
    fprintf(f, ",%" PRIu32 ",", r->prims);
    csv_put_text(f, r->accel);
    fputc(',', f);
    csv_put_text(f, r->params);
    fputc(',', f);
    csv_put_text(f, r->workload);
    fprintf(f, ",%" PRIu32 ",%d,%" PRIu64 ",%016" PRIx64, r->rays, r->threads, r->seed, r->rayset_hash);
    put_ms(f, r, "%.4f", r->build_ms);
    put_ms(f, r, "%.4f", r->trace_ms);
    put_ms(f, r, "%.4f", r->trace_ms_min);
    put_ms(f, r, "%.4f", r->trace_ms_max);
    put_ms(f, r, "%.6g", r->mrays_per_s);
    put_ms(f, r, "%.6g", r->ratio_vs_embree);
    put_ms(f, r, "%.6g", r->ratio_min);
    put_ms(f, r, "%.6g", r->ratio_max);
    put_ms(f, r, "%.4f", r->embree_ms);
    if (r->no_rays) fputs(",,", f);
    else fprintf(f, ",%" PRIu64 ",%.6g", r->mem_bytes, r->prims ? (double)r->mem_bytes / r->prims : 0.0);
    put_per_ray(f, r, r->counters.prim_tests);
    put_per_ray(f, r, r->counters.prim_hits);
    put_per_ray(f, r, r->counters.box_tests);
    put_per_ray(f, r, r->counters.steps);
    put_per_ray(f, r, r->counters.empty_leaves);
    put_per_ray(f, r, r->counters.mailbox_hits);
    for (int i = 0; csv_predicted_columns[i]; i++) put_stat(f, r, csv_predicted_columns[i]);
    fprintf(f, ",%" PRIu64 ",%" PRIu64 ",%" PRIu64 ",%" PRIu64 ",%" PRIu64, r->agree, r->mismatch_real,
            r->mismatch_edge, r->mismatch_tol, r->mismatch_refwrong);
    fprintf(f, ",%" PRIu64 ",%" PRIu64 ",%" PRIu32 ",%.1f", r->mismatch_origin, r->mismatch_unjudged, r->illposed_rays,
            r->judge_ms);
    fprintf(f, ",%d,", r->serial ? 1 : 0);
    if (r->width > 0 && r->height > 0) fprintf(f, "%dx%d", r->width, r->height);
    put_size(f, r->spp);
    put_size(f, r->repeat);
    put_size(f, r->no_rays ? 0 : r->passes);
    fputc(',', f);
    csv_put_text(f, r->no_rays ? "" : r->timed_path);
    fputc(',', f);
    csv_put_text(f, r->no_rays || !r->timed_from ? "" : r->timed_from);
    put_stats(f, r);
    const char *const tail[] = {r->run_id, r->cell_key, r->git_rev, r->machine, r->cpu, r->date}; /* columns_tail */
    for (int i = 0; i < 6; i++) {
        fputc(',', f);
        csv_put_text(f, tail[i]);
    }
    fputc('\n', f);
}

int csv_format_row(const csv_row *r, char **text, size_t *len)
{
    *text = NULL;
    *len = 0;
    FILE *f = open_memstream(text, len);
    if (!f) return -1;
    put_row(f, r);
    if (fclose(f) != 0 || !*text) {
        free(*text);
        *text = NULL;
        return -1;
    }
    return 0;
}

int csv_write_row(FILE *f, const csv_row *r)
{
    char *text;
    size_t len;
    if (csv_format_row(r, &text, &len)) return -1;
    int rc = fwrite(text, 1, len, f) == len && fflush(f) == 0 ? 0 : -1;
    free(text);
    return rc;
}

size_t csv_split_record(const char *text, size_t n, int *nfields, bool *complete, csv_span *spans, int maxfields)
{
    size_t i = 0;
    int nf = 0;
    *complete = false;
    for (;;) {
        /* One field from i: quoted (to its closing quote) or plain (to a comma or line break). */
        csv_span sp = {i, 0, i < n && text[i] == '"'};
        if (sp.quoted) {
            for (i++;; i++) {
                if (i >= n) break;
                if (text[i] != '"') continue;
                if (i + 1 < n && text[i + 1] == '"') i++;
                else {
                    i++;
                    break;
                }
            }
        }
        while (i < n && text[i] != ',' && text[i] != '\n') i++;
        sp.len = i - sp.off;
        if (sp.len && text[i - 1] == '\r' && i < n && text[i] == '\n') sp.len--;
        if (spans && nf < maxfields) spans[nf] = sp;
        nf++;
        if (i >= n) break;
        if (text[i++] == '\n') {
            *complete = true;
            break;
        }
    }
    *nfields = nf;
    return i;
}

void csv_field(const char *text, csv_span span, char *buf, size_t len)
{
    size_t k = 0, i = span.off, end = span.off + span.len;
    if (span.quoted) {
        i++;
        if (end > i && text[end - 1] == '"') end--;
    }
    if (i < end && text[i] == '\'') i++; /* put_text's guard */
    for (; i < end && k + 1 < len; i++) {
        if (span.quoted && text[i] == '"' && i + 1 < end && text[i + 1] == '"') i++;
        buf[k++] = text[i];
    }
    if (len) buf[k] = 0;
}
