/* test_bvh_gs: Goldsmith and Salmon's hierarchy, `bvh-gs`
 * (accel/bvh_gs/bvh_goldsmith_salmon.c on the n-ary kit accel/bvh_gs/nary.h and
 * accel/bvh_gs/build_gs.c), beyond the conformance suite.
 *
 *   eq3         a hand-built tree of three boxes (a root over two boxes
 *               and a primitive, two primitives in each box): eq. (3)
 *               computed by hand, 3 box tests and 1 + (6 + 10) 2 / 18
 *               primitive tests per ray, from nary_predict and from the
 *               builder's own cost of the same tree made by hand
 *   tie         a hand-built tree whose two children grow equally to take
 *               a new box: the search goes down both, and the cheaper
 *               placement (a new parent in the second) wins; searching
 *               only the first child places it worse (hand-computed
 *               increases 52 and 64)
 *   accounting  on random boxes, nested boxes and identical boxes, every
 *               insertion grows the tree's cost by what the search said,
 *               the tree is consistent, maxchildren holds, ties happen
 *   model       random lines through the root of a tree of tiny spheres
 *               (so almost nothing is hit and nothing is pruned): the
 *               measured box and primitive tests per ray within 3 % of
 *               eq. (3)'s prediction, where its assumptions hold
 *   traversal   stored and nearest, counting and counting-free, with and
 *               without scratch (a tree wider than the local stack), give
 *               exhaustive's answers
 *   shuffles    through the registry: shuffles=8 never costs more than
 *               shuffles=1 with the same --seed, and less for some seed;
 *               seeds change the tree; order=given is id order; the
 *               refusals (shuffles without order=shuffle, maxchildren=1,
 *               memcap) name the parameter */
#include <string.h>
#include "accel/bvh_gs/build_gs.h"
#include "accel/common/shuffle.h"
#include "testlib.h"
#define PRIMS_TEST_SEED 0x65e1
#include "prims_testlib.h"

/* A box [x0, x1] x [0, 1] x [0, 1]: surface 4 (x1 - x0) + 2. */
static box3 slab_x(float x0, float x1) { return box(v3(x0, 0, 0), v3(x1, 1, 1)); }

/* ------------------------------------------------------------- eq. (3) */

static void test_eq3(void)
{
    /* p0, p1 in B1 = [0,1] (S 6); p2, p3 in B2 = [2,4] (S 10); p4 under
     * the root A = [0,4] (S 18) beside them. */
    box3 prims[5] = {slab_x(0, 0.5f), slab_x(0.5f, 1), slab_x(2, 3), slab_x(3, 4), slab_x(1.5f, 2)};
    nary_node nodes[8] = {
        {slab_x(0, 4), 1, 3},                                 /* A: B1, B2, p4 */
        {slab_x(0, 1), 4, 2},  {slab_x(2, 4), 6, 2}, {prims[4], 4, 0},
        {prims[0], 0, 0},      {prims[1], 1, 0},     {prims[2], 2, 0}, {prims[3], 3, 0},
    };
    nary_t t = {.nodes = nodes, .nnodes = 8};
    CHECK(nary_measure(&t) == 0);
    char err[256];
    CHECK_MSG(nary_check(&t, prims, 5, 0, err, sizeof err) == 0, "%s", err);
    CHECK(t.nleaves == 5 && t.max_depth == 2 && t.max_children == 3 && t.stack_need == 4);
    /* By hand: the root's box, then its two boxes, for every ray that hits
     * it; the primitive under the root always, those in B1 and B2 with
     * probability 6/18 and 10/18. */
    nary_prediction p = nary_predict(&t);
    CHECK_NEAR(p.box_tests, 3.0, 1e-12);
    CHECK_NEAR(p.prim_tests, 1.0 + (6.0 * 2 + 10.0 * 2) / 18.0, 1e-12);
    /* Steps: A opened always, B1 and B2 with 6/18 and 10/18, and each
     * primitive tested. */
    CHECK_NEAR(p.steps, 1.0 + (6.0 + 10.0) / 18.0 + p.prim_tests, 1e-12);
    accel_stat st[ACCEL_STATS_MAX];
    int n = nary_stats(&t, 5, st, ACCEL_STATS_MAX);
    CHECK(n == 9 && !strcmp(st[6].name, "predicted_box_tests_per_ray") && st[6].value == p.box_tests);
    CHECK(!strcmp(st[7].name, "predicted_tests_per_ray") && st[7].value == p.prim_tests);
    CHECK(!strcmp(st[8].name, "predicted_steps_per_ray") && st[8].value == p.steps);
    CHECK_NEAR(st[5].value, 7.0 / 3.0, 1e-12); /* avg_children: 7 children over 3 interior nodes */

    /* The same tree by hand in the builder: its cost is S(A) IC(A) =
     * 18 x 3 + 6 x 2 + 10 x 2 = 86, and laid out it predicts the same. */
    gs_builder b;
    CHECK(gs_builder_init(&b, prims, 5, NULL) == 0);
    uint32_t a = gs_add_interior(&b, GS_NONE), b1 = gs_add_interior(&b, a), b2 = gs_add_interior(&b, a);
    gs_add_leaf(&b, a, 4);
    gs_add_leaf(&b, b1, 0), gs_add_leaf(&b, b1, 1), gs_add_leaf(&b, b2, 2), gs_add_leaf(&b, b2, 3);
    CHECK_NEAR(gs_cost(&b), 86.0, 1e-12);
    nary_t laid;
    CHECK(gs_finish(&b, &laid) == 0);
    CHECK_MSG(nary_check(&laid, prims, 5, 0, err, sizeof err) == 0, "%s", err);
    nary_prediction q = nary_predict(&laid);
    CHECK_NEAR(q.box_tests, p.box_tests, 1e-12);
    CHECK_NEAR(q.prim_tests, p.prim_tests, 1e-12);
    CHECK_NEAR(1.0 + gs_cost(&b) / gs_area(laid.nodes[0].box), q.box_tests + q.prim_tests, 1e-12);
    nary_free(&laid);
    gs_builder_free(&b);
    printf("eq3: %.4f box and %.4f primitive tests per ray by eq. (3), 3 and %.4f by hand\n", p.box_tests,
           p.prim_tests, 1.0 + 32.0 / 18.0);
}

/* ----------------------------------------------------------------- tie */

/* R over L = [-10,-2] (a1 = [-10,-2], a2 = [-10,-9]) and Rt = [2,10]
 * (b1 = [2,3], b2 = [9,10]); X = [-0.5,0.5] grows L and Rt by 10 each.
 * By hand (S = 4w + 2): at R a sibling costs 82, a new parent over L or
 * Rt 88; in L (I = 2 x 10 = 20) a sibling 20 + 44 = 64, a new parent over
 * a1 (growth 10; a2's is 38) 20 + 2 x 44 = 108; in Rt a sibling 64 again
 * and a new parent over b1 (growth 10) 20 + 2 x 16 = 52: the best. */
static void test_tie(void)
{
    box3 boxes[5] = {slab_x(-10, -2), slab_x(-10, -9), slab_x(2, 3), slab_x(9, 10), slab_x(-0.5f, 0.5f)};
    for (int first_only = 0; first_only < 2; first_only++) {
        nary_gs_config cfg = {.max_children = 0, .ties_first_only = first_only};
        gs_builder b;
        CHECK(gs_builder_init(&b, boxes, 5, &cfg) == 0);
        uint32_t r = gs_add_interior(&b, GS_NONE), l = gs_add_interior(&b, r), rt = gs_add_interior(&b, r);
        gs_add_leaf(&b, l, 0), gs_add_leaf(&b, l, 1);
        uint32_t b1 = gs_add_leaf(&b, rt, 2);
        gs_add_leaf(&b, rt, 3);
        double before = gs_cost(&b), increase;
        CHECK_NEAR(before, 82.0 * 2 + 34.0 * 2 + 34.0 * 2, 1e-12);
        CHECK(gs_insert(&b, 4, &increase) == 0);
        CHECK_NEAR(gs_cost(&b) - before, increase, 1e-9);
        uint32_t x = b.nnodes - 1; /* the new leaf */
        CHECK(b.nodes[x].prim == 4);
        uint32_t parent = b.nodes[x].parent;
        if (!first_only) {
            /* Both tied children searched: a new parent over b1, inside Rt. */
            CHECK_NEAR(increase, 52.0, 1e-12);
            CHECK(parent == b.nodes[b1].parent && b.nodes[parent].parent == rt && b.nodes[parent].nchildren == 2);
            CHECK(b.tie_descents == 1);
        } else {
            /* Only L searched: one more child of L. */
            CHECK_NEAR(increase, 64.0, 1e-12);
            CHECK(parent == l && b.nodes[l].nchildren == 3);
            CHECK(b.tie_descents == 0);
        }
        nary_t t;
        char err[256];
        CHECK(gs_finish(&b, &t) == 0);
        CHECK_MSG(nary_check(&t, boxes, 5, 0, err, sizeof err) == 0, "%s", err);
        printf("tie: %s: increase %.1f\n", first_only ? "first minimal child only" : "every minimal child", increase);
        nary_free(&t);
        gs_builder_free(&b);
    }
}

/* ---------------------------------------------------------- accounting */

static void check_accounting(const char *name, const box3 *boxes, uint32_t n, uint32_t max_children, bool first_only)
{
    nary_gs_config cfg = {.max_children = max_children, .ties_first_only = first_only};
    gs_builder b;
    CHECK(gs_builder_init(&b, boxes, n, &cfg) == 0);
    int bad = 0;
    double cost = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        double increase, after;
        CHECK(gs_insert(&b, i, &increase) == 0);
        after = gs_cost(&b);
        if (fabs(after - cost - increase) > 1e-9 * (after + 1.0)) bad++;
        cost = after;
    }
    CHECK_MSG(bad == 0, "%s: %d insertions grew the cost by another amount than the search said", name, bad);
    nary_t t;
    char err[256];
    CHECK(gs_finish(&b, &t) == 0);
    CHECK_MSG(nary_check(&t, boxes, n, max_children, err, sizeof err) == 0, "%s: %s", name, err);
    CHECK(t.nleaves == n && t.nnodes <= 2 * n - 1);
    if (max_children) CHECK(t.max_children <= max_children);
    if (first_only) CHECK(b.tie_descents == 0);
    nary_prediction p = nary_predict(&t);
    CHECK_NEAR(p.box_tests + p.prim_tests, 1.0 + cost / gs_area(t.nodes[0].box), 1e-9 * (p.box_tests + p.prim_tests));
    printf("accounting: %-9s max %u%s: %u nodes, depth %u, widest %u, %llu tie descents, eq. (3) %.2f + %.2f\n", name,
           max_children, first_only ? " first-only" : "", t.nnodes, t.max_depth, t.max_children,
           (unsigned long long)b.tie_descents, p.box_tests, p.prim_tests);
    nary_free(&t);
    gs_builder_free(&b);
}

static void test_accounting(void)
{
    enum { N = 400 };
    static box3 rnd_boxes[N], nested[N], same[N];
    for (int i = 0; i < N; i++) {
        vec3 c = rnd_v3(-20, 20), e = rnd_v3(0.1f, 3);
        rnd_boxes[i] = box(v3_sub(c, e), v3_add(c, e));
        /* Nested: groups of boxes inside one another, so a new box often lies inside several children (ties at 0). */
        float s = (float)(i % 10) + 1.0f;
        vec3 g = v3((float)(i / 10 % 4) * 30.0f, 0, 0);
        nested[i] = box(v3_sub(g, v3(s, s, s)), v3_add(g, v3(s, s, s)));
        same[i] = box(v3(0, 0, 0), v3(1, 1, 1));
    }
    const struct { const char *name; const box3 *boxes; } sets[] = {{"random", rnd_boxes}, {"nested", nested}, {"identical", same}};
    const uint32_t widths[] = {0, 2, 3};
    for (int s = 0; s < 3; s++)
        for (int w = 0; w < 3; w++)
            for (int f = 0; f < 2; f++) check_accounting(sets[s].name, sets[s].boxes, N, widths[w], f);
    /* Nested boxes tie: the search goes down more than one child. */
    gs_builder b;
    CHECK(gs_builder_init(&b, nested, N, NULL) == 0);
    double inc;
    for (uint32_t i = 0; i < N; i++) CHECK(gs_insert(&b, (i * 7919u) % N, &inc) == 0);
    CHECK_MSG(b.tie_descents > 0, "no tie on nested boxes");
    gs_builder_free(&b);
    /* Identical boxes: eq. (3) gains nothing from nesting them, and every
     * one becomes a child of the root. */
    nary_t t;
    CHECK(nary_build_gs(&t, same, NULL, N, NULL) == 0);
    CHECK(t.nnodes == N + 1 && t.max_children == N && t.stack_need == N);
    nary_free(&t);
}

/* ------------------------------------------------------ model and rays */

static void finish_prims(prims_t *p)
{
    char err[256];
    if (prims_finish(p, err, sizeof err)) {
        fprintf(stderr, "prims_finish: %s\n", err);
        exit(2);
    }
}

static void test_model(void)
{
    /* 600 spheres of radius 1e-3 in clusters over a 40-unit box: a ray
     * almost never hits one, so no interval is shortened. */
    prims_t p;
    prims_init(&p);
    for (int g = 0; g < 30; g++) {
        vec3 c = rnd_v3(-20, 20);
        for (int i = 0; i < 20; i++) prims_add_sphere(&p, v3_add(c, rnd_v3(-3, 3)), 1e-3f);
    }
    finish_prims(&p);
    nary_t t;
    CHECK(nary_build_gs(&t, p.bounds, NULL, p.count, NULL) == 0);
    nary_prediction want = nary_predict(&t);
    nary_scratch s;
    CHECK(nary_scratch_init(&s, &t) == 0);
    enum { RAYS = 40000 };
    counters_t c[2] = {{0}};
    for (int i = 0; i < RAYS; i++) {
        ray_t ray = random_line(t.nodes[0].box);
        hit_t h = hit_none(&ray);
        nary_intersect_stored(&t, &p, &s, &ray, &h, &c[0]);
        nary_occluded_nearest(&t, &p, &s, &ray, &c[1]);
    }
    for (int k = 0; k < 2; k++) {
        double box = (double)c[k].box_tests / RAYS, tests = (double)c[k].prim_tests / RAYS,
               steps = (double)c[k].steps / RAYS;
        printf("model: %s: %.3f box tests per ray (eq. (3) %.3f), %.3f primitive tests (eq. (3) %.3f), %.3f steps "
               "(predicted %.3f), %llu hits\n",
               k ? "nearest, any hit" : "stored, closest", box, want.box_tests, tests, want.prim_tests, steps,
               want.steps, (unsigned long long)c[k].prim_hits);
        CHECK_MSG(fabs(steps - want.steps) <= 0.03 * want.steps, "steps %.3f, predicted %.3f", steps, want.steps);
        CHECK_MSG(fabs(box - want.box_tests) <= 0.03 * want.box_tests, "box tests %.3f, predicted %.3f", box, want.box_tests);
        CHECK_MSG(fabs(tests - want.prim_tests) <= 0.03 * want.prim_tests, "tests %.3f, predicted %.3f", tests,
                  want.prim_tests);
    }
    nary_scratch_free(&s);
    nary_free(&t);
    prims_free(&p);
}

typedef bool (*isect_fn)(const nary_t *, const prims_t *, nary_scratch *, const ray_t *, hit_t *, counters_t *);
typedef bool (*occl_fn)(const nary_t *, const prims_t *, nary_scratch *, const ray_t *, counters_t *);
typedef bool (*isect_fast_fn)(const nary_t *, const prims_t *, nary_scratch *, const ray_t *, hit_t *);
typedef bool (*occl_fast_fn)(const nary_t *, const prims_t *, nary_scratch *, const ray_t *);
static const struct {
    const char *name;
    isect_fn isect;
    occl_fn occl;
    isect_fast_fn isect_fast;
    occl_fast_fn occl_fast;
} traversals[] = {
    {"stored", nary_intersect_stored, nary_occluded_stored, nary_intersect_stored_fast, nary_occluded_stored_fast},
    {"nearest", nary_intersect_nearest, nary_occluded_nearest, nary_intersect_nearest_fast, nary_occluded_nearest_fast},
};

static void check_rays(const char *name, const nary_t *t, const prims_t *p)
{
    nary_scratch s;
    CHECK(nary_scratch_init(&s, t) == 0);
    for (int k = 0; k < 2; k++) {
        int diff = 0, hits = 0;
        counters_t c = {0};
        for (int i = 0; i < 3000; i++) {
            ray_t ray = i % 2 ? random_line(p->box) : make_ray(rnd_v3(-25, 25), random_dir(), 0.0f, rnd(1, 30));
            hit_t want = hit_none(&ray), got = hit_none(&ray), fast = hit_none(&ray), bare = hit_none(&ray);
            exhaustive(p, &ray, &want, false);
            bool r = traversals[k].isect(t, p, &s, &ray, &got, &c);
            bool rf = traversals[k].isect_fast(t, p, &s, &ray, &fast);
            traversals[k].isect_fast(t, p, NULL, &ray, &bare);
            bool o = traversals[k].occl(t, p, &s, &ray, &c);
            hits += r;
            diff += r != (want.prim != HIT_NONE) || memcmp(&got.t, &want.t, sizeof got.t) != 0;
            /* Without scratch a wide tree is scanned leaf by leaf: among coincident triangles another may win, at the same t. */
            diff += rf != r || memcmp(&fast, &got, sizeof got) != 0 || memcmp(&bare.t, &got.t, sizeof got.t) != 0;
            diff += o != exhaustive(p, &ray, NULL, true) || traversals[k].occl_fast(t, p, &s, &ray) != o ||
                    traversals[k].occl_fast(t, p, NULL, &ray) != o;
        }
        printf("rays: %-9s %-7s hits %d, %.2f box tests, %.2f primitive tests per query\n", name, traversals[k].name,
               hits, (double)c.box_tests / 6000, (double)c.prim_tests / 6000);
        CHECK(hits > 50);
        CHECK_MSG(diff == 0, "%s %s: %d answers differ from exhaustive's", name, traversals[k].name, diff);
        CHECK(c.empty_leaves == 0 && c.mailbox_hits == 0 && c.steps > 0);
    }
    /* A ray that misses the root: one box test, nothing else. */
    ray_t away = make_ray(v3(1000, 1000, 1000), v3(1, 0, 0), 0.0f, INFINITY);
    for (int k = 0; k < 2 && t->nodes[0].count; k++) {
        counters_t c = {0};
        hit_t h = hit_none(&away);
        CHECK(!traversals[k].isect(t, p, &s, &away, &h, &c) && c.box_tests == 1 && c.prim_tests == 0 && c.steps == 0);
    }
    nary_scratch_free(&s);
}

static void test_traversal(void)
{
    prims_t p;
    prims_init(&p);
    rnd_soup(&p, 300, 20.0f);
    finish_prims(&p);
    uint32_t *order = malloc(p.count * sizeof *order);
    for (uint32_t i = 0; i < p.count; i++) order[i] = i;
    shuffle_ids(order, p.count, 99);
    nary_t t;
    CHECK(nary_build_gs(&t, p.bounds, order, p.count, NULL) == 0);
    check_rays("soup", &t, &p);
    nary_free(&t);
    nary_gs_config bin = {.max_children = 2};
    CHECK(nary_build_gs(&t, p.bounds, order, p.count, &bin) == 0);
    check_rays("soup-bin", &t, &p);
    nary_free(&t);
    free(order);
    prims_free(&p);

    /* 300 copies of one triangle and a few others: a root wider than the
     * local stack, so a traversal without scratch takes the fallback. */
    prims_init(&p);
    uint32_t v[3] = {prims_add_vertex(&p, v3(-5, -5, 0)), prims_add_vertex(&p, v3(5, -5, 0)), prims_add_vertex(&p, v3(0, 5, 0))};
    for (int i = 0; i < 300; i++) prims_add_triangle(&p, v[0], v[1], v[2]);
    for (int i = 0; i < 20; i++) prims_add_sphere(&p, rnd_v3(-20, 20), 1.0f);
    finish_prims(&p);
    CHECK(nary_build_gs(&t, p.bounds, NULL, p.count, NULL) == 0);
    CHECK_MSG(t.max_children > NARY_STACK_LOCAL, "widest node %u", t.max_children);
    check_rays("wide", &t, &p);
    nary_free(&t);
    prims_free(&p);
}

/* ------------------------------------------------------ the accelerator */

static accel *build_seeded(const scene_t *s, const char *settings, uint64_t seed, char *err, size_t errlen)
{
    const struct accel_ops *ops = accel_find("bvh-gs");
    accel_params p;
    params_defaults(&p, ops->params);
    p.seed = seed;
    if (!strcmp(settings, "memcap=1")) p.memcap_mib = 1, settings = ""; /* the harness's cap, as --memcap sets it */
    if (params_set_list(&p, settings, err, errlen)) return NULL;
    return accel_build(ops, s, &p, err, errlen);
}

/* eq. (3)'s total, box and primitive tests per ray, from the statistics. */
static double predicted(const accel *a)
{
    accel_stat st[ACCEL_STATS_MAX];
    int n = accel_stats(a, st, ACCEL_STATS_MAX);
    double sum = 0;
    int found = 0;
    for (int i = 0; i < n; i++)
        if (!strcmp(st[i].name, "predicted_box_tests_per_ray") || !strcmp(st[i].name, "predicted_tests_per_ray"))
            sum += st[i].value, found++;
    CHECK(found == 2);
    return sum;
}

static void test_shuffles(void)
{
    const char *scenes[] = {"spd:balls:2", "spd:tetra:3"};
    for (int sc = 0; sc < 2; sc++) {
        scene_t *s = test_scene(scenes[sc]);
        char err[512];
        int lower = 0;
        double first_seed_cost = 0;
        bool seeds_differ = false;
        for (uint64_t seed = 1; seed <= 4; seed++) {
            accel *one = build_seeded(s, "shuffles=1", seed, err, sizeof err);
            accel *many = build_seeded(s, "shuffles=8", seed, err, sizeof err);
            CHECK_MSG(one && many, "%s", err);
            if (!one || !many) continue;
            double c1 = predicted(one), c8 = predicted(many);
            printf("shuffles: %s seed %llu: eq. (3) %.4f with 1 shuffle, %.4f with 8\n", s->name,
                   (unsigned long long)seed, c1, c8);
            CHECK_MSG(c8 <= c1, "%s seed %llu: 8 shuffles cost %.6f, one %.6f", s->name, (unsigned long long)seed, c8, c1);
            lower += c8 < c1;
            if (seed == 1) first_seed_cost = c1;
            else seeds_differ |= c1 != first_seed_cost;
            one->ops->destroy(one);
            many->ops->destroy(many);
        }
        CHECK_MSG(lower > 0, "%s: 8 shuffles never beat one", s->name);
        CHECK_MSG(seeds_differ, "%s: --seed does not change the shuffled tree", s->name);

        /* order=given is the builder in id order. */
        accel *given = build_seeded(s, "order=given", 1, err, sizeof err);
        nary_t t;
        CHECK(nary_build_gs(&t, s->prims.bounds, NULL, s->prims.count, NULL) == 0);
        nary_prediction pr = nary_predict(&t);
        CHECK(given && predicted(given) == pr.box_tests + pr.prim_tests);
        nary_free(&t);
        if (given) given->ops->destroy(given);
        accel *sorted = build_seeded(s, "order=sorted,maxchildren=4", 1, err, sizeof err);
        CHECK_MSG(sorted != NULL, "%s", err);
        if (sorted) {
            printf("shuffles: %s: eq. (3) %.4f in given order, %.4f sorted (maxchildren=4)\n", s->name,
                   pr.box_tests + pr.prim_tests, predicted(sorted));
            sorted->ops->destroy(sorted);
        }
        scene_free(s);
    }

    /* Refusals: one line naming the parameter. */
    scene_t *s = test_scene("spd:balls:4");
    char err[512];
    const struct { const char *settings, *says; } bad[] = {
        {"order=given,shuffles=2", "needs order=shuffle"},
        {"maxchildren=1", "maxchildren=1"},
        {"maxchildren=70000", "maxchildren=70000"},
        {"shuffles=0", "shuffles=0"},
        {"order=random", "order=random"},
        {"traverse=heap", "traverse=heap"},
        {"memcap=1", "over memcap=1 MiB"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        err[0] = 0;
        accel *a = build_seeded(s, bad[i].settings, 1, err, sizeof err);
        CHECK_MSG(!a && strstr(err, bad[i].says) && !strchr(err, '\n'), "%s: %s", bad[i].settings, a ? "built" : err);
        if (a) a->ops->destroy(a);
    }
    scene_free(s);
}

int main(void)
{
    test_eq3();
    test_tie();
    test_accounting();
    test_model();
    test_traversal();
    test_shuffles();
    return check_report();
}
