/* dircube.h: the direction cube of the directional techniques (the survey
 * of J. Arvo and D. Kirk, "A Survey of Ray Tracing Acceleration
 * Techniques", 1989, s6.1 and figure 19).
 *
 * A direction is mapped to one of six faces of an axis-aligned cube
 * centred at the origin, by its dominant axis and that axis's sign, and to
 * coordinates (u, v) in [-1, 1]^2 on that face: the two other components
 * divided by the dominant one's magnitude, U and V being the two other
 * axes in lexicographic order (+-x: u = y, v = z; +-y: u = x, v = z; +-z:
 * u = x, v = y), exactly as figure 19.
 *
 * Faces: 0 +x, 1 -x, 2 +y, 3 -y, 4 +z, 5 -z (face / 2 is the axis, face & 1
 * the negative sign).
 *
 * Tie rule (figure 19's strict comparisons): x is dominant only when |x|
 * is strictly larger than |y| and |z|; otherwise y when |y| > |z|;
 * otherwise z. So a tie goes to the LATER axis: |x| == |y| > |z| is y,
 * |x| == |z| or |y| == |z| (as the largest) is z, (1,1,1) is z. The sign
 * is positive only for a component > 0: a -0 or +0 dominant component
 * (only the zero vector has one) is the negative face, so (0,0,0) is -z.
 *
 * Used by the light buffer (one cube per light) and ray classification
 * (the direction part of a ray's 5-D point). */
#ifndef ACCELBENCH_DIRCUBE_H
#define ACCELBENCH_DIRCUBE_H

#include "../../prims/vec3.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The face 0..5 of direction d (any length), by the tie rule above. A NaN
 * component fails every comparison: the face is then unspecified but in
 * 0..5. */
int dircube_face(vec3 d);

/* u and v of d on face (0..5): the lexicographic other components over the
 * magnitude of face's axis component. On the face dircube_face(d) returns,
 * |u|, |v| <= 1 exactly (a correctly rounded quotient of a magnitude by a
 * larger or equal one); on another face the quotients are clamped to
 * [-1, 1]. A zero axis component (or a face out of range) gives u = v = 0. */
void dircube_uv(vec3 d, int face, float *u, float *v);

#ifdef __cplusplus
}
#endif

#endif
