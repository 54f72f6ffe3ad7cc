/* advise_cmd.c: `accelbench advise` (see advise_cmd.h). Here: the options,
 * checked before anything runs, then per scene every candidate built at
 * every value of its search (its table's "tune:" line) and its cost
 * model's predicted work per ray read from its statistics, without tracing
 * a ray, into DIR/predictions.csv; then scripts/advise.py turns the
 * predictions into times with the machine's calibration, ranks the
 * candidates and, with --check, measures them (argument vectors, no
 * shell). */
#include "advise_cmd.h"

#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "../../accel/accel.h"
#include "../../scenes/memory_cap.h"
#include "../../scenes/scene.h"
#include "../measure/accel_choice.h"
#include "../measure/measure.h"
#include "../run/csv.h"
#include "../run/output.h"
#include "../workloads/workload.h"
#include "../workloads/resources.h"
#include "cli_args.h"
#include "options.h"

/* The candidates: every structure whose cost model predicts its work from
 * the built structure (docs/method.md, "Cost models"). bvh is built at its
 * default in any case: Embree's time is estimated from its prediction. */
#define ADVISE_ACCELS "grid,grid-raybox,octree,bsp,slabs-kk,bvh-gs,lightbuf,bvh"
#define ADVISE_EMBREE_PROXY "bvh"
#define ADVISE_WORKLOADS "primary,shadow,reflection,diffuse,random"

static void advise_usage(FILE *out)
{
    fprintf(out,
            "usage: accelbench advise SCENE [--workloads LIST] [--accels LIST] [--calibration DIR] [--no-tune]\n"
            "                         [--check] [--res WxH] [--repeat N] [--seed S] [--out DIR] [--quiet]\n"
            "  Which structure to use, before tracing: each candidate is built on the scene at every value of its\n"
            "  search (`accelbench list accels`, \"tune:\") and its cost model predicts its work per ray; the\n"
            "  machine's calibration (`accelbench calibrate`) turns work into time per workload; the candidates\n"
            "  are ranked by predicted time, each at its best predicted setting, with the predicted ratio to\n"
            "  Embree and the term that dominates. --check then measures them (`accelbench run`, paired with\n"
            "  Embree) and reports the regret: the advised choice's measured time over the measured best's.\n"
            "  SCENE             a scene, a comma-separated list or a set (set:medium), as run takes them\n"
            "  --workloads LIST  workloads (default " ADVISE_WORKLOADS ")\n"
            "  --accels LIST     candidates (default " ADVISE_ACCELS ")\n"
            "  --calibration DIR a folder `accelbench calibrate` wrote (default ./calibration)\n"
            "  --no-tune         each candidate at its default only\n"
            "  --check           measure the candidates at their advised settings, one thread, and report the regret\n"
            "  --res WxH, --repeat N, --seed S   the measured rays of --check (default 64x64, 3, 1)\n"
            "  --out DIR         output folder (default results/advise-<date-time>)\n"
            "  --quiet           no progress, nothing listed (the ranking is still printed)\n"
            "  Writes DIR/predictions.csv, advice.csv, advice.md; with --check also DIR/check/ (a run folder),\n"
            "  regret.csv and regret.md. Exit status: 0, 1 when a build, the ranking or a run failed, 2 on bad\n"
            "  input.\n");
}

/* The candidates' tables, from a comma-separated list of names. 0, or 2 after printing why. */
static int read_candidates(const char *list, const struct accel_ops **ops, int max, int *n)
{
    char buf[1024];
    if (snprintf(buf, sizeof buf, "%s", list) >= (int)sizeof buf) {
        fprintf(stderr, "accelbench advise: --accels: the list is too long\n");
        return 2;
    }
    *n = 0;
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (strchr(tok, '[')) {
            fprintf(stderr, "accelbench advise: --accels: %s: give names only; advise searches the parameters\n",
                    term_text(tok));
            return 2;
        }
        const struct accel_ops *a = accel_find(tok);
        if (!a) {
            fprintf(stderr, "accelbench advise: --accels: unknown accelerator '%s' (see: accelbench list accels)\n",
                    term_text(tok));
            return 2;
        }
        bool dup = false;
        for (int i = 0; i < *n; i++) dup |= ops[i] == a;
        if (dup) continue;
        if (*n == max) {
            fprintf(stderr, "accelbench advise: --accels: at most %d candidates\n", max);
            return 2;
        }
        ops[(*n)++] = a;
    }
    if (*n == 0) {
        fprintf(stderr, "accelbench advise: --accels: no accelerator named\n");
        return 2;
    }
    return 0;
}

/* Every name of the workload list known. 0, or 2 after printing the first unknown one. */
static int check_workloads(const char *list)
{
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", list);
    int n = 0;
    for (char *save = NULL, *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save), n++)
        if (!workload_find(tok)) {
            fprintf(stderr, "accelbench advise: --workloads: unknown workload '%s' (see: accelbench list workloads)\n",
                    term_text(tok));
            return 2;
        }
    if (n == 0) {
        fprintf(stderr, "accelbench advise: --workloads: no workload named\n");
        return 2;
    }
    return 0;
}

/* The scenes of SCENE into o (a list and sets expanded, as run's --scenes),
 * each checked without being read. 0, or 2 after printing why. */
static int read_scenes(const char *arg, options *o)
{
    if (options_add_scenes(o, arg)) return 2;
    for (int i = 0; i < o->nscenes; i++) {
        char err[512];
        if (scene_check(o->scenes[i], err, sizeof err)) {
            fprintf(stderr, "accelbench advise: %s\n", err);
            return 2;
        }
    }
    return 0;
}

/* The values a candidate's search tries ("KEY=V|V|..." of its table), or
 * only its default (none declared, or --no-tune): the key in key (empty
 * when there is no search) and the values in vals, '|'-separated. */
static void search_values(const struct accel_ops *a, bool tune, char *key, size_t klen, char *vals, size_t vlen)
{
    key[0] = vals[0] = 0;
    if (!tune || !a->tune) return;
    const char *eq = strchr(a->tune, '=');
    if (!eq) return;
    snprintf(key, klen, "%.*s", (int)(eq - a->tune), a->tune);
    snprintf(vals, vlen, "%s", eq + 1);
}

static double stat_or_nan(const accel_stat *st, int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (!strcmp(st[i].name, name)) return st[i].value;
    return NAN;
}

/* One build: its prediction written as a row of f. 0, or -1 when the build failed (said on stderr). */
static int predict_one(FILE *f, const scene_t *s, const struct accel_ops *a, const char *key, const char *value,
                       bool candidate, bool quiet)
{
    char spec[600], err[1024];
    if (key[0]) snprintf(spec, sizeof spec, "%s[%s=%s]", a->name, key, value);
    else snprintf(spec, sizeof spec, "%s", a->name);
    accel_config ac;
    if (accel_spec_expand(spec, &ac, 1, err, sizeof err) != 1) {
        fprintf(stderr, "accelbench advise: %s: %s\n", spec, err);
        return -1;
    }
    ac.params.threads = 1;
    ac.params.seed = 1;
    accel_settle_params(ac.ops, &ac.params);
    params_format(&ac.params, ac.params_str, sizeof ac.params_str);
    accel_config_label(&ac, ac.label, sizeof ac.label);
    resources_bound_accel_params(&ac.params);
    double ms;
    accel *built = build_accel(&ac, s, &ms);
    if (!built) return -1;
    accel_stat st[ACCEL_STATS_MAX];
    int n = accel_stats(built, st, ACCEL_STATS_MAX);
    size_t mem = built->ops->memory(built);
    built->ops->destroy(built);
    const char *text[] = {s->name, a->name, ac.label, ac.params_str, key, key[0] ? value : ""};
    for (int i = 0; i < 6; i++) {
        if (i) fputc(',', f);
        csv_put_text(f, text[i]);
        if (i == 0) fprintf(f, ",%u,%u", (unsigned)s->prims.count, (unsigned)s->nlights);
    }
    fprintf(f, ",%d,%.6g,%zu", candidate ? 1 : 0, ms, mem);
    for (int i = 0; csv_predicted_columns[i]; i++) {
        double v = stat_or_nan(st, n, csv_predicted_columns[i]);
        if (isnan(v)) fputc(',', f);
        else fprintf(f, ",%.9g", v);
    }
    fputc('\n', f);
    fflush(f);
    if (!quiet) fprintf(stderr, "  %s %s: build %.1f ms\n", term_text(s->name), term_text(ac.label), ms);
    return 0;
}

/* Every candidate at every value of its search on every scene, into path. 0, or 1 when nothing could be
 * predicted or the file could not be written. */
static int write_predictions(const char *path, const char **scenes, int nscenes, const struct accel_ops **cands,
                             int ncands, bool tune, bool quiet)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        fprintf(stderr, "accelbench advise: %s: %s\n", path, strerror(errno));
        return 1;
    }
    fprintf(f, "scene,prims,lights,accel,label,params,key,value,candidate,build_ms,mem_bytes");
    for (int i = 0; csv_predicted_columns[i]; i++) fprintf(f, ",%s", csv_predicted_columns[i]);
    fputc('\n', f);
    int built = 0, failed = 0;
    const struct accel_ops *proxy = accel_find(ADVISE_EMBREE_PROXY);
    for (int si = 0; si < nscenes; si++) {
        char err[1024];
        scene_t *s = scene_load(scenes[si], err, sizeof err);
        if (!s) {
            fprintf(stderr, "accelbench advise: %s\n", err);
            fclose(f);
            return 1;
        }
        if (!quiet) fprintf(stderr, "[%d/%d] %s: %u primitives\n", si + 1, nscenes, term_text(s->name), (unsigned)s->prims.count);
        bool proxy_built = false;
        for (int ci = 0; ci < ncands; ci++) {
            const struct accel_ops *a = cands[ci];
            if ((a->flags & ACCEL_SHADOW_ONLY) && s->nlights == 0) continue; /* nothing it answers */
            char key[64], vals[512];
            search_values(a, tune, key, sizeof key, vals, sizeof vals);
            char *save = NULL;
            for (char *v = key[0] ? strtok_r(vals, "|", &save) : vals; v; v = key[0] ? strtok_r(NULL, "|", &save) : NULL) {
                if (predict_one(f, s, a, key, v, true, quiet)) failed++;
                else built++;
                if (!key[0]) break;
            }
            proxy_built |= a == proxy;
        }
        if (!proxy_built && proxy) {
            if (predict_one(f, s, proxy, "", "", false, quiet)) failed++;
        }
        scene_free(s);
    }
    bool bad = ferror(f) != 0;
    if (fclose(f) || bad) {
        fprintf(stderr, "accelbench advise: %s: write failed\n", path);
        return 1;
    }
    if (failed && !quiet) fprintf(stderr, "accelbench advise: %d build(s) failed; those settings are not ranked\n", failed);
    return built ? 0 : 1;
}

int advise_main(int argc, char **argv)
{
    static const struct option opts[] = {
        {"workloads", required_argument, NULL, 'w'}, {"accels", required_argument, NULL, 'a'},
        {"calibration", required_argument, NULL, 'c'}, {"no-tune", no_argument, NULL, 'T'},
        {"check", no_argument, NULL, 'k'},          {"res", required_argument, NULL, 'r'},
        {"repeat", required_argument, NULL, 'n'},   {"seed", required_argument, NULL, 'e'},
        {"out", required_argument, NULL, 'o'},      {"quiet", no_argument, NULL, 'q'},
        {"help", no_argument, NULL, 'h'},           {NULL, 0, NULL, 0}};
    const char *workloads = ADVISE_WORKLOADS, *accels = ADVISE_ACCELS, *calibration = "calibration",
               *res = "64x64", *repeat = "3", *seed = "1", *out = NULL;
    bool tune = true, check = false, quiet = false;
    int c;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "hq", opts, NULL)) != -1) {
        switch (c) {
        case 'w': workloads = optarg; break;
        case 'a': accels = optarg; break;
        case 'c': calibration = optarg; break;
        case 'T': tune = false; break;
        case 'k': check = true; break;
        case 'r': {
            int w, h;
            if (options_parse_res(optarg, &w, &h)) return 2;
            res = optarg;
            break;
        }
        case 'n': {
            long n;
            if (options_parse_long("repeat", optarg, 1, 1000, &n)) return 2;
            repeat = optarg;
            break;
        }
        case 'e': {
            uint64_t v;
            if (options_parse_seed(optarg, &v)) return 2;
            seed = optarg;
            break;
        }
        case 'o': out = optarg; break;
        case 'q': quiet = true; break;
        case 'h': advise_usage(stdout); return 0;
        default: return cli_bad_option("advise", argv[optind - 1]);
        }
    }
    const char *scene_arg = cli_one_operand("advise", "scene", "SCENE", argc, argv);
    if (!scene_arg) return 2;
    const struct accel_ops *cands[OPT_LIST_MAX];
    int ncands;
    if (read_candidates(accels, cands, OPT_LIST_MAX, &ncands)) return 2;
    options scenes = {0};
    int rc = read_scenes(scene_arg, &scenes);
    if (rc == 0) rc = check_workloads(workloads);
    char cal_csv[PATH_MAX];
    snprintf(cal_csv, sizeof cal_csv, "%s/calibration.csv", calibration);
    if (rc == 0 && access(cal_csv, R_OK) != 0) {
        fprintf(stderr, "accelbench advise: %s: %s (run `accelbench calibrate --out %s` first, or name one with "
                        "--calibration DIR)\n", term_text(cal_csv), strerror(errno), term_text(calibration));
        rc = 2;
    }
    char dir[PATH_MAX], path[PATH_MAX + 32], script[PATH_MAX], self[PATH_MAX];
    if (rc == 0) rc = output_folder(out, "advise-", dir, sizeof dir);
    if (rc == 0) {
        /* This binary's path, read before the builds: a rebuild meanwhile would leave /proc/self/exe "(deleted)". */
        ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
        self[n > 0 ? n : 0] = 0;
        memory_cap_set_mib(0);
        snprintf(path, sizeof path, "%s/predictions.csv", dir);
        rc = write_predictions(path, scenes.scenes, scenes.nscenes, cands, ncands, tune, quiet);
    }
    options_free(&scenes);
    if (rc) return rc;
    snprintf(script, sizeof script, "%s/scripts/advise.py", ACCELBENCH_SOURCE_DIR);
    char *args[] = {(char *)python_interpreter(), script, dir, "--calibration", (char *)calibration, "--workloads",
                    (char *)workloads, "--accelbench", self, "--res", (char *)res, "--repeat", (char *)repeat,
                    "--seed", (char *)seed, check ? "--check" : "--no-check", quiet ? "--quiet" : NULL, NULL};
    rc = spawn_wait(args);
    return rc == 0 ? 0 : rc == 2 ? 2 : 1;
}
