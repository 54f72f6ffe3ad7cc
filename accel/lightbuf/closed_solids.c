/* closed_solids.c: the mesh analysis of closed_solids.h. */
#include "closed_solids.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "../bvh/bvh.h"
#include "../common/memcap.h"

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

/* Whether every vertex of the triangles tr[0..n) lies behind or on every
 * one of their planes, up to SOLID_FLAT times the diagonal of their box:
 * float vertices of coplanar faces (a rotated box's split quads) are never
 * exactly coplanar. Triangles of (nearly) zero area have no plane to
 * check. */
static bool comp_volume_positive(dvec3 (*tr)[3], uint32_t n)
{
    double vol = 0;
    for (uint32_t j = 0; j < n; j++) vol += dv3_dot(tr[j][0], dv3_cross(tr[j][1], tr[j][2]));
    return vol > 0;
}

static bool comp_convex(dvec3 (*tr)[3], uint32_t n)
{
    dvec3 lo = tr[0][0], hi = tr[0][0];
    for (uint32_t j = 0; j < n; j++)
        for (int v = 0; v < 3; v++)
            lo = dv3_min(lo, tr[j][v]), hi = dv3_max(hi, tr[j][v]);
    double diag = dv3_len(dv3_sub(hi, lo)), tol = SOLID_FLAT * diag;
    for (uint32_t i = 0; i < n; i++) {
        dvec3 nrm = dv3_cross(dv3_sub(tr[i][1], tr[i][0]), dv3_sub(tr[i][2], tr[i][0]));
        double ln = dv3_len(nrm);
        if (!(ln > 1e-12 * diag * diag)) continue;
        for (uint32_t j = 0; j < n; j++)
            for (int v = 0; v < 3; v++)
                if (dv3_dot(nrm, dv3_sub(tr[j][v], tr[i][0])) > tol * ln) return false;
    }
    return true;
}

/* --- embedded components: no two triangles meet but where the mesh joins them --- */

/* Whether triangles a and b (no shared vertex) are separated along one of
 * the axes of the separating axis test (their normals, the cross products
 * of their edges, and the in-plane normals of every edge, for coplanar
 * ones) by a gap of more than tol. */
static bool tris_apart(const dvec3 a[3], const dvec3 b[3], double tol)
{
    dvec3 ea[3], eb[3], ax[23];
    for (int k = 0; k < 3; k++) ea[k] = dv3_sub(a[(k + 1) % 3], a[k]), eb[k] = dv3_sub(b[(k + 1) % 3], b[k]);
    dvec3 na = dv3_cross(ea[0], ea[1]), nb = dv3_cross(eb[0], eb[1]);
    int n = 0;
    ax[n++] = na, ax[n++] = nb;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) ax[n++] = dv3_cross(ea[i], eb[j]);
    for (int k = 0; k < 3; k++) ax[n++] = dv3_cross(na, ea[k]), ax[n++] = dv3_cross(na, eb[k]);
    for (int k = 0; k < n; k++) {
        double l = dv3_len(ax[k]);
        if (!(l > 0)) continue;
        double alo = INFINITY, ahi = -INFINITY, blo = INFINITY, bhi = -INFINITY;
        for (int v = 0; v < 3; v++) {
            double x = dv3_dot(ax[k], a[v]) / l, y = dv3_dot(ax[k], b[v]) / l;
            alo = fmin(alo, x), ahi = fmax(ahi, x), blo = fmin(blo, y), bhi = fmax(bhi, y);
        }
        if (ahi + tol < blo || bhi + tol < alo) return true;
    }
    return false;
}

/* Whether triangles a and b, sharing exactly vertex a[ia] = b[ib], meet
 * only there: a plane through it has a's other vertices on one side and
 * b's strictly on the other (by an angle of 1e-7), the candidates being
 * the separating axis test's (two wedges meeting only at their apex are
 * separated by such a plane). On the near side a vertex may lie in the
 * plane (coplanar fans: the separating line runs along an edge). */
static bool tris_touch_at_vertex(const dvec3 a[3], int ia, const dvec3 b[3], int ib)
{
    dvec3 v = a[ia], ra[2], rb[2];
    for (int k = 0, m = 0; k < 3; k++)
        if (k != ia) ra[m++] = dv3_sub(a[k], v);
    for (int k = 0, m = 0; k < 3; k++)
        if (k != ib) rb[m++] = dv3_sub(b[k], v);
    dvec3 ea[3] = {ra[0], ra[1], dv3_sub(ra[1], ra[0])}, eb[3] = {rb[0], rb[1], dv3_sub(rb[1], rb[0])};
    dvec3 na = dv3_cross(ra[0], ra[1]), nb = dv3_cross(rb[0], rb[1]), ax[2 + 9 + 12];
    int n = 0;
    ax[n++] = na, ax[n++] = nb;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) ax[n++] = dv3_cross(ea[i], eb[j]);
    for (int k = 0; k < 3; k++)
        ax[n++] = dv3_cross(na, ea[k]), ax[n++] = dv3_cross(na, eb[k]), ax[n++] = dv3_cross(nb, ea[k]),
        ax[n++] = dv3_cross(nb, eb[k]);
    for (int k = 0; k < n; k++) {
        double l = dv3_len(ax[k]);
        if (!(l > 0)) continue;
        double amax = -INFINITY, amin = INFINITY, bmax = -INFINITY, bmin = INFINITY;
        for (int m = 0; m < 2; m++) {
            double x = dv3_dot(ax[k], ra[m]) / (l * dv3_len(ra[m])), y = dv3_dot(ax[k], rb[m]) / (l * dv3_len(rb[m]));
            amax = fmax(amax, x), amin = fmin(amin, x), bmax = fmax(bmax, y), bmin = fmin(bmin, y);
        }
        /* a below (touching allowed) and b strictly above, or the mirror. */
        if ((amax <= 1e-12 && bmin > 1e-7) || (bmax <= 1e-12 && amin > 1e-7) || (amin >= -1e-12 && bmax < -1e-7) ||
            (bmin >= -1e-12 && amax < -1e-7))
            return true;
    }
    return false;
}

/* Whether triangles a and b, sharing the edge from a[i] to a[(i+1)%3]
 * (b's vertex off it is b[jb]), meet only along it: their third vertices,
 * seen across the edge, are not folded onto one another (more than about
 * 1e-6 radians apart). */
static bool tris_touch_at_edge(const dvec3 a[3], int i, const dvec3 b[3], int jb)
{
    dvec3 p = a[i], e = dv3_sub(a[(i + 1) % 3], p);
    double ee = dv3_dot(e, e);
    if (!(ee > 0)) return false;
    dvec3 wa = dv3_sub(a[(i + 2) % 3], p), wb = dv3_sub(b[jb], p);
    dvec3 pa = dv3_madd(wa, e, -dv3_dot(wa, e) / ee), pb = dv3_madd(wb, e, -dv3_dot(wb, e) / ee);
    double la = dv3_len(pa), lb = dv3_len(pb);
    if (!(la > 0 && lb > 0)) return false;
    return dv3_dot(pa, pb) / (la * lb) < 1.0 - 1e-12;
}

/* How many of b's vertices (canonical ids) are among a's; *ia, *ib: the
 * last such pair's indices, *off: the last vertex of b that is not. */
static int shared_vertices(const uint32_t a[3], const uint32_t b[3], int *ia, int *ib, int *off)
{
    int n = 0;
    for (int j = 0; j < 3; j++) {
        bool in = false;
        for (int i = 0; i < 3; i++)
            if (a[i] == b[j]) in = true, *ia = i, *ib = j;
        n += in;
        if (!in) *off = j;
    }
    return n;
}

/* The pair i, j of a component passes when it meets only where the mesh
 * joins it (see the three tests above). A triangle with a repeated vertex
 * fails against its neighbours (not culling is safe). */
static bool pair_ok(dvec3 (*tr)[3], uint32_t (*tv)[3], uint32_t i, uint32_t j, double tol)
{
    int ia = 0, ib = 0, off = 0;
    int shared = shared_vertices(tv[i], tv[j], &ia, &ib, &off);
    if (shared == 0) return tris_apart(tr[i], tr[j], tol);
    if (shared == 1) return tris_touch_at_vertex(tr[i], ia, tr[j], ib);
    if (shared != 2) return false;
    /* The edge of a whose two ends are both b's. */
    for (int k = 0; k < 3; k++) {
        uint32_t x = tv[i][k], y = tv[i][(k + 1) % 3];
        bool xin = x == tv[j][0] || x == tv[j][1] || x == tv[j][2], yin = y == tv[j][0] || y == tv[j][1] || y == tv[j][2];
        if (xin && yin && x != y) return tris_touch_at_edge(tr[i], k, tr[j], off);
    }
    return false;
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
                if (j > i && box_overlap(boxes[i], boxes[j]) && !pair_ok(tr, tv, i, j, tol)) goto out;
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
        ci->ok[c] = (m <= SOLID_CONVEX_MAX_TRIS && comp_convex(&ci->ctris[f], m) && comp_volume_positive(&ci->ctris[f], m)) ||
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
