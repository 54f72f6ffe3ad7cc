/* fuzz_mesh: the mesh reader (scenes/load_mesh.c: the pre-checks of
 * scenes/mesh_check.c, assimp, the checks of what assimp gives and the
 * scene made of it) on any bytes. The first byte picks the format (the
 * extension assimp goes by): OBJ when it is 0 mod 16, else PLY, OFF and
 * STL in turn (1, 2, 3 mod 16 and so on); the rest is the file. OBJ gets
 * one value in sixteen because assimp's OBJ reader costs about 60 ms an
 * input here against 0.3 ms for the others: it allocates, fills and frees
 * stream buffers of 16 MiB per file, fresh mappings each time under ASan's
 * allocator. At one value in four, OBJ inputs took 95 % of the time.
 * The path is in a folder that does not exist, so files a mesh names (an
 * OBJ's mtllib) are never found.
 *
 * assimp runs in this process (scene_mesh_from_memory_in_process), not in
 * the child accelbench forks for it: libFuzzer's process is the isolation,
 * a crash in assimp is reported as one, and a fork per input would cost
 * most of the time. Nothing is built from what loads: building every
 * accelerator over meshes is fuzz_scenes' work (a name line, then the
 * file), and costs tens of milliseconds an input under ASan. What
 * loads is only checked for what the loader promises: every triangle
 * names a vertex it has. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../scenes/scene.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    static const char *const names[] = {"fuzz.obj", "fuzz.ply", "fuzz.off", "fuzz.stl"};
    if (size == 0) return 0;
    const char *name = names[data[0] % 16 == 0 ? 0 : 1 + (data[0] % 16 - 1) % 3];
    char path[64];
    snprintf(path, sizeof path, "/nonexistent-accelbench-fuzz/%s", name);
    char *bytes = malloc(size); /* size - 1 bytes and the NUL a file read gives */
    if (!bytes) return 0;
    memcpy(bytes, data + 1, size - 1);
    bytes[size - 1] = '\0';
    char err[512];
    scene_t *s = scene_mesh_from_memory_in_process("fuzz", path, name, bytes, size - 1, err, sizeof err);
    free(bytes);
    if (!s) return 0;
    const prims_t *p = &s->prims;
    for (uint32_t t = 0; t < p->ntris; t++)
        for (int k = 0; k < 3; k++)
            if (p->tris[t].v[k] >= p->nverts) {
                fprintf(stderr, "fuzz: triangle %u names vertex %u of %u\n", t, p->tris[t].v[k], p->nverts);
                abort();
            }
    scene_free(s);
    return 0;
}
