/* compressed.c: whole-file reads through libarchive (see compressed.h).
 *
 * A plain path is opened with every decompression filter and the "raw"
 * format, so libarchive sniffs gzip/xz/bzip2/zstd/... by magic bytes and an
 * uncompressed file passes through unchanged. ARCHIVE#MEMBER opens the
 * archive with every format, walks the entries to MEMBER and reads it; a
 * member whose name says it is compressed is then decompressed in memory
 * the same way as a plain path. */
#include "compressed.h"

#include <archive.h>
#include <archive_entry.h>
#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* Suffixes that name a compression wrapper rather than the file format. */
static const char *const compress_suffixes[] = {".gz", ".xz", ".bz2", ".zst", ".zstd", ".lz4", ".lzma", ".lz", ".Z", ".bz"};
#define N_SUFFIXES (sizeof compress_suffixes / sizeof compress_suffixes[0])

static bool has_suffix(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n > m && strcmp(s + n - m, suffix) == 0;
}

static bool compressed_by_name(const char *name)
{
    for (size_t i = 0; i < N_SUFFIXES; i++)
        if (has_suffix(name, compress_suffixes[i])) return true;
    return false;
}

/* Copy src into dst[n], cutting it short if it does not fit. */
static void copy_cut(char *dst, size_t n, const char *src)
{
    size_t m = strlen(src);
    if (m >= n) m = n - 1;
    memcpy(dst, src, m);
    dst[m] = '\0';
}

/* Base name with every trailing compression suffix removed. */
static void inner_name(const char *path, char *out, size_t outlen)
{
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    copy_cut(out, outlen, base);
    for (bool again = true; again;) {
        again = false;
        for (size_t i = 0; i < N_SUFFIXES; i++)
            if (has_suffix(out, compress_suffixes[i])) {
                out[strlen(out) - strlen(compress_suffixes[i])] = '\0';
                again = true;
            }
    }
}

void compressed_extension(const char *name, char *ext, size_t extlen)
{
    const char *base = strrchr(name, '/');
    base = base ? base + 1 : name;
    const char *dot = strrchr(base, '.');
    if (extlen == 0) return;
    ext[0] = '\0';
    if (!dot || dot == base) return;
    size_t i = 0;
    for (const char *c = dot + 1; *c && i + 1 < extlen; c++) ext[i++] = (char)tolower((unsigned char)*c);
    ext[i] = '\0';
}

static bool is_file(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && !S_ISDIR(st.st_mode);
}

/* Split PATH into the disk file and the member (NULL for a plain file).
 * A path that exists as a whole is plain even if it contains '#'; otherwise
 * the longest prefix before a '#' that exists is the archive. */
static void split_path(const char *path, char *file, size_t filelen, const char **member)
{
    *member = NULL;
    copy_cut(file, filelen, path);
    if (is_file(path) || !strchr(path, '#')) return;
    for (const char *h = strrchr(path, '#'); h; ) {
        size_t n = (size_t)(h - path);
        if (n < filelen) {
            memcpy(file, path, n);
            file[n] = '\0';
            if (is_file(file)) {
                *member = h + 1;
                return;
            }
        }
        /* try the next '#' to the left */
        const char *prev = NULL;
        for (const char *c = path; c < h; c++)
            if (*c == '#') prev = c;
        h = prev;
    }
    /* nothing exists: report the part before the last '#' as the archive */
    const char *h = strrchr(path, '#');
    size_t n = (size_t)(h - path);
    if (n >= filelen) n = filelen - 1;
    memcpy(file, path, n);
    file[n] = '\0';
    *member = h + 1;
}

void compressed_disk_file(const char *path, char *file, size_t filelen)
{
    const char *member;
    split_path(path, file, filelen, &member);
}

bool compressed_exists(const char *path)
{
    char file[4096];
    struct stat st;
    compressed_disk_file(path, file, sizeof file);
    return stat(file, &st) == 0;
}

/* Read the current entry's data to the end into a malloc'd buffer with a
 * terminating NUL. hint is the expected size or 0. */
static int read_entry(struct archive *a, size_t hint, const char *what, file_data_t *out, char *err, size_t errlen)
{
    size_t cap = hint ? hint + 1 : 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    if (!buf) {
        snprintf(err, errlen, "%s: out of memory", what);
        return -1;
    }
    for (;;) {
        if (n == cap) {
            size_t ncap = cap * 2;
            char *nb = realloc(buf, ncap + 1);
            if (!nb) {
                free(buf);
                snprintf(err, errlen, "%s: out of memory reading %zu bytes", what, n);
                return -1;
            }
            buf = nb;
            cap = ncap;
        }
        la_ssize_t r = archive_read_data(a, buf + n, cap - n);
        if (r < 0) {
            snprintf(err, errlen, "%s: %s", what, archive_error_string(a) ? archive_error_string(a) : "read error");
            free(buf);
            return -1;
        }
        if (r == 0) break;
        n += (size_t)r;
    }
    buf[n] = '\0';
    out->data = buf;
    out->size = n;
    return 0;
}

/* Read a single (possibly compressed) stream that is already opened as the
 * raw format: it has exactly one entry, the whole decompressed data. */
static int read_raw(struct archive *a, const char *what, file_data_t *out, char *err, size_t errlen)
{
    struct archive_entry *e;
    int r = archive_read_next_header(a, &e);
    if (r == ARCHIVE_EOF) { /* no entry: nothing to read */
        out->data = calloc(1, 1);
        out->size = 0;
        if (!out->data) snprintf(err, errlen, "%s: out of memory", what);
        return out->data ? 0 : -1;
    }
    if (r != ARCHIVE_OK && r != ARCHIVE_WARN) {
        snprintf(err, errlen, "%s: %s", what, archive_error_string(a) ? archive_error_string(a) : "cannot read");
        return -1;
    }
    return read_entry(a, 0, what, out, err, errlen);
}

static struct archive *raw_reader(void)
{
    struct archive *a = archive_read_new();
    if (!a) return NULL;
    archive_read_support_filter_all(a);
    archive_read_support_format_raw(a);
    return a;
}

static int read_plain(const char *file, file_data_t *out, char *err, size_t errlen)
{
    int fd = open(file, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        snprintf(err, errlen, "%s: %s", file, strerror(errno));
        return -1;
    }
    struct stat st;
    if (fstat(fd, &st) != 0) memset(&st, 0, sizeof st);
    if (S_ISDIR(st.st_mode)) {
        close(fd);
        snprintf(err, errlen, "%s: %s", file, strerror(EISDIR));
        return -1;
    }
    if (S_ISREG(st.st_mode) && st.st_size == 0) { /* libarchive calls this an unrecognized format */
        close(fd);
        out->data = calloc(1, 1);
        out->size = 0;
        if (!out->data) snprintf(err, errlen, "%s: out of memory", file);
        return out->data ? 0 : -1;
    }
    struct archive *a = raw_reader();
    if (!a) {
        close(fd);
        snprintf(err, errlen, "%s: out of memory", file);
        return -1;
    }
    int rc = -1;
    if (archive_read_open_fd(a, fd, 1 << 16) != ARCHIVE_OK)
        snprintf(err, errlen, "%s: %s", file, archive_error_string(a) ? archive_error_string(a) : "cannot open");
    else
        rc = read_raw(a, file, out, err, errlen);
    archive_read_free(a);
    close(fd);
    return rc;
}

/* Decompress an in-memory member whose name says it is compressed. */
static int decompress_member(const char *what, file_data_t *f, char *err, size_t errlen)
{
    struct archive *a = raw_reader();
    if (!a) {
        snprintf(err, errlen, "%s: out of memory", what);
        return -1;
    }
    file_data_t inner = {0};
    int rc = -1;
    if (archive_read_open_memory(a, f->data, f->size) != ARCHIVE_OK)
        snprintf(err, errlen, "%s: %s", what, archive_error_string(a) ? archive_error_string(a) : "cannot open");
    else
        rc = read_raw(a, what, &inner, err, errlen);
    archive_read_free(a);
    if (rc == 0) {
        free(f->data);
        f->data = inner.data;
        f->size = inner.size;
    }
    return rc;
}

static bool same_member(const char *entry, const char *member)
{
    while (entry[0] == '.' && entry[1] == '/') entry += 2;
    while (member[0] == '.' && member[1] == '/') member += 2;
    return strcmp(entry, member) == 0;
}

static int read_member(const char *file, const char *member, const char *path, file_data_t *out, char *err, size_t errlen)
{
    int fd = open(file, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        snprintf(err, errlen, "%s: %s", file, strerror(errno));
        return -1;
    }
    struct archive *a = archive_read_new();
    if (!a) {
        close(fd);
        snprintf(err, errlen, "%s: out of memory", file);
        return -1;
    }
    archive_read_support_filter_all(a);
    archive_read_support_format_all(a);
    int rc = -1;
    if (archive_read_open_fd(a, fd, 1 << 16) != ARCHIVE_OK) {
        snprintf(err, errlen, "%s: %s", file, archive_error_string(a) ? archive_error_string(a) : "cannot open");
    } else {
        struct archive_entry *e;
        bool found = false;
        for (;;) {
            int r = archive_read_next_header(a, &e);
            if (r == ARCHIVE_EOF) break;
            if (r != ARCHIVE_OK && r != ARCHIVE_WARN) {
                snprintf(err, errlen, "%s: %s", file, archive_error_string(a) ? archive_error_string(a) : "cannot read");
                found = true; /* an error, not a missing member */
                break;
            }
            const char *name = archive_entry_pathname(e);
            if (name && same_member(name, member) && archive_entry_filetype(e) == AE_IFREG) {
                found = true;
                la_int64_t sz = archive_entry_size_is_set(e) ? archive_entry_size(e) : 0;
                size_t hint = sz > 0 && (uint64_t)sz < SIZE_MAX / 2 ? (size_t)sz : 0;
                rc = read_entry(a, hint, path, out, err, errlen);
                break;
            }
        }
        if (!found) snprintf(err, errlen, "no member %s in %s", member, file);
    }
    archive_read_free(a);
    close(fd);
    if (rc == 0 && compressed_by_name(member) && decompress_member(path, out, err, errlen) != 0) {
        compressed_free(out);
        rc = -1;
    }
    return rc;
}

int compressed_read(const char *path, file_data_t *out, char *err, size_t errlen)
{
    memset(out, 0, sizeof *out);
    char file[4096];
    const char *member;
    split_path(path, file, sizeof file, &member);
    int rc = member ? read_member(file, member, path, out, err, errlen) : read_plain(file, out, err, errlen);
    if (rc == 0) inner_name(member ? member : file, out->name, sizeof out->name);
    return rc;
}

void compressed_free(file_data_t *f)
{
    free(f->data);
    f->data = NULL;
    f->size = 0;
}
