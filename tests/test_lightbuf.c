/* test_lightbuf: Haines and Greenberg's light buffer `lightbuf`
 * (accel/lightbuf/lightbuf_haines_greenberg.c), beyond the conformance suite.
 *
 *   fullocc      a polygon covering every cell of a face gives each a
 *                full-occlusion record at its farthest depth; what lies
 *                beyond is dropped from the lists; a point beyond is in
 *                shadow with no test, a point between the polygon's
 *                nearest and farthest depth (a tie with the record) reads
 *                the list, a segment whose tnear starts past the polygon
 *                is lit; a small triangle gives no record
 *   single       a cell listing one triangle keeps its slab: a point on
 *                its lit side is lit with no primitive test, a point
 *                behind it is in shadow (the list of one is never simply
 *                dropped), and with a second primitive behind it the cell
 *                is no longer single and a point on that one is shadowed
 *   cull         only closed, consistently oriented, outward solids that
 *                are convex or embedded (no self-intersection) lose their
 *                back faces, for a light outside: an outward cube
 *                (indexed, and with every triangle's own vertices) and a
 *                dented (concave) cube do; an inward cube, an open cube, a
 *                folded (self-intersecting) cube and a cube around the
 *                light do not; answers unchanged; gen:room's rotated box
 *                does (coplanar up to float rounding); the closed bunny
 *                does
 *   conservative random triangles, spheres, cones and polygons, a light
 *                outside them and one among them, random points: every
 *                primitive that blocks a point's shadow ray is in the
 *                point's cell or the near list (res 1, 7, 32, 100), and
 *                every setting answers as testing every primitive does,
 *                counting and counting-free, also for any-hit rays that
 *                carry a light but do not end at it (the fallback)
 *   auto         res=auto: a fine cube for a far cluster, a coarse one
 *                for the same cluster around the light
 *   refusals     memcap, res out of range, a bad switch value
 *   model        the predicted list entries a query reads (directions
 *                uniform over the solid angle of the cells that list
 *                something): by hand, 1 for one tiny triangle; a
 *                triangle in the centre cell of +x and two in a corner
 *                cell at res 3, weighted by solid angles integrated here
 *                numerically; and the measured tests of shadow rays from
 *                points uniform on a sphere around the light, beyond 3000
 *                tiny triangles, kept when their cell lists something,
 *                with single, fullocc and cull off, within 2 % (or 4
 *                standard deviations of the count) at res 4 and 32; with
 *                them on, the prediction bounds the measured tests
 *                from above */
#include <math.h>
#include <string.h>
#include "accel/common/dircube.h"
#include "accel/lightbuf/lightbuf_haines_greenberg.h"
#include "testlib.h"

static uint32_t rng = 777;
static float urand(void) { return test_urand(&rng); }
static float srand1(void) { return 2.0f * urand() - 1.0f; }

static accel *lb_with(const scene_t *s, const char *cfg) { return test_build_or_die("lightbuf", s, cfg); }

static void finish(scene_t *s) { test_finish_scene(s); }

static uint32_t tri(scene_t *s, vec3 a, vec3 b, vec3 c)
{
    prims_t *p = &s->prims;
    return prims_add_triangle(p, prims_add_vertex(p, a), prims_add_vertex(p, b), prims_add_vertex(p, c));
}

/* A shadow ray from pt to light l, as spawn_shadow makes them. */
static ray_t shadow_ray(const scene_t *s, vec3 pt, uint32_t l)
{
    vec3 to = v3_sub(s->lights[l], pt);
    float dist = v3_len(to);
    return (ray_t){pt, 0.0f, v3_scale(to, 1.0f / dist), dist, l, 0};
}

/* The cell a query of point pt reads (the accelerator's own rule). */
static uint32_t cell_of(const scene_t *s, uint32_t l, vec3 pt, uint32_t res)
{
    vec3 L = s->lights[l];
    vec3 w = v3((float)((double)pt.x - L.x), (float)((double)pt.y - L.y), (float)((double)pt.z - L.z));
    int f = dircube_face(w);
    float u, v;
    dircube_uv(w, f, &u, &v);
    int i = (int)floorf((u + 1.0f) * 0.5f * (float)res), j = (int)floorf((v + 1.0f) * 0.5f * (float)res);
    i = i < 0 ? 0 : i >= (int)res ? (int)res - 1 : i;
    j = j < 0 ? 0 : j >= (int)res ? (int)res - 1 : j;
    return ((uint32_t)f * res + (uint32_t)j) * res + (uint32_t)i;
}

static bool every_prim(const scene_t *s, const ray_t *r)
{
    for (uint32_t id = 0; id < s->prims.count; id++)
        if (prim_occluded_fast(&s->prims, id, r)) return true;
    return false;
}

static bool ask(accel *a, const ray_t *r, counters_t *c)
{
    memset(c, 0, sizeof *c);
    return a->ops->occluded(a, NULL, r, c);
}

#define LIST_CAP 4096
static uint32_t ids[LIST_CAP];
static float depths[LIST_CAP];

static bool listed(accel *a, uint32_t l, uint32_t cell, uint32_t id)
{
    float occ;
    bool single;
    uint32_t n = lightbuf_debug_cell(a, l, cell, ids, depths, LIST_CAP, &occ, &single);
    for (uint32_t k = 0; k < n && k < LIST_CAP; k++)
        if (ids[k] == id) return true;
    return false;
}

/* ------------------------------------------------------------ fullocc */

static void test_fullocc(void)
{
    scene_t *s = scene_new("fullocc");
    prims_t *p = &s->prims;
    uint32_t v[4] = {prims_add_vertex(p, v3(-10, -10, 5)), prims_add_vertex(p, v3(10, -10, 5)),
                     prims_add_vertex(p, v3(10, 10, 5)), prims_add_vertex(p, v3(-10, 10, 5))};
    uint32_t quad = prims_add_polygon(p, v, 4);
    uint32_t far = tri(s, v3(-0.5f, -0.5f, 20), v3(0.5f, -0.5f, 20), v3(0, 0.5f, 20)); /* behind the quad */
    tri(s, v3(-0.2f, -0.2f, -5), v3(0.2f, -0.2f, -5), v3(0, 0.2f, -5));                /* small, on -z */
    scene_add_light(s, v3(0, 0, 0));
    finish(s);
    const uint32_t res = 8;
    accel *a = lb_with(s, "res=8");
    /* Every +z cell (face 4): a record at the quad's farthest depth, 15. */
    int records = 0, far_listed = 0, quad_listed = 0;
    for (uint32_t c = 4 * res * res; c < 5 * res * res; c++) {
        float occ;
        bool single;
        lightbuf_debug_cell(a, 0, c, ids, depths, LIST_CAP, &occ, &single);
        records += occ >= 15.0f && occ <= 15.0f * (1 + 1e-5f);
        far_listed += listed(a, 0, c, far);
        quad_listed += listed(a, 0, c, quad);
    }
    CHECK_MSG(records == (int)(res * res), "%d of %u +z cells have the quad's record", records, res * res);
    CHECK_MSG(far_listed == 0, "the triangle behind the record stays in %d lists", far_listed);
    CHECK(quad_listed == (int)(res * res));
    /* The small triangle on -z covers no cell: no record there. */
    int minus_records = 0;
    for (uint32_t c = 5 * res * res; c < 6 * res * res; c++) {
        float occ;
        bool single;
        lightbuf_debug_cell(a, 0, c, ids, depths, LIST_CAP, &occ, &single);
        minus_records += occ < INFINITY;
    }
    CHECK(minus_records == 0);

    counters_t c;
    /* Beyond the record: in shadow, one cell read, no test. */
    ray_t r = shadow_ray(s, v3(0.3f, 0.2f, 30), 0);
    CHECK(ask(a, &r, &c) && c.prim_tests == 0 && c.steps == 1);
    /* Between the light and the quad: lit. */
    r = shadow_ray(s, v3(0.3f, 0.2f, 4), 0);
    CHECK(!ask(a, &r, &c) && !every_prim(s, &r));
    /* Just past the quad, nearer than its farthest point (a tie with the
     * record's range): the list is read, the quad tested, in shadow. */
    r = shadow_ray(s, v3(0.3f, 0.2f, 5.01f), 0);
    CHECK(ask(a, &r, &c) && c.prim_tests >= 1 && every_prim(s, &r));
    /* On the quad's lit side: lit. */
    r = shadow_ray(s, v3(0.3f, 0.2f, 4.999f), 0);
    CHECK(!ask(a, &r, &c) && !every_prim(s, &r));
    /* From beyond the record, but tnear starts the segment before the
     * quad: lit, and the record must not say otherwise. */
    r = shadow_ray(s, v3(0.3f, 0.2f, 30), 0);
    r.tnear = r.tfar * (26.0f / 30.0f); /* z = 4 */
    CHECK(!ask(a, &r, &c) && !every_prim(s, &r));
    /* fullocc=off: the same answers through tests. */
    accel *b = lb_with(s, "res=8,fullocc=off");
    r = shadow_ray(s, v3(0.3f, 0.2f, 30), 0);
    CHECK(ask(b, &r, &c) && c.prim_tests >= 1);
    float occ;
    bool single;
    lightbuf_debug_cell(b, 0, cell_of(s, 0, v3(0, 0, 30), res), ids, depths, LIST_CAP, &occ, &single);
    CHECK(occ == INFINITY);
    b->ops->destroy(b);
    a->ops->destroy(a);
    scene_free(s);
}

/* ------------------------------------------------------------- single */

static void test_single(void)
{
    scene_t *s = scene_new("single");
    uint32_t t = tri(s, v3(-1, -1, 5), v3(1, -1, 5), v3(0, 1, 5));
    tri(s, v3(-1, -1, -5), v3(1, -1, -5), v3(0, 1, -5)); /* elsewhere */
    scene_add_light(s, v3(0, 0, 0));
    finish(s);
    accel *a = lb_with(s, "res=8");
    uint32_t cell = cell_of(s, 0, v3(0, 0, 5), 8);
    float occ;
    bool single;
    uint32_t n = lightbuf_debug_cell(a, 0, cell, ids, depths, LIST_CAP, &occ, &single);
    CHECK(n == 1 && ids[0] == t && single);
    counters_t c;
    /* A point on the triangle's lit side, off its nearest point (so the
     * depth order alone would not stop before it): lit, by the plane test
     * alone. */
    const vec3 lit = v3(0.3f, -0.5f, 4.9999f);
    n = lightbuf_debug_cell(a, 0, cell_of(s, 0, lit, 8), ids, depths, LIST_CAP, &occ, &single);
    CHECK(n == 1 && ids[0] == t && single);
    ray_t r = shadow_ray(s, lit, 0);
    CHECK(!ask(a, &r, &c) && c.prim_tests == 0 && c.box_tests == 1);
    /* A point behind it (free space, or any surface there): the list of
     * one still shadows it. */
    r = shadow_ray(s, v3(0.01f, 0.02f, 9), 0);
    CHECK(ask(a, &r, &c) && c.prim_tests == 1 && every_prim(s, &r));
    a->ops->destroy(a);
    a = lb_with(s, "res=8,single=off");
    lightbuf_debug_cell(a, 0, cell, ids, depths, LIST_CAP, &occ, &single);
    CHECK(!single);
    r = shadow_ray(s, lit, 0);
    CHECK(!ask(a, &r, &c) && c.prim_tests == 1);
    a->ops->destroy(a);
    scene_free(s);

    /* A second primitive behind the triangle: the cell lists both, is not
     * single, and a point on the one behind is shadowed by the first. */
    s = scene_new("single-behind");
    t = tri(s, v3(-1, -1, 5), v3(1, -1, 5), v3(0, 1, 5));
    uint32_t q = tri(s, v3(-3, -3, 9), v3(3, -3, 9), v3(0, 3, 9));
    scene_add_light(s, v3(0, 0, 0));
    finish(s);
    a = lb_with(s, "res=8");
    n = lightbuf_debug_cell(a, 0, cell, ids, depths, LIST_CAP, &occ, &single);
    CHECK(n == 2 && ids[0] == t && ids[1] == q && !single);
    r = shadow_ray(s, v3(0.01f, 0.02f, 8.9999f), 0);
    CHECK(ask(a, &r, &c) && every_prim(s, &r));
    a->ops->destroy(a);
    scene_free(s);
}

/* --------------------------------------------------------------- cull */

enum { CUBE_OUT, CUBE_IN, CUBE_OPEN, CUBE_DENTED, CUBE_SPLIT, CUBE_FOLDED };

/* A unit cube at lo: outward or inward wound, open (no top), dented (the
 * top made of four triangles to a centre pushed in: concave, embedded),
 * with every triangle on its own vertices (matched by position), or
 * folded (one corner pushed through the bottom: closed and outward by its
 * volume, but self-intersecting). */
static void cube(scene_t *s, vec3 lo, int how)
{
    prims_t *p = &s->prims;
    vec3 c[8];
    uint32_t v[8];
    for (int i = 0; i < 8; i++) {
        c[i] = v3(lo.x + (i & 1), lo.y + ((i >> 1) & 1), lo.z + ((i >> 2) & 1));
        if (i == 7 && how == CUBE_FOLDED) c[i] = v3(lo.x + 0.3f, lo.y + 0.4f, lo.z - 0.7f);
        v[i] = prims_add_vertex(p, c[i]);
    }
    /* Outward (right-handed normals pointing out). */
    static const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int f = 0; f < 6; f++) {
        const int *q = faces[f];
        if (f == 1 && how == CUBE_OPEN) continue;
        if (f == 1 && how == CUBE_DENTED) {
            uint32_t m = prims_add_vertex(p, v3(lo.x + 0.5f, lo.y + 0.5f, lo.z + 0.5f));
            for (int e = 0; e < 4; e++) prims_add_triangle(p, v[q[e]], v[q[(e + 1) % 4]], m);
            continue;
        }
        int t[2][3] = {{q[0], q[1], q[2]}, {q[0], q[2], q[3]}};
        for (int k = 0; k < 2; k++) {
            if (how == CUBE_IN) prims_add_triangle(p, v[t[k][0]], v[t[k][2]], v[t[k][1]]);
            else if (how == CUBE_SPLIT) tri(s, c[t[k][0]], c[t[k][1]], c[t[k][2]]);
            else prims_add_triangle(p, v[t[k][0]], v[t[k][1]], v[t[k][2]]);
        }
    }
}

static uint32_t culled(const scene_t *s, accel *a, uint32_t l)
{
    uint32_t res, nnear, nculled;
    double rho;
    lightbuf_debug_light(a, l, &res, &nnear, &nculled, &rho);
    (void)s;
    return nculled;
}

/* Shadow rays from random points in and around the cube: the same
 * answers as testing every primitive. */
static void cube_answers(const scene_t *s, accel *a, const char *what)
{
    int wrong = 0;
    for (int i = 0; i < 4000; i++) {
        vec3 pt = v3(0.5f + 1.5f * srand1(), 0.5f + 1.5f * srand1(), 0.5f + 1.5f * srand1());
        ray_t r = shadow_ray(s, pt, 0);
        counters_t c;
        wrong += ask(a, &r, &c) != every_prim(s, &r);
    }
    CHECK_MSG(wrong == 0, "%s: %d answers differ from testing every primitive", what, wrong);
}

static void test_cull(void)
{
    static const struct { int how; vec3 light; uint32_t want; const char *what; } cases[] = {
        {CUBE_OUT, {5, 6, 7}, 6, "outward cube"},
        {CUBE_SPLIT, {5, 6, 7}, 6, "outward cube, every triangle on its own vertices"},
        {CUBE_IN, {5, 6, 7}, 0, "inward cube"},
        {CUBE_OPEN, {5, 6, 7}, 0, "open cube"},
        {CUBE_DENTED, {5, 6, 7}, 6, "dented (concave, embedded) cube"},
        {CUBE_FOLDED, {5, 6, 7}, 0, "folded (self-intersecting) cube"},
        /* In the dent: outside the solid, inside its hull; the bottom and
         * the four sides face away, the dent's four faces toward it. */
        {CUBE_DENTED, {0.5f, 0.5f, 0.9f}, 10, "dented cube with the light in its dent"},
        {CUBE_OUT, {0.5f, 0.4f, 0.3f}, 0, "outward cube around the light"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        scene_t *s = scene_new("cube");
        cube(s, v3(0, 0, 0), cases[k].how);
        scene_add_light(s, cases[k].light);
        finish(s);
        accel *a = lb_with(s, "res=4");
        CHECK_MSG(culled(s, a, 0) == cases[k].want, "%s: %u culled, want %u", cases[k].what, culled(s, a, 0),
                  cases[k].want);
        cube_answers(s, a, cases[k].what);
        a->ops->destroy(a);
        a = lb_with(s, "res=4,cull=off");
        CHECK(culled(s, a, 0) == 0);
        a->ops->destroy(a);
        scene_free(s);
    }
    /* gen:room, rotated off the axes (its split quads are coplanar only up
     * to float rounding): its box loses its back faces, its hall (the
     * lights are inside) does not. */
    scene_t *s = test_scene("gen:room");
    accel *a = lb_with(s, "");
    uint32_t total = 0;
    for (uint32_t l = 0; l < s->nlights; l++) total += culled(s, a, l);
    CHECK_MSG(total > 0 && total < 12 * s->nlights, "gen:room: %u culled over %u lights", total, s->nlights);
    printf("gen:room: %u primitives culled over %u lights\n", total, s->nlights);
    a->ops->destroy(a);
    scene_free(s);
    /* The bunny, closed and embedded (non-convex): about half its triangles
     * face away from each light. */
    s = test_scene("bunny");
    a = lb_with(s, "");
    total = culled(s, a, 0);
    CHECK_MSG(total > s->prims.count / 4 && total < s->prims.count, "bunny: %u of %u culled", total, s->prims.count);
    printf("bunny: %u of %u triangles culled for light 0\n", total, s->prims.count);
    a->ops->destroy(a);
    scene_free(s);
}

/* ------------------------------------------------------- conservative */

static scene_t *random_scene(void)
{
    scene_t *s = scene_new("random");
    prims_t *p = &s->prims;
    for (int i = 0; i < 300; i++) {
        vec3 c = v3(srand1(), srand1(), srand1());
        tri(s, v3_add(c, v3_scale(v3(srand1(), srand1(), srand1()), 0.3f)),
            v3_add(c, v3_scale(v3(srand1(), srand1(), srand1()), 0.3f)),
            v3_add(c, v3_scale(v3(srand1(), srand1(), srand1()), 0.3f)));
    }
    for (int i = 0; i < 10; i++) prims_add_sphere(p, v3(srand1(), srand1(), srand1()), 0.05f + 0.1f * urand());
    for (int i = 0; i < 6; i++)
        prims_add_cone(p, v3(srand1(), srand1(), srand1()), 0.1f * urand(), v3(srand1(), srand1(), srand1()),
                       0.02f + 0.1f * urand());
    for (int i = 0; i < 4; i++) { /* a pentagon each */
        vec3 c = v3(srand1(), srand1(), srand1());
        uint32_t v[5];
        for (int k = 0; k < 5; k++) {
            float ang = 6.2831853f * (float)k / 5.0f;
            v[k] = prims_add_vertex(p, v3_add(c, v3(0.3f * cosf(ang), 0.2f * sinf(ang), 0.1f * cosf(ang))));
        }
        prims_add_polygon(p, v, 5);
    }
    scene_add_light(s, v3(3.0f, 2.5f, 4.0f));   /* outside */
    scene_add_light(s, v3(0.1f, 0.05f, -0.02f)); /* among the primitives */
    finish(s);
    return s;
}

static void test_conservative(void)
{
    scene_t *s = random_scene();
    static const uint32_t resolutions[] = {1, 7, 32, 100};
    for (size_t k = 0; k < sizeof resolutions / sizeof resolutions[0]; k++) {
        char cfg[64];
        snprintf(cfg, sizeof cfg, "res=%u,cull=off,single=off,fullocc=off", resolutions[k]);
        accel *a = lb_with(s, cfg);
        int missing = 0, blockers = 0;
        for (uint32_t l = 0; l < s->nlights; l++) {
            uint32_t res, nnear, nculled;
            double rho;
            lightbuf_debug_light(a, l, &res, &nnear, &nculled, &rho);
            for (int i = 0; i < 3000; i++) {
                vec3 pt = v3(1.3f * srand1(), 1.3f * srand1(), 1.3f * srand1());
                ray_t r = shadow_ray(s, pt, l);
                uint32_t cell = cell_of(s, l, pt, res);
                for (uint32_t id = 0; id < s->prims.count; id++) {
                    if (!prim_occluded_fast(&s->prims, id, &r)) continue;
                    blockers++;
                    if (!listed(a, l, cell, id) && !listed(a, l, UINT32_MAX, id)) {
                        if (missing++ < 5)
                            fprintf(stderr, "res %u light %u: primitive %u blocks (%g %g %g) but is not in cell %u\n",
                                    res, l, id, pt.x, pt.y, pt.z, cell);
                    }
                }
            }
        }
        CHECK_MSG(missing == 0 && blockers > 1000, "%s: %d of %d blockers not listed", cfg, missing, blockers);
        a->ops->destroy(a);
    }
    /* Every setting answers as testing every primitive, counting and not,
     * on shadow rays and on any-hit rays that carry a light but do not
     * end at it. */
    static const char *const settings[] = {"", "cull=off", "single=off", "fullocc=off", "res=1", "res=5", "res=64", "res=auto"};
    for (size_t k = 0; k < sizeof settings / sizeof settings[0]; k++) {
        accel *a = lb_with(s, settings[k]);
        int wrong = 0, fast_wrong = 0;
        for (int i = 0; i < 6000; i++) {
            vec3 pt = v3(1.3f * srand1(), 1.3f * srand1(), 1.3f * srand1());
            uint32_t l = (uint32_t)i % s->nlights;
            ray_t r = shadow_ray(s, pt, l);
            if (i % 5 == 4) r.tfar *= 0.5f + 0.4f * urand(); /* stops short of the light */
            if (i % 7 == 6) r.light = i % 2 ? RAY_NO_LIGHT : 9;
            counters_t c;
            bool want = every_prim(s, &r), got = ask(a, &r, &c);
            wrong += got != want;
            fast_wrong += a->ops->occluded_fast(a, NULL, &r) != got;
        }
        CHECK_MSG(wrong == 0 && fast_wrong == 0, "[%s]: %d answers differ from every primitive's, %d fast ones", settings[k],
                  wrong, fast_wrong);
        a->ops->destroy(a);
    }
    scene_free(s);
}

/* res=auto: about four primitives a cell where the scene is seen. A
 * cluster far from the light gets a fine cube, the same cluster around
 * the light a coarse one. */
static void test_auto(void)
{
    uint32_t res[2];
    for (int k = 0; k < 2; k++) {
        scene_t *s = scene_new("auto");
        for (int i = 0; i < 2000; i++) {
            vec3 c = v3(srand1(), srand1(), srand1());
            tri(s, c, v3_add(c, v3(0.01f, 0, 0)), v3_add(c, v3(0, 0.01f, 0)));
        }
        scene_add_light(s, k ? v3(0.01f, 0.02f, 0.03f) : v3(40, 30, 20));
        finish(s);
        accel *a = lb_with(s, "res=auto");
        uint32_t nnear, nculled;
        double rho;
        lightbuf_debug_light(a, 0, &res[k], &nnear, &nculled, &rho);
        a->ops->destroy(a);
        scene_free(s);
    }
    /* Far: 2000 centres within a few of the coarse cube's 500 cells; around: all 6 faces' ~500. */
    CHECK_MSG(res[0] >= 100 && res[0] <= 512, "far cluster: res=auto chose %u", res[0]);
    CHECK_MSG(res[1] >= 8 && res[1] <= 16, "cluster around the light: res=auto chose %u", res[1]);
    printf("res=auto: %u for a far cluster, %u around the light\n", res[0], res[1]);
}

/* ----------------------------------------------------------- refusals */

static void test_refusals(void)
{
    scene_t *s = test_scene("spd:balls:1");
    const struct accel_ops *ops = accel_find("lightbuf");
    char err[512];
    accel *a = test_build_with(ops, s, "res=1024,memcap=1", 1, err, sizeof err);
    CHECK_MSG(!a && strstr(err, "memcap=1"), "res=1024 under memcap=1: %s", a ? "built" : err);
    if (a) a->ops->destroy(a);
    test_expect_refusal("lightbuf", s, "res=1025", "res");
    test_expect_refusal("lightbuf", s, "res=0", "res");
    test_expect_refusal("lightbuf", s, "cull=maybe", "cull");
    scene_free(s);
    /* The lists, not the cells, over the cap: spd:balls:3's three lights
     * at res=256 need 22.6 MiB before their lists (cells 18 MiB, scratch
     * 4.5 MiB), and their lists some MiB more. */
    s = test_scene("spd:balls:3");
    a = test_build_with(ops, s, "res=256,memcap=23", 1, err, sizeof err);
    CHECK_MSG(!a && strstr(err, "lists"), "res=256 under memcap=23: %s", a ? "built" : err);
    if (a) a->ops->destroy(a);
    a = test_build_with(ops, s, "res=256,memcap=64", 1, err, sizeof err);
    CHECK_MSG(a != NULL, "res=256 under memcap=64: %s", a ? "" : err);
    if (a) {
        CHECK(a->ops->memory(a) <= (size_t)64 << 20);
        a->ops->destroy(a);
    }
    scene_free(s);
}

/* The solid angle of [u0, u1] x [v0, v1] on a cube face at distance 1:
 * the integral of (1 + u^2 + v^2)^(-3/2), by the midpoint rule. */
static double solid_angle_numeric(double u0, double u1, double v0, double v1)
{
    const int n = 400;
    double sum = 0.0, du = (u1 - u0) / n, dv = (v1 - v0) / n;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double u = u0 + (i + 0.5) * du, v = v0 + (j + 0.5) * dv;
            sum += pow(1.0 + u * u + v * v, -1.5);
        }
    return sum * du * dv;
}

static void test_model(void)
{
    {
        scene_t *s = scene_new("one tiny triangle");
        vec3 p = v3(10, 0, 0);
        tri(s, p, v3_add(p, v3(0, 0.01f, 0)), v3_add(p, v3(0, 0, 0.01f)));
        scene_add_light(s, v3(0, 0, 0));
        finish(s);
        accel *a = lb_with(s, "res=1");
        CHECK(fabs(test_stat(a, "predicted_tests_per_ray") - 1.0) < 1e-9 && test_stat(a, "predicted_steps_per_ray") == 1.0);
        a->ops->destroy(a);
        scene_free(s);
    }
    {
        /* res 3 on +x: u, v in thirds; (10, 0, 0) is the centre cell,
         * (10, 7, 7) and (10, 8, 8) (u = v = 0.7, 0.8) the corner cell. */
        scene_t *s = scene_new("centre and corner");
        static const float at[3][3] = {{10, 0, 0}, {10, 7, 7}, {10, 8, 8}};
        for (int k = 0; k < 3; k++) {
            vec3 p = v3(at[k][0], at[k][1], at[k][2]);
            tri(s, p, v3_add(p, v3(0, 0.01f, 0)), v3_add(p, v3(0, 0, 0.01f)));
        }
        scene_add_light(s, v3(0, 0, 0));
        finish(s);
        accel *a = lb_with(s, "res=3");
        const double third = 1.0 / 3.0, centre = solid_angle_numeric(-third, third, -third, third),
                     corner = solid_angle_numeric(third, 1, third, 1), want = (centre + 2 * corner) / (centre + corner);
        double got = test_stat(a, "predicted_tests_per_ray");
        printf("model by hand res=3: %.6f, want %.6f (solid angles %.6f, %.6f)\n", got, want, centre, corner);
        CHECK(fabs(got - want) < 1e-5);
        a->ops->destroy(a);
        scene_free(s);
    }
    scene_t *s = scene_new("tiny triangles around a light");
    for (int i = 0; i < 3000; i++) {
        vec3 p = v3(10 * srand1(), 10 * srand1(), 10 * srand1());
        if (v3_len(p) < 1.0f) continue;
        tri(s, p, v3_add(p, v3(0.02f, 0, 0)), v3_add(p, v3(0, 0.02f, 0.01f)));
    }
    scene_add_light(s, v3(0.3f, 0.2f, 0.1f));
    finish(s);
    static const char *const cfgs[] = {"res=4,single=off,fullocc=off,cull=off", "res=32,single=off,fullocc=off,cull=off",
                                       "res=32"};
    static const uint32_t res[] = {4, 32, 32};
    const uint32_t N = 200000;
    for (int k = 0; k < 3; k++) {
        accel *a = lb_with(s, cfgs[k]);
        const double want = test_stat(a, "predicted_tests_per_ray");
        counters_t c = {0};
        uint32_t shadowed = 0;
        rng = 4242;
        for (uint32_t i = 0; i < N; i++) {
            vec3 d;
            do d = v3(srand1(), srand1(), srand1());
            while (v3_len(d) > 1.0f || v3_len(d) < 1e-3f);
            vec3 pt = v3_add(s->lights[0], v3_scale(d, 100.0f / v3_len(d)));
            float occ;
            bool single;
            uint32_t ids[1];
            float depths[1];
            if (!lightbuf_debug_cell(a, 0, cell_of(s, 0, pt, res[k]), ids, depths, 0, &occ, &single)) {
                i--; /* a direction where no surface lies: no query starts there */
                continue;
            }
            ray_t r = shadow_ray(s, pt, 0);
            shadowed += a->ops->occluded(a, NULL, &r, &c);
        }
        const double got = (double)c.prim_tests / N, steps = (double)c.steps / N;
        printf("model %-40s %u rays (%u shadowed): tests %.4f predicted %.4f, cells read %.4f\n", cfgs[k], N, shadowed,
               got, want, steps);
        if (k < 2) {
            CHECK_MSG(fabs(got - want) < fmax(0.02 * want, 4.0 * sqrt(want / N)), "%s: tests %.4f, predicted %.4f",
                      cfgs[k], got, want);
            CHECK_MSG(fabs(steps - 1.0) < 1e-9, "%s: %.4f cells read per query", cfgs[k], steps);
        } else {
            CHECK_MSG(got <= want, "%s: tests %.4f above the bound %.4f", cfgs[k], got, want);
        }
        a->ops->destroy(a);
    }
    scene_free(s);
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    test_model();
    test_fullocc();
    test_single();
    test_cull();
    test_conservative();
    test_auto();
    test_refusals();
    return check_report();
}
