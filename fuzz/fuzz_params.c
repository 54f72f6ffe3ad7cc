/* fuzz_params: the --param parser (accel/params.c params_set) and every
 * accelerator's reading of its values at build time, on any text. Each
 * line is KEY=VALUE, set on every registered accelerator's table (unknown
 * keys are refused there), or ACCEL.KEY=VALUE, set on that one only, as
 * --param gives it. Every accelerator is then built with what was set
 * (under a memory cap of FUZZ_MEMCAP_MIB: exercise.h), over the fixed
 * scene, and traced (exercise.c) with the scene's primary and random rays.
 * A line "--accels LIST" goes to the --accels parser instead
 * (harness/measure/accel_choice.c, sweeps included): it must stay inside the array it
 * is given and label every instance it returns. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../harness/measure/accel_choice.h"
#include "exercise.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size);

#define MAX_ACCELS 32
#define MAX_INSTANCES 8 /* small, so that a sweep's limit is reached often */

static void fuzz_accel_list(const char *list)
{
    accel_config out[MAX_INSTANCES + 1];
    memset(&out[MAX_INSTANCES], 0xA5, sizeof out[MAX_INSTANCES]); /* a guard the parser must not touch */
    accel_config guard;
    memcpy(&guard, &out[MAX_INSTANCES], sizeof guard);
    char err[512] = "";
    int n = accel_spec_expand(list, out, MAX_INSTANCES, err, sizeof err);
    if (n > MAX_INSTANCES || memcmp(&guard, &out[MAX_INSTANCES], sizeof guard) != 0) {
        fprintf(stderr, "fuzz: --accels gave %d instances into an array of %d\n", n, MAX_INSTANCES);
        abort();
    }
    if (n < 0 && err[0] == '\0') {
        fprintf(stderr, "fuzz: --accels refused without a reason\n");
        abort();
    }
    for (int i = 0; i < n; i++) {
        char label[1024];
        accel_config_label(&out[i], label, sizeof label);
    }
}

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size)
{
    accel_params params[MAX_ACCELS];
    int n = 0;
    for (; accel_registry[n] && n < MAX_ACCELS; n++) {
        params_defaults(&params[n], accel_registry[n]->params);
        params[n].threads = 1;
    }
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    char err[512], *save = NULL;
    for (char *line = strtok_r(text, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        if (strncmp(line, "--accels ", 9) == 0) {
            fuzz_accel_list(line + 9);
            continue;
        }
        char *eq = strchr(line, '='), *key = line;
        if (!eq) continue;
        *eq = '\0';
        char *dot = strchr(key, '.');
        const struct accel_ops *only = NULL;
        if (dot) { /* ACCEL.KEY when ACCEL is one; else the dot is part of the key */
            *dot = '\0';
            only = accel_find(key);
            if (only) key = dot + 1;
            else *dot = '.';
        }
        for (int i = 0; i < n; i++)
            if (!only || accel_registry[i] == only) (void)params_set(&params[i], key, eq + 1, err, sizeof err);
    }
    free(text);
    for (int i = 0; i < n; i++) fuzz_cap_memory(&params[i]);
    int nsets;
    rayset_t *const *sets = fuzz_scene_rays(&nsets);
    nsets = nsets < 2 ? nsets : 2; /* primary and random rays: a fine grid walks thousands of cells a ray */
    for (int i = 0; i < n; i++) {
        char canon[1024];
        params_format(&params[i], canon, sizeof canon);
        if (fuzz_first_time(accel_registry[i]->name, canon)) fuzz_accel(accel_registry[i], fuzz_scene(), &params[i], sets, nsets);
    }
    return 0;
}
