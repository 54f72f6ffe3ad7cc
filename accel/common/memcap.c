/* memcap.c: the refusal of memcap.h. */
#include "memcap.h"

#include <stdarg.h>
#include <stdio.h>

bool memcap_exceeded(uint64_t bytes, uint64_t cap_mib, char *err, size_t errlen, const char *what_fmt, ...)
{
    if (cap_mib > (UINT64_MAX >> 20) || bytes <= cap_mib << 20) return false; /* a cap past 2^64 bytes: none */
    if (!errlen) return true;
    va_list ap;
    va_start(ap, what_fmt);
    size_t used = memory_refusal_what(err, errlen, what_fmt, ap);
    va_end(ap);
    snprintf(err + used, errlen - used, " need %.1f MiB, over memcap=%llu MiB", (double)bytes / 1048576.0,
             (unsigned long long)cap_mib);
    return true;
}
