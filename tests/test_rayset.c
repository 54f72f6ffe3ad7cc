/* test_rayset: ray sets are deterministic, replayable and thread-count
 * independent, and the ray file rejects damage.
 *  - the same (scene, workload, seed) gives the same hash twice; another
 *    seed gives another hash (for the seeded workloads);
 *  - a saved and reloaded set has the same hash and gives bit-identical
 *    answers;
 *  - 1 and 2 threads give bit-identical answers and counters for
 *    exhaustive, and identical answers for Embree;
 *  - a truncated, corrupted or foreign file is refused with a reason. */
#include <string.h>
#include <unistd.h>
#include "testlib.h"

static bool same_answers(const answers_t *a, const answers_t *b)
{
    if (a->count != b->count) return false;
    if (a->hits) return memcmp(a->hits, b->hits, a->count * sizeof *a->hits) == 0;
    return memcmp(a->occluded, b->occluded, a->count) == 0;
}

static void copy_file_truncated(const char *from, const char *to, long cut, long flip_at)
{
    FILE *f = fopen(from, "rb"), *g = fopen(to, "wb");
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    char *buf = malloc((size_t)n);
    if (fread(buf, 1, (size_t)n, f) != (size_t)n) abort();
    if (flip_at >= 0) buf[flip_at] ^= 0x40;
    fwrite(buf, 1, (size_t)(n - cut), g);
    free(buf);
    fclose(f);
    fclose(g);
}

int main(void)
{
    /* The mountain has glass spheres: every workload, whitted:refracted too, has rays. */
    scene_t *s = test_scene("spd:mount:3");
    accel *ref1 = test_build("embree", s, 1), *ref2 = test_build("embree", s, 2);
    accel *ex = test_build("exhaustive", s, 1);
    char err[512];
    for (int w = 0; workload_table[w].name; w++) {
        const char *name = workload_table[w].name;
        workload_opts o1 = test_wl(40, 30, 1), o2 = test_wl(40, 30, 2);
        rayset_t *a = workload_table[w].make(s, ref1, &o1), *b = workload_table[w].make(s, ref2, &o2);
        CHECK_MSG(a->count > 0 && a->hash == b->hash, "%s: ray set differs between 1 and 2 threads", name);
        o1.seed = 8;
        rayset_t *c = workload_table[w].make(s, ref1, &o1);
        if (!strcmp(name, "diffuse") || !strcmp(name, "random"))
            CHECK_MSG(c->hash != a->hash, "%s: the seed does not change the ray set", name);
        else
            CHECK_MSG(c->hash == a->hash, "%s: a seed-free workload changed with the seed", name);

        /* Save, reload, replay. */
        char path[256];
        snprintf(path, sizeof path, "/tmp/accelbench-test-%d-%s.rays", (int)getpid(), name);
        CHECK(rayset_save(a, path, err, sizeof err) == 0);
        rayset_t *r = rayset_load(path, err, sizeof err);
        CHECK_MSG(r != NULL, "%s", err);
        if (r) {
            CHECK(r->hash == a->hash && r->count == a->count && r->query == a->query);
            CHECK(!strcmp(r->workload, name) && !strcmp(r->scene, s->name));
            answers_t *x = test_trace(ex, a, 1), *y = test_trace(ex, r, 1);
            CHECK_MSG(same_answers(x, y), "%s: replayed rays answer differently", name);
            answers_free(x);
            answers_free(y);
            rayset_free(r);
        }

        /* Thread-count independence of the answers and counters. */
        answers_t *e1 = test_trace(ex, a, 1), *e2 = test_trace(ex, a, 2);
        CHECK_MSG(same_answers(e1, e2), "%s: exhaustive answers differ between 1 and 2 threads", name);
        CHECK(memcmp(&e1->total, &e2->total, sizeof e1->total) == 0);
        answers_t *m1 = test_trace(ref1, a, 1), *m2 = test_trace(ref1, a, 2);
        CHECK_MSG(same_answers(m1, m2), "%s: embree answers differ between 1 and 2 threads", name);
        answers_free(e1), answers_free(e2), answers_free(m1), answers_free(m2);

        /* Damaged files. */
        if (w == 0) {
            char bad[300];
            snprintf(bad, sizeof bad, "%s.bad", path);
            copy_file_truncated(path, bad, 7, -1);
            rayset_t *t = rayset_load(bad, err, sizeof err);
            CHECK_MSG(!t && strstr(err, "truncated"), "truncated file: %s", err);
            copy_file_truncated(path, bad, 0, 400); /* a flipped bit inside the rays */
            t = rayset_load(bad, err, sizeof err);
            CHECK_MSG(!t && strstr(err, "hash"), "corrupt file: %s", err);
            copy_file_truncated(path, bad, 0, 0); /* bad magic */
            t = rayset_load(bad, err, sizeof err);
            CHECK_MSG(!t && strstr(err, "not an accelbench ray file"), "foreign file: %s", err);
            t = rayset_load("/nonexistent/x.rays", err, sizeof err);
            CHECK_MSG(!t && strstr(err, "/nonexistent/x.rays"), "missing file: %s", err);
            remove(bad);
        }
        remove(path);
        rayset_free(a);
        rayset_free(b);
        rayset_free(c);
    }
    /* Rays no workload makes are refused on load, with their index. */
    const struct { vec3 dir; float tnear, tfar; const char *why; } bad_rays[] = {
        {{0, 0, 0}, 0.0f, 1.0f, "ray 1 has a zero-length direction"},
        {{0, NAN, 1}, 0.0f, 1.0f, "ray 1 has a NaN"},
        {{0, 0, 1}, 2.0f, 1.0f, "ray 1 has an empty range"},
    };
    for (int k = 0; k < 3; k++) {
        rayset_t *rs = rayset_new("random", s->name, 1, QUERY_CLOSEST);
        ray_t good = {v3(0, 0, 5), 0.0f, v3(0, 0, -1), INFINITY, RAY_NO_LIGHT, 0};
        ray_t badr = {v3(0, 0, 5), bad_rays[k].tnear, bad_rays[k].dir, bad_rays[k].tfar, RAY_NO_LIGHT, 0};
        rayset_push(rs, &good, 0);
        rayset_push(rs, &badr, 0);
        rayset_seal(rs);
        char path[256];
        snprintf(path, sizeof path, "/tmp/accelbench-test-%d-bad.rays", (int)getpid());
        CHECK(rayset_save(rs, path, err, sizeof err) == 0);
        rayset_t *t = rayset_load(path, err, sizeof err);
        CHECK_MSG(!t && strstr(err, bad_rays[k].why), "bad ray %d: %s", k, t ? "accepted" : err);
        remove(path);
        rayset_free(rs);
    }

    ex->ops->destroy(ex);
    ref1->ops->destroy(ref1);
    ref2->ops->destroy(ref2);
    scene_free(s);
    return check_report();
}
