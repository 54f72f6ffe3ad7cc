/* options_resources.c: the memory cap applied to a command's options and
 * what they size checked against it before any scene is loaded (see
 * options.h; the estimates are workloads/resources.h's). */
#include "options.h"

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include "../../scenes/scene.h"
#include "../render/render.h"
#include "../workloads/resources.h"

int resources_apply_memcap(options *o)
{
    memory_cap_set_mib(o->memcap_mib);
    for (int i = 0; i < o->naccels; i++) resources_bound_accel_params(&o->accels[i].params);
    return 0;
}

/* The fewest heap bytes one primitive of any kind takes in a scene: its
 * kind, index, bounds and material, and a triangle's three indices and
 * degenerate flag (the smallest kind; vertices may be shared). */
#define PRIM_MIN_BYTES (1 + sizeof(uint32_t) + sizeof(box3) + sizeof(uint16_t) + sizeof(tri_t) + 1)

int resources_check_options(const options *o, const char *cmd)
{
    char err[1024];
    if (resources_check_threads(o->threads, "--threads", err, sizeof err)) goto refuse;
    for (int i = 0; i < o->nscenes; i++) {
        uint64_t prims;
        if (scene_generated(o->scenes[i], &prims) &&
            memory_cap_exceeded(memory_mul(prims, PRIM_MIN_BYTES), err, sizeof err,
                                "scene %s: %llu primitives (at least %zu bytes each)", o->scenes[i],
                                (unsigned long long)prims, (size_t)PRIM_MIN_BYTES))
            goto refuse;
    }
    if (o->rays_file) {
        /* The file is read whole, then copied into the set; its rays are at least 40 bytes each. */
        struct stat st;
        if (stat(o->rays_file, &st) == 0 && st.st_size > 0) {
            uint64_t size = (uint64_t)st.st_size, n = size / sizeof(ray_t);
            uint64_t bytes = memory_add(memory_mul(size, 2), cell_answers_bytes(n, QUERY_CLOSEST));
            if (memory_cap_exceeded(bytes, err, sizeof err, "--rays %s: a %llu-byte file of up to %llu rays and their answers",
                                    o->rays_file, (unsigned long long)size, (unsigned long long)n))
                goto refuse;
        }
        return 0;
    }
    if (!strcmp(cmd, "render")) {
        /* Without --res the image is the scene's own size, known once it is loaded (cli/render_cmd.c checks it then). */
        if (o->res_given &&
            render_check_memory(o->scenes[0], o->wl.width, o->wl.height, o->wl.spp, o->wl.corners, o->heatmap != NULL,
                                   err, sizeof err))
            goto refuse;
        return 0;
    }
    /* The sets do not depend on the scene at one light. */
    for (int i = 0; i < o->nworkloads; i++)
        if (workload_check_memory(o->workloads[i]->name, o->scenes[0], &o->wl, 1, err, sizeof err)) goto refuse;
    return 0;
refuse:
    fprintf(stderr, "accelbench: %s\n", err);
    return 2;
}
