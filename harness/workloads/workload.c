/* workload.c: making the ray sets (see workload.h). */
#include "workload.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "resources.h"
#include "rng.h"
#include "spawn.h"
#include "trace.h"

/* rng streams: one per use, so workloads never share random numbers */
enum { STREAM_PIXEL = 1, STREAM_DIFFUSE = 2, STREAM_RANDOM = 3 };

void hit_frame(const scene_t *s, const ray_t *r, const hit_t *h, vec3 *org, vec3 *n)
{
    surface_point sp = prim_surface_point(&s->prims, r, h);
    *n = v3_dot(sp.normal, r->dir) > 0.0f ? v3_scale(sp.normal, -1.0f) : sp.normal;
    *org = offset_ray_origin(sp.p, sp.err, *n);
}

/* Camera frame shared by primary rays: unit forward, and right/up scaled
 * so that one pixel step moves the image-plane point by one pixel. */
typedef struct { vec3 from, forward, right, up; float x0, y0; } eye_t;

static eye_t eye_setup(const camera_t *cam, int width, int height)
{
    eye_t e;
    e.from = cam->from;
    e.forward = v3_norm(v3_sub(cam->at, cam->from));
    vec3 right = v3_norm(v3_cross(e.forward, cam->up));
    vec3 up = v3_cross(right, e.forward);
    /* NFF: fov spans the centres of the top and bottom pixel rows. */
    float half = tanf(cam->fov_deg * (float)M_PI / 360.0f);
    float step = height > 1 ? 2.0f * half / (float)(height - 1) : 2.0f * half;
    e.right = v3_scale(right, step);
    e.up = v3_scale(up, -step); /* pixel y grows downward */
    e.x0 = 0.5f * (float)(width - 1);
    e.y0 = 0.5f * (float)(height - 1);
    return e;
}

static ray_t eye_ray(const eye_t *e, float px, float py, float hither)
{
    vec3 d = v3_add(e->forward, v3_add(v3_scale(e->right, px - e->x0), v3_scale(e->up, py - e->y0)));
    ray_t r = {e->from, hither, v3_norm(d), INFINITY, RAY_NO_LIGHT, RAY_NO_ORIGIN};
    return r;
}

rayset_t *workload_primary(const scene_t *s, const workload_opts *o)
{
    rayset_t *rs = rayset_new("primary", s->name, o->seed, QUERY_CLOSEST);
    int w = o->width, h = o->height, spp = o->spp < 1 ? 1 : o->spp;
    rs->width = (uint32_t)w;
    rs->height = (uint32_t)h;
    rs->spp = (uint32_t)spp;
    /* Corner rays are the SPD's (W+1) x (H+1) grid of rays spanning the
     * full view angle: NFF's angle runs between the outermost rays. */
    eye_t e = o->corners ? eye_setup(&s->camera, w + 1, h + 1) : eye_setup(&s->camera, w, h);
    float hither = s->camera.hither > 0.0f ? s->camera.hither : 0.0f;
    if (o->corners) {
        /* (w+1) x (h+1) corner rays; each is charged to the pixel below-right of it (clamped). */
        for (int y = 0; y <= h; y++)
            for (int x = 0; x <= w; x++) {
                ray_t r = eye_ray(&e, (float)x, (float)y, hither);
                uint32_t px = (uint32_t)((y < h ? y : h - 1) * w + (x < w ? x : w - 1));
                rayset_push(rs, &r, px);
            }
        rs->spp = 1;
    } else {
        /* spp samples stratified on a ceil(sqrt(spp))^2 grid, jittered per cell. */
        int side = (int)ceilf(sqrtf((float)spp));
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                uint32_t pixel = (uint32_t)(y * w + x);
                for (int k = 0; k < spp; k++) {
                    float sx = 0.0f, sy = 0.0f;
                    if (spp > 1) {
                        uint64_t idx = (uint64_t)pixel * (uint64_t)spp + (uint64_t)k;
                        sx = ((float)(k % side) + rng_float(o->seed, STREAM_PIXEL, idx, 0)) / (float)side - 0.5f;
                        sy = ((float)(k / side) + rng_float(o->seed, STREAM_PIXEL, idx, 1)) / (float)side - 0.5f;
                    }
                    ray_t r = eye_ray(&e, (float)x + sx, (float)y + sy, hither);
                    rayset_push(rs, &r, pixel);
                }
            }
    }
    rayset_seal(rs);
    return rs;
}

/* The set's estimate against the memory cap before any of it is made
 * (resources.h, which also says what it counts). The table's make() has no
 * error path, so a refusal is exit 2 with its line, as for the random
 * workload's box. run and verify have checked the same at one light before
 * their first scene; here the scene's lights are known. */
void workload_refuse(const char *err)
{
    fflush(stdout);
    fprintf(stderr, "accelbench: %s\n", err);
    exit(2);
}

void workload_require_memory(const char *name, const scene_t *s, const workload_opts *o)
{
    char err[1024];
    if (workload_check_memory(name, s->name, o, s->nlights, err, sizeof err)) workload_refuse(err);
}

static rayset_t *make_primary(const scene_t *s, accel *ref, const workload_opts *o)
{
    (void)ref;
    workload_require_memory("primary", s, o);
    return workload_primary(s, o);
}

answers_t *workload_reference_hits(accel *ref, const rayset_t *prim, const workload_opts *o)
{
    answers_t *a = answers_new(prim, false);
    trace_rayset(ref, prim, o->threads, a);
    return a;
}

/* What a secondary workload spawns at one reference hit f of ray i (its
 * pixel): rays into the set rs and, for a further generation, into next. */
typedef void (*bounce_fn)(const scene_t *s, const workload_opts *o, const spawn_t *f, uint32_t i, uint32_t pixel,
                          rayset_t *rs, rayset_t *next);

/* A secondary workload: from the primary rays, `depth` generations of the
 * reference's hits, each hit spawning rays by bounce; the set keeps every
 * generation's rays in order, each with its primary ray's pixel. */
static rayset_t *make_bounces(const scene_t *s, accel *ref, const workload_opts *o, const char *name, query_kind q,
                              int depth, bounce_fn bounce)
{
    workload_require_memory(name, s, o);
    rayset_t *gen = workload_primary(s, o);
    rayset_t *rs = rayset_new(name, s->name, o->seed, q);
    rs->width = gen->width, rs->height = gen->height, rs->spp = gen->spp;
    for (int g = 1; g <= depth && gen->count; g++) {
        answers_t *a = workload_reference_hits(ref, gen, o);
        rayset_t *next = rayset_new(name, s->name, o->seed, q);
        next->width = gen->width; /* keep pixel tracking on */
        for (uint32_t i = 0; i < gen->count; i++) {
            if (a->hits[i].prim == HIT_NONE) continue;
            spawn_t f = spawn_at(s, &gen->rays[i], &a->hits[i]);
            bounce(s, o, &f, i, gen->pixel[i], rs, next);
        }
        answers_free(a);
        rayset_free(gen);
        gen = next;
    }
    rayset_free(gen);
    rayset_seal(rs);
    return rs;
}

/* shadow: a ray to every light on the lit side. */
static void bounce_shadow(const scene_t *s, const workload_opts *o, const spawn_t *f, uint32_t i, uint32_t pixel,
                          rayset_t *rs, rayset_t *next)
{
    (void)o, (void)i, (void)next;
    ray_t r;
    for (uint32_t l = 0; l < s->nlights; l++)
        if (spawn_shadow(s, f, l, &r)) rayset_push(rs, &r, pixel);
}

/* reflection: the mirror ray, which the next generation follows. */
static void bounce_reflection(const scene_t *s, const workload_opts *o, const spawn_t *f, uint32_t i, uint32_t pixel,
                              rayset_t *rs, rayset_t *next)
{
    (void)s, (void)o, (void)i;
    ray_t r = spawn_reflect(f);
    rayset_push(next, &r, pixel);
    rayset_push(rs, &r, pixel);
}

/* A cosine-distributed direction about n (Malley's method: uniform disk
 * point lifted to the hemisphere). */
static vec3 cosine_dir(vec3 n, float u1, float u2)
{
    vec3 a = fabsf(n.x) > 0.9f ? v3(0, 1, 0) : v3(1, 0, 0);
    vec3 t = v3_norm(v3_cross(a, n)), b = v3_cross(n, t);
    float r = sqrtf(u1), phi = 2.0f * (float)M_PI * u2;
    float z = sqrtf(fmaxf(0.0f, 1.0f - u1));
    return v3_norm(v3_add(v3_scale(n, z), v3_add(v3_scale(t, r * cosf(phi)), v3_scale(b, r * sinf(phi)))));
}

/* diffuse: one cosine-distributed ray, drawn from ray i's stream. */
static void bounce_diffuse(const scene_t *s, const workload_opts *o, const spawn_t *f, uint32_t i, uint32_t pixel,
                           rayset_t *rs, rayset_t *next)
{
    (void)s, (void)next;
    vec3 d = cosine_dir(f->n, rng_float(o->seed, STREAM_DIFFUSE, i, 0), rng_float(o->seed, STREAM_DIFFUSE, i, 1));
    ray_t r = {f->org_out, 0.0f, d, INFINITY, RAY_NO_LIGHT, f->prim};
    rayset_push(rs, &r, pixel);
}

static rayset_t *make_shadow(const scene_t *s, accel *ref, const workload_opts *o)
{
    return make_bounces(s, ref, o, "shadow", QUERY_ANY, 1, bounce_shadow);
}

static rayset_t *make_reflection(const scene_t *s, accel *ref, const workload_opts *o)
{
    int depth = o->depth > 0 ? o->depth : WORKLOAD_REFLECTION_DEPTH;
    return make_bounces(s, ref, o, "reflection", QUERY_CLOSEST, depth, bounce_reflection);
}

static rayset_t *make_diffuse(const scene_t *s, accel *ref, const workload_opts *o)
{
    return make_bounces(s, ref, o, "diffuse", QUERY_CLOSEST, 1, bounce_diffuse);
}

/* Consecutive zero-length segments after which the box is taken to have no
 * two distinct points a draw can reach. A box with two float values along
 * one axis gives a zero-length segment with probability about 1/2, so a
 * healthy box ends a run of 200 with probability 2^-200. */
#define RANDOM_MAX_REDRAWS 200

rayset_t *workload_random(const scene_t *s, const workload_opts *o, char *err, size_t errlen)
{
    rayset_t *rs = rayset_new("random", s->name, o->seed, QUERY_CLOSEST);
    /* The box grown by 5% so that segments also start and end outside the geometry. */
    box3 b = s->bounds;
    vec3 ext = box_extent(b), pad = v3_scale(ext, 0.05f);
    b.lo = v3_sub(b.lo, pad);
    ext = v3_add(ext, v3_scale(pad, 2.0f));
    uint64_t n = (uint64_t)o->width * (uint64_t)o->height * (uint64_t)(o->spp < 1 ? 1 : o->spp);
    for (uint64_t i = 0, draw = 0, redraws = 0; i < n; draw++) {
        vec3 p0 = v3_add(b.lo, v3_mul(ext, v3(rng_float(o->seed, STREAM_RANDOM, draw, 0), rng_float(o->seed, STREAM_RANDOM, draw, 1),
                                              rng_float(o->seed, STREAM_RANDOM, draw, 2))));
        vec3 p1 = v3_add(b.lo, v3_mul(ext, v3(rng_float(o->seed, STREAM_RANDOM, draw, 3), rng_float(o->seed, STREAM_RANDOM, draw, 4),
                                              rng_float(o->seed, STREAM_RANDOM, draw, 5))));
        vec3 d = v3_sub(p1, p0);
        float len = v3_len(d);
        if (!(len > 0.0f) || !isfinite(len)) { /* a zero-length segment is redrawn, a bounded number of times */
            if (++redraws < RANDOM_MAX_REDRAWS) continue;
            snprintf(err, errlen, "random workload: scene '%s' has no box to draw segments in: %d draws in a row gave a "
                     "zero-length segment (its bounds (%g %g %g) .. (%g %g %g) are a point, or nearly)", s->name,
                     RANDOM_MAX_REDRAWS, s->bounds.lo.x, s->bounds.lo.y, s->bounds.lo.z, s->bounds.hi.x,
                     s->bounds.hi.y, s->bounds.hi.z);
            rayset_free(rs);
            return NULL;
        }
        redraws = 0;
        ray_t r = {p0, 0.0f, v3_scale(d, 1.0f / len), len, RAY_NO_LIGHT, RAY_NO_ORIGIN};
        rayset_push(rs, &r, 0);
        i++;
    }
    rayset_seal(rs);
    return rs;
}

/* The table's form has no error path: a scene the random workload cannot
 * draw in is bad input, exit 2 with the reason. */
static rayset_t *make_random(const scene_t *s, accel *ref, const workload_opts *o)
{
    (void)ref;
    workload_require_memory("random", s, o);
    char err[512];
    rayset_t *rs = workload_random(s, o, err, sizeof err);
    if (!rs) workload_refuse(err);
    return rs;
}

/* The whitted workload's four parts, one ray set each (workload_whitted.c). */
static rayset_t *make_whitted_eye(const scene_t *s, accel *ref, const workload_opts *o)
{
    return workload_whitted(s, ref, o, WHITTED_EYE);
}
static rayset_t *make_whitted_reflected(const scene_t *s, accel *ref, const workload_opts *o)
{
    return workload_whitted(s, ref, o, WHITTED_REFLECTED);
}
static rayset_t *make_whitted_refracted(const scene_t *s, accel *ref, const workload_opts *o)
{
    return workload_whitted(s, ref, o, WHITTED_REFRACTED);
}
static rayset_t *make_whitted_shadow(const scene_t *s, accel *ref, const workload_opts *o)
{
    return workload_whitted(s, ref, o, WHITTED_SHADOW);
}

const workload_def workload_table[] = {
    {"primary", "pinhole camera rays through pixel centres (or corners), spp per pixel", QUERY_CLOSEST, make_primary},
    {"shadow", "occlusion rays from reference primary hits to every light on the lit side", QUERY_ANY, make_shadow},
    {"reflection", "mirror bounces from reference hits, generations 1..depth (default 3)", QUERY_CLOSEST, make_reflection},
    {"diffuse", "one cosine-distributed bounce from every reference primary hit", QUERY_CLOSEST, make_diffuse},
    {"random", "segments between uniform random points of the scene box (W*H*spp rays)", QUERY_CLOSEST, make_random},
    {"whitted:eye", "SPD protocol: eye rays through the (W+1)x(H+1) pixel corners", QUERY_CLOSEST, make_whitted_eye},
    {"whitted:reflected", "SPD protocol: reflection rays of the ray tree to depth 5 (eye ray = 1)", QUERY_CLOSEST,
     make_whitted_reflected},
    {"whitted:refracted", "SPD protocol: refraction rays (Snell's law where T > 0) of that tree", QUERY_CLOSEST,
     make_whitted_refracted},
    {"whitted:shadow", "SPD protocol: shadow rays from every hit of that tree to the lights it faces", QUERY_ANY,
     make_whitted_shadow},
    {NULL, NULL, QUERY_CLOSEST, NULL},
};

const workload_def *workload_find(const char *name)
{
    for (int i = 0; workload_table[i].name; i++)
        if (strcmp(workload_table[i].name, name) == 0) return &workload_table[i];
    return NULL;
}

/* The rays a primary set of o has: W*H*spp, or (W+1)(H+1) corner rays. */
uint64_t workload_primary_rays(const workload_opts *o)
{
    uint64_t w = o->width > 0 ? (uint64_t)o->width : 1, h = o->height > 0 ? (uint64_t)o->height : 1;
    uint64_t spp = o->spp > 1 ? (uint64_t)o->spp : 1;
    return o->corners ? (w + 1) * (h + 1) : memory_mul(w * h, spp);
}

resources_estimate workload_estimate(const char *name, const workload_opts *o, uint32_t nlights)
{
    resources_estimate e = {0, 0};
    uint64_t n = workload_primary_rays(o);
    /* The derived workloads start from the primary set and the reference's answers for it. */
    uint64_t base = memory_add(rayset_bytes(n, true), answers_bytes(n, QUERY_CLOSEST, false));
    if (!strcmp(name, "primary")) {
        e.rays = n;
        e.bytes = cell_bytes(n, QUERY_CLOSEST, true);
    } else if (!strcmp(name, "shadow")) {
        e.rays = memory_mul(n, nlights ? nlights : 1);
        uint64_t making = memory_add(base, rayset_bytes(e.rays, true));
        e.bytes = resources_max(making, cell_bytes(e.rays, QUERY_ANY, true));
    } else if (!strcmp(name, "reflection")) {
        /* Every generation is at most the one before; the set keeps them all. */
        e.rays = memory_mul(n, o->depth > 0 ? (uint64_t)o->depth : WORKLOAD_REFLECTION_DEPTH);
        uint64_t making = memory_add(memory_add(base, rayset_bytes(n, true)), rayset_bytes(e.rays, true));
        e.bytes = resources_max(making, cell_bytes(e.rays, QUERY_CLOSEST, true));
    } else if (!strcmp(name, "diffuse")) {
        e.rays = n;
        e.bytes = resources_max(memory_add(base, rayset_bytes(n, true)), cell_bytes(n, QUERY_CLOSEST, true));
    } else if (!strncmp(name, "whitted:", 8)) {
        whitted_part part = WHITTED_EYE;
        while (part < WHITTED_PARTS && strcmp(whitted_part_name[part], name)) part++;
        e = whitted_estimate(o, nlights, true, part < WHITTED_PARTS ? part : WHITTED_SHADOW);
    } else { /* random: W*H*spp segments, without pixels (and without corners) */
        workload_opts plain = *o;
        plain.corners = false;
        e.rays = workload_primary_rays(&plain);
        e.bytes = cell_bytes(e.rays, QUERY_CLOSEST, false);
    }
    return e;
}

/* The estimate e of workload name against the set's limit and the cap. */
int workload_check_estimate(const char *name, const char *scene, const workload_opts *o, uint32_t nlights,
                          resources_estimate e, char *err, size_t errlen)
{
    char image[96];
    bool whitted = !strncmp(name, "whitted:", 8);
    resources_describe_image(image, sizeof image, o->width, o->height, o->spp,
                   whitted || (o->corners && strcmp(name, "random") != 0));
    if (e.rays > RAYSET_RAYS_MAX) {
        snprintf(err, errlen,
                 "%s on %s: %s makes up to %llu rays, more than a ray set holds (2^32 - 1); lower --res, --spp or "
                 "--depth", name, scene, image, (unsigned long long)e.rays);
        return -1;
    }
    char lights[48] = "";
    if (!strcmp(name, "shadow")) snprintf(lights, sizeof lights, ", %u light%s", nlights, nlights == 1 ? "" : "s");
    if (!strcmp(name, "reflection"))
        snprintf(lights, sizeof lights, ", depth %d", o->depth > 0 ? o->depth : WORKLOAD_REFLECTION_DEPTH);
    if (whitted)
        snprintf(lights, sizeof lights, ", tree depth %d, %u light%s", o->depth > 0 ? o->depth : WORKLOAD_WHITTED_DEPTH,
                 nlights, nlights == 1 ? "" : "s");
    if (memory_cap_exceeded(e.bytes, err, errlen, "%s on %s: up to %llu rays (%s%s) and their answers", name, scene,
                            (unsigned long long)e.rays, image, lights))
        return -1;
    return 0;
}

int workload_check_memory(const char *name, const char *scene, const workload_opts *o, uint32_t nlights, char *err,
                             size_t errlen)
{
    return workload_check_estimate(name, scene, o, nlights, workload_estimate(name, o, nlights), err, errlen);
}
