/* mailbox.c: allocation of the mailboxes (mailbox.h). */
#include "mailbox.h"

#include <stdlib.h>

int mailbox_init(mailbox_t *m, uint32_t count)
{
    /* One spare stamp, so that a scene with no primitives still allocates. */
    m->stamp = calloc((size_t)count + 1, sizeof *m->stamp);
    m->count = count;
    m->rid = 0;
    return m->stamp ? 0 : -1;
}

void mailbox_free(mailbox_t *m)
{
    free(m->stamp);
    m->stamp = NULL;
    m->count = 0;
}
