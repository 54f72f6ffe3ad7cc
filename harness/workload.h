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
 *
 * Secondary rays are made from the REFERENCE accelerator's hits, so no
 * accelerator's bug changes the ray set. Ray sets are deterministic for a
 * (scene, workload, options, seed) and kept in scanline order (generation
 * by generation for reflections). */
#ifndef ACCELBENCH_WORKLOAD_H
#define ACCELBENCH_WORKLOAD_H

#include "../accel/accel.h"
#include "rayset.h"

typedef struct {
    int width, height; /* image size */
    int spp;           /* samples per pixel */
    bool corners;      /* rays through pixel corners instead of centres */
    int depth;         /* reflection generations */
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

/* Primary rays alone (also used by the renderer). */
rayset_t *workload_primary(const scene_t *s, const workload_opts *o);
/* The random workload, or NULL with the reason when the scene's box has no
 * two points a draw can tell apart (a point): zero-length segments are
 * redrawn at most 200 times in a row. The table's make() for "random"
 * prints that reason and exits 2. */
rayset_t *workload_random(const scene_t *s, const workload_opts *o, char *err, size_t errlen);

/* Where secondary rays leave a hit: the origin, on the incoming ray's side
 * of the surface in exact arithmetic (prim_surface_point and
 * offset_ray_origin: pbrt-v4's error bounds), and the unit geometric normal
 * turned to face the incoming ray. Every workload and the renderer spawn
 * through this one function. */
void hit_frame(const scene_t *s, const ray_t *r, const hit_t *h, vec3 *org, vec3 *n);

#endif
