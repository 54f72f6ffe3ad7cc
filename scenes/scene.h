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

/* Whitted-style material: colour, diffuse weight, mirror weight. */
typedef struct {
    vec3 color;
    float kd, ks;
} material_t;

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
    box3 bounds;         /* == prims.box */
} scene_t;

/* Make a scene from a name:
 *   spd:balls:SIZE          SPD sphereflake, true spheres (SIZE 1..7, default 4)
 *   spd:balls:SIZE:t[RES]   the same tessellated into triangles (RES default 3)
 *   NAME                    a catalogue mesh (see scene_catalogue_print), e.g. bunny
 *   PATH                    a mesh file read through assimp (OBJ, PLY, OFF, STL,
 *                           glTF, ...), optionally compressed (.gz, .xz, ...),
 *                           or ARCHIVE#MEMBER for one file in a tarball (see
 *                           compressed.h); "file:PATH" forces the file reading.
 * Returns the scene, or NULL with a one-line reason in err that names the
 * file (and line where the loader knows it). */
scene_t *scene_load(const char *name, char *err, size_t errlen);
void scene_free(scene_t *s);

/* Print the catalogue: one line per name, with its source and summary. */
void scene_catalogue_print(FILE *out);

/* Helpers for scene makers (loaders and generators). A scene_t comes only
 * from scene_new() (it carries private bookkeeping behind the public
 * struct) and goes back through scene_free(). Out of memory aborts, as in
 * the primitive store. */
scene_t *scene_new(const char *name);
/* Returns the new material's index; at most 65536 materials. */
uint16_t scene_add_material(scene_t *s, material_t m);
void scene_add_light(scene_t *s, vec3 p);
/* Record the material of every primitive added since the last call. */
void scene_set_material_upto(scene_t *s, uint16_t material);
/* Finish: prims_finish, bounds, and defaults for what the source did not
 * give. has_camera false: a camera looking at the bounds centre from the
 * (1, 0.6, 0.8) direction with y up (z up, looking from (1, 0.8, 0.6), when
 * the bounds are thinnest in y, as for z-up models), far enough that the bounding sphere
 * fills the 45 degree view, 512x512. No lights: two point lights above and
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
