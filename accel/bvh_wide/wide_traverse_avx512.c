/* wide_traverse_avx512.c: the wide BVH's walk (wide_walk.h) with AVX-512
 * box kernels: the AVX2 arithmetic on 128- and 256-bit registers
 * (AVX-512VL; the body shared with the AVX2 kernels, wide_traverse_avx.h),
 * the comparison into a mask register instead of vector masks and a
 * movemask. Compiled for AVX-512F and VL by per-function target
 * attributes only, run only where __builtin_cpu_supports says so
 * (wide_isa.c). */
#if defined(__x86_64__) || defined(__i386__)
#define WIDE_TARGET __attribute__((target("avx512f,avx512vl,avx2,fma")))
#define WIDE_AVX_MASK4(a, z) ((unsigned)_mm_cmp_ps_mask(a, z, _CMP_LE_OQ))
#define WIDE_AVX_MASK8(a, z) ((unsigned)_mm256_cmp_ps_mask(a, z, _CMP_LE_OQ))
#define WIDE_AVX_NAME(x) avx512_##x
#define WIDE_AVX_TABLE wide_kernels_avx512
#include "wide_traverse_avx.h"
#endif
