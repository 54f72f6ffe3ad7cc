/* coincident.h: coincident primitives, which no subdivision separates.
 *
 * Meshes repeat faces (scanned and CAD data): copies of one triangle lie in
 * every cell any one of them touches, so a builder that subdivides while a
 * cell holds more than k primitives recurses to its depth limit around
 * them, and a grid sized from the primitive count cuts their one box into
 * cells each holding every copy. The rule the builders share: coincident
 * primitives count once, where a builder compares a count with its
 * threshold (a leaf's maxprims, a grid's resolution from N). A scene
 * without coincident primitives gets exactly the structure it got before.
 *
 * Coincident: the same kind and the same points, bit for bit (-0 and +0
 * alike): a triangle's three vertices in any order (either winding), a
 * sphere's centre and radius, a cone's two ends in either order, a
 * polygon's vertices in the same order from the same first one. Found in
 * O(N) expected by hashing those coordinates (accel/common/hash.h), each
 * hash match checked coordinate by coordinate. */
#ifndef ACCELBENCH_COINCIDENT_H
#define ACCELBENCH_COINCIDENT_H

#include <stdbool.h>
#include <stdint.h>
#include "../../prims/prims.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    uint32_t *rep;     /* [count]: the smallest id coincident with each primitive; NULL when all are distinct */
    uint32_t classes;  /* distinct primitives: count less the copies */
} prim_classes;

/* Classify p's primitives. 0, or -1 out of memory (c then says "all
 * distinct", so a caller may go on with the old rule). rep stays NULL when
 * no two primitives coincide. */
int prim_classes_init(prim_classes *c, const prims_t *p);
void prim_classes_free(prim_classes *c);
/* Bytes prim_classes_init holds at its peak for n primitives (the table and rep). */
uint64_t prim_classes_scratch_bytes(uint32_t n);

/* Whether ids[0..n) hold at most max distinct primitives (coincident ones
 * counted once). n <= max answers at once; with no copies in the scene
 * (c NULL or c->rep NULL) it is n <= max. Otherwise O(n min(max, 32)), or a
 * sort of the n representatives past that. */
bool prim_classes_at_most(const prim_classes *c, const uint32_t *ids, uint32_t n, uint64_t max);

#ifdef __cplusplus
}
#endif

#endif
