/* test_bsp: the BSP tree `bsp` (accel/bsp/bsp_kaplan_jansen.c, its kd-tree kit
 * accel/bsp/kd_*.c and prims/clip.c), beyond the conformance suite.
 *
 *   in-plane    rays lying exactly in split planes of built trees (every
 *               traversal, every builder): the same answer as exhaustive,
 *               ray for ray; rays lying in the root plane across a shared
 *               edge that lies in it hit one of the two triangles
 *   straddle    a triangle crossing a split plane is in both subtrees, and
 *               rays from either side and from behind find it
 *   maxdepth=0  one cell: every ray tests exactly what exhaustive tests
 *   refusals    absurd depths, a bad value, perfect splits without SAH,
 *               the memory cap
 *   sah         two clusters far apart: the root plane separates them
 *   clip        prim_clip_bounds on hand-made triangles and a sphere
 *   mailbox     on and off give the same answers; on skips re-tests */
#include <string.h>
#include "accel/bsp/bsp_kaplan_jansen.h"
#include "testlib.h"

static const char *const travs[] = {"recursive", "sequential", "havran"};
static const char *const builders[] = {"split=midpoint", "split=sah", "split=sah,perfect=on"};

static accel *bsp_with(const scene_t *s, const char *cfg) { return test_build_or_die("bsp", s, cfg); }

static void tri(scene_t *s, vec3 a, vec3 b, vec3 c)
{
    uint32_t i = prims_add_vertex(&s->prims, a), j = prims_add_vertex(&s->prims, b), k = prims_add_vertex(&s->prims, c);
    prims_add_triangle(&s->prims, i, j, k);
}

static void finish(scene_t *s) { test_finish_scene(s); }

static void push(rayset_t *rs, vec3 o, vec3 d)
{
    ray_t r = {o, 0.0f, d, INFINITY, RAY_NO_LIGHT, 0};
    rayset_push(rs, &r, 0);
}

/* A small deterministic generator (the tests must not depend on libc's). */
static uint32_t rng = 12345;
static float urand(void) { return test_urand(&rng); }
static float srand1(void) { return 2.0f * urand() - 1.0f; }

/* Does the subtree at node hold primitive id? */
static bool subtree_has(const kd_tree *t, uint32_t node, uint32_t id)
{
    const kd_node *n = &t->nodes[node];
    if (kd_is_leaf(n)) {
        uint32_t k;
        const uint32_t *ids = kd_leaf_ids(t, n, &k);
        for (uint32_t i = 0; i < k; i++)
            if (ids[i] == id) return true;
        return false;
    }
    return subtree_has(t, node + 1, id) || subtree_has(t, kd_above(n), id);
}

/* Every ray: the same primitive and the same t bits as exhaustive. */
static void check_same(const char *what, accel *a, accel *ex, const rayset_t *rs, uint32_t *hits_out)
{
    answers_t *got = test_trace(a, rs, 1), *want = test_trace(ex, rs, 1);
    uint32_t diff = 0, hits = 0, first = 0;
    for (uint32_t i = 0; i < rs->count; i++) {
        hit_t g = got->hits[i], w = want->hits[i];
        hits += w.prim != HIT_NONE;
        bool same = g.prim == w.prim && (w.prim == HIT_NONE || memcmp(&g.t, &w.t, sizeof g.t) == 0);
        if (!same && !diff++) first = i;
    }
    CHECK_MSG(diff == 0, "%s: %u of %u rays differ from exhaustive (first %u)", what, diff, rs->count, first);
    if (hits_out) *hits_out = hits;
    answers_free(got);
    answers_free(want);
}

/* ---- rays lying in split planes ---- */

/* 300 small random triangles in [-1,1]^3, and the corners that make the
 * root cell exactly that cube (so the midpoint planes are 0, +-0.5, ...). */
static scene_t *random_scene(void)
{
    scene_t *s = scene_new("random-tris");
    rng = 777;
    tri(s, v3(-1, -1, -1), v3(-0.99f, -1, -1), v3(-1, -0.99f, -1));
    tri(s, v3(1, 1, 1), v3(0.99f, 1, 1), v3(1, 0.99f, 1));
    for (int i = 0; i < 300; i++) {
        vec3 c = v3(0.85f * srand1(), 0.85f * srand1(), 0.85f * srand1());
        vec3 a = v3_add(c, v3(0.25f * srand1(), 0.25f * srand1(), 0.25f * srand1()));
        vec3 b = v3_add(c, v3(0.25f * srand1(), 0.25f * srand1(), 0.25f * srand1()));
        vec3 d = v3_add(c, v3(0.25f * srand1(), 0.25f * srand1(), 0.25f * srand1()));
        tri(s, a, b, d);
    }
    finish(s);
    return s;
}

/* Rays lying in the split planes of the first interior nodes: the origin's
 * coordinate on the axis is the split, the direction's is +0 or -0; some
 * also lie in a second plane (axis-aligned, two zero components). */
static rayset_t *in_plane_rays(const kd_tree *t, int *nplanes)
{
    rayset_t *rs = rayset_new("in-plane", "random-tris", 0, QUERY_CLOSEST);
    int planes = 0;
    for (uint32_t n = 0; n < t->nnodes && planes < 60; n++) {
        const kd_node *nd = &t->nodes[n];
        if (kd_is_leaf(nd)) continue;
        planes++;
        int a = kd_axis(nd), a1 = (a + 1) % 3, a2 = (a + 2) % 3;
        for (int k = 0; k < 12; k++) {
            float o[3], d[3];
            o[a] = nd->split;
            o[a1] = 1.3f * srand1();
            o[a2] = 1.3f * srand1();
            d[a] = (k & 1) ? -0.0f : 0.0f;
            d[a1] = srand1();
            d[a2] = srand1();
            if (k >= 9) d[a1] = (k & 2) ? -0.0f : 0.0f, d[a2] = 1.0f - 2.0f * (k == 10); /* along a2 only */
            if (d[a1] == 0 && d[a2] == 0) d[a2] = 1.0f;
            push(rs, v3(o[0], o[1], o[2]), v3(d[0], d[1], d[2]));
        }
    }
    rayset_seal(rs);
    *nplanes = planes;
    return rs;
}

static void test_in_plane(void)
{
    scene_t *s = random_scene();
    accel *ex = test_build("exhaustive", s, 1);
    for (size_t bi = 0; bi < 3; bi++) {
        accel *a0 = bsp_with(s, builders[bi]);
        int planes = 0;
        rayset_t *rs = in_plane_rays(bsp_debug_tree(a0), &planes);
        a0->ops->destroy(a0);
        CHECK_MSG(planes >= 20, "%s: only %d split planes", builders[bi], planes);
        for (int ti = 0; ti < 3; ti++) {
            char cfg[128], what[300];
            snprintf(cfg, sizeof cfg, "%s,traverse=%s", builders[bi], travs[ti]);
            accel *a = bsp_with(s, cfg);
            uint32_t hits = 0;
            snprintf(what, sizeof what, "in-plane rays [%s]", cfg);
            check_same(what, a, ex, rs, &hits);
            CHECK_MSG(hits * 4 >= rs->count, "%s: only %u of %u rays hit; the test proves little", what, hits, rs->count);
            printf("%-50s %u rays in %d planes, %u hit\n", what, rs->count, planes, hits);
            a->ops->destroy(a);
        }
        rayset_free(rs);
    }
    ex->ops->destroy(ex);
    scene_free(s);

    /* Two triangles sharing an edge that lies in the root plane x = 0 of
     * the midpoint tree, one on each side. Rays lying in that plane cross
     * the shared edge: one of the two must be hit (watertight), whichever
     * side of the plane the traversal takes. */
    s = scene_new("edge-in-plane");
    tri(s, v3(-1, -1, -1), v3(-0.99f, -1, -1), v3(-1, -0.99f, -1));
    tri(s, v3(1, 1, 1), v3(0.99f, 1, 1), v3(1, 0.99f, 1));
    tri(s, v3(0, -0.5f, 0.2f), v3(0, 0.5f, 0.2f), v3(-0.5f, 0, 0.2f)); /* id 2, x <= 0 */
    tri(s, v3(0, 0.5f, 0.2f), v3(0, -0.5f, 0.2f), v3(0.5f, 0, 0.2f));  /* id 3, x >= 0 */
    finish(s);
    rayset_t *rs = rayset_new("edge", s->name, 0, QUERY_CLOSEST);
    for (int k = -4; k <= 4; k++) {
        push(rs, v3(0, 0.1f * (float)k, -1), v3(0.0f, 0, 1));
        push(rs, v3(-0.0f, 0.1f * (float)k, 2), v3(-0.0f, 0, -1));
        push(rs, v3(0, 0.1f * (float)k - 0.6f, -1), v3(0.0f, 0.5f, 1)); /* slanted, still in x = 0 */
    }
    rayset_seal(rs);
    for (size_t bi = 0; bi < 3; bi++)
        for (int ti = 0; ti < 3; ti++) {
            char cfg[128];
            snprintf(cfg, sizeof cfg, "%s,traverse=%s,maxprims=1", builders[bi], travs[ti]);
            accel *a = bsp_with(s, cfg);
            const kd_tree *t = bsp_debug_tree(a);
            if (bi == 0) CHECK_MSG(!kd_is_leaf(&t->nodes[0]) && kd_axis(&t->nodes[0]) == 0 && t->nodes[0].split == 0.0f,
                                   "[%s]: the root plane is not x = 0", cfg);
            answers_t *got = test_trace(a, rs, 1);
            uint32_t bad = 0;
            for (uint32_t i = 0; i < rs->count; i++) {
                hit_t h = got->hits[i];
                float want = i % 3 == 2 ? 1.2f : i % 3 == 0 ? 1.2f : 1.8f;
                if (!((h.prim == 2 || h.prim == 3) && fabsf(h.t - want) < 1e-5f)) bad++;
            }
            CHECK_MSG(bad == 0, "[%s]: %u of %u rays along the shared edge in the plane missed it", cfg, bad, rs->count);
            answers_free(got);
            a->ops->destroy(a);
        }
    rayset_free(rs);
    scene_free(s);
}

/* ---- a primitive straddling a plane ---- */

/* For every interior node: where the triangle's part inside the node's cell
 * reaches beyond the plane on both sides (by more than the slack), both
 * children hold it. Returns how many such nodes there were. */
static int straddle_check(const kd_tree *t, const prims_t *p, uint32_t node, box3 cell, uint32_t id, const char *what)
{
    const kd_node *n = &t->nodes[node];
    if (kd_is_leaf(n)) return 0;
    int a = kd_axis(n);
    box3 below = cell, above = cell;
    if (a == 0) below.hi.x = above.lo.x = n->split;
    if (a == 1) below.hi.y = above.lo.y = n->split;
    if (a == 2) below.hi.z = above.lo.z = n->split;
    int found = 0;
    box3 part = prim_clip_bounds(p, id, cell);
    bool inb = subtree_has(t, node + 1, id), ina = subtree_has(t, kd_above(n), id);
    if ((inb || ina) && !box_is_empty(part) && v3_get(part.lo, a) < n->split - 2 * t->pad &&
        v3_get(part.hi, a) > n->split + 2 * t->pad) {
        found = 1;
        CHECK_MSG(inb && ina, "%s: node %u splits the triangle at %g (axis %d) but only the %s side holds it", what, node,
                  (double)n->split, a, inb ? "below" : "above");
    }
    return found + straddle_check(t, p, node + 1, below, id, what) + straddle_check(t, p, kd_above(n), above, id, what);
}

static void test_straddle(void)
{
    scene_t *s = scene_new("straddle");
    tri(s, v3(-1, -1, -1), v3(-0.99f, -1, -1), v3(-1, -0.99f, -1));
    tri(s, v3(1, 1, 1), v3(0.99f, 1, 1), v3(1, 0.99f, 1));
    /* Clutter on both sides, so the trees go deep around the big one. */
    rng = 99;
    for (int i = 0; i < 40; i++) {
        vec3 c = v3(0.8f * srand1(), 0.8f * srand1(), urand() < 0.5f ? -0.6f : 0.8f);
        tri(s, c, v3_add(c, v3(0.1f, 0, 0.05f)), v3_add(c, v3(0, 0.1f, -0.05f)));
    }
    uint32_t big = s->prims.count;
    tri(s, v3(-0.8f, -0.8f, 0.5f), v3(0.8f, -0.8f, 0.5f), v3(0.05f, 0.8f, 0.5f));
    finish(s);
    accel *ex = test_build("exhaustive", s, 1);
    rayset_t *rs = rayset_new("straddle", s->name, 0, QUERY_CLOSEST);
    for (int k = 0; k < 9; k++) {
        float x = -0.6f + 0.15f * (float)k, y = -0.6f;
        push(rs, v3(x, y, 0.0f), v3(0, 0, 1));     /* from below z = 0.5, on either side of x = 0 */
        push(rs, v3(x, y, 0.7f), v3(0, 0, -1));    /* from above */
        push(rs, v3(-x, y, 0.3f), v3(0.2f, 0, 1)); /* slanted */
    }
    rayset_seal(rs);
    for (size_t bi = 0; bi < 3; bi++) {
        accel *a0 = bsp_with(s, builders[bi]);
        const kd_tree *t = bsp_debug_tree(a0);
        char what[128];
        snprintf(what, sizeof what, "straddle [%s]", builders[bi]);
        int nodes = straddle_check(t, &s->prims, 0, t->box, big, what);
        CHECK_MSG(nodes >= 2, "%s: only %d planes cut the big triangle", what, nodes);
        if (bi == 0) CHECK(kd_axis(&t->nodes[0]) == 0 && t->nodes[0].split == 0.0f && subtree_has(t, 1, big) &&
                           subtree_has(t, kd_above(&t->nodes[0]), big));
        printf("%s: %d planes cut the big triangle, each with it on both sides\n", what, nodes);
        a0->ops->destroy(a0);
        for (int ti = 0; ti < 3; ti++) {
            char cfg[100];
            snprintf(cfg, sizeof cfg, "%s,traverse=%s", builders[bi], travs[ti]);
            accel *a = bsp_with(s, cfg);
            answers_t *got = test_trace(a, rs, 1);
            uint32_t onbig = 0;
            for (uint32_t i = 0; i < rs->count; i++) onbig += got->hits[i].prim == big;
            CHECK_MSG(onbig == rs->count, "[%s]: %u of %u rays at the big triangle hit it", cfg, onbig, rs->count);
            answers_free(got);
            snprintf(what, sizeof what, "straddle rays [%s]", cfg);
            check_same(what, a, ex, rs, NULL);
            a->ops->destroy(a);
        }
    }
    rayset_free(rs);
    ex->ops->destroy(ex);
    scene_free(s);
}

/* ---- maxdepth=0: one cell ---- */

static void test_one_cell(void)
{
    scene_t *s = test_scene("spd:balls:2");
    accel *ref = test_build("embree", s, 1), *ex = test_build("exhaustive", s, 1);
    workload_opts o = test_wl(16, 16, 1);
    /* Rays from inside the scene box and shadow rays (from surfaces), so
     * that every ray enters the one cell. */
    const char *wls[] = {"inside", "shadow"};
    for (int w = 0; w < 2; w++) {
        rayset_t *rs;
        if (w == 0) {
            rs = rayset_new("inside", s->name, 0, QUERY_CLOSEST);
            box3 b = s->prims.box;
            vec3 e = box_extent(b);
            rng = 31;
            for (int i = 0; i < 300; i++)
                push(rs, v3_add(b.lo, v3_mul(e, v3(urand(), urand(), urand()))), v3(srand1(), srand1(), srand1()));
            rayset_seal(rs);
        } else {
            rs = workload_find(wls[w])->make(s, ref, &o);
        }
        answers_t *want = answers_new(rs, true);
        trace_rayset(ex, rs, 1, want);
        for (int ti = 0; ti < 3; ti++)
            for (int sah = 0; sah < 2; sah++) {
                char cfg[128];
                snprintf(cfg, sizeof cfg, "maxdepth=0,traverse=%s%s", travs[ti], sah ? ",split=sah" : "");
                accel *a = bsp_with(s, cfg);
                const kd_tree *t = bsp_debug_tree(a);
                CHECK(t->nnodes == 1 && t->nleaves == 1 && t->ninterior == 0 && t->nrefs == s->prims.count);
                answers_t *got = answers_new(rs, true);
                trace_rayset(a, rs, 1, got);
                uint32_t diff = 0;
                for (uint32_t i = 0; i < rs->count; i++) diff += got->per_ray[i].prim_tests != want->per_ray[i].prim_tests;
                CHECK_MSG(diff == 0, "[%s] %s: %u of %u rays test other than exhaustive's count", cfg, wls[w], diff,
                          rs->count);
                CHECK_MSG(got->total.prim_tests == want->total.prim_tests && got->total.steps == rs->count,
                          "[%s] %s: tests %llu vs %llu, steps %llu", cfg, wls[w], (unsigned long long)got->total.prim_tests,
                          (unsigned long long)want->total.prim_tests, (unsigned long long)got->total.steps);
                if (ti == 0 && !sah)
                    printf("maxdepth=0 %s: %.1f tests per ray, exhaustive %.1f\n", wls[w],
                           (double)got->total.prim_tests / rs->count, (double)want->total.prim_tests / rs->count);
                answers_free(got);
                a->ops->destroy(a);
            }
        answers_free(want);
        rayset_free(rs);
    }
    ex->ops->destroy(ex);
    ref->ops->destroy(ref);
    scene_free(s);
}

/* ---- refusals ---- */

static void expect_refusal(const scene_t *s, const char *cfg, const char *needle)
{
    test_expect_refusal("bsp", s, cfg, needle);
}

static void test_refusals(void)
{
    scene_t *s = test_scene("spd:balls:3");
    expect_refusal(s, "maxdepth=65", "maxdepth=65");
    expect_refusal(s, "maxdepth=1000000", "maxdepth");
    expect_refusal(s, "maxdepth=-1", "maxdepth");
    expect_refusal(s, "maxdepth=deep", "maxdepth");
    expect_refusal(s, "maxprims=-2", "maxprims");
    expect_refusal(s, "emptybonus=1.5", "emptybonus");
    expect_refusal(s, "perfect=on", "perfect");
    expect_refusal(s, "traverse=sideways", "traverse");
    /* The cap. Subdividing every non-empty cell of 821 spheres to depth 64
     * would take far more than 4 MiB; the 66,431 primitives of balls:5
     * need more than 1 MiB of events at the SAH root alone, and more than
     * 1 MiB of midpoint tree. */
    expect_refusal(s, "maxdepth=64,maxprims=0,memcap=4", "memcap=4 MiB");
    scene_t *s5 = test_scene("spd:balls:5");
    expect_refusal(s5, "memcap=1", "memcap=1 MiB");
    expect_refusal(s5, "split=sah,memcap=1", "memcap=1 MiB");
    scene_free(s5);
    /* The deepest accepted depth still builds on a small scene. */
    scene_t *r = random_scene();
    accel *a = bsp_with(r, "maxdepth=64");
    CHECK(bsp_debug_tree(a)->max_depth <= 64);
    a->ops->destroy(a);
    scene_free(r);
    scene_free(s);
}

/* ---- SAH on a hand-built case ---- */

static void test_sah_split(void)
{
    scene_t *s = scene_new("two-clusters");
    rng = 4242;
    for (int c = 0; c < 2; c++)
        for (int i = 0; i < 30; i++) {
            vec3 o = v3(9.0f * (float)c + 0.9f * urand(), 0.9f * urand(), 0.9f * urand());
            tri(s, o, v3_add(o, v3(0.1f, 0, 0)), v3_add(o, v3(0, 0.1f, 0.1f)));
        }
    finish(s);
    for (int perfect = 0; perfect < 2; perfect++) {
        accel *a = bsp_with(s, perfect ? "split=sah,perfect=on" : "split=sah");
        const kd_tree *t = bsp_debug_tree(a);
        const kd_node *root = &t->nodes[0];
        CHECK_MSG(!kd_is_leaf(root) && kd_axis(root) == 0, "perfect=%d: the root is not a plane on x", perfect);
        float sp = root->split, ahi = -INFINITY, blo = INFINITY;
        for (uint32_t id = 0; id < s->prims.count; id++) {
            box3 bb = prim_bounds(&s->prims, id);
            if (id < 30) ahi = fmaxf(ahi, bb.hi.x);
            else blo = fminf(blo, bb.lo.x);
        }
        CHECK_MSG(sp > ahi && sp < blo, "perfect=%d: the root plane x = %g does not separate the clusters (%g, %g)",
                  perfect, (double)sp, (double)ahi, (double)blo);
        uint32_t wrong = 0;
        for (uint32_t id = 0; id < s->prims.count; id++) {
            bool left = id < 30;
            wrong += subtree_has(t, left ? 1 : kd_above(root), id) != true;
            wrong += subtree_has(t, left ? kd_above(root) : 1, id) != false;
        }
        CHECK_MSG(wrong == 0, "perfect=%d: %u cluster memberships wrong", perfect, wrong);
        printf("sah perfect=%d: root plane x = %g between the clusters, which end at %g and start at %g\n", perfect,
               (double)sp, (double)ahi, (double)blo);
        a->ops->destroy(a);
    }
    scene_free(s);
}

/* ---- prim_clip_bounds ---- */

static void test_clip(void)
{
    scene_t *s = scene_new("clip");
    tri(s, v3(0, 0, 0), v3(2, 0, 0), v3(0, 2, 0));
    tri(s, v3(5, 5, 5), v3(6, 5, 5), v3(5, 6, 5));
    tri(s, v3(0, 0, -1), v3(2, 0, 1), v3(0, 2, 1)); /* slanted */
    prims_add_sphere(&s->prims, v3(0, 0, 0), 1.0f);
    finish(s);
    const prims_t *p = &s->prims;
    box3 box = {{1, -1, -1}, {3, 3, 1}};
    /* The part with x >= 1: (1,0), (2,0), (1,1). Exact but for y = 1, an
     * interpolated coordinate: rounded outward by at most an ulp. */
    box3 c = prim_clip_bounds(p, 0, box);
    CHECK_MSG(c.lo.x == 1 && c.hi.x == 2 && c.lo.y == 0 && c.hi.y >= 1 && c.hi.y <= nextafterf(1, 2) && c.lo.z == 0 &&
                  c.hi.z == 0,
              "clip: [%.9g %.9g] [%.9g %.9g] [%.9g %.9g]", c.lo.x, c.hi.x, c.lo.y, c.hi.y, c.lo.z, c.hi.z);
    CHECK(box_is_empty(prim_clip_bounds(p, 1, box)));
    /* The slanted one: z = x + y - 1, so x >= 1 gives z in [0, 1]. */
    c = prim_clip_bounds(p, 2, box);
    CHECK_NEAR(c.lo.x, 1.0, 1e-6);
    CHECK_NEAR(c.hi.x, 2.0, 1e-6);
    CHECK_NEAR(c.hi.y, 1.0, 1e-6);
    CHECK_NEAR(c.lo.z, 0.0, 1e-6);
    CHECK_NEAR(c.hi.z, 1.0, 1e-6);
    CHECK(c.lo.x >= box.lo.x && c.hi.z <= box.hi.z); /* inside the box */
    /* Touching at a vertex only: the point. */
    box3 corner = {{2, -1, -1}, {3, 1, 1}};
    c = prim_clip_bounds(p, 0, corner);
    CHECK_MSG(!box_is_empty(c) && c.lo.x == 2 && c.hi.x == 2 && c.lo.y == 0 && c.hi.y == 0, "vertex touch");
    /* A sphere: its bounds within the box, empty when it misses. */
    c = prim_clip_bounds(p, 3, box);
    CHECK(c.lo.x == 1 && c.hi.x == 1 && c.lo.y == -1 && c.hi.y == 1);
    box3 far = {{1, 1, 1}, {3, 3, 3}}; /* the box's corner (1,1,1) is sqrt 3 from the centre */
    CHECK(box_is_empty(prim_clip_bounds(p, 3, far)));
    scene_free(s);
}

/* ---- mailboxes ---- */

static void test_mailbox(void)
{
    scene_t *s = test_scene("spd:balls:2");
    workload_opts o = test_wl(24, 24, 1);
    rayset_t *rs = workload_find("random")->make(s, NULL, &o);
    for (int ti = 0; ti < 3; ti++) {
        char con[64], coff[64];
        snprintf(con, sizeof con, "traverse=%s", travs[ti]);
        snprintf(coff, sizeof coff, "traverse=%s,mailbox=off", travs[ti]);
        accel *on = bsp_with(s, con), *off = bsp_with(s, coff);
        answers_t *a = test_trace(on, rs, 1), *b = test_trace(off, rs, 1);
        uint32_t diff = 0;
        for (uint32_t i = 0; i < rs->count; i++)
            diff += a->hits[i].prim != b->hits[i].prim || memcmp(&a->hits[i].t, &b->hits[i].t, sizeof(float)) != 0;
        CHECK_MSG(diff == 0, "[%s]: %u answers change with the mailbox", con, diff);
        CHECK_MSG(a->total.mailbox_hits > 0 && b->total.mailbox_hits == 0, "[%s]: mailbox hits %llu / %llu", con,
                  (unsigned long long)a->total.mailbox_hits, (unsigned long long)b->total.mailbox_hits);
        CHECK(a->total.prim_tests + a->total.mailbox_hits == b->total.prim_tests);
        answers_free(a);
        answers_free(b);
        on->ops->destroy(on);
        off->ops->destroy(off);
    }
    rayset_free(rs);
    scene_free(s);
}

int main(void)
{
    test_clip();
    test_sah_split();
    test_in_plane();
    test_straddle();
    test_one_cell();
    test_refusals();
    test_mailbox();
    return check_report();
}
