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

void hash_clear(hash_table *h)
{
    memset(h->slots, 0, ((size_t)h->mask + 1) * sizeof *h->slots);
    h->count = 0;
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

bool hash_remove(hash_table *h, uint64_t key)
{
    if (!h->slots) return false;
    uint32_t i = probe(h, key);
    if (!h->slots[i].used) return false;
    /* Algorithm R: walk the run after i; an entry whose home is not
     * cyclically in (i, j] would be cut off from it by the hole at i, so it
     * moves into the hole, which moves to j. */
    for (uint32_t j = i;;) {
        j = (j + 1) & h->mask;
        if (!h->slots[j].used) break;
        uint32_t k = home(h, h->slots[j].key);
        bool stays = i <= j ? (i < k && k <= j) : (i < k || k <= j);
        if (stays) continue;
        h->slots[i] = h->slots[j];
        i = j;
    }
    h->slots[i].used = 0;
    h->count--;
    return true;
}

/* ------------------------------------------------------------ hash_mod */

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
