/* cli_args.c: see cli_args.h. */
#include "cli_args.h"

#include <getopt.h>
#include <stdio.h>
#include "../run/output.h"

int cli_bad_option(const char *cmd, const char *arg)
{
    fprintf(stderr, "accelbench %s: unknown or incomplete option '%s' (see accelbench %s --help)\n", cmd,
            term_text(arg), cmd);
    return 2;
}

const char *cli_one_run_folder(const char *cmd, int argc, char **argv)
{
    if (optind >= argc) {
        fprintf(stderr, "accelbench %s: no run folder given (accelbench %s RUN_DIR; see --help)\n", cmd, cmd);
        return NULL;
    }
    if (optind + 1 < argc) {
        fprintf(stderr, "accelbench %s: unexpected argument '%s' (one run folder; see --help)\n", cmd,
                term_text(argv[optind + 1]));
        return NULL;
    }
    return argv[optind];
}

int cli_no_operands(const char *cmd, int argc, char **argv)
{
    if (optind >= argc) return 0;
    fprintf(stderr, "accelbench %s: unexpected argument '%s' (see --help)\n", cmd, term_text(argv[optind]));
    return 2;
}
