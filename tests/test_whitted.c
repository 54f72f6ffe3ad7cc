/* test_whitted: the whitted workload's ray trees against hand counts, and
 * the rules they are spawned by (harness/workloads/spawn.h).
 *
 * 1. Two facing mirror spheres, the eye between them looking into one
 *    through a field of view so narrow (1e-3 degrees) that every ray of the
 *    tree stays near the axis: each of the 3 x 3 corner eye rays hits A,
 *    then its reflections bounce B, A, B, A (tree depth 5); a light above
 *    the axis is faced by all 5 hits, a light behind B only by A's 3:
 *    9 eye rays, 9 x 4 = 36 reflected, 0 refracted, 9 x 8 = 72 shadow.
 * 2. One glass sphere (T > 0, Ks > 0) on the axis: every hit both reflects
 *    and refracts; the rays that enter keep bouncing inside (front, back,
 *    front, back, front at depths 1..5) while the ones leaving it miss:
 *    9 x 4 reflected, 9 x 4 refracted, and shadow rays to a light behind
 *    the eye from the hits that face it (the outer front, and the two
 *    inside hits on the back: 3 per tree).
 * 3. Snell's law: the refracted direction's sines obey n1 sin = n2 sin
 *    entering and leaving, and a ray leaving glass beyond the critical
 *    angle is totally internally reflected (no refraction ray).
 * 4. A smooth triangle: the shading normal at its centroid is the
 *    normalised mean of its vertex normals, and the reflection follows it.
 * 5. Every accelerator agrees with Embree on the four parts (test_accels
 *    does that through the registry; here one check on the glass scene). */
#include <math.h>
#include <string.h>
#include "harness/workloads/spawn.h"
#include "testlib.h"

static scene_t *axis_scene(const char *name, bool glass)
{
    scene_t *s = scene_new(name);
    material_t mirror = {v3(1, 1, 1), 0.2f, 0.8f, 0.0f, 1.0f}, clear = {v3(1, 1, 1), 0.1f, 0.1f, 0.9f, 1.5f};
    prims_add_sphere(&s->prims, v3(0, 0, 10), glass ? 2.0f : 5.0f);
    if (!glass) prims_add_sphere(&s->prims, v3(0, 0, -10), 5.0f);
    scene_set_material_upto(s, scene_add_material(s, glass ? clear : mirror));
    if (glass) {
        scene_add_light(s, v3(0, 0, -5)); /* behind the eye */
    } else {
        scene_add_light(s, v3(0, 20, 0)); /* above the axis: faced by every hit */
        scene_add_light(s, v3(0, 0, -30)); /* behind B: faced by A's front only */
    }
    s->camera = (camera_t){v3(0, 0, 0), v3(0, 0, 1), v3(0, 1, 0), 1e-3f, 0.0f, 2, 2};
    char err[256];
    if (scene_finish(s, true, err, sizeof err)) {
        fprintf(stderr, "%s: %s\n", name, err);
        exit(2);
    }
    return s;
}

static void count_parts(const char *name, bool glass, const uint32_t want[WHITTED_PARTS])
{
    scene_t *s = axis_scene(name, glass);
    accel *ref = test_build("embree", s, 1);
    workload_opts o = test_wl(2, 2, 1);
    o.depth = 0; /* the SPD's 5 */
    for (int p = 0; p < WHITTED_PARTS; p++) {
        rayset_t *rs = workload_whitted(s, ref, &o, (whitted_part)p);
        printf("%s %-18s %3u rays (hand count %u)\n", name, whitted_part_name[p], rs->count, want[p]);
        CHECK_MSG(rs->count == want[p], "%s %s: %u rays, by hand %u", name, whitted_part_name[p], rs->count, want[p]);
        CHECK(!strcmp(rs->workload, whitted_part_name[p]) && rs->query == (p == WHITTED_SHADOW ? QUERY_ANY : QUERY_CLOSEST));
        CHECK(rs->width == 2 && rs->height == 2);
        for (uint32_t i = 0; i < rs->count; i++) CHECK(rs->pixel[i] < 4 && ray_traceable(&rs->rays[i]));
        if (p == WHITTED_EYE) {
            answers_t *a = test_trace(ref, rs, 1);
            uint32_t hits = 0;
            for (uint32_t i = 0; i < rs->count; i++) hits += a->hits[i].prim != HIT_NONE;
            CHECK_MSG(hits == rs->count, "%s: %u of %u eye rays hit", name, hits, rs->count);
            answers_free(a);
        }
        /* A tree of depth 1 is the eye rays and their shadow rays (A's front faces every light). */
        if (p != WHITTED_EYE) {
            workload_opts one = o;
            one.depth = 1;
            rayset_t *flat = workload_whitted(s, ref, &one, (whitted_part)p);
            uint32_t flat_want = p == WHITTED_SHADOW ? 9 * s->nlights : 0;
            CHECK_MSG(flat->count == flat_want, "%s %s at depth 1: %u rays, by hand %u", name, whitted_part_name[p],
                      flat->count, flat_want);
            rayset_free(flat);
        }
        rayset_free(rs);
    }
    ref->ops->destroy(ref);
    scene_free(s);
}

/* A triangle in the plane z = 0 (normal +z), hit at (0.25, 0.25, 0). */
static scene_t *plane_scene(float t, float ior, bool smooth)
{
    scene_t *s = scene_new("plane");
    uint32_t a = prims_add_vertex(&s->prims, v3(-1, -1, 0));
    prims_add_vertex(&s->prims, v3(3, -1, 0));
    prims_add_vertex(&s->prims, v3(-1, 3, 0));
    prims_add_triangle(&s->prims, a, a + 1, a + 2);
    if (smooth) {
        scene_set_vertex_normal(s, a, v3(1, 0, 1));
        scene_set_vertex_normal(s, a + 1, v3(-1, 0, 1));
        scene_set_vertex_normal(s, a + 2, v3(0, 1, 1));
    }
    scene_set_material_upto(s, scene_add_material(s, (material_t){v3(1, 1, 1), 0.5f, 0.5f, t, ior}));
    char err[256];
    CHECK_MSG(scene_finish(s, false, err, sizeof err) == 0, "%s", err);
    return s;
}

static spawn_t hit_plane(const scene_t *s, vec3 dir, ray_t *r)
{
    vec3 p = v3(0.25f, 0.25f, 0.0f);
    *r = (ray_t){v3_sub(p, v3_scale(dir, 4.0f)), 0.0f, dir, INFINITY, RAY_NO_LIGHT, 0};
    hit_t h = hit_none(r);
    counters_t c = {0};
    CHECK(prim_intersect(&s->prims, 0, r, &h, &c));
    return spawn_at(s, r, &h);
}

static void test_snell(void)
{
    scene_t *s = plane_scene(0.9f, 1.5f, false);
    /* Entering: from +z (the outward side of the winding's normal) at 45 degrees. */
    ray_t r, t;
    vec3 d = v3_norm(v3(1, 0, -1));
    spawn_t f = hit_plane(s, d, &r);
    CHECK(f.entering && v3_dot(f.n, d) < 0);
    CHECK(spawn_refract(&f, &t));
    float sin_in = sqrtf(0.5f), sin_out = sqrtf(t.dir.x * t.dir.x + t.dir.y * t.dir.y);
    CHECK_MSG(fabsf(sin_in - 1.5f * sin_out) < 1e-5f, "entering: sin %g vs 1.5 sin %g", sin_in, 1.5f * sin_out);
    CHECK_MSG(t.dir.z < 0 && t.org.z < 0 && f.org_out.z > 0, "the refracted ray starts below, the others above");
    ray_t m = spawn_reflect(&f);
    CHECK(fabsf(m.dir.x - d.x) < 1e-6f && fabsf(m.dir.z + d.z) < 1e-6f && m.org.z > 0);
    /* Leaving: from -z at 30 degrees refracts (sin 0.5 * 1.5 = 0.75), at 60 degrees it is totally reflected. */
    d = v3_norm(v3(sinf(0.5235988f), 0, cosf(0.5235988f)));
    f = hit_plane(s, d, &r);
    CHECK(!f.entering);
    CHECK(spawn_refract(&f, &t));
    sin_out = sqrtf(t.dir.x * t.dir.x + t.dir.y * t.dir.y);
    CHECK_MSG(fabsf(1.5f * 0.5f - sin_out) < 1e-5f, "leaving: 1.5 sin %g vs sin %g", 0.75, sin_out);
    d = v3_norm(v3(sinf(1.0471976f), 0, cosf(1.0471976f)));
    f = hit_plane(s, d, &r);
    CHECK_MSG(!spawn_refract(&f, &t), "total internal reflection gave a refraction ray");
    scene_free(s);
}

static void test_smooth_normal(void)
{
    scene_t *s = plane_scene(0.0f, 1.0f, true);
    CHECK(scene_prim_smooth(s, 0));
    ray_t r;
    spawn_t f = hit_plane(s, v3(0, 0, -1), &r);
    /* (0.25, 0.25) has barycentrics (0.375, 0.3125, 0.3125) on (-1,-1), (3,-1), (-1,3). */
    vec3 n = v3_add(v3_add(v3_scale(v3_norm(v3(1, 0, 1)), 0.375f), v3_scale(v3_norm(v3(-1, 0, 1)), 0.3125f)),
                    v3_scale(v3_norm(v3(0, 1, 1)), 0.3125f));
    n = v3_norm(n);
    CHECK_MSG(fabsf(f.ns.x - n.x) < 1e-5f && fabsf(f.ns.y - n.y) < 1e-5f && fabsf(f.ns.z - n.z) < 1e-5f,
              "shading normal (%g %g %g), want (%g %g %g)", f.ns.x, f.ns.y, f.ns.z, n.x, n.y, n.z);
    CHECK(f.n.z == 1.0f); /* the geometric normal is the plane's */
    ray_t m = spawn_reflect(&f);
    vec3 want = v3_norm(v3_sub(v3(0, 0, -1), v3_scale(n, 2.0f * v3_dot(v3(0, 0, -1), n))));
    CHECK_MSG(fabsf(m.dir.x - want.x) < 1e-5f && fabsf(m.dir.y - want.y) < 1e-5f, "the reflection ignores the shading normal");
    scene_free(s);
}

static void test_agreement(void)
{
    scene_t *s = axis_scene("glass", true);
    accel *ref = test_build("embree", s, 1), *ex = test_build("exhaustive", s, 1);
    workload_opts o = test_wl(8, 8, 1);
    o.depth = 0;
    for (int p = 0; p < WHITTED_PARTS; p++) {
        rayset_t *rs = workload_whitted(s, ref, &o, (whitted_part)p);
        answers_t *want = test_trace(ref, rs, 1), *got = test_trace(ex, rs, 1);
        verify_result vr;
        verify_answers(s, rs, got, want, &vr);
        CHECK_MSG(rs->count > 0 && vr.mismatches[MM_REAL] == 0, "glass %s: %u rays, %llu real", whitted_part_name[p],
                  rs->count, (unsigned long long)vr.mismatches[MM_REAL]);
        answers_free(want);
        answers_free(got);
        rayset_free(rs);
    }
    ex->ops->destroy(ex);
    ref->ops->destroy(ref);
    scene_free(s);
}

int main(void)
{
    const uint32_t mirrors[WHITTED_PARTS] = {9, 36, 0, 72}, glass[WHITTED_PARTS] = {9, 36, 36, 27};
    count_parts("mirrors", false, mirrors);
    count_parts("glass", true, glass);
    test_snell();
    test_smooth_normal();
    test_agreement();
    return check_report();
}
