/* catalogue.c: scene names to scenes (scene_load) and the list of named
 * scenes (scene_catalogue_print).
 *
 * The named meshes are files shipped by Debian packages, so every machine
 * that installs the package has the same bytes, and nothing is downloaded,
 * plus three meshes kept in the repository (scenes/data/, credits in
 * scenes/README.md), found through the source directory meson compiles in.
 * A name is resolved in this order: "spd:" generators, "file:PATH",
 * catalogue names, then anything that looks like a path. Named sets of
 * scenes ("set:...") are expanded by scene_set_expand(), not loaded. */
#include "nff.h"
#include "scene.h"
#include "compressed.h"
#include "spd.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

typedef struct {
    const char *name;
    const char *path;    /* FILE or ARCHIVE#MEMBER, see compressed.h */
    const char *package; /* the Debian package that ships it; NULL: in the repository */
    const char *summary;
} catalogue_entry;

#define CGAL_DATA "/usr/share/doc/libcgal-demo/data.tar.gz#data/meshes/"
#define OPENFOAM_EXAMPLES "/usr/share/doc/openfoam-examples/examples/"
#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#define REPO_DATA ACCELBENCH_SOURCE_DIR "/scenes/data/"

static const catalogue_entry catalogue[] = {
    {"bunny", CGAL_DATA "bunny00.off", "libcgal-demo", "Stanford bunny, 75,408 triangles, closed"},
    {"elephant", CGAL_DATA "refined_elephant.off", "libcgal-demo", "elephant, refined, 88,928 triangles"},
    {"elephant-small", CGAL_DATA "elephant.off", "libcgal-demo", "elephant, 5,558 triangles"},
    {"armadillo", CGAL_DATA "armadillo.off", "libcgal-demo", "Stanford armadillo, 52,000 triangles"},
    {"dragon", CGAL_DATA "ChineseDragon-10kv.off", "libcgal-demo", "Chinese dragon, 19,994 triangles"},
    {"glbunny", "/usr/share/glmark2/models/bunny.obj", "glmark2-data", "glmark2's bunny, 69,666 triangles"},
    {"head", "/usr/share/opencascade/data/stl/head.stl", "occt-misc", "OCCT sample head scan (STL), 117,694 triangles"},
    {"motorbike", OPENFOAM_EXAMPLES "resources/geometry/motorBike.obj.gz", "openfoam-examples",
     "OpenFOAM tutorial motorbike and rider (OBJ), 331,653 triangles"},
    {"buildings", OPENFOAM_EXAMPLES "incompressible/simpleFoam/windAroundBuildings/constant/triSurface/buildings.obj.gz",
     "openfoam-examples", "OpenFOAM windAroundBuildings city block (OBJ), 400,020 triangles"},
    {"sibenik", REPO_DATA "sibenik.obj.xz", NULL, "Sibenik cathedral interior, 75,284 triangles (M. Dabrovic, RNA.HR)"},
    {"dragon100k", REPO_DATA "dragon100k.obj.xz", NULL, "Stanford dragon decimated to 100,000 triangles"},
    {"buddha100k", REPO_DATA "buddha100k.obj.xz", NULL, "Stanford Happy Buddha decimated to 100,000 triangles"},
};
#define CATALOGUE_N (sizeof catalogue / sizeof catalogue[0])

static bool disk_file_exists(const char *path)
{
    char file[4096];
    struct stat st;
    compressed_disk_file(path, file, sizeof file);
    return stat(file, &st) == 0;
}

/* --- named sets --- */

typedef struct {
    const char *name;
    const char *summary;
    const char *scenes; /* comma-separated; "" for set:scaling, the union of the families */
} scene_set;

static const scene_set sets[] = {
    {"set:medium", "the medium benchmark set: Debian-packaged and repository meshes",
     "bunny,elephant,armadillo,dragon,glbunny,motorbike,buildings,head,sibenik,dragon100k,buddha100k"},
    {"set:spd", "the seven classic SPD databases at their default sizes",
     "spd:balls:4,spd:gears:4,spd:mount:6,spd:rings:7,spd:teapot:12,spd:tetra:6,spd:tree:11"},
    {"set:scaling", "all the set:scaling:* families below, in that order", ""},
    {"set:scaling:balls", "sphereflake sizes 1..6 (11 to 597,872 primitives)",
     "spd:balls:1,spd:balls:2,spd:balls:3,spd:balls:4,spd:balls:5,spd:balls:6"},
    {"set:scaling:tetra", "tetrahedron sizes 4..9 (256 to 262,144 triangles)",
     "spd:tetra:4,spd:tetra:5,spd:tetra:6,spd:tetra:7,spd:tetra:8,spd:tetra:9"},
    {"set:scaling:mount", "fractal mountain sizes 4..9 (516 to 524,292 primitives)",
     "spd:mount:4,spd:mount:5,spd:mount:6,spd:mount:7,spd:mount:8,spd:mount:9"},
    {"set:scaling:gears", "gears sizes 2..12 (1,169 to 252,289 polygons)",
     "spd:gears:2,spd:gears:3,spd:gears:4,spd:gears:5,spd:gears:6,spd:gears:7,spd:gears:8,spd:gears:9,"
     "spd:gears:10,spd:gears:11,spd:gears:12"},
    {"set:scaling:jacks", "jacks sizes 2..6 (81 to 337,041 primitives)",
     "spd:jacks:2,spd:jacks:3,spd:jacks:4,spd:jacks:5,spd:jacks:6"},
    {"set:scaling:balls-t", "sphereflake sizes 2..5 tessellated at RES 3 (9,830 to 7,174,442 triangles)",
     "spd:balls:2:t,spd:balls:3:t,spd:balls:4:t,spd:balls:5:t"},
};
#define SETS_N (sizeof sets / sizeof sets[0])

/* Append "sep item" to out (length *len); false if it does not fit. */
static bool append(char *out, size_t outlen, size_t *len, const char *item)
{
    int n = snprintf(out + *len, outlen - *len, "%s%s", *len ? "," : "", item);
    if (n < 0 || (size_t)n >= outlen - *len) return false;
    *len += (size_t)n;
    return true;
}

int scene_set_expand(const char *name, char *out, size_t outlen)
{
    const scene_set *set = NULL;
    for (size_t i = 0; i < SETS_N; i++)
        if (strcmp(name, sets[i].name) == 0) set = &sets[i];
    if (!set) return 0;
    if (!out || outlen == 0) return -1;
    out[0] = '\0';
    size_t len = 0;
    bool ok = true;
    if (set->scenes[0])
        ok = append(out, outlen, &len, set->scenes);
    else
        for (size_t i = 0; i < SETS_N && ok; i++)
            if (strncmp(sets[i].name, "set:scaling:", 12) == 0) ok = append(out, outlen, &len, sets[i].scenes);
    if (!ok) {
        out[0] = '\0';
        return -1;
    }
    return 1;
}

/* --- the catalogue --- */

void scene_catalogue_print(FILE *out)
{
    fprintf(out, "SPD 3.14 generators (Haines' Standard Procedural Databases, built in):\n"
                 "  spd:NAME[:SIZE][:t[RES]]  true primitives, or with :t / :tRES triangles only (RES 1..64, default 3)\n");
    for (int i = 0; i < spd_ngenerators; i++) {
        const spd_generator *g = &spd_generators[i];
        char label[64];
        snprintf(label, sizeof label, "spd:%s", g->name);
        fprintf(out, "  %-14s size 1..%-2d default %-2d  %s  (%s)\n", label, g->max_size, g->default_size, g->summary,
                g->file);
    }
    fprintf(out, "generated (built in):\n"
                 "  gen:room        a 10000x8000x600 hall at coordinates in the thousands: decals, slivers, needles,\n"
                 "                  spheres, a column; the secondary-ray robustness test\n"
                 "  gen:room:empty  its convex shell with decals and corner slivers only: nothing can cast a shadow\n");
    fprintf(out, "meshes:\n");
    for (size_t i = 0; i < CATALOGUE_N; i++) {
        const catalogue_entry *e = &catalogue[i];
        fprintf(out, "%-16s %s  [%s%s]  %s\n", e->name, e->path, e->package ? e->package : "in the repository",
                disk_file_exists(e->path) ? "" : ", not installed", e->summary);
    }
    fprintf(out, "sets (for --scenes; expanded to their scene lists):\n");
    for (size_t i = 0; i < SETS_N; i++) fprintf(out, "  %-20s %s\n", sets[i].name, sets[i].summary);
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

/* spd:NAME, spd:NAME:SIZE, spd:NAME:t[RES], spd:NAME:SIZE:t[RES] */
static scene_t *load_spd(const char *name, char *err, size_t errlen)
{
    char buf[256];
    if (snprintf(buf, sizeof buf, "%s", name + 4) >= (int)sizeof buf) {
        snprintf(err, errlen, "%.64s...: name too long", name);
        return NULL;
    }
    char *part[4] = {buf, NULL, NULL, NULL};
    int nparts = 1;
    for (char *c = buf; *c; c++)
        if (*c == ':') {
            *c = '\0';
            if (nparts == 4) break;
            part[nparts++] = c + 1;
        }
    const spd_generator *g = spd_generator_find(part[0]);
    if (!g) {
        /* scene_spd() words the error, with the list of generators. */
        return scene_spd(name, part[0], 0, 0, err, errlen);
    }
    int size = g->default_size, res = 0;
    const char *tess = NULL;
    if (nparts > 3) {
        snprintf(err, errlen, "%s: expected spd:NAME[:SIZE][:t[RES]]", name);
        return NULL;
    }
    if (nparts >= 2) {
        if (nparts == 2 && part[1][0] == 't')
            tess = part[1];
        else if (!parse_int(part[1], 1, g->max_size, &size)) {
            snprintf(err, errlen, "spd:%s:%s: size must be 1..%d", g->name, part[1], g->max_size);
            return NULL;
        }
    }
    if (nparts == 3) tess = part[2];
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
    return scene_spd(name, g->name, size, res, err, errlen);
}

/* A catalogue mesh: say which package to install when it is missing. */
/* A file: NFF by its extension (also under .gz/.xz/.bz2), else assimp. */
static scene_t *load_file(const char *name, const char *path, char *err, size_t errlen)
{
    char base[1024];
    snprintf(base, sizeof base, "%s", path);
    char *dot = strrchr(base, '.');
    if (dot && (!strcmp(dot, ".gz") || !strcmp(dot, ".xz") || !strcmp(dot, ".bz2"))) {
        *dot = 0;
        dot = strrchr(base, '.');
    }
    if (dot && !strcasecmp(dot, ".nff")) return scene_load_nff(name, path, err, errlen);
    return scene_load_mesh(name, path, err, errlen);
}

static scene_t *load_catalogue(const catalogue_entry *e, char *err, size_t errlen)
{
    if (!disk_file_exists(e->path)) {
        char file[4096];
        compressed_disk_file(e->path, file, sizeof file);
        if (e->package)
            snprintf(err, errlen, "scene '%s': %s: %s (install the Debian package %s: apt-get install %s)", e->name, file,
                     strerror(ENOENT), e->package, e->package);
        else
            snprintf(err, errlen, "scene '%s': %s: %s (it ships in the repository's scenes/data/; was the source tree moved?)",
                     e->name, file, strerror(ENOENT));
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
    if (strcmp(name, "gen:room") == 0 || strcmp(name, "gen:room:empty") == 0)
        return scene_gen_room(name, name[8] != '\0', err, errlen);
    if (strncmp(name, "gen:", 4) == 0) {
        snprintf(err, errlen, "unknown generated scene '%s' (known: gen:room, gen:room:empty)", name);
        return NULL;
    }
    if (strncmp(name, "set:", 4) == 0) {
        char list[8];
        if (scene_set_expand(name, list, sizeof list) != 0)
            snprintf(err, errlen, "'%s' is a set of scenes, not one scene (expand it with scene_set_expand)", name);
        else
            snprintf(err, errlen, "unknown scene set '%s' (see: accelbench list scenes)", name);
        return NULL;
    }
    if (strncmp(name, "file:", 5) == 0) {
        if (!name[5]) {
            snprintf(err, errlen, "file: needs a path, as in file:PATH");
            return NULL;
        }
        return load_file(name, name + 5, err, errlen);
    }
    for (size_t i = 0; i < CATALOGUE_N; i++)
        if (strcmp(name, catalogue[i].name) == 0) return load_catalogue(&catalogue[i], err, errlen);
    if (looks_like_path(name)) return load_file(name, name, err, errlen);
    snprintf(err, errlen, "unknown scene '%s' (see: accelbench list scenes)", name);
    return NULL;
}
