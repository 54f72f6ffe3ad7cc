/* report_cmd.c: `accelbench report RUN_DIR` (see report_cmd.h): the
 * options, then run/run_outputs.h's report_write. */
#include "report_cmd.h"

#include <getopt.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include "../run/run_outputs.h"

static void report_usage(FILE *out)
{
    fprintf(out,
            "usage: accelbench report RUN_DIR [--out FILE.html] [--pictures auto|on|off] [--quiet]\n"
            "  One self-contained HTML page of a run folder (images embedded): machine, revision, threads and\n"
            "  command; a sortable table of every cell coloured by its ratio to Embree; the plots; per-scene\n"
            "  heat maps of primary-ray cost on one colour scale and a picture of each scene; cost growth fitted\n"
            "  on scaling series (spd:FAMILY:N); real mismatches with their verify commands; reproduce findings.\n"
            "  --out FILE.html         where to write it (default RUN_DIR/report.html)\n"
            "  --pictures auto|on|off  render heat maps and pictures with this build (auto: scenes of at most\n"
            "                          100000 primitives; each costs one build per accelerator, default auto)\n"
            "  --quiet                 do not print what was written\n"
            "  Exit status: 0, 1 when the page could not be written, 2 on bad input.\n");
}

int report_main(int argc, char **argv)
{
    static const struct option opts[] = {{"out", required_argument, NULL, 'o'},
                                         {"pictures", required_argument, NULL, 'p'},
                                         {"quiet", no_argument, NULL, 'q'},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    const char *out = NULL, *pictures = "auto";
    bool quiet = false;
    int c;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "hq", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case 'p':
            if (strcmp(optarg, "auto") && strcmp(optarg, "on") && strcmp(optarg, "off")) {
                fprintf(stderr, "accelbench report: --pictures %s: expected auto, on or off\n", optarg);
                return 2;
            }
            pictures = optarg;
            break;
        case 'q': quiet = true; break;
        case 'h': report_usage(stdout); return 0;
        default:
            fprintf(stderr, "accelbench report: unknown or incomplete option '%s' (see accelbench report --help)\n",
                    argv[optind - 1]);
            return 2;
        }
    }
    if (optind >= argc) {
        fprintf(stderr, "accelbench report: no run folder given (accelbench report RUN_DIR; see --help)\n");
        return 2;
    }
    if (optind + 1 < argc) {
        fprintf(stderr, "accelbench report: unexpected argument '%s' (one run folder; see --help)\n", argv[optind + 1]);
        return 2;
    }
    return report_write(argv[optind], out, pictures, quiet);
}
