/* nff_write.c: the NFF writer (scene_write_nff) and the geometry hash that
 * tells whether a round trip kept the scene (scene_geometry_hash).
 *
 * Format reference: NFF.TXT v3.9 by Eric Haines. The layout follows the SPD
 * 3.14 writer (shared/SPD-SCENES.md): `b`, `v`, the lights, then the
 * objects with an `f` before each change of material, and `c` with all
 * eight numbers on one line. Unlike the SPD's %g, numbers are printed with
 * %.9g: nine significant digits identify every float exactly, so a scene
 * written and read back is bit-identical in its geometry. */
#include "nff.h"

#include <ctype.h>
#include <errno.h>
#include <string.h>

/* ----------------------------------------------------------------- hash */

#define FNV_OFFSET 0xcbf29ce484222325ull
#define FNV_PRIME 0x100000001b3ull

/* Hash a 32-bit value as 4 little-endian bytes, so the hash does not
 * depend on the host's byte order. */
static uint64_t fnv_u32(uint64_t h, uint32_t v)
{
    for (int i = 0; i < 4; i++) {
        h ^= (v >> (8 * i)) & 0xffu;
        h *= FNV_PRIME;
    }
    return h;
}

static uint64_t fnv_float(uint64_t h, float f)
{
    uint32_t bits;
    memcpy(&bits, &f, sizeof bits);
    return fnv_u32(h, bits);
}

static uint64_t fnv_vec3(uint64_t h, vec3 v)
{
    return fnv_float(fnv_float(fnv_float(h, v.x), v.y), v.z);
}

/* A smooth primitive's vertex normals (after its geometry), so that a
 * round trip that lost them or a `pp` read as `p` changes the hash. */
static uint64_t hash_normals(uint64_t h, const scene_t *s, uint32_t id)
{
    if (!scene_prim_smooth(s, id)) return h;
    const prims_t *p = &s->prims;
    uint32_t k = p->index[id];
    h = fnv_u32(h, 0x7070u); /* "pp" */
    if (p->kind[id] == PRIM_TRIANGLE)
        for (int j = 0; j < 3; j++) h = fnv_vec3(h, s->normals[p->tris[k].v[j]]);
    else
        for (uint32_t j = 0; j < p->polygons[k].count; j++)
            h = fnv_vec3(h, s->normals[p->poly_verts[p->polygons[k].first + j]]);
    return h;
}

static uint64_t hash_prim(uint64_t h, const prims_t *p, uint32_t id)
{
    uint32_t k = p->index[id];
    h ^= p->kind[id];
    h *= FNV_PRIME;
    switch (p->kind[id]) {
    case PRIM_TRIANGLE:
        for (int j = 0; j < 3; j++) h = fnv_vec3(h, p->verts[p->tris[k].v[j]]);
        break;
    case PRIM_SPHERE:
        h = fnv_float(fnv_vec3(h, p->spheres[k].center), p->spheres[k].radius);
        break;
    case PRIM_CONE: {
        const cone_t *c = &p->cones[k];
        h = fnv_float(fnv_vec3(h, c->base), c->base_radius);
        h = fnv_float(fnv_vec3(h, c->apex), c->apex_radius);
        break;
    }
    case PRIM_POLYGON: {
        const polygon_t *g = &p->polygons[k];
        h = fnv_u32(h, g->count);
        for (uint32_t j = 0; j < g->count; j++) h = fnv_vec3(h, p->verts[p->poly_verts[g->first + j]]);
        break;
    }
    default:
        break;
    }
    return h;
}

uint64_t scene_geometry_hash(const scene_t *s)
{
    uint64_t h = FNV_OFFSET;
    for (uint32_t id = 0; id < s->prims.count; id++) h = hash_normals(hash_prim(h, &s->prims, id), s, id);
    return h;
}

/* --------------------------------------------------------------- writer */

static void put_vec3(FILE *f, vec3 v)
{
    fprintf(f, "%.9g %.9g %.9g", (double)v.x, (double)v.y, (double)v.z);
}

/* The scene's origin in a comment line: unprintable bytes (a newline in
 * a name would end the comment) become '?'. */
static void write_origin(FILE *f, const scene_t *s)
{
    fputs("# ", f);
    for (const char *c = s->source[0] ? s->source : s->name; *c; c++)
        fputc(isprint((unsigned char)*c) ? *c : '?', f);
    fputs(", written by accelbench (NFF, NFF.TXT v3.9)\n", f);
}

static void write_header(FILE *f, const scene_t *s)
{
    const camera_t *c = &s->camera;
    write_origin(f, s);
    fputs("# f lines: shine is not kept by accelbench; written as 3.0827\n", f);
    fputs("b ", f);
    put_vec3(f, s->background);
    fputs("\nv\nfrom ", f);
    put_vec3(f, c->from);
    fputs("\nat ", f);
    put_vec3(f, c->at);
    fputs("\nup ", f);
    put_vec3(f, c->up);
    fprintf(f, "\nangle %.9g\nhither %.9g\nresolution %d %d\n", (double)c->fov_deg, (double)c->hither, c->width,
            c->height);
    for (uint32_t i = 0; i < s->nlights; i++) {
        fputs("l ", f);
        put_vec3(f, s->lights[i]);
        fputc('\n', f);
    }
}

static void write_material(FILE *f, const material_t *m)
{
    fputs("f ", f);
    put_vec3(f, m->color);
    fprintf(f, " %.9g %.9g 3.0827 %.9g %.9g\n", (double)m->kd, (double)m->ks, (double)m->t, (double)m->ior);
}

/* A `p N` block: the count, then one vertex per line; or, given vertex
 * normals, a `pp N` block with each vertex's normal after it. */
static void write_points(FILE *f, const prims_t *p, const vec3 *normals, const uint32_t *idx, uint32_t n)
{
    fprintf(f, "%s %u\n", normals ? "pp" : "p", n);
    for (uint32_t j = 0; j < n; j++) {
        put_vec3(f, p->verts[idx[j]]);
        if (normals) {
            fputc(' ', f);
            put_vec3(f, normals[idx[j]]);
        }
        fputc('\n', f);
    }
}

static void write_prim(FILE *f, const scene_t *s, uint32_t id)
{
    const prims_t *p = &s->prims;
    const vec3 *normals = scene_prim_smooth(s, id) ? s->normals : NULL;
    uint32_t k = p->index[id];
    switch (p->kind[id]) {
    case PRIM_TRIANGLE:
        write_points(f, p, normals, p->tris[k].v, 3);
        break;
    case PRIM_SPHERE:
        fputs("s ", f);
        put_vec3(f, p->spheres[k].center);
        fprintf(f, " %.9g\n", (double)p->spheres[k].radius);
        break;
    case PRIM_CONE: {
        const cone_t *c = &p->cones[k];
        fputs("c ", f);
        put_vec3(f, c->base);
        fprintf(f, " %.9g ", (double)c->base_radius);
        put_vec3(f, c->apex);
        fprintf(f, " %.9g\n", (double)c->apex_radius);
        break;
    }
    case PRIM_POLYGON:
        write_points(f, p, normals, p->poly_verts + p->polygons[k].first, p->polygons[k].count);
        break;
    default:
        break;
    }
}

/* The objects, with an `f` whenever the material changes. A scene that
 * was never finished may have no per-primitive materials: no `f` then. */
static void write_objects(FILE *f, const scene_t *s)
{
    const prims_t *p = &s->prims;
    uint32_t current = UINT32_MAX;
    for (uint32_t id = 0; id < p->count; id++) {
        if (s->prim_material && s->prim_material[id] < s->nmaterials && s->prim_material[id] != current) {
            current = s->prim_material[id];
            write_material(f, &s->materials[current]);
        }
        write_prim(f, s, id);
    }
}

int scene_write_nff(const scene_t *s, const char *path, char *err, size_t errlen)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        snprintf(err, errlen, "%s: %s", path, strerror(errno));
        return -1;
    }
    write_header(f, s);
    write_objects(f, s);
    /* Both checks: a full disk can show up in either. */
    int bad = ferror(f);
    int saved = errno;
    if (fclose(f) != 0 && !bad) {
        bad = 1;
        saved = errno;
    }
    if (bad) {
        snprintf(err, errlen, "%s: write error: %s", path, strerror(saved));
        return -1;
    }
    return 0;
}
