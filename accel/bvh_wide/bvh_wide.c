/* bvh_wide.c: `bvh`, the wide SIMD BVH: a binned SAH binary tree
 * collapsed to 2, 4 or 8 children a node, traversed nearest child first
 * with all children's boxes tested at once by SSE4.2, AVX2 or AVX-512
 * kernels chosen at run time. Reference: docs/accels/wide-bvh.md.
 *
 * Papers:
 *   - the kit's binned SAH build (accel/bvh/build_sah.c): MacDonald and
 *     Booth, The Visual Computer 6(3), 1990; Wald, IEEE RT 2007 (binning);
 *     leaf costs in whole packets of 4 and the small-node bin rule as
 *     Embree's builder (Wald et al., ACM TOG 33(4), 2014, s4.3); subtrees
 *     built on the harness's threads, the same tree for any thread count
 *     (accel/bvh/build.c: Wald, IEEE TVCG 2012);
 *   - split=sbvh: Stich, Friedrich, Dietrich, HPG 2009, s3 (alpha: s3.2),
 *     accel/bvh/build_sbvh.c, primitives clipped by prims/clip.c;
 *   - wide nodes and the collapse (accel/bvh_wide/collapse.c): Dammertz, Hanika,
 *     Keller, EGSR 2008; Ernst, Greiner, IEEE RT 2008; Wald, Benthin,
 *     Boulos, IEEE RT 2008;
 *   - robust box tests: Ize, JCGT 2(2), 2013 (fma=off), or one fused
 *     multiply-add a plane with directed per-ray constants (fma=on,
 *     accel/bvh_wide/wide_walk.h);
 *   - robust=off: Moller and Trumbore, JGT 2(1), 1997 (the triangle
 *     packets' test, prims/tri_packet_mt.h) and plain box constants, not
 *     watertight, as Embree's default;
 *   - order=octant and compress=on: Ylitie, Karras, Laine, HPG 2017,
 *     s3.2 and s3.1; the per-octant permutation as Fuetterling et al.,
 *     HPG 2017;
 *   - tree=embree: Embree's own builder (rtcBuildBVH), a diagnostic that
 *     splits a gap against Embree into tree and kernel.
 *
 * Pipeline: primitive boxes -> binary tree (object or spatial splits) ->
 * collapse to width W (bigleaf, slots) -> triangle packets (packets=on) ->
 * per-octant orders -> quantisation (compress=on). isa=auto and fma=auto
 * are settled before the CSV writes the parameters (settle_params), so
 * the params column names what ran. A kernel this CPU lacks, fma=on under
 * the SSE4.2 kernel, compress or tree=embree at a width other than 8 are
 * refused with one line.
 *
 * Memory (accel/bvh_wide/wide.h): nodes of 64 (W=2), 128 (W=4), 256 (W=8) or
 * 128 (compressed) bytes, 64-byte aligned, root always interior; refs, 4
 * bytes a reference in leaf order; packets, 160 bytes each, ceil(count/4)
 * per all-triangle leaf. memory() = the object + nodes + refs + packets.
 * Per thread: the stack, 12 bytes an entry, (W - 1)(depth + 1) + 1 + 8
 * entries, which no walk can overflow. Build scratch is freed in build().
 *
 * Invariants: an unused slot holds the empty box, which every ray misses;
 * every kernel computes the scalar kernel's distances bit for bit, so all
 * walk the same way; a box the exact ray meets is never rejected by
 * rounding (also a quantised one, rounded outward; robust=off gives this
 * and watertightness up); with split=sbvh a
 * primitive may be in two leaves and is counted once per leaf that tests
 * it.
 *
 * Counters: box_tests = used child slots of every node visited; steps =
 * nodes visited plus leaves tested; prim_tests and prim_hits by prims/.
 * Statistics: the tree's shape, and the cost model's prediction of
 * box_tests, prim_tests and steps per ray (wide_predict.c: the
 * surface-area argument over uniform random lines).
 * Not implemented: Stich et al.'s reference unsplitting. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../accel.h"
#include "bvh_wide.h"
#include "../common/memcap.h"
#include "../../prims/checked_alloc.h"
#include "../common/big_alloc.h"

static const accel_param champ_params[] = {
    PARAM_ROW_CHOICE("width", "8", "2|4|8", "children per node (2: binary nodes, both children tested together by SSE4.2)"),
    PARAM_ROW_INT("bins", "16", 2, 256, "binned SAH: bins per axis (Wald 2007)"),
    PARAM_ROW_BOOL("smallbins", "on", "split=object: on: a node of n primitives binned into min(bins, 4 + n/20) slots "
                                      "(Embree's rule); off: bins (split=sbvh: always off)"),
    PARAM_ROW_CHOICE("binrange", "node", "node|centroids",
                     "binned SAH: the bins span the node's box (as tinybvh bins) or its centroids' bounds (Wald 2007, "
                     "Embree)"),
    PARAM_ROW_INT("leafsize", "4", 1, 32, "largest leaf the SAH builder may make"),
    PARAM_ROW_INT("minleaf", "0", 0, 32, "a node of at most this many primitives is always a leaf (Embree's minLeafSize)"),
    PARAM_ROW_INT("bigleaf", "0", 0, WIDE_MAX_LEAF,
                  "collapse: an interior node of at most this many primitives becomes one leaf when the SAH prices it "
                  "no higher than its split (Embree's leaves at a wide node's children); 0: off"),
    PARAM_ROW_CHOICE("slots", "split", "split|size", "slot order: split (the binary tree's), size (most primitives first, as Embree orders them)"),
    PARAM_ROW_REAL("travcost", "2", 0.1, 100.0, "SAH: cost of a node visit over one primitive test (bigger: larger leaves)"),
    PARAM_ROW_CHOICE("split", "object", "object|sbvh", "object: binned SAH object splits; sbvh: with spatial splits (Stich et al. 2009)"),
    PARAM_ROW_REAL("alpha", "1e-5", 0.0, 1.0, "sbvh: try a spatial split when the object split's overlap passes alpha x the root's area"),
    PARAM_ROW_CHOICE("binning", "split", "split|clip", "sbvh: straddlers binned by split (Embree's float split, an estimate) or clip (exact, slower)"),
    PARAM_ROW_CHOICE("order", "distance", "distance|octant",
                     "closest hit: children sorted by entry distance, or octant: in the node's order for the ray's "
                     "octant (Ylitie et al. 2017)"),
    PARAM_ROW_BOOL("packets", "on", "on: leaves of triangles only tested as prims/ triangle packets (4 in SoA); off: through refs"),
    PARAM_ROW_CHOICE("isa", "auto", "auto|scalar|sse42|avx2|avx512", "box kernels: auto is the best this CPU has"),
    PARAM_ROW_CHOICE("tree", "own", "own|embree",
                     "own: the builds above; embree: Embree's own builder's 8-wide tree (rtcBuildBVH), our kernels over "
                     "it (a diagnostic: width=8, split=object only)"),
    PARAM_ROW_CHOICE("fma", "auto", "off|on|auto",
                     "box test: on: one fused multiply-add a plane with directed per-ray constants; off: subtract, "
                     "multiply (Ize's scaled far reciprocal); auto: on where the kernels have FMA (AVX2, AVX-512)"),
    PARAM_ROW_BOOL("robust", "on",
                   "on: watertight triangle packets (t refined in double), conservative box tests; off: "
                   "Moller-Trumbore packets and plain box tests, exact only to rounding (Embree's default)"),
    PARAM_ROW_BOOL("compress", "off", "on: 8-wide nodes of 128 bytes, child boxes as 8-bit planes (Ylitie et al. 2017); off: 256, float planes"),
    PARAM_ROW_END,
};

typedef struct {
    accel base;
    const prims_t *p;
    wide_bvh w;
    wide_isa isa;
    const wide_kernels *k;
} champ_t;

struct accel_ctx {
    wide_entry *stack; /* wide_stack_cap(&w) + WIDE_STACK_SLACK entries */
};

/* ---------------------------------------------------------------- build */

static void champ_destroy(accel *a)
{
    champ_t *t = (champ_t *)a;
    if (!t) return;
    wide_free(&t->w);
    free(t);
}

/* The binary build's peak: boxes, the builder's centroids and tasks, its
 * nodes (2n - 1) and refs, bvh_finish's depth stack. */
static uint64_t binary_bytes(uint64_t n)
{
    uint64_t nodes = n ? 2 * n - 1 : 0;
    uint64_t per_prim = sizeof(box3) + sizeof(vec3) + sizeof(uint32_t) + BVH_TOPDOWN_TASK_BYTES;
    return memcap_add(memcap_mul(n + 1, per_prim), memcap_mul(nodes, sizeof(bvh_node) + 2 * sizeof(uint32_t)));
}

/* The collapse's peak: the binary tree still held, the wide nodes, the
 * pending triples and (bigleaf, slots=size) the subtrees' spans with their
 * walk's order and stack (collapse.c). */
static uint64_t collapse_bytes(const bvh_t *b, uint64_t wide_nodes, uint32_t width)
{
    uint64_t bin = memcap_add(memcap_mul(b->nnodes, sizeof(bvh_node) + 3 * sizeof(uint32_t) + 20),
                              memcap_mul(b->nrefs, sizeof(uint32_t)));
    return memcap_add(bin, memcap_mul(wide_nodes, wide_node_bytes(width)));
}

/* fma=auto: on where the kernels that run have FMA instructions. */
static bool fma_by_default(wide_isa running) { return running == WIDE_ISA_AVX2 || running == WIDE_ISA_AVX512; }

/* isa: the choice resolved on this CPU (auto: the best it has). */
static wide_isa isa_of(const accel_params *params)
{
    int choice = params_choice(params, "isa");
    return choice == 0 ? wide_isa_best() : (wide_isa)(choice - 1);
}

/* Rules between the parameters, and the CPU's: compress=on and tree=embree
 * need width=8 (tree=embree also split=object), an isa this CPU has, and
 * fma=on kernels that have fused multiply-add. */
static int champ_check(const accel_params *params, char *err, size_t errlen)
{
    static const char *const names[] = {"auto", "scalar", "sse42", "avx2", "avx512"};
    static const char *const needs[] = {"", "", "SSE4.2", "AVX2 and FMA", "AVX-512F and AVX-512VL"};
    const uint32_t width = 2u << params_choice(params, "width");
    const bool compress = params_bool(params, "compress"), sbvh = params_choice(params, "split") == 1;
    if (compress && width != 8) {
        snprintf(err, errlen, "bvh compress=on: quantised nodes are 8 wide (width=8)");
        return -1;
    }
    if (params_choice(params, "tree") == 1 && (width != 8 || sbvh)) {
        snprintf(err, errlen, "bvh tree=embree: Embree's tree is 8 wide with object splits (width=8, split=object)");
        return -1;
    }
    int choice = params_choice(params, "isa");
    wide_isa isa = isa_of(params);
    if (choice && (!wide_isa_supported(isa) || !wide_kernels_for(isa, 8, false, false, true))) {
        snprintf(err, errlen, "isa=%s: this CPU lacks %s; isa=auto picks the best it has (%s)", names[choice],
                 needs[choice], wide_isa_names[wide_isa_best()]);
        return -1;
    }
    if (params_choice(params, "fma") == 1 && !wide_kernels_for(isa, width, compress, true, true)) {
        snprintf(err, errlen, "bvh fma=on: the SSE4.2 kernels (isa=sse42, and every ISA at width=2) have no fused "
                              "multiply-add");
        return -1;
    }
    return 0;
}

/* sbvh's clip: the part of a primitive inside a box, exactly (prims/clip.c);
 * and its binning estimate of a box's two halves. */
static box3 clip_prim(const void *ctx, uint32_t prim, box3 box) { return prim_clip_bounds(ctx, prim, box); }
static void split_prim(const void *ctx, uint32_t prim, box3 box, int axis, float pos, box3 *left, box3 *right)
{
    prim_split_bounds(ctx, prim, box, axis, pos, left, right);
}

static accel *champ_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    const int wsel = params_choice(params, "width"), by_size = params_choice(params, "slots"),
              embree_tree = params_choice(params, "tree"), sbvh = params_choice(params, "split"),
              exact_bins = params_choice(params, "binning"), octant = params_choice(params, "order"),
              fma = params_choice(params, "fma"), binrange = params_choice(params, "binrange");
    const bool small_bins = params_bool(params, "smallbins"), packets = params_bool(params, "packets"),
               compress = params_bool(params, "compress"), robust = params_bool(params, "robust");
    const long bins = params_int(params, "bins"), leafsize = params_int(params, "leafsize"),
               minleaf = params_int(params, "minleaf"), bigleaf = params_int(params, "bigleaf");
    const double travcost = params_real(params, "travcost"), alpha = params_real(params, "alpha");
    const wide_isa isa = isa_of(params);
    const uint64_t memcap = params_memcap(params, 4096);
    const uint32_t width = 2u << wsel;
    const prims_t *p = &scene->prims;
    const uint32_t n = p->count;
    if (n > WIDE_INDEX) {
        snprintf(err, errlen, "bvh: %u primitives, more than leaf indices reach (%u)", n, WIDE_INDEX);
        return NULL;
    }
    /* sbvh: references up to twice the primitives (bvh_sbvh_config.dup),
     * 32 bytes each while building, and the tree over them; and once more
     * the binary bytes of 2n for the threaded build's subtrees (their
     * references' copies and their trees, within budgets that sum to 2n). */
    const uint64_t sbvh_bytes = memcap_add(memcap_mul(2, binary_bytes(2 * (uint64_t)n)), memcap_mul(2 * (uint64_t)n, 32));
    if (memcap_exceeded(sbvh ? sbvh_bytes : binary_bytes(n),
                        memcap, err, errlen, "bvh: the binary SAH build over %u primitives", n))
        return NULL;

    champ_t *t = calloc(1, sizeof *t);
    box3 *boxes = big_alloc(((size_t)n + 1) * sizeof *boxes);
    bvh_t bin = {0};
    if (!t || !boxes) goto oom;
    t->base.scene = scene;
    t->p = p;
    t->isa = wide_isa_running(isa, width); /* the kernel that runs */
    const bool fused = fma == 2 ? fma_by_default(wide_isa_running(isa, width)) : fma == 1;
    t->k = wide_kernels_for(isa, width, compress, fused, robust);
    if (!t->k) { /* champ_check refused fma=on where no kernel has it */
        snprintf(err, errlen, "bvh: no box kernels for isa=%s at width=%u", wide_isa_names[isa], width);
        goto fail;
    }

    /* The kit's binary tree over the primitives' boxes. */
    for (uint32_t id = 0; id < n; id++) boxes[id] = prim_bounds(p, id);
    if (embree_tree) {
        /* Embree's build primitives (32 bytes) and nodes and leaves (at
         * most one of each per primitive, 272 and 12 bytes), then our
         * nodes (at most one per primitive) and refs. */
        if (memcap_exceeded(memcap_mul(n, 32 + 272 + 12 + WIDE_NODE_BYTES(8) + 4), memcap, err, errlen,
                            "bvh tree=embree: Embree's build over %u primitives", n))
            goto fail;
        if (wide_build_embree(&t->w, boxes, n, params->threads > 0 ? (uint32_t)params->threads : 1, err, errlen))
            goto fail;
        free(boxes);
        boxes = NULL;
        t->w.octant_order = octant;
        goto pack;
    }
    bvh_config cfg;
    bvh_config_defaults(&cfg);
    cfg.bins = (uint32_t)bins;
    /* split=object only: under split=sbvh the fewer bins made more
     * references (bytes per triangle on the bunny 84 instead of 76, on
     * Sponza 92 instead of 87) and no faster build (the spatial bins
     * dominate it). */
    cfg.small_bins = small_bins && !sbvh;
    cfg.bin_node_box = binrange == 0;
    cfg.max_leaf = (uint32_t)leafsize;
    cfg.min_leaf = (uint32_t)minleaf;
    cfg.cost_traversal = (float)travcost;
    /* A scene of triangles only: a leaf costs whole packets (build_sah.c).
     * On the bunny: 67.5 bytes a triangle instead of 89.3, leaves of 3.7
     * triangles instead of 2.8, 2-3 % fewer box tests. Other primitives
     * are tested one by one, so they are counted as such. Not tied to
     * packets=on: packets=off is the same tree with its leaves through
     * refs (test_champion compares the two ray for ray). */
    cfg.leaf_block = p->ntris == n ? PRIM_TRI_LANES : 1;
    /* The subtrees on the harness's threads: the same tree for any count
     * (build.c), so a run's thread count never changes what is traced. */
    cfg.threads = params->threads > 0 ? (uint32_t)params->threads : 1;
    if (sbvh) {
        bvh_sbvh_config sc;
        bvh_sbvh_config_defaults(&sc);
        sc.alpha = alpha, sc.clip = clip_prim, sc.ctx = p;
        if (!exact_bins) sc.split = split_prim;
        if (bvh_build_sbvh(&bin, boxes, n, &cfg, &sc)) goto oom;
    } else if (bvh_build_sah(&bin, boxes, NULL, n, &cfg)) {
        goto oom;
    }
    free(boxes);
    boxes = NULL;

    /* Collapsed to width, its exact size checked first. */
    const wide_merge merge = {(uint32_t)bigleaf, (float)travcost, cfg.leaf_block, by_size};
    wide_plan plan;
    if (wide_plan_collapse(&plan, &bin, width, &merge)) goto oom;
    if (memcap_exceeded(collapse_bytes(&bin, plan.nodes, width), memcap, err, errlen,
                        "bvh: %u BVH%u nodes over %u primitives with the binary tree they come from", plan.nodes,
                        width, n)) {
        wide_plan_free(&plan);
        goto fail;
    }
    int collapsed = wide_collapse(&t->w, &bin, width, &merge, &plan);
    wide_plan_free(&plan);
    if (collapsed) goto oom;
    t->w.spatial = sbvh;
    t->w.octant_order = octant;
    bvh_free(&bin);

pack:
    /* The all-triangle leaves packed, their size checked first. */
    if (packets) {
        uint64_t npk = wide_count_packets(&t->w, p);
        if (memcap_exceeded(memcap_add(wide_memory(&t->w), memcap_mul(npk, sizeof(prim_tri_packet))), memcap,
                            err, errlen, "bvh: %u BVH%u nodes and %llu triangle packets over %u primitives",
                            t->w.nnodes, width, (unsigned long long)npk, n))
            goto fail;
        if (wide_pack_leaves(&t->w, p)) goto oom;
    }
    /* compress=on: the nodes quantised, both arrays held while it runs. */
    if (compress) {
        if (memcap_exceeded(memcap_add(wide_memory(&t->w), memcap_mul(t->w.nnodes, sizeof(wide8q_node))),
                            memcap, err, errlen, "bvh compress=on: %u BVH8 nodes and their quantised copies",
                            t->w.nnodes))
            goto fail;
        if (wide_quantize(&t->w, err, errlen)) goto fail;
    }
    return &t->base;
oom:
    snprintf(err, errlen, "bvh: out of memory building over %u primitives", n);
fail:
    free(boxes);
    bvh_free(&bin);
    champ_destroy(t ? &t->base : NULL);
    return NULL;
}

/* The params say the ISA that runs: isa=auto as build() will resolve it
 * on this CPU, then wide_isa_running's rule (at width=2 every SIMD ISA
 * runs the SSE4.2 kernel, so they say sse42); and smallbins=off under
 * split=sbvh, which ignores it. */
static void champ_settle_params(accel_params *params)
{
    char ignored[256];
    const uint32_t width = 2u << params_choice(params, "width");
    /* split=sbvh bins every node into `bins` (champ_build): say so. */
    if (params_choice(params, "split") == 1) params_set(params, "smallbins", "off", ignored, sizeof ignored);
    /* An ISA this CPU lacks stays, for champ_check to refuse. */
    wide_isa isa = isa_of(params);
    if (!wide_isa_supported(isa)) return;
    wide_isa running = wide_isa_running(isa, width);
    params_set(params, "isa", wide_isa_names[running], ignored, sizeof ignored);
    /* fma=auto: as build() resolves it for the kernels that run */
    if (params_choice(params, "fma") == 2) params_set(params, "fma", fma_by_default(running) ? "on" : "off", ignored, sizeof ignored);
}

/* -------------------------------------------------------------- context */

static accel_ctx *champ_context_new(accel *a)
{
    champ_t *t = (champ_t *)a;
    uint32_t cap = wide_stack_cap(&t->w);
    /* context_new cannot fail through the interface: out of memory is exit 2 (prims/checked_alloc.h) */
    accel_ctx *ctx = checked_calloc(1, sizeof *ctx, "a bvh tracing context");
    ctx->stack = checked_calloc((size_t)cap + WIDE_STACK_SLACK, sizeof *ctx->stack, "a bvh thread's traversal stack");
    return ctx;
}

static void champ_context_free(accel_ctx *ctx)
{
    if (!ctx) return;
    free(ctx->stack);
    free(ctx);
}

/* ---------------------------------------------------------------- trace */

static bool champ_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    const champ_t *t = (const champ_t *)a;
    return t->k->intersect(&t->w, t->p, ctx->stack, ray, hit, c);
}

static bool champ_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    const champ_t *t = (const champ_t *)a;
    return t->k->occluded(&t->w, t->p, ctx->stack, ray, c);
}

static bool champ_intersect_fast(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit)
{
    const champ_t *t = (const champ_t *)a;
    return t->k->intersect_fast(&t->w, t->p, ctx->stack, ray, hit);
}

static bool champ_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *ray)
{
    const champ_t *t = (const champ_t *)a;
    return t->k->occluded_fast(&t->w, t->p, ctx->stack, ray);
}

/* ------------------------------------------------------------ the rest */

static size_t champ_memory(const accel *a)
{
    const champ_t *t = (const champ_t *)a;
    return sizeof *t + wide_memory(&t->w);
}

static int champ_stats(const accel *a, accel_stat *out, int max)
{
    const champ_t *t = (const champ_t *)a;
    return wide_stats(&t->w, t->p->count, out, max);
}

static box3 champ_bounds(const accel *a) { return wide_bounds(&((const champ_t *)a)->w); }

/* For tests (tests/test_champion.c): the tree and the kernels that run. */
const wide_bvh *bvh_wide_tree(const accel *a, wide_isa *isa)
{
    const champ_t *t = (const champ_t *)a;
    if (isa) *isa = t->isa;
    return &t->w;
}

/* Every width with every instruction set this CPU has (the conformance
 * suite cannot skip a variant that this machine refuses, so the list is
 * made at start-up from the CPU), then the leaf, bin, walk and build
 * settings; a setting that names isa=sse42 only where the CPU has it. */
static const char *const champ_settings[] = {
    "width=2,isa=scalar",
    "width=2,isa=sse42",
    "robust=off",
    "leafsize=1,width=4",
    "packets=off",
    "leafsize=16,bins=4",
    "smallbins=off",
    "binrange=centroids",
    "order=octant",
    "order=octant,width=4,isa=scalar",
    "minleaf=4,bigleaf=28,travcost=4,slots=size,binrange=centroids",
    "tree=embree",
    "fma=off",
    "fma=on,isa=scalar",
    "compress=on",
    "compress=on,isa=scalar",
    "compress=on,isa=sse42",
    "compress=on,split=sbvh,order=octant",
    "split=sbvh",
    "split=sbvh,alpha=0,width=4,leafsize=1",
    "split=sbvh,binning=clip,width=2",
};
#define CHAMP_NSETTINGS (sizeof champ_settings / sizeof champ_settings[0])
static const char *champ_variants[2 * WIDE_ISA_COUNT + CHAMP_NSETTINGS + 1];
__attribute__((constructor)) static void champ_fill_variants(void)
{
    static const char *const all[2][WIDE_ISA_COUNT] = {
        {"width=4,isa=scalar", "width=4,isa=sse42", "width=4,isa=avx2", "width=4,isa=avx512"},
        {"width=8,isa=scalar", "width=8,isa=sse42", "width=8,isa=avx2", "width=8,isa=avx512"},
    };
    size_t n = 0;
    for (int w = 0; w < 2; w++)
        for (int i = 0; i < WIDE_ISA_COUNT; i++)
            if (wide_isa_supported((wide_isa)i) && wide_kernels_for((wide_isa)i, 8, false, false, true))
                champ_variants[n++] = all[w][i];
    for (size_t k = 0; k < CHAMP_NSETTINGS; k++)
        if (!strstr(champ_settings[k], "isa=sse42") || wide_isa_supported(WIDE_ISA_SSE42))
            champ_variants[n++] = champ_settings[k];
    champ_variants[n] = NULL;
}

const struct accel_ops accel_bvh = {
    .version = 2,
    .name = "bvh",
    .summary = "wide SIMD BVH: binned SAH tree collapsed to 4 or 8 children, nearest-first traversal, box kernels "
               "by run-time ISA dispatch (scalar, SSE4.2, AVX2, AVX-512)",
    .paper = "MacDonald & Booth 1990; Wald, IEEE RT 2007; Dammertz et al., EGSR 2008; Ernst & Greiner, IEEE RT 2008; "
             "Wald, Benthin, Boulos, IEEE RT 2008; Ylitie, Karras, Laine, HPG 2017 (order=octant, compress=on) and "
             "Fuetterling et al., HPG 2017 (order=octant)",
    .params = champ_params,
    .flags = 0,
    .build = champ_build,
    .context_new = champ_context_new,
    .context_free = champ_context_free,
    .intersect = champ_intersect,
    .occluded = champ_occluded,
    .memory = champ_memory,
    .destroy = champ_destroy,
    .stats = champ_stats,
    .reset = NULL,
    .bounds = champ_bounds,
    .intersect_fast = champ_intersect_fast,
    .occluded_fast = champ_occluded_fast,
    .variants = champ_variants,
    .settle_params = champ_settle_params,
    .check = champ_check,
    .cost = {1, 1, 0},
    .tune = "leafsize=1|2|4|8", /* the largest leaf the SAH may make */
};
