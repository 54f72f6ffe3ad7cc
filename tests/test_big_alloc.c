/* test_big_alloc: large blocks on huge pages (accel/common/big_alloc.h):
 * a block of 2 MiB or more starts on a 2 MiB boundary, a smaller one on a
 * cache line; big_calloc's blocks are zero, its overflowing products
 * refused; every block is writable to its end and freed with free() (the
 * sanitizer build checks both), and realloc keeps a block's contents. */
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "accel/common/big_alloc.h"
#include "check.h"

static bool all_zero(const unsigned char *p, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (p[i]) return false;
    return true;
}

int main(void)
{
    const size_t sizes[] = {0, 1, 63, 64, 100, 4096, BIG_ALLOC_HUGE_FROM - 1, BIG_ALLOC_HUGE_FROM,
                            BIG_ALLOC_HUGE_FROM + 1, 3 * BIG_ALLOC_HUGE_FROM + 12345};
    for (size_t k = 0; k < sizeof sizes / sizeof *sizes; k++) {
        size_t n = sizes[k];
        unsigned char *p = big_alloc(n);
        CHECK_MSG(p != NULL, "big_alloc(%zu)", n);
        if (!p) continue;
        size_t align = n >= BIG_ALLOC_HUGE_FROM ? BIG_ALLOC_HUGE_FROM : 64;
        CHECK_MSG((uintptr_t)p % align == 0, "big_alloc(%zu) at %p, not %zu-aligned", n, (void *)p, align);
        memset(p, 0xab, n);
        free(p);
        unsigned char *z = big_calloc(n, 1);
        CHECK_MSG(z && all_zero(z, n), "big_calloc(%zu, 1) not zero", n);
        free(z);
    }
    /* Products past SIZE_MAX are refused rather than wrapped to a small block. */
    CHECK(big_calloc(SIZE_MAX / 8 + 1, 8) == NULL);
    CHECK(big_calloc((size_t)1 << 40, (size_t)1 << 40) == NULL);
    /* bvh_finish shrinks the kit's node array with realloc. */
    size_t n = 5 * BIG_ALLOC_HUGE_FROM;
    unsigned char *p = big_alloc(n);
    CHECK(p != NULL);
    if (p) {
        for (size_t i = 0; i < n; i++) p[i] = (unsigned char)(i * 7);
        unsigned char *q = realloc(p, n / 3);
        CHECK(q != NULL);
        bool same = q != NULL;
        for (size_t i = 0; q && i < n / 3; i++) same = same && q[i] == (unsigned char)(i * 7);
        CHECK_MSG(same, "realloc lost the contents of a big_alloc block");
        free(q ? q : p);
    }
    return check_report();
}
