/* compressed.c: whole-file reads through libarchive (see compressed.h).
 *
 * A plain path is opened with every decompression filter and the "raw"
 * format, so libarchive sniffs gzip/xz/bzip2/zstd/... by magic bytes and an
 * uncompressed file passes through unchanged. ARCHIVE#MEMBER opens the
 * archive with every format, walks the entries to MEMBER and reads it; a
 * member whose name says it is compressed is then decompressed in memory
 * the same way as a plain path.
 *
 * Only regular files are read: a FIFO without a writer would block the
 * open for ever, and /dev/zero or /dev/urandom never end. Everything read
 * into memory (a file, a member, a member's decompressed data) counts
 * against the memory cap (memory_cap.h) as it arrives, so a compression
 * bomb stops at the cap instead of filling the machine. */
#include "compressed.h"
#include "memory_cap.h"

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

const char *file_kind(mode_t mode)
{
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "a special file";
}

/* Open a file to be read whole: a regular file only, else -1 with the
 * reason. stat() comes first, so a FIFO or a device is refused before an
 * open could block on it or act on it; the open does not block, and
 * fstat() checks the file actually opened (another may have taken its
 * name in between). */
static int open_regular(const char *file, char *err, size_t errlen)
{
    struct stat st;
    if (stat(file, &st) != 0) {
        snprintf(err, errlen, "%s: %s", file, strerror(errno));
        return -1;
    }
    int fd = S_ISREG(st.st_mode) ? open(file, O_RDONLY | O_CLOEXEC | O_NONBLOCK) : -1;
    if (S_ISREG(st.st_mode) && fd < 0) {
        snprintf(err, errlen, "%s: %s", file, strerror(errno));
        return -1;
    }
    if (fd >= 0 && fstat(fd, &st) != 0) st.st_mode = 0;
    if (!S_ISREG(st.st_mode)) {
        if (fd >= 0) close(fd);
        snprintf(err, errlen, "%s: %s, not a regular file (scenes are read from regular files)", file,
                 file_kind(st.st_mode));
        return -1;
    }
    return fd;
}

/* The most a read may hold: the memory cap less what the caller holds. */
static size_t read_limit(size_t held)
{
    uint64_t cap = memory_cap_bytes();
    if (cap > SIZE_MAX / 2) cap = SIZE_MAX / 2;
    return (size_t)cap > held ? (size_t)cap - held : 0;
}

/* Read the current entry's data to the end into a malloc'd buffer with a
 * terminating NUL. hint is the expected size or 0. More than limit bytes
 * is the memory cap's error, found as the data arrive. */
static int read_entry(struct archive *a, size_t hint, size_t limit, const char *what, file_data_t *out, char *err,
                      size_t errlen)
{
    if (hint > limit) {
        (void)memory_cap_exceeded(hint, err, errlen, "%s: its contents", what);
        return -1;
    }
    size_t cap = hint ? hint + 1 : 1 << 16, n = 0;
    if (cap > limit) cap = limit;
    char *buf = malloc(cap + 1);
    if (!buf) {
        snprintf(err, errlen, "%s: out of memory", what);
        return -1;
    }
    for (;;) {
        if (n == cap && cap == limit) { /* full: anything more passes the cap */
            char probe;
            la_ssize_t r = archive_read_data(a, &probe, 1);
            if (r == 0) break;
            free(buf);
            if (r < 0)
                snprintf(err, errlen, "%s: %s", what, archive_error_string(a) ? archive_error_string(a) : "read error");
            else
                memory_cap_stopped(err, errlen, "%s: its contents run past %zu bytes", what, limit);
            return -1;
        }
        if (n == cap) {
            size_t ncap = cap > limit / 2 ? limit : cap * 2;
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
 * raw format: it has exactly one entry, the whole decompressed data. size
 * is the stream's size when it is known (0 if not), which is the data's
 * when no decompression filter was recognised. */
static int read_raw(struct archive *a, size_t size, size_t limit, const char *what, file_data_t *out, char *err,
                    size_t errlen)
{
    struct archive_entry *e;
    int r = archive_read_next_header(a, &e);
    if (r == ARCHIVE_EOF && archive_filter_count(a) > 1) { /* a compressed stream of nothing */
        snprintf(err, errlen, "%s: decompresses to nothing (the compressed file holds an empty file)", what);
        return -1;
    }
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
    return read_entry(a, archive_filter_count(a) == 1 ? size : 0, limit, what, out, err, errlen);
}

static struct archive *raw_reader(void)
{
    struct archive *a = archive_read_new();
    if (!a) return NULL;
    archive_read_support_filter_all(a);
    archive_read_support_format_raw(a);
    archive_read_support_format_empty(a); /* so that an empty stream is not "Unrecognized archive format" */
    return a;
}

static int read_plain(const char *file, file_data_t *out, char *err, size_t errlen)
{
    int fd = open_regular(file, err, errlen);
    if (fd < 0) return -1;
    struct stat st;
    if (fstat(fd, &st) != 0) memset(&st, 0, sizeof st);
    if (st.st_size == 0) { /* libarchive calls this an unrecognized format */
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
        rc = read_raw(a, st.st_size > 0 && (uint64_t)st.st_size < SIZE_MAX / 2 ? (size_t)st.st_size : 0, read_limit(0),
                      file, out, err, errlen);
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
        rc = read_raw(a, 0, read_limit(f->size), what, &inner, err, errlen);
    archive_read_free(a);
    if (rc == 0) {
        free(f->data);
        f->data = inner.data;
        f->size = inner.size;
    }
    return rc;
}

/* Whether an entry's name is the member asked for: a leading "./" and a
 * trailing '/' (tar's directories) are not part of a name. */
static bool same_member(const char *entry, const char *member)
{
    while (entry[0] == '.' && entry[1] == '/') entry += 2;
    while (member[0] == '.' && member[1] == '/') member += 2;
    size_t n = strlen(entry), m = strlen(member);
    while (n > 1 && entry[n - 1] == '/') n--;
    while (m > 1 && member[m - 1] == '/') m--;
    return n == m && memcmp(entry, member, n) == 0;
}

/* How many hard links read_member follows from one member to another. */
#define MAX_LINK_HOPS 8

/* Walk the archive in fd to member and read it (0, or -1 with err). A
 * member that is a hard link without data of its own returns 1 with the
 * member it links to in target (its data came earlier in the archive). */
static int scan_member(int fd, const char *file, const char *member, const char *path, file_data_t *out,
                       char *target, size_t targetlen, char *err, size_t errlen)
{
    struct archive *a = archive_read_new();
    if (!a) {
        snprintf(err, errlen, "%s: out of memory", file);
        return -1;
    }
    archive_read_support_filter_all(a);
    archive_read_support_format_all(a);
    int rc = -1;
    if (archive_read_open_fd(a, fd, 1 << 16) != ARCHIVE_OK) {
        snprintf(err, errlen, "%s: %s", file, archive_error_string(a) ? archive_error_string(a) : "cannot open");
        archive_read_free(a);
        return -1;
    }
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
        if (!name || !same_member(name, member)) continue;
        found = true;
        la_int64_t sz = archive_entry_size_is_set(e) ? archive_entry_size(e) : 0;
        const char *link = archive_entry_hardlink(e);
        if (link && sz <= 0) {
            copy_cut(target, targetlen, link);
            rc = 1;
        } else if (link || archive_entry_filetype(e) == AE_IFREG) {
            size_t hint = sz > 0 && (uint64_t)sz < SIZE_MAX / 2 ? (size_t)sz : 0;
            rc = read_entry(a, hint, read_limit(0), path, out, err, errlen);
        } else if (archive_entry_filetype(e) == AE_IFLNK) {
            const char *to = archive_entry_symlink(e);
            snprintf(err, errlen, "%s in %s is a symbolic link to %s, not a file (name the file it links to)", member,
                     file, to ? to : "?");
        } else {
            snprintf(err, errlen, "%s in %s is %s, not a file", member, file,
                     archive_entry_filetype(e) == AE_IFDIR ? "a directory" : "a special file");
        }
        break;
    }
    if (!found) snprintf(err, errlen, "no member %s in %s", member, file);
    archive_read_free(a);
    return rc;
}

/* ARCHIVE#MEMBER: the member's data, following hard links to the member
 * that holds them (tar stores a hard link's data once, with the first
 * name), then decompressed if its name says so. */
static int read_member(const char *file, const char *member, const char *path, file_data_t *out, char *err, size_t errlen)
{
    char want[1024], target[1024];
    copy_cut(want, sizeof want, member);
    int rc = 1;
    for (int hop = 0; rc == 1; hop++) {
        if (hop > MAX_LINK_HOPS) {
            snprintf(err, errlen, "%s in %s: more than %d hard links in a row", member, file, MAX_LINK_HOPS);
            return -1;
        }
        int fd = open_regular(file, err, errlen);
        if (fd < 0) return -1;
        rc = scan_member(fd, file, want, path, out, target, sizeof target, err, errlen);
        close(fd);
        if (rc == 1) copy_cut(want, sizeof want, target);
    }
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
