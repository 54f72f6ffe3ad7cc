/* test_degenerate: builds over coincident primitives.
 *
 * Real meshes carry duplicates (scanned and CAD data repeat faces). A cell
 * whose primitives cannot be split apart must become a leaf, so every
 * builder stays near its usual cost when many primitives coincide. For
 * every registered accelerator (defaults, and the settings in
 * extra_settings that build another way) and three duplicate scenes:
 *
 *   dup1e4     10^4 copies of one triangle
 *   dup1e5     10^5 copies of one triangle
 *   dup10x1e4  10^4 copies of each of 10 triangles
 *
 * against as many distinct small triangles in the same box (distinct1e4,
 * distinct1e5), the build's CPU time, the structure's memory() and the
 * build's peak resident memory stay within DUP_RATIO times the distinct
 * scene's (each with a floor below which noise decides: DUP_TIME_FLOOR_MS,
 * DUP_MEM_FLOOR, DUP_RSS_FLOOR). Answers: on the primary, shadow and random
 * workloads, hit or miss as exhaustive says on every ray, and verify's rule
 * (harness/measure/verify.h: any primitive at the same t, coincident copies being
 * equally right) with no real mismatch.
 *
 * Every build runs in a child process watched by the parent, which kills it
 * once it passes a few times its limits (time or resident memory), so a
 * build that blows up fails here instead of taking the machine. */
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "testlib.h"

#define DUP_RATIO 10.0
#define DUP_TIME_FLOOR_MS 50.0
#define DUP_MEM_FLOOR (1u << 20)       /* memory(), bytes */
#define DUP_RSS_FLOOR (32L << 10)      /* peak resident growth, KiB */
#define DISTINCT_KILL_S 120.0          /* a distinct build is only bounded, never compared */
#define TRACE_KILL_S 120.0             /* the answers' check after a build */

/* Settings besides the defaults whose builders differ (raycls lazy=off
 * holds too, but its distinct 10^5 build alone takes 10 s and 0.5 GB). */
static const struct { const char *name, *settings; } extra_settings[] = {
    {"grid", "insert=bbox"},     {"bsp", "split=sah"},        {"bsp", "split=sah,perfect=on"},
    {"octree", "term=cost"},     {"octree", "insert=glassner"}, {"bvh-gs", "order=given"},
    {"slabs-kk", "tree=gs"},     {"slabs-kk", "tree=sah"},
    {"bvh", "split=sbvh"},       {"bvh", "tree=embree"},      {"lightbuf", "res=auto"},
};

/* ------------------------------------------------------------ scenes */

static uint32_t rng = 2024;
static double urand(void) { return (double)test_urand(&rng); }

static uint32_t vtx(scene_t *s, double x, double y, double z) { return prims_add_vertex(&s->prims, v3((float)x, (float)y, (float)z)); }

/* The duplicated triangle: oblique, so that its box (the unit cube) has volume,
 * and facing scene_finish's automatic camera. */
static const double big_tri[3][3] = {{1, 0, 0}, {0, 1, 0.2}, {0.1, 0.2, 1}};

/* Each copy gets vertices of its own (as a mesh with repeated faces has). */
static void add_copies(scene_t *s, const double t[3][3], uint32_t copies)
{
    for (uint32_t k = 0; k < copies; k++)
        prims_add_triangle(&s->prims, vtx(s, t[0][0], t[0][1], t[0][2]), vtx(s, t[1][0], t[1][1], t[1][2]),
                           vtx(s, t[2][0], t[2][1], t[2][2]));
}

static scene_t *finished(scene_t *s)
{
    test_finish_scene(s);
    return s;
}

static scene_t *dup_scene(const char *name, uint32_t copies)
{
    scene_t *s = scene_new(name);
    add_copies(s, big_tri, copies);
    return finished(s);
}

/* n distinct triangles of side about the box's over cbrt(n), in the
 * duplicated triangle's box (the usual density of a mesh). */
static scene_t *distinct_scene(const char *name, uint32_t n)
{
    scene_t *s = scene_new(name);
    double side = 1.5 / cbrt((double)n);
    for (uint32_t k = 0; k < n; k++) {
        double c[3] = {urand(), urand(), urand()};
        uint32_t v[3];
        for (int i = 0; i < 3; i++)
            v[i] = vtx(s, c[0] + side * (urand() - 0.5), c[1] + side * (urand() - 0.5), c[2] + side * (urand() - 0.5));
        prims_add_triangle(&s->prims, v[0], v[1], v[2]);
    }
    return finished(s);
}

/* Ten triangles about half the box across, copies of each. */
static scene_t *dup10_scene(const char *name, uint32_t copies)
{
    scene_t *s = scene_new(name);
    for (int k = 0; k < 10; k++) {
        double t[3][3], c[3] = {urand(), urand(), urand()};
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) t[i][j] = c[j] + 0.6 * (urand() - 0.5);
        add_copies(s, (const double(*)[3])t, copies);
    }
    return finished(s);
}

/* ------------------------------------------------ one build, watched */

typedef struct {
    int built;            /* 1: built, 0: refused (err says why) */
    double cpu_ms;        /* the build's CPU time, every thread */
    double wall_ms;
    uint64_t mem;         /* memory() */
    long rss_kb;          /* peak resident growth over the build */
    char err[200];
} build_report;

typedef struct {
    int done;
    uint64_t rays, hitmiss, tdiff, real, unjudged;
} check_report_t;

typedef struct {
    rayset_t *sets[3];
    answers_t *want[3];
    int nsets;
} ray_check;

static double now_ms(clockid_t clk)
{
    struct timespec ts;
    clock_gettime(clk, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

static long rss_kb_of(pid_t pid)
{
    char path[64];
    snprintf(path, sizeof path, "/proc/%d/statm", (int)pid);
    FILE *f = fopen(path, "r");
    long size = 0, res = 0;
    if (f) {
        if (fscanf(f, "%ld %ld", &size, &res) != 2) res = 0;
        fclose(f);
    }
    return res * (sysconf(_SC_PAGESIZE) / 1024);
}

static void write_all(int fd, const void *p, size_t n)
{
    while (n) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) _exit(3);
        p = (const char *)p + w;
        n -= (size_t)w;
    }
}

/* The child: build, report, check the answers, report. */
static void child(const struct accel_ops *ops, const char *settings, const scene_t *s, const ray_check *rc, int fd)
{
    build_report br = {0};
    long rss0 = rss_kb_of(getpid());
    double c0 = now_ms(CLOCK_PROCESS_CPUTIME_ID), w0 = now_ms(CLOCK_MONOTONIC);
    accel *a = test_build_with(ops, s, settings, 1, br.err, sizeof br.err);
    br.cpu_ms = now_ms(CLOCK_PROCESS_CPUTIME_ID) - c0;
    br.wall_ms = now_ms(CLOCK_MONOTONIC) - w0;
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    br.rss_kb = ru.ru_maxrss - rss0;
    br.built = a != NULL;
    if (a) br.mem = a->ops->memory(a);
    write_all(fd, &br, sizeof br);
    check_report_t cr = {0};
    for (int k = 0; a && rc && k < rc->nsets; k++) {
        const rayset_t *rs = rc->sets[k];
        if ((ops->flags & ACCEL_SHADOW_ONLY) && rs->query != QUERY_ANY) continue;
        answers_t *got = test_trace(a, rs, 1);
        for (uint32_t i = 0; i < rs->count; i++) {
            cr.rays++;
            if (rs->query == QUERY_ANY) {
                cr.hitmiss += got->occluded[i] != rc->want[k]->occluded[i];
                continue;
            }
            hit_t g = got->hits[i], w = rc->want[k]->hits[i];
            cr.hitmiss += (g.prim == HIT_NONE) != (w.prim == HIT_NONE);
            cr.tdiff += g.prim != HIT_NONE && w.prim != HIT_NONE && g.t != w.t;
        }
        verify_result vr;
        verify_answers(s, rs, got, rc->want[k], &vr);
        cr.real += vr.mismatches[MM_REAL];
        cr.unjudged += vr.mismatches[MM_UNJUDGED];
        answers_free(got);
    }
    cr.done = 1;
    write_all(fd, &cr, sizeof cr);
    _exit(0);
}

/* Read exactly n bytes if they are there; 1 when read, 0 when not yet. */
static int try_read(int fd, void *p, size_t n, size_t *got)
{
    while (*got < n) {
        ssize_t r = read(fd, (char *)p + *got, n - *got);
        if (r > 0) *got += (size_t)r;
        else if (r < 0 && errno == EINTR) continue;
        else return 0;
    }
    return 1;
}

typedef struct {
    build_report b;
    check_report_t c;
    int killed;          /* 1: over time, 2: over memory, 3: died */
    double killed_at_s;
    long killed_rss_kb;
} outcome;

/* Build in a child, kill it past kill_s seconds or kill_rss_kb of resident
 * growth during the build (TRACE_KILL_S for the check after). */
static outcome watched_build(const struct accel_ops *ops, const char *settings, const scene_t *s, const ray_check *rc,
                             double kill_s, long kill_rss_kb)
{
    outcome o;
    memset(&o, 0, sizeof o);
    int fds[2];
    if (pipe(fds)) {
        perror("pipe");
        exit(2);
    }
    fflush(NULL);
    long base_rss = rss_kb_of(getpid());
    pid_t pid = fork();
    if (pid < 0) {
        perror("fork");
        exit(2);
    }
    if (pid == 0) {
        close(fds[0]);
        child(ops, settings, s, rc, fds[1]);
    }
    close(fds[1]);
    fcntl(fds[0], F_SETFL, O_NONBLOCK);
    double t0 = now_ms(CLOCK_MONOTONIC), phase0 = t0;
    size_t got_b = 0, got_c = 0;
    int have_b = 0, status = 0;
    for (;;) {
        if (!have_b && try_read(fds[0], &o.b, sizeof o.b, &got_b)) {
            have_b = 1;
            phase0 = now_ms(CLOCK_MONOTONIC);
        }
        if (have_b && try_read(fds[0], &o.c, sizeof o.c, &got_c)) break;
        pid_t w = waitpid(pid, &status, WNOHANG);
        if (w == pid) {
            if (have_b) try_read(fds[0], &o.c, sizeof o.c, &got_c);
            if (!o.c.done) o.killed = 3;
            pid = 0;
            break;
        }
        double el = (now_ms(CLOCK_MONOTONIC) - phase0) / 1e3;
        long rss = rss_kb_of(pid) - base_rss;
        if ((!have_b && (el > kill_s || rss > kill_rss_kb)) || (have_b && el > TRACE_KILL_S)) {
            o.killed = !have_b && rss > kill_rss_kb ? 2 : 1;
            o.killed_at_s = (now_ms(CLOCK_MONOTONIC) - t0) / 1e3;
            o.killed_rss_kb = rss;
            kill(pid, SIGKILL);
            break;
        }
        struct timespec ts = {0, 5 * 1000 * 1000};
        nanosleep(&ts, NULL);
    }
    if (pid > 0) waitpid(pid, &status, 0);
    close(fds[0]);
    if (!have_b) o.b.built = 0;
    return o;
}

/* ------------------------------------------------------------ checks */

typedef struct {
    const char *name;
    scene_t *s;
    int distinct; /* index of the distinct scene it is compared with, -1 for a distinct one */
    ray_check rc; /* zero until make_rays */
} case_t;

static void make_rays(case_t *c, accel *ref)
{
    static const char *const wl[] = {"primary", "shadow", "random"};
    workload_opts o = test_wl(12, 12, 1);
    for (int k = 0; k < 3; k++) {
        rayset_t *rs = workload_find(wl[k])->make(c->s, ref, &o);
        c->rc.sets[k] = rs;
        c->rc.want[k] = test_trace(ref, rs, 1);
    }
    c->rc.nsets = 3;
    /* The check must see hits through the duplicates. */
    uint32_t hits = 0;
    for (uint32_t i = 0; i < c->rc.sets[0]->count; i++) hits += c->rc.want[0]->hits[i].prim != HIT_NONE;
    if (hits < 10) {
        fprintf(stderr, "%s: only %u primary rays hit; the check would prove little\n", c->name, hits);
        exit(2);
    }
}

static void run_one(const struct accel_ops *ops, const char *settings, case_t *cases, int ncases)
{
    char label[200];
    snprintf(label, sizeof label, "%s%s%s%s", ops->name, *settings ? "[" : "", settings, *settings ? "]" : "");
    outcome res[8];
    int before = check_failed;
    for (int i = 0; i < ncases; i++) {
        case_t *c = &cases[i];
        double kill_s = DISTINCT_KILL_S;
        long kill_rss = 4L << 20;
        if (c->distinct >= 0) {
            const outcome *d = &res[c->distinct];
            double lim_ms = fmax(DUP_RATIO * d->b.cpu_ms, DUP_TIME_FLOOR_MS);
            long lim_rss = (long)fmax(DUP_RATIO * (double)d->b.rss_kb, (double)DUP_RSS_FLOOR);
            /* Wall time on a loaded machine may run well past CPU time. */
            kill_s = 10.0 * lim_ms / 1e3 + 5.0;
            kill_rss = 2 * lim_rss + (256L << 10);
        }
        res[i] = watched_build(ops, settings, c->s, c->distinct >= 0 ? &c->rc : NULL, kill_s, kill_rss);
        outcome *o = &res[i];
        if (o->killed == 1 || o->killed == 2) {
            printf("  %-30s %-10s killed after %.1f s at %ld MiB resident (over %s)\n", label, c->name, o->killed_at_s,
                   o->killed_rss_kb >> 10, o->killed == 1 ? "time" : "memory");
            CHECK_MSG(0, "%s on %s: killed, over %s", label, c->name, o->killed == 1 ? "time" : "memory");
            continue;
        }
        CHECK_MSG(o->killed == 0, "%s on %s: the build's process died", label, c->name);
        CHECK_MSG(o->b.built, "%s on %s: build failed: %s", label, c->name, o->b.err);
        if (!o->b.built || o->killed) continue;
        printf("  %-30s %-11s cpu %9.1f ms  wall %9.1f ms  memory %11llu  rss +%7ld KiB", label, c->name, o->b.cpu_ms,
               o->b.wall_ms, (unsigned long long)o->b.mem, o->b.rss_kb);
        if (c->distinct < 0) {
            printf("\n");
            continue;
        }
        const outcome *d = &res[c->distinct];
        printf("  x%.1f x%.1f x%.1f\n", o->b.cpu_ms / fmax(d->b.cpu_ms, 1e-3), (double)o->b.mem / fmax((double)d->b.mem, 1),
               (double)o->b.rss_kb / fmax((double)d->b.rss_kb, 1));
        if (!d->b.built || d->killed) continue;
        CHECK_MSG(o->b.cpu_ms <= fmax(DUP_RATIO * d->b.cpu_ms, DUP_TIME_FLOOR_MS), "%s on %s: build %.1f ms, %s %.1f ms",
                  label, c->name, o->b.cpu_ms, cases[c->distinct].name, d->b.cpu_ms);
        CHECK_MSG((double)o->b.mem <= fmax(DUP_RATIO * (double)d->b.mem, DUP_MEM_FLOOR), "%s on %s: memory() %llu, %s %llu",
                  label, c->name, (unsigned long long)o->b.mem, cases[c->distinct].name, (unsigned long long)d->b.mem);
        CHECK_MSG((double)o->b.rss_kb <= fmax(DUP_RATIO * (double)d->b.rss_kb, DUP_RSS_FLOOR),
                  "%s on %s: peak resident +%ld KiB, %s +%ld KiB", label, c->name, o->b.rss_kb, cases[c->distinct].name,
                  d->b.rss_kb);
        CHECK_MSG(o->c.done && o->c.rays > 0, "%s on %s: the answers were not checked", label, c->name);
        CHECK_MSG(o->c.hitmiss == 0, "%s on %s: %llu of %llu rays hit where exhaustive misses or the other way", label,
                  c->name, (unsigned long long)o->c.hitmiss, (unsigned long long)o->c.rays);
        CHECK_MSG(o->c.real == 0 && o->c.unjudged == 0, "%s on %s: %llu real mismatches, %llu unjudged", label, c->name,
                  (unsigned long long)o->c.real, (unsigned long long)o->c.unjudged);
        if (o->c.tdiff) printf("  %s on %s: %llu hits at another float t than exhaustive's (verify: the same hit)\n", label,
                               c->name, (unsigned long long)o->c.tdiff);
    }
    printf("%-40s %s\n", label, check_failed == before ? "holds" : "FAILS");
}

int main(int argc, char **argv)
{
    setvbuf(stdout, NULL, _IOLBF, 0);
    /* Optional: only the accelerators named (a debugging aid). */
#ifdef __SANITIZE_ADDRESS__
    /* Under AddressSanitizer the scenes of 10^5 primitives only repeat the
     * 10^4 ones' code at ten times the cost (most of the sanitizer suite's
     * four minutes here); they are the release suite's, where their times
     * and memory mean something. */
    printf("distinct1e5, dup1e5, dup10x1e4: run by the release build's suite, not under AddressSanitizer\n");
    case_t cases[] = {
        {.name = "distinct1e4", .s = distinct_scene("distinct1e4", 10000), .distinct = -1},
        {.name = "dup1e4", .s = dup_scene("dup1e4", 10000), .distinct = 0},
    };
#else
    case_t cases[] = {
        {.name = "distinct1e4", .s = distinct_scene("distinct1e4", 10000), .distinct = -1},
        {.name = "distinct1e5", .s = distinct_scene("distinct1e5", 100000), .distinct = -1},
        {.name = "dup1e4", .s = dup_scene("dup1e4", 10000), .distinct = 0},
        {.name = "dup1e5", .s = dup_scene("dup1e5", 100000), .distinct = 1},
        {.name = "dup10x1e4", .s = dup10_scene("dup10x1e4", 10000), .distinct = 1},
    };
#endif
    int ncases = (int)(sizeof cases / sizeof cases[0]);
    for (int i = 0; i < ncases; i++)
        if (cases[i].distinct >= 0) {
            accel *ref = test_build("exhaustive", cases[i].s, 1);
            make_rays(&cases[i], ref);
            ref->ops->destroy(ref);
        }
    for (int i = 0; accel_registry[i]; i++) {
        const struct accel_ops *ops = accel_registry[i];
        bool wanted = argc < 2;
        for (int k = 1; k < argc; k++) wanted |= !strcmp(argv[k], ops->name);
        if (!wanted) continue;
        run_one(ops, "", cases, ncases);
        for (size_t k = 0; k < sizeof extra_settings / sizeof extra_settings[0]; k++)
            if (!strcmp(extra_settings[k].name, ops->name)) run_one(ops, extra_settings[k].settings, cases, ncases);
    }
    for (int i = 0; i < ncases; i++) {
        for (int k = 0; k < cases[i].rc.nsets; k++) {
            rayset_free(cases[i].rc.sets[k]);
            answers_free(cases[i].rc.want[k]);
        }
        scene_free(cases[i].s);
    }
    return check_report();
}
