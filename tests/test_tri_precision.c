/* test_tri_precision.c: the triangle test's hit distance is accurate at the
 * hit's own scale, and the same bit for bit on every triangle path.
 *
 *   accuracy    random triangles spanning 1 to 1e4 units with coordinates
 *               up to 1e4, each hit by a ray at t in [1e-3, 10] through a
 *               random interior point: |t - t_exact| (t_exact: the ray's
 *               crossing with the plane, in long double) within verify.h's
 *               tol bound, TOL_ULPS u (|o| + t |d|) / (|d| max(|cos|,
 *               GRAZE_COS)) (the sheared test's own float t was off by up to
 *               thousands of times it: the terms it sums are the size of the
 *               triangle, not of t);
 *   polygons    the same for quads through polygon_intersect (its
 *               float plane is accurate at the hit's scale already),
 *               against the double Newell plane of
 *               polygon_intersect_double;
 *   paths       a scene of such triangles and rays aimed at them: the
 *               one-triangle test over every triangle (the closest hit),
 *               the SSE2 packet test over all of them, exhaustive, and the
 *               wide BVH at every width, ISA this CPU has and fma setting,
 *               closest and any hit: the same prim and t, bit for bit;
 *   thin wall   the ray that starts 1.2e-4 from a thin wall seen edge-on
 *               (test_verify.c's origin case): the plane lies behind the
 *               origin, so no hit; with tnear below it, t is the plane's. */
#include <math.h>
#include <string.h>
#include "accel/bvh_wide/bvh_wide.h"
#include "../prims/prims_internal.h"
#include "testlib.h"

#define FLOAT_U 0x1p-24

static double urand(uint32_t *st) { return (double)test_urand(st); }

/* Log-uniform in [lo, hi]. */
static double log_uniform(uint32_t *st, double lo, double hi) { return lo * pow(hi / lo, urand(st)); }

static vec3 random_unit(uint32_t *st)
{
    for (;;) {
        double x = 2 * urand(st) - 1, y = 2 * urand(st) - 1, z = 2 * urand(st) - 1, l = sqrt(x * x + y * y + z * z);
        if (l > 0.1 && l <= 1.0) return v3((float)(x / l), (float)(y / l), (float)(z / l));
    }
}

typedef struct {
    vec3 a, b, c;
    ray_t r;
} tri_case;

/* A triangle of size in [1, 1e4] whose corners have coordinates up to
 * about 1e4, and a ray that reaches an interior point of it (barycentrics
 * >= 0.05) at t in [1e-3, 10], not grazing (|cos| >= 0.05: the graze has
 * its own class). The hit point's coordinates are log-uniform in magnitude
 * from 1e-2 to 1e4, so the ray's origin is often much nearer the
 * coordinate origin than the triangle is large: a room's floor seen from
 * its furniture, where the tol bound, which scales with |o| + t |d|, is
 * tight. */
static tri_case random_case(uint32_t *st)
{
    for (;;) {
        tri_case k;
        double size = log_uniform(st, 1.0, 1e4), h[3];
        for (int i = 0; i < 3; i++) h[i] = (urand(st) < 0.5 ? -1 : 1) * log_uniform(st, 1e-2, 1e4);
        /* Barycentrics of the hit point, each at least 0.05. */
        double l0 = 0.05 + 0.9 * urand(st), l1 = 0.05 + 0.9 * urand(st), l2 = 0.05 + 0.9 * urand(st),
               sum = l0 + l1 + l2;
        l0 /= sum, l1 /= sum, l2 /= sum;
        if (l0 < 0.05 || l1 < 0.05 || l2 < 0.05) continue;
        /* Edges b - a and c - a, then a from h = a + l1 (b - a) + l2 (c - a). */
        vec3 e1 = v3_scale(random_unit(st), (float)size), e2 = v3_scale(random_unit(st), (float)size);
        vec3 hp = v3((float)h[0], (float)h[1], (float)h[2]);
        k.a = v3_sub(hp, v3_add(v3_scale(e1, (float)l1), v3_scale(e2, (float)l2)));
        k.b = v3_add(k.a, e1), k.c = v3_add(k.a, e2);
        vec3 d = random_unit(st);
        vec3 n = v3_cross(v3_sub(k.b, k.a), v3_sub(k.c, k.a));
        double nl = v3_len(n);
        if (!(nl > 0) || fabs(v3_dot(n, d)) / nl < 0.05) continue;
        /* Sliver triangles (an angle under ~1e-3) are the edge class's; keep
         * the triangle well shaped: its area at least 1e-3 of size^2. */
        if (nl < 1e-3 * size * size) continue;
        /* The hit point from the float corners, in double. */
        double hx = l0 * k.a.x + l1 * k.b.x + l2 * k.c.x, hy = l0 * k.a.y + l1 * k.b.y + l2 * k.c.y,
               hz = l0 * k.a.z + l1 * k.b.z + l2 * k.c.z;
        double t = log_uniform(st, 1e-3, 10.0);
        ray_t r = {v3((float)(hx - t * d.x), (float)(hy - t * d.y), (float)(hz - t * d.z)), 0.0f, d, INFINITY,
                   RAY_NO_LIGHT, RAY_NO_ORIGIN};
        k.r = r;
        return k;
    }
}

/* The ray's crossing with the plane of a, b, c, in long double (64-bit
 * significand): the float inputs' differences are exact there, and the
 * rest rounds at 2^-64 of the triangle's size. */
static long double exact_t(vec3 a, vec3 b, vec3 c, const ray_t *r)
{
    long double e1[3] = {(long double)b.x - a.x, (long double)b.y - a.y, (long double)b.z - a.z};
    long double e2[3] = {(long double)c.x - a.x, (long double)c.y - a.y, (long double)c.z - a.z};
    long double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    long double ao[3] = {(long double)a.x - r->org.x, (long double)a.y - r->org.y, (long double)a.z - r->org.z};
    long double num = n[0] * ao[0] + n[1] * ao[1] + n[2] * ao[2];
    long double den = n[0] * r->dir.x + n[1] * r->dir.y + n[2] * r->dir.z;
    return num / den;
}

static double maxabs3(vec3 v) { return fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z))); }

/* verify.h's tol bound for a hit at t on a triangle of normal n. */
static double tol_bound(vec3 a, vec3 b, vec3 c, const ray_t *r, double t)
{
    vec3 n = v3_cross(v3_sub(b, a), v3_sub(c, a));
    double dlen = v3_len(r->dir), cosv = fabs(v3_dot(n, r->dir)) / (v3_len(n) * dlen);
    return TOL_ULPS * FLOAT_U * (maxabs3(r->org) + fabs(t) * maxabs3(r->dir)) / (dlen * fmax(cosv, GRAZE_COS));
}

static void test_accuracy(void)
{
    uint32_t st = 12345;
    const int n = 200000;
    int misses = 0, over = 0;
    double worst = 0.0; /* the largest |t - t_exact| / bound */
    for (int i = 0; i < n; i++) {
        tri_case k = random_case(&st);
        float t, u, v;
        long double te = exact_t(k.a, k.b, k.c, &k.r);
        if (!triangle_intersect(k.a, k.b, k.c, &k.r, k.r.tfar, &t, &u, &v)) {
            if (te >= 0 && misses++ < 5) fprintf(stderr, "a miss where the plane lies at t = %.9Lg\n", te);
            continue;
        }
        double bound = tol_bound(k.a, k.b, k.c, &k.r, (double)te), err = fabsl((long double)t - te);
        if (err / bound > worst) worst = err / bound;
        if (err > bound && over++ < 5)
            fprintf(stderr, "t %.9g, exact %.9Lg: off by %.3g, %.1f times the bound\n", t, te, err, err / bound);
    }
    printf("accuracy: %d rays, %d missed, %d off by more than the tol bound; worst %.3g of it\n", n, misses, over,
           worst);
    CHECK_MSG(misses == 0, "%d rays through interior points missed", misses);
    CHECK_MSG(over == 0, "%d of %d hits off by more than verify.h's tol bound", over, n);
    /* A few float steps, not 64: the distance is rounded once from double. */
    CHECK_MSG(worst < 4.0 / TOL_ULPS, "the worst error is %.3g of the bound (%.3g float steps)", worst,
              worst * TOL_ULPS);
}

/* The same for polygons (the SPD's NFF "p"): a quad, the random case's
 * triangle completed to a parallelogram (a, b, b + c - a, c), its float
 * plane as the scene stores it (prims.c), against the verification
 * arbiter polygon_intersect_double (the Newell plane in double). The
 * float plane n . x = offset is accurate at the hit's scale: on the plane,
 * offset = n . x is no larger than the hit's coordinates, and the
 * normal's rounding moves n . x by u |x|, so t is within a few float
 * steps of |o| + t |d| whatever the polygon's size; this guards it. */
static void test_polygon_accuracy(void)
{
    uint32_t st = 4242;
    const int n = 20000;
    int misses = 0, over = 0;
    double worst = 0.0;
    for (int i = 0; i < n; i++) {
        tri_case k = random_case(&st);
        vec3 q[4] = {k.a, k.b, v3_sub(v3_add(k.b, k.c), k.a), k.c};
        uint32_t idx[4] = {0, 1, 2, 3};
        dvec3 nd;
        double off;
        int axis;
        if (!polygon_plane(q, idx, 4, &nd, &off, &axis)) continue;
        double te;
        if (!polygon_intersect_double(q, idx, 4, &k.r, &te)) continue; /* behind the origin by rounding */
        /* Ill-posed (verify.h's origin class): the crossing within float
         * noise of the origin, where the float plane may put it behind. */
        vec3 nf = v3((float)nd.x, (float)nd.y, (float)nd.z);
        double m = maxabs3(k.r.org);
        for (int c = 0; c < 4; c++) m = fmax(m, maxabs3(q[c]));
        if (te * fabs(v3_dot(nf, k.r.dir)) <= ORIGIN_ULPS * FLOAT_U * (maxabs3(k.r.org) + m)) continue;
        float t;
        if (!polygon_intersect(q, idx, 4, nf, (float)off, &k.r, k.r.tfar, &t)) {
            if (misses++ < 3) fprintf(stderr, "polygon: a miss where the plane lies at t = %.9g\n", te);
            continue;
        }
        double bound = tol_bound(k.a, k.b, k.c, &k.r, te), err = fabs((double)t - te);
        if (err / bound > worst) worst = err / bound;
        if (err > bound && over++ < 5)
            fprintf(stderr, "polygon: t %.9g, exact %.9g: off by %.3g, %.1f times the bound\n", t, te, err,
                    err / bound);
    }
    printf("polygon accuracy: %d rays, %d missed, %d off by more than the tol bound; worst %.3g of it\n", n, misses,
           over, worst);
    CHECK_MSG(misses == 0, "%d rays through interior points missed", misses);
    CHECK_MSG(over == 0, "%d of %d polygon hits off by more than verify.h's tol bound", over, n);
    CHECK_MSG(worst < 4.0 / TOL_ULPS, "the worst polygon error is %.3g of the bound", worst);
}

/* The closest hit of r over the scene's triangles, one triangle_intersect
 * each, in id order (ties keep the first). */
static hit_t one_by_one(const prims_t *p, const ray_t *r)
{
    hit_t h = hit_none(r);
    for (uint32_t id = 0; id < p->count; id++) {
        vec3 a, b, c;
        tri_verts(p, p->index[id], &a, &b, &c);
        float t, u, v;
        if (triangle_intersect(a, b, c, r, h.t, &t, &u, &v)) h.t = t, h.u = u, h.v = v, h.prim = id;
    }
    return h;
}

static int same_hit(hit_t x, hit_t y) { return x.prim == y.prim && memcmp(&x.t, &y.t, sizeof x.t) == 0; }

static void test_paths(void)
{
    enum { NTRI = 96, NRAY = 4000 };
    uint32_t st = 777;
    scene_t *s = scene_new("large triangles");
    prims_t *p = &s->prims;
    tri_case cases[NTRI];
    for (int i = 0; i < NTRI; i++) {
        cases[i] = random_case(&st);
        uint32_t a = prims_add_vertex(p, cases[i].a), b = prims_add_vertex(p, cases[i].b),
                 c = prims_add_vertex(p, cases[i].c);
        prims_add_triangle(p, a, b, c);
    }
    test_finish_scene(s);
    ray_t *rays = malloc(NRAY * sizeof *rays);
    hit_t *ref = malloc(NRAY * sizeof *ref);
    uint32_t hits = 0;
    for (int i = 0; i < NRAY; i++) {
        /* A ray at triangle k: a random interior point, a random direction. */
        uint32_t k = (uint32_t)(urand(&st) * NTRI) % NTRI;
        double l1 = 0.1 + 0.4 * urand(&st), l2 = 0.1 + 0.4 * urand(&st), l0 = 1 - l1 - l2;
        vec3 d = random_unit(&st);
        double t = log_uniform(&st, 1e-3, 10.0);
        const tri_case *q = &cases[k];
        double hx = l0 * q->a.x + l1 * q->b.x + l2 * q->c.x, hy = l0 * q->a.y + l1 * q->b.y + l2 * q->c.y,
               hz = l0 * q->a.z + l1 * q->b.z + l2 * q->c.z;
        ray_t r = {v3((float)(hx - t * d.x), (float)(hy - t * d.y), (float)(hz - t * d.z)), 0.0f, d, INFINITY,
                   RAY_NO_LIGHT, RAY_NO_ORIGIN};
        rays[i] = r;
        ref[i] = one_by_one(p, &r);
        hits += ref[i].prim != HIT_NONE;
    }
    CHECK_MSG(hits > NRAY * 9 / 10, "only %u of %d rays hit: the comparison proves little", hits, NRAY);

    /* The packet test over every triangle. */
    uint32_t ids[NTRI];
    for (uint32_t i = 0; i < NTRI; i++) ids[i] = i;
    prim_tri_packet *pk = malloc(prim_tri_packets(NTRI) * sizeof *pk);
    prim_tri_pack(p, ids, NTRI, pk);
    int differ = 0;
    for (int i = 0; i < NRAY; i++) {
        hit_t h = hit_none(&rays[i]);
        counters_t cnt = {0};
        prim_intersect_tris(pk, prim_tri_packets(NTRI), &rays[i], &h, &cnt);
        if (!same_hit(h, ref[i]) && differ++ < 3)
            fprintf(stderr, "packets: ray %d: prim %u t %a, one by one prim %u t %a\n", i, h.prim, h.t, ref[i].prim,
                    ref[i].t);
    }
    CHECK_MSG(differ == 0, "the packet test differs from the one-triangle test on %d rays", differ);
    printf("paths: %d rays (%u hit), packets: %s\n", NRAY, hits, differ ? "DIFFER" : "bit-identical");
    free(pk);

    /* Accelerators through prims/: exhaustive, and the wide BVH everywhere. */
    char cfgs[64][96];
    const char *names[64];
    int ncfg = 0;
    names[ncfg] = "exhaustive", cfgs[ncfg++][0] = 0;
    for (int width = 2; width <= 8; width *= 2)
        for (int isa = WIDE_ISA_SCALAR; isa < WIDE_ISA_COUNT; isa++)
            for (int fused = 0; fused < 2; fused++) {
                if (!wide_isa_supported((wide_isa)isa) || (fused && (isa == WIDE_ISA_SSE42 || width == 2))) continue;
                names[ncfg] = "bvh";
                snprintf(cfgs[ncfg++], sizeof cfgs[0], "width=%d,isa=%s,fma=%s", width, wide_isa_names[isa],
                         fused ? "on" : "off");
            }
    names[ncfg] = "bvh", snprintf(cfgs[ncfg++], sizeof cfgs[0], "width=8,isa=scalar,packets=off");
    for (int k = 0; k < ncfg; k++) {
        accel *a = test_build_or_die(names[k], s, cfgs[k]);
        accel_ctx *ctx = a->ops->context_new ? a->ops->context_new(a) : NULL;
        int bad = 0, bad_any = 0;
        for (int i = 0; i < NRAY; i++) {
            hit_t h = hit_none(&rays[i]);
            counters_t cnt = {0};
            a->ops->intersect(a, ctx, &rays[i], &h, &cnt);
            if (!same_hit(h, ref[i]) && bad++ < 3)
                fprintf(stderr, "%s [%s]: ray %d: prim %u t %a, one by one prim %u t %a\n", names[k], cfgs[k], i,
                        h.prim, h.t, ref[i].prim, ref[i].t);
            /* Any hit over [0, the closest hit's t] and [0, just past it]. */
            if (ref[i].prim != HIT_NONE) {
                ray_t upto = rays[i], past = rays[i];
                upto.tfar = ref[i].t;
                past.tfar = nextafterf(ref[i].t, INFINITY);
                bad_any += a->ops->occluded(a, ctx, &upto, &cnt) != (one_by_one(p, &upto).prim != HIT_NONE);
                bad_any += !a->ops->occluded(a, ctx, &past, &cnt);
            }
        }
        CHECK_MSG(bad == 0 && bad_any == 0, "%s [%s]: %d closest and %d any-hit answers differ", names[k], cfgs[k],
                  bad, bad_any);
        printf("paths: %-10s %-34s %s\n", names[k], cfgs[k], bad || bad_any ? "DIFFER" : "bit-identical");
        if (a->ops->context_free) a->ops->context_free(ctx);
        a->ops->destroy(a);
    }
    free(rays);
    free(ref);
    scene_free(s);
}

/* test_verify.c's thin wall: the origin lies 1.2e-4 from the plane of a
 * triangle 40 high and 0.0036 wide seen nearly edge-on; the plane crosses
 * the ray at t = -0.00057 (the sheared float sum said 0.0040). */
static void test_thin_wall(void)
{
    const vec3 a = v3(0x1.d90ffap+5f, 0x1.8cdcfap+6f, 0.0f), b = v3(0x1.d908cep+5f, 0x1.8ce69ap+6f, 0.0f),
               c = v3(0x1.d908cep+5f, 0x1.8ce69ap+6f, 0x1.4p+5f);
    const vec3 o = v3(0x1.d90a46p+5f, 0x1.8ce4f6p+6f, 0x1.c89454p+4f), d = v3(0x1.959586p-2f, -0x1.f7d776p-2f, 0x1.8ceeb2p-1f);
    ray_t r = {o, 0.0f, d, 608.137451f, RAY_NO_LIGHT, RAY_NO_ORIGIN};
    long double te = exact_t(a, b, c, &r);
    CHECK_MSG(te < -5e-4L && te > -7e-4L, "the plane's t: %Lg", te);
    float t, u, v;
    bool hit = triangle_intersect(a, b, c, &r, r.tfar, &t, &u, &v);
    CHECK_MSG(!hit, "a hit at t = %g on a plane that lies behind the origin", t);
    /* The same test over a range that starts before the plane (tnear is
     * checked by the test, not by its sign): the crossing, accurately. */
    ray_t back = r;
    back.org = v3(o.x - d.x, o.y - d.y, o.z - d.z);
    te = exact_t(a, b, c, &back);
    hit = triangle_intersect(a, b, c, &back, back.tfar, &t, &u, &v);
    CHECK_MSG(hit && fabsl((long double)t - te) <= tol_bound(a, b, c, &back, (double)te), "t %g, exact %Lg",
              hit ? t : -1.0f, te);
    printf("thin wall: the plane at t = %.6Lg behind the origin: %s\n", exact_t(a, b, c, &r), "no hit");
}

int main(void)
{
    test_accuracy();
    test_polygon_accuracy();
    test_thin_wall();
    test_paths();
    return check_report();
}
