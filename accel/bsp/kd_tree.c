/* kd_tree.c: the kd-tree's storage (kd_tree.h): the root cell, depth-first
 * node emission, leaf lists, and the memory cap every byte of the tree and
 * of its build scratch is charged against (accel/common/memcap.h), so an
 * absurd depth on a large scene fails with a reason instead of swapping.
 * The builders are kd_midpoint.c and kd_sah.c. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "kd_build.h"
#include "../common/memcap.h"

int kd_default_depth(uint64_t n)
{
    int log2n = 0;
    while (n >= 2) n >>= 1, log2n++;
    return (int)lround(8.0 + 1.3 * log2n);
}

void kd_fail(kd_builder *b, const char *fmt, ...)
{
    if (b->failed) return;
    b->failed = true;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(b->err, b->errlen, fmt, ap);
    va_end(ap);
}

static uint64_t tree_bytes(const kd_tree *t)
{
    return (uint64_t)t->nodes_cap * sizeof(kd_node) + (uint64_t)t->ids_cap * sizeof(uint32_t);
}

/* Would tree_bytes + scratch + extra bytes exceed the cap? Fails if so. */
static bool over_cap(kd_builder *b, uint64_t extra)
{
    if (b->failed) return true;
    uint64_t total = memcap_add(memcap_add(tree_bytes(b->t), b->scratch), extra);
    const kd_config *c = b->cfg;
    if (!memcap_exceeded(total, c->memcap_mib, b->err, b->errlen,
                         "split=%s maxdepth=%d maxprims=%d: the tree and its build scratch",
                         c->split == KD_SPLIT_SAH ? "sah" : "midpoint", c->maxdepth, c->maxprims))
        return false;
    b->failed = true;
    return true;
}

bool kd_charge(kd_builder *b, int64_t bytes)
{
    if (bytes < 0) {
        b->scratch -= (uint64_t)-bytes;
        return !b->failed;
    }
    if (over_cap(b, (uint64_t)bytes)) return false;
    b->scratch += (uint64_t)bytes;
    return true;
}

void *kd_scratch_alloc(kd_builder *b, size_t n, size_t size)
{
    uint64_t bytes = memcap_mul(n ? n : 1, size);
    if (bytes > INT64_MAX || !kd_charge(b, (int64_t)bytes)) return NULL;
    void *ptr = malloc((size_t)bytes);
    if (!ptr) {
        kd_charge(b, -(int64_t)bytes);
        kd_fail(b, "out of memory (%.1f MiB of build scratch)", (double)bytes / 1048576.0);
    }
    return ptr;
}

void kd_scratch_free(kd_builder *b, void *ptr, size_t n, size_t size)
{
    if (!ptr) return;
    free(ptr);
    kd_charge(b, -(int64_t)((n ? n : 1) * size));
}

/* Grow an array to hold need elements: by 1.5x, or to what the cap still
 * leaves when 1.5x would cross it (never element by element, which would
 * copy quadratically), or fail with the cap's reason. */
static bool grow(kd_builder *b, void **arr, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap) return true;
    if (b->failed) return false;
    size_t want = *cap + *cap / 2 + 64;
    if (want < need) want = need;
    uint64_t cap_mib = b->cfg->memcap_mib;
    if (cap_mib <= (UINT64_MAX >> 20)) {
        uint64_t limit = cap_mib << 20, used = memcap_add(tree_bytes(b->t), b->scratch);
        uint64_t room = used < limit ? (limit - used) / size : 0; /* elements that still fit */
        if ((uint64_t)(want - *cap) > room) want = *cap + (size_t)room;
        if (want < need) {
            if (!over_cap(b, memcap_mul(need - *cap, size))) kd_fail(b, "internal: the memory cap's room miscounted");
            return false;
        }
    }
    void *q = realloc(*arr, want * size);
    if (!q) {
        kd_fail(b, "out of memory growing the tree to %.1f MiB", (double)(want * size) / 1048576.0);
        return false;
    }
    *arr = q;
    *cap = want;
    return true;
}

static uint32_t append_node(kd_builder *b, kd_node n)
{
    kd_tree *t = b->t;
    if (b->failed) return UINT32_MAX;
    if (t->nnodes >= KD_INDEX_MAX) {
        kd_fail(b, "more than 2^30 nodes (a kd_node holds a 30-bit child index): lower maxdepth");
        return UINT32_MAX;
    }
    size_t cap = t->nodes_cap;
    void *arr = t->nodes;
    if (!grow(b, &arr, &cap, (size_t)t->nnodes + 1, sizeof(kd_node))) return UINT32_MAX;
    t->nodes = arr;
    t->nodes_cap = (uint32_t)cap;
    t->nodes[t->nnodes] = n;
    return t->nnodes++;
}

uint32_t kd_emit_interior(kd_builder *b, int axis, float split)
{
    kd_node n;
    n.split = split;
    n.bits = (uint32_t)axis;
    uint32_t k = append_node(b, n);
    if (k != UINT32_MAX) b->t->ninterior++;
    return k;
}

void kd_link_above(kd_builder *b, uint32_t node)
{
    if (b->failed || node == UINT32_MAX) return;
    kd_tree *t = b->t;
    t->nodes[node].bits = t->nnodes << 2 | (t->nodes[node].bits & 3u);
}

static int cmp_u32(const void *x, const void *y)
{
    uint32_t a = *(const uint32_t *)x, c = *(const uint32_t *)y;
    return (a > c) - (a < c);
}

void kd_emit_leaf(kd_builder *b, uint32_t *ids, uint32_t n, int depth)
{
    kd_tree *t = b->t;
    if (b->failed) return;
    if (n > KD_INDEX_MAX) {
        kd_fail(b, "a leaf of %u primitives, more than a kd_node's 30-bit count", n);
        return;
    }
    kd_node node;
    node.first = 0;
    node.bits = n << 2 | KD_LEAF;
    if (n == 1) node.first = ids[0];
    if (n >= 2) {
        if (t->nids + n > UINT32_MAX) {
            kd_fail(b, "more than 2^32 primitive references in leaves: lower maxdepth");
            return;
        }
        void *arr = t->ids;
        size_t cap = t->ids_cap;
        if (!grow(b, &arr, &cap, t->nids + n, sizeof(uint32_t))) return;
        t->ids = arr;
        t->ids_cap = cap;
        qsort(ids, n, sizeof *ids, cmp_u32);
        memcpy(t->ids + t->nids, ids, (size_t)n * sizeof *ids);
        node.first = (uint32_t)t->nids;
        t->nids += n;
    }
    if (append_node(b, node) == UINT32_MAX) return;
    t->nleaves++;
    t->nempty += n == 0;
    t->nrefs += n;
    if ((uint32_t)depth > t->max_depth) t->max_depth = (uint32_t)depth;
}

void kd_free(kd_tree *t)
{
    free(t->nodes);
    free(t->ids);
    memset(t, 0, sizeof *t);
}

size_t kd_memory(const kd_tree *t) { return (size_t)tree_bytes(t); }

/* The root cell: the primitives' bounds; an axis of (almost) no extent is
 * widened by 1e-3 of the largest extent (or of the coordinates' magnitude),
 * so that every cell has a positive surface area and midpoints exist. */
static box3 root_box(const prims_t *p)
{
    box3 b = p->count && !box_is_empty(p->box) ? p->box : (box3){{-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}};
    vec3 e = box_extent(b);
    float maxe = fmaxf(e.x, fmaxf(e.y, e.z));
    float mag = fmaxf(fmaxf(fabsf(b.lo.x), fmaxf(fabsf(b.lo.y), fabsf(b.lo.z))),
                      fmaxf(fabsf(b.hi.x), fmaxf(fabsf(b.hi.y), fabsf(b.hi.z))));
    float base = maxe > 0 ? maxe : fmaxf(1.0f, mag);
    for (int a = 0; a < 3; a++)
        if (kd_get(b.hi, a) - kd_get(b.lo, a) <= 1e-7f * base) {
            kd_set(&b.lo, a, kd_get(b.lo, a) - 1e-3f * base);
            kd_set(&b.hi, a, kd_get(b.hi, a) + 1e-3f * base);
        }
    return b;
}

int kd_build(kd_tree *t, const prims_t *p, const kd_config *cfg, char *err, size_t errlen)
{
    memset(t, 0, sizeof *t);
    kd_builder b = {.t = t, .p = p, .cfg = cfg, .err = err, .errlen = errlen};
    if (cfg->maxdepth < 0 || cfg->maxdepth > KD_MAX_DEPTH) kd_fail(&b, "maxdepth=%d: must be in 0..%d", cfg->maxdepth, KD_MAX_DEPTH);
    if (p->count > KD_INDEX_MAX) kd_fail(&b, "%u primitives: a kd-tree holds at most 2^30 - 1", p->count);
    t->box = root_box(p);
    box3 r = t->box;
    float mag = fmaxf(fmaxf(fabsf(r.lo.x), fmaxf(fabsf(r.lo.y), fabsf(r.lo.z))),
                      fmaxf(fabsf(r.hi.x), fmaxf(fabsf(r.hi.y), fabsf(r.hi.z))));
    t->pad = 2e-6f * mag + 1e-6f * box_diagonal(r);
    if (!b.failed && cfg->split == KD_SPLIT_MIDPOINT && kd_charge(&b, (int64_t)prim_classes_scratch_bytes(p->count))) {
        if (prim_classes_init(&b.classes, p)) kd_fail(&b, "out of memory (finding coincident primitives)");
        kd_charge(&b, -(int64_t)prim_classes_scratch_bytes(p->count));
        if (b.classes.rep) kd_charge(&b, (int64_t)p->count * (int64_t)sizeof(uint32_t));
    }
    if (!b.failed) {
        if (cfg->split == KD_SPLIT_SAH) kd_build_sah(&b);
        else kd_build_midpoint(&b);
    }
    if (b.classes.rep) kd_charge(&b, -(int64_t)p->count * (int64_t)sizeof(uint32_t));
    prim_classes_free(&b.classes);
    if (!b.failed && t->nnodes == 0) kd_fail(&b, "internal: the builder made no node");
    if (b.failed) {
        kd_free(t);
        return -1;
    }
    return 0;
}

int kd_predict(const kd_tree *t, uint32_t nprims, bool mailbox, line_prediction *out, double *nodes_met)
{
    line_model m;
    if (line_model_init(&m, t->box, nprims, mailbox)) return -1;
    *nodes_met = 0.0;
    /* Depth first: the below child is the next node, so a stack of the
     * above children's cells is all the walk keeps. */
    struct { uint32_t node; int depth; box3 cell; } stack[KD_MAX_DEPTH + 2];
    int sp = 0;
    if (t->nnodes) stack[sp++] = (typeof(stack[0])){0, 0, t->box};
    while (sp) {
        typeof(stack[0]) e = stack[--sp];
        for (;;) {
            const kd_node *nd = &t->nodes[e.node];
            if (kd_is_leaf(nd)) {
                uint32_t n;
                const uint32_t *ids = kd_leaf_ids(t, nd, &n);
                line_model_cell(&m, e.cell, e.depth, ids, n);
                break;
            }
            *nodes_met += line_model_prob(&m, e.cell);
            const int a = kd_axis(nd);
            box3 below = e.cell, above = e.cell;
            v3_set(&below.hi, a, nd->split);
            v3_set(&above.lo, a, nd->split);
            stack[sp++] = (typeof(stack[0])){kd_above(nd), e.depth + 1, above};
            e = (typeof(stack[0])){e.node + 1, e.depth + 1, below};
        }
    }
    *out = line_model_result(&m);
    *nodes_met += out->cells;
    line_model_free(&m);
    return 0;
}
