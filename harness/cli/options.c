/* options.c: parsing the selectors and knobs shared by run, verify and
 * render (getopt_long). Every error is one line naming the option and the
 * value, and returns 2. */
#include "options.h"
#include "../measure/accel_choice.h"
#include "../run/output.h"
#include "../workloads/resources.h"
#include "../run/shard.h"
#include "../measure/verify.h"
#include "../../prims/checked_alloc.h"

#include <errno.h>
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { OPT_SAVE_RAYS = 256, OPT_RAYS, OPT_RAY, OPT_NO_PLOTS, OPT_CORNERS, OPT_SPP, OPT_DEPTH, OPT_HEATMAP, OPT_JUDGE_SECONDS,
       OPT_VIEW, OPT_REDO, OPT_KEEP_GOING, OPT_WARM_PASSES, OPT_MEMCAP, OPT_SHADOW_ACCEL, OPT_SHARD, OPT_REPORT, OPT_HEATMAP_MAX,
       OPT_UP, OPT_LIGHT };

static const struct option long_opts[] = {
    {"scenes", required_argument, NULL, 's'},  {"scene", required_argument, NULL, 's'},
    {"accels", required_argument, NULL, 'a'},  {"accel", required_argument, NULL, 'a'},
    {"workloads", required_argument, NULL, 'w'}, {"workload", required_argument, NULL, 'w'},
    {"threads", required_argument, NULL, 't'}, {"repeat", required_argument, NULL, 'n'},
    {"param", required_argument, NULL, 'p'},   {"res", required_argument, NULL, 'r'},
    {"seed", required_argument, NULL, 'S'},    {"out", required_argument, NULL, 'o'},
    {"spp", required_argument, NULL, OPT_SPP}, {"corners", no_argument, NULL, OPT_CORNERS},
    {"depth", required_argument, NULL, OPT_DEPTH},
    {"save-rays", required_argument, NULL, OPT_SAVE_RAYS}, {"rays", required_argument, NULL, OPT_RAYS},
    {"ray", required_argument, NULL, OPT_RAY}, {"no-plots", no_argument, NULL, OPT_NO_PLOTS},
    {"heatmap", required_argument, NULL, OPT_HEATMAP}, {"quiet", no_argument, NULL, 'q'},
    {"judge-seconds", required_argument, NULL, OPT_JUDGE_SECONDS},
    {"view", required_argument, NULL, OPT_VIEW},
    {"up", required_argument, NULL, OPT_UP}, {"light", required_argument, NULL, OPT_LIGHT},
    {"memcap", required_argument, NULL, OPT_MEMCAP},
    {"redo", no_argument, NULL, OPT_REDO},
    {"warm-passes", no_argument, NULL, OPT_WARM_PASSES},
    {"keep-going", no_argument, NULL, OPT_KEEP_GOING},
    {"shard", required_argument, NULL, OPT_SHARD},
    {"shadow-accel", required_argument, NULL, OPT_SHADOW_ACCEL},
    {"report", no_argument, NULL, OPT_REPORT}, {"heatmap-max", required_argument, NULL, OPT_HEATMAP_MAX},
    {"help", no_argument, NULL, 'h'},          {NULL, 0, NULL, 0},
};

#define VIEW_USAGE \
    "  --view 'SPEC'           look from elsewhere: any of eye=X,Y,Z;at=X,Y,Z;up=X,Y,Z;fov=DEG;light=X,Y,Z, applied to\n" \
    "                          every scene after loading (as SCENE@SPEC; catalogue views: SCENE@NAME, accelbench list scenes)\n" \
    SCENE_UP_LIGHT_USAGE

#define MEMCAP_USAGE \
    "  --memcap MIB            refuse work estimated above MIB MiB before allocating it (default: half the memory\n" \
    "                          this process may use; also bounds every accelerator's build; docs/limits.md)\n"

void options_usage(FILE *out, const char *cmd)
{
    if (strcmp(cmd, "render") == 0) {
        fprintf(out,
                "usage: accelbench render --scene S --accel A --out FILE.png [options]\n"
                "  Whitted ray tracing (point-light shadows, mirror reflection and refraction to depth 3,\n"
                "  smooth `pp` normals) through any accelerator that answers closest-hit queries.\n"
                "  --shadow-accel A        answer the shadow rays through accelerator A (e.g. lightbuf, which answers\n"
                "                          only those), every other ray through --accel (not with --heatmap)\n"
                "  --heatmap tests|steps   write a per-pixel cost image of the primary rays instead\n"
                "  --heatmap-max N         the heat map's colour scale runs 0..N (default: 0..the image's maximum;\n"
                "                          one N for several accelerators puts them on the same scale)\n"
                "  --res WxH               image size (default: the scene's view, e.g. 512x512)\n"
                "  --spp N                 samples per pixel (default 1)\n"
                "  --param ACCEL.KEY=VALUE accelerator parameter (see accelbench list accels)\n"
                "  --threads N             threads for the heat map's tracing (default: all cores)\n"
                "%s%s", VIEW_USAGE, MEMCAP_USAGE);
        return;
    }
    fprintf(out,
            "usage: accelbench %s --scenes LIST --accels LIST --workloads LIST [options]\n"
            "  LIST is comma-separated; see `accelbench list` for the names.\n"
            "  --scenes LIST           scene names: spd:balls:3, spd:gears:2:t, bunny, set:medium, a file ...\n"
            "  --accels LIST           accelerators (default: all; verify: all but embree), or instances with\n"
            "                          parameters and sweeps: 'grid,grid[res=40x40x40],bsp[split=sah|midpoint]'\n"
            "                          (a | list: one instance per value; several: their product)\n"
            "  --workloads LIST        primary,shadow,reflection,diffuse,random, and whitted: the SPD protocol's ray\n"
            "                          tree as whitted:eye,whitted:reflected,whitted:refracted,whitted:shadow\n"
            "                          (default: the five before whitted)\n"
            "  --param ACCEL.KEY=VALUE set an accelerator parameter (repeatable)\n"
            "  --res WxH               primary image size (default 128x128)\n"
            "  --spp N                 samples per pixel (default 1)\n"
            "  --corners               rays through pixel corners, (W+1)x(H+1) (SPD's rule)\n"
            "  --depth N               reflection generations (default 3); whitted's tree depth, the eye ray 1 (default 5)\n"
            "  --seed S                random seed of the ray sets and of seeded builds (bvh-gs's shuffles) (default 1)\n"
            "  --threads N             tracing threads (default: all cores)\n"
            "  --rays FILE             replay a saved ray set instead of making workloads\n"
            "  --save-rays PATH        save the ray sets (a file for one set, else a folder)\n"
            "  --judge-seconds S       time the exact judge may spend on one cell's disputed rays; rays past it\n"
            "                          are counted as unjudged (default %g; 0 = no limit)\n"
            "  A shadow-only accelerator (lightbuf) makes no cell of a closest-hit workload: each such pair is said\n"
            "  on stderr; when no cell at all is left, the command exits 2 with one line saying why.\n"
            "%s%s",
            cmd, VERIFY_JUDGE_SECONDS, VIEW_USAGE, MEMCAP_USAGE);
    if (strcmp(cmd, "run") == 0)
        fprintf(out,
                "  --repeat N              timed repeats after one warm-up; the median is reported (default 5)\n"
                "  --out DIR               output folder (default results/<date-time>); matrix.csv is appended,\n"
                "                          and cells it already has with the same options are skipped (resumes a run)\n"
                "  --redo                  measure those cells again, replacing their rows\n"
                "  --keep-going            a cell whose build fails (over a memory cap, say) is reported and skipped,\n"
                "                          the others measured; exit 2 at the end when any was (default: stop there)\n"
                "  --warm-passes           an accelerator built while tracing (raycls) is not reset before its\n"
                "                          timed passes: they measure the structure the first pass grew, not its\n"
                "                          growth (CSV timed_from=warm; default: every pass from the post-build state)\n"
                "  --no-plots              do not call scripts/plot.py at the end\n"
                "  --shard K/N             run only shard K of N (1 <= K <= N <= 4096): the matrix's cells, balanced by\n"
                "                          estimated cost, in N disjoint shards; writes DIR/shard.txt for accelbench merge\n"
                "  --report                also write DIR/report.html at the end (accelbench report --help)\n"
                "  Every cell is verified against Embree as it runs; mismatch counts go in the CSV.\n"
                "  SIGINT/SIGTERM abandon the cell in progress and print the command that resumes.\n"
                "  Exit status: 0, 1 when a write failed (disk full ...), 2 on bad input, 128+N on signal N.\n");
    else
        fprintf(out,
                "  --ray I                 replay ray I: print every answer and the exact judge's t for each\n"
                "  The table ends in one line: total: cells, rays, real mismatches, the counts of the classes that do\n"
                "  not fail verify (edge, origin, tol, refwrong, unjudged) and what the exit status is.\n"
                "  Exit status: 0 when no real mismatch, 1 on any real mismatch, 2 on bad input.\n");
}

/* A copy of s that options_free releases: the lists point into it. */
static char *owned_copy(options *o, const char *s)
{
    char **grown = realloc(o->owned, (size_t)(o->nowned + 1) * sizeof *grown);
    char *dup = strdup(s);
    if (!grown || !dup) {
        fprintf(stderr, "accelbench: out of memory copying the options\n");
        exit(2);
    }
    o->owned = grown;
    return o->owned[o->nowned++] = dup;
}

/* Split a comma list in place into parts. */
static int split(char *s, const char **parts, int max, const char *what)
{
    int n = 0;
    for (char *tok = strtok(s, ","); tok; tok = strtok(NULL, ",")) {
        if (n == max) {
            fprintf(stderr, "accelbench: too many %s (at most %d)\n", what, max);
            return -1;
        }
        parts[n++] = tok;
    }
    if (n == 0) {
        fprintf(stderr, "accelbench: empty list of %s\n", what);
        return -1;
    }
    return n;
}

/* An option only one subcommand takes: true when cmd is it, else false after the one-line error. */
static bool option_of(const char *cmd, const char *owner, const char *option)
{
    if (strcmp(cmd, owner) == 0) return true;
    fprintf(stderr, "accelbench %s: %s is an option of %s (see accelbench %s --help)\n", cmd, option, owner, owner);
    return false;
}

int options_parse_long(const char *opt, const char *s, long lo, long hi, long *out)
{
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (errno || end == s || *end || v < lo || v > hi) {
        fprintf(stderr, "accelbench: --%s %s: expected an integer in %ld..%ld\n", opt, s, lo, hi);
        return -1;
    }
    *out = v;
    return 0;
}

/* One side of --res: digits only, read without wrapping (sscanf's %d wraps 4294967360 to 64). */
static bool parse_side(const char *s, const char *end, long *out)
{
    if (s == end || end - s > 9) return false;
    long v = 0;
    for (const char *c = s; c < end; c++) {
        if (*c < '0' || *c > '9') return false;
        v = v * 10 + (*c - '0');
    }
    *out = v;
    return true;
}

int options_parse_seed(const char *s, uint64_t *out)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    /* strtoull takes "-1" as 2^64 - 1: a sign is refused, not wrapped */
    if (errno || end == s || *end || strchr(s, '-') || strchr(s, '+')) {
        fprintf(stderr, "accelbench: --seed %s: expected an unsigned integer\n", s);
        return -1;
    }
    *out = v;
    return 0;
}

int options_parse_res(const char *s, int *width, int *height)
{
    const char *x = strchr(s, 'x');
    long wd, ht;
    if (!x || !parse_side(s, x, &wd) || !parse_side(x + 1, x + 1 + strlen(x + 1), &ht) || wd < 1 || ht < 1 ||
        wd > IMAGE_SIDE_MAX || ht > IMAGE_SIDE_MAX) {
        fprintf(stderr, "accelbench: --res %s: expected WxH with 1 <= W, H <= %d\n", s, IMAGE_SIDE_MAX);
        return -1;
    }
    *width = (int)wd;
    *height = (int)ht;
    return 0;
}

/* A path option's value: refused over OPT_PATH_MAX bytes, since the names made from it (DIR/matrix.csv, the ray
 * files of --save-rays, temporary files beside them) must fit the harness's path buffers uncut. */
static int check_path(const char *opt, const char *path)
{
    size_t n = strlen(path);
    if (n == 0) {
        fprintf(stderr, "accelbench: --%s: an empty path\n", opt);
        return -1;
    }
    if (n > OPT_PATH_MAX) {
        fprintf(stderr, "accelbench: --%s '%.60s...': a path of %zu bytes, more than %d (use a shorter path, or a "
                        "symbolic link to the folder)\n", opt, path, n, OPT_PATH_MAX);
        return -1;
    }
    return 0;
}

static char *join_args(int argc, char **argv)
{
    size_t len = 1;
    for (int i = 0; i < argc; i++) len += strlen(argv[i]) + 3;
    char *s = checked_calloc(len, 1, "the command line's copy");
    for (int i = 0; i < argc; i++) {
        if (i) strcat(s, " ");
        bool q = strpbrk(argv[i], " \t'\"") != NULL;
        if (q) strcat(s, "'");
        strcat(s, argv[i]);
        if (q) strcat(s, "'");
    }
    return s;
}

/* --view reaches every command through the scene names: SCENE@SPEC is
 * what scene_load applies after loading, so run, verify and render need no
 * code of their own for it, and the CSV's scene column says which view. */
static void add_view(options *o)
{
    size_t total = 0, vlen = strlen(o->view);
    for (int i = 0; i < o->nscenes; i++) total += strlen(o->scenes[i]) + vlen + 2;
    o->view_names = checked_malloc(total, "the scene names with their --view");
    char *p = o->view_names;
    for (int i = 0; i < o->nscenes; i++) {
        int n = sprintf(p, "%s@%s", o->scenes[i], o->view);
        o->scenes[i] = p;
        p += n + 1;
    }
}

/* The values of the options that are checked together once all are read. */
typedef struct {
    const char *accels, *workloads, *shadow; /* --accels (default: all), --workloads, --shadow-accel */
    const char *params[OPT_LIST_MAX];        /* every --param, in order */
    int nparams;
    bool res_given, view_given;
} option_values;

/* The defaults of every option, the command as typed, and the default accelerators. */
static void options_defaults(options *o, const char *cmd, int argc, char **argv, option_values *a)
{
    memset(o, 0, sizeof *o);
    long nproc = sysconf(_SC_NPROCESSORS_ONLN);
    o->threads = nproc > 0 ? (int)nproc : 1;
    o->repeat = 5;
    o->ray_index = -1;
    o->plots = true;
    o->judge_seconds = VERIFY_JUDGE_SECONDS;
    o->wl = (workload_opts){.width = 128, .height = 128, .spp = 1, .depth = 0 /* each workload's own */, .seed = 1};
    o->argv_line = join_args(argc, argv);
    /* Default accelerators: all of them; verify leaves out the reference itself. */
    static char all_accels[1024];
    all_accels[0] = 0;
    for (int i = 0; accel_registry[i]; i++) {
        if (!strcmp(cmd, "verify") && !strcmp(accel_registry[i]->name, ACCEL_REFERENCE)) continue;
        if (all_accels[0]) strcat(all_accels, ",");
        strcat(all_accels, accel_registry[i]->name);
    }
    *a = (option_values){.accels = all_accels};
}

int options_add_scenes(options *o, const char *arg)
{
    char *dup = owned_copy(o, arg);
    const char *items[OPT_LIST_MAX];
    int n = split(dup, items, OPT_LIST_MAX, "scenes");
    if (n < 0) return 2;
    for (int i = 0; i < n; i++) {
        /* A set name (set:medium, set:scaling:balls ...) stands for its scenes. */
        char expanded[4096];
        int set = scene_set_expand(items[i], expanded, sizeof expanded);
        if (set < 0) {
            fprintf(stderr, "accelbench: --scenes: set '%s' is too long to expand\n", items[i]);
            return 2;
        }
        const char *one[1] = {items[i]};
        const char **list = one;
        const char *parts[OPT_LIST_MAX];
        int m = 1;
        if (set == 1) {
            m = split(owned_copy(o, expanded), parts, OPT_LIST_MAX, "scenes");
            if (m < 0) return 2;
            list = parts;
        }
        for (int k = 0; k < m; k++) {
            /* A scene named twice (itself, or within a set) is one set of cells, measured once. */
            bool listed = false;
            for (int j = 0; j < o->nscenes && !listed; j++) listed = !strcmp(o->scenes[j], list[k]);
            if (listed) continue;
            if (o->nscenes == OPT_LIST_MAX) {
                fprintf(stderr, "accelbench: too many scenes (at most %d)\n", OPT_LIST_MAX);
                return 2;
            }
            o->scenes[o->nscenes++] = list[k];
        }
    }
    return 0;
}

/* The options only run or render take. 0, or 2 after printing why. */
static int read_command_option(options *o, const char *cmd, int c, option_values *a)
{
    switch (c) {
    case OPT_REPORT:
        if (!option_of(cmd, "run", "--report")) return 2;
        o->report = true;
        break;
    case OPT_HEATMAP_MAX: {
        char *end;
        errno = 0;
        double m = strtod(optarg, &end);
        if (!option_of(cmd, "render", "--heatmap-max")) return 2;
        if (errno || end == optarg || *end || !(m > 0.0 && m <= 1e15)) {
            fprintf(stderr, "accelbench: --heatmap-max %s: expected a number above 0\n", optarg);
            return 2;
        }
        o->heatmap_max = m;
        break;
    }
    case OPT_REDO:
        if (!option_of(cmd, "run", "--redo")) return 2;
        o->redo = true;
        break;
    case OPT_KEEP_GOING:
        if (!option_of(cmd, "run", "--keep-going")) return 2;
        o->keep_going = true;
        break;
    case OPT_WARM_PASSES:
        if (strcmp(cmd, "run") != 0) {
            fprintf(stderr, "accelbench %s: --warm-passes is an option of run (see accelbench run --help)\n", cmd);
            return 2;
        }
        o->warm_passes = true;
        break;
    case OPT_SHARD: {
        char why[256];
        if (strcmp(cmd, "run") != 0) {
            fprintf(stderr, "accelbench %s: --shard is an option of run (see accelbench run --help)\n", cmd);
            return 2;
        }
        if (shard_parse(optarg, &o->shard_k, &o->shard_n, why, sizeof why)) {
            fprintf(stderr, "accelbench: %s\n", why);
            return 2;
        }
        break;
    }
    case OPT_SHADOW_ACCEL:
        if (!option_of(cmd, "render", "--shadow-accel")) return 2;
        a->shadow = optarg;
        break;
    case OPT_HEATMAP:
        if (strcmp(optarg, "tests") && strcmp(optarg, "steps")) {
            fprintf(stderr, "accelbench: --heatmap %s: expected tests or steps\n", optarg);
            return 2;
        }
        o->heatmap = optarg;
        break;
    }
    return 0;
}

/* One option c (getopt_long's value) into o and a. 0; 1 after printing the
 * help; 2 after printing why it is refused. */
static int read_option(options *o, const char *cmd, int c, char **argv, option_values *a)
{
    long v;
    switch (c) {
    case 's': return options_add_scenes(o, optarg);
    case 'a': a->accels = optarg; break;
    case 'w': a->workloads = optarg; break;
    case 't': if (options_parse_long("threads", optarg, 1, 1024, &v)) return 2; o->threads = (int)v; break;
    case 'n': if (options_parse_long("repeat", optarg, 1, 1000, &v)) return 2; o->repeat = (int)v; break;
    case 'p':
        if (a->nparams == OPT_LIST_MAX) { fprintf(stderr, "accelbench: too many --param\n"); return 2; }
        a->params[a->nparams++] = optarg;
        break;
    case 'r': if (options_parse_res(optarg, &o->wl.width, &o->wl.height)) return 2; a->res_given = true; break;
    case 'S': if (options_parse_seed(optarg, &o->wl.seed)) return 2; break;
    case 'o': if (check_path("out", optarg)) return 2; o->out = optarg; break;
    case OPT_SPP: if (options_parse_long("spp", optarg, 1, 4096, &v)) return 2; o->wl.spp = (int)v; break;
    case OPT_DEPTH: if (options_parse_long("depth", optarg, 1, 64, &v)) return 2; o->wl.depth = (int)v; break;
    case OPT_CORNERS: o->wl.corners = true; break;
    case OPT_SAVE_RAYS: if (check_path("save-rays", optarg)) return 2; o->save_rays = optarg; break;
    case OPT_RAYS: if (check_path("rays", optarg)) return 2; o->rays_file = optarg; break;
    case OPT_RAY: if (options_parse_long("ray", optarg, 0, 4294967295L, &v)) return 2; o->ray_index = v; break;
    case OPT_NO_PLOTS: o->plots = false; break;
    case OPT_REPORT:
    case OPT_HEATMAP_MAX:
    case OPT_REDO:
    case OPT_KEEP_GOING:
    case OPT_WARM_PASSES:
    case OPT_SHARD:
    case OPT_SHADOW_ACCEL:
    case OPT_HEATMAP: return read_command_option(o, cmd, c, a);
    case OPT_JUDGE_SECONDS: {
        char *end;
        errno = 0;
        double j = strtod(optarg, &end);
        if (errno || end == optarg || *end || !(j >= 0.0 && j <= 86400.0)) {
            fprintf(stderr, "accelbench: --judge-seconds %s: expected seconds in 0..86400\n", optarg);
            return 2;
        }
        o->judge_seconds = j;
        break;
    }
    case OPT_MEMCAP: {
        char why[256];
        if (resources_parse_memcap(optarg, &o->memcap_mib, why, sizeof why)) {
            fprintf(stderr, "accelbench: %s\n", why);
            return 2;
        }
        break;
    }
    case OPT_VIEW:
    case OPT_UP:
    case OPT_LIGHT: {
        /* --view, --up and --light make one view spec, parsed whole as each is added. */
        char why[1024];
        const char *opt = c == OPT_VIEW ? "view" : c == OPT_UP ? "up" : "light";
        if (c == OPT_VIEW && a->view_given) {
            fprintf(stderr, "accelbench: --view given twice (then '%s')\n", optarg);
            return 2;
        }
        a->view_given |= c == OPT_VIEW;
        if (scene_view_option(o->view_spec, sizeof o->view_spec, opt, optarg, why, sizeof why) != 0) {
            fprintf(stderr, "accelbench: %s\n", why);
            return 2;
        }
        o->view = o->view_spec;
        break;
    }
    case 'q': o->quiet = true; break;
    case 'h': options_usage(stdout, cmd); return 1;
    default:
        fprintf(stderr, "accelbench %s: unknown or incomplete option '%s' (see accelbench %s --help)\n", cmd,
                argv[optind - 1], cmd);
        return 2;
    }
    return 0;
}

/* The scenes given: at least one, every name within a scene's, each one
 * found and its view valid. 0, or 2 after printing why. */
static int check_scenes(options *o, const char *cmd, const option_values *a)
{
    if (o->nscenes == 0) {
        fprintf(stderr, "accelbench %s: no scene given (--scenes LIST; see accelbench list scenes)\n", cmd);
        return 2;
    }
    if (o->heatmap_max > 0 && !o->heatmap) {
        fprintf(stderr, "accelbench render: --heatmap-max sets a heat map's scale: give --heatmap tests|steps too\n");
        return 2;
    }
    o->res_given = a->res_given;
    if (o->view) add_view(o);
    for (int i = 0; i < o->nscenes; i++) { /* the name goes uncut into the scene, its ray sets and the CSV */
        size_t n = strlen(o->scenes[i]), most = sizeof ((scene_t *)0)->name - 1;
        if (n > most) {
            fprintf(stderr, "accelbench: scene '%.60s...': a name of %zu bytes%s, more than %zu (use a shorter path, "
                            "or a symbolic link to the file)\n", term_text(o->scenes[i]), n, o->view ? " with its --view" : "", most);
            return 2;
        }
    }
    /* An absent repository mesh or a bad view fails now, not after the
     * scenes before it have run. */
    for (int i = 0; i < o->nscenes; i++) {
        char why[1024];
        if (scene_check(o->scenes[i], why, sizeof why) != 0) {
            fprintf(stderr, "accelbench: %s\n", term_text(why));
            return 2;
        }
    }
    return 0;
}

/* Every --param ACCEL.KEY=VALUE set on the instances of ACCEL. 0, or 2 after printing why. */
static int apply_params(options *o, const option_values *a)
{
    for (int k = 0; k < a->nparams; k++) {
        char buf[256];
        if (strlen(a->params[k]) >= sizeof buf) {
            fprintf(stderr, "accelbench: --param '%.60s...': longer than %zu bytes\n", a->params[k], sizeof buf - 1);
            return 2;
        }
        snprintf(buf, sizeof buf, "%s", a->params[k]);
        char *dot = strchr(buf, '.'), *eq = strchr(buf, '=');
        if (!dot || !eq || eq < dot) {
            fprintf(stderr, "accelbench: --param %s: expected ACCEL.KEY=VALUE\n", a->params[k]);
            return 2;
        }
        *dot = 0;
        *eq = 0;
        bool used = false;
        for (int i = 0; i < o->naccels; i++) {
            if (strcmp(o->accels[i].ops->name, buf) != 0) continue;
            char err[256];
            if (accel_config_set(&o->accels[i], dot + 1, eq + 1, err, sizeof err)) {
                fprintf(stderr, "accelbench: --param %s: %s: %s\n", a->params[k], buf, err);
                return 2;
            }
            used = true;
        }
        if (!used) {
            fprintf(stderr, "accelbench: --param %s: accelerator '%s' is not in --accels\n", a->params[k], buf);
            return 2;
        }
    }
    return 0;
}

/* The accelerator instances: --accels expanded, render's shadow
 * accelerator, --param, their labels, the memory cap and a check build of
 * each. 0, or 2 after printing why. */
static int read_accels(options *o, const option_values *a)
{
    /* Accelerators, then their parameters: instances of NAME[k=v|w,...] expanded (accel_choice.h). */
    char aerr[1024];
    int na = accel_spec_expand(a->accels, o->accels, OPT_LIST_MAX - 1, aerr, sizeof aerr);
    if (na < 0) {
        fprintf(stderr, "accelbench: %s\n", aerr);
        return 2;
    }
    for (int i = 0; i < na; i++) {
        o->accels[i].params.threads = o->threads;
        o->accels[i].params.seed = o->wl.seed; /* seeded builders (bvh-gs's shuffles) follow the ray sets' seed */
    }
    o->naccels = na;
    /* render's shadow accelerator goes after the one --accel names, so that
     * --param and the memory cap reach it like any other. */
    if (a->shadow) {
        const struct accel_ops *ops = accel_find(a->shadow);
        if (!ops) {
            fprintf(stderr, "accelbench: --shadow-accel: unknown accelerator '%s' (see: accelbench list accels)\n", a->shadow);
            return 2;
        }
        if (o->heatmap) {
            fprintf(stderr, "accelbench render: --shadow-accel and --heatmap: a heat map traces primary rays only\n");
            return 2;
        }
        if (na != 1) {
            fprintf(stderr, "accelbench render: --shadow-accel needs exactly one --accel for the other rays\n");
            return 2;
        }
        o->accels[na].ops = ops;
        params_defaults(&o->accels[na].params, ops->params);
        o->accels[na].params.threads = o->threads;
        o->accels[na].params.seed = o->wl.seed;
        o->naccels = na + 1;
        o->shadow_accel = true;
    }
    if (apply_params(o, a)) return 2;
    /* The parameters are written down (params_str, the label: the cell key's words) without the memory cap: a
     * limit that only bounds memory does not change what a cell measures, so the same command under another
     * ulimit -v or Slurm --mem finds its cells done. */
    for (int i = 0; i < o->naccels; i++) {
        accel_config *ac = &o->accels[i];
        accel_settle_params(ac->ops, &ac->params); /* machine-dependent values (bvh's isa=auto) as they will run */
        params_format(&ac->params, ac->params_str, sizeof ac->params_str);
        /* Short label for tables: the name, plus [k=v,...] for the parameters that differ from the defaults. */
        accel_config_label(ac, ac->label, sizeof ac->label);
        for (int j = 0; j < i; j++)
            if (o->accels[j].ops == ac->ops && !strcmp(o->accels[j].params_str, ac->params_str)) {
                fprintf(stderr, "accelbench: --accels: %s is given twice (same parameters)\n", ac->label);
                return 2;
            }
    }
    /* The memory cap, given to every accelerator's parameters, for the builds. */
    if (resources_apply_memcap(o)) return 2;
    /* Rules between an instance's parameters are refused now, not at the first cell; nothing is built. */
    for (int i = 0; i < o->naccels; i++) {
        char why[600];
        if (accel_config_check(&o->accels[i], why, sizeof why)) {
            fprintf(stderr, "accelbench: --accels %s: %s\n", o->accels[i].label, why);
            return 2;
        }
    }
    return 0;
}

/* The workloads: --workloads (whitted naming its four parts, each once)
 * or the five classic ones, and --rays' rules. 0, or 2 after printing why. */
static int read_workloads(options *o, const option_values *a)
{
    if (!a->workloads) {
        /* The five classic workloads; whitted is asked for by name (its SPD corner grid and ray tree are a
         * protocol of their own, and its parts are empty on scenes without glass or mirrors). */
        for (int i = 0; workload_table[i].name; i++)
            if (strncmp(workload_table[i].name, "whitted:", 8)) o->workloads[o->nworkloads++] = &workload_table[i];
    } else {
        const char *wn[OPT_LIST_MAX];
        char *wdup = owned_copy(o, a->workloads);
        int nw = split(wdup, wn, OPT_LIST_MAX, "workloads");
        if (nw < 0) return 2;
        for (int i = 0; i < nw; i++) {
            /* "whitted" names its four parts, one ray set per ray type. */
            const workload_def *parts[WHITTED_PARTS];
            int np = 0;
            if (!strcmp(wn[i], "whitted"))
                for (int k = 0; k < WHITTED_PARTS; k++) parts[np++] = workload_find(whitted_part_name[k]);
            else if ((parts[0] = workload_find(wn[i]))) np = 1;
            if (!np) {
                fprintf(stderr, "accelbench: unknown workload '%s' (see: accelbench list workloads)\n", wn[i]);
                return 2;
            }
            for (int k = 0; k < np; k++) { /* a workload named twice is one set of cells */
                bool listed = false;
                for (int j = 0; j < o->nworkloads; j++) listed |= o->workloads[j] == parts[k];
                if (!listed) o->workloads[o->nworkloads++] = parts[k];
            }
        }
    }
    if (o->rays_file && a->workloads) {
        fprintf(stderr, "accelbench: --rays replays the ray set of its file and --workloads makes new ones: give one "
                        "of them\n");
        return 2;
    }
    if (o->rays_file && o->nscenes != 1) {
        fprintf(stderr, "accelbench: --rays replays one ray set: give exactly one scene\n");
        return 2;
    }
    return 0;
}

int options_parse(options *o, const char *cmd, int argc, char **argv)
{
    option_values a;
    options_defaults(o, cmd, argc, argv, &a);
    int c, rc;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "hq", long_opts, NULL)) != -1)
        if ((rc = read_option(o, cmd, c, argv, &a))) return rc;
    if (optind < argc) {
        fprintf(stderr, "accelbench %s: unexpected argument '%s' (see accelbench %s --help)\n", cmd, argv[optind], cmd);
        return 2;
    }
    if (check_scenes(o, cmd, &a) || read_accels(o, &a) || read_workloads(o, &a)) return 2;
    o->wl.threads = o->threads;
    /* What the options size (threads, ray sets, generated scenes), refused before the first scene loads. */
    if (resources_check_options(o, cmd)) return 2;
    return 0;
}

void options_free(options *o)
{
    free(o->argv_line);
    free(o->view_names);
    for (int i = 0; i < o->nowned; i++) free(o->owned[i]);
    free(o->owned);
}

/* Append one shell word, quoted when it holds anything the shell would split or expand. */
static void append_word(char *buf, size_t len, const char *word)
{
    size_t used = strlen(buf);
    bool plain = *word != 0;
    for (const char *c = word; *c; c++)
        if (!strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789:,._/=+-@%#", *c)) plain = false;
    snprintf(buf + used, len - used, plain ? " %s" : " '%s'", word);
}

void options_replay_command(const options *o, const char *scene, const char *workload, const accel_config *ac,
                            uint32_t ray, char *buf, size_t len)
{
    char word[1200];
    snprintf(buf, len, "accelbench verify");
    append_word(buf, len, "--scenes");
    /* A --view comes back as --view: its commas cannot go inside --scenes. */
    size_t sl = strlen(scene), vl = o->view ? strlen(o->view) : 0;
    if (o->view && sl > vl && scene[sl - vl - 1] == '@' && !strcmp(scene + sl - vl, o->view)) {
        snprintf(word, sizeof word, "%.*s", (int)(sl - vl - 1), scene);
        append_word(buf, len, word);
        append_word(buf, len, "--view");
        append_word(buf, len, o->view);
    } else {
        append_word(buf, len, scene);
    }
    if (o->rays_file) {
        append_word(buf, len, "--rays");
        append_word(buf, len, o->rays_file);
    } else {
        char depth[32] = ""; /* 0: each workload's default, which --depth cannot say */
        if (o->wl.depth > 0) snprintf(depth, sizeof depth, " --depth %d", o->wl.depth);
        snprintf(word, sizeof word, "--workloads %s --res %dx%d --spp %d --seed %llu%s%s", workload, o->wl.width,
                 o->wl.height, o->wl.spp, (unsigned long long)o->wl.seed, depth, o->wl.corners ? " --corners" : "");
        size_t used = strlen(buf);
        snprintf(buf + used, len - used, " %s", word);
    }
    append_word(buf, len, "--accels");
    append_word(buf, len, ac->ops->name);
    /* Every parameter that differs from its default, so the replay builds the same structure. */
    for (int k = 0; k < ac->params.count; k++) {
        const accel_param *p = &ac->params.table[k];
        if (strcmp(ac->params.values[k], p->default_value) == 0) continue;
        append_word(buf, len, "--param");
        snprintf(word, sizeof word, "%s.%s=%s", ac->ops->name, p->name, ac->params.values[k]);
        append_word(buf, len, word);
    }
    size_t used = strlen(buf);
    snprintf(buf + used, len - used, " --ray %u", ray);
}
