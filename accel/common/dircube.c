/* dircube.c: figure 19's direction-to-face mapping (see dircube.h). */
#include "dircube.h"

int dircube_face(vec3 d)
{
    float ax = fabsf(d.x), ay = fabsf(d.y), az = fabsf(d.z);
    /* Figure 19's comparisons, in its order: a tie never picks the earlier axis. */
    if (ax > ay && ax > az) return d.x > 0.0f ? 0 : 1;
    if (ay > az) return d.y > 0.0f ? 2 : 3;
    return d.z > 0.0f ? 4 : 5;
}

void dircube_uv(vec3 d, int face, float *u, float *v)
{
    int axis = face >> 1;
    float major = fabsf(axis == 0 ? d.x : axis == 1 ? d.y : d.z);
    /* The other two axes in lexicographic order. */
    float a = axis == 0 ? d.y : d.x, b = axis == 2 ? d.y : d.z;
    if (!(major > 0.0f)) {
        *u = *v = 0.0f;
        return;
    }
    *u = a / major;
    *v = b / major;
}
