/* spawn.h: the secondary rays of a hit, by Whitted's rules as the SPD
 * Readme's testing procedure states them (items 7-10): shadow rays to the
 * lights the surface faces, a reflection ray from every reflector or
 * transmitter (Ks > 0 or T > 0), a refraction ray by Snell's law from every
 * transmitter unless the ray is totally internally reflected. The shadow,
 * reflection and whitted workloads and the renderer all spawn through
 * here, so they agree on every rule.
 *
 * Origins are robust (prim_surface_point and offset_ray_origin: pbrt-v4's
 * error bounds): on the incoming ray's side of the surface for shadow and
 * reflection rays, on the far side for refraction rays, in exact
 * arithmetic. Directions use the shading normal (scene_shading_normal: the
 * interpolated `pp` normal of a smooth primitive, else the geometric one),
 * and fall back to the geometric normal where the shading normal would
 * send a reflected ray into the surface or a refracted one out of it. The
 * shadow rule ("no shadow ray when the surface normal points away from the
 * light") uses the geometric normal, the side the origin is on. */
#ifndef ACCELBENCH_SPAWN_H
#define ACCELBENCH_SPAWN_H

#include "../../scenes/scene.h"

typedef struct {
    const material_t *m;
    vec3 dir;        /* the incoming ray's direction (unit for every workload's rays) */
    vec3 n;          /* unit geometric normal, turned to face the incoming ray */
    vec3 ns;         /* unit shading normal, on the same side as n */
    bool entering;   /* the ray enters the primitive (against its outward normal) */
    vec3 org_out;    /* origin for rays leaving on the incoming side */
    vec3 org_in;     /* origin for rays going through the surface */
    uint32_t prim;   /* the hit primitive: every spawned ray's `origin` */
} spawn_t;

/* The frame of hit h (a hit, h->prim != HIT_NONE) of ray r. */
spawn_t spawn_at(const scene_t *s, const ray_t *r, const hit_t *h);

/* A shadow ray to light l (any-hit, tfar at the light, ray->light = l):
 * false when the surface faces away from the light or the light is at the
 * origin. */
bool spawn_shadow(const scene_t *s, const spawn_t *f, uint32_t l, ray_t *out);
/* The mirror reflection. */
ray_t spawn_reflect(const spawn_t *f);
/* The refraction by Snell's law with the material's index of refraction
 * (from outside: 1 / ior; leaving the primitive: ior; an ior <= 0 counts
 * as 1): false on total internal reflection. */
bool spawn_refract(const spawn_t *f, ray_t *out);

#endif
