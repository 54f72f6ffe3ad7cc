/* spawn.c: secondary rays from a hit (see spawn.h). */
#include "spawn.h"

#include <math.h>

spawn_t spawn_at(const scene_t *s, const ray_t *r, const hit_t *h)
{
    spawn_t f;
    surface_point sp = prim_surface_point(&s->prims, r, h);
    f.m = &s->materials[s->prim_material ? s->prim_material[h->prim] : 0];
    f.dir = r->dir;
    f.prim = h->prim;
    f.entering = v3_dot(sp.normal, f.dir) < 0.0f;
    f.n = f.entering ? sp.normal : v3_scale(sp.normal, -1.0f);
    vec3 ns = scene_shading_normal(s, h->prim, &sp);
    if (v3_dot(ns, f.n) < 0.0f) ns = v3_scale(ns, -1.0f);
    f.ns = ns;
    f.org_out = offset_ray_origin(sp.p, sp.err, f.n);
    f.org_in = offset_ray_origin(sp.p, sp.err, v3_scale(f.n, -1.0f));
    return f;
}

bool spawn_shadow(const scene_t *s, const spawn_t *f, uint32_t l, ray_t *out)
{
    vec3 to = v3_sub(s->lights[l], f->org_out);
    float dist = v3_len(to);
    /* SPD rule 10: no shadow ray from a surface facing away from the light. */
    if (!(dist > 0.0f) || v3_dot(to, f->n) <= 0.0f) return false;
    *out = (ray_t){f->org_out, 0.0f, v3_scale(to, 1.0f / dist), dist, l, f->prim};
    return true;
}

static vec3 reflect(vec3 d, vec3 n) { return v3_sub(d, v3_scale(n, 2.0f * v3_dot(d, n))); }

ray_t spawn_reflect(const spawn_t *f)
{
    vec3 d = reflect(f->dir, f->ns);
    /* A shading normal far from the geometric one can mirror into the surface. */
    if (v3_dot(d, f->n) <= 0.0f) d = reflect(f->dir, f->n);
    return (ray_t){f->org_out, 0.0f, v3_norm(d), INFINITY, RAY_NO_LIGHT, f->prim};
}

/* Snell's law about unit normal n facing the incoming unit direction d,
 * eta = n_incoming / n_transmitted: false on total internal reflection. */
static bool refract(vec3 d, vec3 n, float eta, vec3 *t)
{
    float cosi = -v3_dot(d, n);
    float k = 1.0f - eta * eta * (1.0f - cosi * cosi);
    if (k < 0.0f) return false;
    *t = v3_add(v3_scale(d, eta), v3_scale(n, eta * cosi - sqrtf(k)));
    return true;
}

bool spawn_refract(const spawn_t *f, ray_t *out)
{
    float ior = f->m->ior > 0.0f ? f->m->ior : 1.0f;
    float eta = f->entering ? 1.0f / ior : ior;
    vec3 t, d = v3_norm(f->dir);
    if (!refract(d, f->ns, eta, &t)) return false;
    /* Through the shading normal the ray may stay on the incoming side: the geometric one then. */
    if (v3_dot(t, f->n) >= 0.0f && (!refract(d, f->n, eta, &t) || v3_dot(t, f->n) >= 0.0f)) return false;
    *out = (ray_t){f->org_in, 0.0f, v3_norm(t), INFINITY, RAY_NO_LIGHT, f->prim};
    return true;
}
