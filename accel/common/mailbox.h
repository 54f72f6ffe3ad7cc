/* mailbox.h: per-context mailboxes keyed by ray id (Arnaldi, Priol,
 * Bouatouch, "A New Space Subdivision Method for Ray Tracing CSG Modelled
 * Scenes", The Visual Computer 3(2), 1987; the survey of Arvo and Kirk,
 * 1989, s5.3).
 *
 * A structure that stores a primitive in several cells or leaves would test
 * it again each time a ray meets it there. The mailbox remembers, per
 * primitive, the id of the last ray that tested it; a second test by the
 * same ray is skipped. The stamps live in the tracing context (one per
 * thread), never in the shared structure, so tracing stays thread-safe and
 * nothing shared is written.
 *
 * Ray ids count 1, 2, 3, ... per context; 0 means "never tested". When the
 * 32-bit id wraps, every stamp is cleared and counting restarts at 1, so a
 * stale stamp can never equal a live id (once per 2^32 - 1 rays).
 *
 * Memory: 4 bytes per primitive per context, plus the 16-byte struct. */
#ifndef ACCELBENCH_MAILBOX_H
#define ACCELBENCH_MAILBOX_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    uint32_t *stamp; /* [count] last ray id that tested each primitive; 0 = never */
    uint32_t count;  /* primitives */
    uint32_t rid;    /* id of the current ray; 0 before the first */
} mailbox_t;

/* Stamps for count primitives, all "never". 0, or -1 out of memory. */
int mailbox_init(mailbox_t *m, uint32_t count);
void mailbox_free(mailbox_t *m);
/* Bytes held. */
static inline size_t mailbox_memory(const mailbox_t *m) { return (size_t)m->count * sizeof *m->stamp; }

/* Start a ray: returns its id (never 0). */
static inline uint32_t mailbox_next_ray(mailbox_t *m)
{
    if (++m->rid == 0) {
        memset(m->stamp, 0, (size_t)m->count * sizeof *m->stamp);
        m->rid = 1;
    }
    return m->rid;
}

/* The id of the last ray that tested primitive id (0: none). */
static inline uint32_t mailbox_stamp(const mailbox_t *m, uint32_t id) { return m->stamp[id]; }
/* Has ray rid already tested primitive id? */
static inline bool mailbox_seen(const mailbox_t *m, uint32_t id, uint32_t rid) { return m->stamp[id] == rid; }
/* Ray rid tests primitive id now. */
static inline void mailbox_mark(mailbox_t *m, uint32_t id, uint32_t rid) { m->stamp[id] = rid; }

#ifdef __cplusplus
}
#endif

#endif
