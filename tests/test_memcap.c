/* test_memcap: the kit's memory cap (accel/common/memcap.h): within the cap
 * nothing is written, over it the one-line reason names what, the need in
 * MiB and the cap; the saturating arithmetic cannot wrap an absurd
 * estimate back under the cap. */
#include <string.h>
#include "accel/common/memcap.h"
#include "check.h"

int main(void)
{
    char err[256] = "untouched";
    CHECK(!memcap_exceeded(4ull << 20, 4, err, sizeof err, "grid %d", 1)); /* exactly the cap */
    CHECK(strcmp(err, "untouched") == 0);
    CHECK(!memcap_exceeded(0, 0, err, sizeof err, "nothing"));
    CHECK(memcap_exceeded(4ull << 20 | 1, 4, err, sizeof err, "just over")); /* one byte over */
    CHECK(memcap_exceeded(10ull << 19, 4, err, sizeof err, "res=%dx%dx%d: %d cells", 100, 100, 100, 1000000));
    printf("%s\n", err);
    CHECK(strcmp(err, "res=100x100x100: 1000000 cells need 5.0 MiB, over memcap=4 MiB") == 0);
    CHECK(strchr(err, '\n') == NULL);
    CHECK(memcap_exceeded(3ull << 30, 1024, err, sizeof err, "tree"));
    CHECK(strcmp(err, "tree need 3072.0 MiB, over memcap=1024 MiB") == 0);
    /* A short buffer truncates the reason but still refuses. */
    char tiny[12];
    CHECK(memcap_exceeded(1ull << 40, 1, tiny, sizeof tiny, "a long description"));
    CHECK(strlen(tiny) == sizeof tiny - 1);
    CHECK(memcap_exceeded(1, 0, NULL, 0, "no buffer"));
    /* Saturation. */
    CHECK(memcap_mul(UINT64_MAX / 2, 3) == UINT64_MAX && memcap_mul(1000, 24) == 24000 && memcap_mul(5, 0) == 0);
    CHECK(memcap_add(UINT64_MAX - 1, 2) == UINT64_MAX && memcap_add(1, 2) == 3);
    CHECK(memcap_exceeded(memcap_add(memcap_mul(1ull << 40, 1ull << 30), 5), 1ull << 30, err, sizeof err, "huge"));
    /* A cap beyond 2^64 bytes is no cap. */
    CHECK(!memcap_exceeded(UINT64_MAX, UINT64_MAX, err, sizeof err, "anything"));
    return check_report();
}
