/* closed_solids.h: which of a scene's triangles and polygons lie on closed
 * solids whose outside is known: mesh topology (vertices matched by exact
 * position, every undirected edge used exactly once each way, connected
 * components) and, per component, convexity (every vertex behind every
 * plane, within SOLID_FLAT of the component's size, positive volume) or,
 * failing that, embedding (no two triangles meet but where the mesh joins
 * them, the pairs found over the kit's BVH); the geometry of both tests is
 * prims/tri_set.h's. The light buffer's
 * culling (lightbuf_haines_greenberg.c, cull=on; docs/accels/directional.md)
 * drops the faces of such a solid that face away from a light outside it.
 *
 * Everything is in double (prims/vec3.h dvec3). Reentrant: builds may run
 * at once. */
#ifndef ACCELBENCH_CLOSED_SOLIDS_H
#define ACCELBENCH_CLOSED_SOLIDS_H

#include <stdbool.h>
#include <stdint.h>
#include "../../prims/prims.h"

#define SOLID_NONE UINT32_MAX
#define SOLID_CONVEX_MAX_TRIS 4096 /* the convexity check is quadratic in a component's size */
#define SOLID_FLAT 1e-6            /* convexity tolerance, relative to a component's box diagonal */

/* The closed solids of a scene's triangles and polygons: comp[id] is the
 * component of primitive id when it lies wholly on one qualifying
 * component, else SOLID_NONE; ctris[] are the triangles of the qualifying
 * components, grouped by component (cfirst[c] .. cfirst[c + 1]). */
typedef struct {
    uint32_t *comp;
    uint32_t ncomps;
    uint32_t *cfirst;
    dvec3 (*ctris)[3];
    uint32_t (*ctv)[3]; /* their vertices' canonical ids (position classes) */
    bool *ok;           /* [ncomps] the component qualifies */
} closed_solids;

/* The analysis of p's triangles and polygons' ear triangles into s.
 * Returns 0, or -1 out of memory (s then empty). */
int closed_solids_find(const prims_t *p, closed_solids *s);
void closed_solids_free(closed_solids *s);
/* An upper bound of the bytes closed_solids_find(p) allocates at once
 * (saturating), for the caller's memory cap. */
uint64_t closed_solids_bytes(const prims_t *p);

#endif
