/* params.h: typed accelerator parameters.
 *
 * Every accelerator declares a table of accel_param rows: name, kind, range
 * or choices, default and help. params_set checks a value against its row
 * when it is given (the harness's NAME[k=v|w] and --param ACCEL.KEY=VALUE
 * both come here), so build() reads typed values through getters that
 * cannot fail. `list accels`, the docs' parameter sections and every
 * refusal's "must be ..." come from the same row (params_allowed). Rules
 * between two parameters are the accelerator's check() (accel.h). The
 * canonical string "key=value,key=value" in table order names the
 * configuration in the CSV.
 *
 * What the harness decides for every accelerator (threads, seed, the
 * memory cap) are fields of accel_params, not rows of a table. */
#ifndef ACCELBENCH_PARAMS_H
#define ACCELBENCH_PARAMS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum {
    PARAM_BOOL,   /* on|off */
    PARAM_INT,    /* an integer in lo..hi, or the row's word (e.g. "auto") when it has one */
    PARAM_REAL,   /* a finite number in [lo, hi] */
    PARAM_CHOICE, /* one of choices, "a|b|c"; read as its index */
    PARAM_SIZE,   /* a count in lo..hi, with an optional k, M or G suffix (powers of 1024) */
    PARAM_STRING, /* text the row's check() accepts (a grammar such as grid's res) */
} param_kind;

typedef struct accel_param {
    const char *name; /* NULL ends the table */
    param_kind kind;
    const char *default_value;
    const char *help; /* one line: what it does; the allowed values come from the kind */
    double lo, hi;    /* INT, REAL, SIZE: the inclusive range */
    const char *words; /* CHOICE: "a|b|c"; INT: a word accepted besides the range, or NULL;
                        * STRING: what check() accepts, as people read it */
    /* STRING: 0 when value is well formed, else -1 (params_set then says
     * what words allows). */
    int (*check)(const char *value);
} accel_param;

#define PARAM_ROW_BOOL(name, def, help) {name, PARAM_BOOL, def, help, 0, 1, NULL, NULL}
#define PARAM_ROW_INT(name, def, lo, hi, help) {name, PARAM_INT, def, help, lo, hi, NULL, NULL}
#define PARAM_ROW_INT_OR(name, def, word, lo, hi, help) {name, PARAM_INT, def, help, lo, hi, word, NULL}
#define PARAM_ROW_REAL(name, def, lo, hi, help) {name, PARAM_REAL, def, help, lo, hi, NULL, NULL}
#define PARAM_ROW_CHOICE(name, def, choices, help) {name, PARAM_CHOICE, def, help, 0, 0, choices, NULL}
#define PARAM_ROW_SIZE(name, def, lo, hi, help) {name, PARAM_SIZE, def, help, lo, hi, NULL, NULL}
#define PARAM_ROW_STRING(name, def, grammar, check, help) {name, PARAM_STRING, def, help, 0, 0, grammar, check}
#define PARAM_ROW_END {NULL, PARAM_BOOL, NULL, NULL, 0, 0, NULL, NULL}

#define ACCEL_PARAMS_MAX 32

typedef struct accel_params {
    const accel_param *table;
    int count;
    char values[ACCEL_PARAMS_MAX][64]; /* as given, canonical for the CSV */
    long ival[ACCEL_PARAMS_MAX];       /* BOOL 0/1, INT, SIZE, CHOICE index */
    double rval[ACCEL_PARAMS_MAX];     /* REAL */
    bool word[ACCEL_PARAMS_MAX];       /* INT: the value is the row's word */
    int threads;   /* set by the harness: the threads a builder may use */
    uint64_t seed; /* set by the harness: --seed (default 1), for builders that draw random numbers */
    /* Set by the harness: the memory cap in MiB (--memcap), 0 for none;
     * a builder refuses past min(its own cap, this) (params_memcap). */
    uint64_t memcap_mib;
    /* When not NULL, every getter adds one to reads[row] (the conformance
     * suite proves that build() reads every key). */
    unsigned *reads;
} accel_params;

/* Fill values with the table's defaults (which must parse: the conformance
 * suite checks every table). */
void params_defaults(accel_params *p, const accel_param *table);
/* Set KEY=VALUE, checked against its row. Returns 0, or -1 with one line
 * "KEY=VALUE: must be ALLOWED" (or the unknown key and the known ones). */
int params_set(accel_params *p, const char *key, const char *value, char *err, size_t errlen);
/* Set every KEY=VALUE of "k=v,k=v" ("" sets nothing). Returns 0, or -1
 * with the reason of the first one that fails. */
int params_set_list(accel_params *p, const char *settings, char *err, size_t errlen);
/* What a row allows, as people read it: "on|off", "an integer in 0..64",
 * "auto or an integer in 1..1024", "a number in [0, 1]", "a|b|c". */
void params_allowed(const accel_param *row, char *buf, size_t len);
/* The row of key in p's table, or -1. */
int params_index(const accel_params *p, const char *key);

/* Typed readers for build(). The value was checked when it was set; a key
 * not in the table or read as another kind is a programming error and
 * aborts with its name. */
bool params_bool(const accel_params *p, const char *key);
long params_int(const accel_params *p, const char *key);      /* INT (not its word), SIZE */
/* INT with a word ("auto"): if_word when the value is the word. */
long params_int_or(const accel_params *p, const char *key, long if_word);
double params_real(const accel_params *p, const char *key);
int params_choice(const accel_params *p, const char *key);    /* the index in the row's choices */
const char *params_string(const accel_params *p, const char *key); /* STRING, or any kind's text */
/* The memory cap a builder refuses past, in MiB: min(own_mib, the
 * harness's memcap_mib when set). */
uint64_t params_memcap(const accel_params *p, uint64_t own_mib);

/* The value of a key as text ("" for a key not in the table); not counted
 * as a read. */
const char *params_get(const accel_params *p, const char *key);
/* "key=value,key=value" in table order. */
void params_format(const accel_params *p, char *buf, size_t len);

#ifdef __cplusplus
}
#endif

#endif
