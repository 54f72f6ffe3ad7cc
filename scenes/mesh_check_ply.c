/* mesh_check_ply.c: the PLY check before assimp reads a file (mesh_check.h).
 *
 * assimp's PLY reader allocates what a count says before it reads what the
 * count counts: an element count of 2e9 in the header is a 24 GB
 * std::bad_alloc, and a face list of 1.2e22 items in the body (its count
 * taken modulo 2^32) took 80 s and 21 GB before failing the same way. It
 * also loops forever on a header that ends before its end_header line (a
 * truncated file), and crashed or hung on a control character after
 * end_header or a NUL inside the header. So the header must be text and is read as assimp reads it,
 * every element count must fit in the bytes after it at the least one
 * instance takes,
 * and the body is walked element by element as the header declares it,
 * every list's count against what its line (ASCII) or the rest of the file
 * (binary) holds; an ASCII line short of its numbers is refused too, since
 * assimp would read the next line's as its own. A header this walk cannot
 * follow (an unknown type in a binary file, more elements or properties
 * than it keeps) is left to assimp after the count check. */
#include "mesh_check.h"

#include <ctype.h>
#include <stdio.h>
#include <string.h>

#define MAX_ELEMENTS 64
#define MAX_PROPERTIES 64

typedef struct {
    bool list;
    unsigned count_size; /* a list's count type, in bytes */
    unsigned size;       /* the scalar's, or a list item's, in bytes; 0 for an unknown type */
} ply_property;

typedef struct {
    char name[32];
    double count;  /* as declared */
    unsigned line; /* of its "element" line */
    int nprops;
    ply_property props[MAX_PROPERTIES];
} ply_element;

typedef struct {
    int format; /* 0 ascii, 1 binary little-endian, 2 binary big-endian */
    int nel;
    bool whole; /* every element and property kept, every type known: the body can be walked */
    ply_element el[MAX_ELEMENTS];
} ply_header;

/* Bytes of a PLY scalar type, 0 for an unknown one. */
static unsigned type_size(const char *t)
{
    static const struct { const char *name; unsigned size; } types[] = {
        {"char", 1}, {"uchar", 1}, {"int8", 1}, {"uint8", 1}, {"short", 2}, {"ushort", 2}, {"int16", 2},
        {"uint16", 2}, {"int", 4}, {"uint", 4}, {"int32", 4}, {"uint32", 4}, {"float", 4}, {"float32", 4},
        {"double", 8}, {"float64", 8}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(t, types[i].name) == 0) return types[i].size;
    return 0;
}

/* The leading digits of s, as assimp reads a count ("5z" is 5), without
 * its 32-bit wrap. */
static double leading_count(const char *s)
{
    double x = 0;
    for (; isdigit((unsigned char)*s); s++) x = 10 * x + (*s - '0');
    return x;
}

/* One header line into h; -1 with the reason for a line that is none of
 * the header's: assimp's reader skips such a line and, with a property
 * misspelt, reads the body against a header it misunderstood (under
 * AddressSanitizer: writes past its own buffers). */
static int header_line(ply_header *h, const char *l, unsigned line, const char *path, char *err, size_t errlen)
{
    static const char *const keywords[] = {"ply", "format", "element", "property", "comment", "obj_info"};
    char w[5][64] = {{0}};
    int nw = sscanf(l, "%63s %63s %63s %63s %63s", w[0], w[1], w[2], w[3], w[4]);
    bool known = false;
    for (size_t k = 0; k < sizeof keywords / sizeof keywords[0]; k++) known |= strcmp(w[0], keywords[k]) == 0;
    if (!known) {
        snprintf(err, errlen, "%s: line %u: '%s' is not a PLY header keyword (ply, format, element, property, "
                 "comment, obj_info, end_header)", path, line, w[0]);
        return -1;
    }
    if (nw >= 2 && strcmp(w[0], "format") == 0) {
        h->format = !strcmp(w[1], "binary_little_endian") ? 1 : !strcmp(w[1], "binary_big_endian") ? 2 : 0;
    } else if (nw >= 2 && strcmp(w[0], "element") == 0) {
        if (h->nel == MAX_ELEMENTS) {
            h->whole = false;
            return 0;
        }
        /* The count of whichever word assimp takes it from: it took "element 18446744073709551615 vertex"
         * as 2^32 - 1, so the largest. */
        double c = 0;
        for (int k = 1; k < nw; k++) c = leading_count(w[k]) > c ? leading_count(w[k]) : c;
        ply_element *e = &h->el[h->nel++];
        *e = (ply_element){{0}, c, line, 0, {{0}}};
        snprintf(e->name, sizeof e->name, "%.31s", nw >= 3 ? w[1] : "?");
    } else if (nw >= 3 && strcmp(w[0], "property") == 0 && h->nel > 0) {
        ply_element *e = &h->el[h->nel - 1];
        bool list = strcmp(w[1], "list") == 0;
        ply_property p = {list, list ? type_size(w[2]) : 0, type_size(w[list ? 3 : 1])};
        if (e->nprops == MAX_PROPERTIES || (list && nw < 5) || (h->format && (!p.size || (list && !p.count_size))))
            h->whole = false;
        else
            e->props[e->nprops++] = p;
    }
    return 0;
}

/* The bytes one instance of e takes at least: ASCII a digit and a blank per
 * property, binary its scalars and its lists' counts; 1 for none. */
static double least_bytes(const ply_header *h, const ply_element *e)
{
    double n = 0;
    for (int k = 0; k < e->nprops; k++) n += h->format == 0 ? 2 : e->props[k].list ? e->props[k].count_size : e->props[k].size;
    return n > 0 ? n : 1;
}

/* ------------------------------------------------------------ the body */

/* ASCII: one instance a line, as assimp reads them (it ignores what a line
 * holds beyond its properties, and a line short of them makes it read the
 * next line's numbers as this one's: different geometry without a word):
 * every instance's line must hold its scalars, each list's count and that
 * many items. A line longer than the reader's buffer is taken on trust. */
static int walk_ascii(const ply_header *h, mesh_lines *r, const char *path, char *err, size_t errlen)
{
    for (int i = 0; i < h->nel; i++) {
        const ply_element *e = &h->el[i];
        for (double k = 0; k < e->count; k++) {
            const char *l = mesh_next_line(r);
            if (!l) {
                snprintf(err, errlen, "%s: ends after %.0f of the %.0f '%s' elements the header declares (truncated "
                         "file?)", path, k, e->count, e->name);
                return -1;
            }
            if (r->cut) continue;
            double tokens = 0, need = 0;
            const char *t[MAX_PROPERTIES + 1];
            for (const char *p = l + strspn(l, MESH_BLANKS); *p; p += strspn(p, MESH_BLANKS), tokens++) {
                if (tokens <= MAX_PROPERTIES) t[(int)tokens] = p;
                p += strcspn(p, MESH_BLANKS);
            }
            for (int j = 0; j < e->nprops && need <= tokens; j++) {
                /* a list's count is at token need (only the first MAX_PROPERTIES + 1 are kept: past them the
                 * counts are of items, and a later list is not checked) */
                double n = e->props[j].list && need <= MAX_PROPERTIES && need < tokens ? leading_count(t[(int)need]) : 0;
                need += 1 + n;
            }
            if (need > tokens) {
                snprintf(err, errlen, "%s: line %u: '%s' element %.0f needs %.0f numbers, the line holds %.0f "
                         "(truncated or corrupt file?)", path, r->line, e->name, k, need, tokens);
                return -1;
            }
        }
    }
    return 0;
}

/* A binary unsigned count of n bytes, in the file's byte order. */
static double binary_count(const unsigned char *b, unsigned n, bool big)
{
    double v = 0;
    for (unsigned i = 0; i < n; i++) v = 256 * v + b[big ? i : n - 1 - i];
    return v;
}

/* Binary: instances back to back; every list's count against the bytes left. */
static int walk_binary(const ply_header *h, const char *data, const char *p, const char *end, const char *path,
                       char *err, size_t errlen)
{
    for (int i = 0; i < h->nel; i++) {
        const ply_element *e = &h->el[i];
        for (double k = 0; k < e->count; k++)
            for (int j = 0; j < e->nprops; j++) {
                const ply_property *q = &e->props[j];
                double left = (double)(end - p);
                unsigned head = q->list ? q->count_size : q->size;
                double n = head <= left && q->list ? binary_count((const unsigned char *)p, head, h->format == 2) : 0;
                if (head + n * q->size > left) {
                    snprintf(err, errlen, "%s: byte %zu: '%s' element %.0f needs %.0f bytes, %.0f are left (truncated "
                             "or corrupt file?)", path, (size_t)(p - data), e->name, k, head + n * q->size, left);
                    return -1;
                }
                p += head + (size_t)n * q->size;
            }
    }
    return 0;
}

/* A NUL byte in the header, up to the line that starts with end_header:
 * the line checks below read each line as a C string and would stop at it,
 * while assimp reads on past it (and looped forever on a misspelt format
 * line followed by one). -1 with its line. */
static int header_nul(const char *data, const char *end, const char *path, char *err, size_t errlen)
{
    unsigned line = 1;
    for (const char *c = data; c < end; c++) {
        if (*c == '\0') {
            snprintf(err, errlen, "%s: line %u: byte 0x00 in the PLY header, which is text", path, line);
            return -1;
        }
        if (*c != '\n') continue;
        line++;
        const char *w = c + 1;
        while (w < end && (*w == ' ' || *w == '\t')) w++;
        if ((size_t)(end - w) >= 10 && memcmp(w, "end_header", 10) == 0) return 0;
    }
    return 0;
}

int mesh_check_ply(const char *data, size_t size, const char *path, char *err, size_t errlen)
{
    mesh_lines r = {data, data + size, 0, false, {0}};
    ply_header h = {.whole = true};
    if (header_nul(data, data + size, path, err, errlen)) return -1;
    for (const char *l; (l = mesh_next_line(&r));) {
        /* Header lines are text: assimp takes no other blank than a space or a tab, and hung or crashed on
         * "end_header" followed by a vertical tab. */
        for (const char *c = l; *c; c++)
            if (!isprint((unsigned char)*c) && *c != ' ' && *c != '\t' && *c != '\r') {
                snprintf(err, errlen, "%s: line %u: byte 0x%02x in the PLY header, which is text", path, r.line,
                         (unsigned char)*c);
                return -1;
            }
        l += strspn(l, MESH_BLANKS);
        if (!mesh_keyword(l, "end_header")) {
            if (header_line(&h, l, r.line, path, err, errlen)) return -1;
            continue;
        }
        double bytes = (double)(r.end - r.p);
        for (int i = 0; i < h.nel; i++) {
            double need = h.el[i].count * least_bytes(&h, &h.el[i]);
            if (need > bytes) {
                snprintf(err, errlen, "%s: line %u: declares %.0f elements, which need at least %.0f bytes; %.0f "
                         "follow the header (truncated or corrupt file?)", path, h.el[i].line, h.el[i].count, need, bytes);
                return -1;
            }
            bytes -= need;
        }
        if (!h.whole) return 0;
        return h.format == 0 ? walk_ascii(&h, &r, path, err, errlen)
                             : walk_binary(&h, data, r.p, r.end, path, err, errlen);
    }
    snprintf(err, errlen, "%s: the PLY header has no end_header line (truncated file?)", path);
    return -1;
}
