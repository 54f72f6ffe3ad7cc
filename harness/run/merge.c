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

/* The columns a row's cell key names too: a row whose column says otherwise is refused. */
static const char *const keyed[] = {"scene", "accel", "params", "workload", "repeat"};
#define NKEYED (int)(sizeof keyed / sizeof keyed[0])

/* One merge: its options, the shard folders read, every row filed under its cell. */
typedef struct {
    const char *out;
    bool plots, quiet, allow_mixed;
    int nd;                     /* shard folders */
    shard_dir *d;
    char out_real[PATH_MAX];
    bool out_exists;
    char header[CSV_HEADER_MAX + 2];
    size_t header_len;
    int ncols, key_col, git_col, keyed_col[NKEYED];
    shard_manifest *m0;         /* the first folder's manifest, which every other must equal */
    int ncells;
    key_ref *keys;              /* the matrix's cell keys, sorted */
    int *count;                 /* [cell] rows found */
    const char **row;           /* [cell] its first row, row_len bytes, in folder first_dir */
    size_t *row_len;
    int *first_dir;
    int *shard_seen;            /* [1..N] folders of each shard */
    char lines[65536];          /* the listing after the summary line */
    size_t ll;
    int extra, torn;            /* rows not of the matrix; torn rows dropped */
    char revs[16][128];         /* the git revisions of the rows, with the folders of each */
    char rev_dirs[16][1024];
    int nrevs;
    char out_dir[PATH_MAX], csv_path[PATH_MAX + 16], info_path[PATH_MAX + 16];
    char err[8192];
} merge_job;

#define LIST(...) do { if (j->ll < sizeof j->lines) j->ll += (size_t)snprintf(j->lines + j->ll, sizeof j->lines - j->ll, __VA_ARGS__); } while (0)

/* The options and the folders given. -1 to go on, else the exit status. */
static int merge_args(merge_job *j, int argc, char **argv)
{
    static const struct option opts[] = {
        {"out", required_argument, NULL, OPT_OUT},
        {"no-plots", no_argument, NULL, OPT_NO_PLOTS},
        {"allow-mixed-revisions", no_argument, NULL, OPT_ALLOW_MIXED},
        {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    j->plots = true;
    int c;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "hq", opts, NULL)) != -1) {
        switch (c) {
        case OPT_OUT: j->out = optarg; break;
        case OPT_NO_PLOTS: j->plots = false; break;
        case OPT_ALLOW_MIXED: j->allow_mixed = true; break;
        case 'q': j->quiet = true; break;
        case 'h': merge_usage(stdout); return 0;
        default:
            fprintf(stderr, "accelbench merge: unknown or incomplete option '%s' (see accelbench merge --help)\n",
                    argv[optind - 1]);
            return 2;
        }
    }
    j->nd = argc - optind;
    if (j->nd < 1 || !j->out) {
        fprintf(stderr, "accelbench merge: %s (see accelbench merge --help)\n",
                j->nd < 1 ? "no shard folder given" : "no --out DIR given");
        return 2;
    }
    if (strlen(j->out) > OPT_PATH_MAX) { /* refused, never cut */
        fprintf(stderr, "accelbench merge: --out '%.60s...': a path of %zu bytes, more than %d\n", j->out, strlen(j->out),
                OPT_PATH_MAX);
        return 2;
    }
    return -1;
}

/* Every folder: its manifest and its CSV, read whole. 0, or 2 after printing why. */
static int read_shards(merge_job *j, char **dirs)
{
    int status = 0;
    for (int i = 0; i < j->nd && !status; i++) {
        j->d[i].dir = dirs[i];
        if (strlen(j->d[i].dir) > OPT_PATH_MAX) { /* DIR/matrix.csv and DIR/shard.txt must fit uncut */
            fprintf(stderr, "accelbench merge: '%.60s...': a folder path of %zu bytes, more than %d\n", j->d[i].dir,
                    strlen(j->d[i].dir), OPT_PATH_MAX);
            status = 2;
            break;
        }
        char real[PATH_MAX], path[PATH_MAX + 32];
        if (j->out_exists && realpath(j->d[i].dir, real) && !strcmp(real, j->out_real)) {
            fprintf(stderr, "accelbench merge: --out %s is one of the shard folders; choose another\n", j->out);
            status = 2;
            break;
        }
        if (shard_manifest_read(j->d[i].dir, &j->d[i].m, j->err, sizeof j->err)) {
            fprintf(stderr, "accelbench merge: %s\n", j->err);
            status = 2;
            break;
        }
        snprintf(path, sizeof path, "%s/matrix.csv", j->d[i].dir);
        j->d[i].csv = slurp(path, &j->d[i].csv_len);
        if (!j->d[i].csv) {
            fprintf(stderr, "accelbench merge: %s: cannot read: %s\n", path, strerror(errno));
            status = 2;
            break;
        }
        const char *nl = memchr(j->d[i].csv, '\n', j->d[i].csv_len);
        size_t first = nl ? (size_t)(nl - j->d[i].csv) : j->d[i].csv_len;
        if (j->d[i].csv_len >= 3 && memcmp(j->d[i].csv, "\xEF\xBB\xBF", 3) == 0) {
            fprintf(stderr, "accelbench merge: %s: starts with a UTF-8 byte-order mark, which run never writes; remove "
                            "those 3 bytes\n", path);
            status = 2;
            break;
        }
        if (!nl || first != j->header_len || memcmp(j->d[i].csv, j->header, j->header_len)) {
            fprintf(stderr, "accelbench merge: %s: not this version's columns (its header differs from accelbench %s's)\n",
                    path, ACCELBENCH_GIT_REV);
            status = 2;
            break;
        }
        snprintf(path, sizeof path, "%s/run.txt", j->d[i].dir);
        j->d[i].run_txt = slurp(path, NULL);
    }

    return status;
}

/* One matrix: the same shard count, options and cells in every manifest. 0, or 2 after printing why. */
static int check_one_matrix(merge_job *j)
{
    int status = 0;
    j->m0 = j->nd ? &j->d[0].m : NULL;
    for (int i = 1; i < j->nd && !status; i++) {
        shard_manifest *m = &j->d[i].m;
        char why[4096] = "";
        if (m->n != j->m0->n) snprintf(why, sizeof why, "%s is shard %d/%d, %s is shard %d/%d", j->d[0].dir, j->m0->k, j->m0->n, j->d[i].dir, m->k, m->n);
        else if (strcmp(m->options, j->m0->options)) {
            char diff[3000];
            options_diff(j->m0->options, m->options, diff, sizeof diff);
            snprintf(why, sizeof why, "options differ between %s and %s: %s", j->d[0].dir, j->d[i].dir, diff);
        } else if (m->ncells != j->m0->ncells) snprintf(why, sizeof why, "%s lists %d cells, %s %d", j->d[0].dir, j->m0->ncells, j->d[i].dir, m->ncells);
        else
            for (int k = 0; k < m->ncells && !why[0]; k++)
                if (strcmp(m->cells[k].key, j->m0->cells[k].key) || m->cells[k].shard != j->m0->cells[k].shard)
                    snprintf(why, sizeof why, "cell %d differs between %s and %s (another build's split or matrix)", k, j->d[0].dir, j->d[i].dir);
        if (why[0]) {
            fprintf(stderr, "accelbench merge: the shards are not of one matrix: %s\n", why);
            status = 2;
        }
    }
    return status;
}

/* One folder's rows, each filed under its cell (the first of a cell is
 * kept), its revision noted; a torn row is dropped with a warning. 0, or
 * 2 after printing a row whose columns contradict its cell key. */
static int file_rows(merge_job *j, int i)
{
    int status = 0;
    j->shard_seen[j->d[i].m.k]++;
    const char *t = j->d[i].csv;
    size_t n = j->d[i].csv_len, off = j->header_len + 1, counted = off;
    csv_span sp[256];
    int line = 2; /* of the record at off: the line breaks before it counted */
    while (off < n && !status) {
        for (; counted < off; counted++) line += j->d[i].csv[counted] == '\n';
        int nf;
        bool complete;
        size_t len = csv_split_record(t + off, n - off, &nf, &complete, sp, 256);
        if (!complete || nf != j->ncols) {
            /* A torn last row (a task killed while writing it): its cell is not done. */
            fprintf(stderr, "accelbench merge: warning: %s/matrix.csv: a torn %s row dropped (%d fields)\n", j->d[i].dir,
                    off + len < n ? "inner" : "last", nf);
            j->torn++;
            off += len ? len : n - off;
            continue;
        }
        char key[CELL_KEY_MAX], rev[128];
        csv_field(t + off, sp[j->key_col], key, sizeof key);
        csv_field(t + off, sp[j->git_col], rev, sizeof rev);
        for (int k = 0; k < NKEYED && !status; k++) {
            char col[CELL_KEY_MAX], want[CELL_KEY_MAX];
            csv_field(t + off, sp[j->keyed_col[k]], col, sizeof col);
            if (cell_key_value(key, keyed[k], want, sizeof want) != 0) continue;
            /* a value a spreadsheet would run may be written with a leading ' (the CSV documentation) */
            bool quoted = col[0] == '\'' && want[0] && strchr("=+-@", want[0]) && !strcmp(col + 1, want);
            if (strcmp(col, want) != 0 && !quoted) {
                fprintf(stderr, "accelbench merge: %s/matrix.csv: line %d: column %s is '%s' but its cell key says "
                                "'%s': a row edited by hand? (mend or drop it)\n", j->d[i].dir, line, keyed[k], col,
                        want);
                status = 2;
            }
        }
        if (status) break;
        key_ref probe = {key, 0}, *hit = bsearch(&probe, j->keys, (size_t)j->ncells, sizeof *j->keys, by_key);
        if (!hit) {
            if (j->extra++ < 50) LIST("  not of this matrix: %s (in %s)\n", key, j->d[i].dir);
        } else {
            int k = hit->index;
            if (j->count[k]++ == 0) j->row[k] = t + off, j->row_len[k] = len, j->first_dir[k] = i;
            else if (j->count[k] == 2) LIST("  duplicated: %s (in %s and %s)\n", key, j->d[j->first_dir[k]].dir, j->d[i].dir);
        }
        int r = 0;
        while (r < j->nrevs && strcmp(j->revs[r], rev)) r++;
        if (r == j->nrevs && j->nrevs < 16) snprintf(j->revs[j->nrevs], sizeof j->revs[0], "%s", rev), j->rev_dirs[j->nrevs++][0] = 0;
        if (r < j->nrevs && !strstr(j->rev_dirs[r], j->d[i].dir)) {
            size_t rl = strlen(j->rev_dirs[r]);
            snprintf(j->rev_dirs[r] + rl, sizeof j->rev_dirs[0] - rl, "%s%s", rl ? ", " : "", j->d[i].dir);
        }
        off += len;
    }
    return status;
}

/* Every row of every folder filed under its cell. 0, or 2 after printing why. */
static int file_all_rows(merge_job *j)
{
    int status = 0;
    j->ncells = j->m0 ? j->m0->ncells : 0;
    j->keys = calloc((size_t)j->ncells + 1, sizeof *j->keys);
    j->count = calloc((size_t)j->ncells + 1, sizeof *j->count);
    j->row = calloc((size_t)j->ncells + 1, sizeof *j->row);
    j->row_len = calloc((size_t)j->ncells + 1, sizeof *j->row_len);
    j->first_dir = calloc((size_t)j->ncells + 1, sizeof *j->first_dir);
    j->shard_seen = calloc((size_t)(j->m0 ? j->m0->n : 0) + 1, sizeof *j->shard_seen);
    if (!j->keys || !j->count || !j->row || !j->row_len || !j->first_dir || !j->shard_seen) {
        fprintf(stderr, "accelbench merge: out of memory\n");
        status = 2;
    }
    for (int k = 0; k < j->ncells && !status; k++) j->keys[k] = (key_ref){j->m0->cells[k].key, k};
    if (!status) qsort(j->keys, (size_t)j->ncells, sizeof *j->keys, by_key);
    for (int i = 0; i < j->nd && !status; i++) status = file_rows(j, i);
    return status;
}

/* Each cell exactly once, and the revisions one (or --allow-mixed-revisions). 0, or 2 after printing the listing. */
static int check_cells(merge_job *j)
{
    int status = 0;
    int missing = 0, duplicated = 0;
    for (int k = 0; k < j->ncells && !status; k++) {
        duplicated += j->count[k] > 1;
        if (j->count[k] == 0) {
            missing++;
            if (missing <= 200) LIST("  missing: %s (shard %d/%d%s)\n", j->m0->cells[k].key, j->m0->cells[k].shard, j->m0->n,
                                     j->shard_seen[j->m0->cells[k].shard] ? "" : ", no folder given");
        }
    }
    for (int s = 1; j->m0 && s <= j->m0->n && !status; s++)
        if (j->shard_seen[s] > 1) LIST("  shard %d/%d given %d times\n", s, j->m0->n, j->shard_seen[s]);
    if (!status && (missing || duplicated || j->extra)) {
        fprintf(stderr, "accelbench merge: %d of the matrix's %d cells missing, %d duplicated, %d rows not of this matrix "
                        "(from %d folders of %d shards):\n%s",
                missing, j->ncells, duplicated, j->extra, j->nd, j->m0->n, j->lines);
        if (missing > 200) fprintf(stderr, "  ... and %d more missing\n", missing - 200);
        status = 2;
    }
    if (!status && j->nrevs > 1) {
        fprintf(stderr, "accelbench merge: %s: rows of %d git revisions:\n", j->allow_mixed ? "warning" : "the shards disagree",
                j->nrevs);
        for (int r = 0; r < j->nrevs; r++) fprintf(stderr, "  %s: %s\n", j->revs[r], j->rev_dirs[r]);
        if (!j->allow_mixed) {
            fprintf(stderr, "  (run the shards with one build, or --allow-mixed-revisions)\n");
            status = 2;
        }
    }
    return status;
}

/* OUT/matrix.csv and OUT/merge.txt, both checked before either is written. 0, or the exit status after printing why. */
static int write_merged(merge_job *j)
{
    int status = 0;
    if (!status) status = output_folder(j->out, "", j->out_dir, sizeof j->out_dir);
    if (!status) {
        /* Both files checked before either is written: a special file under either name is never replaced. */
        snprintf(j->csv_path, sizeof j->csv_path, "%s/matrix.csv", j->out_dir);
        snprintf(j->info_path, sizeof j->info_path, "%s/merge.txt", j->out_dir);
        if (output_replaceable(j->csv_path, j->err, sizeof j->err) || output_replaceable(j->info_path, j->err, sizeof j->err)) {
            fprintf(stderr, "accelbench merge: %s\n", j->err);
            status = 2;
        }
    }
    if (!status) {
        size_t total = j->header_len + 1;
        for (int k = 0; k < j->ncells; k++) total += j->row_len[k];
        char *text = malloc(total + 1);
        if (!text) {
            fprintf(stderr, "accelbench merge: out of memory\n");
            status = 2;
        } else {
            size_t n = 0;
            memcpy(text, j->header, j->header_len);
            n = j->header_len;
            text[n++] = '\n';
            for (int k = 0; k < j->ncells; k++) memcpy(text + n, j->row[k], j->row_len[k]), n += j->row_len[k];
            status = write_replacing(j->csv_path, text, n, j->err, sizeof j->err);
            if (status) fprintf(stderr, "accelbench merge: %s\n", j->err);
            free(text);
        }
    }
    if (!status) {
        size_t cap = 4096 + strlen(j->m0->options);
        for (int i = 0; i < j->nd; i++) cap += strlen(j->d[i].dir) + 64 + (j->d[i].run_txt ? strlen(j->d[i].run_txt) : 0);
        char *info = malloc(cap);
        if (!info) {
            fprintf(stderr, "accelbench merge: out of memory\n");
            status = 2;
        } else {
            size_t n = (size_t)snprintf(info, cap, "merged: %d cells of %d shards by accelbench %s (%s)\ngit_rev: %s\noptions: %s\nfolders:",
                                        j->ncells, j->m0->n, ACCELBENCH_GIT_REV, run_id_current(), j->nrevs ? j->revs[0] : "",
                                        j->m0->options);
            for (int i = 0; i < j->nd; i++) n += (size_t)snprintf(info + n, cap - n, " %s (%d/%d)", j->d[i].dir, j->d[i].m.k, j->d[i].m.n);
            n += (size_t)snprintf(info + n, cap - n, "\n");
            for (int i = 0; i < j->nd; i++)
                if (j->d[i].run_txt) n += (size_t)snprintf(info + n, cap - n, "\n--- %s/run.txt (shard %d/%d)\n%s", j->d[i].dir, j->d[i].m.k, j->d[i].m.n, j->d[i].run_txt);
            status = write_replacing(j->info_path, info, strlen(info), j->err, sizeof j->err);
            if (status) fprintf(stderr, "accelbench merge: %s\n", j->err);
            free(info);
        }
    }
    return status;
}

static void merge_job_free(merge_job *j)
{
    for (int i = 0; i < j->nd && j->d; i++) {
        shard_manifest_free(&j->d[i].m);
        free(j->d[i].csv);
        free(j->d[i].run_txt);
    }
    free(j->d);
    free(j->keys);
    free(j->count);
    free(j->row);
    free(j->row_len);
    free(j->first_dir);
    free(j->shard_seen);
    free(j);
}

int merge_main(int argc, char **argv)
{
    merge_job *j = calloc(1, sizeof *j);
    if (!j) {
        fprintf(stderr, "accelbench merge: out of memory\n");
        return 2;
    }
    int status = merge_args(j, argc, argv);
    if (status >= 0) {
        free(j);
        return status;
    }
    j->out_exists = realpath(j->out, j->out_real) != NULL;
    j->d = calloc((size_t)j->nd, sizeof *j->d);
    if (!j->d) {
        fprintf(stderr, "accelbench merge: out of memory\n");
        free(j);
        return 2;
    }
    csv_header(j->header, sizeof j->header - 1);
    j->header_len = strlen(j->header);
    j->ncols = csv_columns(), j->key_col = csv_column_index("cell_key"), j->git_col = csv_column_index("git_rev");
    for (int k = 0; k < NKEYED; k++) j->keyed_col[k] = csv_column_index(keyed[k]);

    status = read_shards(j, argv + optind);
    if (!status) status = check_one_matrix(j);
    if (!status) status = file_all_rows(j);
    if (!status) status = check_cells(j);
    if (!status) status = write_merged(j);
    if (!status && !j->quiet)
        fprintf(stderr, "merged %d cells of %d shards into %s%s\n", j->ncells, j->m0->n, j->csv_path,
                j->torn ? " (torn rows dropped: their cells were found in other rows)" : "");
    /* The plots and the report, as run --report writes them (run_outputs.h). */
    if (!status && j->plots && run_dir_outputs(j->out_dir, j->quiet)) status = 1;

    merge_job_free(j);
    return status;
}
