/* test_raycls: Arvo and Kirk's ray classification `raycls`
 * (accel/raycls_arvo_kirk.c), beyond the conformance suite.
 *
 *   beams       random hypercubes (every face, origin boxes and u-v cells
 *               from the whole range down to 2^-10) against random boxes:
 *               the cone-sphere test never drops a box the exact beam test
 *               keeps, and the exact test keeps every box that a sampled ray
 *               of the beam (origin in the box, direction in the cell)
 *               meets, so it is conservative; it is also tighter (counted)
 *   brute force random rays (origins inside and outside the scene box, some
 *               1e12 away, axis rays, ties between direction components, finite and
 *               infinite tfar, positive tnear) on a mixed scene (triangles,
 *               spheres, cones) and spd:tree:2, closest and any hit, against
 *               a test of every primitive in id order (`exhaustive`): the
 *               same t bit for bit (a different primitive only at the same
 *               t), the same occlusion; for the defaults and every setting
 *               that changes the walk
 *   lazy=eager  the lazily built tree and the eagerly built one with the
 *               same maxdepth and maxcands give bit-identical hits (t, u, v,
 *               primitive) and the same primitive tests; after reset() a
 *               lazy trace gives the same counters and grows the same tree
 *   threads     the eager tree (immutable) on 2 threads answers as on 1
 *   memcap      a build over the cap is refused with the reason; lazy growth
 *               past the cap stops splitting (refusals counted, memory()
 *               within the cap) with answers still exact; so does an eager
 *               build the cap cuts short
 *   refusals    bad parameter values name the parameter */
#include <string.h>
#include "accel/raycls_arvo_kirk.h"
#include "testlib.h"

static uint32_t rng = 777;
static float urand(void) { return test_urand(&rng); }
static float srand1(void) { return 2.0f * urand() - 1.0f; }

static accel *rc_with(const scene_t *s, const char *cfg) { return test_build_or_die("raycls", s, cfg); }

/* ---------------------------------------------------------- the beams */

/* A random sub-interval of [-1, 1] (scaled by span), as wide as 2 or as
 * narrow as 2^-10 of it. */
static void interval(float span, float *lo, float *hi)
{
    float w = 2.0f * span * exp2f(-10.0f * urand());
    float a = -span + (2.0f * span - w) * urand();
    *lo = a, *hi = a + w;
}

/* Does the ray o + t d, t >= 0, meet box q (double slab test)? */
static bool ray_meets(const double o[3], const double d[3], box3 q)
{
    double t0 = 0, t1 = INFINITY;
    const float lo[3] = {q.lo.x, q.lo.y, q.lo.z}, hi[3] = {q.hi.x, q.hi.y, q.hi.z};
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0) {
            if (o[k] < lo[k] || o[k] > hi[k]) return false;
            continue;
        }
        double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
        if (a > b) {
            double x = a;
            a = b, b = x;
        }
        t0 = fmax(t0, a), t1 = fmin(t1, b);
    }
    return t0 <= t1;
}

static void test_beams(void)
{
    int trials = 40000, exact_kept = 0, cone_only = 0, sampled_hits = 0, dropped_by_cone = 0, sampled_missed = 0;
    for (int i = 0; i < trials; i++) {
        int face = (int)(urand() * 6) % 6;
        float lo[5], hi[5];
        for (int k = 0; k < 3; k++) interval(4.0f, &lo[k], &hi[k]);
        for (int k = 3; k < 5; k++) interval(1.0f, &lo[k], &hi[k]);
        vec3 c = v3(6 * srand1(), 6 * srand1(), 6 * srand1());
        vec3 e = v3(urand() * urand() * 2, urand() * urand() * 2, urand() * urand() * 2);
        if (i % 5 == 0) e.y = 0; /* flat boxes, as axis-aligned polygons have */
        box3 q = {v3_sub(c, e), v3_add(c, e)};
        bool cone, exact;
        raycls_debug_beam_tests(face, lo, hi, 1e-6f, q, &cone, &exact);
        exact_kept += exact;
        cone_only += cone && !exact;
        dropped_by_cone += exact && !cone;
        /* Rays of the beam: origin in the box, direction in the cell. */
        int a = face / 2, ua = a == 0 ? 1 : 0, va = a == 2 ? 1 : 2;
        for (int r = 0; r < 48; r++) {
            double o[3], d[3];
            for (int k = 0; k < 3; k++) o[k] = lo[k] + (double)(hi[k] - lo[k]) * urand();
            d[a] = (face & 1) ? -1.0 : 1.0;
            d[ua] = lo[3] + (double)(hi[3] - lo[3]) * urand();
            d[va] = lo[4] + (double)(hi[4] - lo[4]) * urand();
            if (ray_meets(o, d, q)) {
                sampled_hits++;
                sampled_missed += !exact;
                break;
            }
        }
    }
    printf("beams: %d trials, exact keeps %d, cone keeps %d more, a sampled beam ray meets the box in %d\n", trials,
           exact_kept, cone_only, sampled_hits);
    CHECK_MSG(dropped_by_cone == 0, "the cone-sphere test dropped %d boxes the exact test keeps", dropped_by_cone);
    CHECK_MSG(sampled_missed == 0, "the exact test dropped %d boxes a ray of the beam meets", sampled_missed);
    CHECK(cone_only > 0 && sampled_hits > 100 && exact_kept < trials); /* the checks can fail */
}

/* ------------------------------------------------------------- scenes */

static void finish(scene_t *s) { test_finish_scene(s); }

static uint32_t vtx(scene_t *s, vec3 p) { return prims_add_vertex(&s->prims, p); }

/* ntris small random triangles, nspheres spheres and ncones cones in
 * [0, 10]^3, some axis-aligned (lying in planes of the tree's splits). */
static scene_t *soup(const char *name, uint32_t ntris, uint32_t nspheres, uint32_t ncones)
{
    scene_t *s = scene_new(name);
    for (uint32_t i = 0; i < ntris; i++) {
        vec3 c = v3(10 * urand(), 10 * urand(), 10 * urand());
        if (i % 9 == 0) c.x = 5.0f;
        vec3 a = v3_add(c, v3(srand1(), srand1(), srand1())), b = v3_add(c, v3(srand1(), srand1(), srand1()));
        if (i % 9 == 0) a.x = b.x = 5.0f;
        prims_add_triangle(&s->prims, vtx(s, c), vtx(s, a), vtx(s, b));
    }
    for (uint32_t i = 0; i < nspheres; i++)
        prims_add_sphere(&s->prims, v3(10 * urand(), 10 * urand(), 10 * urand()), 0.1f + 0.5f * urand());
    for (uint32_t i = 0; i < ncones; i++) {
        vec3 b = v3(10 * urand(), 10 * urand(), 10 * urand());
        prims_add_cone(&s->prims, b, 0.3f * urand(), v3_add(b, v3(srand1(), 2 * srand1(), srand1())), 0.2f);
    }
    finish(s);
    return s;
}

/* Random rays about the scene's box: origins inside and outside it,
 * directions random, along axes (with -0 components) or with exactly tied
 * components, tnear 0 or positive, tfar infinite or finite. */
static rayset_t *random_rays(const scene_t *s, query_kind q, uint32_t count)
{
    rayset_t *rs = rayset_new("random", s->name, 1, q);
    box3 b = s->bounds;
    vec3 c = box_center(b), e = box_extent(b);
    for (uint32_t i = 0; i < count; i++) {
        float spread = (i % 3 == 0) ? 3.0f : 0.5f; /* a third start outside the box */
        vec3 o = v3(c.x + spread * e.x * srand1(), c.y + spread * e.y * srand1(), c.z + spread * e.z * srand1());
        vec3 d = v3(srand1(), srand1(), srand1());
        if (i % 3 == 0) d = v3_sub(v3(c.x + 0.4f * e.x * srand1(), c.y + 0.4f * e.y * srand1(), c.z + 0.4f * e.z * srand1()), o);
        if (i % 17 == 0) d = v3(0.0f, (i & 32) ? -0.0f : 0.0f, (i & 64) ? -1.0f : 1.0f);
        if (i % 19 == 0) d.y = (i & 8) ? d.x : -d.x; /* |x| == |y| */
        if (i % 23 == 0) d.z = d.y;
        if (i % 29 == 0) { /* from very far: too far to classify soundly, the root list serves */
            d = v3(srand1(), srand1(), srand1());
            o = v3_sub(c, v3_scale(d, 1e12f));
        }
        if (d.x == 0 && d.y == 0 && d.z == 0) d.x = 1;
        float tnear = (i % 5 == 0) ? urand() * 0.5f * v3_len(e) / v3_len(d) : 0.0f;
        float tfar = (i % 4 == 0) ? tnear + urand() * v3_len(e) / v3_len(d) : INFINITY;
        ray_t r = {o, tnear, d, tfar, RAY_NO_LIGHT, 0};
        rayset_push(rs, &r, 0);
    }
    rayset_seal(rs);
    return rs;
}

/* ------------------------------------------------------------- checks */

static bool same_bits(float a, float b) { return memcmp(&a, &b, sizeof a) == 0; }

/* got against want: the same t bits (prim may differ only at a tie). */
static void compare(const char *what, const rayset_t *rs, const answers_t *got, const answers_t *want)
{
    uint32_t bad = 0, ties = 0, hits = 0;
    for (uint32_t i = 0; i < rs->count; i++) {
        if (rs->query == QUERY_ANY) {
            hits += want->occluded[i];
            if (got->occluded[i] != want->occluded[i] && bad++ < 3)
                fprintf(stderr, "%s: shadow ray %u: %d, want %d\n", what, i, got->occluded[i], want->occluded[i]);
            continue;
        }
        const hit_t *g = &got->hits[i], *w = &want->hits[i];
        hits += w->prim != HIT_NONE;
        bool ok = (g->prim == HIT_NONE) == (w->prim == HIT_NONE) && same_bits(g->t, w->t);
        if (ok && g->prim != w->prim) ties++;
        if (!ok && bad++ < 3)
            fprintf(stderr, "%s: ray %u: prim %u t %.9g, want prim %u t %.9g\n", what, i, g->prim, g->t, w->prim, w->t);
    }
    printf("  %-52s %5u rays %5u hits %u ties: %s\n", what, rs->count, hits, ties, bad ? "MISMATCH" : "same");
    CHECK_MSG(bad == 0, "%s: %u of %u rays differ", what, bad, rs->count);
    CHECK_MSG(hits > rs->count / 20, "%s: only %u hits; the check would prove little", what, hits);
}

static void test_brute_force(scene_t *s, rayset_t *const sets[2])
{
    static const char *const cfgs[] = {"", "beam=exact", "maxcands=1", "truncate=0.05", "truncate=0.01,maxcands=2",
                                       "lazy=off", "lazy=off,beam=exact,maxdepth=3,maxcands=8", "maxdepth=0",
                                       "maxdepth=12,maxcands=1,beam=exact"};
    accel *ex = test_build("exhaustive", s, 1);
    for (int q = 0; q < 2; q++) {
        answers_t *want = test_trace(ex, sets[q], 1);
        for (size_t k = 0; k < sizeof cfgs / sizeof cfgs[0]; k++) {
            accel *a = rc_with(s, cfgs[k]);
            answers_t *got = test_trace(a, sets[q], 1);
            char what[400];
            snprintf(what, sizeof what, "%s %s [%s]", s->name, q ? "any" : "closest", cfgs[k]);
            compare(what, sets[q], got, want);
            answers_free(got);
            a->ops->destroy(a);
        }
        answers_free(want);
    }
    ex->ops->destroy(ex);
}

static bool same_hits(const rayset_t *rs, const answers_t *a, const answers_t *b)
{
    for (uint32_t i = 0; i < rs->count; i++) {
        if (rs->query == QUERY_ANY) {
            if (a->occluded[i] != b->occluded[i]) return false;
        } else if (memcmp(&a->hits[i], &b->hits[i], sizeof a->hits[i])) {
            return false;
        }
    }
    return true;
}

/* Lazy against eager with the same rule, and reset(). */
static void test_lazy_eager(scene_t *s, rayset_t *const sets[], int nsets)
{
    const char *rule = "maxdepth=2,maxcands=4";
    char lazy_cfg[100], eager_cfg[100];
    snprintf(lazy_cfg, sizeof lazy_cfg, "%s,lazy=on", rule);
    snprintf(eager_cfg, sizeof eager_cfg, "%s,lazy=off", rule);
    accel *lazy = rc_with(s, lazy_cfg), *eager = rc_with(s, eager_cfg);
    for (int k = 0; k < nsets; k++) {
        const rayset_t *rs = sets[k];
        accel_reset(lazy);
        answers_t *l = test_trace(lazy, rs, 1), *e = test_trace(eager, rs, 1);
        CHECK_MSG(same_hits(rs, l, e), "%s %s: lazy and eager answers differ", s->name, rs->workload);
        CHECK_MSG(rs->query == QUERY_ANY || l->total.prim_tests == e->total.prim_tests,
                  "%s %s: lazy %llu and eager %llu primitive tests", s->name, rs->workload,
                  (unsigned long long)l->total.prim_tests, (unsigned long long)e->total.prim_tests);
        /* After reset: the same counters and the same tree again. */
        uint32_t n1, n2;
        uint64_t e1, e2, r1, r2;
        raycls_debug_counts(lazy, &n1, &e1, &r1);
        accel_reset(lazy);
        uint32_t n0;
        uint64_t e0, r0;
        raycls_debug_counts(lazy, &n0, &e0, &r0);
        CHECK_MSG(n0 == 6 && r0 == 0, "reset left %u nodes, %llu refusals", n0, (unsigned long long)r0);
        answers_t *again = test_trace(lazy, rs, 1);
        raycls_debug_counts(lazy, &n2, &e2, &r2);
        CHECK_MSG(same_hits(rs, l, again) && !memcmp(&l->total, &again->total, sizeof l->total),
                  "%s %s: a trace after reset differs", s->name, rs->workload);
        CHECK_MSG(n1 == n2 && e1 == e2 && r1 == r2, "%s %s: the tree grew differently after reset", s->name,
                  rs->workload);
        /* The eager tree is immutable: 2 threads answer as 1, with the same
         * primitive tests (steps and box tests depend on which rays each
         * thread's leaf cache saw before). */
        answers_t *two = test_trace(eager, rs, 2);
        CHECK_MSG(same_hits(rs, e, two) && e->total.prim_tests == two->total.prim_tests &&
                      e->total.prim_hits == two->total.prim_hits && e->total.mailbox_hits == two->total.mailbox_hits &&
                      e->total.empty_leaves == two->total.empty_leaves,
                  "%s %s: the eager tree on 2 threads differs", s->name, rs->workload);
        printf("  lazy=eager %-12s %-10s %6u rays: lazy made %u hypercubes, %llu list entries\n", s->name, rs->workload,
               rs->count, n1, (unsigned long long)e1);
        answers_free(l);
        answers_free(e);
        answers_free(again);
        answers_free(two);
    }
    lazy->ops->destroy(lazy);
    eager->ops->destroy(eager);
}

static void test_memcap(void)
{
    char err[512];
    /* The build: 20000 primitives need some 1.4 MiB of root lists and tables. */
    scene_t *big = soup("big", 20000, 0, 0);
    accel *a = test_build_with(accel_find("raycls"), big, "memcap=1", 1, err, sizeof err);
    CHECK_MSG(a == NULL && strstr(err, "memcap=1") != NULL, "build over memcap=1: %s", a ? "built" : err);
    if (a) a->ops->destroy(a);
    scene_free(big);

    /* Lazy growth past the cap, and an eager build cut short by it. */
    scene_t *s = soup("capped", 3000, 100, 20);
    rayset_t *rs = random_rays(s, QUERY_CLOSEST, 20000);
    accel *ex = test_build("exhaustive", s, 1);
    answers_t *want = test_trace(ex, rs, 1);
    static const char *const cfgs[] = {"memcap=1,maxcands=1,maxdepth=10", "memcap=1,lazy=off,maxdepth=6,maxcands=1"};
    for (int k = 0; k < 2; k++) {
        a = rc_with(s, cfgs[k]);
        answers_t *got = test_trace(a, rs, 1);
        uint32_t nodes;
        uint64_t entries, refusals;
        raycls_debug_counts(a, &nodes, &entries, &refusals);
        size_t mem = a->ops->memory(a);
        printf("  memcap [%s]: %u hypercubes, %llu entries, %zu bytes, %llu refusals\n", cfgs[k], nodes,
               (unsigned long long)entries, mem, (unsigned long long)refusals);
        CHECK_MSG(refusals > 0, "[%s]: the cap never refused", cfgs[k]);
        CHECK_MSG(mem <= (1u << 20), "[%s]: memory() %zu over the cap", cfgs[k], mem);
        compare(cfgs[k], rs, got, want);
        answers_free(got);
        a->ops->destroy(a);
    }
    answers_free(want);
    ex->ops->destroy(ex);
    rayset_free(rs);
    scene_free(s);
}

static void test_refusals(void)
{
    scene_t *s = soup("params", 10, 0, 0);
    static const char *const bad[][2] = {
        {"maxdepth=21", "maxdepth"}, {"maxdepth=-1", "maxdepth"}, {"maxdepth=x", "maxdepth"}, {"maxcands=0", "maxcands"},
        {"truncate=-1", "truncate"}, {"lazy=maybe", "lazy"},     {"beam=box", "beam"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) test_expect_refusal("raycls", s, bad[i][0], bad[i][1]);
    scene_free(s);
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    test_beams();
    test_refusals();

    scene_t *scenes[2] = {soup("mixed", 400, 40, 12), test_scene("spd:tree:2")};
    for (int i = 0; i < 2; i++) {
        rayset_t *sets[2] = {random_rays(scenes[i], QUERY_CLOSEST, 6000), random_rays(scenes[i], QUERY_ANY, 6000)};
        test_brute_force(scenes[i], sets);
        /* The harness's workloads too, for lazy against eager. */
        accel *ref = test_build("embree", scenes[i], 1);
        workload_opts o = test_wl(48, 48, 1);
        rayset_t *all[8] = {sets[0], sets[1]};
        int n = 2;
        for (int w = 0; workload_table[w].name && n < 8; w++) all[n++] = workload_table[w].make(scenes[i], ref, &o);
        test_lazy_eager(scenes[i], all, n);
        for (int k = 0; k < n; k++) rayset_free(all[k]);
        ref->ops->destroy(ref);
        scene_free(scenes[i]);
    }
    test_memcap();
    return check_report();
}
