/* tune_cmd.c: `accelbench tune` (see tune_cmd.h): the options, checked
 * here so that a mistake is one line before anything runs, then
 * scripts/tune.py, which runs the training and the measuring matrices with
 * this binary (argument vectors, no shell) and writes the tables. */
#include "tune_cmd.h"

#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#include <getopt.h>
#include <limits.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include "../run/output.h"
#include "cli_args.h"
#include "options.h"

static void tune_usage(FILE *out)
{
    fprintf(out,
            "usage: accelbench tune --scenes LIST --workloads LIST [--accels LIST] [--res WxH] [--repeat N]\n"
            "                       [--threads N] [--seed S] [--out DIR] [--quiet]\n"
            "  Each structure at its best for the scene. For every accelerator that declares a search (`accelbench\n"
            "  list accels`, its \"tune:\" line: one parameter, the values to try), per scene and workload: every\n"
            "  value traced on training rays (a quarter as many, other rays: half the resolution, seed + 1; paired\n"
            "  with Embree; DIR/training/), the one with the lowest ratio to Embree chosen, then the default and\n"
            "  the chosen setting measured on the real rays, paired with Embree, into DIR/matrix.csv.\n"
            "  DIR/tuning.csv and tuning.md: per cell the default, the choice, both ratios, the gain and the\n"
            "  search's own time; per structure the geometric-mean gain over its default.\n"
            "  --scenes LIST      scenes, as run takes them\n"
            "  --workloads LIST   workloads, as run takes them\n"
            "  --accels LIST      accelerators (default: every one with a search); others, and instances given\n"
            "                     with parameters, are measured as given\n"
            "  --res WxH          image size of the measured rays (default 64x64; training at half per axis)\n"
            "  --repeat N         timed repeats of the training and the measured cells (default 3)\n"
            "  --threads N        tracing threads (default: all cores)\n"
            "  --seed S           seed of the measured rays (default 1; training S + 1)\n"
            "  --out DIR          output folder (default results/tune-<date-time>); rerun to resume\n"
            "  --quiet            no progress from the runs (a failing run's last lines still), nothing listed\n"
            "  Exit status: 0, 1 when a run failed, 2 on bad input.\n");
}

int tune_main(int argc, char **argv)
{
    static const struct option opts[] = {
        {"scenes", required_argument, NULL, 's'}, {"workloads", required_argument, NULL, 'w'},
        {"accels", required_argument, NULL, 'a'}, {"res", required_argument, NULL, 'r'},
        {"repeat", required_argument, NULL, 'n'}, {"threads", required_argument, NULL, 't'},
        {"seed", required_argument, NULL, 'e'},   {"out", required_argument, NULL, 'o'},
        {"quiet", no_argument, NULL, 'q'},        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0}};
    const char *scenes = NULL, *workloads = NULL, *accels = "", *res = "64x64", *repeat = "3", *threads = "",
               *seed = "1", *out = NULL;
    bool quiet = false;
    int c;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "hq", opts, NULL)) != -1) {
        switch (c) {
        case 's': scenes = optarg; break;
        case 'w': workloads = optarg; break;
        case 'a': accels = optarg; break;
        case 'r': {
            int w, h;
            if (options_parse_res(optarg, &w, &h)) return 2;
            res = optarg;
            break;
        }
        case 'n':
        case 't': {
            long n;
            if (options_parse_long(c == 'n' ? "repeat" : "threads", optarg, 1, c == 'n' ? 1000 : 1024, &n)) return 2;
            *(c == 'n' ? &repeat : &threads) = optarg;
            break;
        }
        case 'e': {
            uint64_t v;
            if (options_parse_seed(optarg, &v)) return 2;
            if (v == UINT64_MAX) {
                fprintf(stderr, "accelbench tune: --seed %s: leaves no seed + 1 for the training rays\n",
                        term_text(optarg));
                return 2;
            }
            seed = optarg;
            break;
        }
        case 'o': out = optarg; break;
        case 'q': quiet = true; break;
        case 'h': tune_usage(stdout); return 0;
        default: return cli_bad_option("tune", argv[optind - 1]);
        }
    }
    if (cli_no_operands("tune", argc, argv)) return 2;
    if (!scenes || !workloads) {
        fprintf(stderr, "accelbench tune: --%s is required (see --help)\n", scenes ? "workloads" : "scenes");
        return 2;
    }
    char dir[PATH_MAX], script[PATH_MAX], self[PATH_MAX];
    if (output_folder(out, "tune-", dir, sizeof dir)) return 2;
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    self[n > 0 ? n : 0] = 0;
    snprintf(script, sizeof script, "%s/scripts/tune.py", ACCELBENCH_SOURCE_DIR);
    char *args[] = {(char *)python_interpreter(), script, "--accelbench", self, "--scenes", (char *)scenes,
                    "--workloads", (char *)workloads, "--accels", (char *)accels, "--res", (char *)res,
                    "--repeat", (char *)repeat, "--threads", (char *)threads, "--seed", (char *)seed, "--out", dir,
                    quiet ? "--quiet" : NULL, NULL};
    int rc = spawn_wait(args);
    return rc == 0 ? 0 : rc == 2 ? 2 : 1;
}
