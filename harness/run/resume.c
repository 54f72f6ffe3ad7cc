/* resume.c: run's results file on disk: reading it, repairing a torn
 * tail, appending and replacing rows with every write checked (see
 * resume.h). */
#include "resume.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>
#include "csv.h"
#include "output.h"

typedef struct {
    char *text;       /* the record with its line break */
    size_t len;
    char *key, *run_id, *git_rev;
} record;

struct results_store {
    char path[PATH_MAX];     /* as given: messages name it */
    char real[PATH_MAX];     /* symlinks resolved: rewrites rename onto it */
    char tmp_dir[PATH_MAX];  /* the folder of real: temporary files go there, so rename stays in one file system */
    char tmp_prefix[PATH_MAX + 16]; /* ".matrix.csv.tmp." */
    int fd;                  /* read-write, appending */
    int dir_fd;              /* the locked folder */
    bool regular;            /* a regular file: rows are read, cut back and rewritten */
    off_t size;              /* bytes in the file (regular files) */
    char header[CSV_HEADER_MAX + 1]; /* with its line break */
    size_t header_len;
    int ncols, key_col, run_col, git_col;
    record *rec;
    int nrec, cap;
    int *index;              /* open addressing: record index + 1, 0 empty */
    size_t index_cap;        /* a power of two, at least twice nrec */
};

static void set_err(char *err, size_t errlen, const char *path, const char *what)
{
    snprintf(err, errlen, "%s: %s: %s", path, what, strerror(errno));
}

/* write(2) all of buf, through short writes and EINTR. */
static int write_all(int fd, const char *buf, size_t len)
{
    while (len) {
        ssize_t w = write(fd, buf, len);
        if (w < 0 && errno == EINTR) continue;
        if (w < 0) return -1;
        if (w == 0) {
            errno = EIO;
            return -1;
        }
        buf += w;
        len -= (size_t)w;
    }
    return 0;
}

/* fdatasync, except where the file has nothing to sync (a device, a pipe). */
static int sync_fd(int fd, bool regular)
{
    if (!regular) return 0;
    while (fdatasync(fd) != 0) {
        if (errno == EINTR) continue;
        if (errno == EINVAL || errno == EROFS) return 0; /* the file system does not sync this file: nothing to wait for */
        return -1;
    }
    return 0;
}

/* ------------------------------------------------------------ the index */

static uint64_t key_hash(const char *s)
{
    uint64_t h = 0xcbf29ce484222325ull; /* FNV-1a 64 */
    for (; *s; s++) h = (h ^ (unsigned char)*s) * 0x100000001b3ull;
    return h;
}

static int index_find(const results_store *s, const char *key)
{
    if (!s->index_cap) return -1;
    for (size_t i = key_hash(key) & (s->index_cap - 1);; i = (i + 1) & (s->index_cap - 1)) {
        int r = s->index[i];
        if (r == 0) return -1;
        if (strcmp(s->rec[r - 1].key, key) == 0) return r - 1;
    }
}

/* Index record r; a key already there now names r (the later row counts).
 * Returns 1 when the key was there, 0 when new, -1 out of memory. */
static int index_add(results_store *s, int r)
{
    const char *key = s->rec[r].key;
    if (!key[0]) return 0; /* a row without a key (written by hand) matches no cell */
    if ((size_t)(s->nrec + 1) * 2 > s->index_cap) {
        size_t cap = s->index_cap ? s->index_cap : 64;
        while ((size_t)(s->nrec + 1) * 2 > cap) cap *= 2;
        int *idx = calloc(cap, sizeof *idx);
        if (!idx) return -1;
        int *old = s->index;
        size_t old_cap = s->index_cap;
        s->index = idx;
        s->index_cap = cap;
        for (size_t i = 0; i < old_cap; i++)
            if (old[i]) {
                size_t k = key_hash(s->rec[old[i] - 1].key) & (cap - 1);
                while (idx[k]) k = (k + 1) & (cap - 1);
                idx[k] = old[i];
            }
        free(old);
    }
    for (size_t i = key_hash(key) & (s->index_cap - 1);; i = (i + 1) & (s->index_cap - 1)) {
        if (s->index[i] == 0) {
            s->index[i] = r + 1;
            return 0;
        }
        if (strcmp(s->rec[s->index[i] - 1].key, key) == 0) {
            s->index[i] = r + 1;
            return 1;
        }
    }
}

static int index_rebuild(results_store *s)
{
    memset(s->index, 0, s->index_cap * sizeof *s->index);
    for (int r = 0; r < s->nrec; r++)
        if (index_add(s, r) < 0) return -1;
    return 0;
}

/* ------------------------------------------------------------ records */

static void record_free(record *r)
{
    free(r->text);
    free(r->key);
    free(r->run_id);
    free(r->git_rev);
}

/* A record from the text of one row (ncols fields, with its line break). */
static int record_make(const results_store *s, const char *text, size_t len, record *out)
{
    memset(out, 0, sizeof *out);
    csv_span sp[256];
    int nf;
    bool complete;
    csv_split_record(text, len, &nf, &complete, sp, (int)(sizeof sp / sizeof sp[0]));
    if (nf != s->ncols || s->ncols > (int)(sizeof sp / sizeof sp[0])) return -1; /* callers pass whole rows */
    out->text = malloc(len + 1);
    out->key = malloc(CELL_KEY_MAX);
    out->run_id = malloc(RUN_ID_MAX * 2);
    out->git_rev = malloc(128);
    if (!out->text || !out->key || !out->run_id || !out->git_rev) {
        record_free(out);
        return -1;
    }
    memcpy(out->text, text, len);
    out->text[len] = 0;
    out->len = len;
    csv_field(text, sp[s->key_col], out->key, CELL_KEY_MAX);
    csv_field(text, sp[s->run_col], out->run_id, RUN_ID_MAX * 2);
    csv_field(text, sp[s->git_col], out->git_rev, 128);
    return 0;
}

static int records_push(results_store *s, record *r)
{
    if (s->nrec == s->cap) {
        int cap = s->cap ? 2 * s->cap : 64;
        record *p = realloc(s->rec, (size_t)cap * sizeof *p);
        if (!p) return -1;
        s->rec = p;
        s->cap = cap;
    }
    s->rec[s->nrec++] = *r;
    return 0;
}

/* ------------------------------------------------------------ opening */

/* Lock the folder, so that no other run writes the same file. */
static int lock_folder(results_store *s, const char *dir, char *err, size_t errlen)
{
    s->dir_fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (s->dir_fd < 0) {
        set_err(err, errlen, dir, "cannot open the output folder");
        return -1;
    }
    if (flock(s->dir_fd, LOCK_EX | LOCK_NB) != 0) {
        if (errno == EWOULDBLOCK)
            snprintf(err, errlen, "%s: another accelbench run is writing to this folder (it holds its lock); wait for it "
                                  "to end or choose another --out", dir);
        else set_err(err, errlen, dir, "cannot lock the output folder");
        return -1;
    }
    return 0;
}

/* Where rewrites go: beside the file itself, symlinks resolved. Also
 * removes temporary files a killed run left there (the folder's lock says
 * no run is writing them now). */
static void rewrite_place(results_store *s)
{
    if (!realpath(s->path, s->real)) snprintf(s->real, sizeof s->real, "%s", s->path);
    snprintf(s->tmp_dir, sizeof s->tmp_dir, "%s", s->real);
    char *slash = strrchr(s->tmp_dir, '/');
    const char *base = slash ? slash + 1 : s->real;
    snprintf(s->tmp_prefix, sizeof s->tmp_prefix, ".%s.tmp.", base);
    if (slash) *slash = 0;
    else snprintf(s->tmp_dir, sizeof s->tmp_dir, ".");
    if (slash == s->tmp_dir) snprintf(s->tmp_dir, sizeof s->tmp_dir, "/");
    DIR *d = opendir(s->tmp_dir);
    if (!d) return;
    size_t plen = strlen(s->tmp_prefix);
    for (struct dirent *e; (e = readdir(d));)
        if (strncmp(e->d_name, s->tmp_prefix, plen) == 0) unlinkat(dirfd(d), e->d_name, 0);
    closedir(d);
}

/* The whole file into memory. */
static char *read_all(int fd, size_t *len)
{
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    if (!buf) return NULL;
    for (;;) {
        if (n == cap) {
            char *p = cap < SIZE_MAX / 2 ? realloc(buf, cap * 2) : NULL;
            if (!p) {
                free(buf);
                return NULL;
            }
            buf = p;
            cap *= 2;
        }
        ssize_t r = pread(fd, buf + n, cap - n, (off_t)n);
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) {
            free(buf);
            return NULL;
        }
        if (r == 0) break;
        n += (size_t)r;
    }
    *len = n;
    return buf;
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

/* Distinct run ids among the rows (-1 when out of memory: it is for a message). */
static int count_runs(const results_store *s)
{
    if (s->nrec == 0) return 0;
    const char **ids = malloc((size_t)s->nrec * sizeof *ids);
    if (!ids) return -1;
    for (int i = 0; i < s->nrec; i++) ids[i] = s->rec[i].run_id;
    qsort(ids, (size_t)s->nrec, sizeof *ids, cmp_str);
    int runs = 1;
    for (int i = 1; i < s->nrec; i++) runs += strcmp(ids[i - 1], ids[i]) != 0;
    free(ids);
    return runs;
}

/* Cut the file back to size bytes (a torn tail, a failed append). */
static int cut_back(results_store *s, off_t size)
{
    if (!s->regular) return 0;
    if (ftruncate(s->fd, size) != 0) return -1;
    s->size = size;
    return sync_fd(s->fd, true);
}

/* Read the rows; 0, or -1 with err and *status. */
static int load_rows(results_store *s, results_found *found, char *err, size_t errlen, int *status)
{
    size_t n = 0;
    char *text = read_all(s->fd, &n);
    if (!text) {
        set_err(err, errlen, s->path, "cannot read");
        *status = 2;
        return -1;
    }
    s->size = (off_t)n;
    int rc = 0;
    if (n >= 3 && memcmp(text, "\xEF\xBB\xBF", 3) == 0) { /* a spreadsheet's save: said as it is, not as columns */
        snprintf(err, errlen, "%s: starts with a UTF-8 byte-order mark, which this program never writes; remove those 3 "
                              "bytes or choose a new --out", s->path);
        free(text);
        *status = 2;
        return -1;
    }
    const char *nl = memchr(text, '\n', n);
    size_t first = nl ? (size_t)(nl - text) : n;
    size_t cmp_len = first && text[first - 1] == '\r' ? first - 1 : first;
    if (!nl) {
        /* No whole header: empty, or killed while writing the header. */
        if (n > 0 && !(n <= s->header_len && memcmp(text, s->header, n) == 0)) {
            snprintf(err, errlen, "%s: exists with other columns (not this version's header); choose a new --out", s->path);
            *status = 2;
            rc = -1;
        } else if (n > 0) {
            found->torn_line = 1;
            snprintf(found->torn_why, sizeof found->torn_why, "the header cut short");
        }
        free(text);
        if (rc == 0 && n > 0 && cut_back(s, 0)) {
            set_err(err, errlen, s->path, "write failed");
            *status = 1;
            rc = -1;
        }
        return rc;
    }
    if (cmp_len != s->header_len - 1 || memcmp(text, s->header, cmp_len) != 0) {
        int nf;
        bool complete;
        csv_split_record(text, n, &nf, &complete, NULL, 0);
        snprintf(err, errlen, "%s: exists with other columns (%d, this version writes %d%s); choose a new --out", s->path,
                 nf, s->ncols, nf == s->ncols - 2 ? ": made before rows had run_id and cell_key" : "");
        free(text);
        *status = 2;
        return -1;
    }
    size_t off = first + 1;
    int line = 2;
    while (off < n) {
        int nf;
        bool complete;
        size_t len = csv_split_record(text + off, n - off, &nf, &complete, NULL, 0);
        if (!complete || nf != s->ncols) {
            if (off + len < n) {
                snprintf(err, errlen, "%s: line %d: %d fields, expected %d: not a row this program writes (only a "
                                      "torn last row is repaired); mend the file or choose a new --out", s->path, line,
                         nf, s->ncols);
                *status = 2;
                rc = -1;
                break;
            }
            /* The last record, torn: drop it from the file. */
            found->torn_line = line;
            if (!complete) snprintf(found->torn_why, sizeof found->torn_why, "no line break at the end of the file");
            else snprintf(found->torn_why, sizeof found->torn_why, "%d fields, expected %d", nf, s->ncols);
            if (cut_back(s, (off_t)off)) {
                set_err(err, errlen, s->path, "write failed");
                *status = 1;
                rc = -1;
            }
            break;
        }
        record r;
        if (record_make(s, text + off, len, &r) || records_push(s, &r)) {
            snprintf(err, errlen, "%s: out of memory reading its rows", s->path);
            *status = 2;
            rc = -1;
            break;
        }
        int dup = index_add(s, s->nrec - 1);
        if (dup < 0) {
            snprintf(err, errlen, "%s: out of memory reading its rows", s->path);
            *status = 2;
            rc = -1;
            break;
        }
        if (dup) { /* this program writes a cell once: which row counts would be a guess */
            snprintf(err, errlen, "%s: line %d: cell %s is in an earlier row too (a cell has one row); mend the file "
                                  "or choose a new --out", s->path, line, s->rec[s->nrec - 1].key);
            *status = 2;
            rc = -1;
            break;
        }
        for (size_t i = off; i < off + len; i++) line += text[i] == '\n';
        off += len;
    }
    free(text);
    return rc;
}

results_store *results_open(const char *dir, const char *path, results_found *found, char *err, size_t errlen,
                            int *status)
{
    memset(found, 0, sizeof *found);
    results_store *s = calloc(1, sizeof *s);
    if (!s) {
        snprintf(err, errlen, "%s: out of memory", path);
        *status = 2;
        return NULL;
    }
    s->fd = s->dir_fd = -1;
    snprintf(s->path, sizeof s->path, "%s", path);
    csv_header(s->header, sizeof s->header - 1);
    s->header_len = strlen(s->header);
    s->header[s->header_len++] = '\n';
    s->header[s->header_len] = 0;
    s->ncols = csv_columns();
    s->key_col = csv_column_index("cell_key");
    s->run_col = csv_column_index("run_id");
    s->git_col = csv_column_index("git_rev");
    *status = 2;
    if (lock_folder(s, dir, err, errlen)) goto fail;
    if (output_replaceable(path, err, errlen)) goto fail;
    s->fd = open(path, O_RDWR | O_CREAT | O_APPEND | O_CLOEXEC, 0666);
    if (s->fd < 0) {
        set_err(err, errlen, path, "cannot open for appending");
        goto fail;
    }
    struct stat st;
    if (fstat(s->fd, &st) != 0) {
        set_err(err, errlen, path, "cannot open for appending");
        goto fail;
    }
    s->regular = S_ISREG(st.st_mode);
    if (s->regular) {
        rewrite_place(s);
        if (load_rows(s, found, err, errlen, status)) goto fail;
    }
    if (s->size == 0) {
        /* A new file (or not a regular one): the header first. */
        found->header_written = true;
        if (write_all(s->fd, s->header, s->header_len) || sync_fd(s->fd, s->regular)) {
            set_err(err, errlen, path, "write failed");
            int e = errno;
            cut_back(s, 0);
            errno = e;
            *status = 1;
            goto fail;
        }
        s->size = (off_t)s->header_len;
    }
    found->rows = s->nrec;
    found->runs = count_runs(s);
    *status = 0;
    return s;
fail:
    results_close(s, NULL, 0);
    return NULL;
}

const char *results_find(const results_store *s, const char *key, const char **git_rev)
{
    int r = index_find(s, key);
    if (r < 0) return NULL;
    if (git_rev) *git_rev = s->rec[r].git_rev;
    return s->rec[r].run_id;
}

static int append_row(results_store *s, const char *text, size_t len, char *err, size_t errlen)
{
    off_t before = s->size;
    if (write_all(s->fd, text, len) || sync_fd(s->fd, s->regular)) {
        int e = errno;
        cut_back(s, before); /* no half row left behind */
        errno = e;
        set_err(err, errlen, s->path, "write failed");
        return -1;
    }
    s->size += (off_t)len;
    return 0;
}

/* The file rewritten with `r` in place of every row of its key (in the
 * first one's place), through a temporary file renamed over it. */
static int replace_rows(results_store *s, record *r, char *err, size_t errlen)
{
    char tmp[2 * PATH_MAX + 64];
    snprintf(tmp, sizeof tmp, "%s/%s%ld", s->tmp_dir, s->tmp_prefix, (long)getpid());
    struct stat st;
    mode_t mode = fstat(s->fd, &st) == 0 ? st.st_mode & 07777 : 0644;
    int fd = open(tmp, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0) {
        set_err(err, errlen, s->path, "write failed (cannot create a temporary file beside it)");
        return -1;
    }
    bool placed = false, ok = fchmod(fd, mode) == 0 && write_all(fd, s->header, s->header_len) == 0;
    off_t size = (off_t)s->header_len;
    for (int i = 0; i < s->nrec && ok; i++) {
        const record *x = &s->rec[i];
        if (strcmp(x->key, r->key) == 0) {
            if (placed) continue;
            x = r;
            placed = true;
        }
        ok = write_all(fd, x->text, x->len) == 0;
        size += (off_t)x->len;
    }
    if (ok) ok = fsync(fd) == 0;
    int e = errno;
    if (close(fd) != 0 && ok) {
        ok = false;
        e = errno;
    }
    if (ok && rename(tmp, s->real) != 0) {
        ok = false;
        e = errno;
    }
    if (!ok) {
        unlink(tmp);
        errno = e;
        set_err(err, errlen, s->path, "write failed");
        return -1;
    }
    /* The folder's entry is the new file now; sync it so the rename lasts. */
    int dfd = open(s->tmp_dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dfd >= 0) {
        fsync(dfd);
        close(dfd);
    }
    int nfd = open(s->real, O_RDWR | O_APPEND | O_CLOEXEC);
    if (nfd < 0) {
        set_err(err, errlen, s->path, "cannot reopen after rewriting it");
        return -1;
    }
    close(s->fd);
    s->fd = nfd;
    s->size = size;
    /* The same change in memory: r in the first row of its key, the others gone. */
    int w = 0;
    placed = false;
    for (int i = 0; i < s->nrec; i++) {
        if (strcmp(s->rec[i].key, r->key) == 0) {
            record_free(&s->rec[i]);
            if (placed) continue;
            s->rec[i] = *r;
            placed = true;
        }
        s->rec[w++] = s->rec[i];
    }
    s->nrec = w;
    return 0;
}

int results_put(results_store *s, const char *key, const char *text, size_t len, char *err, size_t errlen)
{
    record r;
    if (record_make(s, text, len, &r)) {
        snprintf(err, errlen, "%s: out of memory", s->path);
        return -1;
    }
    if (strcmp(r.key, key) != 0) { /* the row's cell_key column is the key it is filed under */
        snprintf(err, errlen, "%s: internal error: a row filed under another cell key than its own", s->path);
        record_free(&r);
        return -1;
    }
    int rc;
    if (s->regular && index_find(s, key) >= 0) {
        rc = replace_rows(s, &r, err, errlen);
        if (rc == 0 && index_rebuild(s)) rc = -1;
        if (rc) record_free(&r);
        return rc;
    }
    rc = append_row(s, text, len, err, errlen);
    if (rc == 0 && !s->regular) { /* nothing is read back from a device or a pipe */
        record_free(&r);
        return 0;
    }
    if (rc == 0 && records_push(s, &r) == 0) {
        if (index_add(s, s->nrec - 1) >= 0) return 0;
        snprintf(err, errlen, "%s: out of memory", s->path);
        return -1;
    }
    if (rc == 0) snprintf(err, errlen, "%s: out of memory", s->path);
    record_free(&r);
    return -1;
}

int results_close(results_store *s, char *err, size_t errlen)
{
    if (!s) return 0;
    int rc = 0;
    if (s->fd >= 0 && close(s->fd) != 0) {
        if (err) set_err(err, errlen, s->path, "write failed");
        rc = -1;
    }
    if (s->dir_fd >= 0) close(s->dir_fd); /* and with it the folder's lock */
    for (int i = 0; i < s->nrec; i++) record_free(&s->rec[i]);
    free(s->rec);
    free(s->index);
    free(s);
    return rc;
}

int write_file_checked(const char *path, const char *mode, const char *text, char *err, size_t errlen)
{
    if (output_replaceable(path, err, errlen)) return -2;
    FILE *f = fopen(path, mode);
    if (!f) {
        set_err(err, errlen, path, "cannot open");
        return -2;
    }
    size_t len = strlen(text);
    bool ok = fwrite(text, 1, len, f) == len && fflush(f) == 0;
    int e = errno;
    if (fclose(f) != 0 && ok) {
        ok = false;
        e = errno;
    }
    if (!ok) {
        errno = e;
        set_err(err, errlen, path, "write failed");
        return -1;
    }
    return 0;
}
