/* fuzz_rays: the ray-file loader (harness/workloads/rayset.c) on any bytes, twice:
 * as given (almost always refused by the hash, which a fuzzer cannot
 * forge) and with the hash restamped over the bytes, so the header and ray
 * checks behind it see the mutations. A set it accepts is checked against
 * the fixed scene's lights and traced by every accelerator built over that
 * scene (exercise.c), with the scene's own workload rays. */
#include <stdlib.h>
#include <string.h>
#include "exercise.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

static void one(const void *bytes, size_t size)
{
    char err[512];
    rayset_t *rs = rayset_from_memory(bytes, size, "fuzz.rays", err, sizeof err);
    if (!rs) return;
    const scene_t *s = fuzz_scene();
    if (rayset_check_lights(rs, "fuzz.rays", s->name, s->nlights, err, sizeof err) == 0 &&
        rayset_check_origins(rs, "fuzz.rays", s->name, s->prims.count, err, sizeof err) == 0) {
        int n;
        rayset_t *const *own = fuzz_scene_rays(&n);
        rayset_t *sets[17];
        memcpy(sets, own, (size_t)n * sizeof *sets);
        sets[n++] = rs;
        for (int i = 0; accel_registry[i]; i++) fuzz_accel(accel_registry[i], s, NULL, sets, n);
    }
    rayset_free(rs);
}

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    one(data, size);
    void *copy = malloc(size ? size : 1);
    if (!copy) return 0;
    memcpy(copy, data, size);
    rayset_file_rehash(copy, size);
    one(copy, size);
    free(copy);
    return 0;
}
