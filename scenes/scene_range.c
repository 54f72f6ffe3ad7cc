/* scene_range.c: the ranges every scene lies in (the bounds and why they
 * are what they are: scene.h). scene_finish calls both checks, so every
 * loader and generator ends in them; the messages name the store's index
 * of the culprit, for sources that have no file line to name. */
#include "scene.h"

#include <string.h>

static bool vec_ok(vec3 v) { return scene_coord_ok(v.x) && scene_coord_ok(v.y) && scene_coord_ok(v.z); }
static bool view_vec_ok(vec3 v) { return scene_view_coord_ok(v.x) && scene_view_coord_ok(v.y) && scene_view_coord_ok(v.z); }

static int check_vertices(const prims_t *p, char *err, size_t errlen)
{
    for (uint32_t i = 0; i < p->nverts; i++) {
        vec3 v = p->verts[i];
        if (vec_ok(v)) continue;
        if (!v3_finite(v))
            snprintf(err, errlen, "vertex %u has a NaN or infinite coordinate (%g %g %g)", i, v.x, v.y, v.z);
        else
            snprintf(err, errlen, "vertex %u (%g %g %g) is outside the scene range: coordinates must be " SCENE_COORD_RANGE,
                     i, v.x, v.y, v.z);
        return -1;
    }
    return 0;
}

/* Primitive ids of the k-th sphere or cone, for the message. */
static uint32_t prim_id_of(const prims_t *p, prim_kind kind, uint32_t k)
{
    for (uint32_t id = 0; id < p->count; id++)
        if (p->kind[id] == kind && p->index[id] == k) return id;
    return UINT32_MAX;
}

static int check_spheres(const prims_t *p, char *err, size_t errlen)
{
    for (uint32_t k = 0; k < p->nspheres; k++) {
        sphere_t s = p->spheres[k];
        if (scene_ball_ok(s.center, s.radius)) continue;
        snprintf(err, errlen, "sphere %u (primitive %u) with centre (%g %g %g) and radius %g reaches outside the scene "
                 "range: centre +- radius must be " SCENE_COORD_RANGE, k, prim_id_of(p, PRIM_SPHERE, k), s.center.x,
                 s.center.y, s.center.z, s.radius);
        return -1;
    }
    return 0;
}

/* Refuse cone k: "cone K (primitive ID) with base ... radius R: " + why. */
static int cone_fail(const prims_t *p, uint32_t k, const char *why, char *err, size_t errlen)
{
    cone_t c = p->cones[k];
    snprintf(err, errlen, "cone %u (primitive %u) with base (%g %g %g) radius %g, apex (%g %g %g) radius %g %s", k,
             prim_id_of(p, PRIM_CONE, k), c.base.x, c.base.y, c.base.z, c.base_radius, c.apex.x, c.apex.y, c.apex.z,
             c.apex_radius, why);
    return -1;
}

const char *scene_cone_problem(cone_t c)
{
    float len = v3_len(v3_sub(c.apex, c.base)); /* as cone_intersect computes it */
    if (!scene_ball_ok(c.base, c.base_radius) || !scene_ball_ok(c.apex, c.apex_radius))
        return "reaches outside the scene range: each end +- its radius must be " SCENE_COORD_RANGE;
    if (!(len > 0.0f)) return "has no axis direction in float (base and apex too close)";
    if (!(fabsf(c.apex_radius - c.base_radius) <= SCENE_CONE_SLOPE_MAX * len))
        return "is flatter than a float cone can be: |apex radius - base radius| / |apex - base| must be at most 2^24";
    return NULL;
}

static int check_cones(const prims_t *p, char *err, size_t errlen)
{
    for (uint32_t k = 0; k < p->ncones; k++) {
        const char *why = scene_cone_problem(p->cones[k]);
        if (why) return cone_fail(p, k, why, err, errlen);
    }
    return 0;
}

int scene_check_geometry(const scene_t *s, char *err, size_t errlen)
{
    const prims_t *p = &s->prims;
    return check_vertices(p, err, errlen) || check_spheres(p, err, errlen) || check_cones(p, err, errlen) ? -1 : 0;
}

int scene_check_view(const camera_t *c, const vec3 *lights, uint32_t nlights, char *err, size_t errlen)
{
    const struct { const char *what; vec3 v; } pts[] = {{"eye", c->from}, {"look-at point", c->at}, {"up vector", c->up}};
    for (size_t i = 0; i < sizeof pts / sizeof pts[0]; i++)
        if (!view_vec_ok(pts[i].v)) {
            snprintf(err, errlen, "camera %s (%g %g %g) is outside the view range: coordinates must be " SCENE_VIEW_RANGE,
                     pts[i].what, pts[i].v.x, pts[i].v.y, pts[i].v.z);
            return -1;
        }
    for (uint32_t l = 0; l < nlights; l++)
        if (!view_vec_ok(lights[l])) {
            vec3 p = lights[l];
            snprintf(err, errlen, "light %u (%g %g %g) is outside the view range: coordinates must be " SCENE_VIEW_RANGE,
                     l, p.x, p.y, p.z);
            return -1;
        }
    if (!(c->fov_deg > 0.0f && c->fov_deg < 180.0f)) {
        snprintf(err, errlen, "camera angle %g is not in (0, 180) degrees", (double)c->fov_deg);
        return -1;
    }
    if (!(c->hither >= 0.0f && c->hither <= SCENE_VIEW_MAX)) {
        snprintf(err, errlen, "camera hither %g is not in [0, 2^36]", (double)c->hither);
        return -1;
    }
    /* In double, where these products cannot underflow or overflow: the
     * float frame of the workloads then normalises cleanly. */
    dvec3 dir = dv3_sub(dv3(c->at), dv3(c->from)), up = dv3(c->up), side = dv3_cross(dir, up);
    double ld = sqrt(dv3_dot(dir, dir)), lu = sqrt(dv3_dot(up, up)), ls = sqrt(dv3_dot(side, side));
    if (!(ld >= SCENE_VIEW_MIN_LEN)) {
        snprintf(err, errlen, "eye and at are the same point (%g %g %g) or closer than 2^-40", c->from.x, c->from.y,
                 c->from.z);
        return -1;
    }
    if (!(lu >= SCENE_VIEW_MIN_LEN) || !(ls > 1e-6 * ld * lu)) {
        snprintf(err, errlen, "up (%g %g %g) is zero or along the view direction (or shorter than 2^-40)", c->up.x,
                 c->up.y, c->up.z);
        return -1;
    }
    return 0;
}
