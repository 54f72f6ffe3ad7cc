/* load_mesh.c: any mesh file assimp reads (OBJ, PLY, OFF, STL, glTF, ...)
 * as a triangle scene.
 *
 * The file is read whole through compressed.c (so .gz and ARCHIVE#MEMBER
 * work) and handed to assimp from memory, with the inner file's extension
 * as the format hint. Post-processing is limited to what makes triangles
 * without changing the geometry: Triangulate, JoinIdenticalVertices (shared
 * vertices) and PreTransformVertices (node transforms applied, one flat
 * list of meshes). Nothing that drops degenerate triangles or reorders
 * faces: degenerate triangles are kept so primitive ids match the file.
 *
 * Two things about assimp (Debian's 5.2.5) shape the code:
 * - It is built with its internal assertions on, and a malformed file can
 *   trip one and abort the process: a truncated OFF leaves faces with no
 *   indices, which Triangulate asserts on. So the file is imported with no
 *   post-processing, checked here, and only then post-processed
 *   (aiApplyPostProcessing). An empty buffer asserts too, so it is caught
 *   first.
 * - Several readers do not fail on bad data but log an error and carry on
 *   with altered data (the OFF reader clamps an out-of-range vertex index
 *   to the last vertex and drops faces of more than 9 vertices; the OBJ
 *   reader drops empty faces). The log is captured during the import and
 *   any error-level message fails the load, so a scene is never silently
 *   different from its file. Capturing uses assimp's global logger, so
 *   loading is not thread-safe (scenes are loaded by one thread).
 *
 * Points and lines are skipped and counted in the scene's source string;
 * the default camera, lights and material come from scene_finish(). */
#include "scene.h"
#include "compressed.h"

#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <limits.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    char first_error[256]; /* the first error-level log message, "" if none */
} log_capture;

/* assimp formats messages as "Error, T0: text\n" (or "Warn, ..."). */
static void on_log(const char *message, char *user)
{
    log_capture *cap = (log_capture *)(void *)user;
    if (cap->first_error[0] || strncmp(message, "Error", 5) != 0) return;
    const char *text = strstr(message, ": ");
    text = text ? text + 2 : message;
    snprintf(cap->first_error, sizeof cap->first_error, "%s", text);
    size_t n = strlen(cap->first_error);
    while (n && (cap->first_error[n - 1] == '\n' || cap->first_error[n - 1] == '\r')) cap->first_error[--n] = '\0';
}

/* The raw import's structure must be sound before post-processing runs on
 * it (see the header comment), and coordinates must be finite; checking
 * them here, before vertices are joined, names the vertex as assimp read it
 * (for OFF, the file's own vertex number). */
static int check_raw(const struct aiScene *as, const char *path, char *err, size_t errlen)
{
    for (unsigned m = 0; m < as->mNumMeshes; m++) {
        const struct aiMesh *mesh = as->mMeshes[m];
        if (mesh->mNumVertices && !mesh->mVertices) {
            snprintf(err, errlen, "%s: mesh %u has no vertex positions", path, m);
            return -1;
        }
        for (unsigned f = 0; f < mesh->mNumFaces; f++) {
            const struct aiFace *face = &mesh->mFaces[f];
            if (face->mNumIndices == 0 || !face->mIndices) {
                snprintf(err, errlen, "%s: face %u of mesh %u has no vertices (truncated or malformed file)", path, f, m);
                return -1;
            }
            for (unsigned k = 0; k < face->mNumIndices; k++)
                if (face->mIndices[k] >= mesh->mNumVertices) {
                    snprintf(err, errlen, "%s: face %u of mesh %u uses vertex %u of %u", path, f, m,
                             face->mIndices[k], mesh->mNumVertices);
                    return -1;
                }
        }
        for (unsigned v = 0; v < mesh->mNumVertices; v++) {
            struct aiVector3D p = mesh->mVertices[v];
            if (!isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z)) {
                snprintf(err, errlen, "%s: vertex %u of mesh %u has a NaN or infinite coordinate (%g %g %g)", path, v, m,
                         p.x, p.y, p.z);
                return -1;
            }
        }
    }
    return 0;
}

/* --- OFF pre-check ---
 * assimp's OFF reader reads missing numbers as 0, so a file cut inside a
 * line loads as different geometry without a word. Plain "OFF" files (the
 * CGAL meshes) are therefore checked here first, line by line as assimp
 * reads them: the counts, NV lines of at least 3 numbers, NF lines of
 * "K i1 .. iK" with every index in range. Extra numbers (colours) are
 * allowed. Variants (COFF, NOFF, STOFF, 4OFF, nOFF, headerless) go to assimp
 * unchecked. */

typedef struct {
    const char *p, *end;
    unsigned line;   /* number of the line last returned, 1-based */
    char buf[4096];  /* assimp's line limit too */
} line_reader;

/* The next line that is not blank once its '#' comment is removed; NULL at
 * the end of the data. */
static const char *next_line(line_reader *r)
{
    while (r->p < r->end) {
        const char *eol = memchr(r->p, '\n', (size_t)(r->end - r->p));
        if (!eol) eol = r->end;
        size_t n = (size_t)(eol - r->p);
        if (n >= sizeof r->buf) n = sizeof r->buf - 1;
        memcpy(r->buf, r->p, n);
        r->buf[n] = '\0';
        r->p = eol < r->end ? eol + 1 : r->end;
        r->line++;
        char *hash = strchr(r->buf, '#');
        if (hash) *hash = '\0';
        if (r->buf[strspn(r->buf, " \t\r\f\v")]) return r->buf;
    }
    return NULL;
}

/* Parse up to max whole numbers (integers when ints) from s; returns how
 * many parsed before something that is not a number. */
static int parse_numbers(const char *s, double *v, int max, bool ints)
{
    int n = 0;
    while (n < max) {
        char *e;
        double x = ints ? (double)strtol(s, &e, 10) : strtod(s, &e);
        if (e == s || (*e && !strchr(" \t\r\f\v", *e))) break;
        v[n++] = x;
        s = e;
    }
    return n;
}

static int off_check(const char *data, size_t size, const char *path, char *err, size_t errlen)
{
    line_reader r = {data, data + size, 0, {0}};
    const char *l = next_line(&r);
    if (!l) return 0; /* assimp will say what is wrong */
    l += strspn(l, " \t\r\f\v");
    if (strncmp(l, "OFF", 3) != 0 || (l[3] && !strchr(" \t\r\f\v", l[3]))) return 0;
    double cnt[3];
    int n = parse_numbers(l + 3, cnt, 3, true);
    if (n == 0) {
        if (!(l = next_line(&r))) {
            snprintf(err, errlen, "%s: ends after the OFF header, with no counts", path);
            return -1;
        }
        n = parse_numbers(l, cnt, 3, true);
    }
    if (n < 2 || cnt[0] < 0 || cnt[1] < 0 || cnt[0] > UINT32_MAX || cnt[1] > UINT32_MAX) {
        snprintf(err, errlen, "%s: line %u: expected the vertex and face counts", path, r.line);
        return -1;
    }
    uint32_t nv = (uint32_t)cnt[0], nf = (uint32_t)cnt[1];
    for (uint32_t v = 0; v < nv; v++) {
        double xyz[3];
        if (!(l = next_line(&r))) {
            snprintf(err, errlen, "%s: ends after %u of %u vertices (truncated file?)", path, v, nv);
            return -1;
        }
        if (parse_numbers(l, xyz, 3, false) < 3) {
            snprintf(err, errlen, "%s: line %u: vertex %u needs 3 coordinates", path, r.line, v);
            return -1;
        }
    }
    for (uint32_t f = 0; f < nf; f++) {
        double idx[11];
        if (!(l = next_line(&r))) {
            snprintf(err, errlen, "%s: ends after %u of %u faces (truncated file?)", path, f, nf);
            return -1;
        }
        int got = parse_numbers(l, idx, 11, true);
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

/* Import with assimp: NULL with the reason in err on failure. */
static const struct aiScene *import(const file_data_t *f, const char *path, char *err, size_t errlen)
{
    if (f->size == 0) {
        snprintf(err, errlen, "%s: empty file", path);
        return NULL;
    }
    if (f->size > UINT_MAX) {
        snprintf(err, errlen, "%s: %zu bytes is too large for assimp's memory reader", path, f->size);
        return NULL;
    }
    char ext[16];
    compressed_extension(f->name, ext, sizeof ext);
    if (strcmp(ext, "off") == 0 && off_check(f->data, f->size, path, err, errlen) != 0) return NULL;

    /* The properties stay with the import and apply to the post-processing
     * below: drop every vertex attribute but the position, so vertices are
     * joined by position alone (STL repeats each vertex with its facet's
     * normal; OBJ splits vertices at UV seams). Only geometric normals are
     * used here. */
    struct aiPropertyStore *props = aiCreatePropertyStore();
    aiSetImportPropertyInteger(props, AI_CONFIG_PP_RVC_FLAGS,
                               aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS | aiComponent_COLORS |
                                   aiComponent_TEXCOORDS | aiComponent_BONEWEIGHTS);
    log_capture cap = {{0}};
    struct aiLogStream stream = {on_log, (char *)(void *)&cap};
    aiAttachLogStream(&stream);
    const struct aiScene *as = aiImportFileFromMemoryWithProperties(f->data, (unsigned)f->size, 0, ext, props);
    aiDetachLogStream(&stream);
    aiReleasePropertyStore(props);

    if (!as) {
        snprintf(err, errlen, "%s: assimp: %s", path, aiGetErrorString());
        return NULL;
    }
    if (cap.first_error[0]) {
        snprintf(err, errlen, "%s: assimp: %s", path, cap.first_error);
        aiReleaseImport(as);
        return NULL;
    }
    if (check_raw(as, path, err, errlen) != 0) {
        aiReleaseImport(as);
        return NULL;
    }
    /* On failure this releases the scene itself. */
    as = aiApplyPostProcessing(as, aiProcess_RemoveComponent | aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                       aiProcess_PreTransformVertices);
    if (!as) snprintf(err, errlen, "%s: assimp: %s", path, aiGetErrorString());
    return as;
}

scene_t *scene_load_mesh(const char *name, const char *path, char *err, size_t errlen)
{
    file_data_t f;
    if (compressed_read(path, &f, err, errlen) != 0) return NULL;
    const struct aiScene *as = import(&f, path, err, errlen);
    compressed_free(&f);
    if (!as) return NULL;

    scene_t *s = scene_new(name);
    prims_t *p = &s->prims;
    uint64_t skipped = 0;
    for (unsigned m = 0; m < as->mNumMeshes; m++) {
        const struct aiMesh *mesh = as->mMeshes[m];
        uint32_t base = p->nverts;
        if ((uint64_t)base + mesh->mNumVertices > UINT32_MAX) {
            snprintf(err, errlen, "%s: more than 2^32 vertices", path);
            aiReleaseImport(as);
            scene_free(s);
            return NULL;
        }
        for (unsigned v = 0; v < mesh->mNumVertices; v++) {
            struct aiVector3D q = mesh->mVertices[v];
            prims_add_vertex(p, v3(q.x, q.y, q.z));
        }
        for (unsigned k = 0; k < mesh->mNumFaces; k++) {
            const struct aiFace *face = &mesh->mFaces[k];
            if (face->mNumIndices < 3) {
                skipped++;
                continue;
            }
            /* Triangulate leaves only triangles; a fan covers anything else. */
            for (unsigned j = 2; j < face->mNumIndices; j++)
                prims_add_triangle(p, base + face->mIndices[0], base + face->mIndices[j - 1], base + face->mIndices[j]);
        }
    }
    aiReleaseImport(as);

    if (skipped)
        snprintf(s->source, sizeof s->source, "%s (%llu point/line faces skipped)", path, (unsigned long long)skipped);
    else
        snprintf(s->source, sizeof s->source, "%s", path);
    if (scene_finish(s, false, err, errlen) != 0) {
        scene_free(s);
        return NULL;
    }
    return s;
}
