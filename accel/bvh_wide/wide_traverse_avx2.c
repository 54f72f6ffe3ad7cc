/* wide_traverse_avx2.c: the wide BVH's walk (wide_walk.h) with AVX2 box
 * kernels: a BVH8 node's 8 children in one 256-bit register, a BVH4 node's
 * 4 in a 128-bit one (VEX-encoded), the body shared with the AVX-512
 * kernels (wide_traverse_avx.h), the comparison by vector masks and a
 * movemask. Compiled for AVX2 and FMA by per-function target attributes
 * only (the build does not contract; the FMA intrinsics are fma=on's
 * distances, which the scalar reference computes with fmaf, and
 * compress=on's plane decoding, whose product is exact, so distances stay
 * the scalar kernel's), run only where __builtin_cpu_supports says so
 * (wide_isa.c). */
#if defined(__x86_64__) || defined(__i386__)
#define WIDE_TARGET __attribute__((target("avx2,fma")))
#define WIDE_AVX_MASK4(a, z) ((unsigned)_mm_movemask_ps(_mm_cmp_ps(a, z, _CMP_LE_OQ)))
#define WIDE_AVX_MASK8(a, z) ((unsigned)_mm256_movemask_ps(_mm256_cmp_ps(a, z, _CMP_LE_OQ)))
#define WIDE_AVX_NAME(x) avx2_##x
#define WIDE_AVX_TABLE wide_kernels_avx2
#include "wide_traverse_avx.h"
#endif
