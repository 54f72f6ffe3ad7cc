/* test_accels: the conformance suite over the registry.
 *
 * Every registered accelerator, with its defaults and with every variant
 * its table declares (accel_ops.variants), runs the same fixed suite; a new
 * accelerator is under test by its registry line alone.
 *
 * Scenes, made here:
 *   closed     a subdivided icosahedron and a cube, indexed (shared edges
 *              and vertices), with rays aimed exactly at every vertex and
 *              every edge midpoint: none may slip through
 *   planes     axis-aligned quads lying in the planes 0, 1/4, 1/2, 3/4, 1 of
 *              each axis (voxel and split planes of power-of-two grids and
 *              median splits), with axis-aligned rays whose other direction
 *              components are +0 and -0, some starting in those planes
 *   coincident duplicate triangles and coplanar quads triangulated both ways
 *   degenerate zero-area triangles (collinear, repeated vertex) and needles
 *   tiny       a dense cluster 1e-3 across inside a box 2e4 across
 * plus spd:balls:1 (true spheres and a polygon) and spd:tree:2 (cones).
 * On each: all five workloads and the special rays above, checked against
 * Embree by verify (no real mismatch), 1 and 2 threads bit-identical
 * (answers and counters), the counting-free methods giving the counting
 * ones' answers, reset() giving a first trace's counters again, memory()
 * positive and unchanged by tracing (once reset: a lazily built structure
 * grows while tracing), statistics with registered names.
 *
 * And every parameter table (check_table): each row has help, a kind, a
 * default that parses; a value outside each range or choice list is
 * refused with a line naming it; every variant parses and passes check();
 * build() reads every key (getter calls counted per key), so a row no
 * build uses fails.
 *
 * Rays that are not traceable (NaN or infinite components, components
 * beyond 2^60, a zero direction, tnear > tfar) are answered "miss" by the
 * harness and never reach an accelerator (prims/ray.h ray_traceable,
 * harness/workloads/trace.c): checked here for every accelerator through
 * trace_rayset.
 *
 * Watertightness is asserted for the accelerators that test through prims/
 * (watertight triangles); Embree (non-robust mode), CGAL's AABB tree
 * (double-precision tests) and any variant with robust=off (bvh's
 * Moller-Trumbore packets) are not watertight: their slips through shared
 * edges are printed, and verify classifies them (edge or refwrong), but do
 * not fail the suite. */
#include <string.h>
#include "testlib.h"

/* ------------------------------------------------------------ scenes */

static uint32_t vtx(scene_t *s, double x, double y, double z) { return prims_add_vertex(&s->prims, v3((float)x, (float)y, (float)z)); }

static void quad(scene_t *s, vec3 o, vec3 u, vec3 v, bool other_diagonal)
{
    uint32_t a = prims_add_vertex(&s->prims, o), b = prims_add_vertex(&s->prims, v3_add(o, u));
    uint32_t c = prims_add_vertex(&s->prims, v3_add(v3_add(o, u), v)), d = prims_add_vertex(&s->prims, v3_add(o, v));
    if (other_diagonal) {
        prims_add_triangle(&s->prims, a, b, d);
        prims_add_triangle(&s->prims, b, c, d);
    } else {
        prims_add_triangle(&s->prims, a, b, c);
        prims_add_triangle(&s->prims, a, c, d);
    }
}

/* An icosahedron subdivided twice onto the unit sphere at c (320
 * triangles), indexed so that neighbours share vertices exactly. */
static void icosphere(scene_t *s, vec3 c, float r)
{
    const double t = (1.0 + sqrt(5.0)) / 2.0;
    double v[162][3] = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                        {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    int f[320][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                     {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4},   {3, 4, 2},  {3, 2, 6},   {3, 6, 8},
                     {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},  {9, 8, 1}};
    int nv = 12, nf = 20;
    for (int level = 0; level < 2; level++) {
        int mids[162][162];
        memset(mids, -1, sizeof mids);
        int g[320][3], ng = 0;
        for (int i = 0; i < nf; i++) {
            int m[3];
            for (int e = 0; e < 3; e++) {
                int a = f[i][e], b = f[i][(e + 1) % 3];
                if (mids[a][b] < 0) {
                    for (int k = 0; k < 3; k++) v[nv][k] = 0.5 * (v[a][k] + v[b][k]);
                    mids[a][b] = mids[b][a] = nv++;
                }
                m[e] = mids[a][b];
            }
            int tri[4][3] = {{f[i][0], m[0], m[2]}, {f[i][1], m[1], m[0]}, {f[i][2], m[2], m[1]}, {m[0], m[1], m[2]}};
            memcpy(g[ng], tri, sizeof tri);
            ng += 4;
        }
        memcpy(f, g, sizeof g);
        nf = ng;
    }
    uint32_t base = s->prims.nverts;
    for (int i = 0; i < nv; i++) {
        double len = sqrt(v[i][0] * v[i][0] + v[i][1] * v[i][1] + v[i][2] * v[i][2]);
        vtx(s, c.x + r * v[i][0] / len, c.y + r * v[i][1] / len, c.z + r * v[i][2] / len);
    }
    for (int i = 0; i < nf; i++) prims_add_triangle(&s->prims, base + (uint32_t)f[i][0], base + (uint32_t)f[i][1], base + (uint32_t)f[i][2]);
}

static void cube(scene_t *s, vec3 lo, float size)
{
    uint32_t v[8];
    for (int i = 0; i < 8; i++) v[i] = vtx(s, lo.x + size * (i & 1), lo.y + size * ((i >> 1) & 1), lo.z + size * ((i >> 2) & 1));
    static const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (int k = 0; k < 6; k++) {
        prims_add_triangle(&s->prims, v[faces[k][0]], v[faces[k][1]], v[faces[k][2]]);
        prims_add_triangle(&s->prims, v[faces[k][0]], v[faces[k][2]], v[faces[k][3]]);
    }
}

static void fill_closed(scene_t *s)
{
    icosphere(s, v3(0, 0, 0), 1.0f);
    cube(s, v3(2.0f, -0.5f, -0.5f), 1.0f);
}

static void fill_planes(scene_t *s)
{
    for (int axis = 0; axis < 3; axis++)
        for (int k = 0; k <= 4; k++) {
            float c[3] = {0, 0, 0}, u[3] = {0, 0, 0}, w[3] = {0, 0, 0};
            c[axis] = 0.25f * (float)k;
            u[(axis + 1) % 3] = 0.5f;
            w[(axis + 2) % 3] = 0.5f;
            c[(axis + 1) % 3] = 0.125f * (float)(k % 3);
            c[(axis + 2) % 3] = 0.125f * (float)((k + 1) % 3);
            quad(s, v3(c[0], c[1], c[2]), v3(u[0], u[1], u[2]), v3(w[0], w[1], w[2]), k & 1);
        }
}

static void fill_coincident(scene_t *s)
{
    uint32_t a = vtx(s, 0, 0, 0), b = vtx(s, 1, 0, 0), c = vtx(s, 0, 1, 0);
    prims_add_triangle(&s->prims, a, b, c);
    prims_add_triangle(&s->prims, a, b, c); /* the same triangle twice */
    prims_add_triangle(&s->prims, c, b, a); /* and wound the other way */
    quad(s, v3(0, 0, 0.5f), v3(1, 0, 0), v3(0, 1, 0), false);
    quad(s, v3(0, 0, 0.5f), v3(1, 0, 0), v3(0, 1, 0), true); /* coplanar, other diagonal */
    quad(s, v3(0.25f, 0.25f, 0.5f), v3(0.5f, 0, 0), v3(0, 0.5f, 0), false); /* overlapping part */
    cube(s, v3(-1, -1, -1), 0.5f);
}

static void fill_degenerate(scene_t *s)
{
    for (int k = 0; k < 8; k++) {
        double x = 0.3 * k;
        prims_add_triangle(&s->prims, vtx(s, x, 0, 0), vtx(s, x + 0.1, 0.1, 0), vtx(s, x + 0.2, 0.2, 0)); /* collinear */
        uint32_t p = vtx(s, x, 1, 0);
        prims_add_triangle(&s->prims, p, p, vtx(s, x + 0.1, 1.2, 0)); /* repeated vertex */
        prims_add_triangle(&s->prims, vtx(s, x, -1, 0), vtx(s, x + 1e-6, -1, 0), vtx(s, x + 0.05, 0.5, 0.3)); /* needle */
        prims_add_triangle(&s->prims, vtx(s, x, 0.5, -0.2), vtx(s, x + 0.01, 0.5, -0.2), vtx(s, x + 0.005, 0.5, 1.0)); /* sliver */
    }
    quad(s, v3(-0.5f, -1.5f, -0.5f), v3(3.0f, 0, 0), v3(0, 0, 1.5f), false); /* a floor, so the rays hit something */
}

static void fill_tiny(scene_t *s)
{
    uint64_t st = 12345;
    for (int k = 0; k < 400; k++) {
        double p[9];
        for (int i = 0; i < 9; i++) {
            st = st * 6364136223846793005ull + 1442695040888963407ull;
            p[i] = 1e-3 * (double)(st >> 11) / 9007199254740992.0;
        }
        prims_add_triangle(&s->prims, vtx(s, p[0], p[1], p[2]), vtx(s, p[3], p[4], p[5]), vtx(s, p[6], p[7], p[8]));
    }
    prims_add_triangle(&s->prims, vtx(s, -1e4, -1e4, -1e4), vtx(s, -1e4 + 1, -1e4, -1e4), vtx(s, -1e4, -1e4 + 1, -1e4));
    prims_add_triangle(&s->prims, vtx(s, 1e4, 1e4, 1e4), vtx(s, 1e4 - 1, 1e4, 1e4), vtx(s, 1e4, 1e4 - 1, 1e4));
}

static scene_t *made_scene(const char *name, void (*fill)(scene_t *))
{
    scene_t *s = scene_new(name);
    fill(s);
    char err[256];
    if (scene_finish(s, false, err, sizeof err)) {
        fprintf(stderr, "%s: %s\n", name, err);
        exit(2);
    }
    return s;
}

/* The tiny cluster is invisible from the default camera, which frames the
 * huge box: look at it from close by. */
static void look_at_cluster(scene_t *s)
{
    s->camera.from = v3(2e-3f, 1.5e-3f, 3e-3f);
    s->camera.at = v3(5e-4f, 5e-4f, 5e-4f);
    s->camera.up = v3(0, 1, 0);
    s->camera.fov_deg = 40.0f;
    s->camera.hither = 0.0f;
}

/* ------------------------------------------------------- special rays */

static void push(rayset_t *rs, vec3 org, vec3 dir, float tnear, float tfar)
{
    ray_t r = {org, tnear, dir, tfar, RAY_NO_LIGHT, 0};
    rayset_push(rs, &r, 0);
}

/* Rays from inside each closed convex mesh (the icosphere's centre, the
 * cube's) aimed exactly at every vertex and edge midpoint of its own
 * triangles: a ray leaving a closed surface from inside must cross it, so
 * each must hit, whatever rounding does near the edge. */
static rayset_t *watertight_rays(const scene_t *s)
{
    rayset_t *rs = rayset_new("watertight", s->name, 1, QUERY_CLOSEST);
    const prims_t *p = &s->prims;
    const vec3 centres[2] = {v3(0, 0, 0), v3(2.5f, 0, 0)}; /* fill_closed's */
    for (uint32_t t = 0; t < p->ntris; t++)
        for (int e = 0; e < 3; e++) {
            vec3 a = p->verts[p->tris[t].v[e]], b = p->verts[p->tris[t].v[(e + 1) % 3]];
            vec3 c = centres[a.x > 1.5f];
            vec3 targets[2] = {a, v3_scale(v3_add(a, b), 0.5f)};
            for (int k = 0; k < 2; k++) push(rs, c, v3_sub(targets[k], c), 0.0f, INFINITY); /* t = 1 at the target */
        }
    rayset_seal(rs);
    return rs;
}

/* Axis-aligned rays with +0 and -0 in the other components, from a grid of
 * origins that includes the planes the quads lie in. */
static rayset_t *axis_rays(const scene_t *s)
{
    rayset_t *rs = rayset_new("axis", s->name, 1, QUERY_CLOSEST);
    for (int axis = 0; axis < 3; axis++)
        for (int sign = 0; sign < 2; sign++)
            for (int zeros = 0; zeros < 4; zeros++)
                for (int i = 0; i <= 8; i++)
                    for (int j = 0; j <= 8; j++) {
                        float d[3], o[3];
                        d[axis] = sign ? -1.0f : 1.0f;
                        d[(axis + 1) % 3] = (zeros & 1) ? -0.0f : 0.0f;
                        d[(axis + 2) % 3] = (zeros & 2) ? -0.0f : 0.0f;
                        o[axis] = sign ? 2.0f : -1.0f;
                        o[(axis + 1) % 3] = 0.125f * (float)i;
                        o[(axis + 2) % 3] = 0.125f * (float)j;
                        push(rs, v3(o[0], o[1], o[2]), v3(d[0], d[1], d[2]), 0.0f, INFINITY);
                    }
    rayset_seal(rs);
    return rs;
}

/* Rays no accelerator may see: the harness answers them "miss". */
static rayset_t *untraceable_rays(const scene_t *s, query_kind q, const ray_t *good)
{
    rayset_t *rs = rayset_new("untraceable", s->name, 1, q);
    vec3 c = box_center(s->bounds), at = v3(c.x, c.y, c.z - 10.0f);
    push(rs, v3(NAN, c.y, c.z), v3(0, 0, 1), 0.0f, INFINITY);
    push(rs, at, v3(0, NAN, 1), 0.0f, INFINITY);
    push(rs, v3(INFINITY, c.y, c.z), v3(0, 0, 1), 0.0f, INFINITY);
    push(rs, at, v3(0, -INFINITY, 1), 0.0f, INFINITY);
    push(rs, v3(3e18f, c.y, c.z), v3(0, 0, 1), 0.0f, INFINITY);
    push(rs, at, v3(0, 0, 3e18f), 0.0f, INFINITY);
    push(rs, at, v3(0, 0, 0), 0.0f, INFINITY);
    push(rs, at, v3(0, 0, 1), 5.0f, 1.0f); /* tnear > tfar */
    push(rs, at, v3(0, 0, 1), NAN, INFINITY);
    push(rs, at, v3(0, 0, 1), 0.0f, NAN);
    push(rs, at, v3(0, 0, 1), -1.0f, INFINITY);
    rayset_push(rs, good, 0); /* a good one among them: it hits */
    rayset_seal(rs);
    return rs;
}

/* ------------------------------------------------------------ checks */

static bool same_answers(const answers_t *a, const answers_t *b)
{
    if (a->count != b->count || a->query != b->query) return false;
    if (a->query == QUERY_ANY) return a->count == 0 || memcmp(a->occluded, b->occluded, a->count) == 0;
    for (uint32_t i = 0; i < a->count; i++)
        if (a->hits[i].prim != b->hits[i].prim || memcmp(&a->hits[i].t, &b->hits[i].t, sizeof(float)) != 0) return false;
    return true;
}

static bool same_counters(const counters_t *a, const counters_t *b) { return memcmp(a, b, sizeof *a) == 0; }

/* Trace with the counting-free methods (the timed path), one thread. */
static answers_t *trace_fast(accel *a, const rayset_t *rs)
{
    answers_t *out = answers_new(rs, false);
    trace_rayset_passes(a, rs, 1, 1, TRACE_FAST, out);
    return out;
}

typedef struct {
    const char *label;
    accel *a;
    bool watertight; /* tests through prims/ */
} subject;

/* Wrong answers of peers we do not own, documented rather than hidden:
 * each cell listed here must still show them (see check_set). */
static const struct { const char *label, *scene, *workload, *why; } known_wrong_cells[] = {
    {"cgal-aabb", "tiny", "shadow",
     "Simple_cartesian<double>'s segment/triangle predicate is inexact: 7e4-long shadow segments against "
     "1e-4 triangles give wrong do_intersect answers both ways; kernel=epick (exact predicates) has none"},
    {"cgal-aabb", "tiny", "whitted:shadow", "the same shadow segments as the shadow workload's (see the line above)"},
};

static const char *known_wrong(const char *label, const char *scene, const char *workload)
{
    for (size_t i = 0; i < sizeof known_wrong_cells / sizeof known_wrong_cells[0]; i++)
        if (!strcmp(known_wrong_cells[i].label, label) && !strcmp(known_wrong_cells[i].scene, scene) &&
            !strcmp(known_wrong_cells[i].workload, workload))
            return known_wrong_cells[i].why;
    return NULL;
}

/* One ray set through one subject: every property the suite asks. */
static void check_set(const scene_t *s, const subject *sub, accel *ref, const rayset_t *rs)
{
    accel *a = sub->a;
    if ((a->ops->flags & ACCEL_SHADOW_ONLY) && rs->query != QUERY_ANY) return;
    const char *what = rs->workload;
    int threads = accel_serial(a) ? 1 : 2;
    accel_reset(a);
    size_t mem0 = a->ops->memory(a);
    answers_t *want = test_trace(ref, rs, 1), *one = test_trace(a, rs, 1);
    verify_result vr;
    verify_answers(s, rs, one, want, &vr);
    const char *known = known_wrong(sub->label, s->name, what);
    if (known) {
        /* Asserted, not skipped: when the peer stops being wrong here, the
         * exception must go. */
        CHECK_MSG(vr.mismatches[MM_REAL] > 0, "%s on %s %s: the known wrong answers are gone; drop the exception",
                  sub->label, s->name, what);
        printf("  %s on %s %s: %llu real mismatches, known: %s\n", sub->label, s->name, what,
               (unsigned long long)vr.mismatches[MM_REAL], known);
    } else {
        CHECK_MSG(vr.mismatches[MM_REAL] == 0, "%s on %s %s: %llu real mismatches", sub->label, s->name, what,
                  (unsigned long long)vr.mismatches[MM_REAL]);
    }
    CHECK_MSG(vr.mismatches[MM_UNJUDGED] == 0, "%s on %s %s: %llu unjudged", sub->label, s->name, what,
              (unsigned long long)vr.mismatches[MM_UNJUDGED]);
    if (!accel_serial(a)) {
        answers_t *two = test_trace(a, rs, threads);
        CHECK_MSG(same_answers(one, two) && same_counters(&one->total, &two->total),
                  "%s on %s %s: 1 and 2 threads differ", sub->label, s->name, what);
        answers_free(two);
    }
    if (accel_resets(a)) {
        /* After a reset the structure is as built: the same trace again. */
        accel_reset(a);
        answers_t *again = test_trace(a, rs, 1);
        CHECK_MSG(same_answers(one, again) && same_counters(&one->total, &again->total),
                  "%s on %s %s: a trace after reset() differs from the first", sub->label, s->name, what);
        answers_free(again);
    }
    if (a->ops->version >= 2 && a->ops->intersect_fast && a->ops->occluded_fast) {
        accel_reset(a);
        answers_t *fast = trace_fast(a, rs);
        CHECK_MSG(same_answers(one, fast), "%s on %s %s: the counting-free methods answer differently", sub->label,
                  s->name, what);
        answers_free(fast);
    }
    /* A lazily built structure grows while tracing (memory() is what it
     * holds now); reset() returns it to its post-build size. */
    accel_reset(a);
    CHECK_MSG(a->ops->memory(a) == mem0, "%s on %s %s: memory() changed while tracing (%zu -> %zu)", sub->label, s->name,
              what, mem0, a->ops->memory(a));
    if (!strcmp(what, "watertight")) {
        uint32_t slipped = 0;
        for (uint32_t i = 0; i < rs->count; i++) slipped += one->hits[i].prim == HIT_NONE;
        if (sub->watertight)
            CHECK_MSG(slipped == 0, "%s: %u of %u rays through shared edges and vertices slipped through", sub->label,
                      slipped, rs->count);
        else if (slipped)
            printf("  %s (not watertight by design): %u of %u rays through shared edges and vertices slipped through\n",
                   sub->label, slipped, rs->count);
    }
    if (!strcmp(what, "untraceable")) {
        for (uint32_t i = 0; i + 1 < rs->count; i++)
            CHECK_MSG(rs->query == QUERY_ANY ? !one->occluded[i] : one->hits[i].prim == HIT_NONE,
                      "%s: untraceable ray %u was answered as a hit", sub->label, i);
        uint32_t last = rs->count - 1;
        CHECK_MSG(rs->query == QUERY_ANY ? one->occluded[last] : one->hits[last].prim != HIT_NONE,
                  "%s: the traceable ray among the untraceable ones missed", sub->label);
    }
    answers_free(want);
    answers_free(one);
}

static void check_interface(const subject *sub)
{
    const accel *a = sub->a;
    CHECK_MSG(a->ops->version == ACCEL_OPS_VERSION, "%s: interface version %d, not %d", sub->label, a->ops->version,
              ACCEL_OPS_VERSION);
    CHECK_MSG(a->ops->memory(a) > 0, "%s: memory() is 0", sub->label);
    if (a->ops->stats) {
        accel_stat st[ACCEL_STATS_MAX];
        int n = a->ops->stats(a, st, ACCEL_STATS_MAX);
        CHECK_MSG(n >= 0 && n <= ACCEL_STATS_MAX, "%s: stats() returned %d", sub->label, n);
        for (int i = 0; i < n && i < ACCEL_STATS_MAX; i++) {
            CHECK_MSG(accel_stat_known(a->ops, st[i].name),
                      "%s: statistic '%s' is neither in accel_stat_names[] nor its table's stat_names", sub->label,
                      st[i].name);
            CHECK_MSG(isfinite(st[i].value) && st[i].value >= 0, "%s: statistic %s = %g", sub->label, st[i].name, st[i].value);
        }
        /* Every statistic it declares as its own is one it reports, and is
         * not a shared name (which has its column already). */
        for (const char *const *own = a->ops->stat_names; own && *own; own++) {
            bool reported = false;
            for (int i = 0; i < n && i < ACCEL_STATS_MAX; i++) reported |= !strcmp(st[i].name, *own);
            CHECK_MSG(reported, "%s: declares the statistic %s and does not report it", sub->label, *own);
            for (int k = 0; accel_stat_names[k]; k++)
                CHECK_MSG(strcmp(accel_stat_names[k], *own), "%s: declares the shared statistic %s as its own",
                          sub->label, *own);
        }
    } else {
        CHECK_MSG(!a->ops->stat_names, "%s: declares statistics and has no stats()", sub->label);
    }
    box3 b = accel_bounds(a), sb = a->scene->bounds;
    CHECK_MSG(b.lo.x <= sb.lo.x && b.lo.y <= sb.lo.y && b.lo.z <= sb.lo.z && b.hi.x >= sb.hi.x && b.hi.y >= sb.hi.y &&
                  b.hi.z >= sb.hi.z,
              "%s: bounds() do not contain the scene", sub->label);
}

/* value at row is refused by params_set with one line naming key and value. */
static void expect_refused(const struct accel_ops *ops, const accel_param *row, const char *value)
{
    accel_params p;
    params_defaults(&p, ops->params);
    char err[512] = "", want[200];
    snprintf(want, sizeof want, "%s=%s: must be ", row->name, value);
    CHECK_MSG(params_set(&p, row->name, value, err, sizeof err) != 0 && strstr(err, want) && !strchr(err, '\n'),
              "%s: %s=%s accepted or refused without naming it: %s", ops->name, row->name, value, err);
}

/* The parameter table as data: every row named, helped, of a known kind
 * whose default parses; a value outside each range refused; every variant
 * parses and passes check(); build() reads every key (counted through
 * accel_params.reads on scene s). */
static void check_table(const struct accel_ops *ops, const scene_t *s)
{
    char err[512];
    int nrows = 0;
    for (const accel_param *row = ops->params; row->name; row++, nrows++) {
        CHECK_MSG(*row->name && strchr(row->name, '=') == NULL && strchr(row->name, ',') == NULL, "%s: row name '%s'",
                  ops->name, row->name);
        CHECK_MSG(row->help && *row->help, "%s.%s: no help", ops->name, row->name);
        CHECK_MSG(strcmp(row->name, "memcap"), "%s: memcap is the harness's (accel_params.memcap_mib), not a row",
                  ops->name);
        accel_params p;
        params_defaults(&p, ops->params);
        CHECK_MSG(params_set(&p, row->name, row->default_value, err, sizeof err) == 0, "%s: default %s", ops->name, err);
        char allowed[256] = "";
        params_allowed(row, allowed, sizeof allowed);
        CHECK_MSG(*allowed, "%s.%s: nothing allowed", ops->name, row->name);
        char v[64];
        switch (row->kind) {
        case PARAM_BOOL: expect_refused(ops, row, "maybe"); break;
        case PARAM_INT:
        case PARAM_SIZE:
            CHECK_MSG(row->lo <= row->hi, "%s.%s: empty range", ops->name, row->name);
            snprintf(v, sizeof v, "%.0f", row->lo - 1);
            expect_refused(ops, row, v);
            snprintf(v, sizeof v, "%.0f", row->hi + 1);
            expect_refused(ops, row, v);
            expect_refused(ops, row, "1x");
            break;
        case PARAM_REAL:
            CHECK_MSG(row->lo <= row->hi, "%s.%s: empty range", ops->name, row->name);
            snprintf(v, sizeof v, "%.17g", row->lo - fmax(1, fabs(row->lo)));
            expect_refused(ops, row, v);
            snprintf(v, sizeof v, "%.17g", row->hi + fmax(1, fabs(row->hi)));
            expect_refused(ops, row, v);
            expect_refused(ops, row, "nan");
            break;
        case PARAM_CHOICE:
            CHECK_MSG(row->words && *row->words, "%s.%s: no choices", ops->name, row->name);
            expect_refused(ops, row, "nosuch");
            break;
        case PARAM_STRING:
            CHECK_MSG(row->check && row->words, "%s.%s: a string without its grammar", ops->name, row->name);
            expect_refused(ops, row, "?");
            break;
        default: CHECK_MSG(0, "%s.%s: kind %d", ops->name, row->name, (int)row->kind);
        }
    }
    CHECK_MSG(nrows <= ACCEL_PARAMS_MAX, "%s: %d rows, more than %d", ops->name, nrows, ACCEL_PARAMS_MAX);
    for (const char *const *v = ops->version >= 2 ? ops->variants : NULL; v && *v; v++) {
        accel_params p;
        params_defaults(&p, ops->params);
        CHECK_MSG(params_set_list(&p, *v, err, sizeof err) == 0 && accel_check_params(ops, &p, err, sizeof err) == 0,
                  "%s: variant %s: %s", ops->name, *v, err);
    }
    /* `accelbench tune`'s search: one known key, each value allowed by its
     * row and by check(), the default among them. */
    if (ops->tune) {
        const char *eq = strchr(ops->tune, '=');
        char key[64] = "";
        CHECK_MSG(eq && eq - ops->tune < (long)sizeof key && !strchr(ops->tune, ','), "%s: tune %s: not KEY=V|V",
                  ops->name, ops->tune);
        if (eq && eq - ops->tune < (long)sizeof key) {
            memcpy(key, ops->tune, (size_t)(eq - ops->tune));
            const accel_param *row = ops->params;
            while (row->name && strcmp(row->name, key)) row++;
            CHECK_MSG(row->name != NULL, "%s: tune names no parameter %s", ops->name, key);
            bool has_default = false;
            int nvalues = 0;
            for (const char *v = eq + 1; *v; nvalues++) {
                size_t len = strcspn(v, "|");
                char val[64];
                snprintf(val, sizeof val, "%.*s", (int)len, v);
                accel_params tp;
                params_defaults(&tp, ops->params);
                CHECK_MSG(params_set(&tp, key, val, err, sizeof err) == 0 && accel_check_params(ops, &tp, err, sizeof err) == 0,
                          "%s: tune value %s=%s: %s", ops->name, key, val, err);
                has_default |= row->name && !strcmp(val, row->default_value);
                v += len + (v[len] == '|');
            }
            CHECK_MSG(nvalues >= 2 && has_default, "%s: tune %s: %d values, default %s among them: %s", ops->name,
                      ops->tune, nvalues, row->name ? row->default_value : "?", has_default ? "yes" : "no");
        }
    }
    /* check() runs uncounted, so a key only check() reads is found unused */
    accel_params p;
    params_defaults(&p, ops->params);
    accel_settle_params(ops, &p);
    unsigned reads[ACCEL_PARAMS_MAX] = {0};
    CHECK_MSG(accel_check_params(ops, &p, err, sizeof err) == 0, "%s: defaults refused by check(): %s", ops->name, err);
    p.reads = reads;
    accel *a = ops->build(s, &p, err, sizeof err);
    CHECK_MSG(a != NULL, "%s: defaults on %s: %s", ops->name, s->name, err);
    if (!a) return;
    a->ops = ops, a->scene = s;
    a->ops->destroy(a);
    for (int k = 0; k < p.count; k++)
        CHECK_MSG(reads[k] > 0, "%s: build() never reads its parameter %s", ops->name, p.table[k].name);
}

typedef struct {
    scene_t *s;
    accel *ref;
    rayset_t *sets[16];
    int nsets;
} suite_scene;

static void add_workloads(suite_scene *ss, int res)
{
    workload_opts o = test_wl(res, res, 2);
    for (int w = 0; workload_table[w].name; w++) ss->sets[ss->nsets++] = workload_table[w].make(ss->s, ss->ref, &o);
    /* The first primary ray that hits, as the traceable control ray. */
    const rayset_t *prim = ss->sets[0];
    answers_t *a = test_trace(ss->ref, prim, 1);
    uint32_t i = 0;
    while (i < prim->count && a->hits[i].prim == HIT_NONE) i++;
    if (i == prim->count) {
        fprintf(stderr, "%s: no primary ray hits; the suite would prove nothing\n", ss->s->name);
        exit(2);
    }
    ss->sets[ss->nsets++] = untraceable_rays(ss->s, QUERY_CLOSEST, &prim->rays[i]);
    ss->sets[ss->nsets++] = untraceable_rays(ss->s, QUERY_ANY, &prim->rays[i]);
    answers_free(a);
}

/* Whether settings turn a `robust` parameter off (bvh[robust=off]: not
 * watertight by design, as Embree's default). */
static bool robust_off(const struct accel_ops *ops, const char *settings)
{
    accel_params p;
    char err[256];
    params_defaults(&p, ops->params);
    return params_index(&p, "robust") >= 0 && params_set_list(&p, settings, err, sizeof err) == 0 &&
           !strcmp(params_get(&p, "robust"), "off");
}

/* Whether ops is one the command line asks for: every one when none is
 * named (`test_accels [NAME ...]`). */
static bool wanted(const struct accel_ops *ops, int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (!strcmp(argv[i], ops->name)) return true;
    return argc < 2;
}

int main(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (!accel_find(argv[i])) {
            fprintf(stderr, "test_accels: %s is not registered in this program\n", argv[i]);
            return 2;
        }
    setvbuf(stdout, NULL, _IOLBF, 0);
    suite_scene scenes[8];
    int nscenes = 0;
    struct { const char *name; void (*fill)(scene_t *); } made[] = {
        {"closed", fill_closed}, {"planes", fill_planes}, {"coincident", fill_coincident},
        {"degenerate", fill_degenerate}, {"tiny", fill_tiny},
    };
    for (size_t i = 0; i < sizeof made / sizeof made[0]; i++) {
        suite_scene *ss = &scenes[nscenes++];
        memset(ss, 0, sizeof *ss);
        ss->s = made_scene(made[i].name, made[i].fill);
        if (!strcmp(made[i].name, "tiny")) look_at_cluster(ss->s);
        ss->ref = test_build("embree", ss->s, 2);
        add_workloads(ss, 24);
        if (!strcmp(made[i].name, "closed")) ss->sets[ss->nsets++] = watertight_rays(ss->s);
        if (!strcmp(made[i].name, "planes")) ss->sets[ss->nsets++] = axis_rays(ss->s);
    }
    /* The mountain's glass spheres give every accelerator refracted rays (whitted:refracted). */
    static const char *const spd[] = {"spd:balls:1", "spd:tree:2", "spd:mount:2"};
    for (int i = 0; i < 3; i++) {
        suite_scene *ss = &scenes[nscenes++];
        memset(ss, 0, sizeof *ss);
        ss->s = test_scene(spd[i]);
        ss->ref = test_build("embree", ss->s, 2);
        add_workloads(ss, 24);
    }

    for (int i = 0; accel_registry[i]; i++) {
        const struct accel_ops *ops = accel_registry[i];
        if (!wanted(ops, argc, argv)) continue;
        check_table(ops, scenes[nscenes - 3].s); /* spd:balls:1 */
        /* The defaults, then every variant the table lists (all of them:
         * a variant the suite left out would pass unseen). */
        const char *const *variants = ops->version >= 2 ? ops->variants : NULL;
        int nv = 1;
        for (const char *const *v = variants; v && *v; v++) nv++;
        const char **settings = malloc((size_t)nv * sizeof *settings);
        CHECK(settings != NULL);
        if (!settings) continue;
        settings[0] = "";
        for (int k = 1; k < nv; k++) settings[k] = variants[k - 1];
        for (int k = 0; k < nv; k++) {
            char label[600];
            snprintf(label, sizeof label, "%s%s%s%s", ops->name, *settings[k] ? "[" : "", settings[k], *settings[k] ? "]" : "");
            int before = check_failed;
            for (int si = 0; si < nscenes; si++) {
                suite_scene *ss = &scenes[si];
                char err[512];
                accel *a = test_build_with(ops, ss->s, settings[k], 2, err, sizeof err);
                CHECK_MSG(a != NULL, "%s on %s: build failed: %s", label, ss->s->name, err);
                if (!a) continue;
                subject sub = {label, a, !(ops->flags & ACCEL_NO_COUNTERS) && !robust_off(ops, settings[k])};
                if (si == 0) check_interface(&sub);
                for (int r = 0; r < ss->nsets; r++) check_set(ss->s, &sub, ss->ref, ss->sets[r]);
                a->ops->destroy(a);
            }
            printf("%-40s %s\n", label, check_failed == before ? "conforms" : "FAILS");
        }
        free(settings);
    }
    for (int si = 0; si < nscenes; si++) {
        for (int r = 0; r < scenes[si].nsets; r++) rayset_free(scenes[si].sets[r]);
        scenes[si].ref->ops->destroy(scenes[si].ref);
        scene_free(scenes[si].s);
    }
    return check_report();
}
