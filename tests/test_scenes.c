/* test_scenes.c: scene loading and generation.
 *
 * The SPD sphereflake against the counts of shared/SPD-SCENES.md and
 * coordinates derived by hand from its rules; mesh loading through assimp
 * (a catalogue mesh, OBJ and glTF files written here, gzipped and inside
 * a tarball);
 * and the one-line errors for bad input, which must name the file; the
 * scene path (repository meshes found by file name, the message when one
 * is absent), named views and view specs (NAME@VIEW, --view's parser);
 * reading files: only regular ones, within the memory cap. */
#include "../scenes/compressed.h"
#include "../scenes/memory_cap.h"
#include "../scenes/scene.h"
#include "check.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define TMP "/tmp/accelbench_test_scenes"

static char err[1024];

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    if (!f) {
        perror(path);
        exit(2);
    }
    fputs(text, f);
    fclose(f);
}

static bool vec_near(vec3 a, double x, double y, double z, double eps)
{
    return fabs(a.x - x) <= eps && fabs(a.y - y) <= eps && fabs(a.z - z) <= eps;
}

/* Load a name that must fail; the error must contain want. */
static void expect_error(const char *name, const char *want)
{
    err[0] = '\0';
    scene_t *s = scene_load(name, err, sizeof err);
    CHECK_MSG(s == NULL, "%s loaded but should fail", name);
    CHECK_MSG(strstr(err, want) != NULL, "%s: error '%s' lacks '%s'", name, err, want);
    CHECK_MSG(strchr(err, '\n') == NULL, "error is not one line: '%s'", err);
    scene_free(s);
}

static void test_balls_counts(void)
{
    static const uint32_t spheres[] = {0, 10, 91, 820, 7381, 66430};
    for (int size = 1; size <= 5; size++) {
        char name[32];
        snprintf(name, sizeof name, "spd:balls:%d", size);
        scene_t *s = scene_load(name, err, sizeof err);
        CHECK_MSG(s != NULL, "%s: %s", name, err);
        if (!s) continue;
        CHECK(spd_balls_sphere_count(size) == spheres[size]);
        CHECK(s->prims.nspheres == spheres[size]);
        CHECK(s->prims.npolygons == 1 && s->prims.ntris == 0);
        CHECK(s->prims.count == spheres[size] + 1); /* SPD's count: spheres + 1 floor quad */
        CHECK(strcmp(s->name, name) == 0);
        CHECK(s->source[0] != '\0');
        scene_free(s);
    }
    scene_t *s = scene_load("spd:balls", err, sizeof err); /* default size 4 */
    CHECK_MSG(s != NULL, "%s", err);
    if (s) CHECK(s->prims.nspheres == 7381 && s->prims.count == 7382);
    scene_free(s);
}

static void test_balls_geometry(void)
{
    scene_t *s = scene_load("spd:balls:1", err, sizeof err);
    CHECK_MSG(s != NULL, "%s", err);
    if (!s) return;
    const prims_t *p = &s->prims;

    /* The floor comes first: one quad polygon, corners in the SPD's order. */
    CHECK(p->kind[0] == PRIM_POLYGON && p->kind[1] == PRIM_SPHERE);
    const polygon_t *floor_poly = &p->polygons[p->index[0]];
    CHECK(floor_poly->count == 4);
    if (floor_poly->count == 4) {
        const uint32_t *fv = &p->poly_verts[floor_poly->first];
        CHECK(vec_near(p->verts[fv[0]], 12, 12, -0.5, 0));
        CHECK(vec_near(p->verts[fv[1]], -12, 12, -0.5, 0));
        CHECK(vec_near(p->verts[fv[2]], -12, -12, -0.5, 0));
        CHECK(vec_near(p->verts[fv[3]], 12, -12, -0.5, 0));
    }
    CHECK(p->ndegenerate == 0);

    /* Root: centre 0, radius 0.5. */
    sphere_t root = p->spheres[p->index[1]];
    CHECK(vec_near(root.center, 0, 0, 0, 0));
    CHECK_NEAR(root.radius, 0.5, 0);

    /* First child of the root. The first trio vector (1,1,0)/sqrt2 turned
     * about a = (1,-1,0)/sqrt2 by asin(2/sqrt6) (cos = 1/sqrt3): a.v = 0 and
     * a x v = (0,0,1), so Rodrigues gives v/sqrt3 + (0,0,1)*2/sqrt6 =
     * (1,1,2)/sqrt6. The k=0 copy is not turned, and the root's M is the
     * identity, so the child sits at (1,1,2)/sqrt6 * (0.5 + 0.5/3)
     * = (2,2,4)/(3 sqrt6) = (0.272166, 0.272166, 0.544331), radius 1/6. */
    double k = 2.0 / (3.0 * sqrt(6.0));
    sphere_t c0 = p->spheres[p->index[2]];
    CHECK(vec_near(c0.center, k, k, 2 * k, 1e-5));
    CHECK_NEAR(c0.radius, 1.0 / 6.0, 1e-6);
    /* Second child: (1,0,-1)/sqrt2 turned the same way. a.v = 1/2,
     * a x v = (1,1,1)/2, so v/sqrt3 + (1,1,1)/2*sqrt(2/3) + a/2*(1 - 1/sqrt3)
     * = (cos 15deg, sin 15deg, 0): on the equator, at distance 2/3. */
    double c15 = cos(M_PI / 12), s15 = sin(M_PI / 12);
    CHECK(vec_near(p->spheres[p->index[3]].center, c15 * 2 / 3, s15 * 2 / 3, 0, 1e-5));
    /* Third: (0,1,-1)/sqrt2, the mirror image: (sin 15, cos 15, 0). */
    CHECK(vec_near(p->spheres[p->index[4]].center, s15 * 2 / 3, c15 * 2 / 3, 0, 1e-5));
    /* Fourth: the first turned 120 degrees about +Z: azimuth 165 degrees,
     * horizontal length sqrt(2)/sqrt(6) * 2/3, same height. */
    double h = sqrt(2.0) / sqrt(6.0) * 2 / 3;
    CHECK(vec_near(p->spheres[p->index[5]].center, h * cos(165 * M_PI / 180), h * sin(165 * M_PI / 180), 2 * k, 1e-5));
    /* All 9 children touch the root and have radius 1/6. */
    for (int i = 0; i < 9; i++) {
        sphere_t c = p->spheres[p->index[2 + i]];
        CHECK_NEAR(v3_len(c.center), 0.5 + 1.0 / 6.0, 1e-6);
        CHECK_NEAR(c.radius, 1.0 / 6.0, 1e-7);
    }

    /* View, lights, background, materials. */
    const camera_t *cam = &s->camera;
    CHECK(vec_near(cam->from, 2.1, 1.3, 1.7, 1e-6) && vec_near(cam->at, 0, 0, 0, 0) && vec_near(cam->up, 0, 0, 1, 0));
    CHECK(cam->fov_deg == 45.0f && cam->width == 512 && cam->height == 512);
    CHECK_NEAR(cam->hither, 0.01, 1e-9);
    CHECK(s->nlights == 3);
    if (s->nlights == 3)
        CHECK(vec_near(s->lights[0], 4, 3, 2, 0) && vec_near(s->lights[1], 1, -4, 4, 0) && vec_near(s->lights[2], -3, 1, 5, 0));
    CHECK(vec_near(s->background, 0.078, 0.361, 0.753, 1e-6));
    CHECK(s->nmaterials == 2);
    const material_t *fm = &s->materials[s->prim_material[0]], *sm = &s->materials[s->prim_material[1]];
    CHECK(vec_near(fm->color, 1, 0.75, 0.33, 1e-6) && fm->kd == 0.8f && fm->ks == 0.0f);
    CHECK(vec_near(sm->color, 1, 0.9, 0.7, 1e-6) && sm->kd == 0.5f && sm->ks == 0.5f);
    CHECK(s->prim_material[10] == s->prim_material[1]);
    scene_free(s);

    /* Depth-first order: in balls 2, id 2 is the root's first child and id 3
     * is that child's first child. Its M turns +Z to d = (1,1,2)/sqrt6 about
     * a = (-1,1,0)/sqrt2 by acos(2/sqrt6); a.d = 0, a x d = (1,1,-1)/sqrt3, so
     * M d = d*(2/sqrt6) + (1,1,-1)/sqrt3 * (1/sqrt3) = (2,2,1)/3. Radius
     * 1/18, at distance 1/6 + 1/18 = 2/9 from the child's centre. */
    s = scene_load("spd:balls:2", err, sizeof err);
    CHECK_MSG(s != NULL, "%s", err);
    if (!s) return;
    p = &s->prims;
    sphere_t g = p->spheres[p->index[3]];
    CHECK(vec_near(g.center, k + 2.0 / 3 * 2 / 9, k + 2.0 / 3 * 2 / 9, 2 * k + 1.0 / 3 * 2 / 9, 1e-5));
    CHECK_NEAR(g.radius, 1.0 / 18.0, 1e-7);
    /* After the first child's 9 children (ids 3..11), id 12 is the root's second child. */
    CHECK_NEAR(p->spheres[p->index[12]].radius, 1.0 / 6.0, 1e-7);
    CHECK(vec_near(p->spheres[p->index[12]].center, c15 * 2 / 3, s15 * 2 / 3, 0, 1e-5));
    scene_free(s);
}

static void test_balls_tessellated(void)
{
    scene_t *s = scene_load("spd:balls:2:t3", err, sizeof err);
    CHECK_MSG(s != NULL, "%s", err);
    if (s) {
        CHECK(s->prims.ntris == 91 * 108 + 2 && s->prims.count == 9830 && s->prims.nspheres == 0);
        CHECK(s->prims.nverts == 4 + 91 * 56); /* 6*3^2 + 2 shared vertices per sphere */
        CHECK(s->prims.ndegenerate == 0);
    }
    scene_free(s);

    s = scene_load("spd:balls:1:t", err, sizeof err); /* default resolution 3 */
    CHECK_MSG(s != NULL, "%s", err);
    if (s) {
        const prims_t *p = &s->prims;
        CHECK(p->ntris == 10 * 108 + 2);
        /* The root's triangles: vertices on the sphere, wound outward. */
        int on = 0, out = 0;
        for (uint32_t id = 2; id < 2 + 108; id++) {
            const tri_t *t = &p->tris[p->index[id]];
            vec3 a = p->verts[t->v[0]], b = p->verts[t->v[1]], c = p->verts[t->v[2]];
            on += fabsf(v3_len(a) - 0.5f) < 1e-6f && fabsf(v3_len(b) - 0.5f) < 1e-6f && fabsf(v3_len(c) - 0.5f) < 1e-6f;
            vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
            out += v3_dot(n, v3_add(v3_add(a, b), c)) > 0;
        }
        CHECK(on == 108 && out == 108);
        /* Cube corners are grid points: (1,1,1)/sqrt3 is a vertex. */
        bool corner = false;
        for (uint32_t v = 4; v < 4 + 56; v++)
            corner |= vec_near(p->verts[v], 0.5 / sqrt(3), 0.5 / sqrt(3), 0.5 / sqrt(3), 1e-6);
        CHECK(corner);
    }
    scene_free(s);

    s = scene_load("spd:balls:3:t1", err, sizeof err); /* a cube per sphere */
    CHECK_MSG(s != NULL, "%s", err);
    if (s) CHECK(s->prims.ntris == 820 * 12 + 2 && s->prims.nverts == 4 + 820 * 8);
    scene_free(s);
}

static void test_catalogue_bunny(void)
{
    scene_t *s = scene_load("bunny", err, sizeof err);
    CHECK_MSG(s != NULL, "bunny: %s", err);
    if (!s) return;
    CHECK(s->prims.ntris == 75408 && s->prims.count == 75408 && s->prims.nspheres == 0);
    CHECK(s->prims.nverts == 37706);
    CHECK(v3_finite(s->bounds.lo) && v3_finite(s->bounds.hi) && !box_is_empty(s->bounds));
    CHECK(strcmp(s->name, "bunny") == 0 && strstr(s->source, "bunny00.off") != NULL);
    /* Defaults: camera and lights outside the bounds, one grey material. */
    box3 b = s->bounds;
    vec3 f = s->camera.from;
    CHECK(!(f.x >= b.lo.x && f.x <= b.hi.x && f.y >= b.lo.y && f.y <= b.hi.y && f.z >= b.lo.z && f.z <= b.hi.z));
    CHECK(vec_near(s->camera.at, box_center(b).x, box_center(b).y, box_center(b).z, 1e-6));
    CHECK(s->camera.hither > 0 && s->camera.hither < 0.01f * box_diagonal(b));
    CHECK(s->camera.width == 512 && s->camera.fov_deg == 45.0f);
    CHECK(s->nlights == 2);
    for (uint32_t i = 0; i < s->nlights; i++) {
        vec3 l = s->lights[i];
        CHECK(v3_len(v3_sub(l, box_center(b))) > 0.5f * box_diagonal(b));
    }
    CHECK(s->nmaterials == 1 && s->materials[0].kd == 0.8f && s->materials[0].ks == 0.2f);
    CHECK(s->prim_material[0] == 0 && s->prim_material[75407] == 0);
    scene_free(s);

    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    scene_catalogue_print(m);
    fclose(m);
    CHECK(strstr(buf, "spd:balls") && strstr(buf, "\nbunny ") && strstr(buf, "libcgal-demo") && strstr(buf, "glmark2-data"));
    free(buf);
}

/* A quad, a triangle, a degenerate triangle and a line. */
static const char *small_obj =
    "# test mesh\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
    "f 1 2 3 4\n"
    "f 1 2 5\n"
    "f 1 1 1\n"
    "l 1 5\n";

static void check_small_obj(const char *name)
{
    scene_t *s = scene_load(name, err, sizeof err);
    CHECK_MSG(s != NULL, "%s: %s", name, err);
    if (!s) return;
    CHECK_MSG(s->prims.ntris == 4 && s->prims.count == 4, "%s: %u triangles", name, s->prims.ntris);
    CHECK(s->prims.ndegenerate == 1);
    CHECK(vec_near(s->bounds.lo, 0, 0, 0, 0) && vec_near(s->bounds.hi, 1, 1, 1, 0));
    CHECK_MSG(strstr(s->source, "1 point/line faces skipped") != NULL, "source '%s'", s->source);
    CHECK(strcmp(s->name, name) == 0);
    scene_free(s);
}

static void test_files(void)
{
    write_file(TMP "/small.obj", small_obj);
    check_small_obj(TMP "/small.obj");
    check_small_obj("file:" TMP "/small.obj");
    CHECK(system("gzip -c " TMP "/small.obj > " TMP "/small.obj.gz") == 0);
    check_small_obj(TMP "/small.obj.gz");
    CHECK(system("mkdir -p " TMP "/t/sub && cp " TMP "/small.obj " TMP "/small.obj.gz " TMP "/t/sub/ && "
                 "tar -C " TMP "/t -czf " TMP "/meshes.tar.gz sub") == 0);
    check_small_obj(TMP "/meshes.tar.gz#sub/small.obj");
    check_small_obj(TMP "/meshes.tar.gz#sub/small.obj.gz");
    expect_error(TMP "/meshes.tar.gz#sub/nothere.obj", "no member sub/nothere.obj in " TMP "/meshes.tar.gz");

    /* An OBJ whose .mtl is missing, with "usemtl" before any object: assimp
     * logs errors about both but reads the geometry, so it loads. */
    write_file(TMP "/nomtl.obj", "mtllib nothere.mtl\nusemtl red\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    scene_t *s = scene_load(TMP "/nomtl.obj", err, sizeof err);
    CHECK_MSG(s && s->prims.ntris == 1, "nomtl.obj: %s", err);
    scene_free(s);
}

/* glTF with its buffer in a separate .bin: assimp must find the buffer
 * beside the .gltf, on disk and inside an archive, whatever the current
 * directory. One triangle (0,0,0) (2,0,0) (0,3,0). */
static void test_gltf(void)
{
    static const unsigned char bin[44] = {
        0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,          /* (0,0,0) */
        0, 0, 0, 0x40, 0, 0, 0, 0, 0, 0, 0, 0,       /* (2,0,0) */
        0, 0, 0, 0, 0, 0, 0x40, 0x40, 0, 0, 0, 0,    /* (0,3,0) */
        0, 0, 1, 0, 2, 0, 0, 0};                     /* uint16 indices 0 1 2, padding */
    CHECK(system("mkdir -p " TMP "/g/m") == 0);
    FILE *f = fopen(TMP "/g/m/tri.bin", "wb");
    if (!f) return;
    fwrite(bin, 1, sizeof bin, f);
    fclose(f);
    write_file(TMP "/g/m/tri.gltf",
               "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
               "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
               "\"buffers\":[{\"uri\":\"tri.bin\",\"byteLength\":44}],"
               "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":6}],"
               "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\",\"min\":[0,0,0],\"max\":[2,3,0]},"
               "{\"bufferView\":1,\"componentType\":5123,\"count\":3,\"type\":\"SCALAR\"}]}");
    CHECK(system("gzip -kf " TMP "/g/m/tri.gltf && tar -C " TMP "/g -czf " TMP "/g.tar.gz m") == 0);
    const char *names[] = {TMP "/g/m/tri.gltf", TMP "/g/m/tri.gltf.gz", TMP "/g.tar.gz#m/tri.gltf"};
    for (int i = 0; i < 3; i++) {
        scene_t *s = scene_load(names[i], err, sizeof err);
        CHECK_MSG(s != NULL, "%s: %s", names[i], err);
        if (!s) continue;
        CHECK(s->prims.ntris == 1 && s->prims.nverts == 3);
        CHECK(vec_near(s->bounds.lo, 0, 0, 0, 0) && vec_near(s->bounds.hi, 2, 3, 0, 0));
        scene_free(s);
    }
}

static void test_errors(void)
{
    expect_error(TMP "/missing.obj", TMP "/missing.obj: No such file or directory");
    expect_error("/nonexistent/data.tar.gz#a.off", "/nonexistent/data.tar.gz: No such file or directory");
    expect_error("nosuchscene", "unknown scene 'nosuchscene' (see: accelbench list scenes)");
    expect_error("spd:cubes", "unknown SPD database 'cubes'");
    expect_error("spd:balls:99", "spd:balls:99: size must be 1..7");
    expect_error("spd:balls:0", "size must be 1..7");
    expect_error("spd:balls:x", "size must be 1..7");
    expect_error("spd:balls:2:t99", "resolution must be 1..64");
    expect_error("spd:balls:2:q", "spd:balls:2:q");

    /* Garbage: bytes that are no mesh. As OBJ assimp reads nothing. */
    char junk[4096];
    for (size_t i = 0; i < sizeof junk - 1; i++) junk[i] = (char)(1 + (i * 7919 + 13) % 251);
    junk[sizeof junk - 1] = '\0';
    write_file(TMP "/garbage.obj", junk);
    expect_error(TMP "/garbage.obj", TMP "/garbage.obj");
    write_file(TMP "/garbage.off", junk);
    expect_error(TMP "/garbage.off", TMP "/garbage.off: assimp:");
    write_file(TMP "/words.obj", "hello world\nthis is not a mesh\n");
    expect_error(TMP "/words.obj", TMP "/words.obj: no primitives");
    write_file(TMP "/empty.obj", "");
    expect_error(TMP "/empty.obj", TMP "/empty.obj: empty file");

    /* Truncated OFF, cut in the vertices and in the faces (assimp 5.2 would
     * assert in Triangulate on these if the loader did not check first). */
    /* Truncated OFF, cut in the vertices, between faces and inside a face.
     * assimp 5.2 would assert in Triangulate on the first two, and read the
     * missing index of the third as 0, so the loader checks OFF itself. */
    write_file(TMP "/trunc1.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n");
    expect_error(TMP "/trunc1.off", TMP "/trunc1.off: ends after 2 of 4 vertices");
    write_file(TMP "/trunc2.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n");
    expect_error(TMP "/trunc2.off", TMP "/trunc2.off: ends after 1 of 2 faces");
    write_file(TMP "/trunc3.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2");
    expect_error(TMP "/trunc3.off", TMP "/trunc3.off: line 8: face 1 needs 3 vertex indices");
    write_file(TMP "/trunc4.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1\n");
    expect_error(TMP "/trunc4.off", TMP "/trunc4.off: line 5: vertex 2 needs 3 coordinates");
    /* assimp would clamp the index to the last vertex and carry on. */
    write_file(TMP "/badindex.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    expect_error(TMP "/badindex.off", TMP "/badindex.off: line 6: face 0 uses vertex 7 of 3");
    /* assimp's OBJ reader logs and drops an empty face: the log fails the load. */
    write_file(TMP "/emptyface.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf\n");
    expect_error(TMP "/emptyface.obj", TMP "/emptyface.obj: assimp: Obj: Ignoring empty face");
    /* Comments, blank lines and the counts on the header line are fine. */
    write_file(TMP "/good.off", "OFF 4 2 0\n# corners\n\n0 0 0\n1 0 0\n1 1 0\n0 1 0 # last\n3 0 1 2\n3 0 2 3\n");
    scene_t *s = scene_load(TMP "/good.off", err, sizeof err);
    CHECK_MSG(s && s->prims.ntris == 2 && s->prims.nverts == 4, "good.off: %s", err);
    scene_free(s);

    /* assimp hangs on a PLY header cut before end_header, and crashes on a
     * mesh without faces (a point cloud); both are caught first. */
    write_file(TMP "/cut.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n");
    expect_error(TMP "/cut.ply", TMP "/cut.ply: the PLY header has no end_header line");
    write_file(TMP "/points.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                  "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n");
    expect_error(TMP "/points.ply", TMP "/points.ply: mesh 0 has 3 vertices but no faces");
    /* A misspelt header line: assimp skips it and reads the body against
     * the header it misunderstood (past its own buffers, ASan saw). */
    write_file(TMP "/misspelt.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                    "propefrty float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                    "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    expect_error(TMP "/misspelt.ply",
                 TMP "/misspelt.ply: line 6: 'propefrty' is not a PLY header keyword (ply, format, element, property, "
                     "comment, obj_info, end_header)");

    write_file(TMP "/nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    expect_error(TMP "/nan.obj", TMP "/nan.obj: vertex 1 of mesh 0 has a NaN");
    write_file(TMP "/badindex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    expect_error(TMP "/badindex.obj", TMP "/badindex.obj: assimp:");
}

/* compressed_read on path: -1 with want in its message. */
static void expect_read_error(const char *path, const char *want)
{
    file_data_t f;
    err[0] = '\0';
    int rc = compressed_read(path, &f, err, sizeof err);
    CHECK_MSG(rc == -1 && strstr(err, want), "%s: rc %d, '%s' (want '%s')", path, rc, err, want);
    if (rc == 0) compressed_free(&f);
}

/* Only regular files are read (a FIFO without a writer would block the
 * open for ever: the alarm fails the test instead), and what is read,
 * decompressed, stays within the memory cap: a gzip of 16 MiB of zeros
 * stops at a cap of 4 MiB, and reads whole at 16 (the cap itself fits). */
static void test_read_limits(void)
{
    alarm(60);
    CHECK(mkfifo(TMP "/fifo.obj", 0600) == 0);
    expect_read_error(TMP "/fifo.obj", TMP "/fifo.obj: a FIFO (named pipe), not a regular file");
    expect_read_error("/dev/zero", "/dev/zero: a character device, not a regular file");
    expect_read_error(TMP, TMP ": a directory, not a regular file");
    CHECK(system("head -c 16777216 /dev/zero | gzip -1 > " TMP "/zeros.gz") == 0);
    memory_cap_set_mib(4);
    expect_read_error(TMP "/zeros.gz", TMP "/zeros.gz: its contents run past 4194304 bytes: stopped by the memory "
                                       "cap of 4 MiB (--memcap 4); raise it with --memcap MIB");
    memory_cap_set_mib(16);
    file_data_t f;
    CHECK_MSG(compressed_read(TMP "/zeros.gz", &f, err, sizeof err) == 0 && f.size == 16u << 20, "%s", err);
    compressed_free(&f);
    memory_cap_set_mib(0);
    char line[256];
    memory_cap_set_mib(7);
    memory_cap_stopped(line, sizeof line, "%s: x", "f");
    CHECK_MSG(!strcmp(line, "f: x: stopped by the memory cap of 7 MiB (--memcap 7); raise it with --memcap MIB"), "%s",
              line);
    memory_cap_set_mib(0);
    alarm(0);
}

/* --- the scene path and views --- */

#define SP TMP "/path"

static void test_scene_path(void)
{
    /* A one-triangle stand-in for Sibenik in the second folder of the path
     * and another for Sponza in the first: the path is searched before
     * ../shared/scenes, and in order. */
    CHECK(system("mkdir -p " SP "/a " SP "/b " SP "/empty && "
                 "printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' | xz -c > " SP "/b/sibenik.obj.xz && "
                 "printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n' | xz -c > " SP "/a/sponza.obj.xz && "
                 "cp " SP "/a/sponza.obj.xz " SP "/b/") == 0);
    /* The shared folder as this run has it (the environment may move it). */
    char shared[4096];
    const char *env_shared = getenv("ACCELBENCH_SHARED_SCENES");
    snprintf(shared, sizeof shared, "%s", env_shared ? env_shared : "/../shared/scenes");
    setenv("ACCELBENCH_SCENES", SP "/nothere::" SP "/a:" SP "/b", 1);
    char path[4096], where[4096];
    CHECK(scene_path_find("sibenik.obj.xz", path, sizeof path, where, sizeof where));
    CHECK_MSG(!strcmp(path, SP "/b/sibenik.obj.xz"), "found %s", path);
    CHECK_MSG(!strcmp(where, SP "/nothere, " SP "/a, " SP "/b"), "looked in '%s'", where);
    CHECK(scene_path_find("sponza.obj.xz", path, sizeof path, where, sizeof where));
    CHECK(!strcmp(path, SP "/a/sponza.obj.xz"));
    /* Not in the user's folders: the shared folder beside the checkout is last. */
    CHECK(!scene_path_find("nosuch.obj.xz", path, sizeof path, where, sizeof where));
    if (shared[0])
        CHECK_MSG(strstr(where, SP "/b, ") && strstr(where, shared), "looked in '%s'", where);
    else /* the defaults dropped, as on a machine without them */
        CHECK_MSG(!strcmp(where, SP "/nothere, " SP "/a, " SP "/b"), "looked in '%s'", where);

    scene_t *s = scene_load("sibenik", err, sizeof err);
    CHECK_MSG(s && s->prims.ntris == 1, "sibenik from the path: %s", err);
    if (s) CHECK(strcmp(s->source, SP "/b/sibenik.obj.xz") == 0);
    scene_free(s);
    CHECK(scene_catalogue_available("sibenik@nave", where, sizeof where) && !strcmp(where, SP "/b/sibenik.obj.xz"));
    CHECK(scene_catalogue_available("bunny", where, sizeof where));
    CHECK(!scene_catalogue_available("gen:room", where, sizeof where) && strstr(where, "not a catalogue scene"));
    CHECK(!scene_catalogue_available("sibenik@roof", where, sizeof where) && strstr(where, "unknown view 'roof'"));

    /* A machine without the meshes: the error names the file, every folder
     * searched, and the public repository and path to get it from. */
    setenv("ACCELBENCH_SCENES", SP "/empty", 1);
    setenv("ACCELBENCH_SHARED_SCENES", "", 1);
    expect_error("dragon100k", "scene 'dragon100k': dragon100k.obj.xz is not on the scene path (looked in " SP "/empty); get it from");
    expect_error("dragon100k", "github.com/nwtnni/photon, file models/dragon.obj");
    expect_error("sibenik@nave", "github.com/taqu/BoundingVolumeHierarchy, file sibenik.zip");
    expect_error("sponza", "github.com/jan-van-bergen/GPU-Raytracer, folder Data/Sponza/models");
    CHECK(!scene_catalogue_available("sibenik", where, sizeof where) && strstr(where, "sibenik.obj.xz is not on the scene path"));
    char *buf = NULL;
    size_t len = 0;
    FILE *m = open_memstream(&buf, &len);
    scene_catalogue_print(m);
    fclose(m);
    CHECK_MSG(strstr(buf, "\nsibenik          sibenik.obj.xz  [scene path, absent: from github.com/taqu") != NULL, "%s", buf);
    free(buf);
    /* The shared folder may be moved too. */
    setenv("ACCELBENCH_SCENES", "", 1);
    setenv("ACCELBENCH_SHARED_SCENES", SP "/a", 1);
    CHECK(scene_path_find("sponza.obj.xz", path, sizeof path, where, sizeof where) && !strcmp(where, SP "/a"));
    /* The user folder scripts/get-scenes.sh fills: after the shared folder,
     * when no folder replaces the defaults; $XDG_CACHE_HOME, else ~/.cache. */
    const char *env_xdg = getenv("XDG_CACHE_HOME");
    char xdg[4096];
    snprintf(xdg, sizeof xdg, "%s", env_xdg ? env_xdg : "");
    unsetenv("ACCELBENCH_SHARED_SCENES");
    CHECK(system("mkdir -p " SP "/xdg/accelbench/scenes && cp " SP "/a/sponza.obj.xz " SP
                 "/xdg/accelbench/scenes/only-cached.obj.xz") == 0);
    setenv("XDG_CACHE_HOME", SP "/xdg", 1);
    CHECK(scene_path_user_folder(path, sizeof path) && !strcmp(path, SP "/xdg/accelbench/scenes"));
    CHECK(scene_path_find("only-cached.obj.xz", path, sizeof path, where, sizeof where));
    CHECK_MSG(!strcmp(path, SP "/xdg/accelbench/scenes/only-cached.obj.xz"), "found %s", path);
    CHECK(!scene_path_find("nosuch.obj.xz", path, sizeof path, where, sizeof where));
    CHECK_MSG(strstr(where, "/../shared/scenes, " SP "/xdg/accelbench/scenes") != NULL, "looked in '%s'", where);
    setenv("XDG_CACHE_HOME", "relative", 1); /* not absolute: ignored, as the XDG rules say */
    const char *home = getenv("HOME");
    if (home && home[0] == '/') {
        char want[4096];
        snprintf(want, sizeof want, "%s/.cache/accelbench/scenes", home);
        CHECK(scene_path_user_folder(path, sizeof path) && !strcmp(path, want));
    }
    if (env_xdg)
        setenv("XDG_CACHE_HOME", xdg, 1);
    else
        unsetenv("XDG_CACHE_HOME");
    if (env_shared)
        setenv("ACCELBENCH_SHARED_SCENES", shared, 1);
    else
        unsetenv("ACCELBENCH_SHARED_SCENES");
    setenv("ACCELBENCH_SCENES", SP "/a:" SP "/b", 1);
}

static bool same_vec(vec3 a, vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

/* Named views on the stand-ins of test_scene_path (ACCELBENCH_SCENES still
 * names them): the values are the catalogue's. */
static void test_named_views(void)
{
    scene_t *s = scene_load("sibenik@nave", err, sizeof err);
    CHECK_MSG(s != NULL, "sibenik@nave: %s", err);
    if (s) {
        CHECK(same_vec(s->camera.from, v3(-18, -10, 0)) && same_vec(s->camera.at, v3(0, -11, 0)));
        CHECK(same_vec(s->camera.up, v3(0, 1, 0)) && s->camera.fov_deg == 45.0f);
        CHECK(s->nlights == 2 && same_vec(s->lights[0], v3(-6, -4, 0)) && same_vec(s->lights[1], v3(6, -3, 2)));
        CHECK(!strcmp(s->name, "sibenik@nave") && !strcmp(s->view, "nave"));
    }
    scene_free(s);
    /* The default view of sibenik is the nave: inside, never the roof. */
    s = scene_load("sibenik", err, sizeof err);
    if (s) CHECK(same_vec(s->camera.from, v3(-18, -10, 0)) && s->nlights == 2 && !strcmp(s->view, "nave"));
    scene_free(s);
    s = scene_load("sponza@courtyard", err, sizeof err);
    CHECK_MSG(s != NULL, "sponza@courtyard: %s", err);
    if (s) {
        CHECK(same_vec(s->camera.from, v3(120, 18, -2)) && same_vec(s->camera.at, v3(-100, 30, -2)));
        CHECK(same_vec(s->camera.up, v3(0, 1, 0)) && s->camera.fov_deg == 60.0f);
        CHECK(s->nlights == 2 && same_vec(s->lights[0], v3(0, 120, 0)) && same_vec(s->lights[1], v3(-80, 25, -2)));
    }
    scene_free(s);
    /* A view spec after a named view changes only what it names. */
    s = scene_load("sibenik@nave@fov=60", err, sizeof err);
    CHECK_MSG(s != NULL, "%s", err);
    if (s) CHECK(s->camera.fov_deg == 60.0f && same_vec(s->camera.from, v3(-18, -10, 0)) && !strcmp(s->view, "nave@fov=60"));
    scene_free(s);

    expect_error("sibenik@roof", "scene 'sibenik@roof': unknown view 'roof' (known: nave; or a view spec eye=X,Y,Z");
    expect_error("sponza@nave", "unknown view 'nave' (known: courtyard;");
    expect_error("spd:balls:1@nave", "unknown view 'nave' (spd:balls:1 has no named views; give a view spec");
    expect_error("@nave", "no scene before the '@'");
    /* Views are checked before the mesh is read: this file does not exist. */
    expect_error(TMP "/nothere.obj@eye=1,2", "view 'eye=1,2': expected eye=X,Y,Z");
}

/* View specs on any scene: applied after loading, what they leave out
 * kept; impossible cameras refused. */
static void test_view_specs(void)
{
    write_file(TMP "/v.obj", small_obj);
    scene_t *s = scene_load(TMP "/v.obj@eye=1,2,3;at=0.5,0.5,0;up=0,0,1;fov=30", err, sizeof err);
    CHECK_MSG(s != NULL, "%s", err);
    if (s) {
        CHECK(same_vec(s->camera.from, v3(1, 2, 3)) && same_vec(s->camera.at, v3(0.5f, 0.5f, 0)));
        CHECK(same_vec(s->camera.up, v3(0, 0, 1)) && s->camera.fov_deg == 30.0f);
        CHECK(!strcmp(s->view, "eye=1,2,3;at=0.5,0.5,0;up=0,0,1;fov=30"));
        CHECK(!strcmp(s->name, TMP "/v.obj@eye=1,2,3;at=0.5,0.5,0;up=0,0,1;fov=30"));
    }
    scene_free(s);
    s = scene_load("spd:balls:1@fov=20", err, sizeof err); /* the SPD's eye stays */
    if (s) CHECK(s->camera.fov_deg == 20.0f && vec_near(s->camera.from, 2.1, 1.3, 1.7, 1e-6) && s->nlights == 3);
    scene_free(s);
    s = scene_load("spd:balls:1", err, sizeof err);
    if (s) CHECK(!strcmp(s->view, "source"));
    scene_free(s);
    expect_error("spd:balls:1@eye=0,0,0", "view eye=0,0,0: eye and at are the same point");
    expect_error("spd:balls:1@eye=0,0,5", "up (0 0 1) is zero or along the view direction");
    expect_error("spd:balls:1@up=0,0,0", "is zero or along");

    /* '@' in a folder name, and a file whose whole name has one. */
    CHECK(system("mkdir -p '" TMP "/at@dir' && cp " TMP "/v.obj '" TMP "/at@dir/v.obj' && cp " TMP "/v.obj '" TMP
                 "/v@2.obj'") == 0);
    s = scene_load(TMP "/at@dir/v.obj@fov=10", err, sizeof err);
    CHECK_MSG(s && s->camera.fov_deg == 10.0f, "%s", err);
    scene_free(s);
    s = scene_load(TMP "/v@2.obj", err, sizeof err);
    CHECK_MSG(s && !strcmp(s->view, "automatic"), "%s", err);
    scene_free(s);

    /* The parser alone: --view's. */
    scene_view v;
    CHECK(scene_view_parse("fov=45;up=0,1,0", &v, err, sizeof err) == 0 &&
          v.given == (SCENE_VIEW_FOV | SCENE_VIEW_UP) && v.fov_deg == 45.0f && v.nlights == 0);
    CHECK(scene_view_parse("eye=-1.5e2,+2,.5", &v, err, sizeof err) == 0 && same_vec(v.eye, v3(-150, 2, 0.5f)));
    /* An up axis instead of a vector, and lights, repeatable up to SCENE_VIEW_MAX_LIGHTS. */
    CHECK(scene_view_parse("up=z;light=1,2,3;light=-4,5,6", &v, err, sizeof err) == 0 && v.up_axis == SCENE_UP_Z &&
          v.nlights == 2 && same_vec(v.lights[1], v3(-4, 5, 6)));
    CHECK(scene_view_parse("up=auto", &v, err, sizeof err) == 0 && v.up_axis == SCENE_UP_AUTO);
    CHECK(scene_view_parse("up=0,0,1", &v, err, sizeof err) == 0 && v.up_axis == SCENE_UP_NONE);
    static const struct { const char *spec, *want; } bad[] = {
        {"up=W", "'up=W': expected up=X,Y,Z, three finite numbers, or an axis X, Y, Z or auto"},
        {"up=Z;up=Y", "'up=Y': up given twice"},
        {"light=1,2", "'light=1,2': expected light=X,Y,Z"},
        {"light=1,1,1;light=2,2,2;light=3,3,3;light=4,4,4;light=5,5,5", "'light=5,5,5': more than 4 lights"},
        {"", "empty view"},
        {"eye=1,2", "'eye=1,2': expected eye=X,Y,Z"},
        {"eye=1,2,3,4", "'eye=1,2,3,4': expected eye=X,Y,Z"},
        {"at=a,b,c", "'at=a,b,c': expected at=X,Y,Z"},
        {"up=1, 2,3", "'up=1, 2,3'"},
        {"eye=nan,0,0", "'eye=nan,0,0'"},
        {"eye=1e99,0,0", "'eye=1e99,0,0'"},
        {"fov=0", "'fov=0': expected an angle in degrees, 0 < DEG < 180"},
        {"fov=180", "'fov=180'"},
        {"fov=45deg", "'fov=45deg'"},
        {"zoom=2", "'zoom=2': unknown part 'zoom' (known: eye, at, up, fov, light)"},
        {"fov=40;fov=50", "'fov=50': fov given twice"},
        {"fov=40;", "empty part"},
        {";fov=40", "empty part"},
        {"eye", "'eye': expected KEY=VALUE"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        err[0] = '\0';
        CHECK_MSG(scene_view_parse(bad[i].spec, &v, err, sizeof err) == -1, "'%s' parsed", bad[i].spec);
        CHECK_MSG(strstr(err, bad[i].want) != NULL && !strchr(err, '\n'), "'%s': error '%s' lacks '%s'", bad[i].spec, err,
                  bad[i].want);
    }
}

int main(void)
{
    if (system("rm -rf " TMP " && mkdir -p " TMP) != 0) return 2;
    test_balls_counts();
    test_balls_geometry();
    test_balls_tessellated();
    test_catalogue_bunny();
    test_files();
    test_gltf();
    test_errors();
    test_read_limits();
    test_scene_path();
    test_named_views();
    test_view_specs();
    unsetenv("ACCELBENCH_SCENES");
    return check_report();
}
