/* workload_whitted.c: the SPD protocol's Whitted ray trees as four ray
 * sets, one per ray type (see workload.h, workload_whitted).
 *
 * The protocol is the SPD Readme's "Testing Procedures" (Haines, SPD 3.14):
 * 6) 512 x 512 pixels, rays through the corners, 513 x 513 eye rays;
 * 7) maximum tree depth 5, the eye ray of depth 1; 8) every ray hitting a
 * reflective or transmitting object spawns a reflection ray below that
 * depth; 9) every ray hitting a transmitter spawns a refraction ray by
 * Snell's law, unless total internal reflection occurs (the reflection ray
 * is still spawned); 10) no shadow ray where the surface normal points away
 * from the light, transmitters included. The Readme's figures for its
 * seven databases (eye hits, reflected, refracted and shadow rays) are what
 * `accelbench reproduce spd` compares against. Shadow rays go from every
 * hit of the tree, the last generation's too (they end in a light, not in
 * a further tree level).
 *
 * A generation is traced through the reference accelerator before the
 * next is made, so no accelerator under test changes the rays. */
#include "workload.h"

#include <string.h>
#include "resources.h"
#include "spawn.h"

const char *const whitted_part_name[WHITTED_PARTS] = {"whitted:eye", "whitted:reflected", "whitted:refracted",
                                                      "whitted:shadow"};

static bool scene_has_transmitter(const scene_t *s)
{
    for (uint32_t i = 0; i < s->nmaterials; i++)
        if (s->materials[i].t > 0.0f) return true;
    return false;
}

static bool scene_has_reflector(const scene_t *s)
{
    for (uint32_t i = 0; i < s->nmaterials; i++)
        if (s->materials[i].ks > 0.0f || s->materials[i].t > 0.0f) return true;
    return false;
}

bool workload_empty_by_rule(const workload_def *w, const scene_t *s)
{
    if (!strcmp(w->name, whitted_part_name[WHITTED_REFRACTED])) return !scene_has_transmitter(s);
    if (!strcmp(w->name, whitted_part_name[WHITTED_REFLECTED])) return !scene_has_reflector(s);
    return false;
}

/* The set's estimate against the memory cap, with what the scene's materials allow. */
static void require_memory(const scene_t *s, const workload_opts *o, whitted_part part)
{
    char err[1024];
    if (whitted_check_memory(s->name, o, s->nlights, scene_has_transmitter(s), part, err, sizeof err))
        workload_refuse(err);
}

static rayset_t *new_part(const scene_t *s, const workload_opts *o, whitted_part part, const rayset_t *eye)
{
    rayset_t *rs = rayset_new(whitted_part_name[part], s->name, o->seed, part == WHITTED_SHADOW ? QUERY_ANY : QUERY_CLOSEST);
    rs->width = eye->width, rs->height = eye->height, rs->spp = eye->spp;
    return rs;
}

rayset_t *workload_whitted(const scene_t *s, accel *ref, const workload_opts *o, whitted_part part)
{
    require_memory(s, o, part);
    workload_opts corners = *o;
    corners.corners = true;
    rayset_t *gen = workload_primary(s, &corners);
    if (part == WHITTED_EYE) { /* sealed already: the hash is of the rays, not the name */
        snprintf(gen->workload, sizeof gen->workload, "%s", whitted_part_name[part]);
        return gen;
    }
    rayset_t *out = new_part(s, o, part, gen);
    int depth = o->depth > 0 ? o->depth : WORKLOAD_WHITTED_DEPTH;
    /* Only shadow rays leave the last generation's hits: the other parts need not trace it. */
    int traced = part == WHITTED_SHADOW ? depth : depth - 1;
    for (int d = 1; d <= traced && gen->count; d++) {
        answers_t *a = workload_reference_hits(ref, gen, o);
        rayset_t *next = rayset_new("whitted", s->name, o->seed, QUERY_CLOSEST);
        next->width = gen->width; /* keep pixel tracking on */
        for (uint32_t i = 0; i < gen->count; i++) {
            if (a->hits[i].prim == HIT_NONE) continue;
            spawn_t f = spawn_at(s, &gen->rays[i], &a->hits[i]);
            ray_t r;
            if (part == WHITTED_SHADOW)
                for (uint32_t l = 0; l < s->nlights; l++)
                    if (spawn_shadow(s, &f, l, &r)) rayset_push(out, &r, gen->pixel[i]);
            if (d == depth) continue; /* the tree ends here: no further closest-hit rays */
            if (f.m->ks > 0.0f || f.m->t > 0.0f) {
                r = spawn_reflect(&f);
                rayset_push(next, &r, gen->pixel[i]);
                if (part == WHITTED_REFLECTED) rayset_push(out, &r, gen->pixel[i]);
            }
            if (f.m->t > 0.0f && spawn_refract(&f, &r)) {
                rayset_push(next, &r, gen->pixel[i]);
                if (part == WHITTED_REFRACTED) rayset_push(out, &r, gen->pixel[i]);
            }
        }
        answers_free(a);
        rayset_free(gen);
        gen = next;
    }
    rayset_free(gen);
    rayset_seal(out);
    return out;
}

resources_estimate whitted_estimate(const workload_opts *o, uint32_t nlights, bool transmitters, whitted_part part)
{
    workload_opts eye = *o;
    eye.corners = true;
    uint64_t n = workload_primary_rays(&eye), depth = o->depth > 0 ? (uint64_t)o->depth : WORKLOAD_WHITTED_DEPTH;
    /* Generation g (the eye rays are 1) has at most n b^(g-1) rays, b = 2
     * where a transmitter can both reflect and refract, else 1; the
     * secondary rays of each kind at generation g at most the hits of g-1. */
    uint64_t gen = n, closest = 0, widest = n, secondary = 0;
    for (uint64_t g = 1; g <= depth; g++) {
        closest = memory_add(closest, gen);
        widest = gen > widest ? gen : widest;
        if (g > 1) secondary = memory_add(secondary, gen / (transmitters ? 2 : 1));
        gen = transmitters ? memory_mul(gen, 2) : gen;
    }
    resources_estimate e;
    e.rays = part == WHITTED_EYE ? n : part == WHITTED_SHADOW ? memory_mul(closest, nlights ? nlights : 1)
             : part == WHITTED_REFRACTED && !transmitters ? 0 : secondary;
    bool any = part == WHITTED_SHADOW;
    /* Making: two generations and the answers of one alive beside the part being filled. */
    uint64_t making = memory_add(memory_add(memory_mul(rayset_bytes(widest, true), 2),
                                            answers_bytes(widest, QUERY_CLOSEST, false)),
                                 rayset_bytes(e.rays, true));
    e.bytes = resources_max(making, cell_bytes(e.rays, any ? QUERY_ANY : QUERY_CLOSEST, true));
    return e;
}

int whitted_check_memory(const char *scene, const workload_opts *o, uint32_t nlights, bool transmitters,
                            whitted_part part, char *err, size_t errlen)
{
    return workload_check_estimate(whitted_part_name[part], scene, o, nlights, whitted_estimate(o, nlights, transmitters, part),
                          err, errlen);
}
