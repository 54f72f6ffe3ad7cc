/* wide_isa.c: which box kernels this CPU can run, and the kernel tables by
 * instruction set and width (wide.h). One binary for every x86-64 machine:
 * the SIMD kernels are compiled with per-function target attributes and
 * chosen here at run time with __builtin_cpu_supports, never by -march. */
#include "wide.h"

bool wide_isa_supported(wide_isa isa)
{
#if defined(__x86_64__) || defined(__i386__)
    __builtin_cpu_init(); /* needed before main (constructors), harmless after */
    switch (isa) {
    case WIDE_ISA_SCALAR: return true;
    case WIDE_ISA_SSE42: return __builtin_cpu_supports("sse4.2");
    case WIDE_ISA_AVX2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case WIDE_ISA_AVX512: return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl");
    default: return false;
    }
#else
    return isa == WIDE_ISA_SCALAR;
#endif
}

wide_isa wide_isa_best(void)
{
    for (int i = WIDE_ISA_COUNT - 1; i > 0; i--)
        if (wide_isa_supported((wide_isa)i)) return (wide_isa)i;
    return WIDE_ISA_SCALAR;
}

wide_isa wide_isa_running(wide_isa isa, uint32_t width)
{
    return width == 2 && isa != WIDE_ISA_SCALAR && isa < WIDE_ISA_COUNT ? WIDE_ISA_SSE42 : isa;
}

const wide_kernels *wide_kernels_for(wide_isa isa, uint32_t width, bool quantized, bool fused, bool robust)
{
    const int layout = quantized    ? WIDE_LAYOUT_8Q
                       : width == 8 ? WIDE_LAYOUT_8
                       : width == 4 ? WIDE_LAYOUT_4
                                    : WIDE_LAYOUT_2;
    if (quantized && width != 8) return NULL;
    const wide_kernels *k = NULL;
    switch (wide_isa_running(isa, width)) { /* at width 2: scalar or sse42, the tables that have it */
    case WIDE_ISA_SCALAR: k = &wide_kernels_scalar[layout][fused][robust]; break;
#if defined(__x86_64__) || defined(__i386__)
    case WIDE_ISA_SSE42: k = &wide_kernels_sse42[layout][fused][robust]; break;
    case WIDE_ISA_AVX2: k = &wide_kernels_avx2[layout][fused][robust]; break;
    case WIDE_ISA_AVX512: k = &wide_kernels_avx512[layout][fused][robust]; break;
#endif
    default: return NULL;
    }
    return k->intersect ? k : NULL;
}
