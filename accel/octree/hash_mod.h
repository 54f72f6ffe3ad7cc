/* hash_mod.h: the table of Glassner's octree (octree_glassner.c) from node
 * names to nodes: bucket = key modulo a prime size, chained, keys up to 96
 * bits, built once. */
#ifndef ACCELBENCH_HASH_MOD_H
#define ACCELBENCH_HASH_MOD_H

#include <assert.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* hash_mod: the table of Glassner's octree (A. S. Glassner, "Space
 * Subdivision for Fast Ray Tracing", IEEE CG&A 4(10), 1984; the survey of
 * Arvo and Kirk, 1989, s5.1): the bucket of a key is the key modulo the
 * table's size, which Glassner found a good hash for his node names. The
 * caller passes the bucket ("home"), so a key built digit by digit (a
 * child's name is radix * parent + digit) has its home updated
 * incrementally by hash_mod_extend, exact for keys of any length, with no
 * division of the whole key.
 *
 * Collisions are chained, not probed: siblings' names differ in the last
 * digit only, so their homes are consecutive, and open addressing with
 * linear probing turns such runs into long probe sequences (measured on a
 * deep octree at load 1/2: 8.5 slots per lookup on average, runs of 61);
 * in separate buckets they never meet. The table is built once from all
 * its entries (hash_mod_build), each bucket's entries stored contiguously
 * (start[] offsets, as a CSR array), then only read: no insertion, no
 * removal. Concurrent readers are fine.
 *
 * Keys are up to 96 bits (a 64-bit low word and a 32-bit high word), never
 * 0 and never twice.
 *
 * Memory layout: start[size + 1] uint32 offsets (4 bytes a bucket) and
 * entries[count] of 16 bytes (key low 8, key high 4, value 4), in bucket
 * order. */
typedef struct {
    uint64_t key_lo; /* bits 0..63 of the key */
    uint32_t key_hi; /* bits 64..95 */
    uint32_t value;
} hash_mod_entry;
static_assert(sizeof(hash_mod_entry) == 16, "hash_mod_entry is 16 bytes");

typedef struct {
    uint32_t *start;         /* [size + 1]: bucket b is entries[start[b] .. start[b + 1]) */
    hash_mod_entry *entries; /* [count] */
    uint32_t size;           /* buckets, 3 <= size <= HASH_MOD_MAX_SIZE */
    uint32_t count;          /* entries */
} hash_mod_table;

/* Sizes stay below 2^28, so that radix * home + digit fits 32 bits for
 * every radix up to 15 (hash_mod_extend divides in 32 bits). */
#define HASH_MOD_MAX_SIZE ((1u << 28) - 1)

/* The smallest prime >= n (and >= 3); 0 when that passes HASH_MOD_MAX_SIZE. */
uint32_t hash_mod_prime_at_least(uint64_t n);
/* The bucket of the key (hi * 2^64 + lo) mod size. */
uint32_t hash_mod_home_of(uint32_t size, uint64_t lo, uint32_t hi);
static inline uint32_t hash_mod_home(const hash_mod_table *h, uint64_t lo, uint32_t hi)
{
    return hash_mod_home_of(h->size, lo, hi);
}
/* The bucket of radix * K + digit from the bucket of K (radix <= 15,
 * digit < radix): exact, since (radix K + d) mod s = (radix (K mod s) + d)
 * mod s. */
static inline uint32_t hash_mod_extend(const hash_mod_table *h, uint32_t home, uint32_t radix, uint32_t digit)
{
    return (home * radix + digit) % h->size;
}
/* Build h with size buckets (any size in 3..HASH_MOD_MAX_SIZE; a prime
 * spreads keys modulo it best) over entries[0..count) (copied). 0, or -1
 * with h empty: a bad size, a key 0, a key given twice, out of memory. */
int hash_mod_build(hash_mod_table *h, uint32_t size, const hash_mod_entry *entries, uint32_t count);
void hash_mod_free(hash_mod_table *h);
/* The value stored for the key whose bucket is home, or NULL. If probes is
 * not NULL, the number of entries compared is added to it (1 when the key
 * is first in its bucket; for an absent key, the bucket's length, 0 for an
 * empty bucket). */
static inline const uint32_t *hash_mod_find(const hash_mod_table *h, uint64_t lo, uint32_t hi, uint32_t home,
                                            uint32_t *probes)
{
    uint32_t b = h->start[home], e = h->start[home + 1];
    for (uint32_t i = b; i < e; i++)
        if (h->entries[i].key_lo == lo && h->entries[i].key_hi == hi) {
            if (probes) *probes += i - b + 1;
            return &h->entries[i].value;
        }
    if (probes) *probes += e - b;
    return NULL;
}
/* Bytes held. */
static inline size_t hash_mod_memory(const hash_mod_table *h)
{
    return h->start ? ((size_t)h->size + 1) * sizeof(uint32_t) + (size_t)h->count * sizeof(hash_mod_entry) : 0;
}

#ifdef __cplusplus
}
#endif

#endif
