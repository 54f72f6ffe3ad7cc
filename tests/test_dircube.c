/* test_dircube: the kit's direction cube (accel/common/dircube.h), the
 * survey's figure 19: the six faces on the axes, the ties between
 * components (strict comparisons: a tie goes to the later axis), the sign
 * of a zero component, u and v as the lexicographic other components over
 * the dominant magnitude, within [-1, 1] on random directions and exactly
 * +-1 on the cube's edges, and the clamp on a face that is not the
 * direction's own. */
#include <stdint.h>
#include "accel/common/dircube.h"
#include "check.h"

static uint32_t rng = 99;
static float srand1(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (float)(rng >> 8) / 8388608.0f - 1.0f;
}

static void uv_is(vec3 d, int face, float u, float v)
{
    float gu, gv;
    dircube_uv(d, face, &gu, &gv);
    CHECK_MSG(gu == u && gv == v, "(%g, %g, %g) on face %d: u %g v %g, want %g %g", d.x, d.y, d.z, face, gu, gv, u, v);
}

int main(void)
{
    /* The six axes, any length. */
    CHECK(dircube_face(v3(1, 0, 0)) == 0 && dircube_face(v3(-3, 0, 0)) == 1);
    CHECK(dircube_face(v3(0, 2, 0)) == 2 && dircube_face(v3(0, -1, 0)) == 3);
    CHECK(dircube_face(v3(0, 0, 5)) == 4 && dircube_face(v3(0, 0, -1e-30f)) == 5);
    uv_is(v3(1, 0, 0), 0, 0, 0);
    uv_is(v3(0, 0, -7), 5, 0, 0);
    /* u, v: the other two axes in lexicographic order over |dominant|. */
    uv_is(v3(2, 1, -1), 0, 0.5f, -0.5f);   /* +x: u = y, v = z */
    uv_is(v3(-4, -1, 2), 1, -0.25f, 0.5f); /* -x */
    uv_is(v3(1, 4, -2), 2, 0.25f, -0.5f);  /* +y: u = x, v = z */
    uv_is(v3(-2, -8, 4), 3, -0.25f, 0.5f); /* -y */
    uv_is(v3(1, -2, 4), 4, 0.25f, -0.5f);  /* +z: u = x, v = y */
    uv_is(v3(3, 1, -6), 5, 0.5f, 1.0f / 6.0f);
    /* Ties (figure 19's strict comparisons): the later axis wins. */
    CHECK(dircube_face(v3(1, 1, 0)) == 2);    /* x = y: y */
    CHECK(dircube_face(v3(-1, -1, 0.5f)) == 3);
    CHECK(dircube_face(v3(1, 0, 1)) == 4);    /* x = z: z */
    CHECK(dircube_face(v3(0, 1, -1)) == 5);   /* y = z: z */
    CHECK(dircube_face(v3(1, 1, 1)) == 4);    /* all: z */
    CHECK(dircube_face(v3(-1, 1, -1)) == 5);
    CHECK(dircube_face(v3(2, 1, 1)) == 0);    /* x strictly largest */
    /* On the cube's edges u or v is exactly +-1. */
    uv_is(v3(1, 1, 0), 2, 1.0f, 0.0f);
    uv_is(v3(-1, 0, -1), 5, -1.0f, 0.0f);
    uv_is(v3(1, 1, 1), 4, 1.0f, 1.0f);
    /* Zero components: the sign is positive only for > 0, so the zero
     * vector is -z; -0 components give u or v of -0 (== 0). */
    CHECK(dircube_face(v3(0, 0, 0)) == 5);
    CHECK(dircube_face(v3(-0.0f, 0, -0.0f)) == 5);
    CHECK(dircube_face(v3(0.5f, -0.0f, 0)) == 0);
    uv_is(v3(0, 0, 0), 5, 0, 0);
    uv_is(v3(0.5f, -0.0f, 0), 0, 0, 0);
    /* Another face than the direction's own: clamped to the square; a
     * zero axis component or a bad face: 0. */
    uv_is(v3(1, 4, 0), 0, 1.0f, 0.0f);
    uv_is(v3(0, 4, 1), 0, 0, 0);
    uv_is(v3(1, 1, 1), 6, 0, 0);
    uv_is(v3(1, 1, 1), -1, 0, 0);
    /* Random directions: the face's axis is a largest magnitude with the
     * face's sign, and u, v are in [-1, 1] and reproduce the direction. */
    for (int i = 0; i < 100000; i++) {
        vec3 d = v3(srand1(), srand1(), srand1());
        if (i % 7 == 0) d.y = d.x;     /* ties */
        if (i % 11 == 0) d.z = -d.y;
        if (i % 13 == 0) d.x = 0.0f;
        if (d.x == 0 && d.y == 0 && d.z == 0) continue;
        int f = dircube_face(d), a = f / 2;
        float c[3] = {d.x, d.y, d.z}, m = fabsf(c[a]);
        CHECK(f >= 0 && f < 6);
        CHECK(m >= fabsf(d.x) && m >= fabsf(d.y) && m >= fabsf(d.z) && m > 0);
        CHECK((f & 1) ? c[a] < 0 : c[a] > 0);
        float u, v;
        dircube_uv(d, f, &u, &v);
        CHECK(fabsf(u) <= 1.0f && fabsf(v) <= 1.0f);
        int ua = a == 0 ? 1 : 0, va = a == 2 ? 1 : 2;
        CHECK(u == c[ua] / m && v == c[va] / m);
    }
    return check_report();
}
