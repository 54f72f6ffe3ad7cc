/* report_cmd.c: `accelbench report RUN_DIR` (see report_cmd.h): the
 * options, then run/run_outputs.h's report_write. */
#include "report_cmd.h"

#include <getopt.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include "../run/run_outputs.h"
#include "cli_args.h"

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
        default: return cli_bad_option("report", argv[optind - 1]);
        }
    }
    const char *dir = cli_one_run_folder("report", argc, argv);
    if (!dir) return 2;
    return report_write(dir, out, pictures, quiet);
}
