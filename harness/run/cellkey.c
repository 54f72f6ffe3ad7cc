/* cellkey.c: run ids and cell keys (see cellkey.h). */
#include "cellkey.h"

#include <ctype.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <sys/random.h>
#include <time.h>
#include <unistd.h>

const char *run_id_current(void)
{
    static char id[RUN_ID_MAX];
    if (id[0]) return id;
    time_t now = time(NULL);
    struct tm tm;
    gmtime_r(&now, &tm);
    char stamp[32];
    strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", &tm);
    uint32_t bits = 0;
    if (getrandom(&bits, sizeof bits, GRND_NONBLOCK) != (ssize_t)sizeof bits) {
        /* No entropy yet (early boot): the clock's nanoseconds and the pid still tell two runs apart. */
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        bits = (uint32_t)ts.tv_nsec * 2654435761u ^ (uint32_t)getpid();
    }
    snprintf(id, sizeof id, "%s-%06x", stamp, bits & 0xffffffu);
    return id;
}

/* Appends " NAME=VALUE" (no space before the first word) with VALUE's
 * '%', spaces and control characters as %XX. Returns the new length, or
 * len when it did not fit. */
static size_t put_word(char *buf, size_t len, size_t n, const char *name, const char *value)
{
    if (n >= len) return len;
    int w = snprintf(buf + n, len - n, "%s%s=", n ? " " : "", name);
    if (w < 0 || (size_t)w >= len - n) return len;
    n += (size_t)w;
    for (const unsigned char *c = (const unsigned char *)(value ? value : ""); *c; c++) {
        bool escape = *c == '%' || *c <= ' ' || *c == 0x7f;
        if (n + (escape ? 3 : 1) >= len) return len;
        if (escape) n += (size_t)snprintf(buf + n, len - n, "%%%02X", *c);
        else buf[n++] = (char)*c;
    }
    buf[n] = 0;
    return n;
}

int cell_key_format(const cell_key_parts *k, char *buf, size_t len)
{
    if (len == 0) return -1;
    buf[0] = 0;
    char v[64];
    size_t n = 0;
    n = put_word(buf, len, n, "scene", k->scene);
    n = put_word(buf, len, n, "accel", k->accel);
    n = put_word(buf, len, n, "params", k->params);
    n = put_word(buf, len, n, "workload", k->workload);
    if (k->wl) {
        snprintf(v, sizeof v, "%dx%d", k->wl->width, k->wl->height);
        n = put_word(buf, len, n, "res", v);
        snprintf(v, sizeof v, "%d", k->wl->spp);
        n = put_word(buf, len, n, "spp", v);
        n = put_word(buf, len, n, "corners", k->wl->corners ? "1" : "0");
        snprintf(v, sizeof v, "%d", k->wl->depth);
        n = put_word(buf, len, n, "depth", v);
        snprintf(v, sizeof v, "%llu", (unsigned long long)k->wl->seed);
        n = put_word(buf, len, n, "seed", v);
    } else {
        snprintf(v, sizeof v, "%016llx", (unsigned long long)k->rays_hash);
        n = put_word(buf, len, n, "rays", v);
    }
    snprintf(v, sizeof v, "%d", k->threads);
    n = put_word(buf, len, n, "threads", v);
    snprintf(v, sizeof v, "%d", k->repeat);
    n = put_word(buf, len, n, "repeat", v);
    if (k->warm) n = put_word(buf, len, n, "passes", "warm");
    return n < len ? 0 : -1;
}

int cell_key_value(const char *key, const char *name, char *buf, size_t len)
{
    size_t nl = strlen(name);
    for (const char *w = key; w && *w; w = strchr(w, ' ') ? strchr(w, ' ') + 1 : NULL) {
        if (strncmp(w, name, nl) != 0 || w[nl] != '=') continue;
        size_t n = 0;
        for (const char *c = w + nl + 1; *c && *c != ' '; c++) {
            unsigned v;
            char ch = *c;
            if (*c == '%' && sscanf(c + 1, "%2x", &v) == 1 && isxdigit((unsigned char)c[1]) && isxdigit((unsigned char)c[2])) {
                ch = (char)v;
                c += 2;
            }
            if (n + 1 >= len) return -1;
            buf[n++] = ch;
        }
        buf[n] = 0;
        return 0;
    }
    return -1;
}
