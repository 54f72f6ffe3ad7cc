/* hash_mod.c: the chained table of hash_mod.h. */
#include "hash_mod.h"

#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

static bool is_prime(uint32_t n)
{
    if (n < 2) return false;
    if (n % 2 == 0) return n == 2;
    for (uint32_t d = 3; (uint64_t)d * d <= n; d += 2)
        if (n % d == 0) return false;
    return true;
}

uint32_t hash_mod_prime_at_least(uint64_t n)
{
    if (n < 3) n = 3;
    for (uint64_t k = n; k <= HASH_MOD_MAX_SIZE; k++)
        if (is_prime((uint32_t)k)) return (uint32_t)k;
    return 0;
}

uint32_t hash_mod_home_of(uint32_t size, uint64_t lo, uint32_t hi)
{
    /* (hi 2^64 + lo) mod s, in 64 bits: every factor is below s < 2^28. */
    uint64_t s = size, two64 = (UINT64_MAX % s + 1) % s;
    return (uint32_t)(((hi % s) * two64 + lo % s) % s);
}

int hash_mod_build(hash_mod_table *h, uint32_t size, const hash_mod_entry *entries, uint32_t count)
{
    memset(h, 0, sizeof *h);
    if (size < 3 || size > HASH_MOD_MAX_SIZE) return -1;
    h->start = calloc((size_t)size + 1, sizeof *h->start);
    h->entries = malloc(((size_t)count + 1) * sizeof *h->entries);
    uint32_t *home = malloc(((size_t)count + 1) * sizeof *home);
    uint32_t *cur = malloc((size_t)size * sizeof *cur);
    if (!h->start || !h->entries || !home || !cur) goto fail;
    h->size = size;
    /* Counting sort by bucket: sizes, offsets, then placement. */
    for (uint32_t i = 0; i < count; i++) {
        if (!entries[i].key_lo && !entries[i].key_hi) goto fail;
        home[i] = hash_mod_home_of(size, entries[i].key_lo, entries[i].key_hi);
        h->start[home[i] + 1]++;
    }
    for (uint32_t b = 0; b < size; b++) h->start[b + 1] += h->start[b];
    memcpy(cur, h->start, (size_t)size * sizeof *cur);
    for (uint32_t i = 0; i < count; i++) {
        uint32_t b = home[i];
        for (uint32_t k = h->start[b]; k < cur[b]; k++)
            if (h->entries[k].key_lo == entries[i].key_lo && h->entries[k].key_hi == entries[i].key_hi) goto fail;
        h->entries[cur[b]++] = entries[i];
    }
    h->count = count;
    free(home);
    free(cur);
    return 0;
fail:
    free(home);
    free(cur);
    hash_mod_free(h);
    return -1;
}

void hash_mod_free(hash_mod_table *h)
{
    free(h->start);
    free(h->entries);
    memset(h, 0, sizeof *h);
}
