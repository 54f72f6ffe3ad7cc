/* params.h: named accelerator parameters with defaults.
 *
 * Every accelerator declares a table of accel_param; the harness resolves
 * the user's --param ACCEL.KEY=VALUE settings against it (unknown keys are
 * an error) and passes the full set, defaults filled in, to build(). The
 * canonical string "key=value,key=value" in table order names the
 * configuration in the CSV. */
#ifndef ACCELBENCH_PARAMS_H
#define ACCELBENCH_PARAMS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
    const char *name;          /* NULL ends the table */
    const char *default_value;
    const char *help;          /* one line, with the allowed values */
} accel_param;

#define ACCEL_PARAMS_MAX 32

typedef struct accel_params {
    const accel_param *table;
    int count;
    char values[ACCEL_PARAMS_MAX][64];
    int threads;   /* set by the harness: the threads a builder may use (not a table entry) */
    uint64_t seed; /* set by the harness: --seed (default 1), for builders that draw random numbers (not a table entry) */
} accel_params;

/* Fill values with the table's defaults. */
void params_defaults(accel_params *p, const accel_param *table);
/* Set KEY=VALUE. Returns 0, or -1 with a reason (unknown key, value too long). */
int params_set(accel_params *p, const char *key, const char *value, char *err, size_t errlen);
/* Set every KEY=VALUE of "k=v,k=v" ("" sets nothing). Returns 0, or -1
 * with the reason of the first one that fails. */
int params_set_list(accel_params *p, const char *settings, char *err, size_t errlen);
/* The value of a key from the table (never NULL for a table key). */
const char *params_get(const accel_params *p, const char *key);
/* Typed readers: 0 on success, -1 with "KEY=VALUE: reason" in err. */
int params_get_long(const accel_params *p, const char *key, long lo, long hi, long *out, char *err, size_t errlen);
int params_get_double(const accel_params *p, const char *key, double lo, double hi, double *out, char *err, size_t errlen);
/* One of a list of words, e.g. {"off","hit","almost",NULL}: returns its index. */
int params_get_choice(const accel_params *p, const char *key, const char *const *choices, int *out, char *err, size_t errlen);
/* "key=value,key=value" in table order. */
void params_format(const accel_params *p, char *buf, size_t len);

#ifdef __cplusplus
}
#endif

#endif
