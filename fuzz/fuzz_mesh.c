/* fuzz_mesh: the mesh loader's front end (scenes/load_mesh.c with the
 * pre-checks of scenes/mesh_check.c, then assimp) on any bytes. The first
 * byte picks the format, OBJ, PLY, OFF or STL (the extension assimp goes
 * by); the rest is the file. The path is in a folder that does not exist,
 * so files a mesh names (an OBJ's mtllib) are never found. What loads is
 * built and traced by every accelerator (exercise.c). */
#include <stdlib.h>
#include <string.h>
#include "../scenes/scene.h"
#include "exercise.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    static const char *const names[] = {"fuzz.obj", "fuzz.ply", "fuzz.off", "fuzz.stl"};
    if (size == 0) return 0;
    const char *name = names[data[0] % 4];
    char path[64];
    snprintf(path, sizeof path, "/nonexistent-accelbench-fuzz/%s", name);
    char *bytes = malloc(size); /* size - 1 bytes and the NUL a file read gives */
    if (!bytes) return 0;
    memcpy(bytes, data + 1, size - 1);
    bytes[size - 1] = '\0';
    char err[512];
    scene_t *s = scene_mesh_from_memory("fuzz", path, name, bytes, size - 1, err, sizeof err);
    free(bytes);
    if (s) fuzz_exercise(s, NULL);
    scene_free(s);
    return 0;
}
