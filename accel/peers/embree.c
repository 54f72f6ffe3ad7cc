/* embree.c: Intel Embree 3 (Debian's libembree-dev) as reference and peer.
 * Reference: docs/accels/peers.md.
 *
 * Paper: I. Wald, S. Woop, C. Benthin, G. S. Johnson, M. Ernst, "Embree: A
 * Kernel Framework for Efficient CPU Ray Tracing", ACM TOG 33(4), 2014
 * (section 4: SAH BVH builders; section 5: single-ray traversal kernels).
 *
 * Role: the verification reference (every other accelerator is checked
 * against its answers) and the speed bar (ratio_vs_embree in the CSV).
 *
 * Geometry, one Embree geometry per primitive kind:
 *   0 triangles  RTC_GEOMETRY_TYPE_TRIANGLE over the scene's vertices
 *   1 spheres    RTC_GEOMETRY_TYPE_SPHERE_POINT (float4 x, y, z, r)
 *   2 polygons   RTC_GEOMETRY_TYPE_TRIANGLE over their ear-clipping
 *                triangles (prims_t.poly_tris), all mapped to the polygon
 *   3 cones      RTC_GEOMETRY_TYPE_USER whose callbacks call prims/'s exact
 *                cone test (Embree has no open truncated cone); the
 *                reference then checks the accelerators' structure, and
 *                prims/ has its own exact unit tests for the cone
 * prim_of[geom][primID] maps Embree's ids back to scene primitive ids.
 *
 * Parameters: embree_params below (the build quality, the robust flag).
 * Memory: the bytes Embree's device reports allocating (memory monitor
 * callback), which include its own copies of the vertex and index buffers,
 * plus our id maps.
 * Counters: Embree's work is not observable (ACCEL_NO_COUNTERS); its
 * intersect_fast/occluded_fast are its own queries, which intersect and
 * occluded call. The cone callbacks use prims/'s counting-free tests.
 * Context: one RTCIntersectContext per thread, initialised once. */
#include <embree3/rtcore.h>
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "../accel.h"
#include "embree.h"
#include "../../prims/checked_alloc.h"

static const accel_param embree_params[] = {
    PARAM_ROW_CHOICE("quality", "medium", "medium|low|high", "BVH build quality (rtcSetSceneBuildQuality)"),
    PARAM_ROW_BOOL("robust", "off", "RTC_SCENE_FLAG_ROBUST (avoids optimizations that cost watertightness)"),
    PARAM_ROW_END,
};

typedef struct {
    const prims_t *prims;
    const uint32_t *prim_of;
} cone_user;

typedef struct {
    accel base;
    RTCDevice device;
    RTCScene scene;
    uint32_t *prim_of[4]; /* [geometry][embree primID] -> scene primitive id */
    bool ids_identity;    /* one kind of primitive only: primID is the scene id, skip the map */
    size_t id_bytes;
    _Atomic long long device_bytes; /* running total from the memory monitor */
    cone_user cone_user;  /* what the cone callbacks see */
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
    for (int g = 0; g < 4; g++) free(e->prim_of[g]);
    free(e);
}

/* A triangle geometry over the scene's vertex array with the given index
 * triples (the triangles themselves, or the polygons' ear-clipping). */
static int add_triangle_geometry(embree_accel *e, const prims_t *p, const tri_t *tris, uint32_t ntris, unsigned geom_id)
{
    RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), p->nverts);
    unsigned *ix = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), ntris);
    if (!v || !ix) {
        rtcReleaseGeometry(g);
        return -1;
    }
    for (uint32_t i = 0; i < p->nverts; i++) {
        v[3 * i + 0] = p->verts[i].x;
        v[3 * i + 1] = p->verts[i].y;
        v[3 * i + 2] = p->verts[i].z;
    }
    memcpy(ix, tris, (size_t)ntris * sizeof *tris);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(e->scene, g, geom_id);
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

/* Cones: a user geometry. The callbacks receive the scene's primitive
 * store (cone_user) and Embree's primID = the cone's index; prim_of[3]
 * gives its scene id. */
static void cone_bounds(const struct RTCBoundsFunctionArguments *args)
{
    const cone_user *cu = args->geometryUserPtr;
    box3 b = prim_bounds(cu->prims, cu->prim_of[args->primID]);
    args->bounds_o->lower_x = b.lo.x, args->bounds_o->lower_y = b.lo.y, args->bounds_o->lower_z = b.lo.z;
    args->bounds_o->upper_x = b.hi.x, args->bounds_o->upper_y = b.hi.y, args->bounds_o->upper_z = b.hi.z;
}

static void cone_intersect(const struct RTCIntersectFunctionNArguments *args)
{
    if (args->N != 1 || !args->valid[0]) return;
    const cone_user *cu = args->geometryUserPtr;
    struct RTCRayHit *rh = (struct RTCRayHit *)args->rayhit;
    ray_t r = {v3(rh->ray.org_x, rh->ray.org_y, rh->ray.org_z), rh->ray.tnear,
               v3(rh->ray.dir_x, rh->ray.dir_y, rh->ray.dir_z), rh->ray.tfar, RAY_NO_LIGHT, 0};
    hit_t h = hit_none(&r);
    uint32_t id = cu->prim_of[args->primID];
    if (!prim_intersect_fast(cu->prims, id, &r, &h)) return;
    vec3 n = prim_normal(cu->prims, &h, &r);
    rh->ray.tfar = h.t;
    rh->hit.u = h.u;
    rh->hit.v = h.v;
    rh->hit.Ng_x = n.x, rh->hit.Ng_y = n.y, rh->hit.Ng_z = n.z;
    rh->hit.primID = args->primID;
    rh->hit.geomID = args->geomID;
    rh->hit.instID[0] = args->context->instID[0];
}

static void cone_occluded(const struct RTCOccludedFunctionNArguments *args)
{
    if (args->N != 1 || !args->valid[0]) return;
    const cone_user *cu = args->geometryUserPtr;
    struct RTCRay *rr = (struct RTCRay *)args->ray;
    ray_t r = {v3(rr->org_x, rr->org_y, rr->org_z), rr->tnear, v3(rr->dir_x, rr->dir_y, rr->dir_z), rr->tfar, RAY_NO_LIGHT, 0};
    if (prim_occluded_fast(cu->prims, cu->prim_of[args->primID], &r)) rr->tfar = -INFINITY;
}

static int add_cones(embree_accel *e, const prims_t *p)
{
    e->cone_user.prims = p;
    e->cone_user.prim_of = e->prim_of[3];
    RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, p->ncones);
    rtcSetGeometryUserData(g, &e->cone_user);
    rtcSetGeometryBoundsFunction(g, cone_bounds, NULL);
    rtcSetGeometryIntersectFunction(g, cone_intersect);
    rtcSetGeometryOccludedFunction(g, cone_occluded);
    rtcCommitGeometry(g);
    rtcAttachGeometryByID(e->scene, g, 3);
    rtcReleaseGeometry(g);
    return 0;
}

static accel *embree_build(const scene_t *scene, const accel_params *params, char *err, size_t errlen)
{
    static const enum RTCBuildQuality quality_of[] = {RTC_BUILD_QUALITY_MEDIUM, RTC_BUILD_QUALITY_LOW, RTC_BUILD_QUALITY_HIGH};
    int quality = params_choice(params, "quality");
    bool robust = params_bool(params, "robust");

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
    size_t per_geom[4] = {p->ntris, p->nspheres, p->npoly_tris, p->ncones};
    for (int g = 0; g < 4; g++) {
        e->prim_of[g] = malloc((per_geom[g] + 1) * sizeof(uint32_t));
        if (!e->prim_of[g]) {
            snprintf(err, errlen, "out of memory for %u primitive ids", p->count);
            embree_destroy(&e->base);
            return NULL;
        }
        e->id_bytes += per_geom[g] * sizeof(uint32_t);
    }
    static const int geom_of_kind[PRIM_KINDS] = {[PRIM_TRIANGLE] = 0, [PRIM_SPHERE] = 1, [PRIM_POLYGON] = 2, [PRIM_CONE] = 3};
    e->ids_identity = p->npolygons == 0;
    for (uint32_t id = 0; id < p->count; id++) {
        uint32_t k = p->index[id];
        if (p->kind[id] == PRIM_POLYGON) {
            const polygon_t *poly = &p->polygons[k];
            for (uint32_t t = 0; t < poly->count - 2; t++) e->prim_of[2][poly->tri_first + t] = id;
        } else {
            e->prim_of[geom_of_kind[p->kind[id]]][k] = id;
        }
        if (k != id) e->ids_identity = false;
    }

    if ((p->ntris && add_triangle_geometry(e, p, p->tris, p->ntris, 0)) || (p->nspheres && add_spheres(e, p)) ||
        (p->npoly_tris && add_triangle_geometry(e, p, p->poly_tris, p->npoly_tris, 2)) || (p->ncones && add_cones(e, p))) {
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
    accel_ctx *ctx = checked_malloc(sizeof *ctx, "an Embree tracing context");
    rtcInitIntersectContext(&ctx->ic);
    return ctx;
}

static void embree_context_free(accel_ctx *ctx) { free(ctx); }

/* Embree has no counters, so its counting-free methods are the real ones
 * and the counting ones (which have nothing to count) call them. */
static bool embree_intersect_fast(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit)
{
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

static bool embree_occluded_fast(accel *a, accel_ctx *ctx, const ray_t *ray)
{
    embree_accel *e = (embree_accel *)a;
    struct RTCRay r;
    to_rtc(ray, &r);
    rtcOccluded1(e->scene, &ctx->ic, &r);
    return r.tfar < 0.0f; /* Embree sets tfar to -inf on a hit */
}

static bool embree_intersect(accel *a, accel_ctx *ctx, const ray_t *ray, hit_t *hit, counters_t *c)
{
    (void)c;
    return embree_intersect_fast(a, ctx, ray, hit);
}

static bool embree_occluded(accel *a, accel_ctx *ctx, const ray_t *ray, counters_t *c)
{
    (void)c;
    return embree_occluded_fast(a, ctx, ray);
}

static size_t embree_memory(const accel *a)
{
    const embree_accel *e = (const embree_accel *)a;
    long long b = atomic_load(&((embree_accel *)e)->device_bytes);
    return (b > 0 ? (size_t)b : 0) + e->id_bytes;
}

const struct accel_ops accel_embree = {
    .version = 2,
    .name = "embree",
    .summary = "Intel Embree 3 SAH BVH, single-ray kernels (the reference and speed bar)",
    .paper = "Wald et al., Embree: A Kernel Framework for Efficient CPU Ray Tracing, TOG 2014, sections 4-5",
    .params = embree_params,
    .flags = ACCEL_NO_COUNTERS,
    .build = embree_build,
    .context_new = embree_context_new,
    .context_free = embree_context_free,
    .intersect = embree_intersect,
    .occluded = embree_occluded,
    .memory = embree_memory,
    .destroy = embree_destroy,
    .intersect_fast = embree_intersect_fast,
    .occluded_fast = embree_occluded_fast,
    .cost = {1, 1, 0},
};

RTCScene embree_scene_of(accel *a) { return ((embree_accel *)a)->scene; }
