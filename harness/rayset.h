/* rayset.h: a recorded, hashed, replayable set of rays.
 *
 * A ray set is made once per (scene, workload, seed) and every accelerator
 * traces exactly these rays in this order. It carries the query kind
 * (closest hit or any hit) and, for image-shaped workloads, the pixel each
 * ray belongs to (for per-pixel cost heat maps).
 *
 * File format (little-endian, written and read by this machine's ABI):
 *   char magic[8] = "ABRAYS1\n"; uint32 query; uint32 count;
 *   uint32 width, height, spp; uint32 has_pixels; uint64 seed; uint64 hash;
 *   char workload[32]; char scene[256];
 *   ray_t rays[count]          (40 bytes each, see prims/ray.h)
 *   uint32 pixel[count]        (when has_pixels)
 */
#ifndef ACCELBENCH_RAYSET_H
#define ACCELBENCH_RAYSET_H

#include <stddef.h>
#include <stdint.h>
#include "../prims/ray.h"

typedef enum { QUERY_CLOSEST = 0, QUERY_ANY = 1 } query_kind;

typedef struct {
    char workload[32];
    char scene[256];
    uint64_t seed;
    query_kind query;
    uint32_t count, cap;
    ray_t *rays;
    uint32_t *pixel;          /* [count] pixel index y*width+x, or NULL */
    uint32_t width, height, spp;
    uint64_t hash;            /* rayset_hash() of the rays, set by rayset_seal() */
} rayset_t;

rayset_t *rayset_new(const char *workload, const char *scene, uint64_t seed, query_kind q);
/* Append a ray (and its pixel when the set tracks pixels). */
void rayset_push(rayset_t *rs, const ray_t *r, uint32_t pixel);
/* Compute and store the hash; call once all rays are in. */
void rayset_seal(rayset_t *rs);
/* FNV-1a 64 over the query kind, the count and the ray bytes. */
uint64_t rayset_hash(const rayset_t *rs);
void rayset_free(rayset_t *rs);

int rayset_save(const rayset_t *rs, const char *path, char *err, size_t errlen);
/* Reads and checks the file (magic, sizes, stored hash) and every ray:
 * a NaN or infinite origin or direction, a zero-length direction or an
 * empty [tnear, tfar] range is refused with the ray's index. Workloads
 * never make such rays, so accelerators may assume they do not occur. */
rayset_t *rayset_load(const char *path, char *err, size_t errlen);

#endif
