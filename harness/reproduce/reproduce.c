/* reproduce.c: `accelbench reproduce EXPERIMENT`: the usage and the
 * dispatch to the experiments (reproduce.h). */
#include "reproduce.h"

#include <string.h>
#include "reproduce_kit.h"

typedef struct {
    const char *name;
    int (*run)(int argc, char **argv);
    void (*usage)(FILE *out);
    const char *summary; /* one line for accelbench --help */
} experiment;

static const experiment experiments[] = {
    {"woo92", reproduce_woo92, woo92_usage, "Woo 1992's Tables 1-4 and an ablation, re-run: our numbers, verified"},
    {"havran", reproduce_havran, havran_usage, "Havran and Sixta's grids and Havran's octrees (RTN 1999) on the SPD, plus BSPs"},
    {"spd", reproduce_spd, spd_usage, "the SPD Readme's testing procedure: its ray counts and tests per ray beside ours"},
    {"survey", reproduce_survey, survey_usage, "every structure of the survey, default and tuned: its Figure 1's considerations as numbers"},
};
#define N_EXPERIMENTS (int)(sizeof experiments / sizeof experiments[0])

void reproduce_list(FILE *out, const char *indent, int width)
{
    for (int i = 0; i < N_EXPERIMENTS; i++)
        fprintf(out, "%sreproduce %-*s %s\n", indent, width, experiments[i].name, experiments[i].summary);
}

/* "woo92, havran, spd": the names, for messages. */
static void known_names(char *buf, size_t len)
{
    size_t n = 0;
    buf[0] = '\0';
    for (int i = 0; i < N_EXPERIMENTS && n < len; i++)
        n += (size_t)snprintf(buf + n, len - n, "%s%s", i ? ", " : "", experiments[i].name);
}

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
    char known[256];
    known_names(known, sizeof known);
    fprintf(stderr, "accelbench reproduce: unknown experiment '%s' (known: %s; see accelbench reproduce --help)\n", exp,
            known);
    return 2;
}
