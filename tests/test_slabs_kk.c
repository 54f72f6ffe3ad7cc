/* test_slabs_kk: Kay and Kajiya's slab hierarchy `slabs-kk`
 * (accel/slabs_kk/slabs_kay_kajiya.c) and its plane-set volume test
 * (accel/slabs_kk/planeset.h), beyond the conformance suite.
 *
 *   parallel    rays parallel to slabs, +0 and -0 components, on an axis and
 *               on a diagonal: inside or outside by N . O alone, exactly
 *               (one float step outside is a miss, in the plane is a hit)
 *   random      random volumes and rays (zero components, lattice points,
 *               rays aimed at the volume) against a double-precision
 *               reference written the other way (explicit parallel
 *               branch): the test never misses a volume the reference
 *               meets, and accepts one it misses only within rounding
 *   cube        a rotated cube: its 7-normal volume contains it and is
 *               tighter than its AABB (a lattice count of the volumes),
 *               and its 3-normal volume is exactly its AABB
 *   tree        every tree (median, gs, sah; 3 and 7 normals; leaves of 1
 *               and 4): each node's volume holds its children's, each
 *               leaf's holds its primitives' extents, each primitive is in
 *               one leaf, the statistics and memory add up
 *   heap order  the heap walk expands nodes by nondecreasing key, never one
 *               beyond the closest hit, and a subset of what the
 *               depth-first walk expands (so never more steps) with the
 *               same answer as exhaustive; the depth-first walk does visit
 *               out of key order (the check can fail)
 *   refusals    bad parameter values name the parameter
 *   area        planeset_area (the cost model's volume areas) by hand: a
 *               box, a cube whose diagonal slabs do not bind, one with a
 *               corner cut off, a flat square (both sides), an empty
 *               volume, and the same cube far from the origin */
#include <string.h>
#include "accel/slabs_kk/slabs_kay_kajiya.h"
#include "testlib.h"

/* A small deterministic generator (the tests must not depend on libc's). */
static uint32_t rng = 4242;
static float urand(void) { return test_urand(&rng); }
static float srand1(void) { return 2.0f * urand() - 1.0f; }

static accel *kk_with(const scene_t *s, const char *cfg) { return test_build_or_die("slabs-kk", s, cfg); }

static void finish(scene_t *s) { test_finish_scene(s); }

static void tri(scene_t *s, vec3 a, vec3 b, vec3 c)
{
    uint32_t i = prims_add_vertex(&s->prims, a), j = prims_add_vertex(&s->prims, b), k = prims_add_vertex(&s->prims, c);
    prims_add_triangle(&s->prims, i, j, k);
}

static double ndot(uint32_t k, double x, double y, double z)
{
    const float *n = planeset_normals[k];
    return n[0] * x + n[1] * y + n[2] * z;
}

/* ------------------------------------------------------ the slab test */

/* Clip [t0, t1] by volume v over K normals. */
static bool clip(const planeset_slab *v, uint32_t K, vec3 o, vec3 d, float t0, float t1, float *a, float *z)
{
    planeset_ray r;
    if (!planeset_ray_init(&r, K, o, d)) return false;
    *a = t0, *z = t1;
    return K == 3 ? planeset_clip(&r, v, 3, a, z) : planeset_clip(&r, v, 7, a, z);
}

/* The exact volume of the points of a triangle's vertices (extents by
 * hand: the vertices are small lattice values, so every N . x is exact). */
static void volume_of(const vec3 *pts, int n, planeset_slab *v)
{
    for (uint32_t k = 0; k < PLANESET_MAX; k++) {
        v[k][0] = INFINITY, v[k][1] = -INFINITY;
        for (int i = 0; i < n; i++) {
            float e = (float)ndot(k, pts[i].x, pts[i].y, pts[i].z);
            v[k][0] = fminf(v[k][0], e), v[k][1] = fmaxf(v[k][1], e);
        }
    }
}

static void test_parallel(void)
{
    /* The unit cube: axes [0, 1], diagonals from its corners. */
    const vec3 corners[8] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    planeset_slab cube[PLANESET_MAX];
    volume_of(corners, 8, cube);
    CHECK(cube[3][0] == 0.0f && cube[3][1] == 3.0f && cube[4][0] == -1.0f && cube[4][1] == 2.0f);
    const float zeros[2] = {0.0f, -0.0f};
    for (uint32_t K = 3; K <= 7; K += 4)
        for (int s = 0; s < 2; s++) {
            float a, z;
            /* In the face y = 1, parallel to it: inside, hit over [0.5, 1.5]. */
            CHECK(clip(cube, K, v3(-0.5f, 1.0f, 0.5f), v3(1.0f, zeros[s], 0.0f), 0.0f, INFINITY, &a, &z));
            CHECK(a <= 0.5f && a > 0.5f - 1e-5f && z >= 1.5f && z < 1.5f + 1e-5f);
            /* One float step outside that face (either side): a miss, even with tfar = inf. */
            vec3 above = v3(0.5f, nextafterf(1.0f, 2.0f), 0.5f), below = v3(0.5f, nextafterf(0.0f, -1.0f), 0.5f);
            CHECK(!clip(cube, K, above, v3(1.0f, zeros[s], 0.0f), 0.0f, INFINITY, &a, &z));
            CHECK(!clip(cube, K, below, v3(1.0f, zeros[s], zeros[1 - s]), 0.0f, INFINITY, &a, &z));
            /* Along an edge of the box, two zero components. */
            CHECK(clip(cube, K, v3(-1.0f, 1.0f, 0.0f), v3(1.0f, zeros[s], zeros[1 - s]), 0.0f, INFINITY, &a, &z));
            CHECK(a <= 1.0f && a > 1.0f - 1e-5f && z >= 2.0f && z < 2.0f + 1e-5f);
            /* Parallel and inside: that slab limits nothing. */
            CHECK(clip(cube, K, v3(0.5f, 0.5f, -2.0f), v3(zeros[s], zeros[1 - s], 1.0f), 0.0f, INFINITY, &a, &z));
            CHECK(a <= 2.0f && a > 2.0f - 1e-5f && z >= 3.0f && z < 3.0f + 1e-5f);
        }

    /* A diagonal: the triangle (1,0,0) (0,1,0) (0,0,1) lies in x + y + z = 1,
     * so its (1,1,1) slab is [1, 1]. A ray along (1, -1, +-0) is parallel to
     * that slab (and to the (1,1,-1) one) and lies in the triangle's plane
     * from (0, 0.5, 0.5): a hit over [0, 0.5]. Moved off the plane by one
     * float step of N . O (z + 2^-23, N . O = 1 + 2^-23, both exact), only
     * the diagonal slab can reject it: a miss, and the 3-normal box (which
     * has no such slab) still hits. */
    const vec3 t3[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    planeset_slab flat[PLANESET_MAX];
    volume_of(t3, 3, flat);
    CHECK(flat[3][0] == 1.0f && flat[3][1] == 1.0f);
    for (int s = 0; s < 2; s++)
        for (int flip = 0; flip < 2; flip++) {
            vec3 d = flip ? v3(-1.0f, 1.0f, zeros[s]) : v3(1.0f, -1.0f, zeros[s]);
            vec3 o = flip ? v3(0.5f, 0.0f, 0.5f) : v3(0.0f, 0.5f, 0.5f);
            float a, z;
            CHECK(clip(flat, 7, o, d, 0.0f, INFINITY, &a, &z) && a == 0.0f && z >= 0.5f && z < 0.5f + 1e-5f);
            vec3 off = v3(o.x, o.y, o.z + 0x1p-23f);
            CHECK(!clip(flat, 7, off, d, 0.0f, INFINITY, &a, &z));
            CHECK(clip(flat, 3, off, d, 0.0f, INFINITY, &a, &z));
            vec3 below = v3(o.x, o.y, o.z - 0x1p-24f); /* N . O = 1 - 2^-24, a float: just below the plane */
            CHECK(!clip(flat, 7, below, d, 0.0f, INFINITY, &a, &z));
        }

    /* N . D = 1 + 1e-20 - 1 on (1,1,1): the double sum rounds to 0, so
     * its sign is unknown and that slab must limit nothing. The exact ray
     * starts in the plane x + y + z = 1 and leaves it at once: it meets the
     * flat volume at t = 0 only, and the test may not miss that. */
    planeset_ray nr;
    CHECK(planeset_ray_init(&nr, 7, v3(0.0f, 0.5f, 0.5f), v3(1.0f, 1e-20f, -1.0f)));
    CHECK(nr.s_near[3] == INFINITY && nr.s_far[3] == -INFINITY);
    float na = 0.0f, nz = INFINITY;
    CHECK(planeset_clip(&nr, flat, 7, &na, &nz) && na == 0.0f);

    /* Rays that cannot hit anything are refused; so is a normal count other than 3 or 7. */
    planeset_ray r;
    CHECK(!planeset_ray_init(&r, 7, v3(NAN, 0, 0), v3(1, 0, 0)));
    CHECK(!planeset_ray_init(&r, 7, v3(0, 0, 0), v3(0, INFINITY, 0)));
    CHECK(!planeset_ray_init(&r, 7, v3(0, 0, 0), v3(0.0f, -0.0f, 0.0f)));
    CHECK(!planeset_ray_init(&r, 5, v3(0, 0, 0), v3(1, 0, 0)));
    CHECK(planeset_ray_init(&r, 3, v3(0, 0, 0), v3(0.0f, -0.0f, 1e-30f)));
}

/* The reference: double precision, parallel slabs by an explicit branch. */
static bool ref_clip(const planeset_slab *v, uint32_t K, vec3 o, vec3 d, double *t0, double *t1)
{
    for (uint32_t k = 0; k < K; k++) {
        double no = ndot(k, o.x, o.y, o.z), nd = ndot(k, d.x, d.y, d.z);
        if (nd == 0.0) {
            if (no < v[k][0] || no > v[k][1]) return false;
            continue;
        }
        double ta = (v[k][0] - no) / nd, tb = (v[k][1] - no) / nd;
        if (ta > tb) {
            double s = ta;
            ta = tb, tb = s;
        }
        *t0 = fmax(*t0, ta);
        *t1 = fmin(*t1, tb);
    }
    return *t0 <= *t1;
}

/* Lattice values (so rays lie in planes and meet edges exactly) or random ones. */
static float lattice(void) { return (float)((int)(urand() * 9.0f) - 4) * 0.5f; }
static float comp(void)
{
    int k = (int)(urand() * 8.0f);
    return k == 0 ? 0.0f : k == 1 ? -0.0f : k == 2 ? lattice() : srand1();
}

static void test_random(void)
{
    int n = 200000, hits = 0, missed = 0, loose = 0, parallel = 0;
    for (int i = 0; i < n; i++) {
        uint32_t K = i % 2 ? 7 : 3;
        /* A volume: of 3 random points (a triangle), lattice or not. */
        vec3 pts[3];
        for (int j = 0; j < 3; j++)
            pts[j] = urand() < 0.5f ? v3(lattice(), lattice(), lattice()) : v3(2 * srand1(), 2 * srand1(), 2 * srand1());
        planeset_slab v[PLANESET_MAX];
        for (uint32_t k = 0; k < PLANESET_MAX; k++) {
            v[k][0] = INFINITY, v[k][1] = -INFINITY;
            for (int j = 0; j < 3; j++) {
                double e = ndot(k, pts[j].x, pts[j].y, pts[j].z);
                v[k][0] = fminf(v[k][0], (float)e), v[k][1] = fmaxf(v[k][1], (float)e);
                if ((double)v[k][0] > e) v[k][0] = nextafterf(v[k][0], -INFINITY); /* outward */
                if ((double)v[k][1] < e) v[k][1] = nextafterf(v[k][1], INFINITY);
            }
        }
        vec3 o = urand() < 0.5f ? v3(lattice(), lattice(), lattice()) : v3(3 * srand1(), 3 * srand1(), 3 * srand1());
        vec3 d = v3(comp(), comp(), comp());
        if (urand() < 0.5f) { /* aimed at a point of the triangle, some components zeroed */
            float u = urand(), w = urand() * (1.0f - u);
            vec3 t = v3_add(pts[0], v3_add(v3_scale(v3_sub(pts[1], pts[0]), u), v3_scale(v3_sub(pts[2], pts[0]), w)));
            d = v3_sub(t, o);
            if (urand() < 0.25f) d.x = urand() < 0.5f ? 0.0f : -0.0f;
            if (urand() < 0.25f) d.y = -d.x; /* parallel to a diagonal when d.z is 0 */
        }
        planeset_ray r;
        if (!planeset_ray_init(&r, K, o, d)) continue;
        for (uint32_t k = 0; k < K; k++) parallel += isinf(r.inv_near[k]);
        double rt0 = 0.0, rt1 = INFINITY;
        bool want = ref_clip(v, K, o, d, &rt0, &rt1);
        float a = 0.0f, z = INFINITY;
        bool got = K == 3 ? planeset_clip(&r, v, 3, &a, &z) : planeset_clip(&r, v, 7, &a, &z);
        hits += want;
        if (want && !got) missed++;
        if (want && got && (a > rt0 || z < rt1)) missed++; /* the interval must contain the reference's */
        /* A false hit only within the rounding band (an interval of a few ulps, or just empty). */
        if (got && !want && !(rt0 - rt1 <= 1e-5 * fmax(1.0, fabs(rt0)))) loose++;
    }
    printf("random volumes: %d hits of %d, %d parallel slabs; missed %d, loose %d\n", hits, n, parallel, missed, loose);
    CHECK(hits > n / 5);
    CHECK(parallel > n / 10);
    CHECK(missed == 0);
    CHECK(loose == 0);
}

/* ------------------------------------------------------- rotated cube */

static vec3 rotate(vec3 p, const double R[3][3])
{
    return v3((float)(R[0][0] * p.x + R[0][1] * p.y + R[0][2] * p.z),
              (float)(R[1][0] * p.x + R[1][1] * p.y + R[1][2] * p.z),
              (float)(R[2][0] * p.x + R[2][1] * p.y + R[2][2] * p.z));
}

static void test_rotated_cube(void)
{
    /* The cube [-1,1]^3 turned 35 degrees about x, then 40 about z. */
    double a = 35.0 * M_PI / 180.0, b = 40.0 * M_PI / 180.0;
    double Rx[3][3] = {{1, 0, 0}, {0, cos(a), -sin(a)}, {0, sin(a), cos(a)}};
    double Rz[3][3] = {{cos(b), -sin(b), 0}, {sin(b), cos(b), 0}, {0, 0, 1}}, R[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) R[i][j] = Rz[i][0] * Rx[0][j] + Rz[i][1] * Rx[1][j] + Rz[i][2] * Rx[2][j];
    scene_t *s = scene_new("rotated-cube");
    vec3 c[8];
    for (int i = 0; i < 8; i++) c[i] = rotate(v3(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1), R);
    const int faces[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (int f = 0; f < 6; f++) {
        tri(s, c[faces[f][0]], c[faces[f][1]], c[faces[f][2]]);
        tri(s, c[faces[f][0]], c[faces[f][2]], c[faces[f][3]]);
    }
    finish(s);

    /* One leaf of all 12 triangles: the root's volume is the cube's. */
    accel *a7 = kk_with(s, "maxleaf=16"), *a3 = kk_with(s, "maxleaf=16,normals=3");
    planeset_slab v7[PLANESET_MAX], v3s[PLANESET_MAX];
    uint32_t index, count;
    const uint32_t *refs;
    CHECK(slabs_kk_debug_node(a7, 0, v7, &index, &count, &refs) == 7 && count == 12);
    CHECK(slabs_kk_debug_node(a3, 0, v3s, &index, &count, &refs) == 3 && count == 12);
    /* 3 normals: exactly the AABB of the vertices, and the same as the first three of 7. */
    box3 bb = box_empty();
    for (int i = 0; i < 8; i++) bb = box_grow(bb, c[i]);
    CHECK(v3s[0][0] == bb.lo.x && v3s[0][1] == bb.hi.x && v3s[1][0] == bb.lo.y && v3s[1][1] == bb.hi.y &&
          v3s[2][0] == bb.lo.z && v3s[2][1] == bb.hi.z);
    CHECK(memcmp(v3s, v7, 3 * sizeof v3s[0]) == 0);
    box3 got = accel_bounds(a7);
    CHECK(memcmp(&got, &bb, sizeof bb) == 0);

    /* Lattice count over the AABB: points in the cube, in the 7-normal volume. */
    const int L = 64;
    long in_cube = 0, in_vol = 0, cube_not_vol = 0, total = 0;
    for (int i = 0; i < L; i++)
        for (int j = 0; j < L; j++)
            for (int k = 0; k < L; k++) {
                double x = bb.lo.x + (bb.hi.x - bb.lo.x) * (i + 0.5) / L;
                double y = bb.lo.y + (bb.hi.y - bb.lo.y) * (j + 0.5) / L;
                double z = bb.lo.z + (bb.hi.z - bb.lo.z) * (k + 0.5) / L;
                /* In the cube: R^T p within [-1, 1]^3 (a small margin inward for the float vertices). */
                bool cube = true;
                for (int r = 0; r < 3; r++) cube = cube && fabs(R[0][r] * x + R[1][r] * y + R[2][r] * z) <= 1.0 - 1e-6;
                bool vol = true;
                for (uint32_t n = 0; n < 7; n++) {
                    double e = ndot(n, x, y, z);
                    vol = vol && e >= v7[n][0] && e <= v7[n][1];
                }
                total++;
                in_cube += cube, in_vol += vol, cube_not_vol += cube && !vol;
            }
    double fc = (double)in_cube / total, fv = (double)in_vol / total;
    printf("rotated cube: of its AABB, the cube fills %.3f, the 7-normal volume %.3f (the AABB 1)\n", fc, fv);
    CHECK(cube_not_vol == 0);       /* the volume holds the cube */
    CHECK(fc > 0.2 && fc < 0.6);    /* the rotation makes the AABB loose: the test means something */
    CHECK(fv < 0.85);               /* the diagonals cut the AABB's corners */
    CHECK(fv > fc);                 /* and, being 14 planes, cannot be the cube */
    a7->ops->destroy(a7);
    a3->ops->destroy(a3);
    scene_free(s);
}

/* ------------------------------------------------------------- trees */

static scene_t *soup(void)
{
    scene_t *s = scene_new("kk-soup");
    rng = 777;
    for (int i = 0; i < 400; i++) {
        vec3 c = v3(4 * srand1(), 4 * srand1(), 4 * srand1());
        vec3 p[3];
        for (int j = 0; j < 3; j++) p[j] = v3_add(c, v3(0.3f * srand1(), 0.3f * srand1(), 0.3f * srand1()));
        tri(s, p[0], p[1], p[2]);
        if (i % 7 == 0) prims_add_sphere(&s->prims, c, 0.05f + 0.2f * urand());
        if (i % 11 == 0) prims_add_cone(&s->prims, c, 0.1f, v3_add(c, v3(0.2f, 0.5f, -0.1f)), 0.02f);
    }
    finish(s);
    return s;
}

static bool holds(const planeset_slab *outer, const planeset_slab *inner, uint32_t K)
{
    for (uint32_t k = 0; k < K; k++)
        if (!(outer[k][0] <= inner[k][0] && outer[k][1] >= inner[k][1])) return false;
    return true;
}

static void check_tree(const scene_t *s, const char *cfg, uint32_t expect_normals)
{
    accel *a = kk_with(s, cfg);
    const prims_t *p = &s->prims;
    accel_stat st[ACCEL_STATS_MAX];
    int ns = accel_stats(a, st, ACCEL_STATS_MAX);
    double nodes = -1, leaves = -1;
    for (int i = 0; i < ns; i++) {
        if (!strcmp(st[i].name, "nodes")) nodes = st[i].value;
        if (!strcmp(st[i].name, "leaves")) leaves = st[i].value;
    }
    uint32_t nn = (uint32_t)(nodes + leaves);
    uint8_t *seen = calloc(p->count, 1);
    uint32_t bad_child = 0, bad_leaf = 0, twice = 0, nleaves = 0, refs_total = 0, K = 0;
    for (uint32_t i = 0; i < nn; i++) {
        planeset_slab v[PLANESET_MAX], w[PLANESET_MAX];
        uint32_t index, count, ci, cc;
        const uint32_t *refs;
        K = slabs_kk_debug_node(a, i, v, &index, &count, &refs);
        if (!count) {
            for (uint32_t c = 0; c < 2; c++) {
                /* Children come after their parents, in the same layout. */
                CHECK(index + c > i && slabs_kk_debug_node(a, index + c, w, &ci, &cc, &refs) == K);
                bad_child += !holds(v, w, K);
            }
            continue;
        }
        nleaves++;
        refs_total += count;
        for (uint32_t j = 0; j < count; j++) {
            uint32_t id = refs[index + j];
            twice += seen[id]++ != 0;
            planeset_slab e[PLANESET_MAX];
            for (uint32_t k = 0; k < K; k++) {
                const float *n = planeset_normals[k];
                prim_extent(p, id, v3(n[0], n[1], n[2]), &e[k][0], &e[k][1]);
            }
            bad_leaf += !holds(v, e, K);
        }
    }
    planeset_slab v[PLANESET_MAX];
    uint32_t index, count;
    const uint32_t *refs;
    CHECK(slabs_kk_debug_node(a, nn, v, &index, &count, &refs) == 0); /* nn is past the last node */
    CHECK_MSG(K == expect_normals && bad_child == 0 && bad_leaf == 0 && twice == 0 && refs_total == p->count,
              "[%s] on %s: %u normals, %u children outside, %u primitives outside, %u twice, %u refs of %u", cfg,
              s->name, K, bad_child, bad_leaf, twice, refs_total, p->count);
    CHECK(nleaves == (uint32_t)leaves && nodes == leaves - 1);
    size_t node_size = K == 3 ? 32 : 64;
    CHECK(a->ops->memory(a) >= nn * node_size + p->count * sizeof(uint32_t));
    CHECK(a->ops->memory(a) < nn * node_size + p->count * sizeof(uint32_t) + 4096);
    free(seen);
    a->ops->destroy(a);
}

static void test_trees(void)
{
    scene_t *s = soup();
    const char *cfgs[] = {"", "normals=3", "tree=gs", "tree=sah", "tree=sah,normals=3,maxleaf=4", "maxleaf=4"};
    for (size_t i = 0; i < sizeof cfgs / sizeof cfgs[0]; i++)
        check_tree(s, cfgs[i], strstr(cfgs[i], "normals=3") ? 3 : 7);
    scene_t *balls = test_scene("spd:balls:1"), *tree = test_scene("spd:tree:2");
    check_tree(balls, "tree=gs", 7);
    check_tree(tree, "", 7);
    /* One primitive per leaf by default: n leaves, n - 1 interior nodes. */
    accel *a = kk_with(s, "");
    accel_stat st[ACCEL_STATS_MAX];
    int ns = accel_stats(a, st, ACCEL_STATS_MAX);
    for (int i = 0; i < ns; i++)
        if (!strcmp(st[i].name, "leaves")) CHECK(st[i].value == s->prims.count);
    a->ops->destroy(a);
    scene_free(balls);
    scene_free(tree);
    scene_free(s);
}

/* -------------------------------------------------------- heap order */

static void test_heap_order(void)
{
    scene_t *s = soup();
    accel *ex = test_build("exhaustive", s, 1);
    enum { CAP = 1 << 14 };
    static uint32_t hn[CAP], dn[CAP];
    static float hk[CAP], dk[CAP];
    static uint8_t mark[1 << 12];
    const char *trees[] = {"", "tree=gs", "tree=sah,normals=3", "maxleaf=4"};
    for (size_t ti = 0; ti < sizeof trees / sizeof trees[0]; ti++) {
        char hcfg[128], dcfg[128];
        snprintf(hcfg, sizeof hcfg, "%s%straverse=heap", trees[ti], *trees[ti] ? "," : "");
        snprintf(dcfg, sizeof dcfg, "%s%straverse=dfs", trees[ti], *trees[ti] ? "," : "");
        accel *h = kk_with(s, hcfg), *d = kk_with(s, dcfg);
        accel_ctx *hctx = h->ops->context_new(h), *ectx = NULL;
        uint32_t rays = 0, hits = 0, unordered = 0, beyond = 0, not_subset = 0, more_steps = 0, wrong = 0;
        uint32_t dfs_unordered = 0, heap_steps = 0, dfs_steps = 0;
        rng = 99 + (uint32_t)ti;
        for (int i = 0; i < 3000; i++) {
            /* From anywhere around the soup toward a point near one of its primitives. */
            vec3 o = v3(8 * srand1(), 8 * srand1(), 8 * srand1());
            box3 aim = prim_bounds(&s->prims, (uint32_t)(urand() * s->prims.count) % s->prims.count);
            vec3 t = v3_add(box_center(aim), v3(0.2f * srand1(), 0.2f * srand1(), 0.2f * srand1()));
            ray_t ray = {o, 0.0f, v3_sub(t, o), INFINITY, RAY_NO_LIGHT, 0};
            if (i % 5 == 0) ray.dir.y = i % 10 ? 0.0f : -0.0f; /* parallel to the y slabs */
            hit_t hh, dh, want = hit_none(&ray);
            uint32_t nh = slabs_kk_debug_visits(h, &ray, false, hn, hk, CAP, &hh);
            uint32_t nd = slabs_kk_debug_visits(d, &ray, false, dn, dk, CAP, &dh);
            CHECK(nh <= CAP && nd <= CAP);
            ex->ops->intersect(ex, ectx, &ray, &want, &(counters_t){0});
            rays++;
            hits += want.prim != HIT_NONE;
            wrong += hh.prim != want.prim || memcmp(&hh.t, &want.t, sizeof hh.t) != 0;
            wrong += dh.prim != want.prim || memcmp(&dh.t, &want.t, sizeof dh.t) != 0;
            for (uint32_t k = 1; k < nh; k++) unordered += hk[k] < hk[k - 1];
            for (uint32_t k = 1; k < nd; k++) dfs_unordered += dk[k] < dk[k - 1];
            /* Figure 9's stop: nothing expanded lies beyond the closest hit
             * (its leaf's key is at most the hit, and keys never decrease). */
            for (uint32_t k = 0; k < nh; k++) beyond += want.prim != HIT_NONE && hk[k] > want.t;
            /* Depth-first must expand every node the heap expands: each has
             * a key <= the hit and a parent both expand. */
            for (uint32_t k = 0; k < nd; k++) mark[dn[k]] = 1;
            for (uint32_t k = 0; k < nh; k++) not_subset += !mark[hn[k]];
            for (uint32_t k = 0; k < nd; k++) mark[dn[k]] = 0;
            more_steps += nh > nd;
            heap_steps += nh, dfs_steps += nd;
            /* The counting walk counts those steps. */
            counters_t c = {0};
            hit_t ch = hit_none(&ray);
            h->ops->intersect(h, hctx, &ray, &ch, &c);
            CHECK(c.steps == nh && ch.prim == hh.prim);
        }
        printf("heap order [%s]: %u rays, %u hits; steps heap %u dfs %u; heap out of order %u, beyond the hit %u, "
               "not in dfs %u, wrong %u; dfs out of order %u\n",
               trees[ti], rays, hits, heap_steps, dfs_steps, unordered, beyond, not_subset, wrong, dfs_unordered);
        CHECK(hits > rays / 4 && hits < rays);
        CHECK(unordered == 0);
        CHECK(beyond == 0);
        CHECK(not_subset == 0 && more_steps == 0);
        CHECK(wrong == 0);
        CHECK(dfs_unordered > 0);    /* the order check can fail: depth-first is not sorted */
        CHECK(heap_steps < dfs_steps); /* and the sort saves steps */
        h->ops->context_free(hctx);
        h->ops->destroy(h);
        d->ops->destroy(d);
    }
    ex->ops->destroy(ex);
    scene_free(s);
}

/* ---------------------------------------------------------- refusals */

static void test_refusals(void)
{
    scene_t *s = soup();
    const char *bad[][2] = {{"normals=5", "normals"}, {"tree=kd", "tree"}, {"traverse=bfs", "traverse"},
                            {"maxleaf=0", "maxleaf"}, {"maxleaf=17", "maxleaf"}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) test_expect_refusal("slabs-kk", s, bad[i][0], bad[i][1]);
    /* The memory cap: 7381 spheres need some 2.5 MiB with 7 normals. */
    scene_t *big = test_scene("spd:balls:4");
    char err[512] = "";
    accel *a = test_build_with(accel_find("slabs-kk"), big, "memcap=1", 1, err, sizeof err);
    CHECK_MSG(!a && strstr(err, "memcap=1"), "memcap=1: %s", a ? "accepted" : err);
    if (a) a->ops->destroy(a);
    a = test_build_with(accel_find("slabs-kk"), big, "memcap=16", 1, err, sizeof err);
    CHECK_MSG(a != NULL, "memcap=16: %s", err);
    if (a) a->ops->destroy(a);
    scene_free(big);
    scene_free(s);
}

/* The 7-normal volume of box [lo, lo + 1]^3 moved by off, its diagonal
 * slabs exactly the cube's ranges (so not binding). */
static void cube_volume(planeset_slab v[7], double off)
{
    for (int k = 0; k < 7; k++) {
        double lo = 0, hi = 0;
        for (int c = 0; c < 3; c++) {
            double n = planeset_normals[k][c];
            lo += n < 0 ? n * (off + 1) : n * off;
            hi += n < 0 ? n * off : n * (off + 1);
        }
        v[k][0] = (float)lo, v[k][1] = (float)hi;
    }
}

static void test_area(void)
{
    planeset_slab v[7];
    cube_volume(v, 0.0);
    CHECK(fabs(planeset_area(v, 3) - 6.0) < 1e-12);
    CHECK(fabs(planeset_area(v, 7) - 6.0) < 1e-9);
    /* N = (1,1,1) cut at 2.5: a corner tetrahedron of legs 0.5 goes, three
     * right triangles of area 1/8 off the faces, an equilateral triangle
     * of side sqrt(0.5) on: 6 - 3/8 + sqrt(3)/8. */
    v[3][1] = 2.5f;
    const double cut = 6.0 - 0.375 + sqrt(3.0) / 8.0;
    printf("area: corner cut %.9f, by hand %.9f\n", planeset_area(v, 7), cut);
    CHECK(fabs(planeset_area(v, 7) - cut) < 1e-9);
    /* A flat unit square (z = 0): both sides. */
    cube_volume(v, 0.0);
    v[2][1] = 0.0f;
    for (int k = 3; k < 7; k++) { /* the diagonals' ranges over the square */
        double lo = 0, hi = 0;
        for (int c = 0; c < 2; c++) {
            double n = planeset_normals[k][c];
            lo += n < 0 ? n : 0, hi += n < 0 ? 0 : n;
        }
        v[k][0] = (float)lo, v[k][1] = (float)hi;
    }
    CHECK(fabs(planeset_area(v, 7) - 2.0) < 1e-9);
    CHECK(fabs(planeset_area(v, 3) - 2.0) < 1e-12);
    v[0][0] = 2.0f; /* lo > hi: empty */
    CHECK(planeset_area(v, 7) == 0.0 && planeset_area(v, 3) == 0.0);
    cube_volume(v, 10000.0);
    CHECK(fabs(planeset_area(v, 7) - 6.0) < 1e-6);
}

int main(void)
{
    test_parallel();
    test_random();
    test_rotated_cube();
    test_trees();
    test_heap_order();
    test_refusals();
    test_area();
    return check_report();
}
