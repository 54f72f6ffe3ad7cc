/* test_nff.c: the NFF reader and writer (scenes/nff.h).
 *
 * A hand-written file with every entity (NFF.TXT v3.9 and the SPD writer's
 * variants: `c` on one line and on three, `b` before `v`, `l` with and
 * without colour, `pp`, a concave polygon, comments) checked value by
 * value; round trips (a scene built in memory with every primitive kind,
 * the sphereflake, a catalogue mesh, a gzipped file) that must keep the
 * geometry bit for bit; one-line "PATH:LINE: reason" errors for bad input
 * with the right line; and a seeded fuzz run (NFF_FUZZ=N for more than the
 * default 300 mutations) that must never crash. */
#include "../scenes/nff.h"
#include "check.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char tmpdir[256];
static char err[1024];

static void tmp_path(char *out, size_t outlen, const char *file)
{
    snprintf(out, outlen, "%s/%s", tmpdir, file);
}

static void write_file(const char *path, const char *data, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (!f) {
        perror(path);
        exit(2);
    }
    fwrite(data, 1, size, f);
    fclose(f);
}

/* Write text to a temporary file named file and load it. */
static scene_t *load_text(const char *file, const char *text, char *path, size_t pathlen)
{
    tmp_path(path, pathlen, file);
    write_file(path, text, strlen(text));
    err[0] = '\0';
    return scene_load_nff(file, path, err, sizeof err);
}

static bool vec_eq(vec3 a, float x, float y, float z)
{
    return a.x == x && a.y == y && a.z == z;
}

/* ------------------------------------------------------ every entity */

static const char *every_entity =
    "# every NFF entity, SPD layout first (b before v)\n"
    "b 0.078 0.361 0.753\n"                 /* 2 */
    "v\n"
    "from 2.1 1.3 1.7\n"
    "at 0 0 0   # a trailing comment\n"
    "up 0 0 1\n"
    "angle 45\n"
    "hither 0.01\n"
    "resolution 320 240\n"                  /* 9 */
    "l 4 3 2\n"                             /* no colour */
    "l 1 -4 4 0.5 0.6 0.7\n"                /* with colour */
    "f 1 0.9 0.7 0.5 0.5 3.0827 0 1\n"      /* 12: material 0 */
    "s 0 0 0 0.5\n"                         /* prim 0 */
    "c 0 0 1 0.15 0 0 2 0.1\n"              /* prim 1: SPD's one-line c */
    "c\n"                                   /* prim 2: NFF.TXT's three-line c, inside visible */
    "1 1 1 -0.3\n"
    "1 1 3 -0.2\n"
    "f 1 0.9 0.7 0.5 0.5 3.0827 0 1\n"      /* a repeat: no new material */
    "f 1 0.75 0.33 0.8 0 100000 0 1\n"      /* material 1 */
    "p 3\n"                                 /* prim 3: triangle */
    "0 0 -1\n1 0 -1\n0 1 -1\n"
    "pp 3\n"                                /* prim 4: patch triangle */
    "0 0 -2 0 0 1\n1 0 -2 0 0 1\n0 1 -2 0 0 1\n"
    "p 6 # a concave L\n"                   /* prim 5: polygon */
    "0 0 5\n2 0 5\n2 1 5\n1 1 5\n1 2 5\n0 2 5\n"
    "pp 4\n"                                /* prim 6: patch quad */
    "0 0 6 0 0 1\n1 0 6 0 0 1\n1 1 6 0 0 1\n0 1 6 0 0 1\n"
    "p 5\n"                                 /* prim 7: duplicates merged: a triangle */
    "0 0 7\n1 0 7\n1 0 7\n0 1 7\n0 0 7\n"
    "s 3 3 3 1e-3 p 4 -12 -12 -0.5 12 -12 -0.5 12 12 -0.5 -12 12 -0.5\n"; /* prims 8, 9: all on one line */

static void check_every_entity_prims(const scene_t *s)
{
    const prims_t *p = &s->prims;
    CHECK(p->count == 10);
    CHECK(p->nspheres == 2 && p->ncones == 2 && p->ntris == 3 && p->npolygons == 3);
    static const uint8_t kinds[10] = {PRIM_SPHERE, PRIM_CONE, PRIM_CONE, PRIM_TRIANGLE, PRIM_TRIANGLE,
                                      PRIM_POLYGON, PRIM_POLYGON, PRIM_TRIANGLE, PRIM_SPHERE, PRIM_POLYGON};
    for (uint32_t i = 0; i < 10 && i < p->count; i++) CHECK_MSG(p->kind[i] == kinds[i], "prim %u kind %u", i, p->kind[i]);
    if (p->count != 10) return;
    CHECK(vec_eq(p->spheres[0].center, 0, 0, 0) && p->spheres[0].radius == 0.5f);
    CHECK(vec_eq(p->spheres[1].center, 3, 3, 3) && p->spheres[1].radius == 1e-3f);
    const cone_t *c = p->cones;
    CHECK(vec_eq(c[0].base, 0, 0, 1) && c[0].base_radius == 0.15f && vec_eq(c[0].apex, 0, 0, 2) && c[0].apex_radius == 0.1f);
    CHECK(vec_eq(c[1].base, 1, 1, 1) && c[1].base_radius == 0.3f && vec_eq(c[1].apex, 1, 1, 3) && c[1].apex_radius == 0.2f);
    const tri_t *t = &p->tris[p->index[4]];
    CHECK(vec_eq(p->verts[t->v[0]], 0, 0, -2) && vec_eq(p->verts[t->v[1]], 1, 0, -2) && vec_eq(p->verts[t->v[2]], 0, 1, -2));
    t = &p->tris[p->index[7]];
    CHECK(vec_eq(p->verts[t->v[0]], 0, 0, 7) && vec_eq(p->verts[t->v[1]], 1, 0, 7) && vec_eq(p->verts[t->v[2]], 0, 1, 7));
    const polygon_t *g = &p->polygons[p->index[5]];
    CHECK(g->count == 6 && !g->degenerate);
    CHECK(vec_eq(p->verts[p->poly_verts[g->first + 3]], 1, 1, 5));
    CHECK_NEAR(g->normal.z, 1.0, 1e-6);
    g = &p->polygons[p->index[6]];
    CHECK(g->count == 4 && vec_eq(p->verts[p->poly_verts[g->first + 2]], 1, 1, 6));
    g = &p->polygons[p->index[9]];
    CHECK(g->count == 4 && vec_eq(p->verts[p->poly_verts[g->first]], -12, -12, -0.5f));
}

static void test_every_entity(void)
{
    char path[512];
    scene_t *s = load_text("every.nff", every_entity, path, sizeof path);
    CHECK_MSG(s != NULL, "%s", err);
    if (!s) return;
    check_every_entity_prims(s);
    CHECK(vec_eq(s->background, 0.078f, 0.361f, 0.753f));
    const camera_t *c = &s->camera;
    CHECK(vec_eq(c->from, 2.1f, 1.3f, 1.7f) && vec_eq(c->at, 0, 0, 0) && vec_eq(c->up, 0, 0, 1));
    CHECK(c->fov_deg == 45.0f && c->hither == 0.01f && c->width == 320 && c->height == 240);
    CHECK(s->nlights == 2);
    if (s->nlights == 2) CHECK(vec_eq(s->lights[0], 4, 3, 2) && vec_eq(s->lights[1], 1, -4, 4));
    CHECK(s->nmaterials == 2);
    if (s->nmaterials == 2) {
        CHECK(vec_eq(s->materials[0].color, 1, 0.9f, 0.7f) && s->materials[0].kd == 0.5f && s->materials[0].ks == 0.5f);
        CHECK(vec_eq(s->materials[1].color, 1, 0.75f, 0.33f) && s->materials[1].kd == 0.8f && s->materials[1].ks == 0);
    }
    for (uint32_t i = 0; i < s->prims.count; i++) CHECK(s->prim_material[i] == (i < 3 ? 0 : 1));
    CHECK_MSG(strstr(s->source, "1 inside-visible cones") != NULL, "source '%s'", s->source);
    scene_free(s);
}

/* No `v`, `l` or `f`: the defaults, and material-less primitives before an `f`. */
static void test_defaults(void)
{
    char path[512];
    scene_t *s = load_text("defaults.nff", "s 0 0 0 1\nf 1 0 0 1 0 1 0 1\ns 3 0 0 1\n", path, sizeof path);
    CHECK_MSG(s != NULL, "%s", err);
    if (!s) return;
    CHECK(s->camera.fov_deg == 45.0f && s->camera.width == 512 && s->nlights == 2);
    CHECK(s->nmaterials == 2 && s->prim_material[0] == 0 && s->prim_material[1] == 1);
    CHECK(s->materials[0].kd == 0.8f && vec_eq(s->materials[1].color, 1, 0, 0));
    CHECK(vec_eq(s->background, 0, 0, 0));
    scene_free(s);
}

/* --------------------------------------------------------- round trips */

/* Write s, read it back; the geometry, counts, camera, lights and
 * materials must be the same. */
static void round_trip(const scene_t *s, const char *file)
{
    char path[512];
    tmp_path(path, sizeof path, file);
    CHECK_MSG(scene_write_nff(s, path, err, sizeof err) == 0, "%s: %s", file, err);
    scene_t *r = scene_load_nff(file, path, err, sizeof err);
    CHECK_MSG(r != NULL, "%s: %s", file, err);
    if (!r) return;
    CHECK_MSG(scene_geometry_hash(r) == scene_geometry_hash(s), "%s: hash differs", file);
    const prims_t *a = &s->prims, *b = &r->prims;
    CHECK(a->count == b->count && a->ntris == b->ntris && a->nspheres == b->nspheres && a->ncones == b->ncones &&
          a->npolygons == b->npolygons);
    CHECK(memcmp(&s->camera, &r->camera, sizeof s->camera) == 0);
    CHECK(s->nlights == r->nlights && memcmp(s->lights, r->lights, s->nlights * sizeof *s->lights) == 0);
    CHECK(vec_eq(r->background, s->background.x, s->background.y, s->background.z));
    bool same_materials = a->count == b->count;
    for (uint32_t i = 0; same_materials && i < a->count; i++) {
        material_t x = s->materials[s->prim_material[i]], y = r->materials[r->prim_material[i]];
        same_materials = memcmp(&x, &y, sizeof x) == 0;
    }
    CHECK_MSG(same_materials, "%s: per-primitive materials differ", file);
    /* pp stays pp: the same smooth primitives with the same normals (the hash covers them too). */
    bool same_smooth = a->count == b->count && (s->normals != NULL) == (r->normals != NULL);
    for (uint32_t i = 0; same_smooth && i < a->count; i++) same_smooth = scene_prim_smooth(s, i) == scene_prim_smooth(r, i);
    CHECK_MSG(same_smooth, "%s: smooth (pp) primitives differ", file);
    CHECK(memcmp(&a->box, &b->box, sizeof a->box) == 0);
    printf("round trip %s: %u primitives\n", file, b->count);
    scene_free(r);
}

/* Every kind, with floats that %g would round: a round trip must be exact. */
static scene_t *build_mixed_scene(void)
{
    scene_t *s = scene_new("mixed");
    prims_t *p = &s->prims;
    const float odd[] = {0.1f, 1.0f / 3.0f, -123456.789f, 1e-7f, 9.8765432e8f /* near SCENE_COORD_MAX */, -0.0f, 1e-40f /* denormal */, 2.7182817f};
    uint32_t v[8];
    for (int i = 0; i < 8; i++) v[i] = prims_add_vertex(p, v3(odd[i], odd[(i + 3) % 8], (float)i * 0.7f));
    prims_add_triangle(p, v[0], v[1], v[2]);
    prims_add_triangle(p, v[2], v[1], v[3]); /* shares two vertices */
    prims_add_triangle(p, v[4], v[4], v[5]); /* degenerate, but a mesh may have it */
    uint16_t m0 = scene_add_material(s, (material_t){v3(0.1f, 0.2f, 0.3f), 0.45f, 0.55f, 0.0f, 1.0f});
    scene_set_material_upto(s, m0);
    prims_add_sphere(p, v3(odd[0], odd[1], odd[2]), 1.0f / 7.0f);
    prims_add_cone(p, v3(0, 0, 0), 0.3f, v3(0.1f, 0.2f, 1.0f / 3.0f), 0.0f);
    prims_add_cone(p, v3(1, 1, 1), 0.25f, v3(1, 1, 2), 0.25f);
    uint16_t m1 = scene_add_material(s, (material_t){v3(1.0f / 3.0f, 0.9f, 0.7f), 0.5f, 0.5f, 0.25f, 1.5f});
    scene_set_material_upto(s, m1);
    uint32_t quad[4] = {v[0], v[1], v[3], v[2]};
    prims_add_polygon(p, quad, 4);
    uint32_t base = p->nverts;
    const float l[6][2] = {{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}}; /* concave */
    for (int i = 0; i < 6; i++) prims_add_vertex(p, v3(l[i][0] * 0.1f, l[i][1] * 0.1f, 0.3f));
    uint32_t lidx[6] = {base, base + 1, base + 2, base + 3, base + 4, base + 5};
    prims_add_polygon(p, lidx, 6);
    /* A smooth (pp) concave polygon and a smooth triangle; the other triangles stay flat. */
    for (int i = 0; i < 6; i++) scene_set_vertex_normal(s, base + (uint32_t)i, v3(0.1f * (float)i, 0.2f, 1.0f));
    uint32_t t0 = p->nverts;
    for (int i = 0; i < 3; i++) prims_add_vertex(p, v3((float)i, 1.0f / 3.0f, 0.7f * (float)(i == 1)));
    prims_add_triangle(p, t0, t0 + 1, t0 + 2);
    for (int i = 0; i < 3; i++) scene_set_vertex_normal(s, t0 + (uint32_t)i, v3(0.0f, (float)i - 1.0f, 2.0f));
    scene_set_material_upto(s, m0);
    scene_add_light(s, v3(0.1f, 10, 1.0f / 3.0f));
    s->background = v3(0.078f, 0.361f, 0.753f);
    s->camera = (camera_t){v3(5, 0.1f, 3), v3(0, 0, 0), v3(0, 0, 1), 37.5f, 1e-3f, 640, 480};
    if (scene_finish(s, true, err, sizeof err) != 0) {
        fprintf(stderr, "mixed scene: %s\n", err);
        exit(2);
    }
    return s;
}

static void test_round_trips(void)
{
    scene_t *s = build_mixed_scene();
    round_trip(s, "mixed.nff");
    scene_free(s);

    const char *names[] = {"spd:balls:2", "spd:teapot:3", "dragon"};
    for (int i = 0; i < 3; i++) {
        s = scene_load(names[i], err, sizeof err);
        if (!s && strstr(err, "install the Debian package")) {
            printf("skipped %s round trip: %s\n", names[i], err);
            continue;
        }
        CHECK_MSG(s != NULL, "%s: %s", names[i], err);
        if (!s) continue;
        if (i == 1) { /* the teapot's patches are smooth, its checkerboard is not */
            uint32_t smooth = 0;
            for (uint32_t k = 0; k < s->prims.count; k++) smooth += scene_prim_smooth(s, k);
            CHECK_MSG(smooth == s->prims.count - 9, "teapot:3: %u of %u primitives smooth, expected all but the 9 squares",
                      smooth, s->prims.count);
        }
        round_trip(s, i == 0 ? "balls2.nff" : i == 1 ? "teapot3.nff" : "dragon.nff");
        scene_free(s);
    }
}

/* A gzipped NFF reads through compressed.h like a plain one. */
static void test_gzip(void)
{
    char path[512], cmd[1200];
    scene_t *s = load_text("gz.nff", every_entity, path, sizeof path);
    uint64_t want = s ? scene_geometry_hash(s) : 0;
    scene_free(s);
    snprintf(cmd, sizeof cmd, "gzip -f '%s' 2>/dev/null", path);
    if (system(cmd) != 0) {
        printf("skipped the gzip test: no gzip\n");
        return;
    }
    strcat(path, ".gz");
    s = scene_load_nff("gz", path, err, sizeof err);
    CHECK_MSG(s != NULL, "%s", err);
    if (s) CHECK(scene_geometry_hash(s) == want && s->prims.count == 10);
    scene_free(s);
}

/* -------------------------------------------------------------- errors */

typedef struct {
    const char *text;
    int line;
    const char *want;
} bad_case;

static const bad_case bad_cases[] = {
    {"s 0 0 0 1\nq 1 2 3\n", 2, "unknown keyword 'q'"},
    {"p 4\n0 0 0\nx 1 0\n1 1 0\n0 1 0\n", 3, "expected a number in 'p 4' vertex 2, got 'x'"},
    {"s 0 0 0 1\nc 0 0 0 1\n0 0", 3, "unexpected end of file in 'c'"},
    {"c\n0 0 0 1\n0 0 1\n\n\n", 3, "unexpected end of file in 'c'"},
    {"s 0 0 0 1\n\np 0\n", 3, "at least 3 vertices"},
    {"p 1\n0 0 0\n", 1, "at least 3 vertices"},
    {"s 1 1 1 1\np 2\n0 0 0\n1 1 1\n", 2, "at least 3 vertices"},
    {"p 4\n0 0 0\n0 0 0\n1 1 1\n1 1 1\n", 1, "distinct"},
    {"s 0 0 nan 1\n", 1, "not a finite number"},
    {"s 0 0 0 1\ns 0 0 0\ninf\n", 3, "not a finite number"},
    {"s 0 0 1e39 1\n", 1, "out of float range"},
    {"s 0 0 0 -1\n", 1, "sphere radius"},
    {"s 0 0 0 1\n\ns 0 0 0 0\n", 3, "sphere radius"},
    {"v\nfrom 0 0 5\nup 0 0 1\nat 0 0 0\n", 3, "expected 'at' in 'v' (line 1), got 'up'"},
    {"b 0 0 0\nv\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\ns 0 0 0 1\n", 8, "expected 'resolution'"},
    {"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 512\n", 7, "unexpected end of file"},
    {"v\nfrom 0 0 5\nat 0 0 0\nup 0 0 1\nangle 45\nhither 1\nresolution 512 512\n", 1, "along the view direction"},
    {"s 0 0 0 1\np 20000000\n", 2, "absurd"},
    {"p 3.5\n", 1, "expected a vertex count"},
    {"s 0 0 0 1 2\n", 1, "unexpected number '2'"},
    {"c 0 0 0 1 0 0 1 -1\n", 1, "mixed signs"},
    {"c 0 0 0 1 0 0 0 1\n", 1, "same point"},
    {"c 0 0 0 0 0 0 1 0\n", 1, "both radii zero"},
    {"s 0 0 0 1 # comment 1 2 3\n# q\n  1\n", 3, "unexpected number '1'"},
    {"l 1 2 3 0.5 0.5\n", 1, "unexpected end of file in 'l'"},
    {"pp 3\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 x\n", 4, "in 'pp 3' vertex 3, got 'x'"},
    {"s 0 0 0 1\nv\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 9 9\n"
     "v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 45\nhither 1\nresolution 9 9\n", 9, "a second 'v'"},
    {"v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 180\nhither 1\nresolution 9 9\n", 5, "view angle"},
    {"s 0 0 0 1\nf 1 1 1 1 1\n", 2, "unexpected end of file in 'f'"},
    {"s\x01 0 0 0 1\n", 1, "unknown keyword 's?'"},
};

/* The error must be "PATH:LINE: ..." with the expected line and text. */
static void test_errors(void)
{
    char path[512], prefix[600];
    for (size_t i = 0; i < sizeof bad_cases / sizeof bad_cases[0]; i++) {
        const bad_case *b = &bad_cases[i];
        char file[32];
        snprintf(file, sizeof file, "bad%zu.nff", i);
        scene_t *s = load_text(file, b->text, path, sizeof path);
        CHECK_MSG(s == NULL, "case %zu loaded", i);
        scene_free(s);
        snprintf(prefix, sizeof prefix, "%s:%d: ", path, b->line);
        CHECK_MSG(strncmp(err, prefix, strlen(prefix)) == 0, "case %zu: '%s' does not start with '%s'", i, err, prefix);
        CHECK_MSG(strstr(err, b->want) != NULL, "case %zu: '%s' lacks '%s'", i, err, b->want);
        CHECK_MSG(strchr(err, '\n') == NULL, "case %zu: more than one line", i);
        if (getenv("NFF_SHOW_ERRORS")) printf("%s\n", err);
    }
    /* Nothing to trace: the path and "no primitives". */
    const char *empty[] = {"", "# only a comment\n\n", "b 1 1 1\nl 1 1 1\n"};
    for (int i = 0; i < 3; i++) {
        scene_t *s = load_text("empty.nff", empty[i], path, sizeof path);
        CHECK(s == NULL);
        scene_free(s);
        CHECK_MSG(strncmp(err, path, strlen(path)) == 0 && strstr(err, "no primitives"), "'%s'", err);
    }
    tmp_path(path, sizeof path, "missing.nff");
    CHECK(scene_load_nff("missing", path, err, sizeof err) == NULL);
    CHECK_MSG(strstr(err, path) != NULL, "'%s'", err);
    scene_t *s = build_mixed_scene();
    CHECK(scene_write_nff(s, "/nonexistent-dir/x.nff", err, sizeof err) != 0);
    CHECK_MSG(strncmp(err, "/nonexistent-dir/x.nff: ", 24) == 0, "'%s'", err);
    scene_free(s);
}

/* ---------------------------------------------------------------- fuzz */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;

static uint32_t rng(void) /* xorshift64*: deterministic across runs */
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return (uint32_t)((rng_state * 2685821657736338717ull) >> 32);
}

static const char *fuzz_seed_text =
    "b 0.078 0.361 0.753\nv\nfrom 2.1 1.3 1.7\nat 0 0 0\nup 0 0 1\nangle 45\nhither 0.01\nresolution 512 512\n"
    "l 4 3 2\nl 1 -4 4 1 1 1\nf 1 0.75 0.33 0.8 0 100000 0 1\n"
    "p 4\n12 12 -0.5\n-12 12 -0.5\n-12 -12 -0.5\n12 -12 -0.5\n"
    "f 1 0.9 0.7 0.5 0.5 3.0827 0 1\ns 0 0 0 0.5\ns 0.272166 0.272166 0.544331 0.166667\n"
    "c 0 0 0 0.15 0 0 1 0.1005\nc\n1 1 1 -0.3\n1 1 3 -0.2\n"
    "pp 3\n0 0 1 0 0 1\n1 0 1 0 0 1\n0 1 1 0 0 1\n"
    "p 6 # L\n0 0 5\n2 0 5\n2 1 5\n1 1 5\n1 2 5\n0 2 5\n";

/* Tokens that poke at the number parser and the count limits. */
static const char *fuzz_words[] = {"nan", "inf", "1e39", "-0", "99999999", "p", "pp", "c", "v", "#", "\n", "0x1p3",
                                   "1e-45", "-", "4294967297", "from", "\0"};

static size_t mutate(char *buf, size_t n, size_t cap)
{
    size_t at = n ? rng() % n : 0;
    switch (rng() % 8) {
    case 0: /* truncate */
        return at;
    case 1: /* one byte changed */
        if (n) buf[at] = (char)(rng() & 0xff);
        return n;
    case 2: /* one byte deleted */
        if (n) memmove(buf + at, buf + at + 1, n - at - 1);
        return n ? n - 1 : 0;
    case 3:
    case 4:
    case 5: { /* a digit changed: keeps the file mostly valid */
        static const char digits[] = "0123456789.-e ";
        if (n) buf[at] = digits[rng() % (sizeof digits - 1)];
        return n;
    }
    default: { /* a word inserted */
        const char *w = fuzz_words[rng() % (sizeof fuzz_words / sizeof fuzz_words[0])];
        size_t wl = strlen(w) ? strlen(w) : 1; /* the empty word "\0" inserts a NUL byte */
        if (n + wl + 1 > cap) return n;
        memmove(buf + at + wl, buf + at, n - at);
        memcpy(buf + at, w, wl);
        return n + wl;
    }
    }
}

static void test_fuzz(int runs)
{
    char path[512];
    tmp_path(path, sizeof path, "fuzz.nff");
    size_t seed_len = strlen(fuzz_seed_text), cap = 2 * seed_len + 256;
    char *buf = malloc(cap);
    int loaded = 0, failed = 0, bad_errors = 0;
    for (int i = 0; i < runs; i++) {
        memcpy(buf, fuzz_seed_text, seed_len);
        size_t n = seed_len;
        int edits = 1 + (int)(rng() % 4);
        for (int e = 0; e < edits; e++) n = mutate(buf, n, cap);
        write_file(path, buf, n);
        err[0] = '\0';
        scene_t *s = scene_load_nff("fuzz", path, err, sizeof err);
        if (s) {
            loaded++;
            if (s->prims.count == 0) bad_errors++;
            scene_free(s);
        } else {
            failed++;
            if (!err[0] || strncmp(err, path, strlen(path)) != 0 || strchr(err, '\n')) {
                bad_errors++;
                fprintf(stderr, "fuzz run %d: bad error '%s'\n", i, err);
            }
        }
    }
    free(buf);
    CHECK(loaded + failed == runs);
    CHECK(bad_errors == 0);
    CHECK(loaded > 0 && failed > 0); /* the mutations exercise both paths */
    printf("fuzz: %d mutations, %d loaded, %d rejected\n", runs, loaded, failed);
}

int main(void)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/accelbench_test_nff.%d", (int)getpid());
    mkdir(tmpdir, 0755);
    test_every_entity();
    test_defaults();
    test_round_trips();
    test_gzip();
    test_errors();
    const char *env = getenv("NFF_FUZZ");
    test_fuzz(env && atoi(env) > 0 ? atoi(env) : 300);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmpdir);
    return check_report();
}
