/* test_raycoh: Ohta and Maekawa's ray coherence `raycoh`
 * (accel/raycoh_ohta_maekawa.c), beyond the conformance suite.
 *
 *   cones       random pairs of spheres (apart, touching, overlapping,
 *               nested, one a point), random segments from a point of the
 *               first (inside or on its surface) to a point of the second:
 *               the cube of every tested res lists the second sphere in the
 *               cell of the segment's direction, and the stored distance
 *               bound d is at most the segment's length
 *   origins     secondary rays (shadow, reflection, diffuse, whitted's)
 *               carry the primitive they leave: in range, and their origin
 *               within a few ulps of its bounds; eye and random rays carry
 *               RAY_NO_ORIGIN (gen:room, and spd:gears:1 for refracted rays)
 *   brute force secondary rays with their origins (the workloads' own, and
 *               the same origins with random directions, some into the
 *               surface, some with positive tnear, finite and infinite
 *               tfar) on mixed scenes, closest and any hit, against a test
 *               of every primitive (`exhaustive`): the same t bit for bit,
 *               the same occlusion; most of them answered by a cube
 *   wrong       the same rays with a wrong origin (random primitives, out
 *               of range, RAY_NO_ORIGIN): still exact (fallback or a cube
 *               whose sphere holds the origin after all)
 *   memcap      a build over the cap is refused with the reason
 *   refusals    bad parameter values name the parameter */
#include <string.h>
#include "accel/raycoh_ohta_maekawa.h"
#include "testlib.h"

static uint32_t rng = 4242;
static float urand(void)
{
    rng = rng * 1664525u + 1013904223u;
    return (float)(rng >> 8) / 16777216.0f;
}
static float srand1(void) { return 2.0f * urand() - 1.0f; }

static vec3 unit_random(void)
{
    for (;;) {
        vec3 d = v3(srand1(), srand1(), srand1());
        float l = v3_len(d);
        if (l > 1e-3f && l <= 1.0f) return v3_scale(d, 1.0f / l);
    }
}

/* A point of the ball (c, r): on its surface half the time (the tangent extremes). */
static vec3 ball_point(vec3 c, float r)
{
    float k = urand() < 0.5f ? 1.0f : cbrtf(urand());
    return v3_add(c, v3_scale(unit_random(), r * k));
}

static accel *rc_with(const scene_t *s, const char *cfg)
{
    char err[512];
    accel *a = test_build_with(accel_find("raycoh"), s, cfg, 1, err, sizeof err);
    if (!a) {
        fprintf(stderr, "raycoh [%s] on %s: %s\n", cfg, s->name, err);
        exit(2);
    }
    return a;
}

/* ---------------------------------------------------------- the cones */

static void test_cones(void)
{
    static const uint32_t res[] = {1, 2, 3, 8, 17, 64};
    uint64_t tested = 0, missed = 0, short_d = 0;
    for (int pair = 0; pair < 3000; pair++) {
        float scale = exp2f(20.0f * urand() - 10.0f);
        vec3 c1 = v3_scale(v3(srand1(), srand1(), srand1()), scale);
        float r1 = urand() < 0.1f ? 0.0f : scale * 0.3f * urand();
        float gap = scale * (urand() < 0.2f ? 0.01f * urand() : 3.0f * urand());
        float r2 = scale * 0.5f * urand();
        vec3 c2 = v3_add(c1, v3_scale(unit_random(), r1 + r2 + gap - (urand() < 0.1f ? 2.0f * gap : 0.0f)));
        uint32_t rs = res[pair / 500];
        float d = raycoh_debug_depth(c1, r1, c2, r2);
        for (int k = 0; k < 40; k++) {
            vec3 p = ball_point(c1, r1), q = ball_point(c2, r2);
            /* The exact spheres: points rounded outside them are not the theorem's. */
            if (v3_len(v3_sub(p, c1)) > r1 || v3_len(v3_sub(q, c2)) > r2) continue;
            vec3 dir = v3_sub(q, p);
            if (v3_len(dir) == 0.0f) continue;
            tested++;
            if (!raycoh_debug_listed(c1, r1, c2, r2, rs, dir)) {
                if (missed++ < 5)
                    fprintf(stderr, "  res %u: spheres (%g %g %g) r %g, (%g %g %g) r %g: dir (%g %g %g) not listed\n", rs,
                            c1.x, c1.y, c1.z, r1, c2.x, c2.y, c2.z, r2, dir.x, dir.y, dir.z);
            }
            if ((double)d > (double)v3_len(dir) * (1 + 1e-6)) short_d++;
        }
    }
    printf("cones: %llu segments, %llu not listed, %llu shorter than d\n", (unsigned long long)tested,
           (unsigned long long)missed, (unsigned long long)short_d);
    CHECK(tested > 50000);
    CHECK(missed == 0);
    CHECK(short_d == 0);
    /* Apart by far: a narrow cone lists few cells, so the test means something. */
    int listed = 0;
    for (int k = 0; k < 1000; k++) listed += raycoh_debug_listed(v3(0, 0, 0), 1, v3(100, 0, 0), 1, 8, unit_random());
    CHECK_MSG(listed < 100, "a narrow cone listed in %d of 1000 random directions' cells", listed);
}

/* ---------------------------------------------------------- origins */

/* Whether p is within a relative slack of box b. */
static bool near_box(vec3 p, box3 b)
{
    float e = 1e-4f * (box_diagonal(b) + fmaxf(fmaxf(fabsf(p.x), fabsf(p.y)), fabsf(p.z))) + 1e-6f;
    return p.x >= b.lo.x - e && p.x <= b.hi.x + e && p.y >= b.lo.y - e && p.y <= b.hi.y + e && p.z >= b.lo.z - e &&
           p.z <= b.hi.z + e;
}

static void test_origins(const scene_t *s, accel *ref)
{
    workload_opts o = test_wl(16, 16, 1);
    o.depth = 5;
    static const char *const wls[] = {"primary", "random", "shadow", "reflection", "diffuse", "whitted:eye",
                                      "whitted:reflected", "whitted:refracted", "whitted:shadow"};
    for (size_t w = 0; w < sizeof wls / sizeof wls[0]; w++) {
        rayset_t *rs = workload_find(wls[w])->make(s, ref, &o);
        bool none = strcmp(wls[w], "primary") == 0 || strcmp(wls[w], "random") == 0 || strcmp(wls[w], "whitted:eye") == 0;
        uint32_t bad = 0;
        for (uint32_t i = 0; i < rs->count; i++) {
            const ray_t *r = &rs->rays[i];
            if (none) bad += r->origin != RAY_NO_ORIGIN;
            else bad += r->origin >= s->prims.count || !near_box(r->org, prim_bounds(&s->prims, r->origin));
        }
        printf("origins: %s %s: %u rays, %u wrong\n", s->name, wls[w], rs->count, bad);
        CHECK_MSG(bad == 0, "%s %s: %u rays with a wrong origin", s->name, wls[w], bad);
        rayset_free(rs);
    }
}

/* ---------------------------------------------------------- brute force */

/* The rays: each workload's own, then every other one's direction made random. */
static rayset_t *secondary_rays(const scene_t *s, accel *ref, query_kind q)
{
    workload_opts o = test_wl(24, 24, 1);
    rayset_t *out = rayset_new("random", s->name, 1, q);
    static const char *const wls[] = {"shadow", "reflection", "diffuse", "whitted:refracted", "whitted:reflected"};
    for (size_t w = 0; w < sizeof wls / sizeof wls[0]; w++) {
        rayset_t *rs = workload_find(wls[w])->make(s, ref, &o);
        for (uint32_t i = 0; i < rs->count; i++) {
            ray_t r = rs->rays[i];
            if (q == QUERY_ANY && r.tfar == INFINITY) r.tfar = 1e30f;
            if (i % 2) {
                /* t in units of dir: |dir| of 1, 3 and 1e-3. (Not far smaller: at 1e-22 a float
                 * |dir|^2 is denormal and the primitives' own tests, exhaustive's and bsp's too,
                 * stop being exact, so no reference is left to compare with.) */
                r.dir = v3_scale(unit_random(), i % 4 == 1 ? 1.0f : i % 8 == 3 ? 3.0f : 1e-3f);
                float len = 1.0f / v3_len(r.dir);
                r.tfar = i % 3 ? INFINITY : 0.5f * box_diagonal(s->prims.box) * len;
                if (i % 5 == 0) r.tnear = 0.01f * r.tfar;
                if (q == QUERY_ANY && r.tfar == INFINITY) r.tfar = 2.0f * box_diagonal(s->prims.box) * len;
            }
            rayset_push(out, &r, 0);
        }
        rayset_free(rs);
    }
    rayset_seal(out);
    return out;
}

/* Every ray through a and the exhaustive reference: the same t, the same occlusion. */
static void compare(const scene_t *s, accel *a, accel *ex, const rayset_t *rs, const char *label)
{
    accel_ctx *ca = a->ops->context_new ? a->ops->context_new(a) : NULL;
    accel_ctx *ce = ex->ops->context_new ? ex->ops->context_new(ex) : NULL;
    uint32_t wrong = 0, fast_wrong = 0, hits = 0, cube = 0;
    counters_t c = {0};
    for (uint32_t i = 0; i < rs->count; i++) {
        const ray_t *r = &rs->rays[i];
        cube += raycoh_debug_uses_cube(a, r);
        if (rs->query == QUERY_CLOSEST) {
            hit_t h1 = hit_none(r), h2 = hit_none(r), h3 = hit_none(r);
            bool b1 = a->ops->intersect(a, ca, r, &h1, &c), b2 = ex->ops->intersect(ex, ce, r, &h2, &c);
            bool b3 = a->ops->intersect_fast(a, ca, r, &h3);
            hits += b2;
            if (b1 != b2 || h1.t != h2.t) {
                if (wrong++ < 5)
                    fprintf(stderr, "  %s %s ray %u: raycoh %u t %.9g, exhaustive %u t %.9g\n", s->name, label, i, h1.prim,
                            h1.t, h2.prim, h2.t);
            }
            fast_wrong += b3 != b1 || h3.t != h1.t || h3.prim != h1.prim;
        } else {
            bool b1 = a->ops->occluded(a, ca, r, &c), b2 = ex->ops->occluded(ex, ce, r, &c);
            bool b3 = a->ops->occluded_fast(a, ca, r);
            hits += b2;
            if (b1 != b2 && wrong++ < 5) fprintf(stderr, "  %s %s ray %u: raycoh %d, exhaustive %d\n", s->name, label, i, b1, b2);
            fast_wrong += b3 != b1;
        }
    }
    printf("brute force: %-12s %-34s %s rays %6u hits %6u by cube %6u wrong %u fast-wrong %u\n", s->name, label,
           rs->query == QUERY_ANY ? "any    " : "closest", rs->count, hits, cube, wrong, fast_wrong);
    CHECK_MSG(wrong == 0, "%s %s: %u wrong answers", s->name, label, wrong);
    CHECK_MSG(fast_wrong == 0, "%s %s: %u fast answers differ", s->name, label, fast_wrong);
    CHECK_MSG(hits > 0, "%s %s: nothing hit; the test proves nothing", s->name, label);
    if (a->ops->context_free) a->ops->context_free(ca);
    if (ex->ops->context_free) ex->ops->context_free(ce);
}

/* The same rays with a wrong origin: random primitives, out of range, none. */
static rayset_t *with_wrong_origins(const scene_t *s, const rayset_t *rs)
{
    rayset_t *out = rayset_new("random", s->name, 1, rs->query);
    for (uint32_t i = 0; i < rs->count; i++) {
        ray_t r = rs->rays[i];
        uint32_t k = i % 4;
        r.origin = k == 0 ? RAY_NO_ORIGIN : k == 1 ? s->prims.count + i : (uint32_t)(urand() * (float)s->prims.count) % s->prims.count;
        rayset_push(out, &r, 0);
    }
    rayset_seal(out);
    return out;
}

static void test_brute(const char *scene, const char *const *cfgs)
{
    scene_t *s = test_scene(scene);
    accel *ex = test_build("exhaustive", s, 1);
    if (strcmp(scene, "gen:room") == 0 || strcmp(scene, "spd:gears:1") == 0) test_origins(s, ex);
    for (int k = 0; cfgs[k]; k++) {
        accel *a = rc_with(s, cfgs[k]);
        printf("  [%s]: %u clusters, %zu bytes\n", cfgs[k], raycoh_debug_clusters(a), a->ops->memory(a));
        for (int q = 0; q < 2; q++) {
            rayset_t *rs = secondary_rays(s, ex, q ? QUERY_ANY : QUERY_CLOSEST);
            char label[96];
            snprintf(label, sizeof label, "[%s]", cfgs[k]);
            compare(s, a, ex, rs, label);
            rayset_t *w = with_wrong_origins(s, rs);
            snprintf(label, sizeof label, "[%s] wrong origins", cfgs[k]);
            compare(s, a, ex, w, label);
            rayset_free(w);
            rayset_free(rs);
        }
        a->ops->destroy(a);
    }
    ex->ops->destroy(ex);
    scene_free(s);
}

/* lights=on: shadow rays toward a light go through the light's cube (a
 * light buffer): the same answers as exhaustive, work counted as the light
 * buffer counts it (so different from the clusters' cubes), and the light
 * buffer's memory on top. */
static void test_lights(void)
{
    scene_t *s = test_scene("spd:gears:1");
    accel *ex = test_build("exhaustive", s, 1);
    accel *off = rc_with(s, ""), *on = rc_with(s, "lights=on");
    workload_opts o = test_wl(24, 24, 1);
    rayset_t *rs = workload_find("shadow")->make(s, ex, &o);
    CHECK(rs->count > 0 && rs->rays[0].light != RAY_NO_LIGHT);
    compare(s, on, ex, rs, "[lights=on] shadow");
    counters_t con = {0}, coff = {0};
    accel_ctx *xon = on->ops->context_new(on), *xoff = off->ops->context_new(off);
    for (uint32_t i = 0; i < rs->count; i++) {
        on->ops->occluded(on, xon, &rs->rays[i], &con);
        off->ops->occluded(off, xoff, &rs->rays[i], &coff);
    }
    on->ops->context_free(xon), off->ops->context_free(xoff);
    CHECK_MSG(con.steps != coff.steps || con.prim_tests != coff.prim_tests,
              "lights=on counted as lights=off: the light's cube was not used");
    CHECK(on->ops->memory(on) > off->ops->memory(off));
    rayset_free(rs);
    on->ops->destroy(on), off->ops->destroy(off), ex->ops->destroy(ex);
    scene_free(s);
}

/* ---------------------------------------------------------- refusals */

static void test_memcap(void)
{
    scene_t *s = test_scene("spd:balls:2");
    char err[512];
    accel *a = test_build_with(accel_find("raycoh"), s, "memcap=1,objsize=1,res=64", 1, err, sizeof err);
    CHECK_MSG(a == NULL && strstr(err, "memcap=1") != NULL, "build over memcap=1: %s", a ? "built" : err);
    printf("memcap: %s\n", err);
    if (a) a->ops->destroy(a);
    /* Within the cap at objsize 1: lists grown while building are checked too. */
    a = test_build_with(accel_find("raycoh"), s, "memcap=2,objsize=1,res=16", 1, err, sizeof err);
    CHECK_MSG(a == NULL ? strstr(err, "memcap=2") != NULL : a->ops->memory(a) <= 3u << 20, "memcap=2: %s",
              a ? "over" : err);
    if (a) a->ops->destroy(a);
    scene_free(s);
}

static void test_refusals(void)
{
    scene_t *s = test_scene("spd:balls:1");
    struct { const char *cfg, *want; } bad[] = {
        {"res=0", "res"},           {"res=65", "res"},           {"objsize=0", "objsize"},
        {"objsize=70000", "objsize"}, {"spheres=maybe", "spheres"},     {"fallback=nosuch", "fallback=nosuch: must be a registered"},
        {"fallback=raycoh", "fallback=raycoh: must be"}, {"fallback=lightbuf", "fallback=lightbuf: must be"},
        {"fallback=grid-raybox", "fallback=grid-raybox: must be"}, {"lights=maybe", "lights"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char err[512] = "";
        accel *a = test_build_with(accel_find("raycoh"), s, bad[i].cfg, 1, err, sizeof err);
        CHECK_MSG(!a && strstr(err, bad[i].want), "[%s]: want '%s', got '%s'", bad[i].cfg, bad[i].want, a ? "built" : err);
        if (a) a->ops->destroy(a);
    }
    scene_free(s);
}

int main(void)
{
    test_refusals();
    test_memcap();
    test_cones();
    test_lights();
    static const char *const mixed[] = {"", "res=1,objsize=1", "res=5,objsize=3", "res=5,objsize=3,spheres=off", "res=16,objsize=1000,fallback=exhaustive",
                                        NULL};
    static const char *const big[] = {"", "res=3,objsize=4", "objsize=2,spheres=off", "lights=on", NULL};
    test_brute("gen:room", mixed);
    test_brute("spd:balls:2", mixed);
    test_brute("spd:tree:2", big);
    test_brute("spd:gears:1", big); /* polygons, and glass: refracted rays leave from the far side */
    return check_report();
}
