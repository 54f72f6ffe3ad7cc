/* wide.h: the wide BVH of the `bvh` accelerator (accel/bvh_wide/bvh_wide.c):
 * node layouts for 2, 4 and 8 children and the quantised 8-wide one of
 * compress=on (wide_quantize.c), the collapse from the kit's binary
 * tree (collapse.c), Embree's own 8-wide tree copied in for `tree=embree`
 * (wide_embree.c), the traversal kernels per instruction set
 * (wide_traverse_*.c on the one walk of wide_walk.h) and their dispatch
 * (wide_isa.c).
 *
 * Literature (docs/accels/wide-bvh.md has the full citations): the kit's
 * binned SAH tree (build_sah.c); wide SoA nodes tested with SIMD and the
 * greedy collapse (open the child of largest area until the node is full)
 * of Dammertz et al. (EGSR 2008), Ernst and Greiner and Wald et al. (IEEE
 * RT 2008); Ize's robust box test (JCGT 2013) as accel/common/slab.h
 * applies it, near and far planes chosen by the sign of the reciprocal
 * (Williams et al., JGT 2005), so +-0 components need no branch.
 *
 * Node layouts (W = 2, 4 or 8 children; sizes asserted below):
 *   box[6][W]  floats, one row per plane, W children side by side (SoA):
 *              rows 0 lo_x, 1 hi_x, 2 lo_y, 3 hi_y, 4 lo_z, 5 hi_z; an
 *              unused slot holds the empty box (lo +inf, hi -inf), which
 *              every ray misses, so the SIMD test needs no lane mask;
 *   child[W]   uint32: an interior child's node index; a leaf's first entry
 *              of refs with WIDE_LEAF set, or (a leaf of triangles only,
 *              after wide_pack_leaves) its first packet with WIDE_LEAF and
 *              WIDE_PACKED set; WIDE_EMPTY for an unused slot;
 *   count[W]   uint8: a leaf's primitives (1..255), 0 for an interior child;
 *   nchildren  uint8: used slots, always the first ones;
 *   padding, then
 *   order[4]   the slots front to back for rays of each octant with x >= 0
 *              (WIDE_ORDER), 3 bits a position in a uint8 (W=2), uint16
 *              (W=4) or uint32 (W=8), in the last 2W bytes of the node: the
 *              used slots sorted by their box centres projected on the
 *              octant's diagonal (nearest first, ties by slot), then the
 *              unused ones; `order=octant` walks them (Ylitie, Karras,
 *              Laine, HPG 2017, s3.2, as a permutation per octant).
 *   BVH2: 2*6*4 + 2*4 + 2 + 1 + 1 + 4 = 64 bytes (1 line);
 *   BVH4: 4*6*4 + 4*4 + 4 + 1 + 3 + 8 = 128 bytes (2 lines);
 *   BVH8: 8*6*4 + 8*4 + 8 + 1 + 7 + 16 = 256 bytes (4 lines).
 * Memory layout: nodes[nnodes] (64-byte aligned; node 0 the root, which is
 * always interior: a tree whose binary root is a leaf gets a root of one
 * leaf child), then refs[nrefs] uint32 primitive ids, each leaf's a
 * contiguous run (taken over from the binary tree), then (packets on)
 * packets[npackets], prims/'s prim_tri_packet (160 bytes: 4 triangles'
 * corners in SoA and their ids), each all-triangle leaf's
 * ceil(count / 4) of them contiguous, 64-byte aligned. An empty scene has
 * nnodes == 0. Total = node bytes * nnodes + 4 nrefs + 160 npackets
 * (wide_memory()).
 * compress=on (wide_quantize, wide_quantize.c): BVH8 nodes with their
 *   children's boxes quantised to 8 bits a plane, in the style of Ylitie,
 *   Karras and Laine, HPG 2017, section 3.1 (their 80-byte node keeps child
 *   and triangle base indices; this one keeps the child and count words
 *   above, so the walk is unchanged but for the box test), 128 bytes:
 *   q[6][8]     uint8, the box rows as above, each plane as a multiple of
 *               its axis's scale above the node's origin;
 *   origin[3]   float, the lower corner of the node's box;
 *   scale_exp[3] uint8, the biased float exponent e of the axis's scale
 *               2^(e - 127), 1..247, so q * scale is exact (at most 8 + 24
 *               bits, never overflowing) and a plane decodes as
 *               origin + q * scale with one rounding, the same in every
 *               kernel whether it multiplies and adds or fuses them;
 *   nchildren   uint8 (an unused slot decodes to a box at the origin, so
 *               the kernels mask the hits with the used slots instead);
 *   child[8], count[8], 8 bytes of padding, order[4] as above.
 *   The first cache line holds all the box test reads, the second the
 *   words it reads after. Each plane is rounded outward at build: the
 *   largest lower q and the smallest upper q whose decoded plane, computed
 *   as the kernels compute it, still contains the child's box; the scale
 *   is the smallest power of two whose 255 steps reach the node's upper
 *   corner. So a quantised slot always contains the exact one and the
 *   box test stays conservative; its orders are those of the decoded
 *   boxes.
 * Per context: the traversal stack (wide_entry), 12 bytes an entry,
 * (W - 1) (depth + 1) + 1 entries, enough for any walk of this tree
 * (wide_stack_cap()), and WIDE_STACK_SLACK more. */
#ifndef ACCELBENCH_BVH_WIDE_H
#define ACCELBENCH_BVH_WIDE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include "../bvh/bvh.h"
#include "../common/slab.h"

#ifdef __cplusplus
extern "C" {
#endif

#define WIDE_LEAF 0x80000000u  /* child[] flag: a leaf, the rest is its first entry of refs */
#define WIDE_PACKED 0x40000000u /* with WIDE_LEAF: a leaf of triangles packed, the rest its first packet */
#define WIDE_INDEX 0x3FFFFFFFu  /* child[] bits of a leaf's first ref or packet */
#define WIDE_EMPTY 0xFFFFFFFFu /* child[] of an unused slot */
#define WIDE_MAX_LEAF 255      /* count[] is a byte */

typedef struct {
    float box[6][2];   /* 48: planes of the 2 children, SoA (rows above) */
    uint32_t child[2]; /*  8 */
    uint8_t count[2];  /*  2 */
    uint8_t nchildren; /*  1 */
    uint8_t pad;       /*  1 */
    uint8_t order[4];  /*  4: the slots nearest first per octant (WIDE_ORDER) */
} wide2_node;
_Static_assert(sizeof(wide2_node) == 64, "wide2_node: 2*6*4 + 2*4 + 2 + 1 + 1 + 4 = 64 bytes (one cache line)");

typedef struct {
    float box[6][4];   /* 96: planes of the 4 children, SoA (rows above) */
    uint32_t child[4]; /* 16: node index, WIDE_LEAF | first ref, or WIDE_EMPTY */
    uint8_t count[4];  /*  4: leaf primitives, 0 for interior */
    uint8_t nchildren; /*  1: used slots */
    uint8_t pad[3];    /*  3 */
    uint16_t order[4]; /*  8: the slots nearest first per octant (WIDE_ORDER) */
} wide4_node;
_Static_assert(sizeof(wide4_node) == 128, "wide4_node: 4*6*4 + 4*4 + 4 + 1 + 3 + 8 = 128 bytes (two cache lines)");

typedef struct {
    float box[6][8];
    uint32_t child[8];
    uint8_t count[8];
    uint8_t nchildren;
    uint8_t pad[7];
    uint32_t order[4];
} wide8_node;
_Static_assert(sizeof(wide8_node) == 256, "wide8_node: 8*6*4 + 8*4 + 8 + 1 + 7 + 16 = 256 bytes (four cache lines)");

typedef struct {
    uint8_t q[6][8];      /* 48: the planes of the 8 children as box rows, in units of the axis scale above origin */
    float origin[3];      /* 12: the node box's lower corner */
    uint8_t scale_exp[3]; /*  3: per axis the biased exponent of the scale, 2^(e - 127), 1..WIDE_Q_MAX_EXP */
    uint8_t nchildren;    /*  1: used slots, always the first ones */
    uint32_t child[8];    /* 32: as wide8_node's */
    uint8_t count[8];     /*  8 */
    uint8_t pad[8];       /*  8 */
    uint32_t order[4];    /* 16: as wide8_node's */
} wide8q_node;
_Static_assert(sizeof(wide8q_node) == 128,
               "wide8q_node: 48 + 12 + 3 + 1 + 32 + 8 + 8 + 16 = 128 bytes (two cache lines)");
_Static_assert(offsetof(wide8q_node, child) == 64, "wide8q_node: the box test reads only its first line");
#define WIDE_Q_MAX_EXP 247 /* 255 * 2^(247 - 127) < FLT_MAX: q * scale never overflows */

/* A quantised plane decoded: origin + q * 2^(e - 127). q * scale is exact,
 * so the sum rounds once, as the SIMD kernels' fused or separate
 * multiply-add does. */
static inline float wide_q_scale(uint8_t e)
{
    union { uint32_t u; float f; } s = {(uint32_t)e << 23};
    return s.f;
}
static inline float wide_q_plane(float origin, uint8_t q, uint8_t e) { return origin + (float)q * wide_q_scale(e); }

/* Every layout is box[6][W], child[W], count[W], nchildren at the same
 * offsets in units of W, so one accessor serves all widths. */
#define WIDE_NODE_BYTES(W) ((W) == 2 ? sizeof(wide2_node) : (W) == 4 ? sizeof(wide4_node) : sizeof(wide8_node))
_Static_assert(offsetof(wide2_node, child) == 24 * 2 && offsetof(wide2_node, count) == 28 * 2 &&
                   offsetof(wide2_node, nchildren) == 29 * 2 && offsetof(wide2_node, order) == 30 * 2,
               "wide2_node layout");
_Static_assert(offsetof(wide4_node, child) == 24 * 4 && offsetof(wide4_node, count) == 28 * 4 &&
                   offsetof(wide4_node, nchildren) == 29 * 4 && offsetof(wide4_node, order) == 30 * 4,
               "wide4_node layout");
_Static_assert(offsetof(wide8_node, child) == 24 * 8 && offsetof(wide8_node, count) == 28 * 8 &&
                   offsetof(wide8_node, nchildren) == 29 * 8 && offsetof(wide8_node, order) == 30 * 8,
               "wide8_node layout");
#define WIDE_ROWS(node) ((float *)(node))
#define WIDE_CHILD(node, W) ((uint32_t *)((char *)(node) + 24 * (W)))
#define WIDE_COUNT(node, W) ((uint8_t *)((char *)(node) + 28 * (W)))
#define WIDE_NCHILDREN(node, W) (*((uint8_t *)((char *)(node) + 29 * (W))))
/* The order of node's slots for octant oct (0..3, below): position i
 * (i = 0 nearest) holds slot (WIDE_ORDER(node, W, oct) >> 3 i) & 7. The
 * orders are the node's last 2W bytes, from WIDE_ORDER_OFFSET(W). */
#define WIDE_ORDER_OFFSET(W) (30 * (W))
#define WIDE_ORDER(node, W, oct)                                                                                      \
    ((W) == 2   ? (uint32_t)((const uint8_t *)((const char *)(node) + WIDE_ORDER_OFFSET(2)))[oct]                     \
     : (W) == 4 ? (uint32_t)((const uint16_t *)((const char *)(node) + WIDE_ORDER_OFFSET(4)))[oct]                    \
                : ((const uint32_t *)((const char *)(node) + WIDE_ORDER_OFFSET(8)))[oct])
/* The same accessors for either layout: Q says the nodes are wide8q_node
 * (w->quantized; W is then 8). */
#define WIDE_NODE_SIZE(W, Q) ((Q) ? sizeof(wide8q_node) : WIDE_NODE_BYTES(W))
#define WIDE_NODE_AT(nodes, i, W, Q) ((char *)(nodes) + (size_t)(i) * WIDE_NODE_SIZE(W, Q))
#define WIDE_CHILD_Q(node, W, Q)                                                                                      \
    ((Q) ? (uint32_t *)((char *)(node) + offsetof(wide8q_node, child)) : WIDE_CHILD(node, W))
#define WIDE_COUNT_Q(node, W, Q)                                                                                      \
    ((Q) ? (uint8_t *)((char *)(node) + offsetof(wide8q_node, count)) : WIDE_COUNT(node, W))
#define WIDE_NCHILDREN_Q(node, W, Q) ((Q) ? ((wide8q_node *)(node))->nchildren : WIDE_NCHILDREN(node, W))
#define WIDE_ORDER_Q(node, W, Q, oct)                                                                                 \
    ((Q) ? ((const uint32_t *)((const char *)(node) + offsetof(wide8q_node, order)))[oct] : WIDE_ORDER(node, W, oct))
/* The octants whose orders a node keeps: those of directions with x >= 0,
 * oct = (y < 0) | (z < 0) << 1. A ray with x < 0 walks the order of the
 * opposite octant backwards: the two orders are reverses of each other. */
#define WIDE_OCTANTS 4

/* Slot k's box from a node's rows (WIDE_ROWS). */
static inline box3 wide_slot_box(const float *rows, uint32_t W, uint32_t k)
{
    return (box3){{rows[0 * W + k], rows[2 * W + k], rows[4 * W + k]}, {rows[1 * W + k], rows[3 * W + k], rows[5 * W + k]}};
}

/* A slot's key in octant oct's order: its box centre, doubled (the order is
 * the same), projected on the octant's diagonal (1, +-1, +-1). */
static inline float wide_octant_key(box3 b, uint32_t oct)
{
    const float sy = oct & 1 ? -1.0f : 1.0f, sz = oct & 2 ? -1.0f : 1.0f;
    return (b.lo.x + b.hi.x) + sy * (b.lo.y + b.hi.y) + sz * (b.lo.z + b.hi.z);
}

/* Instruction sets of the box kernels, in order of preference. */
typedef enum { WIDE_ISA_SCALAR = 0, WIDE_ISA_SSE42, WIDE_ISA_AVX2, WIDE_ISA_AVX512, WIDE_ISA_COUNT } wide_isa;
extern const char *const wide_isa_names[WIDE_ISA_COUNT + 1]; /* "scalar", "sse42", "avx2", "avx512", NULL */

/* Whether this CPU runs isa's kernels (scalar always; the others by
 * __builtin_cpu_supports: sse4.2; avx2 and fma; avx512f and avx512vl). */
bool wide_isa_supported(wide_isa isa);
/* The best supported one. */
wide_isa wide_isa_best(void);
/* The ISA whose kernels run for isa at width: isa itself, but at width 2
 * every SIMD ISA runs the SSE4.2 kernels (two children fill half a 128-bit
 * register; wider ones would add nothing). The one place that rule is
 * written: the kernel table, the tree's isa and the CSV's params follow it. */
wide_isa wide_isa_running(wide_isa isa, uint32_t width);

typedef struct {
    void *nodes;        /* [nnodes] wide2_node, wide4_node or wide8_node, 64-byte aligned */
    uint32_t *refs;     /* [nrefs] primitive ids, by leaf */
    uint32_t width;     /* 2, 4 or 8 */
    uint32_t nnodes, nrefs;
    uint32_t nleaves;   /* leaf children over all nodes */
    uint32_t max_depth; /* deepest leaf, root = 0, a leaf one below its node */
    uint64_t nchildren; /* used slots over all nodes: interior children + leaves */
    prim_tri_packet *packets; /* [npackets] the all-triangle leaves' triangles (wide_pack_leaves), or NULL */
    uint32_t npackets;
    bool octant_order;  /* the closest-hit walk takes the children hit in the node's order for the ray's octant
                         * (order=octant), not sorted by entry distance (order=distance) */
    bool quantized;     /* compress=on: nodes are wide8q_node (wide_quantize), width 8 */
    bool spatial;       /* built with spatial splits: a primitive may be in several leaves, each slot bounding the part
                         * of it that the leaf stands for (set by the caller after wide_collapse) */
} wide_bvh;

/* Big leaves in the collapse (Embree's rule): an interior binary node that
 * would become a wide node becomes one leaf of its subtree's primitives
 * instead when they are at most max_leaf (0: never) and the SAH prices that
 * leaf no higher than the node's split, ct A + ci (N(L) A(L) + N(R) A(R))
 * against ci N A, counts in whole leaf_block blocks (ci = 1). The binary
 * builder decides its leaves locally; Embree's decides them only at the
 * children of a wide node, after splitting the largest of them until the
 * node is full (kernels/builders/bvh_builder_sah.h), so its leaves are
 * larger (up to 7 blocks of 4) and its nodes fuller. */
typedef struct {
    uint32_t max_leaf;
    float cost_traversal;
    uint32_t leaf_block;
    bool by_size; /* slots ordered by primitives below, most first (stable) */
} wide_merge;

/* The collapse of b to width with merge rule m (NULL: none), planned: the
 * wide nodes it makes, so that a caller can check a memory cap before
 * wide_collapse allocates them, and the per-binary-node runs of refs the
 * merge rule reads (collapse.c), computed once for both. */
typedef struct {
    uint32_t nodes;      /* wide nodes the collapse makes */
    struct wide_span *span; /* collapse.c's, or NULL when m needs none */
} wide_plan;
/* 0, or -1 out of memory (*plan empty). */
int wide_plan_collapse(wide_plan *plan, const bvh_t *b, uint32_t width, const wide_merge *m);
void wide_plan_free(wide_plan *plan);
/* Collapse the binary tree b to width 2, 4 or 8 (2: the binary tree's
 * own nodes, re-laid): each wide node starts from
 * the two children of a binary interior node and repeatedly replaces the
 * child of largest surface area that is interior by its two children,
 * until it has width of them or all are leaves (ties: the first in slot
 * order). Takes over b's refs (b->refs becomes NULL); b's nodes are only
 * read. plan: wide_plan_collapse's for the same b, width and m. 0, or -1
 * out of memory (w empty, b unchanged). */
int wide_collapse(wide_bvh *w, bvh_t *b, uint32_t width, const wide_merge *m, const wide_plan *plan);
void wide_free(wide_bvh *w);
/* Slot k of node ni: its box, child word and leaf count (0 interior). */
void wide_set_slot(wide_bvh *w, uint32_t ni, uint32_t k, box3 box, uint32_t child, uint32_t count);
/* Node ni's slot orders per octant (WIDE_ORDER) from its n used slots' boxes. */
void wide_set_orders(wide_bvh *w, uint32_t ni, uint32_t n);
/* tree=embree: the 8-wide tree Embree's own builder makes over boxes
 * (rtcBuildBVH with the settings of its BVH8Triangle4 scene builder,
 * wide_embree.c), on that many threads. 0, or -1 with the reason in err. */
int wide_build_embree(wide_bvh *w, const box3 *boxes, uint32_t n, uint32_t threads, char *err, size_t errlen);
/* compress=on: w's 8-wide nodes replaced by quantised ones (wide8q_node),
 * w->quantized set. 0; -1 out of memory, or (the reason in err) a node
 * whose box no scale up to 2^(WIDE_Q_MAX_EXP - 127) spans (a scene wider
 * than about FLT_MAX); w unchanged on failure. */
int wide_quantize(wide_bvh *w, char *err, size_t errlen);
/* The node orders per octant (WIDE_ORDER) of n slots with these boxes, in
 * a node of width W (collapse.c). */
void wide_orders_of(const box3 *box, uint32_t n, uint32_t W, uint32_t order[WIDE_OCTANTS]);
/* Slot k's box in node ni, decoded if w->quantized. */
box3 wide_node_slot_box(const wide_bvh *w, uint32_t ni, uint32_t k);
/* Packets wide_pack_leaves would make: ceil(count / 4) for every leaf whose
 * primitives are all triangles. */
uint64_t wide_count_packets(const wide_bvh *w, const prims_t *p);
/* Copy every all-triangle leaf's triangles into packets (prims.h
 * prim_tri_pack) and point its slot at them (WIDE_PACKED); the walk then
 * tests them with prims/tri_packet.h's bodies inlined (those of
 * prim_intersect_tris / prim_occluded_tris), which answer and count as the
 * leaf tests over refs do. Other leaves keep their refs.
 * 0, or -1 out of memory (w unchanged). */
int wide_pack_leaves(wide_bvh *w, const prims_t *p);
size_t wide_node_bytes(uint32_t width);
/* The union of the root's slots: everything (empty for an empty tree). */
box3 wide_bounds(const wide_bvh *w);
/* Bytes held: nodes and refs. */
size_t wide_memory(const wide_bvh *w);
/* Stack entries a walk of w can need at most. */
uint32_t wide_stack_cap(const wide_bvh *w);
/* The cost model (wide_predict.c): counters per line that meets the
 * root's box, for lines uniform over those, walked whole. */
typedef struct {
    double steps, box_tests, prim_tests; /* all -1: out of memory */
} wide_prediction;
wide_prediction wide_predict(const wide_bvh *w);
/* Statistics (accel.h): nodes, leaves, max_depth, avg_leaf_prims,
 * refs_per_prim, avg_children, and wide_predict's
 * predicted_box_tests_per_ray, predicted_tests_per_ray and
 * predicted_steps_per_ray. */
int wide_stats(const wide_bvh *w, uint32_t nprims, accel_stat *out, int max);
/* For tests: every node's slots hold their children's bounds (a child
 * node's box is the union of its slots; a leaf's holds its primitives'
 * boxes[], or with w->spatial meets them), unused slots empty, every
 * primitive in one leaf (w->spatial: in at least one), the counts
 * right. 0, or -1 with the first failure in err. */
int wide_check(const wide_bvh *w, const box3 *boxes, uint32_t n, char *err, size_t errlen);

/* A stack entry: a child (as child[] holds it), its leaf count and the
 * distance at which the ray enters its box. The stack has
 * wide_stack_cap(w) + WIDE_STACK_SLACK of them: order=octant's push writes
 * every slot of a node and keeps the hit ones (wide_push_octant). */
typedef struct {
    uint32_t child;
    uint32_t count;
    float t;
} wide_entry;
_Static_assert(sizeof(wide_entry) == 12, "wide_entry is 12 bytes");
#define WIDE_STACK_SLACK 8

/* The four queries of one width and instruction set. stack has
 * wide_stack_cap(w) entries. The accel.h contract; the _fast ones count
 * nothing and give the same answers bit for bit. */
typedef struct {
    bool (*intersect)(const wide_bvh *w, const prims_t *p, wide_entry *stack, const ray_t *ray, hit_t *hit,
                      counters_t *c);
    bool (*occluded)(const wide_bvh *w, const prims_t *p, wide_entry *stack, const ray_t *ray, counters_t *c);
    bool (*intersect_fast)(const wide_bvh *w, const prims_t *p, wide_entry *stack, const ray_t *ray, hit_t *hit);
    bool (*occluded_fast)(const wide_bvh *w, const prims_t *p, wide_entry *stack, const ray_t *ray);
} wide_kernels;

/* The kernels of isa for width 2, 4 or 8 (those of
 * wide_isa_running(isa, width)), on quantised nodes (compress=on, width 8)
 * or not, with fma=on's fused distances or not, robust=on's conservative
 * box test and watertight triangle packets or robust=off's plain ones
 * (wide_walk.h); NULL when this build or that ISA has none for it (a
 * non-x86 target: only scalar; fma=on under SSE4.2, which has no fused
 * multiply-add). */
const wide_kernels *wide_kernels_for(wide_isa isa, uint32_t width, bool quantized, bool fused, bool robust);

/* For tests: the reference kernel's hit mask for box in slot 0 of an
 * 8-wide node whose other slots are empty, against ray's [tnear, tfar],
 * with fma=on's arithmetic (fused) or fma=off's. */
unsigned wide_box_probe(const ray_t *ray, box3 box, bool fused);

/* Per ISA the kernels by node layout, [fused] and [robust] (0: off, 1:
 * on; wide_traverse_*.c); an entry an ISA lacks is all NULL. */
enum { WIDE_LAYOUT_2, WIDE_LAYOUT_4, WIDE_LAYOUT_8, WIDE_LAYOUT_8Q, WIDE_LAYOUTS };
extern const wide_kernels wide_kernels_scalar[WIDE_LAYOUTS][2][2];
#if defined(__x86_64__) || defined(__i386__)
extern const wide_kernels wide_kernels_sse42[WIDE_LAYOUTS][2][2];
extern const wide_kernels wide_kernels_avx2[WIDE_LAYOUTS][2][2];
extern const wide_kernels wide_kernels_avx512[WIDE_LAYOUTS][2][2];
#endif

#ifdef __cplusplus
}
#endif

#endif
