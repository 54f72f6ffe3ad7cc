/* scene.c: the scene object and the helpers every scene maker shares:
 * materials, lights, per-primitive materials, and the finishing step that
 * validates the primitives and supplies a camera, lights and a material
 * when the source (a bare mesh file) has none. */
#include "scene.h"
#include "../prims/checked_alloc.h"

#include <stdlib.h>
#include <string.h>

/* The public struct plus the bookkeeping scene_set_material_upto() needs.
 * scene_t is first, so a scene_t * from scene_new() is also a scene_impl *. */
typedef struct {
    scene_t pub;
    uint32_t material_upto; /* prims [0, material_upto) have a material */
    uint32_t normals_cap;   /* vertices the normals array has room for */
} scene_impl;

static void *xrealloc(void *p, size_t n) { return checked_realloc(p, n, "a scene's lights, materials or table of materials"); }

scene_t *scene_new(const char *name)
{
    scene_impl *si = xrealloc(NULL, sizeof *si);
    memset(si, 0, sizeof *si);
    scene_t *s = &si->pub;
    snprintf(s->name, sizeof s->name, "%s", name ? name : "");
    prims_init(&s->prims);
    s->background = v3(0.0f, 0.0f, 0.0f); /* NFF's default */
    s->bounds = box_empty();
    return s;
}

void scene_free(scene_t *s)
{
    if (!s) return;
    prims_free(&s->prims);
    free(s->lights);
    free(s->materials);
    free(s->prim_material);
    free(s->normals);
    free((scene_impl *)s);
}

uint16_t scene_add_material(scene_t *s, material_t m)
{
    if (s->nmaterials > UINT16_MAX) { /* loaders check first where they can name the line */
        fprintf(stderr, "accelbench: scene %s has more than 65536 materials\n", s->source[0] ? s->source : s->name);
        exit(2);
    }
    s->materials = xrealloc(s->materials, (s->nmaterials + 1) * sizeof *s->materials);
    s->materials[s->nmaterials] = m;
    return (uint16_t)s->nmaterials++;
}

void scene_add_light(scene_t *s, vec3 p)
{
    s->lights = xrealloc(s->lights, (s->nlights + 1) * sizeof *s->lights);
    s->lights[s->nlights++] = p;
}

void scene_set_material_upto(scene_t *s, uint16_t material)
{
    scene_impl *si = (scene_impl *)s;
    uint32_t n = s->prims.count;
    if (n <= si->material_upto) return;
    s->prim_material = xrealloc(s->prim_material, (size_t)n * sizeof *s->prim_material);
    for (uint32_t i = si->material_upto; i < n; i++) s->prim_material[i] = material;
    si->material_upto = n;
}

/* Room for vertex normals [0, n), new ones zero (no normal): exactly n,
 * or, growing one vertex at a time, the capacity doubled. */
static void reserve_normals(scene_t *s, uint32_t n, bool exact)
{
    scene_impl *si = (scene_impl *)s;
    if (n <= si->normals_cap) return;
    uint32_t cap = exact ? n : si->normals_cap ? si->normals_cap : 64;
    while (cap < n) cap = cap > UINT32_MAX / 2 ? n : cap * 2;
    s->normals = checked_realloc(s->normals, (size_t)cap * sizeof *s->normals, "a scene's vertex normals");
    memset(s->normals + si->normals_cap, 0, (size_t)(cap - si->normals_cap) * sizeof *s->normals);
    si->normals_cap = cap;
}

void scene_reserve_vertex_normals(scene_t *s, uint32_t n) { reserve_normals(s, n, true); }

void scene_set_vertex_normal(scene_t *s, uint32_t v, vec3 n)
{
    reserve_normals(s, v + 1, false);
    float len = v3_len(n);
    /* One already unit length (to a few float steps) is kept bit for bit,
     * so that a normal written and read back is the same normal. */
    if (!(len > 0.0f) || !isfinite(len)) n = v3(0, 0, 0);
    else if (fabsf(len - 1.0f) > 1e-6f) n = v3_scale(n, 1.0f / len);
    s->normals[v] = n;
}

static bool has_normal(const scene_t *s, uint32_t v)
{
    if (v >= ((const scene_impl *)s)->normals_cap) return false; /* a scene not finished yet may hold fewer */
    vec3 n = s->normals[v];
    return n.x != 0.0f || n.y != 0.0f || n.z != 0.0f;
}

bool scene_prim_smooth(const scene_t *s, uint32_t id)
{
    if (!s->normals) return false;
    const prims_t *p = &s->prims;
    uint32_t k = p->index[id];
    if (p->kind[id] == PRIM_TRIANGLE)
        return has_normal(s, p->tris[k].v[0]) && has_normal(s, p->tris[k].v[1]) && has_normal(s, p->tris[k].v[2]);
    if (p->kind[id] != PRIM_POLYGON) return false;
    const polygon_t *g = &p->polygons[k];
    for (uint32_t i = 0; i < g->count; i++)
        if (!has_normal(s, p->poly_verts[g->first + i])) return false;
    return true;
}

vec3 scene_shading_normal(const scene_t *s, uint32_t id, const surface_point *sp)
{
    if (sp->tri[0] == SURFACE_NO_TRIANGLE || !scene_prim_smooth(s, id)) return sp->normal;
    vec3 n = v3(0, 0, 0);
    for (int k = 0; k < 3; k++) n = v3_madd(n, s->normals[sp->tri[k]], sp->w[k]);
    float len = v3_len(n);
    /* Opposite normals at the corners can cancel: the flat normal then. */
    return len > 1e-6f && isfinite(len) ? v3_scale(n, 1.0f / len) : sp->normal;
}

static const char *what(const scene_t *s)
{
    return s->source[0] ? s->source : s->name;
}

/* The axis (SCENE_UP_X, _Y or _Z) that axis stands for in s: AUTO is the
 * thinnest extent, ties going to Y, then Z; CATALOGUE is Z when Y alone is
 * the thinnest, else Y. */
static int resolve_axis(const scene_t *s, int axis)
{
    vec3 e = box_extent(s->bounds);
    if (axis == SCENE_UP_CATALOGUE) return e.y < e.x && e.y < e.z ? SCENE_UP_Z : SCENE_UP_Y;
    if (axis != SCENE_UP_AUTO) return axis;
    if (e.y <= e.x && e.y <= e.z) return SCENE_UP_Y;
    return e.z <= e.x ? SCENE_UP_Z : SCENE_UP_X;
}

vec3 scene_up_vector(const scene_t *s, int axis)
{
    int a = resolve_axis(s, axis);
    return a == SCENE_UP_X ? v3(1, 0, 0) : a == SCENE_UP_Z ? v3(0, 0, 1) : v3(0, 1, 0);
}

/* The default view: look at the centre of the bounds from a fixed octant,
 * just far enough that all eight box corners fall inside the 45 degree
 * field (with a 5% margin), so the model fills the frame. The direction
 * to the eye has 0.6 along the up axis for 1 and 0.8 along the other two
 * (the Y and Z frames are the ones catalogue meshes are seen in). */
static void default_camera(scene_t *s, int axis)
{
    vec3 c = box_center(s->bounds);
    float radius = 0.5f * box_diagonal(s->bounds);
    if (!(radius > 0.0f) || !isfinite(radius)) radius = 1.0f; /* a single point */
    int a = resolve_axis(s, axis);
    vec3 up = scene_up_vector(s, a);
    vec3 dir = v3_norm(a == SCENE_UP_Z ? v3(1.0f, 0.8f, 0.6f) : a == SCENE_UP_Y ? v3(1.0f, 0.6f, 0.8f)
                                                                                 : v3(0.6f, 0.8f, 1.0f));
    vec3 right = v3_norm(v3_cross(up, dir)), up2 = v3_cross(dir, right);
    const float tan_half = tanf(22.5f * (float)M_PI / 180.0f);
    /* A corner at depth z toward the eye and lateral offsets x, y is in
     * view when max(|x|, |y|) <= tan_half * (dist - z). */
    float dist = 0.0f;
    for (int k = 0; k < 8; k++) {
        vec3 corner = v3(k & 1 ? s->bounds.hi.x : s->bounds.lo.x, k & 2 ? s->bounds.hi.y : s->bounds.lo.y,
                         k & 4 ? s->bounds.hi.z : s->bounds.lo.z);
        vec3 o = v3_sub(corner, c);
        float lateral = fmaxf(fabsf(v3_dot(o, right)), fabsf(v3_dot(o, up2)));
        dist = fmaxf(dist, v3_dot(o, dir) + 1.05f * lateral / tan_half);
    }
    if (!(dist > radius * 0.01f)) dist = radius / tan_half;
    camera_t *cam = &s->camera;
    cam->from = v3_madd(c, dir, dist);
    cam->at = c;
    cam->up = up;
    cam->fov_deg = 45.0f;
    /* Well inside the gap between the eye and the nearest corner, yet
     * large enough not to matter for float precision. */
    cam->hither = 1e-3f * radius;
    cam->width = cam->height = 512;
}

/* Two lights behind the camera and above it, one to each side, both 1.5
 * eye distances from the centre: outside the bounding sphere, hence
 * outside the bounds. */
static void default_lights(scene_t *s)
{
    const camera_t *cam = &s->camera;
    vec3 back = v3_sub(cam->from, cam->at);
    float dist = v3_len(back);
    if (!(dist > 0.0f) || !isfinite(dist)) dist = 1.0f;
    back = v3_norm(back);
    vec3 right = v3_norm(v3_cross(cam->up, back));
    vec3 up = v3_cross(back, right);
    vec3 d1 = v3_norm(v3_add(v3_add(back, v3_scale(up, 0.6f)), v3_scale(right, 0.5f)));
    vec3 d2 = v3_norm(v3_add(v3_add(back, v3_scale(up, 0.9f)), v3_scale(right, -0.7f)));
    scene_add_light(s, v3_madd(cam->at, d1, 1.5f * dist));
    scene_add_light(s, v3_madd(cam->at, d2, 1.5f * dist));
}

int scene_finish(scene_t *s, bool has_camera, char *err, size_t errlen)
{
    if (s->prims.count == 0) {
        snprintf(err, errlen, "%s: no primitives", what(s));
        return -1;
    }
    char why[400];
    /* The ranges first (scene.h says why they are what they are): the
     * finishing below already does float arithmetic on the geometry. */
    if (scene_check_geometry(s, why, sizeof why) != 0 || prims_finish(&s->prims, why, sizeof why) != 0) {
        snprintf(err, errlen, "%s: %s", what(s), why);
        return -1;
    }
    s->bounds = s->prims.box;
    if (!isfinite(box_diagonal(s->bounds))) { /* cannot happen within the ranges; a float check costs nothing */
        snprintf(err, errlen, "%s: the bounding box's diagonal is not finite", what(s));
        return -1;
    }

    /* Vertex normals, when there are any, cover every vertex. */
    if (s->normals) reserve_normals(s, s->prims.nverts, false);
    scene_impl *si = (scene_impl *)s;
    if (si->material_upto < s->prims.count) {
        material_t grey = {v3(0.8f, 0.8f, 0.8f), 0.8f, 0.2f, 0.0f, 1.0f};
        scene_set_material_upto(s, scene_add_material(s, grey));
    }
    if (!has_camera) default_camera(s, SCENE_UP_CATALOGUE);
    snprintf(s->view, sizeof s->view, "%s", has_camera ? "source" : "automatic");
    s->made_up = (has_camera ? 0 : SCENE_MADE_CAMERA) | (s->nlights ? 0 : SCENE_MADE_LIGHTS);
    if (s->nlights == 0) default_lights(s);
    /* The source's view and lights, and also the defaults: within the
     * geometry's range they always fit, but the check is where rays start. */
    if (scene_check_view(&s->camera, s->lights, s->nlights, why, sizeof why) != 0) {
        snprintf(err, errlen, "%s: %s", what(s), why);
        return -1;
    }
    return 0;
}

void scene_set_up_axis(scene_t *s, int axis)
{
    if (!(s->made_up & SCENE_MADE_CAMERA)) {
        s->camera.up = scene_up_vector(s, axis);
        return;
    }
    default_camera(s, axis);
    if (s->made_up & SCENE_MADE_LIGHTS) {
        s->nlights = 0;
        default_lights(s);
    }
}
