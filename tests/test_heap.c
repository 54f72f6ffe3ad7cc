/* test_heap: the kit's distance heap (accel/bvh/heap.h): entries come
 * out in non-decreasing key order with their values, interleaved pushes
 * and pops keep the order, it grows from capacity 0, and clear empties it
 * while keeping the memory. Checked against a sorted reference on random
 * keys with many ties. */
#include <stdlib.h>
#include "accel/bvh/heap.h"
#include "check.h"
#define PRIMS_TEST_SEED 0x4ea9
#include "prims_testlib.h"

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

int main(void)
{
    minheap h;
    CHECK(minheap_init(&h, 0) == 0 && h.cap == 0);
    minheap_entry e;
    CHECK(!minheap_pop(&h, &e));
    enum { N = 5000 };
    static float keys[N];
    for (uint32_t i = 0; i < N; i++) {
        keys[i] = (float)(rng_next() % 1000) * 0.25f; /* ties */
        CHECK(minheap_push(&h, keys[i], i) || 0);
    }
    CHECK(h.n == N && h.cap >= N);
    qsort(keys, N, sizeof keys[0], cmp_float);
    int order_bad = 0, value_bad = 0;
    for (uint32_t i = 0; i < N; i++) {
        if (!minheap_pop(&h, &e) || e.key != keys[i]) order_bad++;
        if (e.value >= N) value_bad++;
    }
    CHECK(order_bad == 0 && value_bad == 0);
    CHECK(!minheap_pop(&h, &e));

    /* Interleaved, as a traversal uses it: pop one, push two farther. */
    minheap_clear(&h);
    CHECK(minheap_push(&h, 1.0f, 0));
    float last = -INFINITY;
    int pops = 0, bad = 0;
    while (minheap_pop(&h, &e) && pops < 3000) {
        if (e.key < last) bad++;
        last = e.key;
        pops++;
        if (e.value < 1000) {
            CHECK(minheap_push(&h, e.key + rnd(0.0f, 2.0f), 2 * e.value + 1) || 0);
            CHECK(minheap_push(&h, e.key + rnd(0.0f, 2.0f), 2 * e.value + 2) || 0);
        }
    }
    CHECK(bad == 0 && pops > 1000);
    uint32_t cap = h.cap;
    minheap_clear(&h);
    CHECK(h.n == 0 && h.cap == cap && !minheap_pop(&h, &e));
    /* Infinite keys order too. */
    CHECK(minheap_push(&h, INFINITY, 1) && minheap_push(&h, -INFINITY, 2) && minheap_push(&h, 0.0f, 3));
    CHECK(minheap_pop(&h, &e) && e.value == 2 && minheap_pop(&h, &e) && e.value == 3 && minheap_pop(&h, &e) && e.value == 1);
    minheap_free(&h);
    CHECK(h.e == NULL && h.cap == 0);
    return check_report();
}
