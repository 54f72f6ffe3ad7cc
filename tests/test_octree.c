/* test_octree: Glassner's octree (accel/octree/octree_glassner.c) beyond the
 * conformance suite.
 *
 * - Names and hashing on a hand-built case: three small triangles whose
 *   octree (maxdepth 2, maxprims 1) is known in advance: root 1 and node
 *   18 interior, leaves 11, 181, 188, every other name absent (an empty
 *   voxel); each stored name sits in bucket name mod size (a prime at
 *   least the names), point location returns the expected names, and the
 *   table's statistics are consistent. The octree's hash_mod table on its
 *   own: buckets of 96-bit keys, the incremental bucket, lookups of present
 *   and absent keys, refusals (key 0, a key twice, a bad size).
 * - Names past 64 bits: a dense cluster at maxdepth 20 reaches depth 20,
 *   whose 21-digit names (about 1.1e20 and up) are found in the table and
 *   read back digit by digit as the octants of the path.
 * - minlen stepping: eight one-triangle octants (maxdepth 1); a ray through
 *   the centre vertex and one through an edge take exactly two voxels with
 *   walk=glassner (the moved point crosses all the exit faces at once) and
 *   one zero-length voxel per extra exit face with walk=fujimoto; both hit
 *   what the exhaustive test hits, with no fallback.
 * - The walks' safety nets, made to fire (a backward step, a tiny step
 *   cap), still give exhaustive's answers.
 * - maxdepth=0: one cell, whose tests per ray equal exhaustive's exactly
 *   (closest hit and any hit) on every ray that meets the box.
 * - Refusals: absurd depths (21, -1, 1000, a word) and a build passing
 *   its memcap, each with a one-line reason naming the parameter.
 * - No fallback of either walk on the SPD sphereflake's five workloads. */
#include <string.h>
#include "accel/octree/hash_mod.h"
#include "accel/common/slab.h"
#include "accel/octree/octree_glassner.h"
#include "testlib.h"

typedef unsigned __int128 u128;

static accel *build(const scene_t *s, const char *cfg)
{
    char err[512];
    accel *a = test_build_with(accel_find("octree"), s, cfg, 1, err, sizeof err);
    if (!a) {
        fprintf(stderr, "octree [%s] failed to build: %s\n", cfg, err);
        exit(2);
    }
    return a;
}

static scene_t *finish(scene_t *s)
{
    char err[256];
    if (scene_finish(s, false, err, sizeof err)) {
        fprintf(stderr, "%s: %s\n", s->name, err);
        exit(2);
    }
    return s;
}

static uint32_t tri(scene_t *s, vec3 a, vec3 b, vec3 c)
{
    prims_t *p = &s->prims;
    return prims_add_triangle(p, prims_add_vertex(p, a), prims_add_vertex(p, b), prims_add_vertex(p, c));
}

/* A small triangle inside the cube [c - r, c + r]^3 (it spans x and y). */
static uint32_t small_tri(scene_t *s, vec3 c, float r)
{
    return tri(s, v3(c.x - r, c.y - r, c.z), v3(c.x + r, c.y - r, c.z), v3(c.x, c.y + r, c.z + r));
}

static bool is_prime(uint32_t n)
{
    if (n < 2) return false;
    for (uint32_t d = 2; (uint64_t)d * d <= n; d++)
        if (n % d == 0) return false;
    return true;
}

/* ---------------------------------------------------- hash_mod alone */

static void test_hash_mod(void)
{
    uint32_t size = hash_mod_prime_at_least(100);
    CHECK(size == 101);
    CHECK(hash_mod_prime_at_least(0) == 3 && hash_mod_prime_at_least(HASH_MOD_MAX_SIZE + 1ull) == 0);
    /* Buckets of wide keys against 128-bit arithmetic, built digit by digit. */
    hash_mod_table h;
    hash_mod_entry one = {1, 0, 0};
    CHECK(hash_mod_build(&h, size, &one, 1) == 0);
    u128 k = 1;
    uint32_t home = hash_mod_home(&h, 1, 0);
    for (int d = 0; d < 27; d++) {
        uint32_t digit = 1 + (uint32_t)(d * 5 % 8);
        k = k * 10 + digit;
        home = hash_mod_extend(&h, home, 10, digit);
        uint32_t direct = hash_mod_home(&h, (uint64_t)k, (uint32_t)(k >> 64));
        CHECK_MSG(home == direct && direct == (uint32_t)(k % size), "digit %d: home %u, direct %u, want %u", d, home,
                  direct, (uint32_t)(k % size));
    }
    hash_mod_free(&h);
    /* 300 keys, wide and narrow, in 101 buckets: every one found with its
     * value, absent ones not, probe counts within the bucket's length. */
    enum { NK = 300 };
    hash_mod_entry e[NK];
    for (uint32_t i = 0; i < NK; i++) e[i] = (hash_mod_entry){7 + 101ull * 3 * i, i % 3 ? 0 : i, i};
    CHECK(hash_mod_build(&h, size, e, NK) == 0 && h.count == NK);
    int bad = 0;
    uint32_t total = 0;
    for (uint32_t i = 0; i < NK; i++) {
        uint32_t pr = 0, hm = hash_mod_home(&h, e[i].key_lo, e[i].key_hi);
        const uint32_t *v = hash_mod_find(&h, e[i].key_lo, e[i].key_hi, hm, &pr);
        bad += !v || *v != i || pr < 1 || pr > h.start[hm + 1] - h.start[hm];
        total += pr;
        pr = 0;
        bad += hash_mod_find(&h, e[i].key_lo + 1, e[i].key_hi, hash_mod_home(&h, e[i].key_lo + 1, e[i].key_hi), &pr) != NULL;
    }
    CHECK_MSG(bad == 0 && total >= NK, "%d wrong lookups", bad);
    hash_mod_free(&h);
    /* Refused: a key 0, a key twice, a size out of range. */
    hash_mod_entry dup[3] = {{5, 0, 1}, {9, 2, 2}, {5, 0, 3}}, zero = {0, 0, 1};
    CHECK(hash_mod_build(&h, 11, dup, 3) == -1 && !h.start);
    CHECK(hash_mod_build(&h, 11, &zero, 1) == -1);
    CHECK(hash_mod_build(&h, 2, dup, 2) == -1 && hash_mod_build(&h, HASH_MOD_MAX_SIZE + 1, dup, 2) == -1);
}

/* ------------------------------------------------------- names, hand-built */

static void test_names(void)
{
    /* C in octant 1 of the root; A and B in node 18's octants 1 and 8. The
     * bounds [0.5, 7.5]^3 put the root's mid planes at 4 and node 18's at
     * 5.75 (up to pad). */
    scene_t *s = scene_new("names");
    uint32_t C = small_tri(s, v3(1, 1, 1), 0.5f);
    uint32_t A = small_tri(s, v3(5, 5, 5), 0.5f);
    uint32_t B = small_tri(s, v3(7, 7, 7), 0.5f);
    finish(s);
    accel *a = build(s, "maxdepth=2,maxprims=1");
    octree_info in;
    octree_debug_info(a, &in);
    CHECK_MSG(in.interior == 2 && in.leaves == 3 && in.empty == 12 && in.depth == 2,
              "interior %u leaves %u empty %u depth %d", in.interior, in.leaves, in.empty, in.depth);
    CHECK_MSG(in.table_count == 5 && is_prime(in.table_size) && in.table_size >= in.table_count,
              "table %u names in %u slots", in.table_count, in.table_size);

    struct { uint64_t name; int kind; uint32_t id; } want[] = {
        {1, OCTREE_INTERIOR, 0}, {11, OCTREE_LEAF, C}, {18, OCTREE_INTERIOR, 0}, {181, OCTREE_LEAF, A},
        {188, OCTREE_LEAF, B},   {12, OCTREE_ABSENT, 0}, {17, OCTREE_ABSENT, 0},  {185, OCTREE_ABSENT, 0},
        {111, OCTREE_ABSENT, 0}, {1881, OCTREE_ABSENT, 0},
    };
    uint32_t maxp = 0;
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        octree_node_info n = octree_debug_node(a, want[i].name, 0);
        CHECK_MSG(n.kind == want[i].kind, "name %llu: kind %d, want %d", (unsigned long long)want[i].name, n.kind,
                  want[i].kind);
        CHECK_MSG(n.home == want[i].name % in.table_size, "name %llu: home %u", (unsigned long long)want[i].name, n.home);
        if (want[i].kind == OCTREE_LEAF)
            CHECK_MSG(n.count == 1 && n.ids[0] == want[i].id, "leaf %llu: %u candidates", (unsigned long long)want[i].name,
                      n.count);
        if (n.kind != OCTREE_ABSENT) {
            if (n.probes > maxp) maxp = n.probes;
            CHECK(n.probes >= 1);
        }
    }
    CHECK_MSG(in.probes_max == maxp && in.probes_avg >= 1.0 && in.probes_avg <= in.probes_max,
              "probes avg %g max %u (seen %u)", in.probes_avg, in.probes_max, maxp);
    CHECK(in.probes_miss_avg >= 0.0 && in.probes_miss_avg <= in.table_count);

    /* Point location by names; a tie on a mid plane goes the ray's way. */
    float mx = 0.5f * (in.root.lo.x + in.root.hi.x); /* the root's x mid plane, about 4 */
    struct { vec3 q, dir; uint64_t name; int depth; } loc[] = {
        {{1, 1, 1}, {1, 0, 0}, 11, 1},   {{5, 5, 5}, {1, 0, 0}, 181, 2}, {{7, 7, 7}, {1, 0, 0}, 188, 2},
        {{7, 1, 1}, {1, 0, 0}, 12, 1},   {{1, 7, 7}, {1, 0, 0}, 17, 1},  {{5, 7, 5}, {1, 0, 0}, 183, 2},
        {{mx, 1, 1}, {1, 0, 0}, 12, 1},  {{mx, 1, 1}, {-1, 0, 0}, 11, 1}, {{mx, 1, 1}, {0, 1, 0}, 12, 1},
    };
    for (size_t i = 0; i < sizeof loc / sizeof loc[0]; i++) {
        uint64_t lo;
        uint32_t hi;
        int depth;
        octree_debug_locate(a, loc[i].q, loc[i].dir, &lo, &hi, &depth);
        CHECK_MSG(lo == loc[i].name && hi == 0 && depth == loc[i].depth, "locate %zu: name %llu depth %d, want %llu %d",
                  i, (unsigned long long)lo, depth, (unsigned long long)loc[i].name, loc[i].depth);
    }
    a->ops->destroy(a);
    scene_free(s);
}

/* --------------------------------------------------- names past 64 bits */

static void test_deep_names(void)
{
    /* 300 triangles in a 1e-5 cluster at (1, 1, 1) inside a box 8.5
     * across: at depth 20 a voxel is 8e-6 across, and grown by the
     * insertion pad (2.5e-5) it still touches the whole cluster, so the
     * tree goes down to maxdepth 20 there. */
    scene_t *s = scene_new("deep");
    uint64_t st = 99;
    for (int k = 0; k < 300; k++) {
        float c[3];
        for (int i = 0; i < 3; i++) {
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            c[i] = 1.0f + 1e-5f * (float)((st >> 11) / 9007199254740992.0);
        }
        small_tri(s, v3(c[0], c[1], c[2]), 1e-6f);
    }
    small_tri(s, v3(-3, -3, -3), 0.5f);
    small_tri(s, v3(4.5f, 4.5f, 4.5f), 0.5f);
    finish(s);
    const char *cfgs[] = {"maxdepth=20,maxprims=8", "maxdepth=20,maxprims=8,walk=fujimoto"};
    for (int w = 0; w < 2; w++) {
        accel *a = build(s, cfgs[w]);
        octree_info in;
        octree_debug_info(a, &in);
        CHECK_MSG(in.depth == 20, "%s: depth %d", cfgs[w], in.depth);
        /* The voxel of one cluster triangle's centre: depth 20, 21 digits. */
        const prims_t *p = &s->prims;
        box3 tb = prim_bounds(p, 17);
        vec3 q = box_center(tb);
        uint64_t lo;
        uint32_t hi;
        int depth;
        octree_debug_locate(a, q, v3(1, 0, 0), &lo, &hi, &depth);
        u128 name = ((u128)hi << 64) | lo;
        CHECK_MSG(depth == 20 && hi != 0, "%s: depth %d, high word %u", cfgs[w], depth, hi);
        octree_node_info n = octree_debug_node(a, lo, hi);
        CHECK_MSG(n.kind == OCTREE_LEAF && n.count > 0, "%s: the depth-20 name is not a stored leaf", cfgs[w]);
        bool listed = false;
        for (uint32_t i = 0; i < n.count; i++) listed |= n.ids[i] == 17;
        CHECK_MSG(listed, "%s: triangle 17 is not a candidate of its own voxel", cfgs[w]);
        CHECK(n.home == (uint32_t)(name % in.table_size));
        /* Read the digits back: 20 octants 1..8 under a leading 1, which
         * retrace the box of the voxel down from the root. */
        int digits[21], nd = 0;
        for (u128 x = name; x; x /= 10) digits[nd < 21 ? nd : 20] = (int)(x % 10), nd++;
        CHECK_MSG(nd == 21 && digits[20] == 1, "%s: %d digits", cfgs[w], nd);
        box3 b = in.root;
        bool inside = nd == 21;
        for (int d = 19; d >= 0 && inside; d--) {
            int oct = digits[d] - 1;
            inside = oct >= 0 && oct < 8;
            if (!inside) break;
            vec3 m = box_center(b);
            if (oct & 1) b.lo.x = m.x; else b.hi.x = m.x;
            if (oct & 2) b.lo.y = m.y; else b.hi.y = m.y;
            if (oct & 4) b.lo.z = m.z; else b.hi.z = m.z;
        }
        CHECK_MSG(inside && q.x >= b.lo.x && q.x <= b.hi.x && q.y >= b.lo.y && q.y <= b.hi.y && q.z >= b.lo.z &&
                      q.z <= b.hi.z,
                  "%s: the name's digits do not lead to the point", cfgs[w]);
        /* Rays into the cluster hit what exhaustive hits. */
        accel *ex = test_build("exhaustive", s, 1);
        accel_ctx *cx = a->ops->context_new(a);
        int agree = 0, total = 0;
        for (int i = 0; i < 300; i++) {
            box3 bi = prim_bounds(p, (uint32_t)i);
            vec3 target = box_center(bi);
            ray_t r = {v3(-2.0f, 0.5f + 0.001f * (float)i, 3.0f), 0.0f, v3_sub(target, v3(-2.0f, 0.5f + 0.001f * (float)i, 3.0f)), INFINITY, RAY_NO_LIGHT, 0};
            hit_t h1 = hit_none(&r), h2 = hit_none(&r);
            counters_t c1 = {0}, c2 = {0};
            a->ops->intersect(a, cx, &r, &h1, &c1);
            ex->ops->intersect(ex, NULL, &r, &h2, &c2);
            total++;
            /* The same primitive, or (coincident hits) another at the same t. */
            agree += h1.prim == h2.prim ? h1.t == h2.t : h1.prim != HIT_NONE && h2.prim != HIT_NONE && h1.t == h2.t;
        }
        uint64_t rel, exh;
        octree_debug_fallbacks(cx, &rel, &exh);
        printf("deep %-40s depth %d, %u nodes, %u leaves, table %u/%u, probes avg %.3f max %u miss %.3f; agree %d/%d, "
               "relocated %llu, exhaustive %llu\n",
               cfgs[w], in.depth, in.interior, in.leaves, in.table_count, in.table_size, in.probes_avg, in.probes_max,
               in.probes_miss_avg, agree, total, (unsigned long long)rel, (unsigned long long)exh);
        CHECK_MSG(agree == total, "%s: %d of %d rays into the cluster agree with exhaustive", cfgs[w], agree, total);
        CHECK_MSG(exh == 0, "%s: %llu walks fell back to testing everything", cfgs[w], (unsigned long long)exh);
        a->ops->context_free(cx);
        ex->ops->destroy(ex);
        a->ops->destroy(a);
    }
    scene_free(s);
}

/* ------------------------------------------------------- minlen stepping */

typedef struct {
    const char *what;
    ray_t ray;
    uint64_t steps[2]; /* glassner, fujimoto */
} step_case;

static void test_stepping(void)
{
    /* One triangle in each octant of the box [0.5, 7.5]^3 (mid planes at
     * 4), lying in the plane z = 2 or 6 around the octant's centre, plus a
     * vertical one in octant 4 (x and y high, z low) in the plane x = 6. */
    scene_t *s = scene_new("octants");
    for (int oct = 0; oct < 8; oct++) {
        vec3 c = v3(oct & 1 ? 6.0f : 2.0f, oct & 2 ? 6.0f : 2.0f, oct & 4 ? 6.0f : 2.0f);
        tri(s, v3(c.x - 1.5f, c.y - 1.5f, c.z), v3(c.x + 1.5f, c.y - 1.5f, c.z), v3(c.x, c.y + 1.5f, c.z));
    }
    uint32_t wall = tri(s, v3(6, 4.5f, 2), v3(6, 7.5f, 2), v3(6, 6, 3.5f));
    finish(s);
    /* The root's mid planes (about 4; pad moves them by float steps): the
     * rays below start a whole unit before them along (1, 1, *), so their
     * exit planes' ts tie exactly (m - (m - 1) = 1 in float). */
    vec3 m;
    {
        accel *a = build(s, "maxdepth=1,maxprims=0");
        octree_info in;
        octree_debug_info(a, &in);
        m = box_center(in.root);
        a->ops->destroy(a);
    }
    step_case cases[] = {
        /* Through the centre vertex (4, 4, 4) into octant 8, hitting its
         * triangle at (6, 6, 6): Glassner moves across three faces at once;
         * Fujimoto's 3DDDA takes x, y, z in turn (two zero-length voxels). */
        {"vertex", {{m.x - 1, m.y - 1, m.z - 1}, 0, {1, 1, 1}, INFINITY, RAY_NO_LIGHT, 0}, {2, 4}},
        /* Through the edge x = y = 4 at z = 2.5 into octant 4, hitting the
         * wall at (6, 6, 2.5): two faces at once, or one zero-length voxel. */
        {"edge", {{m.x - 1, m.y - 1, 2.5f}, 0, {1, 1, 0}, INFINITY, RAY_NO_LIGHT, 0}, {2, 3}},
        /* A face exit for comparison: octant 1 to octant 2 only. */
        {"face", {{3, 2.2f, 2.5f}, 0, {1, 0, 0}, INFINITY, RAY_NO_LIGHT, 0}, {2, 2}},
    };
    uint32_t want_prim[] = {7, wall, HIT_NONE};
    accel *ex = test_build("exhaustive", s, 1);
    for (int w = 0; w < 2; w++) {
        accel *a = build(s, w ? "maxdepth=1,maxprims=0,walk=fujimoto" : "maxdepth=1,maxprims=0");
        octree_info in;
        octree_debug_info(a, &in);
        CHECK_MSG(in.interior == 1 && in.leaves == 8 && in.depth == 1, "octants: %u interior, %u leaves", in.interior,
                  in.leaves);
        CHECK_NEAR(in.minlen, 2.0, 1e-3); /* z: [2, 6] halved */
        accel_ctx *cx = a->ops->context_new(a);
        for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
            const ray_t *r = &cases[i].ray;
            hit_t h = hit_none(r), he = hit_none(r);
            counters_t c = {0}, ce = {0};
            a->ops->intersect(a, cx, r, &h, &c);
            ex->ops->intersect(ex, NULL, r, &he, &ce);
            CHECK_MSG(h.prim == want_prim[i] && he.prim == want_prim[i] && h.t == he.t,
                      "%s walk %d: prim %u t %g, exhaustive %u t %g, want %u", cases[i].what, w, h.prim, h.t, he.prim,
                      he.t, want_prim[i]);
            CHECK_MSG(c.steps == cases[i].steps[w], "%s walk %d: %llu voxels, want %llu", cases[i].what, w,
                      (unsigned long long)c.steps, (unsigned long long)cases[i].steps[w]);
            /* Any hit takes the same voxels up to the occluder. */
            counters_t co = {0};
            bool occ = a->ops->occluded(a, cx, r, &co);
            CHECK_MSG(occ == (want_prim[i] != HIT_NONE), "%s walk %d: occluded %d", cases[i].what, w, occ);
        }
        uint64_t rel, exh;
        octree_debug_fallbacks(cx, &rel, &exh);
        CHECK_MSG(rel == 0 && exh == 0, "walk %d: %llu relocations, %llu exhaustive fallbacks", w,
                  (unsigned long long)rel, (unsigned long long)exh);
        a->ops->context_free(cx);
        a->ops->destroy(a);
    }
    ex->ops->destroy(ex);
    scene_free(s);
}

/* ------------------------------------------------------- safety nets */

/* The walks' checks, made to fire: Glassner's step turned backwards (the
 * moved point lands in the voxel just left, which the check refuses, so
 * every step is located by ray parameter instead), and a step cap of 2
 * (longer walks finish by testing every primitive). Answers stay
 * exhaustive's. */
static void test_safety_nets(void)
{
    scene_t *s = test_scene("spd:balls:2");
    accel *ref = test_build("embree", s, 1), *ex = test_build("exhaustive", s, 1);
    workload_opts o = test_wl(24, 24, 1);
    rayset_t *rs = workload_find("primary")->make(s, ref, &o);
    struct { const char *cfg; int back, cap; } cases[] = {
        {"maxdepth=6", 1, 0}, {"maxdepth=6", 0, 1}, {"maxdepth=6,walk=fujimoto", 0, 1},
    };
    answers_t *want = test_trace(ex, rs, 1);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        accel *a = build(s, cases[k].cfg);
        octree_info in;
        octree_debug_info(a, &in);
        octree_debug_sabotage(a, cases[k].back ? -0.5f * in.minlen : 0.5f * in.minlen, cases[k].cap ? 2 : UINT64_MAX);
        accel_ctx *cx = a->ops->context_new(a);
        int bad = 0;
        for (uint32_t i = 0; i < rs->count; i++) {
            hit_t h = hit_none(&rs->rays[i]);
            counters_t c = {0};
            a->ops->intersect(a, cx, &rs->rays[i], &h, &c);
            bad += h.prim != want->hits[i].prim || h.t != want->hits[i].t;
        }
        uint64_t rel, exh;
        octree_debug_fallbacks(cx, &rel, &exh);
        printf("safety net [%s]%s: %u rays, relocated %llu, exhaustive %llu, %d differ\n", cases[k].cfg,
               cases[k].back ? " step backwards" : " step cap 2", rs->count, (unsigned long long)rel,
               (unsigned long long)exh, bad);
        CHECK_MSG(bad == 0, "[%s]: %d rays differ from exhaustive", cases[k].cfg, bad);
        CHECK_MSG(cases[k].back ? rel > 100 && exh == 0 : exh > 100, "[%s]: the net did not catch (%llu, %llu)",
                  cases[k].cfg, (unsigned long long)rel, (unsigned long long)exh);
        a->ops->context_free(cx);
        a->ops->destroy(a);
    }
    answers_free(want);
    rayset_free(rs);
    ref->ops->destroy(ref);
    ex->ops->destroy(ex);
    scene_free(s);
}

/* --------------------------------------------------------- maxdepth 0 */

static void test_one_cell(void)
{
    scene_t *s = test_scene("spd:balls:2");
    accel *ref = test_build("embree", s, 1), *ex = test_build("exhaustive", s, 1);
    workload_opts o = test_wl(32, 32, 1);
    const char *wls[] = {"random", "shadow"};
    for (int w = 0; w < 2; w++) {
        rayset_t *all = workload_find(wls[w])->make(s, ref, &o);
        for (int walk = 0; walk < 2; walk++) {
            accel *a = build(s, walk ? "maxdepth=0,walk=fujimoto" : "maxdepth=0");
            octree_info in;
            octree_debug_info(a, &in);
            /* The rays that meet the cell (random segments also run outside
             * the scene's box, where the octree tests nothing at all). */
            rayset_t *rs = rayset_new(all->workload, all->scene, all->seed, all->query);
            for (uint32_t i = 0; i < all->count; i++) {
                slab_ray sr;
                float t0 = all->rays[i].tnear, t1 = all->rays[i].tfar;
                if (slab_ray_init(&sr, all->rays[i].org, all->rays[i].dir) && slab_clip(&sr, &in.root, &t0, &t1))
                    rayset_push(rs, &all->rays[i], 0);
            }
            rayset_seal(rs);
            CHECK_MSG(rs->count * 10 >= all->count * 8, "%s: only %u of %u rays meet the box", wls[w], rs->count, all->count);
            CHECK(in.interior == 0 && in.leaves == 1 && in.depth == 0);
            answers_t *got = test_trace(a, rs, 1), *want = test_trace(ex, rs, 1);
            printf("one cell %-7s walk %d: %u rays, tests %llu (exhaustive %llu), voxels %llu\n", wls[w], walk, rs->count,
                   (unsigned long long)got->total.prim_tests, (unsigned long long)want->total.prim_tests,
                   (unsigned long long)got->total.steps);
            CHECK_MSG(got->total.prim_tests == want->total.prim_tests && got->total.prim_tests > 0,
                      "%s: %llu tests, exhaustive %llu", wls[w], (unsigned long long)got->total.prim_tests,
                      (unsigned long long)want->total.prim_tests);
            CHECK_MSG(got->total.steps == rs->count, "%s: %llu voxels for %u rays", wls[w],
                      (unsigned long long)got->total.steps, rs->count);
            for (uint32_t i = 0; i < rs->count; i++) {
                bool same = rs->query == QUERY_ANY ? got->occluded[i] == want->occluded[i]
                                                   : got->hits[i].prim == want->hits[i].prim && got->hits[i].t == want->hits[i].t;
                if (!same) {
                    CHECK_MSG(same, "%s ray %u: the one cell answers differently from exhaustive", wls[w], i);
                    break;
                }
            }
            answers_free(got);
            answers_free(want);
            rayset_free(rs);
            a->ops->destroy(a);
        }
        rayset_free(all);
    }
    ref->ops->destroy(ref);
    ex->ops->destroy(ex);
    scene_free(s);
}

/* ------------------------------------------------------------ refusals */

static void test_refusals(void)
{
    scene_t *s = test_scene("spd:balls:2");
    const struct accel_ops *ops = accel_find("octree");
    struct { const char *cfg, *needle; } bad[] = {
        {"maxdepth=21", "maxdepth=21: must be an integer in 0..20"},
        {"maxdepth=-1", "maxdepth=-1: must be an integer in 0..20"},
        {"maxdepth=1000", "maxdepth=1000: must be an integer in 0..20"},
        {"maxdepth=deep", "maxdepth=deep: must be an integer in 0..20"},
        {"maxprims=-3", "maxprims=-3"},
        {"walk=samet", "walk=samet: must be glassner|fujimoto"},
        {"maxdepth=20,maxprims=0,memcap=1", "over memcap=1 MiB"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char err[512] = "";
        double t0 = clock_ms();
        accel *a = test_build_with(ops, s, bad[i].cfg, 1, err, sizeof err);
        double ms = clock_ms() - t0;
        CHECK_MSG(!a, "%s: built", bad[i].cfg);
        if (a) a->ops->destroy(a);
        CHECK_MSG(strstr(err, bad[i].needle) && !strchr(err, '\n'), "%s: reason '%s'", bad[i].cfg, err);
        CHECK_MSG(ms < 10000, "%s: refused after %.0f ms", bad[i].cfg, ms);
        printf("refused %-34s %s\n", bad[i].cfg, err);
    }
    scene_free(s);
}

/* -------------------------------------- no fallback on ordinary scenes */

static void test_no_fallbacks(void)
{
    scene_t *s = test_scene("spd:balls:2");
    accel *ref = test_build("embree", s, 1);
    workload_opts o = test_wl(48, 48, 1);
    const char *cfgs[] = {"", "walk=fujimoto", "maxdepth=12,maxprims=1", "maxdepth=12,maxprims=1,walk=fujimoto"};
    for (size_t k = 0; k < sizeof cfgs / sizeof cfgs[0]; k++) {
        accel *a = build(s, cfgs[k]);
        accel_ctx *cx = a->ops->context_new(a);
        uint64_t nrays = 0;
        for (int w = 0; workload_table[w].name; w++) {
            rayset_t *rs = workload_table[w].make(s, ref, &o);
            for (uint32_t i = 0; i < rs->count; i++) {
                const ray_t *r = &rs->rays[i];
                counters_t c = {0};
                if (rs->query == QUERY_ANY) {
                    a->ops->occluded(a, cx, r, &c);
                } else {
                    hit_t h = hit_none(r);
                    a->ops->intersect(a, cx, r, &h, &c);
                }
            }
            nrays += rs->count;
            rayset_free(rs);
        }
        uint64_t rel, exh;
        octree_debug_fallbacks(cx, &rel, &exh);
        printf("fallbacks [%s]: %llu rays, relocated %llu, exhaustive %llu\n", cfgs[k], (unsigned long long)nrays,
               (unsigned long long)rel, (unsigned long long)exh);
        CHECK_MSG(exh == 0, "[%s]: %llu walks tested everything", cfgs[k], (unsigned long long)exh);
        CHECK_MSG(rel * 1000 <= nrays, "[%s]: %llu relocations in %llu rays", cfgs[k], (unsigned long long)rel,
                  (unsigned long long)nrays);
        a->ops->context_free(cx);
        a->ops->destroy(a);
    }
    ref->ops->destroy(ref);
    scene_free(s);
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    test_hash_mod();
    test_names();
    test_deep_names();
    test_stepping();
    test_safety_nets();
    test_one_cell();
    test_refusals();
    test_no_fallbacks();
    return check_report();
}
