/* scene_path.c: finding repository meshes by file name on the scene path.
 *
 * The meshes fetched from public repositories (Sibenik, Sponza, the 100k
 * Stanford scans) may not be committed to the project, so they live outside
 * it: in the folders of $ACCELBENCH_SCENES, then in two default folders:
 * the shared folder beside the checkout (../shared/scenes, where developers
 * and CI have them; meson compiles the source directory in) and the user's
 * cache, where scripts/get-scenes.sh puts them ($XDG_CACHE_HOME, else
 * ~/.cache, then accelbench/scenes). $ACCELBENCH_SHARED_SCENES replaces both
 * defaults with one folder, and empty drops them, so a test can see what a
 * fresh machine sees. The environment is read on every call: tests change it
 * between loads. */
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

bool scene_path_user_folder(char *out, size_t outlen)
{
    const char *xdg = getenv("XDG_CACHE_HOME"), *home = getenv("HOME");
    int n;
    if (xdg && xdg[0] == '/') n = snprintf(out, outlen, "%s/accelbench/scenes", xdg);
    else if (home && home[0] == '/') n = snprintf(out, outlen, "%s/.cache/accelbench/scenes", home);
    else return false;
    return n > 0 && (size_t)n < outlen;
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
    if (shared) {
        if (try_dir(shared, strlen(shared), file, out, outlen, where, wherelen)) return true;
    } else {
        if (try_dir(SHARED_SCENES, strlen(SHARED_SCENES), file, out, outlen, where, wherelen)) return true;
        char cache[4096];
        if (scene_path_user_folder(cache, sizeof cache) &&
            try_dir(cache, strlen(cache), file, out, outlen, where, wherelen))
            return true;
    }
    if (!where[0]) snprintf(where, wherelen, "no folder: $ACCELBENCH_SCENES and $ACCELBENCH_SHARED_SCENES are empty");
    return false;
}
