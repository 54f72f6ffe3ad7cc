/* predict_cmd.c: `accelbench predict RUN_DIR` (see predict_cmd.h): the
 * options, then scripts/predict.py over the run folder's matrix.csv, run
 * with an argument vector (no shell). */
#include "predict_cmd.h"

#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#include <getopt.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <unistd.h>
#include "../run/output.h"
#include "cli_args.h"

static void predict_usage(FILE *out)
{
    fprintf(out,
            "usage: accelbench predict RUN_DIR [--out DIR] [--no-plot] [--quiet]\n"
            "  How well each structure's cost model predicts its measured work: for every configuration with a\n"
            "  model (grid, grid-raybox, octree, bsp, slabs-kk, bvh-gs, bvh, lightbuf; docs/accels, \"Cost model\")\n"
            "  and each counter (tests, box tests, steps per ray), per workload and over all: the cells, Spearman's\n"
            "  rank correlation of predicted and measured, the median relative error and the median ratio; then\n"
            "  the rank correlation of trace time with the predicted and with the measured work.\n"
            "  Writes prediction.csv, prediction_time.csv, prediction.md and prediction.png (predicted against\n"
            "  measured, log-log).\n"
            "  --out DIR    where to write them (an existing folder; default RUN_DIR)\n"
            "  --no-plot    the CSV and Markdown only\n"
            "  --quiet      do not print what was written\n"
            "  Exit status: 0, 1 when the script failed, 2 on bad input.\n");
}

int predict_main(int argc, char **argv)
{
    static const struct option opts[] = {{"out", required_argument, NULL, 'o'},
                                         {"no-plot", no_argument, NULL, 'n'},
                                         {"quiet", no_argument, NULL, 'q'},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    const char *out = NULL;
    bool quiet = false, no_plot = false;
    int c;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "hq", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case 'n': no_plot = true; break;
        case 'q': quiet = true; break;
        case 'h': predict_usage(stdout); return 0;
        default: return cli_bad_option("predict", argv[optind - 1]);
        }
    }
    const char *dir = cli_one_run_folder("predict", argc, argv);
    char csv[PATH_MAX], script[PATH_MAX];
    if (!dir) return 2;
    if (run_folder_csv("predict", dir, csv, sizeof csv)) return 2;
    if (out && !path_is_dir(out)) {
        fprintf(stderr, "accelbench predict: --out %s: no such folder\n", term_text(out));
        return 2;
    }
    snprintf(script, sizeof script, "%s/scripts/predict.py", ACCELBENCH_SOURCE_DIR);
    char self[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    self[n > 0 ? n : 0] = 0;
    char *args[12];
    int k = 0;
    args[k++] = (char *)python_interpreter();
    args[k++] = script;
    args[k++] = (char *)dir;
    args[k++] = "--accelbench";
    args[k++] = self;
    if (out) args[k++] = "--out", args[k++] = (char *)out;
    if (no_plot) args[k++] = "--no-plot";
    if (quiet) args[k++] = "--quiet";
    args[k] = NULL;
    int rc = spawn_wait(args);
    return rc == 0 ? 0 : rc == 2 ? 2 : 1;
}
