/* tri_set.c: the geometry of tri_set.h, in double. */
#include "tri_set.h"

#include <math.h>

bool tri_set_volume_positive(dvec3 (*tr)[3], uint32_t n)
{
    double vol = 0;
    for (uint32_t j = 0; j < n; j++) vol += dv3_dot(tr[j][0], dv3_cross(tr[j][1], tr[j][2]));
    return vol > 0;
}

bool tri_set_convex(dvec3 (*tr)[3], uint32_t n, double flat)
{
    dvec3 lo = tr[0][0], hi = tr[0][0];
    for (uint32_t j = 0; j < n; j++)
        for (int v = 0; v < 3; v++)
            lo = dv3_min(lo, tr[j][v]), hi = dv3_max(hi, tr[j][v]);
    double diag = dv3_len(dv3_sub(hi, lo)), tol = flat * diag;
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

bool tri_pair_joined_only(dvec3 (*tr)[3], uint32_t (*tv)[3], uint32_t i, uint32_t j, double tol)
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
