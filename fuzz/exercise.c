/* exercise.c: build every accelerator and trace a few rays (exercise.h).
 *
 * $FUZZ_SKIP_ACCELS (comma-separated names) leaves accelerators out, so
 * that a campaign can go on past a crash already reported in one of them;
 * scripts/fuzz.sh never sets it. */
#include "exercise.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../harness/workloads/trace.h"
#include "../harness/workloads/workload.h"

static bool skipped(const char *name)
{
    const char *list = getenv("FUZZ_SKIP_ACCELS");
    size_t n = strlen(name);
    for (const char *p = list; p && *p; p += strcspn(p, ",") + (p[strcspn(p, ",")] != 0))
        if (strncmp(p, name, n) == 0 && (p[n] == ',' || p[n] == 0)) return true;
    return false;
}

/* An answer the harness would index out of bounds with (verify, the
 * workloads and the renderer look the primitive up): stop here, with what
 * it was. Wrong distances are verify's business, not a fuzzer's. */
static void check_hit(const struct accel_ops *ops, const scene_t *s, const ray_t *r, const hit_t *h, bool hit)
{
    bool ok = hit ? h->prim < s->prims.count : h->prim == HIT_NONE;
    if (ok) return;
    fprintf(stderr, "fuzz: %s answered prim %u t %g for a ray with [tnear, tfar] = [%g, %g] (%u primitives, hit %d)\n",
            ops->name, h->prim, h->t, r->tnear, r->tfar, s->prims.count, hit);
    abort();
}

static void trace_set(accel *a, accel_ctx *ctx, const rayset_t *rs)
{
    const struct accel_ops *ops = a->ops;
    bool v2 = ops->version >= 2;
    counters_t c = {0};
    for (uint32_t i = 0; i < rs->count; i++) {
        const ray_t *r = &rs->rays[i];
        if (!ray_traceable(r)) continue; /* the harness answers those itself */
        if (ops->intersect) {
            hit_t h = hit_none(r);
            check_hit(ops, a->scene, r, &h, ops->intersect(a, ctx, r, &h, &c));
            if (v2 && ops->intersect_fast) {
                h = hit_none(r);
                check_hit(ops, a->scene, r, &h, ops->intersect_fast(a, ctx, r, &h));
            }
        }
        (void)ops->occluded(a, ctx, r, &c);
        if (v2 && ops->occluded_fast) (void)ops->occluded_fast(a, ctx, r);
    }
}

void fuzz_cap_memory(accel_params *p)
{
    if (!p->memcap_mib || p->memcap_mib > FUZZ_MEMCAP_MIB) p->memcap_mib = FUZZ_MEMCAP_MIB;
}

void fuzz_accel(const struct accel_ops *ops, const scene_t *s, const accel_params *params, rayset_t *const *sets,
                int nsets)
{
    if (skipped(ops->name)) return;
    accel_params capped;
    if (params) capped = *params;
    else {
        params_defaults(&capped, ops->params);
        capped.threads = 1;
    }
    fuzz_cap_memory(&capped);
    params = &capped;
    char err[512];
    accel *a = accel_build(ops, s, params, err, sizeof err);
    if (!a) return;
    accel_ctx *ctx = ops->context_new ? ops->context_new(a) : NULL;
    for (int k = 0; k < nsets; k++) {
        if (sets[k]) trace_set(a, ctx, sets[k]);
        if (ops->version >= 2 && ops->reset) ops->reset(a);
    }
    accel_stat st[ACCEL_STATS_MAX];
    (void)accel_stats(a, st, ACCEL_STATS_MAX);
    (void)ops->memory(a);
    (void)accel_bounds(a);
    if (ctx) ops->context_free(ctx);
    ops->destroy(a);
}

/* Rays of s's workloads at 4x4; the reference for the secondary ones is
 * exhaustive, the simplest accelerator (NULL sets where it does not build). */
static int make_rays(const scene_t *s, rayset_t **sets)
{
    workload_opts o = {4, 4, 1, false, 2, 7, 1};
    int n = 0;
    char err[512];
    sets[n++] = workload_primary(s, &o);
    sets[n++] = workload_random(s, &o, err, sizeof err);
    const struct accel_ops *ex = accel_find("exhaustive");
    accel_params p;
    params_defaults(&p, ex->params);
    p.threads = 1;
    accel *ref = accel_build(ex, s, &p, err, sizeof err);
    if (!ref) return n;
    for (int w = 0; workload_table[w].name; w++)
        if (strcmp(workload_table[w].name, "primary") && strcmp(workload_table[w].name, "random"))
            sets[n++] = workload_table[w].make(s, ref, &o);
    ref->ops->destroy(ref);
    return n;
}

void fuzz_exercise(const scene_t *s, const rayset_t *extra)
{
    rayset_t *sets[16];
    int n = make_rays(s, sets);
    sets[n++] = (rayset_t *)extra;
    for (int i = 0; accel_registry[i]; i++) fuzz_accel(accel_registry[i], s, NULL, sets, n);
    for (int k = 0; k < n - 1; k++) rayset_free(sets[k]);
}

void fuzz_exercise_one(const scene_t *s, const char *key)
{
    int count = 0;
    while (accel_registry[count]) count++;
    uint64_t h = 0xcbf29ce484222325u;
    for (const char *c = key; *c; c++) h = (h ^ (unsigned char)*c) * 0x100000001b3u;
    rayset_t *sets[16];
    int n = make_rays(s, sets);
    fuzz_accel(accel_registry[h % (uint64_t)count], s, NULL, sets, n);
    for (int k = 0; k < n; k++) rayset_free(sets[k]);
}

const scene_t *fuzz_scene(void)
{
    static scene_t *s;
    if (s) return s;
    s = scene_new("fuzz-scene");
    prims_t *p = &s->prims;
    const vec3 v[] = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {-2, 0, -1}, {0, 0, -1},
                      {0, 1, -1},  {-1, 1, -1}, {-1, 2, -1}, {-2, 2, -1}};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++) prims_add_vertex(p, v[i]);
    prims_add_triangle(p, 0, 1, 2);
    prims_add_triangle(p, 0, 2, 3);
    prims_add_triangle(p, 0, 0, 1); /* degenerate: kept, never hit */
    prims_add_sphere(p, v3(0.5f, 0.5f, 0.5f), 0.25f);
    prims_add_cone(p, v3(-0.5f, -0.5f, 0), 0.2f, v3(-0.5f, -0.5f, 1), 0.05f);
    const uint32_t ell[] = {4, 5, 6, 7, 8, 9}; /* concave */
    prims_add_polygon(p, ell, 6);
    char err[512];
    if (scene_finish(s, false, err, sizeof err) != 0) {
        fprintf(stderr, "fuzz: the fixed scene: %s\n", err);
        abort();
    }
    return s;
}

rayset_t *const *fuzz_scene_rays(int *count)
{
    static rayset_t *sets[16];
    static int n = -1;
    if (n < 0) n = make_rays(fuzz_scene(), sets);
    *count = n;
    return sets;
}

#define SEEN_SLOTS (1u << 16)

bool fuzz_first_time(const char *kind, const char *key)
{
    static uint64_t seen[SEEN_SLOTS];
    static unsigned nseen;
    uint64_t h = 0xcbf29ce484222325u; /* FNV-1a of kind, a separator, key */
    for (const char *c = kind; *c; c++) h = (h ^ (unsigned char)*c) * 0x100000001b3u;
    h = (h ^ 0xff) * 0x100000001b3u;
    for (const char *c = key; *c; c++) h = (h ^ (unsigned char)*c) * 0x100000001b3u;
    h |= 1; /* 0 marks an empty slot */
    if (nseen >= SEEN_SLOTS / 2) {
        memset(seen, 0, sizeof seen);
        nseen = 0;
    }
    unsigned i = (unsigned)h & (SEEN_SLOTS - 1);
    for (; seen[i]; i = (i + 1) & (SEEN_SLOTS - 1))
        if (seen[i] == h) return false;
    seen[i] = h;
    nseen++;
    return true;
}
