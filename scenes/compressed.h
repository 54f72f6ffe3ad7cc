/* compressed.h: read one whole input file into memory, whatever it is
 * wrapped in.
 *
 * Mesh files come from Debian packages, where they are often gzipped or sit
 * inside a tarball (libcgal-demo ships its meshes in data.tar.gz). Rather
 * than unpack them to disk, the loaders name them as
 *   PATH                a plain or compressed file (.gz, .xz, .bz2, .zst, ...,
 *                       recognised by content, not by name)
 *   ARCHIVE#MEMBER      one member of a tar (or any libarchive format),
 *                       itself possibly compressed (data.tar.gz#x.off, or
 *                       x.tar#y.obj.gz)
 * and get the decompressed bytes plus the inner file name, whose extension
 * tells the mesh reader the format. All reading goes through libarchive. */
#ifndef ACCELBENCH_COMPRESSED_H
#define ACCELBENCH_COMPRESSED_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/stat.h>

typedef struct {
    char *data;      /* malloc'd; data[size] == '\0' so text parsers can stop there */
    size_t size;
    char name[512];  /* base name of what was read, compression suffixes removed:
                      * "bunny00.off" for data.tar.gz#data/meshes/bunny00.off,
                      * "x.obj" for dir/x.obj.gz */
} file_data_t;

/* Read PATH (see above) into *out. Only a regular file is read (a FIFO or
 * a device is refused before it is opened for reading), and what is held
 * in memory, decompressed, stays within the memory cap (memory_cap.h). A
 * member that is a hard link is read from the member it links to. Returns
 * 0, or -1 with a one-line reason in err naming the file: "PATH: <strerror>"
 * when it cannot be opened, "PATH: a FIFO (named pipe), not a regular
 * file ...", "no member M in ARCHIVE" when the member is missing, "M in
 * ARCHIVE is a symbolic link to T ..." or "... is a directory ...", "PATH:
 * decompresses to nothing ...", the memory cap's line, or libarchive's
 * reason when the data is corrupt. */
int compressed_read(const char *path, file_data_t *out, char *err, size_t errlen);
void compressed_free(file_data_t *f);

/* The file on disk that PATH reads from: PATH itself, or the ARCHIVE part of
 * ARCHIVE#MEMBER (the longest prefix before a '#' that is an existing file,
 * else the part before the last '#'). Used to tell which package is missing. */
void compressed_disk_file(const char *path, char *file, size_t filelen);

/* Whether PATH's disk file (above) exists; the member is not looked for. */
bool compressed_exists(const char *path);

/* The lower-case extension of a file name without the dot ("off"), or ""
 * when there is none. Writes at most extlen-1 characters. */
void compressed_extension(const char *name, char *ext, size_t extlen);

/* A file type other than a regular file, in words ("a FIFO (named pipe)"),
 * for the messages that refuse one. */
const char *file_kind(mode_t mode);

#endif
