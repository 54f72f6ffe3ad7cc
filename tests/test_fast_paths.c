/* test_fast_paths: the counting-free methods and version 2 of the tables
 * this change made (exhaustive, embree, grid, grid-raybox).
 *
 * For each accelerator with its defaults and every declared variant, on
 * every workload of spd:balls:2 and bunny (exhaustive: spd:balls:2 only),
 * intersect_fast/occluded_fast answer exactly what intersect/occluded do,
 * ray for ray and bit for bit (a mutating accelerator is reset before each
 * pass, so both passes start from the same lists); the counting pass does
 * count. grid-raybox's reset() returns its lists to the post-build order
 * (the list hash), after move-to-front has changed them; the grids' stats
 * use registered names and agree with the resolution, their bounds hold
 * the scene. */
#include <string.h>
#include "accel/grid_woo.h"
#include "testlib.h"

/* Build NAME with "k=v,k=v" over its defaults. */
static accel *build_variant(const struct accel_ops *ops, const scene_t *s, const char *cfg)
{
    char err[512];
    accel *a = test_build_with(ops, s, cfg, 1, err, sizeof err);
    if (!a) {
        fprintf(stderr, "build %s [%s] failed: %s\n", ops->name, cfg ? cfg : "", err);
        exit(2);
    }
    return a;
}

/* One pass over the ray set, counting or not; answers into hits/occ. */
static void pass(accel *a, const rayset_t *rs, bool fast, hit_t *hits, uint8_t *occ, counters_t *c)
{
    const struct accel_ops *ops = a->ops;
    if (ops->reset) ops->reset(a);
    accel_ctx *ctx = ops->context_new ? ops->context_new(a) : NULL;
    for (uint32_t i = 0; i < rs->count; i++) {
        const ray_t *r = &rs->rays[i];
        if (rs->query == QUERY_CLOSEST) {
            hits[i] = hit_none(r);
            if (fast) ops->intersect_fast(a, ctx, r, &hits[i]);
            else ops->intersect(a, ctx, r, &hits[i], c);
        } else {
            occ[i] = fast ? ops->occluded_fast(a, ctx, r) : ops->occluded(a, ctx, r, c);
        }
    }
    if (ops->context_free) ops->context_free(ctx);
}

static void check_accel(const struct accel_ops *ops, const scene_t *s, rayset_t **sets, int nsets, const char *cfg)
{
    accel *a = build_variant(ops, s, cfg);
    CHECK_MSG(ops->version == 2 && ops->intersect_fast && ops->occluded_fast, "%s: version %d", ops->name, ops->version);
    int diff = 0;
    uint64_t rays = 0;
    counters_t c = {0};
    for (int k = 0; k < nsets; k++) {
        const rayset_t *rs = sets[k];
        hit_t *h1 = calloc(rs->count + 1, sizeof *h1), *h2 = calloc(rs->count + 1, sizeof *h2);
        uint8_t *o1 = calloc(rs->count + 1, 1), *o2 = calloc(rs->count + 1, 1);
        pass(a, rs, false, h1, o1, &c);
        pass(a, rs, true, h2, o2, NULL);
        for (uint32_t i = 0; i < rs->count; i++)
            diff += rs->query == QUERY_CLOSEST ? memcmp(&h1[i], &h2[i], sizeof h1[i]) != 0 : o1[i] != o2[i];
        rays += rs->count;
        free(h1), free(h2), free(o1), free(o2);
    }
    printf("%-12s %-12s %-30s rays %6llu tests/ray %6.2f: %d fast answers differ\n", s->name, ops->name, cfg ? cfg : "(defaults)",
           (unsigned long long)rays, (double)c.prim_tests / (double)rays, diff);
    CHECK_MSG(diff == 0, "%s %s [%s]: %d fast answers differ", s->name, ops->name, cfg ? cfg : "", diff);
    CHECK_MSG(c.prim_tests > 0 || (ops->flags & ACCEL_NO_COUNTERS), "%s: the counting pass counted nothing", ops->name);
    a->ops->destroy(a);
}

static void check_grid_v2(const scene_t *s, rayset_t *primary)
{
    const char *names[] = {"grid", "grid-raybox"};
    for (int k = 0; k < 2; k++) {
        accel *a = build_variant(accel_find(names[k]), s, NULL);
        accel_stat st[ACCEL_STATS_MAX];
        int n = accel_stats(a, st, ACCEL_STATS_MAX); /* drops (and warns about) unregistered names */
        /* the eight of the grid, then its cost model's three predictions (tests/test_line_model.c checks
         * the values) */
        CHECK_MSG(n == 11, "%s: %d statistics", names[k], n);
        double v[16] = {0};
        const char *want[] = {"nodes", "leaves", "empty_leaves", "avg_leaf_prims", "refs_per_prim", "res_x", "res_y", "res_z"};
        for (int i = 0; i < n && i < 8; i++) {
            CHECK(strcmp(st[i].name, want[i]) == 0);
            v[i] = st[i].value;
        }
        int res[3];
        grid_debug_dims(a, res);
        CHECK(v[5] == res[0] && v[6] == res[1] && v[7] == res[2] && v[0] == (double)res[0] * res[1] * res[2]);
        CHECK(v[1] + v[2] == v[0] && v[1] > 0 && v[3] >= 1.0 && v[4] >= 1.0);
        box3 b = accel_bounds(a);
        CHECK(b.lo.x <= s->bounds.lo.x && b.lo.y <= s->bounds.lo.y && b.lo.z <= s->bounds.lo.z &&
              b.hi.x >= s->bounds.hi.x && b.hi.y >= s->bounds.hi.y && b.hi.z >= s->bounds.hi.z);
        printf("%s %s: %.0f cells (%dx%dx%d), %.0f non-empty, %.2f per non-empty cell, %.2f per primitive\n", s->name,
               names[k], v[0], res[0], res[1], res[2], v[1], v[3], v[4]);
        a->ops->destroy(a);
    }
    /* Move-to-front changes the lists; reset puts them back. */
    accel *a = build_variant(accel_find("grid-raybox"), s, NULL);
    CHECK(a->ops->reset && (a->ops->flags & ACCEL_MUTATES));
    CHECK(accel_find("grid")->reset == NULL);
    uint64_t built = grid_debug_list_hash(a);
    hit_t *h = calloc(primary->count, sizeof *h);
    counters_t c = {0};
    accel_ctx *ctx = a->ops->context_new(a);
    for (uint32_t i = 0; i < primary->count; i++) {
        h[i] = hit_none(&primary->rays[i]);
        a->ops->intersect(a, ctx, &primary->rays[i], &h[i], &c);
    }
    a->ops->context_free(ctx);
    CHECK_MSG(grid_debug_list_hash(a) != built, "move-to-front left the lists as built");
    a->ops->reset(a);
    CHECK_MSG(grid_debug_list_hash(a) == built, "reset did not restore the post-build lists");
    free(h);
    a->ops->destroy(a);
}

static void check_scene(const char *name, bool with_exhaustive)
{
    scene_t *s = test_scene(name);
    accel *ref = test_build("embree", s, 1);
    workload_opts o = test_wl(40, 40, 1);
    rayset_t *sets[16];
    int nsets = 0;
    for (int w = 0; workload_table[w].name; w++) sets[nsets++] = workload_table[w].make(s, ref, &o);
    ref->ops->destroy(ref);
    const char *accels[] = {"exhaustive", "embree", "grid", "grid-raybox"};
    for (int k = with_exhaustive ? 0 : 1; k < 4; k++) {
        const struct accel_ops *ops = accel_find(accels[k]);
        check_accel(ops, s, sets, nsets, NULL);
        for (int v = 0; ops->variants && ops->variants[v]; v++) check_accel(ops, s, sets, nsets, ops->variants[v]);
    }
    check_grid_v2(s, sets[0]);
    for (int i = 0; i < nsets; i++) rayset_free(sets[i]);
    scene_free(s);
}

int main(void)
{
    check_scene("spd:balls:2", true);
    check_scene("bunny", false);
    return check_report();
}
