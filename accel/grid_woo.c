/* grid_woo.c: uniform grids, raw (`grid`) and with Woo's optimised
 * Snyder-Barr ray boxes (`grid-raybox`). Reference: docs/accels/grids.md.
 *
 * Papers:
 *   A. Woo, "Ray Tracing Polygons using Spatial Subdivision", Graphics
 *     Interface 1992: s3 ray boxes, s4 [Woo90] box check, s5.1-5.3
 *     move-to-front and ray ids, s6 dynamic box and per-voxel box B, s6.2
 *     beta, s7.2 eye at the origin, s7.3 t clipping, s8.2 resolution.
 *   J. Amanatides, A. Woo, Eurographics 1987: the floating-point 3DDDA.
 *   J. Snyder, A. Barr, SIGGRAPH 1987: ray bounding boxes.
 *   Arnaldi, Priol, Bouatouch 1987 (mailboxes) and the Arvo-Kirk survey
 *     (1989) s5.2-5.3: a walk may end only on a hit inside the current voxel.
 *   Havran, Sixta, RTN 12(1) 1999: res=cubic:D.
 *
 * Both accelerators share every line of code and the parameter keys (the
 * table is GRID_PARAM_TABLE, the method tables GRID_OPS at the end); they
 * differ in defaults and one flag:
 *   grid         every Woo switch off. Thread-safe: with mtf on, each
 *                context reorders its own copy of the id array; with mtf or
 *                rayid on, order_dependent() makes the harness trace it on
 *                one thread.
 *   grid-raybox  ray box and every switch Woo keeps. ACCEL_MUTATES:
 *                move-to-front reorders the SHARED lists; reset() sorts
 *                them back to their post-build (id) order.
 *
 * Memory (memory() counts it; ncells = X*Y*Z, cell c = i + X*(j + Y*k)):
 * CSR start[ncells + 1] and ids[nrefs] (uint32), the B boxes and a
 * whole-voxel byte per cell with voxbox=on, eye-relative bounds (24 bytes a
 * primitive) with eyeorigin=on, and X+Y+Z+3 plane floats. Per thread: the
 * mailbox stamps (4 bytes a primitive) and, for grid with mtf, its own ids.
 *
 * Invariants of the walk:
 *   - the next plane's t is (plane - org) * (1/dir) from the stored plane,
 *     never accumulated, so each voxel's [tMin, tMax] is exact to an ulp
 *     and insertion and traversal see the same planes;
 *   - every candidate is tested over [tnear, tHit), so the running hit is
 *     the survey's stored mailbox result, and the walk ends at the first
 *     voxel whose tMax >= tHit: a hit is final only in its own voxel;
 *   - a primitive within pad (about 16 float ulps at the scene's scale) of
 *     a plane is listed on both sides, so stopping one voxel early on a hit
 *     at a plane misses nothing;
 *   - culling (ray box, B, woo90) never stamps the mailbox: only a tested
 *     primitive is marked;
 *   - any-hit queries stop at the first occluder and never move lists.
 *
 * Counters: box_tests = grid clip + B + crossing + woo90/almost-hit slab
 * tests; steps = voxels entered; empty_leaves; mailbox_hits.
 * intersect_fast/occluded_fast are the same walk without counters.
 * Not implemented: Woo s6.3, s7.1, the s7.2 plane-numerator saving (prims/
 * owns the plane test). Building is single-threaded. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "accel.h"
#include "common/coincident.h"
#include "common/mailbox.h"
#include "common/float_res.h"
#include "common/line_model.h"
#include "common/memcap.h"
#include "common/prim_hit.h"
#include "common/slab.h"
#include "grid_woo.h"
#include "../prims/checked_alloc.h"

#define RAYID_WINDOW 64u
#define RES_MAX 100000
#define GRID_MEMCAP_MIB 4096 /* the grid's own cap (params_memcap) */

enum { MTF_OFF = 0, MTF_HIT = 1, MTF_ALMOST = 2 };

/* res: "auto", "cubic:D" with D in (0, 10000], or "NxMxK" with each in
 * 1..RES_MAX. Returns 0 (auto), 1 (cubic, *d set), 2 (NxMxK, res set), or
 * -1 for anything else. */
static int parse_res(const char *rs, double *d, int res[3])
{
    char tail;
    if (strcmp(rs, "auto") == 0) return 0;
    if (strncmp(rs, "cubic:", 6) == 0)
        return sscanf(rs + 6, "%lf%c", d, &tail) == 1 && *d > 0 && *d <= 1e4 ? 1 : -1;
    if (sscanf(rs, "%dx%dx%d%c", &res[0], &res[1], &res[2], &tail) != 3) return -1;
    for (int a = 0; a < 3; a++)
        if (res[a] < 1 || res[a] > RES_MAX) return -1;
    return 2;
}

static int check_res(const char *value)
{
    double d;
    int res[3];
    return parse_res(value, &d, res) < 0 ? -1 : 0;
}

#define STR_(x) #x
#define STR(x) STR_(x)
#define GRID_PARAM_TABLE(RES, RAYBOX, MTF, DYN, VOX, BETA, TCLIP, WOO90)                                             \
    {                                                                                                                \
        PARAM_ROW_STRING("res", RES, "auto, cubic:D with D in (0, 10000], or NxMxK with each in 1.." STR(RES_MAX),    \
                         check_res,                                                                                  \
                         "cells per axis: auto (Woo 1992 s8.2: m = n^(1/3)*density on the longest axis); cubic:D "    \
                         "(cubic voxels, about D x N: Havran-Sixta RTN 12(1)); NxMxK as given"),                      \
        PARAM_ROW_REAL("density", "1.0", 1e-6, 1e6, "multiplies m in res=auto"),                                     \
        PARAM_ROW_CHOICE("insert", "exact", "bbox|exact", "voxel insertion: exact (prim_overlaps_box), bbox (bounds overlap)"), \
        PARAM_ROW_BOOL("mailbox", "on", "Arnaldi mailboxes, per-thread last ray id per primitive"),                   \
        PARAM_ROW_BOOL("raybox", RAYBOX, "Snyder-Barr ray bounding box per voxel vs primitive bounds"),               \
        PARAM_ROW_CHOICE("mtf", MTF, "off|hit|almost", "Woo s5.1-5.2 move-to-front of the voxel list (non-shadow rays)"), \
        PARAM_ROW_BOOL("dynbox", DYN, "Woo s6 dynamic ray box: far end shrinks to the current hit"),                 \
        PARAM_ROW_BOOL("voxbox", VOX, "Woo s6 per-voxel box B of the candidates, tested first"),                     \
        PARAM_ROW_REAL("beta", BETA, -1e6, 1e6,                                                                      \
                       "Woo s6.2 skip crossing tests when t2-t1 > beta*voxel diagonal; <= 0 disables"),              \
        PARAM_ROW_BOOL("eyeorigin", "off", "Woo s7.2 eye-relative ray boxes for rays from the camera"),              \
        PARAM_ROW_BOOL("tclip", TCLIP, "Woo s7.3 primitive tests clipped to t > t1 of the voxel"),                   \
        PARAM_ROW_CHOICE("rayid", "off", "off|twopass", "Woo s5.3 two passes, recently tested (ray id within 64) first"), \
        PARAM_ROW_BOOL("woo90", WOO90, "Woo s4 [Woo90] bounds check before the primitive test (ray segment vs bounds)"), \
        PARAM_ROW_END,                                                                                               \
    }

static const accel_param grid_params[] = GRID_PARAM_TABLE("cubic:20", "off", "off", "off", "off", "0", "off", "off");
static const accel_param grid_raybox_params[] = GRID_PARAM_TABLE("cubic:5", "on", "almost", "on", "on", "0.75", "on", "on");

typedef struct {
    accel base;
    const prims_t *p;
    int n[3];
    uint32_t stride[3];
    uint32_t ncells;
    size_t nrefs;
    uint32_t nonempty; /* cells with at least one candidate */
    uint32_t maxlist;  /* the longest cell list (move-to-front's scratch) */
    float *planes[3]; /* [n[a] + 1], one allocation */
    box3 box;         /* planes[a][0] .. planes[a][n[a]] */
    box3 clip;        /* box grown by pad: the ray's clip box */
    float pad;
    float voxdiag;
    uint32_t *start, *ids;
    box3 *vbox;
    uint8_t *vfull;
    box3 *relb;
    vec3 eye;
    bool exact, mailbox, raybox, dynbox, voxbox, eyeorigin, tclip, rayid, woo90;
    bool shared_mtf; /* grid-raybox: move-to-front on the shared lists */
    int mtf;
    float beta;
} grid_t;

struct accel_ctx {
    mailbox_t mb;  /* ray-id stamps (mailbox or rayid on; else mb.stamp is NULL) */
    uint32_t *ids; /* per-thread list copy (grid with mtf), or NULL */
    uint32_t *moved; /* mtf: 2 maxlist, the positions moved in a voxel and the list being rearranged */
};

static inline vec3 vmin(vec3 a, vec3 b) { return v3(f_min_keep(a.x, b.x), f_min_keep(a.y, b.y), f_min_keep(a.z, b.z)); }
static inline vec3 vmax(vec3 a, vec3 b) { return v3(f_max_keep(a.x, b.x), f_max_keep(a.y, b.y), f_max_keep(a.z, b.z)); }
static inline box3 box_pad(box3 b, float e)
{
    b.lo = v3_sub(b.lo, v3(e, e, e));
    b.hi = v3_add(b.hi, v3(e, e, e));
    return b;
}

void grid_auto_resolution(box3 box, uint64_t n, double density, int res[3])
{
    double s[3] = {0, 0, 0};
    if (!box_is_empty(box)) {
        vec3 e = box_extent(box);
        s[0] = e.x, s[1] = e.y, s[2] = e.z;
    }
    double maxs = fmax(s[0], fmax(s[1], s[2]));
    double m = cbrt((double)n) * density;
    for (int a = 0; a < 3; a++) {
        double r = maxs > 0 ? s[a] / maxs * m : 1.0;
        long v = isfinite(r) ? lround(fmin(r, (double)GRID_AUTO_MAX)) : 1;
        res[a] = v < 1 ? 1 : v > GRID_AUTO_MAX ? GRID_AUTO_MAX : (int)v;
    }
}

void grid_cubic_resolution(box3 box, uint64_t n, double d, int res[3])
{
    double s[3] = {0, 0, 0}, volume = 1;
    int k = 0;
    if (!box_is_empty(box)) {
        vec3 e = box_extent(box);
        s[0] = e.x, s[1] = e.y, s[2] = e.z;
    }
    for (int a = 0; a < 3; a++)
        if (s[a] > 0) volume *= s[a], k++;
    double cells = fmax((double)n * d, 1.0), h = k ? pow(volume / cells, 1.0 / k) : 0;
    for (int a = 0; a < 3; a++) {
        double r = s[a] > 0 && h > 0 ? s[a] / h : 1.0;
        long v = isfinite(r) ? lround(fmin(r, (double)GRID_AUTO_MAX)) : 1;
        res[a] = v < 1 ? 1 : v > GRID_AUTO_MAX ? GRID_AUTO_MAX : (int)v;
    }
}

/* ---------------------------------------------------------------- build */

/* Cells along axis a that the padded voxels covering [lo, hi] touch. */
static void cell_span(const grid_t *g, int a, float lo, float hi, int *i0, int *i1)
{
    const float *pl = g->planes[a];
    int n = g->n[a];
    float inv = (float)n / (pl[n] - pl[0]);
    float f0 = floorf((lo - pl[0]) * inv), f1 = floorf((hi - pl[0]) * inv);
    /* !(f >= 0): a NaN guess too (a denormal extent makes inv infinite and 0 * inf NaN; the fuzzer's binary
     * STL): it starts from cell 0 and the walks below find the cell exactly */
    int a0 = !(f0 >= 0) ? 0 : f0 > (float)(n - 1) ? n - 1 : (int)f0;
    int a1 = !(f1 >= 0) ? 0 : f1 > (float)(n - 1) ? n - 1 : (int)f1;
    while (a0 > 0 && pl[a0] + g->pad >= lo) a0--;
    while (a0 < n - 1 && pl[a0 + 1] + g->pad < lo) a0++;
    while (a1 < n - 1 && pl[a1 + 1] - g->pad <= hi) a1++;
    while (a1 > 0 && pl[a1] - g->pad > hi) a1--;
    *i0 = a0, *i1 = a1 < a0 ? a0 : a1;
}

static inline box3 voxel_box(const grid_t *g, int i, int j, int k)
{
    box3 b = {{g->planes[0][i], g->planes[1][j], g->planes[2][k]},
              {g->planes[0][i + 1], g->planes[1][j + 1], g->planes[2][k + 1]}};
    return b;
}

/* One pass over every (primitive, cell) pair the insertion rule accepts:
 * fill == NULL counts into start[c + 1], else writes ids[start[c]++]. */
static void insert_pass(grid_t *g, uint32_t *fill)
{
    const prims_t *p = g->p;
    for (uint32_t id = 0; id < p->count; id++) {
        box3 b = prim_bounds(p, id);
        if (box_is_empty(b)) continue;
        int lo[3], hi[3];
        for (int a = 0; a < 3; a++) cell_span(g, a, v3_get(b.lo, a), v3_get(b.hi, a), &lo[a], &hi[a]);
        for (int k = lo[2]; k <= hi[2]; k++)
            for (int j = lo[1]; j <= hi[1]; j++)
                for (int i = lo[0]; i <= hi[0]; i++) {
                    box3 v = box_pad(voxel_box(g, i, j, k), g->pad);
                    if (g->exact ? !prim_overlaps_box(p, id, v) : !box_overlap(b, v)) continue;
                    uint32_t c = (uint32_t)i + g->stride[1] * (uint32_t)j + g->stride[2] * (uint32_t)k;
                    if (fill) fill[g->start[c]++] = id;
                    else g->start[c + 1]++;
                }
    }
}

static void grid_destroy(accel *a)
{
    grid_t *g = (grid_t *)a;
    if (!g) return;
    free(g->planes[0]);
    free(g->start);
    free(g->ids);
    free(g->vbox);
    free(g->vfull);
    free(g->relb);
    free(g);
}

static accel *grid_build_common(const scene_t *scene, const accel_params *params, char *err, size_t errlen,
                                bool shared_mtf)
{
    double density = params_real(params, "density"), beta = params_real(params, "beta");
    int exact = params_choice(params, "insert"), mtf = params_choice(params, "mtf"), rayid = params_choice(params, "rayid");
    bool mailbox = params_bool(params, "mailbox"), raybox = params_bool(params, "raybox"),
         dynbox = params_bool(params, "dynbox"), voxbox = params_bool(params, "voxbox"),
         eyeorigin = params_bool(params, "eyeorigin"), tclip = params_bool(params, "tclip"),
         woo90 = params_bool(params, "woo90");
    uint64_t memcap = params_memcap(params, GRID_MEMCAP_MIB);

    const prims_t *p = &scene->prims;
    /* Coincident copies (common/coincident.h) count once in the resolution's
     * n: copies of one triangle share every cell it touches, so cells made
     * for them would only multiply their lists. */
    prim_classes pc;
    if (prim_classes_init(&pc, p)) pc.classes = p->count;
    prim_classes_free(&pc);
    int res[3];
    double cubic_d;
    int form = parse_res(params_string(params, "res"), &cubic_d, res);
    if (form == 0) grid_auto_resolution(p->count ? p->box : box_empty(), pc.classes, density, res);
    else if (form == 1) grid_cubic_resolution(p->count ? p->box : box_empty(), pc.classes, cubic_d, res);

    /* The grid box: the primitives' bounds, flat axes padded. */
    box3 b = p->count && !box_is_empty(p->box) ? p->box : (box3){{-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}};
    vec3 e = box_extent(b);
    float maxe = fmaxf(e.x, fmaxf(e.y, e.z));
    float base = maxe > 0 ? maxe : fmaxf(1.0f, fmaxf(v3_max_abs(b.lo), v3_max_abs(b.hi)));
    for (int a = 0; a < 3; a++) {
        float *lo = a == 0 ? &b.lo.x : a == 1 ? &b.lo.y : &b.lo.z;
        float *hi = a == 0 ? &b.hi.x : a == 1 ? &b.hi.y : &b.hi.z;
        if (*hi - *lo <= 1e-7f * base) *lo -= 1e-3f * base, *hi += 1e-3f * base;
    }
    float pad = 2e-6f * fmaxf(v3_max_abs(b.lo), v3_max_abs(b.hi)) + 1e-6f * box_diagonal(b);
    /* No cell narrower than float coordinates at the box resolve (common/float_res.h): far from the origin the
     * slack would put every primitive in every nearby cell. */
    float min_cell = float_res_min_cell(b, pad);
    for (int a = 0; a < 3; a++) {
        double fit = floor((double)(v3_get(b.hi, a) - v3_get(b.lo, a)) / min_cell);
        if (fit < res[a]) res[a] = fit < 1 ? 1 : (int)fit;
    }

    /* Memory cap, first for the cell arrays (before allocating anything). */
    uint64_t ncells = (uint64_t)res[0] * (uint64_t)res[1] * (uint64_t)res[2];
    uint64_t cell_bytes = (ncells + 1) * 4 + (voxbox ? ncells * (sizeof(box3) + 1) : 0);
    if (memcap_exceeded(cell_bytes, memcap, err, errlen, "res=%dx%dx%d: %llu cells (cell arrays)", res[0],
                        res[1], res[2], (unsigned long long)ncells))
        return NULL;
    if (ncells >= UINT32_MAX) {
        snprintf(err, errlen, "res=%dx%dx%d: %llu cells, more than 32-bit cell indices reach", res[0], res[1], res[2],
                 (unsigned long long)ncells);
        return NULL;
    }

    grid_t *g = calloc(1, sizeof *g);
    if (!g) goto oom;
    g->base.scene = scene;
    g->p = p;
    g->exact = exact, g->mailbox = mailbox, g->raybox = raybox, g->mtf = mtf, g->dynbox = dynbox;
    g->voxbox = voxbox, g->eyeorigin = eyeorigin, g->tclip = tclip, g->rayid = rayid, g->woo90 = woo90;
    g->beta = (float)beta;
    g->shared_mtf = shared_mtf;
    g->eye = scene->camera.from;
    for (int a = 0; a < 3; a++) g->n[a] = res[a];
    g->ncells = (uint32_t)ncells;
    g->stride[0] = 1, g->stride[1] = (uint32_t)res[0], g->stride[2] = (uint32_t)res[0] * (uint32_t)res[1];

    g->planes[0] = malloc(sizeof(float) * ((size_t)res[0] + res[1] + res[2] + 3));
    if (!g->planes[0]) goto oom;
    g->planes[1] = g->planes[0] + res[0] + 1;
    g->planes[2] = g->planes[1] + res[1] + 1;
    float w[3];
    for (int a = 0; a < 3; a++) {
        float lo = v3_get(b.lo, a), hi = v3_get(b.hi, a);
        w[a] = (hi - lo) / (float)res[a];
        for (int i = 0; i < res[a]; i++) g->planes[a][i] = lo + (float)i * w[a];
        g->planes[a][res[a]] = hi;
    }
    vec3 cs = v3(w[0], w[1], w[2]);
    g->box = b;
    g->voxdiag = v3_len(cs);
    g->pad = pad;
    g->clip = box_pad(b, g->pad);

    g->start = calloc(ncells + 1, sizeof *g->start);
    if (!g->start) goto oom;
    if (voxbox) {
        g->vbox = malloc(ncells * sizeof *g->vbox);
        g->vfull = calloc(ncells, 1);
        if (!g->vbox || !g->vfull) goto oom;
    }

    /* Count, check the cap, fill (start[c] runs as the cursor, then is
     * shifted back to the cell's begin). */
    insert_pass(g, NULL);
    uint64_t nrefs = 0;
    for (uint64_t c = 0; c < ncells; c++) {
        g->nonempty += g->start[c + 1] != 0;
        nrefs += g->start[c + 1];
        if (nrefs >= UINT32_MAX) break;
        g->start[c + 1] = (uint32_t)nrefs;
    }
    uint64_t extra_bytes = eyeorigin ? (uint64_t)p->count * sizeof(box3) : 0;
    if (nrefs >= UINT32_MAX) {
        snprintf(err, errlen, "res=%dx%dx%d: more than 2^32 list entries", res[0], res[1], res[2]);
        grid_destroy(&g->base);
        return NULL;
    }
    if (memcap_exceeded(cell_bytes + nrefs * 4 + extra_bytes, memcap, err, errlen,
                        "res=%dx%dx%d: %llu cells and %llu list entries", res[0], res[1], res[2],
                        (unsigned long long)ncells, (unsigned long long)nrefs)) {
        grid_destroy(&g->base);
        return NULL;
    }
    g->nrefs = nrefs;
    g->ids = malloc((nrefs ? nrefs : 1) * sizeof *g->ids);
    if (!g->ids) goto oom;
    insert_pass(g, g->ids);
    for (uint64_t c = ncells; c > 0; c--) g->start[c] = g->start[c - 1];
    g->start[0] = 0;
    for (uint64_t c = 0; c < ncells; c++)
        if (g->start[c + 1] - g->start[c] > g->maxlist) g->maxlist = g->start[c + 1] - g->start[c];

    if (voxbox) {
        for (int k = 0; k < res[2]; k++)
            for (int j = 0; j < res[1]; j++)
                for (int i = 0; i < res[0]; i++) {
                    uint32_t c = (uint32_t)i + g->stride[1] * (uint32_t)j + g->stride[2] * (uint32_t)k;
                    box3 v = box_pad(voxel_box(g, i, j, k), g->pad), u = box_empty();
                    for (uint32_t r = g->start[c]; r < g->start[c + 1]; r++) u = box_union(u, prim_bounds(p, g->ids[r]));
                    u.lo = v3_max(u.lo, v.lo);
                    u.hi = v3_min(u.hi, v.hi);
                    g->vfull[c] = u.lo.x <= v.lo.x && u.lo.y <= v.lo.y && u.lo.z <= v.lo.z && u.hi.x >= v.hi.x &&
                                  u.hi.y >= v.hi.y && u.hi.z >= v.hi.z;
                    g->vbox[c] = box_pad(u, g->pad);
                }
    }
    if (eyeorigin) {
        g->relb = malloc(((size_t)p->count + 1) * sizeof *g->relb);
        if (!g->relb) goto oom;
        for (uint32_t id = 0; id < p->count; id++) {
            box3 r = prim_bounds(p, id);
            r.lo = v3_sub(r.lo, g->eye);
            r.hi = v3_sub(r.hi, g->eye);
            g->relb[id] = box_pad(r, g->pad);
        }
    }
    return &g->base;

oom:
    snprintf(err, errlen, "out of memory building a %dx%dx%d grid", res[0], res[1], res[2]);
    grid_destroy(g ? &g->base : NULL);
    return NULL;
}

static accel *grid_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    return grid_build_common(scene, params, err, errlen, false);
}

static accel *grid_raybox_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    return grid_build_common(scene, params, err, errlen, true);
}

/* -------------------------------------------------------------- context */

static accel_ctx *grid_context_new(accel *a)
{
    grid_t *g = (grid_t *)a;
    /* context_new cannot fail through the interface: out of memory is exit 2 (prims/checked_alloc.h) */
    accel_ctx *ctx = checked_calloc(1, sizeof *ctx, "a grid tracing context");
    if ((g->mailbox || g->rayid) && mailbox_init(&ctx->mb, g->p->count))
        checked_alloc_failed((uint64_t)g->p->count * sizeof(uint32_t), "a grid thread's mailboxes");
    if (g->mtf != MTF_OFF && !g->shared_mtf) {
        ctx->ids = checked_calloc(g->nrefs ? g->nrefs : 1, sizeof *ctx->ids, "a grid thread's move-to-front lists");
        memcpy(ctx->ids, g->ids, g->nrefs * sizeof *ctx->ids);
    }
    if (g->mtf != MTF_OFF)
        ctx->moved = checked_calloc(2 * (size_t)g->maxlist + 1, sizeof *ctx->moved, "a grid thread's move-to-front scratch");
    return ctx;
}

static void grid_context_free(accel_ctx *ctx)
{
    if (!ctx) return;
    mailbox_free(&ctx->mb);
    free(ctx->ids);
    free(ctx->moved);
    free(ctx);
}

/* ---------------------------------------------------------------- trace */

/* What the walk knows about its ray. The slab test (accel/common/slab.h)
 * is the kit's plain one: the grid pads its boxes and t ranges by its own
 * slack instead of scaling t (see Slack above). */
typedef struct {
    slab_ray sr; /* origin and reciprocal direction per axis */
    float d[3];  /* direction per axis: its sign steps the 3DDDA */
    vec3 org, dir;
    float pad; /* position slack */
    float dt;  /* t slack */
    float thr; /* beta threshold in t units (INFINITY: never skip) */
    bool eye;  /* origin == camera.from and eyeorigin on */
} rinfo;

/* The Snyder-Barr ray box of [t1, t2], padded; eye-relative when r->eye. */
static inline box3 ray_box(const rinfo *r, float t1, float t2)
{
    vec3 p1, p2;
    if (r->eye) {
        p1 = v3_scale(r->dir, t1);
        p2 = v3_scale(r->dir, t2);
    } else {
        p1 = v3_madd(r->org, r->dir, t1);
        p2 = v3_madd(r->org, r->dir, t2);
    }
    box3 b = {vmin(p1, p2), vmax(p1, p2)};
    return box_pad(b, r->pad);
}

/* woo90 / almost-hit: does the segment [t1, t2] pass through the bounds? */
static inline bool seg_in_bounds(const rinfo *r, box3 b, float t1, float t2)
{
    b = box_pad(b, r->pad);
    float a = t1 - r->dt, z = t2 + r->dt;
    return slab_clip(&r->sr, &b, &a, &z);
}

static inline void move_front(uint32_t *ids, uint32_t b, uint32_t k)
{
    uint32_t id = ids[k];
    memmove(&ids[b + 1], &ids[b], (size_t)(k - b) * sizeof *ids);
    ids[b] = id;
}

/* Move-to-front of position k, deferred when there is scratch: moved[]
 * collects the positions (ascending, as the walk meets them) and
 * apply_moves rearranges the list once at the end of the voxel. The walk
 * reads only positions after the last move, which a move does not shift,
 * so deferring changes nothing it sees, and the list ends exactly as the
 * moves one by one leave it; one by one, though, n copies of a triangle
 * that all "almost hit" shift the list n times, O(n^2) a ray. */
static inline void mtf_move(uint32_t *ids, uint32_t b, uint32_t k, uint32_t *moved, uint32_t *nmoved)
{
    if (moved) moved[(*nmoved)++] = k;
    else move_front(ids, b, k);
}

/* The list [b, e) after moving to the front, in turn, the entries at the
 * positions moved[0..n): the last moved first, then the others in order. */
static void apply_moves(uint32_t *ids, uint32_t b, uint32_t e, const uint32_t *moved, uint32_t n, uint32_t *tmp)
{
    uint32_t j = 0, m = 0;
    for (uint32_t i = n; i > 0; i--) tmp[j++] = ids[moved[i - 1]];
    for (uint32_t k = b; k < e; k++) {
        if (m < n && moved[m] == k) m++;
        else tmp[j++] = ids[k];
    }
    memcpy(&ids[b], tmp, (size_t)(e - b) * sizeof *ids);
}


/* The walk, ONE source for all four methods: shadow (any hit) and counting
 * are compile-time constants at the call sites, so the counting-free
 * methods are this body with every counter write compiled out and exactly
 * the same arithmetic (the same answers, bit for bit). */
static inline __attribute__((always_inline)) bool walk(grid_t *g, accel_ctx *ctx, const ray_t *ray, hit_t *hit,
                                                       counters_t *c, const bool shadow, const bool counting)
{
    if (!g->nrefs) return false;
    const prims_t *p = g->p;
    rinfo r;
    /* A ray no primitive can hit (NaN, infinite, zero direction) misses
     * here, before the 3DDDA would turn a NaN into a cell index. */
    if (!slab_ray_init(&r.sr, ray->org, ray->dir)) return false;
    r.org = ray->org, r.dir = ray->dir;
    r.d[0] = ray->dir.x, r.d[1] = ray->dir.y, r.d[2] = ray->dir.z;

    /* Counted locally (prim_intersect may write *c, so the compiler could
     * not keep them in registers) and added to *c at the end. */
    uint64_t nbox = 1, nsteps = 0, nempty = 0, nmbox = 0; /* the grid clip is a box test */
    float t0 = ray->tnear, t1 = ray->tfar;
    if (!slab_clip(&r.sr, &g->clip, &t0, &t1)) {
        if (counting) c->box_tests++;
        return false;
    }
    bool occluded = false;

    r.pad = g->pad + 1e-6f * v3_max_abs(ray->org);
    r.dt = r.pad / v3_max_abs(ray->dir);
    r.thr = g->beta > 0 ? g->beta * g->voxdiag / v3_len(ray->dir) : INFINITY;
    r.eye = g->eyeorigin && g->raybox && ray->org.x == g->eye.x && ray->org.y == g->eye.y && ray->org.z == g->eye.z;

    /* Ray id for mailboxes and rayid. The walk reads the stamps through a
     * local copy of the mailbox: its address never escapes, so the stamp
     * pointer stays in a register across the calls into prims/ (through
     * ctx it would be reloaded after each). */
    mailbox_t mbox, *mb = NULL;
    uint32_t rid = 0;
    if (ctx && ctx->mb.stamp) {
        rid = mailbox_next_ray(&ctx->mb);
        mbox = ctx->mb;
        mb = &mbox;
    }
    uint32_t *ids = ctx && ctx->ids ? ctx->ids : g->ids;
    /* Deferred move-to-front (one pass only: rayid's second pass reads the
     * list as the first pass's moves left it). */
    uint32_t *moved = !shadow && g->mtf != MTF_OFF && !g->rayid && ctx ? ctx->moved : NULL, nmoved = 0;

    /* Entry voxel and the next plane per axis. */
    int idx[3], step[3];
    float tn[3];
    uint32_t cell = 0;
    for (int a = 0; a < 3; a++) {
        const float *pl = g->planes[a];
        int n = g->n[a];
        float o = r.sr.org[a], pa = r.d[a] == 0.0f ? o : o + r.d[a] * t0;
        float f = floorf((pa - pl[0]) * ((float)n / (pl[n] - pl[0])));
        int i = !(f >= 0) ? 0 : f > (float)(n - 1) ? n - 1 : (int)f; /* NaN: 0, as in cell_span */
        while (i > 0 && pa < pl[i]) i--;
        while (i < n - 1 && pa >= pl[i + 1]) i++;
        idx[a] = i;
        if (r.d[a] > 0) step[a] = 1, tn[a] = (pl[i + 1] - o) * r.sr.inv[a];
        else if (r.d[a] < 0) step[a] = -1, tn[a] = (pl[i] - o) * r.sr.inv[a];
        else step[a] = 0, tn[a] = INFINITY;
        cell += (uint32_t)i * g->stride[a];
    }

    ray_t rr = *ray; /* the ray the primitive tests see (tclip raises tnear) */
    const int npass = g->rayid ? 2 : 1;
    float tcur = t0;
    for (;;) {
        int ax = tn[0] < tn[1] ? (tn[0] < tn[2] ? 0 : 2) : (tn[1] < tn[2] ? 1 : 2);
        float tout = f_min_keep(tn[ax], t1);
        if (tout < tcur) tout = tcur;
        nsteps++;
        uint32_t b = g->start[cell], e = g->start[cell + 1];
        if (b == e) {
            nempty++;
            goto next;
        }
        float v1 = tcur, v2 = tout;
        if (g->voxbox && !g->vfull[cell]) {
            nbox++;
            if (!slab_clip(&r.sr, &g->vbox[cell], &v1, &v2)) goto next;
        }
        if (g->tclip) rr.tnear = f_max_keep(ray->tnear, v1 - (r.dt + 1e-6f * fabsf(v1)));
        float vh = !shadow && g->dynbox ? f_min_keep(v2, hit->t) : v2; /* far end of the ray box */
        bool cross = false;
        box3 rb;
        if (g->raybox && vh - v1 <= r.thr) cross = true, rb = ray_box(&r, v1, vh);
        const box3 *bounds = r.eye ? g->relb : p->bounds;

        for (int pass = 0; pass < npass; pass++)
            for (uint32_t k = b; k < e; k++) {
                uint32_t id = ids[k];
                if (mb) {
                    uint32_t st = mailbox_stamp(mb, id);
                    if (npass == 2) {
                        bool recent = st != 0 && rid - st < RAYID_WINDOW;
                        if (pass == 0 ? !recent : recent) continue;
                    }
                    if (g->mailbox && st == rid) {
                        nmbox++;
                        continue;
                    }
                }
                if (cross) {
                    nbox++;
                    if (!box_overlap(rb, bounds[id])) continue;
                }
                float segf = !shadow ? f_min_keep(v2, hit->t) : v2;
                if (g->woo90) {
                    nbox++;
                    if (!seg_in_bounds(&r, p->bounds[id], v1, segf)) continue;
                }
                if (mb) mailbox_mark(mb, id, rid);
                if (shadow) {
                    if (prim_test_any(p, id, &rr, c, counting)) {
                        occluded = true;
                        goto out;
                    }
                    continue;
                }
                if (prim_test_closest(p, id, &rr, hit, c, counting)) {
                    if (g->dynbox && g->raybox) {
                        vh = f_min_keep(v2, hit->t);
                        if (vh - v1 <= r.thr) cross = true, rb = ray_box(&r, v1, vh);
                    }
                    if (g->mtf != MTF_OFF) mtf_move(ids, b, k, moved, &nmoved);
                } else if (g->mtf == MTF_ALMOST) {
                    bool almost = g->woo90;
                    if (!almost) {
                        nbox++;
                        almost = seg_in_bounds(&r, p->bounds[id], v1, segf);
                    }
                    if (almost) mtf_move(ids, b, k, moved, &nmoved);
                }
            }
        if (nmoved) {
            apply_moves(ids, b, e, moved, nmoved, moved + g->maxlist);
            nmoved = 0;
        }
    next:
        if (!shadow && hit->t <= tout) break;
        if (tn[ax] >= t1) break;
        idx[ax] += step[ax];
        if ((unsigned)idx[ax] >= (unsigned)g->n[ax]) break;
        cell = step[ax] > 0 ? cell + g->stride[ax] : cell - g->stride[ax];
        tcur = tout;
        tn[ax] = (g->planes[ax][idx[ax] + (step[ax] > 0)] - r.sr.org[ax]) * r.sr.inv[ax];
    }
out:
    if (counting)
        counters_add(c, &(counters_t){.box_tests = nbox, .steps = nsteps, .empty_leaves = nempty, .mailbox_hits = nmbox});
    return shadow ? occluded : hit->prim != HIT_NONE;
}

static bool grid_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    return walk((grid_t *)a, ctx, ray, hit, c, false, true);
}

static bool grid_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    return walk((grid_t *)a, ctx, ray, NULL, c, true, true);
}

static bool grid_intersect_fast(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit)
{
    return walk((grid_t *)a, ctx, ray, hit, NULL, false, false);
}

static bool grid_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *ray)
{
    return walk((grid_t *)a, ctx, ray, NULL, NULL, true, false);
}

static size_t grid_memory(const accel *a)
{
    const grid_t *g = (const grid_t *)a;
    size_t m = sizeof *g + ((size_t)g->ncells + 1) * 4 + g->nrefs * 4;
    m += sizeof(float) * ((size_t)g->n[0] + g->n[1] + g->n[2] + 3);
    if (g->vbox) m += (size_t)g->ncells * (sizeof(box3) + 1);
    if (g->relb) m += (size_t)g->p->count * sizeof(box3);
    return m;
}

/* ---------------------------------------------------------------- debug */

void grid_debug_dims(const accel *a, int res[3])
{
    const grid_t *g = (const grid_t *)a;
    for (int k = 0; k < 3; k++) res[k] = g->n[k];
}

const uint32_t *grid_debug_cell(const accel *a, int i, int j, int k, uint32_t *count)
{
    const grid_t *g = (const grid_t *)a;
    uint32_t c = (uint32_t)i + g->stride[1] * (uint32_t)j + g->stride[2] * (uint32_t)k;
    *count = g->start[c + 1] - g->start[c];
    return g->ids + g->start[c];
}

uint64_t grid_debug_list_hash(const accel *a)
{
    const grid_t *g = (const grid_t *)a;
    uint64_t h = 1469598103934665603ull;
    for (size_t r = 0; r < g->nrefs; r++) {
        h ^= g->ids[r];
        h *= 1099511628211ull;
    }
    return h;
}

/* ------------------------------------------------------- version 2 */

/* The random-line model (common/line_model.h) over every cell: voxels
 * entered, the candidates each line meets (list entries, once per line with
 * mailboxes) and the one clip test of the grid's box; without culling the
 * candidates are the primitive tests. The checks that cull (Woo's B per
 * voxel, the ray box, woo90, almost-hit) follow the same argument as far as
 * it goes: a line that meets a voxel meets its B with probability
 * A(B) / A(voxel), so the candidates checked are the entries of the voxels
 * whose B the line meets; woo90 tests a candidate only when the line meets
 * its bounds, so the primitive tests are at most the sum over primitives of
 * P(the line meets its bounds) (once per line with mailboxes: a tested
 * primitive is marked). The ray box's own share is not stated: each checked
 * candidate counts one crossing test (nearly every segment in a voxel is
 * shorter than the beta threshold at 0.75: the mean chord of a cube is 0.38
 * of its diagonal), one woo90 test and, with mtf=almost without woo90, one
 * almost-hit test, so with the ray box the box tests are an upper bound and
 * so are the primitive tests without woo90 (a culled candidate is not
 * marked, the next voxel checks it again). Returns the rows written. */
static int grid_predict(const grid_t *g, accel_stat *out)
{
    line_model m;
    if (line_model_init(&m, g->box, g->p->count, g->mailbox) != 0) return 0;
    double bchecks = 0.0, checked = 0.0; /* sum of P(C) over the voxels whose B is tested; of P(B) count(C) */
    for (int k = 0; k < g->n[2]; k++)
        for (int j = 0; j < g->n[1]; j++)
            for (int i = 0; i < g->n[0]; i++) {
                box3 cell = {v3(g->planes[0][i], g->planes[1][j], g->planes[2][k]),
                             v3(g->planes[0][i + 1], g->planes[1][j + 1], g->planes[2][k + 1])};
                uint32_t c = (uint32_t)i + g->stride[1] * (uint32_t)j + g->stride[2] * (uint32_t)k;
                uint32_t count = g->start[c + 1] - g->start[c];
                line_model_cell(&m, cell, 0, g->ids + g->start[c], count);
                if (!count) continue;
                const bool btest = g->voxbox && !g->vfull[c];
                if (btest) bchecks += line_model_prob(&m, cell);
                checked += count * line_model_prob(&m, btest ? box_meet(g->vbox[c], cell) : cell);
            }
    line_prediction pr = line_model_result(&m);
    double tests = pr.tests;
    if (g->woo90) {
        double met = 0.0;
        for (uint32_t id = 0; id < g->p->count; id++) met += line_model_prob(&m, box_meet(prim_bounds(g->p, id), g->box));
        if (met < tests) tests = met;
    } else if (g->voxbox && checked < tests) {
        tests = checked;
    }
    line_model_free(&m);
    const int per_candidate = g->raybox + g->woo90 + (g->mtf == MTF_ALMOST && !g->woo90);
    out[0] = (accel_stat){"predicted_steps_per_ray", pr.cells};
    out[1] = (accel_stat){"predicted_tests_per_ray", tests};
    out[2] = (accel_stat){"predicted_box_tests_per_ray", 1.0 + bchecks + per_candidate * checked};
    return 3;
}

static int grid_stats(const accel *a, accel_stat *out, int max)
{
    const grid_t *g = (const grid_t *)a;
    uint32_t count = g->p->count;
    accel_stat all[11] = {
        {"nodes", (double)g->ncells},
        {"leaves", (double)g->nonempty},
        {"empty_leaves", (double)(g->ncells - g->nonempty)},
        {"avg_leaf_prims", g->nonempty ? (double)g->nrefs / g->nonempty : 0.0},
        {"refs_per_prim", count ? (double)g->nrefs / count : 0.0},
        {"res_x", g->n[0]},
        {"res_y", g->n[1]},
        {"res_z", g->n[2]},
    };
    int n = 8 + grid_predict(g, all + 8);
    if (n > max) n = max;
    for (int k = 0; k < n; k++) out[k] = all[k];
    return n;
}

static int cmp_id(const void *x, const void *y)
{
    uint32_t a = *(const uint32_t *)x, b = *(const uint32_t *)y;
    return (a > b) - (a < b);
}

/* grid-raybox's move-to-front only permutes each cell's list, and the
 * build writes every list in ascending id order (insert_pass), so sorting
 * each list restores the post-build state exactly, with no copy of it
 * kept. Insertion sort for the short lists (adaptive to the few entries a
 * run moved), qsort for long ones. */
static void grid_reset(accel *a)
{
    grid_t *g = (grid_t *)a;
    if (!g->shared_mtf || g->mtf == MTF_OFF) return;
    for (uint32_t c = 0; c < g->ncells; c++) {
        uint32_t *l = g->ids + g->start[c], n = g->start[c + 1] - g->start[c];
        if (n > 32) {
            qsort(l, n, sizeof *l, cmp_id);
            continue;
        }
        for (uint32_t i = 1; i < n; i++) {
            uint32_t v = l[i], j = i;
            for (; j > 0 && l[j - 1] > v; j--) l[j] = l[j - 1];
            l[j] = v;
        }
    }
}

static box3 grid_bounds(const accel *a) { return ((const grid_t *)a)->box; }

/* rayid's window and `grid`'s per-thread move-to-front lists carry history
 * from ray to ray within a thread: which rays a thread traced before
 * decides the counters (and the tie-breaks), so on 2 threads they varied
 * from run to run. Such a grid is traced on one thread (accel_serial). */
static bool grid_order_dependent(const accel *a)
{
    const grid_t *g = (const grid_t *)a;
    return g->rayid || g->mtf != MTF_OFF;
}

/* The settings the conformance suite runs besides the defaults: the
 * switches that change the walk's logic most, and a small fixed grid
 * (many candidates per cell, primitives crossing many cells); for `grid`
 * also mtf and rayid, which make it order-dependent (traced on one thread,
 * like grid-raybox). */
static const char *const grid_variants[] = {"mailbox=off", "insert=bbox", "voxbox=on,woo90=on,tclip=on", "res=4x4x4",
                                            "mtf=almost,rayid=twopass", "res=auto", NULL};
static const char *const grid_raybox_variants[] = {"mtf=off", "raybox=off", "res=4x4x4",
                                                   "eyeorigin=on,rayid=twopass", NULL};

/* The two tables differ in a few slots only (SQLite's IOMETHODS habit). */
/* What `accelbench tune` searches: Woo's rule and cubic voxels from 5 to 80
 * per primitive (Havran and Sixta found 20 better than 1 on the SPD). */
#define GRID_TUNE "res=auto|cubic:5|cubic:10|cubic:20|cubic:40|cubic:80"

#define GRID_OPS(SYM, NAME, SUMMARY, PAPER, PARAMS, FLAGS, BUILD, RESET, VARIANTS, TRACE_COST, BUILD_COST)          \
    const struct accel_ops SYM = {                                                                                   \
        .version = 2,                                                                                                \
        .name = NAME,                                                                                                \
        .summary = SUMMARY,                                                                                          \
        .paper = PAPER,                                                                                              \
        .params = PARAMS,                                                                                            \
        .flags = FLAGS,                                                                                              \
        .build = BUILD,                                                                                              \
        .context_new = grid_context_new,                                                                             \
        .context_free = grid_context_free,                                                                           \
        .intersect = grid_intersect,                                                                                 \
        .occluded = grid_occluded,                                                                                   \
        .memory = grid_memory,                                                                                       \
        .destroy = grid_destroy,                                                                                     \
        .stats = grid_stats,                                                                                         \
        .reset = RESET,                                                                                              \
        .bounds = grid_bounds,                                                                                       \
        .intersect_fast = grid_intersect_fast,                                                                       \
        .occluded_fast = grid_occluded_fast,                                                                         \
        .variants = VARIANTS,                                                                                        \
        .order_dependent = grid_order_dependent,                                                                     \
        .cost = {TRACE_COST, BUILD_COST, 0},                                                                         \
        .tune = GRID_TUNE,                                                                                           \
    }

GRID_OPS(accel_grid, "grid", "uniform grid, Amanatides-Woo 3DDDA, mailboxes, no ray boxes (Woo switches available, off)",
         "Amanatides & Woo, Eurographics 1987; Arvo & Kirk 1989 survey s5.2-5.3; grid size Woo GI 1992 s8.2",
         grid_params, 0, grid_build, NULL, grid_variants, 2, 1);

/* ACCEL_MUTATES: move-to-front reorders the shared lists; reset sorts them back. */
GRID_OPS(accel_grid_raybox, "grid-raybox",
         "uniform grid with Snyder-Barr ray boxes and Woo's 1992 optimisations (move-to-front mutates)",
         "Woo, Ray Tracing Polygons using Spatial Subdivision, GI 1992, s4-s8; Snyder & Barr 1987", grid_raybox_params,
         ACCEL_MUTATES, grid_raybox_build, grid_reset, grid_raybox_variants, 3, 1);
