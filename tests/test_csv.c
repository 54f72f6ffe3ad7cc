/* test_csv.c: the results CSV's identity columns and its file on disk
 * (resumable runs):
 *  - cell keys (harness/run/cellkey.h): every option that shapes a cell's rays
 *    or timing changes the key, the ray-set form names the rays' hash,
 *    escaping keeps one reading, a key that does not fit is refused;
 *  - run ids: one per process, time-sortable;
 *  - rows (harness/run/csv.h): the header's run_id and cell_key columns, a row
 *    split back into exactly the header's fields (quoted commas, quotes and
 *    line breaks), a row of no rays with its measured columns empty, the
 *    predicted_*_per_ray columns beside the measured counters filled from
 *    the statistics of those names (empty without them, no stat_ twin);
 *  - the store (harness/run/resume.h): a new file gets its header, rows are
 *    found by key after reopening, a torn last row (no line break; too few
 *    fields) is dropped, a cut header is rewritten, a malformed earlier row
 *    or another header is refused (status 2), a row of a known key replaces
 *    the old one in place through a temporary file (none left behind), a
 *    stale temporary file is removed, a second store on the folder is
 *    refused, a write to a full device is "write failed: No space left on
 *    device" (status 1), and an append cut short by the file size limit
 *    is undone (no half row). */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>
#include "harness/run/cellkey.h"
#include "harness/run/csv.h"
#include "harness/run/resume.h"
#include "check.h"

/* ------------------------------------------------------------ cell keys */

static void test_cell_keys(void)
{
    workload_opts wl = {.width = 24, .height = 16, .spp = 2, .corners = false, .depth = 3, .seed = 7, .threads = 2};
    cell_key_parts k = {.scene = "spd:balls:1", .accel = "grid", .params = "res=auto,mailbox=on", .workload = "primary",
                        .wl = &wl, .threads = 2, .repeat = 5};
    char base[CELL_KEY_MAX], other[CELL_KEY_MAX];
    CHECK(cell_key_format(&k, base, sizeof base) == 0);
    CHECK_MSG(strcmp(base, "scene=spd:balls:1 accel=grid params=res=auto,mailbox=on workload=primary res=24x16 spp=2 "
                           "corners=0 depth=3 seed=7 threads=2 repeat=5") == 0, "%s", base);
    /* Each option that shapes the rays or the timing makes another key. */
    struct { const char *what; workload_opts wl; int threads, repeat; const char *params, *workload, *scene; } v[] = {
        {"res", {25, 16, 2, false, 3, 7, 2}, 2, 5, NULL, NULL, NULL},
        {"spp", {24, 16, 1, false, 3, 7, 2}, 2, 5, NULL, NULL, NULL},
        {"corners", {24, 16, 2, true, 3, 7, 2}, 2, 5, NULL, NULL, NULL},
        {"depth", {24, 16, 2, false, 4, 7, 2}, 2, 5, NULL, NULL, NULL},
        {"seed", {24, 16, 2, false, 3, 8, 2}, 2, 5, NULL, NULL, NULL},
        {"threads", {24, 16, 2, false, 3, 7, 2}, 1, 5, NULL, NULL, NULL},
        {"repeat", {24, 16, 2, false, 3, 7, 2}, 2, 3, NULL, NULL, NULL},
        {"params", {24, 16, 2, false, 3, 7, 2}, 2, 5, "res=auto,mailbox=off", NULL, NULL},
        {"workload", {24, 16, 2, false, 3, 7, 2}, 2, 5, NULL, "shadow", NULL},
        {"view", {24, 16, 2, false, 3, 7, 2}, 2, 5, NULL, NULL, "spd:balls:1@fov=30"},
    };
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) {
        cell_key_parts x = k;
        x.wl = &v[i].wl;
        x.threads = v[i].threads;
        x.repeat = v[i].repeat;
        if (v[i].params) x.params = v[i].params;
        if (v[i].workload) x.workload = v[i].workload;
        if (v[i].scene) x.scene = v[i].scene;
        CHECK(cell_key_format(&x, other, sizeof other) == 0);
        CHECK_MSG(strcmp(base, other) != 0, "changing %s left the key alone", v[i].what);
    }
    /* The tracing threads of the workload options are not an option of their own (threads is). */
    workload_opts wl2 = wl;
    wl2.threads = 9;
    cell_key_parts same = k;
    same.wl = &wl2;
    CHECK(cell_key_format(&same, other, sizeof other) == 0 && strcmp(base, other) == 0);

    /* Rays given as a set: named by their hash, no ray options. */
    cell_key_parts r = k;
    r.wl = NULL;
    r.rays_hash = 0x00ab12cd34ef5678ull;
    CHECK(cell_key_format(&r, other, sizeof other) == 0);
    CHECK_MSG(strcmp(other, "scene=spd:balls:1 accel=grid params=res=auto,mailbox=on workload=primary "
                            "rays=00ab12cd34ef5678 threads=2 repeat=5") == 0, "%s", other);

    /* A space or a % in a value is escaped: the words still split at spaces. */
    cell_key_parts e = k;
    e.scene = "/tmp/my scene%.obj";
    CHECK(cell_key_format(&e, other, sizeof other) == 0);
    CHECK_MSG(strncmp(other, "scene=/tmp/my%20scene%25.obj accel=grid ", 40) == 0, "%s", other);

    /* Too small a buffer: refused, never a cut key taken as valid. */
    CHECK(cell_key_format(&k, other, 40) == -1);
    CHECK(cell_key_format(&k, other, strlen(base)) == -1);
    CHECK(cell_key_format(&k, other, strlen(base) + 1) == 0);
}

static void test_run_id(void)
{
    const char *a = run_id_current(), *b = run_id_current();
    CHECK(a == b && strlen(a) == 22);
    CHECK_MSG(a[8] == '-' && a[15] == '-' && strspn(a, "0123456789-") >= 16 && strspn(a + 16, "0123456789abcdef") == 6,
              "%s", a);
}

/* ------------------------------------------------------------ rows */

static csv_row sample_row(const char *scene, const char *workload, const char *key)
{
    csv_row r = {
        .scene = scene, .prims = 11, .accel = "grid", .params = "res=auto,mailbox=on", .workload = workload,
        .rays = 100, .threads = 2, .seed = 1, .rayset_hash = 0x1234, .build_ms = 1.5, .trace_ms = 2.5,
        .trace_ms_min = 1.75, .trace_ms_max = 3, .mrays_per_s = 0.04, .ratio_vs_embree = 1.2, .ratio_min = 1.1,
        .ratio_max = 1.3, .embree_ms = 2.25, .mem_bytes = 1000, .has_counters = true, .agree = 100, .width = 10,
        .height = 10, .spp = 1, .repeat = 3, .passes = 4, .timed_path = "fast", .git_rev = "abc",
        .machine = "host", .cpu = "cpu, with a comma", .date = "2026-01-01T00:00:00Z",
    };
    r.counters.prim_tests = 250;
    r.nstats = 2;
    r.stats[0].name = "nodes";
    r.stats[0].value = 42;
    r.stats[1].name = "predicted_box_tests_per_ray";
    r.stats[1].value = 7.25;
    snprintf(r.run_id, sizeof r.run_id, "%s", run_id_current());
    snprintf(r.cell_key, sizeof r.cell_key, "%s", key);
    return r;
}

/* Field `name` of a formatted row. */
static void row_field(const char *text, size_t len, const char *name, char *buf, size_t buflen)
{
    csv_span sp[256];
    int nf;
    bool complete;
    csv_split_record(text, len, &nf, &complete, sp, 256);
    int i = csv_column_index(name);
    buf[0] = 0;
    if (i >= 0 && i < nf) csv_field(text, sp[i], buf, buflen);
}

static void test_rows(void)
{
    char h[CSV_HEADER_MAX];
    csv_header(h, sizeof h);
    /* the stat_ columns (one per accel_stat_column) after timed_path; the row's identity before the tail */
    static const char tail[] = ",run_id,cell_key,git_rev,machine,cpu,date";
    CHECK(strstr(h, ",timed_path,timed_from,stat_nodes,") != NULL);
    CHECK(strlen(h) > strlen(tail) && strcmp(h + strlen(h) - strlen(tail), tail) == 0);
    int commas = 0;
    for (const char *p = h; *p; p++) commas += *p == ',';
    CHECK(csv_columns() == commas + 1);
    CHECK(csv_column_index("scene") == 0 && csv_column_index("rayset_hash") == 8 && csv_column_index("agree") == 29);
    /* eq. (3)'s predictions beside the measured counters, and not again as stat_ columns. */
    CHECK(strstr(h, ",mailbox_hits_per_ray,predicted_tests_per_ray,predicted_box_tests_per_ray,predicted_steps_per_ray,"
                    "agree,") != NULL);
    CHECK(csv_column_index("stat_predicted_tests_per_ray") == -1 && !strstr(h, "stat_predicted"));
    CHECK(csv_column_index("stat_avg_children") > csv_column_index("stat_nodes"));
    CHECK(csv_column_index("stat_nodes") > csv_column_index("timed_path"));
    CHECK(csv_column_index("date") == csv_columns() - 1 && csv_column_index("nope") == -1);

    csv_row r = sample_row("a \"quoted\", scene\nwith a line break", "primary", "scene=x accel=grid params=a=1,b=2");
    char *text;
    size_t len;
    CHECK(csv_format_row(&r, &text, &len) == 0);
    int nf;
    bool complete;
    CHECK(csv_split_record(text, len, &nf, &complete, NULL, 0) == len);
    CHECK_MSG(nf == csv_columns() && complete, "%d fields, complete %d", nf, complete);
    char f[CELL_KEY_MAX];
    row_field(text, len, "scene", f, sizeof f);
    CHECK_MSG(strcmp(f, r.scene) == 0, "%s", f);
    row_field(text, len, "cell_key", f, sizeof f);
    CHECK(strcmp(f, r.cell_key) == 0);
    /* Names a spreadsheet would run (and one beginning with the guard itself) are written after a ' and read back. */
    const char *formula[] = {"=cmd", "+1", "-x", "@at", "'q", "=a,\"b\""};
    for (int i = 0; i < 6; i++) {
        csv_row g = sample_row(formula[i], "primary", "scene=x accel=grid params=");
        char *gt;
        size_t gl;
        CHECK(csv_format_row(&g, &gt, &gl) == 0);
        CHECK_MSG(gt && (gt[0] == '\'' || (gt[0] == '"' && gt[1] == '\'')), "%s", gt);
        row_field(gt, gl, "scene", f, sizeof f);
        CHECK_MSG(strcmp(f, formula[i]) == 0, "%s", f);
        free(gt);
    }
    row_field(text, len, "run_id", f, sizeof f);
    CHECK(strcmp(f, run_id_current()) == 0);
    row_field(text, len, "cpu", f, sizeof f);
    CHECK(strcmp(f, "cpu, with a comma") == 0);
    row_field(text, len, "tests_per_ray", f, sizeof f);
    CHECK(strcmp(f, "2.5") == 0);
    row_field(text, len, "res", f, sizeof f);
    CHECK(strcmp(f, "10x10") == 0);
    row_field(text, len, "predicted_box_tests_per_ray", f, sizeof f);
    CHECK_MSG(strcmp(f, "7.25") == 0, "%s", f);
    row_field(text, len, "predicted_tests_per_ray", f, sizeof f);
    CHECK_MSG(f[0] == 0, "'%s' with no such statistic", f); /* the accelerator reported none */
    row_field(text, len, "stat_nodes", f, sizeof f);
    CHECK(strcmp(f, "42") == 0);
    /* Cut anywhere short of its line break, the record is torn. */
    for (size_t cut = 1; cut < len; cut += 7) {
        csv_split_record(text, cut, &nf, &complete, NULL, 0);
        CHECK_MSG(!complete, "cut at %zu of %zu reads as complete", cut, len);
    }
    free(text);

    /* A set of no rays: counts stay, times, ratios, memory, per-ray counters, passes and statistics are empty. */
    r = sample_row("s", "shadow", "k");
    r.rays = 0;
    r.agree = 0;
    r.no_rays = true;
    r.width = r.height = r.spp = 0;
    CHECK(csv_format_row(&r, &text, &len) == 0);
    csv_split_record(text, len, &nf, &complete, NULL, 0);
    CHECK(nf == csv_columns());
    const char *empty[] = {"build_ms", "trace_ms", "trace_ms_min", "trace_ms_max", "mrays_per_s", "ratio_vs_embree",
                           "ratio_min", "ratio_max", "embree_ms", "mem_bytes", "bytes_per_prim", "tests_per_ray",
                           "passes", "timed_path", "stat_nodes", "predicted_box_tests_per_ray", "res", "spp"};
    for (size_t i = 0; i < sizeof empty / sizeof empty[0]; i++) {
        row_field(text, len, empty[i], f, sizeof f);
        CHECK_MSG(f[0] == 0, "%s is '%s' in a row of no rays", empty[i], f);
    }
    row_field(text, len, "rays", f, sizeof f);
    CHECK(strcmp(f, "0") == 0);
    row_field(text, len, "agree", f, sizeof f);
    CHECK(strcmp(f, "0") == 0);
    free(text);

    /* Records: a quoted line break does not end one, \r\n does. */
    const char *two = "a,\"b\nc\",d\r\ne,f\n";
    size_t n1 = csv_split_record(two, strlen(two), &nf, &complete, NULL, 0);
    CHECK(nf == 3 && complete && n1 == 11);
    csv_span sp[4];
    csv_split_record(two, strlen(two), &nf, &complete, sp, 4);
    csv_field(two, sp[1], f, sizeof f);
    CHECK(strcmp(f, "b\nc") == 0);
    csv_field(two, sp[2], f, sizeof f);
    CHECK(strcmp(f, "d") == 0);
}

/* ------------------------------------------------------------ the store */

static char dir[] = "/tmp/accelbench-csv-XXXXXX";

static char *slurp(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    char *buf = malloc(1 << 20);
    *len = buf ? fread(buf, 1, (1 << 20) - 1, f) : 0;
    fclose(f);
    if (buf) buf[*len] = 0;
    return buf;
}

static int count_lines(const char *path)
{
    size_t len;
    char *t = slurp(path, &len);
    int n = 0;
    for (size_t i = 0; t && i < len; i++) n += t[i] == '\n';
    free(t);
    return n;
}

/* Put the row of scene/workload under its own key. */
static int put(results_store *s, const char *scene, const char *workload, double trace_ms, char *err, size_t errlen)
{
    char key[CELL_KEY_MAX];
    snprintf(key, sizeof key, "scene=%s workload=%s", scene, workload);
    csv_row r = sample_row(scene, workload, key);
    r.trace_ms = trace_ms;
    char *text;
    size_t len;
    if (csv_format_row(&r, &text, &len)) return -1;
    int rc = results_put(s, key, text, len, err, errlen);
    free(text);
    return rc;
}

static void append_raw(const char *path, const char *text)
{
    FILE *f = fopen(path, "ab");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static void test_store(void)
{
    if (!mkdtemp(dir)) {
        CHECK(!"mkdtemp");
        return;
    }
    char path[256], err[1200];
    snprintf(path, sizeof path, "%s/matrix.csv", dir);
    results_found fd;
    int status;

    /* New: the header, no rows; three rows go in. */
    results_store *s = results_open(dir, path, &fd, err, sizeof err, &status);
    CHECK_MSG(s && status == 0 && fd.header_written && fd.rows == 0, "%s", err);
    if (!s) return;
    /* The folder is taken: a second store is refused. */
    results_found f2;
    results_store *s2 = results_open(dir, path, &f2, err, sizeof err, &status);
    CHECK_MSG(!s2 && status == 2 && strstr(err, "another accelbench run is writing to this folder"), "%s", err);
    CHECK(put(s, "a", "primary", 1, err, sizeof err) == 0);
    CHECK(put(s, "a", "shadow", 2, err, sizeof err) == 0);
    CHECK(put(s, "b", "primary", 3, err, sizeof err) == 0);
    CHECK(results_close(s, err, sizeof err) == 0);
    CHECK(count_lines(path) == 4);

    /* Reopened: three rows of one run, found by key. */
    s = results_open(dir, path, &fd, err, sizeof err, &status);
    CHECK_MSG(s && fd.rows == 3 && fd.runs == 1 && !fd.torn_line && !fd.header_written, "%s", err);
    if (!s) return;
    const char *rev = NULL;
    CHECK(results_find(s, "scene=a workload=shadow", &rev) && strcmp(rev, "abc") == 0);
    CHECK(strcmp(results_find(s, "scene=b workload=primary", NULL), run_id_current()) == 0);
    CHECK(results_find(s, "scene=b workload=shadow", NULL) == NULL);

    /* A known key replaces its row in place, through a temporary file that does not stay. */
    char stale[300];
    CHECK(put(s, "a", "shadow", 99, err, sizeof err) == 0);
    CHECK(count_lines(path) == 4);
    size_t len;
    char *t = slurp(path, &len);
    const char *l2 = t ? strchr(strchr(t, '\n') + 1, '\n') + 1 : NULL;
    CHECK(t && strstr(t, ",99.0000,") && l2 && strncmp(l2, "a,", 2) == 0 && strstr(l2, ",99.0000,") < strchr(l2, '\n'));
    CHECK(t && !strstr(t, ",2.0000,"));
    free(t);
    snprintf(stale, sizeof stale, "%s/.matrix.csv.tmp.%ld", dir, (long)getpid());
    CHECK(access(stale, F_OK) != 0);
    /* After the rewrite, appends go to the new file. */
    CHECK(put(s, "c", "primary", 4, err, sizeof err) == 0);
    CHECK(results_close(s, err, sizeof err) == 0);
    CHECK(count_lines(path) == 5);

    /* A temporary file of a killed rewrite is removed at the next open. */
    snprintf(stale, sizeof stale, "%s/.matrix.csv.tmp.99999999", dir);
    append_raw(stale, "half a file");
    s = results_open(dir, path, &fd, err, sizeof err, &status);
    CHECK(s && fd.rows == 4 && access(stale, F_OK) != 0);
    results_close(s, err, sizeof err);

    /* Torn: no line break at the end. Dropped, the file cut back to its whole rows. */
    size_t whole;
    free(slurp(path, &whole));
    append_raw(path, "d,11,grid,\"res=auto,mail");
    s = results_open(dir, path, &fd, err, sizeof err, &status);
    CHECK_MSG(s && fd.rows == 4 && fd.torn_line == 6 && strstr(fd.torn_why, "no line break"), "%d %s", fd.torn_line,
              fd.torn_why);
    results_close(s, err, sizeof err);
    free(slurp(path, &len));
    CHECK(len == whole);

    /* Torn: a line of too few fields (a row glued short), last in the file. */
    append_raw(path, "d,11,grid,x\n");
    s = results_open(dir, path, &fd, err, sizeof err, &status);
    CHECK_MSG(s && fd.rows == 4 && fd.torn_line == 6 && strstr(fd.torn_why, "4 fields, expected"), "%s", fd.torn_why);
    results_close(s, err, sizeof err);
    free(slurp(path, &len));
    CHECK(len == whole);

    /* A malformed row before the last is not ours to repair: refused, the file left as it is. */
    append_raw(path, "d,11,grid,x\n");
    s = results_open(dir, path, &fd, err, sizeof err, &status);
    CHECK(s && put(s, "e", "primary", 5, err, sizeof err) == 0); /* the torn line goes, e comes */
    results_close(s, err, sizeof err);
    t = slurp(path, &len);
    size_t good = len;
    free(t);
    char bad[300];
    snprintf(bad, sizeof bad, "%s/bad.csv", dir);
    t = slurp(path, &len);
    FILE *bf = fopen(bad, "wb");
    if (bf && t) {
        char *last = strrchr(t, '\n');
        *last = 0;
        last = strrchr(t, '\n');
        fwrite(t, 1, (size_t)(last - t) + 1, bf); /* all but the last row ... */
        fputs("x,y\n", bf);                        /* ... a malformed one ... */
        fputs(last + 1, bf);                       /* ... and the last row again */
        fputs("\n", bf);
    }
    if (bf) fclose(bf);
    free(t);
    s = results_open(dir, bad, &fd, err, sizeof err, &status);
    CHECK_MSG(!s && status == 2 && strstr(err, "line 6: 2 fields, expected"), "%s", err);
    CHECK(count_lines(path) == 6 && good > whole);

    /* Another header (a file of an older version): refused. */
    FILE *of = fopen(bad, "wb");
    if (of) {
        fputs("scene,prims,accel\nx,1,grid\n", of);
        fclose(of);
    }
    s = results_open(dir, bad, &fd, err, sizeof err, &status);
    CHECK_MSG(!s && status == 2 && strstr(err, "exists with other columns"), "%s", err);

    /* A header cut short (killed while writing it): written again. */
    of = fopen(bad, "wb");
    if (of) {
        fputs("scene,prims,acc", of);
        fclose(of);
    }
    s = results_open(dir, bad, &fd, err, sizeof err, &status);
    CHECK_MSG(s && fd.torn_line == 1 && fd.header_written && fd.rows == 0, "%s", err);
    results_close(s, err, sizeof err);
    char h[CSV_HEADER_MAX];
    csv_header(h, sizeof h);
    t = slurp(bad, &len);
    CHECK(t && len == strlen(h) + 1 && strncmp(t, h, strlen(h)) == 0);
    free(t);

    /* A device (a symlink to /dev/full): refused, status 2, the reason named, the device left alone. */
    char full[300];
    snprintf(full, sizeof full, "%s/full.csv", dir);
    if (symlink("/dev/full", full) == 0) {
        s = results_open(dir, full, &fd, err, sizeof err, &status);
        CHECK_MSG(!s && status == 2 && strstr(err, "full.csv: is a character device, not a regular file"), "%s", err);
        CHECK(write_file_checked(full, "a", "run info\n", err, sizeof err) == -2);
        CHECK_MSG(strstr(err, "full.csv: is a character device, not a regular file") != NULL, "%s", err);
        struct stat st;
        CHECK(lstat(full, &st) == 0 && S_ISLNK(st.st_mode));
        unlink(full);
    } else {
        CHECK(!"cannot make a symlink to /dev/full");
    }
    CHECK(write_file_checked("/nonexistent-dir/run.txt", "a", "x", err, sizeof err) == -2);

    /* An append cut short by the file size limit is undone: no half row. */
    free(slurp(path, &whole));
    struct rlimit old, lim;
    getrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, SIG_IGN);
    lim = old;
    lim.rlim_cur = (rlim_t)whole + 100; /* room for the start of a row, not all of it */
    s = results_open(dir, path, &fd, err, sizeof err, &status);
    CHECK(s != NULL);
    if (s && setrlimit(RLIMIT_FSIZE, &lim) == 0) {
        CHECK(put(s, "f", "primary", 6, err, sizeof err) == -1);
        CHECK_MSG(strstr(err, "matrix.csv: write failed: File too large") != NULL, "%s", err);
        setrlimit(RLIMIT_FSIZE, &old);
        free(slurp(path, &len));
        CHECK_MSG(len == whole, "%zu bytes after the failed append, %zu before", len, whole);
        /* The store goes on: the next row fits again once the limit is lifted. */
        CHECK(put(s, "f", "primary", 6, err, sizeof err) == 0);
    }
    results_close(s, err, sizeof err);
    CHECK(count_lines(path) == 7);

    unlink(bad);
    unlink(path);
    rmdir(dir);
}

int main(void)
{
    test_cell_keys();
    test_run_id();
    test_rows();
    test_store();
    return check_report();
}
