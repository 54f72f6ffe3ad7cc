/* test_hash: the kit's open-addressing hash table (accel/common/hash.h)
 * against a plain array as the reference: inserts (new and existing keys),
 * lookups of present and absent keys, growth from the smallest table; keys of 32-bit range, full 64-bit keys, and
 * structured keys (consecutive, strided, Morton-like) that cluster badly
 * under a weak hash. */
#include <stdlib.h>
#include "accel/common/hash.h"
#include "check.h"
#define PRIMS_TEST_SEED 0x4a54
#include "prims_testlib.h"

enum { N = 20000 };
static uint64_t keys[N];
static uint8_t present[N];

static int check_all(const hash_table *h, const char *what)
{
    int bad = 0;
    uint32_t count = 0;
    for (uint32_t i = 0; i < N; i++) {
        uint32_t *v = hash_find(h, keys[i]);
        if (present[i]) count++;
        if (present[i] ? !v || *v != i : v != NULL) bad++;
    }
    CHECK_MSG(bad == 0 && count == h->count, "%s: %d wrong lookups, count %u vs %u", what, bad, h->count, count);
    return bad;
}

static void run(const char *what, uint64_t (*make)(uint32_t))
{
    for (uint32_t i = 0; i < N; i++) keys[i] = make(i), present[i] = 0;
    hash_table h;
    CHECK(hash_init(&h, 0) == 0);
    for (uint32_t i = 0; i < N; i++) {
        bool added;
        uint32_t *v = hash_insert(&h, keys[i], i, &added);
        CHECK(v && added && *v == i);
        present[i] = 1;
    }
    check_all(&h, what);
    CHECK(h.mask + 1 >= 2 * h.count); /* load at most 1/2 */
    /* Re-inserting keeps the old value. */
    bool added = true;
    uint32_t *v = hash_insert(&h, keys[5], 12345, &added);
    CHECK(v && !added && *v == 5);
    hash_free(&h);
    printf("%s: ok\n", what);
}

static uint64_t consecutive(uint32_t i) { return i; }
static uint64_t strided(uint32_t i) { return (uint64_t)i << 20; }
static uint64_t full64(uint32_t i) { return rng_next() | ((uint64_t)i << 63 >> 63 << 63) | i; }
static uint64_t morton(uint32_t i)
{
    /* Interleave three 10-bit coordinates of a dense block of cells. */
    uint32_t x = i % 32, y = (i / 32) % 32, z = i / 1024;
    uint64_t m = 0;
    for (int b = 0; b < 10; b++) m |= (uint64_t)((x >> b) & 1) << (3 * b) | (uint64_t)((y >> b) & 1) << (3 * b + 1) | (uint64_t)((z >> b) & 1) << (3 * b + 2);
    return m;
}

int main(void)
{
    run("uint32 consecutive", consecutive);
    run("uint32 strided", strided);
    run("uint64 random", full64);
    run("morton codes", morton);
    /* Key 0 and UINT64_MAX are ordinary keys. */
    hash_table h = {0};
    CHECK(hash_find(&h, 0) == NULL);
    CHECK(hash_insert(&h, 0, 1, NULL) && hash_insert(&h, UINT64_MAX, 2, NULL));
    CHECK(*hash_find(&h, 0) == 1 && *hash_find(&h, UINT64_MAX) == 2 && h.count == 2);
    hash_free(&h);
    return check_report();
}
