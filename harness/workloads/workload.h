/* workload.h: the ray workloads.
 *
 *   primary     pinhole camera rays, W x H pixels, spp samples per pixel
 *               (pixel centre for spp 1, stratified jitter otherwise), or
 *               (W+1) x (H+1) rays through pixel corners (SPD's rule)
 *   shadow      from every reference primary hit to every point light on
 *               the lit side of the surface; any-hit queries with ray->light set
 *   reflection  mirror bounces from reference hits, generations 1..depth
 *               (default 3), each generation traced by the reference
 *   diffuse     one cosine-distributed bounce from every primary hit
 *   random      segments between uniform random points of the scene box
 *   whitted:eye, whitted:reflected, whitted:refracted, whitted:shadow
 *               the SPD Readme's testing procedure (workload_whitted below):
 *               the whole Whitted ray tree of the (W+1) x (H+1) pixel-corner
 *               eye rays to depth 5, one ray set per ray type, so that every
 *               counter and time is split by type; `--workloads whitted`
 *               names all four
 *
 * Secondary rays are made from the REFERENCE accelerator's hits, so no
 * accelerator's bug changes the ray set. Ray sets are deterministic for a
 * (scene, workload, options, seed) and kept in scanline order (generation
 * by generation for reflections). */
#ifndef ACCELBENCH_WORKLOAD_H
#define ACCELBENCH_WORKLOAD_H

#include "../../accel/accel.h"
#include "rayset.h"
#include "resources.h"
#include "trace.h"

typedef struct {
    int width, height; /* image size */
    int spp;           /* samples per pixel */
    bool corners;      /* rays through pixel corners instead of centres */
    int depth;         /* reflection generations, whitted's tree depth; 0: each workload's default */
    uint64_t seed;
    int threads;       /* threads for tracing the reference while deriving rays */
} workload_opts;

typedef struct {
    const char *name;
    const char *summary;
    query_kind query;
    /* ref may be NULL for workloads that need no hits (primary, random).
     * Each make() estimates its ray set first and exits 2 with one line
     * when that is over the memory cap (scenes/memory_cap.h, --memcap). */
    rayset_t *(*make)(const scene_t *s, accel *ref, const workload_opts *o);
} workload_def;

extern const workload_def workload_table[];
const workload_def *workload_find(const char *name);

/* The defaults of workload_opts.depth 0. */
#define WORKLOAD_REFLECTION_DEPTH 3
#define WORKLOAD_WHITTED_DEPTH 5 /* the SPD Readme's "maximum tree depth is 5 (where the eye ray is of depth 1)" */

/* The whitted workload (workload_whitted.c): Whitted ray trees by the SPD
 * Readme's testing procedure (items 6-10), from the (W+1) x (H+1) eye
 * rays through the pixel corners (the SPD's 513 x 513 at --res 512x512),
 * to tree depth o->depth (default 5, the eye ray being depth 1). At every
 * hit of the tree (traced by the reference, generation by generation):
 * a shadow ray to every light the surface faces (spawn.h); below the
 * maximum depth, a reflection ray when the material has Ks > 0 or T > 0,
 * and a refraction ray when T > 0 unless totally internally reflected.
 * The four ray types are four ray sets (whitted:eye, :reflected,
 * :refracted, :shadow), each in generation order and each ray charged to
 * its eye ray's pixel; a part asked for alone costs only the tree it
 * needs (the eye rays none, the others the closest-hit tree). */
typedef enum { WHITTED_EYE, WHITTED_REFLECTED, WHITTED_REFRACTED, WHITTED_SHADOW, WHITTED_PARTS } whitted_part;
extern const char *const whitted_part_name[WHITTED_PARTS]; /* "whitted:eye", ... */
rayset_t *workload_whitted(const scene_t *s, accel *ref, const workload_opts *o, whitted_part part);

/* Whether workload w makes no rays on scene s by its own rules, whatever
 * the view and image: whitted:reflected where no material reflects or
 * transmits (Ks = T = 0), whitted:refracted where none transmits (T = 0).
 * Tests that ask every workload for rays excuse an empty set only then. */
bool workload_empty_by_rule(const workload_def *w, const scene_t *s);

/* For the workload files: a refusal (the table's make() has no error
 * path: "accelbench: ERR" and exit 2), the estimate against the memory cap
 * (refused when over), and the reference's hits for a set of closest-hit
 * rays (the caller frees them). */
__attribute__((noreturn)) void workload_refuse(const char *err);
void workload_require_memory(const char *name, const scene_t *s, const workload_opts *o);
answers_t *workload_reference_hits(accel *ref, const rayset_t *rays, const workload_opts *o);

/* Primary rays alone (also used by the renderer). */
rayset_t *workload_primary(const scene_t *s, const workload_opts *o);
/* The random workload, or NULL with the reason when the scene's box has no
 * two points a draw can tell apart (a point): zero-length segments are
 * redrawn at most 200 times in a row. The table's make() for "random"
 * prints that reason and exits 2. */
rayset_t *workload_random(const scene_t *s, const workload_opts *o, char *err, size_t errlen);

/* Secondary rays leave hits through spawn.h (origins, the shadow rule,
 * reflection and refraction), as the renderer's do. */

/* The rays a primary set of o has: W*H*spp, or (W+1)(H+1) corner rays. */
uint64_t workload_primary_rays(const workload_opts *o);
/* The ray set of workload `name` ("primary", "shadow", ...) under o for a
 * scene with nlights lights, made and traced in one cell: the larger of
 * what is alive while it is made (the primary rays and the reference's
 * answers it is derived from, the generations of reflection) and while the
 * cell traces it (the set, the reference's answers, the ill-posed count's,
 * the accelerator's and the timing's). Upper bounds: every primary ray is
 * taken to hit, every hit to see every light. */
resources_estimate workload_estimate(const char *name, const workload_opts *o, uint32_t nlights);
/* 0, or -1 with one line in err: more rays than a set holds, or more bytes
 * than the cap. scene names the scene in the message. */
int workload_check_memory(const char *name, const char *scene, const workload_opts *o, uint32_t nlights, char *err,
                          size_t errlen);
/* The estimate e of workload name against the set's limit and the cap (workload_check_memory's check). */
int workload_check_estimate(const char *name, const char *scene, const workload_opts *o, uint32_t nlights,
                            resources_estimate e, char *err, size_t errlen);
/* A part of the whitted workload: the eye rays (W+1)(H+1); the tree's
 * closest-hit generations at most double where the scene has a
 * transmitter (T > 0: reflection and refraction) and stay as wide where it
 * has none; every hit sees every light. workload_estimate("whitted:...")
 * assumes transmitters; the workload itself checks with what the scene
 * has (whitted_check_memory). */
resources_estimate whitted_estimate(const workload_opts *o, uint32_t nlights, bool transmitters, whitted_part part);
int whitted_check_memory(const char *scene, const workload_opts *o, uint32_t nlights, bool transmitters,
                         whitted_part part, char *err, size_t errlen);

#endif
