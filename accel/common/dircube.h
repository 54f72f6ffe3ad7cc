/* dircube.h: the direction cube of the survey (Arvo and Kirk 1989, s6.1,
 * figure 19): a 3-D direction to one of six faces and u-v coordinates on
 * it, shared by the directional techniques (the light buffer,
 * accel/lightbuf/lightbuf_haines_greenberg.c; ray classification).
 *
 * Faces are numbered 0..5 for +x, -x, +y, -y, +z, -z (face = 2 axis +
 * (component < 0)). On each face, U and V are the other two world axes in
 * lexicographic order (figure 19: x faces u = y, v = z; y faces u = x,
 * v = z; z faces u = x, v = y), divided by the magnitude of the dominant
 * component, so they lie in [-1, 1] on the face the direction maps to.
 *
 * Ties between components follow figure 19's comparisons exactly: x is
 * dominant only when |x| > |y| and |x| > |z| (strictly); otherwise y when
 * |y| > |z|; otherwise z. So a tie goes to the LATER axis: |x| = |y| > |z|
 * is a y face, |x| = |z| or |y| = |z| (the larger ones) a z face, and
 * (1,1,1) is +z. The sign is figure 19's "> 0": the face is the positive
 * one only when the dominant component is > 0, so -0 and 0 there (possible
 * only for the zero vector, which maps to -z) give the negative face. */
#ifndef ACCELBENCH_DIRCUBE_H
#define ACCELBENCH_DIRCUBE_H

#include "../../prims/vec3.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The face of direction d, 0..5 (+x, -x, +y, -y, +z, -z), by the dominant
 * axis with figure 19's tie rule (above). NaN components compare false,
 * so a NaN direction lands on some face; callers pass finite ones. */
int dircube_face(vec3 d);

/* d's coordinates on face `face`: u and v are d's two other components in
 * lexicographic order over |d[face's axis]|. In [-1, 1] when face ==
 * dircube_face(d); for another face they may exceed 1 in magnitude (the
 * point where d's line meets that face's plane), and they are 0 for the
 * zero vector (no division by zero). */
void dircube_uv(vec3 d, int face, float *u, float *v);

#ifdef __cplusplus
}
#endif

#endif
