/* mesh_input.h: what fuzz_mesh and fuzz_obj do with one input: read it as
 * the file `name` (its extension picks assimp's reader) through the mesh
 * loader in this process, and check what loads for what the loader
 * promises (every triangle names a vertex it has); abort when it does not. */
#ifndef ACCELBENCH_FUZZ_MESH_INPUT_H
#define ACCELBENCH_FUZZ_MESH_INPUT_H

#include <stdio.h>
#include <stdlib.h>
#include "../scenes/scene.h"

static inline void fuzz_read_mesh(const char *name, const char *bytes, size_t size)
{
    char path[64], err[512];
    snprintf(path, sizeof path, "/nonexistent-accelbench-fuzz/%s", name);
    scene_t *s = scene_mesh_from_memory_in_process("fuzz", path, name, bytes, size, err, sizeof err);
    if (!s) return;
    const prims_t *p = &s->prims;
    for (uint32_t t = 0; t < p->ntris; t++)
        for (int k = 0; k < 3; k++)
            if (p->tris[t].v[k] >= p->nverts) {
                fprintf(stderr, "fuzz: triangle %u names vertex %u of %u\n", t, p->tris[t].v[k], p->nverts);
                abort();
            }
    scene_free(s);
}

#endif
