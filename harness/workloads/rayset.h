/* rayset.h: a recorded, hashed, replayable set of rays.
 *
 * A ray set is made once per (scene, workload, seed) and every accelerator
 * traces exactly these rays in this order. It carries the query kind
 * (closest hit or any hit) and, for image-shaped workloads, the pixel each
 * ray belongs to (for per-pixel cost heat maps).
 *
 * File format (little-endian, written and read by this machine's ABI):
 *   char magic[8] = "ABRAYS3\n"; uint32 query; uint32 count;
 *   uint32 width, height, spp; uint32 has_pixels; uint64 seed; uint64 hash;
 *   char workload[32]; char scene[256];
 *   ray_t rays[count]          (40 bytes each, see prims/ray.h)
 *   uint32 pixel[count]        (when has_pixels)
 * hash is FNV-1a 64 over every byte of the file, the header's with hash
 * zero: no field changes unnoticed (version 1, "ABRAYS1", hashed the rays
 * only; such files are refused with a word to save them again). Version 3
 * ("ABRAYS3") gave each ray its origin primitive (ray_t.origin, in the
 * bytes version 2 kept 0 in): a version 2 file would read as "every ray
 * leaves primitive 0", so it is refused likewise. It is not the set's
 * rayset_hash(), which identifies the rays in the CSV (and covers origin).
 */
#ifndef ACCELBENCH_RAYSET_H
#define ACCELBENCH_RAYSET_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "../../prims/ray.h"

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
/* Reads and checks the file: magic, sizes, the stored hash, the header (a
 * workload this version makes with its query kind, terminated names, at
 * least one ray, an image size and samples when it has pixels), every
 * pixel index within the image, and every ray by the harness's one rule,
 * prims/ray.h ray_traceable (finite, components within RAY_COORD_MAX, a
 * nonzero direction, 0 <= tnear <= tfar): anything else is refused with
 * one line "PATH: ray I has ..." naming the ray. Workloads never make such
 * rays, so no accelerator sees one. */
rayset_t *rayset_load(const char *path, char *err, size_t errlen);
/* The same from a file's size bytes in memory; path names it in messages.
 * For the fuzzers (fuzz/). */
rayset_t *rayset_from_memory(const void *data, size_t size, const char *path, char *err, size_t errlen);
/* Store in a file's bytes the hash of what they hold now (no other check):
 * for the fuzzer and tests that craft files past the hash check to the
 * checks behind it. */
void rayset_file_rehash(void *data, size_t size);
/* The light index of every ray against the scene a loaded set is replayed
 * on (nlights lights, named scene): RAY_NO_LIGHT or below nlights. Returns
 * 0, or -1 with "PATH: ray I goes to light L, but scene 'S' has N lights". */
int rayset_check_lights(const rayset_t *rs, const char *path, const char *scene, uint32_t nlights, char *err,
                        size_t errlen);

/* The origin primitive of every ray against the scene (nprims primitives):
 * RAY_NO_ORIGIN or below nprims. Returns 0, or -1 with "PATH: ray I leaves
 * primitive P, but scene 'S' has N primitives". */
int rayset_check_origins(const rayset_t *rs, const char *path, const char *scene, uint32_t nprims, char *err,
                         size_t errlen);

/* The most rays a ray set holds (its count is a uint32, in memory and in
 * the file). */
#define RAYSET_RAYS_MAX UINT32_MAX

/* Heap bytes of a ray set of n rays (with each ray's pixel or not) as
 * rayset_push grows it: its capacity doubles from its first, so it holds
 * up to twice n. */
uint64_t rayset_bytes(uint64_t n, bool pixels);

#endif
