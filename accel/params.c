/* params.c: resolving and reading accelerator parameters (see params.h). */
#include "params.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int find(const accel_params *p, const char *key)
{
    for (int i = 0; i < p->count; i++)
        if (strcmp(p->table[i].name, key) == 0) return i;
    return -1;
}

void params_defaults(accel_params *p, const accel_param *table)
{
    memset(p, 0, sizeof *p);
    p->table = table;
    p->threads = 1;
    p->seed = 1; /* --seed's default */
    for (int i = 0; table && table[i].name && i < ACCEL_PARAMS_MAX; i++) {
        snprintf(p->values[i], sizeof p->values[i], "%s", table[i].default_value);
        p->count = i + 1;
    }
}

int params_set(accel_params *p, const char *key, const char *value, char *err, size_t errlen)
{
    int i = find(p, key);
    if (i < 0) {
        size_t n = (size_t)snprintf(err, errlen, "unknown parameter '%s' (known:", key);
        for (int j = 0; j < p->count && n < errlen; j++)
            n += (size_t)snprintf(err + n, errlen - n, " %s", p->table[j].name);
        if (n < errlen) snprintf(err + n, errlen - n, p->count ? ")" : " none)");
        return -1;
    }
    if (strlen(value) >= sizeof p->values[i]) {
        snprintf(err, errlen, "parameter %s: value too long", key);
        return -1;
    }
    snprintf(p->values[i], sizeof p->values[i], "%s", value);
    return 0;
}

int params_set_list(accel_params *p, const char *settings, char *err, size_t errlen)
{
    char buf[1024];
    if (strlen(settings) >= sizeof buf) {
        snprintf(err, errlen, "settings too long: %.40s...", settings);
        return -1;
    }
    snprintf(buf, sizeof buf, "%s", settings);
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        char *eq = strchr(tok, '=');
        if (!eq) {
            snprintf(err, errlen, "'%s': expected KEY=VALUE", tok);
            return -1;
        }
        *eq = 0;
        if (params_set(p, tok, eq + 1, err, errlen)) return -1;
    }
    return 0;
}

const char *params_get(const accel_params *p, const char *key)
{
    int i = find(p, key);
    return i < 0 ? "" : p->values[i];
}

int params_get_long(const accel_params *p, const char *key, long lo, long hi, long *out, char *err, size_t errlen)
{
    const char *s = params_get(p, key);
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end) {
        snprintf(err, errlen, "%s=%s: not an integer", key, s);
        return -1;
    }
    if (v < lo || v > hi) {
        snprintf(err, errlen, "%s=%s: must be in %ld..%ld", key, s, lo, hi);
        return -1;
    }
    *out = v;
    return 0;
}

int params_get_double(const accel_params *p, const char *key, double lo, double hi, double *out, char *err, size_t errlen)
{
    const char *s = params_get(p, key);
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || *end || v != v) {
        snprintf(err, errlen, "%s=%s: not a number", key, s);
        return -1;
    }
    if (v < lo || v > hi) {
        snprintf(err, errlen, "%s=%s: must be in [%g, %g]", key, s, lo, hi);
        return -1;
    }
    *out = v;
    return 0;
}

int params_get_choice(const accel_params *p, const char *key, const char *const *choices, int *out, char *err, size_t errlen)
{
    const char *s = params_get(p, key);
    for (int i = 0; choices[i]; i++)
        if (strcmp(s, choices[i]) == 0) {
            *out = i;
            return 0;
        }
    size_t n = (size_t)snprintf(err, errlen, "%s=%s: must be one of", key, s);
    for (int i = 0; choices[i] && n < errlen; i++)
        n += (size_t)snprintf(err + n, errlen - n, "%s%s", i ? "|" : " ", choices[i]);
    return -1;
}

void params_format(const accel_params *p, char *buf, size_t len)
{
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; i < p->count && n < len; i++)
        n += (size_t)snprintf(buf + n, len - n, "%s%s=%s", i ? "," : "", p->table[i].name, p->values[i]);
}
