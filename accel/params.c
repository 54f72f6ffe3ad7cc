/* params.c: checking, storing and reading accelerator parameters (see params.h). */
#include "params.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int params_index(const accel_params *p, const char *key)
{
    for (int i = 0; i < p->count; i++)
        if (strcmp(p->table[i].name, key) == 0) return i;
    return -1;
}

/* The index of word in "a|b|c", or -1. */
static int choice_index(const char *choices, const char *word)
{
    size_t n = strlen(word);
    int i = 0;
    for (const char *s = choices; s; i++) {
        const char *bar = strchr(s, '|');
        size_t len = bar ? (size_t)(bar - s) : strlen(s);
        if (len == n && n && strncmp(s, word, n) == 0) return i;
        s = bar ? bar + 1 : NULL;
    }
    return -1;
}

static bool parse_long(const char *s, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end) return false;
    *out = v;
    return true;
}

static bool parse_size(const char *s, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s) return false;
    int shift = 0;
    if (*end == 'k' || *end == 'K') shift = 10;
    else if (*end == 'M') shift = 20;
    else if (*end == 'G') shift = 30;
    if (shift) end++;
    if (*end || (v && shift && (v > (LONG_MAX >> shift) || v < -(LONG_MAX >> shift)))) return false;
    *out = shift ? v * (1L << shift) : v;
    return true;
}

/* value read as row's kind: its typed form in *iv (BOOL, INT, SIZE,
 * CHOICE), *rv (REAL) or *word; false when the row does not allow it. */
static bool parse_value(const accel_param *row, const char *value, long *iv, double *rv, bool *word)
{
    *iv = 0;
    *rv = 0;
    *word = false;
    switch (row->kind) {
    case PARAM_BOOL:
        if (!strcmp(value, "on")) *iv = 1;
        else if (strcmp(value, "off")) return false;
        return true;
    case PARAM_INT:
        if (row->words && !strcmp(value, row->words)) {
            *word = true;
            return true;
        }
        return parse_long(value, iv) && *iv >= row->lo && *iv <= row->hi;
    case PARAM_SIZE:
        return parse_size(value, iv) && *iv >= row->lo && *iv <= row->hi;
    case PARAM_REAL: {
        char *end;
        errno = 0;
        double v = strtod(value, &end);
        if (errno || end == value || *end || !isfinite(v) || v < row->lo || v > row->hi) return false;
        *rv = v;
        return true;
    }
    case PARAM_CHOICE:
        *iv = choice_index(row->words, value);
        return *iv >= 0;
    case PARAM_STRING:
        return row->check ? row->check(value) == 0 : true;
    }
    return false;
}

void params_allowed(const accel_param *row, char *buf, size_t len)
{
    switch (row->kind) {
    case PARAM_BOOL: snprintf(buf, len, "on|off"); break;
    case PARAM_INT:
        snprintf(buf, len, "%s%san integer in %.0f..%.0f", row->words ? row->words : "", row->words ? " or " : "",
                 row->lo, row->hi);
        break;
    case PARAM_SIZE: snprintf(buf, len, "a count in %.0f..%.0f (k, M, G: powers of 1024)", row->lo, row->hi); break;
    case PARAM_REAL: snprintf(buf, len, "a number in [%g, %g]", row->lo, row->hi); break;
    case PARAM_CHOICE: snprintf(buf, len, "%s", row->words); break;
    case PARAM_STRING: snprintf(buf, len, "%s", row->words ? row->words : "any text"); break;
    }
}

/* Store value at row i (checked by the caller). */
static void store(accel_params *p, int i, const char *value, long iv, double rv, bool word)
{
    snprintf(p->values[i], sizeof p->values[i], "%s", value);
    p->ival[i] = iv;
    p->rval[i] = rv;
    p->word[i] = word;
}

void params_defaults(accel_params *p, const accel_param *table)
{
    memset(p, 0, sizeof *p);
    p->table = table;
    p->threads = 1;
    p->seed = 1; /* --seed's default */
    for (int i = 0; table && table[i].name && i < ACCEL_PARAMS_MAX; i++) {
        long iv;
        double rv;
        bool word;
        /* A default that does not parse is left as text and zero; the
         * conformance suite refuses such a table. */
        if (!parse_value(&table[i], table[i].default_value, &iv, &rv, &word)) iv = 0, rv = 0, word = false;
        store(p, i, table[i].default_value, iv, rv, word);
        p->count = i + 1;
    }
}

int params_set(accel_params *p, const char *key, const char *value, char *err, size_t errlen)
{
    int i = params_index(p, key);
    if (i < 0) {
        size_t n = (size_t)snprintf(err, errlen, "unknown parameter '%s' (known:", key);
        for (int j = 0; j < p->count && n < errlen; j++)
            n += (size_t)snprintf(err + n, errlen - n, " %s", p->table[j].name);
        if (n < errlen) snprintf(err + n, errlen - n, p->count ? ")" : " none)");
        return -1;
    }
    long iv;
    double rv;
    bool word;
    if (strlen(value) >= sizeof p->values[i] || !parse_value(&p->table[i], value, &iv, &rv, &word)) {
        char allowed[256];
        params_allowed(&p->table[i], allowed, sizeof allowed);
        snprintf(err, errlen, "%s=%.80s%s: must be %s", key, value, strlen(value) > 80 ? "..." : "", allowed);
        return -1;
    }
    store(p, i, value, iv, rv, word);
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

/* The row of key, read as one of the kinds in mask (1 << kind); aborts on
 * a key the table lacks or a read of another kind. */
static int row_for(const accel_params *p, const char *key, unsigned mask)
{
    int i = params_index(p, key);
    if (i < 0 || !(mask & (1u << p->table[i].kind))) {
        fprintf(stderr, "accelbench: internal: parameter '%s' %s\n", key,
                i < 0 ? "is not in the accelerator's table" : "read as another kind than its row's");
        abort();
    }
    if (p->reads) p->reads[i]++;
    return i;
}

bool params_bool(const accel_params *p, const char *key) { return p->ival[row_for(p, key, 1u << PARAM_BOOL)] != 0; }

long params_int(const accel_params *p, const char *key)
{
    int i = row_for(p, key, 1u << PARAM_INT | 1u << PARAM_SIZE);
    if (p->word[i]) {
        fprintf(stderr, "accelbench: internal: parameter '%s' is its word '%s': read it with params_int_or\n", key,
                p->table[i].words);
        abort();
    }
    return p->ival[i];
}

long params_int_or(const accel_params *p, const char *key, long if_word)
{
    int i = row_for(p, key, 1u << PARAM_INT);
    return p->word[i] ? if_word : p->ival[i];
}

double params_real(const accel_params *p, const char *key) { return p->rval[row_for(p, key, 1u << PARAM_REAL)]; }

int params_choice(const accel_params *p, const char *key) { return (int)p->ival[row_for(p, key, 1u << PARAM_CHOICE)]; }

const char *params_string(const accel_params *p, const char *key) { return p->values[row_for(p, key, ~0u)]; }

uint64_t params_memcap(const accel_params *p, uint64_t own_mib)
{
    return p->memcap_mib && p->memcap_mib < own_mib ? p->memcap_mib : own_mib;
}

const char *params_get(const accel_params *p, const char *key)
{
    int i = params_index(p, key);
    return i < 0 ? "" : p->values[i];
}

void params_format(const accel_params *p, char *buf, size_t len)
{
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; i < p->count && n < len; i++)
        n += (size_t)snprintf(buf + n, len - n, "%s%s=%s", i ? "," : "", p->table[i].name, p->values[i]);
}
