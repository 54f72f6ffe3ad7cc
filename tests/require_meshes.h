/* require_meshes.h: the guard of a test program that needs meshes from
 * public repositories (Sibenik, Sponza, the 100k Stanford scans), which the
 * project does not hold: they are on the scene path or not (scenes/scene.h).
 * When one is absent the program stops before its checks with one line
 * naming it and the command that gets it: SKIP, meson's exit status 77, on
 * a user's clean clone; FAIL, exit 1, where the meshes are required (CI=true,
 * or ACCELBENCH_REQUIRE_SCENES=1), so CI never skips them. tests/cli_lib.sh's
 * require_meshes is the same guard for the shell tests. */
#ifndef ACCELBENCH_REQUIRE_MESHES_H
#define ACCELBENCH_REQUIRE_MESHES_H

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "scenes/scene.h"

static inline bool meshes_required(void)
{
    const char *ci = getenv("CI"), *req = getenv("ACCELBENCH_REQUIRE_SCENES");
    return (ci && strcmp(ci, "true") == 0) || (req && strcmp(req, "1") == 0);
}

/* names: catalogue scenes (views allowed), NULL-terminated. */
static inline void require_meshes(const char *const *names)
{
    char absent[512] = "", get[512] = "";
    for (const char *const *n = names; *n; n++) {
        char where[1024];
        if (scene_catalogue_available(*n, where, sizeof where)) continue;
        char base[64];
        snprintf(base, sizeof base, "%.*s", (int)strcspn(*n, "@"), *n);
        size_t a = strlen(absent), g = strlen(get);
        snprintf(absent + a, sizeof absent - a, "%s%s", a ? ", " : "", base);
        snprintf(get + g, sizeof get - g, " %s", base);
    }
    if (!absent[0]) return;
    bool required = meshes_required();
    printf("%s: %s not on the scene path; get it with scripts/get-scenes.sh%s%s\n", required ? "FAIL" : "SKIP", absent,
           get, required ? " (CI=true or ACCELBENCH_REQUIRE_SCENES=1: the meshes are required)" : "");
    exit(required ? 1 : 77);
}

#endif
