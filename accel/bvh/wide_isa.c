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

const wide_kernels *wide_kernels_for(wide_isa isa, uint32_t width)
{
    int k = width == 8 ? 1 : width == 2 ? 2 : 0; /* the tables' order: width 4, 8, 2 */
    isa = wide_isa_running(isa, width); /* at width 2: scalar or sse42, the tables that have it */
    switch (isa) {
    case WIDE_ISA_SCALAR: return &wide_kernels_scalar[k];
#if defined(__x86_64__) || defined(__i386__)
    case WIDE_ISA_SSE42: return &wide_kernels_sse42[k];
    case WIDE_ISA_AVX2: return &wide_kernels_avx2[k];
    case WIDE_ISA_AVX512: return &wide_kernels_avx512[k];
#endif
    default: return NULL;
    }
}

const wide_kernels *wide_kernels_quantized(wide_isa isa)
{
    switch (isa) {
    case WIDE_ISA_SCALAR: return &wide_kernels_scalar_q;
#if defined(__x86_64__) || defined(__i386__)
    case WIDE_ISA_SSE42: return &wide_kernels_sse42_q;
    case WIDE_ISA_AVX2: return &wide_kernels_avx2_q;
    case WIDE_ISA_AVX512: return &wide_kernels_avx512_q;
#endif
    default: return NULL;
    }
}
