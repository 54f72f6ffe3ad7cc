/* reproduce_survey.c: `accelbench reproduce survey`: the comparison the
 * survey's closing section asks for (its Figure 1's considerations as
 * numbers), every structure at its default and at its tuned setting.
 * Here: the shared options, checked, then scripts/survey.py, which runs
 * `accelbench tune`, `run` and scripts/predict.py (argument vectors, no
 * shell) and writes the table; see its text for what each column is. */
#include "reproduce.h"

#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#include <limits.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include "../run/output.h"
#include "reproduce_kit.h"

#define SURVEY_SCENES "set:spd,set:medium,sponza"
#define SURVEY_SCENES_QUICK "spd:balls:1,spd:gears:2,spd:tetra:3"
#define SURVEY_ACCELS "grid,grid-raybox,octree,bsp,bvh-gs,slabs-kk,raycls,lightbuf,raycoh,exhaustive,bvh,embree,cgal-aabb"
#define SURVEY_RES "32x32"
#define SURVEY_RES_QUICK "16x16"

void survey_usage(FILE *out)
{
    fprintf(out,
            "    survey   the survey's structures (and bvh, Embree, CGAL's tree) at their defaults and tuned\n"
            "             (`accelbench tune`), " SURVEY_SCENES " x the five workloads, " SURVEY_RES ", one\n"
            "             thread, paired; one row per structure by family: speed with its 95 %% interval,\n"
            "             growth with scene size, build time and the rays that pay for it, bytes per\n"
            "             primitive, diffuse over primary, default over tuned, the cost model's rank\n"
            "             correlation. survey.csv, survey.md. --quick: " SURVEY_SCENES_QUICK ", " SURVEY_RES_QUICK ".\n"
            "             Every trace is timed on one thread; --threads and --memcap are not taken.\n");
}

int reproduce_survey(int argc, char **argv)
{
    for (int i = 1; i < argc; i++)
        if (!strncmp(argv[i], "--memcap", 8) || !strncmp(argv[i], "--threads", 9)) {
            fprintf(stderr, "accelbench reproduce survey: %s: not taken (one thread; the runs keep their own memory "
                            "cap)\n", term_text(argv[i]));
            return 2;
        }
    rp_kit k;
    memset(&k, 0, sizeof k);
    int parsed = rp_parse(&k, argc, argv, reproduce_usage);
    if (parsed) return parsed == 1 ? 0 : parsed;
    char dir[PATH_MAX], script[PATH_MAX], self[PATH_MAX], repeat[16];
    if (output_folder(k.o.out, "survey-", dir, sizeof dir)) return 2;
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    self[n > 0 ? n : 0] = 0;
    snprintf(script, sizeof script, "%s/scripts/survey.py", ACCELBENCH_SOURCE_DIR);
    snprintf(repeat, sizeof repeat, "%d", k.o.repeat);
    const char *scenes = k.o.scenes ? k.o.scenes : k.o.quick ? SURVEY_SCENES_QUICK : SURVEY_SCENES;
    const char *accels = k.o.accels ? k.o.accels : SURVEY_ACCELS;
    char *args[20] = {(char *)python_interpreter(), script, "--accelbench", self, "--out", dir, "--scenes",
                      (char *)scenes, "--accels", (char *)accels, "--res", k.o.quick ? SURVEY_RES_QUICK : SURVEY_RES,
                      "--repeat", repeat};
    int na = 14;
    if (!k.o.plots) args[na++] = "--no-plots";
    if (k.o.quiet) args[na++] = "--quiet";
    args[na] = NULL;
    int rc = spawn_wait(args);
    return rc == 0 ? 0 : rc == 2 ? 2 : 1;
}
