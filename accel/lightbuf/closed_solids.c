/* closed_solids.c: the mesh analysis of closed_solids.h. */
#include "closed_solids.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "../bvh/bvh.h"
#include "../common/memcap.h"
#include "../../prims/tri_set.h"

typedef struct { uint32_t a, b, tri; } solid_edge;

/* Vertices by position: x and y index the coordinates at base (qsort_r's
 * argument, so that two builds may sort at once). */
static int vkey_cmp(const void *x, const void *y, void *base)
{
    const float *vb = base;
    const float *a = vb + 3 * (size_t)*(const uint32_t *)x, *b = vb + 3 * (size_t)*(const uint32_t *)y;
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
    return 0;
}
static int edge_cmp(const void *x, const void *y)
{
    const solid_edge *a = x, *b = y;
    uint32_t a0 = a->a < a->b ? a->a : a->b, a1 = a->a ^ a->b ^ a0, b0 = b->a < b->b ? b->a : b->b, b1 = b->a ^ b->b ^ b0;
    if (a0 != b0) return a0 < b0 ? -1 : 1;
    if (a1 != b1) return a1 < b1 ? -1 : 1;
    return a->a < b->a ? -1 : a->a > b->a;
}

static uint32_t uf_find(uint32_t *parent, uint32_t x)
{
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

/* Whether the closed component of triangles tr[0..n) is embedded: every
 * pair whose boxes (grown by tol) overlap meets only at the vertices and
 * edges they share, non-adjacent ones at least tol apart; found through
 * the kit's BVH over the grown boxes. Its signed volume must also be
 * positive (outward). false out of memory too (not culling is safe). */
static bool comp_embedded(dvec3 (*tr)[3], uint32_t (*tv)[3], uint32_t n)
{
    dvec3 lo = tr[0][0], hi = tr[0][0];
    double vol = 0;
    for (uint32_t j = 0; j < n; j++) {
        vol += dv3_dot(tr[j][0], dv3_cross(tr[j][1], tr[j][2]));
        for (int v = 0; v < 3; v++)
            lo = dv3_min(lo, tr[j][v]), hi = dv3_max(hi, tr[j][v]);
    }
    double diag = dv3_len(dv3_sub(hi, lo)), tol = 1e-9 * diag;
    if (!(vol > 1e-12 * diag * diag * diag)) return false;
    box3 *boxes = malloc((size_t)n * sizeof *boxes);
    uint32_t *stack = NULL;
    bvh_t b = {0};
    bool ok = false;
    if (!boxes) return false;
    for (uint32_t j = 0; j < n; j++) {
        box3 x = box_empty();
        for (int v = 0; v < 3; v++) {
            vec3 q = v3((float)tr[j][v].x, (float)tr[j][v].y, (float)tr[j][v].z);
            x = box_grow(x, q);
        }
        float g = (float)(2 * tol) + 1e-30f;
        x.lo = v3(nextafterf(x.lo.x - g, -INFINITY), nextafterf(x.lo.y - g, -INFINITY), nextafterf(x.lo.z - g, -INFINITY));
        x.hi = v3(nextafterf(x.hi.x + g, INFINITY), nextafterf(x.hi.y + g, INFINITY), nextafterf(x.hi.z + g, INFINITY));
        boxes[j] = x;
    }
    bvh_config cfg;
    bvh_config_defaults(&cfg);
    if (bvh_build_sah(&b, boxes, NULL, n, &cfg) || !b.nnodes) goto out;
    stack = malloc(((size_t)b.max_depth + 2) * 2 * sizeof *stack);
    if (!stack) goto out;
    for (uint32_t i = 0; i < n; i++) {
        uint32_t top = 0;
        stack[top++] = 0;
        while (top) {
            const bvh_node *nd = &b.nodes[stack[--top]];
            if (!box_overlap(nd->box, boxes[i])) continue;
            if (nd->count == 0) {
                stack[top++] = nd->index, stack[top++] = nd->index + 1;
                continue;
            }
            for (uint32_t k = 0; k < nd->count; k++) {
                uint32_t j = b.refs[nd->index + k];
                if (j > i && box_overlap(boxes[i], boxes[j]) && !tri_pair_joined_only(tr, tv, i, j, tol)) goto out;
            }
        }
    }
    ok = true;
out:
    free(boxes);
    free(stack);
    bvh_free(&b);
    return ok;
}

void closed_solids_free(closed_solids *ci)
{
    free(ci->comp);
    free(ci->cfirst);
    free(ci->ctris);
    free(ci->ctv);
    free(ci->ok);
    memset(ci, 0, sizeof *ci);
}

int closed_solids_find(const prims_t *p, closed_solids *ci)
{
    memset(ci, 0, sizeof *ci);
    uint32_t ntri = p->ntris + p->npoly_tris, nv = p->nverts;
    uint32_t *tv = malloc(((size_t)ntri * 3 + 1) * sizeof *tv), *owner = malloc(((size_t)ntri + 1) * sizeof *owner);
    uint32_t *order = malloc(((size_t)nv + 1) * sizeof *order), *canon = malloc(((size_t)nv + 1) * sizeof *canon);
    solid_edge *edges = malloc(((size_t)ntri * 3 + 1) * sizeof *edges);
    uint32_t *parent = malloc(((size_t)ntri + 1) * sizeof *parent), *bad = calloc((size_t)ntri + 1, sizeof *bad);
    ci->comp = malloc(((size_t)p->count + 1) * sizeof *ci->comp);
    int rc = -1;
    if (!tv || !owner || !order || !canon || !edges || !parent || !bad || !ci->comp) goto out;
    /* Every triangle and polygon ear triangle, with its owner. */
    uint32_t m = 0;
    for (uint32_t id = 0; id < p->count; id++) {
        ci->comp[id] = SOLID_NONE;
        uint32_t k = p->index[id];
        if (p->kind[id] == PRIM_TRIANGLE) {
            memcpy(&tv[3 * m], p->tris[k].v, 3 * sizeof *tv);
            owner[m++] = id;
        } else if (p->kind[id] == PRIM_POLYGON) {
            const polygon_t *g = &p->polygons[k];
            for (uint32_t t = 0; t + 2 < g->count; t++) {
                memcpy(&tv[3 * m], p->poly_tris[g->tri_first + t].v, 3 * sizeof *tv);
                owner[m++] = id;
            }
        }
    }
    ntri = m;
    /* Vertices matched by exact position. */
    for (uint32_t i = 0; i < nv; i++) order[i] = i;
    float *vbase = nv ? (float *)&p->verts[0].x : NULL; /* a scene of spheres and cones has no vertex array */
    qsort_r(order, nv, sizeof *order, vkey_cmp, vbase);
    for (uint32_t i = 0; i < nv; i++)
        canon[order[i]] = i && !vkey_cmp(&order[i], &order[i - 1], vbase) ? canon[order[i - 1]] : order[i];
    /* Directed edges; an undirected edge must be used exactly once each way. */
    uint32_t ne = 0;
    for (uint32_t t = 0; t < ntri; t++) {
        parent[t] = t;
        for (int e = 0; e < 3; e++) {
            uint32_t a = canon[tv[3 * t + e]], b = canon[tv[3 * t + (e + 1) % 3]];
            if (a != b) edges[ne++] = (solid_edge){a, b, t};
        }
    }
    qsort(edges, ne, sizeof *edges, edge_cmp);
    for (uint32_t i = 0; i < ne;) {
        /* One undirected edge's uses: sorted together by edge_cmp. */
        uint32_t j = i + 1;
        while (j < ne && (edges[j].a == edges[i].a || edges[j].a == edges[i].b) &&
               (edges[j].b == edges[i].a || edges[j].b == edges[i].b))
            j++;
        bool ok = j - i == 2 && edges[i].a == edges[i + 1].b && edges[i].b == edges[i + 1].a;
        for (uint32_t k = i; k < j; k++) {
            uint32_t x = uf_find(parent, edges[i].tri), y = uf_find(parent, edges[k].tri);
            if (x != y) parent[x] = y;
            if (!ok) bad[edges[k].tri] = 1;
        }
        i = j;
    }
    /* Components: bad if any triangle is, too large, or not convex. */
    uint32_t *cid = malloc(((size_t)ntri + 1) * sizeof *cid), *csize = calloc((size_t)ntri + 1, sizeof *csize);
    if (!cid || !csize) {
        free(cid), free(csize);
        goto out;
    }
    for (uint32_t t = 0; t < ntri; t++) {
        uint32_t r = uf_find(parent, t);
        csize[r]++;
        if (bad[t]) bad[r] = 1;
    }
    /* Number the qualifying roots; their triangles grouped. */
    uint32_t nc = 0;
    for (uint32_t t = 0; t < ntri; t++) cid[t] = SOLID_NONE;
    for (uint32_t t = 0; t < ntri; t++)
        if (parent[t] == t && !bad[t]) cid[t] = nc++;
    ci->cfirst = calloc((size_t)nc + 2, sizeof *ci->cfirst);
    uint32_t total = 0;
    for (uint32_t t = 0; t < ntri; t++) {
        uint32_t c = cid[uf_find(parent, t)];
        if (c != SOLID_NONE) ci->cfirst[c + 1]++, total++;
    }
    ci->ctris = malloc(((size_t)total + 1) * sizeof *ci->ctris);
    ci->ctv = malloc(((size_t)total + 1) * sizeof *ci->ctv);
    ci->ok = calloc((size_t)nc + 1, sizeof *ci->ok);
    if (!ci->cfirst || !ci->ctris || !ci->ctv || !ci->ok) {
        free(cid), free(csize);
        goto out;
    }
    for (uint32_t c = 0; c < nc; c++) ci->cfirst[c + 1] += ci->cfirst[c];
    memset(csize, 0, ((size_t)nc + 1) * sizeof *csize); /* fill cursors */
    for (uint32_t t = 0; t < ntri; t++) {
        uint32_t c = cid[uf_find(parent, t)];
        if (c == SOLID_NONE) continue;
        uint32_t slot = ci->cfirst[c] + csize[c]++;
        for (int v = 0; v < 3; v++) ci->ctris[slot][v] = dv3(p->verts[tv[3 * t + v]]), ci->ctv[slot][v] = canon[tv[3 * t + v]];
    }
    ci->ncomps = nc;
    /* Convex (small components: the check is quadratic), else embedded. */
    for (uint32_t c = 0; c < nc; c++) {
        uint32_t f = ci->cfirst[c], m = ci->cfirst[c + 1] - f;
        ci->ok[c] = (m <= SOLID_CONVEX_MAX_TRIS && tri_set_convex(&ci->ctris[f], m, SOLID_FLAT) && tri_set_volume_positive(&ci->ctris[f], m)) ||
                    comp_embedded(&ci->ctris[f], &ci->ctv[f], m);
    }
    /* A primitive qualifies when all its triangles are in one qualifying component. */
    for (uint32_t t = 0; t < ntri; t++) {
        uint32_t c = cid[uf_find(parent, t)], id = owner[t];
        uint32_t want = c != SOLID_NONE && ci->ok[c] ? c : SOLID_NONE;
        bool first = t == 0 || owner[t - 1] != id;
        if (first) ci->comp[id] = want;
        else if (ci->comp[id] != want) ci->comp[id] = SOLID_NONE;
    }
    free(cid);
    free(csize);
    rc = 0;
out:
    free(tv), free(owner), free(order), free(canon), free(edges), free(parent), free(bad);
    if (rc) closed_solids_free(ci);
    return rc;
}

uint64_t closed_solids_bytes(const prims_t *p)
{
    /* Per triangle its vertices, owner, three edges,
     * union-find, flags, component numbers and a copy in double; per
     * vertex its order and canonical id. */
    uint64_t ntri = (uint64_t)p->ntris + p->npoly_tris;
    uint64_t b = memcap_mul(ntri, 12 + 4 + 3 * sizeof(solid_edge) + 4 + 4 + 8 + 3 * sizeof(dvec3) + 12 + 1);
    /* The embedded test's BVH over the component's boxes (the largest
     * component is at most every triangle). */
    b = memcap_add(b, memcap_mul(ntri, sizeof(box3) + 2 * sizeof(bvh_node) + 4 + 8 + 2 * sizeof(vec3) + 12));
    return memcap_add(b, memcap_mul(p->nverts, 8));
}
