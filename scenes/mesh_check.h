/* mesh_check.h: what the mesh loader checks in a file before assimp reads
 * it (mesh_check.c says what and why, per format). Internal to scenes/. */
#ifndef ACCELBENCH_MESH_CHECK_H
#define ACCELBENCH_MESH_CHECK_H

#include <stddef.h>

/* Check data (size bytes, data[size] == '\0') of a file whose lower-case
 * extension is ext ("obj", "off", "ply", "stl"; any other passes). Returns 0, or
 * -1 with "PATH: line L: reason" (or "PATH: reason") in err. */
int mesh_precheck(const char *ext, const char *data, size_t size, const char *path, char *err, size_t errlen);

#endif
