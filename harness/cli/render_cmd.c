/* render_cmd.c: `accelbench render` (see render_cmd.h). */
#include "render_cmd.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../../prims/checked_alloc.h"
#include "../measure/measure.h"
#include "../render/image.h"
#include "../render/render.h"
#include "../workloads/resources.h"
#include "../workloads/trace.h"

static int render_image(const options *o, const scene_t *s, accel *a, accel *shadow, const rayset_t *prim)
{
    counters_t work;
    image_t *im = render_whitted_shadows(s, a, shadow, prim, &work);
    char err[512];
    int rc = image_write_png(im, o->out, err, sizeof err);
    if (rc) fprintf(stderr, "accelbench: %s\n", err);
    else if (!o->quiet) {
        printf("wrote %s: %ux%u, %u spp, %s through %s", o->out, prim->width, prim->height, prim->spp, s->name, a->ops->name);
        if (shadow != a) printf(" (shadow rays through %s)", shadow->ops->name);
        if (!(a->ops->flags & ACCEL_NO_COUNTERS) && !(shadow->ops->flags & ACCEL_NO_COUNTERS))
            printf(", %.1f ray/primitive tests per pixel", (double)work.prim_tests / ((double)prim->width * prim->height));
        printf("\n");
    }
    image_free(im);
    return rc ? 2 : 0;
}

static int render_heatmap(const options *o, const scene_t *s, accel *a, const rayset_t *prim)
{
    if (a->ops->flags & ACCEL_NO_COUNTERS) {
        fprintf(stderr, "accelbench: --heatmap: %s does not expose its counters; choose another accelerator\n", a->ops->name);
        return 2;
    }
    answers_t *ans = answers_new(prim, true);
    trace_rayset(a, prim, cell_threads(a->ops, a, o->threads), ans);
    size_t npix = (size_t)prim->width * prim->height;
    double *cost = checked_calloc(npix, sizeof *cost, "a heat map's per-pixel costs");
    bool steps = strcmp(o->heatmap, "steps") == 0;
    for (uint32_t i = 0; i < prim->count; i++)
        cost[prim->pixel[i]] += (double)(steps ? ans->per_ray[i].steps : ans->per_ray[i].prim_tests) / prim->spp;
    double lo = INFINITY, hi = 0, mean = 0;
    for (size_t i = 0; i < npix; i++) {
        lo = fmin(lo, cost[i]);
        hi = fmax(hi, cost[i]);
        mean += cost[i] / (double)npix;
    }
    image_t *im = image_new((int)prim->width, (int)prim->height);
    double top = o->heatmap_max > 0 ? o->heatmap_max : hi; /* --heatmap-max: one scale for several images */
    for (size_t i = 0; i < npix; i++) colormap_inferno(top > 0 ? (float)fmin(1.0, cost[i] / top) : 0.0f, &im->rgb[i * 3]);
    char err[512];
    int rc = image_write_png(im, o->out, err, sizeof err);
    if (rc) fprintf(stderr, "accelbench: %s\n", err);
    else if (!o->quiet)
        printf("wrote %s: %s per pixel through %s on %s: min %.1f mean %.1f max %.1f (colour scale 0..%s%.6g)\n", o->out,
               o->heatmap, a->ops->name, s->name, lo, mean, hi, o->heatmap_max > 0 ? "" : "max ", top);
    image_free(im);
    free(cost);
    answers_free(ans);
    return rc ? 2 : 0;
}

int render_main(options *o)
{
    if (o->nscenes != 1 || o->naccels != 1 + o->shadow_accel || !o->out) {
        fprintf(stderr, "accelbench render: give one --scene, one --accel and --out FILE.png (see accelbench render --help)\n");
        return 2;
    }
    const accel_config *ac = &o->accels[0];
    if (!ac->ops->intersect) {
        fprintf(stderr, "accelbench render: %s answers shadow rays only and cannot render; give it as --shadow-accel %s beside "
                "an --accel for the other rays\n", ac->ops->name, ac->ops->name);
        return 2;
    }
    char err[512];
    scene_t *s = scene_load(o->scenes[0], err, sizeof err);
    if (!s) {
        fprintf(stderr, "accelbench: %s\n", err);
        return 2;
    }
    workload_opts wl = o->wl;
    if (!o->res_given) {
        wl.width = s->camera.width > 0 ? s->camera.width : 512;
        wl.height = s->camera.height > 0 ? s->camera.height : 512;
    }
    /* The image's memory before the build and the rays (resources.h);
     * with --res it was checked before the scene loaded, without it the
     * size is the scene's own, known only now. */
    if (render_check_memory(s->name, wl.width, wl.height, wl.spp, wl.corners, o->heatmap != NULL, err, sizeof err)) {
        fprintf(stderr, "accelbench: %s%s\n", err, o->res_given ? "" : " (the scene's own resolution: --res sets another)");
        scene_free(s);
        return 2;
    }
    accel *a = accel_build(ac->ops, s, &ac->params, err, sizeof err);
    if (!a) {
        fprintf(stderr, "accelbench: %s on %s: build failed: %s\n", ac->ops->name, s->name, err);
        scene_free(s);
        return 2;
    }
    accel *shadow = a;
    if (o->shadow_accel) {
        const accel_config *sc = &o->accels[1];
        shadow = accel_build(sc->ops, s, &sc->params, err, sizeof err);
        if (!shadow) {
            fprintf(stderr, "accelbench: %s on %s: build failed: %s\n", sc->ops->name, s->name, err);
            a->ops->destroy(a);
            scene_free(s);
            return 2;
        }
    }
    rayset_t *prim = workload_primary(s, &wl);
    int rc = o->heatmap ? render_heatmap(o, s, a, prim) : render_image(o, s, a, shadow, prim);
    rayset_free(prim);
    if (shadow != a) shadow->ops->destroy(shadow);
    a->ops->destroy(a);
    scene_free(s);
    return rc;
}
