/* load_mesh.c: any mesh file assimp reads (OBJ, PLY, OFF, STL, glTF, ...)
 * as a triangle scene.
 *
 * The file is read whole through compressed.c (so .gz and ARCHIVE#MEMBER
 * work) and handed to assimp from memory under its inner name, whose
 * extension tells assimp the format; files it references (.bin, .mtl) are
 * read from beside it (see mem_fs below). Post-processing is limited to
 * what makes triangles without changing the geometry: RemoveComponent (all
 * vertex attributes but positions, so that) JoinIdenticalVertices shares
 * vertices by exact position, Triangulate, and PreTransformVertices (node
 * transforms applied, one flat list of meshes). Nothing that drops
 * degenerate triangles or reorders faces: degenerate triangles are kept so
 * primitive ids follow the file.
 *
 * Two things about assimp (Debian's 5.2.5) shape the code:
 * - It is built with its internal assertions on, and a malformed file can
 *   trip one and abort the process: a truncated OFF leaves faces with no
 *   indices, which Triangulate asserts on, and PreTransformVertices
 *   crashes on a mesh with no faces (a PLY point cloud). So the file is
 *   imported with no post-processing, checked (check_raw()), and only then
 *   post-processed (aiApplyPostProcessing). An empty file asserts too:
 *   caught first.
 * - Several readers do not fail on bad data but log an error and carry on
 *   with altered data: the OFF reader clamps an out-of-range vertex index
 *   to the last vertex, drops faces of more than 9 vertices and reads
 *   missing numbers as 0; the OBJ reader drops empty faces. The log is
 *   captured during the import and an error-level message fails the load
 *   (except the harmless ones, see on_log()), so a scene is never silently
 *   different from its file. OBJ, OFF, PLY and STL files are also checked
 *   beforehand (mesh_check.c), which catches what assimp lets through or
 *   chokes on (a file cut mid-line or mid-face, counts no file could
 *   hold, coordinates outside the scene range) and names the line.
 *   The capture uses assimp's global logger, so loading is not
 *   thread-safe (scenes are loaded by one thread).
 *
 * - Even so, fuzzing keeps finding files that make assimp itself read out
 *   of bounds or abort (CI's fuzz run found one in its own code), and a
 *   bad file must never end the program. So assimp runs in a forked child
 *   (isolate.h): the child imports, post-processes and writes the flat
 *   vertex and triangle lists to a pipe; the parent checks what arrives
 *   and builds the scene. A child that crashes, aborts or runs past the
 *   memory cap is one error line naming the file (exit 2). It costs a
 *   fork per file (about 5 ms beside the 110 ms of reading the bunny).
 *   The fuzzers read the same way without the child
 *   (scene_mesh_from_memory_in_process): the wire goes through a memory
 *   file instead of a pipe, and assimp's crashes reach the fuzzer.
 *
 * Points and lines (OBJ "l" and "p" elements) are skipped and counted in the scene's source string;
 * the default camera, lights and material come from scene_finish(). */
#include "scene.h"
#include "compressed.h"
#include "isolate.h"
#include "memory_cap.h"
#include "mesh_check.h"

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assert.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

typedef struct {
    char first_error[256]; /* the first error-level log message, "" if none */
    int fd;                /* the child's pipe to the parent */
    const char *path;      /* the file, for messages */
} log_capture;

static int send_error(int fd, const char *msg);

/* Whether an assimp message is the std::bad_alloc it caught: its text ends
 * with the exception's what() (a file name in a message does not). */
static bool says_bad_alloc(const char *message)
{
    size_t n = strlen(message), m = strlen("std::bad_alloc");
    while (n && (message[n - 1] == '\n' || message[n - 1] == '\r' || message[n - 1] == ' ')) n--;
    return n >= m && strncmp(message + n - m, "std::bad_alloc", m) == 0;
}

/* The child's report that assimp ran out of memory: it runs under an
 * address-space limit of the memory cap (isolate.h), so it is the cap that
 * stopped it, whatever the file. */
static void send_out_of_memory(int fd, const char *path)
{
    char msg[1024];
    memory_cap_stopped(msg, sizeof msg, "%s: assimp's reader ran out of memory", path);
    (void)send_error(fd, msg);
}

/* assimp formats messages as "Error, T0: text\n" (or "Warn, ..."). Some
 * errors are harmless here and do not count: those about materials and
 * textures (an OBJ's missing .mtl file; materials are not read), and the
 * OBJ reader's complaint about a "usemtl" before any object, after which it
 * reads the geometry all the same. */
static void on_log(const char *message, char *user)
{
    log_capture *cap = (log_capture *)(void *)user;
    /* assimp logs the std::bad_alloc it caught, then may crash releasing
     * what it had (aiApplyPostProcessing's failure path releases the scene
     * twice): the report cannot wait for the import to return. */
    if (strncmp(message, "Error", 5) == 0 && says_bad_alloc(message)) {
        send_out_of_memory(cap->fd, cap->path);
        _exit(0);
    }
    if (cap->first_error[0] || strncmp(message, "Error", 5) != 0) return;
    if (strcasestr(message, "material") || strcasestr(message, "texture") ||
        strstr(message, "No object detected to attach a new mesh instance"))
        return;
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
    if (as->mNumMeshes && !as->mRootNode) {
        snprintf(err, errlen, "%s: assimp gave meshes but no scene graph", path);
        return -1;
    }
    for (unsigned m = 0; m < as->mNumMeshes; m++) {
        const struct aiMesh *mesh = as->mMeshes[m];
        if (mesh->mNumVertices && !mesh->mVertices) {
            snprintf(err, errlen, "%s: mesh %u has no vertex positions", path, m);
            return -1;
        }
        /* PreTransformVertices crashes on a mesh without faces. */
        if (mesh->mNumFaces == 0 || !mesh->mFaces) {
            snprintf(err, errlen, "%s: mesh %u has %u vertices but no faces (a point cloud?)", path, m, mesh->mNumVertices);
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
            if (!scene_coord_ok(p.x) || !scene_coord_ok(p.y) || !scene_coord_ok(p.z)) {
                snprintf(err, errlen, "%s: vertex %u of mesh %u (%g %g %g) is outside the scene range: coordinates must "
                         "be " SCENE_COORD_RANGE, path, v, m, p.x, p.y, p.z);
                return -1;
            }
        }
    }
    return 0;
}

/* --- assimp's file system: everything from memory ---
 * assimp reads the main file, and any file it references (a glTF's .bin
 * buffers, an OBJ's .mtl), through these callbacks. The main file is the
 * buffer already read; a referenced file is looked up beside it in the same
 * container, through compressed_read(): "dir/" for dir/x.gltf(.gz),
 * "ARCHIVE#sub/" for ARCHIVE#sub/x.gltf. (aiImportFileFromMemory would give
 * the main file from memory too, but looks for referenced files in the
 * current directory.) */

typedef struct {
    const file_data_t *main;
    const char *main_name; /* the name assimp is given for the main file */
    char prefix[4096];     /* what a referenced file's name is appended to */
} mem_fs;

typedef struct {
    const char *data;
    size_t size, pos;
    file_data_t owned; /* a referenced file's data, freed on close */
} mem_file;

static size_t mf_read(struct aiFile *f, char *buf, size_t size, size_t count)
{
    mem_file *m = (mem_file *)(void *)f->UserData;
    if (size == 0) return 0;
    size_t n = (m->size - m->pos) / size;
    if (n > count) n = count;
    memcpy(buf, m->data + m->pos, n * size);
    m->pos += n * size;
    return n;
}

static size_t mf_write(struct aiFile *f, const char *buf, size_t size, size_t count)
{
    (void)f, (void)buf, (void)size, (void)count;
    return 0;
}

static size_t mf_tell(struct aiFile *f) { return ((mem_file *)(void *)f->UserData)->pos; }
static size_t mf_size(struct aiFile *f) { return ((mem_file *)(void *)f->UserData)->size; }
static void mf_flush(struct aiFile *f) { (void)f; }

static enum aiReturn mf_seek(struct aiFile *f, size_t offset, enum aiOrigin origin)
{
    mem_file *m = (mem_file *)(void *)f->UserData;
    if (origin == aiOrigin_SET) {
        if (offset > m->size) return aiReturn_FAILURE;
        m->pos = offset;
        return aiReturn_SUCCESS;
    }
    /* relative seeks may go back: the offset is a negative number cast to size_t, as with fseek */
    size_t base = origin == aiOrigin_CUR ? m->pos : m->size;
    ptrdiff_t delta = (ptrdiff_t)offset;
    if ((delta < 0 && (size_t)-delta > base) || (delta > 0 && (size_t)delta > m->size - base)) return aiReturn_FAILURE;
    m->pos = (size_t)((ptrdiff_t)base + delta);
    return aiReturn_SUCCESS;
}

static struct aiFile *fs_open(struct aiFileIO *io, const char *name, const char *mode)
{
    const mem_fs *fs = (const mem_fs *)(void *)io->UserData;
    if (strpbrk(mode, "wa+")) return NULL;
    struct aiFile *f = calloc(1, sizeof *f);
    mem_file *m = calloc(1, sizeof *m);
    if (!f || !m) {
        free(f);
        free(m);
        return NULL;
    }
    if (strcmp(name, fs->main_name) == 0) {
        m->data = fs->main->data;
        m->size = fs->main->size;
    } else {
        char path[8192], why[64];
        if (name[0] == '/')
            snprintf(path, sizeof path, "%s", name);
        else
            snprintf(path, sizeof path, "%s%s", fs->prefix, name[0] == '.' && name[1] == '/' ? name + 2 : name);
        /* The name comes from the file's own text: only a regular file may
         * be read (a "mtllib /dev/zero" would be read forever). */
        char disk[8192];
        struct stat st;
        compressed_disk_file(path, disk, sizeof disk);
        if (stat(disk, &st) != 0 || !S_ISREG(st.st_mode) || compressed_read(path, &m->owned, why, sizeof why) != 0) {
            free(f);
            free(m);
            return NULL; /* assimp reports the file it could not open */
        }
        m->data = m->owned.data;
        m->size = m->owned.size;
    }
    f->ReadProc = mf_read;
    f->WriteProc = mf_write;
    f->TellProc = mf_tell;
    f->FileSizeProc = mf_size;
    f->SeekProc = mf_seek;
    f->FlushProc = mf_flush;
    f->UserData = (aiUserData)(void *)m;
    return f;
}

static void fs_close(struct aiFileIO *io, struct aiFile *f)
{
    (void)io;
    if (!f) return;
    mem_file *m = (mem_file *)(void *)f->UserData;
    compressed_free(&m->owned);
    free(m);
    free(f);
}

/* The container prefix of path (see above): up to its last '/', or to the
 * '#' that starts an archive member with no directory. */
static void container_prefix(const char *path, char *prefix, size_t len)
{
    char disk[4096];
    compressed_disk_file(path, disk, sizeof disk);
    size_t n = 0, dl = strlen(disk);
    if (strlen(path) > dl && path[dl] == '#') n = dl + 1; /* an archive member */
    const char *slash = strrchr(path + n, '/');
    if (slash) n = (size_t)(slash - path) + 1;
    if (n >= len) n = len - 1;
    memcpy(prefix, path, n);
    prefix[n] = '\0';
}

/* What is checked before assimp sees the file: 0, or -1 with the reason. */
static int precheck(const file_data_t *f, const char *path, char *err, size_t errlen)
{
    if (f->size == 0) {
        snprintf(err, errlen, "%s: empty file", path);
        return -1;
    }
    char ext[16];
    compressed_extension(f->name, ext, sizeof ext);
    return mesh_precheck(ext, f->data, f->size, path, err, errlen);
}

/* Import with assimp: NULL with the reason in err on failure. Runs in the
 * child (import_child), fd its pipe. */
static const struct aiScene *import(const file_data_t *f, const char *path, int fd, char *err, size_t errlen)
{
    mem_fs fs = {f, f->name[0] ? f->name : "mesh", {0}};
    container_prefix(path, fs.prefix, sizeof fs.prefix);
    struct aiFileIO io = {fs_open, fs_close, (aiUserData)(void *)&fs};
    /* The properties stay with the import and apply to the post-processing
     * below: drop every vertex attribute but the position, so vertices are
     * joined by position alone (STL repeats each vertex with its facet's
     * normal; OBJ splits vertices at UV seams). Only geometric normals are
     * used here. */
    struct aiPropertyStore *props = aiCreatePropertyStore();
    aiSetImportPropertyInteger(props, AI_CONFIG_PP_RVC_FLAGS,
                               aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS | aiComponent_COLORS |
                                   aiComponent_TEXCOORDS | aiComponent_BONEWEIGHTS);
    log_capture cap = {{0}, fd, path};
    struct aiLogStream stream = {on_log, (char *)(void *)&cap};
    aiAttachLogStream(&stream); /* through the post-processing too: on_log reports running out of memory */
    const struct aiScene *as = aiImportFileExWithProperties(fs.main_name, 0, &io, props);
    aiReleasePropertyStore(props);

    if (!as && says_bad_alloc(aiGetErrorString())) {
        send_out_of_memory(fd, path);
        _exit(0);
    }
    if (!as) snprintf(err, errlen, "%s: assimp: %s", path, aiGetErrorString());
    else if (cap.first_error[0]) snprintf(err, errlen, "%s: assimp: %s", path, cap.first_error);
    if (as && (cap.first_error[0] || check_raw(as, path, err, errlen) != 0)) {
        aiReleaseImport(as);
        as = NULL;
    }
    /* On failure this releases the scene itself. */
    if (as)
        as = aiApplyPostProcessing(as, aiProcess_RemoveComponent | aiProcess_Triangulate |
                                           aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices);
    if (!as && !err[0]) snprintf(err, errlen, "%s: assimp: %s", path, aiGetErrorString());
    aiDetachLogStream(&stream);
    return as;
}

scene_t *scene_load_mesh(const char *name, const char *path, char *err, size_t errlen)
{
    file_data_t f;
    if (compressed_read(path, &f, err, errlen) != 0) return NULL;
    scene_t *s = scene_mesh_from_memory(name, path, f.name, f.data, f.size, err, errlen);
    compressed_free(&f);
    return s;
}

/* --- assimp in a child process (isolate.h says why) ---
 * The child imports, flattens every mesh into one vertex and one triangle
 * list, and writes them to the pipe: a header, then the vertices as 3
 * floats each, then the triangles as 3 uint32 indices each. The parent
 * trusts nothing it did not check: the byte count must match the header's
 * counts and every index must name a vertex. */

#define WIRE_MAGIC 0x4d455348u /* "MESH" */

typedef struct {
    uint32_t magic;
    uint32_t ok;        /* 1: counts and data follow; 0: msg_len bytes of error follow */
    uint32_t msg_len;
    uint32_t pad;
    uint64_t nverts, ntris;
    uint64_t skipped;   /* point and line faces left out */
} wire_header;

typedef struct {
    const file_data_t *f;
    const char *path;
} import_job;

static int send_error(int fd, const char *msg)
{
    wire_header h = {WIRE_MAGIC, 0, (uint32_t)strlen(msg), 0, 0, 0, 0};
    return isolate_write(fd, &h, sizeof h) || isolate_write(fd, msg, h.msg_len) ? 1 : 0;
}

/* Writes the triangles of one mesh, a fan over any face of more than 3
 * vertices (Triangulate leaves only triangles), offset by base. */
static int send_triangles(int fd, const struct aiMesh *mesh, uint32_t base)
{
    uint32_t buf[3 * 1024];
    size_t n = 0;
    for (unsigned k = 0; k < mesh->mNumFaces; k++) {
        const struct aiFace *face = &mesh->mFaces[k];
        for (unsigned j = 2; j < face->mNumIndices; j++) {
            buf[n++] = base + face->mIndices[0];
            buf[n++] = base + face->mIndices[j - 1];
            buf[n++] = base + face->mIndices[j];
            if (n == sizeof buf / sizeof buf[0]) {
                if (isolate_write(fd, buf, n * sizeof buf[0])) return -1;
                n = 0;
            }
        }
    }
    return n ? isolate_write(fd, buf, n * sizeof buf[0]) : 0;
}

/* The header h, then the vertices and triangles of every mesh of as. */
static int send_mesh(int fd, const struct aiScene *as, const wire_header *h)
{
    if (isolate_write(fd, h, sizeof *h)) return 1;
    static_assert(sizeof(struct aiVector3D) == 3 * sizeof(float), "assimp built with float coordinates");
    for (unsigned m = 0; m < as->mNumMeshes; m++)
        if (isolate_write(fd, as->mMeshes[m]->mVertices, as->mMeshes[m]->mNumVertices * sizeof(struct aiVector3D)))
            return 1;
    uint32_t base = 0;
    for (unsigned m = 0; m < as->mNumMeshes; m++) {
        if (send_triangles(fd, as->mMeshes[m], base)) return 1;
        base += as->mMeshes[m]->mNumVertices;
    }
    return 0;
}

static int import_child(int fd, void *arg)
{
    const import_job *job = arg;
    char err[1024] = "";
    const struct aiScene *as = import(job->f, job->path, fd, err, sizeof err);
    if (!as) return send_error(fd, err);
    wire_header h = {WIRE_MAGIC, 1, 0, 0, 0, 0, 0};
    for (unsigned m = 0; m < as->mNumMeshes; m++) {
        const struct aiMesh *mesh = as->mMeshes[m];
        h.nverts += mesh->mNumVertices;
        for (unsigned k = 0; k < mesh->mNumFaces; k++) {
            unsigned n = mesh->mFaces[k].mNumIndices;
            if (n < 3) h.skipped++;
            else h.ntris += n - 2;
        }
    }
    if (h.nverts > UINT32_MAX || h.ntris > UINT32_MAX) {
        snprintf(err, sizeof err, "%s: more than 2^32 %s", job->path, h.nverts > UINT32_MAX ? "vertices" : "triangles");
        aiReleaseImport(as);
        return send_error(fd, err);
    }
    int rc = send_mesh(fd, as, &h);
    aiReleaseImport(as); /* in a child the process ends next; in process (the fuzzers) it must not leak */
    return rc;
}

/* The scene from the child's output: NULL with the reason on anything
 * that does not add up. */
static scene_t *scene_from_wire(const char *name, const char *path, const char *buf, size_t len, char *err,
                                size_t errlen)
{
    wire_header h;
    if (len < sizeof h) {
        snprintf(err, errlen, "%s: assimp's reader gave %zu bytes, no header", path, len);
        return NULL;
    }
    memcpy(&h, buf, sizeof h);
    const char *body = buf + sizeof h;
    size_t body_len = len - sizeof h;
    if (h.magic != WIRE_MAGIC) {
        snprintf(err, errlen, "%s: assimp's reader gave a malformed header", path);
        return NULL;
    }
    if (!h.ok) {
        snprintf(err, errlen, "%.*s", (int)(h.msg_len < body_len ? h.msg_len : body_len), body);
        return NULL;
    }
    if (h.nverts > UINT32_MAX || h.ntris > UINT32_MAX || body_len != h.nverts * 12 + h.ntris * 12) {
        snprintf(err, errlen, "%s: assimp's reader gave %zu bytes for %llu vertices and %llu triangles", path, body_len,
                 (unsigned long long)h.nverts, (unsigned long long)h.ntris);
        return NULL;
    }
    scene_t *s = scene_new(name);
    prims_t *p = &s->prims;
    for (uint64_t v = 0; v < h.nverts; v++) {
        float q[3];
        memcpy(q, body + v * 12, sizeof q);
        prims_add_vertex(p, v3(q[0], q[1], q[2]));
    }
    const char *tris = body + h.nverts * 12;
    for (uint64_t t = 0; t < h.ntris; t++) {
        uint32_t i[3];
        memcpy(i, tris + t * 12, sizeof i);
        if (i[0] >= h.nverts || i[1] >= h.nverts || i[2] >= h.nverts) {
            snprintf(err, errlen, "%s: triangle %llu uses a vertex past the %llu read", path, (unsigned long long)t,
                     (unsigned long long)h.nverts);
            scene_free(s);
            return NULL;
        }
        prims_add_triangle(p, i[0], i[1], i[2]);
    }
    if (h.skipped)
        snprintf(s->source, sizeof s->source, "%s (%llu point/line faces skipped)", path, (unsigned long long)h.skipped);
    else
        snprintf(s->source, sizeof s->source, "%s", path);
    return s;
}

/* The loader, with assimp in a child (isolated) or in this process. */
static scene_t *mesh_from_memory(const char *name, const char *path, const char *file_name, const char *data,
                                 size_t size, bool isolated, char *err, size_t errlen)
{
    file_data_t f = {(char *)data, size, {0}};
    snprintf(f.name, sizeof f.name, "%s", file_name);
    if (precheck(&f, path, err, errlen) != 0) return NULL;

    import_job job = {&f, path};
    char *out, why[256];
    size_t out_len;
    int rc = isolated ? isolate_run(import_child, &job, memory_cap_bytes(), &out, &out_len, why, sizeof why)
                      : isolate_run_in_process(import_child, &job, memory_cap_bytes(), &out, &out_len, why, sizeof why);
    if (rc != 0 && strncmp(why, "wrote more than", 15) == 0) { /* its output is held here: the cap bounds it */
        memory_cap_stopped(err, errlen, "%s: the mesh assimp read is larger than the memory cap allows", path);
        return NULL;
    }
    if (rc != 0) {
        snprintf(err, errlen, "%s: assimp's reader %s on this file (a malformed file, or a form of it assimp cannot read)",
                 path, why);
        return NULL;
    }
    scene_t *s = scene_from_wire(name, path, out, out_len, err, errlen);
    free(out);
    if (s && scene_finish(s, false, err, errlen) != 0) {
        scene_free(s);
        return NULL;
    }
    return s;
}

scene_t *scene_mesh_from_memory(const char *name, const char *path, const char *file_name, const char *data,
                                size_t size, char *err, size_t errlen)
{
    return mesh_from_memory(name, path, file_name, data, size, true, err, errlen);
}

scene_t *scene_mesh_from_memory_in_process(const char *name, const char *path, const char *file_name,
                                           const char *data, size_t size, char *err, size_t errlen)
{
    return mesh_from_memory(name, path, file_name, data, size, false, err, errlen);
}
