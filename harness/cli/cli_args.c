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

const char *cli_one_operand(const char *cmd, const char *what, const char *name, int argc, char **argv)
{
    if (optind >= argc) {
        fprintf(stderr, "accelbench %s: no %s given (accelbench %s %s; see --help)\n", cmd, what, cmd, name);
        return NULL;
    }
    if (optind + 1 < argc) {
        fprintf(stderr, "accelbench %s: unexpected argument '%s' (one %s; see --help)\n", cmd,
                term_text(argv[optind + 1]), what);
        return NULL;
    }
    return argv[optind];
}

const char *cli_one_run_folder(const char *cmd, int argc, char **argv)
{
    return cli_one_operand(cmd, "run folder", "RUN_DIR", argc, argv);
}

int cli_no_operands(const char *cmd, int argc, char **argv)
{
    if (optind >= argc) return 0;
    fprintf(stderr, "accelbench %s: unexpected argument '%s' (see --help)\n", cmd, term_text(argv[optind]));
    return 2;
}
