/* test_mailbox: the kit's per-context mailboxes (accel/common/mailbox.h):
 * a fresh mailbox has seen nothing, a mark is seen by its ray only, ray ids
 * are never 0, two contexts are independent, and when the 32-bit ray id
 * wraps every stamp is cleared so no stale stamp matches a new ray. */
#include "accel/common/mailbox.h"
#include "check.h"

int main(void)
{
    mailbox_t m, other;
    CHECK(mailbox_init(&m, 100) == 0 && mailbox_init(&other, 100) == 0);
    CHECK(mailbox_memory(&m) == 400);
    uint32_t r1 = mailbox_next_ray(&m);
    CHECK(r1 == 1);
    for (uint32_t id = 0; id < 100; id++) CHECK(!mailbox_seen(&m, id, r1) && mailbox_stamp(&m, id) == 0);
    mailbox_mark(&m, 7, r1);
    CHECK(mailbox_seen(&m, 7, r1) && !mailbox_seen(&m, 8, r1) && mailbox_stamp(&m, 7) == r1);
    uint32_t r2 = mailbox_next_ray(&m);
    CHECK(r2 == 2 && !mailbox_seen(&m, 7, r2) && mailbox_stamp(&m, 7) == r1); /* the last tester is still known */
    /* Another context has its own stamps and ids. */
    uint32_t o1 = mailbox_next_ray(&other);
    CHECK(o1 == 1 && !mailbox_seen(&other, 7, o1));

    /* Wrap: stamps from just before the wrap must not match after it. */
    m.rid = UINT32_MAX - 1;
    uint32_t last = mailbox_next_ray(&m);
    CHECK(last == UINT32_MAX);
    mailbox_mark(&m, 3, last);
    mailbox_mark(&m, 1, 1); /* a stamp equal to the id the wrap hands out next */
    uint32_t first = mailbox_next_ray(&m);
    CHECK(first == 1);
    CHECK(!mailbox_seen(&m, 1, first) && !mailbox_seen(&m, 3, first) && mailbox_stamp(&m, 3) == 0);
    mailbox_mark(&m, 3, first);
    CHECK(mailbox_seen(&m, 3, first));

    /* A scene with no primitives still gets a usable (empty) mailbox. */
    mailbox_t empty;
    CHECK(mailbox_init(&empty, 0) == 0 && empty.stamp && mailbox_next_ray(&empty) == 1);
    mailbox_free(&empty);
    mailbox_free(&m);
    mailbox_free(&other);
    CHECK(m.stamp == NULL);
    return check_report();
}
