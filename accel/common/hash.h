/* hash.h: an open-addressing hash table from 64-bit keys to 32-bit values,
 * for coincident.c's grouping of primitives by geometry, its one user.
 *
 * Linear probing (Knuth, TAOCP vol. 3, s6.4, algorithm L), load at most
 * 1/2 (the table doubles before it passes that), keys hashed by the
 * MurmurHash3 64-bit finaliser (Appleby), which sends every input bit to
 * every output bit, so structured keys (cell coordinates, Morton codes)
 * cluster no more than random ones.
 *
 * Memory layout: one array of 2^k slots of 16 bytes (key 8, value 4, used
 * 4), k the smallest with count <= 2^(k-1); 16 to 32 bytes per entry. Not
 * thread-safe for writers; concurrent readers of a table nobody writes are
 * fine. */
#ifndef ACCELBENCH_HASH_H
#define ACCELBENCH_HASH_H

#include <assert.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    uint64_t key;
    uint32_t value;
    uint32_t used; /* 1 when the slot holds an entry */
} hash_slot;
static_assert(sizeof(hash_slot) == 16, "hash_slot is 16 bytes: four to a cache line");

typedef struct {
    hash_slot *slots; /* [mask + 1] */
    uint32_t mask;    /* capacity - 1, capacity a power of two */
    uint32_t count;   /* entries */
} hash_table;

/* An empty table with room for expected entries before it grows. 0, or -1
 * out of memory. */
int hash_init(hash_table *h, uint32_t expected);
void hash_free(hash_table *h);
/* The value stored for key, or NULL. The pointer is valid until the next
 * insertion or removal. */
uint32_t *hash_find(const hash_table *h, uint64_t key);
/* Insert key with value unless present. Returns the value slot (the new
 * one, or the existing one left unchanged) and says which in *added (may
 * be NULL); NULL when growing ran out of memory (the table is unchanged). */
uint32_t *hash_insert(hash_table *h, uint64_t key, uint32_t value, bool *added);

#ifdef __cplusplus
}
#endif

#endif
