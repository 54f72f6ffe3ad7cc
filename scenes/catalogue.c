/* catalogue.c: the named meshes, their named views and the named sets of
 * scenes (scene_catalogue_print lists all three).
 *
 * A named mesh is either a file a Debian package ships (every machine that
 * installs the package has the same bytes, nothing is downloaded) or a file
 * from a public repository, which may not be committed to the project and
 * is found by name on the scene path (scene_path.c); its entry says where
 * to get it, and scenes/README.md credits it. Views are data here, not code
 * in the commands that use them, so a view has one name and one value
 * everywhere (sibenik@nave in reproduce woo92, the rooms test, the CLI).
 * Named sets ("set:...") are expanded by scene_set_expand(), not loaded.
 * The name syntax (spd:, gen:, file:, NAME@VIEW) is scene_load.c's. */
#include "catalogue.h"
#include "compressed.h"
#include "spd.h"

#include <errno.h>
#include <string.h>

typedef struct {
    const char *name;
    const char *path;         /* Debian: FILE or ARCHIVE#MEMBER (compressed.h); else a file name on the scene path */
    const char *package;      /* the Debian package that ships it; NULL: on the scene path */
    const char *origin;       /* scene path files: the public repository and path it was made from */
    const char *default_view; /* a views[] name for this scene, or NULL: scene_finish's automatic camera */
    const char *summary;
} catalogue_entry;

#define CGAL_DATA "/usr/share/doc/libcgal-demo/data.tar.gz#data/meshes/"
#define OPENFOAM_EXAMPLES "/usr/share/doc/openfoam-examples/examples/"

static const catalogue_entry catalogue[] = {
    {"bunny", CGAL_DATA "bunny00.off", "libcgal-demo", NULL, NULL, "Stanford bunny, 75,408 triangles, closed"},
    {"elephant", CGAL_DATA "refined_elephant.off", "libcgal-demo", NULL, NULL, "elephant, refined, 88,928 triangles"},
    {"elephant-small", CGAL_DATA "elephant.off", "libcgal-demo", NULL, NULL, "elephant, 5,558 triangles"},
    {"armadillo", CGAL_DATA "armadillo.off", "libcgal-demo", NULL, NULL, "Stanford armadillo, 52,000 triangles"},
    {"dragon", CGAL_DATA "ChineseDragon-10kv.off", "libcgal-demo", NULL, NULL, "Chinese dragon, 19,994 triangles"},
    {"glbunny", "/usr/share/glmark2/models/bunny.obj", "glmark2-data", NULL, NULL, "glmark2's bunny, 69,666 triangles"},
    {"head", "/usr/share/opencascade/data/stl/head.stl", "occt-misc", NULL, NULL,
     "OCCT sample head scan (STL), 117,694 triangles"},
    {"motorbike", OPENFOAM_EXAMPLES "resources/geometry/motorBike.obj.gz", "openfoam-examples", NULL, NULL,
     "OpenFOAM tutorial motorbike and rider (OBJ), 331,653 triangles"},
    {"buildings", OPENFOAM_EXAMPLES "incompressible/simpleFoam/windAroundBuildings/constant/triSurface/buildings.obj.gz",
     "openfoam-examples", NULL, "above", "OpenFOAM windAroundBuildings city block (OBJ), 400,020 triangles, z up"},
    {"sibenik", "sibenik.obj.xz", NULL, "github.com/taqu/BoundingVolumeHierarchy, file sibenik.zip", "nave",
     "Sibenik cathedral interior, 75,284 triangles (M. Dabrovic, RNA.HR)"},
    {"sponza", "sponza.obj.xz", NULL, "github.com/jan-van-bergen/GPU-Raytracer, folder Data/Sponza/models (381 OBJ files, merged)",
     "courtyard", "Crytek Sponza atrium, 262,205 triangles (F. Meinl, Crytek, CC BY 3.0)"},
    {"dragon100k", "dragon100k.obj.xz", NULL, "github.com/nwtnni/photon, file models/dragon.obj", NULL,
     "Stanford dragon decimated to 100,000 triangles"},
    {"buddha100k", "buddha100k.obj.xz", NULL, "github.com/nwtnni/photon, file models/buddha.obj", NULL,
     "Stanford Happy Buddha decimated to 100,000 triangles"},
};
#define CATALOGUE_N (sizeof catalogue / sizeof catalogue[0])

/* --- named views --- */

typedef struct {
    const char *scene, *name;
    scene_view view;
    const char *why;
} named_view;

#define ALL_PARTS (SCENE_VIEW_EYE | SCENE_VIEW_AT | SCENE_VIEW_UP | SCENE_VIEW_FOV)

static const named_view views[] = {
    /* Sibenik is y up and closed: the automatic camera sees its roof from
     * outside and its lights hang outside, where they light nothing inside. */
    {"sibenik", "nave",
     {ALL_PARTS, {-18, -10, 0}, {0, -11, 0}, {0, 1, 0}, 45, 2, {{-6, -4, 0}, {6, -3, 2}}, SCENE_UP_NONE},
     "inside the nave from the west end toward the altar, lit from inside; every eye ray hits a wall"},
    /* Sponza's bounds are thinnest in y, so the automatic camera even takes
     * it for z up; the courtyard view is ../shared/scenes/README.md's. */
    {"sponza", "courtyard",
     {ALL_PARTS, {120, 18, -2}, {-100, 30, -2}, {0, 1, 0}, 60, 2, {{0, 120, 0}, {-80, 25, -2}}, SCENE_UP_NONE},
     "the atrium from its east end along the courtyard, one light high in the open roof and one under the arcade"},
    /* The city block is z up but not thinnest in y, so the automatic camera
     * uses y up and sees it on its side; its lights were placed for that. */
    {"buildings", "above",
     {ALL_PARTS, {300, -60, 150}, {122, 88, 10}, {0, 0, 1}, 45, 2, {{300, -200, 500}, {-100, 100, 400}}, SCENE_UP_NONE},
     "the block from above its south-east corner, z up, lit from above"},
};
#define VIEWS_N (sizeof views / sizeof views[0])

static const catalogue_entry *find_entry(const char *name)
{
    for (size_t i = 0; i < CATALOGUE_N; i++)
        if (strcmp(name, catalogue[i].name) == 0) return &catalogue[i];
    return NULL;
}

bool catalogue_has(const char *name) { return find_entry(name) != NULL; }

const scene_view *catalogue_view(const char *scene, const char *view, char *err, size_t errlen)
{
    size_t n = 0;
    char known[512] = "";
    for (size_t i = 0; i < VIEWS_N; i++) {
        if (strcmp(views[i].scene, scene) != 0) continue;
        if (strcmp(views[i].name, view) == 0) return &views[i].view;
        n += (size_t)snprintf(known + n, n < sizeof known ? sizeof known - n : 0, "%s%s", n ? ", " : "", views[i].name);
    }
    if (known[0])
        snprintf(err, errlen, "unknown view '%s' (known: %s; or a view spec eye=X,Y,Z;at=X,Y,Z;up=X,Y,Z;fov=DEG)", view,
                 known);
    else
        snprintf(err, errlen, "unknown view '%s' (%s has no named views; give a view spec eye=X,Y,Z;at=X,Y,Z;up=X,Y,Z;fov=DEG)",
                 view, scene);
    return NULL;
}

/* Where entry e's file is: true with its path in file; false with the
 * one-line reason in err ("scene 'x': ..."). */
static bool locate(const catalogue_entry *e, char *file, size_t filelen, char *err, size_t errlen)
{
    if (e->package) {
        if (compressed_exists(e->path)) {
            snprintf(file, filelen, "%s", e->path);
            return true;
        }
        char disk[4096];
        compressed_disk_file(e->path, disk, sizeof disk);
        snprintf(err, errlen, "scene '%s': %s: %s (install the Debian package %s: apt-get install %s)", e->name, disk,
                 strerror(ENOENT), e->package, e->package);
        return false;
    }
    char where[1024];
    if (scene_path_find(e->path, file, filelen, where, sizeof where)) return true;
    snprintf(err, errlen,
             "scene '%s': %s is not on the scene path (looked in %s); get it from %s with scripts/get-scenes.sh %s "
             "(it converts it as scenes/README.md says, into the scene path's user folder)",
             e->name, e->path, where, e->origin, e->name);
    return false;
}

bool catalogue_locate(const char *name, char *file, size_t filelen, char *err, size_t errlen)
{
    const catalogue_entry *e = find_entry(name);
    if (!e) {
        snprintf(err, errlen, "'%s' is not a catalogue scene (see: accelbench list scenes)", name);
        return false;
    }
    return locate(e, file, filelen, err, errlen);
}

scene_t *catalogue_load(const char *name, char *err, size_t errlen)
{
    const catalogue_entry *e = find_entry(name);
    char file[4096];
    if (!e || !locate(e, file, sizeof file, err, errlen)) return NULL;
    scene_t *s = scene_load_mesh(e->name, file, err, errlen);
    if (s && e->default_view) {
        const scene_view *v = catalogue_view(e->name, e->default_view, err, errlen);
        if (!v || scene_view_apply(s, v, e->default_view, err, errlen) != 0) {
            scene_free(s);
            return NULL;
        }
    }
    return s;
}

/* --- named sets --- */

typedef struct {
    const char *name;
    const char *summary;
    const char *scenes; /* comma-separated; "" for set:scaling, the union of the families */
} scene_set;

static const scene_set sets[] = {
    {"set:medium", "the medium benchmark set: Debian-packaged meshes and three from the scene path",
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
    {"set:scaling:tree", "tree sizes 4..16 by 2 (63 to 262,143 primitives: spheres and cones)",
     "spd:tree:4,spd:tree:6,spd:tree:8,spd:tree:10,spd:tree:12,spd:tree:14,spd:tree:16"},
    {"set:scaling:rings", "rings sizes 1..12 (61 to 39,001 primitives: spheres and cones)",
     "spd:rings:1,spd:rings:2,spd:rings:3,spd:rings:4,spd:rings:6,spd:rings:8,spd:rings:10,spd:rings:12"},
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


/* --- the listing --- */

static void print_meshes(FILE *out)
{
    fprintf(out, "meshes (Debian packages, or by file name on the scene path: $ACCELBENCH_SCENES, then ../shared/scenes):\n");
    for (size_t i = 0; i < CATALOGUE_N; i++) {
        const catalogue_entry *e = &catalogue[i];
        char file[4096], why[8192];
        bool here = locate(e, file, sizeof file, why, sizeof why);
        if (e->package)
            fprintf(out, "%-16s %s  [%s%s]  %s\n", e->name, e->path, e->package, here ? "" : ", not installed", e->summary);
        else if (here)
            fprintf(out, "%-16s %s  [scene path]  %s\n", e->name, file, e->summary);
        else
            fprintf(out, "%-16s %s  [scene path, absent: from %s]  %s\n", e->name, e->path, e->origin, e->summary);
    }
}

static void print_views(FILE *out)
{
    fprintf(out, "views (NAME@VIEW; the default applies to NAME alone; any scene takes NAME@eye=X,Y,Z;at=X,Y,Z;up=X,Y,Z;fov=DEG):\n");
    for (size_t i = 0; i < VIEWS_N; i++) {
        const named_view *v = &views[i];
        const catalogue_entry *e = find_entry(v->scene);
        char label[64];
        snprintf(label, sizeof label, "%s@%s", v->scene, v->name);
        const scene_view *w = &v->view;
        fprintf(out, "  %-20s%s eye %g,%g,%g at %g,%g,%g up %g,%g,%g fov %g, %u lights: %s\n", label,
                e && e->default_view && !strcmp(e->default_view, v->name) ? " (default)" : "", w->eye.x, w->eye.y, w->eye.z,
                w->at.x, w->at.y, w->at.z, w->up.x, w->up.y, w->up.z, w->fov_deg, w->nlights, v->why);
    }
}

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
    print_meshes(out);
    print_views(out);
    fprintf(out, "sets (for --scenes; expanded to their scene lists):\n");
    for (size_t i = 0; i < SETS_N; i++) fprintf(out, "  %-20s %s\n", sets[i].name, sets[i].summary);
}
