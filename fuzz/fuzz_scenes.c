/* fuzz_scenes: the --scenes names (scenes/scene_load.c scene_check, its
 * views through scenes/view.c, the sets of scene_set_expand) on any text
 * up to its first NUL or newline. A name scene_check accepts that names a
 * generated scene of at most 5000 primitives is also loaded, with its
 * views, and built and traced by every accelerator (exercise.c); names of
 * files are only checked, never read (the harness stays hermetic and
 * fast). */
#include <stdlib.h>
#include <string.h>
#include "../scenes/scene.h"
#include "exercise.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

#define MAX_GENERATED_PRIMS 5000

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    char name[2048];
    size_t n = size < sizeof name - 1 ? size : sizeof name - 1;
    memcpy(name, data, n);
    name[n] = '\0';
    name[strcspn(name, "\n")] = '\0';
    char err[512], list[4096];
    (void)scene_set_expand(name, list, sizeof list);
    if (scene_check(name, err, sizeof err) != 0) return 0;
    uint64_t prims;
    if (!scene_generated(name, &prims) || prims > MAX_GENERATED_PRIMS) return 0;
    if (!fuzz_first_time("scene", name)) return 0; /* loaded and exercised already */
    scene_t *s = scene_load(name, err, sizeof err);
    if (s) fuzz_exercise(s, NULL);
    scene_free(s);
    return 0;
}
