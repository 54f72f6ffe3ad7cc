/* judge.cpp: the exact judge of disputed rays (judge.h).
 *
 * Number types. Every input (float coordinates, radii, tnear, tfar) is a
 * dyadic rational and converts exactly to Rat, the exact field type of
 * CGAL's Epeck (CGAL::Epeck::FT::ET, GMP rationals through Boost). The
 * judge uses Epeck's two number types, its interval filter and its exact
 * rationals, directly rather than Epeck's lazy kernel objects: those build
 * a heap-allocated expression DAG per operation, and the judge needs the
 * exact rational t itself anyway, not just predicates on it.
 * - Triangles (and polygons, through their ear-clipping triangles): the
 *   line meets the closed triangle iff the three Pluecker volumes
 *   d . (B x C), d . (C x A), d . (A x B) (A, B, C the vertices minus the
 *   origin) have no two opposite signs, and lies in its plane iff all
 *   three vanish; then t = det(A, B, C) / (d . n), a rational.
 * - Spheres and cones: a t^2 + 2 b t + c = 0 with rational a, b, c; a
 *   root is x + y sqrt(D) with rational x = -b/a, y = +-1/a, D = b^2 - a c
 *   (a rational when D = 0 or the equation is linear).
 * Every comparison the judge makes (a root against tnear, tfar or a cone's
 * end planes, two hits against each other, a value against a rounding
 * midpoint) is the sign of a sum of such surds, decided exactly by
 * squaring (sign_surd, cmp): exact predicates on rationals, no separation
 * bounds (CORE::Expr) needed for square roots of degree 2. A rational t is
 * the surd with y = 0, so triangle and quadric hits are compared in one
 * exact type, never through doubles. The double returned is the one
 * nearest the exact t: a 192-bit MPFR estimate (by the cancellation-free
 * root formula), checked and if need be stepped against the exact
 * midpoints to its neighbours (ties to even).
 *
 * Filter. Each test is first run in CGAL's Interval_nt (certified
 * enclosures under upward rounding), as Epeck's filters do: when the
 * intervals prove a miss nothing exact is computed; when they prove a
 * triangle hit in range only its t is computed in Rat; otherwise the
 * whole test is redone in Rat. Most candidates of a search are provable
 * misses, so the exact stage runs for the few real hits and the
 * near-degenerate cases.
 *
 * Search (judge_closest). Scenes of at most BRUTE_MAX primitives: brute
 * force (a tree would not pay for itself). Otherwise a CGAL::AABB_tree in
 * Simple_cartesian<double>, built on the first judge_closest (or
 * judge_candidates) and freed by judge_free, over one box per primitive:
 * prims.bounds (exact vertex min/max for triangles and polygons, centre
 * -+ radius in double rounded outward for spheres, cone bounds rounded
 * outward). The tree is walked with our own traversal
 * traits (AABB_tree::traversal, CGAL's generic walk) that test the ray
 * segment [tnear, tfar] against every node and primitive box inflated by
 *     delta = 2^-30 M + 2^-900,  M = the largest |coordinate| of the box
 *                                    and of the ray origin,
 * and collect every primitive whose inflated box the segment touches; the
 * exact test then runs on those (judge_candidates walks the same tree with
 * 2^-16 M, to include what float tests find within float noise of the
 * ray; see judge.h). Why the margin suffices: the slab test
 * computes (lo - delta - o_i) / d_i with three roundings of at most 2^-53
 * relative each, which is the exact value for a face moved by at most
 * about 3 * 2^-53 * (|lo| + |o_i| + delta) <= 2^-50 M, far less than
 * delta: so every computed entry t is <= the exact entry t of the
 * uninflated box, every computed exit t >= its exit t, and a segment that
 * touches a box exactly is never rejected (nor the nodes containing it).
 * The other errors are inside delta too: cone bounds are computed in
 * double and rounded outward to float, off by a few double ulps of M at
 * most, and a sphere's c -+ r in double by one. The absolute 2^-900 covers
 * boxes and rays at the origin (M = 0) and keeps delta / |d_i| (|d_i| <=
 * FLT_MAX) far above double underflow; an overflow to infinity only
 * happens where the exact t exceeds any finite tfar. Memory: 24 bytes of
 * boxes, 4 of primitive and about 64 of tree node per primitive.
 *
 * Costs (tests/test_judge --bench: median per ray over 3000 rays aimed at
 * random primitives, 2-core VM): judge_closest 15-19 us on bunny (75k
 * triangles, tree built in 25 ms), 13-19 us on dragon, 15-18 us on
 * spd:balls:3; 40-50 us on 330k-600k primitive scenes (tree 0.13-0.23 s),
 * whose rays cross more surfaces; judge_closest_among on 2 candidates
 * 4-6 us. The tree walk is 1-10 us of it; the rest is rational arithmetic
 * on the 2-6 candidates the intervals cannot dismiss. */
#include "judge.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Interval_nt.h>
#include <CGAL/Simple_cartesian.h>
#include <boost/iterator/counting_iterator.hpp>
#include <mpfr.h>
#include "../../prims/checked_alloc.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <new>
#include <string>
#include <utility>
#include <vector>

namespace {

typedef CGAL::Epeck::FT::ET Rat; /* Epeck's exact field type: GMP rationals */
typedef CGAL::Interval_nt<false> Ival; /* needs Protect_FPU_rounding around it */

const uint32_t BRUTE_MAX = 8;

/* ---------------------------------------------------------------------- */
/* exact numbers x + y sqrt(D)                                            */

struct Num {
    Rat x, y, D; /* D >= 0; a rational has y = D = 0 */
};

/* Sign of x + y sqrt(D), exactly: when x and y sqrt(D) differ in sign,
 * the larger magnitude wins, and squares compare magnitudes. */
int sign_surd(const Rat &x, const Rat &y, const Rat &D)
{
    int sx = x.sign(), sy = D.sign() == 0 ? 0 : y.sign();
    if (sy == 0) return sx;
    if (sx == 0 || sx == sy) return sy;
    Rat diff = x * x - y * y * D;
    return sx * diff.sign();
}

/* Sign of p - q. With alpha = (p.x - q.x) + p.y sqrt(p.D) and
 * beta = -q.y sqrt(q.D): if their signs differ, sign(alpha + beta) =
 * sign(alpha) * sign(alpha^2 - beta^2), and alpha^2 - beta^2 is again a
 * surd in sqrt(p.D). */
int cmp(const Num &p, const Num &q)
{
    Rat P = p.x - q.x;
    if (q.y.sign() == 0 || q.D.sign() == 0) return sign_surd(P, p.y, p.D);
    if (p.y.sign() == 0 || p.D.sign() == 0) return sign_surd(P, Rat(-q.y), q.D);
    if (p.D == q.D) return sign_surd(P, Rat(p.y - q.y), p.D);
    int sa = sign_surd(P, p.y, p.D), sb = -q.y.sign();
    if (sa == 0) return sb;
    if (sa == sb) return sa;
    return sa * sign_surd(Rat(P * P + p.y * p.y * p.D - q.y * q.y * q.D), Rat(2 * P * p.y), p.D);
}

/* One exact hit distance, with what describes it. */
struct Root {
    Num v;
    bool surd = false; /* v = (-b + s sqrt(D)) / a, else v = v.x */
    Rat a, b, c;
    int s = 0;
    void set_rational(const Rat &q)
    {
        surd = false;
        v.x = q;
        v.y = 0;
        v.D = 0;
    }
    void set_surd(const Rat &a_, const Rat &b_, const Rat &c_, const Rat &D, int s_)
    {
        surd = true;
        a = a_;
        b = b_;
        c = c_;
        s = s_;
        v.x = -b / a;
        v.y = Rat(s) / a;
        v.D = D;
    }
};

/* ---------------------------------------------------------------------- */
/* the ray, in double (filters) and, on demand, exactly                    */

struct Query {
    double o[3], d[3], tnear, tfar;
    bool empty;       /* NaN or empty range: nothing can hit */
    bool built = false;
    uint32_t nexact = 0; /* exact (rational) primitive tests run */
    Rat O[3], Dv[3], Tn, Tf;
    bool lower = false, upper = false; /* tnear > -inf, tfar < +inf */

    explicit Query(const ray_t *ray)
    {
        o[0] = ray->org.x, o[1] = ray->org.y, o[2] = ray->org.z;
        d[0] = ray->dir.x, d[1] = ray->dir.y, d[2] = ray->dir.z;
        tnear = ray->tnear;
        tfar = ray->tfar;
        empty = !(tnear < tfar); /* also NaN */
    }
    const Query &exact()
    {
        if (!built) {
            for (int i = 0; i < 3; i++) O[i] = o[i], Dv[i] = d[i];
            lower = std::isfinite(tnear);
            upper = std::isfinite(tfar);
            if (lower) Tn = tnear;
            if (upper) Tf = tfar;
            built = true;
        }
        return *this;
    }
    /* tnear <= t < tfar, exactly (exact() has been called). */
    bool in_range(const Num &t) const
    {
        if (lower && sign_surd(Rat(t.x - Tn), t.y, t.D) < 0) return false;
        if (upper && sign_surd(Rat(t.x - Tf), t.y, t.D) >= 0) return false;
        return true;
    }
};

inline void load(const vec3 &v, double out[3]) { out[0] = v.x, out[1] = v.y, out[2] = v.z; }

template <class NT> NT dot(const NT a[3], const NT b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
template <class NT> void cross(const NT a[3], const NT b[3], NT out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

/* ---------------------------------------------------------------------- */
/* triangles                                                               */

/* With A, B, C the vertices relative to the origin: w[k] = d . (edge
 * cross product) are the signed volumes of the ray line with the edges
 * opposite a, b, c (Pluecker tests); the line meets the closed triangle
 * iff none has the opposite sign of another, and lies in its plane iff all
 * vanish. Their sum is d . n, and t = det(A, B, C) / (d . n). */
template <class NT> void tri_terms(const NT a[3], const NT b[3], const NT c[3], const NT o[3], const NT d[3], NT w[3], NT &num)
{
    NT A[3], B[3], C[3], x[3];
    for (int i = 0; i < 3; i++) A[i] = a[i] - o[i], B[i] = b[i] - o[i], C[i] = c[i] - o[i];
    cross(B, C, x);
    w[0] = dot(d, x);
    num = dot(A, x);
    cross(C, A, x);
    w[1] = dot(d, x);
    cross(A, B, x);
    w[2] = dot(d, x);
}

/* Interval filter. MISS: certainly a miss. SURE: the line certainly
 * crosses the triangle's interior at a t certainly in range (only t itself
 * remains to be computed exactly). UNSURE: the exact test decides. */
enum Filter { MISS, SURE, UNSURE };

Filter tri_filter(const Query &q, const vec3 &va, const vec3 &vb, const vec3 &vc)
{
    CGAL::Protect_FPU_rounding<true> upward;
    double da[3], db[3], dc[3];
    load(va, da), load(vb, db), load(vc, dc);
    Ival a[3], b[3], c[3], o[3], d[3], w[3], num;
    for (int i = 0; i < 3; i++) a[i] = da[i], b[i] = db[i], c[i] = dc[i], o[i] = q.o[i], d[i] = q.d[i];
    tri_terms(a, b, c, o, d, w, num);
    int pos = 0, neg = 0, zero = 0;
    for (int k = 0; k < 3; k++) {
        pos += w[k].inf() > 0;
        neg += w[k].sup() < 0;
        zero += w[k].inf() == 0 && w[k].sup() == 0;
    }
    if ((pos && neg) || zero == 3) return MISS;
    Ival den = w[0] + w[1] + w[2];
    if (!(den.inf() > 0 || den.sup() < 0)) return UNSURE;
    Ival t = num / den;
    if (t.sup() < q.tnear || t.inf() >= q.tfar) return MISS;
    bool in_range = t.inf() >= q.tnear && t.sup() < q.tfar;
    return (pos == 3 || neg == 3) && in_range ? SURE : UNSURE;
}

/* The exact test; t is rational. */
bool tri_exact(Query &q, const vec3 &va, const vec3 &vb, const vec3 &vc, Filter f, Rat &t)
{
    q.nexact++;
    const Query &x = q.exact();
    double da[3], db[3], dc[3];
    load(va, da), load(vb, db), load(vc, dc);
    Rat a[3], b[3], c[3];
    for (int i = 0; i < 3; i++) a[i] = da[i], b[i] = db[i], c[i] = dc[i];
    if (f == SURE) { /* t = n.(a - o) / n.d with n = (b - a) x (c - a): the same rational, fewer operations */
        Rat e1[3], e2[3], n[3], ao[3];
        for (int i = 0; i < 3; i++) e1[i] = b[i] - a[i], e2[i] = c[i] - a[i], ao[i] = a[i] - x.O[i];
        cross(e1, e2, n);
        t = dot(n, ao) / dot(n, x.Dv);
        return true;
    }
    Rat w[3], num;
    tri_terms(a, b, c, x.O, x.Dv, w, num);
    int s0 = w[0].sign(), s1 = w[1].sign(), s2 = w[2].sign();
    if ((s0 < 0 || s1 < 0 || s2 < 0) && (s0 > 0 || s1 > 0 || s2 > 0)) return false;
    Rat den = w[0] + w[1] + w[2];
    if (den.sign() == 0) return false; /* all three zero: the line lies in the plane */
    t = num / den;
    Num tv;
    tv.x = t;
    return x.in_range(tv);
}

bool tri_hit(Query &q, const vec3 &a, const vec3 &b, const vec3 &c, Rat &t)
{
    Filter f = tri_filter(q, a, b, c);
    return f != MISS && tri_exact(q, a, b, c, f, t);
}

/* ---------------------------------------------------------------------- */
/* quadrics: spheres and cones                                             */

/* The first root (in increasing t) of a t^2 + 2 b t + c = 0 that is in
 * range and passes ok. a = b = 0: no root, or (c = 0) the whole line is
 * on the surface, which misses by convention. */
template <class Ok> bool first_root(Query &q, const Rat &a, const Rat &b, const Rat &c, Ok ok, Root &out)
{
    const Query &x = q.exact();
    if (a.sign() == 0) {
        if (b.sign() == 0) return false;
        out.set_rational(Rat(-c / (2 * b)));
        return x.in_range(out.v) && ok(out);
    }
    Rat D = b * b - a * c;
    if (D.sign() < 0) return false;
    if (D.sign() == 0) { /* tangent: one rational double root, a hit */
        out.set_rational(Rat(-b / a));
        return x.in_range(out.v) && ok(out);
    }
    int first = a.sign() > 0 ? -1 : 1; /* the smaller root has -sqrt when a > 0 */
    for (int s : {first, -first}) {
        out.set_surd(a, b, c, D, s);
        if (x.in_range(out.v) && ok(out)) return true;
    }
    return false;
}

/* |o + t d - centre|^2 = r^2: a = d.d, b = f.d, c = f.f - r^2, f = o - centre. */
template <class NT> void sphere_terms(const NT ce[3], const NT &r, const NT o[3], const NT d[3], NT &a, NT &b, NT &c)
{
    NT f[3];
    for (int i = 0; i < 3; i++) f[i] = o[i] - ce[i];
    a = dot(d, d);
    b = dot(f, d);
    c = dot(f, f) - r * r;
}

bool sphere_hit(Query &q, const sphere_t &s, Root &out)
{
    double ce[3], r = s.radius;
    load(s.center, ce);
    {
        CGAL::Protect_FPU_rounding<true> upward;
        Ival C[3], o[3], d[3], a, b, c;
        for (int i = 0; i < 3; i++) C[i] = ce[i], o[i] = q.o[i], d[i] = q.d[i];
        sphere_terms(C, Ival(r), o, d, a, b, c);
        if ((b * b - a * c).sup() < 0) return false;
    }
    q.nexact++;
    const Query &x = q.exact();
    Rat C[3], a, b, c;
    for (int i = 0; i < 3; i++) C[i] = ce[i];
    sphere_terms(C, Rat(r), x.O, x.Dv, a, b, c);
    return first_root(q, a, b, c, [](const Root &) { return true; }, out);
}

/* The cone of prims.h with w = A - B, L2 = w.w, h(t) = (o + t d - B).w:
 * L2^2 |x - B|^2 - L2 h^2 - (rb L2 + (ra - rb) h)^2 = a t^2 + 2 b t + c. */
template <class NT>
void cone_terms(const NT B[3], const NT &rb, const NT A[3], const NT &ra, const NT o[3], const NT d[3], NT &a, NT &b, NT &c,
                NT &h0, NT &dw, NT &L2)
{
    NT w[3], p[3];
    for (int i = 0; i < 3; i++) w[i] = A[i] - B[i], p[i] = o[i] - B[i];
    L2 = dot(w, w);
    h0 = dot(p, w);
    dw = dot(d, w);
    NT k = ra - rb, m0 = rb * L2 + k * h0, m1 = k * dw, L4 = L2 * L2;
    a = L4 * dot(d, d) - L2 * dw * dw - m1 * m1;
    b = L4 * dot(p, d) - L2 * h0 * dw - m0 * m1;
    c = L4 * dot(p, p) - L2 * h0 * h0 - m0 * m0;
}

bool cone_hit(Query &q, const cone_t &cn, Root &out)
{
    double B[3], A[3], rb = cn.base_radius, ra = cn.apex_radius;
    load(cn.base, B), load(cn.apex, A);
    {
        CGAL::Protect_FPU_rounding<true> upward;
        Ival IB[3], IA[3], o[3], d[3], a, b, c, h0, dw, L2;
        for (int i = 0; i < 3; i++) IB[i] = B[i], IA[i] = A[i], o[i] = q.o[i], d[i] = q.d[i];
        cone_terms(IB, Ival(rb), IA, Ival(ra), o, d, a, b, c, h0, dw, L2);
        if ((b * b - a * c).sup() < 0) return false;
    }
    q.nexact++;
    const Query &x = q.exact();
    Rat RB[3], RA[3], a, b, c, h0, dw, L2;
    for (int i = 0; i < 3; i++) RB[i] = B[i], RA[i] = A[i];
    cone_terms(RB, Rat(rb), RA, Rat(ra), x.O, x.Dv, a, b, c, h0, dw, L2);
    /* 0 <= h(t) = (h0 + dw t.x) + dw t.y sqrt(D) <= L2, exactly */
    auto between = [&](const Root &t) {
        Rat hx = h0 + dw * t.v.x, hy = dw * t.v.y;
        return sign_surd(hx, hy, t.v.D) >= 0 && sign_surd(Rat(L2 - hx), Rat(-hy), t.v.D) >= 0;
    };
    return first_root(q, a, b, c, between, out);
}

/* ---------------------------------------------------------------------- */
/* one primitive                                                           */

struct Stats {
    uint32_t candidates = 0, exact = 0;
};

/* The exact nearest hit of primitive id in range. */
bool prim_hit(const prims_t *p, uint32_t id, Query &q, Root &out)
{
    uint32_t k = p->index[id];
    switch ((prim_kind)p->kind[id]) {
    case PRIM_TRIANGLE: {
        if (p->tri_degenerate[k]) return false;
        const tri_t &t = p->tris[k];
        Rat tt;
        if (!tri_hit(q, p->verts[t.v[0]], p->verts[t.v[1]], p->verts[t.v[2]], tt)) return false;
        out.set_rational(tt);
        return true;
    }
    case PRIM_POLYGON: {
        const polygon_t &g = p->polygons[k];
        if (g.degenerate) return false;
        bool any = false;
        Rat best, tt;
        for (uint32_t i = 0; i + 2 < g.count; i++) {
            const tri_t &t = p->poly_tris[g.tri_first + i];
            if (tri_hit(q, p->verts[t.v[0]], p->verts[t.v[1]], p->verts[t.v[2]], tt) && (!any || tt < best)) {
                best = tt;
                any = true;
            }
        }
        if (any) out.set_rational(best);
        return any;
    }
    case PRIM_SPHERE:
        return sphere_hit(q, p->spheres[k], out);
    case PRIM_CONE:
        return cone_hit(q, p->cones[k], out);
    default:
        return false;
    }
}

/* ---------------------------------------------------------------------- */
/* exact value to double and to text                                       */

bool odd(double x)
{
    uint64_t u;
    std::memcpy(&u, &x, sizeof u);
    return u & 1;
}

/* Exact midpoint of two finite doubles, as a Num. */
Num midpoint(double a, double b)
{
    Num m;
    m.x = (Rat(a) + Rat(b)) / 2;
    return m;
}

double nearest_double(const Root &t)
{
    mpfr_t x, y;
    mpfr_inits2(192, x, y, (mpfr_ptr)0);
    if (!t.surd) {
        mpfr_set_q(x, t.v.x.backend().data(), MPFR_RNDN);
    } else {
        /* (-b + s sqrt D) / a unless -b and s sqrt D cancel; then the
         * equal c / (-b - s sqrt D) (the product of the roots is c / a). */
        mpfr_set_q(y, t.v.D.backend().data(), MPFR_RNDN);
        mpfr_sqrt(y, y, MPFR_RNDN);
        if (t.s < 0) mpfr_neg(y, y, MPFR_RNDN);
        mpfr_set_q(x, t.b.backend().data(), MPFR_RNDN);
        mpfr_neg(x, x, MPFR_RNDN);
        if (t.s * t.b.sign() <= 0) {
            mpfr_add(x, x, y, MPFR_RNDN);
            mpfr_div_q(x, x, t.a.backend().data(), MPFR_RNDN);
        } else {
            mpfr_sub(x, x, y, MPFR_RNDN);
            mpfr_set_q(y, t.c.backend().data(), MPFR_RNDN);
            mpfr_div(x, y, x, MPFR_RNDN);
        }
    }
    double d = mpfr_get_d(x, MPFR_RNDN);
    mpfr_clears(x, y, (mpfr_ptr)0);
    /* Check against the exact midpoints to the neighbours; step (rarely
     * needed: the estimate is good to ~2^-190) and break ties to even. */
    for (;;) {
        double lo = std::nextafter(d, -INFINITY), hi = std::nextafter(d, INFINITY);
        if (!std::isfinite(d) || !std::isfinite(lo) || !std::isfinite(hi)) return d;
        int cl = cmp(t.v, midpoint(d, lo));
        if (cl < 0 || (cl == 0 && odd(d))) {
            d = lo;
            continue;
        }
        int ch = cmp(t.v, midpoint(d, hi));
        if (ch > 0 || (ch == 0 && odd(d))) {
            d = hi;
            continue;
        }
        return d;
    }
}

std::string mpz_text(mpz_srcptr z)
{
    std::vector<char> buf(mpz_sizeinbase(z, 10) + 2);
    mpz_get_str(buf.data(), 10, z);
    return buf.data();
}

std::string rat_text(const Rat &r)
{
    mpq_srcptr q = r.backend().data();
    return mpz_text(mpq_numref(q)) + "/" + mpz_text(mpq_denref(q));
}

std::string root_text(const Root &t)
{
    if (!t.surd) return rat_text(t.v.x);
    return "(-(" + rat_text(t.b) + (t.s < 0 ? ") - sqrt(" : ") + sqrt(") + rat_text(t.v.D) + "))/(" + rat_text(t.a) + ")";
}

/* ---------------------------------------------------------------------- */
/* the search tree                                                         */

typedef CGAL::Simple_cartesian<double> DK;

/* The boxes the tree is built over: prims.bounds, which contain every
 * primitive exactly (vertex min/max; spheres' and cones' rounded outward). */
std::vector<box3> search_boxes(const prims_t *p) { return std::vector<box3>(p->bounds, p->bounds + p->count); }

inline CGAL::Bbox_3 bbox_of(const box3 &b) { return CGAL::Bbox_3(b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z); }

/* An AABBPrimitiveWithSharedData: just the id; boxes come from search_boxes. */
struct BoxPrim {
    typedef uint32_t Id;
    typedef DK::Point_3 Point;
    typedef DK::Iso_cuboid_3 Datum;
    typedef Point Point_reference;
    typedef Datum Datum_reference;
    typedef const box3 *Shared_data;
    Id i = 0;
    BoxPrim() {}
    BoxPrim(boost::counting_iterator<uint32_t> it, const box3 *) : i(*it) {}
    Id id() const { return i; }
    Datum datum(Shared_data b) const { return Datum(bbox_of(b[i])); }
    Point reference_point(Shared_data b) const
    {
        const box3 &x = b[i];
        return Point(0.5 * ((double)x.lo.x + x.hi.x), 0.5 * ((double)x.lo.y + x.hi.y), 0.5 * ((double)x.lo.z + x.hi.z));
    }
    static Shared_data construct_shared_data(const box3 *b) { return b; }
};

typedef CGAL::AABB_tree<CGAL::AABB_traits<DK, BoxPrim>> Tree;

/* The ray segment against an inflated box, in double (margin: file header).
 * Plain comparisons rather than fmax/fmin: no NaN can arise here, and
 * GCC calls libm for those. */
inline double dmax(double a, double b) { return a > b ? a : b; }
inline double dmin(double a, double b) { return a < b ? a : b; }
inline double dabs(double a) { return a < 0 ? -a : a; }

struct Slab {
    double o[3], d[3], t0, t1, omag, rel; /* rel: the relative margin, 2^-30 for the judge's own search */
    Slab(const Query &q, double rel_margin) : rel(rel_margin)
    {
        omag = 0;
        for (int i = 0; i < 3; i++) o[i] = q.o[i], d[i] = q.d[i], omag = dmax(omag, dabs(o[i]));
        t0 = q.tnear;
        t1 = q.tfar;
    }
    bool touches(const CGAL::Bbox_3 &b) const
    {
        double m = omag;
        for (int i = 0; i < 3; i++) m = dmax(m, dmax(dabs(b.min(i)), dabs(b.max(i))));
        double delta = m * rel + 0x1p-900;
        double tmin = t0, tmax = t1;
        for (int i = 0; i < 3; i++) {
            double lo = b.min(i) - delta, hi = b.max(i) + delta;
            if (d[i] == 0) {
                if (o[i] < lo || o[i] > hi) return false;
                continue;
            }
            double ta = (lo - o[i]) / d[i], tb = (hi - o[i]) / d[i];
            if (ta > tb) std::swap(ta, tb);
            tmin = dmax(tmin, ta);
            tmax = dmin(tmax, tb);
            if (tmin > tmax) return false;
        }
        return true;
    }
};

/* Traversal traits for AABB_tree::traversal: visit every node the
 * inflated segment touches, collect the primitives. */
struct Collect {
    const Slab &slab;
    const box3 *boxes;
    std::vector<uint32_t> &out;
    bool go_further() const { return true; }
    template <class Q> void intersection(const Q &, const BoxPrim &pr)
    {
        if (slab.touches(bbox_of(boxes[pr.id()]))) out.push_back(pr.id());
    }
    template <class Q, class Node> bool do_intersect(const Q &, const Node &n) const { return slab.touches(n.bbox()); }
};

} // namespace

struct judge {
    const scene_t *s;
    Tree *tree = nullptr;
    std::vector<box3> boxes; /* what the tree is built over */
    std::vector<uint32_t> cand;
    Stats last;
};

/* The exact nearest hit among ids; ties to the lowest id. */
static judge_hit closest_among(judge_t *j, const ray_t *r, const uint32_t *ids, size_t n)
{
    const prims_t *p = &j->s->prims;
    Query q(r);
    Root best, cur;
    judge_hit h = {HIT_NONE, r->tfar};
    if (q.empty) return h;
    for (size_t i = 0; i < n; i++) {
        uint32_t id = ids[i];
        if (id >= p->count || id == h.prim) continue;
        if (!prim_hit(p, id, q, cur)) continue;
        int c = h.prim == HIT_NONE ? -1 : cmp(cur.v, best.v);
        if (c < 0 || (c == 0 && id < h.prim)) {
            std::swap(best, cur);
            h.prim = id;
        }
    }
    j->last.exact = q.nexact;
    if (h.prim != HIT_NONE) h.t = nearest_double(best);
    return h;
}

/* No C++ exception may cross into C: an allocation of the judge's failing
 * (the tree, the candidate list, CGAL's numbers) is one line and exit 2,
 * as everywhere else (prims/checked_alloc.h), not std::terminate. */
template <class F> static auto or_exit(F f) -> decltype(f())
{
    try {
        return f();
    } catch (const std::bad_alloc &) {
        checked_alloc_failed(0, "the exact judge");
    }
}

extern "C" {

judge_t *judge_new(const scene_t *s)
{
    return or_exit([&] {
        judge_t *j = new judge;
        j->s = s;
        return j;
    });
}

void judge_free(judge_t *j)
{
    if (!j) return;
    delete j->tree;
    delete j;
}

judge_hit judge_closest_among(judge_t *j, const ray_t *r, const uint32_t *ids, int n)
{
    return or_exit([&] { return closest_among(j, r, ids, n > 0 ? (size_t)n : 0); });
}

/* Fill j->cand with every primitive whose box, inflated by rel M + 2^-900,
 * the segment touches (all of them for a small scene), building the tree
 * on first use. */
static void collect_candidates(judge_t *j, const ray_t *r, double rel)
{
    const prims_t *p = &j->s->prims;
    j->cand.clear();
    if (p->count <= BRUTE_MAX) {
        for (uint32_t id = 0; id < p->count; id++) j->cand.push_back(id);
        return;
    }
    if (!j->tree) {
        j->boxes = search_boxes(p);
        j->tree = new Tree;
        j->tree->insert(boost::counting_iterator<uint32_t>(0), boost::counting_iterator<uint32_t>(p->count), j->boxes.data());
        j->tree->build();
    }
    Query q(r);
    if (q.empty) return;
    Slab slab(q, rel);
    Collect collect{slab, j->boxes.data(), j->cand};
    j->tree->traversal(0, collect);
}

judge_hit judge_closest(judge_t *j, const ray_t *r)
{
    return or_exit([&] {
        collect_candidates(j, r, 0x1p-30);
        j->last.candidates = (uint32_t)j->cand.size();
        return closest_among(j, r, j->cand.data(), j->cand.size());
    });
}

int judge_candidates(judge_t *j, const ray_t *r, uint32_t *ids, int max)
{
    or_exit([&] { collect_candidates(j, r, 0x1p-16); });
    size_t n = std::min(j->cand.size(), max > 0 ? (size_t)max : 0);
    if (n) std::memcpy(ids, j->cand.data(), n * sizeof *ids);
    return (int)j->cand.size();
}

bool judge_describe(judge_t *j, const ray_t *r, uint32_t prim, char *decimal, size_t dlen, char *exact, size_t elen)
{
    const prims_t *p = &j->s->prims;
    Query q(r);
    Root t;
    if (prim >= p->count || q.empty || !prim_hit(p, prim, q, t)) {
        if (dlen) snprintf(decimal, dlen, "miss");
        if (elen) snprintf(exact, elen, "miss");
        return false;
    }
    if (dlen) snprintf(decimal, dlen, "%.17g", nearest_double(t));
    if (elen) or_exit([&] { snprintf(exact, elen, "%s", root_text(t).c_str()); });
    return true;
}

void judge_last_stats(const judge_t *j, uint32_t *candidates, uint32_t *exact_tests)
{
    if (candidates) *candidates = j->last.candidates;
    if (exact_tests) *exact_tests = j->last.exact;
}

} // extern "C"
