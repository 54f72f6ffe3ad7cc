/* test_prim_extent: prim_extent (prims/extent.c), a primitive's extent
 * along a direction. For random triangles, polygons, spheres and cones
 * and random unit and non-unit directions (some with zero components):
 * every sampled surface point (vertices, points inside triangles and
 * polygons, points on spheres, on cone rims and generators) projects
 * inside [lo, hi], and [lo, hi] is tight (within a few float ulps of the
 * extreme sample, the exact extreme for vertices and spheres). Along the
 * coordinate axes the extent of a triangle or polygon is exactly its
 * bounds, of a sphere c -+ r rounded outward. Bad input is refused. */
#include <float.h>
#include "check.h"
#define PRIMS_TEST_SEED 0xe7e47
#include "prims_testlib.h"

static double ddot3(double x, double y, double z, vec3 d) { return x * d.x + y * d.y + z * d.z; }

/* Tolerances: a sample's own double rounding, and how far above the
 * largest sample hi may be (rounding outward, sampling gaps). */
static int outside, loose, tested;

static void expect(const prims_t *p, uint32_t id, vec3 d, double smin, double smax, double gap)
{
    float lo, hi;
    CHECK(prim_extent(p, id, d, &lo, &hi));
    double scale = fmax(fabs(smin), fabs(smax)) + 1e-30, eps = 1e-12 * scale;
    tested++;
    if (smin < (double)lo - eps || smax > (double)hi + eps) {
        if (outside++ < 5) fprintf(stderr, "prim %u kind %d dir %a %a %a: samples [%.17g, %.17g] outside [%.9g, %.9g]\n", id, p->kind[id], d.x, d.y, d.z, smin, smax, lo, hi);
    }
    double ulps = 4.0 * (double)FLT_EPSILON * scale;
    if ((double)hi - smax > ulps + gap || smin - (double)lo > ulps + gap) {
        if (loose++ < 5) fprintf(stderr, "prim %u: [%.9g, %.9g] loose around samples [%.17g, %.17g]\n", id, lo, hi, smin, smax);
    }
}

static vec3 rnd_dir(void)
{
    vec3 d = rnd_v3(-1.0f, 1.0f);
    uint64_t k = rng_next() % 6;
    if (k == 0) d.x = 0.0f;
    if (k == 1) d.y = -0.0f, d.z = 0.0f;
    if (k == 2) d = v3_norm(d);
    if (k == 3) d = v3_scale(d, 1000.0f);
    if (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f) d.z = 1.0f;
    return d;
}

int main(void)
{
    prims_t p;
    prims_init(&p);
    /* Random primitives, at scales and offsets from 1e-3 to 1e4. */
    for (int i = 0; i < 300; i++) {
        float scale = i % 3 == 0 ? 1e-3f : i % 3 == 1 ? 1.0f : 1e4f;
        vec3 c = v3_scale(rnd_v3(-10.0f, 10.0f), scale);
        uint32_t v[6];
        for (int k = 0; k < 6; k++) v[k] = prims_add_vertex(&p, v3_add(c, v3_scale(rnd_v3(-1.0f, 1.0f), scale)));
        prims_add_triangle(&p, v[0], v[1], v[2]);
        prims_add_sphere(&p, c, rnd(0.1f, 2.0f) * scale);
        prims_add_cone(&p, c, rnd(0.0f, 1.0f) * scale, v3_add(c, v3_scale(rnd_v3(-3.0f, 3.0f), scale)),
                       rnd(0.1f, 1.0f) * scale);
        /* A planar pentagon: a regular one in a random plane. */
        vec3 u = v3_norm(rnd_v3(-1.0f, 1.0f)), w = v3_norm(v3_cross(u, rnd_v3(-1.0f, 1.0f)));
        uint32_t pv[5];
        for (int k = 0; k < 5; k++) {
            float a = 6.2831853f * (float)k / 5.0f;
            pv[k] = prims_add_vertex(&p, v3_add(c, v3_scale(v3_add(v3_scale(u, cosf(a)), v3_scale(w, sinf(a))), scale)));
        }
        prims_add_polygon(&p, pv, 5);
    }
    char err[256];
    CHECK_MSG(prims_finish(&p, err, sizeof err) == 0, "%s", err);

    for (uint32_t id = 0; id < p.count; id++)
        for (int rep = 0; rep < 20; rep++) {
            vec3 d = rnd_dir();
            uint32_t k = p.index[id];
            double smin = INFINITY, smax = -INFINITY, gap = 0.0;
            switch ((prim_kind)p.kind[id]) {
            case PRIM_TRIANGLE: {
                vec3 a = p.verts[p.tris[k].v[0]], b = p.verts[p.tris[k].v[1]], c = p.verts[p.tris[k].v[2]];
                for (int s = 0; s < 200; s++) {
                    double x = rndd(0, 1), y = rndd(0, 1);
                    if (x + y > 1) x = 1 - x, y = 1 - y;
                    if (s < 3) x = s == 1, y = s == 2; /* the vertices themselves */
                    double q = ddot3(a.x + x * ((double)b.x - a.x) + y * ((double)c.x - a.x),
                                     a.y + x * ((double)b.y - a.y) + y * ((double)c.y - a.y),
                                     a.z + x * ((double)b.z - a.z) + y * ((double)c.z - a.z), d);
                    smin = fmin(smin, q), smax = fmax(smax, q);
                }
                break;
            }
            case PRIM_POLYGON: {
                const polygon_t *g = &p.polygons[k];
                for (uint32_t j = 0; j < g->count; j++) {
                    vec3 x = p.verts[p.poly_verts[g->first + j]];
                    double q = ddot3(x.x, x.y, x.z, d);
                    smin = fmin(smin, q), smax = fmax(smax, q);
                }
                break;
            }
            case PRIM_SPHERE: {
                sphere_t s = p.spheres[k];
                double len = sqrt((double)d.x * d.x + (double)d.y * d.y + (double)d.z * d.z);
                double cd = ddot3(s.center.x, s.center.y, s.center.z, d);
                smin = cd - s.radius * len, smax = cd + s.radius * len; /* the extreme points themselves */
                break;
            }
            case PRIM_CONE: {
                cone_t c = p.cones[k];
                dvec3 ax = dv3_sub(dv3(c.apex), dv3(c.base));
                double len = sqrt(dv3_dot(ax, ax));
                dvec3 w = {ax.x / len, ax.y / len, ax.z / len};
                dvec3 e1 = dv3_cross(w, fabs(w.x) < 0.5 ? (dvec3){1, 0, 0} : (dvec3){0, 1, 0});
                double l1 = sqrt(dv3_dot(e1, e1));
                e1 = (dvec3){e1.x / l1, e1.y / l1, e1.z / l1};
                dvec3 e2 = dv3_cross(w, e1);
                const int M = 720;
                for (int s = 0; s < M; s++) {
                    double a = 6.283185307179586 * s / M, h = rndd(0, 1);
                    for (int end = 0; end < 3; end++) {
                        double f = end == 2 ? h : end; /* the two rims and a random height */
                        double r = c.base_radius + f * ((double)c.apex_radius - c.base_radius);
                        double x = c.base.x + f * ax.x + r * (cos(a) * e1.x + sin(a) * e2.x);
                        double y = c.base.y + f * ax.y + r * (cos(a) * e1.y + sin(a) * e2.y);
                        double z = c.base.z + f * ax.z + r * (cos(a) * e1.z + sin(a) * e2.z);
                        double q = ddot3(x, y, z, d);
                        smin = fmin(smin, q), smax = fmax(smax, q);
                    }
                }
                /* The rim between samples bulges by at most r (1 - cos(pi / M)) |d|. */
                double rmax = fmax(c.base_radius, c.apex_radius);
                gap = rmax * (1.0 - cos(3.141592653589793 / M)) * v3_len(d) * 1.01;
                break;
            }
            default:
                break;
            }
            expect(&p, id, d, smin, smax, gap);
        }
    printf("%d extents: %d with a sample outside, %d loose\n", tested, outside, loose);
    CHECK(outside == 0);
    CHECK(loose == 0);

    /* Along the axes: exactly the bounds (every step exact). For spheres
     * that is c -+ r rounded outward, which prims_finish's bounds (rounded
     * to nearest) need not be. */
    int axis_bad = 0;
    for (uint32_t id = 0; id < p.count; id++) {
        if (p.kind[id] == PRIM_CONE) continue;
        box3 b = prim_bounds(&p, id);
        if (p.kind[id] == PRIM_SPHERE) {
            sphere_t sp = p.spheres[p.index[id]];
            float lo3[3], hi3[3];
            for (int a = 0; a < 3; a++) {
                double c = v3_get(sp.center, a), lo = c - sp.radius, hi = c + sp.radius;
                lo3[a] = (float)lo, hi3[a] = (float)hi;
                if ((double)lo3[a] > lo) lo3[a] = nextafterf(lo3[a], -INFINITY);
                if ((double)hi3[a] < hi) hi3[a] = nextafterf(hi3[a], INFINITY);
            }
            b = (box3){{lo3[0], lo3[1], lo3[2]}, {hi3[0], hi3[1], hi3[2]}};
        }
        for (int a = 0; a < 3; a++) {
            vec3 d = v3(a == 0, a == 1, a == 2), nd = v3_scale(d, -1.0f);
            float lo, hi, nlo, nhi;
            CHECK(prim_extent(&p, id, d, &lo, &hi) && prim_extent(&p, id, nd, &nlo, &nhi));
            axis_bad += lo != v3_get(b.lo, a) || hi != v3_get(b.hi, a) || nlo != -hi || nhi != -lo;
        }
    }
    CHECK_MSG(axis_bad == 0, "%d axis extents differ from the bounds", axis_bad);
    /* A zero direction gives [0, 0]; bad input is refused and writes nothing. */
    float lo = 7.0f, hi = 7.0f;
    for (uint32_t id = 0; id < 4; id++) CHECK(prim_extent(&p, id, v3(0, 0, 0), &lo, &hi) && lo == 0.0f && hi == 0.0f);
    lo = hi = 7.0f;
    CHECK(!prim_extent(&p, 0, v3(NAN, 0, 0), &lo, &hi) && lo == 7.0f);
    CHECK(!prim_extent(&p, 0, v3(0, INFINITY, 0), &lo, &hi) && lo == 7.0f);
    CHECK(!prim_extent(&p, p.count, v3(1, 0, 0), &lo, &hi) && lo == 7.0f);
    prims_free(&p);
    return check_report();
}
