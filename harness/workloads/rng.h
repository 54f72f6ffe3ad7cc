/* rng.h: counter-based random numbers.
 *
 * Every random number is a pure function of (seed, stream, index), so a
 * ray set is the same whatever the thread count or the order rays are
 * made in. The mixer is SplitMix64's finalizer (Steele, Lea, Flood,
 * "Fast Splittable Pseudorandom Number Generators", OOPSLA 2014). */
#ifndef ACCELBENCH_RNG_H
#define ACCELBENCH_RNG_H

#include <stdint.h>

static inline uint64_t rng_mix(uint64_t z)
{
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* A uniform float in [0, 1) for (seed, stream, index, dimension). */
static inline float rng_float(uint64_t seed, uint32_t stream, uint64_t index, uint32_t dim)
{
    uint64_t h = rng_mix(seed ^ rng_mix(((uint64_t)stream << 32 | dim) ^ rng_mix(index)));
    return (float)(h >> 40) * (1.0f / 16777216.0f);
}

#endif
