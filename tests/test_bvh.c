/* test_bvh: the BVH kit (accel/bvh/bvh.h).
 *
 * Builders (median, binned SAH, incremental insertion in id order and
 * shuffled) on the bunny, a soup of every primitive kind, a cluster of
 * tiny triangles inside a few huge ones, identical boxes and the empty
 * input: the tree passes bvh_check (every primitive in one leaf, every box
 * containing what is below), leaves respect max_leaf, and on the bunny
 * SAH's cost is below the median split's. Traversals (depth-first and
 * heap-ordered, closest and any hit, counting and counting-free) on random
 * rays (from outside, from inside with a finite tfar, axis-aligned with
 * +-0 components) give exactly the exhaustive loop's hit distance (the
 * same primitive but for exact ties), the counting-free ones the counting
 * ones' answers bit for bit; counters are plausible. A hand-made chain 100
 * levels deep overflows the 64-entry local stack, and the traversal still
 * finds the hit in the dropped subtree (the leaf-scan fallback), as it
 * does with a context stack of the right depth. The builders' passes
 * through box4 (prims/box4.h: bounds, centroid bounds, bvh_sah_best's
 * bins and sweeps) give what a plain box_union pass per axis gives, bit
 * for bit (prim_split_bounds's own use of box4 is checked by test_prims). */
#include <stdlib.h>
#include <string.h>
#include "accel/bvh/build.h"
#include "accel/bvh/bvh.h"
#include "check.h"
#include "scenes/scene.h"
#define PRIMS_TEST_SEED 0xb7b7
#include "prims_testlib.h"

typedef int (*builder_fn)(bvh_t *, const box3 *, const vec3 *, uint32_t, const bvh_config *);

typedef struct {
    const char *name;
    builder_fn build;
    uint64_t seed; /* insertion: the shuffle */
} builder_t;

static const builder_t builders[] = {
    {"median", bvh_build_median, 0},
    {"sah", bvh_build_sah, 0},
    {"insert", bvh_build_insert, 0},
    {"insert-shuffled", bvh_build_insert, 12345},
};
#define NBUILDERS (int)(sizeof builders / sizeof builders[0])

static bvh_t build(const builder_t *bd, const prims_t *p, uint32_t max_leaf)
{
    bvh_config cfg;
    bvh_config_defaults(&cfg);
    cfg.max_leaf = max_leaf;
    cfg.insert_seed = bd->seed;
    bvh_t b;
    CHECK(bd->build(&b, p->bounds, NULL, p->count, &cfg) == 0);
    char err[256];
    CHECK_MSG(bvh_check(&b, p->bounds, p->count, err, sizeof err) == 0, "%s: %s", bd->name, err);
    uint32_t biggest = 0;
    for (uint32_t i = 0; i < b.nnodes; i++) biggest = b.nodes[i].count > biggest ? b.nodes[i].count : biggest;
    uint32_t limit = bd->build == bvh_build_insert ? 1 : max_leaf;
    CHECK_MSG(biggest <= limit, "%s: a leaf of %u primitives, limit %u", bd->name, biggest, limit);
    return b;
}

static ray_t random_ray(box3 box, int kind)
{
    vec3 c = box_center(box), e = box_extent(box);
    vec3 target = v3_add(box.lo, v3_mul(e, v3(rnd(0, 1), rnd(0, 1), rnd(0, 1))));
    if (kind == 0) { /* from outside, through a point of the box */
        vec3 o = v3_add(c, v3_scale(v3_norm(rnd_v3(-1, 1)), 1.5f * box_diagonal(box)));
        return ray_through(o, target);
    }
    if (kind == 1) { /* from inside, a segment */
        ray_t r = make_ray(target, rnd_v3(-1, 1), 0.0f, 0.3f * box_diagonal(box));
        return r;
    }
    /* axis-aligned from outside, the other components +-0 */
    int a = (int)(rng_next() % 3);
    float s = rng_next() % 2 ? 1.0f : -1.0f, zero = rng_next() % 2 ? 0.0f : -0.0f;
    vec3 d = v3(a == 0 ? s : zero, a == 1 ? s : zero, a == 2 ? s : zero);
    vec3 o = v3_sub(target, v3_scale(d, box_diagonal(box)));
    return make_ray(o, d, 0.0f, INFINITY);
}

typedef bool (*isect_fn)(const bvh_t *, const prims_t *, bvh_scratch *, const ray_t *, hit_t *, counters_t *);
typedef bool (*occl_fn)(const bvh_t *, const prims_t *, bvh_scratch *, const ray_t *, counters_t *);
typedef bool (*isect_fast_fn)(const bvh_t *, const prims_t *, bvh_scratch *, const ray_t *, hit_t *);
typedef bool (*occl_fast_fn)(const bvh_t *, const prims_t *, bvh_scratch *, const ray_t *);

static const struct {
    const char *name;
    isect_fn isect;
    occl_fn occl;
    isect_fast_fn isect_fast;
    occl_fast_fn occl_fast;
} traversals[] = {
    {"dfs", bvh_intersect_dfs, bvh_occluded_dfs, bvh_intersect_dfs_fast, bvh_occluded_dfs_fast},
    {"heap", bvh_intersect_heap, bvh_occluded_heap, bvh_intersect_heap_fast, bvh_occluded_heap_fast},
};

/* The rays of a scene and the exhaustive loop's answers to them. */
typedef struct {
    int n;
    ray_t *rays;
    hit_t *want;
    bool *want_occluded;
} rayref_t;

static rayref_t make_rays(const prims_t *p, int n)
{
    rayref_t r = {n, malloc(n * sizeof(ray_t)), malloc(n * sizeof(hit_t)), malloc(n * sizeof(bool))};
    for (int i = 0; i < n; i++) {
        r.rays[i] = random_ray(p->box, i % 3);
        r.want[i] = hit_none(&r.rays[i]);
        exhaustive(p, &r.rays[i], &r.want[i], false);
        r.want_occluded[i] = exhaustive(p, &r.rays[i], NULL, true);
    }
    return r;
}

/* Every traversal of tree b against the reference answers. */
static void check_traversals(const char *scene, const char *builder, const bvh_t *b, const prims_t *p,
                             const rayref_t *rr)
{
    bvh_scratch s;
    CHECK(bvh_scratch_init(&s, b) == 0);
    int nrays = rr->n;
    for (int t = 0; t < 2; t++) {
        int tdiff = 0, pdiff = 0, odiff = 0, fdiff = 0, hits = 0, occl = 0;
        counters_t c = {0};
        for (int i = 0; i < nrays; i++) {
            const ray_t *ray = &rr->rays[i];
            hit_t want = rr->want[i], got = hit_none(ray), fast = hit_none(ray), nos = hit_none(ray);
            bool r = traversals[t].isect(b, p, &s, ray, &got, &c);
            bool rf = traversals[t].isect_fast(b, p, &s, ray, &fast);
            traversals[t].isect_fast(b, p, NULL, ray, &nos); /* no scratch */
            hits += r;
            tdiff += memcmp(&got.t, &want.t, sizeof got.t) != 0 || r != (want.prim != HIT_NONE);
            pdiff += got.prim != want.prim;
            fdiff += rf != r || memcmp(&fast, &got, sizeof got) != 0 || memcmp(&nos, &got, sizeof got) != 0;
            bool o = traversals[t].occl(b, p, &s, ray, &c), of = traversals[t].occl_fast(b, p, &s, ray);
            odiff += o != rr->want_occluded[i] || of != o || traversals[t].occl_fast(b, p, NULL, ray) != o;
            occl += o;
        }
        printf("%-8s %-16s %-5s rays %d hits %d occluded %d  tests/ray %.2f box/ray %.2f steps/ray %.2f\n", scene,
               builder, traversals[t].name, nrays, hits, occl, (double)c.prim_tests / (2 * nrays),
               (double)c.box_tests / (2 * nrays), (double)c.steps / (2 * nrays));
        CHECK(hits > nrays / 10);
        CHECK_MSG(tdiff == 0, "%s %s %s: %d hit distances differ from exhaustive", scene, builder, traversals[t].name, tdiff);
        CHECK_MSG(pdiff <= nrays / 500 + 1, "%s %s %s: %d primitives differ", scene, builder, traversals[t].name, pdiff);
        CHECK_MSG(odiff == 0, "%s %s %s: %d occlusion answers differ", scene, builder, traversals[t].name, odiff);
        CHECK_MSG(fdiff == 0, "%s %s %s: %d fast answers differ", scene, builder, traversals[t].name, fdiff);
        CHECK(c.box_tests >= (uint64_t)2 * nrays && c.steps > 0 && c.prim_tests > 0);
        CHECK(c.empty_leaves == 0 && c.mailbox_hits == 0);
    }
    bvh_scratch_free(&s);
}

static void check_scene(const char *name, const prims_t *p, int nrays)
{
    rayref_t rr = make_rays(p, nrays);
    double cost[NBUILDERS];
    for (int k = 0; k < NBUILDERS; k++) {
        bvh_t b = build(&builders[k], p, 4);
        cost[k] = bvh_sah_cost(&b, 1.0, 1.0);
        accel_stat st[8];
        int n = bvh_stats(&b, p->count, st, 8);
        CHECK(n == 5 && strcmp(st[0].name, "nodes") == 0 && st[0].value == b.nnodes - b.nleaves);
        CHECK(st[4].value == 1.0); /* refs_per_prim: no duplication */
        CHECK(bvh_memory(&b) == 32 * (size_t)b.nnodes + 4 * (size_t)b.nrefs && b.nnodes == 2 * b.nleaves - 1);
        box3 bb = bvh_bounds(&b);
        CHECK(memcmp(&bb, &p->box, sizeof bb) == 0);
        printf("%-8s %-16s %u prims: %u nodes, %u leaves, depth %u, SAH cost %.1f\n", name, builders[k].name, p->count,
               b.nnodes, b.nleaves, b.max_depth, cost[k]);
        check_traversals(name, builders[k].name, &b, p, &rr);
        bvh_free(&b);
    }
    /* SAH beats the median split; insertion stays within twice SAH (a
     * child chosen by size rather than growth once made it ten times). */
    CHECK_MSG(cost[1] <= cost[0], "%s: SAH cost %.1f above the median split's %.1f", name, cost[1], cost[0]);
    CHECK_MSG(cost[2] <= 2 * cost[1] && cost[3] <= 2 * cost[1], "%s: insertion costs %.1f, %.1f against SAH's %.1f", name,
              cost[2], cost[3], cost[1]);
    free(rr.rays);
    free(rr.want);
    free(rr.want_occluded);
}

static void add_triangle(prims_t *p, vec3 a, vec3 b, vec3 c)
{
    prims_add_triangle(p, prims_add_vertex(p, a), prims_add_vertex(p, b), prims_add_vertex(p, c));
}

static void finish(prims_t *p)
{
    char err[256];
    if (prims_finish(p, err, sizeof err)) {
        fprintf(stderr, "prims_finish: %s\n", err);
        exit(2);
    }
}

static void test_soup_and_cluster(void)
{
    prims_t p;
    prims_init(&p);
    rnd_soup(&p, 1500, 20.0f);
    finish(&p);
    check_scene("soup", &p, 3000);
    prims_free(&p);

    /* A dense cluster of tiny triangles inside a few huge ones: empty
     * space around a small object, and boxes that overlap everything. */
    prims_init(&p);
    for (int i = 0; i < 2000; i++) {
        vec3 c = rnd_v3(-0.01f, 0.01f);
        add_triangle(&p, v3_add(c, rnd_v3(-1e-3f, 1e-3f)), v3_add(c, rnd_v3(-1e-3f, 1e-3f)), v3_add(c, rnd_v3(-1e-3f, 1e-3f)));
    }
    for (int i = 0; i < 6; i++) add_triangle(&p, rnd_v3(-1000, 1000), rnd_v3(-1000, 1000), rnd_v3(-1000, 1000));
    finish(&p);
    check_scene("cluster", &p, 2000);
    prims_free(&p);
}

static void test_identical_and_empty(void)
{
    prims_t p;
    prims_init(&p);
    for (int i = 0; i < 100; i++) add_triangle(&p, v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0));
    finish(&p);
    for (int k = 0; k < NBUILDERS; k++) {
        bvh_t b = build(&builders[k], &p, 4);
        ray_t ray = ray_through(v3(0.25f, 0.25f, -1.0f), v3(0.25f, 0.25f, 0.0f));
        hit_t h = hit_none(&ray);
        CHECK(bvh_intersect_dfs(&b, &p, NULL, &ray, &h, &(counters_t){0}) && h.t == 1.0f);
        h = hit_none(&ray);
        CHECK(bvh_intersect_heap_fast(&b, &p, NULL, &ray, &h) && h.t == 1.0f);
        bvh_free(&b);
    }
    prims_free(&p);

    prims_init(&p);
    finish(&p);
    for (int k = 0; k < NBUILDERS; k++) {
        bvh_t b;
        CHECK(builders[k].build(&b, p.bounds, NULL, 0, NULL) == 0 && b.nnodes == 0);
        char err[128];
        CHECK(bvh_check(&b, p.bounds, 0, err, sizeof err) == 0);
        ray_t ray = ray_through(v3(0, 0, -1), v3(0, 0, 0));
        hit_t h = hit_none(&ray);
        counters_t c = {0};
        CHECK(!bvh_intersect_dfs(&b, &p, NULL, &ray, &h, &c) && !bvh_occluded_heap(&b, &p, NULL, &ray, &c));
        CHECK(box_is_empty(bvh_bounds(&b)));
        bvh_free(&b);
    }
    prims_free(&p);
}

/* Centroids that differ by a denormal along one axis (the mesh fuzzer's
 * "v 1 2e-45 1"): the SAH's bin scale bins / extent is +inf there, and the
 * slot of a centroid was (uint32_t)inf, undefined behaviour (UBSan stopped
 * lightbuf's and the kit's builds on it). Every builder must give a valid
 * tree that finds the triangles. */
static void test_denormal_extent(void)
{
    prims_t p;
    prims_init(&p);
    for (int i = 0; i < 40; i++) {
        float dy = (float)(i % 5) * 1e-40f; /* denormal: 1e-40 is below FLT_MIN */
        add_triangle(&p, v3(0, dy, 0), v3(1, dy, 0), v3(0, dy, 1));
    }
    finish(&p);
    for (int k = 0; k < NBUILDERS; k++) {
        bvh_t b = build(&builders[k], &p, 2);
        ray_t ray = ray_through(v3(0.25f, -1.0f, 0.25f), v3(0.25f, 0.0f, 0.25f));
        hit_t h = hit_none(&ray);
        CHECK_MSG(bvh_intersect_dfs(&b, &p, NULL, &ray, &h, &(counters_t){0}), "%s: no hit", builders[k].name);
        bvh_free(&b);
    }
    prims_free(&p);
}

/* sbvh's clip over a prims_t. */
static box3 clip_prims(const void *ctx, uint32_t prim, box3 box) { return prim_clip_bounds(ctx, prim, box); }

static void split_prims(const void *ctx, uint32_t prim, box3 box, int axis, float pos, box3 *left, box3 *right)
{
    prim_split_bounds(ctx, prim, box, axis, pos, left, right);
}

static bool sbvh_estimated_bins; /* build_sbvh bins straddlers by prim_split_bounds, not by clipping */

static int build_sbvh(bvh_t *b, const prims_t *p, double alpha, uint32_t threads)
{
    bvh_config cfg;
    bvh_config_defaults(&cfg);
    cfg.threads = threads;
    bvh_sbvh_config sc;
    bvh_sbvh_config_defaults(&sc);
    sc.alpha = alpha, sc.clip = clip_prims, sc.ctx = p;
    if (sbvh_estimated_bins) sc.split = split_prims;
    return bvh_build_sbvh(b, p->bounds, p->count, &cfg, &sc);
}

/* An sbvh tree over p: every primitive in some leaf, every node's box
 * holding its children's, and nrays random rays' closest hits and
 * occlusion those of brute force. */
static void check_sbvh_tree(const bvh_t *sb, const prims_t *p, int nrays)
{
    uint8_t *seen = calloc(p->count, 1);
    for (uint32_t i = 0; i < sb->nnodes; i++) {
        const bvh_node *nd = &sb->nodes[i];
        if (nd->count) {
            for (uint32_t k = 0; k < nd->count; k++) seen[sb->refs[nd->index + k]] = 1;
            continue;
        }
        for (uint32_t k = 0; k < 2; k++) {
            box3 cb = sb->nodes[nd->index + k].box;
            CHECK(box_is_empty(cb) || (v3_get(cb.lo, 0) >= v3_get(nd->box.lo, 0) && v3_get(cb.hi, 0) <= v3_get(nd->box.hi, 0) &&
                                       v3_get(cb.lo, 1) >= v3_get(nd->box.lo, 1) && v3_get(cb.hi, 1) <= v3_get(nd->box.hi, 1) &&
                                       v3_get(cb.lo, 2) >= v3_get(nd->box.lo, 2) && v3_get(cb.hi, 2) <= v3_get(nd->box.hi, 2)));
        }
    }
    uint32_t missing = 0;
    for (uint32_t i = 0; i < p->count; i++) missing += !seen[i];
    CHECK_MSG(missing == 0, "%u primitives in no leaf", missing);
    free(seen);
    uint32_t wrong = 0, hits = 0;
    for (int i = 0; i < nrays; i++) {
        ray_t ray = random_ray(p->box, i % 3);
        hit_t h = hit_none(&ray), ref = hit_none(&ray);
        counters_t c = {0};
        bool got = bvh_intersect_dfs(sb, p, NULL, &ray, &h, &c);
        bool want = false;
        for (uint32_t k = 0; k < p->count; k++) want |= prim_intersect(p, k, &ray, &ref, &c);
        hits += want;
        wrong += got != want || (want && h.t != ref.t) || bvh_occluded_dfs(sb, p, NULL, &ray, &c) != want;
    }
    CHECK_MSG(wrong == 0 && hits > (uint32_t)nrays / 30, "sbvh: %u wrong answers of %d (%u hits)", wrong, nrays, hits);
}

/* sbvh's scene: nsmall small triangles (sides up to 0.03 half) in the
 * cube [-half, half]^3 crossed by nthin long thin ones spanning it in x. */
static void thin_across_small(prims_t *p, int nsmall, int nthin, float half)
{
    prims_init(p);
    const float side = 0.03f * half, dy = 0.1f * half, dz = 0.02f * half;
    for (int i = 0; i < nsmall; i++) {
        vec3 c = rnd_v3(-half, half);
        add_triangle(p, c, v3_add(c, rnd_v3(-side, side)), v3_add(c, rnd_v3(-side, side)));
    }
    for (int i = 0; i < nthin; i++) {
        float y = rnd(-half, half), z = rnd(-half, half);
        add_triangle(p, v3(-half, y, z), v3(half, y + rnd(-dy, dy), z), v3(half, y + rnd(-dy, dy), z + dz));
    }
    finish(p);
}

/* Spatial splits (Stich et al. 2009) on long thin triangles crossing a
 * cloud of small ones, where object splits' children overlap: a tree of
 * lower SAH cost than the object-split one, with primitives in several
 * leaves (and never more references than the budget, 2n), every primitive
 * in some leaf, every node's box holding its children's, the same tree for
 * any thread count, and every ray's closest hit and occlusion those of
 * brute force. alpha=1 never tries a spatial split: one reference each. */
static double sbvh_clipped_cost; /* the clipped-bins tree's SAH cost, which the estimated one must stay near */

static void test_sbvh_once(void)
{
    prims_t p;
    thin_across_small(&p, 300, 60, 10);
    bvh_t obj = build(&builders[1], &p, 4), sb, sb2, one;
    CHECK(build_sbvh(&sb, &p, 1e-5, 0) == 0 && build_sbvh(&sb2, &p, 1e-5, 2) == 0 && build_sbvh(&one, &p, 1.0, 0) == 0);
    double cobj = bvh_sah_cost(&obj, 1, 1), csb = bvh_sah_cost(&sb, 1, 1);
    printf("sbvh (%s bins): SAH cost %.2f (object splits %.2f), %u refs over %u primitives\n",
           sbvh_estimated_bins ? "estimated" : "clipped", csb, cobj, sb.nrefs, p.count);
    if (!sbvh_estimated_bins) sbvh_clipped_cost = csb;
    else CHECK_MSG(csb <= 1.05 * sbvh_clipped_cost, "estimated bins: SAH cost %.3f, clipped bins %.3f", csb, sbvh_clipped_cost);
    CHECK_MSG(csb < cobj, "sbvh's SAH cost %.3f is not below the object split's %.3f", csb, cobj);
    CHECK(sb.nrefs > p.count && sb.nrefs <= 2 * p.count && one.nrefs == p.count);
    CHECK(sb.nnodes == sb2.nnodes && sb.nrefs == sb2.nrefs && !memcmp(sb.nodes, sb2.nodes, sb.nnodes * sizeof *sb.nodes) &&
          !memcmp(sb.refs, sb2.refs, sb.nrefs * sizeof *sb.refs));
    check_sbvh_tree(&sb, &p, 3000);
    bvh_free(&obj), bvh_free(&sb), bvh_free(&sb2), bvh_free(&one);
    prims_free(&p);
}

/* Both binnings of the straddlers: clipped exactly to every slab, and
 * estimated by prim_split_bounds (Embree's float split); the estimated
 * tree's SAH cost within 5 % of the clipped one's. */
static void test_sbvh(void)
{
    uint64_t seed = rng_state; /* the same scene for both */
    sbvh_estimated_bins = false;
    test_sbvh_once();
    rng_state = seed;
    sbvh_estimated_bins = true;
    test_sbvh_once();
    sbvh_estimated_bins = false;
}

/* The threaded sbvh build (build_sbvh.c): 6000 triangles, so the top
 * defers several subtrees of at most BVH_MIN_GRAIN references, each built
 * with a budget of its own. Built on 1, 2 and 4 threads: the same nodes
 * and refs byte for byte, within the 2n budget, spatial splits taken,
 * and a sound tree (check_sbvh_tree); on 0 threads (one pass, one budget
 * for the whole tree) a sound tree too, with the same bound. */
static void test_sbvh_subtrees(void)
{
    prims_t p;
    thin_across_small(&p, 5400, 600, 20);
    sbvh_estimated_bins = true;
    bvh_t t[4];
    const uint32_t threads[4] = {1, 2, 4, 0};
    for (int k = 0; k < 4; k++) CHECK(build_sbvh(&t[k], &p, 1e-5, threads[k]) == 0);
    for (int k = 1; k < 3; k++)
        CHECK_MSG(t[k].nnodes == t[0].nnodes && t[k].nrefs == t[0].nrefs &&
                      !memcmp(t[k].nodes, t[0].nodes, t[0].nnodes * sizeof *t[0].nodes) &&
                      !memcmp(t[k].refs, t[0].refs, t[0].nrefs * sizeof *t[0].refs),
                  "sbvh on %u threads: %u nodes %u refs, on 1: %u nodes %u refs", threads[k], t[k].nnodes, t[k].nrefs,
                  t[0].nnodes, t[0].nrefs);
    for (int k = 0; k < 4; k += 3) {
        CHECK_MSG(t[k].nrefs > p.count && t[k].nrefs <= 2 * p.count, "sbvh on %u threads: %u refs over %u primitives",
                  threads[k], t[k].nrefs, p.count);
        check_sbvh_tree(&t[k], &p, 600);
    }
    printf("sbvh subtrees: %u refs over %u primitives on 1, 2 and 4 threads (the same tree), %u on 0\n", t[0].nrefs,
           p.count, t[3].nrefs);
    for (int k = 0; k < 4; k++) bvh_free(&t[k]);
    sbvh_estimated_bins = false;
    prims_free(&p);
}

/* The threaded binned SAH build (build.c) over a scene's primitives: the
 * top of the tree, then subtrees of about n / BVH_SUBTREES primitives in
 * parallel, each in a node range reserved for it, the ranges' unused ends
 * then squeezed out. On 1, 2 and 4 threads: the same nodes and refs byte
 * for byte; the tree sound (bvh_check: no node unreachable) and dense
 * (2 leaves - 1 nodes, as a one-pass build makes); the same refs order,
 * leaves and depth as the one-pass build (threads 0). */
static void test_sah_subtrees(const char *name, const prims_t *p)
{
    bvh_t t[4];
    const uint32_t threads[4] = {1, 2, 4, 0};
    char err[256];
    for (int k = 0; k < 4; k++) {
        bvh_config cfg;
        bvh_config_defaults(&cfg);
        cfg.threads = threads[k];
        CHECK(bvh_build_sah(&t[k], p->bounds, NULL, p->count, &cfg) == 0);
        CHECK_MSG(bvh_check(&t[k], p->bounds, p->count, err, sizeof err) == 0, "%s sah on %u threads: %s", name,
                  threads[k], err);
        CHECK_MSG(t[k].nnodes == 2 * t[k].nleaves - 1, "%s sah on %u threads: %u nodes for %u leaves", name, threads[k],
                  t[k].nnodes, t[k].nleaves);
    }
    for (int k = 1; k < 3; k++)
        CHECK_MSG(t[k].nnodes == t[0].nnodes && !memcmp(t[k].nodes, t[0].nodes, t[0].nnodes * sizeof *t[0].nodes) &&
                      !memcmp(t[k].refs, t[0].refs, t[0].nrefs * sizeof *t[0].refs),
                  "%s sah on %u threads: %u nodes, on 1: %u", name, threads[k], t[k].nnodes, t[0].nnodes);
    CHECK_MSG(t[3].nleaves == t[0].nleaves && t[3].max_depth == t[0].max_depth &&
                  !memcmp(t[3].refs, t[0].refs, t[0].nrefs * sizeof *t[0].refs),
              "%s sah: %u leaves depth %u on 0 threads, %u leaves depth %u on 1", name, t[3].nleaves, t[3].max_depth,
              t[0].nleaves, t[0].max_depth);
    printf("%s sah subtrees: %u nodes, %u leaves on 0, 1, 2 and 4 threads\n", name, t[0].nnodes, t[0].nleaves);
    for (int k = 0; k < 4; k++) bvh_free(&t[k]);
}

/* prim_split_bounds, an estimate of prim_clip_bounds of a box's two halves:
 * on random triangles, boxes and planes each side contains the exact
 * clip of that half up to float rounding (1e-5 of the box's extent), and
 * is empty only where the exact clip is. */
static void test_split_bounds(void)
{
    prims_t p;
    prims_init(&p);
    for (int i = 0; i < 400; i++) {
        vec3 c = rnd_v3(-5, 5);
        add_triangle(&p, v3_add(c, rnd_v3(-4, 4)), v3_add(c, rnd_v3(-4, 4)), v3_add(c, rnd_v3(-4, 4)));
    }
    finish(&p);
    uint32_t bad = 0, cases = 0;
    for (uint32_t id = 0; id < p.count; id++) {
        for (int k = 0; k < 8; k++) {
            box3 tb = p.bounds[id], box = tb;
            if (k & 1) box = box_meet(tb, (box3){rnd_v3(-9, 0), rnd_v3(0, 9)});
            if (box_is_empty(box)) continue;
            int axis = k % 3;
            float lo = v3_get(box.lo, axis), hi = v3_get(box.hi, axis), pos = lo + (hi - lo) * rnd(0.05f, 0.95f);
            box3 l, r, lh = box, rh = box;
            prim_split_bounds(&p, id, box, axis, pos, &l, &r);
            (&lh.hi.x)[axis] = pos;
            (&rh.lo.x)[axis] = pos;
            box3 el = prim_clip_bounds(&p, id, lh), er = prim_clip_bounds(&p, id, rh);
            float eps = 1e-5f * (v3_get(box_extent(box), 0) + v3_get(box_extent(box), 1) + v3_get(box_extent(box), 2));
            for (int side = 0; side < 2; side++) {
                box3 est = side ? r : l, ex = side ? er : el;
                cases++;
                if (box_is_empty(ex)) continue;
                if (box_is_empty(est)) {
                    bad++;
                    continue;
                }
                for (int a = 0; a < 3; a++)
                    bad += v3_get(ex.lo, a) < v3_get(est.lo, a) - eps || v3_get(ex.hi, a) > v3_get(est.hi, a) + eps;
            }
        }
    }
    printf("prim_split_bounds: %u halves, each holds the exact clip\n", cases);
    CHECK_MSG(bad == 0 && cases > 4000, "prim_split_bounds: %u of %u halves miss the exact clip", bad, cases);
    prims_free(&p);
}

/* The chain: N_k = {N_(k+1), leaf(real k)} for k < L - 1, N_(L-1) =
 * {leaf(decoy), leaf(real L-1)}. Every N's box reaches down to the decoy
 * near the ray origin, so the depth-first walk always enters N_(k+1) first
 * and stacks real k: L entries. The reals lie nearer the deeper they are,
 * so the hit is in a leaf the 64-entry stack had to drop. */
/* bvh_sah_best as a pass per axis with box_union and box_area (the
 * binning of Wald 2007 written plainly), for test_sah_best. */
static bvh_sah_choice sah_best_reference(const uint32_t *ids, uint32_t n, box3 box, const box3 *boxes,
                                         const vec3 *cen, const bvh_config *cfg)
{
    box3 cb = box_empty();
    for (uint32_t i = 0; i < n; i++) cb = box_grow(cb, cen[ids[i]]);
    bvh_sah_choice ch = {.cost = INFINITY, .axis = -1, .slot = 0, .cb = cb, .left = box_empty(), .right = box_empty()};
    uint32_t nb = cfg->bins, blk = cfg->leaf_block;
    for (int axis = 0; axis < 3; axis++) {
        float lo = v3_get(cb.lo, axis), ext = v3_get(cb.hi, axis) - lo;
        if (!(ext > 0.0f)) continue;
        float scale = (float)nb / ext;
        box3 bb[256];
        uint32_t bc[256] = {0};
        for (uint32_t k = 0; k < nb; k++) bb[k] = box_empty();
        for (uint32_t i = 0; i < n; i++) {
            float f = (v3_get(cen[ids[i]], axis) - lo) * scale;
            uint32_t k = !(f > 0.0f) ? 0 : f < (float)nb ? (uint32_t)f : nb - 1;
            bb[k] = box_union(bb[k], boxes[ids[i]]);
            bc[k]++;
        }
        for (uint32_t cut = 0; cut + 1 < nb; cut++) {
            box3 l = box_empty(), r = box_empty();
            uint32_t nl = 0, nr = 0;
            for (uint32_t k = 0; k <= cut; k++) l = box_union(l, bb[k]), nl += bc[k];
            for (uint32_t k = nb - 1; k > cut; k--) r = box_union(r, bb[k]), nr += bc[k];
            if (!nl || !nr) continue;
            double cost = cfg->cost_traversal * (double)box_area(box) +
                          cfg->cost_intersect * ((double)box_area(l) * (double)((nl + blk - 1) / blk * blk) +
                                                 (double)box_area(r) * (double)((nr + blk - 1) / blk * blk));
            if (cost < ch.cost) ch.cost = cost, ch.axis = axis, ch.slot = cut, ch.left = l, ch.right = r;
        }
    }
    return ch;
}

/* bvh_sah_best, bvh_centroid_bounds and bvh_ids_bounds against plain
 * passes, on random subsets of boxes of every shape: random, flat on an
 * axis, points, centroids all equal on one axis, signed zeros. */
static void test_sah_best(void)
{
    enum { N = 3000 };
    box3 *boxes = malloc(N * sizeof *boxes);
    vec3 *cen = malloc(N * sizeof *cen);
    uint32_t *ids = malloc(N * sizeof *ids);
    CHECK(boxes && cen && ids);
    if (!boxes || !cen || !ids) return;
    static const uint32_t bins[] = {2, 3, 7, 16, 32, 256};
    uint32_t bad = 0, cases = 0;
    for (int round = 0; round < 60; round++) {
        int shape = round % 5;
        for (uint32_t i = 0; i < N; i++) {
            vec3 a = rnd_v3(-10, 10), b = v3_add(a, rnd_v3(0, 3));
            if (shape == 1) a.y = b.y = 2.5f;           /* flat */
            if (shape == 2) b = a;                      /* points */
            if (shape == 3) a.z = -1.0f, b.z = 1.0f;    /* centroids equal on z */
            if (shape == 4) a.x = -0.0f, b.x = 0.0f;    /* signed zeros */
            boxes[i] = (box3){a, b};
            cen[i] = box_center(boxes[i]);
        }
        /* every fourth round a small node, where small_bins takes fewer bins */
        uint32_t n = 2 + (uint32_t)(rndd(0, 1) * (round % 4 == 0 ? 200 : N - 2));
        for (uint32_t i = 0; i < n; i++) ids[i] = (uint32_t)(rndd(0, 1) * N) % N;
        box3 plain = box_empty(), plain_cb = box_empty();
        for (uint32_t i = 0; i < n; i++) plain = box_union(plain, boxes[ids[i]]), plain_cb = box_grow(plain_cb, cen[ids[i]]);
        box3 got = bvh_ids_bounds(ids, n, boxes), got_cb = bvh_centroid_bounds(ids, n, cen);
        CHECK_MSG(memcmp(&got, &plain, sizeof got) == 0, "round %d: bvh_ids_bounds differs from box_union's", round);
        CHECK_MSG(memcmp(&got_cb, &plain_cb, sizeof got) == 0, "round %d: bvh_centroid_bounds differs", round);
        bvh_config cfg;
        bvh_config_defaults(&cfg);
        cfg.bins = bins[round % 6];
        cfg.leaf_block = round % 2 ? 4 : 1;
        cfg.cost_traversal = 2.0f;
        /* small_bins in every third round (with 3 or 32 bins; 32 in the
         * small nodes of every fourth round): the reference bins into
         * min(bins, 4 + n / 20) slots, and so must bvh_sah_best. */
        cfg.small_bins = round % 3 == 1;
        bvh_config plain_cfg = cfg;
        plain_cfg.small_bins = false;
        uint32_t want_bins = cfg.small_bins && 4 + n / 20 < cfg.bins ? 4 + n / 20 : cfg.bins;
        plain_cfg.bins = want_bins;
        CHECK_MSG(bvh_sah_bins(n, &cfg) == want_bins, "round %d: bvh_sah_bins(%u) = %u, want %u", round, n,
                  bvh_sah_bins(n, &cfg), want_bins);
        bvh_sah_choice a = bvh_sah_best(ids, n, plain, boxes, cen, &cfg);
        bvh_sah_choice r = sah_best_reference(ids, n, plain, boxes, cen, &plain_cfg);
        CHECK_MSG(a.bins == want_bins, "round %d: binned into %u, want %u", round, a.bins, want_bins);
        cases++;
        /* The cost may differ in the last bits (the sweep sums left to
         * right, the reference per cut); the cut and its boxes may not. */
        bool same = a.axis == r.axis && (a.axis < 0 || (a.slot == r.slot && fabs(a.cost - r.cost) <= 1e-12 * r.cost &&
                                                        memcmp(&a.left, &r.left, sizeof a.left) == 0 &&
                                                        memcmp(&a.right, &r.right, sizeof a.right) == 0)) &&
                    memcmp(&a.cb, &r.cb, sizeof a.cb) == 0;
        if (!same) {
            bad++;
            fprintf(stderr, "round %d (n %u, bins %u): axis %d slot %u cost %.17g, reference axis %d slot %u cost %.17g\n",
                    round, n, cfg.bins, a.axis, a.slot, a.cost, r.axis, r.slot, r.cost);
        }
    }
    CHECK_MSG(bad == 0, "bvh_sah_best differs from the plain passes in %u of %u cases", bad, cases);
    free(boxes);
    free(cen);
    free(ids);
}

static void test_overflow(void)
{
    enum { L = 100 };
    prims_t p;
    prims_init(&p);
    for (int k = 0; k < L; k++) { /* real k at x = 1000 - k: contains (x, 0.25, 0.25) */
        float x = 1000.0f - (float)k;
        add_triangle(&p, v3(x, -1, -1), v3(x, 3, -1), v3(x, -1, 3));
    }
    add_triangle(&p, v3(0.5f, -1, -1), v3(0.5f, 1, -1), v3(0.5f, -1, 1)); /* the decoy: its box holds the ray, it does not */
    finish(&p);
    bvh_t b;
    memset(&b, 0, sizeof b);
    b.nnodes = 1 + 2 * L;
    b.nodes = calloc(b.nnodes, sizeof *b.nodes);
    b.refs = malloc((L + 1) * sizeof *b.refs);
    b.nrefs = L + 1;
    for (uint32_t i = 0; i <= L; i++) b.refs[i] = i;
    for (int k = L - 1; k >= 0; k--) {
        bvh_node *n = &b.nodes[k == 0 ? 0 : 2 * k - 1];
        uint32_t l = 1 + 2 * (uint32_t)k;
        b.nodes[l + 1] = (bvh_node){p.bounds[k], (uint32_t)k, 1};
        if (k == L - 1) b.nodes[l] = (bvh_node){p.bounds[L], L, 1};
        *n = (bvh_node){box_union(b.nodes[l].box, b.nodes[l + 1].box), l, 0};
    }
    b.nleaves = L + 1;
    b.max_depth = L;
    char err[256];
    CHECK_MSG(bvh_check(&b, p.bounds, p.count, err, sizeof err) == 0, "%s", err);

    ray_t ray = make_ray(v3(0, 0.25f, 0.25f), v3(1, 0, 0), 0.0f, INFINITY);
    hit_t h = hit_none(&ray);
    counters_t c = {0};
    CHECK(bvh_intersect_dfs(&b, &p, NULL, &ray, &h, &c)); /* local stack: overflows */
    CHECK_MSG(h.prim == L - 1 && h.t == 1000.0f - (L - 1), "overflowed walk found %u at %g", h.prim, h.t);
    counters_t c2 = {0};
    bvh_scratch s;
    CHECK(bvh_scratch_init(&s, &b) == 0 && s.stack_cap >= L);
    h = hit_none(&ray);
    CHECK(bvh_intersect_dfs(&b, &p, &s, &ray, &h, &c2) && h.prim == L - 1);
    printf("chain of %d: box tests %llu with the overflow scan, %llu with a deep enough stack\n", L,
           (unsigned long long)c.box_tests, (unsigned long long)c2.box_tests);
    CHECK(c.box_tests > c2.box_tests); /* the scan is counted */
    h = hit_none(&ray);
    CHECK(bvh_intersect_dfs_fast(&b, &p, NULL, &ray, &h) && h.prim == L - 1);
    h = hit_none(&ray);
    CHECK(bvh_intersect_heap(&b, &p, NULL, &ray, &h, &c) && h.prim == L - 1);
    /* Any hit: the decoy is missed, some real is found either way. */
    CHECK(bvh_occluded_dfs(&b, &p, NULL, &ray, &c) && bvh_occluded_dfs_fast(&b, &p, &s, &ray));
    ray_t miss = make_ray(v3(0, 0.25f, 0.25f), v3(1, 0, 0), 0.0f, 10.0f);
    CHECK(!bvh_occluded_dfs(&b, &p, NULL, &miss, &c) && !bvh_occluded_heap_fast(&b, &p, &s, &miss));
    bvh_scratch_free(&s);
    bvh_free(&b);
    prims_free(&p);
}

int main(void)
{
    test_overflow();
    test_identical_and_empty();
    test_denormal_extent();
    test_sbvh();
    test_sbvh_subtrees();
    test_split_bounds();
    test_sah_best();
    test_soup_and_cluster();
    char err[512];
    scene_t *s = scene_load("bunny", err, sizeof err);
    if (!s) {
        fprintf(stderr, "cannot load bunny: %s\n", err);
        return 2;
    }
    check_scene("bunny", &s->prims, 3000);
    test_sah_subtrees("bunny", &s->prims);
    scene_free(s);
    return check_report();
}
