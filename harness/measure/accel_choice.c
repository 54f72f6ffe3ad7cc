/* accel_choice.c: --accels lists with instance parameters and sweeps (see accel_choice.h). */
#include "accel_choice.h"

#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include "../../scenes/scene.h"

#define SPEC_KEYS 64
#define SPEC_VALUES 32

typedef struct {
    char key[64];
    const char *values[SPEC_VALUES];
    int nvalues;
} spec_kv;

/* Split one item's bracket body "k=v|w,k2=x" (in place) into kvs. Returns the count or -1. */
static int parse_body(char *body, const char *item, spec_kv *kv, char *err, size_t errlen)
{
    int n = 0;
    char *save = NULL;
    if (!*body) {
        snprintf(err, errlen, "--accels '%s': empty brackets (give KEY=VALUE inside, or drop them)", item);
        return -1;
    }
    for (char *p = body;; p = NULL) {
        char *tok = strtok_r(p, ",", &save);
        if (!tok) break;
        char *eq = strchr(tok, '=');
        if (!eq || eq == tok) {
            snprintf(err, errlen, "--accels '%s': '%s': expected KEY=VALUE inside the brackets", item, tok);
            return -1;
        }
        if (n == SPEC_KEYS) {
            snprintf(err, errlen, "--accels '%s': more than %d parameters", item, SPEC_KEYS);
            return -1;
        }
        *eq = 0;
        if (strlen(tok) >= sizeof kv[n].key) {
            snprintf(err, errlen, "--accels '%.120s': parameter '%.40s...' has a name longer than %zu bytes", item, tok,
                     sizeof kv[n].key - 1);
            return -1;
        }
        snprintf(kv[n].key, sizeof kv[n].key, "%s", tok);
        kv[n].nvalues = 0;
        char *v = eq + 1;
        for (;;) {
            char *bar = strchr(v, '|');
            if (bar) *bar = 0;
            if (!*v) {
                snprintf(err, errlen, "--accels '%s': parameter '%s' has an empty value", item, tok);
                return -1;
            }
            if (kv[n].nvalues == SPEC_VALUES) {
                snprintf(err, errlen, "--accels '%s': parameter '%s' has more than %d values", item, tok, SPEC_VALUES);
                return -1;
            }
            kv[n].values[kv[n].nvalues++] = v;
            if (!bar) break;
            v = bar + 1;
        }
        n++;
    }
    return n;
}

/* Expand one item (NAME or NAME[...]) into out; returns the count or -1. */
static int expand_item(const char *item, accel_config *out, int max, char *err, size_t errlen)
{
    char buf[1024], name[1024];
    if (strlen(item) >= sizeof buf) {
        snprintf(err, errlen, "--accels: '%.40s...' is too long", item);
        return -1;
    }
    snprintf(buf, sizeof buf, "%s", item);
    char *open = strchr(buf, '['), *body = NULL;
    if (open) {
        char *close = strrchr(buf, ']');
        if (!close || close < open) {
            snprintf(err, errlen, "--accels '%s': unclosed '['", item);
            return -1;
        }
        if (close[1]) {
            snprintf(err, errlen, "--accels '%s': '%s' after ']'", item, close + 1);
            return -1;
        }
        *open = *close = 0;
        body = open + 1;
        if (strchr(body, '[') || strchr(body, ']')) {
            snprintf(err, errlen, "--accels '%s': brackets inside brackets", item);
            return -1;
        }
    } else if (strchr(buf, ']')) {
        snprintf(err, errlen, "--accels '%s': ']' without '['", item);
        return -1;
    }
    snprintf(name, sizeof name, "%s", buf);
    const struct accel_ops *ops = accel_find(name);
    if (!ops) {
        snprintf(err, errlen, "unknown accelerator '%s' (see: accelbench list accels)", name);
        return -1;
    }
    spec_kv kv[SPEC_KEYS];
    int nkv = body ? parse_body(body, item, kv, err, errlen) : 0;
    if (nkv < 0) return -1;
    /* Counted before anything is expanded, and stopped as soon as it passes max: the product of many lists
     * overflows any integer. */
    long total = 1;
    bool over = total > max; /* a plain name is one instance, and there may be no room left for it */
    for (int k = 0; k < nkv && !over; k++) {
        total *= kv[k].nvalues;
        over = total > max;
    }
    if (over) {
        /* The item is cut in the message so that the limit stays on the line. */
        if (nkv)
            snprintf(err, errlen, "--accels '%.120s%s': its '|' lists expand to more than the %d instances left "
                     "(at most %d accelerators in all)", item, strlen(item) > 120 ? "..." : "", max, OPT_LIST_MAX - 1);
        else
            snprintf(err, errlen, "--accels '%.120s%s': the list already holds its limit of %d accelerators",
                     item, strlen(item) > 120 ? "..." : "", OPT_LIST_MAX - 1);
        return -1;
    }
    int idx[SPEC_KEYS] = {0};
    for (long c = 0; c < total; c++) {
        accel_config *ac = &out[c];
        memset(ac, 0, sizeof *ac);
        ac->ops = ops;
        params_defaults(&ac->params, ops->params);
        for (int k = 0; k < nkv; k++) {
            char why[512];
            if (accel_config_set(ac, kv[k].key, kv[k].values[idx[k]], why, sizeof why)) {
                snprintf(err, errlen, "--accels '%s': %s: %s", item, name, why);
                return -1;
            }
        }
        /* Odometer: the last list varies fastest. */
        for (int k = nkv - 1; k >= 0; k--) {
            if (++idx[k] < kv[k].nvalues) break;
            idx[k] = 0;
        }
    }
    return (int)total;
}

int accel_spec_expand(const char *list, accel_config *out, int max, char *err, size_t errlen)
{
    int n = 0;
    const char *p = list;
    if (!*p) {
        snprintf(err, errlen, "empty list of accelerators");
        return -1;
    }
    while (*p) {
        /* The item runs to the next comma outside brackets. */
        const char *q = p;
        int depth = 0;
        while (*q && !(*q == ',' && depth == 0)) {
            if (*q == '[') depth++;
            else if (*q == ']' && depth > 0) depth--;
            q++;
        }
        char item[1024];
        if ((size_t)(q - p) >= sizeof item) {
            snprintf(err, errlen, "--accels: '%.40s...' is too long", p);
            return -1;
        }
        snprintf(item, sizeof item, "%.*s", (int)(q - p), p);
        if (!*item) {
            snprintf(err, errlen, "--accels '%s': an empty name between commas", list);
            return -1;
        }
        int m = expand_item(item, out + n, max - n, err, errlen);
        if (m < 0) return -1;
        n += m;
        p = *q ? q + 1 : q;
        if (*q && !*p) {
            snprintf(err, errlen, "--accels '%s': an empty name after the last comma", list);
            return -1;
        }
    }
    return n;
}

int accel_config_set(accel_config *ac, const char *key, const char *value, char *err, size_t errlen)
{
    if (strcmp(key, "memcap") == 0 && params_index(&ac->params, key) < 0) {
        snprintf(err, errlen, "memcap is not a parameter: the memory cap is --memcap MIB, for every accelerator");
        return -1;
    }
    return params_set(&ac->params, key, value, err, errlen);
}

int accel_config_check(const accel_config *ac, char *err, size_t errlen)
{
    return accel_check_params(ac->ops, &ac->params, err, errlen);
}

void accel_config_label(const accel_config *ac, char *buf, size_t len)
{
    /* The defaults as they run on this machine (bvh's isa=auto is avx512
     * here): a value settled from its default is the default. */
    accel_params settled;
    params_defaults(&settled, ac->ops->params);
    accel_settle_params(ac->ops, &settled);
    size_t n = (size_t)snprintf(buf, len, "%s", ac->ops->name);
    const char *sep = "[";
    for (int k = 0; k < ac->params.count && n < len; k++) {
        if (strcmp(ac->params.values[k], ac->params.table[k].default_value) == 0) continue;
        if (k < settled.count && strcmp(ac->params.values[k], settled.values[k]) == 0) continue;
        n += (size_t)snprintf(buf + n, len - n, "%s%s=%s", sep, ac->params.table[k].name, ac->params.values[k]);
        sep = ",";
    }
    if (*sep == ',' && n < len) snprintf(buf + n, len - n, "]");
}
