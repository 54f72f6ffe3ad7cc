/* embree.c: Intel Embree 3 (Debian's libembree-dev) as reference and peer.
 *
 * Paper: I. Wald, S. Woop, C. Benthin, G. S. Johnson, M. Ernst, "Embree: A
 * Kernel Framework for Efficient CPU Ray Tracing", ACM TOG 33(4), 2014
 * (section 4: SAH BVH builders; section 5: single-ray traversal kernels).
 *
 * Role: the verification reference (every other accelerator is checked
 * against its answers) and the speed bar (ratio_vs_embree in the CSV).
 *
 * Geometry: triangles as one RTC_GEOMETRY_TYPE_TRIANGLE (geometry 0),
 * spheres as one RTC_GEOMETRY_TYPE_SPHERE_POINT (geometry 1, float4
 * x,y,z,r). Embree's primIDs index those arrays; prim_of[geom][primID]
 * maps them back to scene primitive ids.
 *
 * Parameters (defaults first):
 *   quality = medium | low | high   rtcSetSceneBuildQuality
 *   robust  = off | on              RTC_SCENE_FLAG_ROBUST (avoids optimizations
 *                                   that cost watertightness)
 * Memory: the bytes Embree's device reports allocating (memory monitor
 * callback), which include its own copies of the vertex and index buffers,
 * plus our id maps.
 * Counters: Embree's work is not observable (ACCEL_OPAQUE).
 * Context: one RTCIntersectContext per thread, initialised once. */
#include <embree3/rtcore.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "accel.h"
#include "embree.h"

static const accel_param embree_params[] = {
    {"quality", "medium", "BVH build quality: low|medium|high"},
    {"robust", "off", "RTC_SCENE_FLAG_ROBUST: off|on"},
    {NULL, NULL, NULL},
};

typedef struct {
    accel base;
    RTCDevice device;
    RTCScene scene;
    uint32_t *prim_of[2]; /* [geometry][embree primID] -> scene primitive id */
    bool ids_identity;    /* one kind of primitive only: primID is the scene id, skip the map */
    size_t id_bytes;
    _Atomic long long device_bytes; /* running total from the memory monitor */
    char error[256];      /* last device error, for build failures */
} embree_accel;

static void on_error(void *user, enum RTCError code, const char *str)
{
    embree_accel *e = user;
    snprintf(e->error, sizeof e->error, "embree error %d: %s", (int)code, str ? str : "?");
}

static bool on_memory(void *user, ssize_t bytes, bool post)
{
    (void)post;
    embree_accel *e = user;
    atomic_fetch_add(&e->device_bytes, (long long)bytes);
    return true;
}

static void embree_destroy(accel *a)
{
    embree_accel *e = (embree_accel *)a;
    if (e->scene) rtcReleaseScene(e->scene);
    if (e->device) rtcReleaseDevice(e->device);
    free(e->prim_of[0]);
    free(e->prim_of[1]);
    free(e);
}

static int add_triangles(embree_accel *e, const prims_t *p)
{
    RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), p->nverts);
    unsigned *ix = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), p->ntris);
    if (!v || !ix) {
        rtcReleaseGeometry(g);
        return -1;
    }
    for (uint32_t i = 0; i < p->nverts; i++) {
        v[3 * i + 0] = p->verts[i].x;
        v[3 * i + 1] = p->verts[i].y;
        v[3 * i + 2] = p->verts[i].z;
    }
    memcpy(ix, p->tris, (size_t)p->ntris * sizeof *p->tris);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(e->scene, g, 0);
    rtcReleaseGeometry(g);
    return 0;
}

static int add_spheres(embree_accel *e, const prims_t *p)
{
    RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), p->nspheres);
    if (!v) {
        rtcReleaseGeometry(g);
        return -1;
    }
    for (uint32_t i = 0; i < p->nspheres; i++) {
        v[4 * i + 0] = p->spheres[i].center.x;
        v[4 * i + 1] = p->spheres[i].center.y;
        v[4 * i + 2] = p->spheres[i].center.z;
        v[4 * i + 3] = p->spheres[i].radius;
    }
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(e->scene, g, 1);
    rtcReleaseGeometry(g);
    return 0;
}

static accel *embree_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    static const char *const qualities[] = {"medium", "low", "high", NULL};
    static const char *const onoff[] = {"off", "on", NULL};
    static const enum RTCBuildQuality quality_of[] = {RTC_BUILD_QUALITY_MEDIUM, RTC_BUILD_QUALITY_LOW, RTC_BUILD_QUALITY_HIGH};
    int quality, robust;
    if (params_get_choice(params, "quality", qualities, &quality, err, errlen) ||
        params_get_choice(params, "robust", onoff, &robust, err, errlen))
        return NULL;

    embree_accel *e = calloc(1, sizeof *e);
    if (!e) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    e->base.scene = scene;
    const prims_t *p = &scene->prims;

    /* Give Embree's builder the same number of threads as the harness. */
    char config[64];
    snprintf(config, sizeof config, "threads=%d", params->threads > 0 ? params->threads : 1);
    e->device = rtcNewDevice(config);
    if (!e->device) {
        snprintf(err, errlen, "rtcNewDevice(\"%s\") failed: error %d", config, (int)rtcGetDeviceError(NULL));
        free(e);
        return NULL;
    }
    rtcSetDeviceErrorFunction(e->device, on_error, e);
    rtcSetDeviceMemoryMonitorFunction(e->device, on_memory, e);
    e->scene = rtcNewScene(e->device);
    rtcSetSceneBuildQuality(e->scene, quality_of[quality]);
    if (robust) rtcSetSceneFlags(e->scene, RTC_SCENE_FLAG_ROBUST);

    /* Map Embree's (geometry, primID) back to scene primitive ids. */
    e->prim_of[0] = malloc(((size_t)p->ntris + 1) * sizeof(uint32_t));
    e->prim_of[1] = malloc(((size_t)p->nspheres + 1) * sizeof(uint32_t));
    if (!e->prim_of[0] || !e->prim_of[1]) {
        snprintf(err, errlen, "out of memory for %u primitive ids", p->count);
        embree_destroy(&e->base);
        return NULL;
    }
    e->id_bytes = ((size_t)p->ntris + p->nspheres) * sizeof(uint32_t);
    e->ids_identity = true;
    for (uint32_t id = 0; id < p->count; id++) {
        e->prim_of[p->kind[id] == PRIM_SPHERE][p->index[id]] = id;
        if (p->index[id] != id) e->ids_identity = false;
    }

    if ((p->ntris && add_triangles(e, p)) || (p->nspheres && add_spheres(e, p))) {
        snprintf(err, errlen, "embree geometry: %s", e->error[0] ? e->error : "buffer allocation failed");
        embree_destroy(&e->base);
        return NULL;
    }
    rtcCommitScene(e->scene);
    if (e->error[0]) {
        snprintf(err, errlen, "embree build: %s", e->error);
        embree_destroy(&e->base);
        return NULL;
    }
    return &e->base;
}

static inline void to_rtc(const ray_t *r, struct RTCRay *out)
{
    out->org_x = r->org.x;
    out->org_y = r->org.y;
    out->org_z = r->org.z;
    out->tnear = r->tnear;
    out->dir_x = r->dir.x;
    out->dir_y = r->dir.y;
    out->dir_z = r->dir.z;
    out->time = 0.0f;
    out->tfar = r->tfar;
    out->mask = 0xFFFFFFFFu;
    out->id = 0;
    out->flags = 0;
}

/* The per-thread context is Embree's intersect context, set up once per
 * thread instead of once per ray (it is on the hot path of every query). */
struct accel_ctx {
    struct RTCIntersectContext ic;
};

static accel_ctx *embree_context_new(accel *a)
{
    (void)a;
    accel_ctx *ctx = malloc(sizeof *ctx);
    if (!ctx) abort();
    rtcInitIntersectContext(&ctx->ic);
    return ctx;
}

static void embree_context_free(accel_ctx *ctx) { free(ctx); }

static bool embree_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    (void)c;
    embree_accel *e = (embree_accel *)a;
    struct RTCRayHit rh;
    to_rtc(ray, &rh.ray);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(e->scene, &ctx->ic, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit->t = rh.ray.tfar;
    hit->u = rh.hit.u;
    hit->v = rh.hit.v;
    hit->prim = e->ids_identity ? rh.hit.primID : e->prim_of[rh.hit.geomID][rh.hit.primID];
    return true;
}

static bool embree_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    (void)c;
    embree_accel *e = (embree_accel *)a;
    struct RTCRay r;
    to_rtc(ray, &r);
    rtcOccluded1(e->scene, &ctx->ic, &r);
    return r.tfar < 0.0f; /* Embree sets tfar to -inf on a hit */
}

static size_t embree_memory(const accel *a)
{
    const embree_accel *e = (const embree_accel *)a;
    long long b = atomic_load(&((embree_accel *)e)->device_bytes);
    return (b > 0 ? (size_t)b : 0) + e->id_bytes;
}

const struct accel_ops accel_embree = {
    .version = 1,
    .name = "embree",
    .summary = "Intel Embree 3 SAH BVH, single-ray kernels (the reference and speed bar)",
    .paper = "Wald et al., Embree: A Kernel Framework for Efficient CPU Ray Tracing, TOG 2014, sections 4-5",
    .params = embree_params,
    .flags = ACCEL_OPAQUE,
    .build = embree_build,
    .context_new = embree_context_new,
    .context_free = embree_context_free,
    .intersect = embree_intersect,
    .occluded = embree_occluded,
    .memory = embree_memory,
    .destroy = embree_destroy,
};

RTCScene embree_scene_of(accel *a) { return ((embree_accel *)a)->scene; }
