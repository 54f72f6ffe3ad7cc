/* scene_cmd.c: looking at scenes without tracing them.
 *
 *   accelbench scene info SCENE [SCENE ...] [--view SPEC] [--up AXIS] [--light X,Y,Z] [--memcap MIB]
 *                                                                         counts by kind, bounds, lights, view, hash
 *   accelbench scene export SCENE --nff FILE [--view SPEC] [--up AXIS] [--light X,Y,Z] [--memcap MIB]
 *                                                                         the scene as NFF (exact %.9g round trip)
 * A view is given as SCENE@VIEW or --view, --up and --light, as for run (scene_load applies it);
 * --memcap is the memory cap a generated scene's estimate is checked
 * against before it is generated (scenes/memory_cap.h). */
#include "scene_cmd.h"

#include <inttypes.h>
#include <stdio.h>
#include <string.h>
#include "../../scenes/nff.h"
#include "../../scenes/scene.h"
#include "options.h"
#include "../workloads/resources.h"
#include "../workloads/trace.h"

static void usage(FILE *out)
{
    fprintf(out,
            "usage: accelbench scene info SCENE [SCENE ...] [--view SPEC] [--up AXIS] [--light X,Y,Z ...] [--memcap MIB]\n"
            "       accelbench scene export SCENE --nff FILE [--view SPEC] [--up AXIS] [--light X,Y,Z ...] [--memcap MIB]\n"
            "  info    primitive counts by kind, bounds, lights, view and a hash of the primitives\n"
            "          (the same hash for the same geometry, whatever file or generator it came from);\n"
            "          SCENE@VIEW or --view 'eye=X,Y,Z;at=X,Y,Z;up=X,Y,Z;fov=DEG;light=X,Y,Z' moves the camera\n"
            "  export  write the scene as NFF, with its camera and lights (those of the view options too); reading it\n"
            "          back gives the same hash\n"
            "%s"
            "  --memcap MIB  refuse a scene estimated above MIB MiB before making it (default: half the memory\n"
            "                this process may use; docs/limits.md)\n", SCENE_UP_LIGHT_USAGE);
}

static void print_info(const scene_t *s, double load_ms)
{
    const prims_t *p = &s->prims;
    const camera_t *c = &s->camera;
    printf("scene      %s\n", s->name);
    printf("source     %s\n", s->source);
    printf("primitives %u: %u triangles (%u degenerate), %u spheres, %u cones, %u polygons; %u vertices\n", p->count,
           p->ntris, p->ndegenerate, p->nspheres, p->ncones, p->npolygons, p->nverts);
    printf("bounds     (%g %g %g) .. (%g %g %g), diagonal %g\n", s->bounds.lo.x, s->bounds.lo.y, s->bounds.lo.z,
           s->bounds.hi.x, s->bounds.hi.y, s->bounds.hi.z, box_diagonal(s->bounds));
    printf("view       %s: from (%g %g %g) at (%g %g %g) up (%g %g %g) angle %g hither %g resolution %dx%d\n", s->view,
           c->from.x, c->from.y, c->from.z, c->at.x, c->at.y, c->at.z, c->up.x, c->up.y, c->up.z, c->fov_deg, c->hither,
           c->width, c->height);
    printf("lights     %u:", s->nlights);
    for (uint32_t i = 0; i < s->nlights; i++) printf(" (%g %g %g)", s->lights[i].x, s->lights[i].y, s->lights[i].z);
    printf("\nmaterials  %u\n", s->nmaterials);
    printf("memory     %zu bytes in the primitive store\n", prims_memory(p));
    printf("hash       %016" PRIx64 "\n", scene_geometry_hash(s));
    printf("load_ms    %.1f\n", load_ms);
}

/* --memcap MIB at argv[*i] (the value next): sets the cap. 0, or 2 after the error line. */
static int take_memcap(int argc, char **argv, int *i, const char *action, bool *given)
{
    uint64_t mib;
    char why[256];
    if (*i + 1 == argc || *given) {
        fprintf(stderr, "accelbench scene %s: %s\n", action, *given ? "--memcap given twice" : "--memcap needs MIB");
        return 2;
    }
    if (resources_parse_memcap(argv[++*i], &mib, why, sizeof why)) {
        fprintf(stderr, "accelbench scene %s: %s\n", action, why);
        return 2;
    }
    memory_cap_set_mib(mib);
    *given = true;
    return 0;
}

/* --view, --up or --light at argv[*i] (also as --OPTION=VALUE), added to the one view spec they make, as for run
 * (options.c): 1 when argv[*i] is none of them, 0 when taken (the value next too), 2 after the error line. */
static int take_view(int argc, char **argv, int *i, const char *action, char *spec, size_t speclen, bool *view_given)
{
    static const char *const view_opts[] = {"view", "up", "light"};
    const char *opt = NULL, *value = NULL;
    for (int k = 0; k < 3 && !opt; k++) {
        size_t n = strlen(view_opts[k]);
        if (strncmp(argv[*i], "--", 2) || strncmp(argv[*i] + 2, view_opts[k], n)) continue;
        if (argv[*i][2 + n] == '=') opt = view_opts[k], value = argv[*i] + 3 + n;
        else if (!argv[*i][2 + n]) opt = view_opts[k], value = *i + 1 < argc ? argv[++*i] : NULL;
    }
    if (!opt) return 1;
    if (!value || (*view_given && *opt == 'v')) {
        fprintf(stderr, "accelbench scene %s: %s\n", action, !value ? (*opt == 'v' ? "--view needs a SPEC" : *opt == 'u'
                        ? "--up needs X, Y, Z or auto" : "--light needs X,Y,Z") : "--view given twice");
        return 2;
    }
    *view_given |= *opt == 'v';
    char err[1024];
    if (scene_view_option(spec, speclen, opt, value, err, sizeof err) != 0) {
        fprintf(stderr, "accelbench: %s\n", err);
        return 2;
    }
    return 0;
}

/* name with the view spec, if any, as SCENE@SPEC into out; false after the error line when it does not fit. */
static bool with_view(const char *name, const char *spec, char *out, size_t len, const char *action)
{
    if (snprintf(out, len, "%s%s%s", name, *spec ? "@" : "", spec) < (int)len) return true;
    fprintf(stderr, "accelbench scene %s: '%.60s...': the name with its view is too long\n", action, name);
    return false;
}

int scene_cmd_main(int argc, char **argv)
{
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    char err[512];
    if (!strcmp(argv[1], "info")) {
        char spec[1024] = "";
        int nnames = 0;
        bool memcap = false, view_given = false;
        for (int i = 2; i < argc; i++) {
            if (strcmp(argv[i], "--memcap") == 0) {
                if (take_memcap(argc, argv, &i, "info", &memcap)) return 2;
                continue;
            }
            int taken = take_view(argc, argv, &i, "info", spec, sizeof spec, &view_given);
            if (taken == 2) return 2;
            if (taken == 1) argv[2 + nnames++] = argv[i];
        }
        if (nnames == 0) {
            fprintf(stderr, "accelbench scene info: name a scene (see accelbench list scenes)\n");
            return 2;
        }
        for (int i = 2; i < 2 + nnames; i++) {
            double t0 = clock_ms();
            char name[4096];
            if (!with_view(argv[i], spec, name, sizeof name, "info")) return 2;
            scene_t *s = scene_load(name, err, sizeof err);
            if (!s) {
                fprintf(stderr, "accelbench: %s\n", err);
                return 2;
            }
            if (i > 2) printf("\n");
            print_info(s, clock_ms() - t0);
            scene_free(s);
        }
        return 0;
    }
    if (!strcmp(argv[1], "export")) {
        const char *nff = NULL;
        char spec[1024] = "", name[4096];
        bool memcap = false, view_given = false;
        for (int i = 3; i < argc; i++) {
            int taken = !strcmp(argv[i], "--memcap") ? 1 : take_view(argc, argv, &i, "export", spec, sizeof spec, &view_given);
            if (taken == 2) return 2;
            if (taken == 0) continue;
            if (!strcmp(argv[i], "--memcap")) {
                if (take_memcap(argc, argv, &i, "export", &memcap)) return 2;
            } else if (!strcmp(argv[i], "--nff") && i + 1 < argc && !nff) {
                nff = argv[++i];
            } else {
                nff = NULL;
                break;
            }
        }
        if (argc < 3 || !nff) {
            fprintf(stderr, "accelbench scene export: usage: accelbench scene export SCENE --nff FILE [--view SPEC] [--up AXIS] "
                            "[--light X,Y,Z ...] [--memcap MIB]\n");
            return 2;
        }
        if (!with_view(argv[2], spec, name, sizeof name, "export")) return 2;
        scene_t *s = scene_load(name, err, sizeof err);
        if (!s) {
            fprintf(stderr, "accelbench: %s\n", err);
            return 2;
        }
        int rc = scene_write_nff(s, nff, err, sizeof err);
        if (rc) fprintf(stderr, "accelbench: %s\n", err);
        else printf("wrote %s: %u primitives, hash %016" PRIx64 "\n", nff, s->prims.count, scene_geometry_hash(s));
        scene_free(s);
        return rc ? 2 : 0;
    }
    fprintf(stderr, "accelbench scene: unknown action '%s' (info or export)\n", argv[1]);
    return 2;
}
