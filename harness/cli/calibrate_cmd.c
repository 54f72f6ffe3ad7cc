/* calibrate_cmd.c: `accelbench calibrate` (see calibrate_cmd.h): measure
 * the calibration matrix with this binary's `run` (unless --from names a
 * run folder), then fit what each counter costs with scripts/calibrate.py.
 * Both are child processes with argument vectors (no shell). */
#include "calibrate_cmd.h"

#ifndef ACCELBENCH_SOURCE_DIR
#define ACCELBENCH_SOURCE_DIR "."
#endif
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "../../accel/accel.h"
#include "../../accel/params.h"
#include "../run/output.h"
#include "cli_args.h"
#include "options.h"

/* The calibration matrix: small SPD scenes of every kind of primitive,
 * every accelerator whose work is observable, at its defaults, four
 * workloads from coherent to incoherent. */
#define CAL_SCENES "spd:balls:3,spd:gears:3,spd:mount:5,spd:tetra:5,spd:rings:5,spd:teapot:8,spd:lattice:6"
#define CAL_SCENES_QUICK "spd:balls:2,spd:gears:2,spd:tetra:4,spd:mount:4"
#define CAL_ACCELS "exhaustive,grid,grid-raybox,octree,bsp,bvh-gs,slabs-kk,raycls,lightbuf,bvh,raycoh"
#define CAL_WORKLOADS "primary,shadow,diffuse,random"
/* Three Debian-packaged meshes, for the structures `advise` ranks: costs
 * fitted on small SPD scenes alone do not carry to meshes, whose walks
 * touch more memory. Exhaustive, ray classification and ray coherence are
 * calibrated on the SPD scenes only (each costs minutes a mesh cell). */
#define CAL_MESHES "bunny,armadillo,elephant"
#define CAL_MESH_ACCELS "grid,grid-raybox,octree,bsp,bvh-gs,slabs-kk,lightbuf,bvh"

static void calibrate_usage(FILE *out)
{
    fprintf(out,
            "usage: accelbench calibrate [--out DIR] [--from RUN_DIR] [--quick] [--threads N] [--quiet]\n"
            "  What a box test, a primitive test and a traversal step of each structure cost on this machine:\n"
            "  per accelerator configuration, its trace time per ray fitted as fixed + costs x counters (least\n"
            "  squares, costs >= 0) over the cells of a calibration matrix, with R^2, the fit's relative errors\n"
            "  and the error held out by scene. Keyed by the CPU and the SIMD instruction set.\n"
            "  The matrix: " CAL_SCENES "\n"
            "    x " CAL_ACCELS "\n"
            "    and " CAL_MESHES " x " CAL_MESH_ACCELS "\n"
            "    x " CAL_WORKLOADS ", 64x64, 3 paired repeats.\n"
            "  Writes DIR/run/ (the matrix), DIR/calibration.csv, calibration_cells.csv and calibration.md.\n"
            "  --out DIR        the output folder (created; default ./calibration)\n"
            "  --from RUN_DIR   fit an existing run folder instead of measuring (DIR/run is not written)\n"
            "  --quick          a smaller matrix (" CAL_SCENES_QUICK ", no meshes, 32x32, 1 repeat)\n"
            "  --threads N      threads of the matrix (default 1: the costs of one core)\n"
            "  --quiet          do not list the files written (the matrix still shows its progress)\n"
            "  Exit status: 0, 1 when the run or the fit failed, 2 on bad input.\n");
}

/* The instruction set `bvh` picks here (its isa=auto settled). */
static const char *machine_isa(void)
{
    static char isa[32] = "";
    const struct accel_ops *b = accel_find("bvh");
    if (!b) return "";
    accel_params p;
    params_defaults(&p, b->params);
    accel_settle_params(b, &p);
    const char *v = params_get(&p, "isa");
    snprintf(isa, sizeof isa, "%s", v ? v : "");
    return isa;
}

int calibrate_main(int argc, char **argv)
{
    static const struct option opts[] = {{"out", required_argument, NULL, 'o'},
                                         {"from", required_argument, NULL, 'f'},
                                         {"quick", no_argument, NULL, 'k'},
                                         {"threads", required_argument, NULL, 't'},
                                         {"quiet", no_argument, NULL, 'q'},
                                         {"help", no_argument, NULL, 'h'},
                                         {NULL, 0, NULL, 0}};
    const char *out = "calibration", *from = NULL, *threads = "1";
    bool quick = false, quiet = false;
    int c;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "hq", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case 'f': from = optarg; break;
        case 'k': quick = true; break;
        case 't': {
            long n;
            if (options_parse_long("threads", optarg, 1, 1024, &n)) return 2; /* run's range */
            threads = optarg;
            break;
        }
        case 'q': quiet = true; break;
        case 'h': calibrate_usage(stdout); return 0;
        default: return cli_bad_option("calibrate", argv[optind - 1]);
        }
    }
    if (cli_no_operands("calibrate", argc, argv)) return 2;
    char run[PATH_MAX], csv[PATH_MAX], script[PATH_MAX], self[PATH_MAX];
    if ((size_t)snprintf(run, sizeof run, "%s/run", out) >= sizeof run - sizeof "/matrix.csv") {
        fprintf(stderr, "accelbench calibrate: --out %.60s...: a path too long\n", term_text(out));
        return 2;
    }
    if (from && run_folder_csv("calibrate", from, csv, sizeof csv)) return 2;
    if (!path_is_dir(out) && mkdir(out, 0777) != 0) {
        fprintf(stderr, "accelbench calibrate: --out %s: cannot create the folder: %s\n", term_text(out),
                strerror(errno));
        return 2;
    }
    ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
    self[n > 0 ? n : 0] = 0;
    if (!from) {
        char *args[] = {self, "run", "--scenes", quick ? CAL_SCENES_QUICK : CAL_SCENES, "--accels", CAL_ACCELS,
                        "--workloads", CAL_WORKLOADS, "--res", quick ? "32x32" : "64x64", "--repeat",
                        quick ? "1" : "3", "--threads", (char *)threads, "--out", run, "--no-plots", NULL};
        int rc = spawn_wait(args);
        if (rc == 0 && !quick) {
            args[3] = CAL_MESHES;
            args[5] = CAL_MESH_ACCELS;
            rc = spawn_wait(args);
        }
        if (rc != 0) {
            fprintf(stderr, "accelbench calibrate: the calibration matrix failed (exit %d); rerun to resume it\n", rc);
            return rc == 2 ? 2 : 1;
        }
    }
    snprintf(script, sizeof script, "%s/scripts/calibrate.py", ACCELBENCH_SOURCE_DIR);
    char *fit[] = {(char *)python_interpreter(), script, (char *)(from ? from : run), "--out", (char *)out, "--isa",
                   (char *)machine_isa(), "--accelbench", self, quiet ? "--quiet" : NULL, NULL};
    int rc = spawn_wait(fit);
    return rc == 0 ? 0 : rc == 2 ? 2 : 1;
}
