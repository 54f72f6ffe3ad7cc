/* test_champion: the wide SIMD BVH `bvh` (accel/bvh_wide/bvh_wide.c,
 * accel/bvh_wide/wide*.{h,c}, collapse.c) beyond the conformance suite.
 *
 *   simd        every instruction set this CPU has, at width 2, 4 and 8,
 *               with fma=off and (but SSE4.2) fma=on, against the scalar
 *               reference traversal of the same tree and fma setting:
 *               ray for ray on every workload of spd:balls:2, spd:tree:2,
 *               bunny and gen:room, bit-identical hits (t, u, v, prim) or
 *               occlusion and identical counters, and the same on
 *               axis-aligned rays with +0 and -0 components from a lattice
 *               over the scene's box (origins in box planes); the counting-free
 *               methods give the same answers; an ISA the CPU lacks is
 *               skipped here by an explicit check (and refused by build);
 *               packets=off (leaves through refs) the same as packets=on;
 *               robust=off (Moller-Trumbore packets, plain box constants)
 *               the same way on the bunny and gen:room
 *   tree        wide_check on every tree built here: slots contain their
 *               children, unused slots empty, each primitive in one leaf,
 *               the counts and statistics right; avg_children within 2..W
 *   leafsize=1  the same answers check with one primitive a leaf
 *   single      one triangle, one sphere: a root with one leaf child
 *   overflow    a box whose entry and exit distances are both +inf under
 *               tfar = +inf is a miss on every width, ISA and fma setting
 *               (the kernels' one comparison, wide_walk.h)
 *   conservative the box test under fma=off and fma=on: a thin box around a
 *               point of the exact ray (flat along an axis the ray does not
 *               move on) is always hit, empty slots never, over 300000
 *               rays with +-0 and tiny components
 *   one point   2000 spheres with one centre and radius and 2000
 *               triangles collapsed to one point: the builder splits by
 *               count, the tree stays shallow, answers match exhaustive
 *   memcap      10^6 triangles: refused with one line naming memcap under
 *               a small cap, built under the default, answers matching
 *               the scalar traversal on a sample of rays
 *   threads     the build over 1, 2 and 3 threads on the bunny, spd:balls:3
 *               and the 10^6-triangle grid: nodes, refs and packets equal
 *               byte for byte (build.c's deterministic parallel subtrees)
 *   sbvh        split=sbvh through every width and ISA against the scalar
 *               traversal on gen:room, width=2 leafsize=1 against
 *               exhaustive on the bunny, and its build over 1, 2 and 3
 *               threads (in threads)
 *   octant      order=octant: every ISA against scalar (in simd), answers
 *               as exhaustive's on the bunny, wide_check refusing a
 *               swapped or repeating octant order
 *   embree      tree=embree (Embree's builder through rtcBuildBVH, our
 *               kernels) and Embree's rules in our own builder (minleaf=4,
 *               bigleaf=28, travcost=4, slots=size) on the bunny: wide_check,
 *               answers as exhaustive's, leaves of 5 to 28 primitives made
 *               by the merge, slots by subtree size, and node and leaf
 *               counts within 2 % of Embree's tree; tree=embree refused
 *               with width=4 or split=sbvh
 *   compress    compress=on (quantised BVH8 nodes): decoded boxes contain
 *               the exact ones within a step, at scales from 1e-30 to
 *               1e37 and zero extents; a node wider than the largest scale
 *               refused; every ISA against scalar (in simd), the one-leaf
 *               root and the overflowing entry (in single and overflow);
 *               answers as exhaustive's on the bunny, 128 bytes a node
 *               saved; wide_check refusing a shrunk quantised slot;
 *               width=4 refused
 *   refusals    width=5, isa=neon, leafsize=0, bins=1; an ISA the CPU lacks;
 *               fma=on where the SSE4.2 kernel runs (isa=sse42, width=2)
 *   settle      isa=auto settles to the ISA build() picks, fma=auto to on
 *               under AVX2 and AVX-512 and off under scalar; smallbins to
 *               off under split=sbvh
 *   robust=off  answers against exhaustive (watertight) on the bunny under
 *               fma=on and off, scalar and SIMD: the same but at edges (a
 *               closest hit's t within a relative 1e-4, the primitive
 *               free only then; rays that differ more at most 1 in 10^4);
 *               robust=on by default, the params saying robust */
#include <math.h>
#include <string.h>
#include "accel/bvh_wide/bvh_wide.h"
#include "../prims/prims_internal.h" /* float_down, float_up */
#include "testlib.h"

static accel *champ_with(const scene_t *s, const char *cfg)
{
    char err[512];
    accel *a = test_build_with(accel_find("bvh"), s, cfg, 1, err, sizeof err);
    if (!a) {
        fprintf(stderr, "bvh [%s] on %s: %s\n", cfg, s->name, err);
        exit(2);
    }
    return a;
}

static void check_tree(const accel *a, const char *label)
{
    const wide_bvh *w = bvh_wide_tree(a, NULL);
    const prims_t *p = &a->scene->prims;
    char err[256] = "";
    int rc = wide_check(w, p->bounds, p->count, err, sizeof err);
    CHECK_MSG(rc == 0, "%s on %s: %s", label, a->scene->name, err);
    if (w->nnodes) {
        double avg = (double)w->nchildren / w->nnodes;
        CHECK_MSG(avg >= 1.0 && avg <= w->width, "%s: avg_children %g", label, avg);
        CHECK_MSG(w->nnodes == 1 || avg >= 2.0, "%s: avg_children %g below 2", label, avg);
    }
    accel_stat st[ACCEL_STATS_MAX];
    int n = accel_stats(a, st, ACCEL_STATS_MAX);
    CHECK_MSG(n == 9, "%s: %d statistics", label, n);
    /* The cost model's prediction (tests/test_wide_predict.c checks its
     * values): at least the root's slots' box tests, some primitive tests. */
    for (int i = 0; i < n && w->nnodes; i++) {
        if (!strcmp(st[i].name, "predicted_box_tests_per_ray"))
            CHECK_MSG(st[i].value >= WIDE_NCHILDREN_Q(w->nodes, w->width, w->quantized), "%s: predicted box tests %g",
                      label, st[i].value);
        if (!strcmp(st[i].name, "predicted_tests_per_ray"))
            CHECK_MSG(st[i].value > 0.0 && isfinite(st[i].value), "%s: predicted tests %g", label, st[i].value);
    }
}

static bool same_hit(const hit_t *x, const hit_t *y)
{
    return x->prim == y->prim && memcmp(&x->t, &y->t, sizeof x->t) == 0 && memcmp(&x->u, &y->u, sizeof x->u) == 0 &&
           memcmp(&x->v, &y->v, sizeof x->v) == 0;
}

static bool same_counters(const counters_t *x, const counters_t *y) { return memcmp(x, y, sizeof *x) == 0; }

/* Every traceable ray of rs through a and ref one at a time: the same
 * answer bit for bit and the same counters, and a's fast methods the same
 * answer. At most 3 failures printed per set. Returns the rays compared. */
static uint32_t compare_ray_array(accel *ref, accel *a, const ray_t *rays, uint32_t count, bool any, const char *label,
                                  const char *wl)
{
    accel_ctx *cr = ref->ops->context_new(ref), *ca = a->ops->context_new(a);
    uint32_t compared = 0, printed = 0;
    for (uint32_t i = 0; i < count; i++) {
        const ray_t *ray = &rays[i];
        if (!ray_traceable(ray)) continue;
        compared++;
        counters_t c1 = {0}, c2 = {0};
        bool ok;
        if (any) {
            bool o1 = ref->ops->occluded(ref, cr, ray, &c1), o2 = a->ops->occluded(a, ca, ray, &c2);
            bool o3 = a->ops->occluded_fast(a, ca, ray);
            ok = o1 == o2 && o2 == o3 && same_counters(&c1, &c2);
        } else {
            hit_t h1 = hit_none(ray), h2 = hit_none(ray), h3 = hit_none(ray);
            bool r1 = ref->ops->intersect(ref, cr, ray, &h1, &c1), r2 = a->ops->intersect(a, ca, ray, &h2, &c2);
            bool r3 = a->ops->intersect_fast(a, ca, ray, &h3);
            ok = r1 == r2 && r2 == r3 && same_hit(&h1, &h2) && same_hit(&h2, &h3) && same_counters(&c1, &c2);
        }
        if (!ok && printed++ < 3)
            fprintf(stderr, "%s on %s %s: ray %u differs from the scalar reference (answer or counters)\n", label,
                    a->scene->name, wl, i);
        CHECK(ok || printed > 3);
    }
    a->ops->context_free(ca);
    ref->ops->context_free(cr);
    return compared;
}

static uint32_t compare_rays(accel *ref, accel *a, const rayset_t *rs, const char *label, const char *wl)
{
    return compare_ray_array(ref, a, rs->rays, rs->count, rs->query == QUERY_ANY, label, wl);
}

/* Axis-aligned rays whose other direction components are +0 or -0, from
 * a lattice over the scene's box that includes its faces and centre
 * planes (so origins lie in planes of child boxes), both ways along each
 * axis: reciprocals of +-inf, plane distances of 0 * inf = NaN. */
static ray_t *axis_rays(const scene_t *s, uint32_t *count)
{
    const int n = 9;
    ray_t *rays = malloc(sizeof *rays * 3 * 2 * 4 * n * n);
    uint32_t k = 0;
    box3 b = s->prims.box;
    float lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
    for (int ax = 0; ax < 3; ax++)
        for (int sign = 0; sign < 2; sign++)
            for (int zeros = 0; zeros < 4; zeros++)
                for (int i = 0; i < n; i++)
                    for (int j = 0; j < n; j++) {
                        int u = (ax + 1) % 3, v = (ax + 2) % 3;
                        float o[3], d[3];
                        o[ax] = sign ? hi[ax] + 1.0f : lo[ax] - 1.0f;
                        o[u] = lo[u] + (hi[u] - lo[u]) * (float)i / (float)(n - 1);
                        o[v] = lo[v] + (hi[v] - lo[v]) * (float)j / (float)(n - 1);
                        d[ax] = sign ? -1.0f : 1.0f;
                        d[u] = (zeros & 1) ? -0.0f : 0.0f;
                        d[v] = (zeros & 2) ? -0.0f : 0.0f;
                        rays[k++] = (ray_t){v3(o[0], o[1], o[2]), 0.0f, v3(d[0], d[1], d[2]), INFINITY, RAY_NO_LIGHT, 0};
                    }
    *count = k;
    return rays;
}

/* Every ISA this CPU has at width W against scalar, on every workload. */
static void simd_vs_scalar(const scene_t *s, accel *embree, int res, const char *extra)
{
    const int first_width = strstr(extra, "compress=on") ? 8 : 2; /* quantised nodes are 8 wide */
    workload_opts o = test_wl(res, res, 2);
    rayset_t *sets[16];
    int nsets = 0;
    for (int w = 0; workload_table[w].name && nsets < 16; w++) sets[nsets++] = workload_table[w].make(s, embree, &o);
    uint32_t naxis;
    ray_t *axis = axis_rays(s, &naxis);
    for (int width = first_width; width <= 8; width *= 2)
        for (int fused = 0; fused < 2; fused++) {
            if (fused && width == 2) continue; /* width 2 runs the SSE4.2 kernel, which has no fma */
            const char *fma = fused ? "on" : "off";
            char cfg[160];
            snprintf(cfg, sizeof cfg, "width=%d,isa=scalar,fma=%s%s", width, fma, extra);
            accel *ref = champ_with(s, cfg);
            check_tree(ref, cfg);
            for (int isa = WIDE_ISA_SSE42; isa < WIDE_ISA_COUNT; isa++) {
                if (!wide_isa_supported((wide_isa)isa)) {
                    printf("%-12s width=%d isa=%-7s skipped: this CPU lacks it\n", s->name, width, wide_isa_names[isa]);
                    continue;
                }
                if (fused && isa == WIDE_ISA_SSE42) continue; /* refused: test_refusals */
                snprintf(cfg, sizeof cfg, "width=%d,isa=%s,fma=%s%s", width, wide_isa_names[isa], fma, extra);
                accel *a = champ_with(s, cfg);
                wide_isa got;
                bvh_wide_tree(a, &got);
                wide_isa want = width == 2 ? WIDE_ISA_SSE42 : (wide_isa)isa; /* BVH2: one SSE4.2 kernel for all */
                CHECK_MSG(got == want, "%s: kernels of %s", cfg, wide_isa_names[got]);
                int before = check_failed;
                uint64_t rays = 0;
                for (int k = 0; k < nsets; k++) rays += compare_rays(ref, a, sets[k], cfg, workload_table[k].name);
                rays += compare_ray_array(ref, a, axis, naxis, false, cfg, "axis rays, closest") +
                        compare_ray_array(ref, a, axis, naxis, true, cfg, "axis rays, any");
                printf("%-12s %-48s %8llu rays over %d workloads and axis rays %s\n", s->name, cfg,
                       (unsigned long long)rays, nsets, check_failed == before ? "bit-identical to scalar" : "DIFFER");
                a->ops->destroy(a);
            }
            if (!fused && !strstr(extra, "robust=off")) {
                /* Leaves through refs instead of packets: the same answers
                 * and counters (not under robust=off: refs keep prims/'
                 * watertight tests). */
                snprintf(cfg, sizeof cfg, "width=%d,isa=scalar,fma=off,packets=off%s", width, extra);
                accel *a = champ_with(s, cfg);
                check_tree(a, cfg);
                int before = check_failed;
                for (int k = 0; k < nsets; k++) compare_rays(ref, a, sets[k], cfg, workload_table[k].name);
                printf("%-12s %-48s %s\n", s->name, cfg, check_failed == before ? "bit-identical to packets=on" : "DIFFER");
                a->ops->destroy(a);
            }
            ref->ops->destroy(ref);
        }
    for (int k = 0; k < nsets; k++) rayset_free(sets[k]);
    free(axis);
}

/* Image sides of the ray sets the kernels are compared on. Under
 * AddressSanitizer a quarter of the rays walk the same kernels at a quarter
 * of the cost (this test was a seventh of the sanitizer suite); the release
 * suite compares the full sets. */
#ifdef __SANITIZE_ADDRESS__
enum { SIMD_RES = 24, SIMD_RES_VARIANT = 16 };
#else
enum { SIMD_RES = 48, SIMD_RES_VARIANT = 32 };
#endif

static void test_simd(void)
{
    static const char *const names[] = {"spd:balls:2", "spd:tree:2", "bunny", "gen:room"};
    for (int i = 0; i < 4; i++) {
        scene_t *s = test_scene(names[i]);
        accel *embree = test_build("embree", s, 2);
        simd_vs_scalar(s, embree, SIMD_RES, "");
        /* order=octant: every ISA's walk in the octant order gives the scalar one's answers and counters */
        simd_vs_scalar(s, embree, SIMD_RES_VARIANT, ",order=octant");
        /* compress=on: every ISA's decoding of the quantised planes gives the scalar one's answers and counters */
        simd_vs_scalar(s, embree, SIMD_RES_VARIANT, ",compress=on");
        if (i == 2) simd_vs_scalar(s, embree, SIMD_RES_VARIANT, ",leafsize=1"); /* leafsize=1 on the bunny */
        /* robust=off: every ISA's Moller-Trumbore packets and plain box constants give the scalar reference's
         * answers and counters (the scenes of triangles, which have packets) */
        if (i >= 2) simd_vs_scalar(s, embree, SIMD_RES_VARIANT, ",robust=off");
        embree->ops->destroy(embree);
        scene_free(s);
    }
}

static scene_t *finished(scene_t *s)
{
    char err[256];
    if (scene_finish(s, false, err, sizeof err)) {
        fprintf(stderr, "%s: %s\n", s->name, err);
        exit(2);
    }
    return s;
}

/* The image side at which the bunny's variants are compared with
 * exhaustive, whose trace is the costly part: under AddressSanitizer a
 * smaller one walks the same code. */
#ifdef __SANITIZE_ADDRESS__
enum { EXHAUSTIVE_RES = 16 };
#else
enum { EXHAUSTIVE_RES = 24 };
#endif

/* Exhaustive's ray sets and answers for one scene at one image side. The
 * bunny is compared against exhaustive at the same side by several tests,
 * and exhaustive's trace of it was most of this test's time: each is made
 * once, for a scene of that name and primitive count, and kept to the end. */
enum { MAX_REFERENCES = 8, MAX_WORKLOADS = 16 };
typedef struct {
    char name[256];
    uint32_t prims;
    int res, nsets;
    rayset_t *sets[MAX_WORKLOADS];
    answers_t *want[MAX_WORKLOADS];
} exhaustive_reference;
static exhaustive_reference references[MAX_REFERENCES];
static int nreferences;

static const exhaustive_reference *reference_for(scene_t *s, int res)
{
    for (int i = 0; i < nreferences; i++)
        if (!strcmp(references[i].name, s->name) && references[i].prims == s->prims.count && references[i].res == res)
            return &references[i];
    if (nreferences == MAX_REFERENCES) {
        fprintf(stderr, "test_champion: more than %d exhaustive references\n", MAX_REFERENCES);
        exit(2);
    }
    exhaustive_reference *r = &references[nreferences++];
    snprintf(r->name, sizeof r->name, "%s", s->name);
    r->prims = s->prims.count, r->res = res, r->nsets = 0;
    accel *ex = test_build("exhaustive", s, 1);
    workload_opts o = test_wl(res, res, 1);
    for (int w = 0; workload_table[w].name && r->nsets < MAX_WORKLOADS; w++, r->nsets++) {
        r->sets[w] = workload_table[w].make(s, ex, &o);
        r->want[w] = test_trace(ex, r->sets[w], 1);
    }
    ex->ops->destroy(ex);
    return r;
}

static void free_references(void)
{
    for (int i = 0; i < nreferences; i++)
        for (int w = 0; w < references[i].nsets; w++) {
            answers_free(references[i].want[w]);
            rayset_free(references[i].sets[w]);
        }
    nreferences = 0;
}

/* Answers of bvh [cfg] against exhaustive on every workload: the same
 * hits bit for bit, or (same_prim false: coincident primitives, where
 * which of equal t is kept depends on the order they are tested in) the
 * same distances. */
static void against_exhaustive(scene_t *s, const char *cfg, int res, bool same_prim)
{
    const exhaustive_reference *ref = reference_for(s, res);
    accel *a = champ_with(s, cfg);
    check_tree(a, cfg);
    for (int w = 0; w < ref->nsets; w++) {
        const rayset_t *rs = ref->sets[w];
        const answers_t *want = ref->want[w];
        answers_t *got = test_trace(a, rs, 1);
        uint32_t diff = 0;
        for (uint32_t i = 0; i < rs->count; i++)
            diff += rs->query == QUERY_ANY ? want->occluded[i] != got->occluded[i]
                   : same_prim ? !same_hit(&want->hits[i], &got->hits[i])
                               : (want->hits[i].prim == HIT_NONE) != (got->hits[i].prim == HIT_NONE) ||
                                     memcmp(&want->hits[i].t, &got->hits[i].t, sizeof(float)) != 0;
        CHECK_MSG(diff == 0, "%s [%s] %s: %u of %u rays differ from exhaustive", s->name, cfg, workload_table[w].name,
                  diff, rs->count);
        answers_free(got);
    }
    a->ops->destroy(a);
}

/* The triangle (0,0,0), (1,0,0), (0,1,0) alone. */
static scene_t *one_triangle(void)
{
    scene_t *s = scene_new("one triangle");
    uint32_t a = prims_add_vertex(&s->prims, v3(0, 0, 0)), b = prims_add_vertex(&s->prims, v3(1, 0, 0)),
             c = prims_add_vertex(&s->prims, v3(0, 1, 0));
    prims_add_triangle(&s->prims, a, b, c);
    return finished(s);
}

static void test_single(void)
{
    scene_t *s = one_triangle();
    for (int w = 2; w <= 16; w *= 2) {
        char cfg[64];
        snprintf(cfg, sizeof cfg, w == 16 ? "compress=on" : "width=%d", w); /* 16: the quantised BVH8 */
        accel *x = champ_with(s, cfg);
        const wide_bvh *t = bvh_wide_tree(x, NULL);
        CHECK(t->nnodes == 1 && t->nleaves == 1 && t->nchildren == 1 && t->max_depth == 1);
        accel_ctx *ctx = x->ops->context_new(x);
        ray_t r = {v3(0.25f, 0.25f, 1), 0, v3(0, 0, -1), INFINITY, RAY_NO_LIGHT, 0};
        hit_t h = hit_none(&r);
        counters_t cnt = {0};
        CHECK(x->ops->intersect(x, ctx, &r, &h, &cnt) && h.prim == 0 && h.t == 1.0f);
        CHECK(cnt.box_tests == 1 && cnt.steps == 2 && cnt.prim_tests == 1);
        r.dir = v3(0, 0, 1);
        CHECK(!x->ops->occluded(x, ctx, &r, &cnt));
        x->ops->context_free(ctx);
        x->ops->destroy(x);
    }
    against_exhaustive(s, "", 16, true);
    against_exhaustive(s, "compress=on", 16, true);
    scene_free(s);

    s = scene_new("one sphere");
    prims_add_sphere(&s->prims, v3(0, 0, 0), 1.0f);
    finished(s);
    against_exhaustive(s, "width=4", 16, true);
    against_exhaustive(s, "width=8,isa=scalar", 16, true);
    scene_free(s);
}

/* The box kernels' one comparison (wide_walk.h: the interval's end at most
 * FLT_MAX): a ray along x whose entry distance overflows to +inf (origin
 * 2^60 before the triangle, RAY_COORD_MAX, the farthest a traceable ray
 * may start; direction 1e-30) and that runs parallel to y outside the
 * box's y slab (entry and exit +inf there) meets the leaf's box with entry
 * +inf and exit +inf under tfar = +inf. Every width and ISA must count that
 * box a miss under fma=off: one node visited, no primitive tested; under
 * fma=on the ray misses too, after one leaf (below). */
static void test_overflowing_entry(void)
{
    scene_t *s = one_triangle();
    for (int w = 2; w <= 16; w *= 2) /* 16: the quantised BVH8 */
        for (int isa = WIDE_ISA_SCALAR; isa < WIDE_ISA_COUNT * 2; isa++) { /* from WIDE_ISA_COUNT: fma=on */
            const bool fused = isa >= WIDE_ISA_COUNT;
            const wide_isa i = (wide_isa)(isa % WIDE_ISA_COUNT);
            if (!wide_isa_supported(i) || (fused && (w == 2 || i == WIDE_ISA_SSE42))) continue;
            char cfg[64];
            snprintf(cfg, sizeof cfg, "width=%d,isa=%s,fma=%s%s", w == 16 ? 8 : w, wide_isa_names[i],
                     fused ? "on" : "off", w == 16 ? ",compress=on" : "");
            accel *x = champ_with(s, cfg);
            accel_ctx *ctx = x->ops->context_new(x);
            ray_t r = {v3(-0x1p60f, -5, 0), 0, v3(1e-30f, 0, 0), INFINITY, RAY_NO_LIGHT, 0};
            CHECK(ray_traceable(&r));
            hit_t h = hit_none(&r);
            counters_t cnt = {0};
            CHECK(!x->ops->intersect(x, ctx, &r, &h, &cnt));
            /* fma=on: the y entry's constant o nmul overflows and is held at
             * -FLT_MAX (wide_fused_init), so the entry is FLT_MAX, not +inf,
             * and the box is taken: one leaf more, still a miss. */
            const uint64_t steps = fused ? 2 : 1;
            CHECK_MSG(cnt.steps == steps && cnt.prim_tests == steps - 1, "[%s] entry +inf, exit +inf: %llu steps, %llu tests",
                      cfg, (unsigned long long)cnt.steps, (unsigned long long)cnt.prim_tests);
            counters_t any = {0};
            CHECK(!x->ops->occluded(x, ctx, &r, &any));
            CHECK_MSG(any.steps == steps, "[%s] any hit: %llu steps", cfg, (unsigned long long)any.steps);
            x->ops->context_free(ctx);
            x->ops->destroy(x);
        }
    printf("entry distance overflowing to +inf under tfar = +inf: a miss on every width, ISA and fma\n");
    scene_free(s);
}

static void test_one_point(void)
{
    scene_t *s = scene_new("one point");
    for (int i = 0; i < 2000; i++) prims_add_sphere(&s->prims, v3(1, 2, 3), 0.5f);
    uint32_t v = prims_add_vertex(&s->prims, v3(1, 2, 3));
    for (int i = 0; i < 2000; i++) prims_add_triangle(&s->prims, v, v, v);
    finished(s);
    const char *cfgs[] = {"", "width=4,leafsize=1", "leafsize=32,bins=2"};
    for (int k = 0; k < 3; k++) {
        accel *a = champ_with(s, cfgs[k]);
        const wide_bvh *t = bvh_wide_tree(a, NULL);
        CHECK_MSG(t->max_depth <= 16, "[%s] depth %u over 4000 primitives at one point", cfgs[k], t->max_depth);
        a->ops->destroy(a);
        against_exhaustive(s, cfgs[k], 12, false);
    }
    scene_free(s);
}

/* A 1000 x 500 height field: 10^6 triangles. */
static scene_t *million(void)
{
    scene_t *s = scene_new("million");
    const int nx = 1000, ny = 500;
    for (int j = 0; j <= ny; j++)
        for (int i = 0; i <= nx; i++)
            prims_add_vertex(&s->prims, v3((float)i, (float)j, 3.0f * sinf(0.05f * (float)i) * cosf(0.07f * (float)j)));
    for (int j = 0; j < ny; j++)
        for (int i = 0; i < nx; i++) {
            uint32_t a = (uint32_t)(j * (nx + 1) + i), b = a + 1, c = a + (uint32_t)nx + 1, d = c + 1;
            prims_add_triangle(&s->prims, a, b, d);
            prims_add_triangle(&s->prims, a, d, c);
        }
    return finished(s);
}

static void test_memcap(void)
{
    scene_t *s = million();
    CHECK(s->prims.count == 1000000);
    char err[512] = "";
    accel *a = test_build_with(accel_find("bvh"), s, "memcap=64", 1, err, sizeof err);
    CHECK_MSG(!a && strstr(err, "memcap=64") && !strchr(err, '\n'), "memcap=64 over 10^6 triangles: %s", a ? "built" : err);
    printf("million      memcap=64 refused: %s\n", err);
    if (a) a->ops->destroy(a);
    const wide_isa isa = wide_isa_best(); /* the defaults' kernels, and their fma setting for the reference */
    accel *ref = champ_with(s, isa == WIDE_ISA_AVX2 || isa == WIDE_ISA_AVX512 ? "isa=scalar,fma=on" : "isa=scalar"),
          *best = champ_with(s, "");
    check_tree(best, "million");
    size_t mem = best->ops->memory(best);
    printf("million      built: %zu bytes (%.1f per triangle)\n", mem, (double)mem / s->prims.count);
    CHECK(mem < 128u * s->prims.count); /* 256-byte nodes over leaves of about 2 triangles: some 70 */
    workload_opts o = test_wl(64, 64, 1);
    accel *embree = test_build("embree", s, 1);
    for (int w = 0; workload_table[w].name; w++) {
        rayset_t *rs = workload_table[w].make(s, embree, &o);
        compare_rays(ref, best, rs, "million", workload_table[w].name);
        rayset_free(rs);
    }
    embree->ops->destroy(embree);
    best->ops->destroy(best);
    ref->ops->destroy(ref);
    scene_free(s);
}

/* a and b hold the same tree, byte for byte. */
static bool same_tree(const wide_bvh *a, const wide_bvh *b)
{
    return a->width == b->width && a->nnodes == b->nnodes && a->nrefs == b->nrefs && a->npackets == b->npackets &&
           a->nleaves == b->nleaves && a->max_depth == b->max_depth && a->nchildren == b->nchildren &&
           !memcmp(a->nodes, b->nodes, (size_t)a->nnodes * wide_node_bytes(a->width)) &&
           !memcmp(a->refs, b->refs, (size_t)a->nrefs * sizeof *a->refs) &&
           (!a->npackets || !memcmp(a->packets, b->packets, (size_t)a->npackets * sizeof *a->packets));
}

static void test_threads(void)
{
    scene_t *scenes[] = {test_scene("bunny"), test_scene("spd:balls:3"), million()};
#ifdef __SANITIZE_ADDRESS__
    /* Three more builds of 10^6 triangles add nothing AddressSanitizer can
     * see that test_memcap's build does not: the release suite runs them. */
    const int nscenes = 2;
    scene_free(scenes[2]);
    printf("million      built on 1, 2 and 3 threads: run by the release build's suite, not under AddressSanitizer\n");
#else
    const int nscenes = 3;
#endif
    for (int i = 0; i < nscenes; i++) {
        char err[512];
        const char *cfg = "";
    again:;
        accel *one = test_build_with(accel_find("bvh"), scenes[i], cfg, 1, err, sizeof err);
        CHECK_MSG(one != NULL, "%s: %s", scenes[i]->name, err);
        for (int threads = 2; one && threads <= 3; threads++) {
            accel *more = test_build_with(accel_find("bvh"), scenes[i], cfg, threads, err, sizeof err);
            CHECK_MSG(more != NULL, "%s: %s", scenes[i]->name, err);
            if (!more) continue;
            CHECK_MSG(same_tree(bvh_wide_tree(one, NULL), bvh_wide_tree(more, NULL)),
                      "%s: the tree built on %d threads differs from the one on 1", scenes[i]->name, threads);
            check_tree(more, "threads");
            more->ops->destroy(more);
        }
        printf("%-12s [%s] built on 1, 2 and 3 threads: the same nodes, refs and packets\n", scenes[i]->name, cfg);
        if (one) one->ops->destroy(one);
        /* The spatial-split build too (not on the 10^6 grid: its time). */
        if (!*cfg && i < 2) {
            cfg = "split=sbvh";
            goto again;
        }
        scene_free(scenes[i]);
    }
}

/* split=sbvh (build_sbvh.c; its SAH cost and duplication are tests/test_bvh.c's)
 * through every width and kernel: SIMD against scalar on gen:room, the
 * answers of a leafsize=1 width=2 tree against exhaustive on the bunny. */
static void test_sbvh(void)
{
    scene_t *s = test_scene("gen:room");
    accel *embree = test_build("embree", s, 2);
    simd_vs_scalar(s, embree, 32, ",split=sbvh");
    embree->ops->destroy(embree);
    scene_free(s);
    s = test_scene("bunny");
    against_exhaustive(s, "split=sbvh,width=2,leafsize=1", EXHAUSTIVE_RES, true);
    scene_free(s);
}

static void test_refusals(void)
{
    scene_t *s = test_scene("spd:balls:1");
    const char *bad[] = {"width=5", "isa=neon", "leafsize=0", "leafsize=33", "bins=1"};
    const char *key[] = {"width", "isa", "leafsize", "leafsize", "bins"};
    for (int i = 0; i < 5; i++) {
        char err[512] = "";
        accel *a = test_build_with(accel_find("bvh"), s, bad[i], 1, err, sizeof err);
        CHECK_MSG(!a && strstr(err, key[i]), "%s: %s", bad[i], a ? "built" : err);
        if (a) a->ops->destroy(a);
    }
    for (int isa = 0; isa < WIDE_ISA_COUNT; isa++) {
        char cfg[64], err[512] = "";
        snprintf(cfg, sizeof cfg, "isa=%s", wide_isa_names[isa]);
        accel *a = test_build_with(accel_find("bvh"), s, cfg, 1, err, sizeof err);
        if (wide_isa_supported((wide_isa)isa)) CHECK_MSG(a != NULL, "%s: %s", cfg, err);
        else CHECK_MSG(!a && strstr(err, "lacks") && !strchr(err, '\n'), "%s refused: %s", cfg, err);
        if (!a) printf("refused as it should: %s\n", err);
        if (a) a->ops->destroy(a);
    }
    /* isa=auto settles to the best ISA, which build() then runs. */
    accel_params p;
    params_defaults(&p, accel_find("bvh")->params);
    accel_settle_params(accel_find("bvh"), &p);
    CHECK(!strcmp(params_get(&p, "isa"), wide_isa_names[wide_isa_best()]));
    accel *a = champ_with(s, "");
    wide_isa got;
    bvh_wide_tree(a, &got);
    CHECK(got == wide_isa_best());
    a->ops->destroy(a);
    printf("isa=auto settles to %s\n", params_get(&p, "isa"));
    /* At width=2 every SIMD ISA runs the SSE4.2 kernel, and says so. */
    if (wide_isa_supported(WIDE_ISA_SSE42)) {
        params_defaults(&p, accel_find("bvh")->params);
        char perr[256];
        CHECK(params_set(&p, "width", "2", perr, sizeof perr) == 0);
        accel_settle_params(accel_find("bvh"), &p);
        CHECK_MSG(!strcmp(params_get(&p, "isa"), "sse42"), "width=2 settles isa to %s", params_get(&p, "isa"));
        a = champ_with(s, "width=2");
        bvh_wide_tree(a, &got);
        CHECK(got == WIDE_ISA_SSE42);
        a->ops->destroy(a);
    }
    /* fma=on refused where the SSE4.2 kernel runs; fma=auto settles to what build() runs. */
    const char *no_fma[] = {"fma=on,isa=sse42", "fma=on,width=2"};
    for (int i = 0; i < 2 && wide_isa_supported(WIDE_ISA_SSE42); i++) {
        char err[512] = "";
        a = test_build_with(accel_find("bvh"), s, no_fma[i], 1, err, sizeof err);
        CHECK_MSG(!a && strstr(err, "fma=on") && strstr(err, "SSE4.2") && !strchr(err, '\n'), "%s: %s", no_fma[i],
                  a ? "built" : err);
        if (a) a->ops->destroy(a);
    }
    params_defaults(&p, accel_find("bvh")->params);
    accel_settle_params(accel_find("bvh"), &p);
    const wide_isa best = wide_isa_best();
    CHECK_MSG(!strcmp(params_get(&p, "fma"), best == WIDE_ISA_AVX2 || best == WIDE_ISA_AVX512 ? "on" : "off"),
              "fma=auto settles to %s under isa=%s", params_get(&p, "fma"), wide_isa_names[best]);
    char ferr[256];
    CHECK(params_set(&p, "isa", "scalar", ferr, sizeof ferr) == 0 && params_set(&p, "fma", "auto", ferr, sizeof ferr) == 0);
    accel_settle_params(accel_find("bvh"), &p);
    CHECK_MSG(!strcmp(params_get(&p, "fma"), "off"), "fma=auto settles to %s under isa=scalar", params_get(&p, "fma"));
    /* smallbins: on by default, settled to off under split=sbvh, which bins every node into `bins`. */
    params_defaults(&p, accel_find("bvh")->params);
    accel_settle_params(accel_find("bvh"), &p);
    CHECK(!strcmp(params_get(&p, "smallbins"), "on"));
    char serr[256];
    CHECK(params_set(&p, "split", "sbvh", serr, sizeof serr) == 0);
    accel_settle_params(accel_find("bvh"), &p);
    CHECK_MSG(!strcmp(params_get(&p, "smallbins"), "off"), "split=sbvh settles smallbins to %s", params_get(&p, "smallbins"));
    scene_free(s);
}

/* order=octant: answers as exhaustive's on the bunny; wide_check sees a
 * node's octant order swapped or made to repeat a slot. */
static void test_octant(void)
{
    scene_t *s = test_scene("bunny");
    against_exhaustive(s, "order=octant", EXHAUSTIVE_RES, true);
    accel *a = champ_with(s, "order=octant,width=8");
    wide_bvh *w = (wide_bvh *)bvh_wide_tree(a, NULL);
    const prims_t *p = &s->prims;
    char err[256];
    uint32_t *order = (uint32_t *)((char *)w->nodes + WIDE_ORDER_OFFSET(8)), keep = order[1];
    order[1] = (keep & ~077u) | (keep & 07) << 3 | (keep >> 3 & 07); /* positions 0 and 1 swapped */
    CHECK_MSG(keep == order[1] || wide_check(w, p->bounds, p->count, err, sizeof err) != 0, "a swapped order passes");
    printf("swapped octant order: %s\n", err);
    order[1] = (keep & ~07u) | (keep >> 3 & 07); /* position 0 repeats position 1's slot */
    CHECK_MSG(wide_check(w, p->bounds, p->count, err, sizeof err) != 0, "a repeated slot passes");
    printf("repeated slot: %s\n", err);
    order[1] = keep;
    CHECK(wide_check(w, p->bounds, p->count, err, sizeof err) == 0);
    a->ops->destroy(a);
    scene_free(s);
}

/* Primitives below slot k of node ni (interior: its slots' sum). */
static uint64_t slot_prims(const wide_bvh *w, uint32_t ni, uint32_t k)
{
    const char *nd = (const char *)w->nodes + (size_t)ni * WIDE_NODE_BYTES(w->width);
    uint32_t ch = WIDE_CHILD(nd, w->width)[k];
    if (ch & WIDE_LEAF) return WIDE_COUNT(nd, w->width)[k];
    const char *c = (const char *)w->nodes + (size_t)ch * WIDE_NODE_BYTES(w->width);
    uint64_t sum = 0;
    for (uint32_t j = 0; j < WIDE_NCHILDREN(c, w->width); j++) sum += slot_prims(w, ch, j);
    return sum;
}

/* tree=embree, and Embree's leaf, slot and binning rules (its bins span
 * the centroids' bounds) in our own builder, which
 * on the bunny make a tree of Embree's shape (measured 4766 nodes and 19518
 * leaves against Embree's 4772 and 19480). */
static void test_embree_rules(void)
{
    scene_t *s = test_scene("bunny");
    static const char *const rules = "minleaf=4,bigleaf=28,travcost=4,slots=size,binrange=centroids";
    against_exhaustive(s, "tree=embree", EXHAUSTIVE_RES, true);
    against_exhaustive(s, rules, EXHAUSTIVE_RES, true);
    accel *e = champ_with(s, "tree=embree"), *a = champ_with(s, rules), *plain = champ_with(s, "minleaf=4,travcost=4");
    const wide_bvh *we = bvh_wide_tree(e, NULL), *wa = bvh_wide_tree(a, NULL), *wp = bvh_wide_tree(plain, NULL);
    CHECK_MSG(fabs((double)wa->nnodes / we->nnodes - 1.0) < 0.02 && fabs((double)wa->nleaves / we->nleaves - 1.0) < 0.02,
              "Embree's rules: %u nodes, %u leaves; Embree's tree %u, %u", wa->nnodes, wa->nleaves, we->nnodes,
              we->nleaves);
    printf("bunny: Embree's rules %u nodes %u leaves, Embree's tree %u nodes %u leaves, without bigleaf %u nodes %u leaves\n",
           wa->nnodes, wa->nleaves, we->nnodes, we->nleaves, wp->nnodes, wp->nleaves);
    /* The merge made leaves above leafsize (4), none above bigleaf; without
     * it there are none above 4. Every node's slots by subtree size. */
    uint32_t big = 0, biggest = 0, plain_big = 0, unsorted = 0;
    for (uint32_t i = 0; i < wa->nnodes; i++) {
        const char *nd = (const char *)wa->nodes + (size_t)i * WIDE_NODE_BYTES(8);
        for (uint32_t k = 0; k < WIDE_NCHILDREN(nd, 8); k++) {
            uint32_t cnt = WIDE_COUNT(nd, 8)[k];
            big += cnt > 4;
            if (cnt > biggest) biggest = cnt;
            if (k && slot_prims(wa, i, k - 1) < slot_prims(wa, i, k)) unsorted++;
        }
    }
    for (uint32_t i = 0; i < wp->nnodes; i++) {
        const char *nd = (const char *)wp->nodes + (size_t)i * WIDE_NODE_BYTES(8);
        for (uint32_t k = 0; k < WIDE_NCHILDREN(nd, 8); k++) plain_big += WIDE_COUNT(nd, 8)[k] > 4;
    }
    CHECK_MSG(big > 0 && biggest <= 28 && plain_big == 0, "leaves over 4: %u (largest %u), without bigleaf %u", big,
              biggest, plain_big);
    CHECK_MSG(unsorted == 0, "slots=size: %u slots after a smaller one", unsorted);
    a->ops->destroy(a);
    e->ops->destroy(e);
    plain->ops->destroy(plain);
    const char *bad[] = {"tree=embree,width=4", "tree=embree,split=sbvh", "bigleaf=256", "slots=depth"};
    const char *key[] = {"tree=embree", "tree=embree", "bigleaf", "slots"};
    for (int i = 0; i < 4; i++) {
        char err[512] = "";
        accel *r = test_build_with(accel_find("bvh"), s, bad[i], 1, err, sizeof err);
        CHECK_MSG(!r && strstr(err, key[i]) && !strchr(err, '\n'), "%s: %s", bad[i], r ? "built" : err);
        if (r) r->ops->destroy(r);
    }
    scene_free(s);
}

/* The box test is conservative under both arithmetics (wide_walk.h): a box
 * around a point the exact ray passes, thin (its planes the floats next
 * to the point, computed in double with room for the double's rounding)
 * or flat on an axis along which the ray does not move (its planes the
 * origin's coordinate), is always hit, and the empty slots beside it
 * never; rays from 1e-3 to 1e6 in scale, with components of 1e-30, +0
 * and -0, tnear 0 or not, tfar finite or not. */
static void test_box_conservative(void)
{
    uint64_t seed = 777;
    uint32_t missed[2] = {0, 0}, empty_hit = 0, n = 0;
    for (int trial = 0; trial < 300000; trial++) {
        double u[8];
        for (int i = 0; i < 8; i++) {
            seed = seed * 6364136223846793005ull + 1442695040888963407ull;
            u[i] = (double)(seed >> 11) * 0x1p-53; /* [0, 1) */
        }
        const float scale = powf(10.0f, (float)(trial % 10) - 3.0f);
        float o[3], d[3];
        for (int ax = 0; ax < 3; ax++) {
            o[ax] = scale * (float)(2.0 * u[ax] - 1.0);
            d[ax] = (float)(2.0 * u[3 + ax] - 1.0);
            const int kind = (trial / 10 + ax * 7) % 13; /* some components +0, -0 or tiny */
            if (kind == 0) d[ax] = 0.0f;
            if (kind == 1) d[ax] = -0.0f;
            if (kind == 2) d[ax] = d[ax] < 0 ? -1e-30f : 1e-30f;
        }
        if (d[0] == 0.0f && d[1] == 0.0f && d[2] == 0.0f) d[0] = 1.0f;
        const float tnear = trial % 3 ? 0.0f : (float)u[6] * scale, t = tnear + (float)u[7] * 4.0f * scale;
        ray_t r = {v3(o[0], o[1], o[2]), tnear, v3(d[0], d[1], d[2]), trial % 2 ? INFINITY : t * 1.5f + 1.0f,
                   RAY_NO_LIGHT, 0};
        if (!ray_traceable(&r)) continue;
        float lo[3], hi[3];
        for (int ax = 0; ax < 3; ax++) {
            const double x = (double)o[ax] + (double)t * (double)d[ax]; /* the exact point, to the double's rounding */
            const double room = fabs(x) * 0x1p-50 + fabs((double)t * (double)d[ax]) * 0x1p-50;
            lo[ax] = float_down(x - room);
            hi[ax] = float_up(x + room);
        }
        const box3 b = {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
        for (int fused = 0; fused < 2; fused++) {
            const unsigned m = wide_box_probe(&r, b, fused);
            missed[fused] += !(m & 1);
            empty_hit += (m & ~1u) != 0;
        }
        n++;
    }
    CHECK_MSG(missed[0] == 0 && missed[1] == 0 && empty_hit == 0,
              "%u rays: boxes around their points missed %u (fma=off) and %u (fma=on) times, empty slots hit %u", n,
              missed[0], missed[1], empty_hit);
    printf("box test: %u rays, each hits a thin box around one of its points under fma=off and fma=on\n", n);
}

/* A quantised node of these boxes: every decoded slot contains its box and
 * is at most one scale step (plus the decoding's rounding) larger on each
 * side; 0, or -1 when wide_quantize refuses (err says why). */
static int quantize_boxes(const box3 *box, uint32_t n, char *err, size_t errlen)
{
    wide_bvh w = {0};
    w.width = 8, w.nnodes = 1;
    w.nodes = aligned_alloc(64, sizeof(wide8_node));
    memset(w.nodes, 0, sizeof(wide8_node));
    for (uint32_t k = 0; k < 8; k++)
        wide_set_slot(&w, 0, k, k < n ? box[k] : box_empty(), k < n ? WIDE_LEAF | k : WIDE_EMPTY, k < n);
    WIDE_NCHILDREN(w.nodes, 8) = (uint8_t)n;
    int rc = wide_quantize(&w, err, errlen);
    if (rc == 0) {
        const wide8q_node *q = w.nodes;
        CHECK(w.quantized && q->nchildren == n);
        for (uint32_t k = 0; k < n; k++) {
            box3 d = wide_node_slot_box(&w, 0, k);
            const float lo[3] = {box[k].lo.x, box[k].lo.y, box[k].lo.z}, hi[3] = {box[k].hi.x, box[k].hi.y, box[k].hi.z};
            const float dlo[3] = {d.lo.x, d.lo.y, d.lo.z}, dhi[3] = {d.hi.x, d.hi.y, d.hi.z};
            for (int ax = 0; ax < 3; ax++) {
                double step = wide_q_scale(q->scale_exp[ax]), slack = step + fabs((double)q->origin[ax]) * 0x1p-23;
                CHECK_MSG(dlo[ax] <= lo[ax] && dhi[ax] >= hi[ax], "slot %u axis %d: [%a, %a] decoded as [%a, %a]", k,
                          ax, lo[ax], hi[ax], dlo[ax], dhi[ax]);
                CHECK_MSG(lo[ax] - dlo[ax] <= slack && dhi[ax] - hi[ax] <= slack,
                          "slot %u axis %d: [%a, %a] decoded loosely as [%a, %a] (step %a)", k, ax, lo[ax], hi[ax],
                          dlo[ax], dhi[ax], step);
            }
        }
    }
    wide_free(&w);
    return rc;
}

/* compress=on (accel/bvh_wide/wide_quantize.c): decoded boxes contain the
 * exact ones and stay within a step of them, on random boxes at every
 * scale from 1e-30 to 1e37, on boxes of zero extent and on one node of
 * the 10^6-triangle grid; a node wider than the largest scale reaches is
 * refused with one line; the bunny's answers as exhaustive's and memory
 * 128 bytes a node less than compress=off's; width=4 refused. */
static void test_compress(void)
{
    uint64_t seed = 12345;
    char err[256];
    for (int trial = 0; trial < 4000; trial++) {
        box3 box[8];
        const uint32_t n = 1 + trial % 8;
        const float mag = powf(10.0f, (float)(trial % 68) - 30.0f); /* 1e-30 .. 1e37 */
        for (uint32_t k = 0; k < n; k++) {
            float c[6];
            for (int i = 0; i < 6; i++) {
                seed = seed * 6364136223846793005ull + 1442695040888963407ull;
                c[i] = mag * ((float)(seed >> 40) / (float)(1 << 24) * 2.0f - 1.0f);
            }
            if (trial % 5 == 0) c[1] = c[0]; /* zero extent on x */
            box[k] = (box3){{fminf(c[0], c[1]), fminf(c[2], c[3]), fminf(c[4], c[5])},
                            {fmaxf(c[0], c[1]), fmaxf(c[2], c[3]), fmaxf(c[4], c[5])}};
        }
        CHECK_MSG(quantize_boxes(box, n, err, sizeof err) == 0, "trial %d: %s", trial, err);
    }
    printf("compress: 4000 random nodes, every decoded slot contains its box within a step\n");
    const box3 wide[2] = {{{-3e38f, 0, 0}, {-2e38f, 1, 1}}, {{2e38f, 0, 0}, {3e38f, 1, 1}}};
    err[0] = 0;
    CHECK_MSG(quantize_boxes(wide, 2, err, sizeof err) != 0 && strstr(err, "compress=on") && strstr(err, "on x") &&
                  !strchr(err, '\n'),
              "a node from -3e38 to 3e38 on x: %s", err[0] ? err : "quantised");
    printf("refused as it should: %s\n", err);

    scene_t *s = test_scene("bunny");
    against_exhaustive(s, "compress=on", EXHAUSTIVE_RES, true);
    against_exhaustive(s, "compress=on,split=sbvh,order=octant", 16, true);
    accel *off = champ_with(s, ""), *on = champ_with(s, "compress=on");
    const wide_bvh *woff = bvh_wide_tree(off, NULL), *won = bvh_wide_tree(on, NULL);
    CHECK(won->quantized && !woff->quantized && won->nnodes == woff->nnodes);
    CHECK_MSG(off->ops->memory(off) - on->ops->memory(on) == (size_t)woff->nnodes * 128,
              "memory %zu against %zu over %u nodes", on->ops->memory(on), off->ops->memory(off), woff->nnodes);
    printf("compress=on on the bunny: %zu bytes against %zu (%u nodes of 128 bytes instead of 256)\n",
           on->ops->memory(on), off->ops->memory(off), won->nnodes);
    /* wide_check sees a quantised slot shrunk below what it holds. */
    wide8q_node *root = won->nodes;
    const uint8_t keep = root->q[1][0];
    root->q[1][0] = root->q[0][0]; /* slot 0's upper x plane down to its lower one */
    CHECK_MSG(wide_check(won, s->prims.bounds, s->prims.count, err, sizeof err) != 0, "a shrunk quantised slot passes");
    printf("shrunk quantised slot: %s\n", err);
    root->q[1][0] = keep;
    CHECK(wide_check(won, s->prims.bounds, s->prims.count, err, sizeof err) == 0);
    on->ops->destroy(on);
    off->ops->destroy(off);
    err[0] = 0;
    accel *a = test_build_with(accel_find("bvh"), s, "compress=on,width=4", 1, err, sizeof err);
    CHECK_MSG(!a && strstr(err, "compress=on") && strstr(err, "width=8"), "compress=on,width=4: %s", a ? "built" : err);
    if (a) a->ops->destroy(a);
    scene_free(s);
}

/* robust=off against exhaustive on the bunny: the same answers except at
 * edges. A closest hit agrees when both miss or both hit at distances
 * within a relative 1e-4 (the primitive may then differ: the two sides of
 * an edge), an any hit when the answers are equal; the rest (a ray slipping
 * through an edge, a graze one test sees and the other not) at most 1 in
 * 10^4 rays. robust is on by default and in the params. */
static void test_robust_off(void)
{
    scene_t *s = test_scene("bunny");
    const exhaustive_reference *ref = reference_for(s, EXHAUSTIVE_RES);
    static const char *const cfgs[] = {"robust=off", "robust=off,fma=off", "robust=off,width=4,isa=scalar,fma=on"};
    accel *a[3];
    for (int k = 0; k < 3; k++) a[k] = champ_with(s, cfgs[k]);
    uint64_t rays = 0, exact[3] = {0}, tol[3] = {0}, differ[3] = {0};
    for (int w = 0; w < ref->nsets; w++) {
        const rayset_t *rs = ref->sets[w];
        const answers_t *want = ref->want[w];
        for (int k = 0; k < 3; k++) {
            answers_t *got = test_trace(a[k], rs, 1);
            for (uint32_t i = 0; i < rs->count; i++) {
                if (rs->query == QUERY_ANY) {
                    if (want->occluded[i] == got->occluded[i]) exact[k]++;
                    else differ[k]++;
                    continue;
                }
                const hit_t *x = &want->hits[i], *y = &got->hits[i];
                const bool hx = x->prim != HIT_NONE, hy = y->prim != HIT_NONE;
                if (!hx && !hy) exact[k]++;
                else if (hx != hy) differ[k]++;
                else if (x->prim == y->prim && x->t == y->t) exact[k]++;
                else if (fabsf(x->t - y->t) <= 1e-4f * fmaxf(fabsf(x->t), fabsf(y->t))) tol[k]++;
                else differ[k]++;
            }
            answers_free(got);
        }
        rays += rs->count;
    }
    for (int k = 0; k < 3; k++) {
        CHECK_MSG(differ[k] * 10000 <= rays, "bunny [%s]: %llu of %llu rays differ from exhaustive beyond the tolerance",
                  cfgs[k], (unsigned long long)differ[k], (unsigned long long)rays);
        printf("bunny [%s]: %llu rays, %llu the same, %llu within the tolerance, %llu beyond (edges)\n", cfgs[k],
               (unsigned long long)rays, (unsigned long long)exact[k], (unsigned long long)tol[k],
               (unsigned long long)differ[k]);
        a[k]->ops->destroy(a[k]);
    }
    /* robust=on by default; the params say robust either way. */
    accel_params p;
    params_defaults(&p, accel_find("bvh")->params);
    accel_settle_params(accel_find("bvh"), &p);
    char fmt[1024], perr[256];
    params_format(&p, fmt, sizeof fmt);
    CHECK_MSG(!strcmp(params_get(&p, "robust"), "on") && strstr(fmt, "robust=on"), "defaults: %s", fmt);
    CHECK(params_set(&p, "robust", "off", perr, sizeof perr) == 0);
    accel_settle_params(accel_find("bvh"), &p);
    params_format(&p, fmt, sizeof fmt);
    CHECK_MSG(strstr(fmt, "robust=off") != NULL, "robust=off: %s", fmt);
    scene_free(s);
}

int main(void)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    test_refusals();
    test_single();
    test_overflowing_entry();
    test_box_conservative();
    test_one_point();
    test_simd();
    test_memcap();
    test_threads();
    test_sbvh();
    test_octant();
    test_embree_rules();
    test_compress();
    test_robust_off();
    free_references();
    return check_report();
}
