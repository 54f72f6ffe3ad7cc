/* prims.c: the primitive store and the dispatch of box overlap, normals
 * and the verification helpers. The ray tests' dispatch, counting and not,
 * is intersect.c; kernels live in triangle.c, sphere.c, cone.c, polygon.c
 * and overlap.c. */
#include "prims.h"
#include "prims_internal.h"
#include "checked_alloc.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Room for `need` items of an array: the capacity doubles from 64 (in 64
 * bits, so the last doubling stops at the 2^32 - 1 ids instead of wrapping
 * to 0), through the checked allocator. An array whose capacity already
 * holds need is left alone, so a maker that knows its counts (the SPD
 * generators) can reserve them exactly. */
static void *grow(void *ptr, uint32_t *cap, uint32_t need, size_t elem, const char *what)
{
    if (need <= *cap) return ptr;
    uint64_t ncap = *cap ? *cap : 64;
    while (ncap < need) ncap *= 2;
    if (ncap > UINT32_MAX) ncap = UINT32_MAX;
    void *n = checked_realloc(ptr, checked_array_bytes((size_t)ncap, elem, what), what);
    *cap = (uint32_t)ncap;
    return n;
}

/* A count about to pass the 2^32 - 1 ids: loaders and generators refuse
 * such scenes first (with the file and line, or the generator's counts), so
 * reaching this is a maker's bug; it is still an exit 2, never a wrap. */
static void check_room(uint32_t count, uint32_t more, const char *what)
{
    if (more > UINT32_MAX - 1 - count) {
        fprintf(stderr, "accelbench: the primitive store holds at most 2^32 - 2 %s\n", what);
        exit(2);
    }
}

void prims_init(prims_t *p)
{
    memset(p, 0, sizeof *p);
    p->box = box_empty();
}

uint32_t prims_add_vertex(prims_t *p, vec3 v)
{
    check_room(p->nverts, 1, "vertices");
    p->verts = grow(p->verts, &p->nverts_cap, p->nverts + 1, sizeof *p->verts, "the primitive store's vertices");
    p->verts[p->nverts] = v;
    return p->nverts++;
}

static uint32_t add_prim(prims_t *p, prim_kind kind, uint32_t index)
{
    uint32_t cap = p->count_cap;
    p->kind = grow(p->kind, &cap, p->count + 1, sizeof *p->kind, "the primitive store's kinds");
    cap = p->count_cap;
    p->index = grow(p->index, &cap, p->count + 1, sizeof *p->index, "the primitive store's indices");
    p->count_cap = cap;
    p->kind[p->count] = (uint8_t)kind;
    p->index[p->count] = index;
    return p->count++;
}

uint32_t prims_add_triangle(prims_t *p, uint32_t a, uint32_t b, uint32_t c)
{
    check_room(p->count, 1, "primitives"); /* the kind's own count is at most this */
    p->tris = grow(p->tris, &p->ntris_cap, p->ntris + 1, sizeof *p->tris, "the primitive store's triangles");
    tri_t t = {{a, b, c}};
    p->tris[p->ntris] = t;
    return add_prim(p, PRIM_TRIANGLE, p->ntris++);
}

uint32_t prims_add_sphere(prims_t *p, vec3 center, float radius)
{
    check_room(p->count, 1, "primitives"); /* the kind's own count is at most this */
    p->spheres = grow(p->spheres, &p->nspheres_cap, p->nspheres + 1, sizeof *p->spheres, "the primitive store's spheres");
    sphere_t s = {center, radius};
    p->spheres[p->nspheres] = s;
    return add_prim(p, PRIM_SPHERE, p->nspheres++);
}

uint32_t prims_add_cone(prims_t *p, vec3 base, float base_radius, vec3 apex, float apex_radius)
{
    check_room(p->count, 1, "primitives"); /* the kind's own count is at most this */
    p->cones = grow(p->cones, &p->ncones_cap, p->ncones + 1, sizeof *p->cones, "the primitive store's cones");
    cone_t c = {base, base_radius, apex, apex_radius};
    p->cones[p->ncones] = c;
    return add_prim(p, PRIM_CONE, p->ncones++);
}

uint32_t prims_add_polygon(prims_t *p, const uint32_t *vertex_indices, uint32_t n)
{
    check_room(p->count, 1, "primitives"); /* the kind's own count is at most this */
    check_room(p->npoly_verts, n, "polygon vertices");
    p->poly_verts = grow(p->poly_verts, &p->npoly_verts_cap, p->npoly_verts + n, sizeof *p->poly_verts,
                         "the primitive store's polygon vertices");
    if (n) memcpy(p->poly_verts + p->npoly_verts, vertex_indices, (size_t)n * sizeof *p->poly_verts);
    p->polygons = grow(p->polygons, &p->npolygons_cap, p->npolygons + 1, sizeof *p->polygons,
                       "the primitive store's polygons");
    polygon_t g;
    memset(&g, 0, sizeof g);
    g.first = p->npoly_verts;
    g.count = n;
    p->polygons[p->npolygons] = g;
    p->npoly_verts += n;
    return add_prim(p, PRIM_POLYGON, p->npolygons++);
}

/* prims_finish for one cone: validation and tight bounds. */
static int finish_cone(prims_t *p, uint32_t id, box3 *b, char *err, size_t errlen)
{
    uint32_t k = p->index[id];
    cone_t c = p->cones[k];
    const char *why = NULL;
    if (!v3_finite(c.base) || !v3_finite(c.apex) || !isfinite(c.base_radius) || !isfinite(c.apex_radius))
        why = "need finite values";
    else if (c.base_radius < 0.0f || c.apex_radius < 0.0f)
        why = "need radii >= 0";
    else if (c.base_radius == 0.0f && c.apex_radius == 0.0f)
        why = "need a radius > 0";
    else if (c.base.x == c.apex.x && c.base.y == c.apex.y && c.base.z == c.apex.z)
        why = "need base != apex";
    if (why) {
        snprintf(err, errlen, "cone %u (primitive %u) has base (%g %g %g) radius %g, apex (%g %g %g) radius %g: %s",
                 k, id, c.base.x, c.base.y, c.base.z, c.base_radius, c.apex.x, c.apex.y, c.apex.z, c.apex_radius, why);
        return -1;
    }
    *b = cone_bounds(c);
    return 0;
}

/* prims_finish for one polygon: validation, plane, triangulation into
 * p->poly_tris at *ntri (scratch holds its points), bounds. */
static int finish_polygon(prims_t *p, uint32_t id, box3 *b, vec3 *scratch, uint32_t (*ltris)[3], uint32_t *ntri,
                          char *err, size_t errlen)
{
    uint32_t k = p->index[id];
    polygon_t *g = &p->polygons[k];
    const uint32_t *idx = p->poly_verts + g->first;
    if (g->count < 3) {
        snprintf(err, errlen, "polygon %u (primitive %u) has %u vertices: need at least 3", k, id, g->count);
        return -1;
    }
    for (uint32_t j = 0; j < g->count; j++) {
        if (idx[j] >= p->nverts) {
            snprintf(err, errlen, "polygon %u (primitive %u) uses vertex %u of %u", k, id, idx[j], p->nverts);
            return -1;
        }
        scratch[j] = p->verts[idx[j]];
        *b = box_grow(*b, scratch[j]);
    }
    dvec3 n;
    double off;
    int axis;
    bool ok = polygon_plane(p->verts, idx, g->count, &n, &off, &axis);
    g->normal = v3((float)n.x, (float)n.y, (float)n.z);
    g->offset = (float)off;
    g->axis = (uint8_t)axis;
    g->degenerate = !ok;
    if (!ok) p->npoly_degenerate++;

    /* Triangulate (even a degenerate polygon: its box overlap is still
     * the exact overlap of its segments) and map to global indices. */
    uint32_t nt = polygon_triangulate(scratch, g->count, g->normal, ltris);
    g->tri_first = *ntri;
    for (uint32_t t = 0; t < nt; t++) {
        tri_t tr = {{idx[ltris[t][0]], idx[ltris[t][1]], idx[ltris[t][2]]}};
        p->poly_tris[*ntri + t] = tr;
    }
    *ntri += nt;
    return 0;
}

int prims_finish(prims_t *p, char *err, size_t errlen)
{
    for (uint32_t i = 0; i < p->nverts; i++)
        if (!v3_finite(p->verts[i])) {
            snprintf(err, errlen, "vertex %u has a NaN or infinite coordinate", i);
            return -1;
        }
    free(p->bounds);
    free(p->tri_degenerate);
    p->bounds = malloc((size_t)(p->count ? p->count : 1) * sizeof *p->bounds);
    p->tri_degenerate = calloc(p->ntris ? p->ntris : 1, 1);
    if (!p->bounds || !p->tri_degenerate) {
        snprintf(err, errlen, "out of memory for %u primitive bounds", p->count);
        return -1;
    }
    p->ndegenerate = 0;
    p->box = box_empty();

    /* Polygons: room for every triangulation (n - 2 triangles each) and
     * scratch for the largest one. */
    uint32_t maxn = 0;
    size_t ntris_total = 0;
    for (uint32_t k = 0; k < p->npolygons; k++) {
        uint32_t n = p->polygons[k].count;
        maxn = n > maxn ? n : maxn;
        ntris_total += n >= 3 ? n - 2 : 0;
    }
    free(p->poly_tris);
    p->poly_tris = NULL;
    p->npoly_tris = 0;
    p->npoly_degenerate = 0;
    vec3 *scratch = NULL;
    uint32_t (*ltris)[3] = NULL;
    if (p->npolygons) {
        p->poly_tris = malloc((ntris_total ? ntris_total : 1) * sizeof *p->poly_tris);
        scratch = malloc((size_t)(maxn ? maxn : 1) * sizeof *scratch);
        ltris = malloc((size_t)(maxn ? maxn : 1) * sizeof *ltris);
        if (!p->poly_tris || !scratch || !ltris) {
            free(scratch);
            free(ltris);
            snprintf(err, errlen, "out of memory for %zu polygon triangles", ntris_total);
            return -1;
        }
    }
    uint32_t ntri = 0;
    int rc = 0;

    for (uint32_t id = 0; id < p->count && rc == 0; id++) {
        uint32_t k = p->index[id];
        box3 b = box_empty();
        if (p->kind[id] == PRIM_CONE) {
            rc = finish_cone(p, id, &b, err, errlen);
        } else if (p->kind[id] == PRIM_POLYGON) {
            rc = finish_polygon(p, id, &b, scratch, ltris, &ntri, err, errlen);
        } else if (p->kind[id] == PRIM_TRIANGLE) {
            const tri_t *t = &p->tris[k];
            for (int j = 0; j < 3 && rc == 0; j++) {
                if (t->v[j] >= p->nverts) {
                    snprintf(err, errlen, "triangle %u (primitive %u) uses vertex %u of %u", k, id, t->v[j], p->nverts);
                    rc = -1;
                } else {
                    b = box_grow(b, p->verts[t->v[j]]);
                }
            }
            if (rc) break;
            vec3 a = p->verts[t->v[0]], bb = p->verts[t->v[1]], c = p->verts[t->v[2]];
            vec3 n = v3_cross(v3_sub(bb, a), v3_sub(c, a));
            if (v3_dot(n, n) == 0.0f || !v3_finite(n)) {
                p->tri_degenerate[k] = 1;
                p->ndegenerate++;
            }
        } else {
            sphere_t s = p->spheres[k];
            if (!v3_finite(s.center) || !isfinite(s.radius) || !(s.radius > 0.0f)) {
                snprintf(err, errlen, "sphere %u (primitive %u) has centre (%g %g %g) radius %g: need finite values and radius > 0",
                         k, id, s.center.x, s.center.y, s.center.z, s.radius);
                rc = -1;
                break;
            }
            /* c -+ r in double, rounded outward: a float sum rounded to
             * nearest can land half a step inside the sphere. */
            double r = s.radius;
            b.lo = v3(float_down(s.center.x - r), float_down(s.center.y - r), float_down(s.center.z - r));
            b.hi = v3(float_up(s.center.x + r), float_up(s.center.y + r), float_up(s.center.z + r));
        }
        if (rc) break;
        p->bounds[id] = b;
        p->box = box_union(p->box, b);
    }
    free(scratch);
    free(ltris);
    p->npoly_tris = ntri;
    return rc;
}

void prims_free(prims_t *p)
{
    free(p->kind);
    free(p->index);
    free(p->bounds);
    free(p->verts);
    free(p->tris);
    free(p->tri_degenerate);
    free(p->spheres);
    free(p->cones);
    free(p->polygons);
    free(p->poly_verts);
    free(p->poly_tris);
    prims_init(p);
}

size_t prims_memory(const prims_t *p)
{
    return (size_t)p->count * (sizeof *p->kind + sizeof *p->index + sizeof *p->bounds) +
           (size_t)p->nverts * sizeof *p->verts + (size_t)p->ntris * (sizeof *p->tris + 1) +
           (size_t)p->nspheres * sizeof *p->spheres + (size_t)p->ncones * sizeof *p->cones +
           (size_t)p->npolygons * sizeof *p->polygons + (size_t)p->npoly_verts * sizeof *p->poly_verts +
           (size_t)p->npoly_tris * sizeof *p->poly_tris;
}

static inline dvec3 hit_point_double(const ray_t *ray, double t)
{
    dvec3 o = dv3(ray->org), d = dv3(ray->dir);
    dvec3 hp = {o.x + d.x * t, o.y + d.y * t, o.z + d.z * t};
    return hp;
}

bool prim_overlaps_box(const prims_t *p, uint32_t id, box3 box)
{
    uint32_t k = p->index[id];
    switch ((prim_kind)p->kind[id]) {
    case PRIM_TRIANGLE: {
        vec3 a, b, c;
        tri_verts(p, k, &a, &b, &c);
        return triangle_overlaps_box(a, b, c, box);
    }
    case PRIM_SPHERE:
        return sphere_overlaps_box(p->spheres[k], box);
    case PRIM_CONE:
        return cone_overlaps_box(p->cones[k], box);
    case PRIM_POLYGON: {
        /* The exact bounds first: they reject most boxes for the price of
         * one test instead of count - 2 triangle tests. */
        if (!box_overlap(p->bounds[id], box)) return false;
        const polygon_t *g = &p->polygons[k];
        return polygon_overlaps_box(p->verts, p->poly_tris + g->tri_first, g->count - 2, box);
    }
    default:
        return false;
    }
}

vec3 prim_normal(const prims_t *p, const hit_t *hit, const ray_t *ray)
{
    uint32_t k = p->index[hit->prim];
    switch ((prim_kind)p->kind[hit->prim]) {
    case PRIM_TRIANGLE: {
        vec3 a, b, c;
        tri_verts(p, k, &a, &b, &c);
        return v3_norm(v3_cross(v3_sub(b, a), v3_sub(c, a)));
    }
    case PRIM_SPHERE: {
        sphere_t s = p->spheres[k];
        vec3 hp = v3_madd(ray->org, ray->dir, hit->t);
        return v3_norm(v3_sub(hp, s.center));
    }
    case PRIM_CONE:
        return cone_normal(p->cones[k], v3_madd(ray->org, ray->dir, hit->t));
    case PRIM_POLYGON:
        return p->polygons[k].normal;
    default:
        return v3(0.0f, 0.0f, 0.0f);
    }
}

bool prim_intersect_double(const prims_t *p, uint32_t id, const ray_t *ray, double *t)
{
    uint32_t k = p->index[id];
    switch ((prim_kind)p->kind[id]) {
    case PRIM_TRIANGLE: {
        if (p->tri_degenerate[k]) return false;
        vec3 a, b, c;
        tri_verts(p, k, &a, &b, &c);
        return triangle_intersect_double(a, b, c, ray, t);
    }
    case PRIM_SPHERE:
        return sphere_intersect_double(p->spheres[k], ray, t);
    case PRIM_CONE:
        return cone_intersect_double(p->cones[k], ray, t);
    case PRIM_POLYGON: {
        const polygon_t *g = &p->polygons[k];
        if (g->degenerate) return false;
        return polygon_intersect_double(p->verts, p->poly_verts + g->first, g->count, ray, t);
    }
    default:
        return false;
    }
}

double prim_plane_distance(const prims_t *p, uint32_t id, vec3 q)
{
    if ((prim_kind)p->kind[id] != PRIM_TRIANGLE) return NAN;
    vec3 a, b, c;
    tri_verts(p, p->index[id], &a, &b, &c);
    const double e1[3] = {(double)b.x - a.x, (double)b.y - a.y, (double)b.z - a.z};
    const double e2[3] = {(double)c.x - a.x, (double)c.y - a.y, (double)c.z - a.z};
    const double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (!(len > 0.0)) return NAN;
    return fabs(n[0] * ((double)q.x - a.x) + n[1] * ((double)q.y - a.y) + n[2] * ((double)q.z - a.z)) / len;
}

double prim_boundary_distance(const prims_t *p, uint32_t id, const ray_t *ray, double t)
{
    uint32_t k = p->index[id];
    switch ((prim_kind)p->kind[id]) {
    case PRIM_TRIANGLE: {
        vec3 a, b, c;
        tri_verts(p, k, &a, &b, &c);
        return triangle_boundary_distance(a, b, c, hit_point_double(ray, t));
    }
    case PRIM_SPHERE:
        return sphere_boundary_distance(p->spheres[k], ray);
    case PRIM_CONE:
        return cone_boundary_distance(p->cones[k], ray, t);
    case PRIM_POLYGON: {
        const polygon_t *g = &p->polygons[k];
        return polygon_boundary_distance(p->verts, p->poly_verts + g->first, g->count, hit_point_double(ray, t));
    }
    default:
        return 0.0;
    }
}
