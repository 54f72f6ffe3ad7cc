/* mesh_check.c: OBJ, OFF, PLY and STL files checked before assimp reads them.
 *
 * assimp (Debian's 5.2.5) carries on with altered data on some bad input,
 * loops on some, and allocates what a header declares before reading it
 * (load_mesh.c's header has the rest of the story). These checks read the
 * formats line by line as assimp does and turn each such case into an
 * error naming the file and the line:
 * - OBJ: a face of 1 or 2 vertices (assimp keeps it as a point or a line,
 *   which the loader skips, so a file cut off mid-face lost its last face
 *   without a word), a vertex line short of a number (assimp then reads
 *   garbage), a face reference that is not an index or names no vertex
 *   before it;
 * - OFF: counts the file's lines cannot hold, in every variant and as
 *   assimp finds them (it allocates them first: a 2e9-vertex header is a
 *   12 GB std::bad_alloc); files with 3D vertices (OFF, COFF, NOFF, STOFF
 *   ...) completely (assimp reads missing numbers as 0, and crashes on
 *   some faces of COFF files);
 * - PLY: counts no file could hold, a header without end_header, an
 *   ASCII line short of its numbers (mesh_check_ply.c);
 * - STL (ASCII): a facet without a normal, of other than 3 vertices, a
 *   number missing, a solid without facets (assimp throws, and leaks);
 *   binary: a size other than its header's triangles take (assimp then
 *   says only that it cannot tell the file's representation);
 * - OBJ, OFF and ASCII STL vertices outside the scene range
 *   (scene.h), here where the line is known (scene_finish checks every
 *   source again).
 * A cut that leaves only complete lines ("f 1 2 3" from "f 1 2 34")
 * cannot be told from a complete file. */
#include "mesh_check.h"
#include "scene.h"

#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* ------------------------------------------------------------ lines:
 * the helpers every format's check shares (mesh_check.h) */

const char *mesh_next_line(mesh_lines *r)
{
    while (r->p < r->end) {
        const char *eol = memchr(r->p, '\n', (size_t)(r->end - r->p));
        if (!eol) eol = r->end;
        size_t n = (size_t)(eol - r->p);
        r->cut = n >= sizeof r->buf;
        if (r->cut) n = sizeof r->buf - 1;
        memcpy(r->buf, r->p, n);
        r->buf[n] = '\0';
        r->p = eol < r->end ? eol + 1 : r->end;
        r->line++;
        char *hash = strchr(r->buf, '#');
        if (hash) *hash = '\0';
        if (r->buf[strspn(r->buf, MESH_BLANKS)]) return r->buf;
    }
    return NULL;
}

int mesh_numbers(const char *s, double *v, int max, bool ints)
{
    int n = 0;
    while (n < max) {
        char *e;
        double x = ints ? (double)strtol(s, &e, 10) : strtod(s, &e);
        if (e == s || (*e && !strchr(MESH_BLANKS, *e))) break;
        v[n++] = x;
        s = e;
    }
    return n;
}

bool mesh_keyword(const char *l, const char *kw)
{
    size_t n = strlen(kw);
    return strncmp(l, kw, n) == 0 && (!l[n] || strchr(MESH_BLANKS, l[n]));
}

int mesh_coords_check(const double *xyz, const char *path, unsigned line, uint32_t v, char *err, size_t errlen)
{
    for (int k = 0; k < 3; k++)
        if (isfinite(xyz[k]) && !(fabs(xyz[k]) <= SCENE_COORD_MAX)) {
            snprintf(err, errlen, "%s: line %u: vertex %u coordinate %g is outside the scene range: coordinates must be "
                     SCENE_COORD_RANGE, path, line, v, xyz[k]);
            return -1;
        }
    return 0;
}

/* -------------------------------------------------------------- OBJ */

/* A face reference V, V/T, V//N or V/T/N (T and N may be empty, as assimp
 * allows): true with its vertex index, false when tok is not one. */
static bool obj_ref(const char *tok, long *v)
{
    char *e;
    errno = 0;
    *v = strtol(tok, &e, 10);
    if (e == tok || errno || (*e && *e != '/')) return false;
    for (int part = 0; *e == '/' && part < 2; part++) {
        char *s = e + 1;
        e = s;
        if (*s && *s != '/' && (strtol(s, &e, 10), e == s)) return false;
    }
    return *e == '\0';
}

/* One "f" line (after the keyword): 1 or 2 references are refused (a face
 * with none assimp refuses itself), each reference must be an index, not
 * 0, and a negative one (counted back from the last vertex) must name one
 * of the nv vertices so far. Positive ones may point forward, as assimp
 * allows; it refuses any beyond the file's count. A line cut by the reader
 * is only checked as far as it was read. */
static int obj_face(char *refs, bool cut, uint32_t nv, const char *path, unsigned line, char *err, size_t errlen)
{
    int n = 0;
    char *save = NULL;
    for (char *tok = strtok_r(refs, MESH_BLANKS, &save); tok; tok = strtok_r(NULL, MESH_BLANKS, &save), n++) {
        long v;
        if (cut && !save[0]) break; /* the last token of a cut line may be cut too */
        if (!obj_ref(tok, &v)) {
            snprintf(err, errlen, "%s: line %u: face vertex '%.32s' is not an index (V, V/T, V//N or V/T/N)", path, line, tok);
            return -1;
        }
        if (v == 0 || (v < 0 && (unsigned long)-v > nv)) {
            snprintf(err, errlen, "%s: line %u: face uses vertex %ld, but %u vertices come before it (OBJ counts from 1, "
                     "negative from the last)", path, line, v, nv);
            return -1;
        }
    }
    if ((n == 1 || n == 2) && !cut) {
        snprintf(err, errlen, "%s: line %u: a face of %d vertices; a face needs at least 3 (a file cut off mid-face?)",
                 path, line, n);
        return -1;
    }
    return 0;
}

/* One logical line into out: a line ending in '\' continues on the next,
 * as assimp reads it. NULL at the end; *first is its first line's number. */
static char *obj_line(mesh_lines *r, char *out, size_t outlen, unsigned *first, bool *cut)
{
    const char *l = mesh_next_line(r);
    if (!l) return NULL;
    *first = r->line;
    *cut = r->cut;
    size_t n = 0;
    for (;;) {
        size_t k = strlen(l);
        if (n + k >= outlen) k = outlen - 1 - n, *cut = true;
        memcpy(out + n, l, k);
        n += k;
        out[n] = '\0';
        while (n && strchr(MESH_BLANKS, out[n - 1])) out[--n] = '\0';
        if (!n || out[n - 1] != '\\' || *cut) return out;
        out[n - 1] = ' ';
        if (!(l = mesh_next_line(r))) return out;
        *cut = *cut || r->cut;
    }
}

static int obj_check(const char *data, size_t size, const char *path, char *err, size_t errlen)
{
    mesh_lines r = {data, data + size, 0, false, {0}};
    uint32_t nv = 0;
    char buf[8192];
    unsigned line;
    bool cut;
    for (char *l; (l = obj_line(&r, buf, sizeof buf, &line, &cut));) {
        l += strspn(l, MESH_BLANKS);
        if (mesh_keyword(l, "v")) {
            double xyz[3];
            if (mesh_numbers(l + 1, xyz, 3, false) < 3) {
                snprintf(err, errlen, "%s: line %u: vertex %u needs 3 coordinates (truncated file?)", path, line, nv + 1);
                return -1;
            }
            if (mesh_coords_check(xyz, path, line, nv + 1, err, errlen)) return -1;
            if (nv == UINT32_MAX) {
                snprintf(err, errlen, "%s: line %u: more than 2^32 - 1 vertices", path, line);
                return -1;
            }
            nv++;
        } else if (mesh_keyword(l, "f") && obj_face(l + 1, cut, nv, path, line, err, errlen)) {
            return -1;
        }
    }
    return 0;
}

/* -------------------------------------------------------------- OFF */

/* Skip blanks, line ends and '#' comment lines as assimp's OFF reader
 * does between tokens, counting line ends into *line. */
static const char *off_skip(const char *p, const char *end, unsigned *line)
{
    while (p < end) {
        if (*p == '\n') (*line)++, p++;
        else if (strchr(MESH_BLANKS, *p)) p++;
        else if (*p == '#') while (p < end && *p != '\n') p++;
        else break;
    }
    return p;
}

/* A count as assimp reads it (strtoul10: leading digits, wrapping at 2^32). */
static uint32_t off_count(const char **p, const char *end)
{
    uint32_t v = 0;
    for (; *p < end && isdigit((unsigned char)**p); (*p)++) v = v * 10u + (uint32_t)(**p - '0');
    return v;
}

/* The counts as assimp's OFF reader finds them (any variant, with or
 * without the header, which it matches as a prefix: "OFF1 ..." is OFF and
 * a count 1) against the lines that follow: one a vertex and one a face.
 * assimp allocates the counts before it reads a line (a 2^31-face header
 * is a 32 GB allocation). */
static int off_counts_check(const char *data, size_t size, const char *path, char *err, size_t errlen)
{
    const char *end = data + size;
    unsigned line = 1;
    const char *p = off_skip(data, end, &line), *q = p;
    bool dimension = false;
    if (end - q > 2 && q[0] == 'S' && q[1] == 'T') q += 2;
    if (end - q > 1 && *q == 'C') q++;
    if (end - q > 1 && *q == 'N') q++;
    if (end - q > 1 && *q == '4') q++;
    if (end - q > 1 && *q == 'n') q++, dimension = true;
    /* Without the OFF keyword the letters before it are still consumed, 'n' still reads a dimension, and
     * the counts follow them (assimp read "C 4294967295 5" as 2^32 - 1 vertices: a 48 GB allocation). */
    p = end - q > 3 && strncmp(q, "OFF", 3) == 0 ? q + 3 : q;
    p = off_skip(p, end, &line);
    if (dimension) (void)off_count(&p, end), p = off_skip(p, end, &line);
    uint32_t nv = off_count(&p, end);
    p = off_skip(p, end, &line);
    uint32_t nf = off_count(&p, end);
    unsigned counts_line = line;
    mesh_lines r = {memchr(p, '\n', (size_t)(end - p)) ? (const char *)memchr(p, '\n', (size_t)(end - p)) + 1 : end,
                     end, 0, false, {0}};
    double lines = 0;
    while (mesh_next_line(&r)) lines++;
    if ((double)nv + nf > lines) {
        snprintf(err, errlen, "%s: line %u: declares %u vertices and %u faces, but %.0f lines follow (truncated or "
                 "corrupt file?)", path, counts_line, nv, nf, lines);
        return -1;
    }
    return 0;
}

/* Whether the n-byte header keyword kw is OFF with 3D vertices whose
 * extra numbers (texture coordinates, colours, a normal) follow x y z:
 * [ST][C][N]OFF. */
static bool off_xyz_keyword(const char *kw, size_t n)
{
    if (n >= 2 && strncmp(kw, "ST", 2) == 0) kw += 2, n -= 2;
    if (n && *kw == 'C') kw++, n--;
    if (n && *kw == 'N') kw++, n--;
    return n == 3 && strncmp(kw, "OFF", 3) == 0;
}

/* OFF with 3D vertices and its keyword whole ([ST][C][N]OFF), or no
 * keyword at all, line by line as assimp reads it: the counts, NV lines of at least 3 numbers, NF
 * lines of "K i1 .. iK" with every index in range; extra numbers (colours)
 * are allowed. Any other file only has its counts checked (above). */
static int off_check(const char *data, size_t size, const char *path, char *err, size_t errlen)
{
    mesh_lines r = {data, data + size, 0, false, {0}};
    const char *l = mesh_next_line(&r);
    if (!l) return 0; /* assimp will say what is wrong */
    l += strspn(l, MESH_BLANKS);
    size_t kw = strcspn(l, MESH_BLANKS);
    /* A file that starts with its counts is read as OFF too (the fuzzer's
     * "3 1 0" file with a face of 295 vertices crashed assimp). */
    bool headerless = kw && strspn(l, "0123456789") == kw; /* a count, not "4OFF" */
    if (headerless) kw = 0;
    else if (!off_xyz_keyword(l, kw)) return off_counts_check(data, size, path, err, errlen);
    double cnt[3];
    int n = mesh_numbers(l + kw, cnt, 3, true);
    if (n == 0) {
        if (!(l = mesh_next_line(&r))) {
            snprintf(err, errlen, "%s: ends after the OFF header, with no counts", path);
            return -1;
        }
        n = mesh_numbers(l, cnt, 3, true);
    }
    if (n < 2 || cnt[0] < 0 || cnt[1] < 0 || cnt[0] > UINT32_MAX || cnt[1] > UINT32_MAX) {
        snprintf(err, errlen, "%s: line %u: expected the vertex and face counts", path, r.line);
        return -1;
    }
    uint32_t nv = (uint32_t)cnt[0], nf = (uint32_t)cnt[1];
    for (uint32_t v = 0; v < nv; v++) {
        double xyz[3];
        if (!(l = mesh_next_line(&r))) {
            snprintf(err, errlen, "%s: ends after %u of %u vertices (truncated file?)", path, v, nv);
            return -1;
        }
        if (mesh_numbers(l, xyz, 3, false) < 3) {
            snprintf(err, errlen, "%s: line %u: vertex %u needs 3 coordinates", path, r.line, v);
            return -1;
        }
        if (mesh_coords_check(xyz, path, r.line, v, err, errlen)) return -1;
    }
    for (uint32_t f = 0; f < nf; f++) {
        double idx[11];
        if (!(l = mesh_next_line(&r))) {
            snprintf(err, errlen, "%s: ends after %u of %u faces (truncated file?)", path, f, nf);
            return -1;
        }
        int got = mesh_numbers(l, idx, 11, true);
        if (got < 1 || idx[0] < 1) {
            snprintf(err, errlen, "%s: line %u: face %u needs a vertex count of at least 1", path, r.line, f);
            return -1;
        }
        if (idx[0] > 9) { /* assimp 5.2 drops such faces; fail like it logs */
            snprintf(err, errlen, "%s: line %u: face %u has %g vertices; assimp's OFF reader takes at most 9", path, r.line, f, idx[0]);
            return -1;
        }
        int k = (int)idx[0];
        if (got < 1 + k) {
            snprintf(err, errlen, "%s: line %u: face %u needs %d vertex indices (truncated file?)", path, r.line, f, k);
            return -1;
        }
        for (int j = 1; j <= k; j++)
            if (idx[j] < 0 || idx[j] >= nv) {
                snprintf(err, errlen, "%s: line %u: face %u uses vertex %g of %u", path, r.line, f, idx[j], nv);
                return -1;
            }
    }
    return 0;
}

/* -------------------------------------------------------------- STL */

/* A number as assimp's fast_atoreal_move takes it (a sign, then a digit or
 * '.' and a digit; or nan, inf), and whole. */
static bool stl_number(const char *tok, double *x)
{
    const char *t = tok + (*tok == '+' || *tok == '-');
    bool named = strncasecmp(t, "nan", 3) == 0 || strncasecmp(t, "inf", 3) == 0;
    if (!named && !(isdigit((unsigned char)t[0]) || (t[0] == '.' && isdigit((unsigned char)t[1])))) return false;
    char *e;
    *x = strtod(tok, &e);
    return e != tok && *e == '\0';
}

/* Three numbers from the same line (assimp reads them across spaces, not
 * line ends); false if there are not three. */
static bool stl_numbers(char **save, double *xyz)
{
    for (int k = 0; k < 3; k++) {
        const char *tok = strtok_r(NULL, MESH_BLANKS, save);
        if (!tok || !stl_number(tok, &xyz[k])) return false;
    }
    return true;
}

/* ASCII STL (assimp's rule: not a binary file's exact size 84 + 50 n, and
 * "solid" first), token by token as assimp's reader goes: every facet is
 * "facet normal X Y Z" on one line and exactly 3 "vertex X Y Z" lines (the
 * coordinates within the scene range) before the next facet or endsolid.
 * assimp throws on a facet without a normal or of other than 3 vertices,
 * on a missing number and on a solid without facets, and leaks the mesh it
 * was filling each time. A binary file (anything else, or "solid" followed
 * by a NUL byte in its 80-byte header, as some writers do) must be exactly
 * the 84 + 50 n bytes its count of n triangles takes: a cut file is named
 * as one. The loader checks binary files' coordinates. */
static int stl_check(const char *data, size_t size, const char *path, char *err, size_t errlen)
{
    uint32_t n = 0;
    if (size >= 84 && (memcpy(&n, data + 80, 4), 84 + 50 * (uint64_t)n == size)) return 0;
    const char *p = data + strspn(data, MESH_BLANKS "\n");
    bool ascii = (size_t)(p - data) + 5 <= size && strncmp(p, "solid", 5) == 0 && !memchr(data, '\0', size < 80 ? size : 80);
    if (!ascii && size < 84) {
        snprintf(err, errlen, "%s: %zu bytes: too short for a binary STL (an 84-byte header) and not an ASCII one "
                 "('solid' first)", path, size);
        return -1;
    }
    if (!ascii) {
        uint64_t want = 84 + 50 * (uint64_t)n;
        snprintf(err, errlen, "%s: a binary STL %s: %zu bytes where its header's %u triangles take %llu", path,
                 size < want ? "cut short (truncated)" : "with bytes after its triangles", size, n,
                 (unsigned long long)want);
        return -1;
    }
    mesh_lines r = {data, data + size, 0, false, {0}};
    unsigned facet = 0;             /* the line of the open facet, 0 before the first */
    int nvert = 3;                  /* vertices of the open facet */
    uint32_t v = 0;                 /* vertices so far */
    const char *why = NULL;
    unsigned at = 0; /* the line the message names */
    for (char *l; !why && (l = (char *)mesh_next_line(&r));) {
        at = r.line;
        char *save = NULL;
        double xyz[3];
        for (char *tok = strtok_r(l, MESH_BLANKS, &save); tok && !why; tok = strtok_r(NULL, MESH_BLANKS, &save)) {
            bool end = strncmp(tok, "endsolid", 8) == 0;
            if ((end || !strcmp(tok, "facet")) && nvert != 3) {
                why = "a facet of other than 3 vertices", at = facet;
            } else if (end) {
                if (v == 0) why = "a solid without facets";
                break; /* the rest of the line is its name */
            } else if (!strcmp(tok, "solid")) {
                break; /* and its name */
            } else if (!strcmp(tok, "facet")) {
                facet = r.line, nvert = 0;
                const char *normal = strtok_r(NULL, MESH_BLANKS, &save);
                if (!normal || strcmp(normal, "normal") || !stl_numbers(&save, xyz)) why = "a facet without 'normal X Y Z'";
            } else if (!strcmp(tok, "vertex")) {
                if (!facet || nvert == 3) why = "a vertex outside a facet, or a facet of more than 3";
                else if (!stl_numbers(&save, xyz)) why = "a vertex without 3 numbers";
                else if (mesh_coords_check(xyz, path, r.line, v, err, errlen)) return -1;
                v++, nvert++;
            }
        }
    }
    if (!why && nvert != 3) why = "a facet of other than 3 vertices (truncated file?)", at = facet;
    if (!why) return 0;
    snprintf(err, errlen, "%s: line %u: %s", path, at, why);
    return -1;
}

int mesh_precheck(const char *ext, const char *data, size_t size, const char *path, char *err, size_t errlen)
{
    if (strcmp(ext, "stl") == 0) return stl_check(data, size, path, err, errlen);
    if (strcmp(ext, "obj") == 0) return obj_check(data, size, path, err, errlen);
    if (strcmp(ext, "off") == 0) return off_check(data, size, path, err, errlen);
    if (strcmp(ext, "ply") == 0) return mesh_check_ply(data, size, path, err, errlen);
    return 0;
}
