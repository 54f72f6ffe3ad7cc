/* polygon.c: the ray/polygon kernels (NFF "p": planar, simple, possibly
 * concave polygons such as the SPD gears' 144-gons; two-sided).
 *
 * Plane: Newell's method (M. E. Newell's, as described by Sutherland,
 * Sproull and Schumacker, "A Characterization of Ten Hidden-Surface
 * Algorithms", Computing Surveys 6(1), 1974, and by Tampieri, "Newell's
 * Method for Computing the Plane Equation of a Polygon", Graphics Gems III):
 * the normal is the sum over the edges of the cross products of
 * consecutive vertices, i.e. twice the vector area. Unlike the cross
 * product of the first two edges it uses every vertex, so it is right for
 * concave polygons, for collinear leading vertices and (as a best fit) for
 * slightly non-planar input such as NFF coordinates printed with %g. We
 * sum (v_i - v_0) x (v_{i+1} - v_0) in double (same sum, smaller terms).
 *
 * Inside test: the crossings (even-odd) test of Eric Haines, "Point in
 * Polygon Strategies", Graphics Gems IV (1994): cast a half-line from the
 * point and count the edges it crosses. Where the 2D frame comes from
 * matters for rounding:
 * - polygon_intersect (float, the one that traces) uses the ray-sheared
 *   frame of the watertight triangle test (shear.h; Woop, Benthin, Wald,
 *   JCGT 2013): the ray is the 2D origin and every vertex's sheared x, y
 *   depend only on the vertex and the ray. An edge p-q (with one endpoint
 *   at y > 0 and the other at y <= 0: half-open in y, so a vertex on the
 *   half-line counts once) is crossed by the half-line y = 0, x > 0 iff its
 *   x-intercept edge(p, q) / (q.y - p.y) is > 0 (strictly: half-open in x).
 *   edge(p, q) = -edge(q, p) bit for bit, with the exact double fallback
 *   when it is 0, so two polygons sharing the edge decide its crossing
 *   identically. Consequence: summing the even-odd answers of all polygons
 *   of a patch, each interior edge is counted twice and cancels, so a ray
 *   through the patch's interior (and not through its boundary) is inside
 *   an ODD number of its polygons, whatever the rounding: at least one hit,
 *   and for a patch that does not fold over itself as seen along the ray,
 *   exactly one. A ray exactly through a shared edge is counted for the
 *   polygon whose interior lies on the +x side of the edge in the sheared
 *   frame (a ray-dependent but consistent choice). The hit distance is then
 *   the ray/plane distance to the stored Newell plane.
 *   Why not the textbook projection that drops the normal's dominant axis
 *   (below)? It first computes the hit point from each polygon's own plane;
 *   two coplanar neighbours round their planes differently, so near their
 *   shared edge the two hit points differ by an ulp and a ray can fall
 *   between them (tests/test_prims_shapes.c measures this: about 1 ray in
 *   9 aimed at the shared edge of two tilted quads hits neither).
 * - polygon_intersect_double (the verification arbiter) is that textbook
 *   method, deliberately a different algorithm from the float one: ray/plane
 *   with a Newell plane computed in double, the hit point projected by
 *   dropping the dominant axis of the normal, crossings there with the same
 *   half-open rules.
 *
 * Triangulation: ear clipping. Meisters, "Polygons Have Ears", American
 * Mathematical Monthly 82(6), 1975, proved that every simple polygon with
 * more than 3 vertices has two non-overlapping ears (a vertex whose two
 * neighbours see each other through the interior), so clipping ears one at
 * a time always finishes with n - 2 triangles. The ear test follows
 * Eberly's description ("Triangulation by Ear Clipping", Geometric Tools,
 * 2002): a strictly convex vertex whose triangle contains no other
 * non-convex vertex (closed triangle, so a vertex on the new diagonal
 * blocks it). The box overlap of a polygon is the overlap of any of its
 * triangles, which is exact because the triangles tile the polygon. */
#include "prims_internal.h"
#include "checked_alloc.h"
#include "shear.h"

#include <float.h>
#include <stdio.h>
#include <stdlib.h>

/* ---------------------------------------------------------------------- */
/* plane                                                                   */

static dvec3 dvec(double x, double y, double z)
{
    dvec3 r = {x, y, z};
    return r;
}

static int dominant_axis_d(dvec3 n)
{
    double ax = fabs(n.x), ay = fabs(n.y), az = fabs(n.z);
    if (ax >= ay && ax >= az) return 0;
    return ay >= az ? 1 : 2;
}

static vec3 vertex_at(const vec3 *verts, const uint32_t *idx, uint32_t i)
{
    return verts[idx ? idx[i] : i];
}

/* Newell's sum in double; idx may be NULL (vertices are verts[0..n)).
 * Returns twice the vector area, and in *bound an upper bound of the
 * terms' magnitudes, for the zero test. Also the vertex centroid. */
static dvec3 newell(const vec3 *verts, const uint32_t *idx, uint32_t n, double *bound, dvec3 *centroid)
{
    dvec3 o = dv3(vertex_at(verts, idx, 0));
    dvec3 sum = {0, 0, 0}, csum = {0, 0, 0}, prev = {0, 0, 0};
    double b = 0.0;
    for (uint32_t i = 1; i < n; i++) {
        dvec3 cur = dv3_sub(dv3(vertex_at(verts, idx, i)), o);
        dvec3 c = dv3_cross(prev, cur);
        sum = dvec(sum.x + c.x, sum.y + c.y, sum.z + c.z);
        csum = dvec(csum.x + cur.x, csum.y + cur.y, csum.z + cur.z);
        b += sqrt(dv3_dot(prev, prev) * dv3_dot(cur, cur));
        prev = cur;
    }
    *bound = b;
    double inv = n ? 1.0 / n : 0.0;
    *centroid = dvec(o.x + csum.x * inv, o.y + csum.y * inv, o.z + csum.z * inv);
    return sum;
}

/* Zero area: the Newell sum is within its own rounding error of zero. Each
 * cross product is computed to a few DBL_EPSILON of |a||b| (the differences
 * from v_0 are exact for float input) and summing n terms adds at most n
 * more, so 4 (n + 4) DBL_EPSILON * bound is safely above the noise; a
 * polygon thinner than that, relative to its size, is degenerate. */
static bool newell_is_zero(dvec3 sum, double bound, uint32_t n)
{
    double len = sqrt(dv3_dot(sum, sum));
    return !(len > 4.0 * (n + 4.0) * DBL_EPSILON * bound);
}

bool polygon_plane(const vec3 *verts, const uint32_t *idx, uint32_t n, dvec3 *normal, double *offset, int *axis)
{
    double bound = 0.0;
    dvec3 cen, s = {0, 0, 0};
    if (n >= 3) s = newell(verts, idx, n, &bound, &cen);
    *axis = dominant_axis_d(s);
    if (n < 3 || newell_is_zero(s, bound, n)) {
        *normal = dvec(0, 0, 0);
        *offset = 0.0;
        return false;
    }
    double len = sqrt(dv3_dot(s, s));
    *normal = dvec(s.x / len, s.y / len, s.z / len);
    *offset = dv3_dot(*normal, cen);
    return true;
}

vec3 polygon_normal(const vec3 *pts, uint32_t n)
{
    dvec3 nd;
    double off;
    int axis;
    if (n < 3 || !polygon_plane(pts, NULL, n, &nd, &off, &axis)) return v3(0, 0, 0);
    return v3((float)nd.x, (float)nd.y, (float)nd.z);
}

/* ---------------------------------------------------------------------- */
/* intersection                                                            */

bool polygon_intersect(const vec3 *verts, const uint32_t *idx, uint32_t n, vec3 normal, float offset,
                       const ray_t *ray, float tmax, float *t)
{
    /* The plane distance first: it rejects most tests before the O(n) loop. */
    float dn = v3_dot(normal, ray->dir);
    if (!(dn != 0.0f)) return false; /* parallel to the plane (or NaN) */
    float tt = (offset - v3_dot(normal, ray->org)) / dn;
    if (!(tt >= ray->tnear && tt < tmax)) return false;

    shear_t s;
    if (!ray_shear(ray->dir, &s)) return false;
    sheared_t p = shear_vertex(&s, verts[idx[n - 1]], ray->org);
    bool inside = false;
    for (uint32_t i = 0; i < n; i++) {
        sheared_t q = shear_vertex(&s, verts[idx[i]], ray->org);
        bool pu = p.y > 0.0f, qu = q.y > 0.0f;
        if (pu != qu) {
            /* x-intercept = edge(p, q) / (q.y - p.y); q.y - p.y > 0 iff qu. */
            float e = edge_function(p, q);
            if (e == 0.0f) e = edge_function_double(p, q);
            if (e != 0.0f && (e > 0.0f) == qu) inside = !inside;
        }
        p = q;
    }
    if (!inside) return false;
    *t = tt;
    return true;
}

bool polygon_intersect_double(const vec3 *verts, const uint32_t *idx, uint32_t n, const ray_t *ray, double *t)
{
    dvec3 nrm;
    double off;
    int axis;
    if (!polygon_plane(verts, idx, n, &nrm, &off, &axis)) return false;
    dvec3 o = dv3(ray->org), d = dv3(ray->dir);
    double dn = dv3_dot(nrm, d);
    if (!(dn != 0.0)) return false;
    double tt = (off - dv3_dot(nrm, o)) / dn;
    if (!(tt >= (double)ray->tnear && tt < (double)ray->tfar)) return false;

    /* The hit point, and the 2D frame that drops the dominant axis. */
    double hp[3] = {o.x + d.x * tt, o.y + d.y * tt, o.z + d.z * tt};
    int ix = (axis + 1) % 3, iy = (axis + 2) % 3;
    bool inside = false;
    vec3 pv = verts[idx[n - 1]];
    double px = v3_get(pv, ix) - hp[ix], py = v3_get(pv, iy) - hp[iy];
    for (uint32_t i = 0; i < n; i++) {
        vec3 qv = verts[idx[i]];
        double qx = v3_get(qv, ix) - hp[ix], qy = v3_get(qv, iy) - hp[iy];
        bool pu = py > 0.0, qu = qy > 0.0;
        if (pu != qu) {
            double e = px * qy - py * qx;
            if (e != 0.0 && (e > 0.0) == qu) inside = !inside;
        }
        px = qx;
        py = qy;
    }
    if (!inside) return false;
    *t = tt;
    return true;
}

double polygon_boundary_distance(const vec3 *verts, const uint32_t *idx, uint32_t n, dvec3 p)
{
    double best = INFINITY;
    for (uint32_t i = 0, j = n - 1; i < n; j = i++)
        best = fmin(best, dv3_point_segment_distance(p, dv3(verts[idx[j]]), dv3(verts[idx[i]])));
    return best;
}

bool polygon_overlaps_box(const vec3 *verts, const tri_t *tris, uint32_t ntris, box3 box)
{
    for (uint32_t i = 0; i < ntris; i++) {
        const uint32_t *v = tris[i].v;
        if (triangle_overlaps_box(verts[v[0]], verts[v[1]], verts[v[2]], box)) return true;
    }
    return false;
}

/* ---------------------------------------------------------------------- */
/* ear clipping                                                            */

typedef struct {
    double *x, *y;       /* 2D coordinates, relative to pts[0] */
    uint32_t *prv, *nxt; /* the remaining polygon, a doubly linked ring */
    uint8_t *convex;     /* strictly convex (turns the polygon's way) */
    double sign;         /* +1 for a counter-clockwise 2D polygon, -1 for clockwise */
} ring_t;

/* Twice the signed area of (a, b, c), times the polygon's orientation:
 * > 0 when the corner at b turns the same way as the polygon. */
static double turn(const ring_t *r, uint32_t a, uint32_t b, uint32_t c)
{
    double o = (r->x[b] - r->x[a]) * (r->y[c] - r->y[a]) - (r->y[b] - r->y[a]) * (r->x[c] - r->x[a]);
    return r->sign * o;
}

static bool same_point(const ring_t *r, uint32_t a, uint32_t b) { return r->x[a] == r->x[b] && r->y[a] == r->y[b]; }

static void update_convex(ring_t *r, uint32_t i) { r->convex[i] = turn(r, r->prv[i], i, r->nxt[i]) > 0.0; }

/* Is i an ear: strictly convex, and no other remaining vertex inside or on
 * its triangle (a, i, c)? Only non-convex vertices can be inside (if a
 * vertex is inside, a reflex one is), so convex ones are skipped. Vertices
 * at the same position as a corner are skipped too: they are where the
 * polygon touches itself (or a duplicate), not an obstruction. */
static bool is_ear(const ring_t *r, uint32_t i)
{
    if (!r->convex[i]) return false;
    uint32_t a = r->prv[i], c = r->nxt[i];
    for (uint32_t j = r->nxt[c]; j != a; j = r->nxt[j]) {
        if (r->convex[j]) continue;
        if (same_point(r, j, a) || same_point(r, j, i) || same_point(r, j, c)) continue;
        if (turn(r, a, i, j) >= 0.0 && turn(r, i, c, j) >= 0.0 && turn(r, c, a, j) >= 0.0) return false;
    }
    return true;
}

static void clip(ring_t *r, uint32_t i, uint32_t (*tris)[3], uint32_t *nt)
{
    uint32_t a = r->prv[i], c = r->nxt[i];
    tris[*nt][0] = a;
    tris[*nt][1] = i;
    tris[*nt][2] = c;
    (*nt)++;
    r->nxt[a] = c;
    r->prv[c] = a;
    update_convex(r, a);
    update_convex(r, c);
}

uint32_t polygon_triangulate(const vec3 *pts, uint32_t n, vec3 normal, uint32_t (*tris)[3])
{
    if (n < 3) return 0;
    if (n == 3) {
        tris[0][0] = 0;
        tris[0][1] = 1;
        tris[0][2] = 2;
        return 1;
    }
    if (!v3_finite(normal) || (normal.x == 0.0f && normal.y == 0.0f && normal.z == 0.0f))
        normal = polygon_normal(pts, n);
    int axis = dominant_axis_d(dv3(normal));
    int ix = (axis + 1) % 3, iy = (axis + 2) % 3;

    ring_t r;
    size_t bytes = (size_t)n * (2 * sizeof(double) + 2 * sizeof(uint32_t) + 1);
    char *mem = checked_malloc(bytes, "a polygon's ear-clipping ring");
    r.x = (double *)mem;
    r.y = r.x + n;
    r.prv = (uint32_t *)(r.y + n);
    r.nxt = r.prv + n;
    r.convex = (uint8_t *)(r.nxt + n);

    /* Project by dropping the dominant axis; the winding in 2D, from the
     * shoelace area, decides what "convex" means, so the normal's sign and
     * the input winding do not matter. */
    double area2 = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        r.x[i] = (double)v3_get(pts[i], ix) - (double)v3_get(pts[0], ix);
        r.y[i] = (double)v3_get(pts[i], iy) - (double)v3_get(pts[0], iy);
        r.prv[i] = i ? i - 1 : n - 1;
        r.nxt[i] = i + 1 < n ? i + 1 : 0;
    }
    for (uint32_t i = 0; i < n; i++) area2 += r.x[i] * r.y[r.nxt[i]] - r.y[i] * r.x[r.nxt[i]];
    r.sign = area2 < 0.0 ? -1.0 : 1.0;
    for (uint32_t i = 0; i < n; i++) update_convex(&r, i);

    uint32_t nt = 0, m = n, i = 0, tries = 0;
    while (m > 3) {
        if (is_ear(&r, i)) {
            uint32_t a = r.prv[i];
            clip(&r, i, tris, &nt);
            m--;
            i = a; /* the neighbours changed: look there first */
            tries = 0;
            continue;
        }
        i = r.nxt[i];
        if (++tries < m) continue;

        /* A full turn without an ear. In a simple polygon that only happens
         * when the remaining ears are flat: collinear vertices (or
         * repeated ones). Clipping a flat vertex costs a zero-area triangle
         * and leaves the shape unchanged. */
        uint32_t j = i;
        bool flat = false;
        do {
            if (turn(&r, r.prv[j], j, r.nxt[j]) == 0.0) {
                flat = true;
                break;
            }
            j = r.nxt[j];
        } while (j != i);
        if (flat) {
            uint32_t a = r.prv[j];
            clip(&r, j, tris, &nt);
            m--;
            i = a;
            tries = 0;
            continue;
        }
        /* Not simple (self-intersecting): fan the rest from i. */
        for (uint32_t k = r.nxt[i]; r.nxt[k] != i; k = r.nxt[k]) {
            tris[nt][0] = i;
            tris[nt][1] = k;
            tris[nt][2] = r.nxt[k];
            nt++;
        }
        free(mem);
        return nt;
    }
    tris[nt][0] = r.prv[i];
    tris[nt][1] = i;
    tris[nt][2] = r.nxt[i];
    nt++;
    free(mem);
    return nt;
}
