/* test_far: the same object near the origin and far from it.
 *
 * A one-unit sphere of 14,400 triangles (a UV sphere, 120 x 60 quads, the
 * poles' quads degenerate) is placed at the origin and 1e3, 1e5 and 1e7
 * units away. Float coordinates at 1e5 are 1/128 apart and at 1e7 a whole
 * unit apart (there the sphere collapses onto a few lattice points): a
 * structure that subdivides by the object's size alone makes cells and
 * planes narrower than the coordinates can tell apart. Every registered
 * accelerator, with its defaults and the settings that shape its
 * subdivision, must at each offset
 *   - build, in memory within MEM_FACTOR of its build at the origin
 *     (memory(), plus a small allowance for fixed-size tables), and
 *   - answer every workload's rays as exhaustive does on the same float
 *     data: the same hit or miss, t within harness/measure/verify.h's agreement
 *     rule (1e-4 max(1, |t|)), for the accelerators that test through
 *     prims/ (exhaustive's own test); Embree's and CGAL's own tests are
 *     held to verify's classes (no real mismatch).
 * It prints the memory and build time of each build. Every build runs
 * under a memory cap of 1024 MiB (testlib's memcap=1024, as --memcap sets
 * it), so a runaway subdivision is refused with its reason instead of taking the machine's memory. Arguments, when given,
 * name the accelerators to run (all of them otherwise). */
#include <math.h>
#include <time.h>
#include "testlib.h"

#define MEM_FACTOR 4.0
#define MEM_SLACK (256u << 10)

static scene_t *far_sphere(double off)
{
    char name[64];
    snprintf(name, sizeof name, "sphere@%g", off);
    scene_t *s = scene_new(name);
    const int nu = 120, nv = 60;
    const double r = 0.5, cx = off, cy = 0.5 * off, cz = -0.25 * off;
    uint32_t base = s->prims.nverts;
    for (int j = 0; j <= nv; j++)
        for (int i = 0; i < nu; i++) {
            double th = M_PI * j / nv, ph = 2.0 * M_PI * i / nu;
            vec3 p = v3((float)(cx + r * sin(th) * cos(ph)), (float)(cy + r * cos(th)), (float)(cz + r * sin(th) * sin(ph)));
            prims_add_vertex(&s->prims, p);
        }
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            uint32_t a = base + (uint32_t)(j * nu + i), b = base + (uint32_t)(j * nu + (i + 1) % nu);
            uint32_t c = a + (uint32_t)nu, d = b + (uint32_t)nu;
            prims_add_triangle(&s->prims, a, c, b);
            prims_add_triangle(&s->prims, b, c, d);
        }
    test_finish_scene(s);
    return s;
}

/* The settings that shape each builder's subdivision, besides its defaults. */
static const struct { const char *accel, *settings; } extra[] = {
    {"grid", "res=auto"},
    {"grid", "res=cubic:4"},
    {"octree", "maxdepth=20,maxprims=8"},
    {"bsp", "split=sah"},
    {"bsp", "split=sah,perfect=on"},
    {"slabs-kk", "tree=sah"},
    {"raycls", "lazy=off"},
    {"lightbuf", "res=auto"},
    {"bvh", "split=sbvh"},
};

static bool through_prims(const struct accel_ops *ops)
{
    return strcmp(ops->name, "embree") != 0 && strcmp(ops->name, "cgal-aabb") != 0;
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

#define NOFF 4
static const double offsets[NOFF] = {0, 1e3, 1e5, 1e7};

typedef struct {
    scene_t *s;
    accel *ref;
    rayset_t *sets[16];
    answers_t *want[16];
    int nsets;
} far_scene;

/* Rays through prims/ against exhaustive's answers: hit or miss equal, t
 * within verify's agreement rule. Returns how many rays differ. */
static uint32_t strict_differences(const rayset_t *rs, const answers_t *got, const answers_t *want, uint32_t *first)
{
    uint32_t bad = 0;
    for (uint32_t i = 0; i < rs->count; i++) {
        bool same;
        if (rs->query == QUERY_ANY) same = got->occluded[i] == want->occluded[i];
        else {
            const hit_t *g = &got->hits[i], *w = &want->hits[i];
            same = (g->prim == HIT_NONE) == (w->prim == HIT_NONE) &&
                   (w->prim == HIT_NONE || fabsf(g->t - w->t) <= 1e-4f * fmaxf(1.0f, fabsf(w->t)));
        }
        if (!same && !bad++) *first = i;
    }
    return bad;
}

static void check_one(const struct accel_ops *ops, const char *settings, far_scene *fs)
{
    char cfg[256], label[300];
    snprintf(cfg, sizeof cfg, "%s%smemcap=1024", settings, *settings ? "," : "");
    snprintf(label, sizeof label, "%s%s%s%s", ops->name, *settings ? "[" : "", settings, *settings ? "]" : "");
    size_t mem[NOFF] = {0};
    double ms[NOFF] = {0};
    printf("%-44s", label);
    fflush(stdout);
    for (int k = 0; k < NOFF; k++) {
        char err[512] = "";
        double t0 = now_ms();
        accel *a = test_build_with(ops, fs[k].s, cfg, 1, err, sizeof err);
        ms[k] = now_ms() - t0;
        CHECK_MSG(a != NULL, "%s at %g: build failed: %s", label, offsets[k], err);
        if (!a) {
            printf(" | %g: REFUSED", offsets[k]);
            continue;
        }
        mem[k] = a->ops->memory(a);
        printf(" | %g: %8.1f KiB %7.1f ms", offsets[k], mem[k] / 1024.0, ms[k]);
        fflush(stdout);
        if (k > 0 && mem[k] > MEM_FACTOR * mem[0] + MEM_SLACK) {
            CHECK_MSG(false, "%s at %g: %zu bytes, %.1fx the origin's %zu", label, offsets[k], mem[k],
                      (double)mem[k] / (mem[0] ? mem[0] : 1), mem[0]);
            a->ops->destroy(a); /* too big to trace in the suite's time */
            continue;
        }
        for (int r = 0; r < fs[k].nsets; r++) {
            const rayset_t *rs = fs[k].sets[r];
            if ((ops->flags & ACCEL_SHADOW_ONLY) && rs->query != QUERY_ANY) continue;
            answers_t *got = test_trace(a, rs, 1);
            verify_result vr;
            verify_answers(fs[k].s, rs, got, fs[k].want[r], &vr);
            CHECK_MSG(vr.mismatches[MM_REAL] == 0, "%s at %g %s: %llu real mismatches", label, offsets[k], rs->workload,
                      (unsigned long long)vr.mismatches[MM_REAL]);
            if (through_prims(ops)) {
                uint32_t first = 0, bad = strict_differences(rs, got, fs[k].want[r], &first);
                CHECK_MSG(bad == 0, "%s at %g %s: %u of %u rays answer unlike exhaustive (first: ray %u)", label,
                          offsets[k], rs->workload, bad, rs->count, first);
            }
            answers_free(got);
        }
        a->ops->destroy(a);
    }
    printf("\n");
}

int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    far_scene fs[NOFF];
    for (int k = 0; k < NOFF; k++) {
        memset(&fs[k], 0, sizeof fs[k]);
        fs[k].s = far_sphere(offsets[k]);
        fs[k].ref = test_build("exhaustive", fs[k].s, 2);
        workload_opts o = test_wl(24, 24, 2);
        uint64_t hits = 0;
        for (int w = 0; workload_table[w].name && fs[k].nsets < 16; w++) {
            rayset_t *rs = workload_table[w].make(fs[k].s, fs[k].ref, &o);
            fs[k].want[fs[k].nsets] = test_trace(fs[k].ref, rs, 2);
            if (rs->query == QUERY_CLOSEST)
                for (uint32_t i = 0; i < rs->count; i++) hits += fs[k].want[fs[k].nsets]->hits[i].prim != HIT_NONE;
            fs[k].sets[fs[k].nsets++] = rs;
        }
        /* Rays that miss everything prove nothing about the subdivision. */
        CHECK_MSG(hits > 100, "%s: only %llu closest-hit rays hit the object", fs[k].s->name, (unsigned long long)hits);
    }
    for (int i = 0; accel_registry[i]; i++) {
        const struct accel_ops *ops = accel_registry[i];
        bool wanted = argc < 2;
        for (int k = 1; k < argc; k++) wanted |= !strcmp(argv[k], ops->name);
        if (!wanted) continue;
        check_one(ops, "", fs);
        for (size_t e = 0; e < sizeof extra / sizeof extra[0]; e++)
            if (!strcmp(extra[e].accel, ops->name)) check_one(ops, extra[e].settings, fs);
    }
    for (int k = 0; k < NOFF; k++) {
        for (int r = 0; r < fs[k].nsets; r++) {
            rayset_free(fs[k].sets[r]);
            answers_free(fs[k].want[r]);
        }
        fs[k].ref->ops->destroy(fs[k].ref);
        scene_free(fs[k].s);
    }
    return check_report();
}
