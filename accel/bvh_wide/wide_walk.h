/* wide_walk.h: the one walk of the wide BVH (wide.h), written once and
 * compiled per width, instruction set, query and counting.
 *
 * Each wide_traverse_<isa>.c defines WIDE_TARGET (a target attribute such
 * as __attribute__((target("avx2,fma"))), nothing for scalar) before
 * including this file, and passes its box kernel to wide_walk(). Every
 * function here carries WIDE_TARGET and is always inlined, so each entry
 * point is one function compiled for its instruction set with its kernel
 * inlined and no indirect call per node (the pattern of walk.h and
 * accel/common/prim_hit.h). No file is compiled with global -m flags: the
 * instruction set is a per-function attribute, chosen at build() time.
 *
 * The walk (Wald et al. 2008, Dammertz et al. 2008): visit a node, test all
 * its children's boxes against [tnear, end] at once (end: the closest hit
 * so far, or tfar for an any-hit query), sort the children that are hit by
 * entry distance (ties by slot: the order is a function of the distances
 * alone, so every kernel that computes the same distances walks the same
 * way; an any-hit query takes them in slot order unsorted, as Embree's
 * any-hit traversal does; docs/accels/wide-bvh.md has the measurement),
 * push them farthest first, pop the nearest (the nearest, when
 * interior, is visited at once without the push and pop). With
 * order=octant (w->octant_order) the closest-hit walk takes the children
 * hit in the node's order for the ray's octant instead (wide.h,
 * wide_push_octant), one interior child hit visited at once, the rest
 * pushed and the nearest popped. A popped entry that
 * starts beyond the closest hit is dropped; a popped leaf is tested through
 * prims/ (its packets by the packet test inlined here with the ray's shear
 * set up once per ray, or one prim_*_leaf call over its refs); an any-hit
 * query ends at the first
 * occluder. The stack is the caller's, wide_stack_cap() entries, which no
 * walk of its tree can overflow.
 *
 * The box test of one child is slab_clip_robust()'s (accel/common/slab.h)
 * with the far scale folded into the ray: per axis tn = (near - org) * inv,
 * tf = (far - org) * inv_far where inv_far = inv * SLAB_FAR_SCALE, rounded
 * once per ray, with the near plane chosen by the sign of inv; a = max(tn,
 * a) and z = min(tf, z) as "if (tn > a) a = tn" does (a NaN never wins: the
 * SSE/AVX max and min return their second operand when either is NaN); hit
 * when a <= z. The far t still carries four roundings (the difference, inv,
 * inv_far, the product), each at most one unit 2^-24, so SLAB_FAR_SCALE
 * = 1 + 2^-21 still covers them (Ize 2013's bound, as slab.h's), and a box
 * the exact ray meets is never rejected by rounding. The interval enters
 * with its start raised to at least -FLT_MAX and its end lowered to at
 * most FLT_MAX (wide_ray_init, wide_t1): then a > -inf and z < inf, so
 * "a <= z" alone is slab_clip's "a <= z, a < inf, z > -inf" (one
 * comparison per slot instead of three; test_champion's overflow test).
 * fma=on (wide_fused_init below) computes each plane's distance with one
 * fused multiply-add and directed per-ray constants instead, conservative
 * with no far scale; the interval and the comparison are the same.
 * robust=off (R false, a compile-time constant as F is) keeps the kernels
 * and the interval but feeds them plain constants (wide_ray_init: no far
 * scale, no directed rounding), so the box test is exact only to
 * rounding, and tests the packets by Moller and Trumbore's test
 * (prims/tri_packet_mt.h) instead of the watertight one, with no shear.
 * The SIMD kernels give the scalar one's distances bit for bit (no
 * contraction: the build has -ffp-contract=off; fma=on's fused
 * multiply-adds are fmaf in the scalar kernel, and compress=on's decoding
 * of a plane as origin + q * scale rounds as the scalar multiply and add
 * do because that product is exact).
 *
 * Counters: box_tests = child boxes tested (the used slots of every node
 * visited), steps = nodes visited plus leaves tested; prim_tests and
 * prim_hits by prims/. Counted in locals, added once. */
#ifndef ACCELBENCH_BVH_WIDE_WALK_H
#define ACCELBENCH_BVH_WIDE_WALK_H

#include <math.h>
#include "wide.h"

#ifndef WIDE_TARGET
#define WIDE_TARGET
#endif
#define WIDE_FN static inline __attribute__((always_inline)) WIDE_TARGET
/* The triangle packet tests inlined into the walk, compiled for its
 * instruction set (prims/tri_packet.h: the same answers bit for bit
 * as prims.h's prim_intersect_tris and prim_occluded_tris). With the test
 * behind a call, every leaf cost the walk a spill and reload of the ray's
 * broadcast planes (all vector registers are the caller's to save) and the
 * ray's shear set up again. */
#define TRI_PACKET_TARGET WIDE_TARGET
#include "../../prims/tri_packet.h"
/* robust=off's Moller-Trumbore packet test, likewise inlined (its SIMD
 * body where the includer defines TRI_PACKET_MT_SSE, fused where it
 * defines TRI_PACKET_MT_FMA; else the reference's lanes in plain C). */
#include "../../prims/tri_packet_mt.h"

/* Per-ray constants of the box kernels. */
typedef struct {
    float org[3], inv[3];       /* origin, 1 / direction (+-inf for +-0) */
    float inv_far[3];           /* inv * SLAB_FAR_SCALE: the far planes' robust reciprocal (robust=off: inv) */
    float nmul[3], nsub[3];     /* fma=on: a near plane's distance is fma(plane, nmul, -nsub) (wide_fused_init;
                                 * robust=off: inv and org * inv) */
    float fmul[3], fsub[3];     /* and a far plane's fma(plane, fmul, -fsub) */
    float t0, tfar;             /* the ray's tnear, at least -FLT_MAX, and tfar, at most FLT_MAX */
    uint32_t near[3], far[3];   /* per axis the box row of the near and far plane: 2 axis + (inv < 0) and the other */
    uint32_t oct;               /* the octant whose order the walk takes (WIDE_ORDER) */
    bool backwards;             /* and whether backwards: x < 0, the opposite octant's order */
    bool sheared;               /* ray_shear's answer for the packet tests: false, no triangle can be hit */
    shear_t shear;              /* the ray's watertight shear (prims/shear.h), once per ray instead of per leaf;
                                 * robust=off: neither set (its packet test needs no shear) */
} wide_ray;

/* fma=on's per-ray constants: per axis, a near plane pl's entry distance
 * is fma(pl, nmul, -nsub) and a far plane's exit distance fma(pl, fmul,
 * -fsub), each rounded once, in place of fma=off's subtraction and
 * multiplication (one instruction and one rounding a plane instead of
 * two, and no far scale).
 *
 * Why it is conservative. Let D = 1/d exactly for the direction's
 * component d. The constants satisfy |nmul| <= |D| <= |fmul| (both of D's
 * sign), nsub >= o nmul and fsub <= o fmul. A near plane's value before
 * rounding is then pl nmul - nsub <= (pl - o) nmul, which is at most the
 * exact distance (pl - o) D when that is >= 0, and <= 0 when it is not; a
 * far plane's is pl fmul - fsub >= (pl - o) fmul, at least (pl - o) D when
 * that is >= 0. The harness traces only ray_traceable rays, whose interval
 * starts at tnear >= 0, so a box the exact ray meets at some t* >= tnear
 * has every near value at most t* and every far one of the axes at least
 * t* before rounding; rounding to nearest is monotone and keeps floats, so
 * after it every entry distance and tnear are at most round(t*) and every
 * exit distance and the interval's end at least round(t*): "a <= z" holds.
 * (Along d = +-0 the same holds with D = +-inf: nmul = +-FLT_MAX and fmul
 * = +-inf, the NaNs of inf - inf fall through the max and min.)
 *
 * The constants, branch-free in float: i = 1/d is within 2^-24 of D
 * relatively (|d| <= 2^60, so i is normal), i (1 -+ 2^-22) rounded stays
 * below and above |D| (nmul capped at FLT_MAX); a product p = o m rounded
 * is moved away from o m by |p| 2^-22 + 2^-149 (at least two of its units
 * in the last place, or the smallest subnormal), clamped to -FLT_MAX for
 * nsub and FLT_MAX for fsub when it overflows (also the NaN of o = 0
 * times fmul = inf: the far distances are then +-inf or NaN either way).
 * The same C on every instruction set (no contraction), so every kernel
 * sees the same constants. */
WIDE_FN void wide_fused_init(wide_ray *r, const float org[3], const float dir[3])
{
    for (uint32_t a = 0; a < 3; a++) {
        const float i = 1.0f / dir[a], lo = i * (1.0f - 0x1p-22f), hi = i * (1.0f + 0x1p-22f);
        const float nmul = fabsf(lo) <= FLT_MAX ? lo : copysignf(FLT_MAX, lo);
        const float p = org[a] * nmul, q = org[a] * hi;
        const float nsub = p + (fabsf(p) * 0x1p-22f + 0x1p-149f), fsub = q - (fabsf(q) * 0x1p-22f + 0x1p-149f);
        r->nmul[a] = nmul;
        r->fmul[a] = hi;
        r->nsub[a] = nsub >= -FLT_MAX ? nsub : -FLT_MAX; /* -inf + inf is NaN: clamped too */
        r->fsub[a] = fsub <= FLT_MAX ? fsub : FLT_MAX;
    }
}

/* false: the ray cannot hit anything (slab_ray_init's refusals: a NaN or
 * infinite component, a zero direction). The fields are slab_ray_init's,
 * written one by one: copying them out of a slab_ray made the compiler
 * move them through the stack in pieces that stalled store forwarding (8 %
 * of the walk's time in perf).
 * R (robust=on) as above. robust=off (!R): the plain constants of a
 * non-conservative box test, as Embree's default and tinybvh use: the far
 * planes take inv itself (no SLAB_FAR_SCALE), and fma=on's constants are
 * inv and org * inv rounded to nearest (no directed rounding), so a plane's
 * distance is (plane - org) * inv, or fma(plane, inv, -org * inv); a box
 * the exact ray grazes may be missed by a rounding. Along a zero direction
 * component inv is +-inf and fma=on's distances may be NaN (inf - inf,
 * 0 * inf), which the max and min drop: that slab then clips nothing (a
 * box taken that the robust test would reject, never one missed). No
 * shear: robust=off's triangle test does not use it. */
WIDE_FN bool wide_ray_init(wide_ray *r, const ray_t *ray, const bool F, const bool R)
{
    const vec3 o = ray->org, d = ray->dir;
    if (!v3_finite(o) || !v3_finite(d) || (d.x == 0.0f && d.y == 0.0f && d.z == 0.0f)) return false;
    const float org[3] = {o.x, o.y, o.z}, dir[3] = {d.x, d.y, d.z};
    for (uint32_t a = 0; a < 3; a++) {
        float inv = 1.0f / dir[a]; /* +-inf for +-0 */
        uint32_t neg = inv < 0.0f;
        r->org[a] = org[a];
        r->inv[a] = inv;
        r->inv_far[a] = R ? inv * SLAB_FAR_SCALE : inv;
        r->near[a] = 2 * a + neg;
        r->far[a] = 2 * a + 1 - neg;
    }
    /* The octant by the signs of inv (a -0 component counts as negative,
     * as it does for the planes). */
    r->backwards = r->near[0] & 1;
    r->oct = ((r->near[1] & 1) | (r->near[2] & 1) << 1) ^ (r->backwards ? 3u : 0u);
    /* The packet tests' shear, set up here once per ray (prim_*_tris set it
     * up per leaf), not lazily at the first packed leaf, which is slower on
     * most rays; it costs the rays that meet no leaf (docs/accels/
     * wide-bvh.md, Measured). */
    if (R) r->sheared = ray_shear(d, &r->shear);
    if (F && R) wide_fused_init(r, org, dir);
    if (F && !R)
        for (uint32_t a = 0; a < 3; a++) {
            r->nmul[a] = r->fmul[a] = r->inv[a];
            r->nsub[a] = r->fsub[a] = org[a] * r->inv[a];
        }
    r->t0 = ray->tnear > -FLT_MAX ? ray->tnear : -FLT_MAX; /* rayset.c refuses NaN tnear and tfar */
    r->tfar = ray->tfar < FLT_MAX ? ray->tfar : FLT_MAX;
    return true;
}

/* The end of the box kernels' interval: the closest hit so far (or tfar),
 * at most FLT_MAX (see the box test above). */
WIDE_FN float wide_t1(float t) { return t < FLT_MAX ? t : FLT_MAX; }

/* A box kernel: the W children of node against [t0, t1] (t0 >= -FLT_MAX,
 * t1 <= FLT_MAX); returns the mask of slots hit and writes every slot's
 * entry distance a into tn[0 .. W). */
typedef unsigned (*wide_box_fn)(const wide_ray *r, const void *node, float t0, float t1, float *tn);

/* One plane's distance in the reference kernel: near (or far) plane pl of
 * axis ax, by fma=on's fused multiply-add (fmaf, exact as the SIMD
 * kernels' instructions are) or fma=off's subtract and multiply. */
WIDE_FN float wide_plane_t(const wide_ray *r, float pl, uint32_t ax, const bool far, const bool F)
{
    if (F) return far ? fmaf(pl, r->fmul[ax], -r->fsub[ax]) : fmaf(pl, r->nmul[ax], -r->nsub[ax]);
    return (pl - r->org[ax]) * (far ? r->inv_far[ax] : r->inv[ax]);
}

/* The reference kernel, one slot at a time (isa=scalar). */
WIDE_FN unsigned wide_box_scalar(const wide_ray *r, const float *rows, const uint32_t W, float t0, float t1,
                                 float *tn, const bool F)
{
    unsigned mask = 0;
    for (uint32_t k = 0; k < W; k++) {
        float a = t0, z = t1;
        for (uint32_t ax = 0; ax < 3; ax++) {
            float n = wide_plane_t(r, rows[r->near[ax] * W + k], ax, false, F);
            float f = wide_plane_t(r, rows[r->far[ax] * W + k], ax, true, F);
            if (n > a) a = n;
            if (f < z) z = f;
        }
        tn[k] = a;
        if (a <= z) mask |= 1u << k;
    }
    return mask;
}

/* The reference kernel on a quantised node (compress=on): each plane
 * decoded (wide_q_plane), then the test above; the unused slots, which
 * decode to a box at the origin, masked off. */
WIDE_FN unsigned wide_box_scalar_q(const wide_ray *r, const wide8q_node *nd, float t0, float t1, float *tn,
                                   const bool F)
{
    unsigned mask = 0;
    for (uint32_t k = 0; k < 8; k++) {
        float a = t0, z = t1;
        for (uint32_t ax = 0; ax < 3; ax++) {
            const float near = wide_q_plane(nd->origin[ax], nd->q[r->near[ax]][k], nd->scale_exp[ax]);
            const float far = wide_q_plane(nd->origin[ax], nd->q[r->far[ax]][k], nd->scale_exp[ax]);
            float n = wide_plane_t(r, near, ax, false, F);
            float f = wide_plane_t(r, far, ax, true, F);
            if (n > a) a = n;
            if (f < z) z = f;
        }
        tn[k] = a;
        if (a <= z) mask |= 1u << k;
    }
    return mask & ((1u << nd->nchildren) - 1);
}

/* A leaf: its packets by the watertight test (R) or robust=off's
 * Moller-Trumbore test (fused as the box test is, F), or its refs through
 * prims/ (the same tests either way: prims/' own, watertight). */
WIDE_FN bool wide_leaf(const wide_bvh *w, const prims_t *p, const wide_ray *r, uint32_t child, uint32_t count,
                       const ray_t *ray, hit_t *hit, counters_t *c, const bool shadow, const bool counting,
                       const bool F, const bool R)
{
    if (child & WIDE_PACKED) {
        const prim_tri_packet *pk = w->packets + (child & WIDE_INDEX);
        if (!R) {
            if (shadow) return tripk_mt_occluded(pk, count, ray, c, counting, F);
            return tripk_mt_intersect(pk, count, ray, hit, c, counting, F);
        }
        if (shadow) return tripk_occluded(&r->shear, r->sheared, pk, count, ray, c, counting);
        return tripk_intersect(&r->shear, r->sheared, pk, count, ray, hit, c, counting);
    }
    const uint32_t *ids = w->refs + (child & WIDE_INDEX);
    if (shadow) return counting ? prim_occluded_leaf(p, ids, count, ray, c) : prim_occluded_leaf_fast(p, ids, count, ray);
    return counting ? prim_intersect_leaf(p, ids, count, ray, hit, c) : prim_intersect_leaf_fast(p, ids, count, ray, hit);
}

/* order=octant: push the children hit (mask) of node in the node's order
 * for the ray's octant, farthest first, at sp; returns the new sp. Every
 * slot is written, the stack pointer advanced past the hit ones only (no
 * branch on the mask; the stack has WIDE_STACK_SLACK entries beyond its
 * capacity for it). */
WIDE_FN uint32_t wide_push_octant(const wide_ray *r, const char *node, unsigned mask, const float *tn,
                                  wide_entry *stack, uint32_t sp, const uint32_t W, const bool Q)
{
    const uint32_t perm = WIDE_ORDER_Q(node, W, Q, r->oct);
    const uint32_t *child = WIDE_CHILD_Q(node, W, Q);
    const uint8_t *count = WIDE_COUNT_Q(node, W, Q);
    for (uint32_t i = 0; i < W; i++) {
        uint32_t k = (perm >> 3 * (r->backwards ? i : W - 1 - i)) & 7;
        stack[sp] = (wide_entry){child[k], count[k], tn[k]};
        sp += (mask >> k) & 1;
    }
    return sp;
}

/* A child about to be pushed, fetched while the nodes and leaves before
 * it are visited: an interior child's box rows (its cache lines), a packed
 * leaf's first packet (whose first load takes a large share of the packet
 * test's time). A small gain at most (docs/accels/wide-bvh.md, Measured). */
WIDE_FN void wide_prefetch(const wide_bvh *w, uint32_t ch, const uint32_t W, const bool Q)
{
    if (!(ch & WIDE_LEAF)) {
        const char *nb = WIDE_NODE_AT(w->nodes, ch, W, Q);
        __builtin_prefetch(nb);
        if (W >= 4) __builtin_prefetch(nb + 64);
        if (W == 8 && !Q) __builtin_prefetch(nb + 128);
    } else if (ch & WIDE_PACKED) {
        const char *pb = (const char *)(w->packets + (ch & WIDE_INDEX));
        __builtin_prefetch(pb);
        __builtin_prefetch(pb + 64);
        __builtin_prefetch(pb + 128);
    }
}

/* The walk for one ordering (octant: order=octant's, a constant where
 * wide_walk calls it, so each ordering is compiled on its own: with the
 * tree's order tested per node the default walk was 8 % slower on Sponza's
 * primary rays, 2-5 % without). */
WIDE_FN bool wide_walk_ordered(const wide_bvh *w, const prims_t *p, wide_entry *stack, const ray_t *ray,
                               hit_t *hit, counters_t *c, const uint32_t W, const bool Q, const bool F,
                               const bool R, const wide_box_fn box, const bool shadow, const bool counting,
                               const bool octant)
{
    wide_ray r;
    if (!w->nnodes || !wide_ray_init(&r, ray, F, R)) return false;
    uint64_t nbox = 0, nsteps = 0;
    uint32_t sp = 0, cur = 0;
    bool occluded = false;
    for (;;) {
        /* Visit node cur: all its children's boxes at once. */
        const char *node = WIDE_NODE_AT(w->nodes, cur, W, Q);
        const uint32_t *child = WIDE_CHILD_Q(node, W, Q);
        const uint8_t *count = WIDE_COUNT_Q(node, W, Q);
        const uint32_t nch = WIDE_NCHILDREN_Q(node, W, Q);
        nsteps++;
        nbox += nch;
        float tn[8] __attribute__((aligned(32)));
        /* The ray's constants read from memory at every node (the empty
         * asm makes the pointer opaque, so they are not hoisted into
         * registers): kept in registers, they were spilled and reloaded
         * around every leaf test that is a call (all vector registers are
         * the caller's to save), on the hot pop path. */
        const wide_ray *rp = &r;
        __asm__("" : "+r"(rp));
        unsigned mask = box(rp, node, rp->t0, shadow ? rp->tfar : wide_t1(hit->t), tn);

        if (octant) {
            /* order=octant: one interior child hit is visited next; more,
             * or a leaf, are pushed in the node's order, the nearest popped
             * first below. */
            if (mask && !(mask & (mask - 1)) && !(child[__builtin_ctz(mask)] & WIDE_LEAF)) {
                cur = child[__builtin_ctz(mask)];
                continue;
            }
            sp = wide_push_octant(&r, node, mask, tn, stack, sp, W, Q);
        } else {
            /* order=distance: the children hit, nearest first (ties by
             * slot; any hit: slot order, unsorted, as Embree's any-hit
             * traversal does), pushed farthest first. The nearest child,
             * when interior, is visited next without a push and pop (it
             * cannot be dropped: its a <= z <= the current end); otherwise
             * it is pushed last, so popped first, like the rest. One or two
             * children hit (most nodes: Embree's traversal has the same two
             * cases, kernels/bvh/bvh_traverser1.h) take branches of their own, the same
             * order as the general insertion sort below. */
            if (mask) {
                const uint32_t k0 = (uint32_t)__builtin_ctz(mask);
                const unsigned rest = mask & (mask - 1);
                if (!rest) {
                    if (!(child[k0] & WIDE_LEAF)) {
                        cur = child[k0];
                        continue;
                    }
                    stack[sp++] = (wide_entry){child[k0], count[k0], tn[k0]};
                } else if (!(rest & (rest - 1))) {
                    const uint32_t k1 = (uint32_t)__builtin_ctz(rest);
                    const bool swap = !shadow && tn[k0] > tn[k1];
                    const uint32_t near = swap ? k1 : k0, far = swap ? k0 : k1;
                    wide_prefetch(w, child[far], W, Q);
                    stack[sp++] = (wide_entry){child[far], count[far], tn[far]};
                    if (!(child[near] & WIDE_LEAF)) {
                        cur = child[near];
                        continue;
                    }
                    stack[sp++] = (wide_entry){child[near], count[near], tn[near]};
                } else {
                    uint32_t ord[8], m = 0;
                    while (mask) {
                        uint32_t k = (uint32_t)__builtin_ctz(mask), j = m++;
                        mask &= mask - 1;
                        while (!shadow && j > 0 && tn[ord[j - 1]] > tn[k]) ord[j] = ord[j - 1], j--;
                        ord[j] = k;
                    }
                    uint32_t last = !(child[ord[0]] & WIDE_LEAF) ? 1 : 0;
                    for (uint32_t i = m; i-- > last;) {
                        wide_prefetch(w, child[ord[i]], W, Q);
                        stack[sp++] = (wide_entry){child[ord[i]], count[ord[i]], tn[ord[i]]};
                    }
                    if (last) {
                        cur = child[ord[0]];
                        continue;
                    }
                }
            }
        }

        /* Pop until an interior node: test the leaves on the way, drop
         * what starts beyond the closest hit. */
        for (;;) {
            if (!sp) goto done;
            wide_entry e = stack[--sp];
            if (!shadow && e.t > hit->t) continue;
            if (!(e.child & WIDE_LEAF)) {
                cur = e.child;
                break;
            }
            nsteps++;
            if (wide_leaf(w, p, &r, e.child, e.count, ray, hit, c, shadow, counting, F, R) && shadow) {
                occluded = true;
                goto done;
            }
        }
    }
done:
    if (counting) {
        c->box_tests += nbox;
        c->steps += nsteps;
    }
    return shadow ? occluded : hit->prim != HIT_NONE;
}

WIDE_FN bool wide_walk(const wide_bvh *w, const prims_t *p, wide_entry *stack, const ray_t *ray, hit_t *hit,
                       counters_t *c, const uint32_t W, const bool Q, const bool F, const bool R,
                       const wide_box_fn box, const bool shadow, const bool counting)
{
    if (!shadow && w->octant_order)
        return wide_walk_ordered(w, p, stack, ray, hit, c, W, Q, F, R, box, false, counting, true);
    return wide_walk_ordered(w, p, stack, ray, hit, c, W, Q, F, R, box, shadow, counting, false);
}

/* The entry points of width W with kernel BOX (Q: on quantised nodes; F:
 * BOX computes fma=on's fused distances), as functions named
 * PREFIX_intersect etc. (robust=on) and PREFIX_mt_intersect etc.
 * (robust=off: the box constants and triangle test of wide_ray_init and
 * wide_leaf), and a wide_kernels initialiser of each. */
#define WIDE_ENTRY_POINTS(PREFIX, W, Q, F, BOX) WIDE_ENTRY_POINTS_(PREFIX, W, Q, F, BOX) /* PREFIX expanded first */
#define WIDE_ENTRY_POINTS_(PREFIX, W, Q, F, BOX)                                                                      \
    WIDE_ENTRY_POINTS_R(PREFIX, W, Q, F, true, BOX)                                                                    \
    WIDE_ENTRY_POINTS_R(PREFIX##_mt, W, Q, F, false, BOX)
#define WIDE_ENTRY_POINTS_R(PREFIX, W, Q, F, R, BOX)                                                                   \
    WIDE_TARGET static bool PREFIX##_intersect(const wide_bvh *w, const prims_t *p, wide_entry *st, const ray_t *ray, \
                                               hit_t *hit, counters_t *c)                                              \
    {                                                                                                                  \
        return wide_walk(w, p, st, ray, hit, c, W, Q, F, R, BOX, false, true);                                         \
    }                                                                                                                  \
    WIDE_TARGET static bool PREFIX##_occluded(const wide_bvh *w, const prims_t *p, wide_entry *st, const ray_t *ray,  \
                                              counters_t *c)                                                           \
    {                                                                                                                  \
        hit_t none = hit_none(ray);                                                                                    \
        return wide_walk(w, p, st, ray, &none, c, W, Q, F, R, BOX, true, true);                                        \
    }                                                                                                                  \
    WIDE_TARGET static bool PREFIX##_intersect_fast(const wide_bvh *w, const prims_t *p, wide_entry *st,              \
                                                    const ray_t *ray, hit_t *hit)                                      \
    {                                                                                                                  \
        return wide_walk(w, p, st, ray, hit, NULL, W, Q, F, R, BOX, false, false);                                     \
    }                                                                                                                  \
    WIDE_TARGET static bool PREFIX##_occluded_fast(const wide_bvh *w, const prims_t *p, wide_entry *st,               \
                                                   const ray_t *ray)                                                   \
    {                                                                                                                  \
        hit_t none = hit_none(ray);                                                                                    \
        return wide_walk(w, p, st, ray, &none, NULL, W, Q, F, R, BOX, true, false);                                    \
    }
#define WIDE_KERNELS(PREFIX) WIDE_KERNELS_(PREFIX)
#define WIDE_KERNELS_(PREFIX) {PREFIX##_intersect, PREFIX##_occluded, PREFIX##_intersect_fast, PREFIX##_occluded_fast}
/* Both robust settings of WIDE_ENTRY_POINTS(PREFIX, ...), indexed [robust]:
 * [0] robust=off, [1] robust=on. */
#define WIDE_KERNELS_RO(PREFIX) WIDE_KERNELS_RO_(PREFIX)
#define WIDE_KERNELS_RO_(PREFIX) {WIDE_KERNELS(PREFIX##_mt), WIDE_KERNELS(PREFIX)}

#endif
