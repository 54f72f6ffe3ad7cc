/* reproduce.c: `accelbench reproduce EXPERIMENT`: the usage and the
 * dispatch to the experiments (reproduce.h). */
#include "reproduce.h"

#include <string.h>
#include "reproduce_kit.h"

typedef struct {
    const char *name;
    int (*run)(int argc, char **argv);
    void (*usage)(FILE *out);
} experiment;

static const experiment experiments[] = {
    {"woo92", reproduce_woo92, woo92_usage},
    {"havran", reproduce_havran, havran_usage},
    {"spd", reproduce_spd, spd_usage},
};
#define N_EXPERIMENTS (int)(sizeof experiments / sizeof experiments[0])

void reproduce_usage(FILE *out)
{
    fprintf(out,
            "usage: accelbench reproduce EXPERIMENT [--out DIR] [--threads N] [--repeat N] [--quick] [--no-plots] [--quiet]\n"
            "                                  [--memcap MIB]\n"
            "  Re-runs a paper's experiments on our scenes and prints the paper's tables with OUR\n"
            "  numbers, each under a \"finding:\" line that compares them with the paper's.\n"
            "  experiments:\n");
    for (int i = 0; i < N_EXPERIMENTS; i++) experiments[i].usage(out);
    rp_usage_options(out);
}

int reproduce_main(int argc, char **argv)
{
    if (argc < 2) {
        reproduce_usage(stderr);
        return 2;
    }
    const char *exp = argv[1];
    if (!strcmp(exp, "--help") || !strcmp(exp, "-h") || !strcmp(exp, "help")) {
        reproduce_usage(stdout);
        return 0;
    }
    for (int i = 0; i < N_EXPERIMENTS; i++)
        if (!strcmp(exp, experiments[i].name)) return experiments[i].run(argc - 1, argv + 1);
    fprintf(stderr, "accelbench reproduce: unknown experiment '%s' (known: woo92, havran, spd; see accelbench reproduce --help)\n",
            exp);
    return 2;
}
