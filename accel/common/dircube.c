/* dircube.c: figure 19's mapping (see dircube.h). */
#include "dircube.h"

int dircube_face(vec3 d)
{
    float ax = fabsf(d.x), ay = fabsf(d.y), az = fabsf(d.z);
    if (ax > ay && ax > az) return d.x > 0.0f ? 0 : 1;
    if (ay > az) return d.y > 0.0f ? 2 : 3;
    return d.z > 0.0f ? 4 : 5;
}

/* Clamped so that a face other than d's own still gives a point of the
 * face square; fminf/fmaxf also turn a NaN quotient into a bound. */
static float unit_clamp(float x) { return fmaxf(-1.0f, fminf(1.0f, x)); }

void dircube_uv(vec3 d, int face, float *u, float *v)
{
    const float c[3] = {d.x, d.y, d.z};
    int axis = face >= 0 && face < 6 ? face / 2 : -1;
    float m = axis >= 0 ? fabsf(c[axis]) : 0.0f;
    if (!(m > 0.0f)) {
        *u = *v = 0.0f;
        return;
    }
    /* The two other axes in lexicographic order. */
    int ua = axis == 0 ? 1 : 0, va = axis == 2 ? 1 : 2;
    *u = unit_clamp(c[ua] / m);
    *v = unit_clamp(c[va] / m);
}
