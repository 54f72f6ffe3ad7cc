/* scene_load.c: scene names to scenes.
 *
 * A name is resolved in this order: "spd:" generators, "gen:" generators,
 * "set:" (an error: sets are expanded by scene_set_expand(), not loaded),
 * "file:PATH", catalogue names (catalogue.c), then anything that looks like
 * a path. Any of them may end in @VIEW parts, applied after loading in
 * order: a catalogue scene's named view, or a view spec (view.c). They are
 * all checked before the scene is read, since a mesh can take seconds to
 * load and a typo in the view should not wait for it. */
#include "catalogue.h"
#include "compressed.h"
#include "nff.h"
#include "spd.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

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

/* spd:NAME, spd:NAME:SIZE, spd:NAME:t[RES], spd:NAME:SIZE:t[RES] into its
 * generator, size and resolution (0: true primitives); NULL with the
 * reason when it is none of them (an unknown or empty generator name too). */
static const spd_generator *parse_spd(const char *name, int *size, int *res, char *err, size_t errlen)
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
        (void)scene_spd(name, part[0], 0, 0, err, errlen); /* words the error, with the list of generators */
        return NULL;
    }
    *size = g->default_size, *res = 0;
    const char *tess = NULL;
    if (nparts > 3) {
        snprintf(err, errlen, "%s: expected spd:NAME[:SIZE][:t[RES]]", name);
        return NULL;
    }
    if (nparts >= 2) {
        if (nparts == 2 && part[1][0] == 't')
            tess = part[1];
        else if (!parse_int(part[1], 1, g->max_size, size)) {
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
        *res = 3; /* the SPD's OUTPUT_RESOLUTION */
        if (tess[1] && !parse_int(tess + 1, 1, 64, res)) {
            snprintf(err, errlen, "%s: tessellation resolution must be 1..64", name);
            return NULL;
        }
    }
    return g;
}

static scene_t *load_spd(const char *name, char *err, size_t errlen)
{
    int size, res;
    const spd_generator *g = parse_spd(name, &size, &res, err, errlen);
    return g ? scene_spd(name, g->name, size, res, err, errlen) : NULL;
}

static scene_t *read_file(const char *name, const char *path, char *err, size_t errlen);

/* A user's file: read_file's scene, whose made-up camera and lights (a
 * file without a view) stand on the scene's own up axis, its thinnest
 * extent (SCENE_UP_AUTO), since such files come z up as often as y up. */
static scene_t *load_file(const char *name, const char *path, char *err, size_t errlen)
{
    scene_t *s = read_file(name, path, err, errlen);
    if (s && (s->made_up & SCENE_MADE_CAMERA)) scene_set_up_axis(s, SCENE_UP_AUTO);
    return s;
}

/* A file: NFF by its extension (also under .gz/.xz/.bz2), else assimp. */
static scene_t *read_file(const char *name, const char *path, char *err, size_t errlen)
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

/* Whether a name that is not a scene name should be read as a file: it
 * exists, or it has a directory part or an extension. */
static bool looks_like_path(const char *name)
{
    if (compressed_exists(name) || strchr(name, '/')) return true;
    const char *dot = strrchr(name, '.');
    return dot && dot != name && dot[1];
}

/* The scene a name (without views) stands for. */
static scene_t *load_base(const char *name, char *err, size_t errlen)
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
    if (catalogue_has(name)) return catalogue_load(name, err, errlen);
    if (looks_like_path(name)) return load_file(name, name, err, errlen);
    snprintf(err, errlen, "unknown scene '%s' (see: accelbench list scenes)", name);
    return NULL;
}

#define MAX_VIEWS 8

typedef struct {
    char label[256];
    scene_view view;
} view_part;

/* Split name into the scene and its '@' view parts: the views start at the
 * first '@' after the last '/' (a folder may have '@' in its name), unless
 * the whole name is a file. Returns the number of parts, or -1 (err). */
static int split_views(const char *name, char *base, size_t baselen, view_part *parts, char *err, size_t errlen)
{
    struct stat st;
    const char *slash = strrchr(name, '/');
    const char *at = stat(name, &st) == 0 ? NULL : strchr(slash ? slash : name, '@');
    size_t n = at ? (size_t)(at - name) : strlen(name);
    if (n >= baselen) {
        snprintf(err, errlen, "%.64s...: name too long", name);
        return -1;
    }
    if (at && n == 0) {
        snprintf(err, errlen, "'%s': no scene before the '@' (NAME@VIEW)", name);
        return -1;
    }
    memcpy(base, name, n);
    base[n] = '\0';
    int count = 0;
    for (const char *p = at; p; p = strchr(p + 1, '@')) {
        const char *next = strchr(p + 1, '@');
        size_t len = next ? (size_t)(next - p - 1) : strlen(p + 1);
        if (count == MAX_VIEWS || len >= sizeof parts[0].label) {
            snprintf(err, errlen, "%s: too many or too long @VIEW parts", name);
            return -1;
        }
        view_part *v = &parts[count++];
        memcpy(v->label, p + 1, len);
        v->label[len] = '\0';
        char why[512];
        if (strchr(v->label, '=')) {
            if (scene_view_parse(v->label, &v->view, why, sizeof why) != 0) {
                snprintf(err, errlen, "scene '%s': view %s", name, why);
                return -1;
            }
        } else {
            const scene_view *named = catalogue_view(base, v->label, why, sizeof why);
            if (!named) {
                snprintf(err, errlen, "scene '%s': %s", name, why);
                return -1;
            }
            v->view = *named;
        }
    }
    return count;
}

scene_t *scene_load(const char *name, char *err, size_t errlen)
{
    char base[1024];
    view_part parts[MAX_VIEWS];
    if (!name) name = "";
    int nviews = split_views(name, base, sizeof base, parts, err, errlen);
    if (nviews < 0) return NULL;
    scene_t *s = load_base(base, err, errlen);
    if (!s) return NULL;
    for (int i = 0; i < nviews; i++) {
        char why[512];
        if (scene_view_apply(s, &parts[i].view, parts[i].label, why, sizeof why) != 0) {
            snprintf(err, errlen, "scene '%s': %s", name, why);
            scene_free(s);
            return NULL;
        }
    }
    snprintf(s->name, sizeof s->name, "%s", name);
    return s;
}

int scene_check(const char *name, char *err, size_t errlen)
{
    char base[1024], file[4096];
    view_part parts[MAX_VIEWS];
    if (split_views(name ? name : "", base, sizeof base, parts, err, errlen) < 0) return -1;
    if (catalogue_has(base) && !catalogue_locate(base, file, sizeof file, err, errlen)) return -1;
    int size, res; /* a generator's name, size and resolution, as load_spd reads them */
    if (strncmp(base, "spd:", 4) == 0 && !parse_spd(base, &size, &res, err, errlen)) return -1;
    if (!strncmp(base, "spd:", 4) || !strcmp(base, "gen:room") || !strcmp(base, "gen:room:empty") || catalogue_has(base))
        return 0;
    /* Every other name is read as load_base reads it, so that a typo or a missing file fails before the scenes
     * before it have run: a file (its disk file, the archive of ARCHIVE#MEMBER) must exist and be readable. */
    const char *path = !strncmp(base, "file:", 5) ? base + 5 : base;
    if (path == base && !looks_like_path(base)) {
        scene_t *none = load_base(base, err, errlen); /* words the error (unknown scene, gen:, set:) */
        if (!none) return -1;
        scene_free(none);
        return 0;
    }
    if (!*path) {
        snprintf(err, errlen, "file: needs a path, as in file:PATH");
        return -1;
    }
    char disk[4096];
    struct stat st;
    compressed_disk_file(path, disk, sizeof disk);
    if (stat(disk, &st) != 0 || access(disk, R_OK) != 0) {
        snprintf(err, errlen, "scene '%s': %s: %s", name, disk, strerror(errno));
        return -1;
    }
    if (S_ISDIR(st.st_mode)) {
        snprintf(err, errlen, "scene '%s': %s is a folder, not a scene file", name, disk);
        return -1;
    }
    return 0;
}

bool scene_generated(const char *name, uint64_t *prims)
{
    char base[1024], err[512];
    view_part parts[MAX_VIEWS];
    *prims = 0;
    if (split_views(name ? name : "", base, sizeof base, parts, err, sizeof err) < 0) return false;
    if (!strcmp(base, "gen:room") || !strcmp(base, "gen:room:empty")) return true;
    int size, res;
    const spd_generator *g = strncmp(base, "spd:", 4) ? NULL : parse_spd(base, &size, &res, err, sizeof err);
    if (g) *prims = spd_prims(g, size, res);
    return g != NULL;
}

bool scene_catalogue_available(const char *name, char *where, size_t len)
{
    char base[1024];
    view_part parts[MAX_VIEWS];
    if (split_views(name ? name : "", base, sizeof base, parts, where, len) < 0) return false;
    return catalogue_locate(base, where, len, where, len);
}
