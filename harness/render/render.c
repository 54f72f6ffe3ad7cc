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

resources_estimate render_estimate(int width, int height, int spp, bool corners, bool heatmap)
{
    workload_opts o = {.width = width, .height = height, .spp = spp, .corners = corners};
    uint64_t n = workload_primary_rays(&o), pixels = memory_mul((uint64_t)(width > 0 ? width : 1), (uint64_t)(height > 0 ? height : 1));
    resources_estimate e = {n, rayset_bytes(n, true)};
    uint64_t image = memory_mul(pixels, 3);
    if (heatmap) /* answers with per-ray counters, then one double a pixel */
        e.bytes = memory_add(e.bytes, memory_add(answers_bytes(n, QUERY_CLOSEST, true),
                                                 memory_add(memory_mul(pixels, sizeof(double)), image)));
    else /* one colour sum a pixel (vec3) beside the image */
        e.bytes = memory_add(e.bytes, memory_add(memory_mul(pixels, sizeof(vec3)), image));
    return e;
}

int render_check_memory(const char *scene, int width, int height, int spp, bool corners, bool heatmap, char *err,
                           size_t errlen)
{
    resources_estimate e = render_estimate(width, height, spp, corners, heatmap);
    char image[96];
    resources_describe_image(image, sizeof image, width, height, spp, corners);
    if (e.rays > RAYSET_RAYS_MAX) {
        snprintf(err, errlen, "render %s: %s is %llu primary rays, more than a ray set holds (2^32 - 1); lower --res or --spp",
                 scene, image, (unsigned long long)e.rays);
        return -1;
    }
    return memory_cap_exceeded(e.bytes, err, errlen, "render %s: a %s %s and its %llu rays", scene, image,
                               heatmap ? "heat map" : "image", (unsigned long long)e.rays)
               ? -1
               : 0;
}
