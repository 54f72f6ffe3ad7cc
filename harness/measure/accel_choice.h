/* accel_choice.h: accelerator instances as --accels names them, parameter
 * sweeps included (docs/cli.md: --accels).
 *
 *   LIST  := ITEM (',' ITEM)*            a comma inside [...] belongs to the item
 *   ITEM  := NAME | NAME '[' KV (',' KV)* ']'
 *   KV    := KEY '=' VALUE ('|' VALUE)*  a '|' list: one instance per value
 *
 * An item with several '|' lists expands to their product, the first list
 * varying slowest: 'bsp[split=sah|midpoint,maxprims=1|4]' is four instances.
 * A key given twice in one item takes its last value (reproduce's cumulative
 * ablation steps rely on it).
 * run, verify, render and reproduce (reproduce_kit.c's rp_measure) build
 * their instances here. */
#ifndef ACCELBENCH_ACCEL_CHOICE_H
#define ACCELBENCH_ACCEL_CHOICE_H

#include <stdbool.h>
#include <stddef.h>
#include "../../accel/accel.h"

/* The most items of a list option (--scenes, --accels, --workloads). */
#define OPT_LIST_MAX 64

/* One accelerator instance: its table, its parameters and how it is named. */
typedef struct {
    const struct accel_ops *ops;
    accel_params params;
    char params_str[512]; /* every parameter, "k=v,k=v" in table order (the CSV's params) */
    char label[600];      /* name, with [params] when they differ from the defaults */
} accel_config;

/* Expand list into at most max instances, each with its table's defaults and
 * the item's settings (threads, seed, params_str and label are the caller's).
 * Returns the count, or -1 with one line in err naming the item and what is
 * wrong (an unclosed bracket, an unknown accelerator or key, an empty value,
 * too many instances). */
int accel_spec_expand(const char *list, accel_config *out, int max, char *err, size_t errlen);

/* Set one parameter of the instance, checked against its table's row (the
 * one parser of NAME[k=v] and --param A.K=V). 0, or -1 with one line
 * "KEY=VALUE: must be ..." (or the unknown key) in err; the caller names
 * the accelerator. */
int accel_config_set(accel_config *ac, const char *key, const char *value, char *err, size_t errlen);

/* The rules between the instance's parameters (its check(), accel.h), with
 * nothing built: 0, or -1 with the reason in err. A refusal only a build
 * can know (a memory estimate over the cap) stays with the build. */
int accel_config_check(const accel_config *ac, char *err, size_t errlen);

/* The label of an instance: its name, plus [k=v,...] for the parameters that
 * differ from the table's defaults ('grid[res=40x40x40]'). */
void accel_config_label(const accel_config *ac, char *buf, size_t len);

#endif
