/* main.c: the accelbench program: subcommand dispatch and `list`.
 *
 *   accelbench list [accels|scenes|workloads]
 *   accelbench list accels --markdown               parameter tables for docs/accels/
 *   accelbench run     --scenes L --accels L --workloads L [...]   benchmark matrix -> CSV + plots
 *   accelbench merge   DIR... --out DIR                          shard folders of run --shard K/N -> one CSV
 *   accelbench verify  --scenes L --accels L --workloads L [...]   agreement with Embree
 *   accelbench render  --scene S --accel A --out FILE.png [...]    image or cost heat map
 *   accelbench reproduce woo92|havran|spd [--out DIR] [--quick] [...]  a paper's tables with our numbers
 *   accelbench report RUN_DIR [--out FILE.html]                     the run folder as one HTML page
 *   accelbench predict RUN_DIR [--out DIR]                          cost models against the measured counters
 *   accelbench calibrate [--out DIR] [--from RUN_DIR]                what each counter costs on this machine
 *   accelbench tune --scenes L --workloads L [--accels L]             each structure at its best per scene
 *   accelbench advise SCENE [--workloads L] [--check]                 which structure, predicted before tracing
 *
 * Exit status: 0 success, 1 verify found a real mismatch or run could not
 * write its results, 2 bad input, 128+N when run stopped on signal N. */
#include <stdio.h>
#include <string.h>
#include "../run/matrix.h"
#include "../run/merge.h"
#include "advise_cmd.h"
#include "calibrate_cmd.h"
#include "options.h"
#include "predict_cmd.h"
#include "render_cmd.h"
#include "../reproduce/reproduce.h"
#include "report_cmd.h"
#include "scene_cmd.h"
#include "tune_cmd.h"
#include "verify_cmd.h"
#include "version.h"

static void usage(FILE *out)
{
    fprintf(out,
            "accelbench: ray tracing acceleration structures side by side, checked against Embree\n"
            "\n"
            "usage: accelbench COMMAND [options]   (accelbench COMMAND --help for its options)\n"
            "  list [accels|scenes|workloads]   names, summaries, parameters with defaults\n"
            "           (list accels --markdown: each parameter table as Markdown, for docs/accels/)\n"
            "  run      benchmark matrix: scenes x accels x workloads -> DIR/matrix.csv and plots\n"
            "  merge    DIR... --out DIR: the folders of run --shard K/N into one matrix.csv, every cell once\n"
            "  verify   every ray's answer against Embree; mismatches classified and replayable\n"
            "  render   a shaded image or a per-pixel cost heat map through one accelerator\n"
            "  reproduce EXPERIMENT   a paper's tables re-run with our numbers, verified against Embree:\n");
    reproduce_list(out, "    ", 6);
    fprintf(out,
            "  report   RUN_DIR: one self-contained HTML page of a run folder (table, plots, heat maps, fits)\n"
            "  predict  RUN_DIR: each structure's cost model against its measured counters (rank correlation, error)\n"
            "  calibrate  what a box test, a primitive test and a step of each structure cost on this machine\n"
            "  tune     each structure's main parameter searched per scene and workload, default against tuned\n"
            "  advise   SCENE: which structure to use, ranked by predicted time before tracing (--check: regret)\n"
            "  scene    info SCENE (counts, bounds, view, hash) | export SCENE --nff FILE\n"
            "  version  the build's git revision\n"
            "  help     this text (also --help, -h)\n"
            "\n"
            "example: accelbench run --scenes spd:balls:3,bunny --accels exhaustive,embree --res 64x64\n");
}

static void list_accels(void)
{
    printf("accelerators (--accels; parameters with --param ACCEL.KEY=VALUE):\n");
    for (int i = 0; accel_registry[i]; i++) {
        const struct accel_ops *a = accel_registry[i];
        printf("  %-14s %s\n", a->name, a->summary);
        printf("  %-14s paper: %s\n", "", a->paper);
        if (a->flags & (ACCEL_MUTATES | ACCEL_SHADOW_ONLY | ACCEL_NO_COUNTERS))
            printf("  %-14s flags:%s%s%s\n", "", a->flags & ACCEL_MUTATES ? " mutates-while-tracing(traced on 1 thread)" : "",
                   a->flags & ACCEL_SHADOW_ONLY ? " shadow-rays-only" : "",
                   a->flags & ACCEL_NO_COUNTERS ? " counters-not-observable" : "");
        if (a->tune) printf("  %-14s tune: %s\n", "", a->tune);
        /* A default this machine settles to another value (bvh's isa=auto) says which: that is what the CSV
         * records, and what the plots and report take as the default. */
        accel_params settled;
        params_defaults(&settled, a->params);
        accel_settle_params(a, &settled);
        for (int k = 0; a->params[k].name; k++) {
            char here[160] = "", allowed[256];
            if (k < settled.count && strcmp(settled.values[k], a->params[k].default_value))
                snprintf(here, sizeof here, "[here: %s] ", settled.values[k]);
            params_allowed(&a->params[k], allowed, sizeof allowed);
            printf("  %-14s   %s=%s  %s(%s) %s\n", "", a->params[k].name, a->params[k].default_value, here, allowed,
                   a->params[k].help);
        }
    }
}

/* One Markdown table cell: '|' escaped, an empty value shown as such. */
static void md_cell(const char *s, bool code)
{
    if (!*s) {
        fputs(" (empty) |", stdout);
        return;
    }
    fputs(code ? " `" : " ", stdout);
    for (; *s; s++) {
        if (*s == '|') putchar('\\');
        putchar(*s);
    }
    fputs(code ? "` |" : " |", stdout);
}

/* `list accels --markdown`: per accelerator, its parameter table as Markdown
 * between the marker comments docs/accels/ pages hold it in; the table's
 * fields as they are. tests/test_docs_params.sh compares the pages with it and
 * scripts/docs-params.sh rewrites them from it. */
static void list_accels_markdown(void)
{
    for (int i = 0; accel_registry[i]; i++) {
        const struct accel_ops *a = accel_registry[i];
        printf("<!-- params:%s begin -->\n", a->name);
        if (!a->params[0].name) printf("`%s` takes no parameters.\n", a->name);
        else {
            printf("| key | default | allowed | help |\n|---|---|---|---|\n");
            for (int k = 0; a->params[k].name; k++) {
                char allowed[256];
                params_allowed(&a->params[k], allowed, sizeof allowed);
                putchar('|');
                md_cell(a->params[k].name, true);
                md_cell(a->params[k].default_value, true);
                md_cell(allowed, false);
                md_cell(a->params[k].help, false);
                putchar('\n');
            }
        }
        printf("<!-- params:%s end -->\n", a->name);
    }
}

static void list_workloads(void)
{
    printf("workloads (--workloads; image size --res WxH, --spp N, --corners, --depth N, --seed S):\n");
    for (int i = 0; workload_table[i].name; i++)
        printf("  %-11s %-8s %s\n", workload_table[i].name, workload_table[i].query == QUERY_ANY ? "any-hit" : "closest",
               workload_table[i].summary);
}

static int cmd_list(int argc, char **argv)
{
    const char *what = argc > 1 ? argv[1] : "all";
    if (strcmp(what, "--help") == 0 || strcmp(what, "-h") == 0) {
        printf("usage: accelbench list [accels|scenes|workloads]\n"
               "       accelbench list accels --markdown   parameter tables as Markdown (docs/accels/)\n");
        return 0;
    }
    if (!strcmp(what, "accels") && argc > 2) {
        if (argc == 3 && !strcmp(argv[2], "--markdown")) {
            list_accels_markdown();
            return 0;
        }
        fprintf(stderr, "accelbench list accels: unknown option '%s' (--markdown)\n", argv[2]);
        return 2;
    }
    bool all = strcmp(what, "all") == 0;
    if (!all && strcmp(what, "accels") && strcmp(what, "scenes") && strcmp(what, "workloads")) {
        fprintf(stderr, "accelbench list: unknown list '%s' (accels, scenes or workloads)\n", what);
        return 2;
    }
    if (all || !strcmp(what, "accels")) list_accels();
    if (all || !strcmp(what, "scenes")) {
        printf("scenes (--scenes):\n");
        scene_catalogue_print(stdout);
    }
    if (all || !strcmp(what, "workloads")) list_workloads();
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h") || !strcmp(argv[1], "help")) {
        usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "version") || !strcmp(cmd, "--version")) {
        printf("accelbench %s\n", ACCELBENCH_GIT_REV);
        return 0;
    }
    if (!strcmp(cmd, "list")) return cmd_list(argc - 1, argv + 1);
    if (!strcmp(cmd, "scene")) return scene_cmd_main(argc - 1, argv + 1);
    if (!strcmp(cmd, "reproduce")) return reproduce_main(argc - 1, argv + 1);
    if (!strcmp(cmd, "merge")) return merge_main(argc - 1, argv + 1);
    if (!strcmp(cmd, "report")) return report_main(argc - 1, argv + 1);
    if (!strcmp(cmd, "predict")) return predict_main(argc - 1, argv + 1);
    if (!strcmp(cmd, "calibrate")) return calibrate_main(argc - 1, argv + 1);
    if (!strcmp(cmd, "tune")) return tune_main(argc - 1, argv + 1);
    if (!strcmp(cmd, "advise")) return advise_main(argc - 1, argv + 1);
    int (*run)(options *) = !strcmp(cmd, "run") ? matrix_run : !strcmp(cmd, "verify") ? verify_main
                                                            : !strcmp(cmd, "render") ? render_main : NULL;
    if (!run) {
        fprintf(stderr, "accelbench: unknown command '%s' (see accelbench --help)\n", cmd);
        return 2;
    }
    options o;
    int rc = options_parse(&o, cmd, argc - 1, argv + 1);
    o.argc_full = argc;
    o.argv_full = argv;
    if (rc == 0) rc = run(&o);
    else if (rc == 1) rc = 0; /* --help */
    options_free(&o);
    return rc;
}
