/* hash.c: the open-addressing table of hash.h. */
#include "hash.h"

#include <stdlib.h>
#include <string.h>

#define HASH_MIN_SLOTS 16u
#define HASH_MAX_SLOTS (1u << 31)

/* MurmurHash3's fmix64 (Appleby): a bijection, full avalanche. */
static inline uint64_t mix(uint64_t k)
{
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdull;
    k ^= k >> 33;
    k *= 0xc4ceb9fe1a85ec53ull;
    k ^= k >> 33;
    return k;
}

static inline uint32_t home(const hash_table *h, uint64_t key) { return (uint32_t)mix(key) & h->mask; }

/* Slots for n entries at load <= 1/2; 0 when n is too large. */
static uint32_t slots_for(uint64_t n)
{
    uint64_t s = HASH_MIN_SLOTS;
    while (s < 2 * n) s *= 2;
    return s > HASH_MAX_SLOTS ? 0 : (uint32_t)s;
}

int hash_init(hash_table *h, uint32_t expected)
{
    uint32_t s = slots_for(expected);
    h->slots = s ? calloc(s, sizeof *h->slots) : NULL;
    h->mask = s ? s - 1 : 0;
    h->count = 0;
    return h->slots ? 0 : -1;
}

void hash_free(hash_table *h)
{
    free(h->slots);
    memset(h, 0, sizeof *h);
}

/* The slot holding key, or the empty slot where it would go. */
static uint32_t probe(const hash_table *h, uint64_t key)
{
    uint32_t i = home(h, key);
    while (h->slots[i].used && h->slots[i].key != key) i = (i + 1) & h->mask;
    return i;
}

uint32_t *hash_find(const hash_table *h, uint64_t key)
{
    if (!h->slots) return NULL;
    hash_slot *s = &h->slots[probe(h, key)];
    return s->used ? &s->value : NULL;
}

/* Rehash into twice the slots. */
static int grow(hash_table *h)
{
    uint64_t n = ((uint64_t)h->mask + 1) * 2;
    if (n > HASH_MAX_SLOTS) return -1;
    hash_table g = {calloc(n, sizeof *g.slots), (uint32_t)(n - 1), h->count};
    if (!g.slots) return -1;
    for (uint32_t i = 0; i <= h->mask; i++)
        if (h->slots[i].used) g.slots[probe(&g, h->slots[i].key)] = h->slots[i];
    free(h->slots);
    *h = g;
    return 0;
}

uint32_t *hash_insert(hash_table *h, uint64_t key, uint32_t value, bool *added)
{
    if (!h->slots && hash_init(h, 0)) return NULL;
    uint32_t i = probe(h, key);
    if (h->slots[i].used) {
        if (added) *added = false;
        return &h->slots[i].value;
    }
    if (2 * ((uint64_t)h->count + 1) > (uint64_t)h->mask + 1) {
        if (grow(h)) return NULL;
        i = probe(h, key);
    }
    h->slots[i] = (hash_slot){key, value, 1};
    h->count++;
    if (added) *added = true;
    return &h->slots[i].value;
}
