/* memory_cap.c: the process's memory cap and its default (see
 * memory_cap.h). */
#include "memory_cap.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#define MIB (1024.0 * 1024.0)

bool memory_cap_parse_bytes(const char *text, uint64_t *bytes)
{
    while (*text == ' ' || *text == '\t') text++;
    if (strncmp(text, "max", 3) == 0 && (text[3] == '\0' || text[3] == '\n')) {
        *bytes = MEMORY_UNLIMITED;
        return true;
    }
    if (*text < '0' || *text > '9') return false;
    char *end;
    unsigned long long v = strtoull(text, &end, 10);
    if (*end != '\0' && *end != '\n') return false;
    /* cgroup v1 writes "no limit" as PAGE_COUNTER_MAX pages, about 2^63. */
    *bytes = v >= (1ull << 62) ? MEMORY_UNLIMITED : (uint64_t)v;
    return true;
}

/* The number in a small file, or false. */
static bool read_number_file(const char *path, uint64_t *out)
{
    FILE *f = fopen(path, "r");
    if (!f) return false;
    char buf[64];
    bool ok = fgets(buf, sizeof buf, f) != NULL && memory_cap_parse_bytes(buf, out);
    fclose(f);
    return ok;
}

static uint64_t rlimit_soft(int resource)
{
    struct rlimit r;
    if (getrlimit(resource, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return MEMORY_UNLIMITED;
    return (uint64_t)r.rlim_cur;
}

/* The tightest limit along the cgroup path from dir up to base (files
 * limit_file and usage_file in each folder), with that group's usage. */
static void cgroup_walk(const char *base, const char *path, const char *limit_file, const char *usage_file,
                        memory_limits *l)
{
    char dir[1024], file[1100];
    if (strstr(path, "..") || snprintf(dir, sizeof dir, "%s%s", base, path) >= (int)sizeof dir) return;
    size_t baselen = strlen(base);
    for (;;) {
        size_t n = strlen(dir);
        while (n > baselen && dir[n - 1] == '/') dir[--n] = '\0';
        uint64_t max, used = 0;
        snprintf(file, sizeof file, "%s/%s", dir, limit_file);
        if (read_number_file(file, &max) && max < l->cgroup_max) {
            snprintf(file, sizeof file, "%s/%s", dir, usage_file);
            if (!read_number_file(file, &used) || used == MEMORY_UNLIMITED) used = 0;
            l->cgroup_max = max;
            l->cgroup_used = used;
        }
        char *slash = strrchr(dir, '/');
        if (n <= baselen || !slash || (size_t)(slash - dir) < baselen) break;
        *slash = '\0';
    }
}

/* The memory controller's limit from /proc/self/cgroup: cgroup v2 ("0::PATH"
 * under /sys/fs/cgroup) or v1 (a "memory" controller line). */
static void cgroup_limits(memory_limits *l)
{
    FILE *f = fopen("/proc/self/cgroup", "r");
    if (!f) return;
    char line[1024];
    while (fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = '\0';
        char *c1 = strchr(line, ':'), *c2 = c1 ? strchr(c1 + 1, ':') : NULL;
        if (!c2) continue;
        *c2 = '\0';
        const char *controllers = c1 + 1, *path = c2 + 1;
        if (!strcmp(line, "0") && !*controllers) {
            cgroup_walk("/sys/fs/cgroup", path, "memory.max", "memory.current", l);
            continue;
        }
        for (const char *p = controllers; p && *p; p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL)
            if (!strncmp(p, "memory", 6) && (p[6] == ',' || p[6] == '\0'))
                cgroup_walk("/sys/fs/cgroup/memory", path, "memory.limit_in_bytes", "memory.usage_in_bytes", l);
    }
    fclose(f);
}

void memory_limits_read(memory_limits *l)
{
    memset(l, 0, sizeof *l);
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    l->physical = pages > 0 && page > 0 ? memory_mul((uint64_t)pages, (uint64_t)page) : MEMORY_UNLIMITED;
    l->as_limit = rlimit_soft(RLIMIT_AS);
    l->data_limit = rlimit_soft(RLIMIT_DATA);
    l->cgroup_max = MEMORY_UNLIMITED;
    /* statm: size resident shared text lib data dt, in pages. */
    FILE *f = fopen("/proc/self/statm", "r");
    unsigned long long size, resident, shared, text, lib, data;
    if (f && fscanf(f, "%llu %llu %llu %llu %llu %llu", &size, &resident, &shared, &text, &lib, &data) == 6 && page > 0) {
        l->as_used = memory_mul(size, (uint64_t)page);
        l->data_used = memory_mul(data, (uint64_t)page);
    }
    if (f) fclose(f);
    cgroup_limits(l);
}

/* Lower *avail to limit - used when that is smaller; true if it was. */
static bool lower_to(uint64_t *avail, uint64_t limit, uint64_t used)
{
    if (limit == MEMORY_UNLIMITED) return false;
    uint64_t left = limit > used ? limit - used : 0;
    if (left >= *avail) return false;
    *avail = left;
    return true;
}

uint64_t memory_cap_default(const memory_limits *l, char *why, size_t whylen)
{
    uint64_t avail = l->physical;
    char what[160];
    if (avail == MEMORY_UNLIMITED) snprintf(what, sizeof what, "no known memory size");
    else snprintf(what, sizeof what, "the %.0f MiB of physical memory", (double)avail / MIB);
    if (lower_to(&avail, l->as_limit, l->as_used))
        snprintf(what, sizeof what, "the %.0f MiB left under the address-space limit of %.0f MiB (RLIMIT_AS, ulimit -v)",
                 (double)avail / MIB, (double)l->as_limit / MIB);
    if (lower_to(&avail, l->data_limit, l->data_used))
        snprintf(what, sizeof what, "the %.0f MiB left under the data limit of %.0f MiB (RLIMIT_DATA, ulimit -d)",
                 (double)avail / MIB, (double)l->data_limit / MIB);
    if (lower_to(&avail, l->cgroup_max, l->cgroup_used))
        snprintf(what, sizeof what, "the %.0f MiB left under the cgroup's memory limit of %.0f MiB", (double)avail / MIB,
                 (double)l->cgroup_max / MIB);
    uint64_t cap = avail / MEMORY_CAP_SHARE_DEN * MEMORY_CAP_SHARE_NUM;
    if (cap < (1u << 20)) cap = 1u << 20;
    if (whylen) snprintf(why, whylen, "default: %s of %s", MEMORY_CAP_SHARE_WORD, what);
    return cap;
}

static struct {
    bool set;
    uint64_t bytes;
    char source[256];
} cap_state;

void memory_cap_set_mib(uint64_t mib)
{
    if (mib == 0) {
        memory_limits l;
        memory_limits_read(&l);
        cap_state.bytes = memory_cap_default(&l, cap_state.source, sizeof cap_state.source);
    } else {
        if (mib > MEMORY_CAP_MIB_MAX) mib = MEMORY_CAP_MIB_MAX;
        cap_state.bytes = mib << 20;
        snprintf(cap_state.source, sizeof cap_state.source, "--memcap %llu", (unsigned long long)mib);
    }
    cap_state.set = true;
}

uint64_t memory_cap_bytes(void)
{
    if (!cap_state.set) memory_cap_set_mib(0);
    return cap_state.bytes;
}

uint64_t memory_cap_mib(void) { return memory_cap_bytes() >> 20; }

const char *memory_cap_source(void)
{
    if (!cap_state.set) memory_cap_set_mib(0);
    return cap_state.source;
}

size_t memory_refusal_what(char *err, size_t errlen, const char *what_fmt, va_list ap)
{
    int n = vsnprintf(err, errlen, what_fmt, ap);
    return n < 0 ? 0 : (size_t)n < errlen ? (size_t)n : errlen - 1;
}

bool memory_cap_exceeded(uint64_t bytes, char *err, size_t errlen, const char *what_fmt, ...)
{
    uint64_t cap = memory_cap_bytes();
    if (bytes <= cap) return false;
    if (!errlen) return true;
    va_list ap;
    va_start(ap, what_fmt);
    size_t used = memory_refusal_what(err, errlen, what_fmt, ap);
    va_end(ap);
    char need[64];
    if (bytes == UINT64_MAX) snprintf(need, sizeof need, "more than 2^64 bytes");
    else snprintf(need, sizeof need, "%llu bytes (%.1f MiB)", (unsigned long long)bytes, (double)bytes / MIB);
    snprintf(err + used, errlen - used, " need %s, above the memory cap of %llu MiB (%s); raise it with --memcap MIB",
             need, (unsigned long long)(cap >> 20), memory_cap_source());
    return true;
}

void memory_cap_stopped(char *err, size_t errlen, const char *what_fmt, ...)
{
    if (!errlen) return;
    va_list ap;
    va_start(ap, what_fmt);
    size_t used = memory_refusal_what(err, errlen, what_fmt, ap);
    va_end(ap);
    snprintf(err + used, errlen - used, ": stopped by the memory cap of %llu MiB (%s); raise it with --memcap MIB",
             (unsigned long long)memory_cap_mib(), memory_cap_source());
}
