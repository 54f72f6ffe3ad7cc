/* test_dircube: the direction cube's mapping (accel/common/dircube.h, the
 * survey's figure 19): the six axes, ties between components (the later
 * axis wins, as figure 19's strict comparisons say), signs (-0 and 0 on
 * the dominant axis only for the zero vector), u-v coordinates in
 * lexicographic axis order, and [-1, 1] over random directions. */
#include <stdint.h>
#include "accel/common/dircube.h"
#include "check.h"

static void expect(vec3 d, int face, float u, float v)
{
    int f = dircube_face(d);
    float gu, gv;
    dircube_uv(d, f, &gu, &gv);
    CHECK_MSG(f == face && gu == u && gv == v, "(%g %g %g): face %d u %g v %g, want %d %g %g", d.x, d.y, d.z, f, gu, gv,
              face, u, v);
}

int main(void)
{
    /* The six axes: faces 0..5 for +x -x +y -y +z -z, at the face centre. */
    expect(v3(1, 0, 0), 0, 0, 0);
    expect(v3(-2, 0, 0), 1, 0, 0);
    expect(v3(0, 3, 0), 2, 0, 0);
    expect(v3(0, -1, 0), 3, 0, 0);
    expect(v3(0, 0, 0.5f), 4, 0, 0);
    expect(v3(0, 0, -1), 5, 0, 0);
    /* -0 in the other components changes nothing. */
    expect(v3(-0.0f, -0.0f, 1), 4, -0.0f, -0.0f);
    expect(v3(-1, -0.0f, 0), 1, -0.0f, 0);
    /* u, v: the other axes in lexicographic order over |major|. */
    expect(v3(4, 2, -1), 0, 0.5f, -0.25f);  /* x face: u = y, v = z */
    expect(v3(-4, 2, -1), 1, 0.5f, -0.25f); /* divided by |x|, not x */
    expect(v3(1, -4, 2), 3, 0.25f, 0.5f);   /* y face: u = x, v = z */
    expect(v3(-2, 1, 4), 4, -0.5f, 0.25f);  /* z face: u = x, v = y */
    /* Ties: figure 19's "ax > ay and ax > az", then "ay > az": the later axis wins. */
    expect(v3(1, 1, 0), 2, 1, 0);
    expect(v3(1, -1, 0), 3, 1, 0);
    expect(v3(1, 0, 1), 4, 1, 0);
    expect(v3(0, 1, -1), 5, 0, 1);
    expect(v3(1, 1, 1), 4, 1, 1);
    expect(v3(-1, -1, -1), 5, -1, -1);
    expect(v3(2, 2, 1), 2, 1, 0.5f);
    /* The zero vector: -z (no component > 0), u = v = 0. */
    expect(v3(0, 0, 0), 5, 0, 0);
    /* Another face than the dominant one: the point on that face's plane. */
    float u, v;
    dircube_uv(v3(2, 1, 0.5f), 4, &u, &v);
    CHECK(u == 4.0f && v == 2.0f);
    /* Random directions: u, v within [-1, 1] on their face, and the face is the
     * largest component's. */
    uint32_t s = 99;
    for (int i = 0; i < 100000; i++) {
        float c[3];
        for (int k = 0; k < 3; k++) {
            s = s * 1664525u + 1013904223u;
            c[k] = (float)((int32_t)(s >> 8) - (1 << 23)) / (float)(1 << 23);
        }
        vec3 d = v3(c[0], c[1], c[2]);
        int f = dircube_face(d);
        dircube_uv(d, f, &u, &v);
        float major = fabsf(c[f >> 1]);
        bool ok = u >= -1 && u <= 1 && v >= -1 && v <= 1 && major >= fabsf(c[0]) && major >= fabsf(c[1]) &&
                  major >= fabsf(c[2]) && ((f & 1) ? c[f >> 1] <= 0 : c[f >> 1] > 0);
        if (!ok) CHECK_MSG(ok, "(%g %g %g): face %d u %g v %g", c[0], c[1], c[2], f, u, v);
    }
    CHECK(1);
    return check_report();
}
