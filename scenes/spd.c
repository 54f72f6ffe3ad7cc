/* spd.c: the SPD emitter (see spd.h), the tessellations of the SPD's -t
 * mode, the generator table and scene_spd().
 *
 * Tessellation rules (shared/SPD-SCENES.md, "Tessellated mode"):
 * - Sphere: the equi-angular cube sphere, 12*RES^2 triangles over
 *   6*RES^2 + 2 shared vertices; see cube_sphere_build().
 * - Cone or cylinder: 4*RES segments around the axis, one band, two
 *   triangles per segment (8*RES), no caps; see emit_cone_tess().
 * - Polygon: polygon_triangulate() (ear clipping), n - 2 triangles over the
 *   polygon's own n vertices.
 *
 * Before generating, scene_spd() sizes the scene from the generator's
 * census (its parameters alone): ids beyond 2^32 and bytes beyond the
 * memory cap (memory_cap.h, --memcap) are refused with one line, and the
 * store is reserved at exactly the estimated sizes (plan_store). */
#include "spd.h"
#include "memory_cap.h"
#include "../prims/checked_alloc.h"

#include <stdlib.h>
#include <string.h>

/* --- math --- */

spd_mat spd_mat_mul(const spd_mat *A, const spd_mat *B)
{
    spd_mat R;
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++)
            R.m[r][k] = A->m[r][0] * B->m[0][k] + A->m[r][1] * B->m[1][k] + A->m[r][2] * B->m[2][k];
    return R;
}

spd_mat spd_mat_scaling(double s)
{
    spd_mat R = {{{s, 0, 0}, {0, s, 0}, {0, 0, s}}};
    return R;
}

spd_mat spd_mat_rotation(spd_vec a, double angle)
{
    /* Rodrigues: c I + s [a]x + (1 - c) a a^T */
    double c = cos(angle), s = sin(angle), t = 1.0 - c;
    spd_mat R = {{{t * a.x * a.x + c, t * a.x * a.y - s * a.z, t * a.x * a.z + s * a.y},
                  {t * a.x * a.y + s * a.z, t * a.y * a.y + c, t * a.y * a.z - s * a.x},
                  {t * a.x * a.z - s * a.y, t * a.y * a.z + s * a.x, t * a.z * a.z + c}}};
    return R;
}

double spd_shine(double angle_deg)
{
    if (angle_deg <= 0.0) return 100000.0;
    if (angle_deg >= 90.0) return 1.0;
    return log(0.5) / log(cos(angle_deg * M_PI / 180.0));
}

static vec3 tof(spd_vec a) { return v3((float)a.x, (float)a.y, (float)a.z); }

static void *xmalloc(size_t n) { return checked_malloc(n, "an SPD generator's scratch space"); }

/* --- the cube sphere ---
 *
 * A grid point of a cube face is the normalized cube point n + x*s + y*t,
 * where n is the face normal, s and t are its in-plane axes (s x t = n) and
 * x, y take the values tan((pi/4)(2k/res - 1)), k = 0..res: equal angles
 * along each face. For +Z (s = +X, t = +Y) the point (i, j) is the SPD's
 * (u, v) = (i, res - j), since normalize(Xu x Yv) is the direction of
 * (tan a_u, -tan b_v, 1); the other faces are the same grid turned onto
 * them. Points on face edges are shared: each is identified by its integer
 * lattice coordinates on the cube [0, res]^3, so a sphere has 6*res^2 + 2
 * vertices.
 *
 * Triangle order: faces +X, -X, +Y, -Y, +Z, -Z; in a face, quads by rows of
 * t (j outer) then s (i inner); in a quad, (i,j)(i+1,j)(i+1,j+1) then
 * (i,j)(i+1,j+1)(i,j+1). Both wind counter-clockwise seen from outside. */
typedef struct {
    uint32_t nverts, ntris;
    spd_vec *dir;
    uint32_t (*tri)[3];
} cube_sphere;

typedef struct { int axis, sign; } signed_axis;

static void cube_sphere_build(cube_sphere *cs, int res)
{
    static const signed_axis faces[6][3] = {
        /*  n        s        t   */
        {{0, +1}, {2, -1}, {1, +1}}, /* +X */
        {{0, -1}, {2, +1}, {1, +1}}, /* -X */
        {{1, +1}, {0, +1}, {2, -1}}, /* +Y */
        {{1, -1}, {0, +1}, {2, +1}}, /* -Y */
        {{2, +1}, {0, +1}, {1, +1}}, /* +Z */
        {{2, -1}, {0, -1}, {1, +1}}, /* -Z */
    };
    const int n1 = res + 1;
    double *tanv = xmalloc((size_t)n1 * sizeof *tanv);
    int32_t *slot = xmalloc((size_t)n1 * n1 * n1 * sizeof *slot);
    uint32_t *grid = xmalloc((size_t)n1 * n1 * sizeof *grid);
    cs->dir = xmalloc((size_t)(6 * res * res + 2) * sizeof *cs->dir);
    cs->tri = xmalloc((size_t)12 * res * res * sizeof *cs->tri);
    for (int k = 0; k <= res; k++) tanv[k] = tan(M_PI / 4.0 * (2.0 * k / res - 1.0));
    tanv[0] = -1.0; /* exact cube edges, whatever tan() rounds to */
    tanv[res] = 1.0;
    for (int k = 0; k < n1 * n1 * n1; k++) slot[k] = -1;
    cs->nverts = cs->ntris = 0;

    for (int f = 0; f < 6; f++) {
        const signed_axis *n = &faces[f][0], *s = &faces[f][1], *t = &faces[f][2];
        for (int j = 0; j <= res; j++)
            for (int i = 0; i <= res; i++) {
                int lat[3];
                lat[n->axis] = n->sign > 0 ? res : 0;
                lat[s->axis] = s->sign > 0 ? i : res - i; /* tan is odd: -tan a_i = tan a_(res-i) */
                lat[t->axis] = t->sign > 0 ? j : res - j;
                int key = lat[0] + n1 * (lat[1] + n1 * lat[2]);
                if (slot[key] < 0) {
                    slot[key] = (int32_t)cs->nverts;
                    cs->dir[cs->nverts++] = spd_norm(spd_v(tanv[lat[0]], tanv[lat[1]], tanv[lat[2]]));
                }
                grid[j * n1 + i] = (uint32_t)slot[key];
            }
        for (int j = 0; j < res; j++)
            for (int i = 0; i < res; i++) {
                uint32_t a = grid[j * n1 + i], b = grid[j * n1 + i + 1];
                uint32_t c = grid[(j + 1) * n1 + i + 1], d = grid[(j + 1) * n1 + i];
                uint32_t *t1 = cs->tri[cs->ntris++], *t2 = cs->tri[cs->ntris++];
                t1[0] = a, t1[1] = b, t1[2] = c;
                t2[0] = a, t2[1] = c, t2[2] = d;
            }
    }
    free(tanv);
    free(slot);
    free(grid);
}

/* --- the context --- */

typedef struct { uint32_t end; uint16_t material; } material_run;

struct spd_ctx {
    scene_t *s;
    int tess_res;          /* 0: true primitives */
    cube_sphere cs;        /* tessellated mode: the unit cube sphere */
    double *cone_cos, *cone_sin; /* tessellated mode: 4*RES segment angles */
    /* Per-primitive materials as runs, written once at the end (setting
     * them per change through scene_set_material_upto would be quadratic). */
    int have_material;
    uint16_t material;
    material_run *runs;
    uint32_t nruns, runs_cap;
    /* Polygon scratch space. */
    spd_vec *kept;
    vec3 *pts;
    uint32_t *idx;
    uint32_t (*tris)[3];
    int cap;
};

static void ctx_init(spd_ctx *c, scene_t *s, int tess_res)
{
    memset(c, 0, sizeof *c);
    c->s = s;
    c->tess_res = tess_res;
    if (tess_res) {
        cube_sphere_build(&c->cs, tess_res);
        int nseg = 4 * tess_res;
        c->cone_cos = xmalloc((size_t)nseg * sizeof *c->cone_cos);
        c->cone_sin = xmalloc((size_t)nseg * sizeof *c->cone_sin);
        for (int k = 0; k < nseg; k++) {
            c->cone_cos[k] = cos(2.0 * M_PI * k / nseg);
            c->cone_sin[k] = sin(2.0 * M_PI * k / nseg);
        }
    }
}

static void push_run(spd_ctx *c)
{
    uint32_t n = c->s->prims.count;
    if (!c->have_material || (c->nruns && c->runs[c->nruns - 1].end >= n)) return;
    if (c->nruns && c->runs[c->nruns - 1].material == c->material) {
        c->runs[c->nruns - 1].end = n;
        return;
    }
    if (c->nruns == c->runs_cap) {
        c->runs_cap = c->runs_cap ? 2 * c->runs_cap : 64;
        c->runs = checked_realloc(c->runs, c->runs_cap * sizeof *c->runs, "an SPD scene's material runs");
    }
    c->runs[c->nruns].end = n;
    c->runs[c->nruns].material = c->material;
    c->nruns++;
}

/* Write the runs into the scene's per-primitive materials and free the context. */
static void ctx_finish(spd_ctx *c)
{
    push_run(c);
    scene_t *s = c->s;
    if (c->nruns) {
        scene_set_material_upto(s, 0); /* allocates prim_material up to the run ends */
        uint32_t start = 0;
        for (uint32_t i = 0; i < c->nruns; i++) {
            for (uint32_t k = start; k < c->runs[i].end; k++) s->prim_material[k] = c->runs[i].material;
            start = c->runs[i].end;
        }
    }
    free(c->runs);
    free(c->cs.dir);
    free(c->cs.tri);
    free(c->cone_cos);
    free(c->cone_sin);
    free(c->kept);
    free(c->pts);
    free(c->idx);
    free(c->tris);
}

/* --- view, lights, materials --- */

void spd_background(spd_ctx *c, double r, double g, double b)
{
    c->s->background = v3((float)r, (float)g, (float)b);
}

void spd_view(spd_ctx *c, spd_vec from, spd_vec at, spd_vec up, double angle_deg, double hither, int xres, int yres)
{
    camera_t *cam = &c->s->camera;
    cam->from = tof(from);
    cam->at = tof(at);
    cam->up = tof(up);
    cam->fov_deg = (float)angle_deg;
    cam->hither = (float)hither;
    cam->width = xres;
    cam->height = yres;
}

void spd_light(spd_ctx *c, spd_vec p) { scene_add_light(c->s, tof(p)); }

void spd_material(spd_ctx *c, double r, double g, double b, double kd, double ks, double shine, double t, double ior)
{
    (void)shine;
    material_t m = {v3((float)r, (float)g, (float)b), (float)kd, (float)ks, (float)t, (float)ior};
    scene_t *s = c->s;
    uint32_t id = s->nmaterials;
    for (uint32_t i = 0; i < s->nmaterials; i++)
        if (material_equal(s->materials[i], m)) {
            id = i;
            break;
        }
    if (c->have_material && id == c->material) return;
    push_run(c); /* the primitives so far keep the old material */
    if (id == s->nmaterials) id = scene_add_material(s, m);
    c->material = (uint16_t)id;
    c->have_material = 1;
}

/* --- primitives --- */

void spd_sphere(spd_ctx *c, spd_vec centre, double r)
{
    prims_t *p = &c->s->prims;
    if (!c->tess_res) {
        prims_add_sphere(p, tof(centre), (float)r);
        return;
    }
    const cube_sphere *cs = &c->cs;
    uint32_t base = p->nverts;
    /* Patches with the sphere's normal at every vertex, as the SPD's -t output. */
    for (uint32_t i = 0; i < cs->nverts; i++)
        scene_set_vertex_normal(c->s, prims_add_vertex(p, tof(spd_add(centre, spd_scale(cs->dir[i], r)))), tof(cs->dir[i]));
    for (uint32_t i = 0; i < cs->ntris; i++)
        prims_add_triangle(p, base + cs->tri[i][0], base + cs->tri[i][1], base + cs->tri[i][2]);
}

/* Tessellated cone: an orthonormal frame (u, v, w) with w along the axis
 * and u perpendicular to w and to the coordinate axis least aligned with it;
 * ring point k at angle 2*pi*k/(4 RES) from u toward v, base ring first
 * (vertices b_0.., then a_0..). Segment k gives (b_k, b_k+1, a_k+1) and
 * (a_k+1, a_k, b_k), wound counter-clockwise seen from outside. A pointed
 * end (radius 0) gives zero-area triangles, kept so the count is 8*RES.
 * Every vertex has the cone's outward normal at its angle, d L + w (rb - ra)
 * normalised (d the radial direction, L the axis length), as the SPD's
 * -t patches. */
static void emit_cone_tess(spd_ctx *c, spd_vec base, double rb, spd_vec apex, double ra)
{
    prims_t *p = &c->s->prims;
    spd_vec w = spd_norm(spd_sub(apex, base));
    double ax = fabs(w.x), ay = fabs(w.y), az = fabs(w.z);
    spd_vec e = ax <= ay && ax <= az ? spd_v(1, 0, 0) : ay <= az ? spd_v(0, 1, 0) : spd_v(0, 0, 1);
    spd_vec u = spd_norm(spd_cross(w, e)), v = spd_cross(w, u);
    uint32_t nseg = 4u * (uint32_t)c->tess_res, b0 = p->nverts, a0 = b0 + nseg;
    double len = spd_len(spd_sub(apex, base));
    for (int end = 0; end < 2; end++) {
        spd_vec o = end ? apex : base;
        double r = end ? ra : rb;
        for (uint32_t k = 0; k < nseg; k++) {
            spd_vec d = spd_add(spd_scale(u, c->cone_cos[k]), spd_scale(v, c->cone_sin[k]));
            uint32_t id = prims_add_vertex(p, tof(spd_add(o, spd_scale(d, r))));
            scene_set_vertex_normal(c->s, id, tof(spd_add(spd_scale(d, len), spd_scale(w, rb - ra))));
        }
    }
    for (uint32_t k = 0; k < nseg; k++) {
        uint32_t k1 = (k + 1) % nseg;
        prims_add_triangle(p, b0 + k, b0 + k1, a0 + k1);
        prims_add_triangle(p, a0 + k1, a0 + k, b0 + k);
    }
}

void spd_cone(spd_ctx *c, spd_vec base, double rb, spd_vec apex, double ra)
{
    if (c->tess_res)
        emit_cone_tess(c, base, rb, apex, ra);
    else
        prims_add_cone(&c->s->prims, tof(base), (float)rb, tof(apex), (float)ra);
}

static void scratch(spd_ctx *c, int n)
{
    if (n <= c->cap) return;
    c->cap = n < 64 ? 64 : 2 * n;
    free(c->kept);
    free(c->pts);
    free(c->idx);
    free(c->tris);
    c->kept = xmalloc((size_t)c->cap * sizeof *c->kept);
    c->pts = xmalloc((size_t)c->cap * sizeof *c->pts);
    c->idx = xmalloc((size_t)c->cap * sizeof *c->idx);
    c->tris = xmalloc((size_t)c->cap * sizeof *c->tris);
}

#define SPD_MERGE_DIST 1e-6 /* the SPD's EPSILON2 (def.h) */

void spd_polygon(spd_ctx *c, const spd_vec *pts, int n)
{
    /* Merge consecutive near-coincident vertices, keeping the first of a run. */
    scratch(c, n);
    spd_vec *kept = c->kept;
    int m = 0;
    for (int i = 0; i < n; i++)
        if (m == 0 || spd_len(spd_sub(pts[i], kept[m - 1])) >= SPD_MERGE_DIST) kept[m++] = pts[i];
    while (m > 1 && spd_len(spd_sub(kept[m - 1], kept[0])) < SPD_MERGE_DIST) m--; /* closing edge */
    if (m < 3) return;
    prims_t *p = &c->s->prims;
    uint32_t base = p->nverts;
    for (int i = 0; i < m; i++) {
        c->pts[i] = tof(kept[i]);
        c->idx[i] = prims_add_vertex(p, c->pts[i]);
    }
    if (m == 3) {
        prims_add_triangle(p, base, base + 1, base + 2);
    } else if (!c->tess_res) {
        prims_add_polygon(p, c->idx, (uint32_t)m);
    } else {
        uint32_t nt = polygon_triangulate(c->pts, (uint32_t)m, v3(0, 0, 0), c->tris);
        for (uint32_t i = 0; i < nt; i++) prims_add_triangle(p, base + c->tris[i][0], base + c->tris[i][1], base + c->tris[i][2]);
    }
}

void spd_patch(spd_ctx *c, const spd_vec pts[3], const spd_vec normals[3])
{
    prims_t *p = &c->s->prims;
    uint32_t a = p->nverts;
    for (int k = 0; k < 3; k++) scene_set_vertex_normal(c->s, prims_add_vertex(p, tof(pts[k])), tof(normals[k]));
    prims_add_triangle(p, a, a + 1, a + 2);
}

/* --- the generator table --- */

const spd_generator spd_generators[] = {
    {"balls", "src/balls.c", 4, 7, "sphereflake: sum 9^k spheres (k = 0..SIZE) over a floor quad; 7,382 prims at 4",
     spd_gen_balls, spd_census_balls, 0},
    {"gears", "src/gears.c", 4, 12, "SIZE^3 gears of 2 concave 144-gons + 144 quads, some glass, on a quad; 9,345 at 4",
     spd_gen_gears, spd_census_gears, 0},
    {"mount", "src/mount.c", 6, 10,
     "fractal mountain of 2*4^SIZE triangles + 4 glass spheres; 8,196 at 6 (sizes > 7: heights not comparable)",
     spd_gen_mount, spd_census_mount, 0},
    {"rings", "src/rings.c", 7, 12, "pyramid of dodecahedral rings, 30 cylinders + 30 spheres each, wall; 8,401 at 7",
     spd_gen_rings, spd_census_rings, 0},
    {"teapot", "src/teapot.c", 12, 64, "Newell teapot, 64n^2-8n triangle patches on an n x n checkerboard; 9,264 at 12",
     spd_gen_teapot, spd_census_teapot, 0},
    {"tetra", "src/tetra.c", 6, 10, "Sierpinski tetrahedron, 4^SIZE triangles; 4,096 at 6", spd_gen_tetra, spd_census_tetra, 0},
    {"tree", "src/tree.c", 11, 18, "Aono-Kunii tree, 2^(SIZE+1)-1 cones + as many spheres, field quad; 8,191 at 11",
     spd_gen_tree, spd_census_tree, 0},
    {"lattice", "src/lattice.c", 12, 64, "(SIZE+1)^3 spheres joined by 3*SIZE*(SIZE+1)^2 cylinders; 8,281 at 12",
     spd_gen_lattice, spd_census_lattice, 0},
    {"shells", "src/shells.c", 5, 12, "Pickover sea shell, 180*2^SIZE+1 overlapping spheres; 5,761 at 5",
     spd_gen_shells, spd_census_shells, 0},
    {"jacks", "src/jacks.c", 1, 7,
     "recursive jacks, sum 8^k jacks (k < SIZE) of 3 cylinders + 6 spheres; 9 at 1; :t always RES 2, as in the SPD",
     spd_gen_jacks, spd_census_jacks, 2},
    {"sombrero", "src/sombrero.c", 1, 7, "sombrero height field, 2(w-1)^2 triangles, w = 32*2^(SIZE-1); 1,922 at 1",
     spd_gen_sombrero, spd_census_sombrero, 0},
};
const int spd_ngenerators = (int)(sizeof spd_generators / sizeof spd_generators[0]);

const spd_generator *spd_generator_find(const char *name)
{
    for (int i = 0; i < spd_ngenerators; i++)
        if (strcmp(spd_generators[i].name, name) == 0) return &spd_generators[i];
    return NULL;
}

uint64_t spd_census_prims(const spd_census *n, int tess_res)
{
    if (!tess_res) return n->spheres + n->cones + n->polygons;
    uint64_t r = (uint64_t)tess_res;
    return n->spheres * 12 * r * r + n->cones * 8 * r + n->polygon_tris;
}

uint64_t spd_prims(const spd_generator *g, int size, int tess_res)
{
    spd_census n;
    g->census(size, &n);
    return spd_census_prims(&n, tess_res && g->forced_res ? g->forced_res : tess_res);
}

/* --- the store a census needs, before generating ---
 *
 * What scene_spd() allocates for a scene, from the census alone, and the
 * store's arrays reserved at exactly those sizes: no doubling slack (up to
 * half of a grown array) and no reallocation copies while generating, so
 * the estimate is what the scene holds. Polygon merging can only make the
 * scene smaller. True mode does not know which polygons have 3 vertices (a
 * triangle each) and which more (a polygon primitive each), so it bounds
 * both: T triangles and P polygon records with T + P = polygons and
 * sum (n - 2) = polygon_tris >= T + 2P, hence P <= polygon_tris - polygons,
 * and T >= polygons - P bounds the polygons' own vertices and triangles;
 * it is exact when every polygon is a triangle, or none is. Not counted:
 * the generators' own small scratch (the sombrero's height grid, a third of
 * its vertex bytes, freed before scene_finish). */
typedef struct {
    uint64_t prims, verts, tris, spheres, cones, polygons, poly_verts, poly_tris;
    uint64_t normals; /* vertex normals (scene_t.normals): every vertex when any primitive is smooth, else 0 */
} store_plan;

static store_plan plan_store(const spd_census *n, int tess_res)
{
    store_plan p = {0};
    uint64_t r = (uint64_t)tess_res;
    if (tess_res) {
        p.tris = memory_add(memory_add(memory_mul(n->spheres, 12 * r * r), memory_mul(n->cones, 8 * r)), n->polygon_tris);
        p.verts = memory_add(memory_add(memory_mul(n->spheres, 6 * r * r + 2), memory_mul(n->cones, 8 * r)),
                             n->polygon_verts);
        p.prims = p.tris;
        /* Tessellated spheres and cones are smooth patches, as the teapot's are. */
        p.normals = n->spheres || n->cones || n->patches ? p.verts : 0;
        return p;
    }
    p.spheres = n->spheres;
    p.cones = n->cones;
    p.tris = n->polygons;
    p.polygons = n->polygon_tris > n->polygons ? n->polygon_tris - n->polygons : 0;
    if (p.polygons > n->polygons) p.polygons = n->polygons;
    uint64_t min_tris = n->polygons - p.polygons; /* the fewest of them that are triangles */
    p.poly_verts = p.polygons ? n->polygon_verts - 3 * min_tris : 0;
    p.poly_tris = p.polygons ? n->polygon_tris - min_tris : 0;
    p.verts = n->polygon_verts;
    p.prims = memory_add(memory_add(n->spheres, n->cones), n->polygons);
    p.normals = n->patches ? p.verts : 0;
    return p;
}

/* Heap bytes of a scene of that plan: the store's arrays (prims/prims.h),
 * the bounds and flags prims_finish adds, the per-primitive materials, the
 * vertex normals, and
 * in tessellated mode the unit cube sphere and cone angles of the context. */
static uint64_t plan_bytes(const store_plan *p, int tess_res)
{
    const prims_t *z = NULL; /* for the element sizes */
    uint64_t b = memory_mul(p->prims, sizeof *z->kind + sizeof *z->index + sizeof *z->bounds + sizeof(uint16_t));
    b = memory_add(b, memory_mul(p->verts, sizeof *z->verts));
    b = memory_add(b, memory_mul(p->tris, sizeof *z->tris + sizeof *z->tri_degenerate));
    b = memory_add(b, memory_mul(p->spheres, sizeof *z->spheres));
    b = memory_add(b, memory_mul(p->cones, sizeof *z->cones));
    b = memory_add(b, memory_mul(p->polygons, sizeof *z->polygons));
    b = memory_add(b, memory_mul(p->poly_verts, sizeof *z->poly_verts));
    b = memory_add(b, memory_mul(p->poly_tris, sizeof *z->poly_tris));
    b = memory_add(b, memory_mul(p->normals, sizeof(vec3)));
    if (tess_res) {
        uint64_t r = (uint64_t)tess_res, n1 = r + 1;
        b = memory_add(b, n1 * n1 * n1 * sizeof(int32_t) + (6 * r * r + 2) * sizeof(spd_vec) + 12 * r * r * 12 +
                              8 * r * sizeof(double));
    }
    return b;
}

/* One array of the store at exactly n items (grow() in prims.c leaves an
 * array alone while its capacity holds what is added). */
static void *reserve(uint64_t n, size_t elem, uint32_t *cap, const char *what)
{
    if (n == 0) return NULL;
    *cap = (uint32_t)n;
    return checked_malloc(checked_array_bytes((size_t)n, elem, what), what);
}

static void reserve_store(prims_t *s, const store_plan *p)
{
    uint32_t count_cap = 0;
    s->kind = reserve(p->prims, sizeof *s->kind, &count_cap, "the primitive store's kinds");
    s->index = reserve(p->prims, sizeof *s->index, &s->count_cap, "the primitive store's indices");
    s->verts = reserve(p->verts, sizeof *s->verts, &s->nverts_cap, "the primitive store's vertices");
    s->tris = reserve(p->tris, sizeof *s->tris, &s->ntris_cap, "the primitive store's triangles");
    s->spheres = reserve(p->spheres, sizeof *s->spheres, &s->nspheres_cap, "the primitive store's spheres");
    s->cones = reserve(p->cones, sizeof *s->cones, &s->ncones_cap, "the primitive store's cones");
    s->polygons = reserve(p->polygons, sizeof *s->polygons, &s->npolygons_cap, "the primitive store's polygons");
    s->poly_verts = reserve(p->poly_verts, sizeof *s->poly_verts, &s->npoly_verts_cap, "the primitive store's polygon vertices");
}

scene_t *scene_spd(const char *name, const char *generator, int size, int tess_res, char *err, size_t errlen)
{
    const spd_generator *g = spd_generator_find(generator);
    if (!g) {
        char known[256] = "";
        for (int i = 0; i < spd_ngenerators; i++) {
            size_t len = strlen(known);
            snprintf(known + len, sizeof known - len, "%s%s", i ? ", " : "", spd_generators[i].name);
        }
        snprintf(err, errlen, "unknown SPD database '%s' (known: %s)", generator, known);
        return NULL;
    }
    if (size < 1 || size > g->max_size) {
        snprintf(err, errlen, "spd:%s:%d: size must be 1..%d", g->name, size, g->max_size);
        return NULL;
    }
    if (tess_res < 0 || tess_res > 64) {
        snprintf(err, errlen, "spd:%s:%d:t%d: tessellation resolution must be 1..64", g->name, size, tess_res);
        return NULL;
    }
    int asked_res = tess_res;
    if (tess_res && g->forced_res) tess_res = g->forced_res;
    spd_census n;
    g->census(size, &n);
    uint64_t r = (uint64_t)tess_res;
    uint64_t prims = spd_census_prims(&n, tess_res);
    uint64_t verts = n.polygon_verts + (tess_res ? n.spheres * (6 * r * r + 2) + n.cones * 8 * r : 0);
    if (prims >= UINT32_MAX || verts >= UINT32_MAX) {
        snprintf(err, errlen, "%s: %llu primitives and %llu vertices exceed the 2^32 ids of the primitive store", name,
                 (unsigned long long)prims, (unsigned long long)verts);
        return NULL;
    }
    /* The memory, before a byte of it is allocated (memory_cap.h). */
    store_plan plan = plan_store(&n, tess_res);
    if (memory_cap_exceeded(plan_bytes(&plan, tess_res), err, errlen, "%s: %llu primitives%s and %llu vertices", name,
                            (unsigned long long)prims, tess_res ? " (triangles)" : "", (unsigned long long)verts))
        return NULL;

    scene_t *s = scene_new(name);
    reserve_store(&s->prims, &plan);
    if (plan.normals) scene_reserve_vertex_normals(s, (uint32_t)plan.normals);
    if (tess_res)
        snprintf(s->source, sizeof s->source, "SPD 3.14 %s -s %d -t %d: %llu triangles%s", g->file, size, asked_res,
                 (unsigned long long)prims, tess_res != asked_res ? " (the generator forces resolution 2)" : "");
    else
        snprintf(s->source, sizeof s->source,
                 "SPD 3.14 %s -s %d -c: %llu primitives (%llu spheres, %llu cones, %llu polygons)", g->file, size,
                 (unsigned long long)prims, (unsigned long long)n.spheres, (unsigned long long)n.cones,
                 (unsigned long long)n.polygons);
    /* The SPD's usual view; every generator sets its own. */
    s->background = v3(SPD_SKY_BLUE);
    spd_ctx c;
    ctx_init(&c, s, tess_res);
    g->generate(&c, size);
    ctx_finish(&c);
    if (scene_finish(s, true, err, errlen) != 0) {
        scene_free(s);
        return NULL;
    }
    return s;
}
