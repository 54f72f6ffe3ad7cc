/* octree_glassner.c: Glassner's octree with named, hashed nodes and
 * sequential traversal (`octree`). Reference: docs/accels/octree.md.
 *
 * Papers:
 *   A. S. Glassner, "Space Subdivision for Fast Ray Tracing", IEEE CG&A
 *     4(10), 1984, as the Arvo-Kirk survey (1989) describes it in s5.1 and
 *     figures 10, 11, 13, 17: candidate lists, names (root 1, child = 10 x
 *     parent + digit 1..8) in a hash table keyed by name mod size, point
 *     location by names, the next voxel from a point moved minlen/2 past
 *     each exit face.
 *   A. Fujimoto, T. Tanaka, K. Iwata, "ARTS", IEEE CG&A 6(4), 1986 (survey
 *     s5.2): 3DDDA among siblings with vertical steps (walk=fujimoto).
 *   Survey s5.3: mailboxes; a walk may end only on a hit in its voxel.
 *   V. Havran, RTN 12(2), 1999: the defaults are his OCTREE84-C.
 *   J. D. MacDonald, K. S. Booth, The Visual Computer 6(3), 1990, s3: the
 *     cost estimate of term=cost, used to STOP only (the planes stay at the
 *     centres; Octree-R's cost-placed planes are not implemented).
 *
 * Names are exact 128-bit integers (depth 20 needs 68 bits), stored in the
 * table as 64 + 32 bits; the bucket is carried down a path as
 * (10 h + digit) mod size (hash_mod_extend). Nothing is truncated.
 *
 * Memory (memory() counts it): the hash_mod_table (start[size + 1] and a
 * 16-byte entry per stored name; value OCT_INTERIOR or a leaf index),
 * oct_leaf[nleaves] (8 bytes: first, count) and ids (uint32, each list
 * ascending). Empty voxels are not stored. Interior nodes have no box:
 * boxes are recomputed from the root by the same float midpoints in the
 * build and both walks, so all see bit-identical planes. Per thread: the
 * mailbox (4 bytes a primitive); paths live on the C stack (<= 21 levels).
 *
 * Invariants:
 *   - a voxel's candidates touch its box grown by pad (the grid's slack),
 *     so a primitive in or near a plane is a candidate on both sides;
 *   - no child edge is shorter than 2^-20 of the root's largest coordinate,
 *     so minlen/2 always moves a point out of its voxel;
 *   - candidates are tested over [tnear, tHit); a closest-hit walk ends in
 *     the first voxel whose exit t >= tHit;
 *   - every step strictly increases the exit t (glassner: checked, with a
 *     relocation by ray parameter and then an all-primitive fallback;
 *     fujimoto: one plane forward per step, capped), so no voxel is
 *     entered twice and every walk ends.
 *
 * Counters: box_tests = root clip + nodes looked up in point locations;
 * steps = voxels entered; empty_leaves; mailbox_hits. intersect_fast /
 * occluded_fast are the same walks without them. Building is
 * single-threaded. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../accel.h"
#include "../common/coincident.h"
#include "../common/line_model.h"
#include "hash_mod.h"
#include "../common/mailbox.h"
#include "../common/memcap.h"
#include "../common/prim_hit.h"
#include "../common/slab.h"
#include "octree_glassner.h"

#define OCT_INTERIOR UINT32_MAX /* table value of an interior node */
#define OCT_EMPTY UINT32_MAX    /* leaf index of an empty voxel */
#define OCT_EDGE_FLOOR (1.0f / 1048576.0f) /* 2^-20 of the root box's largest |coordinate| */

typedef unsigned __int128 oct_name;

/* A stored leaf: its candidates are ids[first .. first + count). */
typedef struct {
    uint32_t first, count;
} oct_leaf;
static_assert(sizeof(oct_leaf) == 8, "oct_leaf is 8 bytes");

enum { TERM_CONST = 0, TERM_COST = 1 };
enum { WALK_GLASSNER = 0, WALK_FUJIMOTO = 1 };

typedef struct {
    accel base;
    const prims_t *p;
    box3 root;        /* the box the root subdivides */
    float pad;        /* insertion slack: voxel boxes grow by it */
    float minlen;     /* shortest voxel edge in the tree */
    float half;       /* minlen / 2: Glassner's step beyond a face */
    int walk, maxdepth;
    bool mailbox;
    hash_mod_table table;
    uint32_t root_home; /* 1 mod table size */
    oct_leaf *leaves;
    uint32_t nleaves, ninterior, nempty;
    uint32_t *ids;
    size_t nrefs;
    int depth;          /* deepest node */
    uint64_t step_cap;  /* a walk longer than this falls back */
    double probes_avg, probes_miss_avg;
    uint32_t probes_max;
} octree_t;

struct accel_ctx {
    mailbox_t mb; /* mailbox=on; else mb.stamp is NULL */
    uint64_t relocated, exhaustive;
};

static inline uint64_t name_lo(oct_name n) { return (uint64_t)n; }
static inline uint32_t name_hi(oct_name n) { return (uint32_t)(n >> 64); }
static inline box3 box_pad(box3 b, float e)
{
    b.lo = v3_sub(b.lo, v3(e, e, e));
    b.hi = v3_add(b.hi, v3(e, e, e));
    return b;
}

/* The mid plane of [lo, hi]: the ONE formula of the build and both walks,
 * so every voxel plane is the same float everywhere. */
static inline float midplane(float lo, float hi) { return 0.5f * (lo + hi); }

/* The octant (x + 2y + 4z, each bit set for the high half) of box b. */
static inline box3 child_box(box3 b, unsigned oct)
{
    box3 c;
    float mx = midplane(b.lo.x, b.hi.x), my = midplane(b.lo.y, b.hi.y), mz = midplane(b.lo.z, b.hi.z);
    c.lo.x = oct & 1 ? mx : b.lo.x, c.hi.x = oct & 1 ? b.hi.x : mx;
    c.lo.y = oct & 2 ? my : b.lo.y, c.hi.y = oct & 2 ? b.hi.y : my;
    c.lo.z = oct & 4 ? mz : b.lo.z, c.hi.z = oct & 4 ? b.hi.z : mz;
    return c;
}

static inline float min_edge(box3 b)
{
    vec3 e = box_extent(b);
    return f_min_keep(e.x, f_min_keep(e.y, e.z));
}

/* ---------------------------------------------------------------- build */

typedef struct {
    octree_t *o;
    int maxprims, term;
    bool glassner;
    double ci, ct;
    float floor_edge; /* children with a shorter edge are not made */
    hash_mod_entry *entries;
    uint32_t nentries, capentries, capleaves;
    size_t caprefs;
    uint64_t scratch;   /* bytes of live child candidate lists */
    uint64_t memcap;    /* MiB */
    uint32_t nprims;
    prim_classes classes; /* coincident primitives, counted once against maxprims */
    char *err;
    size_t errlen;
    bool failed;
} builder;

/* Bytes the build holds now plus extra, with the table it will need
 * (made from the entries while they are still held). */
static uint64_t build_bytes(const builder *B, uint64_t extra)
{
    uint64_t b = memcap_mul(B->capentries, sizeof(hash_mod_entry));
    b = memcap_add(b, memcap_mul(B->capleaves, sizeof(oct_leaf)));
    b = memcap_add(b, memcap_mul(B->caprefs, sizeof(uint32_t)));
    b = memcap_add(b, B->scratch);
    b = memcap_add(b, memcap_mul((uint64_t)B->nentries + 2, sizeof(hash_mod_entry) + 2 * sizeof(uint32_t)));
    return memcap_add(b, extra);
}

static bool over_cap(builder *B, uint64_t extra)
{
    if (B->failed) return true;
    if (memcap_exceeded(build_bytes(B, extra), B->memcap, B->err, B->errlen,
                        "octree maxdepth=%d on %u primitives (%u nodes so far, depth %d):", B->o->maxdepth, B->nprims,
                        B->nentries, B->o->depth)) {
        B->failed = true;
        return true;
    }
    return false;
}

static void fail_oom(builder *B, const char *what)
{
    if (B->failed) return;
    snprintf(B->err, B->errlen, "octree: out of memory (%s)", what);
    B->failed = true;
}

/* arr (elements of size sz, capacity *cap) grown to hold need: the
 * array (moved, perhaps), or NULL with B failed (arr is then untouched). */
static void *grow(builder *B, void *arr, size_t sz, size_t *cap, size_t need, const char *what)
{
    if (need <= *cap) return arr;
    size_t n = *cap ? *cap : 64;
    while (n < need) n *= 2;
    if (over_cap(B, memcap_mul(n - *cap, sz))) return NULL;
    void *q = realloc(arr, n * sz);
    if (!q) {
        fail_oom(B, what);
        return NULL;
    }
    *cap = n;
    return q;
}

static bool add_entry(builder *B, oct_name name, uint32_t value)
{
    if (B->nentries >= HASH_MOD_MAX_SIZE - 64) {
        if (!B->failed)
            snprintf(B->err, B->errlen, "octree maxdepth=%d: more than %u nodes, past the name table's largest size",
                     B->o->maxdepth, HASH_MOD_MAX_SIZE - 64);
        B->failed = true;
        return false;
    }
    size_t cap = B->capentries;
    hash_mod_entry *e = grow(B, B->entries, sizeof *e, &cap, (size_t)B->nentries + 1, "node names");
    if (!e) return false;
    B->entries = e;
    B->capentries = (uint32_t)cap;
    B->entries[B->nentries++] = (hash_mod_entry){name_lo(name), name_hi(name), value};
    return true;
}

/* Does primitive id belong to the voxel whose padded box is v? */
static bool candidate(const builder *B, uint32_t id, box3 v)
{
    const prims_t *p = B->o->p;
    box3 b = prim_bounds(p, id);
    if (!box_overlap(b, v)) return false;
    if (!B->glassner) return prim_overlaps_box(p, id, v);
    /* Glassner: the surface against the six faces of the voxel... */
    for (int a = 0; a < 3; a++)
        for (int side = 0; side < 2; side++) {
            box3 f = v;
            float x = v3_get(side ? v.hi : v.lo, a);
            v3_set(&f.lo, a, x);
            v3_set(&f.hi, a, x);
            if (prim_overlaps_box(p, id, f)) return true;
        }
    /* ...then the contained point: no face is crossed, so the connected
     * surface is wholly inside or wholly outside; it is inside exactly
     * when its tight bounds are. */
    return b.lo.x >= v.lo.x && b.hi.x <= v.hi.x && b.lo.y >= v.lo.y && b.hi.y <= v.hi.y && b.lo.z >= v.lo.z &&
           b.hi.z <= v.hi.z;
}

static void note_voxel(octree_t *o, box3 b, int depth)
{
    float e = min_edge(b);
    if (e < o->minlen) o->minlen = e;
    if (depth > o->depth) o->depth = depth;
}

static void build_node(builder *B, oct_name name, int depth, box3 box, const uint32_t *cand, uint32_t n)
{
    octree_t *o = B->o;
    if (B->failed) return;
    bool split = depth < o->maxdepth && !prim_classes_at_most(&B->classes, cand, n, (uint64_t)B->maxprims) &&
                 0.5f * min_edge(box) >= B->floor_edge;
    if (split) {
        /* The eight candidate lists, one buffer. */
        size_t cap = (size_t)n + n / 2 + 8, used = 0;
        if (over_cap(B, cap * sizeof(uint32_t))) return;
        uint32_t *buf = malloc(cap * sizeof *buf);
        if (!buf) {
            fail_oom(B, "candidate lists");
            return;
        }
        B->scratch += cap * sizeof *buf;
        uint32_t off[9];
        for (unsigned c = 0; c < 8 && !B->failed; c++) {
            off[c] = (uint32_t)used;
            box3 v = box_pad(child_box(box, c), o->pad);
            for (uint32_t k = 0; k < n; k++) {
                if (!candidate(B, cand[k], v)) continue;
                if (used == cap) {
                    size_t ncap = cap * 2;
                    if (over_cap(B, (ncap - cap) * sizeof *buf)) break;
                    uint32_t *q = realloc(buf, ncap * sizeof *buf);
                    if (!q) {
                        fail_oom(B, "candidate lists");
                        break;
                    }
                    B->scratch += (ncap - cap) * sizeof *buf;
                    buf = q, cap = ncap;
                }
                buf[used++] = cand[k];
            }
        }
        off[8] = (uint32_t)used;
        if (!B->failed && B->term == TERM_COST) {
            /* MacDonald-Booth: P(child | voxel) = 1/4 for every octant. */
            double leaf = (double)n * B->ci, sub = 2.0 * B->ct + 0.25 * B->ci * (double)used;
            if (sub >= leaf) split = false;
        }
        if (!B->failed && split && add_entry(B, name, OCT_INTERIOR)) {
            for (unsigned c = 0; c < 8 && !B->failed; c++) {
                box3 cb = child_box(box, c);
                uint32_t nc = off[c + 1] - off[c];
                if (!nc) {
                    o->nempty++; /* Glassner: an empty voxel has no node */
                    note_voxel(o, cb, depth + 1);
                    continue;
                }
                build_node(B, name * 10 + 1 + c, depth + 1, cb, buf + off[c], nc);
            }
        }
        B->scratch -= cap * sizeof *buf;
        free(buf);
        if (split || B->failed) {
            if (split && !B->failed) o->ninterior++;
            return;
        }
    }
    /* A leaf. */
    note_voxel(o, box, depth);
    if (!n) {
        o->nempty++; /* only the root of an empty scene gets here */
        return;
    }
    size_t capl = B->capleaves;
    oct_leaf *lv = grow(B, o->leaves, sizeof *lv, &capl, (size_t)o->nleaves + 1, "leaves");
    if (!lv) return;
    o->leaves = lv;
    B->capleaves = (uint32_t)capl;
    if (o->nrefs + n > UINT32_MAX) {
        snprintf(B->err, B->errlen, "octree maxdepth=%d: more than 2^32 candidate references", o->maxdepth);
        B->failed = true;
        return;
    }
    uint32_t *ids = grow(B, o->ids, sizeof *ids, &B->caprefs, o->nrefs + n, "candidate ids");
    if (!ids) return;
    o->ids = ids;
    if (!add_entry(B, name, o->nleaves)) return;
    o->leaves[o->nleaves++] = (oct_leaf){(uint32_t)o->nrefs, n};
    memcpy(o->ids + o->nrefs, cand, (size_t)n * sizeof *cand);
    o->nrefs += n;
}

static void octree_destroy(accel *a)
{
    octree_t *o = (octree_t *)a;
    if (!o) return;
    hash_mod_free(&o->table);
    free(o->leaves);
    free(o->ids);
    free(o);
}

/* Probe lengths of the table (entries compared): finding every stored
 * name, and looking up the name of every empty voxel (an absent child of
 * an interior node). */
static void table_stats(octree_t *o)
{
    const hash_mod_table *h = &o->table;
    uint64_t sum = 0, miss = 0, nmiss = 0;
    uint32_t mx = 0;
    for (uint32_t home = 0; home < h->size; home++)
        for (uint32_t i = h->start[home]; i < h->start[home + 1]; i++) {
            const hash_mod_entry *s = &h->entries[i];
            uint32_t pr = i - h->start[home] + 1;
            sum += pr;
            if (pr > mx) mx = pr;
            if (s->value != OCT_INTERIOR) continue;
            oct_name nm = ((oct_name)s->key_hi << 64) | s->key_lo;
            for (uint32_t d = 1; d <= 8; d++) {
                oct_name c = nm * 10 + d;
                uint32_t q = 0;
                if (!hash_mod_find(h, name_lo(c), name_hi(c), hash_mod_extend(h, home, 10, d), &q)) miss += q, nmiss++;
            }
        }
    o->probes_avg = h->count ? (double)sum / h->count : 0.0;
    o->probes_max = mx;
    o->probes_miss_avg = nmiss ? (double)miss / (double)nmiss : 0.0;
}

static accel *octree_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    long maxdepth = params_int(params, "maxdepth"), maxprims = params_int(params, "maxprims");
    int term = params_choice(params, "term"), walk = params_choice(params, "walk"), ins = params_choice(params, "insert");
    bool mailbox = params_bool(params, "mailbox");
    double ci = params_real(params, "ci"), ct = params_real(params, "ct");
    uint64_t memcap = params_memcap(params, 4096);

    const prims_t *p = &scene->prims;
    octree_t *o = calloc(1, sizeof *o);
    if (!o) {
        snprintf(err, errlen, "octree: out of memory");
        return NULL;
    }
    o->base.scene = scene;
    o->p = p;
    o->walk = walk;
    o->maxdepth = (int)maxdepth;
    o->mailbox = mailbox;
    o->minlen = INFINITY;

    /* The root box: the primitives' bounds, flat axes widened, grown by pad. */
    box3 b = p->count && !box_is_empty(p->box) ? p->box : (box3){{-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}};
    vec3 e = box_extent(b);
    float maxe = fmaxf(e.x, fmaxf(e.y, e.z));
    float base = maxe > 0 ? maxe : fmaxf(1.0f, fmaxf(v3_max_abs(b.lo), v3_max_abs(b.hi)));
    for (int a = 0; a < 3; a++) {
        float lo = v3_get(b.lo, a), hi = v3_get(b.hi, a);
        if (hi - lo <= 1e-7f * base) v3_set(&b.lo, a, lo - 1e-3f * base), v3_set(&b.hi, a, hi + 1e-3f * base);
    }
    o->pad = 2e-6f * fmaxf(v3_max_abs(b.lo), v3_max_abs(b.hi)) + 1e-6f * box_diagonal(b);
    o->root = box_pad(b, o->pad);

    builder B = {.o = o, .maxprims = (int)maxprims, .term = term, .glassner = ins == 1, .ci = ci, .ct = ct,
                 .memcap = memcap, .nprims = p->count, .err = err, .errlen = errlen};
    B.floor_edge = OCT_EDGE_FLOOR * fmaxf(v3_max_abs(o->root.lo), v3_max_abs(o->root.hi));
    if (over_cap(&B, prim_classes_scratch_bytes(p->count))) goto fail;
    if (prim_classes_init(&B.classes, p)) {
        fail_oom(&B, "coincident primitives");
        goto fail;
    }
    B.scratch += (uint64_t)p->count * sizeof(uint32_t) * (B.classes.rep != NULL);

    /* The root's candidates: every primitive touching the root box (all of
     * them but those whose bounds are empty). */
    uint32_t *all = NULL, nall = 0;
    if (p->count) {
        if (over_cap(&B, (uint64_t)p->count * sizeof *all)) goto fail;
        all = malloc((size_t)p->count * sizeof *all);
        if (!all) {
            fail_oom(&B, "root candidates");
            goto fail;
        }
        B.scratch += (uint64_t)p->count * sizeof *all;
        box3 rv = box_pad(o->root, o->pad);
        for (uint32_t id = 0; id < p->count; id++)
            if (candidate(&B, id, rv)) all[nall++] = id;
    }
    build_node(&B, 1, 0, o->root, all, nall);
    free(all);
    if (B.failed) goto fail;

    /* The name table: a prime number of buckets, load at most 1. */
    uint32_t size = hash_mod_prime_at_least(B.nentries);
    if (!size || hash_mod_build(&o->table, size, B.entries, B.nentries)) {
        snprintf(err, errlen, "octree: cannot make a name table for %u nodes (out of memory)", B.nentries);
        goto fail;
    }
    free(B.entries);
    B.entries = NULL;
    prim_classes_free(&B.classes);
    o->root_home = hash_mod_home(&o->table, 1, 0);
    if (!isfinite(o->minlen)) o->minlen = min_edge(o->root);
    o->half = 0.5f * o->minlen;
    o->step_cap = 3 * ((uint64_t)o->nleaves + o->nempty) + 16; /* no walk enters a voxel twice */
    table_stats(o);
    return &o->base;

fail:
    free(B.entries);
    prim_classes_free(&B.classes);
    octree_destroy(&o->base);
    return NULL;
}

static accel_ctx *octree_context_new(accel *a)
{
    octree_t *o = (octree_t *)a;
    accel_ctx *c = calloc(1, sizeof *c);
    if (!c) return NULL;
    if (o->mailbox && mailbox_init(&c->mb, o->p->count)) {
        free(c);
        return NULL;
    }
    return c;
}

static void octree_context_free(accel_ctx *c)
{
    if (!c) return;
    mailbox_free(&c->mb);
    free(c);
}

/* ---------------------------------------------------------------- walks */

/* The ray as the walks see it. */
typedef struct {
    float o[3], d[3], inv[3];
    float tol; /* Glassner's check: t slack for a gap before the voxel found */
} rstate;

/* A root-to-leaf path: level 0 is the root. */
typedef struct {
    box3 box[OCTREE_MAXDEPTH_LIMIT + 1];
    oct_name name[OCTREE_MAXDEPTH_LIMIT + 1];
    uint32_t home[OCTREE_MAXDEPTH_LIMIT + 1];
    uint8_t oct[OCTREE_MAXDEPTH_LIMIT + 1]; /* octant of the level's node in its parent */
    int level;                              /* of the leaf */
    uint32_t leaf;                          /* its record, or OCT_EMPTY */
} oct_path;

static inline void path_root(const octree_t *o, oct_path *P)
{
    P->box[0] = o->root;
    P->name[0] = 1;
    P->home[0] = o->root_home;
    P->oct[0] = 0;
}

/* The octant on axis a of a node whose mid plane is m: by point (q, ties
 * toward the ray's direction) or by ray parameter (the side the ray is on
 * just after t). */
static inline unsigned side_by_point(const rstate *r, int a, float m, float q)
{
    return q > m || (q == m && !(r->d[a] < 0.0f));
}

static inline unsigned side_by_t(const rstate *r, int a, float m, float t)
{
    if (r->d[a] == 0.0f) return r->o[a] >= m;
    float tm = (m - r->o[a]) * r->inv[a];
    return r->d[a] > 0.0f ? tm <= t : !(tm <= t);
}

/* Descend from the node at level j of P (set) to the voxel holding the
 * point q (by_t false) or the ray just after t (by_t true). Each node
 * looked up is one box test. */
static inline __attribute__((always_inline)) void descend(const octree_t *o, oct_path *P, int j, const float *q,
                                                          const rstate *r, float t, const bool by_t, uint64_t *nbox)
{
    for (;;) {
        const uint32_t *v = hash_mod_find(&o->table, name_lo(P->name[j]), name_hi(P->name[j]), P->home[j], NULL);
        (*nbox)++;
        if (!v || *v != OCT_INTERIOR) {
            P->leaf = v ? *v : OCT_EMPTY;
            break;
        }
        box3 b = P->box[j];
        unsigned oct = 0;
        for (int a = 0; a < 3; a++) {
            float m = midplane(v3_get(b.lo, a), v3_get(b.hi, a));
            oct |= (by_t ? side_by_t(r, a, m, t) : side_by_point(r, a, m, q[a])) << a;
        }
        j++;
        P->box[j] = child_box(b, oct);
        P->name[j] = P->name[j - 1] * 10 + 1 + oct;
        P->home[j] = hash_mod_extend(&o->table, P->home[j - 1], 10, 1 + oct);
        P->oct[j] = (uint8_t)oct;
    }
    P->level = j;
}

/* The ray's interval in box b: entry a (max of the entry planes' t) and
 * exit (min of the exit planes' t, each kept in tx). A zero direction
 * component gives no plane (entry -inf, exit +inf); a NaN t (the origin on
 * the plane of a direction whose reciprocal overflowed) is ignored. */
static inline void voxel_span(const rstate *r, box3 b, float *ta, float *tb, float tx[3])
{
    float a = -INFINITY, z = INFINITY;
    for (int k = 0; k < 3; k++) {
        float lo = v3_get(b.lo, k), hi = v3_get(b.hi, k);
        if (r->d[k] == 0.0f) {
            tx[k] = INFINITY;
            if (r->o[k] < lo || r->o[k] > hi) a = INFINITY;
            continue;
        }
        bool pos = r->d[k] > 0.0f;
        float tn = ((pos ? lo : hi) - r->o[k]) * r->inv[k];
        float tf = ((pos ? hi : lo) - r->o[k]) * r->inv[k];
        tx[k] = tf;
        if (tn > a) a = tn;
        if (tf < z) z = tf;
    }
    *ta = a, *tb = z;
}


/* Test the candidates of ids[0..n): true when an any-hit query found an
 * occluder. Mailboxes skip (and count) a primitive this ray has tested. */
static inline __attribute__((always_inline)) bool test_list(const prims_t *p, const uint32_t *ids, uint32_t n,
                                                            mailbox_t *mb, uint32_t rid, const ray_t *ray, hit_t *hit,
                                                            counters_t *c, uint64_t *nmbox, const bool shadow,
                                                            const bool counting)
{
    for (uint32_t k = 0; k < n; k++) {
        uint32_t id = ids[k];
        if (mb) {
            if (mailbox_seen(mb, id, rid)) {
                (*nmbox)++;
                continue;
            }
            mailbox_mark(mb, id, rid);
        }
        if (shadow) {
            if (prim_test_any(p, id, ray, c, counting)) return true;
        } else {
            prim_test_closest(p, id, ray, hit, c, counting);
        }
    }
    return false;
}

/* The two walks, ONE source for all eight methods (walk kind, shadow and
 * counting are compile-time constants at the call sites). */
static inline __attribute__((always_inline)) bool walk(const octree_t *o, accel_ctx *ctx, const ray_t *ray, hit_t *hit,
                                                       counters_t *c, const int kind, const bool shadow,
                                                       const bool counting)
{
    if (!o->nleaves) return false;
    const prims_t *p = o->p;
    slab_ray sr;
    /* A ray no primitive can hit (NaN, infinite, zero direction) misses
     * before any plane t could turn into a NaN octant. */
    if (!slab_ray_init(&sr, ray->org, ray->dir)) return false;
    uint64_t nbox = 1, nsteps = 0, nempty = 0, nmbox = 0; /* the root clip is a box test */
    float t0 = ray->tnear, t1 = ray->tfar;
    if (!slab_clip(&sr, &o->root, &t0, &t1)) {
        if (counting) c->box_tests++;
        return false;
    }
    rstate r;
    for (int a = 0; a < 3; a++) r.o[a] = sr.org[a], r.inv[a] = sr.inv[a];
    r.d[0] = ray->dir.x, r.d[1] = ray->dir.y, r.d[2] = ray->dir.z;
    r.tol = 0.25f * o->pad / v3_max_abs(ray->dir);

    mailbox_t mbox, *mb = NULL; /* a local copy keeps the stamps in a register */
    uint32_t rid = 0;
    if (ctx && ctx->mb.stamp) {
        rid = mailbox_next_ray(&ctx->mb);
        mbox = ctx->mb;
        mb = &mbox;
    }
    bool occluded = false;
    uint64_t relocated = 0;
    oct_path P;
    path_root(o, &P);
    float tcur = t0;
    if (kind == WALK_GLASSNER) {
        /* Figure 11: Q starts at the ray's point where it enters. */
        float q[3];
        for (int a = 0; a < 3; a++) {
            float x = r.d[a] == 0.0f ? r.o[a] : r.o[a] + tcur * r.d[a];
            q[a] = f_min_keep(f_max_keep(x, v3_get(o->root.lo, a)), v3_get(o->root.hi, a));
        }
        descend(o, &P, 0, q, &r, tcur, false, &nbox);
    } else {
        descend(o, &P, 0, NULL, &r, tcur, true, &nbox);
    }

    bool first = true;
    for (;;) {
        box3 vb = P.box[P.level];
        float ta, tb, tx[3];
        voxel_span(&r, vb, &ta, &tb, tx);
        if (kind == WALK_GLASSNER && !(ta <= tcur + r.tol && (first ? tb >= tcur : tb > tcur))) {
            /* The moved point landed where the ray is not (rounding):
             * locate by ray parameter instead, which cannot. */
            relocated++;
            path_root(o, &P);
            descend(o, &P, 0, NULL, &r, tcur, true, &nbox);
            vb = P.box[P.level];
            voxel_span(&r, vb, &ta, &tb, tx);
            if (!(ta <= tcur + r.tol && (first ? tb >= tcur : tb > tcur))) goto exhaustive;
        }
        first = false;
        if (++nsteps > o->step_cap) goto exhaustive;
        if (P.leaf == OCT_EMPTY) {
            nempty++;
        } else {
            const oct_leaf *L = &o->leaves[P.leaf];
            if (test_list(p, o->ids + L->first, L->count, mb, rid, ray, hit, c, &nmbox, shadow, counting)) {
                occluded = true;
                goto out;
            }
        }
        /* Survey s5.3: a hit ends the walk only inside this voxel. */
        if (!shadow && hit->t <= tb) goto out;
        if (tb >= t1) goto out;

        if (kind == WALK_GLASSNER) {
            /* Q: the exit point moved minlen/2 beyond every exit face. */
            float q[3];
            for (int a = 0; a < 3; a++) {
                float lo = v3_get(vb.lo, a), hi = v3_get(vb.hi, a);
                if (tx[a] == tb) {
                    q[a] = r.d[a] > 0.0f ? hi + o->half : lo - o->half;
                    if (q[a] < v3_get(o->root.lo, a) || q[a] > v3_get(o->root.hi, a)) goto out; /* leaves the root */
                } else {
                    q[a] = f_min_keep(f_max_keep(r.o[a] + tb * r.d[a], lo), hi);
                }
            }
            tcur = tb;
            path_root(o, &P);
            descend(o, &P, 0, q, &r, tcur, false, &nbox);
        } else {
            /* Fujimoto: the 3DDDA's axis; a sibling, or up and down. */
            int ax = tx[0] == tb ? 0 : tx[1] == tb ? 1 : 2;
            unsigned bit = 1u << ax, near = r.d[ax] > 0.0f ? 0u : bit;
            int j = P.level;
            while (j >= 1 && (P.oct[j] & bit) != near) j--;
            if (j == 0) goto out; /* leaves the root */
            unsigned oct = P.oct[j] ^ bit;
            P.box[j] = child_box(P.box[j - 1], oct);
            P.name[j] = P.name[j - 1] * 10 + 1 + oct;
            P.home[j] = hash_mod_extend(&o->table, P.home[j - 1], 10, 1 + oct);
            P.oct[j] = (uint8_t)oct;
            tcur = tb;
            descend(o, &P, j, NULL, &r, tcur, true, &nbox);
        }
    }

exhaustive:
    /* The walk could not go on (rounding at extreme magnitudes): test every
     * primitive; the mailbox skips those already tested. */
    if (ctx) ctx->exhaustive++;
    for (uint32_t id = 0; id < p->count; id++) {
        if (test_list(p, &id, 1, mb, rid, ray, hit, c, &nmbox, shadow, counting)) {
            occluded = true;
            break;
        }
    }
out:
    if (ctx) ctx->relocated += relocated;
    if (counting)
        counters_add(c, &(counters_t){.box_tests = nbox, .steps = nsteps, .empty_leaves = nempty, .mailbox_hits = nmbox});
    return shadow ? occluded : hit->prim != HIT_NONE;
}

static bool octree_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    const octree_t *o = (const octree_t *)a;
    return o->walk == WALK_GLASSNER ? walk(o, ctx, ray, hit, c, WALK_GLASSNER, false, true)
                                    : walk(o, ctx, ray, hit, c, WALK_FUJIMOTO, false, true);
}

static bool octree_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    const octree_t *o = (const octree_t *)a;
    return o->walk == WALK_GLASSNER ? walk(o, ctx, ray, NULL, c, WALK_GLASSNER, true, true)
                                    : walk(o, ctx, ray, NULL, c, WALK_FUJIMOTO, true, true);
}

static bool octree_intersect_fast(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit)
{
    const octree_t *o = (const octree_t *)a;
    return o->walk == WALK_GLASSNER ? walk(o, ctx, ray, hit, NULL, WALK_GLASSNER, false, false)
                                    : walk(o, ctx, ray, hit, NULL, WALK_FUJIMOTO, false, false);
}

static bool octree_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *ray)
{
    const octree_t *o = (const octree_t *)a;
    return o->walk == WALK_GLASSNER ? walk(o, ctx, ray, NULL, NULL, WALK_GLASSNER, true, false)
                                    : walk(o, ctx, ray, NULL, NULL, WALK_FUJIMOTO, true, false);
}

static size_t octree_memory(const accel *a)
{
    const octree_t *o = (const octree_t *)a;
    return sizeof *o + hash_mod_memory(&o->table) + (size_t)o->nleaves * sizeof(oct_leaf) + o->nrefs * sizeof(uint32_t);
}

/* ------------------------------------------------------- version 2 */

/* Every voxel of the tree into the model, from node `name` (its bucket
 * home, its box, its depth) down: an interior node's eight octants, a
 * stored leaf with its list, an absent name an empty voxel. */
static void predict_node(const octree_t *o, line_model *m, oct_name name, uint32_t home, box3 box, int depth)
{
    const uint32_t *v = o->table.size ? hash_mod_find(&o->table, name_lo(name), name_hi(name), home, NULL) : NULL;
    if (v && *v == OCT_INTERIOR) {
        for (unsigned c = 0; c < 8; c++)
            predict_node(o, m, name * 10 + 1 + c, hash_mod_extend(&o->table, home, 10, 1 + c), child_box(box, c),
                         depth + 1);
        return;
    }
    const oct_leaf *L = v ? &o->leaves[*v] : NULL;
    line_model_cell(m, box, depth, L ? o->ids + L->first : NULL, L ? L->count : 0);
}

static int octree_stats(const accel *a, accel_stat *out, int max)
{
    const octree_t *o = (const octree_t *)a;
    /* The random-line model (common/line_model.h) over the finished tree. */
    line_prediction pr = {-1.0, -1.0, -1.0, -1.0, -1.0};
    line_model m;
    if (line_model_init(&m, o->root, o->p->count, o->mailbox) == 0) {
        predict_node(o, &m, 1, o->root_home, o->root, 0);
        pr = line_model_result(&m);
        line_model_free(&m);
    }
    uint32_t count = o->p->count;
    accel_stat all[] = {
        {"nodes", (double)o->ninterior},
        {"leaves", (double)o->nleaves},
        {"empty_leaves", (double)o->nempty},
        {"max_depth", (double)o->depth},
        {"avg_leaf_prims", o->nleaves ? (double)o->nrefs / o->nleaves : 0.0},
        {"refs_per_prim", count ? (double)o->nrefs / count : 0.0},
        /* the table's */
        {"hash_load", o->table.size ? (double)o->table.count / o->table.size : 0.0},
        {"hash_probes_avg", o->probes_avg},
        {"hash_probes_max", (double)o->probes_max},
        {"hash_probes_miss_avg", o->probes_miss_avg},
        /* the random-line model (common/line_model.h); box tests: the root
         * clip and, walk=glassner, a lookup per level of every descent */
        {"predicted_steps_per_ray", pr.cells},
        {"predicted_tests_per_ray", pr.tests},
        {"predicted_box_tests_per_ray", 1.0 + pr.descents},
    };
    int n = 0;
    /* fujimoto: no box-test model; out of memory for the model: none of it */
    size_t rows = sizeof all / sizeof all[0] - (pr.cells < 0.0 ? 3 : o->walk != WALK_GLASSNER);
    for (size_t k = 0; k < rows && n < max; k++)
        out[n++] = all[k];
    return n;
}

static box3 octree_bounds(const accel *a) { return ((const octree_t *)a)->root; }

/* ---------------------------------------------------------------- debug */

octree_node_info octree_debug_node(const accel *a, uint64_t name_lo_, uint32_t name_hi_)
{
    const octree_t *o = (const octree_t *)a;
    octree_node_info n = {OCTREE_ABSENT, 0, NULL, 0, 0};
    if (!o->table.size || (!name_lo_ && !name_hi_)) return n;
    n.home = hash_mod_home(&o->table, name_lo_, name_hi_);
    const uint32_t *v = hash_mod_find(&o->table, name_lo_, name_hi_, n.home, &n.probes);
    if (!v) return n;
    if (*v == OCT_INTERIOR) {
        n.kind = OCTREE_INTERIOR;
        return n;
    }
    n.kind = OCTREE_LEAF;
    n.count = o->leaves[*v].count;
    n.ids = o->ids + o->leaves[*v].first;
    return n;
}

void octree_debug_info(const accel *a, octree_info *out)
{
    const octree_t *o = (const octree_t *)a;
    *out = (octree_info){o->ninterior, o->nleaves, o->nempty, o->depth, o->minlen, o->root, o->table.size,
                         o->table.count, o->probes_avg, o->probes_max, o->probes_miss_avg};
}

void octree_debug_locate(const accel *a, vec3 q, vec3 dir, uint64_t *lo, uint32_t *hi, int *depth)
{
    const octree_t *o = (const octree_t *)a;
    rstate r = {{0}, {dir.x, dir.y, dir.z}, {0}, 0};
    float qq[3] = {q.x, q.y, q.z};
    oct_path P;
    uint64_t nbox = 0;
    path_root(o, &P);
    if (o->table.size) descend(o, &P, 0, qq, &r, 0, false, &nbox);
    else P.level = 0;
    *lo = name_lo(P.name[P.level]);
    *hi = name_hi(P.name[P.level]);
    *depth = P.level;
}

void octree_debug_sabotage(accel *a, float half, uint64_t step_cap)
{
    octree_t *o = (octree_t *)a;
    o->half = half;
    o->step_cap = step_cap;
}

void octree_debug_fallbacks(const accel_ctx *ctx, uint64_t *relocated, uint64_t *exhaustive)
{
    *relocated = ctx ? ctx->relocated : 0;
    *exhaustive = ctx ? ctx->exhaustive : 0;
}

/* ---------------------------------------------------------------- table */

static const accel_param octree_params[] = {
    PARAM_ROW_INT("maxdepth", "6", 0, OCTREE_MAXDEPTH_LIMIT,
                  "deepest node, root 0 (names pass 64 bits at depth 19, held in 128; depth 20 already allows 8^20 "
                  "= 1.2e18 voxels)"),
    PARAM_ROW_INT("maxprims", "2", 0, 1L << 30, "subdivide a voxel with more candidates than this"),
    PARAM_ROW_CHOICE("term", "const", "const|cost", "stop rule: const (maxdepth, maxprims: Havran's O84-C), cost (also MacDonald-Booth SAH)"),
    PARAM_ROW_REAL("ci", "80", 1e-6, 1e12, "term=cost: cost of one primitive test (pbrt-v3 kd-tree)"),
    PARAM_ROW_REAL("ct", "1", 0, 1e12, "term=cost: cost of entering one voxel (pbrt-v3 kd-tree)"),
    PARAM_ROW_CHOICE("insert", "exact", "exact|glassner", "candidates: exact (prim_overlaps_box), glassner (six faces, then a contained point)"),
    PARAM_ROW_CHOICE("walk", "glassner", "glassner|fujimoto",
                     "next voxel: glassner (point moved minlen/2, located by names), fujimoto (3DDDA among siblings)"),
    PARAM_ROW_BOOL("mailbox", "on", "Arnaldi mailboxes, per-thread last ray id per primitive"),
    PARAM_ROW_END,
};

/* The settings the conformance suite runs besides the defaults: each
 * switch, one voxel, names past 64 bits with both walks, deep and fine
 * subdivision with the cost rule. */
static const char *const octree_variants[] = {
    "walk=fujimoto", "mailbox=off", "insert=glassner", "term=cost", "maxdepth=0",
    "maxdepth=20,maxprims=8", "maxdepth=20,maxprims=8,walk=fujimoto", "maxdepth=12,maxprims=0,term=cost,walk=fujimoto",
    NULL};

const struct accel_ops accel_octree = {
    .version = 2,
    .name = "octree",
    .summary = "Glassner's octree: hashed node names, candidate lists, sequential walk by minlen steps (or Fujimoto's)",
    .paper = "Glassner, IEEE CG&A 4(10) 1984; Arvo & Kirk 1989 survey s5.1, s5.3; Fujimoto et al., ARTS, CG&A 1986",
    .params = octree_params,
    .flags = 0,
    .build = octree_build,
    .context_new = octree_context_new,
    .context_free = octree_context_free,
    .intersect = octree_intersect,
    .occluded = octree_occluded,
    .memory = octree_memory,
    .destroy = octree_destroy,
    .stats = octree_stats,
    .reset = NULL,
    .bounds = octree_bounds,
    .intersect_fast = octree_intersect_fast,
    .occluded_fast = octree_occluded_fast,
    .variants = octree_variants,
    .cost = {3, 4, 0},
    .tune = "maxdepth=4|5|6|7|8|10", /* Havran's O84 depth and those around it */
};
