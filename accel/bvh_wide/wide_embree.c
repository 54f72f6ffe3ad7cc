/* wide_embree.c: a wide BVH (wide.h) whose tree is built by Embree's own
 * builder through its public rtcBuildBVH API, for `bvh tree=embree`: our
 * kernels over Embree's tree, so that a trace-time gap against Embree
 * splits into what the tree costs and what the kernels cost.
 *
 * rtcBuildBVH runs Embree's binned SAH builder (BVHBuilderBinnedSAH) over
 * the primitives' boxes with the settings it is handed. The ones here are
 * those of Embree 3's scene builder for static triangle scenes on AVX
 * machines, BVHNBuilderSAH<8,Triangle4> (kernels/bvh/bvh_builder_sah.cpp):
 * branching factor 8, SAH block size 4 (a leaf costs whole blocks of 4),
 * intersection and traversal cost 1, leaves of at least 4 primitives
 * (minLeafSize: a child of 4 or fewer is never split) and at most 28 (seven
 * Triangle4 blocks), depth 40. An N-ary node is made by splitting its
 * largest child until it has 8 children or none is splittable. What Embree
 * adds after its build (layoutLargeNodes: the 0.5 % largest nodes copied
 * together for locality) is not done here.
 *
 * Layout: Embree's nodes and leaves live in its allocator while it builds
 * (enode, eleaf below); they are copied into our wide nodes in depth-first
 * order, root first, each leaf's primitive ids into refs, and released with
 * the RTCBVH. Per width only 8 is made (Embree's BVH8). */
#include <embree3/rtcore.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "wide.h"

#define EMBREE_WIDTH 8

typedef struct {
    uint32_t leaf; /* 0 */
    uint32_t n;
    void *child[EMBREE_WIDTH];
    box3 box[EMBREE_WIDTH];
} enode;

_Static_assert(sizeof(enode) <= 272, "bvh_wide.c's memory cap counts 272 bytes an Embree node");

typedef struct {
    uint32_t leaf; /* 1 */
    uint32_t n;
    uint32_t ids[];
} eleaf;

static void *create_node(RTCThreadLocalAllocator alloc, unsigned int count, void *user)
{
    (void)user;
    enode *e = rtcThreadLocalAlloc(alloc, sizeof *e, 16);
    e->leaf = 0;
    e->n = count;
    return e;
}

static void set_children(void *node, void **children, unsigned int count, void *user)
{
    (void)user;
    enode *e = node;
    for (unsigned int k = 0; k < count; k++) e->child[k] = children[k];
}

static void set_bounds(void *node, const struct RTCBounds **bounds, unsigned int count, void *user)
{
    (void)user;
    enode *e = node;
    for (unsigned int k = 0; k < count; k++)
        e->box[k] = (box3){{bounds[k]->lower_x, bounds[k]->lower_y, bounds[k]->lower_z},
                           {bounds[k]->upper_x, bounds[k]->upper_y, bounds[k]->upper_z}};
}

static void *create_leaf(RTCThreadLocalAllocator alloc, const struct RTCBuildPrimitive *prims, size_t count,
                         void *user)
{
    (void)user;
    eleaf *l = rtcThreadLocalAlloc(alloc, sizeof *l + count * sizeof(uint32_t), 16);
    l->leaf = 1;
    l->n = (uint32_t)count;
    for (size_t i = 0; i < count; i++) l->ids[i] = prims[i].primID;
    return l;
}

/* Counts of the Embree tree below root: interior nodes and primitive refs. */
static void count_tree(const void *root, uint32_t *nodes, uint64_t *refs)
{
    const eleaf *l = root;
    if (l->leaf) {
        *refs += l->n;
        return;
    }
    const enode *e = root;
    ++*nodes;
    for (uint32_t k = 0; k < e->n; k++) count_tree(e->child[k], nodes, refs);
}

/* Wide node ni from Embree node e (depth d), its interior children numbered
 * after it in depth-first order. */
static void copy_node(wide_bvh *w, const enode *e, uint32_t ni, uint32_t depth, uint32_t *nref)
{
    const uint32_t W = w->width;
    for (uint32_t k = 0; k < W; k++) {
        if (k >= e->n) {
            wide_set_slot(w, ni, k, box_empty(), WIDE_EMPTY, 0);
            continue;
        }
        const eleaf *l = e->child[k];
        if (l->leaf) {
            wide_set_slot(w, ni, k, e->box[k], WIDE_LEAF | *nref, l->n);
            memcpy(w->refs + *nref, l->ids, l->n * sizeof(uint32_t));
            *nref += l->n;
            w->nleaves++;
            if (depth + 1 > w->max_depth) w->max_depth = depth + 1;
            continue;
        }
        uint32_t child = w->nnodes++;
        wide_set_slot(w, ni, k, e->box[k], child, 0);
        copy_node(w, e->child[k], child, depth + 1, nref);
    }
    WIDE_NCHILDREN((char *)w->nodes + (size_t)ni * WIDE_NODE_BYTES(W), W) = (uint8_t)e->n;
    wide_set_orders(w, ni, e->n);
    w->nchildren += e->n;
}

int wide_build_embree(wide_bvh *w, const box3 *boxes, uint32_t n, uint32_t threads, char *err, size_t errlen)
{
    memset(w, 0, sizeof *w);
    w->width = EMBREE_WIDTH;
    if (!n) return 0;
    char config[64];
    snprintf(config, sizeof config, "threads=%u", threads ? threads : 1);
    RTCDevice device = rtcNewDevice(config);
    if (!device) {
        snprintf(err, errlen, "bvh tree=embree: rtcNewDevice(\"%s\") failed", config);
        return -1;
    }
    struct RTCBuildPrimitive *prims = malloc((size_t)n * sizeof *prims);
    RTCBVH bvh = rtcNewBVH(device);
    int rc = -1;
    if (!prims || !bvh) {
        snprintf(err, errlen, "bvh tree=embree: out of memory over %u primitives", n);
        goto done;
    }
    for (uint32_t i = 0; i < n; i++)
        prims[i] = (struct RTCBuildPrimitive){boxes[i].lo.x, boxes[i].lo.y, boxes[i].lo.z, 0,
                                              boxes[i].hi.x, boxes[i].hi.y, boxes[i].hi.z, i};
    struct RTCBuildArguments args = rtcDefaultBuildArguments();
    args.buildQuality = RTC_BUILD_QUALITY_MEDIUM;
    args.maxBranchingFactor = EMBREE_WIDTH;
    args.maxDepth = 40;
    args.sahBlockSize = 4;
    args.minLeafSize = 4;
    args.maxLeafSize = 28;
    args.traversalCost = 1.0f;
    args.intersectionCost = 1.0f;
    args.bvh = bvh;
    args.primitives = prims;
    args.primitiveCount = n;
    args.primitiveArrayCapacity = n;
    args.createNode = create_node;
    args.setNodeChildren = set_children;
    args.setNodeBounds = set_bounds;
    args.createLeaf = create_leaf;
    void *root = rtcBuildBVH(&args);
    if (!root) {
        snprintf(err, errlen, "bvh tree=embree: rtcBuildBVH failed (error %d)", (int)rtcGetDeviceError(device));
        goto done;
    }
    /* A root that is a leaf gets a node of one leaf child, as the collapse does. */
    enode single;
    if (((const eleaf *)root)->leaf) {
        single = (enode){.leaf = 0, .n = 1};
        single.child[0] = root;
        single.box[0] = box_empty();
        for (uint32_t i = 0; i < n; i++) single.box[0] = box_union(single.box[0], boxes[i]);
        root = &single;
    }
    uint32_t nodes = 0;
    uint64_t refs = 0;
    count_tree(root, &nodes, &refs);
    w->nodes = aligned_alloc(64, (size_t)nodes * WIDE_NODE_BYTES(EMBREE_WIDTH));
    w->refs = malloc((size_t)refs * sizeof(uint32_t));
    if (!w->nodes || !w->refs) {
        snprintf(err, errlen, "bvh tree=embree: out of memory over %u primitives", n);
        wide_free(w);
        goto done;
    }
    memset(w->nodes, 0, (size_t)nodes * WIDE_NODE_BYTES(EMBREE_WIDTH));
    w->nnodes = 1;
    w->nrefs = (uint32_t)refs;
    uint32_t nref = 0;
    copy_node(w, root, 0, 0, &nref);
    rc = 0;
done:
    if (bvh) rtcReleaseBVH(bvh);
    free(prims);
    rtcReleaseDevice(device);
    return rc;
}
