/* shuffle.h: seeded pseudo-random insertion orders for the builders whose
 * trees depend on the order they see their primitives in (Goldsmith and
 * Salmon's insertion, accel/bvh/build_insert.c and accel/bvh_gs/build_gs.c).
 *
 * The generator is splitmix64 (Steele, Lea, Flood, "Fast Splittable
 * Pseudorandom Number Generators", OOPSLA 2014): any 64-bit seed, 0
 * included, gives a full-period stream, so a seed needs no care. The
 * shuffle is Fisher-Yates (Knuth, TAOCP vol. 2, Algorithm P), drawing j
 * uniformly-enough by a 64-bit remainder (bias below 2^-32 for n < 2^32).
 * Deterministic: the same seed gives the same order on every machine. */
#ifndef ACCELBENCH_SHUFFLE_H
#define ACCELBENCH_SHUFFLE_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The next number of the stream whose state is *s. */
static inline uint64_t splitmix64_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Permute ids[0 .. n) by the stream seeded with seed. */
static inline void shuffle_ids(uint32_t *ids, uint32_t n, uint64_t seed)
{
    uint64_t s = seed;
    for (uint32_t i = n > 0 ? n - 1 : 0; i > 0; i--) {
        uint32_t j = (uint32_t)(splitmix64_next(&s) % ((uint64_t)i + 1));
        uint32_t t = ids[i];
        ids[i] = ids[j];
        ids[j] = t;
    }
}

#ifdef __cplusplus
}
#endif

#endif
