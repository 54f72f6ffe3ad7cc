/* prims.c: the primitive store and the dispatch that counts tests.
 * Kernels live in triangle.c, sphere.c and overlap.c. */
#include "prims.h"
#include "prims_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void *grow(void *ptr, uint32_t *cap, uint32_t need, size_t elem)
{
    if (need <= *cap) return ptr;
    uint32_t ncap = *cap ? *cap : 64;
    while (ncap < need) ncap *= 2;
    void *n = realloc(ptr, (size_t)ncap * elem);
    if (!n) {
        fprintf(stderr, "accelbench: out of memory growing the primitive store to %u items\n", ncap);
        abort();
    }
    *cap = ncap;
    return n;
}

void prims_init(prims_t *p)
{
    memset(p, 0, sizeof *p);
    p->box = box_empty();
}

uint32_t prims_add_vertex(prims_t *p, vec3 v)
{
    p->verts = grow(p->verts, &p->nverts_cap, p->nverts + 1, sizeof *p->verts);
    p->verts[p->nverts] = v;
    return p->nverts++;
}

static uint32_t add_prim(prims_t *p, prim_kind kind, uint32_t index)
{
    uint32_t cap = p->count_cap;
    p->kind = grow(p->kind, &cap, p->count + 1, sizeof *p->kind);
    cap = p->count_cap;
    p->index = grow(p->index, &cap, p->count + 1, sizeof *p->index);
    p->count_cap = cap;
    p->kind[p->count] = (uint8_t)kind;
    p->index[p->count] = index;
    return p->count++;
}

uint32_t prims_add_triangle(prims_t *p, uint32_t a, uint32_t b, uint32_t c)
{
    p->tris = grow(p->tris, &p->ntris_cap, p->ntris + 1, sizeof *p->tris);
    tri_t t = {{a, b, c}};
    p->tris[p->ntris] = t;
    return add_prim(p, PRIM_TRIANGLE, p->ntris++);
}

uint32_t prims_add_sphere(prims_t *p, vec3 center, float radius)
{
    p->spheres = grow(p->spheres, &p->nspheres_cap, p->nspheres + 1, sizeof *p->spheres);
    sphere_t s = {center, radius};
    p->spheres[p->nspheres] = s;
    return add_prim(p, PRIM_SPHERE, p->nspheres++);
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
    for (uint32_t id = 0; id < p->count; id++) {
        uint32_t k = p->index[id];
        box3 b = box_empty();
        if (p->kind[id] == PRIM_TRIANGLE) {
            const tri_t *t = &p->tris[k];
            for (int j = 0; j < 3; j++) {
                if (t->v[j] >= p->nverts) {
                    snprintf(err, errlen, "triangle %u (primitive %u) uses vertex %u of %u", k, id, t->v[j], p->nverts);
                    return -1;
                }
                b = box_grow(b, p->verts[t->v[j]]);
            }
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
                return -1;
            }
            vec3 r = v3(s.radius, s.radius, s.radius);
            b.lo = v3_sub(s.center, r);
            b.hi = v3_add(s.center, r);
        }
        p->bounds[id] = b;
        p->box = box_union(p->box, b);
    }
    return 0;
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
    prims_init(p);
}

size_t prims_memory(const prims_t *p)
{
    return (size_t)p->count * (sizeof *p->kind + sizeof *p->index + sizeof *p->bounds) +
           (size_t)p->nverts * sizeof *p->verts + (size_t)p->ntris * (sizeof *p->tris + 1) +
           (size_t)p->nspheres * sizeof *p->spheres;
}

static inline void tri_verts(const prims_t *p, uint32_t k, vec3 *a, vec3 *b, vec3 *c)
{
    const tri_t *t = &p->tris[k];
    *a = p->verts[t->v[0]];
    *b = p->verts[t->v[1]];
    *c = p->verts[t->v[2]];
}

bool prim_overlaps_box(const prims_t *p, uint32_t id, box3 box)
{
    uint32_t k = p->index[id];
    if (p->kind[id] == PRIM_TRIANGLE) {
        vec3 a, b, c;
        tri_verts(p, k, &a, &b, &c);
        return triangle_overlaps_box(a, b, c, box);
    }
    return sphere_overlaps_box(p->spheres[k], box);
}

bool prim_intersect(const prims_t *p, uint32_t id, const ray_t *ray, hit_t *hit, counters_t *c)
{
    uint32_t k = p->index[id];
    float t, u = 0.0f, v = 0.0f;
    bool ok;
    c->prim_tests++;
    if (p->kind[id] == PRIM_TRIANGLE) {
        if (p->tri_degenerate[k]) return false;
        vec3 a, b, cc;
        tri_verts(p, k, &a, &b, &cc);
        ok = triangle_intersect(a, b, cc, ray, hit->t, &t, &u, &v);
    } else {
        ok = sphere_intersect(p->spheres[k], ray, hit->t, &t);
    }
    if (!ok) return false;
    c->prim_hits++;
    hit->t = t;
    hit->u = u;
    hit->v = v;
    hit->prim = id;
    return true;
}

bool prim_occluded(const prims_t *p, uint32_t id, const ray_t *ray, counters_t *c)
{
    hit_t h = hit_none(ray);
    return prim_intersect(p, id, ray, &h, c);
}

vec3 prim_normal(const prims_t *p, const hit_t *hit, const ray_t *ray)
{
    uint32_t k = p->index[hit->prim];
    if (p->kind[hit->prim] == PRIM_TRIANGLE) {
        vec3 a, b, c;
        tri_verts(p, k, &a, &b, &c);
        return v3_norm(v3_cross(v3_sub(b, a), v3_sub(c, a)));
    }
    sphere_t s = p->spheres[k];
    vec3 hp = v3_madd(ray->org, ray->dir, hit->t);
    return v3_norm(v3_sub(hp, s.center));
}

bool prim_intersect_double(const prims_t *p, uint32_t id, const ray_t *ray, double *t)
{
    uint32_t k = p->index[id];
    if (p->kind[id] == PRIM_TRIANGLE) {
        if (p->tri_degenerate[k]) return false;
        vec3 a, b, c;
        tri_verts(p, k, &a, &b, &c);
        return triangle_intersect_double(a, b, c, ray, t);
    }
    return sphere_intersect_double(p->spheres[k], ray, t);
}

double prim_boundary_distance(const prims_t *p, uint32_t id, const ray_t *ray, double t)
{
    uint32_t k = p->index[id];
    if (p->kind[id] == PRIM_TRIANGLE) {
        vec3 a, b, c;
        tri_verts(p, k, &a, &b, &c);
        dvec3 o = dv3(ray->org), d = dv3(ray->dir);
        dvec3 hp = {o.x + d.x * t, o.y + d.y * t, o.z + d.z * t};
        return triangle_boundary_distance(a, b, c, hp);
    }
    return sphere_boundary_distance(p->spheres[k], ray);
}
