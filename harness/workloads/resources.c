/* resources.c: the memory policy: thread stacks, --memcap and the
 * accelerators' own caps against the cap (see resources.h). */
#include "resources.h"

#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* "WxH at S spp" or "WxH corners", for messages. */
void resources_describe_image(char *buf, size_t len, int w, int h, int spp, bool corners)
{
    if (corners) snprintf(buf, len, "%dx%d pixel corners", w, h);
    else snprintf(buf, len, "%dx%d at %d spp", w, h, spp < 1 ? 1 : spp);
}

uint64_t resources_thread_stack_bytes(void)
{
    pthread_attr_t a;
    size_t stack = 0, guard = 0;
    /* The attributes pthread_create uses when given none (glibc: the
     * stack rlimit at start-up, else 8 MiB). */
    if (pthread_getattr_default_np(&a) == 0) {
        pthread_attr_getstacksize(&a, &stack);
        pthread_attr_getguardsize(&a, &guard);
        pthread_attr_destroy(&a);
    }
    if (stack == 0) stack = 8u << 20;
    return (uint64_t)stack + guard;
}

int resources_check_threads(int threads, const char *option, char *err, size_t errlen)
{
    /* The calling thread is one of them and has its stack already. */
    uint64_t each = resources_thread_stack_bytes(), started = threads > 1 ? (uint64_t)threads - 1 : 0;
    if (memory_cap_exceeded(memory_mul(started, each), err, errlen,
                            "%s %d: the stacks of the %llu threads it starts (%.1f MiB of address space each)", option,
                            threads, (unsigned long long)started, (double)each / 1048576.0))
        return -1;
    return 0;
}

int resources_parse_memcap(const char *arg, uint64_t *mib, char *err, size_t errlen)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(arg, &end, 10);
    if (errno || end == arg || *end || arg[0] == '-' || v < 1 || v > MEMORY_CAP_MIB_MAX) {
        snprintf(err, errlen, "--memcap %s: expected MiB, an integer in 1..%llu", arg,
                 (unsigned long long)MEMORY_CAP_MIB_MAX);
        return -1;
    }
    *mib = v;
    return 0;
}

void resources_bound_accel_params(accel_params *params)
{
    uint64_t cap_mib = memory_cap_mib();
    params->memcap_mib = cap_mib ? cap_mib : 1;
}
