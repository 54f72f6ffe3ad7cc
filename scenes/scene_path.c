/* scene_path.c: finding repository meshes by file name on the scene path.
 *
 * The meshes fetched from public repositories (Sibenik, Sponza, the 100k
 * Stanford scans) may not be committed to the project, so they live outside
 * it: in the folders of $ACCELBENCH_SCENES, then in the shared folder beside
 * the checkout (../shared/scenes, where developers and CI have them; meson
 * compiles the source directory in). $ACCELBENCH_SHARED_SCENES replaces that
 * folder, and empty drops it, so a test can see what a fresh machine sees.
 * The environment is read on every call: tests change it between loads. */
#include "scene.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#define SHARED_SCENES ACCELBENCH_SOURCE_DIR "/../shared/scenes"

/* Try dir/file; append dir to where either way. */
static bool try_dir(const char *dir, size_t dirlen, const char *file, char *out, size_t outlen, char *where,
                    size_t wherelen)
{
    if (dirlen == 0) return false; /* "a::b" and a trailing ':' name no folder */
    size_t n = strlen(where);
    snprintf(where + n, wherelen - n, "%s%.*s", n ? ", " : "", (int)dirlen, dir);
    char path[4096];
    if (snprintf(path, sizeof path, "%.*s/%s", (int)dirlen, dir, file) >= (int)sizeof path) return false;
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode)) return false;
    snprintf(out, outlen, "%s", path);
    return true;
}

bool scene_path_find(const char *file, char *out, size_t outlen, char *where, size_t wherelen)
{
    where[0] = '\0';
    const char *user = getenv("ACCELBENCH_SCENES");
    for (const char *p = user; p && *p;) {
        const char *colon = strchr(p, ':');
        size_t len = colon ? (size_t)(colon - p) : strlen(p);
        if (try_dir(p, len, file, out, outlen, where, wherelen)) return true;
        if (!colon) break;
        p = colon + 1;
    }
    const char *shared = getenv("ACCELBENCH_SHARED_SCENES");
    if (!shared) shared = SHARED_SCENES;
    if (try_dir(shared, strlen(shared), file, out, outlen, where, wherelen)) return true;
    if (!where[0]) snprintf(where, wherelen, "no folder: $ACCELBENCH_SCENES and $ACCELBENCH_SHARED_SCENES are empty");
    return false;
}
