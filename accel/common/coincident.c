/* coincident.c: coincident primitives (coincident.h). */
#include <stdlib.h>
#include <string.h>
#include "coincident.h"
#include "hash.h"

/* The points that define primitive id, in a canonical order; n of them.
 * Polygons are compared in place (their vertex count is unbounded). */
static int canon_points(const prims_t *p, uint32_t id, vec3 out[3], float *radius)
{
    uint32_t i = p->index[id];
    *radius = 0.0f;
    switch (p->kind[id]) {
    case PRIM_TRIANGLE: {
        vec3 v[3];
        for (int k = 0; k < 3; k++) v[k] = p->verts[p->tris[i].v[k]];
        /* Sort the three lexicographically: any order, either winding. */
        for (int a = 0; a < 2; a++)
            for (int b = a + 1; b < 3; b++) {
                bool less = v[b].x < v[a].x || (v[b].x == v[a].x && (v[b].y < v[a].y || (v[b].y == v[a].y && v[b].z < v[a].z)));
                if (less) {
                    vec3 t = v[a];
                    v[a] = v[b], v[b] = t;
                }
            }
        memcpy(out, v, sizeof v);
        return 3;
    }
    case PRIM_SPHERE:
        out[0] = p->spheres[i].center;
        *radius = p->spheres[i].radius;
        return 1;
    case PRIM_CONE: {
        const cone_t *c = &p->cones[i];
        vec3 a = c->base, b = c->apex;
        float ra = c->base_radius, rb = c->apex_radius;
        bool swap = b.x < a.x || (b.x == a.x && (b.y < a.y || (b.y == a.y && (b.z < a.z || (b.z == a.z && rb < ra)))));
        out[0] = swap ? b : a, out[1] = swap ? a : b;
        out[2] = v3(swap ? rb : ra, swap ? ra : rb, 0.0f);
        return 3;
    }
    default:
        return 0;
    }
}

static inline uint64_t mix(uint64_t h, float x)
{
    x += 0.0f; /* -0 and +0 alike */
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    h ^= u;
    h *= 0x100000001b3ull; /* FNV-1a's prime, over 32-bit words */
    return h ^ (h >> 29);
}

static uint64_t geometry_hash(const prims_t *p, uint32_t id)
{
    uint64_t h = 0xcbf29ce484222325ull ^ p->kind[id];
    if (p->kind[id] == PRIM_POLYGON) {
        const polygon_t *g = &p->polygons[p->index[id]];
        for (uint32_t k = 0; k < g->count; k++) {
            vec3 v = p->verts[p->poly_verts[g->first + k]];
            h = mix(mix(mix(h, v.x), v.y), v.z);
        }
        return h;
    }
    vec3 v[3];
    float r;
    int n = canon_points(p, id, v, &r);
    for (int k = 0; k < n; k++) h = mix(mix(mix(h, v[k].x), v[k].y), v[k].z);
    return mix(h, r);
}

static inline bool same_point(vec3 a, vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

static bool same_geometry(const prims_t *p, uint32_t a, uint32_t b)
{
    if (p->kind[a] != p->kind[b]) return false;
    if (p->kind[a] == PRIM_POLYGON) {
        const polygon_t *ga = &p->polygons[p->index[a]], *gb = &p->polygons[p->index[b]];
        if (ga->count != gb->count) return false;
        for (uint32_t k = 0; k < ga->count; k++)
            if (!same_point(p->verts[p->poly_verts[ga->first + k]], p->verts[p->poly_verts[gb->first + k]])) return false;
        return true;
    }
    vec3 va[3], vb[3];
    float ra, rb;
    int n = canon_points(p, a, va, &ra);
    canon_points(p, b, vb, &rb);
    for (int k = 0; k < n; k++)
        if (!same_point(va[k], vb[k])) return false;
    return ra == rb;
}

uint64_t prim_classes_scratch_bytes(uint32_t n)
{
    /* rep, and a table of at most 4n slots of 16 bytes (load 1/4 to 1/2). */
    return (uint64_t)n * 4 + (uint64_t)n * 4 * sizeof(hash_slot) + 64;
}

int prim_classes_init(prim_classes *c, const prims_t *p)
{
    c->rep = NULL;
    c->classes = p->count;
    if (p->count < 2) return 0;
    uint32_t *rep = malloc((size_t)p->count * sizeof *rep);
    hash_table h;
    if (!rep || hash_init(&h, p->count)) {
        free(rep);
        return -1;
    }
    uint32_t classes = 0;
    for (uint32_t id = 0; id < p->count; id++) {
        uint64_t key = geometry_hash(p, id);
        for (;;) {
            bool added;
            uint32_t *v = hash_insert(&h, key, id, &added);
            if (!v) {
                hash_free(&h);
                free(rep);
                return -1;
            }
            if (added) {
                rep[id] = id, classes++;
                break;
            }
            if (same_geometry(p, *v, id)) {
                rep[id] = *v;
                break;
            }
            key = key * 0x9e3779b97f4a7c15ull + 1; /* another geometry with this hash: the next key */
        }
    }
    hash_free(&h);
    if (classes == p->count) {
        free(rep);
        return 0;
    }
    c->rep = rep;
    c->classes = classes;
    return 0;
}

void prim_classes_free(prim_classes *c)
{
    free(c->rep);
    c->rep = NULL;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return x < y ? -1 : x > y;
}

bool prim_classes_at_most(const prim_classes *c, const uint32_t *ids, uint32_t n, uint64_t max)
{
    if (n <= max) return true;
    if (!c || !c->rep) return false;
    enum { SMALL = 32 };
    if (max < SMALL) {
        uint32_t seen[SMALL], k = 0;
        for (uint32_t i = 0; i < n; i++) {
            uint32_t r = c->rep[ids[i]], j = 0;
            while (j < k && seen[j] != r) j++;
            if (j < k) continue;
            if (k == max) return false;
            seen[k++] = r;
        }
        return true;
    }
    uint32_t *r = malloc((size_t)n * sizeof *r);
    if (!r) return false; /* the count as it is: no leaf by this rule */
    for (uint32_t i = 0; i < n; i++) r[i] = c->rep[ids[i]];
    qsort(r, n, sizeof *r, cmp_u32);
    uint64_t distinct = 0;
    for (uint32_t i = 0; i < n && distinct <= max; i++) distinct += i == 0 || r[i] != r[i - 1];
    free(r);
    return distinct <= max;
}
