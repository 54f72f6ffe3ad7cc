/* test_stack: the kit's fixed-capacity traversal stack
 * (accel/common/stack.h): last in, first out with the entry distances, and
 * the documented overflow: a push onto a full stack stores nothing,
 * returns false and leaves `overflowed` set (until init) while the stored
 * entries stay intact. */
#include "accel/common/stack.h"
#include "check.h"

int main(void)
{
    tstack_entry buf[4];
    tstack s;
    tstack_init(&s, buf, 4);
    tstack_entry e;
    CHECK(!tstack_pop(&s, &e) && !s.overflowed);
    for (uint32_t i = 0; i < 4; i++) CHECK(tstack_push(&s, 10 + i, (float)i * 0.5f));
    CHECK(!s.overflowed && s.n == 4);
    CHECK(!tstack_push(&s, 99, 9.0f)); /* full: dropped */
    CHECK(s.overflowed && s.n == 4);
    for (int i = 3; i >= 0; i--) {
        CHECK(tstack_pop(&s, &e));
        CHECK(e.node == 10u + (uint32_t)i && e.t == (float)i * 0.5f);
    }
    CHECK(!tstack_pop(&s, &e));
    CHECK(s.overflowed); /* sticky: the caller checks it after the walk */
    CHECK(tstack_push(&s, 1, 1.0f) && s.overflowed);
    tstack_init(&s, buf, 4);
    CHECK(!s.overflowed && s.n == 0);
    /* Capacity 0: every push overflows. */
    tstack_init(&s, buf, 0);
    CHECK(!tstack_push(&s, 1, 0.0f) && s.overflowed);
    return check_report();
}
