/* tri_set.h: sets of triangles in double (prims/vec3.h dvec3): whether a
 * closed set is convex and outward, and whether two of its triangles meet
 * only where the mesh joins them (their shared vertex or edge, or nowhere
 * within a tolerance). The light buffer's closed-solid analysis
 * (accel/lightbuf/closed_solids.h) decides on them which solids it may
 * cull. */
#ifndef ACCELBENCH_TRI_SET_H
#define ACCELBENCH_TRI_SET_H

#include <stdbool.h>
#include <stdint.h>
#include "vec3.h"

/* Whether the signed volume of the closed set tr[0..n) (the sum of
 * a . (b x c) over its triangles abc) is positive: wound outward. */
bool tri_set_volume_positive(dvec3 (*tr)[3], uint32_t n);
/* Whether every vertex of the triangles tr[0..n) lies behind or on every
 * one of their planes, up to flat times the diagonal of their box: float
 * vertices of coplanar faces (a rotated box's split quads) are never
 * exactly coplanar. Triangles of (nearly) zero area have no plane to
 * check. */
bool tri_set_convex(dvec3 (*tr)[3], uint32_t n, double flat);
/* Whether triangles i and j of tr (their vertices' canonical ids in tv)
 * meet only where the mesh joins them: no shared vertex and more than tol
 * apart, one shared vertex and touching only there, or one shared edge and
 * not folded onto each other. A triangle with a repeated vertex fails
 * against its neighbours. */
bool tri_pair_joined_only(dvec3 (*tr)[3], uint32_t (*tv)[3], uint32_t i, uint32_t j, double tol);

#endif
