/* merge.c: `accelbench merge DIR... --out DIR`: the shard folders of one
 * matrix (run --shard K/N, shard.h) into one matrix.csv.
 *
 * Checked before anything is written, each failure exit 2: every folder
 * has a shard manifest (shard.txt) and a matrix.csv of this version's
 * columns; the manifests describe one matrix (the same N, options line and
 * cells: where they differ is listed); every cell of the matrix has
 * exactly one row among all the folders (missing cells, with the shard
 * that owes them, and duplicated cells, with the folders holding them, are
 * listed; so are rows of cells not in the matrix); every row was measured
 * by one git revision (else the revisions and their folders are listed;
 * --allow-mixed-revisions accepts them).
 *
 * Written: OUT/matrix.csv (the header once, then the rows in the matrix's
 * enumeration order, each row's bytes as its shard wrote them, so the file
 * is a function of the shards' rows alone), through a temporary file
 * renamed into place; OUT/merge.txt (the folders, the matrix, each shard's
 * run.txt); then run_dir_outputs (the plots and the report), as run --report does. */
#include "merge.h"

#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "cellkey.h"
#include "run_outputs.h"
#include "csv.h"
#include "output.h"
#include "resume.h"
#include "shard.h"
#include "version.h"

static void merge_usage(FILE *out)
{
    fprintf(out,
            "usage: accelbench merge DIR... --out DIR [--no-plots] [--quiet] [--allow-mixed-revisions]\n"
            "  Merge the folders of run --shard K/N (each with shard.txt and matrix.csv) into one matrix.csv,\n"
            "  rows in the matrix's cell order, then write the plots as run does.\n"
            "  --out DIR                the merged folder (created; its matrix.csv and merge.txt are replaced)\n"
            "  --no-plots               write neither the plots (scripts/plot.py) nor the report (report.html)\n"
            "  --quiet                  no summary line\n"
            "  --allow-mixed-revisions  accept rows measured by different git revisions (listed as a warning)\n"
            "  Exit status: 0, 1 when a write failed, 2 when a folder is missing or malformed, the shards\n"
            "  disagree on the matrix or the revision, or a cell is missing, duplicated or not of the matrix\n"
            "  (each listed).\n");
}

typedef struct {
    const char *dir;
    shard_manifest m;
    char *csv;       /* the whole matrix.csv */
    size_t csv_len;
    char *run_txt;   /* its run.txt, or NULL */
} shard_dir;

typedef struct {
    const char *key;
    int index;
} key_ref;

static int by_key(const void *a, const void *b)
{
    return strcmp(((const key_ref *)a)->key, ((const key_ref *)b)->key);
}

static char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    for (size_t got; buf && (got = fread(buf + n, 1, cap - n, f)) > 0;) {
        n += got;
        if (n == cap) {
            char *p = realloc(buf, 2 * cap + 1);
            if (!p) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = p;
            cap *= 2;
        }
    }
    bool err = ferror(f);
    fclose(f);
    if (!buf || err) {
        free(buf);
        return NULL;
    }
    buf[n] = 0;
    if (len) *len = n;
    return buf;
}

/* The options lines of two manifests word by word: the words of a that b
 * lacks (and the other way round) into buf. */
static void options_diff(const char *a, const char *b, char *buf, size_t len)
{
    char *x = strdup(a), *y = strdup(b);
    buf[0] = 0;
    if (!x || !y) {
        free(x);
        free(y);
        return;
    }
    const char *wa[64], *wb[64];
    int na = 0, nb = 0;
    for (char *t = strtok(x, " "); t && na < 64; t = strtok(NULL, " ")) wa[na++] = t;
    for (char *t = strtok(y, " "); t && nb < 64; t = strtok(NULL, " ")) wb[nb++] = t;
    for (int i = 0; i < na || i < nb; i++) {
        const char *p = i < na ? wa[i] : "", *q = i < nb ? wb[i] : "";
        if (strcmp(p, q) == 0) continue;
        size_t n = strlen(buf);
        snprintf(buf + n, len - n, "%s%s vs %s", n ? "; " : "", p, q);
    }
    free(x);
    free(y);
}

/* Write text to path through a temporary file beside it, renamed into place. */
static int write_replacing(const char *path, const char *text, size_t len, char *err, size_t errlen)
{
    char tmp[PATH_MAX + 32];
    snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
    FILE *f = fopen(tmp, "wb");
    if (!f) {
        snprintf(err, errlen, "%s: cannot open: %s", tmp, strerror(errno));
        return 2;
    }
    bool ok = fwrite(text, 1, len, f) == len && fflush(f) == 0 && fsync(fileno(f)) == 0;
    int e = errno;
    if (fclose(f) != 0 && ok) ok = false, e = errno;
    if (ok && rename(tmp, path) != 0) ok = false, e = errno;
    if (!ok) {
        unlink(tmp);
        snprintf(err, errlen, "%s: write failed: %s", path, strerror(e));
        return 1;
    }
    return 0;
}

enum { OPT_OUT = 300, OPT_NO_PLOTS, OPT_ALLOW_MIXED };

int merge_main(int argc, char **argv)
{
    static const struct option opts[] = {
        {"out", required_argument, NULL, OPT_OUT},
        {"no-plots", no_argument, NULL, OPT_NO_PLOTS},
        {"allow-mixed-revisions", no_argument, NULL, OPT_ALLOW_MIXED},
        {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    const char *out = NULL;
    bool plots = true, quiet = false, allow_mixed = false;
    int c;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "hq", opts, NULL)) != -1) {
        switch (c) {
        case OPT_OUT: out = optarg; break;
        case OPT_NO_PLOTS: plots = false; break;
        case OPT_ALLOW_MIXED: allow_mixed = true; break;
        case 'q': quiet = true; break;
        case 'h': merge_usage(stdout); return 0;
        default:
            fprintf(stderr, "accelbench merge: unknown or incomplete option '%s' (see accelbench merge --help)\n",
                    argv[optind - 1]);
            return 2;
        }
    }
    int nd = argc - optind;
    if (nd < 1 || !out) {
        fprintf(stderr, "accelbench merge: %s (see accelbench merge --help)\n",
                nd < 1 ? "no shard folder given" : "no --out DIR given");
        return 2;
    }
    if (strlen(out) > OPT_PATH_MAX) { /* refused, never cut */
        fprintf(stderr, "accelbench merge: --out '%.60s...': a path of %zu bytes, more than %d\n", out, strlen(out),
                OPT_PATH_MAX);
        return 2;
    }
    char out_real[PATH_MAX];
    bool out_exists = realpath(out, out_real) != NULL;
    shard_dir *d = calloc((size_t)nd, sizeof *d);
    if (!d) {
        fprintf(stderr, "accelbench merge: out of memory\n");
        return 2;
    }
    int status = 0;
    char err[8192], header[CSV_HEADER_MAX + 2];
    csv_header(header, sizeof header - 1);
    size_t header_len = strlen(header);
    int ncols = csv_columns(), key_col = csv_column_index("cell_key"), git_col = csv_column_index("git_rev");
    /* The columns a row's cell key names too: a row whose column says otherwise is refused. */
    static const char *const keyed[] = {"scene", "accel", "params", "workload", "repeat"};
    int keyed_col[5];
    for (int k = 0; k < 5; k++) keyed_col[k] = csv_column_index(keyed[k]);

    /* Every folder: its manifest and its CSV, read whole. */
    for (int i = 0; i < nd && !status; i++) {
        d[i].dir = argv[optind + i];
        if (strlen(d[i].dir) > OPT_PATH_MAX) { /* DIR/matrix.csv and DIR/shard.txt must fit uncut */
            fprintf(stderr, "accelbench merge: '%.60s...': a folder path of %zu bytes, more than %d\n", d[i].dir,
                    strlen(d[i].dir), OPT_PATH_MAX);
            status = 2;
            break;
        }
        char real[PATH_MAX], path[PATH_MAX + 32];
        if (out_exists && realpath(d[i].dir, real) && !strcmp(real, out_real)) {
            fprintf(stderr, "accelbench merge: --out %s is one of the shard folders; choose another\n", out);
            status = 2;
            break;
        }
        if (shard_manifest_read(d[i].dir, &d[i].m, err, sizeof err)) {
            fprintf(stderr, "accelbench merge: %s\n", err);
            status = 2;
            break;
        }
        snprintf(path, sizeof path, "%s/matrix.csv", d[i].dir);
        d[i].csv = slurp(path, &d[i].csv_len);
        if (!d[i].csv) {
            fprintf(stderr, "accelbench merge: %s: cannot read: %s\n", path, strerror(errno));
            status = 2;
            break;
        }
        const char *nl = memchr(d[i].csv, '\n', d[i].csv_len);
        size_t first = nl ? (size_t)(nl - d[i].csv) : d[i].csv_len;
        if (d[i].csv_len >= 3 && memcmp(d[i].csv, "\xEF\xBB\xBF", 3) == 0) {
            fprintf(stderr, "accelbench merge: %s: starts with a UTF-8 byte-order mark, which run never writes; remove "
                            "those 3 bytes\n", path);
            status = 2;
            break;
        }
        if (!nl || first != header_len || memcmp(d[i].csv, header, header_len)) {
            fprintf(stderr, "accelbench merge: %s: not this version's columns (its header differs from accelbench %s's)\n",
                    path, ACCELBENCH_GIT_REV);
            status = 2;
            break;
        }
        snprintf(path, sizeof path, "%s/run.txt", d[i].dir);
        d[i].run_txt = slurp(path, NULL);
    }

    /* One matrix: the same shard count, options and cells in every manifest. */
    shard_manifest *m0 = nd ? &d[0].m : NULL;
    for (int i = 1; i < nd && !status; i++) {
        shard_manifest *m = &d[i].m;
        char why[4096] = "";
        if (m->n != m0->n) snprintf(why, sizeof why, "%s is shard %d/%d, %s is shard %d/%d", d[0].dir, m0->k, m0->n, d[i].dir, m->k, m->n);
        else if (strcmp(m->options, m0->options)) {
            char diff[3000];
            options_diff(m0->options, m->options, diff, sizeof diff);
            snprintf(why, sizeof why, "options differ between %s and %s: %s", d[0].dir, d[i].dir, diff);
        } else if (m->ncells != m0->ncells) snprintf(why, sizeof why, "%s lists %d cells, %s %d", d[0].dir, m0->ncells, d[i].dir, m->ncells);
        else
            for (int k = 0; k < m->ncells && !why[0]; k++)
                if (strcmp(m->cells[k].key, m0->cells[k].key) || m->cells[k].shard != m0->cells[k].shard)
                    snprintf(why, sizeof why, "cell %d differs between %s and %s (another build's split or matrix)", k, d[0].dir, d[i].dir);
        if (why[0]) {
            fprintf(stderr, "accelbench merge: the shards are not of one matrix: %s\n", why);
            status = 2;
        }
    }

    /* Every row filed under its cell. */
    int ncells = m0 && !status ? m0->ncells : 0;
    key_ref *keys = calloc((size_t)ncells + 1, sizeof *keys);
    int *count = calloc((size_t)ncells + 1, sizeof *count);
    const char **row = calloc((size_t)ncells + 1, sizeof *row);
    size_t *row_len = calloc((size_t)ncells + 1, sizeof *row_len);
    int *first_dir = calloc((size_t)ncells + 1, sizeof *first_dir);
    int *shard_seen = calloc((size_t)(m0 ? m0->n : 0) + 1, sizeof *shard_seen);
    if (!keys || !count || !row || !row_len || !first_dir || !shard_seen) {
        fprintf(stderr, "accelbench merge: out of memory\n");
        status = 2;
    }
    for (int k = 0; k < ncells && !status; k++) keys[k] = (key_ref){m0->cells[k].key, k};
    if (!status) qsort(keys, (size_t)ncells, sizeof *keys, by_key);
    char lines[65536] = "";       /* the listing after the summary line */
    size_t ll = 0;
#define LIST(...) do { if (ll < sizeof lines) ll += (size_t)snprintf(lines + ll, sizeof lines - ll, __VA_ARGS__); } while (0)
    int extra = 0, torn = 0;
    char revs[16][128];
    char rev_dirs[16][1024];
    int nrevs = 0;
    for (int i = 0; i < nd && !status; i++) {
        shard_seen[d[i].m.k]++;
        const char *t = d[i].csv;
        size_t n = d[i].csv_len, off = header_len + 1, counted = off;
        csv_span sp[256];
        int line = 2; /* of the record at off: the line breaks before it counted */
        while (off < n && !status) {
            for (; counted < off; counted++) line += d[i].csv[counted] == '\n';
            int nf;
            bool complete;
            size_t len = csv_split_record(t + off, n - off, &nf, &complete, sp, 256);
            if (!complete || nf != ncols) {
                /* A torn last row (a task killed while writing it): its cell is not done. */
                fprintf(stderr, "accelbench merge: warning: %s/matrix.csv: a torn %s row dropped (%d fields)\n", d[i].dir,
                        off + len < n ? "inner" : "last", nf);
                torn++;
                off += len ? len : n - off;
                continue;
            }
            char key[CELL_KEY_MAX], rev[128];
            csv_field(t + off, sp[key_col], key, sizeof key);
            csv_field(t + off, sp[git_col], rev, sizeof rev);
            for (int k = 0; k < 5 && !status; k++) {
                char col[CELL_KEY_MAX], want[CELL_KEY_MAX];
                csv_field(t + off, sp[keyed_col[k]], col, sizeof col);
                if (cell_key_value(key, keyed[k], want, sizeof want) != 0) continue;
                /* a value a spreadsheet would run may be written with a leading ' (the CSV documentation) */
                bool quoted = col[0] == '\'' && want[0] && strchr("=+-@", want[0]) && !strcmp(col + 1, want);
                if (strcmp(col, want) != 0 && !quoted) {
                    fprintf(stderr, "accelbench merge: %s/matrix.csv: line %d: column %s is '%s' but its cell key says "
                                    "'%s': a row edited by hand? (mend or drop it)\n", d[i].dir, line, keyed[k], col,
                            want);
                    status = 2;
                }
            }
            if (status) break;
            key_ref probe = {key, 0}, *hit = bsearch(&probe, keys, (size_t)ncells, sizeof *keys, by_key);
            if (!hit) {
                if (extra++ < 50) LIST("  not of this matrix: %s (in %s)\n", key, d[i].dir);
            } else {
                int k = hit->index;
                if (count[k]++ == 0) row[k] = t + off, row_len[k] = len, first_dir[k] = i;
                else if (count[k] == 2) LIST("  duplicated: %s (in %s and %s)\n", key, d[first_dir[k]].dir, d[i].dir);
            }
            int r = 0;
            while (r < nrevs && strcmp(revs[r], rev)) r++;
            if (r == nrevs && nrevs < 16) snprintf(revs[nrevs], sizeof revs[0], "%s", rev), rev_dirs[nrevs++][0] = 0;
            if (r < nrevs && !strstr(rev_dirs[r], d[i].dir)) {
                size_t rl = strlen(rev_dirs[r]);
                snprintf(rev_dirs[r] + rl, sizeof rev_dirs[0] - rl, "%s%s", rl ? ", " : "", d[i].dir);
            }
            off += len;
        }
    }
    int missing = 0, duplicated = 0;
    for (int k = 0; k < ncells && !status; k++) {
        duplicated += count[k] > 1;
        if (count[k] == 0) {
            missing++;
            if (missing <= 200) LIST("  missing: %s (shard %d/%d%s)\n", m0->cells[k].key, m0->cells[k].shard, m0->n,
                                     shard_seen[m0->cells[k].shard] ? "" : ", no folder given");
        }
    }
    for (int s = 1; m0 && s <= m0->n && !status; s++)
        if (shard_seen[s] > 1) LIST("  shard %d/%d given %d times\n", s, m0->n, shard_seen[s]);
    if (!status && (missing || duplicated || extra)) {
        fprintf(stderr, "accelbench merge: %d of the matrix's %d cells missing, %d duplicated, %d rows not of this matrix "
                        "(from %d folders of %d shards):\n%s",
                missing, ncells, duplicated, extra, nd, m0->n, lines);
        if (missing > 200) fprintf(stderr, "  ... and %d more missing\n", missing - 200);
        status = 2;
    }
    if (!status && nrevs > 1) {
        fprintf(stderr, "accelbench merge: %s: rows of %d git revisions:\n", allow_mixed ? "warning" : "the shards disagree",
                nrevs);
        for (int r = 0; r < nrevs; r++) fprintf(stderr, "  %s: %s\n", revs[r], rev_dirs[r]);
        if (!allow_mixed) {
            fprintf(stderr, "  (run the shards with one build, or --allow-mixed-revisions)\n");
            status = 2;
        }
    }

    /* The merged folder. */
    char out_dir[PATH_MAX], csv_path[PATH_MAX + 16], info_path[PATH_MAX + 16];
    if (!status) status = output_folder(out, "", out_dir, sizeof out_dir);
    if (!status) {
        /* Both files checked before either is written: a special file under either name is never replaced. */
        snprintf(csv_path, sizeof csv_path, "%s/matrix.csv", out_dir);
        snprintf(info_path, sizeof info_path, "%s/merge.txt", out_dir);
        if (output_replaceable(csv_path, err, sizeof err) || output_replaceable(info_path, err, sizeof err)) {
            fprintf(stderr, "accelbench merge: %s\n", err);
            status = 2;
        }
    }
    if (!status) {
        size_t total = header_len + 1;
        for (int k = 0; k < ncells; k++) total += row_len[k];
        char *text = malloc(total + 1);
        if (!text) {
            fprintf(stderr, "accelbench merge: out of memory\n");
            status = 2;
        } else {
            size_t n = 0;
            memcpy(text, header, header_len);
            n = header_len;
            text[n++] = '\n';
            for (int k = 0; k < ncells; k++) memcpy(text + n, row[k], row_len[k]), n += row_len[k];
            status = write_replacing(csv_path, text, n, err, sizeof err);
            if (status) fprintf(stderr, "accelbench merge: %s\n", err);
            free(text);
        }
    }
    if (!status) {
        size_t cap = 4096 + strlen(m0->options);
        for (int i = 0; i < nd; i++) cap += strlen(d[i].dir) + 64 + (d[i].run_txt ? strlen(d[i].run_txt) : 0);
        char *info = malloc(cap);
        if (!info) {
            fprintf(stderr, "accelbench merge: out of memory\n");
            status = 2;
        } else {
            size_t n = (size_t)snprintf(info, cap, "merged: %d cells of %d shards by accelbench %s (%s)\ngit_rev: %s\noptions: %s\nfolders:",
                                        ncells, m0->n, ACCELBENCH_GIT_REV, run_id_current(), nrevs ? revs[0] : "",
                                        m0->options);
            for (int i = 0; i < nd; i++) n += (size_t)snprintf(info + n, cap - n, " %s (%d/%d)", d[i].dir, d[i].m.k, d[i].m.n);
            n += (size_t)snprintf(info + n, cap - n, "\n");
            for (int i = 0; i < nd; i++)
                if (d[i].run_txt) n += (size_t)snprintf(info + n, cap - n, "\n--- %s/run.txt (shard %d/%d)\n%s", d[i].dir, d[i].m.k, d[i].m.n, d[i].run_txt);
            status = write_replacing(info_path, info, strlen(info), err, sizeof err);
            if (status) fprintf(stderr, "accelbench merge: %s\n", err);
            free(info);
        }
    }
    if (!status && !quiet)
        fprintf(stderr, "merged %d cells of %d shards into %s%s\n", ncells, m0->n, csv_path,
                torn ? " (torn rows dropped: their cells were found in other rows)" : "");
    /* The plots and the report, as run --report writes them (run_outputs.h). */
    if (!status && plots && run_dir_outputs(out_dir, quiet)) status = 1;

    for (int i = 0; i < nd; i++) {
        shard_manifest_free(&d[i].m);
        free(d[i].csv);
        free(d[i].run_txt);
    }
    free(d);
    free(keys);
    free(count);
    free(row);
    free(row_len);
    free(first_dir);
    free(shard_seen);
    return status;
}
