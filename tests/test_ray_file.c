/* test_ray_file: what the ray file loader refuses (harness/workloads/rayset.h), each
 * with one line naming the file and the ray or field:
 *  - any change to a header field the old format did not hash (width,
 *    seed, the scene name), and a file of the old format;
 *  - a ray the harness's rule (prims/ray.h ray_traceable) would not let
 *    through, even with a valid hash: components past 2^60 (Embree aborts
 *    on those), a negative tnear;
 *  - a header no writer of this version makes: an unknown workload or a
 *    query not its own, no rays, a pixel outside the image;
 *  - and rayset_check_lights and rayset_check_origins: a light index or an
 *    origin primitive the scene does not have. */
#include <string.h>
#include <unistd.h>
#include "testlib.h"

static char err[512], path[256];

/* The bytes of a saved set, to damage. */
static char *saved_bytes(const rayset_t *rs, size_t *size)
{
    CHECK(rayset_save(rs, path, err, sizeof err) == 0);
    FILE *f = fopen(path, "rb");
    fseek(f, 0, SEEK_END);
    *size = (size_t)ftell(f);
    rewind(f);
    char *b = malloc(*size);
    if (fread(b, 1, *size, f) != *size) abort();
    fclose(f);
    return b;
}

static void expect_refused(const char *bytes, size_t size, const char *want)
{
    rayset_t *rs = rayset_from_memory(bytes, size, "x.rays", err, sizeof err);
    CHECK_MSG(!rs && strncmp(err, "x.rays: ", 8) == 0 && strstr(err, want), "want '%s', got '%s'", want,
              rs ? "a ray set" : err);
    rayset_free(rs);
}

/* Header byte offsets (rayset.c's file_header). */
enum { OFF_QUERY = 8, OFF_COUNT = 12, OFF_WIDTH = 16, OFF_SPP = 24, OFF_SEED = 32, OFF_WORKLOAD = 48, OFF_SCENE = 80,
       OFF_RAYS = 336 };

static void put_u32(char *b, size_t off, uint32_t v) { memcpy(b + off, &v, 4); }

static void test_header(const rayset_t *prim)
{
    size_t n;
    char *b = saved_bytes(prim, &n);
    rayset_t *ok = rayset_from_memory(b, n, "x.rays", err, sizeof err);
    CHECK_MSG(ok && ok->hash == prim->hash && ok->width == prim->width && ok->spp == prim->spp, "%s", err);
    rayset_free(ok);
    /* Fields version 1 did not hash: each change is now caught. */
    const size_t fields[] = {OFF_WIDTH, OFF_SPP, OFF_SEED, OFF_SCENE + 2, OFF_RAYS + (size_t)prim->count * 40 + 4};
    for (size_t i = 0; i < sizeof fields / sizeof fields[0]; i++) {
        b[fields[i]] ^= 1;
        expect_refused(b, n, "do not match the stored hash");
        b[fields[i]] ^= 1;
    }
    memcpy(b, "ABRAYS1\n", 8);
    expect_refused(b, n, "older format (ABRAYS1");
    memcpy(b, "ABRAYS2\n", 8);
    expect_refused(b, n, "older format (ABRAYS2, rays without their origin primitive)");
    memcpy(b, "ABRAYS3\n", 8);
    /* Past the hash (restamped): what no writer makes. */
    struct { size_t off; uint32_t value; const char *want; } bad[] = {
        {OFF_QUERY, QUERY_ANY, "workload 'primary' with query 1"},
        {OFF_WIDTH, 0, "pixels of a 0x4 image"},
        {OFF_SPP, 0, "at 0 samples"},
        {OFF_RAYS + (size_t)prim->count * 40 + 8, 16, "ray 2 belongs to pixel 16 of a 4x4 image"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char *c = malloc(n);
        memcpy(c, b, n);
        put_u32(c, bad[i].off, bad[i].value);
        rayset_file_rehash(c, n);
        expect_refused(c, n, bad[i].want);
        free(c);
    }
    memcpy(b + OFF_WORKLOAD, "caustic", 8);
    rayset_file_rehash(b, n);
    expect_refused(b, n, "workload 'caustic'");
    free(b);
}

/* One ray, saved, with a valid hash. */
static void expect_ray_refused(ray_t r, const char *want)
{
    rayset_t *rs = rayset_new("random", "s", 1, QUERY_CLOSEST);
    rayset_push(rs, &r, 0);
    rayset_seal(rs);
    size_t n;
    char *b = saved_bytes(rs, &n);
    expect_refused(b, n, want);
    free(b);
    rayset_free(rs);
}

static void test_rays(void)
{
    const char *beyond = "ray 0 has an origin or direction component beyond 2^60";
    expect_ray_refused((ray_t){v3(2e18f, 0, 0), 0, v3(0, 0, 1), INFINITY, RAY_NO_LIGHT, 0}, beyond);
    expect_ray_refused((ray_t){v3(0, 0, 0), 0, v3(0, -3e19f, 1), INFINITY, RAY_NO_LIGHT, 0}, beyond);
    expect_ray_refused((ray_t){v3(0, 0, 0), -1, v3(0, 0, 1), INFINITY, RAY_NO_LIGHT, 0}, "ray 0 has tnear -1 outside");
    expect_ray_refused((ray_t){v3(0, 0, 0), 0, v3(0, 0, 1), NAN, RAY_NO_LIGHT, 0}, "ray 0 has a NaN tnear or tfar");
    expect_ray_refused((ray_t){v3(0, 0, 0), 0, v3(0, INFINITY, 1), 1, RAY_NO_LIGHT, 0}, "ray 0 has a NaN or infinite");
    rayset_t *empty = rayset_new("random", "s", 1, QUERY_CLOSEST);
    rayset_seal(empty);
    size_t n;
    char *b = saved_bytes(empty, &n);
    expect_refused(b, n, "holds no rays");
    free(b);
    rayset_free(empty);
    /* Exactly at the limit is traceable. */
    rayset_t *edge = rayset_new("random", "s", 1, QUERY_CLOSEST);
    ray_t r = {v3(RAY_COORD_MAX, 0, 0), 0, v3(-1, 0, 0), INFINITY, RAY_NO_LIGHT, 0};
    rayset_push(edge, &r, 0);
    rayset_seal(edge);
    b = saved_bytes(edge, &n);
    rayset_t *back = rayset_from_memory(b, n, "x.rays", err, sizeof err);
    CHECK_MSG(back != NULL, "%s", err);
    rayset_free(back);
    free(b);
    rayset_free(edge);
}

static void test_lights(const scene_t *s, accel *ref)
{
    workload_opts o = test_wl(4, 4, 1);
    rayset_t *sh = workload_find("shadow")->make(s, ref, &o);
    CHECK(sh->count > 0);
    CHECK_MSG(rayset_check_lights(sh, "x.rays", s->name, s->nlights, err, sizeof err) == 0, "%s", err);
    sh->rays[sh->count - 1].light = s->nlights;
    CHECK(rayset_check_lights(sh, "x.rays", s->name, s->nlights, err, sizeof err) != 0);
    char want[128];
    snprintf(want, sizeof want, "x.rays: ray %u goes to light %u, but scene 'spd:balls:1' has %u lights", sh->count - 1,
             s->nlights, s->nlights);
    CHECK_MSG(strstr(err, want), "want '%s', got '%s'", want, err);
    /* Shadow rays leave the reference's hit primitive: in range, and one out of range is refused by name. */
    CHECK_MSG(rayset_check_origins(sh, "x.rays", s->name, s->prims.count, err, sizeof err) == 0, "%s", err);
    CHECK(sh->rays[0].origin < s->prims.count);
    sh->rays[0].origin = s->prims.count;
    CHECK(rayset_check_origins(sh, "x.rays", s->name, s->prims.count, err, sizeof err) != 0);
    snprintf(want, sizeof want, "x.rays: ray 0 leaves primitive %u, but scene 'spd:balls:1' has %u primitives",
             s->prims.count, s->prims.count);
    CHECK_MSG(strstr(err, want), "want '%s', got '%s'", want, err);
    sh->rays[0].origin = RAY_NO_ORIGIN;
    CHECK(rayset_check_origins(sh, "x.rays", s->name, s->prims.count, err, sizeof err) == 0);
    rayset_free(sh);
}

int main(void)
{
    snprintf(path, sizeof path, "/tmp/accelbench-ray-file-%d.rays", (int)getpid());
    scene_t *s = test_scene("spd:balls:1");
    accel *ref = test_build("exhaustive", s, 1);
    workload_opts o = test_wl(4, 4, 1);
    rayset_t *prim = workload_primary(s, &o);
    test_header(prim);
    test_rays();
    test_lights(s, ref);
    rayset_free(prim);
    ref->ops->destroy(ref);
    scene_free(s);
    remove(path);
    return check_report();
}
