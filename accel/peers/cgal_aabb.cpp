/* cgal_aabb.cpp: CGAL's AABB_tree (CGAL 5.5, Debian's libcgal-dev) as a peer.
 * Reference: docs/accels/peers.md.
 *
 * Paper: P. Alliez, S. Tayeb, C. Wormser, "3D Fast Intersection and Distance
 * Computation (AABB Tree)", CGAL User and Reference Manual, AABB Tree
 * package: "Interface" (first_intersection(), do_intersect()), "Trees of
 * Custom Primitives" (AABBPrimitiveWithSharedData) and "Implementation
 * Details".
 *
 * What CGAL 5.5 builds (AABB_tree.h expand(), AABB_traits.h
 * Split_primitives): a binary tree, top down, one primitive per leaf, split
 * by std::nth_element on the reference point along the longest axis of the
 * node's box into halves of equal count (object median, no SAH); n
 * primitives make n - 1 nodes. first_intersection(Ray_3) is best-first by
 * slab entry distance; do_intersect is depth-first, left child first,
 * ending at the first primitive that says yes.
 *
 * Primitives, one mixed tree: triangles as kernel Triangle_3 (float to
 * double, exact; zero-area ones left out); polygons as their ear triangles
 * carrying the polygon's id; spheres and cones as a custom primitive whose
 * datum is its bounding box (reference point its centre) and whose
 * Intersection / Do_intersect call prims/ with the float ray. CGAL's
 * functors see only (query, primitive), so the float ray rides in a
 * thread_local pointer set by each query (CGAL runs a query on its
 * caller's thread). The traits class derives from CGAL::AABB_traits and
 * shadows only Intersection_and_primitive_id, Intersection and
 * Do_intersect; boxes, build and ray/box distance are CGAL's.
 *
 * Rays: closest hit = first_intersection of the Ray_3 from org + tnear dir
 * along dir (scaled by a power of two to a largest component in [1, 2)),
 * t = dot(p - org, dir) / dot(dir, dir) of the point p (for a segment, its
 * end nearest the origin), t >= tfar a miss. Any hit = do_intersect of the
 * closed Segment_3 tnear..tfar (a Ray_3 when tfar is infinite; a segment
 * degenerate in doubles is asked as a closest hit). u = v = 0.
 * first_intersection is not exact (CGAL's tracker, #1822 and pull request
 * #3766: candidate points are constructed in doubles); verify reports its
 * mismatches like anyone's.
 *
 * Memory (g++ 12, CGAL 5.5, both kernels; static_asserts below): primitives
 * 8 bytes (scene id, slot), capacity counted (push_back growth); nodes 64
 * bytes (Bbox_3 + two pointers), n - 1 reserved exactly; Triangle_3 72
 * bytes each. Spheres and cones hold only their primitive.
 *
 * Counters: not observable (ACCEL_NO_COUNTERS). No context: the tree is built
 * completely in build() (tree.build()), so concurrent queries only read. */
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Simple_cartesian.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <new>
#include <vector>
#include "../accel.h"

namespace {

const uint32_t NOT_TRI = UINT32_MAX;

/* The float ray of the query running on this thread (see the header). */
thread_local const ray_t *tl_ray;

template <class K> struct Side; /* what the primitives point into */

/* What the tree reads of a primitive to build: its bounding box. */
struct Box_datum {
    CGAL::Bbox_3 box;
    CGAL::Bbox_3 bbox() const { return box; }
};

/* A tree primitive (concept AABBPrimitiveWithSharedData): 8 bytes, the
 * geometry comes from the shared Side. */
template <class K> struct Prim {
    typedef uint32_t Id;                 /* scene primitive id */
    typedef typename K::Point_3 Point;
    typedef Box_datum Datum;
    typedef const Side<K> *Shared_data;
    uint32_t id_ = 0, slot_ = NOT_TRI;   /* slot: index into Side::tris, or NOT_TRI (sphere, cone) */

    Prim() = default;
    Prim(uint32_t id, uint32_t slot) : id_(id), slot_(slot) {}
    Id id() const { return id_; }
    Datum datum(Shared_data s) const;
    Point reference_point(Shared_data s) const;
    static Shared_data construct_shared_data(Shared_data s) { return s; }
};
static_assert(sizeof(Prim<CGAL::Epick>) == 8, "primitive size in the header");

template <class K> struct Side {
    const prims_t *prims;
    std::vector<typename K::Triangle_3> tris;
};

inline CGAL::Bbox_3 to_bbox(box3 b) { return CGAL::Bbox_3(b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z); }

template <class K> Box_datum Prim<K>::datum(Shared_data s) const
{
    return Box_datum{slot_ != NOT_TRI ? s->tris[slot_].bbox() : to_bbox(prim_bounds(s->prims, id_))};
}

/* CGAL's triangle primitive splits on the first vertex; a sphere or cone on
 * its box centre. */
template <class K> typename K::Point_3 Prim<K>::reference_point(Shared_data s) const
{
    if (slot_ != NOT_TRI) return s->tris[slot_].vertex(0);
    CGAL::Bbox_3 b = to_bbox(prim_bounds(s->prims, id_));
    return typename K::Point_3((b.xmin() + b.xmax()) / 2, (b.ymin() + b.ymax()) / 2, (b.zmin() + b.zmax()) / 2);
}

template <class K> struct Traits : CGAL::AABB_traits<K, Prim<K>> {
    typedef typename K::Point_3 Point_3;
    typedef typename K::Ray_3 Ray_3;
    typedef typename K::Triangle_3 Triangle_3;
    /* The kernel's Ray_3 x Triangle_3 result, optional<variant<Point_3,
     * Segment_3>>; spheres and cones report a Point_3 in it too. */
    typedef decltype(K().intersect_3_object()(std::declval<Ray_3>(), std::declval<Triangle_3>())) Tri_result;

    template <class Query> struct Intersection_and_primitive_id {
        typedef std::pair<typename Tri_result::value_type, uint32_t> Type;
    };
    typedef typename Intersection_and_primitive_id<Ray_3>::Type Hit;

    /* Used by first_intersection for every leaf primitive. */
    class Intersection {
        const Traits &tr;
    public:
        explicit Intersection(const Traits &t) : tr(t) {}
        boost::optional<Hit> operator()(const Ray_3 &q, const Prim<K> &p) const
        {
            const Side<K> *s = tr.shared_data();
            if (p.slot_ != NOT_TRI) {
                Tri_result r = K().intersect_3_object()(q, s->tris[p.slot_]);
                if (!r) return boost::none;
                return Hit(*r, p.id_);
            }
            const ray_t *r = tl_ray;
            hit_t h = hit_none(r);
            counters_t unused = {};
            if (!prim_intersect(s->prims, p.id_, r, &h, &unused)) return boost::none;
            double t = h.t;
            Point_3 at(r->org.x + t * r->dir.x, r->org.y + t * r->dir.y, r->org.z + t * r->dir.z);
            return Hit(at, p.id_);
        }
    };
    Intersection intersection_object() const { return Intersection(*this); }

    /* Used by do_intersect for node boxes and leaf primitives. */
    class Do_intersect {
        const Traits &tr;
    public:
        explicit Do_intersect(const Traits &t) : tr(t) {}
        template <class Query> bool operator()(const Query &q, const CGAL::Bbox_3 &b) const
        {
            return K().do_intersect_3_object()(q, b);
        }
        template <class Query> bool operator()(const Query &q, const Prim<K> &p) const
        {
            const Side<K> *s = tr.shared_data();
            if (p.slot_ != NOT_TRI) return K().do_intersect_3_object()(q, s->tris[p.slot_]);
            counters_t unused = {};
            return prim_occluded(s->prims, p.id_, tl_ray, &unused);
        }
    };
    Do_intersect do_intersect_object() const { return Do_intersect(*this); }
};

/* The kernel-independent face of a tree, for the C functions below. */
struct Tree_base {
    virtual ~Tree_base() {}
    virtual bool intersect(const ray_t *r, hit_t *hit) const = 0;
    virtual bool occluded(const ray_t *r) const = 0;
    virtual size_t memory() const = 0;
    virtual size_t size() const = 0;
};

template <class K> struct Tree final : Tree_base {
    typedef typename K::Point_3 Point_3;
    typedef typename K::Vector_3 Vector_3;
    typedef CGAL::AABB_tree<Traits<K>> Aabb;
    Side<K> side;
    Aabb tree;
    static_assert(sizeof(CGAL::AABB_node<Traits<K>>) == 64 && sizeof(typename K::Triangle_3) == 72,
                  "node and triangle sizes in the header");

    explicit Tree(const prims_t *p)
    {
        side.prims = p;
        const prims_t &P = *p;
        size_t ntri = 0;
        for (uint32_t id = 0; id < P.count; id++) {
            if (P.kind[id] == PRIM_TRIANGLE) ntri++;
            if (P.kind[id] == PRIM_POLYGON) ntri += P.polygons[P.index[id]].count - 2;
        }
        side.tris.reserve(ntri);
        auto add_tri = [&](uint32_t id, const tri_t &t) {
            auto pt = [&](uint32_t v) { return Point_3(P.verts[v].x, P.verts[v].y, P.verts[v].z); };
            typename K::Triangle_3 tri(pt(t.v[0]), pt(t.v[1]), pt(t.v[2]));
            if (tri.is_degenerate()) return; /* CGAL's triangle predicates require a proper triangle */
            side.tris.push_back(tri);
            tree.insert(Prim<K>(id, (uint32_t)(side.tris.size() - 1)));
        };
        for (uint32_t id = 0; id < P.count; id++) {
            uint32_t k = P.index[id];
            switch (P.kind[id]) {
            case PRIM_TRIANGLE:
                if (!P.tri_degenerate[k]) add_tri(id, P.tris[k]);
                break;
            case PRIM_POLYGON: {
                const polygon_t &g = P.polygons[k];
                if (g.degenerate) break;
                for (uint32_t j = 0; j + 2 < g.count; j++) add_tri(id, P.poly_tris[g.tri_first + j]);
                break;
            }
            default: /* sphere, cone: tested by prims/ */
                tree.insert(Prim<K>(id, NOT_TRI));
            }
        }
        tree.build(&side); /* sets the shared data and builds now, not at the first query */
    }

    /* dir scaled by a power of two (exactly) to a largest component in [1, 2): CGAL makes a Ray_3 of a
     * point and a vector into two points, start and start + dir, which coincide for a tiny direction
     * (1e-30 from z = 1) and then meet nothing. */
    static Vector_3 ray_vector(const vec3 d)
    {
        const double m = std::max(std::fabs((double)d.x), std::max(std::fabs((double)d.y), std::fabs((double)d.z)));
        int e;
        (void)std::frexp(m, &e); /* m = f 2^e, f in [0.5, 1) */
        return Vector_3(std::ldexp((double)d.x, 1 - e), std::ldexp((double)d.y, 1 - e), std::ldexp((double)d.z, 1 - e));
    }

    bool intersect(const ray_t *r, hit_t *hit) const override
    {
        tl_ray = r;
        const Point_3 org(r->org.x, r->org.y, r->org.z);
        const Vector_3 dir(r->dir.x, r->dir.y, r->dir.z);
        const Point_3 start = r->tnear > 0 ? org + (double)r->tnear * dir : org;
        auto res = tree.first_intersection(typename K::Ray_3(start, ray_vector(r->dir)));
        if (!res) return false;
        const double dd = dir.squared_length();
        auto param = [&](const Point_3 &p) { return ((p - org) * dir) / dd; };
        double t;
        if (const Point_3 *p = boost::get<Point_3>(&res->first))
            t = param(*p);
        else { /* a Segment_3: the ray lies in the triangle's plane */
            const typename K::Segment_3 &s = boost::get<typename K::Segment_3>(res->first);
            t = std::min(param(s.source()), param(s.target()));
        }
        float ft = std::max((float)t, r->tnear); /* rounding may put a hit at tnear just below it */
        if (!(ft < r->tfar)) return false;
        hit->t = ft;
        hit->u = hit->v = 0.0f;
        hit->prim = res->second;
        return true;
    }

    bool occluded(const ray_t *r) const override
    {
        tl_ray = r;
        const Point_3 org(r->org.x, r->org.y, r->org.z);
        const Vector_3 dir(r->dir.x, r->dir.y, r->dir.z);
        const Point_3 start = r->tnear > 0 ? org + (double)r->tnear * dir : org;
        if (std::isinf(r->tfar)) return tree.do_intersect(typename K::Ray_3(start, ray_vector(r->dir)));
        const Point_3 end = org + (double)r->tfar * dir;
        /* A segment shorter than double precision resolves (a tiny direction: the fuzzer's) is one point,
         * which CGAL's segment predicates refuse (a precondition failure ends the program): ask the
         * closest-hit query on the ray, which checks t against [tnear, tfar) itself. */
        if (start == end) {
            hit_t h;
            return intersect(r, &h);
        }
        return tree.do_intersect(typename K::Segment_3(start, end));
    }

    size_t size() const override { return tree.size(); }

    size_t memory() const override
    {
        size_t n = tree.size(), cap = 1;
        while (cap < n) cap *= 2; /* the primitive vector's capacity after n push_backs */
        return (n ? cap : 0) * sizeof(Prim<K>) + (n > 1 ? n - 1 : 0) * sizeof(CGAL::AABB_node<Traits<K>>) +
               side.tris.capacity() * sizeof(typename K::Triangle_3);
    }
};

struct cgal_accel {
    accel base; /* first: the harness sees a struct accel */
    Tree_base *tree;
};

const accel_param cgal_params[] = {
    PARAM_ROW_CHOICE("kernel", "simple", "simple|epick",
                     "CGAL kernel: simple (Simple_cartesian<double>), epick (Exact_predicates_inexact_constructions_kernel)"),
    PARAM_ROW_END,
};

accel *cgal_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    int kernel = params_choice(params, "kernel");
    cgal_accel *a = new (std::nothrow) cgal_accel();
    if (!a) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    a->base.scene = scene;
    try { /* no C++ exception may cross into C */
        if (kernel == 0)
            a->tree = new Tree<CGAL::Simple_cartesian<double>>(&scene->prims);
        else
            a->tree = new Tree<CGAL::Epick>(&scene->prims);
    } catch (const std::bad_alloc &) {
        snprintf(err, errlen, "out of memory building the AABB tree over %u primitives", scene->prims.count);
        delete a;
        return NULL;
    } catch (const std::exception &e) {
        snprintf(err, errlen, "CGAL: %s", e.what());
        delete a;
        return NULL;
    }
    return &a->base;
}

/* Queries allocate (first_intersection's heap); an exception there ends the
 * program (noexcept) rather than unwinding through C. */
bool cgal_intersect(accel *a, accel_ctx *, const ray_t *ray, hit_t *hit, counters_t *) noexcept
{
    return ((cgal_accel *)a)->tree->intersect(ray, hit);
}

bool cgal_occluded(accel *a, accel_ctx *, const ray_t *ray, counters_t *) noexcept
{
    return ((cgal_accel *)a)->tree->occluded(ray);
}

size_t cgal_memory(const accel *a) { return ((const cgal_accel *)a)->tree->memory(); }

const char *const cgal_variants[] = {"kernel=epick", NULL};

/* One primitive per leaf, n - 1 interior nodes; polygons are several ears. */
int cgal_stats(const accel *a, accel_stat *out, int max)
{
    const double n = (double)((const cgal_accel *)a)->tree->size(), prims = a->scene->prims.count;
    const accel_stat all[] = {{"nodes", n > 1 ? n - 1 : 0}, {"leaves", n}, {"avg_leaf_prims", 1.0},
                              {"refs_per_prim", prims > 0 ? n / prims : 0}};
    int k = 0;
    for (; k < max && k < (int)(sizeof all / sizeof all[0]); k++) out[k] = all[k];
    return k;
}

void cgal_destroy(accel *a)
{
    cgal_accel *c = (cgal_accel *)a;
    delete c->tree;
    delete c;
}

} // namespace

extern "C" const struct accel_ops accel_cgal_aabb = {
    /* .version = */ 2,
    /* .name = */ "cgal-aabb",
    /* .summary = */ "CGAL 5.5 AABB_tree: object-median BVH, one primitive per leaf, best-first first_intersection",
    /* .paper = */ "Alliez, Tayeb, Wormser, 3D Fast Intersection and Distance Computation (AABB Tree), CGAL User and "
                   "Reference Manual, AABB Tree package: Interface, Implementation Details",
    /* .params = */ cgal_params,
    /* .flags = */ ACCEL_NO_COUNTERS,
    /* .build = */ cgal_build,
    /* .context_new = */ NULL,
    /* .context_free = */ NULL,
    /* .intersect = */ cgal_intersect,
    /* .occluded = */ cgal_occluded,
    /* .memory = */ cgal_memory,
    /* .destroy = */ cgal_destroy,
    /* .stats = */ cgal_stats,
    /* .reset = */ NULL,
    /* .bounds = */ NULL,
    /* CGAL's work is not counted (OPAQUE): nothing to compile out */
    /* .intersect_fast = */ NULL,
    /* .occluded_fast = */ NULL,
    /* .variants = */ cgal_variants,
    /* .order_dependent = */ NULL,
    /* .settle_params = */ NULL,
    /* .check = */ NULL,
    /* .cost = */ {3, 2, 0},
    /* .stat_names = */ NULL,
    /* .tune = */ NULL,
};
