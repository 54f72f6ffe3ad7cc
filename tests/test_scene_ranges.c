/* test_scene_ranges: the ranges every scene lies in (scenes/scene.h).
 *  - scene_finish refuses a vertex, a sphere, a cone, a camera or a light
 *    outside them with one line naming the culprit by its index, and the
 *    NFF reader and the mesh pre-checks name the file's line;
 *  - a view applied after loading is held to the same ranges;
 *  - a scene at the very edge of the range traces: the float normals of its
 *    largest triangles stay finite (the fourth power the bound is set by),
 *    and every accelerator's primary hits are finite;
 *  - scene_generated counts a generated scene without making it. */
#include <string.h>
#include <unistd.h>
#include "../scenes/nff.h"
#include "testlib.h"

static char err[1024];

/* A one-triangle scene with the given vertices, finished; NULL with err. */
static scene_t *triangle_scene(vec3 a, vec3 b, vec3 c)
{
    scene_t *s = scene_new("tri");
    prims_add_vertex(&s->prims, a);
    prims_add_vertex(&s->prims, b);
    prims_add_vertex(&s->prims, c);
    prims_add_triangle(&s->prims, 0, 1, 2);
    if (scene_finish(s, false, err, sizeof err) == 0) return s;
    scene_free(s);
    return NULL;
}

static void expect_refused(scene_t *s, bool has_camera, const char *want)
{
    int rc = scene_finish(s, has_camera, err, sizeof err);
    CHECK_MSG(rc != 0 && strstr(err, want), "want '%s', got %s '%s'", want, rc ? "error" : "success", rc ? err : "");
    CHECK_MSG(!strchr(err, '\n'), "more than one line: '%s'", err);
    scene_free(s);
}

/* The mesh: finite coordinates whose extent overflows a float. */
static void test_geometry(void)
{
    CHECK(triangle_scene(v3(-3e38f, 0, 0), v3(3e38f, 0, 0), v3(0, 3e38f, 0)) == NULL);
    CHECK_MSG(strstr(err, "vertex 0 (-3e+38 0 0) is outside the scene range") && strstr(err, "2^30"), "%s", err);
    CHECK(triangle_scene(v3(0, 0, 0), v3(1, 0, 0), v3(0, 0x1p30f * 1.0000001f, 0)) == NULL);
    CHECK_MSG(strstr(err, "vertex 2"), "%s", err);
    scene_t *s = triangle_scene(v3(-0x1p30f, 0, 0), v3(0x1p30f, 0, 0), v3(0, 0x1p30f, 0));
    CHECK_MSG(s != NULL, "a scene on the bound: %s", err);
    scene_free(s);

    s = scene_new("spheres");
    prims_add_sphere(&s->prims, v3(0, 0, 0), 1);
    prims_add_sphere(&s->prims, v3(0x1p30f - 512, 0, 0), 1024); /* centre inside, box outside */
    expect_refused(s, false, "sphere 1 (primitive 1) with centre (1.07374e+09 0 0) and radius 1024 reaches outside");
    s = scene_new("radius");
    prims_add_sphere(&s->prims, v3(0, 0, 0), 1e38f);
    expect_refused(s, false, "sphere 0 (primitive 0)");

    s = scene_new("cones");
    prims_add_vertex(&s->prims, v3(0, 0, 0));
    prims_add_vertex(&s->prims, v3(1, 0, 0));
    prims_add_vertex(&s->prims, v3(0, 1, 0));
    prims_add_triangle(&s->prims, 0, 1, 2);
    prims_add_cone(&s->prims, v3(0, 0, 0), 1, v3(0, 0, 1e-30f), 1); /* an axis too short for a float direction */
    expect_refused(s, false, "cone 0 (primitive 1)");
    s = scene_new("flat cone");
    prims_add_cone(&s->prims, v3(0, 0, 0), 1e6f, v3(0, 0, 1e-3f), 0); /* slope 1e9 */
    expect_refused(s, false, "flatter than a float cone can be");
    s = scene_new("wide cone");
    prims_add_cone(&s->prims, v3(0, 0, 0), 2e9f, v3(0, 0, 1), 1);
    expect_refused(s, false, "reaches outside the scene range");
}

static scene_t *sphere_with_camera(vec3 from, vec3 at, vec3 up)
{
    scene_t *s = scene_new("view");
    prims_add_sphere(&s->prims, v3(0, 0, 0), 1);
    s->camera = (camera_t){from, at, up, 45.0f, 0.0f, 8, 8};
    return s;
}

static void test_views(void)
{
    expect_refused(sphere_with_camera(v3(1e20f, 0, 0), v3(0, 0, 0), v3(0, 1, 0)), true,
                   "camera eye (1e+20 0 0) is outside the view range");
    expect_refused(sphere_with_camera(v3(0, 0, 5), v3(0, 0, 0), v3(0, 1e-30f, 0)), true, "up (0 1e-30 0) is zero");
    expect_refused(sphere_with_camera(v3(0, 0, 5), v3(0, 0, 5 + 1e-12f), v3(0, 1, 0)), true, "eye and at are the same point");
    scene_t *s = sphere_with_camera(v3(0, 0, 5), v3(0, 0, 0), v3(0, 1, 0));
    scene_add_light(s, v3(0, 1e12f, 0));
    expect_refused(s, true, "light 0 (0 1e+12 0) is outside the view range");

    /* The automatic camera and lights of the largest scene fit. */
    s = triangle_scene(v3(-0x1p30f, -0x1p30f, -0x1p30f), v3(0x1p30f, -0x1p30f, 0x1p30f), v3(-0x1p30f, 0x1p30f, 0x1p30f));
    CHECK_MSG(s != NULL, "%s", err);
    scene_free(s);

    /* A view applied after loading: the same ranges. */
    scene_view v;
    CHECK(scene_view_parse("eye=1e30,0,0", &v, err, sizeof err) == 0);
    s = test_scene("spd:balls:1");
    CHECK(scene_view_apply(s, &v, "eye=1e30,0,0", err, sizeof err) != 0);
    CHECK_MSG(strstr(err, "view eye=1e30,0,0: camera eye (1e+30 0 0) is outside the view range"), "%s", err);
    CHECK(scene_view_parse("up=0,1e-30,0", &v, err, sizeof err) == 0);
    CHECK(scene_view_apply(s, &v, "up=0,1e-30,0", err, sizeof err) != 0);
    scene_free(s);
}

/* Loaders that know the line name it. */
static void test_lines(void)
{
    char path[256];
    struct { const char *file, *text, *want; } cases[] = {
        {"far.nff", "s 0 0 0 1\nv\nfrom 1e20 0 0\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 8 8\n",
         ":3: 1e20 is outside the view range in 'v from'"},
        {"big.nff", "s 0 0 0 1\n\np 3\n0 0 0\n1 0 0\n0 3e38 0\n", ":6: 3e38 is outside the scene range in 'p 3' vertex 3"},
        {"ball.nff", "s 1073741800 0 0 100\n", ":1: sphere reaches outside the scene range"},
        {"disk.nff", "c 0 0 0 1e6 0 0 1e-3 0\n", ":1: cone is flatter than a float cone can be"},
        {"light.nff", "s 0 0 0 1\nl 0 0 1e12\n", ":2: 1e12 is outside the view range in 'l'"},
        {"huge.obj", "v -3e38 0 0\nv 3e38 0 0\nv 0 3e38 0\nf 1 2 3\n", ": line 1: vertex 1 coordinate -3e+38 is outside"},
        {"cut.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4", ": line 6: a face of 2 vertices"},
        {"short.obj", "v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n", ": line 2: vertex 2 needs 3 coordinates"},
        {"far.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 2e9 0\n3 0 1 2\n", ": line 5: vertex 2 coordinate 2e+09 is outside"},
        {"count.off", "4OFF\n2000000000 2000000000 0\n0 0 0 1\n", ": line 2: declares 2000000000 vertices"},
        {"count2.off", "COFF\n2000000000 2000000000 0\n0 0 0 1 1 1 1\n", ": ends after 1 of 2000000000 vertices"},
        /* fuzz_mesh's first crash: assimp's OFF reader on a 30-vertex COFF face */
        {"face2.off", "COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n30\n",
         ": line 6: face 0 has 30 vertices"},
        {"count.ply", "ply\nformat ascii 1.0\nelement vertex 2000000000\nproperty float x\nend_header\n0\n",
         ": line 3: declares 2000000000 elements"},
        /* fuzz_mesh's first out-of-memory: assimp took "OFF1" for OFF and a count of 1, then 2^31 faces */
        {"glued.off", "OFF1  10737418240 0\n 3\n", ": line 1: declares 1 vertices and 2147483648 faces"},
        /* fuzz_mesh's first timeout: assimp read a count of 2^64 - 1 ("5z" is 5 to it) */
        {"wrap.ply", "ply\nformat ascii 1.0\nelement vertex 18446744073709551615z\nelement face 1\nend_header\n0 0 0\n",
         ": line 3: declares 18446744073709551616 elements"},
        /* and its second out-of-memory: the count before the name, 2^32 - 1 to assimp */
        {"order.ply", "ply\nformat ascii 1.0\nelement 18446744073709551615 vertex 8\nproperty float x\nend_header\n0\n",
         ": line 3: declares 18446744073709551616 elements"},
        /* and its third: a face list of 1.2e22 items (80 s and 21 GB in assimp before std::bad_alloc) */
        {"list.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                     "12222222222222222222222 0 0\n", ": line 6: 'face' element 0 needs"},
        /* a list split over two lines: assimp read the next line's numbers as this one's */
        {"split.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n2\n",
         ": line 13: 'face' element 0 needs 4 numbers, the line holds 3"},
        /* fuzz_mesh's crash and hang in assimp: a vertical tab after end_header */
        {"vt.ply", "ply\nformat ascii 1.0\nend_header\v1\n", ": line 3: byte 0x0b in the PLY header"},
        {"facet.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid t\n",
         ": line 2: a facet of other than 3 vertices"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(path, sizeof path, "/tmp/accelbench-ranges-%d-%s", (int)getpid(), cases[i].file);
        FILE *f = fopen(path, "w");
        fputs(cases[i].text, f);
        fclose(f);
        scene_t *s = scene_load(path, err, sizeof err);
        CHECK_MSG(!s && strncmp(err, path, strlen(path)) == 0 && strstr(err, cases[i].want), "%s: want '%s', got '%s'",
                  cases[i].file, cases[i].want, s ? "a scene" : err);
        scene_free(s);
        remove(path);
    }
    /* fuzz_mesh's hang in assimp: a NUL inside a header line after a misspelt format (the line checks read C
     * strings, so it is looked for in the bytes) */
    static const char nul_ply[] = "ply\nformat binary_little_endirn 1.0\nproperty fl\0\0\0oat x\nelement face 0\nend_header\n";
    snprintf(path, sizeof path, "/tmp/accelbench-ranges-%d-nul.ply", (int)getpid());
    FILE *f = fopen(path, "wb");
    fwrite(nul_ply, 1, sizeof nul_ply - 1, f);
    fclose(f);
    scene_t *s = scene_load(path, err, sizeof err);
    CHECK_MSG(!s && strstr(err, ": line 3: byte 0x00 in the PLY header"), "nul.ply: got '%s'", s ? "a scene" : err);
    scene_free(s);
    remove(path);
}

/* The bound is set by the float normal of the largest triangles: at the
 * edge it is finite and unit, and every accelerator hits with a finite t. */
static void test_edge_traces(void)
{
    const float B = SCENE_COORD_MAX;
    scene_t *s = triangle_scene(v3(-B, -B, -B), v3(B, -B, B), v3(-B, B, B));
    CHECK_MSG(s != NULL, "%s", err);
    if (!s) return;
    ray_t r = {v3(0, 0, 0), 0, v3(0, 0, 1), INFINITY, RAY_NO_LIGHT, 0};
    hit_t h = {1.0f, 0, 0, 0};
    vec3 n = prim_normal(&s->prims, &h, &r);
    CHECK_MSG(v3_finite(n) && fabsf(v3_len(n) - 1.0f) < 1e-5f, "normal (%g %g %g)", n.x, n.y, n.z);
    workload_opts o = test_wl(8, 8, 1);
    rayset_t *rs = workload_primary(s, &o);
    for (int i = 0; accel_registry[i]; i++) {
        if (accel_registry[i]->flags & ACCEL_SHADOW_ONLY) continue; /* no closest-hit queries to ask it */
        accel *a = test_build(accel_registry[i]->name, s, 1);
        answers_t *ans = test_trace(a, rs, 1);
        uint32_t hits = 0;
        bool finite = true;
        for (uint32_t k = 0; k < ans->count; k++)
            if (ans->hits[k].prim != HIT_NONE) hits++, finite = finite && isfinite(ans->hits[k].t);
        CHECK_MSG(hits > 0 && finite, "%s: %u hits, finite %d", a->ops->name, hits, finite);
        answers_free(ans);
        a->ops->destroy(a);
    }
    rayset_free(rs);
    scene_free(s);
}

static void test_generated(void)
{
    uint64_t n;
    CHECK(scene_generated("spd:balls:2", &n) && n == 92); /* 91 spheres and the floor */
    CHECK(scene_generated("spd:balls:5:t64@fov=30", &n) && n == 66430ull * 12 * 64 * 64 + 2); /* the 3.26e9 */
    CHECK(scene_generated("gen:room:empty", &n) && n == 0);
    CHECK(!scene_generated("spd:balls:99", &n) && !scene_generated("bunny", &n) && !scene_generated("x.obj", &n));
}

int main(void)
{
    test_geometry();
    test_views();
    test_lines();
    test_edge_traces();
    test_generated();
    return check_report();
}
