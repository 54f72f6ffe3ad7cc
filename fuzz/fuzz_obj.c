/* fuzz_obj: the mesh reader on any bytes as an OBJ file, assimp's OBJ reader
 * included, in this process (fuzz_mesh says why OBJ has a harness of its
 * own: assimp's 16 MiB stream buffer per file, served from a reused mapping
 * by fuzz/large_blocks.cc). The
 * path is in a folder that does not exist, so an mtllib is never found. */
#include <stdlib.h>
#include <string.h>
#include "mesh_input.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    char *bytes = malloc(size + 1); /* the bytes and the NUL a file read gives */
    if (!bytes) return 0;
    memcpy(bytes, data, size);
    bytes[size] = '\0';
    fuzz_read_mesh("fuzz.obj", bytes, size);
    free(bytes);
    return 0;
}
