/* mesh_check.h: what the mesh loader checks in a file before assimp reads
 * it (mesh_check.c says what and why, per format; the PLY check is
 * mesh_check_ply.c), and the line helpers those checks share. Internal to
 * scenes/. */
#ifndef ACCELBENCH_MESH_CHECK_H
#define ACCELBENCH_MESH_CHECK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* Check data (size bytes, data[size] == '\0') of a file whose lower-case
 * extension is ext ("obj", "off", "ply", "stl"; any other passes). Returns
 * 0, or -1 with "PATH: line L: reason" (or "PATH: reason") in err. */
int mesh_precheck(const char *ext, const char *data, size_t size, const char *path, char *err, size_t errlen);

/* The PLY check (mesh_check_ply.c), the same contract. */
int mesh_check_ply(const char *data, size_t size, const char *path, char *err, size_t errlen);

/* --- shared by the format checks (mesh_check.c) --- */

#define MESH_BLANKS " \t\r\f\v"

typedef struct {
    const char *p, *end;
    unsigned line;   /* number of the line last returned, 1-based */
    bool cut;        /* the line last returned was longer than buf (its tail dropped) */
    char buf[4096];  /* assimp's OFF line limit too */
} mesh_lines;

/* The next line that is not blank once its '#' comment is removed; NULL at
 * the end of the data. */
const char *mesh_next_line(mesh_lines *r);
/* Parse up to max whole numbers (integers when ints) from s; returns how
 * many parsed before something that is not a number. */
int mesh_numbers(const char *s, double *v, int max, bool ints);
/* Whether line l starts with the keyword kw followed by a blank or its end. */
bool mesh_keyword(const char *l, const char *kw);
/* The ranges every scene lies in (scene.h), for vertex v (the format's own
 * numbering) on a line: -1 with "PATH: line L: vertex V coordinate X ...".
 * NaN and inf pass: assimp reads them as such and the loader's own check
 * says so. */
int mesh_coords_check(const double *xyz, const char *path, unsigned line, uint32_t v, char *err, size_t errlen);

#endif
