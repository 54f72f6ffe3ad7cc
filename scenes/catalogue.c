/* catalogue.c: scene names to scenes (scene_load) and the list of named
 * scenes (scene_catalogue_print).
 *
 * The named meshes are files shipped by Debian packages, so every machine
 * that installs the package has the same bytes, and nothing is downloaded.
 * A name is resolved in this order: "spd:" generators, "file:PATH",
 * catalogue names, then anything that looks like a path. */
#include "scene.h"
#include "compressed.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

typedef struct {
    const char *name;
    const char *path;    /* FILE or ARCHIVE#MEMBER, see compressed.h */
    const char *package; /* the Debian package that ships it */
    const char *summary;
} catalogue_entry;

#define CGAL_DATA "/usr/share/doc/libcgal-demo/data.tar.gz#data/meshes/"

static const catalogue_entry catalogue[] = {
    {"bunny", CGAL_DATA "bunny00.off", "libcgal-demo", "Stanford bunny, 75,408 triangles, closed"},
    {"elephant", CGAL_DATA "refined_elephant.off", "libcgal-demo", "elephant, refined, 88,928 triangles"},
    {"elephant-small", CGAL_DATA "elephant.off", "libcgal-demo", "elephant, 5,558 triangles"},
    {"armadillo", CGAL_DATA "armadillo.off", "libcgal-demo", "Stanford armadillo, 52,000 triangles"},
    {"dragon", CGAL_DATA "ChineseDragon-10kv.off", "libcgal-demo", "Chinese dragon, 19,994 triangles"},
    {"glbunny", "/usr/share/glmark2/models/bunny.obj", "glmark2-data", "glmark2's bunny, 69,666 triangles"},
    {"head", "/usr/share/opencascade/data/stl/head.stl", "occt-misc", "OCCT sample head scan (STL), 117,694 triangles"},
};
#define CATALOGUE_N (sizeof catalogue / sizeof catalogue[0])

static bool disk_file_exists(const char *path)
{
    char file[4096];
    struct stat st;
    compressed_disk_file(path, file, sizeof file);
    return stat(file, &st) == 0;
}

void scene_catalogue_print(FILE *out)
{
    fprintf(out, "%-16s %s  [%s]  %s\n", "spd:balls[:SIZE[:t[RES]]]", "generator (SPD 3.14 src/balls.c)", "built in",
            "Haines' sphereflake, SIZE 1..7 (default 4: 7,381 spheres + floor); :t[RES] as cube-sphere triangles, RES 1..64 (default 3)");
    for (size_t i = 0; i < CATALOGUE_N; i++) {
        const catalogue_entry *e = &catalogue[i];
        fprintf(out, "%-16s %s  [%s%s]  %s\n", e->name, e->path, e->package,
                disk_file_exists(e->path) ? "" : ", not installed", e->summary);
    }
}

/* Parse a whole decimal int in [lo, hi]; false if s is not one. */
static bool parse_int(const char *s, int lo, int hi, int *out)
{
    if (!*s) return false;
    for (const char *c = s; *c; c++)
        if (*c < '0' || *c > '9') return false;
    errno = 0;
    long v = strtol(s, NULL, 10);
    if (errno || v < lo || v > hi) return false;
    *out = (int)v;
    return true;
}

/* spd:balls[:SIZE[:t[RES]]] */
static scene_t *load_spd(const char *name, char *err, size_t errlen)
{
    const char *gen = name + 4;
    if (strcmp(gen, "balls") != 0 && strncmp(gen, "balls:", 6) != 0) {
        snprintf(err, errlen, "unknown scene '%s' (see: accelbench list scenes)", name);
        return NULL;
    }
    int size = 4, res = 0;
    if (gen[5] == ':') {
        char buf[64];
        snprintf(buf, sizeof buf, "%s", gen + 6);
        char *tess = strchr(buf, ':');
        if (tess) *tess++ = '\0';
        if (!parse_int(buf, 1, 7, &size)) {
            snprintf(err, errlen, "spd:balls:%s: size must be 1..7", buf);
            return NULL;
        }
        if (tess) {
            if (tess[0] != 't') {
                snprintf(err, errlen, "%s: expected ':t' or ':tRES' after the size", name);
                return NULL;
            }
            res = 3; /* the SPD's OUTPUT_RESOLUTION */
            if (tess[1] && !parse_int(tess + 1, 1, 64, &res)) {
                snprintf(err, errlen, "%s: tessellation resolution must be 1..64", name);
                return NULL;
            }
        }
    }
    return scene_spd_balls(name, size, res, err, errlen);
}

/* A catalogue mesh: say which package to install when it is missing. */
static scene_t *load_catalogue(const catalogue_entry *e, char *err, size_t errlen)
{
    if (!disk_file_exists(e->path)) {
        char file[4096];
        compressed_disk_file(e->path, file, sizeof file);
        snprintf(err, errlen, "scene '%s': %s: %s (install the Debian package %s: apt-get install %s)", e->name, file,
                 strerror(ENOENT), e->package, e->package);
        return NULL;
    }
    return scene_load_mesh(e->name, e->path, err, errlen);
}

/* Whether a name that is not a scene name should be read as a file: it
 * exists, or it has a directory part or an extension. */
static bool looks_like_path(const char *name)
{
    if (disk_file_exists(name) || strchr(name, '/')) return true;
    const char *dot = strrchr(name, '.');
    return dot && dot != name && dot[1];
}

scene_t *scene_load(const char *name, char *err, size_t errlen)
{
    if (!name || !*name) {
        snprintf(err, errlen, "empty scene name (see: accelbench list scenes)");
        return NULL;
    }
    if (strncmp(name, "spd:", 4) == 0) return load_spd(name, err, errlen);
    if (strncmp(name, "file:", 5) == 0) {
        if (!name[5]) {
            snprintf(err, errlen, "file: needs a path, as in file:PATH");
            return NULL;
        }
        return scene_load_mesh(name, name + 5, err, errlen);
    }
    for (size_t i = 0; i < CATALOGUE_N; i++)
        if (strcmp(name, catalogue[i].name) == 0) return load_catalogue(&catalogue[i], err, errlen);
    if (looks_like_path(name)) return scene_load_mesh(name, name, err, errlen);
    snprintf(err, errlen, "unknown scene '%s' (see: accelbench list scenes)", name);
    return NULL;
}
