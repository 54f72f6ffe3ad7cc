/* fuzz_scenes: the --scenes names (scenes/scene_load.c scene_check, its
 * views through scenes/view.c, the sets of scene_set_expand) on any text
 * up to its first NUL or newline, and every accelerator's build over any
 * scene. A name scene_check accepts that names a generated scene of at
 * most MAX_PRIMS primitives is also loaded, with its views, and built and
 * traced by one accelerator, the one its name picks (exercise.c
 * fuzz_exercise_one: a new scene costs one build, and the mutations of a
 * name reach the others). Names of files are only
 * checked, never read (the harness stays hermetic and fast), except that
 * when the name ends in .obj, .ply, .off or .stl (before an optional
 * "@VIEW", one view spec) and a newline follows, the rest of the input is
 * that file: it is read (in this process, as fuzz_mesh reads) and what
 * loads, up to MAX_PRIMS triangles, is built and traced too, by the
 * accelerator its geometry picks. So the shapes a file can hold and no generator makes
 * (triangles repeated many times, an object far from the origin, slivers,
 * coordinates at the scene range's edge) reach the builders. */
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "../scenes/scene.h"
#include "exercise.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

#define MAX_PRIMS 5000

/* The mesh format of a file name by its extension, or NULL. */
static const char *mesh_format(const char *name)
{
    static const char *const known[] = {".obj", ".ply", ".off", ".stl"};
    const char *dot = strrchr(name, '.');
    for (size_t i = 0; dot && i < sizeof known / sizeof known[0]; i++)
        if (strcasecmp(dot, known[i]) == 0) return known[i];
    return NULL;
}

/* A key for what a loaded mesh scene is (its vertices, triangles and the
 * view), so that a mutation that changes nothing of it (a comment, a
 * blank, a number written another way) is not built again. */
static void geometry_key(const scene_t *s, const char *view, char *key, size_t len)
{
    uint64_t h = 0xcbf29ce484222325u;
    const prims_t *p = &s->prims;
    const unsigned char *parts[] = {(const void *)p->verts, (const void *)p->tris, (const void *)view};
    size_t sizes[] = {p->nverts * sizeof *p->verts, p->ntris * sizeof *p->tris, strlen(view)};
    for (int k = 0; k < 3; k++)
        for (size_t i = 0; i < sizes[k]; i++) h = (h ^ parts[k][i]) * 0x100000001b3u;
    snprintf(key, len, "%016llx", (unsigned long long)h);
}

/* name (FILE.EXT or FILE.EXT@SPEC) with the file's bytes: loaded, viewed and exercised. */
static void exercise_file(char *name, const unsigned char *data, size_t size)
{
    char *at = strchr(name, '@');
    const char *view = at ? at + 1 : "";
    if (at) *at = '\0';
    const char *ext = mesh_format(name);
    if (!ext || !*name) return;
    char file_name[16], err[512];
    snprintf(file_name, sizeof file_name, "fuzz%s", ext);
    char *bytes = malloc(size + 1); /* and the NUL a file read gives */
    if (!bytes) return;
    memcpy(bytes, data, size);
    bytes[size] = '\0';
    scene_t *s = scene_mesh_from_memory_in_process(name, "/nonexistent-accelbench-fuzz/scene", file_name, bytes, size,
                                                   err, sizeof err);
    free(bytes);
    scene_view v;
    if (s && *view && (scene_view_parse(view, &v, err, sizeof err) != 0 ||
                       scene_view_apply(s, &v, view, err, sizeof err) != 0)) {
        scene_free(s);
        s = NULL;
    }
    char key[32];
    if (s && s->prims.count <= MAX_PRIMS) {
        geometry_key(s, view, key, sizeof key);
        if (fuzz_first_time("mesh", key)) fuzz_exercise_one(s, key);
    }
    scene_free(s);
}

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    char name[2048];
    size_t n = size < sizeof name - 1 ? size : sizeof name - 1;
    memcpy(name, data, n);
    name[n] = '\0';
    size_t line = strcspn(name, "\n");
    bool has_file = line < n && data[line] == '\n';
    name[line] = '\0';
    char err[512], list[4096];
    (void)scene_set_expand(name, list, sizeof list);
    if (scene_check(name, err, sizeof err) != 0) return 0;
    uint64_t prims;
    if (!scene_generated(name, &prims)) {
        if (has_file) exercise_file(name, data + line + 1, size - line - 1);
        return 0;
    }
    if (prims > MAX_PRIMS) return 0;
    if (!fuzz_first_time("scene", name)) return 0; /* loaded and exercised already */
    scene_t *s = scene_load(name, err, sizeof err);
    if (s) fuzz_exercise_one(s, name);
    scene_free(s);
    return 0;
}
