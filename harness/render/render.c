/* render.c: Whitted shading and cost heat maps (see render.h).
 *
 * Shading: ambient 0.1 plus, per light the surface faces and that an
 * occlusion query says is visible, Lambert kd * colour * cos / sqrt(#lights)
 * (cos against the shading normal: `pp` normals interpolated); plus ks
 * times the mirror-reflected colour and T times the refracted colour, to
 * depth 3. The secondary rays are the whitted workload's (spawn.h): the
 * same origins, shadow rule, reflection and refraction. Two-sided: the
 * normals are turned toward the viewer. Every ray goes through the chosen
 * accelerator (the shadow rays through --shadow-accel's when given: a
 * shadow-only one such as the light buffer), so two correct accelerators
 * give the same picture up to float noise at edges. */
#include "render.h"
#include "../measure/measure.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "image.h"
#include "../workloads/resources.h"
#include "../workloads/spawn.h"
#include "../workloads/trace.h"
#include "../../prims/checked_alloc.h"

#define RENDER_DEPTH 3

typedef struct {
    const scene_t *s;
    accel *a, *sa; /* closest hits; shadow rays (sa may be a) */
    accel_ctx *ctx, *sctx;
    counters_t c;
    float light_scale;
} shader_t;

static vec3 shade(shader_t *sh, const ray_t *r, int depth)
{
    const scene_t *s = sh->s;
    hit_t h = hit_none(r);
    if (!sh->a->ops->intersect(sh->a, sh->ctx, r, &h, &sh->c)) return s->background;
    spawn_t f = spawn_at(s, r, &h);
    const material_t *m = f.m;
    vec3 col = v3_scale(m->color, 0.1f);
    for (uint32_t l = 0; l < s->nlights; l++) {
        ray_t sr;
        if (!spawn_shadow(s, &f, l, &sr)) continue;
        float cosine = v3_dot(sr.dir, f.ns);
        if (cosine <= 0.0f || sh->sa->ops->occluded(sh->sa, sh->sctx, &sr, &sh->c)) continue;
        col = v3_add(col, v3_scale(m->color, m->kd * cosine * sh->light_scale));
    }
    if (depth >= RENDER_DEPTH) return col;
    if (m->ks > 0.0f) {
        ray_t rr = spawn_reflect(&f);
        col = v3_add(col, v3_scale(shade(sh, &rr, depth + 1), m->ks));
    }
    ray_t tr;
    if (m->t > 0.0f && spawn_refract(&f, &tr)) col = v3_add(col, v3_scale(shade(sh, &tr, depth + 1), m->t));
    return col;
}

image_t *render_whitted(const scene_t *s, accel *a, const rayset_t *prim, counters_t *work)
{
    return render_whitted_shadows(s, a, a, prim, work);
}

image_t *render_whitted_shadows(const scene_t *s, accel *a, accel *shadow, const rayset_t *prim, counters_t *work)
{
    image_t *im = image_new((int)prim->width, (int)prim->height);
    vec3 *sum = checked_calloc((size_t)prim->width * prim->height, sizeof *sum, "an image's colour sums");
    shader_t sh = {.s = s, .a = a, .sa = shadow, .ctx = a->ops->context_new ? a->ops->context_new(a) : NULL,
                   .light_scale = s->nlights ? 1.0f / sqrtf((float)s->nlights) : 1.0f};
    sh.sctx = shadow == a ? sh.ctx : shadow->ops->context_new ? shadow->ops->context_new(shadow) : NULL;
    for (uint32_t i = 0; i < prim->count; i++) sum[prim->pixel[i]] = v3_add(sum[prim->pixel[i]], shade(&sh, &prim->rays[i], 1));
    float inv = 1.0f / (float)prim->spp;
    for (uint32_t y = 0; y < prim->height; y++)
        for (uint32_t x = 0; x < prim->width; x++) image_set(im, (int)x, (int)y, v3_scale(sum[y * prim->width + x], inv));
    if (a->ops->context_free) a->ops->context_free(sh.ctx);
    if (shadow != a && shadow->ops->context_free) shadow->ops->context_free(sh.sctx);
    if (work) *work = sh.c;
    free(sum);
    return im;
}

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
        if (!(a->ops->flags & ACCEL_OPAQUE) && !(shadow->ops->flags & ACCEL_OPAQUE))
            printf(", %.1f ray/primitive tests per pixel", (double)work.prim_tests / ((double)prim->width * prim->height));
        printf("\n");
    }
    image_free(im);
    return rc ? 2 : 0;
}

static int render_heatmap(const options *o, const scene_t *s, accel *a, const rayset_t *prim)
{
    if (a->ops->flags & ACCEL_OPAQUE) {
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
    if (resources_check_render(s->name, wl.width, wl.height, wl.spp, wl.corners, o->heatmap != NULL, err, sizeof err)) {
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
