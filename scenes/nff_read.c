/* nff_read.c: the NFF reader (scene_load_nff).
 *
 * Format reference: NFF.TXT v3.9 by Eric Haines, as summarised (and checked
 * against the SPD 3.14 writer) in shared/SPD-SCENES.md. The reader works on
 * whitespace-separated TOKENS, not lines: NFF.TXT shows `c` on three lines
 * but the SPD writer puts its eight numbers on one, and both must load.
 * `#` starts a comment that runs to the end of the line, also in the middle
 * of a line.
 *
 * It is lenient about order (the SPD writes `b` before `v`; entities may
 * come in any order after that) and strict about values: every error is one
 * line "PATH:LINE: reason" naming the offending token's line, and garbage
 * never crashes or hangs it (counts are bounded and storage grows only with
 * what was actually read, so a huge declared count in a small file costs
 * nothing). Coordinates and radii are checked against the ranges every
 * scene lies in (scene.h) as they are read, so that message names the
 * line too. */
#include "nff.h"
#include "compressed.h"
#include "memory_cap.h"
#include "../prims/checked_alloc.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

/* A `p`/`pp` with more vertices than this is garbage, not a polygon. */
#define NFF_MAX_POLY_VERTS 10000000u
/* Image sizes beyond the largest any command makes (memory_cap.h; the
 * SPD uses 512) are refused where they are read, not when an image of
 * 10^12 pixels is about to be allocated. */
#define NFF_MAX_RESOLUTION IMAGE_SIDE_MAX

/* ---------------------------------------------------------------- lexer */

/* The tokenizer: tracks the line of every token, so errors can name it.
 * Tokens point into the file's bytes (not NUL-terminated: tok, len). */
typedef struct {
    const char *p, *end; /* unread text */
    int line;            /* line of *p */
    const char *tok;     /* current token; NULL at end of file */
    size_t len;
    int tok_line;        /* its line; at end of file, the last token's line */
} nff_lexer;

static void lex_init(nff_lexer *lx, const char *data, size_t size)
{
    lx->p = data;
    lx->end = data + size;
    lx->line = 1;
    lx->tok = NULL;
    lx->len = 0;
    lx->tok_line = 1;
}

/* Whitespace by the C locale; a NUL byte is not whitespace, so binary
 * garbage turns into tokens that fail to parse instead of vanishing. */
static bool lex_space(char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

static void lex_skip_blank(nff_lexer *lx)
{
    while (lx->p < lx->end) {
        char c = *lx->p;
        if (c == '\n') {
            lx->line++;
            lx->p++;
        } else if (lex_space(c)) {
            lx->p++;
        } else if (c == '#') {
            while (lx->p < lx->end && *lx->p != '\n') lx->p++;
        } else {
            return;
        }
    }
}

/* Advance to the next token; false at end of file (tok becomes NULL and
 * tok_line stays on the last token, the line an "unexpected end" names). */
static bool lex_next(nff_lexer *lx)
{
    lex_skip_blank(lx);
    if (lx->p >= lx->end) {
        lx->tok = NULL;
        lx->len = 0;
        return false;
    }
    lx->tok = lx->p;
    lx->tok_line = lx->line;
    while (lx->p < lx->end && !lex_space(*lx->p) && *lx->p != '#') lx->p++;
    lx->len = (size_t)(lx->p - lx->tok);
    return true;
}

static bool lex_is(const nff_lexer *lx, const char *word)
{
    return lx->tok && lx->len == strlen(word) && memcmp(lx->tok, word, lx->len) == 0;
}

/* The current token for a message: at most 32 bytes, unprintable bytes as
 * '?', so an error stays one readable line whatever the file holds. */
static const char *lex_show(const nff_lexer *lx, char *buf, size_t buflen)
{
    size_t n = lx->len < 32 ? lx->len : 32, k = 0;
    for (size_t i = 0; i < n && k + 1 < buflen; i++) {
        unsigned char c = (unsigned char)lx->tok[i];
        buf[k++] = isprint(c) ? (char)c : '?';
    }
    buf[k] = '\0';
    if (lx->len > n && k + 4 < buflen) strcat(buf, "...");
    return buf;
}

/* --------------------------------------------------------------- parser */

typedef struct {
    nff_lexer lx;
    const char *path;
    scene_t *s;
    char *err;
    size_t errlen;
    /* where we are, for messages: "in 'p 4' vertex 2" */
    const char *entity;      /* "c", "p", "v from", ... */
    uint32_t entity_n;       /* the count of a p/pp, else 0 */
    uint32_t entity_vertex;  /* 1-based vertex being read, else 0 */
    int view_line;           /* line of the `v`, 0 if none yet */
    bool have_material;
    uint16_t material;       /* the current `f` */
    uint32_t inside_cones;   /* cones given with negative radii */
    vec3 *pts;               /* the vertices of the polygon being read */
    vec3 *nrms;              /* their `pp` normals (same capacity) */
    uint32_t *idx;           /* and their indices in the store (same capacity) */
    uint32_t npts, pts_cap;
} nff_parser;

static bool fail(nff_parser *ps, int line, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Report "PATH:LINE: reason"; returns false so callers can `return fail(...)`. */
static bool fail(nff_parser *ps, int line, const char *fmt, ...)
{
    char why[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof why, fmt, ap);
    va_end(ap);
    snprintf(ps->err, ps->errlen, "%s:%d: %s", ps->path, line, why);
    return false;
}

/* " in 'p 4' vertex 2" for the entity being read. */
static const char *where(const nff_parser *ps, char *buf, size_t buflen)
{
    if (ps->entity_n && ps->entity_vertex)
        snprintf(buf, buflen, "in '%s %u' vertex %u", ps->entity, ps->entity_n, ps->entity_vertex);
    else if (ps->entity_n)
        snprintf(buf, buflen, "in '%s %u'", ps->entity, ps->entity_n);
    else
        snprintf(buf, buflen, "in '%s'", ps->entity);
    return buf;
}

static void enter(nff_parser *ps, const char *entity, uint32_t n)
{
    ps->entity = entity;
    ps->entity_n = n;
    ps->entity_vertex = 0;
}

/* Take the next token, which must exist (we are inside an entity). */
static bool need_token(nff_parser *ps)
{
    if (lex_next(&ps->lx)) return true;
    char w[96];
    return fail(ps, ps->lx.tok_line, "unexpected end of file %s", where(ps, w, sizeof w));
}

/* Whether the current token is a complete C number (any float syntax
 * strtof takes), and its value. The file's bytes end in a NUL (see
 * compressed.h), and a token ends at whitespace, '#' or that NUL, all of
 * which stop strtof, so it cannot read past the token. */
static bool token_number(const nff_lexer *lx, float *out)
{
    if (!lx->tok || lx->len == 0) return false;
    char *end;
    *out = strtof(lx->tok, &end);
    return end == lx->tok + lx->len;
}

/* Read one finite float. */
static bool read_float(nff_parser *ps, float *out)
{
    if (!need_token(ps)) return false;
    char w[96], t[40];
    if (!token_number(&ps->lx, out))
        return fail(ps, ps->lx.tok_line, "expected a number %s, got '%s'", where(ps, w, sizeof w),
                    lex_show(&ps->lx, t, sizeof t));
    if (isfinite(*out)) return true;
    /* Text that is finite as a double but not as a float is out of range;
     * "nan" and "inf" are simply not allowed. */
    double d = strtod(ps->lx.tok, NULL);
    if (isfinite(d))
        return fail(ps, ps->lx.tok_line, "number '%s' is out of float range %s", lex_show(&ps->lx, t, sizeof t),
                    where(ps, w, sizeof w));
    return fail(ps, ps->lx.tok_line, "'%s' is not a finite number %s", lex_show(&ps->lx, t, sizeof t),
                where(ps, w, sizeof w));
}

static bool read_vec3(nff_parser *ps, vec3 *out)
{
    return read_float(ps, &out->x) && read_float(ps, &out->y) && read_float(ps, &out->z);
}

/* Read one number of the geometry (view false) or of the view and lights
 * (view true) within the ranges every scene lies in (scene.h): checked
 * here, where the line is known, rather than only in scene_finish. */
static bool read_coord(nff_parser *ps, bool view, float *out)
{
    if (!read_float(ps, out)) return false;
    if (view ? scene_view_coord_ok(*out) : scene_coord_ok(*out)) return true;
    char w[96], t[40];
    return fail(ps, ps->lx.tok_line, "%s is outside the %s range %s: numbers must be %s", lex_show(&ps->lx, t, sizeof t),
                view ? "view" : "scene", where(ps, w, sizeof w), view ? SCENE_VIEW_RANGE : SCENE_COORD_RANGE);
}

static bool read_point(nff_parser *ps, bool view, vec3 *out)
{
    return read_coord(ps, view, &out->x) && read_coord(ps, view, &out->y) && read_coord(ps, view, &out->z);
}

/* Read a decimal integer in [lo, hi] (digits only: a count or a size). */
static bool read_uint(nff_parser *ps, const char *what, unsigned long lo, unsigned long hi, unsigned long *out)
{
    if (!need_token(ps)) return false;
    char w[96], t[40];
    const nff_lexer *lx = &ps->lx;
    unsigned long v = 0;
    bool ok = lx->len > 0;
    for (size_t i = 0; ok && i < lx->len; i++) {
        if (lx->tok[i] < '0' || lx->tok[i] > '9') ok = false;
        else if (v <= hi) v = v * 10 + (unsigned long)(lx->tok[i] - '0'); /* stops growing once too big */
    }
    if (!ok)
        return fail(ps, lx->tok_line, "expected %s (a whole number) %s, got '%s'", what, where(ps, w, sizeof w),
                    lex_show(lx, t, sizeof t));
    if (v > hi)
        return fail(ps, lx->tok_line, "%s '%s' is absurd (more than %lu) %s", what, lex_show(lx, t, sizeof t), hi,
                    where(ps, w, sizeof w));
    if (v < lo)
        return fail(ps, lx->tok_line, "%s '%s' is below %lu %s", what, lex_show(lx, t, sizeof t), lo,
                    where(ps, w, sizeof w));
    *out = v;
    return true;
}

/* ------------------------------------------------------------- entities */

/* `v`: from, at, up, angle, hither, resolution, in exactly that order.
 * entity is the sub-keyword with its `v` ("v from"), for messages. */
static bool expect_sub(nff_parser *ps, const char *entity, int vline)
{
    const char *sub = entity + 2;
    if (!lex_next(&ps->lx))
        return fail(ps, ps->lx.tok_line, "unexpected end of file in 'v' (line %d): expected '%s'", vline, sub);
    if (!lex_is(&ps->lx, sub)) {
        char t[40];
        return fail(ps, ps->lx.tok_line, "expected '%s' in 'v' (line %d), got '%s' (the sub-keywords are from, at, "
                    "up, angle, hither, resolution, in that order)", sub, vline, lex_show(&ps->lx, t, sizeof t));
    }
    ps->entity = entity;
    return true;
}

static bool parse_view(nff_parser *ps)
{
    int vline = ps->lx.tok_line;
    if (ps->view_line)
        return fail(ps, vline, "a second 'v' (the first is on line %d)", ps->view_line);
    ps->view_line = vline;
    camera_t *c = &ps->s->camera;
    unsigned long w, h;
    enter(ps, "v", 0);
    if (!expect_sub(ps, "v from", vline) || !read_point(ps, true, &c->from)) return false;
    if (!expect_sub(ps, "v at", vline) || !read_point(ps, true, &c->at)) return false;
    if (!expect_sub(ps, "v up", vline) || !read_point(ps, true, &c->up)) return false;
    if (!expect_sub(ps, "v angle", vline) || !read_float(ps, &c->fov_deg)) return false;
    if (!(c->fov_deg > 0.0f && c->fov_deg < 180.0f))
        return fail(ps, ps->lx.tok_line, "view angle %g is not in (0, 180) degrees", (double)c->fov_deg);
    if (!expect_sub(ps, "v hither", vline) || !read_coord(ps, true, &c->hither)) return false;
    if (c->hither < 0.0f) return fail(ps, ps->lx.tok_line, "negative hither %g", (double)c->hither);
    if (!expect_sub(ps, "v resolution", vline) || !read_uint(ps, "a width", 1, NFF_MAX_RESOLUTION, &w) ||
        !read_uint(ps, "a height", 1, NFF_MAX_RESOLUTION, &h))
        return false;
    c->width = (int)w;
    c->height = (int)h;
    /* A camera needs a direction and an up that is not along it. */
    vec3 dir = v3_sub(c->at, c->from);
    if (dir.x == 0.0f && dir.y == 0.0f && dir.z == 0.0f)
        return fail(ps, vline, "'v': from and at are the same point");
    vec3 side = v3_cross(dir, c->up);
    if (side.x == 0.0f && side.y == 0.0f && side.z == 0.0f)
        return fail(ps, vline, "'v': up is zero or along the view direction");
    return true;
}

static bool parse_background(nff_parser *ps)
{
    enter(ps, "b", 0);
    return read_vec3(ps, &ps->s->background);
}

/* `l X Y Z [R G B]`: the colour is there when the next token is a number.
 * scene_t keeps light positions only, so the colour is read and dropped. */
static bool parse_light(nff_parser *ps)
{
    vec3 pos, colour;
    enter(ps, "l", 0);
    if (!read_point(ps, true, &pos)) return false;
    nff_lexer ahead = ps->lx;
    float x;
    if (lex_next(&ahead) && token_number(&ahead, &x) && !read_vec3(ps, &colour)) return false;
    scene_add_light(ps->s, pos);
    return true;
}

/* Give the primitives read so far the current material. Those before the
 * first `f` get scene_finish's grey, made here because scene_finish only
 * fills in primitives nobody has given a material. */
static void settle_materials(nff_parser *ps)
{
    if (!ps->have_material) {
        if (ps->s->prims.count == 0) return;
        material_t grey = {v3(0.8f, 0.8f, 0.8f), 0.8f, 0.2f, 0.0f, 1.0f};
        ps->material = scene_add_material(ps->s, grey);
        ps->have_material = true;
    }
    scene_set_material_upto(ps->s, ps->material);
}

/* `f R G B Kd Ks Shine T ior`. A repeat of the current material (SPD
 * writers repeat `f` per object) reuses it rather than growing the table. */
static bool parse_material(nff_parser *ps)
{
    int line = ps->lx.tok_line;
    material_t m;
    float shine;
    enter(ps, "f", 0);
    if (!read_vec3(ps, &m.color) || !read_float(ps, &m.kd) || !read_float(ps, &m.ks) || !read_float(ps, &shine) ||
        !read_float(ps, &m.t) || !read_float(ps, &m.ior))
        return false;
    settle_materials(ps);
    if (ps->have_material && material_equal(ps->s->materials[ps->material], m)) return true;
    if (ps->s->nmaterials > UINT16_MAX) return fail(ps, line, "more than 65536 different materials");
    ps->material = scene_add_material(ps->s, m);
    ps->have_material = true;
    return true;
}

/* The store holds 2^32 - 1 primitives and vertices at most. */
static bool room_for(nff_parser *ps, int line, uint32_t nverts)
{
    const prims_t *p = &ps->s->prims;
    if (p->count == UINT32_MAX - 1 || nverts > UINT32_MAX - 1 - p->nverts)
        return fail(ps, line, "too many primitives or vertices for the primitive store");
    return true;
}

/* `c bx by bz br ax ay az ar`. Both radii negative means only the inside
 * is visible; the store's cones are two-sided, so keep |r| and count it. */
static bool parse_cone(nff_parser *ps)
{
    int line = ps->lx.tok_line;
    vec3 b, a;
    float rb, ra;
    enter(ps, "c", 0);
    if (!read_point(ps, false, &b) || !read_coord(ps, false, &rb) || !read_point(ps, false, &a) ||
        !read_coord(ps, false, &ra))
        return false;
    if (rb < 0.0f || ra < 0.0f) {
        if (rb > 0.0f || ra > 0.0f)
            return fail(ps, line, "cone radii %g and %g have mixed signs (both negative means inside visible)",
                        (double)rb, (double)ra);
        rb = fabsf(rb);
        ra = fabsf(ra);
        ps->inside_cones++;
    }
    if (rb == 0.0f && ra == 0.0f) return fail(ps, line, "cone with both radii zero");
    if (b.x == a.x && b.y == a.y && b.z == a.z) return fail(ps, line, "cone base and apex are the same point");
    cone_t cone = {b, rb, a, ra};
    const char *why = scene_cone_problem(cone);
    if (why) return fail(ps, line, "cone %s", why);
    if (!room_for(ps, line, 0)) return false;
    prims_add_cone(&ps->s->prims, b, rb, a, ra);
    return true;
}

/* `s cx cy cz r`. NFF.TXT allows a negative (inside visible) radius, but
 * no SPD scene uses one and a two-sided store has no use for it. */
static bool parse_sphere(nff_parser *ps)
{
    int line = ps->lx.tok_line;
    vec3 c;
    float r;
    enter(ps, "s", 0);
    if (!read_point(ps, false, &c) || !read_coord(ps, false, &r)) return false;
    if (!(r > 0.0f)) return fail(ps, line, "sphere radius %g is not positive", (double)r);
    if (!scene_ball_ok(c, r))
        return fail(ps, line, "sphere reaches outside the scene range: centre +- radius must be " SCENE_COORD_RANGE);
    if (!room_for(ps, line, 0)) return false;
    prims_add_sphere(&ps->s->prims, c, r);
    return true;
}

static void push_point(nff_parser *ps, vec3 v, vec3 normal)
{
    if (ps->npts == ps->pts_cap) {
        uint32_t cap = ps->pts_cap ? 2 * ps->pts_cap : 64;
        ps->pts = checked_realloc(ps->pts, (size_t)cap * sizeof *ps->pts, "an NFF polygon's vertices");
        ps->nrms = checked_realloc(ps->nrms, (size_t)cap * sizeof *ps->nrms, "an NFF patch's normals");
        ps->idx = checked_realloc(ps->idx, (size_t)cap * sizeof *ps->idx, "an NFF polygon's vertex indices");
        ps->pts_cap = cap;
    }
    ps->nrms[ps->npts] = normal;
    ps->pts[ps->npts++] = v;
}

static bool same_point(vec3 a, vec3 b)
{
    return a.x == b.x && a.y == b.y && a.z == b.z;
}

/* Drop a vertex equal to the one before it (and a last one equal to the
 * first), as the SPD polygon writer does before output. Exact equality,
 * not the SPD's 1e-6, because a reader should not move geometry. */
static void merge_duplicates(nff_parser *ps)
{
    uint32_t k = 0;
    for (uint32_t i = 0; i < ps->npts; i++)
        if (k == 0 || !same_point(ps->pts[i], ps->pts[k - 1])) ps->nrms[k] = ps->nrms[i], ps->pts[k++] = ps->pts[i];
    while (k > 1 && same_point(ps->pts[k - 1], ps->pts[0])) k--;
    ps->npts = k;
}

/* `p N` + N `x y z` lines, or `pp N` + N `x y z nx ny nz` lines (patch
 * normals go into scene_t.normals, for shading and secondary-ray
 * directions; a zero normal leaves its vertex without one, and so the
 * patch flat).
 * A declared triangle is kept even when degenerate, like every mesh
 * loader here (the store keeps zero-area triangles so ids stay stable, and
 * a written mesh must read back); larger polygons lose consecutive
 * duplicate vertices and must keep 3. */
static bool parse_polygon(nff_parser *ps, bool patch)
{
    int line = ps->lx.tok_line;
    const char *kw = patch ? "pp" : "p";
    unsigned long n;
    enter(ps, kw, 0);
    if (!read_uint(ps, "a vertex count", 0, NFF_MAX_POLY_VERTS, &n)) return false;
    if (n < 3) return fail(ps, line, "'%s %lu': a polygon needs at least 3 vertices", kw, n);
    enter(ps, kw, (uint32_t)n);
    ps->npts = 0;
    for (uint32_t i = 0; i < n; i++) {
        vec3 v, normal = {0, 0, 0};
        ps->entity_vertex = i + 1;
        if (!read_point(ps, false, &v) || (patch && !read_vec3(ps, &normal))) return false;
        push_point(ps, v, normal);
    }
    if (n > 3) merge_duplicates(ps);
    if (ps->npts < 3)
        return fail(ps, line, "'%s %lu' has only %u distinct consecutive vertices", kw, n, ps->npts);
    if (!room_for(ps, line, ps->npts)) return false;
    prims_t *p = &ps->s->prims;
    uint32_t first = p->nverts;
    for (uint32_t i = 0; i < ps->npts; i++) {
        uint32_t v = prims_add_vertex(p, ps->pts[i]);
        if (patch) scene_set_vertex_normal(ps->s, v, ps->nrms[i]);
    }
    if (ps->npts == 3) {
        prims_add_triangle(p, first, first + 1, first + 2);
    } else {
        for (uint32_t i = 0; i < ps->npts; i++) ps->idx[i] = first + i;
        prims_add_polygon(p, ps->idx, ps->npts);
    }
    return true;
}

/* One entity, starting at the current (keyword) token. */
static bool parse_entity(nff_parser *ps)
{
    nff_lexer *lx = &ps->lx;
    if (lex_is(lx, "v")) return parse_view(ps);
    if (lex_is(lx, "b")) return parse_background(ps);
    if (lex_is(lx, "l")) return parse_light(ps);
    if (lex_is(lx, "f")) return parse_material(ps);
    if (lex_is(lx, "c")) return parse_cone(ps);
    if (lex_is(lx, "s")) return parse_sphere(ps);
    if (lex_is(lx, "p")) return parse_polygon(ps, false);
    if (lex_is(lx, "pp")) return parse_polygon(ps, true);
    char t[40];
    float x;
    if (token_number(lx, &x))
        return fail(ps, lx->tok_line, "unexpected number '%s' where a keyword should be (too many numbers before it?)",
                    lex_show(lx, t, sizeof t));
    return fail(ps, lx->tok_line, "unknown keyword '%s'", lex_show(lx, t, sizeof t));
}

static bool parse_file(nff_parser *ps)
{
    while (lex_next(&ps->lx))
        if (!parse_entity(ps)) return false;
    settle_materials(ps);
    return true;
}

scene_t *scene_load_nff(const char *name, const char *path, char *err, size_t errlen)
{
    file_data_t f;
    if (compressed_read(path, &f, err, errlen) != 0) return NULL;
    scene_t *s = scene_parse_nff(name, path, f.data, f.size, err, errlen);
    compressed_free(&f);
    return s;
}

scene_t *scene_parse_nff(const char *name, const char *path, const char *data, size_t size, char *err, size_t errlen)
{
    nff_parser ps;
    memset(&ps, 0, sizeof ps);
    lex_init(&ps.lx, data, size);
    ps.path = path;
    ps.err = err;
    ps.errlen = errlen;
    ps.entity = "";
    ps.s = scene_new(name);
    bool ok = parse_file(&ps);
    free(ps.pts);
    free(ps.nrms);
    free(ps.idx);
    scene_t *s = ps.s;
    if (!ok) {
        scene_free(s);
        return NULL;
    }
    if (ps.inside_cones)
        snprintf(s->source, sizeof s->source, "%s (%u inside-visible cones, kept two-sided)", path, ps.inside_cones);
    else
        snprintf(s->source, sizeof s->source, "%s", path);
    if (scene_finish(s, ps.view_line != 0, err, errlen) != 0) {
        scene_free(s);
        return NULL;
    }
    return s;
}
