/* resources.c: the harness's estimates against the memory cap (see
 * resources.h). */
#include "resources.h"

#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include "trace.h"

/* rayset_push's first capacity (rayset.c). */
#define RAYSET_FIRST_CAP 4096u

uint64_t resources_rayset_bytes(uint64_t n, bool pixels)
{
    if (n == 0) return 0;
    uint64_t cap = RAYSET_FIRST_CAP;
    while (cap < n && cap < RESOURCES_RAYS_MAX) cap *= 2;
    if (cap > RESOURCES_RAYS_MAX) cap = RESOURCES_RAYS_MAX;
    if (n > cap) cap = n; /* beyond what a set holds: the count is refused anyway */
    return memory_mul(cap, sizeof(ray_t) + (pixels ? sizeof(uint32_t) : 0));
}

uint64_t resources_answers_bytes(uint64_t n, query_kind q, bool per_ray_counters)
{
    uint64_t each = (q == QUERY_CLOSEST ? sizeof(hit_t) : sizeof(uint8_t)) + (per_ray_counters ? sizeof(counters_t) : 0);
    return memory_mul(n ? n : 1, each);
}

static uint64_t max_u64(uint64_t a, uint64_t b) { return a > b ? a : b; }

/* A cell tracing a set of n rays of query q (measure.c, matrix.c): the
 * reference's answers stay for the whole cell; the ill-posed count traces
 * the set for nearest hits beside them (then frees them), and the
 * accelerator's warm-up answers and the timing's scratch answers come
 * after, beside the reference's. */
static uint64_t cell_answers_bytes(uint64_t n, query_kind q)
{
    uint64_t ref = resources_answers_bytes(n, q, false), closest = resources_answers_bytes(n, QUERY_CLOSEST, false);
    return memory_add(ref, max_u64(closest, memory_mul(ref, 2)));
}

/* The structs a cell allocates beside its arrays (the set's and the
 * answers' headers, the allocator's own bookkeeping): a few hundred bytes,
 * rounded up. */
#define CELL_OVERHEAD_BYTES 4096

static uint64_t cell_bytes(uint64_t n, query_kind q, bool pixels)
{
    return memory_add(memory_add(resources_rayset_bytes(n, pixels), cell_answers_bytes(n, q)), CELL_OVERHEAD_BYTES);
}

/* The rays a primary set of o has: W*H*spp, or (W+1)(H+1) corner rays. */
static uint64_t primary_rays(const workload_opts *o)
{
    uint64_t w = o->width > 0 ? (uint64_t)o->width : 1, h = o->height > 0 ? (uint64_t)o->height : 1;
    uint64_t spp = o->spp > 1 ? (uint64_t)o->spp : 1;
    return o->corners ? (w + 1) * (h + 1) : memory_mul(w * h, spp);
}

resources_estimate resources_workload(const char *name, const workload_opts *o, uint32_t nlights)
{
    resources_estimate e = {0, 0};
    uint64_t n = primary_rays(o);
    /* The derived workloads start from the primary set and the reference's answers for it. */
    uint64_t base = memory_add(resources_rayset_bytes(n, true), resources_answers_bytes(n, QUERY_CLOSEST, false));
    if (!strcmp(name, "primary")) {
        e.rays = n;
        e.bytes = cell_bytes(n, QUERY_CLOSEST, true);
    } else if (!strcmp(name, "shadow")) {
        e.rays = memory_mul(n, nlights ? nlights : 1);
        uint64_t making = memory_add(base, resources_rayset_bytes(e.rays, true));
        e.bytes = max_u64(making, cell_bytes(e.rays, QUERY_ANY, true));
    } else if (!strcmp(name, "reflection")) {
        /* Every generation is at most the one before; the set keeps them all. */
        e.rays = memory_mul(n, o->depth > 0 ? (uint64_t)o->depth : WORKLOAD_REFLECTION_DEPTH);
        uint64_t making = memory_add(memory_add(base, resources_rayset_bytes(n, true)), resources_rayset_bytes(e.rays, true));
        e.bytes = max_u64(making, cell_bytes(e.rays, QUERY_CLOSEST, true));
    } else if (!strcmp(name, "diffuse")) {
        e.rays = n;
        e.bytes = max_u64(memory_add(base, resources_rayset_bytes(n, true)), cell_bytes(n, QUERY_CLOSEST, true));
    } else if (!strncmp(name, "whitted:", 8)) {
        whitted_part part = WHITTED_EYE;
        while (part < WHITTED_PARTS && strcmp(whitted_part_name[part], name)) part++;
        e = resources_whitted(o, nlights, true, part < WHITTED_PARTS ? part : WHITTED_SHADOW);
    } else { /* random: W*H*spp segments, without pixels (and without corners) */
        workload_opts plain = *o;
        plain.corners = false;
        e.rays = primary_rays(&plain);
        e.bytes = cell_bytes(e.rays, QUERY_CLOSEST, false);
    }
    return e;
}

resources_estimate resources_whitted(const workload_opts *o, uint32_t nlights, bool transmitters, whitted_part part)
{
    workload_opts eye = *o;
    eye.corners = true;
    uint64_t n = primary_rays(&eye), depth = o->depth > 0 ? (uint64_t)o->depth : WORKLOAD_WHITTED_DEPTH;
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
    uint64_t making = memory_add(memory_add(memory_mul(resources_rayset_bytes(widest, true), 2),
                                            resources_answers_bytes(widest, QUERY_CLOSEST, false)),
                                 resources_rayset_bytes(e.rays, true));
    e.bytes = max_u64(making, cell_bytes(e.rays, any ? QUERY_ANY : QUERY_CLOSEST, true));
    return e;
}

/* "WxH at S spp" or "WxH corners", for messages. */
static void describe_image(char *buf, size_t len, int w, int h, int spp, bool corners)
{
    if (corners) snprintf(buf, len, "%dx%d pixel corners", w, h);
    else snprintf(buf, len, "%dx%d at %d spp", w, h, spp < 1 ? 1 : spp);
}

/* The estimate e of workload name against the set's limit and the cap. */
static int check_estimate(const char *name, const char *scene, const workload_opts *o, uint32_t nlights,
                          resources_estimate e, char *err, size_t errlen)
{
    char image[96];
    bool whitted = !strncmp(name, "whitted:", 8);
    describe_image(image, sizeof image, o->width, o->height, o->spp,
                   whitted || (o->corners && strcmp(name, "random") != 0));
    if (e.rays > RESOURCES_RAYS_MAX) {
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

int resources_check_workload(const char *name, const char *scene, const workload_opts *o, uint32_t nlights, char *err,
                             size_t errlen)
{
    return check_estimate(name, scene, o, nlights, resources_workload(name, o, nlights), err, errlen);
}

int resources_check_whitted(const char *scene, const workload_opts *o, uint32_t nlights, bool transmitters,
                            whitted_part part, char *err, size_t errlen)
{
    return check_estimate(whitted_part_name[part], scene, o, nlights, resources_whitted(o, nlights, transmitters, part),
                          err, errlen);
}

resources_estimate resources_render(int width, int height, int spp, bool corners, bool heatmap)
{
    workload_opts o = {.width = width, .height = height, .spp = spp, .corners = corners};
    uint64_t n = primary_rays(&o), pixels = memory_mul((uint64_t)(width > 0 ? width : 1), (uint64_t)(height > 0 ? height : 1));
    resources_estimate e = {n, resources_rayset_bytes(n, true)};
    uint64_t image = memory_mul(pixels, 3);
    if (heatmap) /* answers with per-ray counters, then one double a pixel */
        e.bytes = memory_add(e.bytes, memory_add(resources_answers_bytes(n, QUERY_CLOSEST, true),
                                                 memory_add(memory_mul(pixels, sizeof(double)), image)));
    else /* one colour sum a pixel (vec3) beside the image */
        e.bytes = memory_add(e.bytes, memory_add(memory_mul(pixels, sizeof(vec3)), image));
    return e;
}

int resources_check_render(const char *scene, int width, int height, int spp, bool corners, bool heatmap, char *err,
                           size_t errlen)
{
    resources_estimate e = resources_render(width, height, spp, corners, heatmap);
    char image[96];
    describe_image(image, sizeof image, width, height, spp, corners);
    if (e.rays > RESOURCES_RAYS_MAX) {
        snprintf(err, errlen, "render %s: %s is %llu primary rays, more than a ray set holds (2^32 - 1); lower --res or --spp",
                 scene, image, (unsigned long long)e.rays);
        return -1;
    }
    return memory_cap_exceeded(e.bytes, err, errlen, "render %s: a %s %s and its %llu rays", scene, image,
                               heatmap ? "heat map" : "image", (unsigned long long)e.rays)
               ? -1
               : 0;
}

uint64_t resources_thread_stack_bytes(void)
{
    pthread_attr_t a;
    size_t stack = 0, guard = 0;
    /* The attributes pthread_create uses when given none (glibc: the
     * stack rlimit at start-up, else 8 MiB). */
    if (pthread_getattr_default_np(&a) == 0) {
        pthread_attr_getstacksize(&a, &stack);
        pthread_attr_getguardsize(&a, &guard);
        pthread_attr_destroy(&a);
    }
    if (stack == 0) stack = 8u << 20;
    return (uint64_t)stack + guard;
}

int resources_check_threads(int threads, const char *option, char *err, size_t errlen)
{
    /* The calling thread is one of them and has its stack already. */
    uint64_t each = resources_thread_stack_bytes(), started = threads > 1 ? (uint64_t)threads - 1 : 0;
    if (memory_cap_exceeded(memory_mul(started, each), err, errlen,
                            "%s %d: the stacks of the %llu threads it starts (%.1f MiB of address space each)", option,
                            threads, (unsigned long long)started, (double)each / 1048576.0))
        return -1;
    return 0;
}

int resources_parse_memcap(const char *arg, uint64_t *mib, char *err, size_t errlen)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(arg, &end, 10);
    if (errno || end == arg || *end || arg[0] == '-' || v < 1 || v > MEMORY_CAP_MIB_MAX) {
        snprintf(err, errlen, "--memcap %s: expected MiB, an integer in 1..%llu", arg,
                 (unsigned long long)MEMORY_CAP_MIB_MAX);
        return -1;
    }
    *mib = v;
    return 0;
}

void resources_bound_accel_params(accel_params *params)
{
    uint64_t cap_mib = memory_cap_mib();
    params->memcap_mib = cap_mib ? cap_mib : 1;
}

int resources_apply_memcap(options *o)
{
    memory_cap_set_mib(o->memcap_mib);
    for (int i = 0; i < o->naccels; i++) resources_bound_accel_params(&o->accels[i].params);
    return 0;
}

/* The fewest heap bytes one primitive of any kind takes in a scene: its
 * kind, index, bounds and material, and a triangle's three indices and
 * degenerate flag (the smallest kind; vertices may be shared). */
#define PRIM_MIN_BYTES (1 + sizeof(uint32_t) + sizeof(box3) + sizeof(uint16_t) + sizeof(tri_t) + 1)

int resources_check_options(const options *o, const char *cmd)
{
    char err[1024];
    if (resources_check_threads(o->threads, "--threads", err, sizeof err)) goto refuse;
    for (int i = 0; i < o->nscenes; i++) {
        uint64_t prims;
        if (scene_generated(o->scenes[i], &prims) &&
            memory_cap_exceeded(memory_mul(prims, PRIM_MIN_BYTES), err, sizeof err,
                                "scene %s: %llu primitives (at least %zu bytes each)", o->scenes[i],
                                (unsigned long long)prims, (size_t)PRIM_MIN_BYTES))
            goto refuse;
    }
    if (o->rays_file) {
        /* The file is read whole, then copied into the set; its rays are at least 40 bytes each. */
        struct stat st;
        if (stat(o->rays_file, &st) == 0 && st.st_size > 0) {
            uint64_t size = (uint64_t)st.st_size, n = size / sizeof(ray_t);
            uint64_t bytes = memory_add(memory_mul(size, 2), cell_answers_bytes(n, QUERY_CLOSEST));
            if (memory_cap_exceeded(bytes, err, sizeof err, "--rays %s: a %llu-byte file of up to %llu rays and their answers",
                                    o->rays_file, (unsigned long long)size, (unsigned long long)n))
                goto refuse;
        }
        return 0;
    }
    if (!strcmp(cmd, "render")) {
        /* Without --res the image is the scene's own size, known once it is loaded (render.c checks it then). */
        if (o->res_given &&
            resources_check_render(o->scenes[0], o->wl.width, o->wl.height, o->wl.spp, o->wl.corners, o->heatmap != NULL,
                                   err, sizeof err))
            goto refuse;
        return 0;
    }
    /* The sets do not depend on the scene at one light. */
    for (int i = 0; i < o->nworkloads; i++)
        if (resources_check_workload(o->workloads[i]->name, o->scenes[0], &o->wl, 1, err, sizeof err)) goto refuse;
    return 0;
refuse:
    fprintf(stderr, "accelbench: %s\n", err);
    return 2;
}
