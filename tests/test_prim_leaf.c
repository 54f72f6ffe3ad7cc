/* test_prim_leaf: prims/'s batched leaf tests and counting-free tests
 * (prims/intersect.c). On random triangles, spheres, cones and polygons
 * and random rays: prim_intersect_fast and prim_occluded_fast give the
 * counting tests' answers bit for bit; prim_intersect_leaf keeps the same
 * nearest hit as a loop of prim_intersect and counts one test per
 * primitive and one hit per closer hit; prim_occluded_leaf stops at the
 * first occluder and counts the tests up to it; the _fast leaf forms
 * answer the same; an empty leaf tests nothing. Triangle packets
 * (prim_tri_pack, prim_intersect_tris, prim_occluded_tris and their _fast
 * forms) give prim_intersect_leaf's and prim_occluded_leaf's hits (t, u, v,
 * prim) bit for bit and their counters, on random triangle leaves with
 * degenerate and repeated triangles, random and axis-aligned (+-0) rays
 * and rays through corners and edge midpoints (the double fallback). */
#include <string.h>
#include "check.h"
#define PRIMS_TEST_SEED 0x1eaf
#include "prims_testlib.h"

static bool same_hit(hit_t a, hit_t b) { return memcmp(&a, &b, sizeof a) == 0; }

int main(void)
{
    prims_t p;
    prims_init(&p);
    rnd_soup(&p, 200, 5.0f);
    uint32_t vd = prims_add_vertex(&p, v3(0, 0, 0));
    prims_add_triangle(&p, vd, vd, vd); /* degenerate: never hits, still counted */
    char err[256];
    CHECK_MSG(prims_finish(&p, err, sizeof err) == 0, "%s", err);

    int single_bad = 0, leaf_bad = 0, count_bad = 0, occ_bad = 0, hits = 0;
    uint32_t ids[64];
    _Static_assert(64 >= 41, "ids holds a packet leaf");
    for (int r = 0; r < 4000; r++) {
        ray_t ray = ray_through(rnd_v3(-8.0f, 8.0f), rnd_v3(-4.0f, 4.0f));
        if (r % 3 == 0) ray.tfar = rnd(0.5f, 2.0f);
        /* Single tests: counting and fast agree bit for bit. */
        for (uint32_t id = 0; id < p.count; id += 7) {
            hit_t a = hit_none(&ray), b = hit_none(&ray);
            counters_t c = {0};
            bool ra = prim_intersect(&p, id, &ray, &a, &c), rb = prim_intersect_fast(&p, id, &ray, &b);
            single_bad += ra != rb || !same_hit(a, b) || c.prim_tests != 1 || c.prim_hits != (uint64_t)ra;
            counters_t d = {0};
            single_bad += prim_occluded(&p, id, &ray, &d) != prim_occluded_fast(&p, id, &ray) || d.prim_tests != 1;
        }
        /* A random leaf. */
        uint32_t n = (uint32_t)(rng_next() % 64);
        for (uint32_t k = 0; k < n; k++) ids[k] = (uint32_t)(rng_next() % p.count);
        hit_t want = hit_none(&ray), got = hit_none(&ray), fast = hit_none(&ray);
        counters_t cw = {0}, cg = {0};
        bool any = false;
        for (uint32_t k = 0; k < n; k++) any |= prim_intersect(&p, ids[k], &ray, &want, &cw);
        bool rg = prim_intersect_leaf(&p, ids, n, &ray, &got, &cg), rf = prim_intersect_leaf_fast(&p, ids, n, &ray, &fast);
        leaf_bad += rg != any || rf != any || !same_hit(got, want) || !same_hit(fast, want);
        count_bad += cg.prim_tests != n || cg.prim_tests != cw.prim_tests || cg.prim_hits != cw.prim_hits;
        hits += any;
        /* Occlusion: the first occluder ends the leaf. */
        uint32_t first = n;
        for (uint32_t k = 0; k < n && first == n; k++)
            if (prim_occluded_fast(&p, ids[k], &ray)) first = k;
        counters_t co = {0};
        bool ro = prim_occluded_leaf(&p, ids, n, &ray, &co);
        occ_bad += ro != (first < n) || prim_occluded_leaf_fast(&p, ids, n, &ray) != ro ||
                   co.prim_tests != (first < n ? first + 1 : n) || co.prim_hits != (uint64_t)ro;
    }
    printf("leaves with a hit: %d of 4000\n", hits);
    CHECK(hits > 400);
    CHECK_MSG(single_bad == 0, "%d single tests differ", single_bad);
    CHECK_MSG(leaf_bad == 0, "%d leaves differ", leaf_bad);
    CHECK_MSG(count_bad == 0, "%d leaves counted wrong", count_bad);
    CHECK_MSG(occ_bad == 0, "%d occlusion leaves differ", occ_bad);
    /* Triangle packets against the scalar leaf tests. */
    uint32_t tri_ids[1024], ntri = 0;
    for (uint32_t id = 0; id < p.count && ntri < 1024; id++)
        if (p.kind[id] == PRIM_TRIANGLE) tri_ids[ntri++] = id;
    CHECK(prim_all_triangles(&p, tri_ids, ntri) && !prim_all_triangles(&p, (uint32_t[]){1, 2, 3, 4}, 4));
    int pk_bad = 0, pk_count_bad = 0, pk_hits = 0;
    prim_tri_packet pk[16];
    for (int r = 0; r < 20000; r++) {
        ray_t ray = ray_through(rnd_v3(-8.0f, 8.0f), rnd_v3(-4.0f, 4.0f));
        if (r % 3 == 0) ray.tfar = rnd(0.5f, 2.0f);
        if (r % 5 == 1) ray.tnear = rnd(0.0f, 1.0f);
        if (r % 7 == 2) { /* axis-aligned, the other components +0 or -0 */
            int ax = r % 3;
            float d[3] = {(r & 8) ? -0.0f : 0.0f, (r & 16) ? -0.0f : 0.0f, (r & 32) ? -0.0f : 0.0f};
            d[ax] = (r & 64) ? -1.0f : 1.0f;
            ray.dir = v3(d[0], d[1], d[2]);
            ray.tfar = INFINITY;
        }
        uint32_t n = (uint32_t)(rng_next() % 41); /* up to 11 packets */
        for (uint32_t k = 0; k < n; k++) ids[k] = tri_ids[rng_next() % ntri];
        if (n && r % 4 == 0) ids[rng_next() % n] = tri_ids[ntri - 1]; /* the degenerate one */
        if (n && r % 11 == 3) { /* through a corner or an edge's midpoint: edge functions exactly 0, the double fallback */
            const tri_t *tr = &p.tris[p.index[ids[rng_next() % n]]];
            vec3 a = p.verts[tr->v[0]], b = p.verts[tr->v[1]];
            vec3 target = (r & 1) ? a : v3_scale(v3_add(a, b), 0.5f);
            ray = ray_through(rnd_v3(-8.0f, 8.0f), target);
        }
        prim_tri_pack(&p, ids, n, pk);
        uint32_t npk = prim_tri_packets(n);
        hit_t want = hit_none(&ray), got = hit_none(&ray), fast = hit_none(&ray);
        counters_t cw = {0}, cg = {0}, ow = {0}, og = {0};
        bool rw = prim_intersect_leaf(&p, ids, n, &ray, &want, &cw);
        bool rg = prim_intersect_tris(pk, npk, &ray, &got, &cg), rf = prim_intersect_tris_fast(pk, npk, &ray, &fast);
        pk_bad += rw != rg || rw != rf || !same_hit(want, got) || !same_hit(want, fast);
        pk_count_bad += memcmp(&cw, &cg, sizeof cw) != 0;
        bool ow_r = prim_occluded_leaf(&p, ids, n, &ray, &ow), og_r = prim_occluded_tris(pk, npk, &ray, &og);
        pk_bad += ow_r != og_r || prim_occluded_tris_fast(pk, npk, &ray) != og_r;
        pk_count_bad += memcmp(&ow, &og, sizeof ow) != 0;
        pk_hits += rw;
    }
    printf("triangle packets: %d of 20000 leaves hit\n", pk_hits);
    CHECK(pk_hits > 500);
    CHECK_MSG(pk_bad == 0, "%d packet answers differ from the scalar leaf tests", pk_bad);
    CHECK_MSG(pk_count_bad == 0, "%d packet counters differ from the scalar leaf tests", pk_count_bad);
    /* The empty leaf. */
    ray_t ray = ray_through(v3(0, 0, -10), v3(0, 0, 0));
    hit_t h = hit_none(&ray);
    counters_t c = {0};
    CHECK(!prim_intersect_leaf(&p, ids, 0, &ray, &h, &c) && !prim_occluded_leaf(&p, ids, 0, &ray, &c));
    CHECK(c.prim_tests == 0 && h.prim == HIT_NONE);
    /* The degenerate triangle counts a test and never hits. */
    uint32_t last = p.count - 1;
    ray_t at = ray_through(v3(0, 0, -1), v3(0, 0, 0));
    h = hit_none(&at);
    CHECK(!prim_intersect_leaf(&p, &last, 1, &at, &h, &c) && c.prim_tests == 1);
    prims_free(&p);
    return check_report();
}
