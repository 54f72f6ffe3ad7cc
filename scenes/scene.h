/* scene.h: a scene is primitives plus what a workload needs to make rays
 * (camera, point lights) and what a renderer needs to shade (materials).
 *
 * Scenes are named on the command line (see scene_load()); every source,
 * mesh file or generator, ends in the same scene_t, and nothing downstream
 * knows where a scene came from. */
#ifndef ACCELBENCH_SCENE_H
#define ACCELBENCH_SCENE_H

#include <stdio.h>
#include "../prims/prims.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Pinhole camera, NFF style: fov_deg is the full angle between the centres
 * of the top and bottom pixel rows; the image is square-pixel, so the
 * horizontal angle follows from width/height. */
typedef struct {
    vec3 from, at, up;
    float fov_deg;
    float hither;      /* the near distance of eye rays (tnear) */
    int width, height; /* the source's resolution; workloads may override */
} camera_t;

/* Whitted-style material, NFF's `f R G B Kd Ks Shine T ior` without the
 * Phong exponent: colour, diffuse weight, mirror weight, transmittance and
 * index of refraction (T > 0: a transmitter, refracting with ior by
 * Snell's law; ior matters only then). */
typedef struct {
    vec3 color;
    float kd, ks;
    float t, ior;
} material_t;

/* Whether two materials are the same (loaders share repeated ones). */
static inline bool material_equal(material_t a, material_t b)
{
    return a.color.x == b.color.x && a.color.y == b.color.y && a.color.z == b.color.z && a.kd == b.kd &&
           a.ks == b.ks && a.t == b.t && a.ior == b.ior;
}

typedef struct scene {
    char name[256];      /* as given on the command line */
    char source[512];    /* what it was made from: a file path or a generator with parameters */
    prims_t prims;
    camera_t camera;
    uint32_t nlights;
    vec3 *lights;        /* point lights */
    uint32_t nmaterials;
    material_t *materials;
    uint16_t *prim_material; /* [prims.count] index into materials */
    vec3 background;
    /* Per-vertex shading normals (NFF `pp` patches, the SPD teapot): NULL
     * when the source gave none, else [prims.nverts] unit vectors, zero for
     * a vertex without one. A triangle or polygon whose every vertex has a
     * normal is smooth: scene_shading_normal() interpolates them. */
    vec3 *normals;
    box3 bounds;         /* == prims.box */
    char view[256];      /* where the camera came from: "automatic" (scene_finish's), "source" (the
                          * file's or generator's own), else the views applied, '@'-joined ("nave",
                          * "nave@eye=...") */
    unsigned made_up;    /* SCENE_MADE_CAMERA, SCENE_MADE_LIGHTS: what scene_finish made up because the
                          * source had none, and scene_set_up_axis may build again around another axis */
} scene_t;

#define SCENE_MADE_CAMERA 1u
#define SCENE_MADE_LIGHTS 2u

/* Make a scene from a name (scene_load.c):
 *   spd:balls:SIZE          SPD sphereflake, true spheres (SIZE 1..7, default 4)
 *   spd:balls:SIZE:t[RES]   the same tessellated into triangles (RES default 3)
 *   NAME                    a catalogue mesh (see scene_catalogue_print), e.g. bunny
 *   PATH                    a mesh file read through assimp (OBJ, PLY, OFF, STL,
 *                           glTF, ...), optionally compressed (.gz, .xz, ...),
 *                           or ARCHIVE#MEMBER for one file in a tarball (see
 *                           compressed.h); "file:PATH" forces the file reading.
 *   any of these @VIEW      then a view: a catalogue scene's named view
 *                           (sibenik@nave) or a view spec (scene_view_parse:
 *                           bunny@eye=1,2,3;fov=30, x.obj@up=Z;light=0,0,9);
 *                           several apply in order
 *                           (sibenik@nave@fov=60). The views are the '@' parts
 *                           after the last '/', unless the whole name is a file.
 * A catalogue scene starts from its default view when it has one (sibenik
 * and sponza look from inside). A file without a camera of its own (PATH,
 * file:PATH) is seen upright on its thinnest extent (SCENE_UP_AUTO), lit by
 * the automatic lights above it; a catalogue mesh keeps SCENE_UP_CATALOGUE.
 * Returns the scene, named as given, or NULL with a one-line reason in err
 * that names the file (and line where the loader knows it), or the view and
 * the known view names. */
scene_t *scene_load(const char *name, char *err, size_t errlen);
void scene_free(scene_t *s);
/* What scene_load(name) would refuse without reading any file: a bad or
 * unknown view, a catalogue mesh that is absent, an unknown name, a scene
 * file that does not exist, cannot be read or is a folder. Returns 0, or -1 with
 * scene_load's one-line reason; so a command can refuse before its work. */
int scene_check(const char *name, char *err, size_t errlen);

/* Whether name (views and all) is a generated scene scene_load makes
 * without reading any file (spd:..., gen:room...), with the primitives it
 * would have in *prims, counted without generating it (0 for gen:room's
 * fixed hall of under 100). For callers that bound their work before
 * loading: the fuzzers, a resource estimate. */
bool scene_generated(const char *name, uint64_t *prims);

/* Print the catalogue: one line per name, with its source and summary,
 * marking files that are not installed or not on the scene path, then each
 * scene's named views. */
void scene_catalogue_print(FILE *out);

/* Whether catalogue scene `name` (NAME or NAME@VIEW) can be loaded here:
 * its file is present (not read) and the view, if any, is known. True with
 * the file's path in where; false with the one-line reason scene_load would
 * give (the file, where it was looked for, where to get it). For callers
 * that fall back to a generated stand-in on a machine without the scene. */
bool scene_catalogue_available(const char *name, char *where, size_t len);

/* --- the scene path (scene_path.c) ---
 * Meshes from public repositories are not part of the project (only
 * generated data and what Debian ships is): they are found by file name in
 * the folders of $ACCELBENCH_SCENES (colon-separated), then in
 * $ACCELBENCH_SHARED_SCENES, which defaults to two folders: ../shared/scenes
 * beside the checkout, where developers and CI have them, and the user
 * folder scripts/get-scenes.sh fills (set it empty to search only
 * $ACCELBENCH_SCENES, as on a machine without them). */

/* Find `file` on the scene path: true with its full path in out. where
 * always gets the folders searched, ", "-separated, in order. */
bool scene_path_find(const char *file, char *out, size_t outlen, char *where, size_t wherelen);

/* The user folder of the scene path: $XDG_CACHE_HOME/accelbench/scenes, else
 * $HOME/.cache/accelbench/scenes; false when neither variable is an
 * absolute path. */
bool scene_path_user_folder(char *out, size_t outlen);

/* --- views (view.c) ---
 * A view moves the camera and, for a named view of a closed interior whose
 * default lights hang outside it, the lights. A view spec gives any of
 * eye=X,Y,Z;at=X,Y,Z;up=X,Y,Z;fov=DEG (each at most once, in any order);
 * what it leaves out stays as the scene has it. */
#define SCENE_VIEW_EYE 1u
#define SCENE_VIEW_AT 2u
#define SCENE_VIEW_UP 4u
#define SCENE_VIEW_FOV 8u
#define SCENE_VIEW_MAX_LIGHTS 4

/* An up axis (a view's up=X|Y|Z|auto, the command line's --up). AUTO is
 * the scene's thinnest bounding-box extent, ties going to Y, then Z: a
 * terrain, a floor plan or a city block is flattest along its up axis.
 * CATALOGUE is the catalogue meshes' automatic camera (Y up, Z when Y alone
 * is the thinnest extent): the camera their named views, recorded results
 * and tests are made for, so it does not follow the rule for user files. */
enum { SCENE_UP_NONE, SCENE_UP_X, SCENE_UP_Y, SCENE_UP_Z, SCENE_UP_AUTO, SCENE_UP_CATALOGUE };

typedef struct {
    unsigned given;   /* SCENE_VIEW_* bits: the parts set */
    vec3 eye, at, up;
    float fov_deg;    /* full vertical angle, as camera_t */
    uint32_t nlights; /* > 0: these replace the scene's lights */
    vec3 lights[SCENE_VIEW_MAX_LIGHTS];
    int up_axis;      /* up=X|Y|Z|auto: a SCENE_UP_* (up is then unused); SCENE_UP_NONE for up=X,Y,Z */
} scene_view;

/* Parse a view spec strictly: numbers whole and finite, exactly three per
 * vector, fov in (0, 180), no unknown, repeated or empty part. Two parts go
 * beyond the camera: up=X|Y|Z|auto (an axis, see scene_set_up_axis) and
 * light=X,Y,Z, repeatable up to SCENE_VIEW_MAX_LIGHTS times (the lights
 * then replace the scene's). Returns 0, or -1 with a one-line reason naming
 * the bad part in err. */
int scene_view_parse(const char *spec, scene_view *v, char *err, size_t errlen);
/* Apply v to s and append label to s->view. Fails (-1, err) when the result
 * is no camera: eye at `at`, up zero or along the view direction. */
int scene_view_apply(scene_t *s, const scene_view *v, const char *label, char *err, size_t errlen);
/* The command line's --view, --up AXIS and --light X,Y,Z as one view spec:
 * append option's value to spec (--view SPEC as it is, --up as up=AXIS,
 * --light as light=X,Y,Z; ';'-joined) and parse the whole, so that a
 * conflict (--up with a --view that has up=) is found here. Returns 0, or -1
 * with "--OPTION VALUE: reason" in err. */
int scene_view_option(char *spec, size_t speclen, const char *option, const char *value, char *err, size_t errlen);
/* The unit vector of axis (SCENE_UP_X .. SCENE_UP_AUTO) for s. */
vec3 scene_up_vector(const scene_t *s, int axis);
/* Turn s's camera up to axis. A camera scene_finish made up is made again
 * around the axis (eye above the centre along it), and so are the lights
 * when they were made up too; a camera of the source's or a view's keeps
 * its eye and look-at and takes the axis as its up vector (which the
 * caller checks with scene_check_view). */
void scene_set_up_axis(scene_t *s, int axis);

/* --- the ranges every scene lies in (scene_range.c) ---
 * Tracing works in single precision, so scene_finish refuses, with exit 2
 * and a line naming the culprit, any scene whose numbers would overflow a
 * float formula of tracing; nothing downstream (no accelerator, workload or
 * renderer) needs a check of its own. Loaders that know the file line
 * check the same bounds as they read (NFF, OBJ and OFF), so that their
 * message names the line.
 *
 * SCENE_COORD_MAX = 2^30 (1.07e9) for every coordinate of the geometry:
 * vertices, and the boxes of spheres and cones (centre +- radius, so radii
 * are at most 2^30 too). Why 2^30: the highest power of a length that a
 * float formula of tracing forms is the fourth, in the float length of a
 * triangle's edge cross product (prim_normal, from which every secondary
 * ray leaves a triangle, hence the verify and render normals too): with
 * edge components up to 2 * 2^30, the cross product's components are at
 * most 2 (2^31)^2 = 2^63 and its squared length 3 * 2^126 < FLT_MAX
 * (2^128). Everything else is of lower degree and so keeps a wide margin:
 * the box diagonal (< 2^32), the watertight triangle test's hit distance
 * numerator (a cubic, < 2^110 for origins within SCENE_VIEW_MAX), Embree's
 * own cubic of the same kind, grid cell arithmetic (volume < 2^93), SAH
 * areas, sphere quadrics (< 2^80). A mesh in millimetres a thousand
 * kilometres across still fits.
 *
 * Cones also need an axis a float has a direction for: |apex - base| > 0
 * as the kernel computes it, and a slope |apex_radius - base_radius| /
 * |apex - base| of at most SCENE_CONE_SLOPE_MAX = 2^24 (flatter than 6e-8
 * rad from a disk), since the kernel squares rb + slope * h for heights h
 * up to 2^37: (2^24 2^37)^2 = 2^122 stays finite. Sphere and cone radii
 * may be as small as a float allows: a radius too small to square only
 * misses.
 *
 * SCENE_VIEW_MAX = 2^36 (6.9e10) for the points where rays start or end
 * outside the geometry: the camera's eye and look-at point, the lights,
 * the hither distance (primary rays' tnear) and the components of the up
 * vector. 2^36 holds the automatic camera and lights of any scene within
 * SCENE_COORD_MAX (at most 2^34 from the origin), and keeps every
 * workload's ray origin and the t where it meets the geometry (< 2^37)
 * 2^23 below RAY_COORD_MAX (2^60, Embree's limit less a margin; prims/ray.h).
 * The view direction (at - eye) and the up vector must also be at least
 * SCENE_VIEW_MIN_LEN = 2^-40 long and 1e-6 rad apart, so that the float
 * camera frame normalises without underflow (a cross product of at least
 * 2^-60, squared 2^-120, above the smallest normal float 2^-126). */
#define SCENE_COORD_MAX 0x1p30f
#define SCENE_CONE_SLOPE_MAX 0x1p24f
#define SCENE_VIEW_MAX 0x1p36f
#define SCENE_VIEW_MIN_LEN 0x1p-40f
/* The bounds as messages print them. */
#define SCENE_COORD_RANGE "within +-2^30 (1.07e9)"
#define SCENE_VIEW_RANGE "within +-2^36 (6.87e10)"

/* Whether x is a coordinate the geometry may have (NaN and inf are not). */
static inline bool scene_coord_ok(float x) { return fabsf(x) <= SCENE_COORD_MAX; }
/* Whether x may be a coordinate of the camera or a light. */
static inline bool scene_view_coord_ok(float x) { return fabsf(x) <= SCENE_VIEW_MAX; }
/* Whether the box of a sphere or a cone's end, centre +- r, is in range. */
static inline bool scene_ball_ok(vec3 c, float r)
{
    return scene_coord_ok(r) && scene_coord_ok(c.x - r) && scene_coord_ok(c.x + r) && scene_coord_ok(c.y - r) &&
           scene_coord_ok(c.y + r) && scene_coord_ok(c.z - r) && scene_coord_ok(c.z + r);
}

/* What is wrong with a cone for these ranges ("reaches outside the scene
 * range ...", "is flatter than ..."), or NULL. */
const char *scene_cone_problem(cone_t c);
/* The geometry's ranges (above), before prims_finish: every vertex (even
 * one no primitive uses), every sphere and cone. Returns 0, or -1 with
 * "vertex 3 (0 3e+38 0) ..." (the store's index, and the primitive's id)
 * in err. */
int scene_check_geometry(const scene_t *s, char *err, size_t errlen);
/* A camera and lights: finite and within SCENE_VIEW_MAX, eye != at, an up
 * vector the frame can use, 0 < fov < 180, 0 <= hither <= SCENE_VIEW_MAX.
 * Returns 0, or -1 with a reason naming the part ("light 2 (...) is
 * outside the view range ..."). scene_finish and scene_view_apply call it. */
int scene_check_view(const camera_t *c, const vec3 *lights, uint32_t nlights, char *err, size_t errlen);

/* Helpers for scene makers (loaders and generators). A scene_t comes only
 * from scene_new() (it carries private bookkeeping behind the public
 * struct) and goes back through scene_free(). Out of memory is one line and
 * exit 2, as in the primitive store (prims/checked_alloc.h). */
scene_t *scene_new(const char *name);
/* Returns the new material's index; at most 65536 materials. */
uint16_t scene_add_material(scene_t *s, material_t m);
void scene_add_light(scene_t *s, vec3 p);
/* Room for the normals of vertices [0, n) at exactly that size, for a maker
 * that knows its vertex count (the SPD generators reserve their store so). */
void scene_reserve_vertex_normals(scene_t *s, uint32_t n);
/* Give vertex v (of the primitive store) the shading normal n, normalised
 * (one within 1e-6 of unit length is kept as given, so a round trip through
 * a file keeps it bit for bit); a zero or non-finite n gives it none. */
void scene_set_vertex_normal(scene_t *s, uint32_t v, vec3 n);
/* Whether primitive id has per-vertex normals (a smooth triangle or
 * polygon: every one of its vertices has one). */
bool scene_prim_smooth(const scene_t *s, uint32_t id);
/* The unit normal that shades the surface point sp of primitive id
 * (prim_surface_point's): the vertex normals interpolated with sp's
 * barycentric weights on its (ear) triangle for a smooth primitive, else
 * sp.normal. Not turned toward any ray. */
vec3 scene_shading_normal(const scene_t *s, uint32_t id, const surface_point *sp);
/* Record the material of every primitive added since the last call. */
void scene_set_material_upto(scene_t *s, uint16_t material);
/* Finish: the geometry's ranges (scene_check_geometry), prims_finish,
 * bounds, defaults for what the source did not give, and the view's
 * ranges (scene_check_view). has_camera false: a camera looking at the bounds centre from the
 * (1, 0.6, 0.8) direction with y up (z up, looking from (1, 0.8, 0.6), when
 * the bounds are thinnest in y: SCENE_UP_CATALOGUE; scene_load turns a
 * user's mesh file to SCENE_UP_AUTO with scene_set_up_axis), far enough that
 * the bounding sphere fills the 45 degree view, 512x512. No lights: two point lights above and
 * behind the camera, outside the bounds. Primitives without a material: a
 * grey one (kd 0.8, ks 0.2). Returns 0, or -1 with "SOURCE: reason" in err
 * (SOURCE is s->source, else s->name), e.g. "x.obj: no primitives". */
int scene_finish(scene_t *s, bool has_camera, char *err, size_t errlen);

/* Scene makers (scene_load() dispatches to these). Each returns a finished
 * scene or NULL with a one-line reason; name goes into scene_t.name. */

/* A mesh file through assimp; path may be compressed or ARCHIVE#MEMBER
 * (see compressed.h). Points and lines are skipped and counted in
 * scene_t.source; degenerate triangles are kept. */
scene_t *scene_load_mesh(const char *name, const char *path, char *err, size_t errlen);
/* The same from bytes already in memory (size of them, data[size] ==
 * '\0'): file_name's extension ("x.obj") tells the format, path names the
 * file in messages and is where referenced files (.mtl, .bin) are looked
 * for beside. For the fuzzers (fuzz/), and any caller with the bytes. */
scene_t *scene_mesh_from_memory(const char *name, const char *path, const char *file_name, const char *data,
                                size_t size, char *err, size_t errlen);
/* The same with assimp in this process, not in a child (isolate.h):
 * the same checks, scene and messages, but a file that crashes assimp
 * crashes the caller. For the fuzzers only, whose process is the
 * isolation (and where a fork per input costs most of the time). */
scene_t *scene_mesh_from_memory_in_process(const char *name, const char *path, const char *file_name,
                                           const char *data, size_t size, char *err, size_t errlen);
/* SPD balls (sphereflake), size 1..7; tess_res 0 for true spheres, else
 * 1..64 for cube-sphere triangles (12*tess_res^2 per sphere). */
scene_t *scene_spd_balls(const char *name, int size, int tess_res, char *err, size_t errlen);
/* Spheres in the sphereflake of a size: sum_{k=0..size} 9^k. */
uint64_t spd_balls_sphere_count(int size);

/* Any SPD database (scenes/spd.h): generator "balls", "gears", "mount",
 * "rings", "teapot", "tetra", "tree", "lattice", "shells", "jacks" or
 * "sombrero" at a size (each has its range, see scene_catalogue_print);
 * tess_res 0 for true primitives, else 1..64 for the triangle-only form.
 * scene_load() names them spd:NAME, spd:NAME:SIZE, spd:NAME:t[RES] and
 * spd:NAME:SIZE:t[RES] (RES default 3, the SPD's OUTPUT_RESOLUTION). The
 * camera, lights, background and materials are the SPD view's. Errors:
 * "unknown SPD database 'x' (known: balls, ...)", "spd:gears:99: size must
 * be 1..12", or too many primitives for the store. */
scene_t *scene_spd(const char *name, const char *generator, int size, int tess_res, char *err, size_t errlen);

/* gen:room and gen:room:empty (gen_room.c): a 10000 x 8000 x 600 hall with
 * x and z in the thousands and the floor near height 0, no plane axis-aligned, with coplanar
 * overlapping decals, sliver trims along the corners and (unless empty)
 * needles, a slanted panel, a box, two spheres and a cylinder column; two
 * lights inside. The empty one is convex and lit from inside: nothing in it
 * can shadow anything. */
scene_t *scene_gen_room(const char *name, bool empty, char *err, size_t errlen);

/* Named sets of scenes for the scaling plots: for a set name ("set:medium",
 * "set:spd", "set:scaling", "set:scaling:FAMILY"; scene_catalogue_print
 * lists them) write its comma-separated scene names into out and return 1;
 * return 0 if name is not a set, -1 if it is one but does not fit in
 * outlen (out then holds "" ). */
int scene_set_expand(const char *name, char *out, size_t outlen);

#ifdef __cplusplus
}
#endif

#endif
