/* fuzz_mesh: the mesh reader (scenes/load_mesh.c: the pre-checks of
 * scenes/mesh_check.c, assimp, the checks of what assimp gives and the
 * scene made of it) on any bytes, for PLY, OFF and STL. The first byte
 * picks the format (the extension assimp goes by), the rest is the file.
 * The same bytes also go through the project's OBJ pre-check alone
 * (mesh_precheck), which must accept or refuse them with a reason; assimp's
 * OBJ reader is fuzz_obj's: it allocates and fills a stream buffer of
 * 16 MiB per file, which costs even from a reused mapping
 * (fuzz/large_blocks.cc) a few times what a PLY, OFF or STL input does,
 * and would slow this harness's other formats with it. The path is in a folder that does not exist, so files a mesh
 * names are never found.
 *
 * assimp runs in this process (scene_mesh_from_memory_in_process), not in
 * the child accelbench forks for it: libFuzzer's process is the isolation,
 * a crash in assimp is reported as one (scripts/fuzz.sh --campaign runs in
 * fork mode, so one does not end a campaign), and a fork per input would
 * cost most of the time. Nothing is built from what loads: building every
 * accelerator over meshes is fuzz_scenes' work. What loads is only checked
 * for what the loader promises: every triangle names a vertex it has. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../scenes/mesh_check.h"
#include "mesh_input.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    static const char *const names[] = {"fuzz.ply", "fuzz.off", "fuzz.stl"};
    if (size == 0) return 0;
    char *bytes = malloc(size); /* size - 1 bytes and the NUL a file read gives */
    if (!bytes) return 0;
    memcpy(bytes, data + 1, size - 1);
    bytes[size - 1] = '\0';
    char err[512] = "";
    if (mesh_precheck("obj", bytes, size - 1, "fuzz.obj", err, sizeof err) != 0 && err[0] == '\0') {
        fprintf(stderr, "fuzz: the OBJ pre-check refused without a reason\n");
        abort();
    }
    fuzz_read_mesh(names[data[0] % 3], bytes, size - 1);
    free(bytes);
    return 0;
}
